//! The command line: argument parsing (clap) and one function per command. `main.rs` only calls
//! [`run`] and maps its result to an exit code.
mod bench;
mod cache;
mod checks;
mod child;
mod compare;
mod corpus;
mod demo;
mod isa;
mod list;
mod merge;
mod mesh;
mod plan;
mod prove;
mod render;
mod report;
mod shaders;
mod skips;
mod stress;
mod tune;
mod verbosity;
mod verify;

use self::bench::cmd_bench;
use self::checks::{count, count_u32, parse_size, parse_threshold, select_methods};
use self::compare::cmd_compare;
use self::demo::cmd_demo;
use self::list::cmd_list;
use self::mesh::cmd_mesh;
use self::plan::cmd_plan;
use self::prove::cmd_prove;
use self::render::cmd_render;
use self::shaders::cmd_shaders;
use self::skips::{cmd_skips, SkipsCmd};
use self::stress::cmd_stress;
use self::verify::cmd_verify;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use clap::{ArgGroup, Args, Parser, Subcommand, ValueEnum};

use crate::auto::ErrorBudget;
use crate::error::{Error, Result};
use crate::gpu::vk::{Context, ContextDesc};
use crate::gpu::Renderer;
use crate::scene::{self, Interpolation, Scene};

/// Exit code: a threshold was exceeded (results were still written).
pub const EXIT_THRESHOLD: u8 = 1;
/// Exit code: usage, input or runtime error.
pub const EXIT_ERROR: u8 = 2;

#[derive(Parser, Debug)]
#[command(
    name = "shadelab",
    version, long_version = crate::output::provenance::LONG_VERSION,
    about = "Fast Phong-shading methods against exact Phong, on software Vulkan"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Your own method: a GLSL file in glsl/methods/' vocabulary whose first lines
    /// declare its inputs (`// shadelab-inputs: interpolated_normal`); its id is the file stem.
    /// Repeatable. It joins `all` and can be named in --methods / --method of render, compare,
    /// bench, stress, isa, report and corpus (docs/your-method.md). Child processes get it
    /// in their request.
    #[arg(long = "method-file", value_name = "PATH.glsl", global = true)]
    method_file: Vec<PathBuf>,
    #[command(flatten)]
    verbosity: verbosity::Verbosity,
}

#[derive(Args, Debug, Clone)]
struct SceneArgs {
    /// Scene file (TOML; see README "Scene format").
    #[arg(
        long,
        value_name = "FILE",
        required_unless_present = "mesh",
        conflicts_with = "mesh"
    )]
    scene: Option<PathBuf>,
    /// A mesh file (.obj, .gltf, .glb, .ply) instead of a scene: camera fitted, default light.
    #[arg(long, value_name = "FILE")]
    mesh: Option<PathBuf>,
    /// Image size, overriding the scene's.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Interpolation of the varyings, overriding the scene's.
    #[arg(long, value_enum)]
    interpolation: Option<InterpArg>,
    /// Back-face culling, overriding the scene's `cull` (auto: only closed, consistently
    /// oriented meshes; see `shadelab plan`).
    #[arg(long, value_enum)]
    cull: Option<CullArg>,
}

#[derive(ValueEnum, Debug, Clone, Copy)]
enum CullArg {
    Auto,
    Back,
    None,
}

#[derive(Args, Debug, Clone)]
struct DeviceArgs {
    /// Case-insensitive substring of the Vulkan device name (default: lavapipe / llvmpipe).
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Run under the Khronos validation layer; any message makes the command fail (exit 2).
    #[arg(long)]
    validate: bool,
    /// Which renderer draws: the Vulkan pipeline (lavapipe), or the software scanline engine
    /// (src/software/: every method in its incremental span form, float32, all cores).
    #[arg(long, value_enum, default_value = "vulkan")]
    engine: EngineArg,
}

/// `--precision`, shared by render, compare, stress, bench and isa.
#[derive(Args, Debug, Clone, Copy)]
pub(super) struct PrecisionArgs {
    /// Arithmetic of the method programs: f32, or f16 (the same GLSL compiled with float16_t:
    /// the method and the lighting in float16, inputs converted where read; docs/float16.md).
    /// f16 needs a device with shaderFloat16 (lavapipe has it) and --engine vulkan.
    #[arg(long, default_value = "f32", value_parser = parse_precision())]
    pub precision: crate::method::Precision,
}

/// The parser of `--precision`: the names of [`crate::method::Precision::as_str`].
fn parse_precision() -> impl clap::builder::TypedValueParser<Value = crate::method::Precision> {
    use crate::method::Precision;
    use clap::builder::TypedValueParser;
    // Only the names of Precision::ALL get through, so the FromStr of Precision always succeeds.
    clap::builder::PossibleValuesParser::new(Precision::ALL.map(Precision::as_str))
        .map(|s| s.parse::<Precision>().unwrap_or_default())
}

impl PrecisionArgs {
    /// An error (exit 2) for float16 on the software engine, which computes in float32.
    fn check_engine(&self, dev: &DeviceArgs) -> Result<()> {
        if self.precision != crate::method::Precision::F32 && dev.engine == EngineArg::Software {
            return Err(crate::error::Error::Usage(format!(
                "--precision {}: the software engine computes in float32; use --engine vulkan",
                self.precision
            )));
        }
        Ok(())
    }

    /// The Vulkan renderer of `dev` drawing in this precision (exit 2 when the device lacks
    /// float16 arithmetic).
    fn renderer(&self, dev: &DeviceArgs) -> Result<Renderer> {
        self.check_engine(dev)?;
        renderer(dev)?.with_precision(self.precision)
    }
}

/// `--error-budget` and `--cost-model`, shared by every command that draws `auto`.
#[derive(Args, Debug, Clone)]
struct BudgetArgs {
    /// The error budget of `auto` (`--methods ...,auto`, `--method auto`, skips' auto row): the
    /// largest colour error (linear, max over the channels) it may make; a number or a fraction
    /// like 4/255.
    #[arg(long = "error-budget", value_name = "E", default_value = "1/255", value_parser = ErrorBudget::parse)]
    budget: ErrorBudget,
    /// What ranks auto's candidates: a cost model measured at start, `lavapipe_isolated`
    /// (lavapipe's isolated cost) or `isa:FAMILY` (the static cost on that GPU family, e.g.
    /// isa:amd:navi21, isa:intel:tgl; a bare chip is AMD's; docs/isa.md).
    #[arg(long = "cost-model", value_name = "MODEL", default_value = crate::cost::LAVAPIPE_ISOLATED, value_parser = crate::cost::CostModelId::parse)]
    cost_model: crate::cost::CostModelId,
    #[command(flatten)]
    store: StoreArgs,
}

/// `--no-cache`, shared by every command that compiles for GPU families (isa, report, demo,
/// tune, corpus, bench's speed claims, an `isa:` cost model).
#[derive(Args, Debug, Clone, Default)]
pub(super) struct StoreArgs {
    /// Compile every GPU family now instead of reading the compile store (docs/isa.md
    /// "Compile store"), and store nothing; SHADELAB_NO_CACHE=1 does the same.
    #[arg(long)]
    no_cache: bool,
}

impl StoreArgs {
    /// Turns the store off for this process when asked.
    pub(super) fn apply(&self) {
        if self.no_cache {
            crate::isa::store::disable();
        }
    }
}

/// `--engine`.
#[derive(ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
enum EngineArg {
    Vulkan,
    Software,
}

/// `--scale` of `compare`.
#[derive(ValueEnum, Debug, Clone, Copy)]
enum ScaleArg {
    Fixed,
    Auto,
}

impl From<ScaleArg> for crate::compare::ScaleMode {
    fn from(a: ScaleArg) -> Self {
        match a {
            ScaleArg::Fixed => Self::Fixed,
            ScaleArg::Auto => Self::Auto,
        }
    }
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

#[derive(ValueEnum, Debug, Clone, Copy)]
enum InterpArg {
    ScreenLinear,
    Perspective,
}

#[allow(clippy::large_enum_variant)] // parsed once per process: its size costs nothing
#[derive(Subcommand, Debug)]
enum Command {
    /// Render one method to an 8-bit PNG (and optionally the float images as .npy).
    Render {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Method identifier (see `shadelab list`), or `auto` (per triangle the cheapest method
        /// within --error-budget).
        #[arg(long, default_value = crate::method::PHONG_EXACT)]
        method: String,
        /// Output PNG (sRGB, alpha 0 on the background).
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        /// Also write the linear float colour as .npy, shape (H, W, 4), float32.
        #[arg(long, value_name = "FILE.npy")]
        float: Option<PathBuf>,
        /// Also write the shading normal as .npy, shape (H, W, 4), float32 (w 1 where defined).
        #[arg(long, value_name = "FILE.npy")]
        normals: Option<PathBuf>,
        #[command(flatten)]
        error_budget: BudgetArgs,
        #[command(flatten)]
        precision: PrecisionArgs,
    },
    /// Check GPU methods against their own formula evaluated in f64 at the rasterizer's weights.
    Verify {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all", value_parser = checks::method_list)]
        methods: String,
        /// Judge every method against this method's f64 formula instead of its own (teeth checks).
        #[arg(long, value_name = "METHOD")]
        against: Option<String>,
        /// Precision of the programs: f16 judges them by the float16 bound (u = 2^-11) and,
        /// on Vulkan, against the software engine's float16 twin.
        #[arg(long, default_value = "f32", value_parser = parse_precision())]
        precision: crate::method::Precision,
    },
    /// Compare methods against the f64 exact-Phong truth: statistics, heatmaps, JSON/CSV.
    Compare {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all", value_parser = checks::method_list)]
        methods: String,
        /// Output directory (summary.json, summary.csv, reference.png, <method>/*.png).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Exit 1 when any method's METRIC (a summary.json name, lower is better) is above VALUE;
        /// repeatable. A method with NaN/Inf pixels fails every limit on an error metric.
        #[arg(long = "fail-above", value_name = "METRIC=VALUE")]
        fail_above: Vec<String>,
        /// Exit 1 when any method's METRIC (higher is better: psnr_db) is below VALUE; repeatable.
        #[arg(long = "fail-below", value_name = "METRIC=VALUE")]
        fail_below: Vec<String>,
        /// Heatmap scales: `fixed` (shared by all methods) or `auto` (per image).
        #[arg(long, value_enum, default_value = "fixed")]
        scale: ScaleArg,
        /// Linear luminance error above which a pixel counts in pixels_above_threshold
        /// (default 1/255 of linear luminance; not an sRGB 8-bit step).
        #[arg(long, default_value_t = 1.0 / 255.0, value_parser = parse_threshold)]
        threshold: f64,
        #[command(flatten)]
        error_budget: BudgetArgs,
        #[command(flatten)]
        precision: PrecisionArgs,
    },
    /// Run time against error: validated timing, Pareto chart, the papers' claims, sweeps.
    Bench(BenchCmd),
    /// Sweep each method over its input domain (angle, elevation, light, shininess, span,
    /// length, shape) on the device and in f64; worst cases, validity maps, the validity claims.
    Stress {
        #[command(flatten)]
        device: DeviceArgs,
        /// Comma-separated method identifiers, or `all`.
        #[arg(long, default_value = "all", value_parser = checks::method_list)]
        methods: String,
        /// Output directory (stress.json, charts, validity/<method>.png, cases/<method>.json).
        #[arg(long, value_name = "DIR", required_unless_present = "replay")]
        out: Option<PathBuf>,
        /// Evaluate one case again (a cases/<method>.json, or a worst_case of stress.json).
        #[arg(long, value_name = "CASE.json", conflicts_with = "out")]
        replay: Option<PathBuf>,
        /// Max abs colour error (linear) within which a case is valid.
        #[arg(long, default_value_t = 1.0 / 255.0, value_parser = parse_threshold)]
        threshold: f64,
        /// Local-search rounds around each method's worst case (0: grid only; at most 1000).
        #[arg(long, default_value_t = 8, value_parser = count::<0, 1000>)]
        refine: usize,
        /// (`--replay` takes the precision recorded in the case file.)
        #[command(flatten)]
        precision: PrecisionArgs,
    },
    /// Proven upper bounds of each covered method's normal-space and colour errors, and its
    /// largest valid angle, over two declared domains (interval branch-and-bound): any triangle
    /// (three vertex normals pairwise within --max-angle) and stress's edge geometry (N2 the
    /// bisector), beside the worst values found at real points of each.
    Prove(self::prove::ProveArgs),
    /// The best approximation of the inverse square root for a mesh's own angles: per
    /// triangle the exact domain of N.N, minimax polynomials and Newton seeds fitted to it,
    /// each proven (float32 and float16 rounding included) and costed on every cost model
    /// measured on demand; per model the cheapest proven within --budget, or the statement
    /// that none is cheaper than phong_exact (docs/tune.md).
    Tune(self::tune::TuneArgs),
    /// What skipping saves on one scene: phong_exact timed in the same interleaved rounds with
    /// nothing skipped, back-face culling, no normal target, a depth pre-pass, front-to-back
    /// order, and `auto`; fragment invocations and paired frame-time ratios.
    Skips(SkipsCmd),
    /// What a scene needs: topology (culling), the spread of its vertex normals against each
    /// method's measured validity range, triangle sizes and facing, lighting, what is skipped.
    Plan {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        device: DeviceArgs,
        /// JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Also choose per triangle the cheapest method whose f64 error stays within this
        /// budget (the largest colour error, linear, max over the channels; a number or a
        /// fraction like 4/255), as `auto` would, and count them.
        #[arg(long, value_name = "E", value_parser = ErrorBudget::parse)]
        error_budget: Option<ErrorBudget>,
    },
    /// What each method compiles to on the GPU families of every vendor set up (each vendor's
    /// compiler behind a null device or Mesa's drm-shims: statistics, disassembly; no GPU).
    Isa(self::isa::IsaArgs),
    /// List the methods (`--json` for machines).
    List {
        #[arg(long)]
        json: bool,
    },
    /// Generate a procedural mesh as OBJ, or regenerate the shipped meshes of scenes/.
    Mesh {
        /// Generator: uv_sphere, icosphere, torus or cube.
        #[arg(required_unless_present = "shipped")]
        generator: Option<String>,
        /// Generator parameters as key=value.
        params: Vec<String>,
        /// Output OBJ file.
        #[arg(long, value_name = "FILE.obj", required_unless_present = "shipped")]
        out: Option<PathBuf>,
        /// Write every shipped mesh into DIR instead.
        #[arg(long, value_name = "DIR", conflicts_with_all = ["generator", "out"])]
        shipped: Option<PathBuf>,
    },
    /// Compile glsl/ into spirv/ with shaderc (`--check`: only verify spirv/ is fresh).
    Shaders {
        #[arg(long)]
        check: bool,
        #[arg(long, default_value = "glsl")]
        glsl: PathBuf,
        #[arg(long, default_value = "spirv")]
        spirv: PathBuf,
    },
    /// The quick start's report: `report --scenes scenes --out out/report` (what `make demo`
    /// runs), from a checkout of the repository.
    Demo {
        /// The scene files (*.toml) of this folder.
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        /// Output directory of the report.
        #[arg(long, default_value = "out/report")]
        out: PathBuf,
        #[command(flatten)]
        device: DeviceArgs,
        #[command(flatten)]
        store: StoreArgs,
    },
    /// The main job: compare, bench and stress on the given scenes, written as one offline
    /// HTML report (OUT/index.html, its path printed on stdout).
    #[command(group(ArgGroup::new("source").required(true).multiple(true).args(["scenes", "scene", "mesh", "models"])))]
    Report {
        /// Every scene file (*.toml) of DIR.
        #[arg(long, value_name = "DIR")]
        scenes: Option<PathBuf>,
        /// One scene file (TOML).
        #[arg(long, value_name = "FILE")]
        scene: Option<PathBuf>,
        /// One mesh file, .obj, .gltf, .glb or .ply (camera fitted, default light and material).
        #[arg(long, value_name = "FILE")]
        mesh: Option<PathBuf>,
        /// Every mesh file (.obj, .gltf, .glb, .ply) of DIR as one more scene each (camera fitted),
        /// alone or added to --scenes / --scene / --mesh; the answer covers them.
        #[arg(long, value_name = "DIR")]
        models: Option<PathBuf>,
        /// Bench runs per scene, each a fresh process of this binary (`bench --runs`): the
        /// frame-time and isolated-cost verdicts come from the interval across runs (1: one
        /// run in this process; default 5).
        #[arg(long, value_name = "N", value_parser = count::<1, 100>)]
        runs: Option<usize>,
        /// Output directory (index.html and everything it shows).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Comma-separated method identifiers, or `all` (phong_exact and phong_unnormalized,
        /// the references of bench's ratios, are always included).
        #[arg(long, default_value = "all", value_parser = checks::method_list)]
        methods: String,
        /// Image size of every scene (the default keeps the page of the shipped scenes under
        /// 50 MB).
        #[arg(long, value_name = "WxH", value_parser = parse_size, default_value = "256x256")]
        size: (u32, u32),
        /// Interpolation of the varyings, overriding the scenes'.
        #[arg(long, value_enum)]
        interpolation: Option<InterpArg>,
        /// Bench's long setting (40 timed draws after 3 warm-ups; stress refined 8 rounds)
        /// instead of the short one (10 after 2; 2 rounds), and the static cost's disassembly
        /// and isolated kernels (DIR/isa/asm/: tens of MB).
        #[arg(long)]
        full: bool,
        /// The tune.json of `shadelab tune`: its winners show in the answer's cells ("a tuned
        /// approximation beats exact normalisation here") and in its words (copied to
        /// DIR/tune/tune.json).
        #[arg(long, value_name = "FILE.json")]
        tuned: Option<PathBuf>,
        #[command(flatten)]
        device: DeviceArgs,
        #[command(flatten)]
        store: StoreArgs,
    },
    /// Compare every mesh file of a corpus, or one shard K/N of it (CI matrix, Slurm job
    /// array): per-mesh results, a manifest, the static GPU cost once (docs/corpus.md).
    Corpus(self::corpus::CorpusArgs),
    /// Check the shards of a corpus (union, disjoint, same configuration) and write the corpus
    /// tables: error over meshes per method, worst meshes, the answer per budget.
    Merge(self::merge::MergeArgs),
    /// The compile store of the GPU families' static cost: its folder, entries and size;
    /// checks (--verify) and prunes (--prune, --max-size) it (docs/isa.md "Compile store").
    Cache(self::cache::CacheArgs),
    /// List the Vulkan devices the loader reports.
    Devices,
    /// Internal: one job of a parent shadelab process (src/child.rs), from its request file.
    #[command(hide = true)]
    Child {
        #[arg(value_name = "REQUEST.json")]
        request: PathBuf,
    },
}

// `shadelab bench` (its help is the variant's doc comment).
#[derive(Args, Debug)]
struct BenchCmd {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = checks::method_list)]
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
    error_budget: BudgetArgs,
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

/// Parses the command line and runs it. Errors are printed once by the caller.
pub fn run() -> Result<ExitCode> {
    let cli = Cli::parse();
    cli.verbosity.init(&cli.command);
    self::checks::before_running(&cli)?;
    if let Some(store) = cli.command.store_args() {
        store.apply();
    }
    match cli.command {
        Command::Compare {
            scene,
            device,
            methods,
            out,
            fail_above,
            fail_below,
            scale,
            threshold,
            error_budget,
            precision,
        } => {
            let limits = self::compare::Limits {
                above: &fail_above,
                below: &fail_below,
                precision,
            };
            cmd_compare(
                &scene,
                &device,
                &methods,
                &out,
                &limits,
                scale.into(),
                threshold,
                &error_budget,
            )
        }
        Command::Render {
            scene,
            device,
            method,
            out,
            float,
            normals,
            error_budget,
            precision,
        } => cmd_render(
            &scene,
            &(device, precision),
            &method,
            &out,
            float.as_deref(),
            normals.as_deref(),
            &error_budget,
        ),
        Command::Verify {
            scene,
            device,
            methods,
            against,
            precision,
        } => cmd_verify(&scene, &device, &methods, against.as_deref(), precision),
        Command::Bench(b) => cmd_bench(b),
        Command::Stress {
            device,
            methods,
            out,
            replay,
            threshold,
            refine,
            precision,
        } => {
            let opts = crate::stress::StressOptions {
                threshold,
                refine_rounds: refine,
                progress: true,
                precision: precision.precision,
            };
            cmd_stress(&device, &methods, out.as_deref(), replay.as_deref(), &opts)
        }
        Command::Plan {
            scene,
            device,
            json,
            error_budget,
        } => cmd_plan(&scene, &device, json, error_budget),
        Command::Skips(k) => cmd_skips(k),
        Command::Isa(args) => self::isa::cmd_isa(args),
        Command::Child { request } => self::child::cmd_child(&request),
        Command::Prove(a) => cmd_prove(&a),
        Command::Tune(a) => self::tune::cmd_tune(&a),
        Command::List { json } => cmd_list(json),
        Command::Mesh {
            generator,
            params,
            out,
            shipped,
        } => cmd_mesh(generator, &params, out, shipped),
        Command::Shaders { check, glsl, spirv } => cmd_shaders(check, &glsl, &spirv),
        Command::Demo {
            scenes,
            out,
            device,
            ..
        } => cmd_demo(&scenes, &out, &device),
        c @ Command::Report { .. } => report::run_report(c),
        Command::Corpus(a) => self::corpus::cmd_corpus(a),
        Command::Merge(a) => self::merge::cmd_merge(a),
        Command::Cache(a) => self::cache::cmd_cache(&a),
        Command::Devices => {
            for d in Context::list_devices()? {
                println!("{d}");
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

impl Command {
    /// The `--no-cache` of a command that compiles for GPU families.
    fn store_args(&self) -> Option<&StoreArgs> {
        match self {
            Command::Render { error_budget, .. } | Command::Compare { error_budget, .. } => {
                Some(&error_budget.store)
            }
            Command::Bench(b) => Some(&b.error_budget.store),
            Command::Isa(a) => Some(&a.store),
            Command::Tune(a) => Some(&a.store),
            Command::Corpus(a) => Some(&a.store),
            Command::Demo { store, .. } | Command::Report { store, .. } => Some(store),
            _ => None,
        }
    }
}

impl SceneArgs {
    /// The scene's source as data (what a child process is given).
    fn source(&self) -> scene::SceneSource {
        scene::SceneSource {
            scene: self.scene.clone(),
            mesh: self.mesh.clone(),
            size: self.size,
            interpolation: self.interpolation.map(|i| match i {
                InterpArg::ScreenLinear => Interpolation::ScreenLinear,
                InterpArg::Perspective => Interpolation::Perspective,
            }),
            cull: self.cull.map(|c| match c {
                CullArg::Auto => scene::Cull::Auto,
                CullArg::Back => scene::Cull::Back,
                CullArg::None => scene::Cull::None,
            }),
        }
    }
}

fn load_scene(args: &SceneArgs) -> Result<Scene> {
    let scene = args.source().load()?;
    scene.log_mesh_notes();
    Ok(scene)
}

fn renderer(args: &DeviceArgs) -> Result<Renderer> {
    // render, verify, compare and bench take their software path before asking for a
    // renderer: a command that reaches here with --engine software would silently use Vulkan.
    if args.engine == EngineArg::Software {
        return Err(Error::Usage(
            "--engine software is for render, verify, compare and bench; this command runs on \
             the Vulkan pipeline only: leave --engine out"
                .into(),
        ));
    }
    vulkan_renderer(args)
}

/// The Vulkan renderer whatever `--engine` says: for a software bench's lavapipe column
/// (`--vulkan-paired`), which draws on both.
fn vulkan_renderer(args: &DeviceArgs) -> Result<Renderer> {
    let ctx = Context::new(&ContextDesc {
        device: args.device.clone(),
        validate: args.validate,
    })?;
    Ok(Renderer::new(ctx))
}

/// With `--validate`, any collected message is an error (exit 2), printed in full.
fn check_validation(ctx: &Arc<Context>) -> Result<()> {
    let msgs = ctx.validation_messages();
    if msgs.is_empty() {
        return Ok(());
    }
    for m in &msgs {
        eprintln!("validation: {m}");
    }
    Err(Error::Device(format!(
        "the validation layer reported {} message(s) (printed above)",
        msgs.len()
    )))
}

/// `auto` at the budget, its candidates ordered by the cost model: lavapipe's isolated cost
/// measured now on the run's device, or a GPU family's static cost compiled now.
fn auto_spec(r: &Renderer, b: &BudgetArgs) -> Result<crate::auto::AutoSpec> {
    let t = std::time::Instant::now();
    let ev = crate::cost::Evidence::new().with(r.context().clone());
    let (order, model) = crate::auto::order_by_model(&crate::costs::builtin(), &b.cost_model, &ev)?;
    log::info!(
        "auto: candidates by {} in {} (measured in {:.1} s): {}",
        model.id,
        model.measure.unit,
        t.elapsed().as_secs_f64(),
        crate::auto::order_line(&order)
    );
    let mut spec = crate::auto::AutoSpec::new(b.budget, &order);
    spec.cost_model = model.id;
    Ok(spec)
}
