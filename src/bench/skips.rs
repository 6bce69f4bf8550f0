//! `shadelab skips`: what each skip of the renderer saves on one scene, measured. The same
//! phong_exact draw is timed in the same interleaved rounds ([`super::rounds`]) as uploaded
//! and recorded in several ways: with nothing skipped (no culling, a normal target, the
//! mesh's own triangle order), then with back-face culling (only where the scene culls: a
//! closed, consistently oriented mesh), without the normal target nobody reads when timing,
//! with a depth pre-pass or with the triangles sorted front to back, and `auto` at an error
//! budget. Each row gets its fragment-shader invocations (untimed pipeline-statistics query)
//! and its paired per-round ratio to the first row and to the renderer's default.
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use super::rounds::{round_values, Rounds};
use super::{estimate, ClockCheck, Speed};
use crate::analysis::stats::{paired_ratio, RatioEstimate};
use crate::error::{Error, Result};
use crate::gpu::{
    Clock, DrawList, GpuScene, Renderer, Sample, Shading, TIMING_NORMAL_TARGET, TIMING_PREPASS,
};
use crate::method;
use crate::output::provenance::Provenance;
use crate::scene::{Cull, Scene};

/// Version of skips.json.
pub const SCHEMA_VERSION: u32 = 1;

/// How one row draws phong_exact (or `auto`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Variant {
    /// Back faces culled (the scene's `cull`, `auto` by default; a mesh that is not closed and
    /// consistently oriented is never culled, and the culled rows are left out).
    pub cull: bool,
    /// A normal target is rendered (the shader's second output; nobody reads it when timing).
    pub normal_target: bool,
    /// Depth-only pre-pass of every triangle, then shading with LESS_OR_EQUAL, no depth write.
    pub prepass: bool,
    /// Triangles sorted by the depth of their centroid, nearest first.
    pub front_to_back: bool,
    /// `auto` at the run's error budget instead of phong_exact.
    pub auto: bool,
}

impl Variant {
    /// The row's name: `none` or the skips joined with `+`.
    pub fn name(&self) -> String {
        let mut parts = Vec::new();
        if self.auto {
            parts.push("auto");
        }
        if self.cull {
            parts.push("cull");
        }
        if !self.normal_target {
            parts.push("no_normal");
        }
        if self.prepass {
            parts.push("prepass");
        }
        if self.front_to_back {
            parts.push("front_to_back");
        }
        if parts.is_empty() {
            "none".into()
        } else {
            parts.join("+")
        }
    }
}

/// The rows of a study: `none` (nothing skipped) first, then each skip added in turn, the
/// renderer's default among them; rows that need culling only when the scene culls.
pub fn variants(culls: bool) -> Vec<Variant> {
    let none = Variant {
        cull: false,
        normal_target: true,
        prepass: false,
        front_to_back: false,
        auto: false,
    };
    let cull = Variant {
        cull: culls,
        ..none
    };
    let lean = Variant {
        normal_target: false,
        ..cull
    };
    let mut out = vec![none];
    if culls {
        out.push(cull);
    }
    out.push(lean);
    out.push(Variant {
        prepass: true,
        ..lean
    });
    out.push(Variant {
        front_to_back: true,
        ..lean
    });
    out.push(default_variant(culls, true));
    // The default may coincide with a row above: keep each once, in order.
    let mut seen = Vec::new();
    out.retain(|v| {
        let new = !seen.contains(v);
        seen.push(*v);
        new
    });
    out
}

/// How the renderer times phong_exact (or `auto`) by default on a scene that culls or not.
pub fn default_variant(culls: bool, auto: bool) -> Variant {
    Variant {
        cull: culls,
        normal_target: TIMING_NORMAL_TARGET,
        prepass: TIMING_PREPASS,
        front_to_back: false,
        auto,
    }
}

/// One row of skips.json.
#[derive(Debug, Clone, Serialize)]
pub struct SkipRow {
    pub name: String,
    pub variant: Variant,
    /// Whether this is how the renderer times the draw by default.
    pub is_default: bool,
    /// Fragment-shader invocations of the whole draw (pre-pass included), null without
    /// pipeline statistics.
    pub fragment_invocations: Option<u64>,
    /// Pixels covered in the rendered image.
    pub covered_pixels: usize,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
    /// Paired per-round ratio to `none` (nothing skipped).
    pub ratio_to_none: RatioEstimate,
    pub speed_vs_none: Speed,
    /// Paired per-round ratio to the renderer's default phong_exact draw.
    pub ratio_to_default: RatioEstimate,
    pub speed_vs_default: Speed,
}

/// skips.json.
#[derive(Debug, Clone, Serialize)]
pub struct SkipReport {
    pub schema_version: u32,
    pub provenance: Provenance,
    pub command_line: Vec<String>,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    /// Whether the scene's culling applies (closed, consistently oriented mesh and `cull`).
    pub culls: bool,
    pub clock: ClockCheck,
    pub warmup: usize,
    pub rounds: usize,
    pub ratio_interval: String,
    /// `auto`'s budget and choice.
    pub auto: crate::auto::AutoSummary,
    /// The default phong_exact row's name.
    pub default: String,
    pub rows: Vec<SkipRow>,
    pub total_s: f64,
}

/// Options of a study.
#[derive(Debug, Clone)]
pub struct SkipOptions {
    pub repeat: usize,
    pub warmup: usize,
    pub auto: crate::auto::AutoSpec,
    pub command_line: Vec<String>,
    /// A clock check made before on this device (the report's); `None`: checked here.
    pub clock: Option<ClockCheck>,
}

/// The triangle order nearest first by the depth (z/w) of each triangle's centroid in clip
/// space.
pub fn front_to_back(inputs: &crate::scene::SceneInputs) -> Vec<usize> {
    let corners: Vec<glam::DVec4> = inputs.clip_corners().collect();
    let key: Vec<f64> = corners
        .chunks_exact(3)
        .map(|c| c.iter().map(|p| p.z / p.w).sum::<f64>() / 3.0)
        .collect();
    let mut order: Vec<usize> = (0..key.len()).collect();
    // A NaN key (a corner at w = 0) sorts last, where it cannot hide anything.
    order.sort_by(|&a, &b| {
        key[a]
            .partial_cmp(&key[b])
            .unwrap_or_else(|| key[a].is_nan().cmp(&key[b].is_nan()))
    });
    order
}

/// Runs the study and writes DIR/skips.json and DIR/skips.md.
pub fn skips(
    renderer: &Renderer,
    scene: &Scene,
    out: &Path,
    opts: &SkipOptions,
) -> Result<SkipReport> {
    let start = Instant::now();
    if opts.repeat < 6 {
        return Err(Error::Usage(format!(
            "--repeat {}: a paired interval needs at least 6 rounds",
            opts.repeat
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let exact = method::phong_exact();
    let clock = super::known_or_checked(renderer, scene, opts.clock.as_ref(), "skips")?;

    let mut no_cull = scene.clone();
    no_cull.cull = Cull::None;
    let plain = renderer.prepare(&no_cull, &[exact])?;
    let culled = renderer.prepare(scene, &[exact])?;
    let culls = culled.base().inputs.cull_front.is_some();
    let sorted = renderer.prepare_permuted(scene, &[exact], &front_to_back)?;
    let (_, auto_summary, auto) = crate::auto::frame::choose_checked(
        renderer,
        scene,
        &culled.base().inputs,
        &opts.auto,
        crate::auto::Cache::Use,
        None,
    )?;
    log::info!("skips: {}", auto_summary.line());

    let variants = variants(culls);
    let gpu_of = |v: &Variant| -> &GpuScene {
        // The sorted upload culls as the scene does: every sorted row has `cull == culls`.
        match (v.cull, v.front_to_back) {
            (_, true) => &sorted,
            (true, false) => culled.base(),
            (false, false) => plain.base(),
        }
    };
    let lists: Vec<DrawList> = variants
        .iter()
        .map(|v| {
            let mut list = if v.auto {
                auto.draw_list()
            } else {
                DrawList::whole(gpu_of(v), Shading::Method(exact))
            };
            list.prepass = v.prepass;
            list.normal = v.normal_target;
            list
        })
        .collect();
    let names: Vec<String> = variants.iter().map(Variant::name).collect();
    let default_row = variants
        .iter()
        .position(|v| *v == default_variant(culls, false))
        .ok_or_else(|| Error::Internal("skips: the default draw is not among the rows".into()))?;
    let (samples, values) = time_lists(renderer, &lists, &names, scene, opts, clock.clock)?;
    let rounds_done = samples.first().map_or(0, Vec::len);

    let mut rows = Vec::new();
    for (i, (v, list)) in variants.iter().zip(&lists).enumerate() {
        let invocations = renderer.fragment_invocations_list(list)?;
        let frame = if v.auto {
            renderer.render_auto(&auto)?
        } else {
            renderer.render(list.gpu, Shading::Method(exact), false)?.0
        };
        let (e, ..) = estimate(&samples[i], clock.clock);
        let to_none = paired_ratio(&values[i], &values[0]);
        let to_default = paired_ratio(&values[i], &values[default_row]);
        rows.push(SkipRow {
            name: names[i].clone(),
            variant: *v,
            is_default: i == default_row,
            fragment_invocations: invocations,
            covered_pixels: frame.covered(),
            median_ms: e.median,
            ci95_low_ms: e.ci95_low,
            ci95_high_ms: e.ci95_high,
            speed_vs_none: Speed::from_ratio(&to_none),
            ratio_to_none: to_none,
            speed_vs_default: Speed::from_ratio(&to_default),
            ratio_to_default: to_default,
        });
    }
    let report = SkipReport {
        schema_version: SCHEMA_VERSION,
        provenance: renderer.provenance(),
        command_line: opts.command_line.clone(),
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: culled.base().inputs.triangle_count(),
        culls,
        clock,
        warmup: opts.warmup,
        rounds: rounds_done,
        ratio_interval: super::RATIO_INTERVAL.into(),
        auto: auto_summary,
        default: names[default_row].clone(),
        rows,
        total_s: start.elapsed().as_secs_f64(),
    };
    write_files(out, &report)?;
    Ok(report)
}

/// Per draw list, its value in each round.
type PerRound = Vec<Vec<f64>>;

/// Times every draw list in the same interleaved rounds: each round's samples, and their values
/// in the checked clock.
fn time_lists(
    renderer: &Renderer,
    lists: &[DrawList],
    names: &[String],
    scene: &Scene,
    opts: &SkipOptions,
    clock: Clock,
) -> Result<(Vec<Vec<Sample>>, PerRound)> {
    log::info!(
        "skips: timing {} draws of {} ({}) in the same interleaved rounds: {} warm-up \
         submissions each, then {} rounds",
        lists.len(),
        scene.name,
        names.join(", "),
        opts.warmup,
        opts.repeat
    );
    let draws = renderer.timed_draw_lists(lists)?;
    let mut rounds = Rounds::new(&draws, opts.warmup)?;
    let bar = crate::output::progress_bar(true, opts.repeat as u64);
    for _ in 0..opts.repeat {
        rounds.run(1)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let values: Vec<Vec<f64>> = rounds
        .samples
        .iter()
        .map(|s| round_values(s, clock))
        .collect();
    let samples = rounds.samples;
    drop(draws);
    Ok((samples, values))
}

/// DIR/skips.md and, last (the run's completion marker), DIR/skips.json, each written
/// atomically.
fn write_files(out: &Path, report: &SkipReport) -> Result<()> {
    crate::output::write_bytes_atomic(&out.join("skips.md"), report.markdown().as_bytes())?;
    let json =
        serde_json::to_string_pretty(report).map_err(|e| Error::output("skips.json", e))? + "\n";
    crate::output::write_bytes_atomic(&out.join("skips.json"), json.as_bytes())
}

impl SkipReport {
    /// The table of skips.md (also printed by the command).
    pub fn markdown(&self) -> String {
        let ratio =
            |r: &RatioEstimate| format!("{:.3} [{:.3}, {:.3}]", r.median, r.ci95_low, r.ci95_high);
        let mut s = format!(
            "# Skips on {} ({}x{}, {} triangles, culling {}), {} rounds, clock {}\n\n\
             `auto` at budget {:.3e}: {}\n\n\
             | draw | fragment invocations | covered pixels | median ms | ratio to none | \
             vs none | ratio to default | vs default |\n|---|---:|---:|---:|---|---|---|---|\n",
            self.scene,
            self.width,
            self.height,
            self.triangles,
            if self.culls {
                "applies"
            } else {
                "does not apply (open or inconsistently oriented mesh, or cull = \"none\")"
            },
            self.rounds,
            self.clock.clock,
            self.auto.budget,
            self.auto
                .triangles
                .iter()
                .filter(|(_, k)| *k > 0)
                .map(|(m, k)| format!("{m} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
        );
        for r in &self.rows {
            s += &format!(
                "| {}{} | {} | {} | {:.3} | {} | {} | {} | {} |\n",
                r.name,
                if r.is_default { " (default)" } else { "" },
                r.fragment_invocations
                    .map_or("n/a".into(), |n| n.to_string()),
                r.covered_pixels,
                r.median_ms,
                ratio(&r.ratio_to_none),
                if r.name == "none" {
                    "(itself)"
                } else {
                    r.speed_vs_none.as_str()
                },
                ratio(&r.ratio_to_default),
                if r.is_default {
                    "(itself)"
                } else {
                    r.speed_vs_default.as_str()
                },
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_start_from_none_and_hold_the_default_once() {
        for culls in [true, false] {
            let v = variants(culls);
            assert_eq!(v[0].name(), "none");
            let d = default_variant(culls, false);
            assert_eq!(v.iter().filter(|x| **x == d).count(), 1, "{culls}");
            assert!(v.iter().any(|x| x.auto), "auto is a row");
            // The sorted upload culls as the scene does: so must every sorted row.
            assert!(v.iter().all(|x| !x.front_to_back || x.cull == culls));
            assert_eq!(
                v.iter().any(|x| x.cull),
                culls,
                "cull rows only when culling applies"
            );
            let names: Vec<String> = v.iter().map(Variant::name).collect();
            let mut unique = names.clone();
            unique.sort();
            unique.dedup();
            assert_eq!(unique.len(), names.len(), "{names:?}");
        }
    }

    #[test]
    fn front_to_back_puts_the_nearest_triangle_first() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
        let scene = crate::scene::load_scene(&path).expect("torus");
        let inputs = crate::scene::SceneInputs::new(&scene, crate::method::Geometry::Mesh);
        let order = front_to_back(&inputs);
        let c: Vec<glam::DVec4> = inputs.clip_corners().collect();
        let depth = |t: usize| (0..3).map(|k| c[3 * t + k].z / c[3 * t + k].w).sum::<f64>();
        let d: Vec<f64> = order.iter().map(|&t| depth(t)).collect();
        assert!(d.windows(2).all(|w| w[0] <= w[1]), "sorted nearest first");
        let mut sorted = order.clone();
        sorted.sort();
        assert_eq!(sorted, (0..inputs.triangle_count()).collect::<Vec<_>>());
        // Teeth: the mesh's own order is not sorted.
        let own: Vec<f64> = (0..inputs.triangle_count()).map(depth).collect();
        assert!(!own.windows(2).all(|w| w[0] <= w[1]));
    }
}
