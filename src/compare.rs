//! `shadelab compare`: every method against the f64 exact-Phong truth, per covered pixel.
//! Statistics (intensity per channel and luminance, normal angle and length, FLIP), heatmaps
//! with colorbars, DIR/summary.json (schema in docs/summary.schema.json), DIR/summary.csv and a
//! text table. Background pixels are excluded from every statistic and counted separately;
//! pixels covered by only one of method and reference (a method that changes the geometry)
//! are counted as coverage mismatches; ill-conditioned sliver pixels (src/truth.rs) are counted
//! and left out.
use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::heatmap::{self, HeatmapDesc, Scale};
use crate::methods::{self, Method};
use crate::output;
use crate::render::{Frame, Renderer, Shading};
use crate::scene::Scene;
use crate::truth::{self, Truth};

/// Version of the summary.json schema (docs/summary.schema.json). Bumped on any change that
/// removes or renames a field.
pub const SCHEMA_VERSION: u32 = 1;
/// Rec. 709 luminance weights of linear RGB.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];
/// Default heatmap scales, shared by all methods so images compare side by side.
pub const FIXED_ABS: Scale = Scale::Log { lo: 1e-5, hi: 1.0 };
pub const FIXED_SIGNED: Scale = Scale::Linear { lo: -0.1, hi: 0.1 };
pub const FIXED_ANGLE: Scale = Scale::Linear { lo: 0.0, hi: 10.0 };

/// Heatmap scaling: shared fixed scales, or per image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
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
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            scale: ScaleMode::Fixed,
            threshold: 1.0 / 255.0,
            progress: false,
            images: true,
        }
    }
}

/// Statistics of a signed per-pixel error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntensityStats {
    pub mean_abs_error: f64,
    pub max_abs_error: f64,
    /// (x, y) of the first pixel with the largest |error|, `None` when there are no pixels.
    pub max_error_pixel: Option<[u32; 2]>,
    pub p50_abs_error: f64,
    pub p95_abs_error: f64,
    pub p99_abs_error: f64,
    pub rmse: f64,
    /// 10 log10(1 / MSE) with peak intensity 1; `None` (null) when the error is exactly 0.
    pub psnr_db: Option<f64>,
    pub pixels_above_threshold: usize,
    pub fraction_above_threshold: f64,
}

/// Nearest-rank percentile of `values` (unsorted; reordered in place): the smallest value such
/// that at least `p` percent of the values are at most it. 0 for an empty slice.
pub fn percentile(values: &mut [f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * values.len() as f64).ceil().max(1.0) as usize;
    let k = rank.min(values.len()) - 1;
    *values.select_nth_unstable_by(k, f64::total_cmp).1
}

/// Statistics of `errors`: (x, y, signed error) per pixel.
pub fn intensity_stats(errors: &[(u32, u32, f64)], threshold: f64) -> IntensityStats {
    let n = errors.len();
    let mut abs: Vec<f64> = errors.iter().map(|e| e.2.abs()).collect();
    let (mut sum, mut sq, mut max, mut at, mut above) = (0.0, 0.0, 0.0, None, 0);
    for &(x, y, e) in errors {
        let a = e.abs();
        sum += a;
        sq += a * a;
        if at.is_none() || a > max {
            max = a;
            at = Some([x, y]);
        }
        above += usize::from(a > threshold);
    }
    let mse = if n > 0 { sq / n as f64 } else { 0.0 };
    IntensityStats {
        mean_abs_error: if n > 0 { sum / n as f64 } else { 0.0 },
        max_abs_error: max,
        max_error_pixel: at,
        p50_abs_error: percentile(&mut abs, 50.0),
        p95_abs_error: percentile(&mut abs, 95.0),
        p99_abs_error: percentile(&mut abs, 99.0),
        rmse: mse.sqrt(),
        psnr_db: (mse > 0.0).then(|| 10.0 * (1.0 / mse).log10()),
        pixels_above_threshold: above,
        fraction_above_threshold: if n > 0 { above as f64 / n as f64 } else { 0.0 },
    }
}

/// Per-channel statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelStats {
    pub mean_abs_error: f64,
    pub max_abs_error: f64,
    pub rmse: f64,
}

/// One method's row of the summary. Intensity fields are of the luminance error (linear).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodReport {
    pub name: String,
    /// The reference the statistics are against.
    pub reference: String,
    pub covered_pixels: usize,
    pub coverage_mismatch_pixels: usize,
    pub ill_conditioned_pixels: usize,
    pub non_finite_pixels: usize,
    #[serde(flatten)]
    pub intensity: IntensityStats,
    pub channels: [ChannelStats; 3],
    /// Normal metrics: `None` (null) for methods without a per-pixel normal.
    pub max_normal_angle_deg: Option<f64>,
    pub mean_normal_angle_deg: Option<f64>,
    pub p99_normal_angle_deg: Option<f64>,
    pub max_normal_length_error: Option<f64>,
    /// NVIDIA FLIP on the 8-bit sRGB images, pooled over the pixels covered in both.
    pub flip_mean: f64,
    pub flip_p95: f64,
    /// Output files, relative to the output directory.
    pub files: Vec<String>,
}

/// The numeric per-method metrics `--fail-above` accepts (their JSON names).
pub const METRICS: &[&str] = &[
    "mean_abs_error",
    "max_abs_error",
    "p50_abs_error",
    "p95_abs_error",
    "p99_abs_error",
    "rmse",
    "psnr_db",
    "pixels_above_threshold",
    "fraction_above_threshold",
    "max_normal_angle_deg",
    "mean_normal_angle_deg",
    "p99_normal_angle_deg",
    "max_normal_length_error",
    "flip_mean",
    "flip_p95",
    "non_finite_pixels",
    "coverage_mismatch_pixels",
];

impl MethodReport {
    /// A metric by its JSON name; `None` when the metric is null for this method.
    pub fn metric(&self, name: &str) -> Option<f64> {
        serde_json::to_value(self).ok()?.get(name)?.as_f64()
    }
}

/// The tool, device and scene a summary was made with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub tool: String,
    pub version: String,
    pub git_revision: String,
    pub device: String,
    pub driver: String,
    pub driver_info: String,
    pub vulkan_api: String,
    pub mesa_version: Option<String>,
    pub llvm_version: Option<String>,
}

impl Provenance {
    pub fn new(info: &crate::vk::DeviceInfo) -> Self {
        let after = |key: &str| {
            info.driver_info.find(key).map(|i| {
                info.driver_info[i + key.len()..]
                    .split(|c: char| c.is_whitespace() || c == ')' || c == ',')
                    .next()
                    .unwrap_or("")
                    .to_string()
            })
        };
        Provenance {
            tool: "shadelab".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            git_revision: env!("SHADELAB_GIT_REVISION").into(),
            device: info.name.clone(),
            driver: info.driver_name.clone(),
            driver_info: info.driver_info.clone(),
            vulkan_api: info.api_version.clone(),
            mesa_version: after("Mesa "),
            llvm_version: after("LLVM "),
        }
    }
}

/// Wall time of the phases, and the metric throughput.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    pub total_ms: f64,
    pub render_ms: f64,
    pub reference_ms: f64,
    pub metrics_ms: f64,
    pub flip_ms: f64,
    pub png_ms: f64,
    /// Covered pixels per second of one thread through the statistics (without FLIP and
    /// PNGs). `metrics_ms`, `flip_ms` and `png_ms` are summed over the two worker threads,
    /// so they can add up to more than `total_ms`.
    pub metric_pixels_per_second: f64,
    /// Pixels (whole image) per second of one thread through FLIP.
    pub flip_pixels_per_second: f64,
}

/// DIR/summary.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub schema_version: u32,
    pub provenance: Provenance,
    pub scene: String,
    pub scene_source: String,
    pub triangles: usize,
    pub width: u32,
    pub height: u32,
    pub interpolation: String,
    pub reference: String,
    pub background_pixels: usize,
    pub threshold: f64,
    pub scale: ScaleMode,
    pub timing: Timing,
    pub methods: Vec<MethodReport>,
}

/// The reference's name in outputs.
pub const REFERENCE: &str = "phong_exact_f64";

fn lum(c: DVec3) -> f64 {
    LUMINANCE[0] * c.x + LUMINANCE[1] * c.y + LUMINANCE[2] * c.z
}

fn d3(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// The per-pixel error fields of one method against the reference.
struct Fields {
    errors: Vec<(u32, u32, f64)>,
    channels: [Vec<f64>; 3],
    angles: Vec<f64>,
    max_len: f64,
    abs: Vec<Option<f64>>,
    signed: Vec<Option<f64>>,
    angle: Vec<Option<f64>>,
    both: Vec<bool>,
    mismatch: usize,
    ill: usize,
    non_finite: usize,
}

fn fields(frame: &Frame, has_normal: bool, reference: &Truth) -> Fields {
    let n = reference.pixels.len();
    let mut f = Fields {
        errors: Vec::new(),
        channels: [Vec::new(), Vec::new(), Vec::new()],
        angles: Vec::new(),
        max_len: 0.0,
        abs: vec![None; n],
        signed: vec![None; n],
        angle: vec![None; n],
        both: vec![false; n],
        mismatch: 0,
        ill: 0,
        non_finite: 0,
    };
    for (i, t) in reference.pixels.iter().enumerate() {
        let here = frame.color[i][3] > 0.0;
        let Some(t) = t else {
            f.mismatch += usize::from(here);
            continue;
        };
        if !here {
            f.mismatch += 1;
            continue;
        }
        f.both[i] = true;
        if t.ill_conditioned() {
            f.ill += 1;
            continue;
        }
        let c = d3(frame.color[i]);
        let nrm = d3(frame.normal[i]);
        if !c.is_finite() || (has_normal && !nrm.is_finite()) {
            f.non_finite += 1;
            continue;
        }
        let d = c - t.color;
        let e = lum(c) - lum(t.color);
        f.errors
            .push((i as u32 % frame.width, i as u32 / frame.width, e));
        for k in 0..3 {
            f.channels[k].push(d[k]);
        }
        f.abs[i] = Some(e.abs());
        f.signed[i] = Some(e);
        if let (true, Some(r)) = (has_normal, t.normal) {
            let len = nrm.length();
            let cos = if len > 0.0 {
                (nrm.dot(r) / (len * r.length())).clamp(-1.0, 1.0)
            } else {
                -1.0
            };
            let a = cos.acos().to_degrees();
            f.angles.push(a);
            f.angle[i] = Some(a);
            f.max_len = f.max_len.max((len - 1.0).abs());
        }
    }
    f
}

fn channel_stats(v: &[f64]) -> ChannelStats {
    let n = v.len().max(1) as f64;
    ChannelStats {
        mean_abs_error: v.iter().map(|x| x.abs()).sum::<f64>() / n,
        max_abs_error: v.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        rmse: (v.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
    }
}

fn srgb_rgb8(color: impl Iterator<Item = DVec3>) -> Vec<u8> {
    color
        .flat_map(|c| [c.x, c.y, c.z].map(|v| output::srgb8(v as f32)))
        .collect()
}

/// FLIP between two RGB8 images, pooled (mean, p95) over `mask` pixels.
fn flip(reference: &[u8], test: &[u8], width: u32, height: u32, mask: &[bool]) -> (f64, f64) {
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    let map = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let mut v: Vec<f64> = map
        .iter()
        .zip(mask)
        .filter(|(_, &m)| m)
        .map(|(&e, _)| e as f64)
        .collect();
    let mean = if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    };
    (mean, percentile(&mut v, 95.0))
}

fn rel(dir: &str, file: &str) -> String {
    format!("{dir}/{file}")
}

/// One heatmap to draw: file, values, colorbar label, colormap, scale, and whether it applies.
type MapSpec<'a> = (
    &'static str,
    &'a [Option<f64>],
    &'static str,
    colorous::Gradient,
    Scale,
    bool,
);

/// What the workers of [`compare`] share.
struct Analysis<'a> {
    reference: &'a Truth,
    ref8: &'a [u8],
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
    /// Statistics, FLIP, render.png and the heatmaps of one method's frame.
    fn analyse(&self, m: &Method, frame: &Frame) -> Result<(MethodReport, PhaseTimes)> {
        let (w, h) = (self.width, self.height);
        let t = Instant::now();
        let f = fields(frame, m.has_normal, self.reference);
        let intensity = intensity_stats(&f.errors, self.opts.threshold);
        let channels = [
            channel_stats(&f.channels[0]),
            channel_stats(&f.channels[1]),
            channel_stats(&f.channels[2]),
        ];
        let mut angles = f.angles.clone();
        let (max_a, mean_a, p99_a) = if m.has_normal {
            let n = angles.len().max(1) as f64;
            (
                Some(angles.iter().fold(0.0f64, |a, &b| a.max(b))),
                Some(angles.iter().sum::<f64>() / n),
                Some(percentile(&mut angles, 99.0)),
            )
        } else {
            (None, None, None)
        };
        let metrics_ms = t.elapsed().as_secs_f64() * 1e3;

        let t = Instant::now();
        let test8 = srgb_rgb8(frame.color.iter().map(|&c| d3(c)));
        let (flip_mean, flip_p95) = flip(self.ref8, &test8, w, h, &f.both);
        let flip_ms = t.elapsed().as_secs_f64() * 1e3;

        let t = Instant::now();
        let dir = self.out.join(m.name);
        let mut files = Vec::new();
        if self.opts.images {
            files.push(rel(m.name, "render.png"));
            output::write_png_srgb(&dir.join("render.png"), w, h, &frame.color)?;
        }
        let (abs_scale, signed_scale, angle_scale) = match self.opts.scale {
            ScaleMode::Fixed => (FIXED_ABS, FIXED_SIGNED, FIXED_ANGLE),
            ScaleMode::Auto => {
                let mx = intensity.max_abs_error.max(1e-9);
                (
                    Scale::Log {
                        lo: mx * 1e-4,
                        hi: mx,
                    },
                    Scale::Linear { lo: -mx, hi: mx },
                    Scale::Linear {
                        lo: 0.0,
                        hi: max_a.unwrap_or(0.0).max(1e-6),
                    },
                )
            }
        };
        let maps: [MapSpec; 3] = [
            (
                "error_abs.png",
                &f.abs,
                "|dI| luminance (linear)",
                colorous::MAGMA,
                abs_scale,
                true,
            ),
            (
                "error_signed.png",
                &f.signed,
                "dI = method - reference",
                colorous::RED_BLUE,
                signed_scale,
                true,
            ),
            (
                "error_angle.png",
                &f.angle,
                "normal angle error (deg)",
                colorous::MAGMA,
                angle_scale,
                m.has_normal,
            ),
        ];
        for (file, values, label, gradient, scale, wanted) in maps {
            if !wanted || !self.opts.images {
                continue;
            }
            let fig = heatmap::render(
                values,
                w,
                h,
                &HeatmapDesc {
                    label,
                    gradient,
                    scale,
                },
            )?;
            heatmap::write_png(&dir.join(file), &fig)?;
            files.push(rel(m.name, file));
        }
        let png_ms = t.elapsed().as_secs_f64() * 1e3;

        let report = MethodReport {
            name: m.name.to_string(),
            reference: REFERENCE.to_string(),
            covered_pixels: f.errors.len(),
            coverage_mismatch_pixels: f.mismatch,
            ill_conditioned_pixels: f.ill,
            non_finite_pixels: f.non_finite,
            intensity,
            channels,
            max_normal_angle_deg: max_a,
            mean_normal_angle_deg: mean_a,
            p99_normal_angle_deg: p99_a,
            max_normal_length_error: m.has_normal.then_some(f.max_len),
            flip_mean,
            flip_p95,
            files,
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
    let start = Instant::now();
    let exact = methods::find("phong_exact")?;
    let mut all = methods_.to_vec();
    if !all.iter().any(|m| m.name == exact.name) {
        all.push(exact);
    }
    let prepared = renderer.prepare(scene, &all)?;
    let base = prepared.base();
    let (w, h) = (base.inputs.width, base.inputs.height);

    // The reference: f64 exact Phong at the rasterizer's weights on the scene's own triangles.
    let t0 = Instant::now();
    let (_, ids) = renderer.render(base, Shading::Method(exact), true)?;
    let ids = ids.ok_or_else(|| Error::Device("the id pass returned nothing".into()))?;
    let reference = truth::evaluate(&base.inputs, &ids, exact);
    let background = reference.pixels.iter().filter(|p| p.is_none()).count();
    let ref_colors: Vec<DVec3> = reference
        .pixels
        .iter()
        .map(|p| p.map(|p| p.color).unwrap_or(DVec3::ZERO))
        .collect();
    let ref8 = srgb_rgb8(ref_colors.iter().copied());
    let ref_rgba: Vec<[f32; 4]> = reference
        .pixels
        .iter()
        .map(|p| {
            p.map(|p| [p.color.x as f32, p.color.y as f32, p.color.z as f32, 1.0])
                .unwrap_or([0.0; 4])
        })
        .collect();
    if opts.images {
        output::write_png_srgb(&out.join("reference.png"), w, h, &ref_rgba)?;
    }
    let reference_ms = t0.elapsed().as_secs_f64() * 1e3;

    let bar = progress_bar(opts.progress, methods_.len() as u64);
    // Pipeline: this thread renders (lavapipe runs its own threads), two workers turn frames
    // into statistics, FLIP and PNGs. The bounded channel keeps at most two frames waiting.
    let ctx = Analysis {
        reference: &reference,
        ref8: &ref8,
        out,
        opts,
        width: w,
        height: h,
    };
    let (tx, rx) = std::sync::mpsc::sync_channel::<(usize, &'static Method, Frame)>(2);
    let rx = std::sync::Mutex::new(rx);
    let results = std::sync::Mutex::new(Vec::new());
    let mut render_ms = 0.0;
    let render_result: Result<()> = std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| loop {
                let job = match rx.lock() {
                    Ok(r) => r.recv(),
                    Err(_) => return,
                };
                let Ok((i, m, frame)) = job else { return };
                bar.set_message(m.name);
                let r = ctx.analyse(m, &frame);
                bar.inc(1);
                if let Ok(mut v) = results.lock() {
                    v.push((i, r));
                }
            });
        }
        for (i, m) in methods_.iter().enumerate() {
            let t = Instant::now();
            let (frame, _) = renderer.render(prepared.for_method(m), Shading::Method(m), false)?;
            render_ms += t.elapsed().as_secs_f64() * 1e3;
            if tx.send((i, m, frame)).is_err() {
                break;
            }
        }
        drop(tx);
        Ok(())
    });
    render_result?;
    bar.finish_and_clear();
    let mut results = results
        .into_inner()
        .map_err(|_| Error::Device("a compare worker panicked".into()))?;
    results.sort_by_key(|(i, _)| *i);
    let (mut metrics_ms, mut flip_ms, mut png_ms, mut metric_pixels) = (0.0, 0.0, 0.0, 0usize);
    let mut reports = Vec::new();
    for (_, r) in results {
        let (report, t) = r?;
        metrics_ms += t.metrics_ms;
        flip_ms += t.flip_ms;
        png_ms += t.png_ms;
        metric_pixels += report.covered_pixels;
        reports.push(report);
    }
    if reports.len() != methods_.len() {
        return Err(Error::Device("a compare worker stopped early".into()));
    }
    let secs = |ms: f64| (ms / 1e3).max(1e-9);
    let summary = Summary {
        schema_version: SCHEMA_VERSION,
        provenance: Provenance::new(renderer.context().info()),
        scene: scene.name.clone(),
        scene_source: scene.mesh.source.clone(),
        triangles: base.inputs.triangle_count(),
        width: w,
        height: h,
        interpolation: crate::shaders::interpolation_tag(scene.interpolation)
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
            flip_pixels_per_second: (w as f64 * h as f64 * methods_.len() as f64) / secs(flip_ms),
        },
        methods: reports,
    };
    if opts.images {
        write_summary(out, &summary)?;
    }
    Ok(summary)
}

fn progress_bar(enabled: bool, n: u64) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !enabled || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(n);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} ({elapsed})")
    {
        bar.set_style(style);
    }
    bar
}

/// The CSV columns, in order (one row per method; channel stats flattened as r_/g_/b_).
pub fn csv_header() -> Vec<String> {
    let mut h: Vec<String> = [
        "name",
        "reference",
        "covered_pixels",
        "coverage_mismatch_pixels",
        "ill_conditioned_pixels",
        "non_finite_pixels",
        "mean_abs_error",
        "max_abs_error",
        "max_error_x",
        "max_error_y",
        "p50_abs_error",
        "p95_abs_error",
        "p99_abs_error",
        "rmse",
        "psnr_db",
        "pixels_above_threshold",
        "fraction_above_threshold",
    ]
    .map(String::from)
    .to_vec();
    for c in ["r", "g", "b"] {
        for s in ["mean_abs_error", "max_abs_error", "rmse"] {
            h.push(format!("{c}_{s}"));
        }
    }
    h.extend(
        [
            "max_normal_angle_deg",
            "mean_normal_angle_deg",
            "p99_normal_angle_deg",
            "max_normal_length_error",
            "flip_mean",
            "flip_p95",
        ]
        .map(String::from),
    );
    h
}

fn csv_row(r: &MethodReport) -> Vec<String> {
    let f = |v: f64| format!("{v:e}");
    let o = |v: Option<f64>| v.map(f).unwrap_or_default();
    let i = &r.intensity;
    let mut row = vec![
        r.name.clone(),
        r.reference.clone(),
        r.covered_pixels.to_string(),
        r.coverage_mismatch_pixels.to_string(),
        r.ill_conditioned_pixels.to_string(),
        r.non_finite_pixels.to_string(),
        f(i.mean_abs_error),
        f(i.max_abs_error),
        i.max_error_pixel
            .map(|p| p[0].to_string())
            .unwrap_or_default(),
        i.max_error_pixel
            .map(|p| p[1].to_string())
            .unwrap_or_default(),
        f(i.p50_abs_error),
        f(i.p95_abs_error),
        f(i.p99_abs_error),
        f(i.rmse),
        o(i.psnr_db),
        i.pixels_above_threshold.to_string(),
        f(i.fraction_above_threshold),
    ];
    for c in &r.channels {
        row.extend([f(c.mean_abs_error), f(c.max_abs_error), f(c.rmse)]);
    }
    row.extend([
        o(r.max_normal_angle_deg),
        o(r.mean_normal_angle_deg),
        o(r.p99_normal_angle_deg),
        o(r.max_normal_length_error),
        f(r.flip_mean),
        f(r.flip_p95),
    ]);
    row
}

/// Writes summary.json and summary.csv atomically.
pub fn write_summary(out: &Path, s: &Summary) -> Result<()> {
    let json = serde_json::to_string_pretty(s).map_err(|e| Error::Usage(e.to_string()))? + "\n";
    output::write_bytes_atomic(&out.join("summary.json"), json.as_bytes())?;
    output::write_atomic(&out.join("summary.csv"), |w| {
        let mut c = csv::Writer::from_writer(w);
        c.write_record(csv_header())
            .map_err(std::io::Error::other)?;
        for r in &s.methods {
            c.write_record(csv_row(r)).map_err(std::io::Error::other)?;
        }
        c.flush()
    })
}

/// Parses `METRIC=VALUE` of `--fail-above`.
pub fn parse_limit(s: &str) -> Result<(String, f64)> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| Error::Usage(format!("--fail-above expects METRIC=VALUE, got {s:?}")))?;
    if !METRICS.contains(&k) {
        return Err(Error::Usage(format!(
            "--fail-above: unknown metric {k:?}; valid metrics: {}",
            METRICS.join(", ")
        )));
    }
    let v: f64 = v
        .parse()
        .ok()
        .filter(|v: &f64| !v.is_nan())
        .ok_or_else(|| Error::Usage(format!("--fail-above {k}: {v:?} is not a number")))?;
    Ok((k.to_string(), v))
}

/// Every (method, metric, value, limit) whose value is strictly above its limit. Null metrics
/// (normal metrics of methods without normals) never exceed.
pub fn exceeded(s: &Summary, limits: &[(String, f64)]) -> Vec<(String, String, f64, f64)> {
    let mut out = Vec::new();
    for r in &s.methods {
        for (k, limit) in limits {
            if let Some(v) = r.metric(k) {
                if v > *limit {
                    out.push((r.name.clone(), k.clone(), v, *limit));
                }
            }
        }
    }
    out
}

/// The text table (sorted by mean luminance error).
pub fn table(s: &Summary) -> String {
    let mut rows: Vec<&MethodReport> = s.methods.iter().collect();
    rows.sort_by(|a, b| {
        a.intensity
            .mean_abs_error
            .total_cmp(&b.intensity.mean_abs_error)
    });
    let opt =
        |v: Option<f64>, p: usize| v.map(|x| format!("{x:.p$}")).unwrap_or_else(|| "-".into());
    let mut t = format!(
        "{:<32} {:>10} {:>10} {:>10} {:>8} {:>9} {:>9} {:>8}\n",
        "method", "mean|dI|", "p99|dI|", "max|dI|", "PSNR dB", "max deg", "FLIP", "NaN"
    );
    for r in rows {
        let i = &r.intensity;
        t += &format!(
            "{:<32} {:>10.3e} {:>10.3e} {:>10.3e} {:>8} {:>9} {:>9.4} {:>8}\n",
            r.name,
            i.mean_abs_error,
            i.p99_abs_error,
            i.max_abs_error,
            opt(i.psnr_db, 1),
            opt(r.max_normal_angle_deg, 3),
            r.flip_mean,
            r.non_finite_pixels
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_give_exactly_zero() {
        let e: Vec<_> = (0..100).map(|i| (i % 10, i / 10, 0.0)).collect();
        let s = intensity_stats(&e, 0.01);
        assert_eq!(
            (s.mean_abs_error, s.max_abs_error, s.rmse, s.p99_abs_error),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(s.psnr_db, None);
        assert_eq!(s.pixels_above_threshold, 0);
    }

    #[test]
    fn one_pixel_off_gives_the_known_statistics() {
        let mut e: Vec<_> = (0..100u32).map(|i| (i % 10, i / 10, 0.0)).collect();
        e[37].2 = -0.5; // pixel (7, 3)
        let s = intensity_stats(&e, 0.01);
        assert_eq!(s.max_abs_error, 0.5);
        assert_eq!(s.max_error_pixel, Some([7, 3]));
        assert!((s.mean_abs_error - 0.005).abs() < 1e-15);
        assert!((s.rmse - 0.05).abs() < 1e-15);
        // nearest rank: p99 of 100 values is the 99th smallest = 0, p100 would be 0.5
        assert_eq!(s.p99_abs_error, 0.0);
        assert_eq!(s.p50_abs_error, 0.0);
        assert!((s.psnr_db.unwrap() - 10.0 * (1.0f64 / 0.0025).log10()).abs() < 1e-12);
        assert_eq!(
            (s.pixels_above_threshold, s.fraction_above_threshold),
            (1, 0.01)
        );
    }

    #[test]
    fn percentiles_are_nearest_rank() {
        let mut v: Vec<f64> = (1..=10).map(|x| x as f64).collect();
        assert_eq!(percentile(&mut v, 50.0), 5.0);
        assert_eq!(percentile(&mut v, 95.0), 10.0);
        assert_eq!(percentile(&mut v, 10.0), 1.0);
        assert_eq!(percentile(&mut v, 0.0), 1.0);
        assert_eq!(percentile(&mut [], 50.0), 0.0);
    }

    #[test]
    fn limits_parse_and_reject_unknown_metrics() {
        assert_eq!(
            parse_limit("max_abs_error=0.5").unwrap(),
            ("max_abs_error".into(), 0.5)
        );
        let e = parse_limit("max_error=1").unwrap_err().to_string();
        assert!(
            e.contains("unknown metric \"max_error\"") && e.contains("max_abs_error"),
            "{e}"
        );
        assert!(parse_limit("max_abs_error").is_err());
        assert!(parse_limit("max_abs_error=abc").is_err());
    }

    #[test]
    fn csv_rows_match_the_header() {
        let r = MethodReport {
            name: "x".into(),
            reference: REFERENCE.into(),
            covered_pixels: 1,
            coverage_mismatch_pixels: 0,
            ill_conditioned_pixels: 0,
            non_finite_pixels: 0,
            intensity: intensity_stats(&[(0, 0, 0.25)], 0.1),
            channels: [0, 1, 2].map(|_| ChannelStats {
                mean_abs_error: 0.0,
                max_abs_error: 0.0,
                rmse: 0.0,
            }),
            max_normal_angle_deg: None,
            mean_normal_angle_deg: None,
            p99_normal_angle_deg: None,
            max_normal_length_error: None,
            flip_mean: 0.0,
            flip_p95: 0.0,
            files: vec![],
        };
        assert_eq!(csv_row(&r).len(), csv_header().len());
        assert_eq!(r.metric("max_abs_error"), Some(0.25));
        assert_eq!(r.metric("max_normal_angle_deg"), None);
        for m in METRICS {
            assert!(
                csv_header().iter().any(|h| h == m),
                "metric {m} missing from the CSV"
            );
        }
    }
}
