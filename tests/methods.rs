//! Every method against its own f64 formula on the GPU, the teeth of that check (swapped
//! shaders fail, except the stated pairs, which are checked to pass), and the papers' error
//! bounds measured on the GPU. The real-world meshes are in tests/models.rs.
use shadelab::frame::{Frame, IdFrame};
use shadelab::gpu::{Renderer, Shading};
use shadelab::method::{self, Method, METHODS};
use shadelab::scene::{self, Scene};
use shadelab::truth;

use crate::support::*;

fn all() -> Vec<&'static Method> {
    METHODS.iter().collect()
}

/// Renders every method of `scene` with its id pass.
fn render_all(r: &Renderer, scene: &Scene) -> Vec<(&'static Method, Frame, IdFrame, truth::Truth)> {
    let prepared = r.prepare(scene, &all()).unwrap();
    METHODS
        .iter()
        .map(|m| {
            let gpu = prepared.for_method(m);
            let (frame, ids) = r.render(gpu, Shading::Method(m), true).unwrap();
            let ids = ids.unwrap();
            let own = truth::evaluate(&gpu.inputs, &ids, m);
            (m, frame, ids, own)
        })
        .collect()
}

/// Check 2 of the issue: the GPU image (colour and shading normal) of every method agrees
/// with its own formula in f64 at the rasterizer's weights, within the float32 bound of
/// src/truth.rs, on the coarse sphere (36 deg between neighbouring normals) and the icosphere
/// (63 deg).
#[test]
fn every_method_agrees_with_its_f64_formula() {
    let r = validated_renderer();
    for name in ["sphere_coarse", "icosphere"] {
        let scene = shipped_scene(name, 96);
        for (m, frame, _, own) in render_all(&r, &scene) {
            let a = truth::agreement(&frame, &own);
            eprintln!(
                "{name} {}: ratio {:.3} / {:.3}, {a:?}",
                m.name, a.max_color_ratio, a.max_normal_ratio
            );
            assert!(
                a.within_bound(),
                "{name}: {} outside its float32 bound: {a:?}",
                m.name
            );
            assert!(
                a.covered > 2000,
                "{name}: {} covers only {} pixels",
                m.name,
                a.covered
            );
        }
    }
    assert_validation_clean(r.context());
}

/// Pairs that check 2 cannot tell apart on the symmetric shipped icosphere (large triangles, vertex
/// normals 63 degrees apart: long spans, so the scanline methods' quantisation shows), each for a
/// reason:
/// - gouraud / trueform: the same Gouraud formula (trueform only changes the geometry);
/// - phong_exact / specular_lut: the 4096-sample table's interpolation error (<= 1.8e-5 at n = 50,
///   formulas tests) lies below the float32 bound;
/// - hast_half_vector / quaternion_local: quaternion_local's q is normalize(n + N_i), so it is
///   Hast's reflection with per-vertex normalised half vectors; the two coincide when a triangle's
///   corners sit at equal angles from its flat normal (true on these spheres;
///   `hast_and_local_quaternion_differ_on_irregular_meshes` shows they differ elsewhere);
/// - slerp / spherical_angular: the same function
///   (docs/formulas.md#spherical-angular-interpolation: the closed form equals slerp to 4e-16 in
///   f64), two float computations of it;
const EQUIVALENT_HERE: [(&str, &str); 9] = [
    ("gouraud", "trueform"),
    ("phong_exact", "specular_lut"),
    // the guards (issue 23) are exact normalisation wherever 2^-14 <= N.N <= 65504: all of a
    // shipped scene's pixels
    ("phong_exact", "safe_normalize"),
    ("phong_exact", "filament_clamp"),
    ("safe_normalize", "filament_clamp"),
    ("safe_normalize", "specular_lut"),
    ("filament_clamp", "specular_lut"),
    ("hast_half_vector", "quaternion_local"),
    ("slerp", "spherical_angular"),
];

/// One-way passes: the first method's image passes the second's formula, and not the reverse
/// (checked). segments_k3_poly2's bound is wide where its 8-pixel segment reaches far past a
/// short span (the extrapolated end moves a lot when a corner moves by its rounding), and
/// segments_k2_poly2 (exact Phong at 4-pixel segment ends, slerp to 2e-5 between) differs from
/// it by less there; elsewhere the two differ by up to 0.018 and the reverse check fails.
const ONE_WAY_HERE: [(&str, &str); 1] = [("segments_k2_poly2", "segments_k3_poly2")];

fn equivalent(a: &str, b: &str) -> bool {
    EQUIVALENT_HERE
        .iter()
        .any(|&(x, y)| (x, y) == (a, b) || (x, y) == (b, a))
}

/// Check 3 (teeth): judging a method's image by any other method's formula fails.
#[test]
fn swapping_shaders_fails_the_check() {
    let r = validated_renderer();
    let scene = shipped_scene("icosphere", 96);
    let prepared = r.prepare(&scene, &all()).unwrap();
    let rendered = render_all(&r, &scene);
    let mut passed_as = Vec::new();
    for (m, frame, ids, _) in &rendered {
        for other in METHODS
            .iter()
            .filter(|o| o.name != m.name && o.geometry == m.geometry)
        {
            let a = truth::agreement(
                frame,
                &truth::evaluate(&prepared.for_method(m).inputs, ids, other),
            );
            let one_way = ONE_WAY_HERE.contains(&(m.name, other.name));
            if a.within_bound() && !equivalent(m.name, other.name) && !one_way {
                passed_as.push(format!(
                    "{} passed as {} (ratio {:.3})",
                    m.name, other.name, a.max_color_ratio
                ));
            }
        }
    }
    assert!(
        passed_as.is_empty(),
        "check 2 cannot tell these apart:\n{}",
        passed_as.join("\n")
    );
    // ... and the stated pairs do pass as each other, both ways (gouraud / trueform differ in
    // geometry, so the loop above never judges them: each image is judged on its own inputs)
    let judge = |x: &str, y: &str| {
        let (m, frame, ids, _) = rendered.iter().find(|(m, ..)| m.name == x).unwrap();
        let other = method::find(y).unwrap();
        truth::agreement(
            frame,
            &truth::evaluate(&prepared.for_method(m).inputs, ids, other),
        )
    };
    let mut not_equivalent = Vec::new();
    for (a, b) in EQUIVALENT_HERE {
        for (x, y) in [(a, b), (b, a)] {
            let ag = judge(x, y);
            if !ag.within_bound() {
                not_equivalent.push(format!("{x} judged as {y}: {ag:?}"));
            }
        }
    }
    for (x, y) in ONE_WAY_HERE {
        let reverse = judge(y, x);
        if reverse.within_bound() {
            not_equivalent.push(format!("{y} passes as {x} too: list them as equivalent"));
        }
    }
    assert!(
        not_equivalent.is_empty(),
        "EQUIVALENT_HERE lists pairs that do not pass as each other:\n{}",
        not_equivalent.join("\n")
    );
}

#[test]
fn hast_and_local_quaternion_differ_on_irregular_meshes() {
    let Some(dir) = models_dir() else { return };
    let r = validated_renderer();
    let mut s = scene::scene_for_mesh(&dir.join("suzanne.obj")).unwrap();
    s.width = 96;
    s.height = 96;
    let hast = method::find("hast_half_vector").unwrap();
    let local = method::find("quaternion_local").unwrap();
    let prepared = r.prepare(&s, &[hast, local]).unwrap();
    let gpu = prepared.base();
    let (frame, ids) = r.render(gpu, Shading::Method(hast), true).unwrap();
    let ids = ids.unwrap();
    assert!(truth::agreement(&frame, &truth::evaluate(&gpu.inputs, &ids, hast)).within_bound());
    let swapped = truth::agreement(&frame, &truth::evaluate(&gpu.inputs, &ids, local));
    assert!(
        !swapped.within_bound() && swapped.max_color_ratio > 10.0,
        "{swapped:?}"
    );
}

/// Check 4: the error bounds the papers claim, measured on the GPU against f64 exact Phong
/// (ill-conditioned sliver pixels left out, see shadelab::analysis::pixel::ErrorStats).
#[test]
fn papers_error_bounds_hold_on_the_gpu() {
    let r = validated_renderer();
    for name in ["sphere_coarse", "icosphere"] {
        let scene = shipped_scene(name, 96);
        let stats = errors_against_exact(&r, &scene);
        let get = |n: &str| {
            stats
                .iter()
                .find(|(m, _)| *m == n)
                .map(|(_, s)| s.clone())
                .unwrap()
        };
        // Mikami: normalised relative error <= 1.5 % for z in [0.25, 1]
        // (docs/formulas.md#mikami-square-root); every pixel of these meshes has
        // z >= (1 + 2 cos 63.4 deg)/3 = 0.63.
        for m in ["mikami_const", "mikami_linear", "mikami_quadratic"] {
            let e = get(m).max_normal_length_error.unwrap();
            eprintln!("{name} {m}: max ||N'| - 1| = {e:.5}");
            assert!(
                e <= 0.015,
                "{name}: {m} length error {e} above the paper's 1.5 %"
            );
        }
        // Hast and the quaternion methods need no square root and give unit normals exactly
        // (up to float32 rounding).
        for m in ["hast_half_vector", "quaternion", "quaternion_local"] {
            let e = get(m).max_normal_length_error.unwrap();
            assert!(e < 1e-5, "{name}: {m} is not unit length: {e}");
        }
        // Scalar methods only scale the normal: zero angular error
        // (docs/formulas.md#error-measures).
        for m in [
            "newton_raphson",
            "lyon_taylor",
            "lyon_shift",
            "mikami_quadratic",
            "romanyuk_poly",
        ] {
            let a = get(m).max_normal_angle_deg.unwrap();
            assert!(a < 0.01, "{name}: {m} turns the normal by {a} deg");
        }
        // phong_exact against its own truth: the float32 level.
        assert!(get("phong_exact").max_abs_error < 1e-4);
        if name == "sphere_coarse" {
            // Romanyuk's "8x smaller than Lyon"
            // (docs/formulas.md#romanyuk-romanyuk-pavlyk-polynomial) does not hold where
            // neighbouring normals are less than 60 deg apart (formulas tests): on the coarse
            // sphere (36 deg) Romanyuk's length error exceeds both Lyon forms'. Pinned here on the
            // GPU.
            let len = |n: &str| get(n).max_normal_length_error.unwrap();
            assert!(
                len("romanyuk_poly") > len("lyon_taylor")
                    && len("romanyuk_poly") > len("lyon_shift")
            );
        }
    }
    assert_validation_clean(r.context());
}

/// Every method's error statistics against f64 exact Phong on `scene`.
fn errors_against_exact(
    r: &Renderer,
    scene: &Scene,
) -> Vec<(&'static str, shadelab::analysis::pixel::ErrorStats)> {
    let rendered = render_all(r, scene);
    let (exact, _, exact_ids, _) = rendered
        .iter()
        .find(|(m, ..)| m.name == "phong_exact")
        .unwrap();
    let prepared = r.prepare(scene, &[*exact]).unwrap();
    let reference = truth::evaluate(&prepared.base().inputs, exact_ids, exact);
    rendered
        .iter()
        .map(|(m, frame, ..)| {
            (
                m.name,
                shadelab::analysis::pixel::error_stats(frame, m.has_normal, &reference),
            )
        })
        .collect()
}
