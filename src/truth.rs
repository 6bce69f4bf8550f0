//! The f64 truth: per covered pixel, the triangle index and interpolation weights the
//! rasterizer used (the id pass of src/render.rs), and every method's formula evaluated in f64
//! at those weights from the exact f32 inputs the GPU received.
//!
//! # The float32 bound (why GPU and f64 may differ, and by how much)
//! Let `u = 2^-24` (f32 unit roundoff) and, per triangle, `g = sum_j |grad w_j| * |N_j|` the
//! screen-space gradient size of the interpolated normal (per pixel; from the window-space
//! corners in f64), and `r = x + y + 2` the pixel's distance from the window origin in pixels.
//! 1. Interpolation. The rasterizer evaluates each varying as a plane equation
//!    `a0 + dadx * x + dady * y` in f32. With `a0` set up from a corner and the evaluation each
//!    costing at most two roundings on terms no larger than `1 + g * r` (|N_j| = 1), a varying
//!    component is off by at most `K_INTERP * u * (1 + g * r)`. The weights of the id pass are
//!    varyings too, so the f64 normal built from them carries the same-size error; together
//!    `|dN|_inf <= 2 * K_INTERP * u * (1 + g * r)`.
//! 2. Normalization divides by `|N|` (>= `N_MIN`, the smallest interpolated length over the
//!    frame) and rounds a few times: `|dN'| <= sqrt(3) * |dN|_inf / |N| + K_NORM * u`.
//! 3. Lighting. `N'.L` and `N'.H` move by at most `|dN'| + 3u`; the diffuse term is linear in
//!    it; `s^n` moves by at most `n * ds` (as s <= 1) plus the relative error of `pow`, which
//!    lavapipe evaluates as `exp2(n * log2(s))` with polynomial approximations:
//!    `POW_REL` covers them. Summed over lights with the colour weights:
//!    `|dI| <= sum_l I_L (k_d * dd + k_s * (n * ds + POW_REL * s^n)) + 8u`.
//!
//! The constants are deliberately few and each is stated below with its reason.
use glam::{DMat4, DVec2, DVec3, DVec4};

use crate::formulas::Lighting;
use crate::methods::{Fragment, Method};
use crate::render::{Frame, IdFrame, SceneInputs};

/// f32 unit roundoff.
pub const U: f64 = 1.0 / 16_777_216.0;
/// Roundings per plane-equation evaluation and set-up (2 for a0 + dadx x + dady y, 2 for a0).
pub const K_INTERP: f64 = 4.0;
/// Roundings in `normalize` (dot: 3, inversesqrt: 2, multiply: 1, plus margin).
pub const K_NORM: f64 = 8.0;
/// Relative error budget of lavapipe's `pow` = exp2(n log2 s); Mesa's gallivm approximations
/// are minimax polynomials good to a few 1e-7 relative (checked by the measured ratio in the
/// tests, which stays well below 1).
pub const POW_REL: f64 = 2e-6;

/// The f64 evaluation of one method over a frame.
pub struct Truth {
    pub width: u32,
    pub height: u32,
    /// Per pixel: `None` on the background, else (colour, shading normal, bound on |colour error|).
    pub pixels: Vec<Option<TruthPixel>>,
}

/// One covered pixel of the truth.
#[derive(Debug, Clone, Copy)]
pub struct TruthPixel {
    pub color: DVec3,
    pub normal: DVec3,
    /// The float32 bound on |GPU colour - f64 colour| (any channel) derived in the module doc.
    pub color_bound: f64,
    /// The bound on |GPU normal - f64 normal| (any component).
    pub normal_bound: f64,
    /// `1 + g * r` of the module doc: how much this pixel's triangle amplifies interpolation
    /// rounding. Any varying (the weights too) is off by at most `K_INTERP * U * amplification`.
    pub amplification: f64,
}

/// Weight uncertainty (`K_INTERP * U * amplification`) above which a pixel counts as
/// ill-conditioned: its triangle is so thin on screen (typically a silhouette triangle seen
/// edge-on) that the rasterizer's float32 weights are uncertain by more than 1e-3, and the
/// agreement check is weak there.
pub const ILL_CONDITIONED: f64 = 1e-3;

/// Window-space corners of every triangle, from the uploaded positions and MVP (in f64).
fn window_corners(inputs: &SceneInputs) -> Vec<DVec2> {
    let m = DMat4::from_cols_array_2d(&inputs.params.mvp.map(|c| c.map(|x| x as f64)));
    let (w, h) = (inputs.width as f64, inputs.height as f64);
    inputs
        .positions
        .iter()
        .map(|p| {
            let c = m * DVec4::new(p[0] as f64, p[1] as f64, p[2] as f64, 1.0);
            DVec2::new((c.x / c.w * 0.5 + 0.5) * w, (c.y / c.w * 0.5 + 0.5) * h)
        })
        .collect()
}

/// `g` of the module doc for one triangle: sum of |grad w_j| |N_j| in 1/pixels.
fn normal_gradient(s: [DVec2; 3]) -> f64 {
    let area2 = (s[1] - s[0]).perp_dot(s[2] - s[0]).abs();
    if area2 <= 0.0 {
        return f64::INFINITY;
    }
    // |grad w_j| = |opposite edge| / (2 * area); |N_j| = 1.
    (0..3)
        .map(|j| (s[(j + 2) % 3] - s[(j + 1) % 3]).length() / area2)
        .sum()
}

/// Evaluates `method` in f64 at every covered pixel of `ids`.
pub fn evaluate(inputs: &SceneInputs, ids: &IdFrame, method: &Method) -> Truth {
    let lighting = inputs.lighting();
    let corners = window_corners(inputs);
    let perspective = matches!(
        inputs.interpolation,
        crate::scene::Interpolation::Perspective
    );
    let widen = |v: [f32; 3]| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
    let pixels = ids
        .prim
        .iter()
        .zip(&ids.weights)
        .enumerate()
        .map(|(i, (&prim, w))| {
            if prim == 0 {
                return None;
            }
            let t = (prim - 1) as usize;
            let frag = Fragment {
                weights: DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64),
                corner_normals: [0, 1, 2].map(|k| widen(inputs.view_normals[3 * t + k])),
            };
            let normal = (method.normal_f64)(&frag);
            let color = lighting.shade(normal);
            let (x, y) = ((i as u32 % ids.width) as f64, (i as u32 / ids.width) as f64);
            let mut g = normal_gradient([corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]]);
            if perspective {
                // Perspective-correct interpolation divides by an interpolated 1/w: one more
                // plane equation and a division, bounded like the others (factor 2).
                g *= 2.0;
            }
            let amplification = 1.0 + g * (x + y + 2.0);
            let (color_bound, normal_bound) = bound(&lighting, &frag, amplification);
            Some(TruthPixel {
                color,
                normal,
                color_bound,
                normal_bound,
                amplification,
            })
        })
        .collect();
    Truth {
        width: ids.width,
        height: ids.height,
        pixels,
    }
}

/// The bounds of the module doc at one pixel, for exact normalization.
fn bound(lighting: &Lighting, frag: &Fragment, amplification: f64) -> (f64, f64) {
    let dn_inf = 2.0 * K_INTERP * U * amplification;
    let len = frag.interpolated_normal().length().max(1e-6);
    let dn_unit = 3f64.sqrt() * dn_inf / len + K_NORM * U;
    let dd = dn_unit + 3.0 * U;
    let n = lighting.shininess;
    let unit = crate::formulas::normalize_exact(frag.interpolated_normal());
    let mut di = 8.0 * U;
    for &(_, color, h) in &lighting.lights {
        let s = unit.dot(h).max(0.0);
        let spec = n * dd + POW_REL * s.powf(n).min(1.0);
        let per_channel = lighting.diffuse * dd + lighting.specular * spec;
        di += (color * per_channel).max_element();
    }
    (di, dn_unit)
}

/// How a GPU frame agrees with its f64 truth.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Agreement {
    /// Pixels covered in both.
    pub covered: usize,
    /// Pixels covered in one and not the other (must be 0: same rasterization).
    pub coverage_mismatch: usize,
    /// Max |GPU - f64| over covered pixels and colour channels.
    pub max_color_error: f64,
    /// Max |GPU - f64| over covered pixels and normal components.
    pub max_normal_error: f64,
    /// Max of (error / bound) over pixels: <= 1 means within the derived float32 bound.
    pub max_color_ratio: f64,
    pub max_normal_ratio: f64,
    /// Pixel (x, y) of the largest colour ratio.
    pub worst_pixel: (u32, u32),
    /// Pixels where the GPU produced NaN or Inf.
    pub non_finite: usize,
    /// Covered pixels whose weight uncertainty exceeds [`ILL_CONDITIONED`] (screen-space
    /// slivers): the check is weak there, so they are counted.
    pub ill_conditioned: usize,
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

/// Compares a GPU frame with its truth, pixel by pixel.
pub fn agreement(frame: &Frame, truth: &Truth) -> Agreement {
    let mut a = Agreement {
        covered: 0,
        coverage_mismatch: 0,
        max_color_error: 0.0,
        max_normal_error: 0.0,
        max_color_ratio: 0.0,
        max_normal_ratio: 0.0,
        worst_pixel: (0, 0),
        non_finite: 0,
        ill_conditioned: 0,
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
        a.ill_conditioned += usize::from(K_INTERP * U * t.amplification > ILL_CONDITIONED);
        let gn = frame.normal[i];
        if gc.iter().chain(gn.iter()).any(|v| !v.is_finite()) {
            a.non_finite += 1;
            continue;
        }
        let ce = (0..3)
            .map(|k| (gc[k] as f64 - t.color[k]).abs())
            .fold(0.0, f64::max);
        let ne = (0..3)
            .map(|k| (gn[k] as f64 - t.normal[k]).abs())
            .fold(0.0, f64::max);
        a.max_color_error = a.max_color_error.max(ce);
        a.max_normal_error = a.max_normal_error.max(ne);
        let cr = ce / t.color_bound;
        if cr > a.max_color_ratio {
            a.max_color_ratio = cr;
            a.worst_pixel = (i as u32 % frame.width, i as u32 / frame.width);
        }
        a.max_normal_ratio = a.max_normal_ratio.max(ne / t.normal_bound);
    }
    a
}
