//! The f64 truth: per covered pixel, the triangle index and interpolation weights the
//! rasterizer used (the id pass of src/gpu/renderer.rs), and every method's formula evaluated in f64
//! at those weights from the exact f32 inputs the GPU received.
//!
//! # The float32 bound (why GPU and f64 may differ, and by how much)
//! Let `u = 2^-24` (f32 unit roundoff) and, per triangle, `g = sum_j |grad w_j|` the size of the
//! weights' screen-space gradient (per pixel; from the window-space corners in f64), and
//! `r = x + y + 2` the pixel's distance from the window origin in pixels.
//! 1. Interpolation. The rasterizer evaluates each varying as a plane equation
//!    `a0 + dadx * x + dady * y` in f32. With `a0` set up from a corner and the evaluation each
//!    costing at most two roundings on terms no larger than `(1 + g * r)` times the largest corner
//!    value, a varying is off by at most what an error of `dw = K_INTERP * u * (1 + g * r)` in
//!    each weight would cause. This holds for the weights of the id pass (varyings too) and for
//!    every varying the method interpolates (normal, quaternion, colour, weights), which are
//!    linear in the weights. So GPU and f64 each see the fragment as if its weights were off by
//!    up to `dw` per corner, and first-order propagation through the method's f64 formula gives
//!    `2 * dw * sum_j |dC/dw_j|`, the derivatives taken by central differences in f64.
//!    Perspective-correct interpolation divides by an interpolated 1/w: one more plane equation
//!    and a division, bounded like the others (`dw` doubled).
//! 2. Arithmetic. The method's own f32 formula (normalization, polynomial, quaternion, ...)
//!    rounds its shading normal by at most `K_FORMULA * u * max(1, |N'|)`; the lighting then moves
//!    by the diffuse factor times that, the specular factor `n s^(n-1)` times it, the relative
//!    error `POW_REL` of lavapipe's `pow` (= exp2(n log2 s), polynomial approximations), and 8u
//!    for the sums.
//! 3. Span (scanline methods only, docs/formulas.md#scanline-emulation). The span's set-up in
//!    f32 (edge parameter, end points, the pixel's fraction of the span) rounds on window
//!    coordinates of size up to `S`, as if the pixel and each corner were off by `K_SPAN * u * S`
//!    in x and y; the twin evaluated with each moved that far bounds the effect (jumps at segment
//!    boundaries included).
//! 4. Corner normals (methods that read them: the scanline methods). Their f32 formulas do
//!    arithmetic on the unit corner normals themselves (the span ends' normals, Bishop-Weimer's
//!    plane fit `N = A x + B y + C` and its Taylor coefficients), rounding as if each corner
//!    normal's components were off by `K_FORMULA * u`; the twin evaluated with each component
//!    moved that far each way bounds the effect, like 3. Item 2 alone takes a colour-only
//!    method's cosine to be off by `K_FORMULA * u` absolutely, which holds for cosines of unit
//!    size but not for Bishop-Weimer's, whose Taylor coefficients grow as `1/|C|^5` when the
//!    normal at the centroid `C` is short (nearly opposite corner normals): there the f32
//!    rounding of `C` (absolute, about `u`) is a large relative error (`random_normals` and
//!    `opposite_normals` meshes, tests/software/stress_meshes.rs).
//!
//! The constants are few and each is stated below with its reason. The measured error/bound
//! ratios (`shadelab verify`, tests/gpu.rs) show how much margin they leave.
//!
//! # The float16 bound ([`evaluate_at`] with [`Precision::F16`], docs/float16-twin.md)
//! The same derivation with the method and the lighting computed in binary16 (u = 2^-11,
//! [`Precision::unit_roundoff`]) while the rasterizer stays float32: term 1 (interpolation,
//! `dw` with the f32 `U`) and term 3 (the span's window positions, f32) are unchanged; term 2
//! becomes, per rounding, `u |x| + ETA16` (ETA16 = 2^-25, half the spacing of binary16's
//! subnormals: the absolute error a rounding can make below 2^-14, where relative error is not
//! bounded) and counts what float32 left implicit:
//! - the normal: `(K_FORMULA + 1)` roundings (the +1 converts the interpolated f32 varying to
//!   f16 where the shader reads it);
//! - each cosine N.L: the normal's error through L (`sqrt(3) rn`) and `K_DOT` = 4 roundings of
//!   the dot product and of L's conversion;
//! - `pow = exp2(n log2 s)` in f16 (three roundings, plus the conversion of n): relative error
//!   `u (1 + 2 |ln s^n|) + u |ln s^n|`, and `s^n |ln s^n| <= 1/e`, so at most
//!   `u (s^n + 3/e)` absolute;
//! - the sums and products of the lighting and the conversion of its uniforms: `K_LIGHT` = 9
//!   roundings of the colour's size;
//! - term 4 (corner normals, scanline methods) with u = 2^-11: the unit corner normals are
//!   converted to f16 where the shader reads them and the span ends, Bishop-Weimer's plane fit
//!   and Taylor coefficients are f16 arithmetic on them (`K_FORMULA * u` per component).
//!
//! These are first-order; the terms that are not linear in u are flagged, not bounded: a
//! squared length above 65504 (|N| above 256, or two components above 181) overflows to inf in
//! f16, and the pixel then comes out NaN, zero or inf where the f64 value is finite: counted as
//! `non_finite` (a failure) or as an error far above the bound, never as zero error. A value
//! whose f64 itself exceeds binary16's range is counted as `overflow` ([`TruthPixel::exceeds`]).
pub mod agreement;
mod values;

pub use agreement::*;
pub use values::*;

use glam::{DVec2, DVec3};

use crate::frame::IdFrame;
use crate::method::formulas::Lighting;
use crate::method::{Fragment, Input, Method, Precision, Shaded};
use crate::scene::Interpolation;
use crate::scene::SceneInputs;

/// f32 unit roundoff.
pub const U: f64 = 1.0 / 16_777_216.0;
/// Roundings per plane-equation evaluation and set-up (2 for a0 + dadx x + dady y, 2 for a0).
pub const K_INTERP: f64 = 4.0;
/// Roundings a method's f32 formula may accumulate on its normal (the longest formulas here,
/// the quadratic triangles and the PN field, have about 30 operations; errors add in quadrature
/// in practice, linearly in the worst case of this budget).
pub const K_FORMULA: f64 = 32.0;
/// Relative error budget of lavapipe's `pow` = exp2(n log2 s); Mesa's gallivm approximations
/// are minimax polynomials good to a few 1e-7 relative.
pub const POW_REL: f64 = 2e-6;
/// Central-difference step in the weights (f64: truncation ~h^2, cancellation ~1e-16/h).
const FD_STEP: f64 = 1e-7;
/// Roundings in a scanline method's span set-up (docs/formulas.md#scanline-emulation: the edge
/// parameter u 2, the span end x 3, the pixel's fraction t 2, one spare), each on window
/// coordinates of size up to `S` (the largest |coordinate| of the pixel and the corners): the span
/// behaves as if the pixel were off by up to `K_SPAN * U * S` in x and in y.
pub const K_SPAN: f64 = 8.0;
/// Half the spacing of binary16's subnormals (2^-25): the absolute error one f16 rounding can
/// make below the smallest normal 2^-14, where the relative bound u does not hold.
pub const ETA16: f64 = 1.0 / 33_554_432.0;
/// Roundings of one f16 cosine N.L: three products and two sums (gamma_3 ~ 3u) and the
/// conversion of L to f16.
pub const K_DOT: f64 = 4.0;
/// Roundings of the f16 lighting's sums and products per channel (diffuse x d, specular x sp,
/// their sum, colour x it, the running sum) and of the conversion of its uniforms (ambient,
/// diffuse, specular, light colour).
pub const K_LIGHT: f64 = 9.0;

/// Weight uncertainty (`K_INTERP * U * amplification`) above which a pixel counts as
/// ill-conditioned: its triangle is so thin on screen (typically a silhouette triangle seen
/// edge-on) that the rasterizer's float32 weights are uncertain by more than 1e-3, and the
/// agreement check is weak there.
pub const ILL_CONDITIONED: f64 = 1e-3;

/// The f64 evaluation of one method over a frame.
#[derive(Clone)]
pub struct Truth {
    pub width: u32,
    pub height: u32,
    /// Per pixel: `None` on the background.
    pub pixels: Vec<Option<TruthPixel>>,
}

/// One covered pixel of the truth.
#[derive(Debug, Clone, Copy)]
pub struct TruthPixel {
    pub color: DVec3,
    /// The shading normal, for methods that have one.
    pub normal: Option<DVec3>,
    /// The float32 bound on |GPU colour - f64 colour| (any channel) derived in the module doc.
    pub color_bound: f64,
    /// The bound on |GPU normal - f64 normal| (any component).
    pub normal_bound: f64,
    /// `1 + g * r` of the module doc (doubled for perspective): how much this pixel's triangle
    /// amplifies interpolation rounding. Any weight is off by at most `K_INTERP * U * amplification`.
    pub amplification: f64,
}

impl TruthPixel {
    /// Whether the rasterizer's weights at this pixel are uncertain by more than
    /// [`ILL_CONDITIONED`].
    pub fn ill_conditioned(&self) -> bool {
        K_INTERP * U * self.amplification > ILL_CONDITIONED
    }

    /// What the statistics read of this pixel.
    pub fn value(&self) -> RefPixel {
        RefPixel {
            color: self.color,
            normal: self.normal,
            ill_conditioned: self.ill_conditioned(),
        }
    }

    /// Whether the f64 colour or normal lies outside the range of f32.
    pub fn exceeds_f32(&self) -> bool {
        self.exceeds(Precision::F32)
    }

    /// Whether the f64 colour or normal lies outside the range of `precision` (f32: 3.4e38,
    /// f16: 65504).
    pub fn exceeds(&self, precision: Precision) -> bool {
        let max = match precision {
            Precision::F32 => f32::MAX as f64,
            Precision::F16 => half::f16::MAX.to_f64(),
        };
        let big = |v: DVec3| !v.is_finite() || v.abs().max_element() > max;
        big(self.color) || self.normal.is_some_and(big)
    }
}

/// Window-space corners of every triangle, from the uploaded positions and MVP (in f64).
fn window_corners(inputs: &SceneInputs) -> Vec<DVec2> {
    inputs.clip_corners().map(|c| inputs.to_window(c)).collect()
}

/// `g` of the module doc for one triangle: sum of |grad w_j| in 1/pixels.
fn weight_gradient(s: [DVec2; 3]) -> f64 {
    let area2 = (s[1] - s[0]).perp_dot(s[2] - s[0]).abs();
    if area2 <= 0.0 {
        return f64::INFINITY;
    }
    // |grad w_j| = |opposite edge| / (2 * area).
    (0..3)
        .map(|j| (s[(j + 2) % 3] - s[(j + 1) % 3]).length() / area2)
        .sum()
}

/// Largest channel / component of |a - b|.
pub(crate) fn max_diff(a: DVec3, b: DVec3) -> f64 {
    (a - b).abs().max_element()
}

/// `n s^(n-1)`: how much the specular term moves per unit change of `s = N.H`.
fn specular_slope(n: f64, s: f64) -> f64 {
    if n >= 1.0 {
        n * s.powf(n - 1.0)
    } else {
        n * s.max(1e-6).powf(n - 1.0)
    }
}

/// Evaluates `method` in f64 at every covered pixel of `ids`, with the per-pixel float32 bound.
pub fn evaluate(inputs: &SceneInputs, ids: &IdFrame, method: &Method) -> Truth {
    evaluate_at(inputs, ids, method, Precision::F32)
}

/// [`evaluate`] with the bound of a program computing in `precision` (the float16 bound of the
/// module doc for [`Precision::F16`]).
pub fn evaluate_at(
    inputs: &SceneInputs,
    ids: &IdFrame,
    method: &Method,
    precision: Precision,
) -> Truth {
    let pixel = evaluator(inputs, ids, method, Some(precision));
    Truth {
        width: ids.width,
        height: ids.height,
        pixels: (0..ids.prim.len()).map(pixel).collect(),
    }
}

/// `method` in f64 at every covered pixel of `ids` as a reference for statistics only: the
/// float32 bounds are not computed (which saves the twin's extra evaluations per pixel) and
/// not stored; the conditioning is, as a flag (see [`Values`]).
pub fn values(inputs: &SceneInputs, ids: &IdFrame, method: &Method) -> Values {
    let pixel = evaluator(inputs, ids, method, None);
    let mut v = Values::with_capacity(ids.width, ids.height, ids.covered());
    for i in 0..ids.prim.len() {
        v.push(pixel(i).as_ref());
    }
    v
}

/// The truth at pixel `i` of `ids` (`None` on the background); the bounds (of a program in
/// `bounds`' precision) are NaN when `bounds` is `None`.
fn evaluator<'a>(
    inputs: &'a SceneInputs,
    ids: &'a IdFrame,
    method: &'a Method,
    bounds: Option<Precision>,
) -> impl Fn(usize) -> Option<TruthPixel> + 'a {
    let lighting = inputs.lighting();
    let corners = window_corners(inputs);
    let perspective = inputs.interpolation == Interpolation::Perspective;
    let scanline = method.inputs.contains(&Input::ScanlineSpan);
    move |i| {
        let eval = |frag: &Fragment| method.eval_f64(frag, &lighting);
        let prim = ids.prim[i];
        if prim == 0 {
            return None;
        }
        let w = ids.weights[i];
        let t = (prim - 1) as usize;
        let (x, y) = ((i as u32 % ids.width) as f64, (i as u32 / ids.width) as f64);
        let weights = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
        let frag = inputs.fragment(t, weights, DVec2::new(x + 0.5, y + 0.5));
        let shaded = eval(&frag);
        let g = weight_gradient([corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]]);
        let amplification = (1.0 + g * (x + y + 2.0)) * if perspective { 2.0 } else { 1.0 };
        let (mut color_bound, mut normal_bound) = match bounds {
            Some(p) => bound(&eval, &frag, &shaded, &lighting, amplification, p),
            None => (f64::NAN, f64::NAN),
        };
        if scanline && bounds.is_some() {
            let (c, n) = span_bound(&eval, &frag);
            let (cc, cn) = corner_normal_bound(&eval, &frag, precision_u(bounds));
            color_bound += c + cc;
            normal_bound += n + cn;
        }
        Some(TruthPixel {
            color: shaded.color,
            normal: shaded.normal,
            color_bound,
            normal_bound,
            amplification,
        })
    }
}

/// The extra bound of a scanline method at one pixel: the span set-up's rounding moves the pixel
/// by up to `K_SPAN * U * S` in x and y ([`K_SPAN`]), and each corner likewise. The twin is
/// evaluated with the pixel or one corner moved that far each way (not differentiated: the segment and dichotomy methods quantise the
/// span, and a step across a segment boundary is a jump a derivative would miss); the largest
/// change per axis, summed over the axes and doubled for the curvature a two-point look misses.
fn span_bound(eval: &dyn Fn(&Fragment) -> Shaded, frag: &Fragment) -> (f64, f64) {
    let size = frag
        .window
        .iter()
        .chain([&frag.pixel])
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let dpos = K_SPAN * U * size;
    let here = eval(frag);
    let (mut dc, mut dn) = (0.0, 0.0);
    // The pixel, and each corner on its own (the two span ends round independently, and on a
    // sliver row their independent errors do not cancel as a common shift would).
    for point in 0..4 {
        for d in [DVec2::X, DVec2::Y] {
            let (c, n) = largest_change(eval, frag, &here, |moved, k| match point {
                3 => moved.pixel += d * (k * dpos),
                corner => moved.window[corner] += d * (k * dpos),
            });
            dc += c;
            dn += n;
        }
    }
    (2.0 * dc, 2.0 * dn)
}

/// The largest change of the colour and of the normal (max component) from `here` when `frag`
/// is moved each way (`step` applies a move with sign k = -1, then +1).
fn largest_change(
    eval: &dyn Fn(&Fragment) -> Shaded,
    frag: &Fragment,
    here: &Shaded,
    step: impl Fn(&mut Fragment, f64),
) -> (f64, f64) {
    let (mut c, mut n) = (0.0f64, 0.0f64);
    for k in [-1.0, 1.0] {
        let mut moved = *frag;
        step(&mut moved, k);
        let moved = eval(&moved);
        c = c.max(max_diff(moved.color, here.color));
        if let (Some(a), Some(b)) = (moved.normal, here.normal) {
            n = n.max(max_diff(a, b));
        }
    }
    (c, n)
}

/// The unit roundoff of the program's arithmetic (`bounds` is `Some` where this is asked).
fn precision_u(bounds: Option<Precision>) -> f64 {
    bounds.map_or(U, Precision::unit_roundoff)
}

/// Item 4 of the module doc at one pixel: each corner normal's components moved by
/// `K_FORMULA * u` each way (u of the precision the method's arithmetic runs in: the corner
/// normals are converted to it where read), one at a time; the largest change per component,
/// summed.
fn corner_normal_bound(eval: &dyn Fn(&Fragment) -> Shaded, frag: &Fragment, u: f64) -> (f64, f64) {
    let here = eval(frag);
    let (mut dc, mut dn) = (0.0, 0.0);
    for corner in 0..3 {
        for axis in 0..3 {
            let (c, n) = largest_change(eval, frag, &here, |moved, k| {
                moved.corner_normals[corner][axis] += k * K_FORMULA * u
            });
            dc += c;
            dn += n;
        }
    }
    (dc, dn)
}

/// The bounds of the module doc at one pixel.
fn bound(
    eval: &dyn Fn(&Fragment) -> Shaded,
    frag: &Fragment,
    shaded: &Shaded,
    lighting: &Lighting,
    amplification: f64,
    precision: Precision,
) -> (f64, f64) {
    // 1. interpolation: sum_j |dC/dw_j| and |dN/dw_j| by central differences
    let (mut jc, mut jn) = (0.0, 0.0);
    for j in 0..3 {
        let mut step = DVec3::ZERO;
        step[j] = FD_STEP;
        let plus = eval(&Fragment {
            weights: frag.weights + step,
            ..*frag
        });
        let minus = eval(&Fragment {
            weights: frag.weights - step,
            ..*frag
        });
        jc += max_diff(plus.color, minus.color) / (2.0 * FD_STEP);
        if let (Some(a), Some(b)) = (plus.normal, minus.normal) {
            jn += max_diff(a, b) / (2.0 * FD_STEP);
        }
    }
    let dw = K_INTERP * U * amplification;
    // 2. arithmetic of the method's formula and of the lighting
    if precision == Precision::F16 {
        let (dc, rn) = arithmetic_f16(shaded, lighting);
        return (2.0 * dw * jc + dc, 2.0 * dw * jn + rn);
    }
    let (rn, s_of) = match shaded.normal {
        Some(n) => (K_FORMULA * U * n.length().max(1.0), Some(n)),
        None => (K_FORMULA * U, None),
    };
    let mut dc = 8.0 * U;
    for &(_, color, h) in lighting.lights() {
        // colour-only methods light unit vertex normals somewhere: take the worst s = 1
        let s = s_of.map(|n| n.dot(h).clamp(0.0, 1.0)).unwrap_or(1.0);
        let spec =
            specular_slope(lighting.shininess, s) * rn + POW_REL * s.powf(lighting.shininess);
        dc += (color * (lighting.diffuse * rn + lighting.specular * spec)).max_element();
    }
    (2.0 * dw * jc + dc, 2.0 * dw * jn + rn)
}

/// Term 2 of the float16 bound (module doc): (colour bound, normal bound) of the method's f16
/// formula and the f16 lighting at one pixel.
fn arithmetic_f16(shaded: &Shaded, lighting: &Lighting) -> (f64, f64) {
    let u = Precision::F16.unit_roundoff();
    let size = shaded.normal.map_or(1.0, |n| n.length().max(1.0));
    let one = u * size + ETA16;
    let rn = (K_FORMULA + 1.0) * one;
    let cosine = 3f64.sqrt() * rn + K_DOT * one;
    let n = lighting.shininess;
    let mut magnitude = lighting.ambient.max_element();
    let mut dc = 0.0;
    for &(_, color, h) in lighting.lights() {
        let s = shaded
            .normal
            .map(|v| v.dot(h).clamp(0.0, 1.0))
            .unwrap_or(1.0);
        let sn = s.powf(n);
        let spec = specular_slope(n, s) * cosine
            + u * (sn + 3.0 / std::f64::consts::E)
            + ETA16
            + POW_REL * sn;
        dc += (color * (lighting.diffuse * cosine + lighting.specular * spec)).max_element();
        magnitude += (color * (lighting.diffuse + lighting.specular)).max_element();
    }
    (dc + K_LIGHT * (u * magnitude.max(1.0) + ETA16), rn)
}
