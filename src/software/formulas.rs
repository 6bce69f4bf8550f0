//! The formulas of [`crate::method::formulas`] and [`crate::method::scanline`] in the engine's
//! scalar `S` ([`Real`]: f32, or f16 for the float16 twin), for the software engine: each is
//! the twin of the f64 function of the same name (and of its GLSL twin), with the same
//! constants (rounded to `S`), branches and thresholds, so that the software image and the f64
//! twin differ by rounding (and, for the incremental forms of [`super::spans`], by the drift of
//! their recurrences). Window positions (the span's ends and the pixel's fraction t) stay f32
//! in both precisions, as the rasterizer's; the normals, cosines and colours are in `S`.
//! Nothing here allocates.
use glam::{Vec2, Vec3};

use super::real::{c, Real, V3};
use crate::scene::{Params, MAX_LIGHTS};

/// Twin of `formulas::normalize_exact`: `n / |n|`, the input unchanged at zero length.
#[inline(always)]
pub fn normalize_exact<S: Real>(n: V3<S>) -> V3<S> {
    let len = n.dot(n).sqrt();
    if len > S::ZERO {
        n / len
    } else {
        n
    }
}

/// The lighting as uploaded, read in `S`: twin of `formulas::Lighting`. Cosine `2i` is
/// `N.L_i`, cosine `2i + 1` is `N.H_i` ([`Lighting::dirs`]).
#[derive(Debug, Clone, Copy)]
pub struct Lighting<S> {
    pub ambient: V3<S>,
    pub diffuse: V3<S>,
    pub specular: V3<S>,
    pub shininess: S,
    pub count: usize,
    pub colors: [V3<S>; MAX_LIGHTS],
    /// L_0, H_0, L_1, H_1, ...
    pub dirs: [V3<S>; 2 * MAX_LIGHTS],
}

/// The float32 lighting (the shipped engine).
pub type Lighting32 = Lighting<f32>;

fn v3<S: Real>(v: [f32; 4]) -> V3<S> {
    V3::of(Vec3::new(v[0], v[1], v[2]))
}

impl<S: Real> Lighting<S> {
    /// The uniform block's lighting, `count` lights, each value rounded to `S` where read.
    pub fn new(p: &Params, count: u32) -> Self {
        let count = (count as usize).min(MAX_LIGHTS);
        let mut dirs = [V3::zero(); 2 * MAX_LIGHTS];
        let mut colors = [V3::zero(); MAX_LIGHTS];
        for i in 0..count {
            dirs[2 * i] = v3(p.light_dir[i]);
            dirs[2 * i + 1] = v3(p.half_vec[i]);
            colors[i] = v3(p.light_color[i]);
        }
        Lighting {
            ambient: v3(p.ambient),
            diffuse: v3(p.diffuse),
            specular: v3(p.specular),
            shininess: S::of(p.specular[3]),
            count,
            colors,
            dirs,
        }
    }

    /// Number of cosines a pixel needs (L and H per light).
    pub fn cosines(&self) -> usize {
        2 * self.count
    }

    /// Twin of `Lighting::shade` (glsl/shading.glsl `shade`).
    #[inline(always)]
    pub fn shade(&self, n: V3<S>) -> V3<S> {
        self.shade_cosines(|k| n.dot(self.dirs[k]))
    }

    /// Twin of `Lighting::shade_cosines`: `cosine(2i)` is N.L_i, `cosine(2i + 1)` is N.H_i.
    #[inline(always)]
    pub fn shade_cosines(&self, cosine: impl Fn(usize) -> S) -> V3<S> {
        let mut c = self.ambient;
        for i in 0..self.count {
            let d = cosine(2 * i).max(S::ZERO);
            let s = cosine(2 * i + 1).max(S::ZERO);
            let sp = if s > S::ZERO {
                s.powf(self.shininess)
            } else {
                S::ZERO
            };
            c += self.colors[i] * (self.diffuse * d + self.specular * sp);
        }
        c
    }
}

// Scalar factors k(z) ~ 1/sqrt(z) (docs/formulas.md#newton-raphson-step,
// docs/formulas.md#lyon-taylor-form, docs/formulas.md#lyon-shift-form,
// docs/formulas.md#mikami-square-root, docs/formulas.md#romanyuk-romanyuk-pavlyk-polynomial).

pub fn k_newton<S: Real>(z: S) -> S {
    c::<S>(0.5) * (c::<S>(3.0) - z)
}

pub fn k_lyon2<S: Real>(z: S) -> S {
    let d = z - S::ONE;
    S::ONE - c::<S>(0.5) * d + c::<S>(0.375) * d * d
}

pub fn k_lyon_shift<S: Real>(z: S) -> S {
    let e = S::ONE - z;
    S::ONE + c::<S>(0.5) * (e + e * e)
}

pub fn k_romanyuk<S: Real>(z: S) -> S {
    (c::<S>(0.822) * z - c::<S>(2.046)) * z + c::<S>(2.227)
}

/// Twin of `formulas::safe_normalize_factor` (Unity's SafeNormalize, issue 23).
pub fn k_safe<S: Real>(z: S) -> S {
    S::ONE
        / z.max(c::<S>(crate::method::formulas::HALF_MIN as f32))
            .sqrt()
}

/// Twin of `formulas::filament_clamp_factor` (Filament's saturateMediump, issue 23).
pub fn k_clamp<S: Real>(z: S) -> S {
    S::ONE
        / z.min(c::<S>(crate::method::formulas::MEDIUMP_FLT_MAX as f32))
            .sqrt()
}

pub fn mikami_sqrt<S: Real>(z: S, beta: S) -> S {
    let s0 = c::<S>(2.0 / 3.0) * z + c::<S>(0.35);
    beta * (z - s0 * s0) + s0
}

pub fn beta_const<S: Real>(_z: S) -> S {
    c(0.64)
}

pub fn beta_linear<S: Real>(z: S) -> S {
    c::<S>(1.07) - c::<S>(0.62) * z
}

pub fn beta_quadratic<S: Real>(z: S) -> S {
    (c::<S>(0.763) * z - c::<S>(1.57)) * z + c::<S>(1.31)
}

/// Twin of `formulas::hbb`.
#[inline(always)]
pub fn hbb<S: Real>(n_interp: V3<S>, n_flat: V3<S>) -> V3<S> {
    let h = n_flat + n_interp;
    h * c::<S>(2.0) * (h.dot(n_flat) / h.dot(h)) - n_flat
}

/// Twin of `formulas::quat_from_normal`.
pub fn quat_from_normal<S: Real>(n: V3<S>) -> V3<S> {
    let z = (c::<S>(0.5) * (n.z + S::ONE)).sqrt();
    let two = c::<S>(2.0);
    V3::new(n.x / (two * z), n.y / (two * z), z)
}

/// Twin of `formulas::normal_from_quat`.
#[inline(always)]
pub fn normal_from_quat<S: Real>(q: V3<S>) -> V3<S> {
    let two = c::<S>(2.0);
    V3::new(
        two * q.x * q.z,
        two * q.y * q.z,
        q.z * q.z - q.x * q.x - q.y * q.y,
    ) / q.dot(q)
}

/// Twin of `formulas::onb`.
pub fn onb<S: Real>(n: V3<S>) -> (V3<S>, V3<S>) {
    let s = S::ONE.copysign(n.z);
    let a = -S::ONE / (s + n.z);
    let b0 = n.x * n.y * a;
    let t = V3::new(S::ONE + s * n.x * n.x * a, s * b0, -s * n.x);
    let b = V3::new(b0, s + n.y * n.y * a, -n.y);
    (t, b)
}

/// Twin of `formulas::mid_poly`.
pub fn mid_poly<S: Real>(x: S) -> S {
    (c::<S>(0.103) * x - c::<S>(0.306)) * x + c::<S>(0.705)
}

/// Twin of `formulas::m_ij`.
pub fn m_ij<S: Real>(a: V3<S>, b: V3<S>) -> V3<S> {
    (a + b) * c::<S>(4.0) * mid_poly(a.dot(b))
}

/// Twin of `formulas::m_ij_exact`.
pub fn m_ij_exact<S: Real>(a: V3<S>, b: V3<S>) -> V3<S> {
    normalize_exact(a + b) * c::<S>(4.0)
}

/// Twin of `formulas::bary_quad` with the mid-edge nodes precomputed per triangle
/// (`mids = [mid(n0, n1), mid(n1, n2), mid(n2, n0)]`).
#[inline(always)]
pub fn bary_quad<S: Real>(n: &[V3<S>; 3], mids: &[V3<S>; 3], w: V3<S>) -> V3<S> {
    let two = c::<S>(2.0);
    n[0] * (w.x * (two * w.x - S::ONE))
        + n[1] * (w.y * (two * w.y - S::ONE))
        + n[2] * (w.z * (two * w.z - S::ONE))
        + mids[0] * (w.x * w.y)
        + mids[1] * (w.y * w.z)
        + mids[2] * (w.z * w.x)
}

/// Twin of `formulas::pn_normal`.
#[inline(always)]
pub fn pn_normal<S: Real>(n: &[V3<S>; 3], mids: &[V3<S>; 3], w: V3<S>) -> V3<S> {
    n[0] * (w.x * w.x)
        + n[1] * (w.y * w.y)
        + n[2] * (w.z * w.z)
        + mids[0] * (w.x * w.y)
        + mids[1] * (w.y * w.z)
        + mids[2] * (w.z * w.x)
}

/// Twin of `formulas::lut_lookup` (glsl/methods/specular_lut.glsl `lutLookup`). The table is
/// read like a texture: the coordinates in f32 from the cosine `s`, the sample rounded to `S`.
#[inline(always)]
pub fn lut_lookup<S: Real>(table: &[f32], rows: usize, samples: usize, n: S, s: S) -> S {
    let (n, s) = (n.f32(), s.f32());
    if s.is_nan() || s <= 0.0 {
        return S::ZERO;
    }
    let row = ((n + 0.5).floor().clamp(1.0, rows as f32) as usize) - 1;
    let f = s.min(1.0) * (samples - 1) as f32;
    let i0 = (f.floor() as usize).min(samples - 2);
    let t = f - i0 as f32;
    let base = row * samples + i0;
    S::of(table[base] * (1.0 - t) + table[base + 1] * t)
}

// ---------------------------------------------------------------------------------------------
// The scanline family (twins of src/method/scanline.rs and glsl/scanline.glsl)
// ---------------------------------------------------------------------------------------------

/// Twin of `scanline::Span`: the ends' x in f32 (window positions), their normals in `S`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span<S> {
    pub xa: f32,
    pub na: V3<S>,
    pub xb: f32,
    pub nb: V3<S>,
}

/// Twin of `scanline::span_at` (row `py` clamped to the triangle's rows): the edge parameter
/// and the ends' x in f32, the ends' normals interpolated in `S`.
pub fn span_at<S: Real>(py: f32, s: &[Vec2; 3], nv: &[Vec3; 3]) -> Span<S> {
    let lo = s[0].y.min(s[1].y.min(s[2].y));
    let hi = s[0].y.max(s[1].y.max(s[2].y));
    let py = py.clamp(lo, hi);
    let nv = nv.map(V3::<S>::of);
    let mut sp = Span {
        xa: 1e30,
        na: nv[0],
        xb: -1e30,
        nb: nv[0],
    };
    for e in 0..3 {
        let (p, q) = (s[e], s[(e + 1) % 3]);
        if p.y == q.y {
            continue;
        }
        let u = (py - p.y) / (q.y - p.y);
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let x = p.x * (1.0 - u) + q.x * u;
        let us = S::of(u);
        let n = nv[e] * (S::ONE - us) + nv[(e + 1) % 3] * us;
        if x < sp.xa {
            sp.xa = x;
            sp.na = n;
        }
        if x > sp.xb {
            sp.xb = x;
            sp.nb = n;
        }
    }
    if sp.xa > sp.xb {
        sp.xa = s[0].x;
        sp.xb = s[0].x;
    }
    sp
}

/// Twin of `scanline::span_t`.
#[inline(always)]
pub fn span_t<S>(sp: &Span<S>, px: f32) -> f32 {
    if sp.xb > sp.xa {
        ((px - sp.xa) / (sp.xb - sp.xa)).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Twin of `scanline::PARALLEL` (glsl/scanline.glsl `BY_PRECISION(1e-8, 0.001953125)`: 1e-8 is
/// below float16's range and would round to 0, making parallel span ends divide 0 by 0).
pub const PARALLEL: f32 = 1e-8;
/// The float16 value of [`PARALLEL`] (2^-9).
pub const PARALLEL_F16: f32 = 0.001953125;

/// [`PARALLEL`] in the precision of `S`.
fn parallel<S: Real>() -> S {
    match S::PRECISION {
        crate::method::Precision::F32 => S::of(PARALLEL),
        crate::method::Precision::F16 => S::of(PARALLEL_F16),
    }
}

/// `(c, sin theta, theta)` of unit `a`, `b` (glsl/scanline.glsl `angleBetween`: acos refined by
/// one Newton step on sin), or `None` within [`PARALLEL`] of parallel or antipodal.
pub fn angle<S: Real>(a: V3<S>, b: V3<S>) -> Option<(S, S, S)> {
    let c = a.dot(b).clamp(-S::ONE, S::ONE);
    let s2 = S::ONE - c * c;
    if s2 < parallel::<S>() {
        return None;
    }
    let s = s2.sqrt();
    let t0 = c.acos();
    Some((c, s, t0 + (s * t0.cos() - c * t0.sin())))
}

/// Twin of `scanline::slerp`.
#[inline(always)]
pub fn slerp<S: Real>(a: V3<S>, b: V3<S>, t: S) -> V3<S> {
    match angle(a, b) {
        Some((_, s, th)) => (a * ((S::ONE - t) * th).sin() + b * (t * th).sin()) / s,
        None => normalize_exact(a * (S::ONE - t) + b * t),
    }
}

/// Twin of `scanline::spherical_angular` (the closed form; the software engine seeds its
/// recurrence with it).
pub fn spherical_angular<S: Real>(a: V3<S>, b: V3<S>, t: S) -> V3<S> {
    match angle(a, b) {
        Some((c, s, th)) => a * (t * th).cos() + (b - a * c) * ((t * th).sin() / s),
        None => normalize_exact(a * (S::ONE - t) + b * t),
    }
}

/// Twin of `scanline::mid_approx`.
pub fn mid_approx<S: Real>(nl: V3<S>, np: V3<S>) -> V3<S> {
    let x = nl.dot(np);
    (nl + np) * ((c::<S>(0.103) * x - c::<S>(0.306)) * x + c::<S>(0.705))
}

/// Twin of `scanline::mid_exact`.
pub fn mid_exact<S: Real>(nl: V3<S>, np: V3<S>) -> V3<S> {
    normalize_exact(nl + np)
}

/// Twin of `scanline::inv_root_exact`.
pub fn inv_root_exact<S: Real>(z: S) -> S {
    S::ONE / (c::<S>(2.0) + z).sqrt()
}

/// Twin of `scanline::inv_root_poly1`.
pub fn inv_root_poly1<S: Real>(z: S) -> S {
    c::<S>(0.64) - c::<S>(0.07) * z
}

/// Twin of `scanline::inv_root_poly2`.
pub fn inv_root_poly2<S: Real>(z: S) -> S {
    (c::<S>(0.014253) * z - c::<S>(0.118922)) * z + c::<S>(0.680850)
}

/// Twin of `scanline::levels`.
pub fn levels(width: f32) -> u32 {
    let mut k = 1;
    while k < crate::method::scanline::MAX_LEVELS && ((1u32 << k) as f32) < width {
        k += 1;
    }
    k
}

/// Twin of `scanline::span_normal`.
#[inline(always)]
pub fn span_normal<S: Real>(sp: &Span<S>, x: f32) -> V3<S> {
    if sp.xb > sp.xa {
        sp.na + (sp.nb - sp.na) * S::of((x - sp.xa) / (sp.xb - sp.xa))
    } else {
        sp.na
    }
}

/// Twin of `scanline::plane_normal`: (A, B, C, o), the gradients in `S` from f32 positions.
pub fn plane_normal<S: Real>(s: &[Vec2; 3], n: &[Vec3; 3]) -> (V3<S>, V3<S>, V3<S>, Vec2) {
    let o = (s[0] + s[1] + s[2]) / 3.0;
    let q0 = s[0] - o;
    let (e1, e2) = (s[1] - s[0], s[2] - s[0]);
    let det = e1.x * e2.y - e1.y * e2.x;
    let n = n.map(V3::<S>::of);
    let (a, b) = if det.abs() > 1e-12 {
        let d = S::of(det);
        let (e1, e2) = (e1.to_array().map(S::of), e2.to_array().map(S::of));
        (
            ((n[1] - n[0]) * e2[1] - (n[2] - n[0]) * e1[1]) / d,
            ((n[2] - n[0]) * e1[0] - (n[1] - n[0]) * e2[0]) / d,
        )
    } else {
        (V3::zero(), V3::zero())
    };
    (a, b, n[0] - a * S::of(q0.x) - b * S::of(q0.y), o)
}

/// The Taylor coefficients T0..T5 of `scanline::taylor_cosine` for the cosine with `v`.
pub fn taylor_terms<S: Real>(v: V3<S>, a3: V3<S>, b3: V3<S>, c3: V3<S>) -> [S; 6] {
    let (two, three, four, eight) = (c::<S>(2.0), c::<S>(3.0), c::<S>(4.0), c::<S>(8.0));
    let (a, b, c) = (v.dot(a3), v.dot(b3), v.dot(c3));
    let (d, e, f) = (a3.dot(a3), two * a3.dot(b3), b3.dot(b3));
    let (g, h, i) = (two * a3.dot(c3), two * b3.dot(c3), c3.dot(c3));
    let si = i.sqrt();
    [
        c / si,
        (two * b * i - c * h) / (two * i * si),
        (two * a * i - c * g) / (two * i * si),
        (three * c * h * h - four * c * f * i - four * b * h * i) / (eight * i * i * si),
        (three * c * g * h - two * c * e * i - two * b * g * i - two * a * h * i)
            / (four * i * i * si),
        (three * c * g * g - four * c * d * i - four * a * g * i) / (eight * i * i * si),
    ]
}

/// Twin of `scanline::cosine_slope`: dI/dt of `v.N/|N|` at N with `dN/dt = D`.
pub fn cosine_slope<S: Real>(v: V3<S>, n: V3<S>, d: V3<S>) -> S {
    let n2 = n.dot(n);
    let len = n2.sqrt();
    v.dot(d) / len - v.dot(n) * n.dot(d) / (n2 * len)
}
