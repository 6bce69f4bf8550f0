//! `shadelab stress`: stress.json against its schema (with teeth), the files beside it, the
//! non-finite counts (the same methods compare finds NaN on), and `--replay`.
use crate::support::*;

#[test]
fn stress_writes_its_files_counts_nan_and_replays_its_worst_case() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let methods = "phong_exact,slerp,barycentric_quadratic_exact_mid,segments_k2,trueform";
    let (code, stdout, stderr) = run(&[
        "stress",
        "--validate",
        "--methods",
        methods,
        "--refine",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report = read_json(out.join("stress.json"));
    assert_schema(
        &report,
        "docs/stress.schema.json",
        "/methods/0",
        "non_finite_cases",
    );
    for f in [
        "error_vs_angle.svg",
        "error_vs_angle.png",
        "error_vs_shininess.png",
        "validity/slerp.png",
    ] {
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 1000, "{f}");
    }
    let by_name = |n: &str| {
        report["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()
            .clone()
    };
    // The antipodal pair makes the exact-midpoint quadratic NaN (compare counts it too, in
    // tests/compare.rs): counted, and its worst error is null rather than a small number.
    let bq = by_name("barycentric_quadratic_exact_mid");
    assert!(
        bq["non_finite_cases"].as_u64().unwrap() > 0,
        "{}",
        bq["non_finite_cases"]
    );
    assert!(bq["worst_abs_error"].is_null());
    assert!(
        bq["non_finite_example"]["spec"]["theta_deg"]
            .as_f64()
            .unwrap()
            > 170.0
    );
    // a method with no device program is measured in f64 and says so
    assert_eq!(by_name("trueform")["device_evaluated"], false);
    // the table ranks methods with NaN first
    let first = stdout.lines().nth(1).unwrap();
    let nan_methods: Vec<String> = report["methods"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["non_finite_cases"].as_u64().unwrap() > 0)
        .map(|m| m["name"].as_str().unwrap().to_string())
        .collect();
    assert!(
        nan_methods.iter().any(|n| first.starts_with(n.as_str())),
        "{stdout}"
    );
    // The digital-segment paper's specular bound: fails from n = 67 on (the bound is 4.0004 %
    // there)
    let claim = report["claims"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["method"] == "segments_k2")
        .unwrap();
    assert_eq!(claim["verdict"], "disagrees");
    assert!(
        claim["measured"].as_str().unwrap().contains("n = 67..100"),
        "{claim}"
    );

    // --replay: bit-identical; a changed colour is caught (exit 1); a bad file exits 2
    let case = out.join("cases/slerp.json");
    let (code, stdout, stderr) = run(&["stress", "--replay", case.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.contains("reproduced: the device colour is bit-identical"),
        "{stdout}"
    );
    let mut tampered = read_json(&case);
    let b0 = tampered["device_color_bits"][0].as_u64().unwrap();
    tampered["device_color_bits"][0] = (b0 ^ 1).into();
    let bad = dir.path().join("tampered.json");
    std::fs::write(&bad, tampered.to_string()).unwrap();
    let (code, stdout, _) = run(&["stress", "--replay", bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{stdout}");
    assert!(stdout.contains("NOT reproduced"), "{stdout}");
    // a non-finite case replays too (its NaN colour is null in the file)
    let nan = out.join("cases/barycentric_quadratic_exact_mid_non_finite.json");
    let (code, stdout, stderr) = run(&["stress", "--replay", nan.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.contains("non-finite") && stdout.contains("reproduced"),
        "{stdout}"
    );
    std::fs::write(&bad, "{}").unwrap();
    let (code, _, stderr) = run(&["stress", "--replay", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("tampered.json") && stderr.contains("not a stress case"),
        "{stderr}"
    );
}
