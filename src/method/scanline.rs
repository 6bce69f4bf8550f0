//! The scanline family (docs/formulas.md#scanline-emulation, then slerp, spherical-angular,
//! quadratic and dichotomy of docs/formulas.md#methods): the span through a pixel's row and the
//! interpolations along it, once, generic over the number type ([`super::real`]) like
//! [`super::formulas`]. Each function is the literal port of its GLSL twin in
//! glsl/scanline.glsl or glsl/methods/, with the same branches and thresholds, so that the
//! float32 image and the f64 evaluation differ only by rounding. Window positions are in the
//! position type ([`Float::Pos`]: f64 in the truth, f32 in the engines, as the rasterizer's),
//! the normals and cosines in the scalar.
use glam::{DVec2, DVec3};

use super::formulas::{mid_poly, normalize_exact};
use super::real::{Float, Real, Vector};

/// The span through one row of a triangle: its two ends on the triangle's edges, with the
/// Phong edge normals there (linear along the edge, not unit). `P` is the position type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span<V = DVec3, P = f64> {
    pub xa: P,
    pub na: V,
    pub xb: P,
    pub nb: V,
}

/// A triangle's window-space corners, (x, y) each.
pub type Corners<P> = [[P; 2]; 3];

/// The f64 corners of window positions.
pub fn corners(w: [DVec2; 3]) -> Corners<f64> {
    w.map(|p| p.to_array())
}

/// The span through the row `py` of the triangle with window-space corners `s` and vertex normals
/// `nv` (docs/formulas.md#scanline-emulation). `py` is first clamped to the triangle's rows, so a
/// pixel the rasterizer covers on the triangle's top or bottom row still finds its edges. A
/// triangle with no non-horizontal edge (all corners on one row) gives the empty span at corner 0.
/// The edge parameter and the ends' x are positions; the ends' normals are interpolated in `T`.
pub fn span_at<T: Float, V: Vector<S = T>>(
    py: T::Pos,
    s: Corners<T::Pos>,
    nv: [V; 3],
) -> Span<V, T::Pos> {
    let lo = s[0][1].min(s[1][1].min(s[2][1]));
    let hi = s[0][1].max(s[1][1].max(s[2][1]));
    let py = py.clamp(lo, hi);
    let (zero, one) = (<T::Pos as Float>::ZERO, <T::Pos as Float>::ONE);
    let mut sp = Span {
        xa: Real::c(1e30),
        na: nv[0],
        xb: Real::c(-1e30),
        nb: nv[0],
    };
    for e in 0..3 {
        let (p, q) = (s[e], s[(e + 1) % 3]);
        if p[1] == q[1] {
            continue;
        }
        let u = (py - p[1]) / (q[1] - p[1]);
        if !(zero <= u && u <= one) {
            continue;
        }
        // GLSL mix(x, y, a) = x (1 - a) + y a
        let x = p[0] * (one - u) + q[0] * u;
        let us = T::of_pos(u);
        let n = nv[e] * (T::ONE - us) + nv[(e + 1) % 3] * us;
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
        sp.xa = s[0][0];
        sp.xb = s[0][0];
    }
    sp
}

/// Where pixel `px` lies on the span: `clamp((px - xA) / (xB - xA), 0, 1)`, 0 on an empty span.
#[inline(always)]
pub fn span_t<V, P: Float>(sp: &Span<V, P>, px: P) -> P {
    if sp.xb > sp.xa {
        ((px - sp.xa) / (sp.xb - sp.xa)).clamp(P::ZERO, P::ONE)
    } else {
        P::ZERO
    }
}

/// The unit span-end normals N'_A, N'_B (exact normalisation, as the seeds assume) and `t` of
/// the pixel at `pixel` in the triangle (`window`, `normals`), in f64.
pub fn span_ends(pixel: DVec2, window: [DVec2; 3], normals: [DVec3; 3]) -> (DVec3, DVec3, f64) {
    let sp = span_at(pixel.y, corners(window), normals);
    (
        normalize_exact(sp.na),
        normalize_exact(sp.nb),
        span_t(&sp, pixel.x),
    )
}

/// Below this `1 - c^2` (angle under 1e-4 rad) the angle-based interpolations fall back to
/// `normalize(mix(a, b, t))`, which agrees with them there to ~1e-9. Antipodal ends (no plane)
/// take the same fallback, whose result is the zero vector at t = 1/2 (their documented hazard).
pub const PARALLEL: f64 = 1e-8;
/// [`PARALLEL`] in float16 (glsl/scanline.glsl `BY_PRECISION(1e-8, 0.001953125)`: 1e-8 is below
/// float16's range and would round to 0, making parallel span ends divide 0 by 0): 2^-9.
pub const PARALLEL_F16: f64 = 0.001953125;

/// `(c, sin(theta), theta)` of unit `a`, `b` (`c = a.b` clamped to [-1, 1]), or `None` within
/// [`PARALLEL`] of parallel or antipodal, where the angle-based forms fall back to
/// `normalize(mix)`. glsl/scanline.glsl `angleBetween`: the float programs refine `acos` by one
/// Newton step on sin ([`Float::REFINED_ACOS`]).
#[inline(always)]
pub fn angle<T: Float, V: Vector<S = T>>(a: V, b: V) -> Option<(T, T, T)> {
    let c = a.dot(b).clamp(-T::ONE, T::ONE);
    let s2 = T::ONE - c * c;
    if s2 < T::by_precision(PARALLEL, PARALLEL_F16) {
        return None;
    }
    let s = s2.sqrt();
    let t0 = c.acos();
    let th = if T::REFINED_ACOS {
        t0 + (s * t0.cos() - c * t0.sin())
    } else {
        t0
    };
    Some((c, s, th))
}

/// Spherical linear interpolation between unit `a` and `b` as the papers print it
/// (docs/formulas.md#slerp): `(a sin((1 - t) theta) + b sin(t theta)) / sin(theta)`, `theta = acos(a.b)`, the dot
/// product clamped to [-1, 1].
#[inline(always)]
pub fn slerp<T: Float, V: Vector<S = T>>(a: V, b: V, t: T) -> V {
    match angle(a, b) {
        Some((_, s, th)) => (a * ((T::ONE - t) * th).sin() + b * (t * th).sin()) / s,
        None => normalize_exact(a * (T::ONE - t) + b * t),
    }
}

/// Spherical-angular interpolation in closed form
/// (docs/formulas.md#spherical-angular-interpolation): the Gram-Schmidt form
/// `a cos(t theta) + (b - a c) sin(t theta) / sin(theta)`, `c = a.b`. Equal to [`slerp`] in exact
/// arithmetic; a different float computation.
pub fn spherical_angular<T: Float, V: Vector<S = T>>(a: V, b: V, t: T) -> V {
    match angle(a, b) {
        Some((c, s, th)) => a * (t * th).cos() + (b - a * c) * ((t * th).sin() / s),
        None => normalize_exact(a * (T::ONE - t) + b * t),
    }
}

/// The approximate middle normal of a span
/// (docs/formulas.md#quadratic-interpolation-along-the-span):
/// `(0.103 c^2 - 0.306 c + 0.705) (nl + np)`, `c = nl.np`, a fit of `1/|nl + np|` on c in [0, 1]
/// ([`mid_poly`]).
pub fn mid_approx<V: Vector>(nl: V, np: V) -> V {
    (nl + np) * mid_poly(nl.dot(np))
}

/// The exact middle normal: `normalize(nl + np)`, the angular midpoint of the unit ends.
pub fn mid_exact<T: Float, V: Vector<S = T>>(nl: V, np: V) -> V {
    normalize_exact(nl + np)
}

/// Quadratic interpolation along the span through `nl` (t = 0), `nc` (t = 1/2) and `np` (t = 1)
/// (docs/formulas.md#quadratic-interpolation-along-the-span, the survey's P corrected):
/// `(G t + P) t + nl`, `G = 2np - 4nc + 2nl`, `P = 4nc - 3nl - np`. Not renormalised. (The
/// software engine steps the same polynomial by forward differences.)
pub fn quadratic(nl: DVec3, np: DVec3, nc: DVec3, t: f64) -> DVec3 {
    let g = np * 2.0 - nc * 4.0 + nl * 2.0;
    let p = nc * 4.0 - nl * 3.0 - np;
    (g * t + p) * t + nl
}

/// `1/sqrt(2 + z)`, `z = 2 cos(phi)`: the factor that makes `lo + hi` unit
/// (docs/formulas.md#dichotomy).
pub fn inv_root_exact<T: Real>(z: T) -> T {
    T::c(1.0) / (T::c(2.0) + z).sqrt()
}

/// The degree-1 approximation `0.64 - 0.07 z` of the digital-segment paper
/// (docs/formulas.md#dichotomy).
pub fn inv_root_poly1<T: Real>(z: T) -> T {
    T::c(0.64) - T::c(0.07) * z
}

/// The degree-2 minimax approximation `0.014253 z^2 - 0.118922 z + 0.680850` on phi in [0, 45]
/// degrees (docs/formulas.md#dichotomy; the normalisation survey prints it rounded).
pub fn inv_root_poly2<T: Real>(z: T) -> T {
    (T::c(0.014253) * z - T::c(0.118922)) * z + T::c(0.680850)
}

/// Largest number of halving levels of the dichotomy methods (a span of 4096 pixels).
pub const MAX_LEVELS: u32 = 12;

/// Halving levels for a span of `width` pixels: the least k >= 1 with 2^k >= width, at most
/// [`MAX_LEVELS`] (docs/formulas.md#dichotomy: K = ceil(log2(span pixels)), by comparison, no log).
pub fn levels<P: Float>(width: P) -> u32 {
    let mut k = 1;
    while k < MAX_LEVELS && P::of_usize(1usize << k) < width {
        k += 1;
    }
    k
}

/// Dichotomy (angle halving, docs/formulas.md#dichotomy): the slerp sample nearest `t` on the grid
/// m / 2^k, reached by `k` bisections of the bracket (a, b) with `mid = (lo + hi) f(2 lo.hi)`;
/// `m = floor(t 2^k + 0.5)` (halves up, one rule on GPU and CPU). (The software engine fills the
/// whole grid by the same midpoints.)
pub fn dichotomy(a: DVec3, b: DVec3, t: f64, k: u32, f: fn(f64) -> f64) -> DVec3 {
    let n = 1u32 << k;
    let m = ((t * f64::from(n) + 0.5).floor() as u32).min(n);
    if m == 0 {
        return a;
    }
    if m == n {
        return b;
    }
    let (mut lo, mut hi) = (a, b);
    for l in 0..k {
        let mid = (lo + hi) * f(2.0 * lo.dot(hi));
        if (m >> (k - 1 - l)) & 1 != 0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Where a pixel sits in the digital segments of 2^k pixels of a span
/// (docs/formulas.md#digital-segments): the segment's end positions `xl`, `xp` (pixel centres; the
/// first segment starts at the first covered pixel centre `ceil(xA - 0.5) + 0.5`) and the pixel's
/// index `v` in it, 0..2^k.
pub fn segment(sp: &Span, px: f64, k: u32) -> (f64, f64, u32) {
    let p0 = (sp.xa - 0.5).ceil() + 0.5;
    let j = (px - p0).floor().max(0.0) as u32;
    let len = 1u32 << k;
    let xl = p0 + f64::from((j >> k) << k);
    (xl, xl + f64::from(len), j & (len - 1))
}

/// The Phong normal of the span at `x` (linear in x, extrapolated past the ends; the start
/// normal on an empty span).
#[inline(always)]
pub fn span_normal<T: Float, V: Vector<S = T>>(sp: &Span<V, T::Pos>, x: T::Pos) -> V {
    if sp.xb > sp.xa {
        sp.na + (sp.nb - sp.na) * T::of_pos((x - sp.xa) / (sp.xb - sp.xa))
    } else {
        sp.na
    }
}

/// Bishop-Weimer's screen-linear normal `N(x, y) = A x + B y + C`
/// (docs/formulas.md#bishop-weimer-taylor-shading), fitted to the window corners `s` and normals
/// `n` with the origin at the corners' centroid `o`: returns (A, B, C, o). A triangle with no area
/// on screen (|det| <= 1e-12) gets the constant normal n0.
#[allow(clippy::type_complexity)]
pub fn plane_normal<T: Float, V: Vector<S = T>>(
    s: Corners<T::Pos>,
    n: [V; 3],
) -> (V, V, V, [T::Pos; 2]) {
    let three = <T::Pos as Real>::c(3.0);
    let o = [0, 1].map(|k| (s[0][k] + s[1][k] + s[2][k]) / three);
    let q0 = [s[0][0] - o[0], s[0][1] - o[1]];
    let e1 = [s[1][0] - s[0][0], s[1][1] - s[0][1]];
    let e2 = [s[2][0] - s[0][0], s[2][1] - s[0][1]];
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    let (a, b) = if det.abs() > Real::c(1e-12) {
        let d = T::of_pos(det);
        let (e1, e2) = (e1.map(T::of_pos), e2.map(T::of_pos));
        (
            ((n[1] - n[0]) * e2[1] - (n[2] - n[0]) * e1[1]) / d,
            ((n[2] - n[0]) * e1[0] - (n[1] - n[0]) * e2[0]) / d,
        )
    } else {
        (V::splat(T::ZERO), V::splat(T::ZERO))
    };
    (a, b, n[0] - a * T::of_pos(q0[0]) - b * T::of_pos(q0[1]), o)
}

/// The Taylor coefficients T0..T5 about (0, 0) of `(v.N)/|N|`, `N = A x + B y + C`
/// (docs/formulas.md#bishop-weimer-taylor-shading: T0..T5, derived symbolically).
pub fn taylor_terms<V: Vector>(v: V, a3: V, b3: V, c3: V) -> [V::S; 6] {
    let c = |x: f64| V::S::c(x);
    let (two, three, four, eight) = (c(2.0), c(3.0), c(4.0), c(8.0));
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

/// The second-order Taylor polynomial about (0, 0) of `(v.N)/|N|`, `N = A x + B y + C`, at
/// `p = (x, y)` ([`taylor_terms`]; the software engine steps it by forward differences).
pub fn taylor_cosine(v: DVec3, a3: DVec3, b3: DVec3, c3: DVec3, p: DVec2) -> f64 {
    let [t0, t1, t2, t3, t4, t5] = taylor_terms(v, a3, b3, c3);
    let (x, y) = (p.x, p.y);
    t5 * x * x + t4 * x * y + t3 * y * y + t2 * x + t1 * y + t0
}

/// dI/dt of `v.N/|N|` at N with `dN/dt = D`.
pub fn cosine_slope<V: Vector>(v: V, n: V, d: V) -> V::S {
    let n2 = n.dot(n);
    let len = n2.sqrt();
    v.dot(d) / len - v.dot(n) * n.dot(d) / (n2 * len)
}

/// Hast's Euler integration of `v.N(t)/|N(t)|` along the span
/// (docs/formulas.md#hast-euler-integration, the reconstruction): pixel steps `h = 1/W`, the
/// derivative interpolated between the ends, the end error spread linearly over the span, at the
/// pixel's fraction `t`. (The software engine steps the same sum.)
pub fn euler_cosine(v: DVec3, sp: &Span, t: f64) -> f64 {
    let (na, nb) = (sp.na, sp.nb);
    let w = sp.xb - sp.xa;
    let i0 = v.dot(na) / na.length();
    if w.is_nan() || w <= 0.0 {
        return i0;
    }
    let i1 = v.dot(nb) / nb.length();
    let d = nb - na;
    let (d0, d1) = (cosine_slope(v, na, d), cosine_slope(v, nb, d));
    let h = 1.0 / w;
    let j = t * w;
    let ij = i0 + h * (j * d0 + (d1 - d0) * j * (j - 1.0) / (2.0 * w));
    let iw = i0 + h * (w * d0 + (d1 - d0) * (w - 1.0) / 2.0);
    ij + (i1 - iw) * j / w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::assert_close;

    fn tri() -> (Corners<f64>, [DVec3; 3]) {
        (
            corners([
                DVec2::new(10.0, 10.0),
                DVec2::new(30.0, 12.0),
                DVec2::new(15.0, 40.0),
            ]),
            [DVec3::X, DVec3::Y, DVec3::Z],
        )
    }

    #[test]
    fn span_ends_lie_on_the_edges_with_their_phong_normals() {
        let (s, n) = tri();
        // Row 25: edge 1-2 (u = 13/28) on the right, edge 2-0 (u = 15/30) on the left.
        let sp = span_at(25.0, s, n);
        assert_close("xA", sp.xa, 15.0 + (10.0 - 15.0) * 0.5, 1e-12);
        assert_close("xB", sp.xb, 30.0 + (15.0 - 30.0) * (13.0 / 28.0), 1e-12);
        assert!(
            (sp.na - (n[2] * 0.5 + n[0] * 0.5)).length() < 1e-12,
            "{sp:?}"
        );
        let u = 13.0 / 28.0;
        assert!(
            (sp.nb - (n[1] * (1.0 - u) + n[2] * u)).length() < 1e-12,
            "{sp:?}"
        );
        assert_close("t at xA", span_t(&sp, sp.xa), 0.0, 0.0);
        assert_close("t at xB", span_t(&sp, sp.xb), 1.0, 0.0);
        assert_close("t mid", span_t(&sp, (sp.xa + sp.xb) / 2.0), 0.5, 1e-12);
    }

    #[test]
    fn rows_outside_the_triangle_clamp_to_its_first_and_last_row() {
        let (s, n) = tri();
        assert_eq!(span_at(9.2, s, n), span_at(10.0, s, n));
        assert_eq!(span_at(40.7, s, n), span_at(40.0, s, n));
        // At the top vertex the span is one point with the vertex normal.
        let sp = span_at(10.0, s, n);
        assert_eq!((sp.xa, sp.xb), (10.0, 10.0));
        assert_eq!(sp.na, n[0]);
        assert_eq!(span_t(&sp, 10.5), 0.0);
    }

    #[test]
    fn slerp_and_its_closed_form_are_unit_and_angle_proportional() {
        // 100 degrees apart: at t the angle from a is t * 100 degrees (docs/formulas.md#slerp,
        // docs/formulas.md#spherical-angular-interpolation).
        let a = DVec3::X;
        let b = DVec3::new(100f64.to_radians().cos(), 100f64.to_radians().sin(), 0.0);
        for f in [slerp, spherical_angular] {
            for t in [0.0, 0.1, 0.25, 0.5, 0.9, 1.0] {
                let n = f(a, b, t);
                assert_close("|n|", n.length(), 1.0, 1e-15);
                assert_close("angle", n.angle_between(a), t * 100f64.to_radians(), 1e-12);
            }
            // Nearly parallel: the normalize(mix) fallback, continuous with the closed form.
            let b = DVec3::new(1.0, 1e-5, 0.0).normalize();
            assert_close("tiny", f(a, b, 0.5).angle_between(a), 0.5e-5, 1e-12);
        }
    }

    #[test]
    fn quadratic_passes_through_its_three_normals() {
        let (nl, np) = (DVec3::X, DVec3::new(0.5, 0.0, 0.75f64.sqrt()));
        let nc = mid_exact(nl, np);
        for (t, want) in [(0.0, nl), (0.5, nc), (1.0, np)] {
            assert!(
                (quadratic(nl, np, nc, t) - want).length() < 1e-15,
                "t = {t}"
            );
        }
        // The polynomial middle normal is within 0.5 % of unit length at 60 degrees
        // (docs/formulas.md#quadratic-interpolation-along-the-span: -0.20 % at 40 degrees, -0.30 %
        // at 90).
        assert!((mid_approx(nl, np).length() - 1.0).abs() < 5e-3);
    }

    #[test]
    fn exact_dichotomy_lands_on_slerp_and_the_polynomials_near_it() {
        let a = DVec3::Z;
        let b = DVec3::new(45f64.to_radians().sin(), 0.0, 45f64.to_radians().cos());
        for m in 0..=16u32 {
            let t = f64::from(m) / 16.0;
            let want = slerp(a, b, t);
            let exact = dichotomy(a, b, t, 4, inv_root_exact);
            assert!((exact - want).length() < 1e-14, "m = {m}");
            // docs/formulas.md#dichotomy at 45 degrees (K = 8 there): length errors 0.006 %
            // (degree 2) and 0.16 % (degree 1)
            assert!((dichotomy(a, b, t, 4, inv_root_poly2) - want).length() < 1e-4);
            assert!((dichotomy(a, b, t, 4, inv_root_poly1) - want).length() < 2e-3);
        }
        // t between grid points (0, 1/2, 1 for one level) goes to the nearer one, halves up.
        assert_eq!(dichotomy(a, b, 0.24, 1, inv_root_exact), a);
        let mid = dichotomy(a, b, 0.25, 1, inv_root_exact);
        assert!((mid - slerp(a, b, 0.5)).length() < 1e-15);
        assert_eq!(dichotomy(a, b, 0.75, 1, inv_root_exact), b);
    }

    #[test]
    fn levels_cover_the_span_and_segments_tile_it_from_the_first_pixel() {
        assert_eq!(
            [0.5, 2.0, 2.1, 64.0, 65.0, 1e9].map(levels),
            [1, 1, 2, 6, 7, MAX_LEVELS]
        );
        let sp = Span {
            xa: 10.3,
            na: DVec3::X,
            xb: 30.0,
            nb: DVec3::Y,
        };
        // first covered centre 10.5; pixel 17.5 is index 7: segment 1 of 4-pixel segments
        assert_eq!(segment(&sp, 17.5, 2), (14.5, 18.5, 3));
        assert_eq!(segment(&sp, 10.5, 3), (10.5, 18.5, 0));
        // a pixel left of the first centre clamps into the first segment
        assert_eq!(segment(&sp, 9.5, 1), (10.5, 12.5, 0));
        // the span normal is linear and extrapolates past xB
        let n = span_normal(&sp, 30.0 + 19.7);
        assert!((n - (DVec3::X + (DVec3::Y - DVec3::X) * 2.0)).length() < 1e-12);
    }
}
