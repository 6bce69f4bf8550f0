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
    let methods = bench["methods"].as_array().unwrap();
    let row = |n: &str| methods.iter().find(|m| m["name"] == n).unwrap();
    let (exact, unnormalized) = (row("phong_exact"), row("phong_unnormalized"));
    let ms = |m: &serde_json::Value, k: &str| m[k].as_f64().unwrap();

    // Ratios, recomputed from the rows' medians (gouraud's and newton_raphson's are not 1 by
    // construction, as phong_exact's own is).
    let floor_ms = ms(&bench["floor"], "median_ms");
    let exact_ms = ms(exact, "median_ms");
    for m in methods {
        let med = ms(m, "median_ms");
        let close = |k: &str, want: f64| {
            let got = ms(m, k);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs(),
                "{} {k}: {got} vs {want}",
                m["name"]
            );
        };
        close("ratio_to_phong_exact", med / exact_ms);
        close(
            "ratio_above_floor_to_phong_exact",
            (med - floor_ms) / (exact_ms - floor_ms),
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
    // This run's timing claims, with the verdict its 95% intervals give.
    assert!(claim("gouraud", "50x")["measured"]
        .as_str()
        .unwrap()
        .contains("phong_exact / gouraud"));
    let nr = row("newton_raphson");
    let want = if ms(nr, "ci95_high_ms") < ms(exact, "ci95_low_ms") {
        "agrees"
    } else if ms(nr, "ci95_low_ms") > ms(exact, "ci95_high_ms") {
        "disagrees"
    } else {
        "inconclusive"
    };
    assert_eq!(
        claim("newton_raphson", "faster than exact")["verdict"],
        want
    );
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
        "--mesh",
        obj.to_str().unwrap(),
        "--size",
        "32x32",
        "--methods",
        "barycentric_quadratic_exact_mid",
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
