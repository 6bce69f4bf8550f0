//! The claims that bound a scaled method's length error, judged from their row: the row's
//! kernel gives the formula ([`Scale`]: its f64 instantiation for the sweep, its interval one
//! for [`super::parts::length_error`]'s branch-and-bound) and the claim's kind gives the
//! figure and the criterion ([`Kind::Validity`], [`Bound::Length`], [`Bound::TimesSmaller`]).
//! A method whose kernel `prove` does not cover is judged by the sweep alone (basis found,
//! never agrees); one without a scale is left to `shadelab stress` (not checked here). These
//! checks are the rows' own: `shadelab list --json`, bench's claims, proof.json's `claims`
//! and through bench.json the report's claims matrix all call them through
//! [`crate::method::Method::judge`].
use serde::Serialize;

use super::covered;
use super::interval::Interval;
use super::parts::{at_most, length_error, verdict, Part};
use crate::method::checks::{
    edge_error, interior_error_of, judged_elsewhere, length_error_at, Worst, COLOUR_LEVEL_PCT,
    STEPS, VISIBLE_LENGTH_ERROR_PCT,
};
use crate::method::{
    Basis, Bound, Claim, Criteria, Evidence, Form, Kind, Measurement, Method, Quantity, Scale,
    Verdict,
};

/// Claim `c` of row `m`, judged now by its check: the one entry every layer that writes claims
/// goes through (`shadelab list --json`, bench's claims, proof.json's `claims`, the report
/// through bench.json). A [`crate::method::Check::Proof`] claim by the check of its kind; the others by the
/// method layer's check.
pub fn judge(m: &Method, c: &Claim) -> Measurement {
    if let Some(r) = c.judge_without_proof(m) {
        return r;
    }
    match c.kind {
        Kind::Validity { .. } => usable_up_to(m, c),
        Kind::ErrorBound(Bound::Length { .. }) => length_bound(m, c),
        Kind::ErrorBound(Bound::TimesSmaller { .. }) => times_smaller(m, c),
        _ => judged_elsewhere(m, c),
    }
}

/// A claim of a row, judged now: what `shadelab list --json` writes for it.
pub struct Judged<'a> {
    pub method: &'a Method,
    pub claim: &'a Claim,
}

impl serde::Serialize for Judged<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        crate::method::serialize_claim(self.claim.claim, &judge(self.method, self.claim), s)
    }
}

/// The row as `shadelab list --json` writes it: its columns, and its claims judged now.
pub fn json(m: &Method) -> serde_json::Value {
    let mut v = serde_json::to_value(m).expect("a method row serialises");
    let claims: Vec<_> = m
        .claims
        .iter()
        .map(|claim| Judged { method: m, claim })
        .collect();
    v["claims"] = serde_json::to_value(claims).expect("a claim serialises");
    v
}

/// The row's scale and its formula's words, or None for a method that does not scale the
/// normal.
fn scale_of(m: &Method) -> Option<(&Scale, String)> {
    match &m.kernel {
        crate::method::Kernel::Scaled(s) => Some((s, words(s))),
        _ => None,
    }
}

/// The length error of a scale, in words, with its formula's name.
fn words(s: &Scale) -> String {
    let f = s.factor.name();
    match s.form {
        Form::Over => format!("sqrt(z)/s(z) - 1 with s = {f}"),
        Form::Times | Form::Exact => format!("k(z)|N| - 1 with {f}"),
    }
}

/// "usable for angles between vertex normals up to X" ([`Kind::Validity`]) of a scaled
/// method judged by [`Criteria::LengthAndColour`]: both criteria on its length error, by proof
/// where the kernel is provable ([`usable_up_to_of`]). A claim judged by the colour criterion
/// alone is `shadelab stress`'s, on the rendered colour (not checked here: the length error is
/// not that colour).
pub fn usable_up_to(m: &Method, c: &Claim) -> Measurement {
    match (c.kind, scale_of(m)) {
        (
            Kind::Validity {
                up_to_deg,
                criteria: Criteria::LengthAndColour,
            },
            Some((s, name)),
        ) => usable_up_to_of(
            &|z| length_error_at(s, z),
            m.kernel.provable(),
            &name,
            up_to_deg,
        ),
        _ => judged_elsewhere(m, c),
    }
}

/// A scaled method's length error bounded over a range of N.N ([`Bound::Length`]), judged by
/// proof where the kernel is provable ([`length_bound_of`]).
pub fn length_bound(m: &Method, c: &Claim) -> Measurement {
    match (c.kind, scale_of(m)) {
        (Kind::ErrorBound(Bound::Length { at_most, z }), Some((s, name))) => length_bound_of(
            &|z| length_error_at(s, z),
            m.kernel.provable(),
            &name,
            at_most,
            z,
        ),
        _ => judged_elsewhere(m, c),
    }
}

/// "error N times smaller than another method's" ([`Bound::TimesSmaller`]) between scaled
/// methods, judged by proof where both kernels are provable ([`times_smaller_of`]).
pub fn times_smaller(m: &Method, c: &Claim) -> Measurement {
    let Kind::ErrorBound(Bound::TimesSmaller {
        factor,
        than,
        angles_deg,
    }) = c.kind
    else {
        return judged_elsewhere(m, c);
    };
    let scales: Option<Vec<(&str, &Scale, Option<&Scale>)>> = std::iter::once(Ok(m))
        .chain(than.iter().map(|n| crate::method::find(n)))
        .map(|o| {
            let o = o.ok()?;
            Some((o.name, scale_of(o)?.0, o.kernel.provable()))
        })
        .collect();
    let Some(scales) = scales else {
        return judged_elsewhere(m, c);
    };
    let errs: Vec<Box<dyn Fn(f64) -> f64 + '_>> = scales
        .iter()
        .map(|&(_, s, _)| Box::new(move |z| length_error_at(s, z)) as Box<dyn Fn(f64) -> f64>)
        .collect();
    let both: Vec<Both> = scales
        .iter()
        .zip(&errs)
        .map(|(&(n, _, p), e)| (n, &**e, p))
        .collect();
    times_smaller_of(both[0], &both[1..], factor, angles_deg)
}

/// The evidence of a length-error bound: the f64 sweep's worst |error| (`sweep`, a fraction;
/// NaN when a point was non-finite) and, with `proof`, the proven upper bound over `z` and
/// the best real point the proof found. `found` is the larger of the two real values.
pub(crate) fn length_evidence(sweep: f64, proof: Option<&Scale>, z: Interval) -> Evidence {
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

/// A length error `err(z)` (a fraction) as an f64 formula.
pub(crate) type LengthError<'a> = &'a dyn Fn(f64) -> f64;

/// Length error up to `theta` (the edge's z range, inputs rounded to float32) by two named
/// criteria side by side: the length criterion (|error| <= [`VISIBLE_LENGTH_ERROR_PCT`]) and
/// the colour criterion (|error| <= [`COLOUR_LEVEL_PCT`], one 8-bit level, the criterion of
/// `shadelab stress`), each judged by proof ([`at_most`]). Also the sweep at 1.5 theta, to show
/// how fast it grows beyond.
pub(crate) fn usable_up_to_of(
    err: LengthError,
    proof: Option<&Scale>,
    name: &str,
    theta: f64,
) -> Measurement {
    let at = edge_error(err, theta);
    let beyond = edge_error(err, 1.5 * theta).value();
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
            sweep_how(name)
        ),
    }
}

/// The words of an edge sweep of a length error.
fn sweep_how(name: &str) -> String {
    crate::method::checks::sweep_how(name)
}

/// A proven bound in percent, or "not proven".
fn pct_or_none(p: Option<f64>) -> String {
    p.map_or("not proven".into(), |p| format!("{:.4} %", 100.0 * p))
}

/// Worst length error on z in `[lo, hi]` against the claimed `bound` (a fraction), judged by
/// proof (`proof`: the same scale in intervals; None: found only).
pub(crate) fn length_bound_of(
    err: LengthError,
    proof: Option<&Scale>,
    name: &str,
    bound: f64,
    (lo, hi): (f64, f64),
) -> Measurement {
    let ts = (0..=STEPS).map(|i| i as f64 / STEPS as f64);
    let e = Worst::of(ts.map(|t| 100.0 * err(lo + (hi - lo) * t)));
    let at_hi = 100.0 * err(hi);
    let ev = length_evidence(e.value().abs() / 100.0, proof, Interval::new(lo, hi));
    let part = at_most(ev.proven_upper, ev.found.unwrap_or(f64::NAN), bound);
    let bound_pct = 100.0 * bound;
    Measurement {
        measured: format!(
            "max |error| {:.3} % on z in [{lo}, {hi}]{}; {at_hi:+.3} % at z = {hi}; proven <= {}: \
             {}",
            e.finite.abs(),
            e.note(),
            pct_or_none(ev.proven_upper),
            part.word()
        ),
        verdict: verdict(&[part]),
        evidence: ev,
        how: format!(
            "f64 sweep of {name} at {} points of z in [{lo}, {hi}], run when this was written, \
             and the proof over z in [{lo}, {hi}]; the claim (<= {bound_pct} %) {PROOF_RULE}",
            STEPS + 1
        ),
    }
}

/// A scaled method to compare: its name, its length error in f64 and its scale for the proof
/// (None: found only).
pub(crate) type Both<'a> = (&'a str, LengthError<'a>, Option<&'a Scale>);

/// Worst |length error| of `k` and of each of `others` for normals up to each of `angles`
/// apart, on a triangle's edges (z from the edge's proven range) and over its interior (three
/// free normals pairwise theta apart: z from (1 + 2 cos theta)/3,
/// [`super::covered::triangle_z_range`]). Each (angle, region, other) part holds when the
/// other's found / k's proven >= `factor` (proven: the other's true worst is at least its
/// found value, k's at most its proven one), fails when the other's proven / k's found <
/// `factor`, else is undecided; the verdict as [`verdict`]. The evidence is the ratio k's
/// worst / the other's (claimed <= 1/factor): proven_upper the largest k's proven / other's
/// found, found the largest k's found / other's proven over the parts.
pub(crate) fn times_smaller_of(
    k: Both,
    others: &[Both],
    factor: f64,
    angles: &[f64],
) -> Measurement {
    let mut text = Vec::new();
    let mut parts = Vec::new();
    let (mut proven_ratio, mut found_ratio) = (0.0f64, 0.0f64);
    let mut all_proven = k.2.is_some();
    let mut non_finite = false;
    for &theta in angles {
        for (region, interior) in [("edges", false), ("interior", true)] {
            let (sweep, z): (fn(LengthError, f64) -> Worst, Interval) = if interior {
                (interior_error_of, super::covered::triangle_z_range(theta))
            } else {
                (edge_error, super::covered::z_range(theta))
            };
            let w = sweep(k.1, theta);
            let own = length_evidence(w.value().abs() / 100.0, k.2, z);
            let mut part_text = format!(
                "theta <= {theta} deg, {region}: {:.3} %{} (proven {})",
                w.finite.abs(),
                w.note(),
                pct_or_none(own.proven_upper)
            );
            for &(name, other, other_proof) in others {
                all_proven &= other_proof.is_some();
                let lw = sweep(other, theta);
                let o = length_evidence(lw.value().abs() / 100.0, other_proof, z);
                let (of, op) = (
                    o.found.unwrap_or(f64::NAN),
                    o.proven_upper.unwrap_or(f64::INFINITY),
                );
                let (kf, kp) = (
                    own.found.unwrap_or(f64::NAN),
                    own.proven_upper.unwrap_or(f64::INFINITY),
                );
                // the ratio other / k lies in [of / kp, op / kf]
                let (lo, hi) = (of / kp, op / kf);
                let part = if of.is_nan() || kf.is_nan() {
                    non_finite = true;
                    Part::Fails
                } else if lo >= factor {
                    Part::Holds
                } else if hi < factor {
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
    let names: Vec<&str> = others.iter().map(|o| o.0).collect();
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
             (1 + 2 cos theta)/3 to 1); each of (theta <= {angles:?} deg) x (edges, interior) x \
             ({}) holds when the other's found error / {}'s proven >= {factor} (the claimed \
             factor, no rounding), fails when the other's proven / {}'s found < {factor} or a \
             point is non-finite, else undecided; all hold: agrees, all fail: disagrees, any \
             undecided: inconclusive, else partly; any non-finite point disagrees (proof: \
             src/prove); proven_upper and found: {}'s worst / the other's, claimed <= \
             1/{factor}",
            sweep_how("k(z)|N| - 1 of each"),
            names.join(", "),
            k.0,
            k.0,
            k.0
        ),
    }
}

/// One claim as proof.json lists it: the method table's check, with its basis and figures.
#[derive(Debug, Clone, Serialize)]
pub struct ProofClaim {
    pub method: String,
    pub claim: &'static str,
    pub verdict: Verdict,
    pub basis: Basis,
    /// The proven upper bound of the bounded quantity (null: not proven).
    pub proven_upper: Option<f64>,
    /// The largest value of it found at a real point (null: non-finite, or not given).
    pub found: Option<f64>,
    /// The kind and unit of `proven_upper` and `found` (see [`Quantity`]).
    pub quantity: Option<Quantity>,
    pub measured: String,
    pub how: String,
}

/// The claims of `methods` that are bounds over a domain (basis proven or found), as their
/// rows' checks judge them (by proof where the kernel is provable, [`judge`]); a found
/// one says why it is not proven.
pub fn proof_claims(methods: &[&'static Method]) -> Vec<ProofClaim> {
    let mut out = Vec::new();
    for m in methods {
        for c in m.claims {
            let r = judge(m, c);
            let measured = match r.evidence.basis {
                Basis::Measured => continue,
                Basis::Proven => r.measured,
                Basis::Found => format!(
                    "{}; not proven: {}",
                    r.measured,
                    if covered::factor_of(m).is_some() {
                        "the claim's quantity is not a scaling method's length error"
                    } else {
                        covered::out_of_reach(m)
                    }
                ),
            };
            out.push(ProofClaim {
                method: m.name.into(),
                claim: c.claim,
                verdict: r.verdict,
                basis: r.evidence.basis,
                proven_upper: r.evidence.proven_upper,
                found: r.evidence.found,
                quantity: r.evidence.quantity,
                measured,
                how: r.how,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::formulas as f;
    use crate::method::kernel::{formula, Generic};
    use crate::method::{Method, METHODS};

    static ONE: Generic = formula!(f::k_one);
    static EXACT: Generic = formula!(f::k_exact);
    static LYON2: Generic = formula!(f::k_lyon2);
    static SHIFT: Generic = formula!(f::k_lyon_shift);
    static ROMANYUK: Generic = formula!(f::k_romanyuk);
    static MIKAMI: Generic = formula!(f::s_mikami_const);

    fn row(name: &str) -> &'static Method {
        crate::method::find(name).unwrap()
    }

    /// The length error of `k(z) N` in f64, as the rows' checks sweep it.
    fn err(k: fn(f64) -> f64) -> impl Fn(f64) -> f64 {
        move |z| k(z) * z.sqrt() - 1.0
    }

    #[test]
    fn every_proven_claim_of_the_table_is_proven_and_the_others_are_not() {
        let mut proven = 0;
        for m in METHODS {
            for c in m.claims {
                let r = judge(m, c);
                assert_eq!(r.evidence.basis, c.basis, "{}: {}", m.name, c.claim);
                if c.basis == Basis::Proven {
                    assert!(r.evidence.proven_upper.is_some(), "{}: {r:?}", m.name);
                    proven += 1;
                }
            }
        }
        // Newton's 40 deg, Mikami's 1.5 % (3), Romanyuk's 8x
        assert_eq!(proven, 5);
        // their verdicts, those of formulas.md section 3
        let v = |name, i| judge(row(name), &row(name).claims[i]).verdict;
        assert_eq!(v("newton_raphson", 0), Verdict::Partly);
        for m in ["mikami_const", "mikami_linear", "mikami_quadratic"] {
            assert_eq!(v(m, 0), Verdict::Agrees, "{m}");
        }
        assert_eq!(v("romanyuk_poly", 0), Verdict::Partly);
        // teeth: the same claim on a row whose kernel prove does not cover is found only, or
        // left to stress
        let newton = row("newton_raphson");
        let slerp = Method {
            claims: &[],
            ..*row("slerp")
        };
        let c = &newton.claims[0];
        assert_eq!(judge(&slerp, c).verdict, Verdict::NotChecked);
        let exact = row(crate::method::PHONG_EXACT);
        let by_sweep = judge(exact, c);
        assert_eq!(by_sweep.evidence.basis, Basis::Found, "{by_sweep:?}");
    }

    #[test]
    fn newton_by_proof_flips_for_a_factor_that_does_not_normalise() {
        // k = 1 leaves the interpolated normal as it is: cos(20 deg) - 1 = -6.0 % at 40 deg.
        let one = Scale::times(&ONE);
        let m = usable_up_to_of(&err(f::k_one), Some(&one), "k = 1", 40.0);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert!(m.measured.contains("-6.031 %"), "{m:?}");
        // Newton at 40 deg: -0.535 % holds the 1 % length criterion, fails 1/255 = 0.392 %.
        let newton = row("newton_raphson");
        let m = judge(newton, &newton.claims[0]);
        assert!(
            m.measured.contains("-0.535 %")
                && m.measured.contains("length criterion (<= 1 %) holds")
                && m.measured
                    .contains("colour criterion (<= 1/255 = 0.392 %) fails"),
            "{m:?}"
        );
        assert_eq!(
            (m.verdict, m.evidence.basis),
            (Verdict::Partly, Basis::Proven)
        );
        // the exact factor holds both
        let exact = Scale::times(&EXACT);
        let m = usable_up_to_of(&err(f::k_exact), Some(&exact), "exact", 40.0);
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
        // a claim by the colour criterion alone is stress's, on the rendered colour
        let r = row("romanyuk_poly");
        assert_eq!(judge(r, &r.claims[1]).verdict, Verdict::NotChecked);
    }

    #[test]
    fn a_non_finite_point_disagrees_with_or_without_the_proof() {
        let nan = |_: f64| f64::NAN;
        let (lyon2, shift) = (err(f::k_lyon2), err(f::k_lyon_shift));
        let romanyuk = err(f::k_romanyuk);
        let (sl, ss, sr) = (
            Scale::times(&LYON2),
            Scale::times(&SHIFT),
            Scale::times(&ROMANYUK),
        );
        let angles = [90.0, 60.0, 40.0];
        for m in [
            usable_up_to_of(&nan, None, "NaN", 40.0),
            length_bound_of(&nan, None, "NaN", 0.015, (0.25, 1.0)),
            times_smaller_of(
                ("NaN", &nan, None),
                &[("a", &lyon2, None), ("b", &shift, None)],
                8.0,
                &angles,
            ),
            times_smaller_of(
                ("romanyuk", &romanyuk, Some(&sr)),
                &[("a", &nan, None), ("b", &shift, Some(&ss))],
                8.0,
                &angles,
            ),
        ] {
            assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
            assert!(m.measured.contains("points non-finite)"), "{m:?}");
            assert_eq!(m.evidence.found, None, "{m:?}");
        }
        let _ = sl;
    }

    #[test]
    fn the_8x_claim_by_proof_needs_the_full_factor() {
        // A factor exactly 7.9x better than Lyon's 2nd degree everywhere: short of 8.
        fn k79<T: crate::method::real::Real>(z: T) -> T {
            (T::c(1.0) + (f::k_lyon2(z) * z.sqrt() - T::c(1.0)) / T::c(7.9)) / z.sqrt()
        }
        static K79: Generic = formula!(k79);
        let (s79, lyon) = (Scale::times(&K79), Scale::times(&LYON2));
        let (e79, e2) = (err(k79::<f64>), err(f::k_lyon2));
        let angles = [90.0, 60.0, 40.0];
        let m = times_smaller_of(
            ("k79", &e79, Some(&s79)),
            &[("a", &e2, Some(&lyon)), ("b", &e2, Some(&lyon))],
            8.0,
            &angles,
        );
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        assert_eq!(m.evidence.basis, Basis::Proven, "{m:?}");
        // without the proofs the found ratio 7.9 cannot decide (Lyon's true worst may be
        // larger than its found one): inconclusive, basis found
        let m = times_smaller_of(
            ("k79", &e79, None),
            &[("a", &e2, None), ("b", &e2, None)],
            8.0,
            &angles,
        );
        assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
        assert_eq!(m.evidence.basis, Basis::Found, "{m:?}");
        // Lyon against itself is 1x, never 8x, proven
        let shift = Scale::times(&SHIFT);
        let es = err(f::k_lyon_shift);
        let m = times_smaller_of(
            ("lyon", &e2, Some(&lyon)),
            &[("a", &e2, Some(&lyon)), ("b", &es, Some(&shift))],
            8.0,
            &angles,
        );
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        // the row's claim names the rows it compares with, at the row's angles
        let r = row("romanyuk_poly");
        let m = judge(r, &r.claims[0]);
        assert!(m.measured.contains("theta <= 40 deg, edges"), "{m:?}");
        assert!(m.measured.contains("interior"), "{m:?}");
        assert!(m.measured.contains("vs lyon_shift"), "{m:?}");
        // its figures are ratios of two errors, not errors, and say so (issue 39 item 7)
        assert_eq!(m.evidence.quantity, Some(Quantity::ErrorRatio));
        assert!(m.evidence.found.unwrap() > 1.0, "{m:?}");
    }

    #[test]
    fn a_proven_claim_flips_with_its_figure_between_found_and_proven() {
        let k = Scale::over(&MIKAMI);
        let e = |z: f64| z.sqrt() / f::s_mikami_const(z) - 1.0;
        let m = length_bound_of(&e, Some(&k), "mikami", 0.015, (0.25, 1.0));
        assert_eq!(
            (m.verdict, m.evidence.basis),
            (Verdict::Agrees, Basis::Proven)
        );
        let (p, found) = (m.evidence.proven_upper.unwrap(), m.evidence.found.unwrap());
        assert!(found <= p && p <= found * 1.001 + 1e-12, "{m:?}");
        // the claim tightened to the proven bound still holds; below the found value it is
        // contradicted by a real point; between the two the proof cannot decide
        let at = |b: f64| length_bound_of(&e, Some(&k), "mikami", b, (0.25, 1.0)).verdict;
        assert_eq!(at(p), Verdict::Agrees);
        assert_eq!(at(found * 0.999), Verdict::Disagrees);
        if p > found {
            assert_eq!(at(0.5 * (p + found)), Verdict::Inconclusive);
        }
        // found only (no interval form): never agrees, however small the error
        let m = length_bound_of(&e, None, "mikami", 0.015, (0.25, 1.0));
        assert_eq!(
            (m.verdict, m.evidence.basis, m.evidence.proven_upper),
            (Verdict::Inconclusive, Basis::Found, None)
        );
        // a wrong beta: beta = 0 keeps the start value s0 = 2/3 z + 0.35: -3.2 % at z = 0.25
        let zero = |z: f64| z.sqrt() / f::mikami_sqrt(z, 0.0) - 1.0;
        let m = length_bound_of(&zero, None, "beta = 0", 0.015, (0.25, 1.0));
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        // the row's figure and range are the claim's
        let mk = row("mikami_const");
        let m = judge(mk, &mk.claims[0]);
        assert!(
            m.measured.contains("on z in [0.25, 1]") && m.how.contains("(<= 1.5 %)"),
            "{m:?}"
        );
    }

    #[test]
    fn serialised_claims_carry_the_measurement_their_check_makes_now() {
        for m in METHODS {
            let jm = json(m);
            let claims = jm["claims"].as_array().unwrap();
            assert_eq!(claims.len(), m.claims.len(), "{}", m.name);
            for (c, jc) in m.claims.iter().zip(claims) {
                let now = judge(m, c);
                // the row says how the claim is judged, and its check judges it so
                assert_eq!(now.evidence.basis, c.basis, "{}: {}", m.name, c.claim);
                let keys: Vec<&str> = jc.as_object().unwrap().keys().map(|k| k.as_str()).collect();
                assert_eq!(keys.len(), 8, "{jc}");
                assert_eq!(jc["claim"], c.claim);
                assert_eq!(jc["measured"], now.measured.as_str());
                assert_eq!(jc["verdict"], now.verdict.as_str());
                assert_eq!(jc["basis"], now.evidence.basis.as_str());
                assert_eq!(jc["proven_upper"].as_f64(), now.evidence.proven_upper);
                assert_eq!(jc["found"].as_f64(), now.evidence.found);
                // a bound's figures name their kind and unit; a measured claim has none
                let quantity = now.evidence.quantity.map(|q| q.as_str());
                assert_eq!(jc["quantity"].as_str(), quantity, "{jc}");
                assert_eq!(
                    quantity.is_some(),
                    now.evidence.basis != crate::method::Basis::Measured,
                    "{jc}"
                );
                assert_eq!(jc["how"], now.how.as_str());
                assert!(!now.how.is_empty(), "{}: {}", m.name, c.claim);
            }
        }
    }
}
