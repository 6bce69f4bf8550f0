//! The software engine in float16 (issue 23): the kernels round every operation to binary16,
//! the float16 output agrees with the f64 twins within the float16 bound on every shipped
//! scene and shared model, and the checks fail on a wrong image.
use half::f16;
use shadelab::method::real::{Float, V3};
use shadelab::method::{find, Precision, METHODS};
use shadelab::scene::SceneInputs;
use shadelab::software::{self, render_at};
use shadelab::truth::{agreement_at, evaluate_at};
use shadelab::verify::{twin_agreement, verify_software_at};

use crate::support::*;

const SCENES: &[&str] = SHIPPED_SCENES;

/// x*x - 1 at x = 1 + 3 * 2^-10 (the lavapipe probe): in f16 x*x rounds to
/// 1 + 6 * 2^-10 before the subtraction; the expected value is that rounding done in f64.
#[test]
fn f16_arithmetic_rounds_every_operation() {
    let x64 = 1.0 + 3.0 * 2f64.powi(-10);
    let want = f16::from_f64(x64 * x64).to_f64() - 1.0;
    let x = <f16 as Float>::of(x64 as f32);
    let got = (x * x - <f16 as Float>::ONE).f32() as f64;
    assert_eq!(got, want);
    let x32 = x64 as f32;
    let f32_result = (x32 * x32 - 1.0) as f64;
    assert_ne!(
        got, f32_result,
        "f16 and f32 agree: the f16 type does not round"
    );
    // A three-vector's length overflows in f16 above sqrt(65504) ~ 256 (2 components: 181).
    let v = V3::<f16>::of(glam::Vec3::new(182.0, 182.0, 0.0));
    assert!(v.dot(v).f32().is_infinite());
    let w = V3::<f32>::of(glam::Vec3::new(182.0, 182.0, 0.0));
    assert!(w.dot(w).is_finite());
}

/// Every colour and normal the f16 engine writes is a binary16 value (it went through f16;
/// Gouraud's vertex colours are stepped in f32 like any varying, so only its normals count),
/// and the f16 frame differs from the f32 one.
#[test]
fn f16_frames_hold_binary16_values_and_differ_from_f32() {
    let scene = shipped_scene("sphere_coarse", 64);
    for m in METHODS {
        let inputs = SceneInputs::new(&scene, m.geometry);
        let (h, _) = render_at(&inputs, m, 2, false, Precision::F16).unwrap();
        let (s, _) = render_at(&inputs, m, 2, false, Precision::F32).unwrap();
        let is_half = |v: f32| !v.is_finite() || f16::from_f32(v).to_f32() == v;
        let colours = if matches!(m.kernel, shadelab::method::Kernel::VertexColour) {
            &[][..]
        } else {
            &h.color[..]
        };
        assert!(
            colours
                .iter()
                .chain(&h.normal)
                .flatten()
                .all(|&v| is_half(v)),
            "{}: a value that is not binary16",
            m.name
        );
        assert_ne!(h.color, s.color, "{}: f16 and f32 frames equal", m.name);
    }
}

/// Every method's float16 image within the float16 bound of its own f64 formula on every
/// shipped scene (the list of known failures is empty since half23: dichotomy's grid index from
/// the float32 t, the corner normals' rounding at u = 2^-11 in the bound, the twin's drift).
#[test]
fn every_software_f16_method_agrees_with_its_f64_twin_on_every_shipped_scene() {
    let all: Vec<_> = METHODS.iter().collect();
    for name in SCENES {
        let scene = shipped_scene(name, 96);
        let report = verify_software_at(&scene, &all, None, 2, Precision::F16).unwrap();
        println!("{}", report.table());
        assert!(
            report.passed(),
            "{name}: {}\n{}",
            report.failures().join("; "),
            report.table()
        );
    }
}

#[test]
fn the_f16_check_fails_for_another_method_an_f32_bound_and_a_nan() {
    let scene = shipped_scene("sphere_coarse", 64);
    // flat judged by phong_exact's formula (newton_raphson's 1.4 % length error on this
    // sphere stays inside the float16 bound: dN/bound 0.77).
    let flat = find("flat").unwrap();
    let exact = find("phong_exact").unwrap();
    let wrong = verify_software_at(&scene, &[flat], Some(exact), 2, Precision::F16).unwrap();
    assert!(!wrong.passed(), "{}", wrong.table());
    // The f16 image judged by the float32 bound fails: the f16 bound is not vacuous, and the
    // f32 one is too tight for f16 rounding.
    let inputs = SceneInputs::new(&scene, exact.geometry);
    let (mut frame, ids) = render_at(&inputs, exact, 2, true, Precision::F16).unwrap();
    let ids = ids.unwrap();
    let f16_truth = evaluate_at(&inputs, &ids, exact, Precision::F16);
    let f32_truth = evaluate_at(&inputs, &ids, exact, Precision::F32);
    assert!(agreement_at(&frame, &f16_truth, Precision::F16).within_bound());
    assert!(!agreement_at(&frame, &f32_truth, Precision::F16).within_bound());
    // A NaN is a failure, never zero error.
    let i = ids.prim.iter().position(|&p| p > 0).unwrap();
    frame.color[i][0] = f32::NAN;
    let a = agreement_at(&frame, &f16_truth, Precision::F16);
    assert_eq!(a.non_finite, 1);
    assert!(!a.within_bound());
}

/// The device-against-twin check of `verify --precision f16` on Vulkan, run on two software
/// images (the device's f16 programs arrive with half23's branch): the twin against itself
/// agrees exactly, the float32 image is within twice the float16 bound of it, and a pixel off
/// by 10, or NaN, fails.
#[test]
fn the_twin_check_passes_its_own_image_and_fails_a_wrong_pixel() {
    let scene = shipped_scene("torus", 64);
    let exact = find("phong_exact").unwrap();
    let inputs = SceneInputs::new(&scene, exact.geometry);
    let (twin, ids) = render_at(&inputs, exact, 2, true, Precision::F16).unwrap();
    let truth = evaluate_at(&inputs, &ids.unwrap(), exact, Precision::F16);
    let same = twin_agreement(&twin, &twin, &truth, &truth);
    assert!(
        same.within_bound() && same.max_color_error == 0.0,
        "{same:?}"
    );
    let (f32_frame, _) = render_at(&inputs, exact, 2, false, Precision::F32).unwrap();
    assert!(twin_agreement(&f32_frame, &twin, &truth, &truth).within_bound());
    let i = twin.color.iter().position(|c| c[3] > 0.0).unwrap();
    let mut off = twin.clone();
    off.color[i][1] += 10.0;
    assert!(!twin_agreement(&off, &twin, &truth, &truth).within_bound());
    off.color[i][1] = f32::NAN;
    assert_eq!(twin_agreement(&off, &twin, &truth, &truth).non_finite, 1);
}

/// The float16 drift allowance is the float32 one scaled by the unit roundoffs (2^13).
#[test]
fn drift_allowance_follows_the_unit_roundoff() {
    let (a, b) = (
        software::drift_allowance_at(10.0, Precision::F32),
        software::drift_allowance_at(10.0, Precision::F16),
    );
    assert_eq!(
        b / a,
        Precision::F16.unit_roundoff() / Precision::F32.unit_roundoff()
    );
    assert_eq!(a, software::drift_allowance(10.0));
}

#[test]
fn software_f16_verify_passes_on_every_shared_model() {
    let Some(dir) = models_dir() else { return };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "obj"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .obj in {}", dir.display());
    let all: Vec<_> = METHODS.iter().collect();
    for f in &files {
        let mut s = shadelab::scene::scene_for_mesh(f).unwrap_or_else(|e| panic!("{e}"));
        (s.width, s.height) = (128, 128);
        let report = verify_software_at(&s, &all, None, 2, Precision::F16).unwrap();
        println!("{} at 128:\n{}", f.display(), report.table());
        assert!(
            report.passed(),
            "{}: {}\n{}",
            f.display(),
            report.failures().join("; "),
            report.table()
        );
    }
}
