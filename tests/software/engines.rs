//! The software engine against the Vulkan pipeline and against its f64 twins on the shipped
//! scenes; kept targets; perspective refused.
use shadelab::method::{self, find, Geometry, METHODS};
use shadelab::scene::SceneInputs;
use shadelab::software::{self, render};
use shadelab::truth::{agreement, evaluate};
use shadelab::verify::verify_software;

use crate::support::*;

const SCENES: &[&str] = SHIPPED_SCENES;

/// Software phong_exact and Vulkan phong_exact on one scene: (coverage mismatches, covered
/// pixels, max |sw - vk| / (2 x the float32 bound of the f64 truth at Vulkan's weights),
/// non-finite software pixels).
fn sw_vs_vk(
    name: &str,
    size: u32,
    tamper: impl Fn(&mut shadelab::frame::Frame),
) -> (usize, usize, f64, usize) {
    let scene = shipped_scene(name, size);
    let exact = method::find("phong_exact").unwrap();
    let r = validated_renderer();
    let prepared = r.prepare(&scene, &[exact]).unwrap();
    let (vk, ids) = r
        .render(prepared.base(), shadelab::gpu::Shading::Method(exact), true)
        .unwrap();
    let truth = evaluate(&prepared.base().inputs, &ids.unwrap(), exact);
    let (mut sw, _) = software::render(&prepared.base().inputs, exact, 2, false).unwrap();
    tamper(&mut sw);
    let (mut mismatch, mut covered, mut ratio, mut non_finite) = (0, 0, 0.0f64, 0);
    for (i, t) in truth.pixels.iter().enumerate() {
        let (a, b) = (sw.color[i], vk.color[i]);
        if (a[3] > 0.0) != (b[3] > 0.0) {
            mismatch += 1;
            continue;
        }
        let Some(t) = t else { continue };
        covered += 1;
        if !a.iter().all(|x| x.is_finite()) {
            non_finite += 1;
            continue;
        }
        let d = (0..3)
            .map(|c| (a[c] as f64 - b[c] as f64).abs())
            .fold(0.0, f64::max);
        // Both are within the bound of the same f64 value (up to their weights' rounding):
        // they differ by at most twice it.
        ratio = ratio.max(d / (2.0 * t.color_bound));
    }
    (mismatch, covered, ratio, non_finite)
}

#[test]
fn software_phong_exact_agrees_with_vulkan_on_every_shipped_scene() {
    for name in SCENES {
        let (mismatch, covered, ratio, non_finite) = sw_vs_vk(name, 96, |_| {});
        println!("{name}: covered {covered}, coverage mismatches {mismatch}, colour diff / (2 bound) {ratio:.3}");
        assert_eq!(mismatch, 0, "{name}: pixels covered by one engine only");
        assert_eq!(non_finite, 0, "{name}");
        assert!(ratio <= 1.0, "{name}: colour ratio {ratio}");
    }
}

#[test]
fn the_engine_comparison_fails_on_a_wrong_pixel_a_hole_and_a_nan() {
    let first = |f: &shadelab::frame::Frame| f.color.iter().position(|c| c[3] > 0.0).unwrap();
    let (_, _, r, _) = sw_vs_vk("torus", 64, |f| {
        let i = first(f);
        f.color[i][0] += 1e-3;
    });
    assert!(r > 1.0, "a colour off by 1e-3 passed: {r}");
    let (m, ..) = sw_vs_vk("torus", 64, |f| {
        let i = first(f);
        f.color[i][3] = 0.0;
    });
    assert_eq!(m, 1, "a dropped pixel was not counted");
    let (.., nan) = sw_vs_vk("torus", 64, |f| {
        let i = first(f);
        f.color[i][1] = f32::NAN;
    });
    assert_eq!(nan, 1, "a NaN pixel was not counted");
}

#[test]
fn every_software_method_agrees_with_its_f64_twin_on_every_shipped_scene() {
    let all: Vec<_> = METHODS.iter().collect();
    for name in SCENES {
        let report = verify_software(&shipped_scene(name, 96), &all, None, 2).unwrap();
        assert!(
            report.passed(),
            "{name}: {}\n{}",
            report.failures().join("; "),
            report.table()
        );
    }
}

#[test]
fn the_twin_check_fails_for_another_method_and_for_a_nan() {
    // newton_raphson's image judged by phong_exact's formula must fail (sphere_coarse: vertex
    // normals ~20 degrees apart, so the length error is far above the float32 bound).
    let nr = method::find("newton_raphson").unwrap();
    let exact = method::find("phong_exact").unwrap();
    let report =
        verify_software(&shipped_scene("sphere_coarse", 64), &[nr], Some(exact), 2).unwrap();
    assert!(!report.passed(), "{}", report.table());
    // A NaN in an otherwise correct frame is counted and fails.
    let scene = shipped_scene("sphere_coarse", 64);
    let inputs = SceneInputs::new(&scene, exact.geometry);
    let (mut frame, ids) = software::render(&inputs, exact, 2, true).unwrap();
    let ids = ids.unwrap();
    let truth = evaluate(&inputs, &ids, exact);
    assert!(agreement(&frame, &truth).within_bound());
    let i = ids.prim.iter().position(|&p| p > 0).unwrap();
    frame.color[i][0] = f32::NAN;
    let a = agreement(&frame, &truth);
    assert_eq!(a.non_finite, 1);
    assert!(!a.within_bound());
}

#[test]
fn the_software_engine_refuses_perspective_with_a_clear_error() {
    let mut scene = shipped_scene("torus", 32);
    scene.interpolation = shadelab::scene::Interpolation::Perspective;
    let m = method::find("phong_exact").unwrap();
    let err = software::render(&SceneInputs::new(&scene, m.geometry), m, 1, false).unwrap_err();
    assert!(err.to_string().contains("screen-linearly only"), "{err}");
}

/// Kept targets: a draw clears them first, so gouraud drawn into the targets phong_exact left
/// gives exactly a fresh gouraud frame (without the clear every depth test would fail and the
/// phong_exact colours would stay); without a normal target the frame has no normals.
#[test]
fn kept_targets_are_cleared_by_each_draw() {
    let scene = shipped_scene("torus", 96);
    let inputs = SceneInputs::new(&scene, Geometry::Mesh);
    let (exact, gouraud) = (find("phong_exact").unwrap(), find("gouraud").unwrap());
    let (fresh, _) = render(&inputs, gouraud, 2, false).unwrap();
    let (phong, _) = render(&inputs, exact, 2, false).unwrap();
    let mut kept = software::Targets::new(96, 96, false, false);
    software::render_into(&inputs, exact, 2, &mut kept).unwrap();
    software::render_into(&inputs, gouraud, 2, &mut kept).unwrap();
    let (frame, ids) = kept.into_frames();
    assert!(ids.is_none() && frame.normal.is_empty());
    assert!(fresh.covered() > 1000);
    assert_eq!(
        frame.color, fresh.color,
        "kept targets differ from a fresh frame"
    );
    assert_ne!(
        phong.color, fresh.color,
        "teeth: the two methods draw different colours"
    );
    // A target of another size is refused.
    let mut small = software::Targets::new(64, 64, false, false);
    assert!(software::render_into(&inputs, exact, 1, &mut small).is_err());
}

/// The shared list of shipped scenes is every scene file of scenes/, no more, no less (a scene
/// added without the list would escape the software checks).
#[test]
fn the_shipped_scene_list_is_every_scene_file() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "toml").then(|| p.file_stem()?.to_str().map(str::to_string))?
        })
        .collect();
    files.sort();
    let mut listed: Vec<String> = SHIPPED_SCENES.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(
        files, listed,
        "tests/support.rs SHIPPED_SCENES against scenes/*.toml"
    );
    assert!(!listed.is_empty());
}
