//! `shadelab bench`: structure only (no speed assertions): bench.json against its schema,
//! bench.csv, the charts and claims files, the control, a sweep.
use crate::support::*;

#[test]
fn bench_writes_its_files_in_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, stdout, stderr) = run(&[
        "bench",
        "--runs",
        "1",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "48x48",
        "--validate",
        "--methods",
        "phong_exact,gouraud,newton_raphson,trueform",
        "--isolated-rounds",
        "6",
        "--repeat",
        "6",
        "--warmup",
        "1",
        "--control",
        "--sweep",
        "size",
        "--threads",
        "1",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{stderr}");
    let bench: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("bench.json")).unwrap())
            .unwrap();
    let validator = schema_validator("docs/bench.schema.json");
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
    // The isolated cost: measured for every method with a compute program, its K = 1 kernel
    // the method itself; trueform (its own geometry) has none; a second Pareto chart.
    let row = |n: &str| {
        bench["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()
            .clone()
    };
    for n in ["phong_exact", "gouraud", "newton_raphson"] {
        let r = row(n);
        let (lo, med, hi) = (
            r["isolated_ci95_low_ns"].as_f64().unwrap(),
            r["isolated_ns_per_eval"].as_f64().unwrap(),
            r["isolated_ci95_high_ns"].as_f64().unwrap(),
        );
        assert!(lo <= med && med <= hi, "{n}: {lo} {med} {hi}");
        assert!(
            r["isolated_k1_max_abs_diff_vs_f64"].as_f64().unwrap() < 1e-4,
            "{n}"
        );
    }
    assert!(row("phong_exact")["isolated_ns_per_eval"].as_f64().unwrap() > 0.0);
    assert!(row("gouraud")["isolated_vs_phong_exact"].is_string());
    assert!(row("trueform")["isolated_ns_per_eval"].is_null());
    assert!(dir.path().join("pareto_isolated.png").is_file());
    let claims = bench["claims"].as_array().unwrap();
    assert!(
        claims.iter().any(|c| c["how"]
            .as_str()
            .unwrap()
            .starts_with("measure: isolated cost")),
        "no claim judged by the isolated cost"
    );
    // Provenance of the run: threads, command line, CPU, Mesa and LLVM.
    assert_eq!(bench["lp_num_threads"], "1");
    let cmdline: Vec<&str> = bench["command_line"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(
        cmdline.windows(2).any(|w| w == ["--threads", "1"]),
        "{cmdline:?}"
    );
    assert!(bench["cpu_count"].as_u64().unwrap() >= 1);
    for k in ["mesa_version", "llvm_version"] {
        assert!(
            bench["provenance"][k].is_string(),
            "{k}: {}",
            bench["provenance"]
        );
    }
    // Rounds: exactly --repeat without --until-ci.
    assert_eq!(bench["rounds"]["rounds"], 6);
    assert_eq!(bench["rounds"]["stopped"], "fixed_repeat");
    assert!(bench["ratio_interval"]
        .as_str()
        .unwrap()
        .contains("sign test"));
    // trueform draws its own PN tessellation: timed in the same rounds as that geometry's own
    // constant-colour floor, which is timed against the scene's floor.
    let other = bench["other_floors"].as_array().unwrap();
    assert_eq!(other.len(), 1, "{other:?}");
    assert_eq!(other[0]["name"], "constant_pn_tessellated_3");
    assert_eq!(other[0]["floor_program"], "constant");
    let methods = bench["methods"].as_array().unwrap();
    let all_rows: Vec<&serde_json::Value> = std::iter::once(&bench["floor"])
        .chain(other)
        .chain(methods)
        .collect();
    let by_name = |n: &str| *all_rows.iter().find(|m| m["name"] == n).unwrap();
    for m in &all_rows {
        assert_eq!(m["samples"], 6);
        // every round gives a ratio or is counted as not giving one
        let counted = m["ratio_rounds"].as_u64().unwrap() + m["ratio_non_finite"].as_u64().unwrap();
        assert_eq!(counted, 6, "{m}");
        for (lo, med, hi) in [
            ("ci95_low_ms", "median_ms", "ci95_high_ms"),
            ("ratio_ci95_low", "ratio_median", "ratio_ci95_high"),
            (
                "ratio_to_floor_ci95_low",
                "ratio_to_floor_median",
                "ratio_to_floor_ci95_high",
            ),
        ] {
            let (lo, med, hi) = (
                m[lo].as_f64().unwrap(),
                m[med].as_f64().unwrap(),
                m[hi].as_f64().unwrap(),
            );
            assert!(lo <= med && med <= hi, "{m}");
        }
        let covered = m["covered_pixels"].as_u64().unwrap();
        assert!(covered > 100);
        // overdraw from the untimed invocation count
        if let Some(n) = m["fragment_invocations"].as_u64() {
            let o = m["overdraw"].as_f64().unwrap();
            assert!((o - n as f64 / covered as f64).abs() < 1e-12, "{m}");
            assert!(o >= 1.0, "fewer invocations than covered pixels: {m}");
        }
        // the speed word is the paired interval's
        let (lo, hi) = (
            m["ratio_ci95_low"].as_f64().unwrap(),
            m["ratio_ci95_high"].as_f64().unwrap(),
        );
        let want = if hi < 1.0 {
            "faster"
        } else if lo > 1.0 {
            "slower"
        } else {
            "inconclusive"
        };
        assert_eq!(m["speed_vs_phong_exact"], want, "{m}");
    }
    let row = |n: &str| methods.iter().find(|m| m["name"] == n).unwrap();
    let (exact, unnormalized) = (row("phong_exact"), row("phong_unnormalized"));
    let ms = |m: &serde_json::Value, k: &str| m[k].as_f64().unwrap();
    // phong_exact against itself, round by round: exactly 1
    for k in ["ratio_median", "ratio_ci95_low", "ratio_ci95_high"] {
        assert_eq!(ms(exact, k), 1.0, "{k}");
    }
    assert_eq!(
        row("trueform")["floor_program"],
        "constant_pn_tessellated_3"
    );
    assert_eq!(row("gouraud")["floor_program"], "constant");

    // Ratios of medians, recomputed from the rows (gouraud's and newton_raphson's are not 1 by
    // construction, as phong_exact's own is); above the floor means above the row's own floor.
    let floor_ms = ms(&bench["floor"], "median_ms");
    let exact_ms = ms(exact, "median_ms");
    for m in methods {
        let med = ms(m, "median_ms");
        let own_floor = ms(by_name(m["floor_program"].as_str().unwrap()), "median_ms");
        let close = |k: &str, want: f64| {
            let got = ms(m, k);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs(),
                "{} {k}: {got} vs {want}",
                m["name"]
            );
        };
        close("ratio_to_phong_exact", med / exact_ms);
        close("above_floor_ms", med - own_floor);
        close(
            "ratio_above_floor_to_phong_exact",
            (med - own_floor) / (exact_ms - floor_ms),
        );
    }

    // The op-count excess is phong_exact's counts minus phong_unnormalized's, and the op-count
    // claim reports that excess.
    let delta = &exact["static_ops_above_unnormalized"];
    for k in [
        "div",
        "sqrt",
        "inverse_sqrt",
        "mul",
        "add",
        "pow",
        "other_transcendental",
    ] {
        let count = |m: &serde_json::Value| m["static_ops"][k].as_i64().unwrap();
        assert_eq!(
            delta[k].as_i64().unwrap(),
            count(exact) - count(unnormalized),
            "{k}"
        );
    }
    let claims = bench["claims"].as_array().unwrap();
    let claim = |method: &str, text: &str| {
        claims
            .iter()
            .find(|c| c["method"] == method && c["claim"].as_str().unwrap().contains(text))
            .unwrap_or_else(|| panic!("no claim {text:?} for {method}"))
    };
    let ops = claim("phong_exact", "3 divisions");
    let want = format!(
        "{} div, {} sqrt, {} inverse sqrt, {} mul, {} add",
        delta["div"], delta["sqrt"], delta["inverse_sqrt"], delta["mul"], delta["add"]
    );
    assert!(ops["measured"].as_str().unwrap().contains(&want), "{ops}");

    // The claims follow the methods of this run: every row is about one of them (every method
    // of the seeds is in the table now), and each run method's f64-checked table claims are
    // there with the verdict and measurement `list --json` computes.
    let (code, list, _) = run(&["list", "--json"]);
    assert_eq!(code, 0);
    let list: serde_json::Value = serde_json::from_str(&list).unwrap();
    let table = list["methods"].as_array().unwrap();
    for c in claims {
        let m = c["method"].as_str().unwrap();
        assert!(
            table.iter().any(|t| t["name"] == m),
            "claim of {m}, which the method table does not have: {c}"
        );
        assert!(
            names.contains(&m),
            "claim of {m}, which this run did not draw: {c}"
        );
        assert!(!c["how"].as_str().unwrap().is_empty(), "{c}");
    }
    for t in table
        .iter()
        .filter(|t| names.contains(&t["name"].as_str().unwrap()))
    {
        for tc in t["claims"].as_array().unwrap() {
            if tc["verdict"] == "not_checked" {
                continue;
            }
            let c = claim(t["name"].as_str().unwrap(), tc["claim"].as_str().unwrap());
            assert_eq!(
                (&c["verdict"], &c["measured"]),
                (&tc["verdict"], &tc["measured"])
            );
        }
    }
    // This run's timing claims, with the verdict its paired ratio interval gives (never the
    // two separate intervals).
    assert!(claim("gouraud", "50x")["measured"]
        .as_str()
        .unwrap()
        .contains("phong_exact / gouraud per round"));
    let nr = row("newton_raphson");
    let want = if ms(nr, "ratio_ci95_high") < 1.0 {
        "agrees"
    } else if ms(nr, "ratio_ci95_low") > 1.0 {
        "disagrees"
    } else {
        "inconclusive"
    };
    assert_eq!(
        claim("newton_raphson", "faster than exact")["verdict"],
        want
    );
    assert_eq!(bench["sweeps"][0]["sweep"], "size");
    let points = bench["sweeps"][0]["points"].as_array().unwrap();
    assert!(points.len() >= 12);
    // at least 20 draws per sweep point even with --repeat 6, and the coverage reached
    for p in points {
        assert!(p["samples"].as_u64().unwrap() >= 20, "{p}");
        assert!(p["ci_confidence"].as_f64().unwrap() >= 0.95, "{p}");
    }
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
    assert_eq!(
        lines.len(),
        2 + other.len() + names.len(),
        "header + floors + methods"
    );
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
        err.contains("--error-metric: unknown metric \"nope\""),
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
    assert!(err.contains("--repeat must be at least 1"), "{err}");
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
        err.contains("--max-time must be a number of seconds > 0"),
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

/// A method with NaN pixels has an infinite error: bench still writes its files, keeps the
/// method off the Pareto front, and names it on the chart instead of plotting infinity
/// (the one-triangle mesh of tests/compare.rs, with antipodal vertex normals).
#[test]
fn bench_of_a_nan_method_keeps_it_off_the_front() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("antipodal.obj");
    std::fs::write(
        &obj,
        "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nvn 0 0 1\nf 1//1 2//2 3//3\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let (code, _, stderr) = run(&[
        "bench",
        "--runs",
        "1",
        "--mesh",
        obj.to_str().unwrap(),
        "--size",
        "32x32",
        "--methods",
        "barycentric_quadratic_exact_mid",
        "--isolated-rounds",
        "0",
        "--repeat",
        "3",
        "--warmup",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let bench: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).unwrap()).unwrap();
    let front: Vec<&str> = bench["pareto_front"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(
        !front.contains(&"barycentric_quadratic_exact_mid"),
        "{front:?}"
    );
    let svg = std::fs::read_to_string(out.join("pareto.svg")).unwrap();
    assert!(
        svg.contains("infinite error, not plotted: barycentric_quadratic_exact_mid"),
        "the chart must name the method it leaves off"
    );
}

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
    let bench: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("bench.json")).unwrap())
            .unwrap();
    let validator = schema_validator("docs/bench.schema.json");
    let errors: Vec<String> = validator
        .iter_errors(&bench)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "bench.json vs its schema:\n{}",
        errors.join("\n")
    );
    let mut broken = bench.clone();
    broken["auto_curve"][0]
        .as_object_mut()
        .unwrap()
        .remove("beaten_by");
    assert!(
        !validator.is_valid(&broken),
        "the schema check has no teeth"
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
        assert_eq!(max_abs, row["error"]["max_abs_error"].as_f64().unwrap());
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

/// `shadelab skips` on a closed mesh: every row draws the same pixels, culling halves the
/// fragment invocations, the rows are paired over the same rounds, and skips.json matches its
/// schema. With `--cull none` no culled row appears.
#[test]
fn skips_change_the_work_but_not_the_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let study = |extra: &[&str]| {
        let out = dir.path().join(extra.join("_"));
        let mut args = vec![
            "skips",
            "--scene",
            "scenes/torus.toml",
            "--size",
            "96x96",
            "--validate",
            "--repeat",
            "6",
            "--warmup",
            "1",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (code, stdout, stderr) = run(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(stdout.contains(" (default) |"), "{stdout}");
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("skips.json")).unwrap())
                .unwrap();
        v
    };
    let v = study(&[]);
    assert!(std::fs::read_to_string(dir.path().join("skips.md"))
        .unwrap()
        .contains("| cull+no_normal (default) |"));
    let validator = schema_validator("docs/skips.schema.json");
    assert!(
        validator.is_valid(&v),
        "skips.json does not match its schema"
    );
    let mut broken = v.clone();
    broken["rows"][0]["variant"]
        .as_object_mut()
        .unwrap()
        .remove("prepass");
    assert!(
        !validator.is_valid(&broken),
        "the schema check has no teeth"
    );

    assert_eq!(
        v["culls"], true,
        "the torus is closed and consistently oriented"
    );
    let rows = v["rows"].as_array().unwrap();
    let row = |name: &str| {
        rows.iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("no row {name}"))
    };
    let names: Vec<&str> = rows.iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "none",
            "cull",
            "cull+no_normal",
            "cull+no_normal+prepass",
            "cull+no_normal+front_to_back",
            "auto+cull+no_normal"
        ]
    );
    let covered = row("none")["covered_pixels"].as_u64().unwrap();
    assert!(covered > 1000, "{covered}");
    for r in rows {
        assert_eq!(
            r["covered_pixels"], covered,
            "{}: skips change no pixel",
            r["name"]
        );
        for k in ["ratio_to_none", "ratio_to_default"] {
            assert_eq!(
                r[k]["rounds"], 6,
                "{} {k}: paired over every round",
                r["name"]
            );
            let (lo, m, hi) = (
                r[k]["ci95_low"].as_f64().unwrap(),
                r[k]["median"].as_f64().unwrap(),
                r[k]["ci95_high"].as_f64().unwrap(),
            );
            assert!(
                lo > 0.0 && lo <= m && m <= hi,
                "{} {k}: {lo} {m} {hi}",
                r["name"]
            );
        }
    }
    assert_eq!(rows.iter().filter(|r| r["is_default"] == true).count(), 1);
    assert_eq!(v["default"], "cull+no_normal");
    let inv = |name: &str| row(name)["fragment_invocations"].as_u64().unwrap();
    // Culling leaves out the back faces: about half of the torus's fragments.
    assert!(
        inv("cull") * 10 < inv("none") * 6,
        "cull {} none {}",
        inv("cull"),
        inv("none")
    );
    assert_eq!(
        inv("cull"),
        inv("cull+no_normal"),
        "the normal target changes no fragment"
    );
    // The pre-pass's own fragments are counted too.
    assert!(inv("cull+no_normal+prepass") > inv("cull+no_normal"));

    // Teeth of the culling rows: with culling off there is none.
    let v = study(&["--cull", "none"]);
    assert_eq!(v["culls"], false);
    let rows = v["rows"].as_array().unwrap();
    assert!(rows.iter().all(|r| r["variant"]["cull"] == false));
    assert_eq!(v["default"], "no_normal");
}

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
    let bench: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("bench.json")).unwrap())
            .unwrap();
    let validator = schema_validator("docs/bench.schema.json");
    let errors: Vec<String> = validator
        .iter_errors(&bench)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    let mut broken = bench.clone();
    broken["methods"][0]["runs"]
        .as_object_mut()
        .unwrap()
        .remove("confidence");
    assert!(!validator.is_valid(&broken), "the runs schema has no teeth");
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
        (&["--runs", "0"][..], "--runs must be at least 1"),
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
