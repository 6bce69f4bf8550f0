//! Agreement of a GPU frame with its f64 truth: per pixel error over the float32 bound
//! (`shadelab verify`).
use glam::DVec3;

use super::*;
use crate::frame::Frame;
use crate::method::Precision;

/// How a GPU frame agrees with its f64 truth.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Agreement {
    /// Pixels covered in both.
    pub covered: usize,
    /// Pixels covered in one and not the other (must be 0: same rasterization).
    pub coverage_mismatch: usize,
    /// Max |GPU - f64| over covered pixels and colour channels.
    pub max_color_error: f64,
    /// Max |GPU - f64| over covered pixels and normal components (0 without normals).
    pub max_normal_error: f64,
    /// Max of (error / bound) over pixels: <= 1 means within the derived float32 bound.
    pub max_color_ratio: f64,
    pub max_normal_ratio: f64,
    /// Pixel (x, y) of the largest colour ratio.
    pub worst_pixel: (u32, u32),
    /// Well-conditioned pixels where the GPU produced NaN or Inf although the f64 value is
    /// finite and within the f32 range: a failure.
    pub non_finite: usize,
    /// Pixels where the f64 value itself exceeds the f32 range (the GPU's Inf or NaN is then the
    /// expected f32 outcome): counted, not a failure.
    pub overflow: usize,
    /// Covered pixels whose weight uncertainty exceeds [`ILL_CONDITIONED`] (screen-space
    /// slivers): the check is weak there, so they are counted.
    pub ill_conditioned: usize,
    /// Ill-conditioned pixels where the GPU produced NaN or Inf: reported, not a failure.
    pub non_finite_ill_conditioned: usize,
}

impl Agreement {
    /// True when every covered pixel is within its bound and coverage matches.
    pub fn within_bound(&self) -> bool {
        self.coverage_mismatch == 0
            && self.non_finite == 0
            && self.max_color_ratio <= 1.0
            && self.max_normal_ratio <= 1.0
    }
}

pub(crate) fn finite(v: &[f32; 4]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Compares a GPU frame with its truth, pixel by pixel (a float32 program: an f64 value beyond
/// f32's range makes the frame's inf or NaN expected).
pub fn agreement(frame: &Frame, truth: &Truth) -> Agreement {
    agreement_at(frame, truth, Precision::F32)
}

/// [`agreement`] for a program computing in `precision`: an f64 value beyond that precision's
/// range (65504 in f16) makes the frame's inf or NaN expected (`overflow`); any other
/// non-finite pixel is a failure.
pub fn agreement_at(frame: &Frame, truth: &Truth, precision: Precision) -> Agreement {
    let mut a = Agreement {
        covered: 0,
        coverage_mismatch: 0,
        max_color_error: 0.0,
        max_normal_error: 0.0,
        max_color_ratio: 0.0,
        max_normal_ratio: 0.0,
        worst_pixel: (0, 0),
        non_finite: 0,
        overflow: 0,
        ill_conditioned: 0,
        non_finite_ill_conditioned: 0,
    };
    for (i, t) in truth.pixels.iter().enumerate() {
        let gc = frame.color[i];
        let covered = gc[3] > 0.0;
        let Some(t) = t else {
            a.coverage_mismatch += covered as usize;
            continue;
        };
        if !covered {
            a.coverage_mismatch += 1;
            continue;
        }
        a.covered += 1;
        let ill = t.ill_conditioned();
        a.ill_conditioned += usize::from(ill);
        let gn = frame.normal[i];
        if !finite(&gc) || !finite(&gn) {
            if t.exceeds(precision) {
                a.overflow += 1;
            } else if ill {
                a.non_finite_ill_conditioned += 1;
            } else {
                a.non_finite += 1;
            }
            continue;
        }
        let ce = max_diff(
            DVec3::new(gc[0] as f64, gc[1] as f64, gc[2] as f64),
            t.color,
        );
        a.max_color_error = a.max_color_error.max(ce);
        let cr = ce / t.color_bound;
        if cr > a.max_color_ratio {
            a.max_color_ratio = cr;
            a.worst_pixel = (i as u32 % frame.width, i as u32 / frame.width);
        }
        if let Some(n) = t.normal {
            let ne = max_diff(DVec3::new(gn[0] as f64, gn[1] as f64, gn[2] as f64), n);
            a.max_normal_error = a.max_normal_error.max(ne);
            a.max_normal_ratio = a.max_normal_ratio.max(ne / t.normal_bound);
        }
    }
    a
}
