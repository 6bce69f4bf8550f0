//! `shadelab bench`: `auto` and its budget curve timed and judged like a method.
use crate::support::*;

#[test]
fn bench_times_auto_and_its_budget_curve_like_a_method() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, stdout, stderr) = run(&[
        "bench",
        "--runs",
        "1",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "64x64",
        "--validate",
        "--methods",
        "auto,gouraud",
        "--isolated-rounds",
        "0",
        "--repeat",
        "6",
        "--warmup",
        "1",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let bench = read_json(dir.path().join("bench.json"));
    assert_schema(
        &bench,
        "docs/bench.schema.json",
        "/auto_curve/0",
        "beaten_by",
    );

    // auto at the run's budget and the curve's other three, each a timed row with its error.
    let curve = ["auto", "auto_1_1024", "auto_4_255", "auto_16_255"];
    let rows = bench["methods"].as_array().unwrap();
    for name in curve {
        let row = rows
            .iter()
            .find(|m| m["name"] == name)
            .unwrap_or_else(|| panic!("no row {name} in bench.json"));
        assert!(row["median_ms"].as_f64().unwrap() > 0.0, "{name}");
        assert!(row["ratio_ci95_low"].as_f64().unwrap() > 0.0, "{name}");
        let point = bench["auto_curve"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == name)
            .unwrap_or_else(|| panic!("no auto_curve point {name}"));
        let (max_abs, budget) = (
            point["max_abs_error"].as_f64().unwrap(),
            point["budget"].as_f64().unwrap(),
        );
        // The error a budget bounds: the largest channel's (crate::auto::colour_error).
        let channels = row["error"]["channels"].as_array().unwrap();
        let largest = channels
            .iter()
            .map(|c| c["max_abs_error"].as_f64().unwrap())
            .fold(0.0, f64::max);
        assert_eq!(max_abs, largest);
        assert!(max_abs <= budget, "{name}: {max_abs} > {budget}");
        assert_eq!(point["within_budget"], true);
        assert!(stdout.contains(&format!("{name} (budget")), "{stdout}");
    }
    // The budgets are the issue's, and a looser budget never has a smaller error bound.
    let budget = |n: &str| {
        bench["auto"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["name"] == n)
            .unwrap()["budget"]
            .as_f64()
            .unwrap()
    };
    assert_eq!(budget("auto"), 1.0 / 255.0);
    assert_eq!(budget("auto_1_1024"), 1.0 / 1024.0);
    assert_eq!(budget("auto_16_255"), 16.0 / 255.0);
    let svg = std::fs::read_to_string(dir.path().join("pareto.svg")).unwrap();
    assert!(
        svg.contains("auto_4_255"),
        "the Pareto chart lacks the auto curve"
    );

    // A bad curve is refused before any work.
    let (code, _, stderr) = run(&[
        "bench",
        "--runs",
        "1",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--methods",
        "auto",
        "--auto-curve",
        "1/255,zero",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--auto-curve"), "{stderr}");
}
