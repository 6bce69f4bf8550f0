//! The domain of z = N.N a mesh actually has, exactly per triangle and as a distribution over
//! the pixels it covers.
//!
//! Per triangle: the smallest `|w0 n0 + w1 n1 + w2 n2|^2` over the barycentric weights
//! (w_i >= 0, summing to 1) of its vertex normals as the device receives them (float32,
//! [`smallest_squared_length`], in src/geometry/zdomain.rs for `auto`): a convex quadratic over the triangle (its matrix is the Gram
//! matrix of the normals), minimised exactly: the projection of the origin onto the normals'
//! plane when it falls inside, else the smallest of the three edges' minima (each a
//! one-dimensional quadratic), never by sampling. The mesh's proven domain is
//! [smallest over its triangles, 1], widened by the float32 rounding of the inputs as `prove`
//! widens its own ([`widened`], [`crate::geometry::zdomain::INPUT_ROUNDING`]).
//!
//! The dichotomy methods' factor is `1/sqrt(2 + 2c)`, c the cosine between the unit span ends;
//! per triangle the smallest c is the smallest pairwise cosine of its unit vertex normals
//! ([`smallest_cosine`]): the span ends lie on the spherical triangle of the normals, whose
//! widest pair of points is a pair of corners while the corners are at most 90 deg apart (the
//! distance from a point to a moving point of a great-circle arc has no interior maximum
//! below 90 deg). Beyond 90 deg that figure is a lower end no longer attained: `dichotomy
//! .exact` says so.
//!
//! Per covered pixel (at the render size, the rasterizer's own weights from the id pass): z,
//! and the dichotomy's c and `1/sqrt(2 + 2c)` at the span through the pixel's row.
use glam::{DVec2, DVec3};
use serde::Serialize;

use crate::analysis::stats::{histogram, percentiles};
use crate::frame::IdFrame;
pub use crate::geometry::zdomain::{smallest_squared_length, widened};
use crate::method::scanline::span_ends;
use crate::scene::SceneInputs;

/// The smallest pairwise cosine of the unit vertex normals (the dichotomy's smallest c on the
/// triangle while the normals are at most 90 deg apart).
pub fn smallest_cosine(n: [DVec3; 3]) -> f64 {
    let u = n.map(|v| v.normalize_or_zero());
    u[0].dot(u[1]).min(u[1].dot(u[2])).min(u[2].dot(u[0]))
}

/// A distribution of values: count, extremes, percentiles and a histogram.
#[derive(Debug, Clone, Serialize)]
pub struct Distribution {
    pub count: usize,
    pub min: f64,
    pub max: f64,
    /// The 0.1st, 1st, 50th and 99th percentiles (nearest rank).
    pub p0_1: f64,
    pub p1: f64,
    pub p50: f64,
    pub p99: f64,
    /// (lower edge, upper edge, count), edges as given; values outside every bin are not
    /// counted here (count says how many there are).
    pub histogram: Vec<(f64, f64, usize)>,
}

impl Distribution {
    /// Of `values` over the bins `edges` (ascending; each bin [a, b), the last closed).
    pub fn of(values: &[f64], edges: &[f64]) -> Distribution {
        let mut v: Vec<f64> = values.to_vec();
        let [p0_1, p1, p50, p99] = percentiles(&mut v, [0.1, 1.0, 50.0, 99.0]);
        let histogram = histogram(values, edges);
        Distribution {
            count: values.len(),
            min: values.iter().copied().fold(f64::INFINITY, f64::min),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            p0_1,
            p1,
            p50,
            p99,
            histogram,
        }
    }
}

/// The bins of z: the classes of [`CLASS_EDGES`] (z above 1 by rounding falls in the last).
fn z_bins() -> Vec<f64> {
    let mut e = CLASS_EDGES.to_vec();
    e.push(1.0 + 1e-3);
    e
}

/// The lower ends of the classes of triangles by their smallest z (docs/tune.md): the answer
/// per class is what `auto` would draw on those triangles.
pub const CLASS_EDGES: [f64; 10] = [0.0, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.999];

/// The dichotomy's first halving on the mesh.
#[derive(Debug, Clone, Serialize)]
pub struct Dichotomy {
    /// The smallest pairwise cosine of unit vertex normals over the triangles.
    pub c_min: f64,
    /// The largest pairwise angle, degrees.
    pub max_angle_deg: f64,
    /// Whether c_min is attained by span ends (every triangle's normals within 90 deg).
    pub exact: bool,
    /// The range of `1/sqrt(2 + 2c)` over c in [c_min, 1].
    pub factor_range: [f64; 2],
    /// c at the span ends of each covered pixel's row.
    pub pixels_c: Distribution,
    /// `1/sqrt(2 + 2c)` at each covered pixel.
    pub pixels_factor: Distribution,
}

/// The mesh's domain.
#[derive(Debug, Clone, Serialize)]
pub struct MeshDomain {
    pub triangles: usize,
    /// The smallest z over every triangle (exact per triangle, in f64 from the float32
    /// normals).
    pub z_min: f64,
    /// Which triangle reaches it.
    pub z_min_triangle: usize,
    /// The longest float32 vertex normal (1 up to its rounding).
    pub largest_normal_length: f64,
    /// The proven domain of z: [z_min, largest |n|^2], |N| widened by the inputs' float32
    /// rounding (INPUT_ROUNDING, as `prove`).
    pub z_range: [f64; 2],
    /// Each triangle's smallest z, over the classes' bins.
    pub triangles_z_min: Distribution,
    /// z at each covered pixel (render size, the rasterizer's weights).
    pub pixels_z: Distribution,
    pub dichotomy: Dichotomy,
    /// Per triangle, its smallest z (for the classes).
    #[serde(skip)]
    pub per_triangle: Vec<f64>,
    /// Per covered pixel, its triangle and z.
    #[serde(skip)]
    pub per_pixel: Vec<(u32, f64)>,
}

/// The domain of `inputs` (every triangle) and of the pixels `ids` covers.
pub fn of_mesh(inputs: &SceneInputs, ids: &IdFrame) -> MeshDomain {
    let count = inputs.triangle_count();
    let mut per_triangle = Vec::with_capacity(count);
    let (mut c_min, mut n_max) = (1.0f64, 0.0f64);
    for t in 0..count {
        let n = inputs.vertex_normals(t);
        per_triangle.push(smallest_squared_length(n));
        c_min = c_min.min(smallest_cosine(n));
        n_max = n.iter().map(|v| v.length()).fold(n_max, f64::max);
    }
    let (z_min_triangle, z_min) = per_triangle
        .iter()
        .copied()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, 1.0));
    let (mut per_pixel, mut cs) = (Vec::new(), Vec::new());
    for (k, &p) in ids.prim.iter().enumerate() {
        if p == 0 {
            continue;
        }
        let t = (p - 1) as usize;
        let n = inputs.vertex_normals(t);
        let w = ids.weights[k];
        let v = n[0] * f64::from(w[0]) + n[1] * f64::from(w[1]) + n[2] * f64::from(w[2]);
        per_pixel.push((p - 1, v.length_squared()));
        let window = [0, 1, 2].map(|i| {
            let w = inputs.window[3 * t + i];
            DVec2::new(f64::from(w[0]), f64::from(w[1]))
        });
        let (x, y) = (k as u32 % ids.width, k as u32 / ids.width);
        let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
        let (a, b, _) = span_ends(centre, window, n);
        cs.push(a.dot(b));
    }
    let zs: Vec<f64> = per_pixel.iter().map(|&(_, z)| z).collect();
    let factors: Vec<f64> = cs.iter().map(|c| 1.0 / (2.0 + 2.0 * c).sqrt()).collect();
    let c_edges: Vec<f64> = (0..=20).map(|i| f64::from(i) / 10.0 - 1.0).collect();
    let f_edges: Vec<f64> = (0..=16).map(|i| 0.5 + f64::from(i) * 0.0625).collect();
    let range = widened(z_min, n_max);
    MeshDomain {
        triangles: count,
        z_min,
        z_min_triangle,
        largest_normal_length: n_max,
        z_range: [range.lo, range.hi],
        triangles_z_min: Distribution::of(&per_triangle, &z_bins()),
        pixels_z: Distribution::of(&zs, &z_bins()),
        dichotomy: Dichotomy {
            c_min,
            max_angle_deg: c_min.clamp(-1.0, 1.0).acos().to_degrees(),
            exact: c_min >= 0.0,
            factor_range: [0.5, 1.0 / (2.0 + 2.0 * c_min).max(0.0).sqrt()],
            pixels_c: Distribution::of(&cs, &c_edges),
            pixels_factor: Distribution::of(&factors, &f_edges),
        },
        per_triangle,
        per_pixel,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(rng: &mut fastrand::Rng) -> DVec3 {
        loop {
            let v = DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 2.0 - DVec3::ONE;
            if v.length() > 1e-3 && v.length() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// Three unit normals within `spread` radians of a random axis.
    fn triangle(spread: f64, rng: &mut fastrand::Rng) -> [DVec3; 3] {
        let axis = unit(rng);
        [0; 3].map(|_| (axis + unit(rng) * spread.tan() * rng.f64()).normalize())
    }

    /// The smallest z over a dense grid of weights (n x n per side, the edges included).
    fn sampled(n: [DVec3; 3], steps: usize) -> f64 {
        let mut best = f64::INFINITY;
        for i in 0..=steps {
            for j in 0..=steps - i {
                let (w1, w2) = (i as f64 / steps as f64, j as f64 / steps as f64);
                let v = n[0] * (1.0 - w1 - w2) + n[1] * w1 + n[2] * w2;
                best = best.min(v.length_squared());
            }
        }
        best
    }

    /// How far `minimiser` is from dense sampling on random triangles: (largest amount by which
    /// it lies above the sampled minimum, largest amount below it).
    fn against_sampling(minimiser: fn([DVec3; 3]) -> f64) -> (f64, f64) {
        let mut rng = fastrand::Rng::with_seed(42);
        let (mut above, mut below) = (0.0f64, 0.0f64);
        for k in 0..400 {
            let spread = [0.05, 0.3, 0.8, 1.5][k % 4];
            let n = triangle(spread, &mut rng);
            let (m, s) = (minimiser(n), sampled(n, 300));
            above = above.max(m - s);
            below = below.max(s - m);
        }
        (above, below)
    }

    /// The exact minimum is never above a sampled value and within the grid's resolution of
    /// the sampled minimum: the grid's step is 1/300, the function's slope at most 4, so a
    /// grid point lies within ~2e-4 of the minimum's value (its curvature, less).
    #[test]
    fn the_smallest_z_is_exact_against_dense_sampling() {
        let (above, below) = against_sampling(smallest_squared_length);
        assert!(above <= 1e-12, "above the sampled minimum by {above}");
        assert!(below < 2e-4, "{below}");
    }

    /// Teeth: minimisers that look only at the edges, or at the corners and the centroid, are
    /// above the true minimum on some triangles; the check above fails them.
    #[test]
    fn a_wrong_minimiser_fails_the_sampling_check() {
        fn edges_only(n: [DVec3; 3]) -> f64 {
            [(0, 1), (1, 2), (2, 0)]
                .iter()
                .map(|&(i, j)| ((n[i] + n[j]) * 0.5).length_squared())
                .fold(f64::INFINITY, f64::min)
        }
        fn centroid(n: [DVec3; 3]) -> f64 {
            ((n[0] + n[1] + n[2]) / 3.0).length_squared()
        }
        for wrong in [edges_only as fn([DVec3; 3]) -> f64, centroid] {
            let (above, _) = against_sampling(wrong);
            assert!(above > 1e-6, "{above}");
        }
    }

    /// Known values: three normals pairwise theta apart reach (1 + 2 cos theta)/3 at the
    /// centroid; two equal normals and a third at theta reach cos^2(theta/2) on an edge; equal
    /// normals give 1; antipodal ones 0.
    #[test]
    fn known_triangles() {
        for theta in [10f64, 40.0, 90.0, 119.0] {
            let c = theta.to_radians().cos();
            let tilt = ((2.0 / 3.0) * (1.0 - c)).sqrt().asin();
            let n = [0.0, 1.0, 2.0].map(|i: f64| {
                let phi = i * std::f64::consts::TAU / 3.0;
                DVec3::new(tilt.sin() * phi.cos(), tilt.sin() * phi.sin(), tilt.cos())
            });
            let z = smallest_squared_length(n);
            assert!((z - (1.0 + 2.0 * c) / 3.0).abs() < 1e-12, "{theta}: {z}");
            assert!((smallest_cosine(n) - c).abs() < 1e-12);
            let a = DVec3::Z;
            let b = DVec3::new(theta.to_radians().sin(), 0.0, theta.to_radians().cos());
            let z = smallest_squared_length([a, a, b]);
            assert!((z - (0.5 * theta).to_radians().cos().powi(2)).abs() < 1e-12);
        }
        assert_eq!(smallest_squared_length([DVec3::Z; 3]), 1.0);
        assert!(smallest_squared_length([DVec3::Z, -DVec3::Z, DVec3::X]) < 1e-30);
    }

    /// The dichotomy's smallest c is attained by span ends: over dense pairs of points on two
    /// edges (normalised), none has a smaller cosine, and the corners reach it.
    #[test]
    fn the_smallest_cosine_bounds_every_pair_of_span_ends() {
        let mut rng = fastrand::Rng::with_seed(3);
        for _ in 0..200 {
            let n = triangle(0.6, &mut rng);
            let c = smallest_cosine(n);
            let mut lowest = f64::INFINITY;
            for e in 0..3 {
                let (a0, a1) = (n[e], n[(e + 1) % 3]);
                let (b0, b1) = (n[(e + 1) % 3], n[(e + 2) % 3]);
                for i in 0..=40 {
                    for j in 0..=40 {
                        let a = a0.lerp(a1, f64::from(i) / 40.0).normalize();
                        let b = b0.lerp(b1, f64::from(j) / 40.0).normalize();
                        lowest = lowest.min(a.dot(b));
                    }
                }
            }
            assert!(lowest >= c - 1e-12 && lowest - c < 1e-12, "{lowest} vs {c}");
        }
    }

    #[test]
    fn the_widened_range_holds_the_rounding() {
        let r = widened(0.5, 1.0);
        assert!(r.lo < 0.5 && 0.5 - r.lo < 1e-6 && r.hi > 1.0 && r.hi - 1.0 < 1e-6);
        assert_eq!(widened(0.0, 1.0).lo, 0.0);
    }
}
