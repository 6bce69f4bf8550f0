//! The software engine (src/software/) against the Vulkan pipeline and against the f64 twins.
use shadelab::method::{self, METHODS};
use shadelab::scene::SceneInputs;
use shadelab::software;
use shadelab::truth::{agreement, evaluate};
use shadelab::verify::verify_software;

use glam::{DVec2, DVec3};
use shadelab::method::{find, Geometry};
use shadelab::scene::{Interpolation, Params, MAX_LIGHTS};
use shadelab::software::{drift_allowance, render};

use crate::support::*;

const SCENES: &[&str] = &[
    "cube",
    "icosphere",
    "sphere_coarse",
    "sphere_fine",
    "torus",
    "torus_generated",
];

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

/// One triangle across a `w`-pixel-wide image whose rows are spans of up to ~w pixels, with
/// vertex normals `deg` degrees apart; identity MVP (positions are NDC).
fn long_spans(w: u32, deg: f64) -> SceneInputs {
    let h = 8u32;
    let ndc = |x: f64, y: f64| {
        [
            (2.0 * x / w as f64 - 1.0) as f32,
            (2.0 * y / h as f64 - 1.0) as f32,
            0.5,
        ]
    };
    let positions = vec![
        ndc(0.2, 0.1),
        ndc(w as f64 - 0.3, 0.2),
        ndc(0.4, h as f64 - 0.1),
    ];
    let r = deg.to_radians() / 2.0;
    let n = |a: f64, b: f64| {
        let v = DVec3::new(a.sin(), b.sin(), a.cos() * b.cos()).normalize();
        [v.x as f32, v.y as f32, v.z as f32]
    };
    let mut identity = [[0.0f32; 4]; 4];
    (0..4).for_each(|i| identity[i][i] = 1.0);
    let l = DVec3::new(0.3, 0.2, 1.0).normalize();
    let hv = (l + DVec3::Z).normalize();
    let f4 = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
    let mut params = Params {
        mvp: identity,
        ambient: [0.05, 0.05, 0.05, 0.0],
        diffuse: [0.7, 0.7, 0.7, 0.0],
        specular: [0.3, 0.3, 0.3, 20.0],
        light_dir: [[0.0; 4]; MAX_LIGHTS],
        light_color: [[0.0; 4]; MAX_LIGHTS],
        half_vec: [[0.0; 4]; MAX_LIGHTS],
        const_color: [0.8, 0.8, 0.8, 1.0],
    };
    params.light_dir[0] = f4(l);
    params.half_vec[0] = f4(hv);
    params.light_color[0] = [1.0, 1.0, 1.0, 0.0];
    let mut inputs = SceneInputs {
        width: w,
        height: h,
        interpolation: Interpolation::ScreenLinear,
        geometry: Geometry::Mesh,
        positions,
        view_normals: vec![n(-r, 0.0), n(r, 0.0), n(-r, 0.3)],
        flat_normals: vec![[0.0, 0.0, 1.0]],
        pn_mids: vec![[[0.0, 0.0, 1.0]; 3]],
        window: Vec::new(),
        params,
        light_count: 1,
        cull_front: None,
    };
    inputs.window = inputs
        .clip_corners()
        .map(|c| {
            let p: DVec2 = inputs.to_window(c);
            [p.x as f32, p.y as f32]
        })
        .collect();
    inputs
}

/// Largest |software - f64 twin| (normal components, or colour channels for methods without a
/// normal) per bucket of the step index n along the span.
fn drift(method: &str, w: u32, deg: f64) -> Vec<(u32, f64)> {
    let inputs = long_spans(w, deg);
    let m = find(method).unwrap();
    let (frame, ids) = render(&inputs, m, 2, true).unwrap();
    let ids = ids.unwrap();
    let truth = evaluate(&inputs, &ids, m);
    let edges = [16u32, 64, 256, 1024, 4096];
    let mut worst = vec![0.0f64; edges.len()];
    for (i, t) in truth.pixels.iter().enumerate() {
        let Some(t) = t else { continue };
        let x = i as u32 % w;
        let y = i as u32 / w;
        // the row's first covered pixel
        let row = &ids.prim[(y * w) as usize..((y + 1) * w) as usize];
        let first = row.iter().position(|&p| p > 0).unwrap() as u32;
        let n = x - first;
        let b = edges.iter().position(|&e| n < e).unwrap();
        let (sw, tw) = match t.normal {
            Some(v) => (frame.normal[i], v),
            None => (frame.color[i], t.color),
        };
        let e = (0..3)
            .map(|c| (sw[c] as f64 - tw[c]).abs())
            .fold(0.0, f64::max);
        assert!(e.is_finite(), "{method}: non-finite at {x},{y}");
        worst[b] = worst[b].max(e);
    }
    edges
        .iter()
        .copied()
        .zip(worst)
        .filter(|&(e, _)| e <= w.next_power_of_two().max(16))
        .collect()
}

#[test]
fn recurrence_drift_against_span_length_stays_within_its_allowance() {
    // A measurement: printed with --nocapture, and in README "Software engine".
    for method in [
        "spherical_angular",
        "quadratic_scanline",
        "hast_euler",
        "bishop_weimer",
        "phong_exact",
    ] {
        for deg in [30.0, 90.0] {
            let d = drift(method, 1024, deg);
            let line: Vec<String> = d.iter().map(|(e, v)| format!("n<{e}: {v:.1e}")).collect();
            println!(
                "{method:<20} {deg:>3} deg, 1024 px spans: {}",
                line.join("  ")
            );
            for (e, v) in d {
                // colour slope of this lighting: diffuse 0.7 + 20 x specular 0.3 = 6.7
                let allow = drift_allowance(e as f64) * 6.7 + 1e-5;
                assert!(v <= allow, "{method} {deg} deg n<{e}: {v:e} > {allow:e}");
            }
        }
    }
}

#[test]
fn drift_allowance_is_not_vacuous() {
    // Teeth: a drift as large as the 4096-step one FORMULAS.md 2.11 reports for the float32
    // recurrence (-30 %) exceeds the allowance at 256 steps; the first-order stepping of the
    // per-pixel methods drifts linearly (n steps of a few roundings), far below it.
    assert!(0.3 > drift_allowance(256.0));
    let d = drift("phong_exact", 1024, 90.0);
    let u = 1.0 / 16_777_216.0;
    assert!(d.iter().all(|&(e, v)| v < 4.0 * u * e as f64), "{d:?}");
}

fn summary_schema() -> jsonschema::Validator {
    let s = std::fs::read_to_string(root().join("docs/summary.schema.json")).unwrap();
    jsonschema::validator_for(&serde_json::from_str(&s).unwrap()).unwrap()
}

fn read_json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn compare_with_the_software_engine_writes_a_valid_summary_that_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = |e: &str| dir.path().join(e);
    let methods = "phong_exact,phong_unnormalized,spherical_angular,gouraud";
    let args = |engine: &'static str, o: &std::path::Path| {
        let o = o.to_str().unwrap().to_string();
        let (code, _, err) = run(&[
            "compare",
            "--scene",
            "scenes/torus.toml",
            "--size",
            "96x96",
            "--methods",
            methods,
            "--engine",
            engine,
            "--out",
            &o,
        ]);
        assert_eq!(code, 0, "{engine}: {err}");
        read_json(&std::path::Path::new(&o).join("summary.json"))
    };
    let sw = args("software", &out("sw"));
    let vk = args("vulkan", &out("vk"));
    let schema = summary_schema();
    assert!(
        schema.is_valid(&sw),
        "software summary.json against the schema"
    );
    assert_eq!(sw["engine"], "software");
    assert_eq!(vk["engine"], "vulkan");
    // teeth: an engine the schema does not know is rejected
    let mut wrong = sw.clone();
    wrong["engine"] = "metal".into();
    assert!(!schema.is_valid(&wrong));
    let row = |s: &serde_json::Value, n: &str| {
        s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()
            .clone()
    };
    // judged against the same f64 exact Phong: software phong_exact is at the float32 level
    // (bound: tests/gpu.rs), unnormalized far above it, both on the same covered pixels
    // as Vulkan (coverage: software_phong_exact_agrees_with_vulkan_on_every_shipped_scene)
    assert!(row(&sw, "phong_exact")["max_abs_error"].as_f64().unwrap() < 1e-4);
    assert!(
        row(&sw, "phong_unnormalized")["max_abs_error"]
            .as_f64()
            .unwrap()
            > 1e-2
    );
    assert_eq!(
        row(&sw, "phong_exact")["covered_pixels"],
        row(&vk, "phong_exact")["covered_pixels"]
    );
    for n in methods.split(',') {
        assert_eq!(row(&sw, n)["non_finite_pixels"], 0, "{n}");
        assert!(out("sw").join(n).join("error_abs.png").is_file(), "{n}");
    }
    // auto is drawn by Vulkan only: refused with a usage error, not silently dropped
    let o = out("auto");
    let (code, _, err) = run(&[
        "compare",
        "--scene",
        "scenes/torus.toml",
        "--size",
        "64x64",
        "--methods",
        "phong_exact,auto",
        "--engine",
        "software",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("Vulkan pipeline only"), "{err}");
}

/// The verdict rule of claims.md, from an entry's interval: below the target agrees, above
/// disagrees, holding it (or no finite round) inconclusive.
fn verdict_of(j: &serde_json::Value, target: f64) -> &'static str {
    let (lo, hi) = (j["ci95_low"].as_f64(), j["ci95_high"].as_f64());
    match (lo, hi, j["rounds"].as_u64()) {
        (Some(lo), Some(hi), Some(n)) if n > 0 => {
            if hi < target {
                "agrees"
            } else if lo > target {
                "disagrees"
            } else {
                "inconclusive"
            }
        }
        _ => "inconclusive",
    }
}

#[test]
fn bench_with_the_software_engine_writes_paired_ratios_and_computed_verdicts() {
    let dir = tempfile::tempdir().unwrap();
    // A minimal Vulkan bench.json: the fields the Vulkan column reads.
    let row = |n: &str, lo: f64, hi: f64| {
        serde_json::json!({"name": n, "ratio_median": (lo + hi) / 2.0, "ratio_ci95_low": lo,
            "ratio_ci95_high": hi, "ratio_rounds": 40, "ratio_non_finite": 0})
    };
    let vk = serde_json::json!({"scene": "torus", "width": 64, "height": 64,
        "rounds": {"rounds": 40},
        "methods": [row("gouraud", 0.8, 0.9), row("spherical_angular", 1.0, 1.1)]});
    let vk_path = dir.path().join("vk.json");
    std::fs::write(&vk_path, vk.to_string()).unwrap();
    let out = dir.path().join("sw");
    let bench = |vk: &std::path::Path, out: &std::path::Path| {
        run(&[
            "bench",
            "--scene",
            "scenes/torus.toml",
            "--size",
            "64x64",
            "--engine",
            "software",
            "--methods",
            "gouraud,spherical_angular,dichotomy_exact,dichotomy_poly1",
            "--repeat",
            "6",
            "--warmup",
            "1",
            "--vulkan-bench",
            vk.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let (code, stdout, err) = bench(&vk_path, &out);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("phong_exact"), "{stdout}");
    let b = read_json(&out.join("bench.json"));
    assert_eq!(b["engine"], "software");
    assert_eq!(b["rounds"]["rounds"], 6);
    let methods = b["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 5, "the four methods and phong_exact");
    for m in methods {
        assert_eq!(m["round_ms"].as_array().unwrap().len(), 6, "{m}");
        assert_eq!(
            m["ratio_rounds"].as_u64().unwrap() + m["ratio_non_finite"].as_u64().unwrap(),
            6
        );
    }
    let claims = read_json(&out.join("claims.json"));
    assert_eq!(claims, b["claims"]);
    let md = std::fs::read_to_string(out.join("claims.md")).unwrap();
    let mut judged = 0;
    for c in claims.as_array().unwrap() {
        let target = c["claimed_below"].as_f64().unwrap();
        for engine in ["software", "vulkan"] {
            let j = &c[engine];
            if j.is_null() {
                continue;
            }
            judged += 1;
            assert_eq!(j["verdict"], verdict_of(j, target), "{engine}: {c}");
            // teeth: the same entry with its interval moved across the target flips
            let mut moved = j.clone();
            moved["ci95_low"] = (target * 2.0 + 1.0).into();
            moved["ci95_high"] = (target * 2.0 + 2.0).into();
            assert_eq!(verdict_of(&moved, target), "disagrees");
        }
        let line = format!(
            "| {} / {} |",
            c["num"].as_str().unwrap(),
            c["den"].as_str().unwrap()
        );
        assert!(md.contains(&line), "claims.md lacks {line}:\n{md}");
    }
    // software: gouraud, spherical_angular, dichotomy; Vulkan: gouraud and spherical_angular
    assert_eq!(judged, 5, "{claims}");
    // the Vulkan column's verdicts are computed from the given intervals
    let of = |num: &str| {
        claims
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["num"] == num)
            .unwrap()
            .clone()
    };
    assert_eq!(of("gouraud")["vulkan"]["verdict"], "disagrees");
    assert_eq!(of("spherical_angular")["vulkan"]["verdict"], "disagrees");
    // a bench.json of the software engine is refused as the Vulkan column (exit 2)
    let (code, _, err) = bench(&out.join("bench.json"), &dir.path().join("again"));
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not \"vulkan\""), "{err}");
}

/// `--vulkan-paired`: lavapipe draws the same methods in the same rounds (under the validation
/// layer), so every Vulkan verdict is paired, the dichotomy ratio too (bounded from two
/// intervals, not paired, when it comes from a file), and software / lavapipe is reported.
#[test]
fn bench_with_the_software_engine_pairs_lavapipe_in_the_same_rounds() {
    let dir = tempfile::tempdir().unwrap();
    let args = |extra: &[&str], out: &str| {
        let mut a: Vec<String> = [
            "bench",
            "--scene",
            "scenes/torus.toml",
            "--size",
            "64x64",
            "--engine",
            "software",
            "--validate",
            "--methods",
            "gouraud,dichotomy_exact,dichotomy_poly1",
            "--repeat",
            "6",
            "--warmup",
            "1",
            "--out",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        a.push(dir.path().join(out).to_str().unwrap().to_string());
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run_s = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        run(&refs)
    };
    let (code, stdout, err) = run_s(args(&["--vulkan-paired"], "paired"));
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("software / lavapipe phong_exact per round"),
        "{stdout}"
    );
    let b = read_json(&dir.path().join("paired/bench.json"));
    assert_eq!(b["vulkan_paired"], true);
    assert!(b["vulkan_bench"].is_null());
    let a = &b["software_to_lavapipe"];
    assert_eq!(
        a["rounds"].as_u64().unwrap() + a["non_finite"].as_u64().unwrap(),
        6
    );
    let (lo, hi) = (
        a["ci95_low"].as_f64().unwrap(),
        a["ci95_high"].as_f64().unwrap(),
    );
    assert!(lo > 0.0 && lo <= hi, "{a}");
    assert_eq!(b["vulkan_median_ms"].as_array().unwrap().len(), 4);
    let claim = |b: &serde_json::Value, num: &str| {
        b["claims"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["num"] == num)
            .unwrap()["vulkan"]
            .clone()
    };
    for num in ["gouraud", "dichotomy_poly1"] {
        let v = claim(&b, num);
        assert_eq!(v["paired"], true, "{num}: {v}");
        assert_eq!(
            v["rounds"].as_u64().unwrap() + v["non_finite"].as_u64().unwrap(),
            6
        );
        assert_eq!(v["verdict"], verdict_of(&v, v_target(&b, num)));
    }
    // Teeth: the same Vulkan figures read from a file leave the dichotomy ratio unpaired.
    let vk = serde_json::json!({"scene": "torus", "width": 64, "height": 64,
        "rounds": {"rounds": 6},
        "methods": b["vulkan_median_ms"].as_array().unwrap().iter().map(|p| {
            serde_json::json!({"name": p[0], "ratio_median": 1.0, "ratio_ci95_low": 0.9,
                "ratio_ci95_high": 1.1, "ratio_rounds": 6, "ratio_non_finite": 0})
        }).collect::<Vec<_>>()});
    let vk_path = dir.path().join("vk.json");
    std::fs::write(&vk_path, vk.to_string()).unwrap();
    let (code, _, err) = run_s(args(&["--vulkan-bench", vk_path.to_str().unwrap()], "file"));
    assert_eq!(code, 0, "{err}");
    let f = read_json(&dir.path().join("file/bench.json"));
    assert_eq!(f["vulkan_paired"], false);
    assert!(f["software_to_lavapipe"].is_null());
    assert_eq!(claim(&f, "dichotomy_poly1")["paired"], false);
    // Both sources at once, or either with the Vulkan engine, are refused (exit 2).
    let (code, _, _) = run_s(args(
        &[
            "--vulkan-paired",
            "--vulkan-bench",
            vk_path.to_str().unwrap(),
        ],
        "both",
    ));
    assert_eq!(code, 2);
    let mut vulkan_engine = args(&["--vulkan-paired"], "vk_engine");
    let k = vulkan_engine.iter().position(|a| a == "software").unwrap();
    vulkan_engine[k] = "vulkan".into();
    let (code, _, err) = run_s(vulkan_engine);
    assert_eq!(code, 2, "{err}");
}

/// The claimed bound of the claim whose numerator is `num`.
fn v_target(b: &serde_json::Value, num: &str) -> f64 {
    b["claims"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["num"] == num)
        .unwrap()["claimed_below"]
        .as_f64()
        .unwrap()
}

#[test]
fn software_verify_passes_on_every_shared_model_at_256() {
    // Skipped with a printed message when the models folder is absent (support::models_dir).
    let Some(files) = model_files() else { return };
    assert!(
        files.len() >= 5,
        "expected the 5 models of the README, found {files:?}"
    );
    let all: Vec<_> = METHODS.iter().collect();
    for (k, f) in files.iter().enumerate() {
        let mut s = shadelab::scene::scene_for_mesh(f).unwrap_or_else(|e| panic!("{e}"));
        s.width = 256;
        s.height = 256;
        if k == 0 {
            // teeth: on a real model too, an image judged by another formula fails
            let (nr, exact) = (find("mikami_const").unwrap(), find("phong_exact").unwrap());
            let wrong = verify_software(&s, &[nr], Some(exact), 2).unwrap();
            assert!(!wrong.passed(), "{}", wrong.table());
        }
        let report = verify_software(&s, &all, None, 2).unwrap();
        println!("{}:\n{}", f.display(), report.table());
        assert!(
            report.rows.iter().all(|r| r.agreement.covered > 1000),
            "{}",
            f.display()
        );
        assert!(
            report.passed(),
            "{}: {}\n{}",
            f.display(),
            report.failures().join("; "),
            report.table()
        );
    }
}

/// The allocation counter of the test crate's global allocator (tests/fuzz/engine.rs): per
/// thread, so other tests running at the same time do not enter the count (the software engine
/// on 1 thread draws on the calling thread).
mod allocations {
    pub fn count() -> u64 {
        crate::fuzz::engine::allocations_on_this_thread()
    }
}

/// A shader that counts the allocations made inside the wrapped shader's rows.
struct CountRows<S> {
    inner: S,
    allocs: std::sync::atomic::AtomicU64,
    rows: std::sync::atomic::AtomicU64,
    /// Teeth: allocate in every row.
    leak: bool,
}

impl<S: software::raster::Shader> software::raster::Shader for CountRows<S> {
    type Setup = S::Setup;
    fn setup(&self, tri: &software::raster::Tri) -> S::Setup {
        self.inner.setup(tri)
    }
    fn row(
        &self,
        tri: &software::raster::Tri,
        setup: &S::Setup,
        span: software::raster::RowSpan,
        out: &mut software::raster::RowOut,
        scratch: &mut Vec<glam::Vec3>,
    ) {
        use std::sync::atomic::Ordering::Relaxed;
        let before = allocations::count();
        if self.leak {
            std::hint::black_box(vec![0u8; 16]);
        }
        self.inner.row(tri, setup, span, out, scratch);
        self.allocs
            .fetch_add(allocations::count() - before, Relaxed);
        self.rows.fetch_add(1, Relaxed);
    }
}

#[test]
fn the_span_and_pixel_loops_allocate_nothing() {
    use software::formulas::{self as f, Lighting32};
    use software::spans::{n4, stepped, Along, SpanShader};
    let scene = shipped_scene("sphere_fine", 256);
    let inputs = SceneInputs::new(&scene, Geometry::Mesh);
    let tris = software::raster::setup(&inputs).unwrap();
    let lit = Lighting32::new(&inputs.params, inputs.light_count);
    fn counted<S: software::raster::Shader>(
        tris: &[software::raster::Tri],
        s: S,
        leak: bool,
    ) -> (u64, u64) {
        let c = CountRows {
            inner: s,
            allocs: 0.into(),
            rows: 0.into(),
            leak,
        };
        // 1 thread: the rows run on this thread, where the counter counts
        software::raster::draw(256, 256, tris, &c, 1, true);
        (c.allocs.into_inner(), c.rows.into_inner())
    }
    let alongs = [
        Along::Slerp,
        Along::Chebyshev,
        Along::Quadratic { approx_mid: false },
        Along::Dichotomy(f::inv_root_exact),
        Along::Segments(3, None),
        Along::Segments(3, Some(f::inv_root_poly1)),
        Along::BishopWeimer,
        Along::HastEuler,
    ];
    for along in alongs {
        let (allocs, rows) = counted(&tris, SpanShader { along, lit }, false);
        assert!(rows > 1000, "{along:?}: {rows} rows");
        assert_eq!(allocs, 0, "{along:?}: {allocs} allocations in {rows} rows");
    }
    let per_pixel = stepped(
        |t: &software::raster::Tri| (t.n, ()),
        move |v: glam::Vec3, _: &()| {
            let m = f::normalize_exact(v);
            (lit.shade(m), n4(m))
        },
    );
    let (allocs, rows) = counted(&tris, per_pixel, false);
    assert_eq!(
        allocs, 0,
        "per-pixel form: {allocs} allocations in {rows} rows"
    );
    // teeth: a row that allocates is counted, once per row
    let (allocs, rows) = counted(
        &tris,
        SpanShader {
            along: Along::Chebyshev,
            lit,
        },
        true,
    );
    assert_eq!(allocs, rows);
}

#[test]
fn a_command_without_a_software_path_refuses_the_software_engine() {
    // stress draws on Vulkan only: --engine software must not be ignored silently
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = run(&[
        "stress",
        "--engine",
        "software",
        "--methods",
        "phong_exact",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--engine software is for render"), "{err}");
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
