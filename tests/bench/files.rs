//! `shadelab bench`: the files of a run in their documented shape (bench.json against its
//! schema, bench.csv, the charts, claims), the control, a sweep, and a NaN method kept off the
//! front.
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
    let bench = read_json(dir.path().join("bench.json"));
    assert_schema(
        &bench,
        "docs/bench.schema.json",
        "/methods/0",
        "ci95_high_ms",
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
        // the speed word is the product's rule applied to the row's own paired interval
        let r = shadelab::analysis::stats::RatioEstimate {
            median: m["ratio_median"].as_f64().unwrap_or(f64::NAN),
            ci95_low: m["ratio_ci95_low"].as_f64().unwrap_or(f64::NAN),
            ci95_high: m["ratio_ci95_high"].as_f64().unwrap_or(f64::NAN),
            rounds: m["ratio_rounds"].as_u64().unwrap() as usize,
            non_finite: m["ratio_non_finite"].as_u64().unwrap() as usize,
            confidence: m["ratio_confidence"].as_f64().unwrap(),
        };
        assert_eq!(
            m["speed_vs_phong_exact"],
            shadelab::bench::Speed::from_ratio(&r).as_str(),
            "{m}"
        );
    }
    let row = |n: &str| methods.iter().find(|m| m["name"] == n).unwrap();
    let (exact, unnormalized) = (row("phong_exact"), row("phong_unnormalized"));
    let ms = |m: &serde_json::Value, k: &str| m[k].as_f64().unwrap();
    // every round gave phong_exact a time, and the control (the same program, timed in its
    // own submissions) has rounds of its own: its per-round ratio to phong_exact is finite in
    // every round and not identically 1 (it would be if the control reused phong_exact's
    // samples)
    assert_eq!(exact["ratio_non_finite"], 0);
    let control = row("phong_exact_control");
    assert_eq!(control["ratio_non_finite"], 0, "{control}");
    assert_eq!(control["ratio_rounds"], exact["ratio_rounds"]);
    let (clo, chi) = (
        ms(control, "ratio_ci95_low"),
        ms(control, "ratio_ci95_high"),
    );
    assert!(clo > 0.0 && chi.is_finite() && clo < chi, "{control}");
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
            // every checked claim of the run's methods is in claims.json (the verdict is the
            // same check's: comparing it would compare the check with itself)
            let c = claim(t["name"].as_str().unwrap(), tc["claim"].as_str().unwrap());
            assert!(c["verdict"].is_string(), "{c}");
        }
    }
    // This run's timing claims, with the verdict its paired ratio interval gives (never the
    // two separate intervals); gouraud's 50x is the row's Speed claim, judged like every
    // speed factor (the ratio to phong_exact against 1/50).
    let g = claim("gouraud", "50x");
    let measured = g["measured"].as_str().unwrap();
    assert!(
        measured.contains("gouraud / phong_exact by paired frame time: median")
            && measured.contains("the claim needs <= 0.0200"),
        "{g}"
    );
    // the claim judges this run's paired ratio (its interval is in `measured`) and follows
    // the row's own speed word: faster agrees, slower disagrees, else inconclusive
    let nr = row("newton_raphson");
    let c = claim("newton_raphson", "faster than exact");
    let interval = format!(
        "[{:.4}, {:.4}]",
        ms(nr, "ratio_ci95_low"),
        ms(nr, "ratio_ci95_high")
    );
    assert!(c["measured"].as_str().unwrap().contains(&interval), "{c}");
    let want = match nr["speed_vs_phong_exact"].as_str().unwrap() {
        "faster" => "agrees",
        "slower" => "disagrees",
        _ => "inconclusive",
    };
    assert_eq!(c["verdict"], want, "{c}");
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
    let bench = read_json(out.join("bench.json"));
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
