//! The two input domains `prove` proves over, each up to `--max-angle` theta:
//!
//! - [`Domain::Triangle`]: any triangle: three free unit vertex normals pairwise at most theta
//!   apart, any barycentric weights (w_i >= 0, summing to 1).
//! - [`Domain::Edge`]: stress's case geometry: N0, N1 at most theta apart, N2 their bisector,
//!   weights ((1-s)(1-t), (1-s)t, s).
//!
//! In both, every normal component and weight is perturbed by its float32 rounding. A covered
//! method's errors depend on the inputs only through z = N.N ([`super::covered`]), so a domain
//! enters the proof as its proven range of z ([`Domain::z_range`]) and, for the value at real
//! points, a real triangle of the domain for each z ([`Domain::point_for_z`], written as a
//! `stress` case by [`Domain::spec_at`], replayable with `stress --replay`).
//!
//! The triangle's real points lie on one configuration: the three normals pairwise
//! `theta_e = min(theta, 120 deg)` apart (N2 turned out of the pair's plane by the apex angle,
//! cos(apex) = cos(theta_e) / cos(theta_e / 2)); z from the vertices (1) down the edge N0-N1 to
//! its middle (cos^2(theta/2), with theta itself on that edge), then down the median to the
//! centroid ((1 + 2 cos theta_e) / 3, the smallest z of the domain: the proof in
//! docs/proof.md and [`super::covered::triangle_z_range`]).
use serde::Serialize;

use super::bnb::Point;
use super::covered::{self, SPAN};
use super::interval::Interval;
use crate::cases::{strip_row_weight, CaseSpec, Shape, STRIP_APEX_Y};

/// The domain a figure of proof.json is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Domain {
    /// Three free unit normals pairwise at most theta apart, any weights.
    Triangle,
    /// N0, N1 at most theta apart, N2 their bisector (stress's cases).
    Edge,
}

/// The largest pairwise angle three normals can all make (coplanar, 120 deg apart): the
/// triangle's real points beyond it stay at 120 (with z down to 0, the whole range).
const EQUILATERAL_MAX_DEG: f64 = 120.0;

impl Domain {
    /// Both, in the order proof.json lists them.
    pub const ALL: [Domain; 2] = [Domain::Triangle, Domain::Edge];

    pub fn as_str(self) -> &'static str {
        match self {
            Domain::Triangle => "triangle",
            Domain::Edge => "edge",
        }
    }

    /// What the domain is, as proof.json states it.
    pub fn description(self) -> &'static str {
        match self {
            Domain::Triangle => {
                "any triangle: three free unit vertex normals N0, N1, N2 pairwise at most \
                 max_angle_deg apart, any barycentric weights (w_i >= 0, summing to 1); every \
                 normal component and weight perturbed by its float32 rounding (relative \
                 2^-24); any view and light (they do not change N.N); one white light, \
                 diffuse and specular of the cases (0.6, 0.35, rounded to float32), shininess \
                 as given. N.N over it is [(1 + 2 cos max_angle) / 3, 1] (0 from 120 deg on), \
                 widened by the rounding (docs/proof.md)"
            }
            Domain::Edge => {
                "stress's case geometry: unit vertex normals N0, N1 at angle theta in \
                 [0, max_angle_deg], N2 their bisector; weights ((1-s)(1-t), (1-s)t, s), t and \
                 s in [0, 1] (s = 0: the edge, stress's strip); every normal component and \
                 weight perturbed by its float32 rounding (relative 2^-24); any view and light \
                 (they do not change N.N); one white light, diffuse and specular of the cases \
                 (0.6, 0.35, rounded to float32), shininess as given"
            }
        }
    }

    /// The proven range of z = N.N over the domain up to `max_angle_deg`.
    pub fn z_range(self, max_angle_deg: f64) -> Interval {
        match self {
            Domain::Triangle => covered::triangle_z_range(max_angle_deg),
            Domain::Edge => covered::z_range(max_angle_deg),
        }
    }

    /// A real point of the domain whose z is `z` (clamped into the domain's reach): for the
    /// edge, (theta = max, t, 0) on the edge; for the triangle, the same on the edge where the
    /// edge reaches z, else (theta_e, 1/2, w2) on the median of the equilateral configuration.
    pub fn point_for_z(self, z: f64, max_angle_deg: f64) -> Point {
        let edge_lo = (0.5 * max_angle_deg).to_radians().cos().powi(2);
        if self == Domain::Edge || z >= edge_lo {
            return covered::point_for_z(z, max_angle_deg);
        }
        let theta = max_angle_deg.min(EQUILATERAL_MAX_DEG);
        let c = theta.to_radians().cos();
        // z = c + (1 - c) q with q = sum w_i^2 = (1 - w2)^2 / 2 + w2^2 on the median
        let q = if c < 1.0 { (z - c) / (1.0 - c) } else { 1.0 };
        let w2 = (1.0 - (6.0 * q - 2.0).max(0.0).sqrt()) / 3.0;
        [theta, 0.5, w2.clamp(0.0, 1.0 / 3.0)]
    }

    /// The `stress` case of a real point of the domain: the edge's as
    /// [`covered::spec_at`]; the triangle's with N2 at the apex angle (`theta` <= 120 deg; N2
    /// the bisector beyond, where the edge point is used) and, off the edge, the median's pixel
    /// on the row of weight w2, the view and the light along the exact normal there.
    pub fn spec_at(self, p: &Point, shininess: f64) -> CaseSpec {
        let theta = p[0];
        let apex_deg = if self == Domain::Edge || theta > EQUILATERAL_MAX_DEG {
            0.0
        } else {
            apex_deg(theta)
        };
        let edge = CaseSpec {
            apex_deg,
            ..covered::spec_at(p, shininess)
        };
        if self == Domain::Edge || p[2] <= 0.0 {
            return edge;
        }
        let row = (p[2] * (STRIP_APEX_Y - 0.5)).round() as u32;
        let w2 = strip_row_weight(row);
        // N = ((1 - w2) cos(theta/2) + w2 cos(apex)) M + w2 sin(apex) B, B = M x T: with the
        // pair across the view (azimuth 90), an elevation of its angle from M brings it to +Z,
        // and the light turned as far out of the pair's plane lies along it.
        let (sa, ca) = apex_deg.to_radians().sin_cos();
        let phi = (w2 * sa)
            .atan2((1.0 - w2) * (0.5 * theta).to_radians().cos() + w2 * ca)
            .to_degrees();
        CaseSpec {
            elevation_deg: phi,
            pair_azimuth_deg: 90.0,
            roll_deg: 0.0,
            light_deg: phi,
            light_out_of_plane: true,
            shape: Shape::Strip,
            span_px: SPAN,
            pixel: SPAN / 2,
            row,
            ..edge
        }
    }
}

/// The angle N2 turns out of the pair's plane for three normals pairwise `theta_deg` apart
/// (`theta_deg` <= 120): N2.N0 = cos(apex) cos(theta/2) = cos(theta).
pub fn apex_deg(theta_deg: f64) -> f64 {
    let h = (0.5 * theta_deg).to_radians().cos();
    (theta_deg.to_radians().cos() / h)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// A domain and its description, as proof.json lists them.
#[derive(Debug, Clone, Serialize)]
pub struct DomainInfo {
    pub name: Domain,
    pub description: &'static str,
}

/// Both domains, described.
pub fn described() -> Vec<DomainInfo> {
    Domain::ALL
        .iter()
        .map(|&d| DomainInfo {
            name: d,
            description: d.description(),
        })
        .collect()
}
