//! `shadelab bench`: run time against error. Timing on lavapipe with a validated clock,
//! interleaved repetitions, medians with distribution-free 95% confidence intervals, the error
//! metrics of `compare`, static operation counts of each fragment shader, a Pareto chart, the
//! papers' claims checked, and sweeps over image size and triangle count.
//!
//! Clock: Vulkan timestamps placed as TOOLCHAIN.md found to track the draw on Mesa 22.3 (see
//! `Renderer::timed_draws`). Every run re-checks the placement: at sizes 128..2048 the
//! timestamp interval must track the submit-to-fence wall clock ([`CLOCK_TOLERANCE`]); when it
//! does not, the run says so and times with the wall clock instead.
pub mod chart;
pub mod claims;
pub mod clock;
pub mod isolated;
pub mod report;
pub mod sweep;
#[cfg(test)]
mod tests;

pub use clock::*;
pub use report::*;

use std::path::Path;

use serde::Serialize;

use crate::analysis::stats::{median_ci, pareto_front, Estimate};
use crate::compare::{self, CompareOptions};
use crate::error::{Error, Result};
use crate::gpu::spirv::{self, OpCounts};
use crate::gpu::{Prepared, Renderer, Shading, TimedDraws};
use crate::method::{self, Method};
use crate::output::provenance::cpu_model;
use crate::scene::Scene;

/// Version of the bench.json layout.
pub const SCHEMA_VERSION: u32 = 1;
/// Sizes of the clock check and of `--sweep size`.
pub const SIZES: [u32; 5] = [128, 256, 512, 1024, 2048];
/// The timestamp interval tracks the wall clock when, at every size, it is within this
/// fraction of the wall time or within [`CLOCK_SLACK_MS`] of it (submission overhead
/// dominates small draws).
pub const CLOCK_TOLERANCE: f64 = 0.25;
pub const CLOCK_SLACK_MS: f64 = 2.0;
/// (segments, rings) of the UV spheres of `--sweep triangles`: 2 * segments * (rings - 1)
/// triangles, about 100 to 1,000,000.
pub const SPHERES: [(u32, u32); 5] = [(10, 6), (32, 17), (100, 51), (316, 159), (1000, 501)];

/// What to sweep besides the main bench.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    Size,
    Triangles,
}

/// Options of a bench run.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    pub repeat: usize,
    pub warmup: usize,
    /// A compare metric (JSON name) for the Pareto chart's y axis.
    pub error_metric: String,
    /// Add `phong_exact_control`: phong_exact's program under a second name.
    pub control: bool,
    pub sweeps: Vec<Sweep>,
}
/// Times `draws` round-robin: `warmup` discarded submissions each, then `repeat` rounds, each
/// round visiting every draw once in an order rotated by one per round, so drift of a shared
/// machine hits every draw alike. Returns the samples per draw.
fn interleaved(
    draws: &TimedDraws,
    warmup: usize,
    repeat: usize,
) -> Result<Vec<Vec<crate::gpu::Sample>>> {
    let n = draws.len();
    for i in 0..n {
        for _ in 0..warmup {
            draws.run(i)?;
        }
    }
    let mut out = vec![Vec::with_capacity(repeat); n];
    for round in 0..repeat {
        for k in 0..n {
            let i = (k + round) % n;
            out[i].push(draws.run(i)?);
        }
    }
    Ok(out)
}

/// The estimate from the `clock` the clock check chose, with the name of the clock it really
/// came from: `wall` when timestamps were asked for but no sample has one. Also the wall and
/// timestamp medians.
pub(crate) fn estimate(
    samples: &[crate::gpu::Sample],
    clock: &str,
) -> (Estimate, &'static str, f64, Option<f64>) {
    let wall: Vec<f64> = samples.iter().map(|s| s.wall_ms).collect();
    let ts: Vec<f64> = samples.iter().filter_map(|s| s.timestamp_ms).collect();
    let w = median_ci(&wall);
    let t = (!ts.is_empty()).then(|| median_ci(&ts));
    let (chosen, used) = match t {
        Some(t) if clock == "timestamp" => (t, "timestamp"),
        _ => (w, "wall"),
    };
    (chosen, used, w.median, t.map(|t| t.median))
}
fn static_ops(m: &Method, interp: crate::scene::Interpolation) -> Option<OpCounts> {
    let bytes =
        crate::gpu::shaders::embedded(&crate::gpu::shaders::program_name(m.name, interp), "frag")
            .ok()?;
    spirv::count_ops(bytes).ok()
}

/// Runs the bench and writes DIR/bench.json, bench.csv, pareto.svg/png, claims.json/md (and
/// sweep files).
pub fn bench(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    opts: &BenchOptions,
) -> Result<BenchReport> {
    let start = std::time::Instant::now();
    if !compare::METRICS.contains(&opts.error_metric.as_str()) {
        return Err(Error::Usage(format!(
            "--error-metric: unknown metric {:?}; valid metrics: {}",
            opts.error_metric,
            compare::METRICS.join(", ")
        )));
    }
    if opts.repeat == 0 {
        return Err(Error::Usage("--repeat must be at least 1".into()));
    }
    let exact = method::find("phong_exact")?;
    let unnormalized = method::find("phong_unnormalized")?;
    let mut all = methods_.to_vec();
    for m in [exact, unnormalized] {
        if !all.iter().any(|x| x.name == m.name) {
            all.push(m);
        }
    }
    eprintln!("bench: checking the clock at sizes {SIZES:?}");
    let clock = check_clock(renderer, scene)?;
    eprintln!("bench: clock = {} ({})", clock.clock, clock.reason);

    let prepared = renderer.prepare(scene, &all)?;
    // Shadings: the floor, the methods (and the control), each drawing its own geometry.
    let mut shadings: Vec<Shading> = vec![Shading::Constant];
    shadings.extend(all.iter().map(|m| Shading::Method(m)));
    if opts.control {
        shadings.push(Shading::Control(exact));
    }
    let samples = time_shadings(renderer, &prepared, &shadings, opts)?;

    eprintln!("bench: error metrics (compare, without images)");
    let copts = CompareOptions {
        images: false,
        ..CompareOptions::default()
    };
    let summary = compare::compare(renderer, scene, &all, out, &copts)?;

    // Coverage from each image itself.
    let mut rows = Vec::new();
    for (s, smp) in shadings.iter().zip(&samples) {
        let gpu = match s.method() {
            Some(m) => prepared.for_method(m),
            None => prepared.base(),
        };
        let (frame, _) = renderer.render(gpu, *s, false)?;
        let (e, used_clock, wall, ts) = estimate(smp, &clock.clock);
        let covered = frame.covered();
        let invocations = smp.iter().filter_map(|x| x.fragment_invocations).max();
        let error = s
            .method()
            .and_then(|m| summary.methods.iter().find(|r| r.name == m.name).cloned());
        let ops = s
            .method()
            .and_then(|m| static_ops(m, scene.interpolation))
            .or_else(|| {
                crate::gpu::shaders::embedded(
                    &crate::gpu::shaders::program_name("constant", scene.interpolation),
                    "frag",
                )
                .ok()
                .and_then(|b| spirv::count_ops(b).ok())
            });
        rows.push(MethodTiming {
            name: s.name(),
            median_ms: e.median,
            ci95_low_ms: e.ci95_low,
            ci95_high_ms: e.ci95_high,
            samples: e.samples,
            clock: used_clock.into(),
            wall_median_ms: wall,
            timestamp_median_ms: ts,
            covered_pixels: covered,
            fragment_invocations: invocations,
            invocations_exact: invocations.map(|n| n as usize == covered),
            ns_per_pixel: e.median * 1e6 / covered.max(1) as f64,
            above_floor_ms: 0.0,
            ratio_to_phong_exact: 0.0,
            ratio_above_floor_to_phong_exact: 0.0,
            static_ops: ops,
            static_ops_above_unnormalized: None,
            error,
        });
    }
    let floor = rows.remove(0);
    let phong = rows
        .iter()
        .find(|r| r.name == "phong_exact")
        .map(|r| r.median_ms)
        .unwrap_or(f64::NAN);
    let base_ops = rows
        .iter()
        .find(|r| r.name == "phong_unnormalized")
        .and_then(|r| r.static_ops);
    for r in &mut rows {
        r.above_floor_ms = r.median_ms - floor.median_ms;
        r.ratio_to_phong_exact = r.median_ms / phong;
        r.ratio_above_floor_to_phong_exact =
            (r.median_ms - floor.median_ms) / (phong - floor.median_ms);
        r.static_ops_above_unnormalized = match (r.static_ops, base_ops) {
            (Some(a), Some(b)) => Some(a.minus(&b)),
            _ => None,
        };
    }
    // Only the methods the user asked for (phong_exact / unnormalized are always timed, as
    // the ratios' references, and kept).
    let metric = |r: &MethodTiming| r.error.as_ref().and_then(|e| e.metric(&opts.error_metric));
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.median_ms, metric(r).unwrap_or(f64::NAN)))
        .collect();
    let front: Vec<String> = pareto_front(&points)
        .into_iter()
        .map(|i| rows[i].name.clone())
        .collect();
    let claims = claims::claims(&rows, &floor);

    let mut sweeps = Vec::new();
    for &sw in &opts.sweeps {
        eprintln!("bench: sweep {sw:?}");
        sweeps.push(sweep::sweep(renderer, scene, sw, opts)?);
    }
    let report = BenchReport {
        schema_version: SCHEMA_VERSION,
        provenance: renderer.provenance(),
        cpu_model: cpu_model(),
        lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: prepared.base().inputs.triangle_count(),
        repeat: opts.repeat,
        warmup: opts.warmup,
        clock,
        error_metric: opts.error_metric.clone(),
        floor,
        methods: rows,
        pareto_front: front,
        claims,
        sweeps,
        total_s: start.elapsed().as_secs_f64(),
    };
    write(out, &report)?;
    Ok(report)
}

fn time_shadings(
    renderer: &Renderer,
    prepared: &Prepared,
    shadings: &[Shading],
    opts: &BenchOptions,
) -> Result<Vec<Vec<crate::gpu::Sample>>> {
    // Draws of different geometries need their own targets; group them, time each group.
    let mut out = vec![Vec::new(); shadings.len()];
    let mut groups: Vec<(crate::method::Geometry, Vec<usize>)> = Vec::new();
    for (i, s) in shadings.iter().enumerate() {
        let g = s
            .method()
            .map(|m| m.geometry)
            .unwrap_or(crate::method::Geometry::Mesh);
        match groups.iter_mut().find(|(k, _)| *k == g) {
            Some((_, v)) => v.push(i),
            None => groups.push((g, vec![i])),
        }
    }
    for (_, idx) in groups {
        let first = shadings[idx[0]];
        let gpu = match first.method() {
            Some(m) => prepared.for_method(m),
            None => prepared.base(),
        };
        let group: Vec<Shading> = idx.iter().map(|&i| shadings[i]).collect();
        eprintln!(
            "bench: timing {} programs x {} repetitions ({} warm-up)",
            group.len(),
            opts.repeat,
            opts.warmup
        );
        let draws = renderer.timed_draws(gpu, &group)?;
        for (k, s) in interleaved(&draws, opts.warmup, opts.repeat)?
            .into_iter()
            .enumerate()
        {
            out[idx[k]] = s;
        }
    }
    Ok(out)
}
