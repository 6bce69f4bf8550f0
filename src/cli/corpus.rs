//! `shadelab corpus`: one shard of a mesh corpus (see [`crate::corpus`]); `shadelab merge`
//! lives in merge.rs beside it.
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::corpus::{self, run::ShardOptions, Config, Shard};
use crate::error::{Error, Result};
use crate::method::Precision;

#[derive(Args, Debug)]
pub(super) struct CorpusArgs {
    /// Folder of the corpus: every mesh file under it (.obj, .gltf, .glb, .ply; recursive;
    /// hidden entries skipped).
    #[arg(
        value_name = "DIR",
        required_unless_present = "list",
        conflicts_with = "list"
    )]
    dir: Option<PathBuf>,
    /// A list file instead: one mesh file path a line, relative to the list file's folder.
    #[arg(long, value_name = "FILE")]
    list: Option<PathBuf>,
    /// Output folder of this shard (manifest.json, meshes/<id>/, isa/).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// This shard, K of N, 1-based (a mesh is in shard hash(id) mod N + 1). Default: from
    /// CI_NODE_INDEX/CI_NODE_TOTAL (GitLab parallel), else SLURM_ARRAY_TASK_ID (counted from
    /// SLURM_ARRAY_TASK_MIN) / SLURM_ARRAY_TASK_COUNT, else the whole corpus.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Image size of every mesh (camera fitted to each, as compare --mesh).
    #[arg(long, value_name = "WxH", value_parser = super::parse_size, default_value = "256x256")]
    size: (u32, u32),
    /// Floating-point precision of the programs (recorded in the configuration; f16 is refused:
    /// the corpus's per-mesh compare draws the float32 programs only, for now).
    #[arg(long, default_value = "f32", value_parser = super::parse_precision())]
    precision: Precision,
    /// Linear luminance error above which a pixel counts in pixels_above_threshold.
    #[arg(long, default_value_t = 1.0 / 255.0, value_parser = super::parse_threshold)]
    threshold: f64,
    /// Also time every mesh: `shadelab bench --runs N` (replicated, fresh processes).
    #[arg(long)]
    bench: bool,
    /// Runs of --bench.
    #[arg(long, value_name = "N", default_value_t = 5, requires = "bench", value_parser = super::count::<1, 100>)]
    runs: usize,
    /// Also write compare's images per mesh (render.png, heatmaps).
    #[arg(long)]
    images: bool,
    /// Skip the static GPU cost (isa, run once by shard 1 when the RADV ICD is present).
    #[arg(long)]
    no_isa: bool,
    #[command(flatten)]
    device: super::DeviceArgs,
    #[command(flatten)]
    pub(super) store: super::StoreArgs,
}

impl CorpusArgs {
    /// What a shard reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("manifest.json"),
            inputs: self.list.iter().map(PathBuf::as_path).collect(),
            input_dirs: self
                .dir
                .iter()
                .map(PathBuf::as_path)
                .chain(self.list.as_deref().and_then(std::path::Path::parent))
                .collect(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_corpus(a: CorpusArgs) -> Result<ExitCode> {
    if a.precision == Precision::F16 {
        return Err(Error::Usage(
            "corpus --precision f16: the corpus's per-mesh compare draws float32 programs only; \
             run `compare --precision f16 --mesh FILE` per mesh"
                .into(),
        ));
    }
    if a.size.0 == 0 || a.size.1 == 0 {
        return Err(Error::Usage(
            "corpus --size: width and height must be > 0".into(),
        ));
    }
    let (meshes, source) = match (&a.dir, &a.list) {
        (Some(d), _) => (corpus::list_dir(d, Some(&a.out))?, d.display().to_string()),
        (None, Some(l)) => (corpus::list_file(l)?, l.display().to_string()),
        (None, None) => return Err(Error::Usage("corpus: give DIR or --list FILE".into())),
    };
    let env = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    let shard = Shard::resolve(a.shard.as_deref(), &env)?;
    let methods = super::select_methods(&a.methods)?;
    let mine = meshes.iter().filter(|m| shard.holds(&m.id)).count();
    log::info!(
        "corpus: shard {}/{} (from {}): {mine} of {} meshes -> {}",
        shard.k,
        shard.n,
        shard.source,
        meshes.len(),
        a.out.display()
    );
    let config = Config {
        version: env!("CARGO_PKG_VERSION").into(),
        compare_schema_version: crate::compare::SCHEMA_VERSION,
        methods: methods.iter().map(|m| m.name.to_string()).collect(),
        width: a.size.0,
        height: a.size.1,
        precision: a.precision,
        threshold: a.threshold,
        bench_runs: a.bench.then_some(a.runs),
        images: a.images,
    };
    let r = super::renderer(&a.device)?;
    let exe = std::env::current_exe().map_err(|e| Error::io("current executable", e))?;
    let opts = ShardOptions {
        meshes: &meshes,
        source,
        out: a.out.clone(),
        shard,
        methods,
        config,
        isa: !a.no_isa,
        exe,
    };
    let m = corpus::run::run_shard(&r, &opts)?;
    super::check_validation(r.context())?;
    println!("{}", a.out.join("manifest.json").display());
    log::info!(
        "corpus: shard {}/{} done: {} meshes, {} failed, static cost: {} ({:.1} s)",
        m.shard.k,
        m.shard.n,
        m.meshes.len(),
        m.failed,
        m.isa,
        m.elapsed_s
    );
    Ok(if m.failed > 0 {
        ExitCode::from(super::EXIT_THRESHOLD)
    } else {
        ExitCode::SUCCESS
    })
}
