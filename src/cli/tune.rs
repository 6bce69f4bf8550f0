//! `shadelab tune`: runs [`crate::tune::run`] on each source, prints its table and writes
//! tune.json, tune.txt and the candidates' method files.
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::cost::{CostModelId, Evidence};
use crate::error::Result;
use crate::tune::{self, Source, TuneOptions};

/// `--domain` of `tune --max-angle`.
#[derive(ValueEnum, Debug, Clone, Copy)]
enum DomainArg {
    Triangle,
    Edge,
}

/// The arguments of `shadelab tune`.
#[derive(Debug, Args)]
#[command(group(ArgGroup::new("source").required(true).args(["mesh", "scene", "models", "max_angle"])))]
pub struct TuneArgs {
    /// One mesh file, .obj, .gltf, .glb or .ply (camera fitted, default light and material,
    /// 512x512).
    #[arg(long, value_name = "FILE")]
    mesh: Option<PathBuf>,
    /// One scene file (TOML): its mesh, lights, material and render size.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Every mesh file (.obj, .gltf, .glb, .ply) of DIR, one run each, written to
    /// OUT/<name>/.
    #[arg(long, value_name = "DIR")]
    models: Option<PathBuf>,
    /// No mesh: every triangle whose vertex normals are pairwise at most DEG apart (prove's
    /// triangle domain; `--domain edge` for its edge domain), the default light and material.
    #[arg(long, value_name = "DEG")]
    max_angle: Option<f64>,
    /// With --max-angle: the domain of `prove` (triangle: any triangle; edge: N2 the bisector
    /// of N0 and N1, stress's cases).
    #[arg(long, value_enum, default_value = "triangle", requires = "max_angle")]
    domain: DomainArg,
    /// Render size of the pixels' distribution, overriding the scene's.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// The colour error budget (linear, max over the channels): a number or a fraction like
    /// 1/255 (default 1/255), as every command's --error-budget. A candidate is within it only
    /// by proof.
    #[arg(long = "error-budget", value_name = "E", value_parser = ErrorBudget::parse)]
    error_budget: Option<ErrorBudget>,
    /// The former name of --error-budget, still read (with a warning that it is deprecated).
    #[arg(long = "budget", value_name = "E", value_parser = ErrorBudget::parse, hide = true, conflicts_with = "error_budget")]
    budget: Option<ErrorBudget>,
    /// A cost model to measure (repeatable; default: every model measured on demand:
    /// lavapipe_isolated, isa:FAMILY and isa:FAMILY:f16 for each default family of every
    /// vendor, e.g. isa:amd:navi21, isa:intel:tgl:f16).
    #[arg(long = "cost-model", value_name = "MODEL", value_parser = CostModelId::parse)]
    cost_model: Vec<CostModelId>,
    /// Case-insensitive substring of the Vulkan device of lavapipe_isolated (default:
    /// lavapipe).
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Output directory (tune.json, tune.txt, methods/*.glsl; OUT/<name>/ per mesh of
    /// --models).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    #[command(flatten)]
    pub(super) store: super::StoreArgs,
}

/// The scenes of the arguments, each with its kind, path and output folder.
fn scenes(a: &TuneArgs) -> Result<Vec<(Scene, &'static str, PathBuf, PathBuf)>> {
    let load = |scene: Option<PathBuf>, mesh: Option<PathBuf>| {
        scene::SceneSource {
            scene,
            mesh,
            size: a.size,
            interpolation: None,
            cull: None,
        }
        .load()
    };
    if let Some(p) = &a.mesh {
        return Ok(vec![(
            load(None, Some(p.clone()))?,
            "mesh",
            p.clone(),
            a.out.clone(),
        )]);
    }
    if let Some(p) = &a.scene {
        return Ok(vec![(
            load(Some(p.clone()), None)?,
            "scene",
            p.clone(),
            a.out.clone(),
        )]);
    }
    let Some(dir) = &a.models else {
        return Ok(Vec::new());
    };
    let files = crate::geometry::mesh_files(dir, crate::geometry::Depth::Flat, None)?;
    files
        .into_iter()
        .map(|p| {
            let s = load(None, Some(p.clone()))?;
            let out = a.out.join(tune::prefix_of(&s.name));
            Ok((s, "mesh", p, out))
        })
        .collect()
}

impl TuneArgs {
    /// What tune reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("tune.json"),
            inputs: self
                .mesh
                .iter()
                .chain(&self.scene)
                .map(PathBuf::as_path)
                .collect(),
            input_dirs: self.models.iter().map(PathBuf::as_path).collect(),
            ..Default::default()
        }
    }

    /// `--error-budget`, or its former name `--budget` (deprecated: a warning says so), or the
    /// default 1/255.
    fn error_budget(&self) -> ErrorBudget {
        if self.budget.is_some() {
            log::warn!(
                "--budget is deprecated: use --error-budget (the same option, as every command \
                 that takes an error budget names it)"
            );
        }
        self.error_budget
            .or(self.budget)
            .unwrap_or(ErrorBudget::DEFAULT)
    }
}

pub(super) fn cmd_tune(a: &TuneArgs) -> Result<ExitCode> {
    let budget = a.error_budget();
    if let Some(deg) = a.max_angle {
        if !(deg > 0.0 && deg <= 180.0) {
            return Err(Error::Usage(format!(
                "--max-angle {deg}: expected degrees in (0, 180]"
            )));
        }
    }
    let opts = TuneOptions {
        budget,
        cost_models: a.cost_model.clone(),
        proof: tune::proof::ProofEffort::default(),
        threads: crate::software::default_threads(),
        progress: true,
    };
    let mut ev = Evidence::new();
    match Context::new(&ContextDesc {
        device: a.device.clone(),
        validate: false,
    }) {
        Ok(ctx) => ev.push(ctx),
        Err(e) => log::warn!("tune: no Vulkan device ({e}): lavapipe_isolated is left unmeasured"),
    }
    let registry = crate::costs::builtin();
    let run = |source: &Source, out: &Path| -> Result<()> {
        let report = tune::run(source, &opts, &registry, &ev, out)?;
        tune::write(out, &report)?;
        print!("{}", tune::table(&report));
        println!("wrote {}", out.join("tune.json").display());
        Ok(())
    };
    if let Some(deg) = a.max_angle {
        let domain = match a.domain {
            DomainArg::Triangle => crate::prove::Domain::Triangle,
            DomainArg::Edge => crate::prove::Domain::Edge,
        };
        run(
            &Source::Angle {
                max_angle_deg: deg,
                domain,
            },
            &a.out,
        )?;
    }
    for (scene, kind, path, out) in scenes(a)? {
        let source = Source::Scene {
            scene: &scene,
            kind,
            path: path.display().to_string(),
        };
        run(&source, &out)?;
    }
    Ok(ExitCode::SUCCESS)
}
