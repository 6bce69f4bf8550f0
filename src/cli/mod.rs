//! The command line: argument parsing (clap) and one function per command. `main.rs` only calls
//! [`run`] and maps its result to an exit code.
mod bench;
mod cache;
mod checks;
mod child;
mod compare;
mod corpus;
mod demo;
mod explore;
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
use self::skips::cmd_skips;
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

#[derive(ValueEnum, Debug, Clone, Copy)]
enum InterpArg {
    ScreenLinear,
    Perspective,
}

#[allow(clippy::large_enum_variant)] // parsed once per process: its size costs nothing
#[derive(Subcommand, Debug)]
enum Command {
    /// Render one method to an 8-bit PNG (and optionally the float images as .npy).
    Render(self::render::RenderArgs),
    /// Check GPU methods against their own formula evaluated in f64 at the rasterizer's weights.
    Verify(self::verify::VerifyArgs),
    /// Compare methods against the f64 exact-Phong truth: statistics, heatmaps, JSON/CSV.
    Compare(self::compare::CompareArgs),
    /// Run time against error: validated timing, Pareto chart, the papers' claims, sweeps.
    Bench(self::bench::BenchCmd),
    /// Sweep each method over its input domain (angle, elevation, light, shininess, span,
    /// length, shape) on the device and in f64; worst cases, validity maps, the validity claims.
    Stress(self::stress::StressArgs),
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
    Skips(self::skips::SkipsCmd),
    /// What a scene needs: topology (culling), the spread of its vertex normals against each
    /// method's measured validity range, triangle sizes and facing, lighting, what is skipped.
    Plan(self::plan::PlanArgs),
    /// What each method compiles to on the GPU families of every vendor set up (each vendor's
    /// compiler behind a null device or Mesa's drm-shims: statistics, disassembly; no GPU).
    Isa(self::isa::IsaArgs),
    /// List the methods (`--json` for machines).
    List(self::list::ListArgs),
    /// Generate a procedural mesh as OBJ, or regenerate the shipped meshes of scenes/.
    Mesh(self::mesh::MeshArgs),
    /// Compile glsl/ into spirv/ with shaderc (`--check`: only verify spirv/ is fresh).
    Shaders(self::shaders::ShadersArgs),
    /// The quick start's report: `report --scenes scenes --out out/report` (what `make demo`
    /// runs), from a checkout of the repository.
    Demo(self::demo::DemoArgs),
    /// The main job: compare, bench and stress on the given scenes, written as one offline
    /// HTML report (OUT/index.html, its path printed on stdout).
    Report(self::report::ReportArgs),
    /// Compare every mesh file of a corpus, or one shard K/N of it (CI matrix, Slurm job
    /// array): per-mesh results, a manifest, the static GPU cost once (docs/corpus.md).
    Corpus(self::corpus::CorpusArgs),
    /// Check the shards of a corpus (union, disjoint, same configuration) and write the corpus
    /// tables: error over meshes per method, worst meshes, the answer per budget.
    Merge(self::merge::MergeArgs),
    /// The compile store of the GPU families' static cost: its folder, entries and size;
    /// checks (--verify) and prunes (--prune, --max-size) it (docs/isa.md "Compile store").
    Cache(self::cache::CacheArgs),
    /// A local page where a method is picked or edited and its error map and its cost on every
    /// GPU family follow while you type (docs/explore.md); prints its URL, serves until Ctrl-C.
    Explore(self::explore::ExploreArgs),
    /// List the Vulkan devices the loader reports.
    Devices,
    /// Internal: one job of a parent shadelab process (src/child.rs), from its request file.
    #[command(hide = true)]
    Child(self::child::ChildArgs),
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
        Command::Render(a) => cmd_render(&a),
        Command::Verify(a) => cmd_verify(&a),
        Command::Compare(a) => cmd_compare(&a),
        Command::Bench(b) => cmd_bench(b),
        Command::Stress(a) => cmd_stress(&a),
        Command::Prove(a) => cmd_prove(&a),
        Command::Tune(a) => self::tune::cmd_tune(&a),
        Command::Skips(k) => cmd_skips(k),
        Command::Plan(a) => cmd_plan(&a),
        Command::Isa(args) => self::isa::cmd_isa(args),
        Command::List(a) => cmd_list(a.json),
        Command::Mesh(a) => cmd_mesh(a),
        Command::Shaders(a) => cmd_shaders(&a),
        Command::Demo(a) => cmd_demo(&a),
        Command::Report(a) => report::run_report(a),
        Command::Corpus(a) => self::corpus::cmd_corpus(a),
        Command::Merge(a) => self::merge::cmd_merge(a),
        Command::Cache(a) => self::cache::cmd_cache(&a),
        Command::Explore(a) => self::explore::cmd_explore(&a),
        Command::Devices => {
            for d in Context::list_devices()? {
                println!("{d}");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Child(a) => self::child::cmd(&a),
    }
}

impl Command {
    /// The `--no-cache` of a command that compiles for GPU families.
    fn store_args(&self) -> Option<&StoreArgs> {
        match self {
            Command::Render(a) => Some(&a.error_budget.store),
            Command::Compare(a) => Some(&a.error_budget.store),
            Command::Bench(b) => Some(&b.error_budget.store),
            Command::Isa(a) => Some(&a.store),
            Command::Tune(a) => Some(&a.store),
            Command::Corpus(a) => Some(&a.store),
            Command::Demo(a) => Some(&a.store),
            Command::Report(a) => Some(&a.store),
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

impl SceneArgs {
    /// The scene or mesh file it names (an input of the command).
    fn files(&self) -> Vec<&std::path::Path> {
        self.scene
            .iter()
            .chain(self.mesh.iter())
            .map(PathBuf::as_path)
            .collect()
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
