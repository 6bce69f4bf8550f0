//! `shadelab bench --runs N`: fresh processes merged, verdicts across runs, refusals.
use crate::support::*;

/// `--runs N`: N fresh processes, merged; every program's ratio and verdict come from the
/// interval across runs, each run's own figures are kept, and the control is always timed.
#[test]
fn bench_runs_merges_fresh_processes_and_judges_across_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, _stdout, stderr) = run(&[
        "bench",
        "--runs",
        "2",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "32x32",
        "--methods",
        "phong_exact,gouraud",
        "--repeat",
        "3",
        "--warmup",
        "1",
        "--isolated-rounds",
        "2",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("bench: run 1 of 2"), "{stderr}");
    assert!(stderr.contains("bench: run 2 of 2"), "{stderr}");
    let bench = read_json(dir.path().join("bench.json"));
    assert_schema(
        &bench,
        "docs/bench.schema.json",
        "/methods/0/runs",
        "confidence",
    );
    assert_eq!(bench["runs"]["count"], 2);
    // two runs: [min, max] covers 1 - 2 / 4
    assert_eq!(bench["runs"]["confidence"], 0.5);
    let methods = bench["methods"].as_array().unwrap();
    assert!(methods.iter().any(|m| m["name"] == "phong_exact_control"));
    for m in methods {
        let figs = m["run_figures"].as_array().unwrap();
        let runs: Vec<u64> = figs.iter().map(|f| f["run"].as_u64().unwrap()).collect();
        assert_eq!(runs, [1, 2], "{}", m["name"]);
        let r: Vec<f64> = figs
            .iter()
            .map(|f| f["ratio_median"].as_f64().unwrap())
            .collect();
        let s = &m["runs"];
        assert_eq!(s["count"], 2, "{}", m["name"]);
        assert_eq!(s["ratio_ci95_low"].as_f64().unwrap(), r[0].min(r[1]));
        assert_eq!(s["ratio_ci95_high"].as_f64().unwrap(), r[0].max(r[1]));
        // the row's ratio and verdict are those across runs
        assert_eq!(m["ratio_median"], s["ratio_median"]);
        assert_eq!(m["ratio_rounds"], 2);
        assert_eq!(m["speed_vs_phong_exact"], s["verdict"], "{}", m["name"]);
    }
    let g = methods.iter().find(|m| m["name"] == "gouraud").unwrap();
    assert_eq!(g["isolated_runs"]["count"], 2, "{g}");
    // the pooled rounds of both runs
    assert_eq!(bench["rounds"]["rounds"], 6);
}

#[test]
fn bench_runs_refuses_what_it_cannot_do() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let base = ["bench", "--scene", "scenes/cube.toml", "--size", "32x32"];
    for (extra, want) in [
        (&["--runs", "0"][..], "\"0\" is not a count from 1 to 100"),
        (&["--runs", "2", "--until-ci", "5"][..], "--until-ci"),
        (
            &["--runs", "2", "--engine", "software"][..],
            "--engine software",
        ),
    ] {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out]);
        let (code, _, stderr) = run(&args);
        assert_eq!(code, 2, "{extra:?}: {stderr}");
        assert!(stderr.contains(want), "{extra:?}: {stderr}");
    }
}
