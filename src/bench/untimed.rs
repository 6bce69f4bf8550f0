//! What the timing leaves out: each program's fragment invocations and the error metrics of
//! its row (compare's, or the scene's compare the caller already made).
use std::path::Path;

use super::{BenchOptions, Program, What};
use crate::compare::{self, CompareOptions};
use crate::error::Result;
use crate::gpu::Renderer;
use crate::method::Method;
use crate::scene::Scene;

/// What the timing leaves out: every program's fragment invocations (untimed, one
/// submission each) and compare's error metrics.
pub(super) fn untimed(
    renderer: &Renderer,
    scene: &Scene,
    all: &[&'static Method],
    out: &Path,
    opts: &BenchOptions,
    programs: &[Program],
) -> Result<(Vec<Option<u64>>, compare::Summary)> {
    log::info!("bench: fragment invocations (untimed, one submission per program)");
    let invocations = programs
        .iter()
        .map(|p| renderer.fragment_invocations_list(&p.list()))
        .collect::<Result<Vec<_>>>()?;
    let judged: Vec<&str> = programs
        .iter()
        .filter(|p| !matches!(p.what, What::Floor))
        .map(|p| p.method().map_or(p.name.as_str(), |m| m.name))
        .collect();
    if let Some(summary) = opts
        .compared
        .as_ref()
        .filter(|s| compared_covers(s, renderer.precision(), scene, &judged))
    {
        log::info!("bench: error metrics from the scene's compare");
        // The statistics alone: its images are the compare's, in the compare's folder.
        let mut summary = summary.clone();
        for row in &mut summary.methods {
            row.files.clear();
        }
        return Ok((invocations, summary));
    }
    log::info!("bench: error metrics (compare, without images)");
    let copts = CompareOptions {
        images: false,
        auto: opts.auto.clone(),
        ..CompareOptions::default()
    };
    let summary = compare::compare(renderer, scene, all, out, &copts)?;
    Ok((invocations, summary))
}

/// Whether `summary` is the compare of `scene` at its size, drawn by Vulkan in `precision`,
/// with a row for every name in `judged` (the methods and `auto` rows whose error a timing row
/// shows; the timing floors have none).
pub(crate) fn compared_covers(
    summary: &compare::Summary,
    precision: crate::method::Precision,
    scene: &Scene,
    judged: &[&str],
) -> bool {
    summary.engine == crate::engine::EngineKind::Vulkan
        && summary.precision == precision
        && (summary.width, summary.height) == (scene.width, scene.height)
        && (&summary.scene, &summary.scene_source) == (&scene.name, &scene.mesh.source)
        && judged
            .iter()
            .all(|&name| summary.methods.iter().any(|r| r.name == name))
}
