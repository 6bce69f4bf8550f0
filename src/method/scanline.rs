//! The scanline family in f64 (FORMULAS.md 1.6, 2.10-2.13): the span through a pixel's row and
//! the interpolations along it. Each function is the literal f64 port of its GLSL twin in
//! glsl/scanline.glsl or glsl/methods/, with the same branches and thresholds, so that the
//! float32 image and this f64 evaluation differ only by rounding.
use glam::{DVec2, DVec3};

use super::formulas::normalize_exact;

/// The span through one row of a triangle: its two ends on the triangle's edges, with the
/// Phong edge normals there (linear along the edge, not unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub xa: f64,
    pub na: DVec3,
    pub xb: f64,
    pub nb: DVec3,
}

/// The span through the row `py` of the triangle with window-space corners `s` and vertex
/// normals `nv` (FORMULAS.md 1.6). `py` is first clamped to the triangle's rows, so a pixel
/// the rasterizer covers on the triangle's top or bottom row still finds its edges. A
/// triangle with no non-horizontal edge (all corners on one row) gives the empty span at
/// corner 0.
pub fn span_at(py: f64, s: [DVec2; 3], nv: [DVec3; 3]) -> Span {
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
        let x = mix(p.x, q.x, u);
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

/// GLSL `mix` on scalars: `x (1 - a) + y a`.
fn mix(x: f64, y: f64, a: f64) -> f64 {
    x * (1.0 - a) + y * a
}

/// Where pixel `px` lies on the span: `clamp((px - xA) / (xB - xA), 0, 1)`, 0 on an empty span.
pub fn span_t(sp: &Span, px: f64) -> f64 {
    if sp.xb > sp.xa {
        ((px - sp.xa) / (sp.xb - sp.xa)).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The unit span-end normals N'_A, N'_B (exact normalisation, as the seeds assume) and `t` of
/// the pixel at `pixel` in the triangle (`window`, `normals`).
pub fn span_ends(pixel: DVec2, window: [DVec2; 3], normals: [DVec3; 3]) -> (DVec3, DVec3, f64) {
    let sp = span_at(pixel.y, window, normals);
    (
        normalize_exact(sp.na),
        normalize_exact(sp.nb),
        span_t(&sp, pixel.x),
    )
}

/// Spherical linear interpolation between unit `a` and `b` (FORMULAS.md 2.10), in the
/// Gram-Schmidt closed form of 2.11 (Appendix C `saClosed`): `a cos(t theta) + (b - a c)
/// sin(t theta) / sin(theta)`, `c = a.b` clamped to [-1, 1]. Within 1e-8 of parallel
/// (`1 - c^2 < 1e-8`, theta < 1e-4 rad) it falls back to `normalize(mix(a, b, t))`, which
/// agrees there to ~1e-9; antipodal ends (no plane) take the same fallback, whose result is
/// then the zero vector at t = 1/2 (the method's documented hazard).
pub fn slerp(a: DVec3, b: DVec3, t: f64) -> DVec3 {
    let c = a.dot(b).clamp(-1.0, 1.0);
    let s2 = 1.0 - c * c;
    if s2 < 1e-8 {
        return normalize_exact(a * (1.0 - t) + b * t);
    }
    let th = c.acos();
    a * (t * th).cos() + (b - a * c) * ((t * th).sin() / s2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::assert_close;

    fn tri() -> ([DVec2; 3], [DVec3; 3]) {
        (
            [
                DVec2::new(10.0, 10.0),
                DVec2::new(30.0, 12.0),
                DVec2::new(15.0, 40.0),
            ],
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
    fn slerp_is_unit_and_angle_proportional() {
        // 90 degrees apart: at t the angle from a is t * 90 degrees (FORMULAS.md 2.10).
        let (a, b) = (DVec3::X, DVec3::Y);
        for t in [0.0, 0.1, 0.25, 0.5, 0.9, 1.0] {
            let n = slerp(a, b, t);
            assert_close("|slerp|", n.length(), 1.0, 1e-15);
            assert_close(
                "angle",
                n.angle_between(a),
                t * std::f64::consts::FRAC_PI_2,
                1e-12,
            );
        }
        // Nearly parallel: the normalize(mix) fallback, continuous with the closed form.
        let b = DVec3::new(1.0, 1e-5, 0.0).normalize();
        let n = slerp(DVec3::X, b, 0.5);
        assert_close("tiny angle", n.angle_between(DVec3::X), 0.5e-5, 1e-12);
    }
}
