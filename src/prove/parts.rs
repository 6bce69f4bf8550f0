//! The parts of a bound and their verdict: [`length_error`] proves an upper bound of a scaling
//! method's length error over a range of N.N (and finds the best real point), and [`at_most`] /
//! [`verdict`] turn a proven upper and a found value into a verdict: a part holds only when the
//! proven upper bound is within the bound, fails when a found (real) point exceeds it, and is
//! undecided otherwise. The rows' bound checks ([`super::bounds`]) use them, so `shadelab list
//! --json`, bench.json's claims and proof.json's `claims` carry one verdict each, with its
//! basis (proven, found, measured).
use super::bnb::{self, Effort, Outcome};
use super::covered;
use super::interval::Interval;
use crate::method::real::Real;
use crate::method::Scale;
use crate::method::Verdict;

/// The effort of a claim's proof: tighter than the report's 1 % (one dimension is cheap).
const CLAIM_EFFORT: Effort = Effort {
    tolerance: 1e-3,
    atol: bnb::ATOL,
    max_boxes: 100_000,
    max_seconds: 5.0,
};

/// `| k(z) sqrt(z) - 1 |` at the real point `z`, as a lower bound of its true value (the
/// interval's smallest magnitude at the point); NaN when the formula is not finite there.
fn length_error_at(k: &Scale, z: f64) -> f64 {
    let one = Interval::point(1.0);
    let zi = Interval::point(z);
    let e = k.k(zi) * zi.sqrt() - one;
    if !(e.lo.is_finite() && e.hi.is_finite()) {
        f64::NAN
    } else if e.lo > 0.0 {
        e.lo
    } else if e.hi < 0.0 {
        -e.hi
    } else {
        0.0
    }
}

/// Branch-and-bound of the length error `| k(z) sqrt(z) - 1 |` over `z`: `proven_upper` holds
/// for every real z in it, `found` is reached at a real z (`found_at[0]`).
pub fn length_error(k: &Scale, z: Interval) -> Outcome {
    let point = Interval::point(0.0);
    bnb::maximise(
        [z, point, point],
        CLAIM_EFFORT,
        |c| covered::upper(k, covered::Metric::Length, c[0]),
        |p| Some(length_error_at(k, p[0])),
    )
}

/// One part of a claim against a proven upper and a found lower bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// The proven upper bound supports the claim.
    Holds,
    /// A real point contradicts it (or a real point gave a non-finite value).
    Fails,
    /// Neither: the claimed figure lies between the found value and the proven bound.
    Undecided,
}

impl Part {
    pub fn word(self) -> &'static str {
        match self {
            Part::Holds => "holds (proven)",
            Part::Fails => "fails (found)",
            Part::Undecided => "undecided (between found and proven)",
        }
    }
}

/// "the quantity is at most `bound`": holds when `proven <= bound`, fails when `found > bound`
/// or `found` is NaN (a non-finite point), else undecided. `proven` None: not provable.
pub fn at_most(proven: Option<f64>, found: f64, bound: f64) -> Part {
    if found.is_nan() {
        Part::Fails
    } else if proven.is_some_and(|p| p <= bound) {
        Part::Holds
    } else if found > bound {
        Part::Fails
    } else {
        Part::Undecided
    }
}

/// The claim's verdict from its parts: every part holds: agrees; every part fails: disagrees;
/// any part undecided: inconclusive; else (some hold, some fail) partly.
pub fn verdict(parts: &[Part]) -> Verdict {
    if parts.iter().all(|&p| p == Part::Holds) {
        Verdict::Agrees
    } else if parts.iter().all(|&p| p == Part::Fails) {
        Verdict::Disagrees
    } else if parts.contains(&Part::Undecided) {
        Verdict::Inconclusive
    } else {
        Verdict::Partly
    }
}
