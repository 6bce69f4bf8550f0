//! Sweeps: frame time against image size or triangle count, with a least-squares slope. Each
//! point times its three programs in [`SWEEP_MIN_REPEAT`]..[`SWEEP_MAX_REPEAT`] interleaved
//! rounds and records the exact coverage of its interval.
use super::*;
use crate::analysis::stats::{least_squares, median_ci};

use crate::error::Result;
use crate::geometry::Generator;
use crate::gpu::{Renderer, Shading};
use crate::method::{self};
use crate::scene::Scene;
pub(crate) fn sweep(
    renderer: &Renderer,
    scene: &Scene,
    which: Sweep,
    opts: &BenchOptions,
) -> Result<SweepResult> {
    let exact = method::phong_exact();
    let gouraud = method::vertex_lit_reference();
    let shadings = [
        Shading::Constant,
        Shading::Method(gouraud),
        Shading::Method(exact),
    ];
    let max = renderer.context().info().max_image_dimension_2d;
    let scenes: Vec<Scene> = match which {
        Sweep::Size => SIZES
            .iter()
            .filter(|&&s| s <= max)
            .map(|&s| {
                let mut c = scene.clone();
                c.width = s;
                c.height = s;
                c
            })
            .collect(),
        Sweep::Triangles => SPHERES
            .iter()
            .map(|&(segments, rings)| {
                let mut mesh = Generator::UvSphere { segments, rings }.build()?;
                crate::geometry::fit_unit(&mut mesh);
                let mut c = scene.clone();
                c.mesh = mesh;
                Ok(c)
            })
            .collect::<Result<_>>()?,
    };
    let mut points = Vec::new();
    // At least 20 draws: from 5, a "95 %" interval is [min, max] and covers 93.75 %.
    let reps = (opts.schedule.rounds.repeat).clamp(SWEEP_MIN_REPEAT, SWEEP_MAX_REPEAT);
    for s in &scenes {
        let prepared = renderer.prepare(s, &[gouraud, exact])?;
        let pairs: Vec<_> = shadings.iter().map(|s| (prepared.base(), *s)).collect();
        let draws = renderer.timed_draws(&pairs)?;
        let samples = interleaved(&draws, opts.schedule.rounds.warmup.max(1), reps)?;
        for (sh, smp) in shadings.iter().zip(&samples) {
            let (frame, _) = renderer.render(prepared.base(), *sh, false)?;
            let wall: Vec<f64> = smp.iter().map(|x| x.wall_ms).collect();
            let e = median_ci(&wall);
            let tris = prepared.base().inputs.triangle_count();
            points.push(SweepPoint {
                program: sh.name(),
                work: match which {
                    Sweep::Size => frame.covered() as f64,
                    Sweep::Triangles => tris as f64,
                },
                width: s.width,
                height: s.height,
                triangles: tris,
                covered_pixels: frame.covered(),
                median_ms: e.median,
                ci95_low_ms: e.ci95_low,
                ci95_high_ms: e.ci95_high,
                samples: e.samples,
                ci_confidence: e.confidence,
            });
        }
        log::info!(
            "bench: sweep point {}x{}, {} triangles",
            s.width,
            s.height,
            prepared.base().inputs.triangle_count()
        );
    }
    let mut slopes = Vec::new();
    for sh in &shadings {
        let name = sh.name();
        let pts: Vec<&SweepPoint> = points.iter().filter(|p| p.program == name).collect();
        let xs: Vec<f64> = pts.iter().map(|p| p.work / 1e6).collect();
        let ys: Vec<f64> = pts.iter().map(|p| p.median_ms).collect();
        let lx: Vec<f64> = pts.iter().map(|p| p.work.max(1.0).ln()).collect();
        let ly: Vec<f64> = pts.iter().map(|p| p.median_ms.max(1e-9).ln()).collect();
        slopes.push((name, least_squares(&xs, &ys), least_squares(&lx, &ly)));
    }
    Ok(SweepResult {
        sweep: which,
        work: match which {
            Sweep::Size => "covered pixels".into(),
            Sweep::Triangles => "triangles".into(),
        },
        points,
        slopes,
    })
}
