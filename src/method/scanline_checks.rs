//! The checks behind the scanline family's claims (FORMULAS.md 2.11, 2.13, 2.16, section 3):
//! f64 sweeps run when claims are written, each verdict derived from the measured figure by
//! the rule in its `how` (as in [`super::checks`]). Each core takes the formula under test as a
//! parameter, so the tests can feed a wrong one and see the verdict flip.
use glam::DVec3;

use super::checks::pair;
use super::scanline as s;
use super::{Measurement, Verdict};

/// Points of each sweep.
const STEPS: usize = 20_000;

/// Whether `measured` is within a claim's figure `claimed`, given as the seed prints it: the
/// claim holds up to half a unit of its last printed digit (`half_unit`), since "0.004 %" is
/// what 0.0043 % rounds to.
fn within(measured: f64, claimed: f64, half_unit: f64) -> bool {
    measured <= claimed + half_unit
}

/// Worst absolute and relative error of an approximation `f(z)` of `1/sqrt(2 + z)`,
/// `z = 2 cos(phi)`, over phi in [0, 45] degrees (the range both S002 polynomials are for).
pub(crate) fn inv_root_errors(f: fn(f64) -> f64) -> (f64, f64) {
    (0..=STEPS)
        .map(|i| {
            let phi = 45f64.to_radians() * i as f64 / STEPS as f64;
            let z = 2.0 * phi.cos();
            let exact = s::inv_root_exact(z);
            let abs = (f(z) - exact).abs();
            (abs, abs / exact)
        })
        .fold((0.0, 0.0), |(a, r), (x, y)| {
            (f64::max(a, x), f64::max(r, y))
        })
}

/// A claim "abs <= A, rel <= R %" about an inverse-root polynomial: agrees when both hold,
/// partly when one does.
fn inv_root_claim(
    f: fn(f64) -> f64,
    name: &str,
    abs_claim: (f64, f64),
    rel_claim_pct: (f64, f64),
) -> Measurement {
    let (abs, rel) = inv_root_errors(f);
    let rel_pct = 100.0 * rel;
    let ok_abs = within(abs, abs_claim.0, abs_claim.1);
    let ok_rel = within(rel_pct, rel_claim_pct.0, rel_claim_pct.1);
    Measurement {
        measured: format!("max absolute error {abs:.2e}, relative {rel_pct:.4} %"),
        verdict: match (ok_abs, ok_rel) {
            (true, true) => Verdict::Agrees,
            (false, false) => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: format!(
            "f64 sweep of {name} against 1/sqrt(2 + z), z = 2 cos(phi), phi in [0, 45] deg \
             ({} points, src/method/scanline_checks.rs); each figure agrees when it is within \
             half a unit of the claim's last printed digit",
            STEPS + 1
        ),
    }
}

/// S002 l.625-643: the degree-1 inverse root 0.64 - 0.07 z has max abs error <= 0.0005 and
/// relative error 0.12 %.
pub fn dichotomy_poly1_error() -> Measurement {
    inv_root_claim(
        s::inv_root_poly1,
        "0.64 - 0.07 z",
        (0.0005, 0.00005),
        (0.12, 0.005),
    )
}

/// S002 l.646-658: the degree-2 inverse root has max abs error <= 2e-5 and relative 0.004 %.
pub fn dichotomy_poly2_error() -> Measurement {
    inv_root_claim(
        s::inv_root_poly2,
        "0.014253 z^2 - 0.118922 z + 0.680850",
        (2e-5, 0.5e-5),
        (0.004, 0.0005),
    )
}

/// The closed form of 2.11 and slerp: the largest distance between them over angles up to
/// 170 degrees and t in [0, 1].
pub(crate) fn closed_form_gap(closed: fn(DVec3, DVec3, f64) -> DVec3) -> f64 {
    let mut gap = 0.0f64;
    for a in 1..=17 {
        let (na, nb) = pair(10.0 * a as f64);
        for i in 0..=200 {
            let t = i as f64 / 200.0;
            gap = gap.max((closed(na, nb, t) - s::slerp(na, nb, t)).length());
        }
    }
    gap
}

/// S000 l.100-114 (refs [9, 10]): spherical-angular interpolation gives the slerp normals.
pub fn spherical_angular_is_slerp() -> Measurement {
    let gap = closed_form_gap(s::spherical_angular);
    Measurement {
        measured: format!("largest |closed form - slerp| {gap:.1e}"),
        verdict: if gap < 1e-12 {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "f64: both formulas (src/method/scanline.rs) at angles 10..170 deg and t in [0, 1] \
              (201 points); agrees when they differ by less than 1e-12"
            .into(),
    }
}

/// The worst relative error of the linearly interpolated diffuse intensity at a segment's
/// middle, over light directions, for unit segment-end normals `theta` apart: `interpolate`
/// gives the middle's intensity from the ends' (the method: their mean).
pub(crate) fn segment_diffuse_error(theta_deg: f64, interpolate: fn(f64, f64) -> f64) -> f64 {
    let (nl, np) = pair(theta_deg);
    let mid = (nl + np).normalize();
    let mut worst = 0.0f64;
    // Lights over the hemisphere around the middle normal (where all three are lit).
    for i in 0..=200 {
        for j in 0..400 {
            let (th, ph) = (
                88f64.to_radians() * i as f64 / 200.0,
                std::f64::consts::TAU * j as f64 / 400.0,
            );
            let l = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            let (il, ip, im) = (nl.dot(l), np.dot(l), mid.dot(l));
            if il > 0.0 && ip > 0.0 {
                worst = worst.max((im - interpolate(il, ip)) / im);
            }
        }
    }
    worst
}

/// S002 l.431-467: the linear interpolation of diffuse intensity inside a segment whose end
/// normals are theta apart has relative error at most 1 - cos(theta / 2).
pub fn segments_diffuse_bound() -> Measurement {
    segments_diffuse_bound_with(|a, b| 0.5 * (a + b))
}

pub(crate) fn segments_diffuse_bound_with(interpolate: fn(f64, f64) -> f64) -> Measurement {
    let theta = 4.0;
    let brute = segment_diffuse_error(theta, interpolate);
    let formula = 1.0 - (0.5 * theta as f64).to_radians().cos();
    let agrees = (brute - formula).abs() <= 0.01 * formula;
    Measurement {
        measured: format!(
            "at {theta} deg: brute force {:.4} %, 1 - cos(theta/2) = {:.4} %",
            100.0 * brute,
            100.0 * formula
        ),
        verdict: if agrees {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "f64: the segment middle's exact diffuse intensity against the mean of its ends', \
              worst over 80,400 light directions above the three normals \
              (src/method/scanline_checks.rs); agrees when the worst equals the formula within \
              1 % of it"
            .into(),
    }
}

/// The specular bound of S002 l.472-592: `1 - cos^n(theta/2)`.
pub(crate) fn specular_bound(n: f64, theta_deg: f64) -> f64 {
    1.0 - (0.5 * theta_deg).to_radians().cos().powf(n)
}

/// S002 l.595-598: for the most common materials (n <= 100) the specular error stays within
/// 4 % at 4 degrees between segment-end normals.
pub fn segments_specular_4pct() -> Measurement {
    segments_specular_4pct_with(specular_bound)
}

pub(crate) fn segments_specular_4pct_with(bound: fn(f64, f64) -> f64) -> Measurement {
    let at_100 = bound(100.0, 4.0);
    let largest_n = (1..=1000)
        .take_while(|&n| bound(f64::from(n), 4.0) <= 0.04)
        .last();
    Measurement {
        measured: format!(
            "1 - cos^n(theta/2) at theta = 4 deg: {:.2} % at n = 100; within 4 % up to n = {}",
            100.0 * at_100,
            largest_n.map_or("none".into(), |n| format!(
                "{n} (n = {}: {:.4} %)",
                n + 1,
                100.0 * bound(f64::from(n + 1), 4.0)
            ))
        ),
        verdict: if at_100 <= 0.04 {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "f64: the seed's own bound 1 - cos^n(theta/2) (S002 l.472-592) at theta = 4 deg for \
              n = 1..1000 (src/method/scanline_checks.rs); agrees when it is <= 4 % at n = 100"
            .into(),
    }
}

/// The length error in percent of the middle normal `mid(nl, np)` for unit ends `theta` apart.
pub(crate) fn mid_length_error_pct(theta_deg: f64, mid: fn(DVec3, DVec3) -> DVec3) -> f64 {
    let (nl, np) = pair(theta_deg);
    100.0 * (mid(nl, np).length() - 1.0)
}

/// S000 l.136-146: the middle normal of a scanline is computed approximately as
/// (0.103 c^2 - 0.306 c + 0.705)(N'_p + N'_l). Measured as its length error over the fit's
/// design range, end normals up to 90 degrees apart.
pub fn quadratic_mid_accuracy() -> Measurement {
    quadratic_mid_accuracy_with(s::mid_approx)
}

pub(crate) fn quadratic_mid_accuracy_with(mid: fn(DVec3, DVec3) -> DVec3) -> Measurement {
    let worst = (0..=900)
        .map(|i| mid_length_error_pct(0.1 * f64::from(i), mid))
        .fold(0.0, |w: f64, e| if e.abs() > w.abs() { e } else { w });
    let beyond = mid_length_error_pct(120.0, mid);
    let limit = super::checks::VISIBLE_LENGTH_ERROR_PCT;
    Measurement {
        measured: format!(
            "worst length error {worst:+.3} % for end normals up to 90 deg apart ({beyond:+.2} % \
             at 120 deg)"
        ),
        verdict: if worst.abs() <= limit {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "f64: |mid(N'_l, N'_p)| - 1 for unit ends 0..90 deg apart in 0.1 deg steps \
             (src/method/scanline_checks.rs); agrees when within {limit} % (the project's \
             visible-length threshold)"
        ),
    }
}

/// The worst error of Bishop-Weimer's Taylor cosine against the exact one over a triangle
/// whose normal changes by `extent` (|A| r) from its centre to its edge, over light directions
/// (FORMULAS.md 2.17's example: |A| = |B| = 0.3, C = +Z, measured 1.1e-5 at r |A| = 0.03).
pub(crate) fn taylor_error(
    extent: f64,
    approx: fn(DVec3, DVec3, DVec3, DVec3, glam::DVec2) -> f64,
) -> f64 {
    let (a, b, c) = (
        DVec3::new(0.3, 0.0, 0.0),
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::Z,
    );
    let r = extent / 0.3;
    let mut worst = 0.0f64;
    for k in 0..24 {
        let th = std::f64::consts::TAU * f64::from(k) / 24.0;
        let l = DVec3::new(0.5 * th.cos(), 0.5 * th.sin(), 0.75f64.sqrt());
        for i in 0..=20 {
            for j in 0..=20 {
                let p = glam::DVec2::new(
                    -r + 2.0 * r * f64::from(i) / 20.0,
                    -r + 2.0 * r * f64::from(j) / 20.0,
                );
                let n = a * p.x + b * p.y + c;
                let exact = l.dot(n) / n.length();
                worst = worst.max((approx(l, a, b, c, p) - exact).abs());
            }
        }
    }
    worst
}

/// S004 l.110-120: the second-order Taylor expansion approximates the diffuse intensity over
/// the polygon. Measured as the largest change of the normal across a triangle (from its
/// centre) at which the error stays within one 8-bit step of the intensity.
pub fn bishop_weimer_extent() -> Measurement {
    bishop_weimer_extent_with(s::taylor_cosine)
}

pub(crate) fn bishop_weimer_extent_with(
    approx: fn(DVec3, DVec3, DVec3, DVec3, glam::DVec2) -> f64,
) -> Measurement {
    let extents = [0.03, 0.075, 0.15, 0.3, 0.6];
    let errors: Vec<f64> = extents.iter().map(|&e| taylor_error(e, approx)).collect();
    let step = 1.0 / 255.0;
    let holds = extents
        .iter()
        .zip(&errors)
        .filter(|(_, &e)| e <= step)
        .count();
    let listed: Vec<String> = extents
        .iter()
        .zip(&errors)
        .map(|(x, e)| format!("{e:.1e} at {x}"))
        .collect();
    Measurement {
        measured: format!(
            "worst |Taylor - exact| of N.L/|N| by the normal's change from the centre: {}",
            listed.join(", ")
        ),
        verdict: match holds {
            n if n == extents.len() => Verdict::Agrees,
            0 => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: "f64: src/method/scanline.rs taylor_cosine against N.L/|N| for N = A x + B y + C \
              (|A| = |B| = 0.3, C = +Z) over a square around the centre and 24 light directions \
              (src/method/scanline_checks.rs); agrees when within 1/255 at every extent, \
              partly when only on the smaller ones"
            .into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(m: Measurement) -> Verdict {
        m.verdict
    }

    #[test]
    fn inverse_root_claims_follow_the_measured_errors() {
        // FORMULAS.md section 3: the rounded line has 0.0011 / 0.217 %, the quadratic 2.0e-5 /
        // 0.00403 %.
        let (abs, rel) = inv_root_errors(s::inv_root_poly1);
        assert!((abs - 0.0011).abs() < 1e-4 && (rel * 100.0 - 0.217).abs() < 0.005);
        assert_eq!(v(dichotomy_poly1_error()), Verdict::Disagrees);
        assert_eq!(v(dichotomy_poly2_error()), Verdict::Agrees);
        // teeth: the exact root meets any claim, a constant meets none
        assert_eq!(
            v(inv_root_claim(
                s::inv_root_exact,
                "exact",
                (0.0005, 0.0),
                (0.12, 0.0)
            )),
            Verdict::Agrees
        );
        assert_eq!(
            v(inv_root_claim(|_| 0.6, "0.6", (2e-5, 0.0), (0.004, 0.0))),
            Verdict::Disagrees
        );
    }

    #[test]
    fn spherical_angular_claim_flips_for_a_different_interpolation() {
        assert_eq!(v(spherical_angular_is_slerp()), Verdict::Agrees);
        let nlerp = |a: DVec3, b: DVec3, t: f64| a.lerp(b, t).normalize();
        assert!(closed_form_gap(nlerp) > 1e-3);
    }

    #[test]
    fn quadratic_mid_and_taylor_checks_measure_their_formulas() {
        // FORMULAS.md 2.12: within +-0.33 % up to 90 degrees, -11.6 % at 120.
        let m = quadratic_mid_accuracy();
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
        assert!(m.measured.contains("-11.6"), "{m:?}");
        assert_eq!(
            v(quadratic_mid_accuracy_with(|a, b| (a + b) * 0.5)),
            Verdict::Disagrees
        );
        // FORMULAS.md 2.17: 1.1e-5 at |A| r = 0.03 (r = 0.1), 1.8e-2 at 0.3 (r = 1)
        let e = taylor_error(0.03, s::taylor_cosine);
        assert!(e > 5e-6 && e < 3e-5, "{e}");
        assert_eq!(v(bishop_weimer_extent()), Verdict::Partly);
        assert_eq!(
            v(bishop_weimer_extent_with(|l, a, b, c, p| {
                let n = a * p.x + b * p.y + c;
                l.dot(n) / n.length()
            })),
            Verdict::Agrees
        );
    }

    #[test]
    fn segment_bounds_are_measured_not_assumed() {
        // FORMULAS.md 2.16: brute force 0.0609 % at 4 degrees, 5.91 % at n = 100, "n <= 67"
        // (n = 67 gives 4.0005 %: strictly, n <= 66).
        assert_eq!(v(segments_diffuse_bound()), Verdict::Agrees);
        let m = segments_specular_4pct();
        assert!(
            m.measured.contains("5.91 %") && m.measured.contains("up to n = 66 (n = 67: 4.0005 %)"),
            "{m:?}"
        );
        assert_eq!(m.verdict, Verdict::Disagrees);
        // teeth: an interpolation that is exact at the middle breaks the diffuse claim, and a
        // bound half as large makes the 4 % claim hold
        assert_eq!(
            v(segments_diffuse_bound_with(
                |a, b| (a + b) / (2.0 * 2f64.to_radians().cos())
            )),
            Verdict::Disagrees
        );
        assert_eq!(
            v(segments_specular_4pct_with(
                |n, t| 0.5 * specular_bound(n, t)
            )),
            Verdict::Agrees
        );
    }
}
