//! The results of a comparison: per-method reports, summary.json / summary.csv, the text
//! table and the `--fail-above` limits.
use super::*;
use crate::analysis::pixel::{ChannelStats, IntensityStats};
use crate::output::Provenance;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::output;
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

pub(crate) fn csv_row(r: &MethodReport) -> Vec<String> {
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
