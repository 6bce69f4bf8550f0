//! `shadelab isa --calibrate`: calibration.json against its schema, every figure finite, the
//! models' ratios as their weights say, and checks against published measurements that fail
//! on a wrong weight.
use shadelab::isa::calibrate::{self, Ratio};
use shadelab::isa::throughput;

use crate::isa::families_ready;
use crate::support::{assert_schema, read_json, run};

const FAMILIES: [&str; 2] = ["amd:polaris10", "nvidia:nv162"];

#[test]
fn calibration_json_holds_each_models_ratios_beside_the_measurements() {
    let test = "calibration_json_holds_each_models_ratios_beside_the_measurements";
    if !families_ready(test, &FAMILIES, "SHADELAB_REQUIRE_VENDORS") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal");
    let (code, stdout, stderr) = run(&[
        "isa",
        "--calibrate",
        "--families",
        &FAMILIES.join(","),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("nvidia:nv162"), "{stdout}");
    let json = read_json(out.join("calibration.json"));
    assert_schema(
        &json,
        "docs/calibration.schema.json",
        "/families/0",
        "model",
    );
    let cal: calibrate::Calibration = serde_json::from_value(json.clone()).unwrap();
    for f in &cal.families {
        assert!(f.supported, "{}: {}", f.family, f.status);
        // Every kernel's step and every ratio, all finite.
        assert_eq!(f.step.len(), calibrate::KERNELS.len(), "{}", f.family);
        assert_eq!(f.model.len(), calibrate::RATIOS.len(), "{}", f.family);
        assert!(f
            .step
            .values()
            .chain(f.model.values())
            .all(|v| v.is_finite()));
        assert!(f
            .checks
            .iter()
            .all(|c| c.factor.is_finite() && c.factor > 0.0));
    }
    let nv = cal
        .families
        .iter()
        .find(|f| f.family == "nvidia:nv162")
        .unwrap();
    // The weighted count prices an rsqrt at Turing's weight (a bare count would say 1).
    assert_eq!(nv.model[&Ratio::Rsqrt], throughput::TURING.sfu);
    let rsqrt = nv.checks.iter().find(|c| c.ratio == Ratio::Rsqrt).unwrap();
    assert!(rsqrt.independent && !rsqrt.disagrees, "{rsqrt:?}");
    // ACO's quarter-rate transcendental on GCN.
    let amd = cal
        .families
        .iter()
        .find(|f| f.family == "amd:polaris10")
        .unwrap();
    assert_eq!(amd.model[&Ratio::Rsqrt], 4.0);
    // Teeth: a wrong weight makes the check fail, either way: the bare count (1), or twice
    // Turing's (8).
    for wrong in [1.0, 8.0] {
        let c = calibrate::checks("nvidia:nv162", &[(Ratio::Rsqrt, wrong)].into());
        assert!(c[0].disagrees, "a weight of {wrong} passes: {c:?}");
    }
    // Teeth of the schema on a figure: a non-number ratio is refused.
    let mut bad = json;
    bad["families"][0]["model"]["rsqrt"] = "4".into();
    assert!(!crate::support::schema_validator("docs/calibration.schema.json").is_valid(&bad));
}

#[test]
fn calibrate_refuses_the_method_options() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cal");
    let (code, _, stderr) = run(&[
        "isa",
        "--calibrate",
        "--methods",
        "phong_exact",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--methods"), "{stderr}");
    assert!(!out.join("calibration.json").exists());
}

/// Every family set up prices every calibration step above zero (fused steps aside, each
/// with its reason), and one FMA at one unit where the model counts FMAs. Teeth: Intel read
/// in brw's latency estimate (`cycle_count`, the former ranking) fails, as a reciprocal
/// comes out at or below nothing and an FMA at many cycles.
#[test]
fn every_family_prices_every_step_above_zero() {
    let families =
        crate::store::set_up_families("calibrate::every_family_prices_every_step_above_zero");
    if families.is_empty() {
        return;
    }
    let exe = std::path::PathBuf::from(env!("CARGO_BIN_EXE_shadelab"));
    let report = calibrate::compile(exe, families.clone(), &|_| {}).unwrap();
    let cal = calibrate::calibrate(&report, 0.0);
    let compiled: Vec<&str> = cal
        .families
        .iter()
        .filter(|f| f.supported)
        .map(|f| f.family.as_str())
        .collect();
    assert_eq!(compiled, families, "{:#?}", cal.families);
    for f in &cal.families {
        assert_eq!(f.step.len(), calibrate::KERNELS.len(), "{}", f.family);
        assert!(
            calibrate::not_positive(f).is_empty(),
            "{:?}",
            calibrate::not_positive(f)
        );
        for r in &f.fused {
            assert!(calibrate::fused(&f.family)
                .iter()
                .any(|(x, why)| x == r && !why.is_empty()));
        }
    }
    // Teeth: brw's latency estimate as the model.
    let intel: Vec<&String> = families
        .iter()
        .filter(|f| f.starts_with("intel:"))
        .collect();
    if intel.is_empty() {
        return;
    }
    let latency = calibrate::calibrate_in(&report, 0.0, &|f| {
        f.id.starts_with("intel:")
            .then(|| "cycle_count".to_string())
    });
    let failing: Vec<&str> = latency
        .families
        .iter()
        .filter(|f| f.family.starts_with("intel:") && !calibrate::not_positive(f).is_empty())
        .map(|f| f.family.as_str())
        .collect();
    assert!(!failing.is_empty(), "{:#?}", latency.families);
}
