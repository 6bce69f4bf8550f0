//! The checks behind the scanline family's claims
//! (docs/formulas.md#spherical-angular-interpolation, docs/formulas.md#dichotomy,
//! docs/formulas.md#digital-segments-error-bounds): f64 sweeps run when claims are written, each
//! verdict derived from the measured figure by the rule in its `how` (as in [`super::checks`]).
//! Each core takes the formula under test as a parameter, so the tests can feed a wrong one and see
//! the verdict flip.
use glam::DVec3;

use super::checks::{pair, Worst};
use super::scanline as s;
use super::{Evidence, Measurement, Quantity, Verdict};

/// Points of each sweep.
const STEPS: usize = 20_000;

/// The rule for one claimed bound ("the error does not exceed `claim`"), stated here where the
/// verdict is: `agrees` only when the measurement does not exceed it, `disagrees` when it does
/// (by any amount: no rounding to the claim's printed digits) or is non-finite.
pub(crate) fn figure_verdict(measured: &Worst, claim: f64) -> Verdict {
    if measured.within(claim) {
        Verdict::Agrees
    } else {
        Verdict::Disagrees
    }
}

/// Two figures' verdicts into one: the same verdict for both stays; a mix is partly.
fn combine(a: Verdict, b: Verdict) -> Verdict {
    if a == b {
        a
    } else {
        Verdict::Partly
    }
}

/// Worst absolute and relative error of an approximation `f(z)` of `1/sqrt(2 + z)`,
/// `z = 2 cos(phi)`, over phi in [0, 45] degrees (the range both polynomials of the digital-segment
/// paper are for).
/// Non-finite points are counted ([`Worst`]).
pub(crate) fn inv_root_errors(f: &dyn Fn(f64) -> f64) -> (Worst, Worst) {
    let (mut abs, mut rel) = (Worst::default(), Worst::default());
    for i in 0..=STEPS {
        let phi = 45f64.to_radians() * i as f64 / STEPS as f64;
        let z = 2.0 * phi.cos();
        let exact = s::inv_root_exact(z);
        let e = (f(z) - exact).abs();
        abs.push(e);
        rel.push(e / exact);
    }
    (abs, rel)
}

/// The minimax (best uniform) polynomial of degree `N - 2` for `1/sqrt(2 + z)` on z in
/// [sqrt 2, 2] (phi in [0, 45] degrees) by the Remez exchange: solve p(x_i) + (-1)^i E =
/// f(x_i) on N reference points, move them to the error's extrema on a fine grid, repeat until
/// the levelled error stops changing. Returns the coefficients, lowest degree first.
pub(crate) fn minimax_inv_root<const N: usize>() -> Vec<f64> {
    let (lo, hi) = (2f64.sqrt(), 2.0);
    let f = s::inv_root_exact;
    let deg = N - 2;
    // Chebyshev extrema as the first reference
    let mut x: Vec<f64> = (0..N)
        .map(|i| {
            let c = (std::f64::consts::PI * i as f64 / (N - 1) as f64).cos();
            0.5 * (lo + hi) - 0.5 * (hi - lo) * c
        })
        .collect();
    let grid: Vec<f64> = (0..=20_000)
        .map(|i| lo + (hi - lo) * i as f64 / 20_000.0)
        .collect();
    let mut coef = vec![0.0; deg + 1];
    let mut last = f64::INFINITY;
    for _ in 0..50 {
        // rows [1, x, x^2, .., (-1)^i] . [c0.., E] = f(x_i)
        let mut m: Vec<Vec<f64>> = (0..N)
            .map(|i| {
                let mut row: Vec<f64> = (0..=deg).map(|k| x[i].powi(k as i32)).collect();
                row.push(if i % 2 == 0 { 1.0 } else { -1.0 });
                row.push(f(x[i]));
                row
            })
            .collect();
        // A singular reference gives no solution: NaN coefficients, which the checks count.
        let unknowns = m.len();
        let sol = super::linalg::gauss(&mut m).unwrap_or_else(|| vec![f64::NAN; unknowns]);
        coef = sol[..=deg].to_vec();
        let level = sol[deg + 1].abs();
        let err = |z: f64| coef.iter().rev().fold(0.0, |a, c| a * z + c) - f(z);
        // the error's extrema on the grid, ends included, one per sign run
        let mut ext: Vec<f64> = Vec::new();
        let mut best = grid[0];
        for &z in &grid[1..] {
            if err(z).signum() != err(best).signum() {
                ext.push(best);
                best = z;
            } else if err(z).abs() > err(best).abs() {
                best = z;
            }
        }
        ext.push(best);
        if ext.len() != N || (level - last).abs() <= 1e-15 {
            break;
        }
        last = level;
        x = ext;
    }
    coef
}

/// An inverse root shown beside the one a claim is judged on: its name and the function.
type Beside<'a> = (&'a str, &'a dyn Fn(f64) -> f64);

/// A claim "abs <= A, rel <= R %" about an inverse-root polynomial `f` (the coefficients the
/// seed prints), each figure by [`figure_verdict`] (the rule is stated there), combined by
/// [`combine`]. The polynomials in `beside` (a reconstruction, the minimax polynomial of the
/// same degree) are measured and shown next to it, and do not enter the verdict.
fn inv_root_claim(
    f: &dyn Fn(f64) -> f64,
    name: &str,
    abs_claim: f64,
    rel_claim_pct: f64,
    beside: &[Beside],
) -> Measurement {
    let (abs, rel) = inv_root_errors(f);
    let rel_pct = Worst {
        finite: 100.0 * rel.finite,
        ..rel
    };
    let (va, vr) = (
        figure_verdict(&abs, abs_claim),
        figure_verdict(&rel_pct, rel_claim_pct),
    );
    let others: String = beside
        .iter()
        .map(|(what, g)| {
            let (a, r) = inv_root_errors(*g);
            format!(
                "; {what}: {:.4e}{}, {:.5} %{}",
                a.finite,
                a.note(),
                100.0 * r.finite,
                r.note()
            )
        })
        .collect();
    Measurement {
        evidence: Evidence::found(abs.value(), Quantity::AbsoluteError),
        measured: format!(
            "{name}: max absolute error {:.3e}{} ({va} with {abs_claim:e}), relative {:.5} %{} \
             ({vr} with {rel_claim_pct} %){others}",
            abs.finite,
            abs.note(),
            rel_pct.finite,
            rel.note(),
        ),
        verdict: combine(va, vr),
        how: format!(
            "f64 sweep of {name} against 1/sqrt(2 + z), z = 2 cos(phi), phi in [0, 45] deg \
             ({} points, src/method/scanline_checks.rs); each figure is a bound: agrees only \
             when the measurement does not exceed it, disagrees when it does by any amount (no \
             rounding to the claim's printed digits) or any point is non-finite; both agree: \
             agrees, both disagree: disagrees, otherwise partly{}",
            STEPS + 1,
            if beside.is_empty() {
                ""
            } else {
                "; the polynomials shown beside are measured the same way and do not enter the \
                 verdict"
            }
        ),
    }
}

/// docs/formulas.md#dichotomy: the degree-1 inverse root 0.64 - 0.07 z has max abs error <= 0.0005
/// and relative error 0.12 %.
pub fn dichotomy_poly1_error() -> Measurement {
    inv_root_claim(&s::inv_root_poly1, "0.64 - 0.07 z", 0.0005, 0.12, &[])
}

/// The degree-2 inverse root with the coefficients the papers print (docs/formulas.md#dichotomy:
/// the polynomial the digital-segment paper uses, whose own coefficients are lost from its
/// text): `0.014 z^2 - 0.119 z + 0.681`.
pub(crate) fn inv_root_poly2_published(z: f64) -> f64 {
    (0.014 * z - 0.119) * z + 0.681
}

/// docs/formulas.md#dichotomy: the degree-2 inverse root has max abs error <= 2e-5 and relative
/// 0.004 %. Judged on the published coefficients ([`inv_root_poly2_published`]); beside them the
/// project's 6-digit reconstruction (`scanline::inv_root_poly2`, what dichotomy_poly2 runs and
/// probably what the authors computed before rounding) and the minimax polynomial of degree 2.
pub fn dichotomy_poly2_error() -> Measurement {
    poly2_claim(&inv_root_poly2_published, &s::inv_root_poly2)
}

/// [`dichotomy_poly2_error`] with the published polynomial and the reconstruction as
/// parameters (the tests swap them).
pub(crate) fn poly2_claim(
    published: &dyn Fn(f64) -> f64,
    reconstruction: &dyn Fn(f64) -> f64,
) -> Measurement {
    let c = minimax_inv_root::<4>();
    let minimax = |z: f64| (c[2] * z + c[1]) * z + c[0];
    inv_root_claim(
        published,
        "the published coefficients 0.014 z^2 - 0.119 z + 0.681 (docs/formulas.md#dichotomy)",
        2e-5,
        0.004,
        &[
            (
                "the project's 6-digit reconstruction 0.014253 z^2 - 0.118922 z + 0.680850 \
                 (what dichotomy_poly2 runs; probably what the authors computed before \
                 rounding)",
                reconstruction,
            ),
            (
                "the minimax polynomial of degree 2 (Remez, src/method/scanline_checks.rs), the \
                 best any quadratic can do",
                &minimax,
            ),
        ],
    )
}

/// The closed form of 2.11 and slerp: the largest distance between them over angles up to
/// 170 degrees and t in [0, 1].
pub(crate) fn closed_form_gap(closed: fn(DVec3, DVec3, f64) -> DVec3) -> Worst {
    let mut gap = Worst::default();
    for a in 1..=17 {
        let (na, nb) = pair(10.0 * a as f64);
        for i in 0..=200 {
            let t = i as f64 / 200.0;
            gap.push((closed(na, nb, t) - s::slerp(na, nb, t)).length());
        }
    }
    gap
}

/// docs/formulas.md#spherical-angular-interpolation: spherical-angular interpolation gives the
/// slerp normals.
pub fn spherical_angular_is_slerp() -> Measurement {
    let gap = closed_form_gap(s::spherical_angular);
    Measurement {
        evidence: Evidence::found(gap.value(), Quantity::AbsoluteError),
        measured: format!(
            "largest |closed form - slerp| {:.1e}{}",
            gap.finite,
            gap.note()
        ),
        verdict: if gap.within(1e-12) {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "f64: both formulas (src/method/scanline.rs) at angles 10..170 deg and t in [0, 1] \
              (201 points); agrees when they differ by less than 1e-12"
            .into(),
    }
}

/// Positions inside a segment at which its diffuse error is swept: `t = i / SEGMENT_STEPS`.
const SEGMENT_STEPS: u32 = 16;

/// The worst relative error of the linearly interpolated diffuse intensity inside a segment,
/// over light directions, for unit segment-end normals `theta` apart: at each `t` of the
/// segment the exact intensity of the pixel's normal normalize(lerp(N_l, N_p, t)) (Phong's)
/// against `interpolate(I_l, I_p, t)` (the method: the ends' intensities interpolated
/// linearly).
pub(crate) fn segment_diffuse_error(
    theta_deg: f64,
    interpolate: fn(f64, f64, f64) -> f64,
) -> Worst {
    let (nl, np) = pair(theta_deg);
    // Lights over the hemisphere around the pair's bisector (where all three are lit).
    let lights: Vec<DVec3> = (0..=200)
        .flat_map(|i| {
            (0..400).map(move |j| {
                let (th, ph) = (
                    88f64.to_radians() * f64::from(i) / 200.0,
                    std::f64::consts::TAU * f64::from(j) / 400.0,
                );
                DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos())
            })
        })
        .collect();
    let mut worst = Worst::default();
    for k in 0..=SEGMENT_STEPS {
        let t = f64::from(k) / f64::from(SEGMENT_STEPS);
        let n = nl.lerp(np, t).normalize();
        for l in &lights {
            let (il, ip, im) = (nl.dot(*l), np.dot(*l), n.dot(*l));
            if il > 0.0 && ip > 0.0 {
                worst.push((im - interpolate(il, ip, t)) / im);
            }
        }
    }
    worst
}

/// docs/formulas.md#digital-segments-error-bounds: the linear interpolation of diffuse intensity
/// inside a segment whose end normals are theta apart has relative error at most
/// 1 - cos(theta / 2).
pub fn segments_diffuse_bound() -> Measurement {
    segments_diffuse_bound_with(|a, b, t| a + (b - a) * t)
}

/// The f64 rounding allowed above a bound of a relative error computed as (I - J) / I from
/// dot products of unit vectors: each intensity is within a few ulps of its value relative to
/// its size, and J / I >= cos(theta/2) ~ 1, so the ratio's rounding is a few ulps of 1; 64
/// ulps (1.4e-14) covers it with room, and is 4e-11 of the 4-degree bound.
const RELATIVE_ROUNDING: f64 = 64.0 * f64::EPSILON;

pub(crate) fn segments_diffuse_bound_with(interpolate: fn(f64, f64, f64) -> f64) -> Measurement {
    let theta = 4.0;
    let brute = segment_diffuse_error(theta, interpolate);
    let bound = 1.0 - (0.5 * theta).to_radians().cos();
    Measurement {
        evidence: Evidence::found(brute.value(), Quantity::RelativeError),
        measured: format!(
            "at {theta} deg: worst |relative error| {:.4} %{} ({:+.1e} from the bound), bound \
             1 - cos(theta/2) = {:.4} %",
            100.0 * brute.finite.abs(),
            brute.note(),
            brute.finite.abs() - bound,
            100.0 * bound
        ),
        verdict: if brute.within(bound + RELATIVE_ROUNDING) {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "f64: the exact diffuse intensity of the pixel's normal normalize(lerp(N_l, N_p, t)) \
             against the ends' intensities interpolated linearly, at t = 0, 1/{SEGMENT_STEPS} .. \
             1 of the segment and 80,400 light directions above the three normals, worst \
             |relative error| (src/method/scanline_checks.rs); the claim is a bound: agrees when \
             the worst does not exceed 1 - cos(theta/2) (by more than the f64 rounding of the \
             sweep, {RELATIVE_ROUNDING:.1e}), disagrees when it does or any point is non-finite"
        ),
    }
}

/// The specular bound of docs/formulas.md#digital-segments-error-bounds: `1 - cos^n(theta/2)`.
pub(crate) fn specular_bound(n: f64, theta_deg: f64) -> f64 {
    1.0 - (0.5 * theta_deg).to_radians().cos().powf(n)
}

/// docs/formulas.md#digital-segments-error-bounds: for the most common materials (n <= 100) the
/// specular error stays within 4 % at 4 degrees between segment-end normals.
pub fn segments_specular_4pct() -> Measurement {
    segments_specular_4pct_with(specular_bound)
}

pub(crate) fn segments_specular_4pct_with(bound: fn(f64, f64) -> f64) -> Measurement {
    let at_100 = bound(100.0, 4.0);
    let largest_n = (1..=1000)
        .take_while(|&n| bound(f64::from(n), 4.0) <= 0.04)
        .last();
    Measurement {
        evidence: Evidence::MEASURED,
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
        how: "f64: the paper's own bound 1 - cos^n(theta/2) \
              (docs/formulas.md#digital-segments-error-bounds) at theta = 4 deg for \
              n = 1..1000 (src/method/scanline_checks.rs); agrees when it is <= 4 % at n = 100"
            .into(),
    }
}

/// The length error in percent of the middle normal `mid(nl, np)` for unit ends `theta` apart.
pub(crate) fn mid_length_error_pct(theta_deg: f64, mid: fn(DVec3, DVec3) -> DVec3) -> f64 {
    let (nl, np) = pair(theta_deg);
    100.0 * (mid(nl, np).length() - 1.0)
}

/// docs/formulas.md#quadratic-interpolation-along-the-span: the middle normal of a scanline is
/// computed approximately as (0.103 c^2 - 0.306 c + 0.705)(N'_p + N'_l). Measured as its length
/// error over the fit's design range, end normals up to 90 degrees apart.
pub fn quadratic_mid_accuracy() -> Measurement {
    quadratic_mid_accuracy_with(s::mid_approx)
}

pub(crate) fn quadratic_mid_accuracy_with(mid: fn(DVec3, DVec3) -> DVec3) -> Measurement {
    let worst = Worst::of((0..=900).map(|i| mid_length_error_pct(0.1 * f64::from(i), mid)));
    let beyond = mid_length_error_pct(120.0, mid);
    let limit = super::checks::VISIBLE_LENGTH_ERROR_PCT;
    Measurement {
        evidence: Evidence::found(worst.value() / 100.0, Quantity::RelativeError),
        measured: format!(
            "worst length error {:+.3} %{} for end normals up to 90 deg apart ({beyond:+.2} % \
             at 120 deg)",
            worst.finite,
            worst.note()
        ),
        verdict: if worst.within(limit) {
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

/// The worst error of Bishop-Weimer's Taylor cosine against the exact one over a triangle whose
/// normal changes by `extent` (|A| r) from its centre to its edge, over light directions
/// (docs/formulas.md#bishop-weimer-taylor-shading's example: |A| = |B| = 0.3, C = +Z, measured
/// 1.1e-5 at r |A| = 0.03).
pub(crate) fn taylor_error(
    extent: f64,
    approx: fn(DVec3, DVec3, DVec3, DVec3, glam::DVec2) -> f64,
) -> Worst {
    let (a, b, c) = (
        DVec3::new(0.3, 0.0, 0.0),
        DVec3::new(0.0, 0.3, 0.0),
        DVec3::Z,
    );
    let r = extent / 0.3;
    let mut worst = Worst::default();
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
                worst.push((approx(l, a, b, c, p) - exact).abs());
            }
        }
    }
    worst
}

/// docs/formulas.md#bishop-weimer-taylor-shading: the second-order Taylor expansion approximates
/// the diffuse intensity over the polygon. Measured as the largest change of the normal across a
/// triangle (from its centre) at which the error stays within one 8-bit step of the intensity.
pub fn bishop_weimer_extent() -> Measurement {
    bishop_weimer_extent_with(s::taylor_cosine)
}

pub(crate) fn bishop_weimer_extent_with(
    approx: fn(DVec3, DVec3, DVec3, DVec3, glam::DVec2) -> f64,
) -> Measurement {
    let extents = [0.03, 0.075, 0.15, 0.3, 0.6];
    let errors: Vec<Worst> = extents.iter().map(|&e| taylor_error(e, approx)).collect();
    let step = 1.0 / 255.0;
    let holds = errors.iter().filter(|e| e.within(step)).count();
    let non_finite: usize = errors.iter().map(|e| e.non_finite).sum();
    let listed: Vec<String> = extents
        .iter()
        .zip(&errors)
        .map(|(x, e)| format!("{:.1e}{} at {x}", e.finite, e.note()))
        .collect();
    Measurement {
        evidence: Evidence::found(
            errors.iter().map(Worst::value).fold(0.0, |a, b| {
                if b.is_nan() || a.is_nan() {
                    f64::NAN
                } else {
                    a.max(b.abs())
                }
            }),
            Quantity::AbsoluteError,
        ),
        measured: format!(
            "worst |Taylor - exact| of N.L/|N| by the normal's change from the centre: {}",
            listed.join(", ")
        ),
        verdict: match holds {
            _ if non_finite > 0 => Verdict::Disagrees,
            n if n == extents.len() => Verdict::Agrees,
            0 => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: "f64: src/method/scanline.rs taylor_cosine against N.L/|N| for N = A x + B y + C \
              (|A| = |B| = 0.3, C = +Z) over a square around the centre and 24 light directions \
              (src/method/scanline_checks.rs); agrees when within 1/255 at every extent, \
              partly when only on the smaller ones; any non-finite point disagrees"
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
        // docs/formulas.md#dichotomy: the rounded line has 0.0011 / 0.217 %; the shipped quadratic's
        // 6-digit coefficients 2.20e-5 / 0.00432 %.
        let (abs, rel) = inv_root_errors(&s::inv_root_poly1);
        assert!((abs.finite - 0.0011).abs() < 1e-4 && (rel.finite * 100.0 - 0.217).abs() < 0.005);
        assert_eq!(v(dichotomy_poly1_error()), Verdict::Disagrees);
        let (abs, rel) = inv_root_errors(&s::inv_root_poly2);
        assert!((abs.finite - 2.20e-5).abs() < 0.01e-5, "{abs:?}");
        assert!((rel.finite * 100.0 - 0.00432).abs() < 0.00001, "{rel:?}");
        // teeth: the exact root meets any claim, a constant meets none
        let exact = inv_root_claim(&s::inv_root_exact, "exact", 0.0005, 0.12, &[]);
        assert_eq!(exact.verdict, Verdict::Agrees);
        let c = inv_root_claim(&|_| 0.6, "0.6", 2e-5, 0.004, &[]);
        assert_eq!(c.verdict, Verdict::Disagrees);
        // a NaN anywhere disagrees, with its count
        let nan = |z: f64| {
            if z == 2.0 {
                f64::NAN
            } else {
                s::inv_root_exact(z)
            }
        };
        let m = inv_root_claim(&nan, "NaN at 2", 2e-5, 0.004, &[]);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert!(
            m.measured.contains("(1 of 20001 points non-finite)"),
            "{m:?}"
        );
    }

    /// The digital-segment paper's "abs <= 2e-5, rel 0.004 %" is judged on the published coefficients (0.014, -0.119,
    /// 0.681: 1.0e-3, 50 times the claim), not on the project's 6-digit reconstruction (2.200e-5
    /// / 0.00432 %, which the old rule let "agree when rounded"); the reconstruction and the
    /// minimax quadratic (2.016e-5, also over the claim) are shown beside.
    #[test]
    fn the_degree_2_claim_is_judged_on_the_published_coefficients() {
        let (abs, rel) = inv_root_errors(&inv_root_poly2_published);
        assert!((abs.finite - 1.0e-3).abs() < 0.01e-3, "{abs:?}");
        assert!((100.0 * rel.finite - 0.2).abs() < 0.01, "{rel:?}");
        let m = dichotomy_poly2_error();
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert_eq!(m.evidence.found, Some(abs.finite), "{m:?}");
        assert!(
            m.measured
                .starts_with("the published coefficients 0.014 z^2 - 0.119 z + 0.681")
                && m.measured.contains("6-digit reconstruction")
                && m.measured.contains("2.2000e-5, 0.00432 %")
                && m.measured.contains("2.0160e-5, 0.00403 %"),
            "{m:?}"
        );
        // teeth: with the reconstruction in the published place it still disagrees (2.2e-5 is
        // over 2e-5: no rounding), and a polynomial within both figures agrees
        let m = poly2_claim(&s::inv_root_poly2, &s::inv_root_poly2);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        let m = poly2_claim(&s::inv_root_exact, &s::inv_root_poly2);
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
    }

    #[test]
    fn a_figure_over_its_bound_disagrees_by_any_amount() {
        let w = |x: f64| Worst::of([x].into_iter());
        assert_eq!(figure_verdict(&w(2e-5), 2e-5), Verdict::Agrees);
        assert_eq!(figure_verdict(&w(1.9e-5), 2e-5), Verdict::Agrees);
        // the old rule: agrees_rounded (2.2e-5 rounds to 2e-5 at one digit)
        assert_eq!(figure_verdict(&w(2.2e-5), 2e-5), Verdict::Disagrees);
        assert_eq!(
            figure_verdict(&w(2e-5 * (1.0 + 1e-12)), 2e-5),
            Verdict::Disagrees
        );
        assert_eq!(figure_verdict(&w(f64::NAN), 2e-5), Verdict::Disagrees);
        assert_eq!(combine(Verdict::Agrees, Verdict::Agrees), Verdict::Agrees);
        assert_eq!(
            combine(Verdict::Agrees, Verdict::Disagrees),
            Verdict::Partly
        );
    }

    #[test]
    fn remez_finds_the_equioscillating_minimax_polynomial() {
        // degree 2: error 2.016e-5 levelled at 4 points, below the shipped coefficients' 2.20e-5
        let c = minimax_inv_root::<4>();
        let p = |z: f64| (c[2] * z + c[1]) * z + c[0];
        let (abs, rel) = inv_root_errors(&p);
        assert!((abs.finite - 2.016e-5).abs() < 0.002e-5, "{abs:?} {c:?}");
        assert!((100.0 * rel.finite - 0.00403).abs() < 0.00001, "{rel:?}");
        // teeth: the optimum is better than any perturbation of it, and than the shipped one
        for d in [1e-6, -1e-6] {
            let (q, _) = inv_root_errors(&|z: f64| p(z) + d * (z - 1.7));
            assert!(q.finite > abs.finite, "{d}");
        }
        assert!(inv_root_errors(&s::inv_root_poly2).0.finite > abs.finite);
        // degree 1 against the seed's 0.64 - 0.07 z
        let c1 = minimax_inv_root::<3>();
        let (a1, _) = inv_root_errors(&|z: f64| c1[1] * z + c1[0]);
        assert!(a1.finite < inv_root_errors(&s::inv_root_poly1).0.finite);
    }

    #[test]
    fn spherical_angular_claim_flips_for_a_different_interpolation() {
        assert_eq!(v(spherical_angular_is_slerp()), Verdict::Agrees);
        let nlerp = |a: DVec3, b: DVec3, t: f64| a.lerp(b, t).normalize();
        assert!(closed_form_gap(nlerp).finite > 1e-3);
        assert!(closed_form_gap(|_, _, _| DVec3::NAN).value().is_nan());
    }

    #[test]
    fn quadratic_mid_and_taylor_checks_measure_their_formulas() {
        // docs/formulas.md#quadratic-interpolation-along-the-span: within +-0.33 % up to 90
        // degrees, -11.6 % at 120.
        let m = quadratic_mid_accuracy();
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
        assert!(m.measured.contains("-11.6"), "{m:?}");
        assert_eq!(
            v(quadratic_mid_accuracy_with(|a, b| (a + b) * 0.5)),
            Verdict::Disagrees
        );
        // docs/formulas.md#bishop-weimer-taylor-shading: 1.1e-5 at |A| r = 0.03 (r = 0.1), 1.8e-2
        // at 0.3 (r = 1)
        let e = taylor_error(0.03, s::taylor_cosine).value();
        assert!(e > 5e-6 && e < 3e-5, "{e}");
        // teeth: NaN inputs fail each of these checks, with the count
        for m in [
            quadratic_mid_accuracy_with(|_, _| DVec3::NAN),
            bishop_weimer_extent_with(|_, _, _, _, _| f64::NAN),
            segments_diffuse_bound_with(|_, _, _| f64::NAN),
        ] {
            assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
            assert!(m.measured.contains("points non-finite"), "{m:?}");
        }
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
        // docs/formulas.md#digital-segments-error-bounds: brute force 0.0609 % at 4 degrees, 5.91 % at n = 100,
        // "n <= 67" (n = 67 gives 4.0005 %: strictly, n <= 66).
        assert_eq!(v(segments_diffuse_bound()), Verdict::Agrees);
        let m = segments_specular_4pct();
        assert!(
            m.measured.contains("5.91 %") && m.measured.contains("up to n = 66 (n = 67: 4.0005 %)"),
            "{m:?}"
        );
        assert_eq!(m.verdict, Verdict::Disagrees);
        // teeth: a bound half as large makes the 4 % claim hold
        assert_eq!(
            v(segments_specular_4pct_with(
                |n, t| 0.5 * specular_bound(n, t)
            )),
            Verdict::Agrees
        );
    }

    /// The digital-segment paper's diffuse bound is a bound: over it disagrees by any amount (the old check asked
    /// for "equals the formula within 1 %", which let 1 % over agree), and it is swept over
    /// the whole segment, not only its middle.
    #[test]
    fn the_diffuse_bound_is_judged_one_sided() {
        let bound = 1.0 - 2f64.to_radians().cos();
        let m = segments_diffuse_bound();
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
        let found = m.evidence.found.unwrap();
        assert!((found - bound).abs() < 1e-14, "{found} {bound}");
        // the linear interpolation 0.5 % of the bound too low everywhere: its error is 1.005x
        // the bound at the middle (within the old 1 %)
        let low = segments_diffuse_bound_with(|a, b, t| {
            (a + (b - a) * t) * (1.0 - 0.005 * (1.0 - 2f64.to_radians().cos()))
        });
        assert_eq!(low.verdict, Verdict::Disagrees, "{low:?}");
        // exact at the middle, 1 % low elsewhere: the old check (the middle only) agreed
        let middle_only = |a: f64, b: f64, t: f64| {
            let lin = a + (b - a) * t;
            if t == 0.5 {
                lin
            } else {
                lin * 0.99
            }
        };
        let m = segments_diffuse_bound_with(middle_only);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }
}
