//! `shadelab bench`: run time against error. Timing on lavapipe with a validated clock, every
//! program (the methods, the constant-colour floor of each geometry, the control) in the same
//! interleaved rounds, medians with distribution-free 95% confidence intervals, paired
//! per-round ratios to phong_exact and to the floor ([`rounds`]), the error metrics of
//! `compare`, static operation counts of each fragment shader, overdraw from an untimed
//! pipeline-statistics pass, a Pareto chart, the papers' claims checked, sweeps over image size
//! and triangle count, and a comparison with an earlier run ([`baseline`]).
//!
//! Clock: Vulkan timestamps placed as TOOLCHAIN.md found to track the draw on Mesa 22.3 (see
//! `Renderer::timed_draws`). Every run re-checks the placement: at sizes 128..2048 the
//! timestamp interval must track the submit-to-fence wall clock ([`CLOCK_TOLERANCE`]); when it
//! does not, the run says so and times with the wall clock instead.
pub mod baseline;
pub mod chart;
pub mod claims;
pub mod clock;
pub mod cost;
pub mod isolated;
pub mod per_machine;
mod programs;
pub mod report;
pub mod rounds;
pub mod runs;
pub mod schedule;
pub mod skips;
pub mod software;
pub mod speed_claims;
pub mod sweep;
#[cfg(test)]
mod tests;
mod untimed;

pub use clock::*;
pub use programs::floor_name;
use programs::{programs, Program, What};
pub use report::*;
pub use rounds::{RoundsReport, RoundsSchedule, Stop};
pub use runs::Runs;
use untimed::untimed;

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use crate::analysis::stats::{median_ci, pareto_front_paired, Estimate, RatioEstimate};
use crate::compare;
use crate::error::{Error, Result};
use crate::gpu::spirv::{self, OpCounts};
use crate::gpu::{Clock, DrawList, Prepared, Renderer, TimedDraws};
use crate::method::{self, Method};
use crate::output::provenance::cpu_model;
use crate::scene::Scene;
use rounds::{ratios, round_values, widest, Rounds};

/// Version of the bench.json layout (2: paired ratios, rounds, other floors, overdraw,
/// command line, baseline).
pub const SCHEMA_VERSION: u32 = 2;
/// Fewest timed draws per sweep point (a sign-test interval from 20 samples covers 95.9 %).
pub const SWEEP_MIN_REPEAT: usize = 20;
/// Most timed draws per sweep point (the bench's `--repeat` in between).
pub const SWEEP_MAX_REPEAT: usize = 40;
/// Default time cap of `--until-ci`, seconds of timed rounds.
pub const DEFAULT_MAX_TIME_S: f64 = 300.0;
/// How the paired intervals are computed (bench.json `ratio_interval`).
pub const RATIO_INTERVAL: &str = "sign test: median of the per-round ratios with the \
     distribution-free 95% interval [r(l), r(n+1-l)] of their order statistics, l the largest \
     rank with P(Bin(n, 1/2) < l) <= 2.5 % (no bootstrap)";
/// Sizes of the clock check and of `--sweep size`.
pub const SIZES: [u32; 5] = [128, 256, 512, 1024, 2048];
/// The timestamp interval tracks the wall clock when, at every size, it is within this
/// fraction of the wall time or within [`CLOCK_SLACK_MS`] of it (submission overhead
/// dominates small draws).
pub const CLOCK_TOLERANCE: f64 = 0.25;
pub const CLOCK_SLACK_MS: f64 = 2.0;
/// (segments, rings) of the UV spheres of `--sweep triangles`: 2 * segments * (rings - 1)
/// triangles, about 100 to 1,000,000.
pub const SPHERES: [(u32, u32); 5] = [(10, 6), (32, 17), (100, 51), (316, 159), (1000, 501)];

/// What to sweep besides the main bench.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    Size,
    Triangles,
}

/// Options of a bench run.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Everything about the measurement: runs, rounds, warm-up, isolated rounds, control
    /// ([`schedule::Schedule`], decided once).
    pub schedule: schedule::Schedule,
    /// The compare metric on the Pareto chart's y axis.
    pub error_metric: compare::Metric,
    pub sweeps: Vec<Sweep>,
    /// `--baseline OLD/bench.json` and `--fail-slower PCT`.
    pub baseline: Option<PathBuf>,
    pub fail_slower_pct: Option<f64>,
    /// The command line, recorded in bench.json.
    pub command_line: Vec<String>,
    /// `auto` (named `auto`) and the points of its budget curve (`auto_<k>_255`, `auto_1_<k>`), timed and
    /// judged like the methods.
    pub auto: Vec<crate::auto::AutoSpec>,
    /// Where this process stands: the only run, the parent of `schedule.runs` fresh processes, or
    /// one of them ([`runs`]).
    pub runs: Runs,
    /// Where the static cost of the speed claims' per-family columns comes from.
    pub static_cost: speed_claims::StaticCostSource,
    /// Whether the speed claims' software-engine column is timed (after lavapipe's rounds,
    /// [`speed_claims::software_column`]); `--no-software` leaves it out.
    pub software_column: bool,
    /// The cost models of the speed claims' columns (the CLI and the report give
    /// [`crate::costs::builtin`]; none by default).
    pub costs: crate::cost::Registry,
    /// The scene's compare statistics when the caller has them (the report compared the scene
    /// just before): the error metrics are taken from them instead of drawing every method
    /// again. Used only when they are of this scene's size and precision and hold a row for
    /// every program ([`untimed::compared_covers`]); else compared here.
    pub compared: Option<compare::Summary>,
    /// A clock check made before on this device (the report checks once, with its first
    /// scene's bench, and every later bench and skips of the report uses it); `None`: checked
    /// here.
    pub clock: Option<ClockCheck>,
}

impl Default for BenchOptions {
    /// One run in this process with bench's defaults ([`schedule::Schedule::new`]).
    fn default() -> Self {
        let given = schedule::Given {
            runs: Some(1),
            ..schedule::Given::default()
        };
        BenchOptions {
            schedule: schedule::Schedule::new(schedule::Job::Bench { software: false }, &given)
                .expect("bench's defaults are a valid schedule"),
            error_metric: compare::Metric::P99AbsError,
            sweeps: Vec::new(),
            baseline: None,
            fail_slower_pct: None,
            command_line: Vec::new(),
            auto: Vec::new(),
            runs: Runs::One,
            static_cost: speed_claims::StaticCostSource::Skip,
            software_column: false,
            costs: crate::cost::Registry::new(),
            compared: None,
            clock: None,
        }
    }
}

/// Times `draws` in `repeat` interleaved rounds after `warmup` discarded submissions each
/// (see [`rounds::Rounds`]). Returns the samples per draw.
fn interleaved(
    draws: &TimedDraws,
    warmup: usize,
    repeat: usize,
) -> Result<Vec<Vec<crate::gpu::Sample>>> {
    let mut r = Rounds::new(draws, warmup)?;
    r.run(repeat)?;
    Ok(r.samples)
}

/// The estimate from the `clock` the clock check chose, with the name of the clock it really
/// came from: `wall` when timestamps were asked for but no sample has one. Also the wall and
/// timestamp medians.
pub(crate) fn estimate(
    samples: &[crate::gpu::Sample],
    clock: Clock,
) -> (Estimate, Clock, f64, Option<f64>) {
    let wall: Vec<f64> = samples.iter().map(|s| s.wall_ms).collect();
    let ts: Vec<f64> = samples.iter().filter_map(|s| s.timestamp_ms).collect();
    let w = median_ci(&wall);
    let t = (!ts.is_empty()).then(|| median_ci(&ts));
    let (chosen, used) = match t {
        Some(t) if clock == Clock::Timestamp => (t, Clock::Timestamp),
        _ => (w, Clock::Wall),
    };
    (chosen, used, w.median, t.map(|t| t.median))
}

fn static_ops(
    program: &str,
    interp: crate::scene::Interpolation,
    precision: crate::method::Precision,
) -> Option<OpCounts> {
    let name = crate::gpu::shaders::program_name_in(program, interp, precision);
    // The timed draw's program (no normal target).
    let bytes = crate::gpu::shaders::embedded(&name, crate::gpu::shaders::COLOR_ONLY).ok()?;
    spirv::count_ops(bytes).ok()
}

/// What every run of a bench times: the methods with the references, the clock, the prepared
/// scene and `auto`'s scenes.
struct Setup {
    all: Vec<&'static Method>,
    exact: &'static Method,
    clock: ClockCheck,
    prepared: Prepared,
    autos: Vec<(String, crate::gpu::AutoScene)>,
    auto_summaries: Vec<crate::auto::AutoSummary>,
}

/// The methods with phong_exact and phong_unnormalized added, the clock (checked now, or the
/// parent's in a measurement run), the prepared scene and `auto`'s choices.
fn setup(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    opts: &BenchOptions,
) -> Result<Setup> {
    let exact = method::phong_exact();
    let unnormalized = method::phong_unnormalized();
    let mut all = methods_.to_vec();
    for m in [exact, unnormalized] {
        if !all.iter().any(|x| x.name == m.name) {
            all.push(m);
        }
    }
    let clock = match &opts.runs {
        Runs::Child(run) => ClockCheck {
            clock: run.clock,
            reason: "chosen by the parent run's clock check".into(),
            points: Vec::new(),
        },
        _ => known_or_checked(renderer, scene, opts.clock.as_ref(), "bench")?,
    };

    let prepared = renderer.prepare(scene, &all)?;
    let mut autos = Vec::new();
    let mut auto_summaries = Vec::new();
    for spec in &opts.auto {
        let (_, summary, scene_auto) = crate::auto::frame::choose_checked(
            renderer,
            scene,
            &prepared.base().inputs,
            spec,
            crate::auto::Cache::Use,
            opts.runs.frame_decision(&spec.name),
        )?;
        log::info!("bench: {}", summary.line());
        auto_summaries.push(summary);
        autos.push((spec.name.clone(), scene_auto));
    }
    Ok(Setup {
        all,
        exact,
        clock,
        prepared,
        autos,
        auto_summaries,
    })
}

/// One measurement run of a bench of several runs, in this (fresh) process: the programs'
/// warm-up and rounds and the isolated costs, the reply to its parent ([`runs`]).
pub fn measure_run(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    opts: &BenchOptions,
) -> Result<runs::RunFigures> {
    check_options(opts)?;
    let Runs::Child(run) = &opts.runs else {
        return Err(Error::Internal(
            "measure_run outside a run of a bench of several runs".into(),
        ));
    };
    let s = setup(renderer, scene, methods_, opts)?;
    let programs = programs(&s.prepared, &s.all, Some(s.exact), &s.autos);
    let (samples, rounds) = time_rounds(renderer, &programs, s.clock.clock, opts)?;
    let methods: Vec<&'static Method> = s.all.clone();
    let isolated = isolated_costs(renderer, &methods, opts)?;
    Ok(runs::RunFigures {
        seed: Some(run.seed),
        rounds: rounds.rounds,
        timing_s: rounds.timing_s,
        programs: programs
            .iter()
            .zip(&samples)
            .map(|(p, s)| runs::ProgramRounds::new(&p.name, s))
            .collect(),
        isolated,
    })
}

/// The isolated cost of `methods` (with the control in a bench of several runs), or nothing
/// with `isolated_rounds` 0.
fn isolated_costs(
    renderer: &Renderer,
    methods: &[&'static Method],
    opts: &BenchOptions,
) -> Result<Vec<isolated::IsolatedCost>> {
    let schedule = &opts.schedule;
    if schedule.isolated_rounds == 0 {
        return Ok(Vec::new());
    }
    let iso_opts = isolated::IsolatedOptions {
        rounds: schedule.isolated_rounds,
        control: schedule.many(),
        precision: renderer.precision(),
        order_seed: opts.runs.seed(),
        warmup: schedule.isolated_warmup,
        ..isolated::IsolatedOptions::default()
    };
    let bar = crate::output::progress_bar(true, 0);
    let costs = isolated::measure(renderer.context(), methods, &iso_opts, &|msg| {
        bar.set_message(format!("isolated cost: {msg}"));
        bar.tick();
    })?;
    bar.finish_and_clear();
    Ok(costs)
}

/// The timed rounds of every program: in this process (one run), or pooled from `--runs N`
/// fresh processes (run after run, each in its own rounds) with each run's figures.
fn timed(
    renderer: &Renderer,
    programs: &[Program],
    s: &Setup,
    opts: &BenchOptions,
) -> Result<(
    Vec<Vec<crate::gpu::Sample>>,
    RoundsReport,
    Vec<runs::RunFigures>,
)> {
    let clock = s.clock.clock;
    let Runs::Many(launcher) = &opts.runs else {
        let (samples, report) = time_rounds(renderer, programs, clock, opts)?;
        return Ok((samples, report, Vec::new()));
    };
    let frame = crate::auto::frame::decisions(&s.auto_summaries);
    let figures = runs::run_all(launcher, opts, &s.all, clock, &frame)?;
    let samples: Vec<Vec<crate::gpu::Sample>> = programs
        .iter()
        .map(|p| figures.iter().flat_map(|f| f.samples_of(&p.name)).collect())
        .collect();
    let rounds = samples.first().map_or(0, Vec::len);
    let timing_s = figures.iter().map(|f| f.timing_s).sum();
    let names: Vec<String> = programs.iter().map(|p| p.name.clone()).collect();
    let floors: Vec<usize> = programs.iter().map(|p| p.floor).collect();
    let phong = names
        .iter()
        .position(|n| n == crate::method::PHONG_EXACT)
        .unwrap_or(0);
    let values: Vec<Vec<f64>> = samples.iter().map(|s| round_values(s, clock)).collect();
    let (p, f) = ratios(&values, phong, &floors);
    let report = RoundsReport::new(
        &opts.schedule.rounds,
        rounds,
        Stop::FixedRepeat,
        timing_s,
        widest(&names, &p, &f),
    );
    Ok((samples, report, figures))
}

/// Runs the bench and writes DIR/bench.json, bench.csv, pareto.svg/png, claims.json/md (and
/// sweep files). With `--runs N` the timing comes from N fresh processes ([`runs`]) and the
/// verdicts from the interval across them.
pub fn bench(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    opts: &BenchOptions,
) -> Result<BenchReport> {
    let start = Instant::now();
    preflight(renderer, scene, methods_.len(), opts)?;
    // Read the baseline first: a bad path must not cost a whole run.
    let baseline = opts
        .baseline
        .as_ref()
        .map(|p| baseline::load(p).map(|v| (p, v)))
        .transpose()?;
    let s = setup(renderer, scene, methods_, opts)?;
    let (all, clock) = (&s.all, s.clock.clone());
    let control = opts.schedule.control.then_some(s.exact);
    let programs = programs(&s.prepared, all, control, &s.autos);
    let floors: Vec<usize> = programs.iter().map(|p| p.floor).collect();
    let phong = programs
        .iter()
        .position(|p| p.name == crate::method::PHONG_EXACT)
        .ok_or_else(|| Error::Internal("phong_exact is not among the programs".into()))?;
    let (samples, rounds_report, run_figures) = timed(renderer, &programs, &s, opts)?;
    let values: Vec<Vec<f64>> = samples
        .iter()
        .map(|s| round_values(s, clock.clock))
        .collect();
    let (to_phong, to_floor) = ratios(&values, phong, &floors);
    let (invocations, summary) = untimed(renderer, scene, all, out, opts, &programs)?;
    let mut rows = rows_of(
        renderer,
        scene,
        &programs,
        &samples,
        clock.clock,
        (&to_phong, &to_floor),
        &summary,
        &invocations,
    )?;
    let runs_report =
        (!run_figures.is_empty()).then(|| runs::apply(&mut rows, &run_figures, clock.clock));
    let (mut floors_rows, method_rows, method_values) = split_floors(rows, &programs, values);
    let floor = floors_rows.remove(0);
    let mut rows = method_rows;
    let metric = |r: &MethodTiming| r.error.as_ref().and_then(|e| opts.error_metric.of(e));
    let errors: Vec<f64> = rows.iter().map(|r| metric(r).unwrap_or(f64::NAN)).collect();
    let front: Vec<String> = pareto_front_paired(&errors, &method_values)
        .into_iter()
        .map(|i| rows[i].name.clone())
        .collect();
    let auto_curve = auto_points(&rows, &errors, &method_values, &s.auto_summaries);
    if run_figures.is_empty() {
        set_isolated(renderer, &mut rows, opts)?;
    }
    let front_isolated = isolated::pareto_front(&rows, &errors);
    let len2 = claims::interpolated_len2_range(&s.prepared.base().inputs.view_normals);
    let mut claims = claims::claims(&rows, len2);
    let (speed_claims, static_cost) =
        speed_claims::judge(opts, (scene, out), methods_, &rows, &mut claims);
    let sweeps = opts
        .sweeps
        .iter()
        .map(|&sw| {
            log::info!("bench: sweep {sw:?}");
            sweep::sweep(renderer, scene, sw, opts)
        })
        .collect::<Result<Vec<_>>>()?;
    let mut report = BenchReport {
        schema_version: SCHEMA_VERSION,
        provenance: renderer.provenance(),
        precision: renderer.precision(),
        cpu_model: cpu_model(),
        cpu_count: std::thread::available_parallelism().map_or(0, |n| n.get()),
        lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
        command_line: opts.command_line.clone(),
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: s.prepared.base().inputs.triangle_count(),
        repeat: opts.schedule.rounds.repeat,
        warmup: opts.schedule.rounds.warmup,
        rounds: rounds_report,
        runs: runs_report,
        ratio_interval: (if run_figures.is_empty() {
            RATIO_INTERVAL
        } else {
            runs::RUNS_INTERVAL
        })
        .into(),
        clock,
        error_metric: opts.error_metric,
        floor,
        other_floors: floors_rows,
        methods: rows,
        pareto_front: front,
        pareto_front_isolated: front_isolated,
        claims,
        speed_claims,
        static_cost,
        auto: s.auto_summaries.clone(),
        auto_curve,
        sweeps,
        baseline: None,
        total_s: 0.0,
    };
    if let Some((path, old)) = baseline {
        let new = serde_json::to_value(&report).map_err(|e| Error::output("bench.json", e))?;
        report.baseline = Some(baseline::compare(
            &old,
            &new,
            &path.display().to_string(),
            opts.fail_slower_pct,
        ));
    }
    report.total_s = start.elapsed().as_secs_f64();
    write(out, &report)?;
    Ok(report)
}

/// The options, and compare's memory at the scene's size (before the timed rounds rather
/// than after them).
fn preflight(
    renderer: &Renderer,
    scene: &Scene,
    methods: usize,
    opts: &BenchOptions,
) -> Result<()> {
    check_options(opts)?;
    let heap = Some(renderer.context().heap_bytes()).filter(|&h| h > 0);
    let need = crate::memory::compare(methods);
    crate::memory::check(&need, scene.width, scene.height, heap)
}

/// The isolated cost of every method row, measured in this process.
fn set_isolated(renderer: &Renderer, rows: &mut [MethodTiming], opts: &BenchOptions) -> Result<()> {
    let methods: Vec<&'static Method> = rows
        .iter()
        .filter_map(|r| crate::method::find(&r.name).ok())
        .collect();
    for c in &isolated_costs(renderer, &methods, opts)? {
        if let Some(r) = rows.iter_mut().find(|r| r.name == c.name) {
            r.set_isolated(c);
        }
    }
    Ok(())
}

/// Every program's row: its rounds, image and errors ([`timing_row`]), invocations, op
/// counts, and the figures against its floor and phong_exact.
#[allow(clippy::too_many_arguments)]
fn rows_of(
    renderer: &Renderer,
    scene: &Scene,
    programs: &[Program],
    samples: &[Vec<crate::gpu::Sample>],
    clock: Clock,
    (to_phong, to_floor): (&[RatioEstimate], &[RatioEstimate]),
    summary: &compare::Summary,
    invocations: &[Option<u64>],
) -> Result<Vec<MethodTiming>> {
    let names: Vec<&str> = programs.iter().map(|p| p.name.as_str()).collect();
    let phong = names
        .iter()
        .position(|n| *n == crate::method::PHONG_EXACT)
        .ok_or_else(|| Error::Internal("phong_exact is not among the programs".into()))?;
    let mut rows = Vec::new();
    for (i, p) in programs.iter().enumerate() {
        let (rp, rf) = (&to_phong[i], &to_floor[i]);
        let ops = match p.what {
            What::Auto(_) => None,
            _ => static_ops(
                p.method().map_or("constant", |m| m.name),
                scene.interpolation,
                if p.method().is_some() {
                    renderer.precision()
                } else {
                    crate::method::Precision::F32
                },
            ),
        };
        let mut r = timing_row(renderer, p, &samples[i], clock, (rp, rf), summary)?;
        r.floor_program = names[p.floor].to_string();
        r.fragment_invocations = invocations[i];
        r.invocations_exact = invocations[i].map(|n| n as usize == r.covered_pixels);
        r.overdraw = invocations[i]
            .filter(|_| r.covered_pixels > 0)
            .map(|n| n as f64 / r.covered_pixels as f64);
        r.static_ops = ops;
        rows.push(r);
    }
    let medians: Vec<f64> = rows.iter().map(|r| r.median_ms).collect();
    let (phong_ms, floor_ms) = (medians[phong], medians[0]);
    let base_ops = rows
        .iter()
        .find(|r| r.name == method::phong_unnormalized().name)
        .and_then(|r| r.static_ops);
    for (r, p) in rows.iter_mut().zip(programs) {
        let own_floor = medians[p.floor];
        r.above_floor_ms = r.median_ms - own_floor;
        r.ratio_to_phong_exact = r.median_ms / phong_ms;
        r.ratio_above_floor_to_phong_exact = (r.median_ms - own_floor) / (phong_ms - floor_ms);
        r.static_ops_above_unnormalized = match (r.static_ops, base_ops) {
            (Some(a), Some(b)) => Some(a.minus(&b)),
            _ => None,
        };
    }
    Ok(rows)
}

/// The floors' rows (programs without a method), then the methods' rows with their round
/// values.
#[allow(clippy::type_complexity)]
fn split_floors(
    rows: Vec<MethodTiming>,
    programs: &[Program],
    values: Vec<Vec<f64>>,
) -> (Vec<MethodTiming>, Vec<MethodTiming>, Vec<Vec<f64>>) {
    let is_floor: Vec<bool> = programs
        .iter()
        .map(|p| matches!(p.what, What::Floor))
        .collect();
    let mut floors_rows = Vec::new();
    let mut method_rows = Vec::new();
    let mut method_values = Vec::new();
    for ((r, f), v) in rows.into_iter().zip(is_floor).zip(values) {
        if f {
            floors_rows.push(r);
        } else {
            method_rows.push(r);
            method_values.push(v);
        }
    }
    (floors_rows, method_rows, method_values)
}

/// A program's row from its rounds, its image and compare's statistics (the fields that need
/// every row, the invocations and the op counts are filled in by [`bench`]).
fn timing_row(
    renderer: &Renderer,
    p: &Program,
    samples: &[crate::gpu::Sample],
    clock: Clock,
    (rp, rf): (&RatioEstimate, &RatioEstimate),
    summary: &compare::Summary,
) -> Result<MethodTiming> {
    // Coverage from each image itself.
    let frame = p.render(renderer)?;
    let (e, used_clock, wall, ts) = estimate(samples, clock);
    let covered = frame.covered();
    // The control's error is phong_exact's (the same program); auto's is its own.
    let judged = p.method().map_or(p.name.as_str(), |m| m.name);
    let error = match p.what {
        What::Floor => None,
        _ => summary.methods.iter().find(|r| r.name == judged).cloned(),
    };
    Ok(MethodTiming {
        name: p.name.clone(),
        floor_program: String::new(),
        median_ms: e.median,
        ci95_low_ms: e.ci95_low,
        ci95_high_ms: e.ci95_high,
        samples: e.samples,
        clock: used_clock,
        wall_median_ms: wall,
        timestamp_median_ms: ts,
        covered_pixels: covered,
        fragment_invocations: None,
        invocations_exact: None,
        overdraw: None,
        ns_per_pixel: e.median * 1e6 / covered.max(1) as f64,
        above_floor_ms: 0.0,
        ratio_to_phong_exact: 0.0,
        ratio_above_floor_to_phong_exact: 0.0,
        ratio_median: rp.median,
        ratio_ci95_low: rp.ci95_low,
        ratio_ci95_high: rp.ci95_high,
        ratio_rounds: rp.rounds,
        ratio_non_finite: rp.non_finite,
        ratio_confidence: rp.confidence,
        ratio_to_floor_median: rf.median,
        ratio_to_floor_ci95_low: rf.ci95_low,
        ratio_to_floor_ci95_high: rf.ci95_high,
        ratio_to_floor_non_finite: rf.non_finite,
        speed_vs_phong_exact: Speed::from_ratio(rp),
        static_ops: None,
        static_ops_above_unnormalized: None,
        error,
        isolated_ns_per_eval: None,
        isolated_ci95_low_ns: None,
        isolated_ci95_high_ns: None,
        isolated_ratio_to_phong_exact: None,
        isolated_vs_phong_exact: None,
        isolated_k1_max_abs_diff_vs_f64: None,
        runs: None,
        isolated_runs: None,
        run_figures: Vec::new(),
    })
}

/// Every `auto` row against the fixed methods (rows that are not `auto`), by the paired rule of
/// the Pareto front.
fn auto_points(
    rows: &[MethodTiming],
    errors: &[f64],
    values: &[Vec<f64>],
    autos: &[crate::auto::AutoSummary],
) -> Vec<AutoPoint> {
    let is_auto = |name: &str| autos.iter().any(|a| a.name == name);
    autos
        .iter()
        .filter_map(|a| {
            let i = rows.iter().position(|r| r.name == a.name)?;
            let r = &rows[i];
            // The error the budget bounds (auto's definition): the largest channel's.
            let max_abs = r.error.as_ref().map_or(f64::NAN, |e| {
                crate::auto::colour_error(e.channels.each_ref().map(|c| c.max_abs_error))
            });
            let beaten_by = crate::analysis::stats::dominators(errors, values, i)
                .into_iter()
                .filter(|&j| !is_auto(&rows[j].name))
                .map(|j| rows[j].name.clone())
                .collect();
            Some(AutoPoint {
                name: a.name.clone(),
                budget: a.budget,
                max_abs_error: max_abs,
                within_budget: max_abs <= a.budget,
                error: errors[i],
                ratio_median: r.ratio_median,
                ratio_ci95_low: r.ratio_ci95_low,
                ratio_ci95_high: r.ratio_ci95_high,
                speed_vs_phong_exact: r.speed_vs_phong_exact,
                beaten_by,
            })
        })
        .collect()
}

fn check_options(opts: &BenchOptions) -> Result<()> {
    opts.schedule.rounds.check()?;
    let parent = matches!(opts.runs, Runs::Many(_));
    if !matches!(opts.runs, Runs::Child(_)) && parent != opts.schedule.many() {
        return Err(Error::Internal(format!(
            "bench: a schedule of {} runs in a process that is {:?}",
            opts.schedule.runs, opts.runs
        )));
    }
    if let Some(p) = opts.fail_slower_pct {
        if !(p.is_finite() && p >= 0.0) {
            return Err(Error::Usage(format!(
                "--fail-slower must be a percentage >= 0, got {p}"
            )));
        }
        if opts.baseline.is_none() {
            return Err(Error::Usage(
                "--fail-slower needs --baseline OLD/bench.json to compare with".into(),
            ));
        }
    }
    Ok(())
}

/// Times every program in the same interleaved rounds ([`rounds::run_rounds`]).
fn time_rounds(
    renderer: &Renderer,
    programs: &[Program],
    clock: Clock,
    opts: &BenchOptions,
) -> Result<(Vec<Vec<crate::gpu::Sample>>, RoundsReport)> {
    let lists: Vec<DrawList> = programs.iter().map(Program::list).collect();
    let names: Vec<String> = programs.iter().map(|p| p.name.clone()).collect();
    let floors: Vec<usize> = programs.iter().map(|p| p.floor).collect();
    let phong = names
        .iter()
        .position(|n| n == crate::method::PHONG_EXACT)
        .unwrap_or(0);
    let rounds = &opts.schedule.rounds;
    log::info!(
        "bench: timing {} programs in the same interleaved rounds: {}",
        programs.len(),
        rounds.describe()
    );
    let draws = renderer.timed_draw_lists(&lists)?;
    rounds::run_rounds(&draws, rounds, "bench", |samples| {
        let values: Vec<Vec<f64>> = samples.iter().map(|s| round_values(s, clock)).collect();
        let (p, f) = ratios(&values, phong, &floors);
        widest(&names, &p, &f)
    })
}

/// The paired ratio estimate a row carries against phong_exact (for claims and tests).
pub(crate) fn row_ratio(r: &MethodTiming) -> RatioEstimate {
    RatioEstimate {
        median: r.ratio_median,
        ci95_low: r.ratio_ci95_low,
        ci95_high: r.ratio_ci95_high,
        rounds: r.ratio_rounds,
        non_finite: r.ratio_non_finite,
        confidence: r.ratio_confidence,
    }
}
