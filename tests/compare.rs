//! `shadelab compare`: outputs, schema, statistics against the f64 truth, and --fail-above.
use std::path::Path;

use crate::support::*;

fn schema() -> serde_json::Value {
    read_json(root().join("docs/summary.schema.json"))
}

fn compare(out: &Path, extra: &[&str]) -> (i32, String, String) {
    let mut args = vec![
        "compare",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "64x64",
        "--validate",
        "--methods",
        "phong_exact,phong_unnormalized,flat,gouraud,newton_raphson,trueform",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    run(&args)
}

#[test]
fn compare_writes_a_valid_summary_heatmaps_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = compare(dir.path(), &[]);
    assert_eq!(code, 0, "{stderr}");
    let summary = read_json(dir.path().join("summary.json"));
    assert_schema(
        &summary,
        "docs/summary.schema.json",
        "/methods/0",
        "p99_abs_error",
    );

    let methods = summary["methods"].as_array().unwrap();
    let get = |n: &str| methods.iter().find(|m| m["name"] == n).unwrap().clone();
    // exact Phong against its own f64 truth: the float32 level (bound: tests/gpu.rs)
    assert!(get("phong_exact")["max_abs_error"].as_f64().unwrap() < 1e-4);
    // teeth: without normalization the error is far above it
    assert!(get("phong_unnormalized")["max_abs_error"].as_f64().unwrap() > 1e-2);
    // methods without a per-pixel normal report null normal metrics, not 0
    assert!(get("gouraud")["max_normal_angle_deg"].is_null());
    // flat has a per-pixel normal (the unit face normal): a number, at the float32 level of
    // one normalization (the K_FORMULA budget of src/truth/mod.rs: 32 u = 1.9e-6)
    let flat_len = get("flat")["max_normal_length_error"].as_f64();
    let unit = shadelab::truth::K_FORMULA * shadelab::truth::U;
    assert!(flat_len.is_some_and(|e| e <= unit), "flat: {flat_len:?}");
    // trueform changes the silhouette: pixels covered by only one are counted
    assert!(
        get("trueform")["coverage_mismatch_pixels"]
            .as_u64()
            .unwrap()
            > 0
    );
    assert_eq!(
        get("phong_exact")["coverage_mismatch_pixels"].as_u64(),
        Some(0)
    );
    assert!(summary["background_pixels"].as_u64().unwrap() > 0);
    for m in methods {
        for f in m["files"].as_array().unwrap() {
            assert!(
                dir.path().join(f.as_str().unwrap()).is_file(),
                "missing {f}"
            );
        }
    }
    assert!(dir.path().join("gouraud/error_abs.png").is_file());
    assert!(
        !dir.path().join("gouraud/error_angle.png").exists(),
        "no angle map without normals"
    );
    // CSV: header + one row per method, same columns
    let csv = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + methods.len());
    let cols = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == cols));
    assert!(lines[0].starts_with("name,reference,covered_pixels"));
    // stdout: the table sorted by error, phong_exact first
    let first = stdout.lines().nth(1).unwrap();
    assert!(first.starts_with("phong_exact "), "{stdout}");
}

#[test]
fn fail_above_exits_1_exactly_when_a_metric_exceeds_its_limit() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = compare(dir.path(), &[]);
    assert_eq!(code, 0, "{err}");
    let summary = read_json(dir.path().join("summary.json"));
    let worst = summary["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["max_abs_error"].as_f64().unwrap())
        .fold(0.0, f64::max);
    // equal to the largest value: nothing is above it
    let at = format!("max_abs_error={worst:e}");
    let (code, _, err) = compare(dir.path(), &["--fail-above", &at]);
    assert_eq!(code, 0, "{err}");
    // just below it: exit 1, naming the method and metric; images still written
    std::fs::remove_dir_all(dir.path()).unwrap();
    let below = format!("max_abs_error={:e}", worst * 0.999);
    let (code, _, err) = compare(
        dir.path(),
        &[
            "--fail-above",
            &below,
            "--fail-above",
            "max_normal_angle_deg=1000",
        ],
    );
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("threshold exceeded: ") && err.contains(" max_abs_error = "),
        "{err}"
    );
    assert_eq!(err.matches("threshold exceeded").count(), 1, "{err}");
    assert!(
        dir.path().join("summary.json").is_file()
            && dir.path().join("flat/error_abs.png").is_file()
    );
    // every method over the limit is named
    let (code, _, err) = compare(dir.path(), &["--fail-above", "max_abs_error=1e-3"]);
    assert_eq!(code, 1);
    for m in ["phong_unnormalized", "flat", "gouraud", "newton_raphson"] {
        assert!(
            err.contains(&format!("threshold exceeded: {m} max_abs_error")),
            "{m} not named:\n{err}"
        );
    }
    assert!(!err.contains("threshold exceeded: phong_exact "), "{err}");
    // a bad limit is a usage error before any work
    let (code, _, err) = compare(dir.path(), &["--fail-above", "max_error=1"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown metric \"max_error\""), "{err}");
}

#[test]
fn limits_in_the_wrong_direction_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    // higher PSNR is better: a --fail-above limit on it would pass the worse methods
    let (code, _, err) = compare(dir.path(), &["--fail-above", "psnr_db=40"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--fail-above psnr_db: higher psnr_db is better")
            && err.contains("use --fail-below psnr_db=VALUE"),
        "{err}"
    );
    let (code, _, err) = compare(dir.path(), &["--fail-below", "max_abs_error=0.1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--fail-below max_abs_error: lower max_abs_error is better")
            && err.contains("use --fail-above max_abs_error=VALUE"),
        "{err}"
    );
    assert!(
        !dir.path().join("summary.json").exists(),
        "refused before any work"
    );
}

#[test]
fn fail_below_exits_1_exactly_when_a_metric_is_below_its_limit() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, err) = compare(dir.path(), &[]);
    assert_eq!(code, 0, "{err}");
    let summary = read_json(dir.path().join("summary.json"));
    let psnr = |n: &str| {
        summary["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()["psnr_db"]
            .as_f64()
            .unwrap()
    };
    let worst = psnr("phong_unnormalized").min(psnr("flat"));
    let at = format!("psnr_db={worst:e}");
    let (code, _, err) = compare(dir.path(), &["--fail-below", &at]);
    assert_eq!(code, 0, "at the lowest PSNR nothing is below it: {err}");
    let above = format!("psnr_db={:e}", worst * 1.001);
    let (code, _, err) = compare(dir.path(), &["--fail-below", &above]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("threshold exceeded: ") && err.contains(" psnr_db = ") && err.contains(" < "),
        "{err}"
    );
    assert_eq!(err.matches("threshold exceeded").count(), 1, "{err}");
}

/// One triangle whose vertex normals include an antipodal pair: the interpolated normal passes
/// through zero inside it, and barycentric_quadratic_exact_mid's midpoint normal
/// normalize(n0 + n1) is NaN, so every pixel of that method is NaN.
const ANTIPODAL_OBJ: &str =
    "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nvn 0 0 1\nf 1//1 2//2 3//3\n";

#[test]
fn a_method_that_is_nan_everywhere_fails_every_limit() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("antipodal.obj");
    std::fs::write(&obj, ANTIPODAL_OBJ).unwrap();
    // the loader keeps the antipodal pair (it neither recomputes nor flips normals)
    let scene = shadelab::scene::scene_for_mesh(&obj).unwrap();
    let normals = &scene.mesh.normals;
    assert!(
        normals.contains(&[0.0, 0.0, 1.0]) && normals.contains(&[0.0, 0.0, -1.0]),
        "{normals:?}"
    );
    let out = dir.path().join("out");
    let run_with = |limit: &[&str]| {
        let mut args = vec![
            "compare",
            "--mesh",
            obj.to_str().unwrap(),
            "--size",
            "48x48",
            "--validate",
            "--methods",
            "barycentric_quadratic_exact_mid,phong_exact",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(limit);
        run(&args)
    };
    let (code, stdout, err) = run_with(&["--fail-above", "max_abs_error=0.01"]);
    assert_eq!(code, 1, "{stdout}{err}");
    assert!(
        err.contains("threshold exceeded: barycentric_quadratic_exact_mid max_abs_error = inf")
            && err.contains("(non-finite at "),
        "{err}"
    );
    assert!(!err.contains("threshold exceeded: phong_exact"), "{err}");
    // PSNR, higher-is-better, fails too
    let (code, _, err) = run_with(&["--fail-below", "psnr_db=0"]);
    assert_eq!(code, 1, "{err}");
    // summary.json: null plus the count, still valid against the schema
    let summary = read_json(out.join("summary.json"));
    assert!(jsonschema::validator_for(&schema())
        .unwrap()
        .is_valid(&summary));
    let nan = summary["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "barycentric_quadratic_exact_mid")
        .unwrap();
    assert!(nan["non_finite_pixels"].as_u64().unwrap() > 100, "{nan}");
    for k in [
        "max_abs_error",
        "mean_abs_error",
        "p99_abs_error",
        "psnr_db",
        "flip_mean",
    ] {
        assert!(nan[k].is_null(), "{k}: {}", nan[k]);
    }
    // the table: sorted last, shown as inf
    let rows: Vec<&str> = stdout.lines().collect();
    assert!(rows[1].starts_with("phong_exact "), "{stdout}");
    assert!(
        rows[2].starts_with("barycentric_quadratic_exact_mid ") && rows[2].contains(" inf "),
        "{stdout}"
    );
}

/// Angle-interpolating methods are judged against two references
/// (docs/formulas.md#the-two-references): slerp is far from exact Phong (it interpolates by angle)
/// and at float rounding from exact slerp; methods judged against Phong only carry null there.
#[test]
fn angle_interpolating_methods_report_a_second_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path();
    let (code, _, err) = run(&[
        "compare",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "96x96",
        "--methods",
        "slerp,dichotomy_exact,phong_exact",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let s = read_json(out.join("summary.json"));
    assert!(jsonschema::validator_for(&schema()).unwrap().is_valid(&s));
    let row = |n: &str| {
        s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == n)
            .unwrap()
            .clone()
    };
    let slerp = row("slerp");
    let vs_phong = slerp["max_abs_error"].as_f64().unwrap();
    let vs_slerp = slerp["against_slerp"]["max_abs_error"].as_f64().unwrap();
    assert_eq!(slerp["against_slerp"]["reference"], "slerp_f64");
    // float32 rounding against its own formula; the angle-proportional spacing against Phong
    assert!(vs_slerp < 1e-4, "{vs_slerp}");
    assert!(vs_phong > 10.0 * vs_slerp, "{vs_phong} vs {vs_slerp}");
    // dichotomy rounds t to a grid: off both references, and measured against both
    assert!(
        row("dichotomy_exact")["against_slerp"]["max_abs_error"]
            .as_f64()
            .unwrap()
            > 1e-4
    );
    assert!(row("phong_exact")["against_slerp"].is_null());
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(csv
        .lines()
        .next()
        .unwrap()
        .ends_with("against_slerp_max_normal_angle_deg"));
}

/// What the renderer skips must not change what it draws: back-face culling (`--cull`) covers
/// the same pixels with the same colours on a closed mesh, and a scene without specular
/// (k_s = 0, the specular term compiled out by a specialization constant) still matches the
/// f64 truth. Against that, a scene whose specular is on differs from its k_s = 0 twin.
#[test]
fn culling_and_specialization_change_nothing_visible() {
    let dir = tempfile::tempdir().unwrap();
    let torus = std::fs::read_to_string(root().join("scenes/torus.toml")).unwrap();
    let flat = dir.path().join("matte.toml");
    std::fs::write(
        &flat,
        torus
            .replace(
                "obj = \"torus.obj\"",
                &format!("obj = {:?}", root().join("scenes/torus.obj")),
            )
            .replace("specular = [0.5, 0.5, 0.5]", "specular = [0.0, 0.0, 0.0]"),
    )
    .unwrap();
    let summary = |scene: &str, cull: &str, out: &str| {
        let out = dir.path().join(out);
        let (code, _, err) = run(&[
            "compare",
            "--scene",
            scene,
            "--size",
            "96x96",
            "--validate",
            "--cull",
            cull,
            "--methods",
            "phong_exact,gouraud",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");

        read_json(out.join("summary.json"))
    };
    let shipped = root().join("scenes/torus.toml");
    let shipped = shipped.to_str().unwrap();
    let none = summary(shipped, "none", "none");
    let auto = summary(shipped, "auto", "auto");
    let pick = |s: &serde_json::Value, m: &str, k: &str| {
        s["methods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == m)
            .unwrap()[k]
            .clone()
    };
    for k in ["covered_pixels", "max_abs_error", "mean_abs_error"] {
        let v = pick(&none, "gouraud", k);
        assert!(v.is_number(), "{k}: {v}");
        assert_eq!(v, pick(&auto, "gouraud", k), "{k}");
    }
    let matte = summary(flat.to_str().unwrap(), "auto", "matte");
    assert!(
        pick(&matte, "phong_exact", "max_abs_error")
            .as_f64()
            .unwrap()
            < 1e-5
    );
    let g_matte = pick(&matte, "gouraud", "max_abs_error").as_f64().unwrap();
    let g_shiny = pick(&auto, "gouraud", "max_abs_error").as_f64().unwrap();
    assert!(
        g_matte < g_shiny,
        "the highlight is gone: {g_matte} vs {g_shiny}"
    );
}
