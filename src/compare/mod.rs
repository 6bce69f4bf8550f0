//! `shadelab compare`: every method against the f64 exact-Phong truth, per covered pixel.
//! Statistics (intensity per channel and luminance, normal angle and length, FLIP), heatmaps
//! with colorbars, DIR/summary.json (schema in docs/summary.schema.json), DIR/summary.csv and a
//! text table. The per-pixel error and which pixels enter the statistics are defined once, in
//! [`crate::analysis::pixel`] (shared with `verify`): background, coverage-mismatch,
//! ill-conditioned and non-finite pixels are counted and left out of every statistic (FLIP
//! included), and a method with any non-finite pixel has every error metric infinite (null in
//! JSON, beside its `non_finite_pixels` count), sorts last and fails every limit.
pub mod summary;
#[cfg(test)]
mod tests;

pub use summary::*;

use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::analysis::flip::{flip, srgb_rgb8, FlipReference};
use crate::analysis::pixel::{channel_stats, pixel_errors, IntensityStats, PixelErrors};
use crate::analysis::scan::Prepared;
use crate::analysis::scan::Twin;
use crate::engine::{self, Engine};
use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame, SpareFrames};
use crate::gpu::Renderer;
use crate::method::{self, Method, Reference};
use crate::output;
use crate::output::heatmap::{self, Colormap, HeatmapDesc, Scale};
use crate::scene::{Scene, SceneInputs};
use crate::truth::{self, Values};

/// Version of the summary.json schema (docs/summary.schema.json). Bumped on any change that
/// removes or renames a field or changes its type (2: error metrics are null for a method with
/// non-finite pixels, `pixels_above_threshold` included).
pub const SCHEMA_VERSION: u32 = 2;
/// Default heatmap scales, shared by all methods so images compare side by side.
pub const FIXED_ABS: Scale = Scale::Log { lo: 1e-5, hi: 1.0 };
pub const FIXED_SIGNED: Scale = Scale::Linear { lo: -0.1, hi: 0.1 };
pub const FIXED_ANGLE: Scale = Scale::Linear { lo: 0.0, hi: 10.0 };

/// Heatmap scaling: shared fixed scales, or per image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ScaleMode {
    Fixed,
    Auto,
}

/// Options of a comparison.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    pub scale: ScaleMode,
    /// Luminance error above which a pixel counts in `pixels_above_threshold`.
    pub threshold: f64,
    /// Show a progress bar on stderr (only drawn when stderr is a terminal).
    pub progress: bool,
    /// Write render.png and the heatmaps (`bench` needs only the statistics).
    pub images: bool,
    /// Also compare `auto` (per triangle the cheapest method within a budget), each spec under
    /// its name (`auto`, or `auto_4_255` and the like for the points of bench's curve).
    pub auto: Vec<crate::auto::AutoSpec>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            scale: ScaleMode::Fixed,
            threshold: 1.0 / 255.0,
            progress: false,
            images: true,
            auto: Vec::new(),
        }
    }
}
fn rel(dir: &str, file: &str) -> String {
    format!("{dir}/{file}")
}

/// One heatmap to draw: file, values, colorbar label, colormap, scale, and whether it applies.
type MapSpec<'a> = (
    &'static str,
    heatmap::Field<'a>,
    &'static str,
    Colormap,
    Scale,
    bool,
);

/// What is compared: a method of the table, or `auto`.
#[derive(Debug, Clone, Copy)]
struct Subject<'n> {
    name: &'n str,
    has_normal: bool,
    reference: Reference,
}

impl From<&Method> for Subject<'static> {
    fn from(m: &Method) -> Self {
        Subject {
            name: m.name,
            has_normal: m.has_normal,
            reference: m.reference,
        }
    }
}

/// `auto` in the outputs: no per-pixel normal of its own (gouraud's triangles have none).
fn auto_subject(name: &str) -> Subject<'_> {
    Subject {
        name,
        has_normal: false,
        reference: Reference::Phong,
    }
}

/// What the workers of [`compare`] share.
struct Analysis<'a> {
    /// The run's truth with the constants its scan reads (computed once per run).
    reference: &'a Prepared<'a>,
    /// The second reference (f64 exact slerp along the span), when a method of the run is
    /// judged against it too: its twin at the reference's covered pixels, evaluated once.
    slerp: Option<&'a Twin>,
    /// FLIP's reference half (the reference's 8-bit image filtered once per run).
    flip: &'a FlipReference,
    out: &'a Path,
    opts: &'a CompareOptions,
    width: u32,
    height: u32,
}

/// CPU time of one method's analysis phases.
struct PhaseTimes {
    metrics_ms: f64,
    flip_ms: f64,
    png_ms: f64,
}

impl Analysis<'_> {
    /// The errors against the second reference, for the methods judged against it.
    fn against_slerp(&self, m: Subject, frame: &Frame) -> Result<Option<AgainstReference>> {
        let Some(twin) = self
            .slerp
            .filter(|_| m.reference == Reference::PhongAndSlerp)
        else {
            return Ok(None);
        };
        let s = twin.stats(frame, m.has_normal, self.reference.values())?;
        Ok(Some(AgainstReference {
            reference: SLERP_REFERENCE.to_string(),
            mean_abs_error: s.mean_abs_error,
            max_abs_error: s.max_abs_error,
            max_normal_angle_deg: s.max_normal_angle_deg,
            mean_normal_angle_deg: s.mean_normal_angle_deg,
        }))
    }

    /// Statistics, render.png, the heatmaps and FLIP of one method's frame, in that order: the
    /// frame and the per-pixel maps are freed before FLIP, whose own float images (about 80 MB
    /// at 1024x1024) are then the worker's only large allocation.
    /// Writes the method's heatmaps (|dI|, dI, and the normal angle where it has a normal)
    /// into its folder, adding each file to `files`.
    fn write_heatmaps(
        &self,
        m: Subject,
        f: &PixelErrors,
        (abs_scale, signed_scale, angle_scale): (Scale, Scale, Scale),
        files: &mut Vec<String>,
    ) -> Result<()> {
        let (w, h) = (self.width, self.height);
        let dir = self.out.join(m.name);
        let ((signed, measured), (angle, has_angle)) = (f.signed_map(), f.angle_map());
        let field = |values, mask, abs| heatmap::Field::Masked { values, mask, abs };
        let maps: [MapSpec; 3] = [
            (
                "error_abs.png",
                field(signed, measured, true),
                "|dI| luminance (linear)",
                Colormap::Magma,
                abs_scale,
                true,
            ),
            (
                "error_signed.png",
                field(signed, measured, false),
                "dI = method - reference",
                Colormap::RedBlue,
                signed_scale,
                true,
            ),
            (
                "error_angle.png",
                field(angle, has_angle, false),
                "normal angle error (deg)",
                Colormap::Magma,
                angle_scale,
                m.has_normal,
            ),
        ];
        let mut buffer = Vec::new(); // one figure buffer for the three maps
        for (file, values, label, gradient, scale, wanted) in maps {
            if !wanted || !self.opts.images {
                continue;
            }
            let fig = heatmap::render_reusing(
                values,
                w,
                h,
                &HeatmapDesc {
                    label,
                    gradient,
                    scale,
                },
                buffer,
            )?;
            heatmap::write_png(&dir.join(file), &fig, heatmap::Rows::Field)?;
            buffer = fig.rgb;
            files.push(rel(m.name, file));
        }
        Ok(())
    }

    /// `done` gets the frame back once nothing needs it any more (before FLIP).
    fn analyse(
        &self,
        m: Subject,
        frame: Frame,
        done: impl FnOnce(Frame),
    ) -> Result<(MethodReport, PhaseTimes)> {
        let (w, h) = (self.width, self.height);
        let t = Instant::now();
        // First, so that its per-pixel errors are freed before the main ones are made.
        let against_slerp = self.against_slerp(m, &frame)?;
        let mut f = pixel_errors(&frame, m.has_normal, self.reference);
        let nf = f.non_finite();
        let intensity = if nf {
            IntensityStats::non_finite(f.first_non_finite)
        } else {
            f.intensity_stats(self.opts.threshold)
        };
        let channels = [0, 1, 2].map(|k| channel_stats(&f.channels[k], nf));
        let stats = f.stats();
        let p99_a = m.has_normal.then(|| {
            if nf {
                f64::INFINITY
            } else {
                f.angle_percentile(99.0)
            }
        });
        let (max_a, mean_a) = (stats.max_normal_angle_deg, stats.mean_normal_angle_deg);
        let metrics_ms = t.elapsed().as_secs_f64() * 1e3;

        let t = Instant::now();
        let dir = self.out.join(m.name);
        let mut files = Vec::new();
        // The 8-bit sRGB image, once: render.png's bytes (those of `output::write_png_srgb`)
        // and FLIP's test image, their RGB.
        let test8 = if self.opts.images {
            files.push(rel(m.name, "render.png"));
            let rgba = output::srgb::frame_rgba8(&frame.color);
            output::write_png_rgba8(&dir.join("render.png"), w, h, &rgba)?;
            output::srgb::rgb8_of_rgba8(&rgba)
        } else {
            output::srgb::frame_rgb8(&frame.color)
        };
        let (abs_scale, signed_scale, angle_scale) =
            heatmap_scales(self.opts.scale, intensity.max_abs_error, max_a);
        self.write_heatmaps(m, &f, (abs_scale, signed_scale, angle_scale), &mut files)?;
        let png_ms = t.elapsed().as_secs_f64() * 1e3;

        // FLIP over the same pixels as every other statistic; a method with NaN/Inf has none.
        // It needs only the 8-bit test image and the mask: the frame and the maps go first.
        let t = Instant::now();
        let test8 = (!nf).then_some(test8);
        done(frame);
        let (counts, measured) = (f.counts, std::mem::take(&mut f.measured));
        drop(f);
        let (flip_mean, flip_p95) = match test8 {
            Some(test8) if counts.measured > 0 => flip(self.flip, &test8, &measured),
            // no pixel, no FLIP: NaN (null in summary.json, n/a in the table), never 0
            Some(_) => (f64::NAN, f64::NAN),
            None => (f64::INFINITY, f64::INFINITY),
        };
        let flip_ms = t.elapsed().as_secs_f64() * 1e3;

        let report = MethodReport {
            name: m.name.to_string(),
            reference: REFERENCE.to_string(),
            covered_pixels: counts.measured,
            coverage_mismatch_pixels: counts.coverage_mismatch,
            ill_conditioned_pixels: counts.ill_conditioned,
            non_finite_pixels: counts.non_finite,
            intensity,
            channels,
            max_normal_angle_deg: max_a,
            mean_normal_angle_deg: mean_a,
            p99_normal_angle_deg: p99_a,
            max_normal_length_error: stats.max_normal_length_error,
            flip_mean,
            flip_p95,
            files,
            against_slerp,
        };
        Ok((
            report,
            PhaseTimes {
                metrics_ms,
                flip_ms,
                png_ms,
            },
        ))
    }
}

/// Runs the comparison of `methods` on `scene` and writes everything into `out`.
pub fn compare(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    opts: &CompareOptions,
) -> Result<Summary> {
    compare_with(Engine::Vulkan(renderer), scene, methods_, out, opts)
}

/// [`compare`] with the frames drawn by `engine`: the reference is f64 exact Phong at that
/// engine's own weights (its id pass), so each engine is judged on the pixels it covers.
/// `auto` is drawn by the Vulkan pipeline only.
/// Writes the reference as reference.png (sRGB, alpha 0 on the background).
fn write_reference_png(reference: &Values, out: &Path, w: u32, h: u32) -> Result<()> {
    let ref_rgba: Vec<[f32; 4]> = reference
        .pixels()
        .map(|p| {
            p.map(|p| [p.color.x as f32, p.color.y as f32, p.color.z as f32, 1.0])
                .unwrap_or([0.0; 4])
        })
        .collect();
    output::write_png_srgb(&out.join("reference.png"), w, h, &ref_rgba)
}

/// The run's truth, f64 exact Phong at the id pass `ids`, and, when one of `methods` is judged
/// against it too, the second reference of the angle-interpolating methods: exact slerp along
/// the span, evaluated once (on the second core while this one evaluates the first).
fn references(
    inputs: &SceneInputs,
    ids: &IdFrame,
    methods: &[&'static Method],
) -> Result<(Values, Option<Twin>)> {
    let slerp = methods
        .iter()
        .any(|m| m.reference == Reference::PhongAndSlerp)
        .then(method::slerp_reference);
    // Statistics need no float32 bound (verify checks those): the values alone.
    let (reference, twin) = std::thread::scope(|s| {
        let twin = slerp.map(|m| s.spawn(|| Twin::new(inputs, ids, m)));
        let reference = truth::values(inputs, ids, method::phong_exact());
        (reference, twin.map(|t| t.join()).transpose())
    });
    let twin = twin.map_err(|_| Error::Internal("the slerp twin's thread panicked".into()))?;
    Ok((reference, twin))
}

/// The reports of `results` (the first error, if any), their phase times summed and the
/// covered pixels they measured; an error when fewer than `subjects` came back.
fn gather(results: Analysed, subjects: usize) -> Result<(Vec<MethodReport>, PhaseTimes, usize)> {
    let mut t = PhaseTimes {
        metrics_ms: 0.0,
        flip_ms: 0.0,
        png_ms: 0.0,
    };
    let (mut reports, mut metric_pixels) = (Vec::new(), 0usize);
    for r in results {
        let (report, p) = r?;
        t.metrics_ms += p.metrics_ms;
        t.flip_ms += p.flip_ms;
        t.png_ms += p.png_ms;
        metric_pixels += report.covered_pixels;
        reports.push(report);
    }
    if reports.len() != subjects {
        return Err(Error::Internal("a compare worker stopped early".into()));
    }
    Ok((reports, t, metric_pixels))
}

/// The scales of the three heatmaps (|dI|, dI, normal angle): fixed, or from this method's own
/// largest errors (`max_abs`, `max_angle`); a method with non-finite pixels has no range of its
/// own and gets the fixed span.
fn heatmap_scales(mode: ScaleMode, max_abs: f64, max_angle: Option<f64>) -> (Scale, Scale, Scale) {
    match mode {
        ScaleMode::Fixed => (FIXED_ABS, FIXED_SIGNED, FIXED_ANGLE),
        ScaleMode::Auto => {
            let finite_or = |v: f64, d: f64| if v.is_finite() { v } else { d };
            let mx = finite_or(max_abs, 1.0).max(1e-9);
            (
                Scale::Log {
                    lo: mx * 1e-4,
                    hi: mx,
                },
                Scale::Linear { lo: -mx, hi: mx },
                Scale::Linear {
                    lo: 0.0,
                    hi: finite_or(max_angle.unwrap_or(0.0), 10.0).max(1e-6),
                },
            )
        }
    }
}

/// What a comparison draws: the methods, then `auto` at each spec (Vulkan only).
struct Run<'a> {
    engine: Engine<'a>,
    prepared: &'a engine::Ready<'a>,
    scene: &'a Scene,
    methods: &'a [&'static Method],
    auto: &'a [crate::auto::AutoSpec],
}

/// Each subject's report and phase times, in order.
type Analysed = Vec<Result<(MethodReport, PhaseTimes)>>;

impl Run<'_> {
    /// Pipeline: this thread renders (lavapipe runs its own threads), two workers turn frames
    /// into statistics, FLIP and PNGs. The channel is a rendezvous: a frame is handed over only
    /// when a worker takes it, so at most three frames (32 MB each at 1024x1024) are in use at
    /// once. A worker hands its frame back before FLIP and the next frame is read back into it
    /// (warm pages instead of 32 MB of fresh ones per frame); one spare is kept, the rest
    /// dropped, so at most one frame more than in use exists.
    /// Returns the reports in order, the render time (ms) and `auto`'s choices.
    fn render_and_analyse(
        &self,
        ctx: &Analysis,
        bar: &indicatif::ProgressBar,
    ) -> Result<(Analysed, f64, Vec<crate::auto::AutoSummary>)> {
        let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, Subject, Frame)>(0);
        let rx = std::sync::Mutex::new(rx);
        let results = std::sync::Mutex::new(Vec::new());
        let spare = SpareFrames::new(1);
        let mut render_ms = 0.0;
        let mut auto_summaries = Vec::new();
        let render_result: Result<()> = std::thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| loop {
                    let job = match rx.lock() {
                        Ok(r) => r.recv(),
                        Err(_) => return,
                    };
                    let Ok((i, m, frame)) = job else { return };
                    bar.set_message(m.name.to_string());
                    let r = ctx.analyse(m, frame, |f| spare.give(f));
                    bar.inc(1);
                    if let Ok(mut v) = results.lock() {
                        v.push((i, r));
                    }
                });
            }
            for (i, m) in self.methods.iter().enumerate() {
                let t = Instant::now();
                let (frame, _) = self.prepared.render_into(m, false, spare.take())?;
                render_ms += t.elapsed().as_secs_f64() * 1e3;
                if tx.send((i, Subject::from(*m), frame)).is_err() {
                    break;
                }
            }
            for (k, spec) in self.auto.iter().enumerate() {
                // refused at the start for any other engine
                let Engine::Vulkan(renderer) = self.engine else {
                    break;
                };
                let t = Instant::now();
                let (_, summary, scene_auto) = crate::auto::frame::choose_checked(
                    renderer,
                    self.scene,
                    self.prepared.base(),
                    spec,
                    crate::auto::Cache::Use,
                    None,
                )?;
                auto_summaries.push(summary);
                let frame = renderer.render_auto_into(&scene_auto, spare.take())?;
                drop(scene_auto);
                render_ms += t.elapsed().as_secs_f64() * 1e3;
                if tx
                    .send((self.methods.len() + k, auto_subject(&spec.name), frame))
                    .is_err()
                {
                    break;
                }
            }
            drop(tx);
            Ok(())
        });
        render_result?;
        let mut results = results
            .into_inner()
            .map_err(|_| Error::Internal("a compare worker panicked".into()))?;
        results.sort_by_key(|(i, _)| *i);
        Ok((
            results.into_iter().map(|(_, r)| r).collect(),
            render_ms,
            auto_summaries,
        ))
    }
}

pub fn compare_with(
    engine: Engine,
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    opts: &CompareOptions,
) -> Result<Summary> {
    let start = Instant::now();
    if !opts.auto.is_empty() && !matches!(engine, Engine::Vulkan(_)) {
        return Err(Error::Usage(format!(
            "auto is drawn by the Vulkan pipeline only, not by the {} engine: leave auto out of \
             --methods or use --engine vulkan",
            engine.name()
        )));
    }
    let exact = method::phong_exact();
    let mut all = methods_.to_vec();
    if !all.iter().any(|m| m.name == exact.name) {
        all.push(exact);
    }
    // Before anything is allocated: the truth, the frames and the metrics at this size.
    let heap = match engine {
        Engine::Vulkan(r) => Some(r.context().heap_bytes()).filter(|&h| h > 0),
        Engine::Software { .. } => None,
    };
    crate::memory::check(
        &crate::memory::compare(methods_.len() + opts.auto.len()),
        scene.width,
        scene.height,
        heap,
    )?;
    let prepared = engine::Ready::new(engine, scene, &all)?;
    let base = prepared.base();
    let (w, h) = (base.width, base.height);

    // The reference: f64 exact Phong at the rasterizer's weights on the scene's own triangles.
    let t0 = Instant::now();
    let (_, ids) = prepared.render(exact, true)?;
    let ids = ids.ok_or_else(|| Error::Internal("the id pass returned nothing".into()))?;
    let (reference, slerp) = references(base, &ids, methods_)?;
    drop(ids);
    let background = reference.background();
    let colors = reference.pixels().map(|p| p.map(|p| p.color));
    let flip_reference =
        FlipReference::new(&srgb_rgb8(colors.map(|c| c.unwrap_or(DVec3::ZERO))), w, h);
    if opts.images {
        write_reference_png(&reference, out, w, h)?;
    }
    let prepared_reference = Prepared::new(&reference);
    let reference_ms = t0.elapsed().as_secs_f64() * 1e3;

    let subjects = methods_.len() + opts.auto.len();
    let bar = crate::output::progress_bar(opts.progress, subjects as u64);
    let ctx = Analysis {
        reference: &prepared_reference,
        slerp: slerp.as_ref(),
        flip: &flip_reference,
        out,
        opts,
        width: w,
        height: h,
    };
    let run = Run {
        engine,
        prepared: &prepared,
        scene,
        methods: methods_,
        auto: &opts.auto,
    };
    let (results, render_ms, auto_summaries) = run.render_and_analyse(&ctx, &bar)?;
    bar.finish_and_clear();
    let (reports, t, metric_pixels) = gather(results, subjects)?;
    let PhaseTimes {
        metrics_ms,
        flip_ms,
        png_ms,
    } = t;
    let secs = |ms: f64| (ms / 1e3).max(1e-9);
    let summary = Summary {
        schema_version: SCHEMA_VERSION,
        provenance: engine.provenance(),
        engine: engine.kind(),
        precision: match engine {
            Engine::Vulkan(r) => r.precision(),
            Engine::Software { .. } => crate::method::Precision::F32,
        },
        scene: scene.name.clone(),
        scene_source: scene.mesh.source.clone(),
        mesh_input: scene.mesh_report.as_ref().map(|r| r.input.clone()),
        triangles: base.triangle_count(),
        width: w,
        height: h,
        interpolation: crate::gpu::shaders::interpolation_tag(scene.interpolation)
            .0
            .to_string(),
        reference: REFERENCE.to_string(),
        background_pixels: background,
        threshold: opts.threshold,
        scale: opts.scale,
        timing: Timing {
            total_ms: start.elapsed().as_secs_f64() * 1e3,
            render_ms,
            reference_ms,
            metrics_ms,
            flip_ms,
            png_ms,
            metric_pixels_per_second: metric_pixels as f64 / secs(metrics_ms),
            flip_pixels_per_second: (w as f64 * h as f64 * subjects as f64) / secs(flip_ms),
        },
        methods: reports,
        auto: auto_summaries.first().cloned(),
        auto_curve: auto_summaries.into_iter().skip(1).collect(),
    };
    if opts.images {
        write_summary(out, &summary)?;
    }
    Ok(summary)
}
