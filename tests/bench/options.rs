//! `shadelab bench`: options refused with their messages, `--until-ci` and `--baseline`.
use crate::support::*;

#[test]
fn bench_rejects_bad_options() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, _, err) = run(&[
        "bench",
        "--runs",
        "1",
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
        err.contains("--error-metric") && err.contains("unknown metric \"nope\""),
        "{err}"
    );
    let (code, _, err) = run(&[
        "bench",
        "--runs",
        "1",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "32x32",
        "--isolated-rounds",
        "0",
        "--repeat",
        "0",
        "--out",
        out,
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("\"0\" is not a count from 1 to 100000"),
        "{err}"
    );
    let bench = |extra: &[&str]| {
        let mut args = vec![
            "bench",
            "--runs",
            "1",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "32x32",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out]);
        run(&args)
    };
    let (code, _, err) = bench(&["--until-ci", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("--until-ci must be a percentage > 0"), "{err}");
    let (code, _, err) = bench(&["--until-ci", "1", "--max-time", "0"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("\"0\" is not a number of seconds above 0 and at most 86400"),
        "{err}"
    );
    let (code, _, err) = bench(&["--fail-slower", "5"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--baseline"), "{err}");
    // a baseline that cannot be read fails before any timing
    let (code, _, err) = bench(&["--baseline", "no/such/bench.json"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/bench.json"), "{err}");
    assert!(!err.contains("bench: timing"), "{err}");
}

/// `--until-ci` stops at its target or at its time cap, says which, and records it;
/// `--baseline` compares (not paired) and `--fail-slower` exits 1 naming each slower program,
/// judged on synthetic baselines much faster and much slower than any real run.
#[test]
fn bench_until_ci_and_baseline() {
    let dir = tempfile::tempdir().unwrap();
    let baseline = |ms: f64| {
        let row = |n: &str| serde_json::json!({"name": n, "ci95_low_ms": ms * 0.99, "median_ms": ms, "ci95_high_ms": ms * 1.01});
        let p = dir.path().join(format!("baseline_{ms}.json"));
        let v = serde_json::json!({"floor": row("constant"), "other_floors": [], "methods": [row("phong_exact"), row("gone")]});
        std::fs::write(&p, v.to_string()).unwrap();
        p
    };
    let (fast, slow) = (baseline(1e-6), baseline(1e6));
    let bench = |extra: &[&str], out: &str| {
        let out = dir.path().join(out);
        let mut args = vec![
            "bench",
            "--runs",
            "1",
            "--scene",
            "scenes/sphere_coarse.toml",
            "--size",
            "32x32",
            "--methods",
            "phong_exact",
            "--isolated-rounds",
            "0",
            "--repeat",
            "6",
            "--warmup",
            "1",
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--out", out.to_str().unwrap()]);
        let (code, stdout, stderr) = run(&args);
        let json = std::fs::read_to_string(out.join("bench.json"))
            .map(|t| serde_json::from_str::<serde_json::Value>(&t).unwrap());
        (code, stdout, stderr, json)
    };
    // A target any 6 rounds with a finite ratio meet (a preempted 32x32 draw can make a
    // ratio 10x, so not 1000 %); a baseline far faster than this run: exit 1, named.
    let (code, stdout, stderr, json) = bench(
        &[
            "--until-ci",
            "1e12",
            "--baseline",
            fast.to_str().unwrap(),
            "--fail-slower",
            "5",
        ],
        "a",
    );
    assert_eq!(code, 1, "{stderr}");
    let json = json.unwrap();
    assert_eq!(json["rounds"]["stopped"], "target_reached");
    assert_eq!(json["rounds"]["rounds"], 6);
    assert!(stdout.contains("target reached"), "{stdout}");
    assert!(stdout.contains("not paired"), "{stdout}");
    assert!(
        stderr.contains(
            "phong_exact is slower than the baseline beyond both 95% intervals by more than 5 %"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("constant is slower"), "{stderr}");
    let b = &json["baseline"];
    assert_eq!(b["paired"], false);
    assert_eq!(b["failing"], serde_json::json!(["constant", "phong_exact"]));
    assert_eq!(b["only_in_baseline"], serde_json::json!(["gone"]));
    // An unreachable target: the time cap stops it, says so; a baseline far slower: exit 0.
    let (code, stdout, stderr, json) = bench(
        &[
            "--until-ci",
            "0.000001",
            "--max-time",
            "0.5",
            "--baseline",
            slow.to_str().unwrap(),
            "--fail-slower",
            "5",
        ],
        "b",
    );
    assert_eq!(code, 0, "{stderr}");
    let json = json.unwrap();
    assert_eq!(json["rounds"]["stopped"], "time_cap");
    assert!(json["rounds"]["rounds"].as_u64().unwrap() >= 6);
    assert!(
        json["rounds"]["widest_half_width_pct"].as_f64().unwrap() > 0.000001,
        "{}",
        json["rounds"]
    );
    assert!(stdout.contains("time cap of 0.5 s reached"), "{stdout}");
    assert!(stdout.contains("not reached"), "{stdout}");
    assert!(json["baseline"]["failing"].as_array().unwrap().is_empty());
    assert_eq!(json["baseline"]["programs"][1]["change"], "faster");
}
