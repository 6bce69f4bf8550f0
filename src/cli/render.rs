//! `shadelab render`: one method, one scene, PNG (+ NPY).
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::gpu::Shading;
use crate::method::{self};
use crate::output;
pub(super) fn cmd_render(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    method: &str,
    out: &Path,
    float: Option<&Path>,
    normals: Option<&Path>,
) -> Result<ExitCode> {
    let method = method::find(method)?;
    let scene = load_scene(scene_args)?;
    if dev.engine == EngineArg::Software {
        let inputs = crate::scene::SceneInputs::new(&scene, method.geometry);
        let form = crate::software::form(method.name);
        eprintln!(
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
    let r = renderer(dev)?;
    let prepared = r.prepare(&scene, &[method])?;
    let (frame, _) = r.render(prepared.for_method(method), Shading::Method(method), false)?;
    write_frame(&frame, out, float, normals)?;
    check_validation(r.context())?;
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
