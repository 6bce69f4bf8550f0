//! `shadelab bench`: timed draws, clock check, paired ratios, sweeps, claims, baseline.
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};

// `shadelab bench` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct BenchCmd {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Output directory (bench.json, bench.csv, pareto.svg/png, claims.json/md).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Timed submissions per program (interleaved rounds) in each run (default: 40 with
    /// --runs 1, 7 with more runs; src/bench/schedule.rs; at most 100000).
    #[arg(long, value_parser = count::<1, 100_000>)]
    repeat: Option<usize>,
    /// Independent measurement runs, each in a fresh process (its own Vulkan device, JIT,
    /// warm-up and rounds); the verdicts come from the interval across runs, against
    /// phong_exact_control's spread (default 5; 1: one run in this process; the software
    /// engine: 1; at most 100).
    #[arg(long, value_name = "N", value_parser = count::<1, 100>)]
    runs: Option<usize>,
    /// Discarded submissions per program (the first includes lavapipe's shader JIT; default 3;
    /// at most 1000).
    #[arg(long, value_parser = count::<0, 1000>)]
    warmup: Option<usize>,
    /// The compare metric on the Pareto chart's y axis (a summary.json name).
    #[arg(long, default_value_t = crate::compare::Metric::P99AbsError, value_parser = crate::compare::Metric::parse)]
    error_metric: crate::compare::Metric,
    /// Also time phong_exact's program under a second name (a precision control).
    #[arg(long)]
    control: bool,
    /// Also sweep image size (128..2048) or triangle count (~100..~1,000,000); repeatable.
    /// Each sweep point takes 20 to 40 timed draws per program (--repeat, clamped).
    #[arg(long, value_enum)]
    sweep: Vec<SweepArg>,
    /// After --repeat rounds, add rounds until every paired ratio interval (to phong_exact
    /// and to the floor) is within +-PCT percent of its median, or --max-time is reached.
    #[arg(long, value_name = "PCT", value_parser = checks::percent)]
    until_ci: Option<f64>,
    /// Time cap of --until-ci: seconds of timed rounds (default 300; at most a day).
    #[arg(long, value_name = "SECONDS", value_parser = checks::seconds)]
    max_time: Option<f64>,
    /// lavapipe's thread count: sets LP_NUM_THREADS before the Vulkan instance is created
    /// (0: render on the submitting thread). Recorded in bench.json. With --engine
    /// software: the software engine's threads (default: all cores; at most 1024).
    #[arg(long, value_name = "N", value_parser = count_u32::<0, 1024>)]
    threads: Option<u32>,
    /// Compare with the bench.json of an earlier run (not paired: the runs were not
    /// interleaved). Written to bench.json `baseline` and printed.
    #[arg(long, value_name = "OLD/bench.json")]
    baseline: Option<PathBuf>,
    /// With --baseline: exit 1 when a program's 95% interval lies above the baseline's by
    /// more than PCT percent (or cannot be compared), naming each.
    #[arg(long, value_name = "PCT", requires = "baseline", value_parser = checks::percent)]
    fail_slower: Option<f64>,
    /// Rounds of the isolated cost of each formula (a compute kernel evaluating it K = 0,
    /// 1, 16, 64 times per invocation; 0: skip it)
    /// (default: 21 with --runs 1, 5 per run with more runs; at most 10000).
    #[arg(long, value_name = "N", value_parser = count::<0, 10_000>)]
    isolated_rounds: Option<usize>,
    #[command(flatten)]
    pub(super) error_budget: BudgetArgs,
    #[command(flatten)]
    precision: PrecisionArgs,
    /// With `auto` in --methods: also time `auto` at these budgets (named `auto_<k>_255`, `auto_1_<k>`),
    /// drawn as a curve on the Pareto chart; `none` for no curve.
    #[arg(
        long,
        value_name = "E,E,...",
        default_value = "1/1024,1/255,4/255,16/255",
        value_parser = ErrorBudget::parse_list
    )]
    // Fully qualified: one value (a list), not a repeatable option.
    auto_curve: ::std::vec::Vec<ErrorBudget>,
    /// With --engine software: the bench.json of a Vulkan run (same scene and size), whose
    /// paired ratios are judged beside the software ones in claims.md.
    #[arg(long, value_name = "DIR/bench.json")]
    vulkan_bench: Option<PathBuf>,
    /// With --engine software: also draw every method with lavapipe in the same rounds,
    /// so the Vulkan verdicts of claims.md and software / lavapipe are paired per round.
    #[arg(long, conflicts_with = "vulkan_bench")]
    vulkan_paired: bool,
    /// The claims' per-GPU-family static cost from this isa.json of `shadelab isa` instead of
    /// compiling it now (by default bench compiles its methods on every GPU family set up).
    #[arg(long, value_name = "FILE.json", conflicts_with = "no_isa")]
    isa: Option<PathBuf>,
    /// No per-GPU-family static cost in the claims.
    #[arg(long)]
    no_isa: bool,
    /// No software-engine column in the speed claims (by default the Vulkan bench times the
    /// claims' programs in the software engine after its rounds, into DIR/software/).
    #[arg(long)]
    no_software: bool,
}

/// `--sweep` of `bench`.
#[derive(ValueEnum, Debug, Clone, Copy)]
enum SweepArg {
    Size,
    Triangles,
}

impl From<SweepArg> for crate::bench::Sweep {
    fn from(a: SweepArg) -> Self {
        match a {
            SweepArg::Size => Self::Size,
            SweepArg::Triangles => Self::Triangles,
        }
    }
}

impl BenchCmd {
    /// What bench reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            marker: Some("bench.json"),
            dir: Some(("--out", &self.out)),
            inputs: self
                .scene
                .files()
                .into_iter()
                .chain(self.baseline.as_deref())
                .chain(self.isa.as_deref())
                .chain(self.vulkan_bench.as_deref())
                .collect(),
            ..Default::default()
        }
    }

    /// What the command line gave of the schedule.
    fn given(&self) -> crate::bench::schedule::Given {
        crate::bench::schedule::Given {
            runs: self.runs,
            repeat: self.repeat,
            warmup: self.warmup,
            isolated_rounds: self.isolated_rounds,
            control: self.control,
            until_ci_pct: self.until_ci,
            max_time_s: self.max_time,
        }
    }
}

/// One run here, or the schedule's runs as fresh processes of this binary on the same scene and
/// device ([`crate::bench::runs`]).
fn bench_runs(
    b: &BenchCmd,
    schedule: &crate::bench::schedule::Schedule,
) -> Result<crate::bench::Runs> {
    use crate::bench::runs::{Launcher, Runs};
    if !schedule.many() {
        return Ok(Runs::One);
    }
    Ok(Runs::Many(Launcher {
        exe: std::env::current_exe().map_err(|e| Error::io(std::path::Path::new("shadelab"), e))?,
        scene: b.scene.source(),
        device: crate::gpu::DeviceSpec {
            device: b.device.device.clone(),
            validate: b.device.validate,
            precision: b.precision.precision,
        },
        driver_env: b
            .threads
            .map(|n| ("LP_NUM_THREADS".to_string(), n.to_string()))
            .into_iter()
            .collect(),
    }))
}

/// `--isa FILE`, `--no-isa`, or compile now (the default) with this binary's children.
fn static_cost_source(b: &BenchCmd) -> Result<crate::bench::speed_claims::StaticCostSource> {
    use crate::bench::speed_claims::StaticCostSource;
    Ok(match (&b.isa, b.no_isa) {
        (_, true) => StaticCostSource::Skip,
        (Some(p), _) if !p.is_file() => {
            return Err(Error::Usage(format!("--isa {}: no such file", p.display())))
        }
        (Some(p), _) => StaticCostSource::File(p.clone()),
        (None, false) => StaticCostSource::Run {
            exe: std::env::current_exe()
                .map_err(|e| Error::io(std::path::Path::new("shadelab"), e))?,
            scene: b.scene.scene.clone(),
        },
    })
}

pub(super) fn cmd_bench(b: BenchCmd) -> Result<ExitCode> {
    let (list, with_auto) = crate::auto::split_methods(&b.methods);
    let methods = select_methods(&list)?;
    let scene = load_scene(&b.scene)?;
    let software = b.device.engine == EngineArg::Software;
    let schedule = crate::bench::schedule::Schedule::new(
        crate::bench::schedule::Job::Bench { software },
        &b.given(),
    )?;
    let runs = bench_runs(&b, &schedule)?;
    let static_cost = static_cost_source(&b)?;
    let mut opts = crate::bench::BenchOptions {
        schedule,
        error_metric: b.error_metric,
        sweeps: b.sweep.into_iter().map(Into::into).collect(),
        baseline: b.baseline,
        fail_slower_pct: b.fail_slower,
        command_line: std::env::args().collect(),
        auto: Vec::new(),
        runs,
        static_cost,
        software_column: !b.no_software,
        costs: crate::costs::builtin(),
        compared: None,
        clock: None,
    };
    let (dev, out) = (&b.device, b.out.as_path());
    b.precision.check_engine(dev)?;
    if dev.engine == EngineArg::Software {
        if with_auto {
            return Err(Error::Usage(
                "auto is drawn by the Vulkan pipeline only: leave it out of --methods with \
                 --engine software"
                    .into(),
            ));
        }
        let vulkan_only = [
            ("--sweep", !opts.sweeps.is_empty()),
            ("--baseline", opts.baseline.is_some()),
            ("--control", b.control),
        ];
        if let Some((flag, _)) = vulkan_only.iter().find(|(_, given)| *given) {
            return Err(Error::Usage(format!(
                "{flag} is not measured by bench --engine software (the Vulkan bench has it): \
                 use --engine vulkan"
            )));
        }
        let sw = crate::bench::software::SoftwareOptions {
            rounds: opts.schedule.rounds.clone(),
            threads: b
                .threads
                .map_or_else(crate::software::default_threads, |n| n as usize),
            vulkan_bench: b.vulkan_bench,
            command_line: opts.command_line.clone(),
        };
        let vk = if b.vulkan_paired {
            Some(vulkan_renderer(dev)?)
        } else {
            None
        };
        let report = crate::bench::software::bench(&scene, &methods, out, &sw, vk.as_ref())?;
        print!("{}", crate::bench::software::table(&report));
        if let Some(r) = &vk {
            check_validation(r.context())?;
        }
        return Ok(ExitCode::SUCCESS);
    }
    if b.vulkan_paired || b.vulkan_bench.is_some() {
        return Err(Error::Usage(
            "--vulkan-paired and --vulkan-bench give the Vulkan column of a software bench: \
             use them with --engine software"
                .into(),
        ));
    }
    if let Some(n) = b.threads {
        // lavapipe reads LP_NUM_THREADS when its device is created: this must come before the
        // Vulkan instance (the renderer below). Nothing else runs yet: no other thread reads
        // the environment while it changes.
        std::env::set_var("LP_NUM_THREADS", n.to_string());
    }
    let r = b.precision.renderer(dev)?;
    if with_auto && b.precision.precision != crate::method::Precision::F32 {
        return Err(Error::Usage(
            "auto chooses among float32 programs: leave it out of --methods with --precision f16"
                .into(),
        ));
    }
    if with_auto {
        opts.auto = auto_spec(&r, &b.error_budget)?.with_curve(&b.auto_curve);
    }
    let report = crate::bench::bench(&r, &scene, &methods, out, &opts)?;
    print_table(&report);
    print_notes(&report);
    print!(
        "{}",
        crate::bench::speed_claims::markdown(&report.speed_claims, Some(&report.static_cost))
    );
    log::info!(
        "wrote {} ({:.1} s)",
        out.join("bench.json").display(),
        report.total_s
    );
    check_validation(r.context())?;
    Ok(print_baseline(&report))
}

/// The timing table: the floors first, then the methods by median.
fn print_table(report: &crate::bench::BenchReport) {
    println!(
        "scene {} at {}x{}, {} triangles; clock: {}; LP_NUM_THREADS={}; {} rounds ({})",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        report.clock.clock,
        report.lp_num_threads.as_deref().unwrap_or("unset"),
        report.rounds.rounds,
        report.rounds.stopped.as_str()
    );
    println!(
        "{:<34} {:>9} {:>19} {:>8} {:>26} {:>12} {:>8} {:>12}",
        "program",
        "median ms",
        "95% CI ms",
        "ns/px",
        "/ phong_exact (paired)",
        "speed",
        "overdraw",
        report.error_metric
    );
    let mut rows: Vec<&crate::bench::MethodTiming> = std::iter::once(&report.floor)
        .chain(&report.other_floors)
        .chain(&report.methods)
        .collect();
    let floors = 1 + report.other_floors.len();
    rows[floors..].sort_by(|a, b| a.median_ms.total_cmp(&b.median_ms));
    for m in rows {
        let err = m.error.as_ref().and_then(|e| report.error_metric.of(e));
        println!(
            "{:<34} {:>9.3} {:>19} {:>8.2} {:>26} {:>12} {:>8} {:>12}{}",
            m.name,
            m.median_ms,
            format!("[{:.3}, {:.3}]", m.ci95_low_ms, m.ci95_high_ms),
            m.ns_per_pixel,
            format!(
                "{:.4} [{:.4}, {:.4}]",
                m.ratio_median, m.ratio_ci95_low, m.ratio_ci95_high
            ),
            m.speed_vs_phong_exact.as_str(),
            m.overdraw
                .map(|o| format!("{o:.2}"))
                .unwrap_or_else(|| "-".into()),
            err.map(|e| format!("{e:.3e}"))
                .unwrap_or_else(|| "-".into()),
            if report.pareto_front.contains(&m.name) {
                "  pareto"
            } else {
                ""
            }
        );
    }
    for f in &report.other_floors {
        println!(
            "{}: geometry cost: {:.4}x the scene's floor per round, 95% interval [{:.4}, {:.4}]; methods on it are measured against it",
            f.name, f.ratio_to_floor_median, f.ratio_to_floor_ci95_low, f.ratio_to_floor_ci95_high
        );
    }
    for m in report
        .methods
        .iter()
        .filter(|m| m.floor_program != "constant")
    {
        println!(
            "{}: shading cost on its own geometry: {:.4}x {} per round, 95% interval [{:.4}, {:.4}]",
            m.name,
            m.ratio_to_floor_median,
            m.floor_program,
            m.ratio_to_floor_ci95_low,
            m.ratio_to_floor_ci95_high
        );
    }
}

/// auto's curve, how the rounds stopped, the sweeps' slopes.
fn print_notes(report: &crate::bench::BenchReport) {
    for (a, c) in report.auto_curve.iter().zip(&report.auto) {
        let chosen: Vec<String> = c
            .triangles
            .iter()
            .filter(|(_, k)| *k > 0)
            .map(|(m, k)| format!("{m} {k}"))
            .collect();
        println!(
            "{} (budget {:.3e}): max_abs_error {:.3e} ({}), {:.4} [{:.4}, {:.4}] of phong_exact (paired, {}), {}; triangles: {}",
            a.name,
            a.budget,
            a.max_abs_error,
            if a.within_budget { "within budget" } else { "OVER budget" },
            a.ratio_median,
            a.ratio_ci95_low,
            a.ratio_ci95_high,
            a.speed_vs_phong_exact.as_str(),
            if a.beaten_by.is_empty() {
                "no fixed method beats it".to_string()
            } else {
                format!("beaten by {}", a.beaten_by.join(", "))
            },
            chosen.join(", ")
        );
    }
    if let Some(runs) = &report.runs {
        println!(
            "{} runs, each a fresh process; speed from the interval across runs (coverage {:.2} %), \
             beyond phong_exact_control's spread +-{:.2} %{}",
            runs.count,
            runs.confidence * 100.0,
            runs.control.spread * 100.0,
            if runs.note.is_empty() {
                String::new()
            } else {
                format!("; {}", runs.note)
            }
        );
    }
    let rr = &report.rounds;
    match rr.stopped {
        crate::bench::Stop::FixedRepeat => println!(
            "{} rounds (--repeat); widest paired ratio interval +-{:.2} % ({})",
            rr.rounds, rr.widest_half_width_pct, rr.widest
        ),
        crate::bench::Stop::TargetReached => println!(
            "--until-ci: target reached: every paired ratio interval within +-{} % after {} rounds ({:.1} s); widest +-{:.2} % ({})",
            rr.until_ci_pct.unwrap_or(f64::NAN), rr.rounds, rr.timing_s, rr.widest_half_width_pct, rr.widest
        ),
        crate::bench::Stop::TimeCap => println!(
            "--until-ci: time cap of {} s reached after {} rounds, target +-{} % not reached: widest paired ratio interval +-{:.2} % ({})",
            rr.max_time_s.unwrap_or(f64::NAN), rr.rounds, rr.until_ci_pct.unwrap_or(f64::NAN), rr.widest_half_width_pct, rr.widest
        ),
    }
    for s in &report.sweeps {
        for (name, per_m, loglog) in &s.slopes {
            println!(
                "sweep {:?}: {name}: {per_m:.4} ms per million {}, log-log slope {loglog:.3}",
                s.sweep, s.work
            );
        }
    }
}

/// The comparison with `--baseline` (exit 1 when a program is slower beyond --fail-slower).
fn print_baseline(report: &crate::bench::BenchReport) -> ExitCode {
    let Some(b) = &report.baseline else {
        return ExitCode::SUCCESS;
    };
    println!("baseline {}: {}", b.path, b.note);
    for d in &b.setup_differences {
        println!("baseline: setup differs: {d}");
    }
    for p in &b.programs {
        let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.3}"));
        println!(
            "{:<34} {:>9} [{}, {}] -> {:>9} [{}, {}] ms  {:+.1} %  {:?}{}",
            p.name,
            f(p.baseline_median_ms),
            f(p.baseline_ci95_low_ms),
            f(p.baseline_ci95_high_ms),
            f(p.median_ms),
            f(p.ci95_low_ms),
            f(p.ci95_high_ms),
            p.change_pct.unwrap_or(f64::NAN),
            p.change,
            if p.fails { "  FAILS --fail-slower" } else { "" }
        );
    }
    for (what, list) in [
        ("only in the baseline", &b.only_in_baseline),
        ("only in this run", &b.only_in_this_run),
    ] {
        if !list.is_empty() {
            println!("baseline: {what}: {}", list.join(", "));
        }
    }
    if b.exceeded() {
        let pct = b.fail_slower_pct.unwrap_or(f64::NAN);
        for n in &b.failing {
            eprintln!(
                "shadelab: {n} is slower than the baseline beyond both 95% intervals by more than {pct} % (not paired)"
            );
        }
        for n in &b.not_comparable {
            eprintln!("shadelab: {n} cannot be compared with the baseline (a median or interval end is missing or not finite)");
        }
        return ExitCode::from(EXIT_THRESHOLD);
    }
    ExitCode::SUCCESS
}
