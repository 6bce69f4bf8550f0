//! `shadelab compare`: every method against the f64 exact-Phong truth.
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};
pub(super) fn cmd_compare(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
    fail_above: &[String],
    scale: crate::compare::ScaleMode,
    threshold: f64,
) -> Result<ExitCode> {
    use crate::compare;
    let limits = fail_above
        .iter()
        .map(|s| compare::parse_limit(s))
        .collect::<Result<Vec<_>>>()?;
    if !(threshold.is_finite() && threshold >= 0.0) {
        return Err(Error::Usage(format!(
            "--threshold must be a finite number >= 0, got {threshold}"
        )));
    }
    let methods = select_methods(list)?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let opts = compare::CompareOptions {
        scale,
        threshold,
        progress: true,
        images: true,
    };
    let summary = compare::compare(&r, &scene, &methods, out, &opts)?;
    print!("{}", compare::table(&summary));
    eprintln!(
        "wrote {} ({} methods, {:.1} s; metrics {:.0} Mpixel/s, FLIP {:.1} Mpixel/s)",
        out.join("summary.json").display(),
        summary.methods.len(),
        summary.timing.total_ms / 1e3,
        summary.timing.metric_pixels_per_second / 1e6,
        summary.timing.flip_pixels_per_second / 1e6
    );
    check_validation(r.context())?;
    let over = compare::exceeded(&summary, &limits);
    if over.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    for (m, k, v, limit) in &over {
        eprintln!("threshold exceeded: {m} {k} = {v:.6e} > {limit:e}");
    }
    Ok(ExitCode::from(EXIT_THRESHOLD))
}
