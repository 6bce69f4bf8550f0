//! The results of a comparison: per-method reports, summary.json / summary.csv, the text
//! table and the `--fail-above` / `--fail-below` limits.
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::*;
use crate::analysis::pixel::{ChannelStats, IntensityStats};
use crate::error::{Error, Result};
use crate::output;
use crate::output::Provenance;

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
    /// For angle-interpolating methods ([`crate::method::Reference::PhongAndSlerp`]): the same
    /// statistics against the second reference, f64 exact slerp along the span; `None` (null)
    /// for the others.
    pub against_slerp: Option<AgainstReference>,
}

/// The second reference's name in outputs.
pub const SLERP_REFERENCE: &str = "slerp_f64";

/// A method's luminance and normal errors against a second reference (the pixels and the
/// definition of every other statistic, [`crate::analysis::pixel`]). Infinite (null in JSON)
/// when the method has non-finite pixels.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AgainstReference {
    pub reference: String,
    pub mean_abs_error: f64,
    pub max_abs_error: f64,
    pub max_normal_angle_deg: Option<f64>,
    pub mean_normal_angle_deg: Option<f64>,
}

/// The numeric per-method metrics `--fail-above` / `--fail-below` accept (their JSON names).
/// Every one is better lower except those of [`HIGHER_IS_BETTER`].
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

/// The metrics of [`METRICS`] where higher is better (a limit on them is a floor: `--fail-below`).
pub const HIGHER_IS_BETTER: &[&str] = &["psnr_db"];

impl MethodReport {
    /// A metric by its JSON name, as a number: `None` when it does not apply (normal metrics of
    /// methods without a per-pixel normal, PSNR of an exact match) or the name is unknown.
    /// For a method with non-finite pixels every error metric is infinite (+inf, -inf for PSNR),
    /// though JSON writes it as null; the counts stay counts.
    pub fn metric(&self, name: &str) -> Option<f64> {
        let i = &self.intensity;
        let inf = f64::INFINITY;
        Some(match name {
            "mean_abs_error" => i.mean_abs_error,
            "max_abs_error" => i.max_abs_error,
            "p50_abs_error" => i.p50_abs_error,
            "p95_abs_error" => i.p95_abs_error,
            "p99_abs_error" => i.p99_abs_error,
            "rmse" => i.rmse,
            "psnr_db" => return i.psnr_db,
            "pixels_above_threshold" => i.pixels_above_threshold.map_or(inf, |n| n as f64),
            "fraction_above_threshold" => i.fraction_above_threshold,
            "max_normal_angle_deg" => return self.max_normal_angle_deg,
            "mean_normal_angle_deg" => return self.mean_normal_angle_deg,
            "p99_normal_angle_deg" => return self.p99_normal_angle_deg,
            "max_normal_length_error" => return self.max_normal_length_error,
            "flip_mean" => self.flip_mean,
            "flip_p95" => self.flip_p95,
            "non_finite_pixels" => self.non_finite_pixels as f64,
            "coverage_mismatch_pixels" => self.coverage_mismatch_pixels as f64,
            _ => return None,
        })
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
    /// Which renderer drew the frames: `vulkan` or `software` ([`super::Engine::name`]); a
    /// summary written before the field existed was drawn by Vulkan.
    #[serde(default = "vulkan")]
    pub engine: String,
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
    /// `auto`'s per-triangle choice when it was compared (its row in `methods` is `auto`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub auto: Option<crate::auto::AutoSummary>,
    /// Further budgets of `auto` compared in the same run (bench's curve), each under its name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub auto_curve: Vec<crate::auto::AutoSummary>,
}

fn vulkan() -> String {
    "vulkan".into()
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
            "against_slerp_mean_abs_error",
            "against_slerp_max_abs_error",
            "against_slerp_max_normal_angle_deg",
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
        i.pixels_above_threshold
            .map_or_else(|| f(f64::INFINITY), |n| n.to_string()),
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
    let s = r.against_slerp.as_ref();
    row.extend([
        o(s.map(|s| s.mean_abs_error)),
        o(s.map(|s| s.max_abs_error)),
        o(s.and_then(|s| s.max_normal_angle_deg)),
    ]);
    row
}

/// Writes summary.json and summary.csv atomically.
pub fn write_summary(out: &Path, s: &Summary) -> Result<()> {
    let json =
        serde_json::to_string_pretty(s).map_err(|e| Error::output("summary.json", e))? + "\n";
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

/// Which side of a limit fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// `--fail-above`: a value above the limit fails (lower-is-better metrics).
    Above,
    /// `--fail-below`: a value below the limit fails (higher-is-better metrics).
    Below,
}

impl Bound {
    /// The command-line flag.
    pub fn flag(self) -> &'static str {
        match self {
            Bound::Above => "--fail-above",
            Bound::Below => "--fail-below",
        }
    }
}

/// One `--fail-above` / `--fail-below` limit.
#[derive(Debug, Clone, PartialEq)]
pub struct Limit {
    pub metric: String,
    pub value: f64,
    pub bound: Bound,
}

/// Parses `METRIC=VALUE` of `--fail-above` or `--fail-below`. A lower-is-better metric is
/// refused in `--fail-below` and a higher-is-better one ([`HIGHER_IS_BETTER`]) in
/// `--fail-above`: either limit would pass the worse methods.
pub fn parse_limit(s: &str, bound: Bound) -> Result<Limit> {
    let flag = bound.flag();
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| Error::Usage(format!("{flag} expects METRIC=VALUE, got {s:?}")))?;
    if !METRICS.contains(&k) {
        return Err(Error::Usage(format!(
            "{flag}: unknown metric {k:?}; valid metrics: {}",
            METRICS.join(", ")
        )));
    }
    let higher = HIGHER_IS_BETTER.contains(&k);
    match (bound, higher) {
        (Bound::Above, true) => {
            return Err(Error::Usage(format!(
                "--fail-above {k}: higher {k} is better, so its limit is a floor; \
                 use --fail-below {k}=VALUE"
            )))
        }
        (Bound::Below, false) => {
            return Err(Error::Usage(format!(
                "--fail-below {k}: lower {k} is better, so its limit is a ceiling; \
                 use --fail-above {k}=VALUE"
            )))
        }
        _ => {}
    }
    let value: f64 = v
        .parse()
        .ok()
        .filter(|v: &f64| !v.is_nan())
        .ok_or_else(|| Error::Usage(format!("{flag} {k}: {v:?} is not a number")))?;
    Ok(Limit {
        metric: k.to_string(),
        value,
        bound,
    })
}

/// A limit a method did not meet.
#[derive(Debug, Clone, PartialEq)]
pub struct Exceeded {
    pub method: String,
    pub limit: Limit,
    pub value: f64,
    /// The method's non-finite pixels (its error metrics are infinite when > 0).
    pub non_finite_pixels: usize,
}

impl std::fmt::Display for Exceeded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (op, l) = match self.limit.bound {
            Bound::Above => (">", &self.limit),
            Bound::Below => ("<", &self.limit),
        };
        write!(
            f,
            "{} {} = {:.6e} {op} {:e}",
            self.method, l.metric, self.value, l.value
        )?;
        if self.non_finite_pixels > 0 {
            write!(f, " ({} non-finite pixels)", self.non_finite_pixels)?;
        }
        Ok(())
    }
}

/// Every (method, limit) the method does not meet: a value strictly above its `--fail-above`
/// limit or strictly below its `--fail-below` one. Metrics that do not apply (`None`: normal
/// metrics of methods without normals, PSNR of an exact match) never fail; infinite ones (every
/// error metric of a method with non-finite pixels) always do.
pub fn exceeded(s: &Summary, limits: &[Limit]) -> Vec<Exceeded> {
    let mut out = Vec::new();
    for r in &s.methods {
        for l in limits {
            let Some(v) = r.metric(&l.metric) else {
                continue;
            };
            // written so that a NaN value fails too
            let ok = match l.bound {
                Bound::Above => v <= l.value,
                Bound::Below => v >= l.value,
            };
            if !ok {
                out.push(Exceeded {
                    method: r.name.clone(),
                    limit: l.clone(),
                    value: v,
                    non_finite_pixels: r.non_finite_pixels,
                });
            }
        }
    }
    out
}

/// The text table, sorted by mean luminance error; methods with non-finite pixels last, their
/// errors shown as `inf` and their count in the `NaN` column.
pub fn table(s: &Summary) -> String {
    let mut rows: Vec<&MethodReport> = s.methods.iter().collect();
    rows.sort_by(|a, b| {
        (a.non_finite_pixels > 0)
            .cmp(&(b.non_finite_pixels > 0))
            .then(
                a.intensity
                    .mean_abs_error
                    .total_cmp(&b.intensity.mean_abs_error),
            )
    });
    let e = |v: f64| {
        if v.is_finite() {
            format!("{v:.3e}")
        } else {
            "inf".into()
        }
    };
    let opt = |v: Option<f64>, p: usize| match v {
        Some(x) if x.is_finite() => format!("{x:.p$}"),
        Some(x) if x < 0.0 => "-inf".into(),
        Some(_) => "inf".into(),
        None => "-".into(),
    };
    let mut t = format!(
        "{:<32} {:>10} {:>10} {:>10} {:>8} {:>9} {:>9} {:>8}\n",
        "method", "mean|dI|", "p99|dI|", "max|dI|", "PSNR dB", "max deg", "FLIP", "NaN"
    );
    for r in rows {
        let i = &r.intensity;
        t += &format!(
            "{:<32} {:>10} {:>10} {:>10} {:>8} {:>9} {:>9} {:>8}\n",
            r.name,
            e(i.mean_abs_error),
            e(i.p99_abs_error),
            e(i.max_abs_error),
            opt(i.psnr_db, 1),
            opt(r.max_normal_angle_deg, 3),
            opt(Some(r.flip_mean), 4),
            r.non_finite_pixels
        );
    }
    t
}
