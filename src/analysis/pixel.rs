//! The per-pixel error of a frame against its f64 truth, and the statistics of that error.
use crate::analysis::stats::percentile;
use crate::truth::{finite, max_diff, Truth};
use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::frame::Frame;
/// A method's error against a reference truth (normally f64 exact Phong), over the pixels
/// covered in both. Ill-conditioned pixels (screen-space slivers whose weights the rasterizer
/// extrapolated, see [`ILL_CONDITIONED`]) are counted and left out of the statistics: the
/// reference itself is not meaningful there.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ErrorStats {
    /// Pixels in the statistics.
    pub covered: usize,
    /// Pixels covered by only one of the two (different geometry, e.g. `trueform`).
    pub coverage_mismatch: usize,
    /// Ill-conditioned pixels left out of the statistics.
    pub ill_conditioned: usize,
    /// Well-conditioned pixels with NaN or Inf in the method's colour or normal (not in the
    /// statistics).
    pub non_finite: usize,
    /// Ill-conditioned pixels with NaN or Inf.
    pub non_finite_ill_conditioned: usize,
    /// Max and mean over pixels of the largest |colour - reference| channel.
    pub max_abs_error: f64,
    pub mean_abs_error: f64,
    /// Angle between the method's shading normal and the reference's, degrees (`None`
    /// for methods without a per-pixel normal).
    pub max_normal_angle_deg: Option<f64>,
    pub mean_normal_angle_deg: Option<f64>,
    /// Max ||N'| - 1| of the method's normal.
    pub max_normal_length_error: Option<f64>,
}

/// Statistics of `frame` (a method's GPU output, `has_normal` telling whether its normal
/// target is meaningful) against `reference`.
pub fn error_stats(frame: &Frame, has_normal: bool, reference: &Truth) -> ErrorStats {
    let (mut covered, mut mismatch, mut non_finite) = (0usize, 0usize, 0usize);
    let (mut ill, mut non_finite_ill) = (0usize, 0usize);
    let (mut max_e, mut sum_e, mut max_a, mut sum_a, mut max_l) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (i, t) in reference.pixels.iter().enumerate() {
        let gc = frame.color[i];
        let here = gc[3] > 0.0;
        let Some(t) = t else {
            mismatch += usize::from(here);
            continue;
        };
        if !here {
            mismatch += 1;
            continue;
        }
        let gn = frame.normal[i];
        let bad = !finite(&gc) || (has_normal && !finite(&gn));
        if t.ill_conditioned() {
            ill += 1;
            non_finite_ill += usize::from(bad);
            continue;
        }
        if bad {
            non_finite += 1;
            continue;
        }
        covered += 1;
        let e = max_diff(
            DVec3::new(gc[0] as f64, gc[1] as f64, gc[2] as f64),
            t.color,
        );
        max_e = max_e.max(e);
        sum_e += e;
        if let (true, Some(rn)) = (has_normal, t.normal) {
            let n = DVec3::new(gn[0] as f64, gn[1] as f64, gn[2] as f64);
            let len = n.length();
            let cos = if len > 0.0 {
                (n.dot(rn) / (len * rn.length())).clamp(-1.0, 1.0)
            } else {
                -1.0
            };
            let angle = cos.acos().to_degrees();
            max_a = max_a.max(angle);
            sum_a += angle;
            max_l = max_l.max((len - 1.0).abs());
        }
    }
    let mean = |s: f64| if covered > 0 { s / covered as f64 } else { 0.0 };
    ErrorStats {
        covered,
        coverage_mismatch: mismatch,
        ill_conditioned: ill,
        non_finite,
        non_finite_ill_conditioned: non_finite_ill,
        max_abs_error: max_e,
        mean_abs_error: mean(sum_e),
        max_normal_angle_deg: has_normal.then_some(max_a),
        mean_normal_angle_deg: has_normal.then(|| mean(sum_a)),
        max_normal_length_error: has_normal.then_some(max_l),
    }
}
/// Rec. 709 luminance weights of linear RGB.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];
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
pub(crate) fn lum(c: DVec3) -> f64 {
    LUMINANCE[0] * c.x + LUMINANCE[1] * c.y + LUMINANCE[2] * c.z
}

pub(crate) fn d3(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// The per-pixel error fields of one method against the reference.
pub(crate) struct Fields {
    pub errors: Vec<(u32, u32, f64)>,
    pub channels: [Vec<f64>; 3],
    pub angles: Vec<f64>,
    pub max_len: f64,
    pub abs: Vec<Option<f64>>,
    pub signed: Vec<Option<f64>>,
    pub angle: Vec<Option<f64>>,
    pub both: Vec<bool>,
    pub mismatch: usize,
    pub ill: usize,
    pub non_finite: usize,
}

pub(crate) fn fields(frame: &Frame, has_normal: bool, reference: &Truth) -> Fields {
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

pub(crate) fn channel_stats(v: &[f64]) -> ChannelStats {
    let n = v.len().max(1) as f64;
    ChannelStats {
        mean_abs_error: v.iter().map(|x| x.abs()).sum::<f64>() / n,
        max_abs_error: v.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        rmse: (v.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
    }
}
