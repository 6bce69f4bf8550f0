//! compare and bench with `--engine software`: summary.json and bench.json against their
//! schemas, claims computed by the product's rule from known intervals; commands without a
//! software path refuse it.
use crate::support::*;

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
        read_json(std::path::Path::new(&o).join("summary.json"))
    };
    let sw = args("software", &out("sw"));
    let vk = args("vulkan", &out("vk"));
    let schema = schema_validator("docs/summary.schema.json");
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

/// The verdicts a claim entry may carry.
const VERDICTS: [&str; 3] = ["agrees", "disagrees", "inconclusive"];

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
    let b = read_json(out.join("bench.json"));
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
    let claims = read_json(out.join("claims.json"));
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
            // measured intervals: a verdict of the rule's three (the rule itself is fed known
            // intervals through the Vulkan column below)
            assert!(
                VERDICTS.contains(&j["verdict"].as_str().unwrap()),
                "{engine}: {c}"
            );
            assert!(target > 0.0, "{c}");
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
    // known intervals, both wholly above their targets: the product's rule says disagrees
    let target = |num: &str| of(num)["claimed_below"].as_f64().unwrap();
    assert!(target("gouraud") < 0.8 && target("spherical_angular") < 1.0);
    assert_eq!(of("gouraud")["vulkan"]["verdict"], "disagrees");
    assert_eq!(of("spherical_angular")["vulkan"]["verdict"], "disagrees");
    // and known intervals wholly below (agrees) and across (inconclusive) their targets
    let (tg, ts) = (target("gouraud"), target("spherical_angular"));
    let vk = serde_json::json!({"scene": "torus", "width": 64, "height": 64,
        "rounds": {"rounds": 40},
        "methods": [row("gouraud", 0.5 * tg, 0.9 * tg), row("spherical_angular", 0.9 * ts, 1.1 * ts)]});
    let known = dir.path().join("known.json");
    std::fs::write(&known, vk.to_string()).unwrap();
    let (code, _, err) = bench(&known, &dir.path().join("known"));
    assert_eq!(code, 0, "{err}");
    let k = read_json(dir.path().join("known/claims.json"));
    let of_k = |num: &str| {
        k.as_array()
            .unwrap()
            .iter()
            .find(|c| c["num"] == num)
            .unwrap()["vulkan"]["verdict"]
            .clone()
    };
    assert_eq!(of_k("gouraud"), "agrees", "{k}");
    assert_eq!(of_k("spherical_angular"), "inconclusive", "{k}");
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
    let b = read_json(dir.path().join("paired/bench.json"));
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
        assert!(VERDICTS.contains(&v["verdict"].as_str().unwrap()), "{v}");
        assert!(v_target(&b, num) > 0.0);
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
    let f = read_json(dir.path().join("file/bench.json"));
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
