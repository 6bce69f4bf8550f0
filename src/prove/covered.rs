//! The methods `prove` covers and the domain it proves them over. A covered method scales the
//! interpolated normal by a factor of its squared length (`N' = k(z) N`, z = N.N): its row's
//! kernel carries the factor ([`Scale`]), whose generic formula `prove` instantiates with
//! [`Interval`] and [`Dual`] (the same function the f64 twin and the software engine
//! instantiate). Every other method is listed with the reason it is out of reach.
//!
//! The domains ([`super::domain`]) enter as ranges of z: [`triangle_z_range`] for any triangle
//! (three free unit normals pairwise at most theta apart, any weights), [`z_range`] for the
//! geometry of `stress`'s cases ([`crate::cases::Case`]: N0, N1 `theta` apart, N2 their
//! bisector, weights `((1-s)(1-t), (1-s) t, s)`); in both each normal component and each
//! weight is perturbed by its float32 rounding (relative 2^-24, as the device and the f64 twin
//! receive them), [`INPUT_ROUNDING`]. The view and the light do not change z, so the
//! normal-space errors do not depend on them.
use glam::DVec3;

use super::bnb::{maximise, Cell, Effort, Point};
use super::dual::{mean_value, Dual};
use super::interval::Interval;
use crate::cases::{errors, Case, CaseSpec, Shape};
use crate::method::real::Real;
use crate::method::{Family, Input, Method, Scale};

/// The scale `prove` covers for `m` (None: not covered): its row's kernel
/// ([`crate::method::Kernel::provable`]).
pub fn factor_of(m: &Method) -> Option<&Scale> {
    m.kernel.provable()
}

/// Why a method is not covered.
pub fn out_of_reach(m: &Method) -> &'static str {
    if m.name == crate::method::PHONG_EXACT {
        return "the exact reference itself (its error is 0 by definition)";
    }
    if m.inputs.contains(&Input::SpecularLut) {
        return "its normal is exact normalisation (error 0); its error is the cos^n table's \
                in the specular term, a function of the cosine and the shininess that the \
                normal-space bound does not carry (not formulated in intervals in this version)";
    }
    if !m.has_normal {
        return "no per-pixel normal (colour interpolated or cosines approximated): its error \
                is a colour error over the lighting's inputs too (7+ dimensions), beyond this \
                version's budget";
    }
    match m.family {
        Family::Scanline | Family::DigitalSegments => {
            "the normal depends on the span's ends, its pixel position and length (and for \
             dichotomy on the halving levels): 4+ dimensions with discrete levels, not \
             formulated in intervals in this version"
        }
        Family::VertexAttribute => {
            "the normal is a vector function of the three corner normals and the weights (5+ \
             dimensions): not formulated in intervals in this version"
        }
        _ if m.inputs.contains(&Input::FlatNormal) => {
            "a vector method (the flat normal enters): its angle error needs the triangle's \
             orientation, not formulated in intervals in this version"
        }
        _ => "its normal is not a scale of the interpolated normal: not formulated in intervals",
    }
}

/// How far the float32 rounding of the inputs moves |N| (with the triangle's z range, which
/// `tune` and `auto` share).
pub use crate::geometry::zdomain::INPUT_ROUNDING;

/// The enclosure of `z = N.N` over a cell. With N0, N1 = cos(theta/2) M -+ sin(theta/2) T and
/// N2 = M: `N = (w1 - w0) sin T + ((w0 + w1) cos + w2) M`, and with the weights of the cell,
/// `w1 - w0 = (1 - s)(2t - 1)`, `(w0 + w1) cos + w2 = 1 - (1 - s)(1 - cos)`; then |N| is
/// widened by [`INPUT_ROUNDING`].
pub fn squared_length(c: &Cell) -> Interval {
    let deg = std::f64::consts::PI / 360.0;
    let to_half_rad = Interval::new(deg.next_down(), deg.next_up());
    let half = c[0] * to_half_rad;
    let (sh, ch) = (half.sin(), half.cos());
    let one = Interval::point(1.0);
    let (t, s) = (c[1], c[2]);
    let a = one - s;
    let across = a * (Interval::point(2.0) * t - one);
    let along = one - a * (one - ch);
    // sqr of the widened length: an end below 0 counts as 0 (|N| >= 0).
    (across.sqr() * sh.sqr() + along.sqr())
        .sqrt()
        .widen(INPUT_ROUNDING)
        .sqr()
}

/// The normal-space quantities `prove` bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metric {
    /// `| |N'| - 1 |`.
    Length,
    /// `|N'| - 1`, signed (its maximum carries into the specular term's derivative).
    LengthSigned,
    /// Angle between N' and normalize(N), radians.
    Angle,
}

impl Metric {
    pub fn as_str(self) -> &'static str {
        match self {
            Metric::Length => "length_error",
            Metric::LengthSigned => "length_error_signed",
            Metric::Angle => "angle_error_rad",
        }
    }
}

/// The upper bound of `metric` over the squared lengths `z` for the factor `k` (a covered
/// method's metrics depend on its inputs only through z).
pub fn upper(k: &Scale, metric: Metric, z: Interval) -> f64 {
    let kz = k.k(z);
    if metric == Metric::Angle {
        // k > 0 keeps the direction exactly; a sign change may turn it by pi.
        return if kz.lo > 0.0 {
            0.0
        } else {
            std::f64::consts::PI
        };
    }
    if k.exact_on.is_some_and(|(lo, hi)| z.lo >= lo && z.hi <= hi) {
        // k(z) sqrt(z) = 1 identically on the box: |N'| - 1 = 0
        return 0.0;
    }
    let one = Interval::point(1.0);
    let e = if kz.lo > 0.0 {
        // |N'| - 1 = k(z) sqrt(z) - 1, in the mean-value form (it cancels near z = 1).
        mean_value(
            z,
            |z| k.k(z) * z.sqrt() - one,
            |z| k.k(z) * z.sqrt() - Dual::c(1.0),
        )
    } else {
        let abs_k = if kz.hi <= 0.0 {
            -kz
        } else {
            Interval::new(0.0, kz.mag())
        };
        abs_k * z.sqrt() - one
    };
    if metric == Metric::Length {
        e.mag()
    } else {
        e.hi
    }
}

/// The proven range of z over the domain up to `max_angle_deg`: the lower end by
/// branch-and-bound of `1 - z` over (theta, t, s) (its maximum is a point, the edge's middle at
/// the largest angle, so it converges fast), the upper end `(1 + rounding)^2` (a convex
/// combination of unit vectors is at most 1 long: the triangle inequality).
pub fn z_range(max_angle_deg: f64) -> Interval {
    let unit = Interval::new(0.0, 1.0);
    let root = [Interval::new(0.0, max_angle_deg), unit, unit];
    let effort = Effort {
        tolerance: 1e-6,
        atol: 1e-6,
        max_boxes: 20_000,
        max_seconds: 5.0,
    };
    let o = maximise(
        root,
        effort,
        |c| (Interval::point(1.0) - squared_length(c)).hi,
        |p| {
            let case = Case::new(spec_at(p, 1.0));
            Some(1.0 - case.fragment.interpolated_normal().length_squared())
        },
    );
    let hi = (Interval::point(1.0).widen(INPUT_ROUNDING)).sqr().hi;
    Interval::new((1.0 - o.proven_upper).next_down().max(0.0), hi)
}

/// The proven range of z over a triangle with three free unit vertex normals pairwise at most
/// `max_angle_deg` apart and any weights (each input rounded to float32). With the weights
/// w_i >= 0 summing to 1 and cos(a_ij) >= cos(theta) (a_ij <= theta <= 180 deg):
/// `z = sum w_i^2 + sum_{i != j} w_i w_j cos a_ij >= cos theta + (1 - cos theta) sum w_i^2
/// >= (1 + 2 cos theta) / 3` (sum w_i^2 >= 1/3, and 1 - cos theta >= 0), reached at the
/// centroid of three normals pairwise theta apart (theta <= 120 deg); z >= 0 always, reached
/// from 120 deg on (three coplanar normals 120 deg apart sum to 0), where (1 + 2 cos theta)/3
/// <= 0. The real z of the rounded inputs is within [`INPUT_ROUNDING`] of |N| (the same
/// widening as [`squared_length`]'s). The upper end as [`z_range`]'s. docs/proof.md has the
/// argument; `prove::triangles` samples random triangles against it.
pub fn triangle_z_range(max_angle_deg: f64) -> Interval {
    let deg = std::f64::consts::PI / 180.0;
    let to_rad = Interval::new(deg.next_down(), deg.next_up());
    let cos = (Interval::point(max_angle_deg) * to_rad).cos();
    let lo = ((Interval::point(1.0) + Interval::point(2.0) * cos) / Interval::point(3.0)).lo;
    // |N| widened by the inputs' rounding, as in `squared_length`.
    Interval::new(lo.max(0.0), 1.0)
        .sqrt()
        .widen(INPUT_ROUNDING)
        .sqr()
}

/// A real point on the edge whose squared length is `z` (theta = `max_angle_deg`, t from
/// `z = cos^2 + (2t - 1)^2 sin^2` of half the angle; clamped into the edge).
pub fn point_for_z(z: f64, max_angle_deg: f64) -> Point {
    let h = (0.5 * max_angle_deg).to_radians();
    let (s2, c2) = (h.sin().powi(2), h.cos().powi(2));
    let u = if s2 > 0.0 {
        ((z - c2) / s2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [max_angle_deg, 0.5 * (1.0 - u.sqrt()), 0.0]
}

/// Span of the strip a real point is placed on (the largest `stress --replay` accepts).
pub const SPAN: u32 = 1 << 20;

/// The `stress` case of a real point (theta, t) on the edge: a strip of [`SPAN`] pixels, the
/// pixel nearest t, the view and the light along the exact normal there (the colour's worst
/// place for a method that only scales the normal).
pub fn spec_at(p: &Point, shininess: f64) -> CaseSpec {
    let (theta, t) = (p[0], p[1]);
    let pixel = ((t * f64::from(SPAN)).round() as i64).clamp(0, i64::from(SPAN) - 1) as u32;
    let tq = f64::from(pixel) / f64::from(SPAN);
    let half = (0.5 * theta).to_radians();
    let phi = ((2.0 * tq - 1.0) * half.sin())
        .atan2(half.cos())
        .to_degrees();
    CaseSpec {
        theta_deg: theta,
        elevation_deg: -phi,
        pair_azimuth_deg: 0.0,
        roll_deg: 0.0,
        light_deg: phi,
        light_out_of_plane: false,
        shininess,
        length: 1.0,
        shape: Shape::Strip,
        span_px: SPAN,
        pixel,
        specular_only: false,
        apex_deg: 0.0,
        row: 0,
    }
}

/// The metric and the colour error of `m` at a real case, in f64 (None: ill-conditioned).
pub fn measure(m: &Method, case: &Case, metric: Metric) -> Option<(f64, f64)> {
    if case.ill_conditioned {
        return None;
    }
    let s = m.eval_f64(&case.fragment, &case.lighting);
    let e = errors(case, s.color, s.normal);
    let n = s.normal.unwrap_or(DVec3::splat(f64::NAN));
    let v = match metric {
        Metric::Length => n.length() - 1.0,
        Metric::LengthSigned => n.length() - 1.0,
        // atan2 of |cross| and dot: exact to an ulp near 0, where acos of a dot within an
        // ulp of 1 reads 1.5e-8 rad of nothing; no direction at length 0 (NaN, as `errors`)
        Metric::Angle if n.length() > 0.0 => n
            .cross(case.phong_normal)
            .length()
            .atan2(n.dot(case.phong_normal)),
        Metric::Angle => f64::NAN,
    };
    let v = if metric == Metric::Length { v.abs() } else { v };
    Some((if e.non_finite { f64::NAN } else { v }, e.abs))
}
