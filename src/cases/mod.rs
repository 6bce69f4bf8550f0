//! The cases of the sweeps, shared by the jobs that sweep a method's input domain (`stress`,
//! the isolated cost of `bench`, `plan`): a few named parameters ([`CaseSpec`]) that build one
//! fragment of one triangle ([`Case`]), and the exact references it is judged against; the
//! sweeps themselves are in [`grid`].
//!
//! Geometry of a case. The two vertex normals N0, N1 make the angle `theta_deg` about their
//! bisector M, which points `elevation_deg` away from the viewer (+Z; 90 is edge-on, 180 faces
//! away); `pair_azimuth_deg` turns their plane about M (0: the plane holds the view axis, 90:
//! across it) and `roll_deg` turns everything about the view axis. N2 = M, or M turned by
//! `apex_deg` out of the pair's plane towards M x T (three normals pairwise theta apart for
//! cos(apex) = cos(theta) / cos(theta/2), theta <= 120 deg: `prove`'s triangles). The light makes
//! `light_deg` with M, in the pair's plane (`light_out_of_plane` false) or across it; H =
//! normalize(L + V). On screen, the triangle is a strip whose first row is a span of `span_px`
//! pixels from N0 (left) to N1 (right), its third corner far below ([`STRIP_APEX_Y`]), or one of
//! the shapes of [`Shape`]; the pixel is `pixel` (a pixel index along the span, or along the
//! shape) on the strip's row `row` (0: the span; row r puts r / (STRIP_APEX_Y - 0.5) of the
//! weight on N2, [`strip_row_weight`]: the pixel `span_px / 2` walks the median to N2). In 3-D
//! the triangle is flat across M (flat normal M), which gives the PN mid-edge normals. Every value is
//! rounded to f32 once, so the device and the f64 twin see the same numbers.
pub mod grid;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::method::formulas::{self, Lighting};
use crate::method::{scanline, Fragment};

/// The triangle's shape on screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A span of `span_px` pixels on the first row of a tall triangle.
    Strip,
    /// A sliver lying along a row: 4096 px long, 0.1 px tall, crossing one row of pixels.
    SliverRow,
    /// The same standing along a column: 4096 rows, each span under a pixel wide.
    SliverColumn,
    /// A triangle of about 0.5 pixels holding one pixel centre.
    SubPixel,
}

/// The named parameters of one case (replayable: `stress --replay`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CaseSpec {
    pub theta_deg: f64,
    pub elevation_deg: f64,
    pub pair_azimuth_deg: f64,
    pub roll_deg: f64,
    pub light_deg: f64,
    pub light_out_of_plane: bool,
    pub shininess: f64,
    /// The vertex normals' length (1: unit; the sweep of unnormalised inputs).
    pub length: f64,
    pub shape: Shape,
    pub span_px: u32,
    /// The pixel: its index along the span (strip, sliver row) or column (sliver column).
    pub pixel: u32,
    /// Ambient and diffuse 0, specular 1: the colour is the specular term alone.
    #[serde(default)]
    pub specular_only: bool,
    /// N2 turned from the bisector M by this angle, degrees, out of the pair's plane (towards
    /// M x T); 0 (absent in a file): N2 = M.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub apex_deg: f64,
    /// The strip's pixel row (strip only; 0, absent in a file: the span N0-N1). A pixel off
    /// the median (`span_px / 2`) may lie outside the triangle at a deep row (weights < 0).
    #[serde(default, skip_serializing_if = "is_zero_u32")]
    pub row: u32,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_zero_u32(x: &u32) -> bool {
    *x == 0
}

/// The window y of a strip's third corner (N2's): the rows run from 0 to below it.
pub const STRIP_APEX_Y: f64 = 1e5;

/// The weight on N2 of a strip's pixel on `row` (exact in f64 up to its rounding; the median's
/// pixel has the other two weights equal).
pub fn strip_row_weight(row: u32) -> f64 {
    f64::from(row) / (STRIP_APEX_Y - 0.5)
}

impl Default for CaseSpec {
    fn default() -> Self {
        CaseSpec {
            theta_deg: 30.0,
            elevation_deg: 30.0,
            pair_azimuth_deg: 0.0,
            roll_deg: 0.0,
            light_deg: 30.0,
            light_out_of_plane: false,
            shininess: 20.0,
            length: 1.0,
            shape: Shape::Strip,
            span_px: 64,
            pixel: 20,
            specular_only: false,
            apex_deg: 0.0,
            row: 0,
        }
    }
}

/// Relative length of the interpolated normal below which a case is ill-conditioned: float32
/// weights (relative rounding 6e-8) then turn the direction by up to ~6e-5 rad.
pub const ILL_CONDITIONED: f64 = 1e-3;

/// The material of every case: grey, so that one channel tells the error; the sum is at most 1.
pub const AMBIENT: f64 = 0.05;
pub const DIFFUSE: f64 = 0.6;
pub const SPECULAR: f64 = 0.35;

/// One case: what the method sees, and what it is judged against.
#[derive(Debug, Clone)]
pub struct Case {
    pub spec: CaseSpec,
    pub fragment: Fragment,
    pub lighting: Lighting,
    /// The exact unit Phong normal of the inputs as the method sees them (f32-rounded, scaled
    /// by `length`), in f64.
    pub phong_normal: DVec3,
    /// The interpolated normal is shorter than [`ILL_CONDITIONED`] of the longest vertex
    /// normal (antipodal normals near the middle, zero-length normals): its direction is lost
    /// to the rounding of the inputs, so no float32 method can be judged there. Counted; a
    /// non-finite result still counts as non-finite.
    pub ill_conditioned: bool,
    /// Exact Phong: the lighting of `phong_normal` (docs/formulas.md#the-two-references).
    pub phong: DVec3,
    /// Exact slerp along the span, lit (the second reference of angle-interpolating methods).
    pub slerp: DVec3,
}

fn f32r(x: f64) -> f64 {
    x as f32 as f64
}

fn r3(v: DVec3) -> DVec3 {
    DVec3::new(f32r(v.x), f32r(v.y), f32r(v.z))
}

fn r2(v: DVec2) -> DVec2 {
    DVec2::new(f32r(v.x), f32r(v.y))
}

/// Turns `v` about the view axis by `deg`.
fn roll(v: DVec3, deg: f64) -> DVec3 {
    let (s, c) = deg.to_radians().sin_cos();
    DVec3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}

/// Barycentric weights of `p` in the window triangle `w` (f64; unclamped).
fn weights(p: DVec2, w: [DVec2; 3]) -> DVec3 {
    let e1 = w[1] - w[0];
    let e2 = w[2] - w[0];
    let q = p - w[0];
    let det = e1.x * e2.y - e1.y * e2.x;
    if det == 0.0 {
        return DVec3::new(1.0, 0.0, 0.0);
    }
    let b1 = (q.x * e2.y - q.y * e2.x) / det;
    let b2 = (e1.x * q.y - e1.y * q.x) / det;
    DVec3::new(1.0 - b1 - b2, b1, b2)
}

/// The window corners and the pixel centre of a shape.
fn screen(spec: &CaseSpec) -> ([DVec2; 3], DVec2) {
    match spec.shape {
        Shape::Strip => {
            // The first row of the strip is the span itself: its ends are the corners, so the
            // span-end normals are N0 and N1 exactly, and pixel i sits at t = i / span_px.
            let s = f64::from(spec.span_px.max(1));
            let w = [
                DVec2::new(0.5, 0.5),
                DVec2::new(s + 0.5, 0.5),
                DVec2::new(0.5 * s + 0.5, STRIP_APEX_Y),
            ];
            let i = f64::from(spec.pixel.min(spec.span_px.max(1) - 1));
            let row = f64::from(spec.row).min(STRIP_APEX_Y - 1.0);
            (w, DVec2::new(i + 0.5, row + 0.5))
        }
        // Both slivers: 4096 x 0.1 px (aspect 4e4 at the wide end, 1e4 on average); their
        // pixel centres lie inside from index 0 (the rows or columns 683..4095).
        Shape::SliverRow => {
            let w = [
                DVec2::new(0.0, 0.49),
                DVec2::new(4096.0, 0.45),
                DVec2::new(4096.0, 0.55),
            ];
            let i = 683.0 + f64::from(spec.pixel % 3413);
            (w, DVec2::new(i + 0.5, 0.5))
        }
        Shape::SliverColumn => {
            let w = [
                DVec2::new(0.49, 0.0),
                DVec2::new(0.45, 4096.0),
                DVec2::new(0.55, 4096.0),
            ];
            let i = 683.0 + f64::from(spec.pixel % 3413);
            (w, DVec2::new(0.5, i + 0.5))
        }
        Shape::SubPixel => (
            [
                DVec2::new(0.3, 0.3),
                DVec2::new(0.8, 0.35),
                DVec2::new(0.5, 0.8),
            ],
            DVec2::new(0.5, 0.5),
        ),
    }
}

impl Case {
    /// Builds the case of `spec` (every input rounded to f32 once).
    pub fn new(spec: CaseSpec) -> Case {
        let (th, el) = (spec.theta_deg.to_radians(), spec.elevation_deg.to_radians());
        let m0 = DVec3::new(el.sin(), 0.0, el.cos());
        let across = DVec3::new(el.cos(), 0.0, -el.sin());
        let (sa, ca) = spec.pair_azimuth_deg.to_radians().sin_cos();
        let t0 = across * ca + DVec3::Y * sa;
        let m = roll(m0, spec.roll_deg);
        let t = roll(t0, spec.roll_deg);
        let (sh, ch) = (0.5 * th).sin_cos();
        let apex = if spec.apex_deg == 0.0 {
            m
        } else {
            let (sa, ca) = spec.apex_deg.to_radians().sin_cos();
            m * ca + m.cross(t) * sa
        };
        let unit = [m * ch - t * sh, m * ch + t * sh, apex].map(|n| r3(n.normalize()));
        let normals = unit.map(|n| r3(n * spec.length));
        let (sl, cl) = spec.light_deg.to_radians().sin_cos();
        let side = if spec.light_out_of_plane {
            m.cross(t)
        } else {
            t
        };
        let l = r3((m * cl + side * sl).normalize());
        let h = r3((l + DVec3::Z).try_normalize().unwrap_or(m));
        let (ka, kd, ks) = if spec.specular_only {
            (0.0, 0.0, 1.0)
        } else {
            (AMBIENT, DIFFUSE, SPECULAR)
        };
        let lighting = Lighting::new(
            DVec3::splat(f32r(ka)),
            DVec3::splat(f32r(kd)),
            DVec3::splat(f32r(ks)),
            f32r(spec.shininess),
            &[(l, DVec3::ONE, h)],
        );
        let (window, pixel) = screen(&spec);
        let window = window.map(r2);
        let w = r3(weights(pixel, window));
        // A flat triangle across the bisector: N0's corner on -T, N1's on +T, N2's off the
        // line; its flat normal is M (a sphere patch through the normals would degenerate to a
        // point at theta = 0).
        let positions = [-t, t, m.cross(t)];
        let mut flat = (positions[1] - positions[0])
            .cross(positions[2] - positions[0])
            .normalize_or_zero();
        if flat.dot(unit[0] + unit[1] + unit[2]) < 0.0 {
            flat = -flat;
        }
        let fragment = Fragment {
            weights: w,
            pixel,
            window,
            corner_normals: normals,
            flat_normal: r3(flat),
            pn_mids: formulas::pn_mid_normals(positions, unit).map(r3),
        };
        let interpolated = fragment.interpolated_normal();
        let longest = normals.iter().map(|n| n.length()).fold(0.0, f64::max);
        let ill_conditioned =
            !(interpolated.length() >= ILL_CONDITIONED * longest && longest > 0.0);
        let phong_normal = formulas::normalize_exact(interpolated);
        let (a, b, t) = scanline::span_ends(pixel, window, unit);
        let slerp = lighting.shade(scanline::slerp(a, b, t));
        Case {
            spec,
            phong: lighting.shade(phong_normal),
            phong_normal,
            ill_conditioned,
            slerp,
            fragment,
            lighting,
        }
    }
}

/// How far a result is from its references.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// Max over the channels of |colour - exact Phong| (linear); NaN when non-finite.
    pub abs: f64,
    /// The same against exact slerp along the span.
    pub abs_slerp: f64,
    /// Angle between the method's normal and the exact one, degrees (methods with a normal).
    pub angle_deg: Option<f64>,
    /// | |N| - 1 | of the method's normal.
    pub length: Option<f64>,
    /// Any colour or normal component is NaN or infinite.
    pub non_finite: bool,
    /// The case is ill-conditioned ([`Case::ill_conditioned`]).
    pub ill_conditioned: bool,
}

impl Errors {
    /// The colour error to fold into a worst value: NaN when non-finite (it counts as such),
    /// None for a finite result on an ill-conditioned case (left out).
    pub fn counted(&self) -> Option<f64> {
        if self.non_finite {
            Some(f64::NAN)
        } else if self.ill_conditioned {
            None
        } else {
            Some(self.abs)
        }
    }
}

impl Errors {
    /// The normal's length error ||N| - 1| to fold into a worst value, as [`Errors::counted`]
    /// does the colour's: NaN when the result is non-finite, None for a finite result on an
    /// ill-conditioned case and for a method without a normal.
    pub fn counted_length(&self) -> Option<f64> {
        let length = self.length?;
        if self.non_finite {
            Some(f64::NAN)
        } else if self.ill_conditioned {
            None
        } else {
            Some(length)
        }
    }
}

/// The errors of a result (`color`, `normal`) of `case`.
pub fn errors(case: &Case, color: DVec3, normal: Option<DVec3>) -> Errors {
    let finite = color.is_finite() && normal.is_none_or(|n| n.is_finite());
    let max_abs = |r: DVec3| (color - r).abs().max_element();
    let angle = normal.map(|n| {
        let len = n.length();
        if len > 0.0 && len.is_finite() {
            (n / len)
                .dot(case.phong_normal)
                .clamp(-1.0, 1.0)
                .acos()
                .to_degrees()
        } else {
            f64::NAN
        }
    });
    Errors {
        abs: if finite {
            max_abs(case.phong)
        } else {
            f64::NAN
        },
        abs_slerp: if finite {
            max_abs(case.slerp)
        } else {
            f64::NAN
        },
        angle_deg: angle,
        length: normal.map(|n| (n.length() - 1.0).abs()),
        non_finite: !finite,
        ill_conditioned: case.ill_conditioned,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pair_makes_the_requested_angle_and_the_span_carries_it() {
        for theta in [0.5, 30.0, 120.0, 179.0] {
            let case = Case::new(CaseSpec {
                theta_deg: theta,
                ..CaseSpec::default()
            });
            let n = case.fragment.corner_normals;
            let got = n[0].cross(n[1]).length().atan2(n[0].dot(n[1])).to_degrees();
            assert!((got - theta).abs() < 1e-4, "theta {theta}: {got}");
            let (a, b, _) = scanline::span_ends(
                case.fragment.pixel,
                case.fragment.window,
                case.fragment.corner_normals,
            );
            assert!(a.dot(n[0]) > 1.0 - 1e-6 && b.dot(n[1]) > 1.0 - 1e-6);
        }
    }

    #[test]
    fn elevation_180_faces_away_and_the_pixel_walks_the_span() {
        let away = Case::new(CaseSpec {
            theta_deg: 0.0,
            elevation_deg: 180.0,
            ..CaseSpec::default()
        });
        assert!(away.phong_normal.z < -0.999);
        assert!(
            away.fragment.flat_normal.z < -0.999,
            "the flat normal is the bisector"
        );
        let first = Case::new(CaseSpec {
            pixel: 0,
            ..CaseSpec::default()
        });
        let last = Case::new(CaseSpec {
            pixel: 63,
            ..CaseSpec::default()
        });
        assert_eq!(first.fragment.weights.x, 1.0);
        assert!((last.fragment.weights.y - 63.0 / 64.0).abs() < 1e-6);
    }

    #[test]
    fn non_finite_results_are_flagged_and_never_score_zero() {
        let case = Case::new(CaseSpec::default());
        let e = errors(&case, DVec3::new(f64::NAN, 0.0, 0.0), None);
        assert!(e.non_finite && e.abs.is_nan());
        let exact = errors(&case, case.phong, Some(case.phong_normal));
        assert!(!exact.non_finite && exact.abs == 0.0 && exact.angle_deg.unwrap() < 1e-6);
        let off = errors(&case, case.phong + DVec3::splat(0.01), None);
        assert!((off.abs - 0.01).abs() < 1e-12);
    }
}
