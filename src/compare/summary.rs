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

/// A numeric per-method metric of summary.json, by name in `--fail-above` / `--fail-below`,
/// bench's `--error-metric` and the report's tables. Each is one row of [`METRIC_ROWS`] (in
/// this order): its name, its direction, whether it counts pixels, and its accessor. Written
/// as its name in JSON, read back from it, and parsed from it on the command line
/// ([`Metric::parse`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Metric {
    MeanAbsError,
    MaxAbsError,
    P50AbsError,
    P95AbsError,
    P99AbsError,
    Rmse,
    PsnrDb,
    PixelsAboveThreshold,
    FractionAboveThreshold,
    MaxNormalAngleDeg,
    MeanNormalAngleDeg,
    P99NormalAngleDeg,
    MaxNormalLengthError,
    FlipMean,
    FlipP95,
    NonFinitePixels,
    CoverageMismatchPixels,
}

/// One metric: its JSON (and CSV) name, its direction, whether it counts pixels (written as an
/// integer in CSV), and its value for a method: `None` when it does not apply (normal metrics
/// of methods without a per-pixel normal, PSNR of an exact match). For a method with non-finite
/// pixels every error metric is infinite (+inf, -inf for PSNR), though JSON writes it as null;
/// the counts stay counts.
pub struct MetricRow {
    pub metric: Metric,
    pub name: &'static str,
    /// Higher is better (a limit on it is a floor: `--fail-below`); lower otherwise.
    pub higher_is_better: bool,
    pub count: bool,
    pub value: fn(&MethodReport) -> Option<f64>,
}

const fn row(
    metric: Metric,
    name: &'static str,
    count: bool,
    value: fn(&MethodReport) -> Option<f64>,
) -> MetricRow {
    MetricRow {
        metric,
        name,
        higher_is_better: false,
        count,
        value,
    }
}

/// Every metric, in the order of [`Metric`]'s variants (a test checks it).
pub const METRIC_ROWS: [MetricRow; 17] = {
    use Metric as M;
    [
        row(M::MeanAbsError, "mean_abs_error", false, |r| {
            Some(r.intensity.mean_abs_error)
        }),
        row(M::MaxAbsError, "max_abs_error", false, |r| {
            Some(r.intensity.max_abs_error)
        }),
        row(M::P50AbsError, "p50_abs_error", false, |r| {
            Some(r.intensity.p50_abs_error)
        }),
        row(M::P95AbsError, "p95_abs_error", false, |r| {
            Some(r.intensity.p95_abs_error)
        }),
        row(M::P99AbsError, "p99_abs_error", false, |r| {
            Some(r.intensity.p99_abs_error)
        }),
        row(M::Rmse, "rmse", false, |r| Some(r.intensity.rmse)),
        MetricRow {
            higher_is_better: true,
            ..row(M::PsnrDb, "psnr_db", false, |r| r.intensity.psnr_db)
        },
        row(
            M::PixelsAboveThreshold,
            "pixels_above_threshold",
            true,
            |r| {
                Some(
                    r.intensity
                        .pixels_above_threshold
                        .map_or(f64::INFINITY, |n| n as f64),
                )
            },
        ),
        row(
            M::FractionAboveThreshold,
            "fraction_above_threshold",
            false,
            |r| Some(r.intensity.fraction_above_threshold),
        ),
        row(M::MaxNormalAngleDeg, "max_normal_angle_deg", false, |r| {
            r.max_normal_angle_deg
        }),
        row(M::MeanNormalAngleDeg, "mean_normal_angle_deg", false, |r| {
            r.mean_normal_angle_deg
        }),
        row(M::P99NormalAngleDeg, "p99_normal_angle_deg", false, |r| {
            r.p99_normal_angle_deg
        }),
        row(
            M::MaxNormalLengthError,
            "max_normal_length_error",
            false,
            |r| r.max_normal_length_error,
        ),
        row(M::FlipMean, "flip_mean", false, |r| Some(r.flip_mean)),
        row(M::FlipP95, "flip_p95", false, |r| Some(r.flip_p95)),
        row(M::NonFinitePixels, "non_finite_pixels", true, |r| {
            Some(r.non_finite_pixels as f64)
        }),
        row(
            M::CoverageMismatchPixels,
            "coverage_mismatch_pixels",
            true,
            |r| Some(r.coverage_mismatch_pixels as f64),
        ),
    ]
};

impl Metric {
    /// Its row of [`METRIC_ROWS`].
    pub fn row(self) -> &'static MetricRow {
        &METRIC_ROWS[self as usize]
    }

    /// The metric named `name` (its JSON name).
    pub fn from_name(name: &str) -> Option<Metric> {
        METRIC_ROWS
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.metric)
    }

    /// The JSON name.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The metric named `name`, or an error listing the valid names (`--error-metric`).
    pub fn parse(name: &str) -> std::result::Result<Metric, String> {
        Metric::from_name(name.trim()).ok_or_else(|| {
            format!(
                "unknown metric {name:?}; valid metrics: {}",
                METRICS.join(", ")
            )
        })
    }

    /// Its value for `r` (see [`MetricRow`]).
    pub fn of(self, r: &MethodReport) -> Option<f64> {
        (self.row().value)(r)
    }

    /// The CSV cell: a count as an integer (inf when it cannot be counted), any other number
    /// in `{:e}` notation, empty when it does not apply.
    fn csv(self, r: &MethodReport) -> String {
        match self.of(r) {
            Some(v) if self.row().count && v.is_finite() => (v as u64).to_string(),
            Some(v) => format!("{v:e}"),
            None => String::new(),
        }
    }
}

impl std::fmt::Display for Metric {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Metric {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Metric::parse(s)
    }
}

impl Serialize for Metric {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Metric {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Metric::parse(&name).map_err(serde::de::Error::custom)
    }
}

const fn names<const N: usize>(higher: Option<bool>) -> [&'static str; N] {
    let mut out = [""; N];
    let (mut i, mut k) = (0, 0);
    while i < METRIC_ROWS.len() {
        let take = match higher {
            Some(h) => METRIC_ROWS[i].higher_is_better == h,
            None => true,
        };
        if take {
            out[k] = METRIC_ROWS[i].name;
            k += 1;
        }
        i += 1;
    }
    out
}

const fn count_higher() -> usize {
    let (mut i, mut k) = (0, 0);
    while i < METRIC_ROWS.len() {
        if METRIC_ROWS[i].higher_is_better {
            k += 1;
        }
        i += 1;
    }
    k
}

/// The names of [`METRIC_ROWS`], in order.
pub const METRICS: &[&str] = &names::<{ METRIC_ROWS.len() }>(None);

/// The metrics of [`METRICS`] where higher is better (a limit on them is a floor: `--fail-below`).
pub const HIGHER_IS_BETTER: &[&str] = &names::<{ count_higher() }>(Some(true));

impl MethodReport {
    /// A metric by its JSON name, as a number ([`Metric::of`]); `None` when the name is unknown
    /// too.
    pub fn metric(&self, name: &str) -> Option<f64> {
        Metric::from_name(name).and_then(|m| m.of(self))
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
    /// Which renderer drew the frames: `vulkan` or `software`; a
    /// summary written before the field existed was drawn by Vulkan.
    #[serde(default = "vulkan")]
    pub engine: crate::engine::EngineKind,
    /// The precision the method programs computed in (`f32`, `f16`); absent in a
    /// summary written before the field existed: f32.
    #[serde(default)]
    pub precision: crate::method::Precision,
    pub scene: String,
    pub scene_source: String,
    /// What was read of the mesh file (format, encoding; for glTF the scene, nodes, meshes and
    /// primitives drawn and where their normals came from); absent for a generated mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh_input: Option<crate::geometry::MeshInput>,
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

fn vulkan() -> crate::engine::EngineKind {
    crate::engine::EngineKind::Vulkan
}

/// The reference's name in outputs.
pub const REFERENCE: &str = "phong_exact_f64";
/// A column of summary.csv: a metric of [`METRIC_ROWS`], another field of the row, or the
/// channel statistics (flattened as r_/g_/b_ mean_abs_error, max_abs_error, rmse).
enum Column {
    Metric(Metric),
    Field(&'static str, fn(&MethodReport) -> String),
    Channels,
}

/// The columns of summary.csv, in order.
const CSV_COLUMNS: &[Column] = {
    use Column::{Channels, Field, Metric as C};
    use Metric as M;
    fn e(v: f64) -> String {
        format!("{v:e}")
    }
    fn o(v: Option<f64>) -> String {
        v.map(e).unwrap_or_default()
    }
    &[
        Field("name", |r| r.name.clone()),
        Field("reference", |r| r.reference.clone()),
        Field("covered_pixels", |r| r.covered_pixels.to_string()),
        C(M::CoverageMismatchPixels),
        Field("ill_conditioned_pixels", |r| {
            r.ill_conditioned_pixels.to_string()
        }),
        C(M::NonFinitePixels),
        C(M::MeanAbsError),
        C(M::MaxAbsError),
        Field("max_error_x", |r| {
            r.intensity
                .max_error_pixel
                .map(|p| p[0].to_string())
                .unwrap_or_default()
        }),
        Field("max_error_y", |r| {
            r.intensity
                .max_error_pixel
                .map(|p| p[1].to_string())
                .unwrap_or_default()
        }),
        C(M::P50AbsError),
        C(M::P95AbsError),
        C(M::P99AbsError),
        C(M::Rmse),
        C(M::PsnrDb),
        C(M::PixelsAboveThreshold),
        C(M::FractionAboveThreshold),
        Channels,
        C(M::MaxNormalAngleDeg),
        C(M::MeanNormalAngleDeg),
        C(M::P99NormalAngleDeg),
        C(M::MaxNormalLengthError),
        C(M::FlipMean),
        C(M::FlipP95),
        Field("against_slerp_mean_abs_error", |r| {
            o(r.against_slerp.as_ref().map(|s| s.mean_abs_error))
        }),
        Field("against_slerp_max_abs_error", |r| {
            o(r.against_slerp.as_ref().map(|s| s.max_abs_error))
        }),
        Field("against_slerp_max_normal_angle_deg", |r| {
            o(r.against_slerp
                .as_ref()
                .and_then(|s| s.max_normal_angle_deg))
        }),
    ]
};

/// The channel statistics' CSV names, in order.
const CHANNEL_STATS: [&str; 3] = ["mean_abs_error", "max_abs_error", "rmse"];

/// The CSV columns, in order (one row per method).
pub fn csv_header() -> Vec<String> {
    let mut h = Vec::new();
    for c in CSV_COLUMNS {
        match c {
            Column::Metric(m) => h.push(m.name().to_string()),
            Column::Field(name, _) => h.push(name.to_string()),
            Column::Channels => {
                for ch in ["r", "g", "b"] {
                    h.extend(CHANNEL_STATS.map(|s| format!("{ch}_{s}")));
                }
            }
        }
    }
    h
}

pub(crate) fn csv_row(r: &MethodReport) -> Vec<String> {
    let mut row = Vec::new();
    for c in CSV_COLUMNS {
        match c {
            Column::Metric(m) => row.push(m.csv(r)),
            Column::Field(_, value) => row.push(value(r)),
            Column::Channels => {
                for c in &r.channels {
                    row.extend(
                        [c.mean_abs_error, c.max_abs_error, c.rmse].map(|v| format!("{v:e}")),
                    );
                }
            }
        }
    }
    row
}

/// Writes summary.csv and, last (the run's completion marker), summary.json, atomically.
pub fn write_summary(out: &Path, s: &Summary) -> Result<()> {
    output::write_atomic(&out.join("summary.csv"), |w| {
        let mut c = csv::Writer::from_writer(w);
        c.write_record(csv_header())
            .map_err(std::io::Error::other)?;
        for r in &s.methods {
            c.write_record(csv_row(r)).map_err(std::io::Error::other)?;
        }
        c.flush()
    })?;
    let json =
        serde_json::to_string_pretty(s).map_err(|e| Error::output("summary.json", e))? + "\n";
    output::write_bytes_atomic(&out.join("summary.json"), json.as_bytes())
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
    /// The method's measured pixels: 0 fails every limit (no figure was measured).
    pub measured_pixels: usize,
}

impl std::fmt::Display for Exceeded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (op, l) = match self.limit.bound {
            Bound::Above => (">", &self.limit),
            Bound::Below => ("<", &self.limit),
        };
        let (m, name) = (&self.method, &l.metric);
        if self.non_finite_pixels > 0 {
            let at = non_finite_at(self.non_finite_pixels, self.measured_pixels);
            return write!(
                f,
                "{m} {name} = {:.6e} {op} {:e} ({at})",
                self.value, l.value
            );
        }
        if self.measured_pixels == 0 {
            // an empty set has no figure: no value to print, and no limit can be met
            return write!(
                f,
                "{m} {name} has no value (limit {op} {:e} not met): no pixel measured, the \
                 method covers none of the reference's pixels",
                l.value
            );
        }
        write!(f, "{m} {name} = {:.6e} {op} {:e}", self.value, l.value)
    }
}

/// "non-finite at N of M pixels": a method's `non_finite` pixels among the pixels it and the
/// reference cover outside ill-conditioned slivers (its `measured` finite ones and the
/// non-finite ones), the reason every error figure of it is infinite.
pub fn non_finite_at(non_finite: usize, measured: usize) -> String {
    format!(
        "non-finite at {non_finite} of {} pixels",
        non_finite + measured
    )
}

/// Every (method, limit) the method does not meet: a value strictly above its `--fail-above`
/// limit or strictly below its `--fail-below` one. Metrics that do not apply (`None`: normal
/// metrics of methods without normals, PSNR of an exact match) never fail; infinite ones (every
/// error metric of a method with non-finite pixels) always do, and so does every limit of a
/// method with no measured pixel (it covers none of the reference's pixels: nothing was
/// measured, whatever the metric).
pub fn exceeded(s: &Summary, limits: &[Limit]) -> Vec<Exceeded> {
    let mut out = Vec::new();
    for r in &s.methods {
        for l in limits {
            let none = r.covered_pixels == 0;
            let v = match r.metric(&l.metric) {
                _ if none => r.metric(&l.metric).unwrap_or(f64::NAN),
                Some(v) => v,
                None => continue,
            };
            // written so that a NaN value fails too
            let ok = !none
                && match l.bound {
                    Bound::Above => v <= l.value,
                    Bound::Below => v >= l.value,
                };
            if !ok {
                out.push(Exceeded {
                    method: r.name.clone(),
                    limit: l.clone(),
                    value: v,
                    non_finite_pixels: r.non_finite_pixels,
                    measured_pixels: r.covered_pixels,
                });
            }
        }
    }
    out
}

/// The text table, sorted by mean luminance error; methods with non-finite pixels last, their
/// errors shown as `inf` and their count in the `NaN` column; a method that covers no pixel
/// after them, every statistic `n/a`.
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
    let none = |r: &&&MethodReport| r.covered_pixels == 0 && r.non_finite_pixels == 0;
    for r in rows.iter().filter(|r| !none(r)) {
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
    // A method that covers no pixel has no statistic: n/a, not inf (non-finite) nor 0.
    for r in rows.iter().filter(none) {
        let na = "n/a";
        t += &format!(
            "{:<32} {na:>10} {na:>10} {na:>10} {na:>8} {na:>9} {na:>9} {:>8}  (no pixel covered)\n",
            r.name, r.non_finite_pixels
        );
    }
    t
}
