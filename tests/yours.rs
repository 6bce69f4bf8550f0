//! Issue 28, `--method-file`: the examples of docs/examples/methods/ through compare, stress,
//! isa and report (each under the validation layer where the command has it); two Newton steps
//! more accurate than one; the bit trick's relative error on the device against its known
//! figure within the float32 bound; the refusals (a syntax error at its file and line, an
//! undeclared input, a clashing id, verify without a twin), each with exit 2.
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::support::*;

const EXAMPLES: [&str; 3] = ["newton_two_steps", "fast_inv_sqrt", "guarded_normalize"];

fn example(name: &str) -> PathBuf {
    root()
        .join("docs/examples/methods")
        .join(format!("{name}.glsl"))
}

/// `--method-file F` for every example.
fn method_files() -> Vec<String> {
    EXAMPLES
        .iter()
        .flat_map(|n| {
            [
                "--method-file".to_string(),
                example(n).display().to_string(),
            ]
        })
        .collect()
}

fn run_ok(args: &[String]) -> String {
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, out, err) = run(&a);
    assert_eq!(code, 0, "{args:?}\n{out}\n{err}");
    out
}

fn args(fixed: &[&str], out: &Path) -> Vec<String> {
    let mut a: Vec<String> = fixed.iter().map(|s| s.to_string()).collect();
    a.extend(method_files());
    a.extend(["--out".to_string(), out.display().to_string()]);
    a
}

/// The run's JSON names every example's file and its SHA-256 (computed here from the file).
fn assert_names_the_files(files: &serde_json::Value) {
    let files = files.as_array().expect("method_files");
    for n in EXAMPLES {
        let f = files.iter().find(|f| f["name"] == n).expect(n);
        let sha: String = Sha256::digest(std::fs::read(example(n)).unwrap())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(f["sha256"], sha.as_str(), "{n}");
        assert!(f["path"].as_str().unwrap().ends_with(&format!("{n}.glsl")));
    }
}

#[test]
fn examples_through_compare_two_newton_steps_beat_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let methods = format!("newton_raphson,phong_exact,{}", EXAMPLES.join(","));
    run_ok(&args(
        &[
            "compare",
            "--validate",
            "--scene",
            "scenes/sphere_coarse.toml",
            "--size",
            "96x96",
            "--methods",
            &methods,
        ],
        &out,
    ));
    let s = read_json(out.join("summary.json"));
    assert_schema(&s, "docs/summary.schema.json", "/methods/0", "name");
    assert_names_the_files(&s["provenance"]["method_files"]);
    let get = |n: &str| {
        s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap_or_else(|| panic!("{n} not in summary.json"))
            .clone()
    };
    let max = |n: &str| get(n)["max_abs_error"].as_f64().unwrap();
    for n in EXAMPLES {
        let m = get(n);
        assert_eq!(m["non_finite_pixels"], 0, "{n}");
        assert!(m["covered_pixels"].as_u64().unwrap() > 1000, "{n}");
        assert!(out.join(n).is_dir(), "{n}: no heatmaps");
    }
    // Quadratic convergence: the second step squares the first one's relative error.
    let (one, two) = (max("newton_raphson"), max("newton_two_steps"));
    assert!(
        two < one / 4.0,
        "two Newton steps {two:e} are not more accurate than one {one:e}"
    );
    // The guarded normalize is exact normalisation wherever N.N > tiny: phong_exact's error, up
    // to float32 rounding (phong_exact's own largest error here is ~4e-6, a few ulps of the
    // colour; 1e-5 allows the two programs' different rounding).
    let (g, e) = (max("guarded_normalize"), max("phong_exact"));
    assert!((g - e).abs() <= 1e-5, "guarded {g:e} vs exact {e:e}");
}

#[test]
fn examples_through_stress_judged_against_exact_phong_without_a_twin() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    let methods = format!("newton_raphson,{}", EXAMPLES.join(","));
    let text = run_ok(&args(
        &[
            "stress",
            "--validate",
            "--methods",
            &methods,
            "--refine",
            "1",
        ],
        &out,
    ));
    let r = read_json(out.join("stress.json"));
    assert_schema(&r, "docs/stress.schema.json", "/methods/0", "name");
    assert_names_the_files(&r["provenance"]["method_files"]);
    let get = |n: &str| {
        r["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()
            .clone()
    };
    for n in EXAMPLES {
        let m = get(n);
        assert_eq!(m["own_formula"], "no twin", "{n}");
        assert!(m["device_evaluated"].as_bool().unwrap(), "{n}");
        assert!(m["worst_abs_error_f64"].is_null(), "{n}");
        assert!(m["worst_finite_abs_error"].as_f64().unwrap().is_finite());
        assert!(m["worst_case"]["f64_color"].is_null(), "{n}");
        assert!(m["worst_case"]["exact_phong"].is_array(), "{n}");
    }
    // A built-in method keeps its twin.
    assert!(get("newton_raphson").get("own_formula").is_none());
    assert!(get("newton_raphson")["worst_abs_error_f64"].is_number());
    assert!(text
        .lines()
        .any(|l| l.starts_with("fast_inv_sqrt") && l.contains("no twin")));
    // Its worst case replays on the device; the f64 line says there is no twin.
    let mut replay = vec![
        "stress".to_string(),
        "--replay".into(),
        out.join("cases/fast_inv_sqrt.json").display().to_string(),
    ];
    replay.extend(method_files());
    let text = run_ok(&replay);
    assert!(
        text.contains("f64      no twin")
            && text.contains("error    device ")
            && text.contains("f64 no twin"),
        "{text}"
    );
    // Without the file, the method is unknown (the env of this test holds no method files).
    let (code, _, err) = run(&["stress", "--methods", "fast_inv_sqrt", "--out", "x"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown method \"fast_inv_sqrt\""), "{err}");
}

#[test]
fn examples_through_isa_per_family() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("i");
    let methods = EXAMPLES.join(",");
    run_ok(&args(
        &["isa", "--methods", &methods, "--families", "navi21,gfx1100"],
        &out,
    ));
    let r = read_json(out.join("isa.json"));
    assert_schema(&r, "docs/isa.schema.json", "", "results");
    assert_names_the_files(&r["method_files"]);
    let rows = r["results"].as_array().unwrap();
    for family in ["amd:navi21", "amd:gfx1100"] {
        for n in EXAMPLES {
            let cost = |kind: &str| {
                rows.iter()
                    .find(|x| x["family"] == family && x["method"] == n && x["kind"] == kind)
                    .and_then(|x| x["statistics"]["inverse_throughput"].as_f64())
            };
            assert!(cost("draw").is_some_and(|c| c > 0.0), "{family} {n} draw");
        }
    }
}

#[test]
fn examples_through_report_compete_in_the_answer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let methods = format!("newton_raphson,{}", EXAMPLES.join(","));
    run_ok(&args(
        &[
            "report",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "32x32",
            "--runs",
            "2",
            "--methods",
            &methods,
            "--validate",
        ],
        &out,
    ));
    let a = read_json(out.join("answer.json"));
    assert_schema(&a, "docs/answer.schema.json", "", "cells");
    for n in EXAMPLES {
        assert!(
            a["checks"]
                .as_array()
                .unwrap()
                .iter()
                .any(|c| c["method"] == n),
            "{n} is not checked against the budgets"
        );
        let frame = a["cost_models"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == "lavapipe_frame")
            .expect("the lavapipe frame-time model");
        assert!(
            frame["figures"]
                .as_array()
                .unwrap()
                .iter()
                .any(|f| f["method"] == n && f["ratio"].is_number()),
            "{n} has no frame-time ratio"
        );
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for n in EXAMPLES {
        assert!(html.contains(n), "{n} not on the page");
    }
}

/// The bit trick (0x5f3759df, one Newton step) has a largest relative error of 0.175 % (Lomont
/// 2003: 0.00175228, measured in float32). Its f64 emulation (the same integer guess, the Newton
/// step in f64) over every float32 z in [1/4, 4) must find that figure within float32's bound,
/// and the device's relative length error, on cases around the argmax and over a sweep, must
/// match the emulation case by case within the bound.
#[test]
fn the_bit_trick_error_is_its_known_figure_within_the_bound() {
    use shadelab::gpu::evaluate::{GpuCase, Kernel};
    shadelab::gpu::shaders::register_user(&[example("fast_inv_sqrt")]).unwrap();
    let m = shadelab::method::find("fast_inv_sqrt").unwrap();
    // The float32 bound of a float32 evaluation against the f64 emulation at the same z: the
    // Newton step z y, (z y) y, 1.5 - b/2, y d and the product N y round 5 times, each <= u
    // relative to a value of order 1 (b/2 ~ 1/2 enters 1.5 - b/2 ~ 1 with weight 1/2 < 1); the
    // f64 length and emulation add < 1e-15. Lomont's figure carries it too (float32).
    let u = f64::from(f32::EPSILON) / 2.0;
    let bound = 5.0 * u;
    const KNOWN: f64 = 0.00175228;
    let guess = |z: f32| f32::from_bits(0x5f3759df_u32.wrapping_sub(z.to_bits() >> 1)) as f64;
    let emulated = |z: f32| {
        let y = guess(z);
        let y = y * (1.5 - 0.5 * z as f64 * y * y);
        y * (z as f64).sqrt() - 1.0
    };
    let mut worst = (0.0f64, 0.25f32);
    let mut z = 0.25f32;
    while z < 4.0 {
        let e = emulated(z).abs();
        if e > worst.0 {
            worst = (e, z);
        }
        z = f32::from_bits(z.to_bits() + 1);
    }
    assert!(
        (worst.0 - KNOWN).abs() <= bound,
        "emulated max {} at z = {} vs the known {KNOWN} (bound {bound:e})",
        worst.0,
        worst.1
    );
    // Device cases: |N| = s, s around sqrt(argmax) (every float32 within 256 steps) and a sweep.
    let s0 = (worst.1 as f64).sqrt() as f32;
    let mut lengths: Vec<f32> = (0..512u32)
        .map(|k| f32::from_bits(s0.to_bits() - 256 + k))
        .collect();
    lengths.extend((0..4096).map(|k| 0.5 + 1.5 * k as f32 / 4096.0));
    let frag = |s: f32| shadelab::method::Fragment {
        weights: glam::DVec3::new(1.0, 0.0, 0.0),
        pixel: glam::DVec2::new(0.5, 0.5),
        window: [glam::DVec2::ZERO, glam::DVec2::X, glam::DVec2::Y],
        corner_normals: [glam::DVec3::Z * s as f64, glam::DVec3::Z, glam::DVec3::Z],
        flat_normal: glam::DVec3::Z,
        pn_mids: [glam::DVec3::Z; 3],
    };
    let h = glam::DVec3::new(0.0, 0.6, 0.8);
    let lit = shadelab::method::formulas::Lighting::new(
        glam::DVec3::splat(0.1),
        glam::DVec3::splat(0.6),
        glam::DVec3::splat(0.3),
        20.0,
        &[(h, glam::DVec3::ONE, h)],
    );
    let cases: Vec<GpuCase> = lengths
        .iter()
        .map(|&s| GpuCase::new(&frag(s), &lit).unwrap())
        .collect();
    let r = validated_renderer();
    let out = Kernel::new(r.context(), m).unwrap().run(&cases).unwrap();
    assert_validation_clean(r.context());
    let mut device_max = 0.0f64;
    for (s, o) in lengths.iter().zip(&out) {
        let n = o.normal.expect("a normal");
        let len = n
            .iter()
            .map(|&c| (c as f64) * (c as f64))
            .sum::<f64>()
            .sqrt();
        // The result is N y with |N| = s: its length is s y, 1 + the relative error of y.
        let dev = len - 1.0;
        let want = emulated(s * s);
        assert!(
            (dev - want).abs() <= bound,
            "s = {s}: device {dev:e}, emulation {want:e}, bound {bound:e}"
        );
        device_max = device_max.max(dev.abs());
    }
    // The device's rounding and the known figure's, each within the bound.
    assert!(
        (device_max - KNOWN).abs() <= 2.0 * bound,
        "device max {device_max} vs the known {KNOWN} (bound {bound:e})"
    );
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn refusals_exit_2_naming_the_file_line_input_or_method() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("o").display().to_string();
    let compare = |file: &str| {
        run(&[
            "compare",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "16x16",
            "--method-file",
            file,
            "--out",
            &out,
        ])
    };
    // A syntax error: shaderc's message at the user's file and line.
    let bad = write(
        d,
        "broken.glsl",
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    return R3(vNormal) +;\n}\n",
    );
    let (code, _, err) = compare(&bad);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("{bad}:3: error")), "{err}");
    // The same file fixed compiles (the refusal is the syntax error's).
    let good = write(
        d,
        "fixed.glsl",
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    return R3(vNormal);\n}\n",
    );
    let (code, _, err) = run(&["list", "--method-file", &good]);
    assert_eq!(code, 0, "{err}");
    // An input used but not declared: named, with the line to write.
    let undeclared = write(
        d,
        "uses_flat.glsl",
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    return normalize(R3(vNormal) + R3(vFlat));\n}\n",
    );
    let (code, _, err) = compare(&undeclared);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("flat_normal")
            && err.contains("// shadelab-inputs: interpolated_normal, flat_normal"),
        "{err}"
    );
    // A clashing id: the stem of a built-in method.
    let clash = write(
        d,
        "phong_exact.glsl",
        &std::fs::read_to_string(&good).unwrap(),
    );
    let (code, _, err) = compare(&clash);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("built-in") && err.contains("phong_exact"),
        "{err}"
    );
    // Two files with one stem.
    let sub = d.join("sub");
    std::fs::create_dir(&sub).unwrap();
    let twice = write(&sub, "fixed.glsl", &std::fs::read_to_string(&good).unwrap());
    let (code, _, err) = run(&["list", "--method-file", &good, "--method-file", &twice]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("also the id of"), "{err}");
    // An unknown input name lists the valid ones.
    let unknown = write(
        d,
        "unknown_input.glsl",
        "// shadelab-inputs: normals\nreal3 methodNormal() { return R3(vNormal); }\n",
    );
    let (code, _, err) = compare(&unknown);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("\"normals\"") && err.contains("interpolated_normal"),
        "{err}"
    );
    // Plain float32 code: float32 programs, none in float16 (a warning; a float16 run refuses it).
    let float_only = write(
        d,
        "float_only.glsl",
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    vec3 n = vNormal;\n    return n * inversesqrt(dot(n, n));\n}\n",
    );
    let (code, _, err) = run(&["list", "--method-file", &float_only]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("no float16 programs"), "{err}");
    let f16 = |precision: &str| {
        run(&[
            "compare",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "16x16",
            "--method-file",
            &float_only,
            "--methods",
            "float_only",
            "--precision",
            precision,
            "--out",
            &out,
        ])
    };
    let (code, _, err) = f16("f16");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("float_only has no float16 programs"), "{err}");
    let (code, _, err) = f16("f32");
    assert_eq!(code, 0, "{err}");
    // verify needs a twin: exit 2 naming the method.
    let (code, _, err) = run(&[
        "verify",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "16x16",
        "--method-file",
        &good,
        "--methods",
        "fixed",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("fixed is a user method"), "{err}");
    // ... and the software engine, which has no kernel for it.
    let (code, _, err) = run(&[
        "render",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "16x16",
        "--engine",
        "software",
        "--method-file",
        &good,
        "--method",
        "fixed",
        "--out",
        &d.join("x.png").display().to_string(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("fixed is a user method"), "{err}");
}
