//! spirv/ is fresh, valid and laid out like the Rust twin of the uniform block.
use shadelab::gpu::{shaders, spirv};

use crate::support::root;

#[test]
fn spirv_is_fresh() {
    if let Err(e) = shaders::check_fresh(&root().join("glsl"), &root().join("spirv")) {
        panic!("{e}");
    }
}

/// Teeth: a GLSL edit without regenerating is caught, with the command to run.
#[test]
fn edited_glsl_makes_spirv_stale() {
    let dir = tempfile::tempdir().unwrap();
    let glsl = dir.path().join("glsl");
    copy_dir(&root().join("glsl"), &glsl);
    let f = glsl.join("methods/phong_exact.glsl");
    let text = std::fs::read_to_string(&f).unwrap();
    let edited = text.replace("normalize(R3(vNormal))", "R3(vNormal)");
    assert_ne!(edited, text, "the edit must change the file");
    std::fs::write(&f, edited).unwrap();
    let e = shaders::check_fresh(&glsl, &root().join("spirv"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("spirv/ is stale") && e.contains("run `make spirv`"),
        "{e}"
    );
    // ... and a hand-edited .spv too.
    let spirv = dir.path().join("spirv");
    copy_dir(&root().join("spirv"), &spirv);
    let spv = spirv.join("phong_exact.screen_linear.frag.spv");
    let mut bytes = std::fs::read(&spv).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&spv, bytes).unwrap();
    let e = shaders::check_fresh(&root().join("glsl"), &spirv)
        .unwrap_err()
        .to_string();
    assert!(e.contains("differs from the generated file"), "{e}");
}

fn copy_dir(from: &std::path::Path, to: &std::path::Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.path().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// spirv-val (Khronos SPIRV-Tools) accepts every module for Vulkan 1.3.
#[test]
fn spirv_val_passes_on_every_module() {
    let mut n = 0;
    for e in std::fs::read_dir(root().join("spirv")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "spv") {
            let out = std::process::Command::new("spirv-val")
                .args(["--target-env", "vulkan1.3"])
                .arg(&p)
                .output()
                .expect("spirv-val not found: install spirv-tools (scripts/install-deps.sh test)");
            assert!(
                out.status.success(),
                "{}: {}",
                p.display(),
                String::from_utf8_lossy(&out.stderr)
            );
            n += 1;
        }
    }
    assert!(n >= 8, "only {n} modules in spirv/");
}

/// The std140 block of glsl/common.glsl and `render::Params` have the same member offsets.
#[test]
fn uniform_block_matches_rust_twin() {
    use shadelab::scene::Params;
    use std::mem::{offset_of, size_of};
    let rust = vec![
        offset_of!(Params, mvp),
        offset_of!(Params, ambient),
        offset_of!(Params, diffuse),
        offset_of!(Params, specular),
        offset_of!(Params, light_dir),
        offset_of!(Params, light_color),
        offset_of!(Params, half_vec),
        offset_of!(Params, const_color),
    ];
    for module in [
        "phong_exact.screen_linear.frag",
        "constant.perspective.vert",
        "ids.screen_linear.vert",
    ] {
        let bytes = std::fs::read(root().join("spirv").join(format!("{module}.spv"))).unwrap();
        let glsl: Vec<usize> = spirv::block_member_offsets(&bytes)
            .unwrap()
            .into_iter()
            .map(|o| o as usize)
            .collect();
        assert_eq!(glsl, rust, "{module}: GLSL offsets vs Rust offsets");
    }
    assert_eq!(size_of::<Params>(), 320);
}
