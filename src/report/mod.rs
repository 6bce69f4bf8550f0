//! `shadelab report`: the main job. For each scene it runs [`crate::compare`] (error maps and
//! statistics) and [`crate::bench`] (timing, Pareto chart, the papers' claims), then
//! [`crate::stress`] once (it is scene-independent), and writes DIR/index.html beside the files
//! those jobs wrote: the page only points at them (no copies), plus its own `report.css`,
//! `report.js` and `formulas.html` (the page the claims' citations link to).
//!
//! Invariants of the page ([`html`]): every string from a scene, a method or a measurement is
//! escaped; every `href`/`src` is a relative path to a file under DIR (with an `#id` that page
//! has, when it names one of another HTML page) or an `#id` of the page ([`links::broken_links`]
//! checks all three, and the tests run it); nothing is fetched from the
//! network (no CDN, font or script from elsewhere); the tables and images are plain HTML, and the
//! script only adds sorting and the method/reference viewer.
//!
//! Layout of DIR: `index.html`, `answer.json` and `answer.md` ([`answer`]), `report.css`,
//! `report.js`, `formulas.html` (docs/formulas.md, which the claims cite: [`formulas`]), `scenes/<id>/compare/` (compare's outputs), `scenes/<id>/bench/` (bench's
//! outputs), `scenes/<id>/software/` (the software engine's bench), `stress/` (stress's outputs).
//!
//! The page opens with the answer ([`first_screen::section`]: in words, what differs, per
//! scene, the full grid one click away), then the charts ([`svg`]: small
//! multiples, one panel per method family), the claims matrix, and the scenes, the most telling
//! (the most triangles) first.
pub mod answer;
mod answer_text;
mod body;
pub mod budget;
pub mod cell;
pub mod first_screen;
pub mod formulas;
pub mod front;
pub mod html;
pub mod isa;
pub mod links;
pub mod models;
pub mod sections;
pub mod summary;
pub mod svg;
#[cfg(test)]
mod tests;
pub mod tuned;

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::bench::{BenchOptions, BenchReport};
use crate::compare::{CompareOptions, Summary};
use crate::error::{Error, Result};
use crate::gpu::Renderer;
use crate::method::{self, Method};
use crate::output;
use crate::scene::Scene;
use crate::stress::{StressOptions, StressReport};

/// The page's style sheet and script, written beside index.html.
pub const CSS: &str = include_str!("report.css");
pub const JS: &str = include_str!("report.js");

/// One scene of a report, loaded by the caller.
#[derive(Debug, Clone)]
pub struct ReportScene {
    /// Where it came from (scene file or OBJ), for the page.
    pub source: PathBuf,
    pub scene: Scene,
    /// What loads the same scene: a bench of several runs gives it to each fresh process.
    pub load: crate::scene::SceneSource,
}

/// What the default report of the shipped scenes may weigh, every file under DIR included
/// (docs/report.md): `shadelab report` warns above it; a test holds the shipped scenes under it.
pub const SIZE_LIMIT_BYTES: u64 = 50_000_000;

/// The settings of a report run.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// `--full`: bench's long setting (40 timed draws after 3 warm-ups, stress refined 8 rounds)
    /// instead of the short one (10 after 2, stress refined 2 rounds).
    pub full: bool,
    /// The command line, for the provenance section.
    pub command_line: String,
    /// Show a progress bar on stderr (drawn only when stderr is a terminal).
    pub progress: bool,
    /// The measurement schedule (`report --runs`, `--full`: [`crate::bench::schedule`], decided once
    /// by the caller). Several runs need `exe`.
    pub schedule: crate::bench::schedule::Schedule,
    /// The shadelab binary that starts a bench's fresh-process runs.
    pub exe: Option<PathBuf>,
    /// The device every bench run opens (the report's own).
    pub device: crate::gpu::DeviceSpec,
    /// The cost models of the answer and of the benches' speed claims.
    pub costs: crate::cost::Registry,
    /// `shadelab tune`'s tune.json, an input of the answer ([`tuned`]).
    pub tuned: Option<PathBuf>,
}

/// Everything one scene contributed: the compare summary and the bench report, and where their
/// files are (relative to DIR, `/`-separated).
#[derive(Debug, Clone)]
pub struct SceneResult {
    /// Unique, made of `[A-Za-z0-9_-]` only: a folder name and an HTML id.
    pub id: String,
    pub source: String,
    pub summary: Summary,
    /// compare of the float16 programs (statistics only, in `compare_f16_dir`): the errors of
    /// the answer's float16 cost models; `None` when the device has no float16 arithmetic.
    pub summary_f16: Option<Summary>,
    pub compare_f16_dir: String,
    pub bench: BenchReport,
    pub compare_dir: String,
    pub bench_dir: String,
    /// Pareto charts found in the bench folder (`pareto*.png`), relative to DIR.
    pub pareto_charts: Vec<String>,
    /// What the scene needs (`shadelab plan`), also written as scenes/<id>/plan.json.
    pub plan: crate::plan::Plan,
    pub plan_json: String,
    /// What each skip saves (`shadelab skips`, in scenes/<id>/skips/).
    pub skips: crate::bench::skips::SkipReport,
    pub skips_dir: String,
    /// The software engine's bench of the scene (scenes/<id>/software/).
    pub software: Option<crate::bench::software::SoftwareBench>,
    pub software_dir: String,
}

impl SceneResult {
    /// This (first) scene's clock check as the later scenes' bench and skips take it, saying
    /// where it was made.
    fn clock_for_later_scenes(&self) -> crate::bench::ClockCheck {
        crate::bench::ClockCheck {
            reason: format!(
                "checked once for this report, with scene {}: {}",
                self.id, self.bench.clock.reason
            ),
            ..self.bench.clock.clone()
        }
    }
}

/// What the page says about the run itself.
#[derive(Debug, Clone)]
pub struct RunInfo {
    pub command_line: String,
    pub date_utc: String,
    pub cpu_model: String,
    pub available_threads: usize,
    pub lp_num_threads: Option<String>,
    pub bench_repeat: usize,
    pub bench_warmup: usize,
    pub bench_runs: usize,
    pub stress_refine: usize,
    pub full: bool,
    pub seconds: f64,
}

/// All the page shows.
#[derive(Debug, Clone)]
pub struct ReportData {
    pub scenes: Vec<SceneResult>,
    pub stress: StressReport,
    pub stress_dir: String,
    pub run: RunInfo,
    /// answer.json.
    pub answer: answer::Answer,
    /// `isa` on the report's methods, float32 and float16 (static cost models of the answer).
    pub isa: isa::IsaRun,
    /// The report's methods (the references included), in its order.
    pub methods: Vec<&'static Method>,
    /// What `shadelab tune` found (`--tuned`), copied to DIR/tune/tune.json.
    pub tuned: Option<tuned::Tuned>,
}

/// What a run wrote.
#[derive(Debug, Clone)]
pub struct Written {
    pub index: PathBuf,
    /// Bytes of every file under DIR (the page and everything it can open).
    pub total_bytes: u64,
    pub files: usize,
    /// Methods shown per scene ([`always`] included).
    pub methods: usize,
    pub seconds: f64,
    /// The answer (`shadelab report` prints its words, [`answer::Answer::terminal`]).
    pub answer: answer::Answer,
}

/// The methods a report always includes: the references of bench's ratios (bench times them
/// whatever it is asked, and its rows and claims must have a method section to link to).
pub fn always() -> [&'static Method; 2] {
    [method::phong_exact(), method::phong_unnormalized()]
}

/// A folder name / HTML id from a scene's file stem: `[A-Za-z0-9_-]`, unique among `taken`.
pub fn scene_id(stem: &str, taken: &[String]) -> String {
    let mut base: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if base.is_empty() {
        base = "scene".into();
    }
    let mut id = base.clone();
    let mut n = 2;
    while taken.contains(&id) {
        id = format!("{base}-{n}");
        n += 1;
    }
    id
}

/// The current date and time in UTC, `YYYY-MM-DD HH:MM UTC` (no time-zone database needed).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    format_utc(secs)
}

/// `secs` since 1970-01-01 as `YYYY-MM-DD HH:MM UTC` (Howard Hinnant's civil-from-days).
pub fn format_utc(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02} UTC",
        rem / 3600,
        (rem % 3600) / 60
    )
}

/// `methods` plus [`always`], in the method table's order.
fn with_references(methods: &[&'static Method]) -> Vec<&'static Method> {
    let always = always();
    method::all()
        .into_iter()
        .filter(|m| methods.iter().chain(&always).any(|x| x.name == m.name))
        .collect()
}

/// `pareto*.png` in `dir`, sorted, as paths relative to DIR (`rel` is `dir` relative to DIR).
fn pareto_charts(dir: &Path, rel: &str) -> Result<Vec<String>> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("pareto") && n.ends_with(".png"))
        .map(|n| format!("{rel}/{n}"))
        .collect();
    v.sort();
    Ok(v)
}

/// The report's progress bar (steps: compare, bench and skips per scene, stress, the page),
/// registered so that what the jobs log (`-v`) is printed above it, not through it.
fn progress(opts: &ReportOptions, scenes: usize) -> indicatif::ProgressBar {
    let bar = output::progress_bar(opts.progress, 3 * scenes as u64 + 2);
    output::terminal::show_bar(Some(bar.clone()));
    bar
}

/// Shows the step on the progress bar; where the bar is not drawn (stderr is not a terminal,
/// as under `make demo > log 2>&1`), prints it as a line with the time since the start.
fn step(bar: &indicatif::ProgressBar, progress: bool, msg: String) {
    // `-q` (errors only) hides the steps too.
    if progress && bar.is_hidden() && log::max_level() >= log::LevelFilter::Warn {
        eprintln!("report: [{:.0} s] {msg}", bar.elapsed().as_secs_f64());
    }
    bar.set_message(msg);
}

/// Bytes and number of the files under `dir`.
pub fn tree_size(dir: &Path) -> Result<(u64, usize)> {
    let mut total = (0, 0);
    for e in std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let e = e.map_err(|e| Error::io(dir, e))?;
        let meta = e.metadata().map_err(|err| Error::io(e.path(), err))?;
        if meta.is_dir() {
            let (b, n) = tree_size(&e.path())?;
            total.0 += b;
            total.1 += n;
        } else {
            total.0 += meta.len();
            total.1 += 1;
        }
    }
    Ok(total)
}

/// What every scene of one report run shares: [`SceneRun::scene`] runs one scene's jobs.
struct SceneRun<'a> {
    renderer: &'a Renderer,
    /// The same device drawing the float16 programs, when it can.
    half: Option<&'a Renderer>,
    methods: &'a [&'static Method],
    out: &'a Path,
    /// The schedule of this scene (only the first scene measures the isolated cost:
    /// [`crate::bench::schedule::Schedule::later_scene`]).
    schedule: crate::bench::schedule::Schedule,
    auto: &'a crate::auto::AutoSpec,
    /// The clock check of the report's first scene (its bench's): a property of the device and
    /// driver, checked once and used by every later bench and skips.
    clock: Option<crate::bench::ClockCheck>,
    bar: &'a indicatif::ProgressBar,
    opts: &'a ReportOptions,
}

impl SceneRun<'_> {
    /// Compare, bench, skips and plan of scene `s` (id `id`), written under `scenes/<id>/`.
    fn scene(&self, s: &ReportScene, id: String) -> Result<SceneResult> {
        let compare_dir = format!("scenes/{id}/compare");
        let bench_dir = format!("scenes/{id}/bench");
        step(self.bar, self.opts.progress, format!("{id}: compare"));
        let copts = CompareOptions {
            progress: false,
            ..CompareOptions::default()
        };
        let summary = crate::compare::compare(
            self.renderer,
            &s.scene,
            self.methods,
            &self.out.join(&compare_dir),
            &copts,
        )?;
        let compare_f16_dir = format!("scenes/{id}/compare-f16");
        let summary_f16 = match self.half {
            Some(half) => {
                step(
                    self.bar,
                    self.opts.progress,
                    format!("{id}: compare float16"),
                );
                let opts = CompareOptions {
                    images: false,
                    ..copts
                };
                let dir = self.out.join(&compare_f16_dir);
                // A user method without float16 programs (its file is float32 only) is left
                // out of the float16 compare: its float16 rows then fail their budgets.
                let methods: Vec<&'static Method> = self
                    .methods
                    .iter()
                    .copied()
                    .filter(|m| crate::gpu::shaders::has_precision(m.name, method::Precision::F16))
                    .collect();
                let sum = crate::compare::compare(half, &s.scene, &methods, &dir, &opts)?;
                // Without images compare writes no file: the statistics are the evidence.
                std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
                crate::compare::write_summary(&dir, &sum)?;
                Some(sum)
            }
            None => None,
        };
        self.bar.inc(1);
        step(self.bar, self.opts.progress, format!("{id}: bench"));
        let bdir = self.out.join(&bench_dir);
        std::fs::create_dir_all(&bdir).map_err(|e| Error::io(&bdir, e))?;
        let bopts = BenchOptions {
            schedule: self.schedule.clone(),
            command_line: std::env::args().collect(),
            runs: self.bench_runs(s),
            costs: self.opts.costs.clone(),
            compared: Some(summary.clone()),
            clock: self.clock.clone(),
            ..BenchOptions::default()
        };
        // What the jobs log goes above the bar (output::terminal); the bar is not suspended
        // around them, which would hold its lock while they log.
        let bench = crate::bench::bench(self.renderer, &s.scene, self.methods, &bdir, &bopts)?;
        self.bar.inc(1);
        let pareto = pareto_charts(&bdir, &bench_dir)?;
        step(self.bar, self.opts.progress, format!("{id}: skips"));
        let skips_dir = format!("scenes/{id}/skips");
        let (repeat, warmup) = self.schedule.skips_rounds();
        let sopts = crate::bench::skips::SkipOptions {
            repeat,
            warmup,
            auto: self.auto.clone(),
            command_line: std::env::args().collect(),
            clock: Some(bench.clock.clone()),
        };
        let skips = crate::bench::skips::skips(
            self.renderer,
            &s.scene,
            &self.out.join(&skips_dir),
            &sopts,
        )?;
        self.bar.inc(1);
        step(
            self.bar,
            self.opts.progress,
            format!("{id}: software engine"),
        );
        let software_dir = format!("scenes/{id}/software");
        let software = self.software(s, &self.out.join(&software_dir))?;
        let plan = crate::plan::plan(&s.scene);
        let plan_json = format!("scenes/{id}/plan.json");
        let text =
            serde_json::to_string_pretty(&plan).map_err(|e| Error::output("plan.json", e))?;
        crate::output::write_bytes_atomic(&self.out.join(&plan_json), (text + "\n").as_bytes())?;
        Ok(SceneResult {
            plan,
            plan_json,
            skips,
            skips_dir,
            id,
            source: s.source.display().to_string(),
            summary,
            summary_f16,
            compare_f16_dir,
            bench,
            compare_dir,
            bench_dir,
            pareto_charts: pareto,
            software: Some(software),
            software_dir,
        })
    }

    /// One run here, or the schedule's runs as fresh processes on the same scene (each with its
    /// own Vulkan device, JIT, warm-up and rounds; [`crate::bench::runs`]).
    fn bench_runs(&self, s: &ReportScene) -> crate::bench::Runs {
        match self.opts.exe.clone().filter(|_| self.schedule.many()) {
            None => crate::bench::Runs::One,
            Some(exe) => crate::bench::Runs::Many(crate::bench::runs::Launcher {
                exe,
                scene: s.load.clone(),
                device: self.opts.device.clone(),
                driver_env: Vec::new(),
            }),
        }
    }

    /// The software engine's bench of scene `s` (its own rounds; a cost model of the answer).
    fn software(
        &self,
        s: &ReportScene,
        dir: &Path,
    ) -> Result<crate::bench::software::SoftwareBench> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let sw = crate::bench::software::SoftwareOptions {
            rounds: self.schedule.software_rounds(),
            threads: crate::software::default_threads(),
            vulkan_bench: None,
            command_line: std::env::args().collect(),
        };
        // A user method (--method-file) has no software kernel: not in this cost model.
        let methods: Vec<&'static Method> = (self.methods.iter().copied())
            .filter(|m| m.kernel.exists())
            .collect();
        crate::bench::software::bench(&s.scene, &methods, dir, &sw, None)
    }
}

/// Writes answer.json, answer.md, the style sheet, the script and index.html of `data`.
fn write_page(out: &Path, data: &ReportData) -> Result<PathBuf> {
    // Compact (one line): 1.1 MB against 1.6 MB indented with 63 cost models.
    let json = serde_json::to_string(&data.answer).map_err(|e| Error::output("answer.json", e))?;
    output::write_bytes_atomic(&out.join("answer.json"), (json + "\n").as_bytes())?;
    output::write_bytes_atomic(&out.join("answer.md"), data.answer.markdown().as_bytes())?;
    output::write_bytes_atomic(&out.join("report.css"), CSS.as_bytes())?;
    output::write_bytes_atomic(&out.join("report.js"), JS.as_bytes())?;
    let sources = formulas::page(formulas::SOURCE);
    output::write_bytes_atomic(&out.join(formulas::PAGE), sources.as_bytes())?;
    let page = sections::page(data, &|rel| image::image_dimensions(out.join(rel)).ok());
    let index = out.join("index.html");
    output::write_bytes_atomic(&index, page.as_bytes())?;
    Ok(index)
}

/// Reads `--tuned FILE` and copies it to DIR/tune/tune.json (the page links to the copy).
fn read_tuned(path: Option<&Path>, out: &Path) -> Result<Option<tuned::Tuned>> {
    let Some(path) = path else { return Ok(None) };
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let rel = "tune/tune.json";
    let t = tuned::Tuned::parse(&text, rel, path)?;
    output::write_bytes_atomic(&out.join(rel), text.as_bytes())?;
    Ok(Some(t))
}

/// Runs compare and bench on every scene and stress once, then writes DIR/index.html.
pub fn run(
    renderer: &Renderer,
    scenes: &[ReportScene],
    methods: &[&'static Method],
    out: &Path,
    opts: &ReportOptions,
) -> Result<Written> {
    let start = Instant::now();
    if scenes.is_empty() {
        return Err(Error::Usage("the report has no scene to show".into()));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    // Read before measuring: a bad file must not cost a run.
    let tuned = read_tuned(opts.tuned.as_deref(), out)?;
    let methods = with_references(methods);
    let schedule = &opts.schedule;
    if schedule.many() && opts.exe.is_none() {
        return Err(Error::Usage(format!(
            "a report of {} bench runs needs the shadelab binary to start them",
            schedule.runs
        )));
    }
    let bar = progress(opts, scenes.len());
    let results = measure_scenes(renderer, scenes, &methods, out, opts, &bar)?;
    step(&bar, opts.progress, "stress".to_string());
    let sopts = StressOptions {
        refine_rounds: schedule.stress_refine,
        progress: false,
        ..StressOptions::default()
    };
    let stress = crate::stress::run(renderer.context(), &methods, &sopts)?;
    crate::stress::write(&out.join("stress"), &stress)?;
    bar.inc(1);
    step(
        &bar,
        opts.progress,
        "isa (static cost, float32 and float16)".to_string(),
    );
    let isa = isa::compile_all(out, &methods, &results, opts.full);
    step(&bar, opts.progress, "index.html".to_string());
    let mut data = ReportData {
        answer: answer::answer(&[], &[], &[], Vec::new()),
        isa,
        methods: methods.clone(),
        tuned,
        scenes: results,
        stress,
        stress_dir: "stress".into(),
        run: RunInfo {
            command_line: opts.command_line.clone(),
            date_utc: utc_now(),
            cpu_model: output::provenance::cpu_model(),
            available_threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
            bench_repeat: schedule.rounds.repeat,
            bench_warmup: schedule.rounds.warmup,
            bench_runs: schedule.runs,
            stress_refine: schedule.stress_refine,
            full: opts.full,
            seconds: start.elapsed().as_secs_f64(),
        },
    };
    data.answer = front::answer_of(&data, &opts.costs);
    let index = write_page(out, &data)?;
    bar.inc(1);
    bar.finish_and_clear();
    output::terminal::show_bar(None);
    let broken = links::broken_links(&index)?;
    if !broken.is_empty() {
        return Err(Error::Internal(format!(
            "the report links to {} missing target(s), first: {}",
            broken.len(),
            broken[0]
        )));
    }
    let (total_bytes, files) = tree_size(out)?;
    Ok(Written {
        index,
        total_bytes,
        files,
        methods: methods.len(),
        seconds: start.elapsed().as_secs_f64(),
        answer: data.answer,
    })
}

/// Every scene's compare (float32 and float16), bench, skips and software engine, in the
/// page's order (only the first scene measures the isolated cost and checks the clock).
fn measure_scenes(
    renderer: &Renderer,
    scenes: &[ReportScene],
    methods: &[&'static Method],
    out: &Path,
    opts: &ReportOptions,
    bar: &indicatif::ProgressBar,
) -> Result<Vec<SceneResult>> {
    let schedule = &opts.schedule;
    let mut scenes = scenes.to_vec();
    front::order_scenes(&mut scenes);
    // `auto`'s candidates for the skips rows, by isolated cost: measured once for all scenes.
    let auto = crate::auto::AutoSpec::new(
        crate::auto::ErrorBudget::DEFAULT,
        &crate::plan::auto_order(renderer.context())?,
    );
    // The float16 programs' errors (compare, statistics only) for the float16 cost models.
    let half = Renderer::new(renderer.context().clone())
        .with_precision(crate::method::Precision::F16)
        .ok();
    let mut results: Vec<SceneResult> = Vec::new();
    for s in &scenes {
        let taken: Vec<String> = results.iter().map(|r| r.id.clone()).collect();
        let stem = s
            .source
            .file_stem()
            .map(|x| x.to_string_lossy().into_owned())
            .unwrap_or_default();
        let id = scene_id(&stem, &taken);
        let run = SceneRun {
            renderer,
            half: half.as_ref(),
            methods,
            out,
            schedule: if results.is_empty() {
                schedule.clone()
            } else {
                schedule.later_scene()
            },
            auto: &auto,
            clock: results.first().map(SceneResult::clock_for_later_scenes),
            bar,
            opts,
        };
        results.push(run.scene(s, id)?);
    }
    Ok(results)
}
