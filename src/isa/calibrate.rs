//! `shadelab isa --calibrate`: each family's throughput model against published measurements
//! of real GPUs of the same architecture. Micro-kernels ([`Kernel`]: dependent chains of one
//! operation, as colour-only methods of glsl/methods' vocabulary) are compiled as timed draws
//! on every family set up, each at two chain lengths ([`CHAINS`]); the cost of one step is the
//! difference of the family's ranking statistic over the difference of lengths, so the
//! program around the chain cancels, and a per-pipe model (Mali, Apple) prices the step on the
//! pipe it loads once the chain bounds the program. Each [`Ratio`] is a step's cost over an
//! FMA step's, beside the [`MEASUREMENTS`] (each citing its source) of the architecture and
//! the factor between them. The models are never fitted to these figures.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{IsaOptions, IsaReport};
use crate::error::{Error, Result};

/// The two chain lengths of every kernel: long enough that a chain of FMAs bounds a Valhall
/// program (32 FMAs are half a cycle of its FMA pipe, as much as the shared varying's).
pub const CHAINS: [u32; 2] = [32, 64];
/// Model and measurement disagree beyond this factor (either way): the docs say which the
/// answer uses and why (docs/isa.md, "Calibration").
pub const DISAGREE: f64 = 1.5;

pub use super::kernel::{Kernel, Ratio, KERNELS, RATIOS};

/// A published measurement of a real GPU: the cost of `ratio` in FMAs, a range where the
/// source gives one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Measurement {
    /// The families (ids) of the measured GPU's architecture.
    pub families: &'static [&'static str],
    pub ratio: Ratio,
    pub low: f64,
    pub high: f64,
    pub gpu: &'static str,
    /// Document, table and version (URL).
    pub source: &'static str,
    /// False where the family's compiler model shares its numbers (Apple: agx_performance.c
    /// has philipturner's figures).
    pub independent: bool,
}

/// azhirnov/as-en, "Shader instruction benchmark" tables (AE/docs/papers/bench*/), costs
/// relative to the file's base rate; the RX 570 and Mali-G57 files at the versions named.
const RX570: &str = "azhirnov/as-en AE/docs/papers/bench-gpu/AMD_RX570.md, \"Instruction cost\" \
(version 71fc69b61cf7de4967f9ca7d75d043a8c065504e; https://github.com/azhirnov/as-en)";
const RTX2080: &str = "azhirnov/as-en AE/docs/papers/bench/NVidia_RTX2080.md (snapshot \
2182035b2a09f5b25fc4f3aefb269aa240b857bf; https://github.com/azhirnov/as-en); FMA 2, InvSqrt 7, \
Normalize 3, Dot 4 against Add 1, here over FMA";
const ADRENO640: &str = "Chips and Cheese, \"Inside the Snapdragon 855's iGPU\" \
(https://chipsandcheese.com/2024/05/01/inside-the-snapdragon-855s-igpu/): 407 GOPS FP32 FMA, 55 \
GOPS reciprocal and inverse square root; restated in azhirnov/cpu-gpu-arch gpu/Adreno-600.md \
(2acaba551b1a4f7814c6400743be3181f13016ad)";
const ADRENO660: &str = "azhirnov/as-en AE/docs/papers/bench/Adreno_660.md (snapshot \
2182035b2a09f5b25fc4f3aefb269aa240b857bf; https://github.com/azhirnov/as-en); FMA 1-1.5, \
InvSqrt 6";
const MALI_G57: &str = "azhirnov/as-en AE/docs/papers/bench-gpu/ARM_Mali_G57.md (version \
14857690ea4d0bcdb86d823c48bee83e8db3949d; https://github.com/azhirnov/as-en)";
const APPLE_M1: &str = "azhirnov/as-en AE/docs/papers/bench/Apple_M1.md (snapshot \
2182035b2a09f5b25fc4f3aefb269aa240b857bf; https://github.com/azhirnov/as-en)";
const METAL_BENCHMARKS: &str = "philipturner/metal-benchmarks README.md, \"Instruction \
Throughputs\" (dc2adc640a1588246f4471d415aa6873cb6e3499; \
https://github.com/philipturner/metal-benchmarks)";

const ADRENO_6XX: &[&str] = &["qualcomm:a618", "qualcomm:a630", "qualcomm:a660"];

const fn point(
    families: &'static [&'static str],
    ratio: Ratio,
    v: f64,
    gpu: &'static str,
    source: &'static str,
) -> Measurement {
    Measurement {
        families,
        ratio,
        low: v,
        high: v,
        gpu,
        source,
        independent: true,
    }
}

/// Every measurement the calibration checks against.
pub const MEASUREMENTS: [Measurement; 14] = [
    point(
        &["amd:polaris10"],
        Ratio::Rsqrt,
        3.0,
        "Radeon RX 570 (Polaris, GCN4)",
        RX570,
    ),
    point(
        &["amd:polaris10"],
        Ratio::Normalize,
        1.5,
        "Radeon RX 570 (Polaris, GCN4)",
        RX570,
    ),
    point(
        &["amd:polaris10"],
        Ratio::Dot,
        2.0,
        "Radeon RX 570 (Polaris, GCN4)",
        RX570,
    ),
    point(
        &["nvidia:nv162"],
        Ratio::Rsqrt,
        3.5,
        "GeForce RTX 2080 (TU104, Turing)",
        RTX2080,
    ),
    point(
        &["nvidia:nv162"],
        Ratio::Normalize,
        1.5,
        "GeForce RTX 2080 (TU104, Turing)",
        RTX2080,
    ),
    point(
        &["nvidia:nv162"],
        Ratio::Dot,
        2.0,
        "GeForce RTX 2080 (TU104, Turing)",
        RTX2080,
    ),
    point(
        ADRENO_6XX,
        Ratio::Rsqrt,
        407.0 / 55.0,
        "Adreno 640 (a6xx)",
        ADRENO640,
    ),
    point(
        ADRENO_6XX,
        Ratio::Rcp,
        407.0 / 55.0,
        "Adreno 640 (a6xx)",
        ADRENO640,
    ),
    Measurement {
        families: &["qualcomm:a660"],
        ratio: Ratio::Rsqrt,
        low: 4.0,
        high: 6.0,
        gpu: "Adreno 660 (a6xx)",
        source: ADRENO660,
        independent: true,
    },
    point(
        &["arm:g57"],
        Ratio::Rsqrt,
        3.0,
        "Mali-G57 (Valhall)",
        MALI_G57,
    ),
    point(
        &["arm:g57"],
        Ratio::Normalize,
        1.5,
        "Mali-G57 (Valhall)",
        MALI_G57,
    ),
    point(
        &["arm:g57"],
        Ratio::Dot,
        2.5,
        "Mali-G57 (Valhall)",
        MALI_G57,
    ),
    point(
        &["apple:g13"],
        Ratio::Rsqrt,
        5.0,
        "Apple M1 (G13)",
        APPLE_M1,
    ),
    Measurement {
        families: &["apple:g13"],
        ratio: Ratio::Rsqrt,
        low: 8.0,
        high: 8.0,
        gpu: "Apple M1 Max (G13)",
        source: METAL_BENCHMARKS,
        independent: false,
    },
];

/// model / measured, 1 inside a measured range.
pub fn factor(model: f64, low: f64, high: f64) -> f64 {
    if model < low {
        model / low
    } else if model > high {
        model / high
    } else {
        1.0
    }
}

/// One family's check of one ratio against one measurement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    pub ratio: Ratio,
    pub model: f64,
    pub measured_low: f64,
    pub measured_high: f64,
    pub gpu: String,
    pub source: String,
    pub independent: bool,
    /// model / measured (1 inside a range).
    pub factor: f64,
    /// The factor beyond [`DISAGREE`] either way.
    pub disagrees: bool,
}

/// One family's calibration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FamilyCalibration {
    pub family: String,
    pub supported: bool,
    pub status: String,
    /// The ranking statistic the kernels were read in (docs/isa.md).
    pub statistic: Option<String>,
    /// Its unit ("FP32 FMAs per pixel", "cycles per wave"); where the route counts FMAs, the
    /// FMA step must be one of it ([`not_positive`]).
    #[serde(default)]
    pub unit: Option<String>,
    /// The cost of one step of each kernel, in the statistic's unit.
    pub step: BTreeMap<Kernel, f64>,
    /// Each ratio the model gives (absent where it gives none: an FMA step that costs
    /// nothing, a kernel missing).
    pub model: BTreeMap<Ratio, f64>,
    /// The ratios whose step the family's compiler fuses into its neighbours ([`fused`]):
    /// zero or below by design, reported as fused.
    #[serde(default)]
    pub fused: Vec<Ratio>,
    pub checks: Vec<Check>,
}

/// calibration.json (docs/calibration.schema.json).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    pub schema_version: u32,
    pub chains: [u32; 2],
    /// Each kernel's step, as compiled.
    pub kernels: BTreeMap<Kernel, String>,
    pub disagree_factor: f64,
    pub families: Vec<FamilyCalibration>,
    pub elapsed_s: f64,
}

/// Writes each kernel's method file at each chain length under `dir`: their paths.
pub fn write_kernels(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut paths = Vec::new();
    for k in KERNELS {
        for n in CHAINS {
            let p = dir.join(format!("{}.glsl", k.method(n)));
            std::fs::write(&p, k.glsl(n)).map_err(|e| Error::io(&p, e))?;
            paths.push(p);
        }
    }
    Ok(paths)
}

/// Each family's calibration out of `report` (the kernels compiled as draws), read in each
/// family's ranking statistic.
pub fn calibrate(report: &IsaReport, elapsed_s: f64) -> Calibration {
    calibrate_in(report, elapsed_s, &|f| {
        f.ranking.as_ref().map(|r| r.key.clone())
    })
}

/// [`calibrate`] read in the statistic `key_of` names for each family (another statistic
/// than the ranking: what a test of [`not_positive`] feeds it to show it can fail).
pub fn calibrate_in(
    report: &IsaReport,
    elapsed_s: f64,
    key_of: &dyn Fn(&super::report::FamilyStatus) -> Option<String>,
) -> Calibration {
    let families = report
        .families
        .iter()
        .map(|f| {
            let key = key_of(f);
            let step: BTreeMap<Kernel, f64> = match &key {
                Some(key) if f.supported => KERNELS
                    .iter()
                    .filter_map(|&k| Some((k, step_cost(report, &f.family, k, key)?)))
                    .collect(),
                _ => BTreeMap::new(),
            };
            let model: BTreeMap<Ratio, f64> = RATIOS
                .iter()
                .filter_map(|&r| Some((r, r.of(&step)?)))
                .collect();
            FamilyCalibration {
                checks: checks(&f.id, &model),
                family: f.id.clone(),
                supported: f.supported,
                status: f.status.clone(),
                unit: f.ranking.as_ref().map(|r| r.unit.clone()),
                fused: fused(&f.id).iter().map(|(r, _)| *r).collect(),
                statistic: key,
                step,
                model,
            }
        })
        .collect();
    Calibration {
        schema_version: 1,
        chains: CHAINS,
        kernels: KERNELS.iter().map(|&k| (k, k.step().to_string())).collect(),
        disagree_factor: DISAGREE,
        families,
        elapsed_s,
    }
}

/// The steps `family`'s compiler fuses, each ratio with why ([`Vendor::fused_steps`]); none
/// for an id no route knows.
///
/// [`Vendor::fused_steps`]: super::route::Vendor::fused_steps
pub fn fused(family: &str) -> &'static [(Ratio, &'static str)] {
    super::route::resolve(family).map_or(&[], |(v, chip)| v.fused_steps(&chip))
}

/// What makes `f`'s model unfit to rank programs, a line each (empty when nothing does): a
/// kernel's step that costs nothing or less, a ratio that is zero or negative and not fused
/// ([`fused`]), an FMA step that is not one unit of a model that counts FMAs
/// ([`super::route::Vendor::counts_fmas`]).
pub fn not_positive(f: &FamilyCalibration) -> Vec<String> {
    if !f.supported {
        return Vec::new();
    }
    let mut lines = Vec::new();
    for (k, v) in &f.step {
        let fused_step = f.fused.iter().any(|r| r.kernel() == *k);
        if !(*v > 0.0) && !fused_step {
            lines.push(format!("{}: the {} step costs {v}", f.family, k.name()));
        }
    }
    for (r, v) in &f.model {
        if !(*v > 0.0) && !f.fused.contains(r) {
            lines.push(format!("{}: {} costs {v:.3} FMAs", f.family, r.name()));
        }
    }
    let counts_fmas = super::route::resolve(&f.family).is_ok_and(|(v, _)| v.counts_fmas());
    if let (true, Some(fma)) = (counts_fmas, f.step.get(&Kernel::Fma)) {
        if !(0.9..=1.1).contains(fma) {
            lines.push(format!(
                "{}: an FMA step costs {fma:.3} in a model counted in {}",
                f.family,
                f.unit.as_deref().unwrap_or("FMAs")
            ));
        }
    }
    lines
}

/// The checks of `family`'s `model` ratios against [`MEASUREMENTS`].
pub fn checks(family: &str, model: &BTreeMap<Ratio, f64>) -> Vec<Check> {
    MEASUREMENTS
        .iter()
        .filter(|m| m.families.contains(&family))
        .filter_map(|m| {
            let v = *model.get(&m.ratio)?;
            let f = factor(v, m.low, m.high);
            Some(Check {
                ratio: m.ratio,
                model: v,
                measured_low: m.low,
                measured_high: m.high,
                gpu: m.gpu.into(),
                source: m.source.into(),
                independent: m.independent,
                factor: f,
                disagrees: !(1.0 / DISAGREE..=DISAGREE).contains(&f),
            })
        })
        .collect()
}

/// The cost of one step of `kernel` on `family` (row key) in `key`: the fragment draws'
/// difference over the chains' difference.
fn step_cost(report: &IsaReport, family: &str, kernel: Kernel, key: &str) -> Option<f64> {
    let [a, b] = CHAINS.map(|n| {
        super::table::find_row(
            &report.results,
            family,
            &kernel.method(n),
            "fragment",
            crate::isa::request::RowKind::Draw,
        )
        .and_then(|r| r.statistics.get(key).copied())
    });
    let per = (b? - a?) / f64::from(CHAINS[1] - CHAINS[0]);
    per.is_finite().then_some(per)
}

/// Compiles the kernels on `families` (every default family when empty) with `exe`'s
/// children: the report their calibration is read from. `progress` hears each family.
pub fn compile(
    exe: PathBuf,
    families: Vec<String>,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<IsaReport> {
    let dir = crate::cleanup::TempDir::new("calibrate")
        .map_err(|e| Error::io(std::env::temp_dir(), e))?;
    let paths = write_kernels(dir.path())?;
    // Their float16 programs fail to compile by design (plain float): not worth a warning each.
    let level = log::max_level();
    log::set_max_level(log::LevelFilter::Error.min(level));
    let registered = crate::gpu::shaders::register_user(&paths);
    log::set_max_level(level);
    registered?;
    let methods = KERNELS
        .iter()
        .flat_map(|k| CHAINS.map(|n| k.method(n)))
        .map(|m| crate::method::find(&m))
        .collect::<Result<Vec<_>>>()?;
    let opts = IsaOptions {
        methods,
        families: if families.is_empty() {
            super::route::default_family_ids()
        } else {
            families
        },
        driver_files: None,
        scene: None,
        exe,
        precision: super::Precision::F32,
        probes: Vec::new(),
        // the kernels are keyed by their content, so a second calibration reads them back
        store: super::store::default_store(),
    };
    super::run_with(&opts, true, progress)
}

/// Compiles the kernels on `families` (every default family when empty) with `exe`'s children
/// and writes `out`/calibration.json; the calibration.
pub fn run(
    exe: PathBuf,
    families: Vec<String>,
    out: &Path,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Calibration> {
    let start = std::time::Instant::now();
    let report = compile(exe, families, progress)?;
    let cal = calibrate(&report, start.elapsed().as_secs_f64());
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let path = out.join("calibration.json");
    let json = serde_json::to_vec_pretty(&cal).map_err(|e| Error::output("calibration.json", e))?;
    crate::output::write_bytes_atomic(&path, &json)?;
    Ok(cal)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steps(fma: f64, rsqrt: f64, rcp: f64) -> BTreeMap<Kernel, f64> {
        [
            (Kernel::Fma, fma),
            (Kernel::Rsqrt, rsqrt),
            (Kernel::Rcp, rcp),
        ]
        .into()
    }

    #[test]
    fn ratios_are_steps_over_the_fma_step() {
        let s = steps(1.0, 4.0, 5.0);
        assert_eq!(Ratio::Rsqrt.of(&s), Some(4.0));
        // The reciprocal's step carries an addition: one FMA off.
        assert_eq!(Ratio::Rcp.of(&s), Some(4.0));
        // Teeth: no FMA cost, or no kernel, gives no ratio (never inf or NaN).
        assert_eq!(Ratio::Rsqrt.of(&steps(0.0, 4.0, 5.0)), None);
        assert_eq!(Ratio::Dot.of(&s), None);
    }

    #[test]
    fn the_factor_is_one_inside_a_range_and_the_disagreement_is_flagged() {
        assert_eq!(factor(5.0, 4.0, 6.0), 1.0);
        assert_eq!(factor(8.0, 4.0, 6.0), 8.0 / 6.0);
        assert_eq!(factor(2.0, 4.0, 6.0), 0.5);
        // Turing: a weight of 4 against the RTX 2080's 3.5 agrees; a weight of 1 (a bare
        // count) does not.
        let agree = checks("nvidia:nv162", &[(Ratio::Rsqrt, 4.0)].into());
        assert_eq!(agree.len(), 1);
        assert!(!agree[0].disagrees && agree[0].independent);
        let count = checks("nvidia:nv162", &[(Ratio::Rsqrt, 1.0)].into());
        assert!(count[0].disagrees, "{count:?}");
        assert!(checks("nvidia:nvc0", &[(Ratio::Rsqrt, 1.0)].into()).is_empty());
    }

    #[test]
    fn every_measurement_is_cited_and_finite() {
        for m in MEASUREMENTS {
            assert!(m.source.contains("https://"), "{m:?}");
            assert!(m.low.is_finite() && m.high >= m.low && m.low > 0.0, "{m:?}");
            assert!(m.families.iter().all(|f| f.contains(':')), "{m:?}");
        }
    }

    #[test]
    fn kernels_are_colour_methods_with_their_chain() {
        let g = Kernel::Rsqrt.glsl(64);
        assert_eq!(g.matches("x = inversesqrt(x);").count(), 64 + 1);
        let mut s = steps(1.0, 4.0, 5.0);
        s.insert(Kernel::Dot, 6.0);
        assert_eq!(Ratio::Dot.of(&s), Some(2.0));
        assert!(g.contains("#define METHOD_COLOR") && g.contains("shadelab-inputs:"));
        assert_eq!(Kernel::Dot.method(128), "calibration_dot_128");
    }

    fn family(name: &str, unit: &str, step: BTreeMap<Kernel, f64>) -> FamilyCalibration {
        let model = RATIOS
            .iter()
            .filter_map(|&r| Some((r, r.of(&step)?)))
            .collect();
        FamilyCalibration {
            family: name.into(),
            supported: true,
            status: "compiled".into(),
            statistic: Some("model_cycles".into()),
            unit: Some(unit.into()),
            step,
            model,
            fused: fused(name).iter().map(|(r, _)| *r).collect(),
            checks: Vec::new(),
        }
    }

    #[test]
    fn a_model_that_prices_latency_is_not_positive() {
        let unit = "FP32 FMAs per pixel";
        // A throughput model: every step above zero, one FMA one unit.
        assert!(not_positive(&family("intel:icl", unit, steps(1.0, 2.0, 2.0))).is_empty());
        // Teeth: brw's latency estimate of icl (an FMA 44.25 cycles, a reciprocal with its
        // addition 36): a negative reciprocal and an FMA that is not one unit.
        let latency = not_positive(&family("intel:icl", unit, steps(44.25, 51.0, 36.0)));
        assert_eq!(latency.len(), 2, "{latency:?}");
        assert!(latency[0].contains("rcp costs -0.186"), "{latency:?}");
        assert!(
            latency[1].contains("an FMA step costs 44.250"),
            "{latency:?}"
        );
        // A step that costs nothing fails too, in a model of any unit.
        let free = not_positive(&family(
            "amd:navi21",
            "cycles per wave",
            steps(4.0, 0.0, 8.0),
        ));
        assert_eq!(free.len(), 2, "{free:?}");
        // A fused step is reported as fused, not as a failure; elsewhere the same figure fails.
        assert!(not_positive(&family("arm:t860", "cycles", steps(1.0, 4.0, 1.0))).is_empty());
        assert_eq!(
            not_positive(&family("arm:g57", "cycles", steps(1.0, 4.0, 1.0))).len(),
            1
        );
        for family in ["arm:mali450", "arm:t860"] {
            assert!(
                fused(family).iter().all(|(_, why)| why.len() > 40),
                "{family}"
            );
        }
    }
}
