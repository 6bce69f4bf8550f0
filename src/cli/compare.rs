//! `shadelab compare`: every method against the f64 exact-Phong truth.
use std::process::ExitCode;

use super::*;
use crate::compare::{self, Bound};
use crate::error::{Error, Result};

// `shadelab compare` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct CompareArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
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
    pub(super) error_budget: BudgetArgs,
    #[command(flatten)]
    precision: PrecisionArgs,
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

impl CompareArgs {
    /// What compare reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            marker: Some("summary.json"),
            dir: Some(("--out", &self.out)),
            inputs: self.scene.files(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_compare(a: &CompareArgs) -> Result<ExitCode> {
    let CompareArgs {
        scene: scene_args,
        device: dev,
        methods: list,
        out,
        fail_above,
        fail_below,
        scale,
        threshold,
        error_budget: budget,
        precision: limits_precision,
    } = a;
    let (out, scale, threshold) = (out.as_path(), compare::ScaleMode::from(*scale), *threshold);
    limits_precision.check_engine(dev)?;
    let limits = fail_above
        .iter()
        .map(|s| compare::parse_limit(s, Bound::Above))
        .chain(
            fail_below
                .iter()
                .map(|s| compare::parse_limit(s, Bound::Below)),
        )
        .collect::<Result<Vec<_>>>()?;
    let (list, with_auto) = crate::auto::split_methods(list);
    if with_auto && limits_precision.precision != crate::method::Precision::F32 {
        return Err(Error::Usage(
            "auto chooses among float32 programs: leave it out of --methods with --precision f16"
                .into(),
        ));
    }
    let methods = select_methods(&list)?;
    let scene = load_scene(scene_args)?;
    let mut opts = compare::CompareOptions {
        scale,
        threshold,
        progress: true,
        images: true,
        auto: Vec::new(),
    };
    let r = if dev.engine == EngineArg::Software {
        if with_auto {
            return Err(Error::Usage(
                "auto is drawn by the Vulkan pipeline only: leave it out of --methods with \
                 --engine software"
                    .into(),
            ));
        }
        None
    } else {
        Some(limits_precision.renderer(dev)?)
    };
    let engine = match &r {
        Some(r) => {
            if with_auto {
                opts.auto = vec![auto_spec(r, budget)?];
            }
            crate::engine::Engine::Vulkan(r)
        }
        None => crate::engine::Engine::Software {
            threads: crate::software::default_threads(),
        },
    };
    let summary = compare::compare_with(engine, &scene, &methods, out, &opts)?;
    print!("{}", compare::table(&summary));
    log::info!(
        "wrote {} ({} engine, {} methods, {:.1} s; metrics {:.0} Mpixel/s, FLIP {:.1} Mpixel/s)",
        out.join("summary.json").display(),
        summary.engine,
        summary.methods.len(),
        summary.timing.total_ms / 1e3,
        summary.timing.metric_pixels_per_second / 1e6,
        summary.timing.flip_pixels_per_second / 1e6
    );
    if let Some(r) = &r {
        check_validation(r.context())?;
    }
    let over = compare::exceeded(&summary, &limits);
    let auto_broken = auto_non_finite(&summary);
    if over.is_empty() && auto_broken.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    for e in &over {
        eprintln!("threshold exceeded: {e}");
    }
    for line in &auto_broken {
        eprintln!("threshold exceeded: {line}");
    }
    Ok(ExitCode::from(EXIT_THRESHOLD))
}

/// `auto` promises its budget: a non-finite pixel of it (a form drawn where its rasterizer
/// weights leave the triangle, the sliver pixels of docs/tune.md) fails the run, exit 1, with
/// or without a limit.
pub(super) fn auto_non_finite(summary: &compare::Summary) -> Vec<String> {
    let autos: Vec<&str> = summary
        .auto
        .iter()
        .chain(&summary.auto_curve)
        .map(|a| a.name.as_str())
        .collect();
    summary
        .methods
        .iter()
        .filter(|m| autos.contains(&m.name.as_str()) && m.non_finite_pixels > 0)
        .map(|m| non_finite_line(&m.name, m.non_finite_pixels))
        .collect()
}

/// The line of an `auto` frame with `n` non-finite pixels.
pub(super) fn non_finite_line(name: &str, n: usize) -> String {
    format!(
        "{name}: {n} non-finite pixel(s): auto keeps its budget only where its pixels are \
         finite (a form drawn at pixels whose rasterizer weights leave their triangle, \
         docs/tune.md; another --size usually has none)"
    )
}
