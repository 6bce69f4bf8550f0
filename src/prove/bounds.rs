//! The proof overlay of the method table's bound claims: `crate::method::checks` judges every
//! claim by sampling only (basis found or measured); this module re-judges the bounds the proof
//! covers (Newton-Raphson's 40 deg, Mikami's 1.5 %, Romanyuk's 8x over edges and the triangle's
//! interior) with the same sweeps plus [`super::claims::length_error`]'s branch-and-bound, so
//! the verdict rests on a proven upper bound beside the found value (basis proven). The layers
//! that write claims (`shadelab list --json`, bench's claims, proof.json, and through bench.json
//! the report's claims matrix) go through [`with_proof`] / [`Judged`].
use serde::Serialize;

use super::claims::{at_most, length_error, verdict, Part};
use super::covered::{factor, Factor as ProveFactor};
use super::interval::Interval;
use crate::method::checks::{
    interior_error, mikami_error_pct, mikami_worst, scalar_error, scalar_error_pct, sweep_how,
    Factor, Worst, COLOUR_LEVEL_PCT, MIKAMI_BOUND_PCT, ROMANYUK_ANGLES, ROMANYUK_FACTOR, STEPS,
    VISIBLE_LENGTH_ERROR_PCT,
};
use crate::method::formulas as f;
use crate::method::{Basis, Claim, Evidence, Measurement, Quantity, Verdict};

/// A bound claim the proof judges: (method name, the claim's text in the method table, the
/// proven check).
type Overlay = (&'static str, &'static str, fn() -> Measurement);

/// The claims [`with_proof`] re-judges. A test checks every entry names a claim of the table.
const OVERLAYS: [Overlay; 5] = [
    (
        "newton_raphson",
        "usable for angles between vertex normals up to 40 (degrees assumed) (docs/formulas.md#newton-raphson-step)",
        newton_usable_to_40_deg,
    ),
    ("mikami_const", MIKAMI_CLAIM, mikami_const_within_bound),
    ("mikami_linear", MIKAMI_CLAIM, mikami_linear_within_bound),
    (
        "mikami_quadratic",
        MIKAMI_CLAIM,
        mikami_quadratic_within_bound,
    ),
    (
        "romanyuk_poly",
        "relative error 8x smaller than Lyon's approach (docs/formulas.md#romanyuk-romanyuk-pavlyk-polynomial)",
        romanyuk_8x_smaller,
    ),
];

const MIKAMI_CLAIM: &str =
    "maximum normalised relative error <= 1.5 % (docs/formulas.md#mikami-square-root)";

/// Claim `c` of method `method`, judged by proof where [`OVERLAYS`] covers it, else the method
/// table's own (sampled) check.
pub fn with_proof(method: &str, c: &Claim) -> Measurement {
    match OVERLAYS
        .iter()
        .find(|(m, text, _)| *m == method && *text == c.claim)
    {
        Some((_, _, proven)) => proven(),
        None => (c.check)(),
    }
}

/// A claim as `shadelab list --json` writes it: the 8 keys of `crate::method::Claim`'s own
/// serialisation, measured through [`with_proof`].
pub struct Judged<'a> {
    pub method: &'a str,
    pub claim: &'a Claim,
}

impl Serialize for Judged<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        crate::method::serialize_claim(self.claim.claim, &with_proof(self.method, self.claim), s)
    }
}

/// "usable for angles between vertex normals up to 40 degrees"
/// (docs/formulas.md#newton-raphson-step), by proof.
pub fn newton_usable_to_40_deg() -> Measurement {
    usable_up_to(
        f::k_newton,
        Some(factor!(f::k_newton)),
        "formulas::k_newton",
        40.0,
    )
}

/// Mikami's claim with beta = 0.64, by proof.
pub fn mikami_const_within_bound() -> Measurement {
    mikami_within_bound(
        f::beta_const,
        Some(factor!(super::covered::k_mikami_const)),
        "formulas::beta_const",
        MIKAMI_BOUND_PCT,
    )
}

/// The same claim with beta = 1.07 - 0.62 z.
pub fn mikami_linear_within_bound() -> Measurement {
    mikami_within_bound(
        f::beta_linear,
        Some(factor!(super::covered::k_mikami_linear)),
        "formulas::beta_linear",
        MIKAMI_BOUND_PCT,
    )
}

/// The same claim with beta = 0.763 z^2 - 1.57 z + 1.31.
pub fn mikami_quadratic_within_bound() -> Measurement {
    mikami_within_bound(
        f::beta_quadratic,
        Some(factor!(super::covered::k_mikami_quadratic)),
        "formulas::beta_quadratic",
        MIKAMI_BOUND_PCT,
    )
}

/// "relative error 8x smaller than Lyon's approach"
/// (docs/formulas.md#romanyuk-romanyuk-pavlyk-polynomial), by proof.
pub fn romanyuk_8x_smaller() -> Measurement {
    times_smaller(
        (f::k_romanyuk, Some(factor!(f::k_romanyuk))),
        [
            ("Lyon 2nd degree", f::k_lyon2, Some(factor!(f::k_lyon2))),
            (
                "Lyon shift",
                f::k_lyon_shift,
                Some(factor!(f::k_lyon_shift)),
            ),
        ],
    )
}

/// The evidence of a length-error bound: the f64 sweep's worst |error| (`sweep`, a fraction;
/// NaN when a point was non-finite) and, with `proof`, the proven upper bound over `z` and
/// the best real point the proof found. `found` is the larger of the two real values.
pub(crate) fn length_evidence(sweep: f64, proof: Option<ProveFactor>, z: Interval) -> Evidence {
    let o = proof.map(|k| length_error(k, z));
    let found = match o {
        Some(o) if sweep.is_nan() || o.found.is_nan() => f64::NAN,
        Some(o) => sweep.max(o.found),
        None => sweep,
    };
    Evidence {
        basis: if o.is_some() {
            Basis::Proven
        } else {
            Basis::Found
        },
        proven_upper: o.map(|o| o.proven_upper).filter(|p| p.is_finite()),
        found: found.is_finite().then_some(found),
        quantity: Some(Quantity::RelativeError),
    }
}

/// How a bound claim is judged (the `how` of each).
const PROOF_RULE: &str = "judged by proof (src/prove, `shadelab prove`'s interval \
     branch-and-bound of the same generic formula, outward-rounded): a part holds only when the \
     proven upper bound is within the claimed figure, fails when a real point (the sweep's or \
     the proof's) exceeds it or is non-finite, else is undecided; all hold: agrees, all fail: \
     disagrees, any undecided: inconclusive, else partly";

/// Length error up to `theta` (the edge's z range, inputs rounded to float32) by two named
/// criteria side by side: the length criterion (|error| <= [`VISIBLE_LENGTH_ERROR_PCT`]) and
/// the colour criterion (|error| <= [`COLOUR_LEVEL_PCT`], one 8-bit level, the criterion of
/// `shadelab stress`), each judged by proof ([`at_most`]). Also the sweep
/// at 1.5 theta, to show how fast it grows beyond.
pub(crate) fn usable_up_to(
    k: Factor,
    proof: Option<ProveFactor>,
    name: &str,
    theta: f64,
) -> Measurement {
    let at = scalar_error(k, theta);
    let beyond = scalar_error_pct(k, 1.5 * theta);
    let ev = length_evidence(
        at.value().abs() / 100.0,
        proof,
        super::covered::z_range(theta),
    );
    let found = ev.found.unwrap_or(f64::NAN);
    let (length, colour) = (
        at_most(ev.proven_upper, found, VISIBLE_LENGTH_ERROR_PCT / 100.0),
        at_most(ev.proven_upper, found, COLOUR_LEVEL_PCT / 100.0),
    );
    Measurement {
        measured: format!(
            "worst length error {:+.3} % at {theta} deg{} ({beyond:+.2} % at {} deg); proven \
             |length error| <= {}; length criterion (<= {VISIBLE_LENGTH_ERROR_PCT} %) {}, \
             colour criterion (<= 1/255 = {COLOUR_LEVEL_PCT:.3} %) {}",
            at.finite,
            at.note(),
            1.5 * theta,
            pct_or_none(ev.proven_upper),
            length.word(),
            colour.word()
        ),
        verdict: verdict(&[length, colour]),
        evidence: ev,
        how: format!(
            "{}; proven over N.N from the edge of unit normals {theta} deg apart (stress's case \
             geometry, inputs rounded to float32); two criteria on |length error|: length <= \
             {VISIBLE_LENGTH_ERROR_PCT} % (our visible-length threshold) and colour <= 1/255 \
             (one 8-bit level of a full diffuse term, the criterion of `shadelab stress`), each \
             {PROOF_RULE}",
            sweep_how(&format!("k(z)|N| - 1 with {name}"))
        ),
    }
}

/// A proven bound in percent, or "not proven".
fn pct_or_none(p: Option<f64>) -> String {
    p.map_or("not proven".into(), |p| format!("{:.4} %", 100.0 * p))
}

/// Worst `sqrt(z)/s1 - 1` on z in [0.25, 1] against the claimed `bound_pct`, judged by proof
/// (`proof`: the same factor `1/s1` in intervals; None: found only).
pub(crate) fn mikami_within_bound(
    beta: Factor,
    proof: Option<ProveFactor>,
    name: &str,
    bound_pct: f64,
) -> Measurement {
    let e = mikami_worst(0.25, beta);
    let at1 = mikami_error_pct(1.0, beta);
    let ev = length_evidence(e.value().abs() / 100.0, proof, Interval::new(0.25, 1.0));
    let part = at_most(
        ev.proven_upper,
        ev.found.unwrap_or(f64::NAN),
        bound_pct / 100.0,
    );
    Measurement {
        measured: format!(
            "max |error| {:.3} % on z in [0.25, 1]{}; {at1:+.3} % at z = 1; proven <= {}: {}",
            e.finite.abs(),
            e.note(),
            pct_or_none(ev.proven_upper),
            part.word()
        ),
        verdict: verdict(&[part]),
        evidence: ev,
        how: format!(
            "f64 sweep of sqrt(z)/s1 - 1 (formulas::mikami_sqrt with {name}) at {} points of \
             z in [0.25, 1], run when this was written, and the proof over z in [0.25, 1]; \
             the claim (<= {bound_pct} %) {PROOF_RULE}",
            STEPS + 1
        ),
    }
}

/// A factor in f64 (the sweep) and in intervals (the proof; None: found only).
pub(crate) type Both = (Factor, Option<ProveFactor>);

/// Worst |length error| of `k` and of each Lyon form for normals up to 90, 60 and 40 degrees
/// apart, on a triangle's edges (z from the edge's proven range) and over its interior (three
/// free normals pairwise theta apart: z from (1 + 2 cos theta)/3,
/// [`super::covered::triangle_z_range`]). Each (angle, region, Lyon form) part holds
/// when Lyon's found / k's proven >= 8 (proven: Lyon's true worst is at least its found value,
/// k's at most its proven one), fails when Lyon's proven / k's found < 8, else is undecided;
/// the verdict as [`verdict`]. The evidence is the ratio k's worst / Lyon's worst (claimed <=
/// 1/8): proven_upper the largest k's proven / Lyon's found, found the largest k's found /
/// Lyon's proven over the parts.
pub(crate) fn times_smaller(
    k: Both,
    lyons: [(&str, Factor, Option<ProveFactor>); 2],
) -> Measurement {
    let mut text = Vec::new();
    let mut parts = Vec::new();
    let (mut proven_ratio, mut found_ratio) = (0.0f64, 0.0f64);
    let mut all_proven = k.1.is_some();
    let mut non_finite = false;
    for theta in ROMANYUK_ANGLES {
        for (region, sweep, z) in [
            (
                "edges",
                scalar_error as fn(Factor, f64) -> Worst,
                super::covered::z_range(theta),
            ),
            (
                "interior",
                interior_error,
                super::covered::triangle_z_range(theta),
            ),
        ] {
            let w = sweep(k.0, theta);
            let own = length_evidence(w.value().abs() / 100.0, k.1, z);
            let mut part_text = format!(
                "theta <= {theta} deg, {region}: {:.3} %{} (proven {})",
                w.finite.abs(),
                w.note(),
                pct_or_none(own.proven_upper)
            );
            for (name, lyon, lyon_proof) in lyons {
                all_proven &= lyon_proof.is_some();
                let lw = sweep(lyon, theta);
                let other = length_evidence(lw.value().abs() / 100.0, lyon_proof, z);
                let (of, op) = (
                    other.found.unwrap_or(f64::NAN),
                    other.proven_upper.unwrap_or(f64::INFINITY),
                );
                let (kf, kp) = (
                    own.found.unwrap_or(f64::NAN),
                    own.proven_upper.unwrap_or(f64::INFINITY),
                );
                // the ratio Lyon / k lies in [of / kp, op / kf]
                let (lo, hi) = (of / kp, op / kf);
                let part = if of.is_nan() || kf.is_nan() {
                    non_finite = true;
                    Part::Fails
                } else if lo >= ROMANYUK_FACTOR {
                    Part::Holds
                } else if hi < ROMANYUK_FACTOR {
                    Part::Fails
                } else {
                    Part::Undecided
                };
                proven_ratio = proven_ratio.max(kp / of);
                found_ratio = found_ratio.max(kf / op);
                part_text += &format!(
                    " vs {name} {:.3} %{} (ratio in [{lo:.2}, {hi:.2}]: {})",
                    lw.finite.abs(),
                    lw.note(),
                    part.word()
                );
                parts.push(part);
            }
            text.push(part_text);
        }
    }
    let held = parts.iter().filter(|&&p| p == Part::Holds).count();
    Measurement {
        measured: format!("{held} of {} parts hold; {}", parts.len(), text.join("; ")),
        verdict: if non_finite {
            Verdict::Disagrees
        } else {
            verdict(&parts)
        },
        evidence: Evidence {
            basis: if all_proven {
                Basis::Proven
            } else {
                Basis::Found
            },
            proven_upper: Some(proven_ratio).filter(|r| r.is_finite()),
            found: Some(found_ratio).filter(|r| r.is_finite() && !non_finite),
            quantity: Some(Quantity::ErrorRatio),
        },
        how: format!(
            "{}, and over the interior of a triangle of three normals theta apart (z from \
             (1 + 2 cos theta)/3 to 1); each of (theta <= {ROMANYUK_ANGLES:?} deg) x (edges, \
             interior) x (Lyon 2nd degree, Lyon shift) holds when Lyon's found error / \
             Romanyuk's proven >= {ROMANYUK_FACTOR} (the claimed factor, no rounding), fails \
             when Lyon's proven / Romanyuk's found < {ROMANYUK_FACTOR} or a point is \
             non-finite, else undecided; all hold: agrees, all fail: disagrees, any undecided: \
             inconclusive, else partly; any non-finite point disagrees (proof: src/prove); proven_upper and found: Romanyuk's \
             worst / Lyon's, claimed <= 1/{ROMANYUK_FACTOR}",
            sweep_how("k(z)|N| - 1 with formulas::k_romanyuk, k_lyon2, k_lyon_shift")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::METHODS;

    #[test]
    fn every_overlay_names_a_claim_of_the_table_and_proves_it() {
        for (method, text, _) in OVERLAYS {
            let m = METHODS.iter().find(|m| m.name == method).expect(method);
            let c = m.claims.iter().find(|c| c.claim == text).expect(text);
            let (sampled, proven) = ((c.check)(), with_proof(method, c));
            assert_eq!(sampled.evidence.basis, Basis::Found, "{method}");
            assert_eq!(proven.evidence.basis, Basis::Proven, "{method}: {proven:?}");
            assert!(proven.evidence.proven_upper.is_some(), "{method}");
            // the proof decides the same way as the table's sampled verdict
            assert_eq!(proven.verdict, sampled.verdict, "{method}");
        }
        // a claim it does not cover keeps the table's own check; a wrong method name as well
        let lyon = METHODS.iter().find(|m| m.name == "lyon_taylor").unwrap();
        let c = &lyon.claims[0];
        assert_eq!(with_proof("lyon_taylor", c), (c.check)());
        let mikami = METHODS.iter().find(|m| m.name == "mikami_const").unwrap();
        let c = &mikami.claims[0];
        assert_eq!(with_proof("not_mikami", c).evidence.basis, Basis::Found);
    }

    #[test]
    fn judged_serialises_the_eight_keys_through_the_proof() {
        let m = METHODS.iter().find(|m| m.name == "romanyuk_poly").unwrap();
        let j = serde_json::to_value(Judged {
            method: m.name,
            claim: &m.claims[0],
        })
        .unwrap();
        let now = romanyuk_8x_smaller();
        assert_eq!(j.as_object().unwrap().len(), 8, "{j}");
        assert_eq!(j["claim"], m.claims[0].claim);
        assert_eq!(j["basis"], "proven");
        assert_eq!(j["verdict"], now.verdict.as_str());
        assert_eq!(j["measured"], now.measured.as_str());
        assert_eq!(j["proven_upper"].as_f64(), now.evidence.proven_upper);
        assert_eq!(j["found"].as_f64(), now.evidence.found);
        assert_eq!(j["how"], now.how.as_str());
        // its figures are ratios of two errors, not errors, and say so (issue 39 item 7)
        assert_eq!(j["quantity"], "error_ratio");
        assert!(now.evidence.found.unwrap() > 1.0, "{j}");
    }

    #[test]
    fn newton_by_proof_flips_for_a_factor_that_does_not_normalise() {
        // k = 1 leaves the interpolated normal as it is: cos(20 deg) - 1 = -6.0 % at 40 deg.
        let m = usable_up_to(
            |_| 1.0,
            Some(factor!(super::super::covered::k_one)),
            "k = 1",
            40.0,
        );
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert!(m.measured.contains("-6.031 %"), "{m:?}");
        // Newton at 40 deg: -0.535 % holds the 1 % length criterion, fails 1/255 = 0.392 %.
        let m = newton_usable_to_40_deg();
        assert!(
            m.measured.contains("-0.535 %")
                && m.measured.contains("length criterion (<= 1 %) holds")
                && m.measured
                    .contains("colour criterion (<= 1/255 = 0.392 %) fails"),
            "{m:?}"
        );
        // the exact factor holds both
        let exact = usable_up_to(
            |z| 1.0 / z.sqrt(),
            Some(factor!(super::super::covered::k_exact)),
            "exact",
            40.0,
        );
        assert_eq!(exact.verdict, Verdict::Agrees, "{exact:?}");
    }

    #[test]
    fn a_non_finite_point_disagrees_with_or_without_the_proof() {
        let nan = |_: f64| f64::NAN;
        for m in [
            usable_up_to(nan, None, "NaN", 40.0),
            mikami_within_bound(nan, None, "NaN", 1.5),
            times_smaller(
                (nan, None),
                [("a", f::k_lyon2, None), ("b", f::k_lyon_shift, None)],
            ),
            times_smaller(
                (f::k_romanyuk, Some(factor!(f::k_romanyuk))),
                [("a", nan, None), ("b", f::k_lyon_shift, None)],
            ),
        ] {
            assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
            assert!(m.measured.contains("points non-finite)"), "{m:?}");
            assert_eq!(m.evidence.found, None, "{m:?}");
        }
    }

    #[test]
    fn the_8x_claim_by_proof_needs_the_full_factor() {
        // A factor exactly 7.9x better than Lyon's 2nd degree everywhere: short of 8.
        fn k79<T: crate::method::real::Real>(z: T) -> T {
            (T::c(1.0) + (f::k_lyon2(z) * z.sqrt() - T::c(1.0)) / T::c(7.9)) / z.sqrt()
        }
        let lyon = Some(factor!(f::k_lyon2));
        let m = times_smaller(
            (k79::<f64>, Some(factor!(k79))),
            [("a", f::k_lyon2, lyon), ("b", f::k_lyon2, lyon)],
        );
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert_eq!(m.evidence.basis, Basis::Proven, "{m:?}");
        // without the proofs the found ratio 7.9 cannot decide (Lyon's true worst may be
        // larger than its found one): inconclusive, basis found
        let m = times_smaller(
            (k79, None),
            [("a", f::k_lyon2, None), ("b", f::k_lyon2, None)],
        );
        assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
        assert_eq!(m.evidence.basis, Basis::Found, "{m:?}");
        // Lyon against itself is 1x, never 8x, proven
        let m = times_smaller(
            (f::k_lyon2, lyon),
            [
                ("a", f::k_lyon2, lyon),
                ("b", f::k_lyon_shift, Some(factor!(f::k_lyon_shift))),
            ],
        );
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        let m = romanyuk_8x_smaller();
        assert!(m.measured.contains("theta <= 40 deg, edges"), "{m:?}");
        assert!(m.measured.contains("interior"), "{m:?}");
    }

    #[test]
    fn a_proven_claim_flips_with_its_figure_between_found_and_proven() {
        let k = Some(factor!(super::super::covered::k_mikami_const));
        let m = mikami_within_bound(f::beta_const, k, "beta_const", 1.5);
        assert_eq!(
            (m.verdict, m.evidence.basis),
            (Verdict::Agrees, Basis::Proven)
        );
        let (p, found) = (m.evidence.proven_upper.unwrap(), m.evidence.found.unwrap());
        assert!(found <= p && p <= found * 1.001 + 1e-12, "{m:?}");
        // the claim tightened to the proven bound still holds; below the found value it is
        // contradicted by a real point; between the two the proof cannot decide
        let at = |pct: f64| mikami_within_bound(f::beta_const, k, "beta_const", pct).verdict;
        assert_eq!(at(100.0 * p), Verdict::Agrees);
        assert_eq!(at(100.0 * found * 0.999), Verdict::Disagrees);
        if p > found {
            assert_eq!(at(50.0 * (p + found)), Verdict::Inconclusive);
        }
        // found only (no interval form): never agrees, however small the error
        let m = mikami_within_bound(f::beta_const, None, "beta_const", 1.5);
        assert_eq!(
            (m.verdict, m.evidence.basis, m.evidence.proven_upper),
            (Verdict::Inconclusive, Basis::Found, None)
        );
        // Newton's 40 deg: the 1 % length criterion holds by proof, one level fails by a point
        let m = newton_usable_to_40_deg();
        assert_eq!(
            (m.verdict, m.evidence.basis),
            (Verdict::Partly, Basis::Proven)
        );
        assert!(m.measured.contains("holds (proven)") && m.measured.contains("fails (found)"));
    }
}
