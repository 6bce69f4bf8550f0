//! Each method in its span form (issue 13): what it computes per triangle, per row and per
//! pixel. Per-pixel methods step their interpolated vector (normal, quaternion, weights or
//! colour) by a forward difference and apply their formula; the scanline family walks the span
//! with its own recurrence. Every per-pixel loop is allocation-free: state lives in locals, the
//! dichotomy grids in the per-thread scratch. Generic over the scalar `S` ([`Float`]): the
//! positions (t, its step, z) stay f32, the normals, cosines and colours are `S`.
use std::marker::PhantomData;

use glam::{Vec2, Vec3};

use super::raster::{RowOut, RowSpan, Shader, Tri};
use super::Scalar;
use crate::method::formulas::{self as f, Lighting};
use crate::method::real::V3;
use crate::method::scanline::{self as sc, Span};
use crate::scene::MAX_LIGHTS;

/// The normal output of a method with a per-pixel normal (w = 1).
#[inline(always)]
pub fn n4<S: Scalar>(n: V3<S>) -> [f32; 4] {
    [n.x.f32(), n.y.f32(), n.z.f32(), 1.0]
}

/// Per-pixel methods: a per-corner vector (`attr`, with per-triangle data `D`) interpolated
/// along the span by a forward difference, and `pixel` turning it into (colour, normal).
pub struct Stepped<D, A, F> {
    pub attr: A,
    pub pixel: F,
    pub _d: PhantomData<fn() -> D>,
}

/// A [`Stepped`] shader.
pub fn stepped<D, A, F>(attr: A, pixel: F) -> Stepped<D, A, F>
where
    A: Fn(&Tri) -> ([Vec3; 3], D) + Sync,
    F: Fn(Vec3, &D) -> (Vec3, [f32; 4]) + Sync,
{
    Stepped {
        attr,
        pixel,
        _d: PhantomData,
    }
}

impl<D, A, F> Shader for Stepped<D, A, F>
where
    D: Send + Sync,
    A: Fn(&Tri) -> ([Vec3; 3], D) + Sync,
    F: Fn(Vec3, &D) -> (Vec3, [f32; 4]) + Sync,
{
    type Setup = ([Vec3; 3], D);
    fn setup(&self, tri: &Tri) -> Self::Setup {
        (self.attr)(tri)
    }

    #[inline]
    fn row(&self, tri: &Tri, s: &Self::Setup, span: RowSpan, out: &mut RowOut, _: &mut Vec<Vec3>) {
        let (mut v, dv) = tri.attribute(&s.0, span.centre(span.i0));
        let mut z = span.z;
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                let (c, n) = (self.pixel)(v, &s.1);
                out.put(i, c, n);
            }
            v += dv;
            z += span.dz;
        }
    }
}

/// The span through a row, its unit ends, and `t` with its step at the first pixel.
struct Walk<S> {
    sp: Span<V3<S>, f32>,
    a: V3<S>,
    b: V3<S>,
    t: f32,
    dt: f32,
}

/// The triangle's window corners and vertex normals as the span functions read them.
fn corners<S: Scalar>(tri: &Tri) -> (sc::Corners<f32>, [V3<S>; 3]) {
    (tri.s.map(|p| p.to_array()), tri.n.map(V3::<S>::of))
}

fn walk<S: Scalar>(tri: &Tri, span: &RowSpan) -> Walk<S> {
    let (s, n) = corners::<S>(tri);
    let sp = sc::span_at(span.y as f32 + 0.5, s, n);
    let px = span.i0 as f32 + 0.5;
    let (t, dt) = if sp.xb > sp.xa {
        let dt = 1.0 / (sp.xb - sp.xa);
        ((px - sp.xa) * dt, dt)
    } else {
        (0.0, 0.0)
    };
    Walk {
        sp,
        a: f::normalize_exact(sp.na),
        b: f::normalize_exact(sp.nb),
        t,
        dt,
    }
}

/// A recurrence's value `v` at span fraction `t`, or the value at the nearer end when `t` lies
/// outside [0, 1] (the twins clamp t there).
#[inline(always)]
fn clamped<S: Scalar>(t: f32, v: V3<S>, ends: (V3<S>, V3<S>)) -> V3<S> {
    if t < 0.0 {
        ends.0
    } else if t > 1.0 {
        ends.1
    } else {
        v
    }
}

/// Which interpolation along the span.
#[derive(Debug, Clone, Copy)]
pub enum Along<S> {
    /// slerp evaluated at each pixel's t (the closed form; its recurrence is `Chebyshev`).
    Slerp,
    /// spherical_angular: N(k+1) = 2 cos(phi) N(k) - N(k-1), seeded by the closed form.
    Chebyshev,
    /// quadratic_scanline: G t^2 + P t + Q by second-order forward differences.
    Quadratic { approx_mid: bool },
    /// dichotomy_*: the span's grid m / 2^K filled by halving, each pixel takes its nearest.
    Dichotomy(fn(S) -> S),
    /// segments_k*: ends shaded, the colour stepped by 1/2^k (or dichotomy inside with a root).
    Segments(u32, Option<fn(S) -> S>),
    /// bishop_weimer: each cosine's Taylor polynomial by forward differences.
    BishopWeimer,
    /// hast_euler: each cosine by Euler steps with the end-error correction.
    HastEuler,
}

/// The scanline family's shader.
pub struct SpanShader<S: Scalar> {
    pub along: Along<S>,
    pub lit: Lighting<V3<S>>,
}

/// Per-triangle set-up of the scanline family (only Bishop-Weimer has any).
pub struct SpanSetup<S> {
    o: Vec2,
    taylor: [[S; 6]; 2 * MAX_LIGHTS],
}

/// Fills `grid[0..=n]` (n = 2^k) with the dichotomy samples between unit `a` and `b`: each
/// midpoint `(lo + hi) f(2 lo.hi)` once, the same operations as `scanline::dichotomy` takes on
/// its way to any one sample. The grid holds the `S` values as f32 (exact).
fn halve<S: Scalar>(grid: &mut Vec<Vec3>, a: V3<S>, b: V3<S>, k: u32, inv_root: fn(S) -> S) {
    let n = 1usize << k;
    grid.clear();
    grid.resize(n + 1, Vec3::ZERO);
    grid[0] = a.f32();
    grid[n] = b.f32();
    let mut step = n;
    while step > 1 {
        let half = step / 2;
        let mut j = 0;
        while j < n {
            let (lo, hi) = (V3::<S>::of(grid[j]), V3::<S>::of(grid[j + step]));
            grid[j + half] = ((lo + hi) * inv_root(S::of(2.0) * lo.dot(hi))).f32();
            j += step;
        }
        step = half;
    }
}

impl<S: Scalar> Shader for SpanShader<S> {
    type Setup = SpanSetup<S>;
    fn setup(&self, tri: &Tri) -> SpanSetup<S> {
        let mut taylor = [[S::ZERO; 6]; 2 * MAX_LIGHTS];
        let mut o = Vec2::ZERO;
        if let Along::BishopWeimer = self.along {
            let (s, n) = corners::<S>(tri);
            let (a, b, c, origin) = sc::plane_normal(s, n);
            o = Vec2::from(origin);
            for (k, t) in taylor.iter_mut().enumerate().take(self.lit.cosines()) {
                *t = sc::taylor_terms(self.lit.dir(k), a, b, c);
            }
        }
        SpanSetup { o, taylor }
    }

    fn row(
        &self,
        tri: &Tri,
        st: &SpanSetup<S>,
        span: RowSpan,
        out: &mut RowOut,
        scratch: &mut Vec<Vec3>,
    ) {
        match self.along {
            Along::Slerp => self.slerp(tri, span, out),
            Along::Chebyshev => self.chebyshev(tri, span, out),
            Along::Quadratic { approx_mid } => self.quadratic(tri, span, out, approx_mid),
            Along::Dichotomy(inv_root) => self.dichotomy(tri, span, out, scratch, inv_root),
            Along::Segments(k, inv_root) => self.segments(tri, span, out, scratch, k, inv_root),
            Along::BishopWeimer => self.bishop_weimer(tri, st, span, out),
            Along::HastEuler => self.hast_euler(tri, span, out),
        }
    }
}

impl<S: Scalar> SpanShader<S> {
    /// Interpolation by slerp at each pixel's t (the closed form).
    #[inline]
    fn slerp(&self, tri: &Tri, span: RowSpan, out: &mut RowOut) {
        let lit = &self.lit;
        let mut z = span.z;
        let w = walk::<S>(tri, &span);
        let ang = sc::angle(w.a, w.b);
        let mut t = w.t;
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                let tc = S::of(t.clamp(0.0, 1.0));
                let n = match ang {
                    Some((_, s, th)) => {
                        (w.a * ((S::ONE - tc) * th).sin() + w.b * (tc * th).sin()) / s
                    }
                    None => f::normalize_exact(w.a * (S::ONE - tc) + w.b * tc),
                };
                out.put(i, lit.shade(n).f32(), n4(n));
            }
            t += w.dt;
            z += span.dz;
        }
    }

    /// spherical_angular's Chebyshev recurrence, seeded by the closed form.
    #[inline]
    fn chebyshev(&self, tri: &Tri, span: RowSpan, out: &mut RowOut) {
        let lit = &self.lit;
        let mut z = span.z;
        let w = walk::<S>(tri, &span);
        // Seeded at the first pixel's own t, not clamped: a covered centre a rounding
        // left of xA then stays on the same grid as the rest of the span.
        let t0 = w.t;
        match sc::angle(w.a, w.b) {
            Some((_, _, th)) => {
                let k2 = S::of(2.0) * (th * S::of(w.dt)).cos();
                let mut cur = sc::spherical_angular(w.a, w.b, S::of(t0));
                let mut next = sc::spherical_angular(w.a, w.b, S::of(t0 + w.dt));
                // Outside [0, 1] (rounding at the span's ends, or the clamped top and
                // bottom rows) the twin clamps t: the end values there.
                let ends = (w.a, sc::spherical_angular(w.a, w.b, S::ONE));
                let mut t = t0;
                for i in span.i0..=span.i1 {
                    if out.test(tri, i, z, span.centre(i)) {
                        let n = clamped(t, cur, ends);
                        out.put(i, lit.shade(n).f32(), n4(n));
                    }
                    let n2 = next * k2 - cur;
                    cur = next;
                    next = n2;
                    t += w.dt;
                    z += span.dz;
                }
            }
            None => {
                let mut t = w.t;
                for i in span.i0..=span.i1 {
                    if out.test(tri, i, z, span.centre(i)) {
                        let tc = S::of(t.clamp(0.0, 1.0));
                        let n = f::normalize_exact(w.a * (S::ONE - tc) + w.b * tc);
                        out.put(i, lit.shade(n).f32(), n4(n));
                    }
                    t += w.dt;
                    z += span.dz;
                }
            }
        }
    }

    /// quadratic_scanline's second-order forward differences.
    #[inline]
    fn quadratic(&self, tri: &Tri, span: RowSpan, out: &mut RowOut, approx_mid: bool) {
        let lit = &self.lit;
        let mut z = span.z;
        let w = walk::<S>(tri, &span);
        let (nl, np) = (w.a, w.b);
        let nc = if approx_mid {
            sc::mid_approx(nl, np)
        } else {
            sc::mid_exact(nl, np)
        };
        let (two, three, four) = (S::of(2.0), S::of(3.0), S::of(4.0));
        let g = np * two - nc * four + nl * two;
        let p = nc * four - nl * three - np;
        let (ts, dts) = (S::of(w.t), S::of(w.dt));
        let mut v = (g * ts + p) * ts + nl;
        let mut d1 = g * (two * ts * dts + dts * dts) + p * dts;
        let d2 = g * (two * dts * dts);
        let ends = (nl, (g + p) + nl);
        let (mut t, dt) = (w.t, w.dt);
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                let n = clamped(t, v, ends);
                out.put(i, lit.shade(n).f32(), n4(n));
            }
            v += d1;
            d1 += d2;
            t += dt;
            z += span.dz;
        }
    }

    /// dichotomy_*: the span's grid filled by halving, each pixel takes its nearest sample.
    #[inline]
    fn dichotomy(
        &self,
        tri: &Tri,
        span: RowSpan,
        out: &mut RowOut,
        scratch: &mut Vec<Vec3>,
        inv_root: fn(S) -> S,
    ) {
        let lit = &self.lit;
        let mut z = span.z;
        let w = walk::<S>(tri, &span);
        let k = sc::levels(w.sp.xb - w.sp.xa);
        let n = 1u32 << k;
        halve(scratch, w.a, w.b, k, inv_root);
        let mut t = w.t;
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                let tc = t.clamp(0.0, 1.0);
                let m = ((tc * n as f32 + 0.5).floor() as u32).min(n);
                let v = V3::<S>::of(scratch[m as usize]);
                out.put(i, lit.shade(v).f32(), n4(v));
            }
            t += w.dt;
            z += span.dz;
        }
    }

    /// bishop_weimer: each cosine's Taylor polynomial by forward differences.
    #[inline]
    fn bishop_weimer(&self, tri: &Tri, st: &SpanSetup<S>, span: RowSpan, out: &mut RowOut) {
        let lit = &self.lit;
        let mut z = span.z;
        let c = lit.cosines();
        let x = S::of(span.i0 as f32 + 0.5 - st.o.x);
        let y = S::of(span.y as f32 + 0.5 - st.o.y);
        let (mut v, mut d1, mut d2) = (
            [S::ZERO; 2 * MAX_LIGHTS],
            [S::ZERO; 2 * MAX_LIGHTS],
            [S::ZERO; 2 * MAX_LIGHTS],
        );
        let two = S::of(2.0);
        for k in 0..c {
            let [t0, t1, t2, t3, t4, t5] = st.taylor[k];
            v[k] = t5 * x * x + t4 * x * y + t3 * y * y + t2 * x + t1 * y + t0;
            d1[k] = t5 * (two * x + S::ONE) + t4 * y + t2;
            d2[k] = two * t5;
        }
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                out.put(i, lit.shade_cosines(|k, _| v[k]).f32(), [0.0; 4]);
            }
            for k in 0..c {
                v[k] += d1[k];
                d1[k] += d2[k];
            }
            z += span.dz;
        }
    }

    /// hast_euler: each cosine by Euler steps with the end-error correction.
    #[inline]
    fn hast_euler(&self, tri: &Tri, span: RowSpan, out: &mut RowOut) {
        let lit = &self.lit;
        let mut z = span.z;
        let w = walk::<S>(tri, &span);
        let c = lit.cosines();
        let (na, nb) = (w.sp.na, w.sp.nb);
        let (mut v, mut d1, mut d2) = (
            [S::ZERO; 2 * MAX_LIGHTS],
            [S::ZERO; 2 * MAX_LIGHTS],
            [S::ZERO; 2 * MAX_LIGHTS],
        );
        let mut ends = [(S::ZERO, S::ZERO); 2 * MAX_LIGHTS];
        // Seeded at the first pixel's own t, not clamped (as Chebyshev): a covered
        // centre a rounding outside [xA, xB] takes the end value the twin's clamped t
        // gives, and the rest of the span stays on its own grid.
        let (t, dt) = (w.t, w.dt);
        let (ts, dts, two) = (S::of(t), S::of(dt), S::of(2.0));
        for k in 0..c {
            let dir = lit.dir(k);
            let i0 = dir.dot(na) / na.length();
            // An empty span (or a NaN length): the value at xA throughout.
            let len = w.sp.xb - w.sp.xa;
            if len.is_nan() || len <= 0.0 {
                v[k] = i0;
                ends[k] = (i0, i0);
                continue;
            }
            let i1 = dir.dot(nb) / nb.length();
            let dn = nb - na;
            let half = S::of(0.5) * (sc::cosine_slope(dir, nb, dn) - sc::cosine_slope(dir, na, dn));
            let di = i1 - i0;
            v[k] = i0 + ts * di + half * ts * (ts - S::ONE);
            d1[k] = dts * di + half * dts * (two * ts + dts - S::ONE);
            d2[k] = two * half * dts * dts;
            ends[k] = (i0, i1);
        }
        let mut t = t;
        for i in span.i0..=span.i1 {
            if out.test(tri, i, z, span.centre(i)) {
                let at = |k: usize| match t {
                    t if t < 0.0 => ends[k].0,
                    t if t > 1.0 => ends[k].1,
                    _ => v[k],
                };
                out.put(i, lit.shade_cosines(|k, _| at(k)).f32(), [0.0; 4]);
            }
            for k in 0..c {
                v[k] += d1[k];
                d1[k] += d2[k];
            }
            t += dt;
            z += span.dz;
        }
    }

    /// Digital segments (docs/formulas.md#digital-segments): segments of 2^k pixels from the span's
    /// first pixel centre; each end's normal by accumulating 2^k dN (the first from the span's
    /// formula), normalised and shaded once (the right end of one segment is the left of the next,
    /// the last one extrapolated past the span); inside, the colour stepped by (I_p - I_l) / 2^k,
    /// or with `inv_root` the normals by halving between the unit ends.
    fn segments(
        &self,
        tri: &Tri,
        span: RowSpan,
        out: &mut RowOut,
        grid: &mut Vec<Vec3>,
        k: u32,
        inv_root: Option<fn(S) -> S>,
    ) {
        let lit = &self.lit;
        let (s, n) = corners::<S>(tri);
        let sp = sc::span_at(span.y as f32 + 0.5, s, n);
        let len = 1i64 << k;
        let p0 = (sp.xa - 0.5).ceil() + 0.5;
        let start = (p0 - 0.5) as i64;
        let dseg = if sp.xb > sp.xa {
            (sp.nb - sp.na) * S::of(len as f32 / (sp.xb - sp.xa))
        } else {
            V3::zero()
        };
        let tiny = S::of(1e-12);
        let end = |n: V3<S>| f::normalize_exact(if n.dot(n) > tiny { n } else { sp.na });
        let scale = S::of(1.0 / len as f32);
        let mut seg = i64::MIN;
        let (mut nr, mut np) = (V3::zero(), V3::zero());
        let (mut ip, mut c, mut dc) = (V3::zero(), V3::zero(), V3::zero());
        let mut z = span.z;
        for i in span.i0..=span.i1 {
            let j = (i as i64 - start).max(0);
            let (s, v) = (j >> k, (j & (len - 1)) as usize);
            if s != seg {
                let (nl, il) = if s == seg + 1 {
                    (np, ip)
                } else {
                    nr = sc::span_normal(&sp, p0 + (s << k) as f32);
                    let nl = end(nr);
                    (nl, lit.shade(nl))
                };
                nr += dseg;
                np = end(nr);
                match inv_root {
                    None => {
                        ip = lit.shade(np);
                        dc = (ip - il) * scale;
                        c = il + dc * S::of(v as f32);
                    }
                    Some(r) => {
                        halve(grid, nl, np, k, r);
                        ip = il; // unused with dichotomy inside
                    }
                }
                seg = s;
            }
            if out.test(tri, i, z, span.centre(i)) {
                match inv_root {
                    None => out.put(i, c.f32(), [0.0; 4]),
                    Some(_) => {
                        let n = V3::<S>::of(grid[v]);
                        out.put(i, lit.shade(n).f32(), n4(n));
                    }
                }
            }
            // Pixels left of the first centre p0 (coverage and span rounded apart) sit at
            // v = 0 with the twin; the colour steps from p0 on.
            if i as i64 >= start {
                c += dc;
            }
            z += span.dz;
        }
    }
}
