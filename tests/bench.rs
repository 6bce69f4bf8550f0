//! `shadelab bench`: structure only (no speed assertions): bench.json against its schema,
//! bench.csv, the charts and claims files, the control, a sweep.
use crate::support::*;

#[test]
fn bench_writes_its_files_in_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, stdout, stderr) = run(&[
        "bench",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "48x48",
        "--validate",
        "--methods",
        "phong_exact,gouraud,newton_raphson,trueform",
        "--repeat",
        "6",
        "--warmup",
        "1",
        "--control",
        "--sweep",
        "size",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let bench: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("bench.json")).unwrap())
            .unwrap();
    let schema: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("docs/bench.schema.json")).unwrap(),
    )
    .unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let errors: Vec<String> = validator
        .iter_errors(&bench)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "bench.json does not match docs/bench.schema.json:\n{}",
        errors.join("\n")
    );
    let mut broken = bench.clone();
    broken["methods"][0]
        .as_object_mut()
        .unwrap()
        .remove("ci95_high_ms");
    assert!(
        !validator.is_valid(&broken),
        "the schema check has no teeth"
    );

    let names: Vec<&str> = bench["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    for n in [
        "phong_exact",
        "gouraud",
        "newton_raphson",
        "trueform",
        "phong_unnormalized",
        "phong_exact_control",
    ] {
        assert!(names.contains(&n), "{n} missing from {names:?}");
    }
    assert_eq!(bench["floor"]["name"], "constant");
    for m in bench["methods"].as_array().unwrap() {
        assert_eq!(m["samples"], 6);
        let (lo, med, hi) = (
            m["ci95_low_ms"].as_f64().unwrap(),
            m["median_ms"].as_f64().unwrap(),
            m["ci95_high_ms"].as_f64().unwrap(),
        );
        assert!(lo <= med && med <= hi, "{m}");
        assert!(m["covered_pixels"].as_u64().unwrap() > 100);
    }
    let exact = bench["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "phong_exact")
        .unwrap();
    assert_eq!(exact["ratio_to_phong_exact"], 1.0);
    assert_eq!(exact["static_ops_above_unnormalized"]["inverse_sqrt"], 1);
    // every claim has a verdict, and the speed claim against Gouraud is measured in this run
    let claims = bench["claims"].as_array().unwrap();
    assert!(claims.iter().any(|c| c["method"] == "gouraud"
        && c["measured"]
            .as_str()
            .unwrap()
            .contains("phong_exact / gouraud")));
    assert!(claims.len() >= 15);
    assert_eq!(bench["sweeps"][0]["sweep"], "size");
    assert!(bench["sweeps"][0]["points"].as_array().unwrap().len() >= 12);
    // files
    for f in [
        "bench.csv",
        "pareto.svg",
        "pareto.png",
        "claims.json",
        "claims.md",
        "sweep_size.svg",
        "sweep_size.png",
    ] {
        let p = dir.path().join(f);
        assert!(
            p.is_file() && std::fs::metadata(&p).unwrap().len() > 100,
            "{f} missing or empty"
        );
    }
    let svg = std::fs::read_to_string(dir.path().join("pareto.svg")).unwrap();
    assert!(
        svg.contains("<svg") && svg.contains("phong_exact"),
        "pareto.svg has no labels"
    );
    let png = image::open(dir.path().join("pareto.png")).unwrap();
    assert!(png.width() >= 800);
    let csv = std::fs::read_to_string(dir.path().join("bench.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("name,median_ms,ci95_low_ms,ci95_high_ms,samples,clock,"));
    assert_eq!(lines.len(), 2 + names.len(), "header + floor + methods");
    assert!(lines
        .iter()
        .all(|l| l.split(',').count() == lines[0].split(',').count()));
    assert!(
        stdout.contains("constant") && stdout.contains("pareto"),
        "{stdout}"
    );
}

#[test]
fn bench_rejects_bad_options() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, _, err) = run(&[
        "bench",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "32x32",
        "--error-metric",
        "nope",
        "--out",
        out,
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--error-metric: unknown metric \"nope\""),
        "{err}"
    );
    let (code, _, err) = run(&[
        "bench",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "32x32",
        "--repeat",
        "0",
        "--out",
        out,
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--repeat must be at least 1"), "{err}");
}
