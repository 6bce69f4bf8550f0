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
    let r = renderer(dev)?;
    let prepared = r.prepare(&scene, &[method])?;
    let (frame, _) = r.render(prepared.for_method(method), Shading::Method(method), false)?;
    output::write_png_srgb(out, frame.width, frame.height, &frame.color)?;
    if let Some(f) = float {
        output::write_npy_rgba(f, frame.width, frame.height, &frame.color)?;
    }
    if let Some(n) = normals {
        output::write_npy_rgba(n, frame.width, frame.height, &frame.normal)?;
    }
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}
