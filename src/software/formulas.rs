//! The formulas of [`crate::method::formulas`] and [`crate::method::scanline`] in f32, for the
//! software engine: each is the f32 twin of the f64 function of the same name (and of its GLSL
//! twin), with the same constants, branches and thresholds, so that the software image and the
//! f64 twin differ by rounding (and, for the incremental forms of [`super::spans`], by the
//! drift of their recurrences). Nothing here allocates.
use glam::{Vec2, Vec3};

use crate::scene::{Params, MAX_LIGHTS};

/// Twin of `formulas::normalize_exact`: `n / |n|`, the input unchanged at zero length.
#[inline(always)]
pub fn normalize_exact(n: Vec3) -> Vec3 {
    let len = n.dot(n).sqrt();
    if len > 0.0 {
        n / len
    } else {
        n
    }
}

/// The lighting as uploaded (f32), twin of `formulas::Lighting`. Cosine `2i` is `N.L_i`, cosine
/// `2i + 1` is `N.H_i` ([`Lighting32::dirs`]).
#[derive(Debug, Clone, Copy)]
pub struct Lighting32 {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub shininess: f32,
    pub count: usize,
    pub colors: [Vec3; MAX_LIGHTS],
    /// L_0, H_0, L_1, H_1, ...
    pub dirs: [Vec3; 2 * MAX_LIGHTS],
}

fn v3(v: [f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

impl Lighting32 {
    /// The uniform block's lighting, `count` lights.
    pub fn new(p: &Params, count: u32) -> Self {
        let count = (count as usize).min(MAX_LIGHTS);
        let mut dirs = [Vec3::ZERO; 2 * MAX_LIGHTS];
        let mut colors = [Vec3::ZERO; MAX_LIGHTS];
        for i in 0..count {
            dirs[2 * i] = v3(p.light_dir[i]);
            dirs[2 * i + 1] = v3(p.half_vec[i]);
            colors[i] = v3(p.light_color[i]);
        }
        Lighting32 {
            ambient: v3(p.ambient),
            diffuse: v3(p.diffuse),
            specular: v3(p.specular),
            shininess: p.specular[3],
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
    pub fn shade(&self, n: Vec3) -> Vec3 {
        self.shade_cosines(|k| n.dot(self.dirs[k]))
    }

    /// Twin of `Lighting::shade_cosines`: `cosine(2i)` is N.L_i, `cosine(2i + 1)` is N.H_i.
    #[inline(always)]
    pub fn shade_cosines(&self, cosine: impl Fn(usize) -> f32) -> Vec3 {
        let mut c = self.ambient;
        for i in 0..self.count {
            let d = cosine(2 * i).max(0.0);
            let s = cosine(2 * i + 1).max(0.0);
            let sp = if s > 0.0 { s.powf(self.shininess) } else { 0.0 };
            c += self.colors[i] * (self.diffuse * d + self.specular * sp);
        }
        c
    }
}

// Scalar factors k(z) ~ 1/sqrt(z) (FORMULAS.md 2.4-2.6, 2.8, 2.9).

pub fn k_newton(z: f32) -> f32 {
    0.5 * (3.0 - z)
}

pub fn k_lyon2(z: f32) -> f32 {
    let d = z - 1.0;
    1.0 - 0.5 * d + 0.375 * d * d
}

pub fn k_lyon_shift(z: f32) -> f32 {
    let e = 1.0 - z;
    1.0 + 0.5 * (e + e * e)
}

pub fn k_romanyuk(z: f32) -> f32 {
    (0.822 * z - 2.046) * z + 2.227
}

pub fn mikami_sqrt(z: f32, beta: f32) -> f32 {
    let s0 = (2.0 / 3.0) * z + 0.35;
    beta * (z - s0 * s0) + s0
}

pub fn beta_const(_z: f32) -> f32 {
    0.64
}

pub fn beta_linear(z: f32) -> f32 {
    1.07 - 0.62 * z
}

pub fn beta_quadratic(z: f32) -> f32 {
    (0.763 * z - 1.57) * z + 1.31
}

/// Twin of `formulas::hbb`.
#[inline(always)]
pub fn hbb(n_interp: Vec3, n_flat: Vec3) -> Vec3 {
    let h = n_flat + n_interp;
    2.0 * h * (h.dot(n_flat) / h.dot(h)) - n_flat
}

/// Twin of `formulas::quat_from_normal`.
pub fn quat_from_normal(n: Vec3) -> Vec3 {
    let z = (0.5 * (n.z + 1.0)).sqrt();
    Vec3::new(n.x / (2.0 * z), n.y / (2.0 * z), z)
}

/// Twin of `formulas::normal_from_quat`.
#[inline(always)]
pub fn normal_from_quat(q: Vec3) -> Vec3 {
    Vec3::new(
        2.0 * q.x * q.z,
        2.0 * q.y * q.z,
        q.z * q.z - q.x * q.x - q.y * q.y,
    ) / q.dot(q)
}

/// Twin of `formulas::onb`.
pub fn onb(n: Vec3) -> (Vec3, Vec3) {
    let s = 1.0f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b0 = n.x * n.y * a;
    let t = Vec3::new(1.0 + s * n.x * n.x * a, s * b0, -s * n.x);
    let b = Vec3::new(b0, s + n.y * n.y * a, -n.y);
    (t, b)
}

/// Twin of `formulas::mid_poly`.
pub fn mid_poly(c: f32) -> f32 {
    (0.103 * c - 0.306) * c + 0.705
}

/// Twin of `formulas::m_ij`.
pub fn m_ij(a: Vec3, b: Vec3) -> Vec3 {
    4.0 * (a + b) * mid_poly(a.dot(b))
}

/// Twin of `formulas::m_ij_exact`.
pub fn m_ij_exact(a: Vec3, b: Vec3) -> Vec3 {
    4.0 * normalize_exact(a + b)
}

/// Twin of `formulas::bary_quad` with the mid-edge nodes precomputed per triangle
/// (`mids = [mid(n0, n1), mid(n1, n2), mid(n2, n0)]`).
#[inline(always)]
pub fn bary_quad(n: &[Vec3; 3], mids: &[Vec3; 3], c: Vec3) -> Vec3 {
    n[0] * (c.x * (2.0 * c.x - 1.0))
        + n[1] * (c.y * (2.0 * c.y - 1.0))
        + n[2] * (c.z * (2.0 * c.z - 1.0))
        + mids[0] * (c.x * c.y)
        + mids[1] * (c.y * c.z)
        + mids[2] * (c.z * c.x)
}

/// Twin of `formulas::pn_normal`.
#[inline(always)]
pub fn pn_normal(n: &[Vec3; 3], mids: &[Vec3; 3], w: Vec3) -> Vec3 {
    n[0] * (w.x * w.x)
        + n[1] * (w.y * w.y)
        + n[2] * (w.z * w.z)
        + mids[0] * (w.x * w.y)
        + mids[1] * (w.y * w.z)
        + mids[2] * (w.z * w.x)
}

/// Twin of `formulas::lut_lookup` (glsl/methods/specular_lut.glsl `lutLookup`).
#[inline(always)]
pub fn lut_lookup(table: &[f32], rows: usize, samples: usize, n: f32, s: f32) -> f32 {
    if s.is_nan() || s <= 0.0 {
        return 0.0;
    }
    let row = ((n + 0.5).floor().clamp(1.0, rows as f32) as usize) - 1;
    let f = s.min(1.0) * (samples - 1) as f32;
    let i0 = (f.floor() as usize).min(samples - 2);
    let t = f - i0 as f32;
    let base = row * samples + i0;
    table[base] * (1.0 - t) + table[base + 1] * t
}

// ---------------------------------------------------------------------------------------------
// The scanline family (twins of src/method/scanline.rs and glsl/scanline.glsl)
// ---------------------------------------------------------------------------------------------

/// Twin of `scanline::Span`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub xa: f32,
    pub na: Vec3,
    pub xb: f32,
    pub nb: Vec3,
}

/// Twin of `scanline::span_at` (row `py` clamped to the triangle's rows).
pub fn span_at(py: f32, s: &[Vec2; 3], nv: &[Vec3; 3]) -> Span {
    let lo = s[0].y.min(s[1].y.min(s[2].y));
    let hi = s[0].y.max(s[1].y.max(s[2].y));
    let py = py.clamp(lo, hi);
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
        let n = nv[e] * (1.0 - u) + nv[(e + 1) % 3] * u;
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
pub fn span_t(sp: &Span, px: f32) -> f32 {
    if sp.xb > sp.xa {
        ((px - sp.xa) / (sp.xb - sp.xa)).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Twin of `scanline::PARALLEL`.
pub const PARALLEL: f32 = 1e-8;

/// `(c, sin theta, theta)` of unit `a`, `b` (glsl/scanline.glsl `angleBetween`: acos refined by
/// one Newton step on sin), or `None` within [`PARALLEL`] of parallel or antipodal.
pub fn angle(a: Vec3, b: Vec3) -> Option<(f32, f32, f32)> {
    let c = a.dot(b).clamp(-1.0, 1.0);
    let s2 = 1.0 - c * c;
    if s2 < PARALLEL {
        return None;
    }
    let s = s2.sqrt();
    let t0 = c.acos();
    Some((c, s, t0 + (s * t0.cos() - c * t0.sin())))
}

/// Twin of `scanline::slerp`.
#[inline(always)]
pub fn slerp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    match angle(a, b) {
        Some((_, s, th)) => (a * ((1.0 - t) * th).sin() + b * (t * th).sin()) / s,
        None => normalize_exact(a * (1.0 - t) + b * t),
    }
}

/// Twin of `scanline::spherical_angular` (the closed form; the software engine seeds its
/// recurrence with it).
pub fn spherical_angular(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    match angle(a, b) {
        Some((c, s, th)) => a * (t * th).cos() + (b - a * c) * ((t * th).sin() / s),
        None => normalize_exact(a * (1.0 - t) + b * t),
    }
}

/// Twin of `scanline::mid_approx`.
pub fn mid_approx(nl: Vec3, np: Vec3) -> Vec3 {
    let c = nl.dot(np);
    (nl + np) * ((0.103 * c - 0.306) * c + 0.705)
}

/// Twin of `scanline::mid_exact`.
pub fn mid_exact(nl: Vec3, np: Vec3) -> Vec3 {
    normalize_exact(nl + np)
}

/// Twin of `scanline::inv_root_exact`.
pub fn inv_root_exact(z: f32) -> f32 {
    1.0 / (2.0 + z).sqrt()
}

/// Twin of `scanline::inv_root_poly1`.
pub fn inv_root_poly1(z: f32) -> f32 {
    0.64 - 0.07 * z
}

/// Twin of `scanline::inv_root_poly2`.
pub fn inv_root_poly2(z: f32) -> f32 {
    (0.014253 * z - 0.118922) * z + 0.680850
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
pub fn span_normal(sp: &Span, x: f32) -> Vec3 {
    if sp.xb > sp.xa {
        sp.na + (sp.nb - sp.na) * ((x - sp.xa) / (sp.xb - sp.xa))
    } else {
        sp.na
    }
}

/// Twin of `scanline::plane_normal`: (A, B, C, o).
pub fn plane_normal(s: &[Vec2; 3], n: &[Vec3; 3]) -> (Vec3, Vec3, Vec3, Vec2) {
    let o = (s[0] + s[1] + s[2]) / 3.0;
    let q0 = s[0] - o;
    let (e1, e2) = (s[1] - s[0], s[2] - s[0]);
    let det = e1.x * e2.y - e1.y * e2.x;
    let (a, b) = if det.abs() > 1e-12 {
        (
            ((n[1] - n[0]) * e2.y - (n[2] - n[0]) * e1.y) / det,
            ((n[2] - n[0]) * e1.x - (n[1] - n[0]) * e2.x) / det,
        )
    } else {
        (Vec3::ZERO, Vec3::ZERO)
    };
    (a, b, n[0] - a * q0.x - b * q0.y, o)
}

/// The Taylor coefficients T0..T5 of `scanline::taylor_cosine` for the cosine with `v`.
pub fn taylor_terms(v: Vec3, a3: Vec3, b3: Vec3, c3: Vec3) -> [f32; 6] {
    let (a, b, c) = (v.dot(a3), v.dot(b3), v.dot(c3));
    let (d, e, f) = (a3.dot(a3), 2.0 * a3.dot(b3), b3.dot(b3));
    let (g, h, i) = (2.0 * a3.dot(c3), 2.0 * b3.dot(c3), c3.dot(c3));
    let si = i.sqrt();
    [
        c / si,
        (2.0 * b * i - c * h) / (2.0 * i * si),
        (2.0 * a * i - c * g) / (2.0 * i * si),
        (3.0 * c * h * h - 4.0 * c * f * i - 4.0 * b * h * i) / (8.0 * i * i * si),
        (3.0 * c * g * h - 2.0 * c * e * i - 2.0 * b * g * i - 2.0 * a * h * i)
            / (4.0 * i * i * si),
        (3.0 * c * g * g - 4.0 * c * d * i - 4.0 * a * g * i) / (8.0 * i * i * si),
    ]
}

/// Twin of `scanline::cosine_slope`: dI/dt of `v.N/|N|` at N with `dN/dt = D`.
pub fn cosine_slope(v: Vec3, n: Vec3, d: Vec3) -> f32 {
    let n2 = n.dot(n);
    let len = n2.sqrt();
    v.dot(d) / len - v.dot(n) * n.dot(d) / (n2 * len)
}
