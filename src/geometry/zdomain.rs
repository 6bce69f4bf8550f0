//! The range of z = N.N that interpolating a triangle's three vertex normals produces, exact per
//! triangle: `tune` fits and proves its candidates over it (src/tune/domain.rs), and `auto`
//! draws a tuned method on a triangle only when that triangle's range lies inside the range the
//! method was proven on (src/auto/choice.rs).
//!
//! [`smallest_squared_length`]: the smallest `|w0 n0 + w1 n1 + w2 n2|^2` over the barycentric
//! weights, a convex quadratic minimised exactly (never by sampling). [`widened`]: a smallest z
//! and a longest normal widened by the float32 rounding of the inputs ([`INPUT_ROUNDING`]), the
//! range the device's z can take on the triangle.
use glam::DVec3;

use crate::method::interval::Interval;
use crate::method::real::Real;

/// How far the float32 rounding of the inputs moves |N|: each rounded normal is within
/// 2^-24 |N_i| of the exact one and each rounded weight within 2^-24 w_i + 1e-15, so
/// |N~ - N| <= sum w_i (2^-24 + 2^-24 (1 + 2^-24)) + 3e-15 ~ 1.2e-7 (the weights sum to 1);
/// twice that for margin.
pub const INPUT_ROUNDING: f64 = 2.5e-7;

/// The smallest `|sum w_i n_i|^2` over the weights of a triangle (w_i >= 0, sum 1), exact up
/// to f64 rounding: the function is convex (a Gram matrix), so its minimum is the interior
/// stationary point when that lies inside, else on an edge, where `|a + t (b - a)|^2` is
/// minimal at `t = -a.(b - a) / |b - a|^2` clamped to [0, 1].
pub fn smallest_squared_length(n: [DVec3; 3]) -> f64 {
    let edge = |a: DVec3, b: DVec3| {
        let d = b - a;
        let dd = d.length_squared();
        let t = if dd > 0.0 {
            (-a.dot(d) / dd).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + d * t).length_squared()
    };
    let on_edges = edge(n[0], n[1]).min(edge(n[1], n[2])).min(edge(n[2], n[0]));
    // The plane n0 + w1 d1 + w2 d2: normal equations of the origin's projection.
    let (d1, d2) = (n[1] - n[0], n[2] - n[0]);
    let (a, b, c) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let (r1, r2) = (-n[0].dot(d1), -n[0].dot(d2));
    let det = a * c - b * b;
    if det <= 1e-14 * (a * c).max(f64::MIN_POSITIVE) {
        // The normals' affine hull is a line or a point: the minimum lies on an edge.
        return on_edges;
    }
    let (w1, w2) = ((r1 * c - r2 * b) / det, (a * r2 - b * r1) / det);
    if w1 >= 0.0 && w2 >= 0.0 && w1 + w2 <= 1.0 {
        (n[0] + d1 * w1 + d2 * w2).length_squared().min(on_edges)
    } else {
        on_edges
    }
}

/// The proven range of z for a smallest z of `z_min` and normals up to `n_max` long: |N|
/// widened by [`INPUT_ROUNDING`] each way (and 1e-12 for this module's own f64 rounding).
pub fn widened(z_min: f64, n_max: f64) -> Interval {
    let lo = (Interval::point((z_min - 1e-12).max(0.0)).sqrt() - Interval::point(INPUT_ROUNDING))
        .lo
        .max(0.0);
    let hi = Interval::point(n_max) + Interval::point(INPUT_ROUNDING);
    Interval::new(lo, hi.hi).sqr()
}

/// The range of z the device can produce on the triangle of vertex normals `n` (as uploaded,
/// float32, in f64): its exact smallest z and its longest normal, [`widened`].
pub fn triangle_z_range(n: [DVec3; 3]) -> Interval {
    let longest = n.iter().map(|v| v.length()).fold(0.0, f64::max);
    widened(smallest_squared_length(n), longest)
}
