//! The results of a benchmark: bench.json, bench.csv and the text table.
use std::path::Path;

use serde::Serialize;

use super::*;
use crate::analysis::stats::RatioEstimate;
use crate::compare::{self, MethodReport};
use crate::error::{Error, Result};
use crate::gpu::spirv::{OpCounts, OpCountsDelta};
use crate::method::Verdict;
use crate::output;
use crate::output::Provenance;

/// Where a program lies against phong_exact by the paired interval of its per-round ratio.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Speed {
    /// The whole 95% interval of the ratio lies below 1.
    Faster,
    /// The whole interval lies above 1.
    Slower,
    /// The interval contains 1.
    Inconclusive,
    /// No round gave a finite ratio.
    Unmeasured,
    /// `--runs N`: the control came out faster or slower across runs; nothing is judged.
    TooNoisy,
}

impl Speed {
    /// From a paired ratio to the reference (never from two separate intervals).
    pub fn from_ratio(r: &RatioEstimate) -> Speed {
        if r.rounds == 0 || !(r.ci95_low.is_finite() && r.ci95_high.is_finite()) {
            Speed::Unmeasured
        } else if r.ci95_high < 1.0 {
            Speed::Faster
        } else if r.ci95_low > 1.0 {
            Speed::Slower
        } else {
            Speed::Inconclusive
        }
    }

    /// The snake_case name, as in the JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Speed::Faster => "faster",
            Speed::Slower => "slower",
            Speed::Inconclusive => "inconclusive",
            Speed::Unmeasured => "unmeasured",
            Speed::TooNoisy => "too_noisy",
        }
    }
}

/// One method's (or a floor's) row of bench.json.
#[derive(Debug, Clone, Serialize)]
pub struct MethodTiming {
    pub name: String,
    /// The constant-colour program on the same geometry this program is measured against:
    /// `constant` for the scene's triangles, `constant_pn_tessellated_<level>` for a PN
    /// tessellation (for a floor: the floor it is compared with, `constant`).
    pub floor_program: String,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
    pub samples: usize,
    /// The clock the median comes from (`timestamp` or `wall`).
    pub clock: crate::gpu::Clock,
    pub wall_median_ms: f64,
    pub timestamp_median_ms: Option<f64>,
    /// Covered pixels, counted in the method's own image.
    pub covered_pixels: usize,
    /// Fragment-shader invocations from a pipeline-statistics query in an untimed
    /// submission of its own, and whether they equal the covered pixels (only then are they
    /// an exact per-fragment count; Mesa 22.3 counts whole pixel blocks). `None` without
    /// pipeline statistics.
    pub fragment_invocations: Option<u64>,
    pub invocations_exact: Option<bool>,
    /// fragment_invocations / covered_pixels: shading work per visible pixel (overdraw, plus
    /// the block overcount where `invocations_exact` is false).
    pub overdraw: Option<f64>,
    pub ns_per_pixel: f64,
    /// Median minus its floor's median (same run): for a method with its own geometry, its
    /// shading cost without the cost of that geometry.
    pub above_floor_ms: f64,
    /// Ratio of the medians (kept for continuity; the paired ratio below is the one verdicts use).
    pub ratio_to_phong_exact: f64,
    /// (median - its floor) / (phong_exact - floor).
    pub ratio_above_floor_to_phong_exact: f64,
    /// Paired ratio to phong_exact: median over the rounds of (this program / phong_exact in
    /// the same round), with the sign-test 95% interval (order statistics of the per-round
    /// ratios), the rounds that gave a finite ratio, the rounds that did not, and the exact
    /// coverage of the interval.
    pub ratio_median: f64,
    pub ratio_ci95_low: f64,
    pub ratio_ci95_high: f64,
    pub ratio_rounds: usize,
    pub ratio_non_finite: usize,
    pub ratio_confidence: f64,
    /// The same against `floor_program` in the same round.
    pub ratio_to_floor_median: f64,
    pub ratio_to_floor_ci95_low: f64,
    pub ratio_to_floor_ci95_high: f64,
    pub ratio_to_floor_non_finite: usize,
    /// From the paired ratio to phong_exact.
    pub speed_vs_phong_exact: Speed,
    /// Static scalar operation counts of the fragment shader, and their excess over
    /// `phong_unnormalized` (the cost of the normalization itself).
    pub static_ops: Option<OpCounts>,
    pub static_ops_above_unnormalized: Option<OpCountsDelta>,
    /// The error metrics of `compare` (null for the floor).
    pub error: Option<MethodReport>,
    /// The isolated cost of one evaluation of the method's per-fragment code, apart from
    /// rasterization ([`crate::bench::isolated`]): per-round slopes, median and 95% interval,
    /// ns; null for the floors, for a method without a compute program (trueform) and with
    /// `--isolated-rounds 0`.
    pub isolated_ns_per_eval: Option<f64>,
    pub isolated_ci95_low_ns: Option<f64>,
    pub isolated_ci95_high_ns: Option<f64>,
    /// Paired per round: this method's slope over phong_exact's (null for phong_exact).
    pub isolated_ratio_to_phong_exact: Option<crate::bench::isolated::Interval>,
    /// From that ratio's interval: below 1 cheaper, above 1 dearer, else indistinguishable.
    pub isolated_vs_phong_exact: Option<crate::bench::isolated::Comparison>,
    /// The K = 1 kernel against the method's f64 twin on the timed cases (max colour
    /// difference): the timed code is the method.
    pub isolated_k1_max_abs_diff_vs_f64: Option<f64>,
    /// `--runs N` (N >= 2): the paired frame ratio to phong_exact across runs (the unit: a
    /// run's median ratio), with the verdict that `speed_vs_phong_exact` then repeats; the
    /// `ratio_*` fields above are then these figures too. Null with one run.
    pub runs: Option<crate::bench::runs::RunsSummary>,
    /// The same of the isolated cost (then also `isolated_ratio_to_phong_exact` and
    /// `isolated_vs_phong_exact`); null with one run or without an isolated cost.
    pub isolated_runs: Option<crate::bench::runs::RunsSummary>,
    /// Each run's own figures (empty with one run).
    pub run_figures: Vec<crate::bench::runs::RunFigure>,
}

impl MethodTiming {
    /// Fills the isolated-cost fields from a measurement.
    pub fn set_isolated(&mut self, c: &crate::bench::isolated::IsolatedCost) {
        self.isolated_ns_per_eval = Some(c.ns_per_eval.median);
        self.isolated_ci95_low_ns = Some(c.ns_per_eval.ci95_low);
        self.isolated_ci95_high_ns = Some(c.ns_per_eval.ci95_high);
        self.isolated_ratio_to_phong_exact = c.ratio_to_phong_exact;
        self.isolated_vs_phong_exact = c.versus_phong_exact;
        self.isolated_k1_max_abs_diff_vs_f64 = Some(c.k1_max_abs_diff_vs_f64);
    }
}

/// `auto` at one budget, judged against the fixed methods of the same rounds.
#[derive(Debug, Clone, Serialize)]
pub struct AutoPoint {
    pub name: String,
    pub budget: f64,
    /// Max abs colour error over the covered pixels and the channels (compare's per-channel
    /// `max_abs_error`, [`crate::auto::colour_error`]): the error a budget bounds.
    pub max_abs_error: f64,
    /// Whether `max_abs_error` <= `budget`.
    pub within_budget: bool,
    /// The run's error metric (the Pareto chart's y).
    pub error: f64,
    pub ratio_median: f64,
    pub ratio_ci95_low: f64,
    pub ratio_ci95_high: f64,
    pub speed_vs_phong_exact: Speed,
    /// Fixed methods with an error (the run's metric) at most `error` and faster beyond the
    /// paired interval: empty when no fixed method beats this point.
    pub beaten_by: Vec<String>,
}

/// A claim of the seeds, measured by the run that writes it.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimCheck {
    pub method: String,
    pub claim: String,
    pub measured: String,
    /// Computed from `measured` by the rule in `how`.
    pub verdict: Verdict,
    /// What was measured (timings, SPIR-V counts, GPU errors or an f64 sweep) and the rule
    /// that turns it into the verdict.
    pub how: String,
    /// Why the result comes out as it does.
    pub reason: String,
    /// Proven, found or measured, with the proven upper bound beside the found value.
    #[serde(flatten)]
    pub evidence: crate::method::Evidence,
}

/// One point of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    pub program: String,
    /// Pixels (size sweep) or triangles (triangle sweep).
    pub work: f64,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub covered_pixels: usize,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
    /// Timed draws of the point (at least [`crate::bench::SWEEP_MIN_REPEAT`]) and the exact
    /// coverage of its interval.
    pub samples: usize,
    pub ci_confidence: f64,
}

/// A sweep and its fitted slopes.
#[derive(Debug, Clone, Serialize)]
pub struct SweepResult {
    pub sweep: Sweep,
    /// "covered pixels" or "triangles".
    pub work: String,
    pub points: Vec<SweepPoint>,
    /// Per program: least-squares slope of median_ms against work (ms per million units) and
    /// the log-log slope (1 = linear scaling).
    pub slopes: Vec<(String, f64, f64)>,
}

/// DIR/bench.json.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub schema_version: u32,
    pub provenance: Provenance,
    /// The precision of the timed method programs and isolated kernels (`f32`, `f16`; issue
    /// 23; the floors are float32 always). Absent in files written before: f32.
    #[serde(default)]
    pub precision: crate::method::Precision,
    pub cpu_model: String,
    /// Logical CPUs the process may use.
    pub cpu_count: usize,
    /// LP_NUM_THREADS when the Vulkan instance was created (set by `--threads`, or inherited);
    /// null: lavapipe's default, one thread per CPU.
    pub lp_num_threads: Option<String>,
    /// The command line of the run.
    pub command_line: Vec<String>,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub repeat: usize,
    pub warmup: usize,
    /// How many rounds were run and why they stopped.
    pub rounds: RoundsReport,
    /// `--runs N` (N >= 2): the runs, the coverage of their intervals and the control's noise
    /// floor; null with one run.
    pub runs: Option<crate::bench::runs::RunsReport>,
    /// How the paired ratio intervals are computed.
    pub ratio_interval: String,
    pub clock: ClockCheck,
    pub error_metric: crate::compare::Metric,
    pub floor: MethodTiming,
    /// The constant-colour program on each other geometry of the run (a PN tessellation):
    /// the floor of the methods that draw it; its paired ratio to `floor` is the cost of that
    /// geometry.
    pub other_floors: Vec<MethodTiming>,
    pub methods: Vec<MethodTiming>,
    /// Names of the non-dominated methods (error, paired time): a method is dominated only
    /// when another has an error at most its own and is faster beyond the paired interval.
    pub pareto_front: Vec<String>,
    /// The same by isolated cost: dominated only when another method has an error at most its
    /// own and its isolated-cost interval lies wholly below this one's (empty without the
    /// isolated cost).
    pub pareto_front_isolated: Vec<String>,
    pub claims: Vec<ClaimCheck>,
    /// The seeds' speed claims, a cell per cost model (lavapipe frame time, isolated cost,
    /// software engine, each GPU family's static cost).
    pub speed_claims: Vec<crate::bench::speed_claims::SpeedClaim>,
    /// Where the static cost came from, each family's status, the op-count claim per family.
    pub static_cost: crate::bench::speed_claims::StaticCost,
    /// What `auto` chose at each budget of the run (empty without `auto`).
    pub auto: Vec<crate::auto::AutoSummary>,
    /// `auto` at each budget against the fixed methods: its paired ratio to phong_exact, its
    /// error, and the fixed methods that beat it (error at most its own, faster beyond the
    /// paired interval).
    pub auto_curve: Vec<AutoPoint>,
    pub sweeps: Vec<SweepResult>,
    /// The comparison with `--baseline` (null without it).
    pub baseline: Option<crate::bench::baseline::BaselineComparison>,
    pub total_s: f64,
}
/// Writes every output of a bench run, bench.json (its completion marker) last.
pub fn write(out: &Path, r: &BenchReport) -> Result<()> {
    output::write_atomic(&out.join("bench.csv"), |w| {
        let mut c = csv::Writer::from_writer(w);
        let mut header: Vec<String> = [
            "name",
            "median_ms",
            "ci95_low_ms",
            "ci95_high_ms",
            "samples",
            "clock",
            "wall_median_ms",
            "timestamp_median_ms",
            "covered_pixels",
            "ns_per_pixel",
            "above_floor_ms",
            "ratio_to_phong_exact",
            "ratio_above_floor_to_phong_exact",
            "floor_program",
            "ratio_median",
            "ratio_ci95_low",
            "ratio_ci95_high",
            "ratio_non_finite",
            "ratio_to_floor_median",
            "ratio_to_floor_ci95_low",
            "ratio_to_floor_ci95_high",
            "speed_vs_phong_exact",
            "fragment_invocations",
            "overdraw",
            "ops_div",
            "ops_sqrt",
            "ops_inverse_sqrt",
            "ops_mul",
            "ops_add",
            "ops_pow",
        ]
        .map(String::from)
        .to_vec();
        header.extend(compare::METRICS.iter().map(|m| m.to_string()));
        c.write_record(&header).map_err(std::io::Error::other)?;
        for m in std::iter::once(&r.floor)
            .chain(&r.other_floors)
            .chain(&r.methods)
        {
            let o = |v: Option<f64>| v.map(|x| format!("{x:e}")).unwrap_or_default();
            let ops = m.static_ops;
            let mut row = vec![
                m.name.clone(),
                format!("{:e}", m.median_ms),
                format!("{:e}", m.ci95_low_ms),
                format!("{:e}", m.ci95_high_ms),
                m.samples.to_string(),
                m.clock.to_string(),
                format!("{:e}", m.wall_median_ms),
                o(m.timestamp_median_ms),
                m.covered_pixels.to_string(),
                format!("{:e}", m.ns_per_pixel),
                format!("{:e}", m.above_floor_ms),
                format!("{:e}", m.ratio_to_phong_exact),
                format!("{:e}", m.ratio_above_floor_to_phong_exact),
                m.floor_program.clone(),
                format!("{:e}", m.ratio_median),
                format!("{:e}", m.ratio_ci95_low),
                format!("{:e}", m.ratio_ci95_high),
                m.ratio_non_finite.to_string(),
                format!("{:e}", m.ratio_to_floor_median),
                format!("{:e}", m.ratio_to_floor_ci95_low),
                format!("{:e}", m.ratio_to_floor_ci95_high),
                m.speed_vs_phong_exact.as_str().into(),
                m.fragment_invocations
                    .map(|n| n.to_string())
                    .unwrap_or_default(),
                o(m.overdraw),
            ];
            for f in [
                |o: &OpCounts| o.div,
                |o: &OpCounts| o.sqrt,
                |o: &OpCounts| o.inverse_sqrt,
                |o: &OpCounts| o.mul,
                |o: &OpCounts| o.add,
                |o: &OpCounts| o.pow,
            ] {
                row.push(ops.map(|x| f(&x).to_string()).unwrap_or_default());
            }
            for k in compare::METRICS {
                row.push(o(m.error.as_ref().and_then(|e| e.metric(k))));
            }
            c.write_record(&row).map_err(std::io::Error::other)?;
        }
        c.flush()
    })?;
    write_claims(out, r)?;
    crate::bench::chart::pareto(out, r)?;
    for s in &r.sweeps {
        crate::bench::chart::sweep(out, s)?;
    }
    // Compact (one line): the report writes one per scene (190 KB against 260 KB indented).
    let json = serde_json::to_string(r).map_err(|e| Error::output("bench.json", e))? + "\n";
    output::write_bytes_atomic(&out.join("bench.json"), json.as_bytes())
}

/// claims.json and claims.md: each claim with its verdict and basis (proven, found, measured).
fn write_claims(out: &Path, r: &BenchReport) -> Result<()> {
    let claims = serde_json::to_string_pretty(&r.claims)
        .map_err(|e| Error::output("claims.json", e))?
        + "\n";
    output::write_bytes_atomic(&out.join("claims.json"), claims.as_bytes())?;
    let mut md = String::from("# The seeds' claims, measured\n\n");
    md += &format!(
        "{} at {}x{} on {} ({}), clock: {}, {} interleaved rounds ({}). Written by `shadelab bench`: every verdict below was computed by this run from the measurement in its row, by the rule in its \"how\". Speed verdicts come from the paired per-round ratio to phong_exact ({}).\n\n| method | claim | measured | verdict | how | why |\n|---|---|---|---|---|---|\n",
        r.scene, r.width, r.height, r.provenance.device, r.provenance.driver_info, r.clock.clock,
        r.rounds.rounds, r.rounds.stopped.as_str(), r.ratio_interval
    );
    for c in &r.claims {
        md += &format!(
            "| {} | {} | {} | {} ({}) | {} | {} |\n",
            c.method,
            c.claim,
            c.measured,
            c.verdict,
            c.evidence.basis.as_str(),
            c.how,
            c.reason
        );
    }
    md += &crate::bench::speed_claims::markdown(&r.speed_claims, Some(&r.static_cost));
    output::write_bytes_atomic(&out.join("claims.md"), md.as_bytes())?;
    Ok(())
}
