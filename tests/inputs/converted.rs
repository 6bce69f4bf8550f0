//! glTF written by an outside converter (CesiumGS's obj2gltf, from the npm registry, installed
//! into the user's cache by scripts/setup-converters.sh) from the shared models, against the
//! OBJ it came from. Skipped, visibly, without obj2gltf or the models; failed instead under
//! `SHADELAB_REQUIRE_CONVERTERS=1` (CI sets it).
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use shadelab::geometry::{load_mesh, LoadReport, Mesh};

use crate::support::*;

/// The obj2gltf command: `SHADELAB_OBJ2GLTF`, else the one scripts/setup-converters.sh
/// installs under `$XDG_CACHE_HOME/shadelab/converters` (default `~/.cache`). `None`, with a
/// SKIPPED line, when there is none (a failure under `SHADELAB_REQUIRE_CONVERTERS=1`).
fn obj2gltf() -> Option<PathBuf> {
    let cache = std::env::var_os("XDG_CACHE_HOME")
        .filter(|c| !c.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_default();
    let path = match std::env::var_os("SHADELAB_OBJ2GLTF") {
        Some(p) if !p.is_empty() => PathBuf::from(p),
        _ => cache.join("shadelab/converters/node_modules/.bin/obj2gltf"),
    };
    let works = Command::new(&path)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if works {
        return Some(path);
    }
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let why = format!(
        "no obj2gltf at {} (run scripts/setup-converters.sh, or set SHADELAB_OBJ2GLTF)",
        path.display()
    );
    if std::env::var("SHADELAB_REQUIRE_CONVERTERS").as_deref() == Ok("1") {
        panic!("{test}: SHADELAB_REQUIRE_CONVERTERS=1 but {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED: {test}: {why}");
    None
}

/// `obj2gltf -i OBJ -o OUT extra...`.
fn convert(tool: &Path, obj: &Path, out: &Path, extra: &[&str]) {
    let o = Command::new(tool)
        .arg("-i")
        .arg(obj)
        .arg("-o")
        .arg(out)
        .args(extra)
        .output()
        .expect("run obj2gltf");
    assert!(
        o.status.success() && out.is_file(),
        "obj2gltf {}: {}",
        obj.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn load(p: &Path) -> (Mesh, LoadReport) {
    load_mesh(p).unwrap_or_else(|e| panic!("{e}"))
}

/// compare's per-method figures (summary.json `methods`) of `mesh` at 64x64.
fn figures(mesh: &Path, out: &Path) -> serde_json::Value {
    let (code, _, err) = run(&[
        "compare",
        "--mesh",
        mesh.to_str().unwrap(),
        "--size",
        "64x64",
        "--methods",
        "phong_exact,gouraud,newton_raphson,lyon_taylor",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    read_json(out.join("summary.json"))["methods"].clone()
}

/// Every shared model through obj2gltf (.glb; spot also as .gltf with a data URI and with a
/// .bin beside it) against its OBJ:
/// - where the OBJ has triangles only and no position written twice (spot, fandisk, the
///   bunny), the same mesh bit for bit and the same compare figures;
/// - the teapot writes positions twice (its patch seams): the same positions, and the normals
///   differ exactly at those positions (the OBJ reader smooths per `v` index, the glTF reader
///   across vertices at the same position, both documented);
/// - suzanne's quads: obj2gltf splits them along its own diagonals (earcut), so only the
///   triangle count, the positions and the file's normals are the same.
#[test]
fn gltf_from_obj2gltf_gives_the_statistics_of_its_obj() {
    let Some(tool) = obj2gltf() else { return };
    let Some(models) = models_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let mut identical = Vec::new();
    for name in ["spot", "fandisk", "stanford-bunny", "teapot", "suzanne"] {
        let obj = models.join(format!("{name}.obj"));
        let glb = dir.path().join(format!("{name}.glb"));
        convert(&tool, &obj, &glb, &[]);
        let (a, ra) = load(&obj);
        let (b, rb) = load(&glb);
        assert_eq!(a.triangle_count(), b.triangle_count(), "{name}");
        match name {
            "teapot" => {
                assert_eq!(a.positions, b.positions, "{name}");
                assert!(
                    ra.warnings
                        .iter()
                        .any(|w| w.contains("defined under more than one index")),
                    "{ra:?}"
                );
                // The normals at each position: one in the glTF (welded), two or more in the
                // OBJ exactly where the corners' normals differ.
                // Positions keyed as the reader welds them: -0 and +0 alike (the teapot writes
                // both, under different `v` indices).
                let key = |p: &[f32; 3]| p.map(|c| (c + 0.0).to_bits());
                let normals_at = |m: &Mesh| {
                    let mut at: HashMap<[u32; 3], HashSet<[u32; 3]>> = HashMap::new();
                    for (p, n) in m.positions.iter().zip(&m.normals) {
                        at.entry(key(p)).or_default().insert(n.map(f32::to_bits));
                    }
                    at
                };
                let (na, nb) = (normals_at(&a), normals_at(&b));
                assert!(
                    nb.values().all(|s| s.len() == 1),
                    "{name}: the glTF's normals are welded"
                );
                let differ: Vec<usize> = (0..a.normals.len())
                    .filter(|&i| a.normals[i] != b.normals[i])
                    .collect();
                assert!(
                    !differ.is_empty(),
                    "{name}: the OBJ splits its shading somewhere"
                );
                for i in differ {
                    assert!(na[&key(&a.positions[i])].len() >= 2, "{name}: corner {i}");
                }
                let _ = rb;
            }
            "suzanne" => {
                assert!(ra.had_quads_or_polygons && !ra.computed_normals && !rb.computed_normals);
                // The same positions; at each, the file's normal as obj2gltf normalised it in
                // f64 before rounding to f32 (the OBJ reader normalises the f32 value): equal
                // to a few f32 ulps.
                let pos = |m: &Mesh| -> HashSet<[u32; 3]> {
                    m.positions.iter().map(|p| p.map(f32::to_bits)).collect()
                };
                assert_eq!(pos(&a), pos(&b), "{name}: the same positions");
                let mut at: HashMap<[u32; 3], Vec<[f32; 3]>> = HashMap::new();
                for (p, n) in a.positions.iter().zip(&a.normals) {
                    at.entry(p.map(f32::to_bits)).or_default().push(*n);
                }
                let mut worst = 0f32;
                for (p, n) in b.positions.iter().zip(&b.normals) {
                    let closest = at[&p.map(f32::to_bits)]
                        .iter()
                        .map(|m| (0..3).map(|k| (m[k] - n[k]).abs()).fold(0.0, f32::max))
                        .fold(f32::INFINITY, f32::min);
                    worst = worst.max(closest);
                }
                assert!(worst < 1e-6, "{name}: normals {worst} apart");
            }
            _ => {
                assert_eq!(
                    (&a.positions, &a.normals),
                    (&b.positions, &b.normals),
                    "{name}"
                );
                identical.push((name, obj, glb));
            }
        }
    }
    // The compare figures of the identical ones, and spot's other two encodings.
    let spot = models.join("spot.obj");
    let embedded = dir.path().join("spot_embedded.gltf");
    convert(&tool, &spot, &embedded, &[]);
    let separate = dir.path().join("separate/spot.gltf");
    std::fs::create_dir_all(separate.parent().unwrap()).unwrap();
    convert(&tool, &spot, &separate, &["--separate"]);
    assert!(dir.path().join("separate/spot.bin").is_file());
    for (name, obj, glb) in &identical {
        let want = figures(obj, &dir.path().join(format!("{name}-obj")));
        let got = figures(glb, &dir.path().join(format!("{name}-glb")));
        assert_eq!(want, got, "{name}: compare figures of the OBJ and its glTF");
        if *name == "spot" {
            for g in [&embedded, &separate] {
                assert_eq!(
                    want,
                    figures(g, &dir.path().join("spot-gltf")),
                    "{}",
                    g.display()
                );
            }
        }
    }
    assert_eq!(identical.len(), 3, "spot, fandisk, stanford-bunny");
}

/// Without obj2gltf the test says SKIPPED, and fails under SHADELAB_REQUIRE_CONVERTERS=1.
#[test]
fn a_missing_converter_skips_visibly_and_fails_when_required() {
    let run = |require: &str| {
        rerun_test(
            "inputs::converted::gltf_from_obj2gltf_gives_the_statistics_of_its_obj",
            &[
                ("SHADELAB_OBJ2GLTF", "/nonexistent/obj2gltf".as_ref()),
                ("SHADELAB_REQUIRE_CONVERTERS", require.as_ref()),
            ],
        )
    };
    let skipped = run("0");
    let err = String::from_utf8_lossy(&skipped.stderr);
    assert!(skipped.status.success(), "{err}");
    assert!(err.contains("SKIPPED: inputs::converted::gltf_from_obj2gltf_gives_the_statistics_of_its_obj: no obj2gltf"), "{err}");
    assert!(
        !run("1").status.success(),
        "SHADELAB_REQUIRE_CONVERTERS=1 must fail without obj2gltf"
    );
}
