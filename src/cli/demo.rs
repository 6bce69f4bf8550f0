//! `shadelab demo`: every scene of a folder drawn with phong_exact, one PNG each (a quick check
//! that the device draws; the report of `make demo` is `shadelab report`).
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use super::*;
use crate::error::Result;
use crate::gpu::Shading;
use crate::method::{self};
use crate::output;
use crate::scene::{self};
pub(super) fn cmd_demo(scenes_dir: &Path, out: &Path, dev: &DeviceArgs) -> Result<ExitCode> {
    let files = super::report::scene_files(scenes_dir)?;
    let r = renderer(dev)?;
    let method = method::phong_exact();
    for (i, f) in files.iter().enumerate() {
        let start = Instant::now();
        let scene = scene::load_scene(f)?;
        let prepared = r.prepare(&scene, &[method])?;
        let gpu = prepared.base();
        let (frame, _) = r.render(gpu, Shading::Method(method), false)?;
        let stem = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let png = out.join(format!("{stem}.png"));
        output::write_png_srgb(&png, frame.width, frame.height, &frame.color)?;
        eprintln!(
            "[{}/{}] {} -> {} ({}x{}, {} triangles, {:.0} ms)",
            i + 1,
            files.len(),
            f.display(),
            png.display(),
            frame.width,
            frame.height,
            gpu.inputs.triangle_count(),
            start.elapsed().as_secs_f64() * 1e3
        );
    }
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}
