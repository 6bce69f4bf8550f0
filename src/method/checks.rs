//! The checks behind the method table's claims. Each runs an f64 sweep of the formula in
//! [`formulas`](super::formulas) when claims are written (`shadelab list --json`, and
//! `shadelab bench`'s claims.json/md) and derives its verdict from the number it measured, by
//! a rule stated in its `how`. No verdict is written by hand.
//!
//! Each check's core takes the formula as a parameter, so a test can feed it a deliberately
//! wrong formula and see the verdict flip (the tests at the end). The sweep helpers here are
//! shared with the formulas tests, which pin the same figures against FORMULAS.md section 3.
use glam::DVec3;

use super::formulas as f;
use super::{Measurement, Verdict};

/// A scalar factor `k(z) ~ 1/sqrt(z)`, `z = N.N`.
pub(crate) type Factor = fn(f64) -> f64;

/// Points per edge of a sweep: `t = i / STEPS`, i = 0..=STEPS.
pub(crate) const STEPS: usize = 100_000;

/// `t = i / STEPS`, i = 0..=STEPS, along an edge.
pub(crate) fn ts() -> impl Iterator<Item = f64> {
    (0..=STEPS).map(|i| i as f64 / STEPS as f64)
}

/// Two unit normals `theta` degrees apart, symmetric about +Z in the xz plane.
pub(crate) fn pair(theta_deg: f64) -> (DVec3, DVec3) {
    let h = (0.5 * theta_deg).to_radians();
    (
        DVec3::new(-h.sin(), 0.0, h.cos()),
        DVec3::new(h.sin(), 0.0, h.cos()),
    )
}

/// Angle between two vectors in degrees (atan2 form: accurate for tiny angles).
pub(crate) fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// The signed value of largest magnitude (0 for an empty sweep).
pub(crate) fn worst(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |w: f64, v| if v.abs() > w.abs() { v } else { w })
}

/// Signed relative length error `k(z)|N| - 1` in percent at the worst point of an edge whose
/// unit end normals are `theta` apart (FORMULAS.md 1.3). The edge covers z in
/// [cos^2(theta/2), 1], so this is also the worst case over all angles up to `theta`.
pub(crate) fn scalar_error_pct(k: Factor, theta_deg: f64) -> f64 {
    let (a, b) = pair(theta_deg);
    worst(ts().map(|t| {
        let n = a.lerp(b, t);
        let z = n.dot(n);
        100.0 * (k(z) * z.sqrt() - 1.0)
    }))
}

/// Mikami's normalised relative error `sqrt(z)/s1 - 1` in percent (FORMULAS.md 2.8).
pub(crate) fn mikami_error_pct(z: f64, beta: Factor) -> f64 {
    100.0 * (z.sqrt() / f::mikami_sqrt(z, beta(z)) - 1.0)
}

/// Worst Mikami error on z in [lo, 1] (fine grid, FORMULAS.md 2.8 sweeps [0.25, 1]).
pub(crate) fn mikami_worst_pct(lo: f64, beta: Factor) -> f64 {
    worst(ts().map(|t| mikami_error_pct(lo + (1.0 - lo) * t, beta)))
}

/// Worst angle (degrees) between `method(N)` and normalize(N) along the edge of a pair.
pub(crate) fn worst_edge_angle(theta_deg: f64, method: impl Fn(DVec3) -> DVec3) -> f64 {
    let (a, b) = pair(theta_deg);
    ts().map(|t| {
        let n = a.lerp(b, t);
        angle_deg(method(n), n)
    })
    .fold(0.0, f64::max)
}

/// A length error above this many percent counts as a visible error: the diffuse term scales
/// with the length, so 1 % is 2.6 of 255 levels at full intensity (our threshold; the seeds
/// state none).
pub const VISIBLE_LENGTH_ERROR_PCT: f64 = 1.0;

/// A length within this of 1 counts as exactly unit (f64 rounding of a few operations).
const UNIT_TOLERANCE: f64 = 1e-12;

fn sweep_how(formula: &str) -> String {
    format!(
        "f64 sweep of {formula} (src/method/formulas.rs) at {} points along an edge between two \
         unit vertex normals, run when this was written (src/method/checks.rs)",
        STEPS + 1
    )
}

// ---- claims that are not measured in f64 -----------------------------------------------------

/// Gouraud's "50x": a timing claim, measured by `shadelab bench` (claims.json), not here.
pub fn timing_claim() -> Measurement {
    Measurement {
        measured: "-".into(),
        verdict: Verdict::NotChecked,
        how: "a timing claim: no f64 formula measures it; `shadelab bench` times it on this \
              machine and writes the verdict to claims.json"
            .into(),
    }
}

/// A statement about a method's cost per pixel (operations it needs), not measured yet: the
/// isolated cost of each formula is the `[cost]` issue's measurement.
pub fn cost_claim() -> Measurement {
    Measurement {
        measured: "-".into(),
        verdict: Verdict::NotChecked,
        how: "a cost statement: no f64 formula measures it, and the isolated per-formula cost \
              that would is not measured yet"
            .into(),
    }
}

/// The operation count of normalisation: counted in the compiled SPIR-V by `shadelab bench`.
pub fn op_count_claim() -> Measurement {
    Measurement {
        measured: "-".into(),
        verdict: Verdict::NotChecked,
        how: "an operation count: no f64 formula measures it; `shadelab bench` counts the \
              SPIR-V of phong_exact minus phong_unnormalized and writes the verdict to claims.json"
            .into(),
    }
}

// ---- newton_raphson ---------------------------------------------------------------------------

/// "usable for angles between vertex normals up to 40 degrees" (S000 l.35).
pub fn newton_usable_to_40_deg() -> Measurement {
    usable_up_to(f::k_newton, "formulas::k_newton", 40.0)
}

/// Length error at `theta` against [`VISIBLE_LENGTH_ERROR_PCT`] (and at 1.5 theta, to show
/// how fast it grows beyond).
pub(crate) fn usable_up_to(k: Factor, name: &str, theta: f64) -> Measurement {
    let at = scalar_error_pct(k, theta);
    let beyond = scalar_error_pct(k, 1.5 * theta);
    Measurement {
        measured: format!(
            "worst length error {at:+.3} % at {theta} deg ({beyond:+.2} % at {} deg)",
            1.5 * theta
        ),
        verdict: if at.abs() <= VISIBLE_LENGTH_ERROR_PCT {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "{}; agrees when |length error| at {theta} deg <= {VISIBLE_LENGTH_ERROR_PCT} %",
            sweep_how(&format!("k(z)|N| - 1 with {name}"))
        ),
    }
}

/// The NVIDIA formula exactly as printed in S004 l.169: `N (3 - N.N) / 3`.
fn k_newton_as_printed_in_s004(z: f64) -> f64 {
    (3.0 - z) / 3.0
}

/// "S004 l.169 prints N (3 - N.N)/3": is the printed formula a normalisation?
pub fn newton_as_printed_in_s004() -> Measurement {
    printed_vs_corrected(k_newton_as_printed_in_s004, f::k_newton)
}

/// A normalisation must leave a unit vector unit: `k(1) = 1`. Disagrees when the printed
/// factor fails that and the corrected one (`/2`) passes; inconclusive when both fail.
pub(crate) fn printed_vs_corrected(printed: Factor, corrected: Factor) -> Measurement {
    let (p, c) = (printed(1.0), corrected(1.0));
    let unit = |k: f64| (k - 1.0).abs() <= UNIT_TOLERANCE;
    Measurement {
        measured: format!("k(1) = {p:.6} as printed (/3); k(1) = {c:.6} with /2"),
        verdict: match (unit(p), unit(c)) {
            (true, _) => Verdict::Agrees,
            (false, true) => Verdict::Disagrees,
            (false, false) => Verdict::Inconclusive,
        },
        how: "evaluates the printed factor (3 - z)/3 and formulas::k_newton (3 - z)/2 at z = 1 \
              (a unit normal at a vertex); disagrees when the printed k(1) is not 1 and /2's is \
              (a seed typo)"
            .into(),
    }
}

// ---- lyon_taylor ------------------------------------------------------------------------------

/// "the approximation error is large" (S004 l.181-183).
pub fn lyon_error_is_large() -> Measurement {
    error_is_large(f::k_lyon2, "formulas::k_lyon2")
}

/// "Large" means above [`VISIBLE_LENGTH_ERROR_PCT`]; measured at 40 and 90 degrees: large at
/// both agrees, at neither disagrees, at one of them partly.
pub(crate) fn error_is_large(k: Factor, name: &str) -> Measurement {
    let (e40, e90) = (scalar_error_pct(k, 40.0), scalar_error_pct(k, 90.0));
    let large = |e: f64| e.abs() > VISIBLE_LENGTH_ERROR_PCT;
    Measurement {
        measured: format!("worst length error {e40:+.4} % at 40 deg, {e90:+.2} % at 90 deg"),
        verdict: match (large(e40), large(e90)) {
            (true, true) => Verdict::Agrees,
            (false, false) => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: format!(
            "{}; large = |length error| > {VISIBLE_LENGTH_ERROR_PCT} %: agrees if large at both \
             40 and 90 deg, partly if at one",
            sweep_how(&format!("k(z)|N| - 1 with {name}"))
        ),
    }
}

// ---- hast_half_vector, quaternion: unit length without a square root ---------------------------

/// Angles between the vertex normals swept by the unit-length checks.
const UNIT_ANGLES: [f64; 4] = [40.0, 60.0, 90.0, 120.0];

/// "normalization without a square root" (S000 l.55-63) for Hast-Barrera-Bengtsson.
pub fn hbb_is_unit() -> Measurement {
    flat_based_is_unit(f::hbb)
}

/// The length of `method(lerp, flat)` along edges 40..120 degrees wide, the flat normal on the
/// bisector and on a vertex normal: agrees when it is 1 to 1e-12 everywhere (the result needs
/// no normalisation, so no square root).
pub(crate) fn flat_based_is_unit(method: fn(DVec3, DVec3) -> DVec3) -> Measurement {
    let mut dev = 0.0f64;
    for theta in UNIT_ANGLES {
        let (a, b) = pair(theta);
        for flat in [DVec3::Z, a] {
            for t in ts() {
                dev = dev.max((method(a.lerp(b, t), flat).length() - 1.0).abs());
            }
        }
    }
    let bisector = worst_edge_angle(90.0, |n| method(n, DVec3::Z));
    let vertex = worst_edge_angle(90.0, |n| method(n, pair(90.0).0));
    unit_measurement(
        dev,
        format!(", angle error at 90 deg {bisector:.2} deg (flat normal on the bisector) to {vertex:.1} deg (flat = vertex normal)"),
        "formulas::hbb, flat normal on the bisector and on a vertex normal",
    )
}

/// "no square root needed" (S000 l.187) for Hast's quaternion interpolation.
pub fn quaternion_is_unit() -> Measurement {
    quaternion_recovery_is_unit(f::normal_from_quat)
}

/// The length of `recover(lerp(q_a, q_b))` along edges 40..120 degrees wide: agrees when it is
/// 1 to 1e-12 everywhere.
pub(crate) fn quaternion_recovery_is_unit(recover: fn(DVec3) -> DVec3) -> Measurement {
    let mut dev = 0.0f64;
    for theta in UNIT_ANGLES {
        let (a, b) = pair(theta);
        let (qa, qb) = (f::quat_from_normal(a), f::quat_from_normal(b));
        for t in ts() {
            dev = dev.max((recover(qa.lerp(qb, t)).length() - 1.0).abs());
        }
    }
    let (a, b) = pair(90.0);
    let (qa, qb) = (f::quat_from_normal(a), f::quat_from_normal(b));
    let angle = ts()
        .map(|t| angle_deg(recover(qa.lerp(qb, t)), a.lerp(b, t)))
        .fold(0.0, f64::max);
    unit_measurement(
        dev,
        format!(
            ", angle error vs normalize(lerp) {angle:.2} deg at 90 deg (pair symmetric about +Z)"
        ),
        "formulas::normal_from_quat of the lerped formulas::quat_from_normal",
    )
}

fn unit_measurement(dev: f64, extra: String, what: &str) -> Measurement {
    Measurement {
        measured: format!("max ||N'| - 1| = {dev:.1e}{extra}"),
        verdict: if dev <= UNIT_TOLERANCE {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "{} ({what}; edges {UNIT_ANGLES:?} deg); agrees when |N'| = 1 to {UNIT_TOLERANCE:e} \
             everywhere, i.e. the result needs no square root to be unit",
            sweep_how("|N'|")
        ),
    }
}

// ---- mikami -----------------------------------------------------------------------------------

/// Mikami's claimed bound on the normalised relative error, percent (S000 l.74).
const MIKAMI_BOUND_PCT: f64 = 1.5;

/// "maximum normalised relative error <= 1.5 %" (S000 l.74), beta = 0.64.
pub fn mikami_const_within_bound() -> Measurement {
    mikami_within_bound(f::beta_const, "formulas::beta_const")
}

/// The same claim with beta = 1.07 - 0.62 z.
pub fn mikami_linear_within_bound() -> Measurement {
    mikami_within_bound(f::beta_linear, "formulas::beta_linear")
}

/// The same claim with beta = 0.763 z^2 - 1.57 z + 1.31.
pub fn mikami_quadratic_within_bound() -> Measurement {
    mikami_within_bound(f::beta_quadratic, "formulas::beta_quadratic")
}

/// Worst `sqrt(z)/s1 - 1` on z in [0.25, 1] against the claimed 1.5 %.
pub(crate) fn mikami_within_bound(beta: Factor, name: &str) -> Measurement {
    let e = mikami_worst_pct(0.25, beta);
    let at1 = mikami_error_pct(1.0, beta);
    Measurement {
        measured: format!(
            "max |error| {:.3} % on z in [0.25, 1]; {at1:+.3} % at z = 1",
            e.abs()
        ),
        verdict: if e.abs() <= MIKAMI_BOUND_PCT {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "f64 sweep of sqrt(z)/s1 - 1 (formulas::mikami_sqrt with {name}) at {} points of \
             z in [0.25, 1], run when this was written; agrees when the worst |error| <= \
             {MIKAMI_BOUND_PCT} %",
            STEPS + 1
        ),
    }
}

// ---- romanyuk_poly ----------------------------------------------------------------------------

/// "8x" read as a rounded figure: at least 7.5x counts as 8x.
const ROMANYUK_FACTOR: f64 = 7.5;

/// "relative error 8x smaller than Lyon's approach" (S000 l.79-80).
pub fn romanyuk_8x_smaller() -> Measurement {
    times_smaller(
        f::k_romanyuk,
        [
            ("Lyon 2nd degree", f::k_lyon2),
            ("Lyon shift", f::k_lyon_shift),
        ],
    )
}

/// Worst |length error| of `k` and of each Lyon form for theta <= 60 and <= 90 degrees; each of
/// the four (range, Lyon form) pairs holds when Lyon's error / k's >= 7.5. All hold: agrees;
/// none: disagrees; otherwise partly.
pub(crate) fn times_smaller(k: Factor, lyons: [(&str, Factor); 2]) -> Measurement {
    let mut parts = Vec::new();
    let mut held = 0;
    for theta in [90.0, 60.0] {
        let own = scalar_error_pct(k, theta).abs();
        let mut part = format!("theta <= {theta} deg: {own:.3} %");
        for (name, lyon) in lyons {
            let other = scalar_error_pct(lyon, theta).abs();
            let ratio = other / own;
            held += usize::from(ratio >= ROMANYUK_FACTOR);
            part += &format!(" vs {name} {other:.3} % ({ratio:.1}x)");
        }
        parts.push(part);
    }
    Measurement {
        measured: parts.join("; "),
        verdict: match held {
            4 => Verdict::Agrees,
            0 => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: format!(
            "{}; each of (theta <= 90, <= 60 deg) x (Lyon 2nd degree, Lyon shift) holds when the \
             ratio >= {ROMANYUK_FACTOR} (8x rounded): all agree, none disagrees, else partly",
            sweep_how("k(z)|N| - 1 with formulas::k_romanyuk, k_lyon2, k_lyon_shift")
        ),
    }
}

// ---- trueform ---------------------------------------------------------------------------------

/// The PN tessellator's signature (`formulas::pn_tessellate`).
pub(crate) type Tessellator = fn([DVec3; 3], [DVec3; 3], u32) -> Vec<([DVec3; 3], [DVec3; 3])>;

/// "9 sub-triangles per triangle: 2 extra vertices per edge + 1 centre" (S004 l.54-59).
pub fn trueform_level_3_counts() -> Measurement {
    tessellation_counts(f::pn_tessellate)
}

/// Tessellates a curved triangle at level 3 and counts its triangles and distinct vertices:
/// the claim means 9 triangles and 3 + 3 x 2 + 1 = 10 vertices.
pub(crate) fn tessellation_counts(tessellate: Tessellator) -> Measurement {
    let n = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.3, 0.0, 1.0),
        DVec3::new(0.0, 0.3, 1.0),
    ]
    .map(|v| v.normalize());
    let tris = tessellate(n, n, 3);
    let mut distinct: Vec<[u64; 3]> = tris
        .iter()
        .flat_map(|(ps, _)| ps.iter().map(|v| v.to_array().map(f64::to_bits)))
        .collect();
    distinct.sort_unstable();
    distinct.dedup();
    let (t, v) = (tris.len(), distinct.len());
    Measurement {
        measured: format!("level-3 tessellation: {t} triangles, {v} distinct vertices"),
        verdict: if (t, v) == (9, 10) {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "tessellates a curved triangle with formulas::pn_tessellate at level 3 and counts \
              triangles and bit-identical vertices; agrees for 9 triangles and 10 vertices (3 \
              corners + 2 per edge + 1 centre)"
            .into(),
    }
}

// ---- specular_lut -----------------------------------------------------------------------------

/// "tables for n = 1..255 need more than 4 MB" (S004 l.201-203).
pub fn specular_lut_over_4_mb() -> Measurement {
    lut_bytes(f::specular_lut)
}

/// Builds the 255-row table and measures its size: agrees when it exceeds 4e6 bytes.
pub(crate) fn lut_bytes(build: fn(usize, usize) -> Vec<f32>) -> Measurement {
    let table = build(f::LUT_ROWS, f::LUT_SAMPLES);
    let bytes = std::mem::size_of_val(table.as_slice());
    Measurement {
        measured: format!(
            "this table: {} exponents x {} cosines x 32 bit = {bytes} bytes ({:.2} MB)",
            f::LUT_ROWS,
            f::LUT_SAMPLES,
            bytes as f64 / 1e6
        ),
        verdict: if bytes as f64 > 4e6 {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: "builds the table with formulas::specular_lut (n = 1..255, the sample count the \
              renderer uploads) and measures its bytes; agrees when > 4e6 bytes"
            .into(),
    }
}

#[cfg(test)]
mod tests {
    //! Teeth: every check's core fed a deliberately wrong formula must change its verdict.
    use super::*;

    #[test]
    fn the_table_checks_give_the_verdicts_of_formulas_md_section_3() {
        let v = |m: Measurement| m.verdict;
        assert_eq!(v(newton_usable_to_40_deg()), Verdict::Agrees);
        assert_eq!(v(newton_as_printed_in_s004()), Verdict::Disagrees);
        assert_eq!(v(lyon_error_is_large()), Verdict::Partly);
        assert_eq!(v(hbb_is_unit()), Verdict::Agrees);
        assert_eq!(v(quaternion_is_unit()), Verdict::Agrees);
        assert_eq!(v(mikami_const_within_bound()), Verdict::Agrees);
        assert_eq!(v(mikami_linear_within_bound()), Verdict::Agrees);
        assert_eq!(v(mikami_quadratic_within_bound()), Verdict::Agrees);
        assert_eq!(v(romanyuk_8x_smaller()), Verdict::Partly);
        assert_eq!(v(trueform_level_3_counts()), Verdict::Agrees);
        assert_eq!(v(specular_lut_over_4_mb()), Verdict::Agrees);
        assert_eq!(v(timing_claim()), Verdict::NotChecked);
    }

    #[test]
    fn newton_usable_flips_for_a_factor_that_does_not_normalise() {
        // k = 1 leaves the interpolated normal as it is: cos(20 deg) - 1 = -6.0 % at 40 deg.
        let m = usable_up_to(|_| 1.0, "k = 1", 40.0);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert!(m.measured.contains("-6.031 %"), "{m:?}");
    }

    #[test]
    fn printed_formula_check_flips_when_the_printed_factor_is_right() {
        assert_eq!(
            printed_vs_corrected(f::k_newton, f::k_newton).verdict,
            Verdict::Agrees
        );
        let m = printed_vs_corrected(k_newton_as_printed_in_s004, k_newton_as_printed_in_s004);
        assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
    }

    #[test]
    fn unit_length_checks_flip_for_a_method_that_does_not_normalise() {
        let m = flat_based_is_unit(|n, _| n);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        let m = quaternion_recovery_is_unit(|q| q);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }

    #[test]
    fn mikami_check_flips_for_a_wrong_beta() {
        // beta = 0 keeps the start value s0 = 2/3 z + 0.35: -3.2 % at z = 0.25.
        let m = mikami_within_bound(|_| 0.0, "beta = 0");
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }

    #[test]
    fn error_is_large_and_8x_checks_flip_for_other_factors() {
        // k = 1 (no normalisation) is large at both angles (-6.0 %, -29 %).
        assert_eq!(error_is_large(|_| 1.0, "k = 1").verdict, Verdict::Agrees);
        // Exact 1/sqrt(z) has no error: never large.
        let exact = error_is_large(|z| 1.0 / z.sqrt(), "exact");
        assert_eq!(exact.verdict, Verdict::Disagrees, "{exact:?}");
        // Lyon against itself is 1x, never 8x.
        let m = times_smaller(f::k_lyon2, [("a", f::k_lyon2), ("b", f::k_lyon_shift)]);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }

    #[test]
    fn tessellation_and_lut_checks_flip_for_wrong_builders() {
        let m = tessellation_counts(|p, n, _| f::pn_tessellate(p, n, 2));
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        let m = lut_bytes(|rows, samples| f::specular_lut(rows, samples / 2));
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }
}
