//! `shadelab render`: one method, one scene, PNG (+ NPY).
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::gpu::Shading;
use crate::method::{self};
use crate::output;

// `shadelab render` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct RenderArgs {
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
    pub(super) error_budget: BudgetArgs,
    #[command(flatten)]
    precision: PrecisionArgs,
}

impl RenderArgs {
    /// What render writes and reads ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            files: [
                ("--out", Some(&self.out)),
                ("--float", self.float.as_ref()),
                ("--normals", self.normals.as_ref()),
            ]
            .into_iter()
            .filter_map(|(f, p)| Some((f, p?.as_path())))
            .collect(),
            inputs: self.scene.files(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_render(a: &RenderArgs) -> Result<ExitCode> {
    let RenderArgs {
        scene: scene_args,
        device: dev,
        method,
        out,
        float,
        normals,
        error_budget,
        precision,
    } = a;
    let (out, float, normals) = (out.as_path(), float.as_deref(), normals.as_deref());
    precision.check_engine(dev)?;
    if method == "auto" {
        if precision.precision != crate::method::Precision::F32 {
            return Err(crate::error::Error::Usage(
                "--method auto chooses among float32 programs: leave out --precision f16".into(),
            ));
        }
        return render_auto(scene_args, dev, out, float, normals, error_budget);
    }
    let method = method::find(method)?;
    let scene = load_scene(scene_args)?;
    let files = [
        ("--out", Some(out)),
        ("--float", float),
        ("--normals", normals),
    ];
    super::checks::not_the_mesh(&files, &scene)?;
    if dev.engine == EngineArg::Software {
        let inputs = crate::scene::SceneInputs::new(&scene, method.geometry);
        let form = crate::software::form_of(method);
        log::info!(
            "software engine: {} in its {} ({})",
            method.name,
            if form.scanline {
                "scanline form"
            } else {
                "per-pixel form (no scanline form)"
            },
            form.form
        );
        let (frame, _) =
            crate::software::render(&inputs, method, crate::software::default_threads(), false)?;
        return write_frame(&frame, out, float, normals);
    }
    let r = precision.renderer(dev)?;
    let prepared = r.prepare(&scene, &[method])?;
    // The normal target only when its .npy is asked for.
    let (frame, _) = r.render_with(
        prepared.for_method(method),
        Shading::Method(method),
        false,
        normals.is_some(),
    )?;
    write_frame(&frame, out, float, normals)?;
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}

/// `render --method auto`: the per-triangle choice within `--error-budget`, drawn group by
/// group (Vulkan only).
fn render_auto(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    out: &Path,
    float: Option<&Path>,
    normals: Option<&Path>,
    budget: &super::BudgetArgs,
) -> Result<ExitCode> {
    if dev.engine == EngineArg::Software {
        return Err(crate::error::Error::Usage(
            "auto draws each group of triangles with its own Vulkan pipeline: use --engine vulkan"
                .into(),
        ));
    }
    let scene = load_scene(scene_args)?;
    let files = [
        ("--out", Some(out)),
        ("--float", float),
        ("--normals", normals),
    ];
    super::checks::not_the_mesh(&files, &scene)?;
    let r = renderer(dev)?;
    let spec = auto_spec(&r, budget)?;
    let inputs = crate::scene::SceneInputs::new(&scene, crate::method::Geometry::Mesh);
    let (_, summary, a) = crate::auto::frame::choose_checked(
        &r,
        &scene,
        &inputs,
        &spec,
        crate::auto::Cache::Use,
        None,
    )?;
    log::info!("{}", summary.line());
    let frame = r.render_auto(&a)?;
    write_frame(&frame, out, float, normals)?;
    check_validation(r.context())?;
    // non-finite pixels fail auto's promise (the PNG shows them as black)
    let bad = frame
        .color
        .iter()
        .filter(|c| c.iter().any(|v| !v.is_finite()))
        .count();
    if bad > 0 {
        eprintln!(
            "threshold exceeded: {}",
            super::compare::non_finite_line("auto", bad)
        );
        return Ok(ExitCode::from(EXIT_THRESHOLD));
    }
    Ok(ExitCode::SUCCESS)
}

fn write_frame(
    frame: &crate::frame::Frame,
    out: &Path,
    float: Option<&Path>,
    normals: Option<&Path>,
) -> Result<ExitCode> {
    output::write_png_srgb(out, frame.width, frame.height, &frame.color)?;
    if let Some(f) = float {
        output::write_npy_rgba(f, frame.width, frame.height, &frame.color)?;
    }
    if let Some(n) = normals {
        output::write_npy_rgba(n, frame.width, frame.height, &frame.normal)?;
    }
    Ok(ExitCode::SUCCESS)
}
