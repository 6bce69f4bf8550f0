//! The papers' claims that are bounds, judged by proof where the method is covered: a claim
//! holds by proof when the proven upper bound is within it, fails by a found point when a real
//! (replayable) point exceeds it; `basis` says which decided. Claims on methods out of reach
//! are listed as not checked, with the reason. (The f64-sweep verdicts of
//! `crate::method::checks` stay as they are; this list stands beside them.)
use serde::Serialize;

use super::covered::{self, Metric};
use super::{prove_metric, ProveOptions};
use crate::method::{self, Method, Verdict};

/// One claim judged by proof.
#[derive(Debug, Clone, Serialize)]
pub struct ProofClaim {
    pub method: String,
    pub claim: &'static str,
    /// "proven" (every part decided by a proven bound), "found" (by real points), "proven and
    /// found" (mixed), "none" (undecided or not checked).
    pub basis: &'static str,
    pub verdict: Verdict,
    pub measured: String,
    pub how: String,
}

/// A part of a claim: holds by proof, fails by a found point, or undecided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    HoldsProven,
    FailsFound,
    FailsProven,
    Undecided,
}

/// "the error is at most `bound`" against a proven upper and a found lower bound.
fn at_most(proven: f64, found: f64, bound: f64) -> Part {
    if proven <= bound {
        Part::HoldsProven
    } else if found > bound {
        Part::FailsFound
    } else {
        Part::Undecided
    }
}

fn verdict(parts: &[Part]) -> (Verdict, &'static str) {
    let holds = parts.iter().filter(|&&p| p == Part::HoldsProven).count();
    let by_found = parts.iter().filter(|&&p| p == Part::FailsFound).count();
    let fails = by_found + parts.iter().filter(|&&p| p == Part::FailsProven).count();
    let verdict = if parts.contains(&Part::Undecided) {
        Verdict::Inconclusive
    } else if holds == parts.len() {
        Verdict::Agrees
    } else if fails == parts.len() {
        Verdict::Disagrees
    } else {
        Verdict::Partly
    };
    let basis = if verdict == Verdict::Inconclusive {
        "none"
    } else if by_found == 0 {
        "proven"
    } else if by_found == parts.len() {
        "found"
    } else {
        "proven and found"
    };
    (verdict, basis)
}

fn word(p: Part) -> &'static str {
    match p {
        Part::HoldsProven => "holds (proven)",
        Part::FailsFound => "fails (found)",
        Part::FailsProven => "fails (proven)",
        Part::Undecided => "undecided",
    }
}

/// The length error's (proven, found) of `name` up to `theta`.
fn length(name: &str, theta: f64, opts: &ProveOptions) -> Option<(f64, f64)> {
    let m = method::find(name).ok()?;
    let k = covered::factor_of(name)?;
    let o = prove_metric(m, k, Metric::Length, theta, opts);
    Some((o.proven_upper, o.found))
}

fn mikami(name: &str, opts: &ProveOptions) -> Option<ProofClaim> {
    // z = N.N in [0.25, 1], the claim's range: the edge of normals up to 120 degrees apart.
    let (proven, found) = length(name, 120.0, opts)?;
    let part = at_most(proven, found, 0.015);
    let (verdict, basis) = verdict(&[part]);
    Some(ProofClaim {
        method: name.into(),
        claim: "maximum normalised relative error <= 1.5 % (S000 l.74)",
        basis,
        verdict,
        measured: format!(
            "| |N'| - 1 | proven <= {proven:.6}, found {found:.6} over normals up to 120 deg \
             apart (z in [0.25, 1]): {}",
            word(part)
        ),
        how: "shadelab prove: interval branch-and-bound of the length error, domain theta <= \
              120 deg; agrees when the proven bound <= 0.015, disagrees when a found point > \
              0.015"
            .into(),
    })
}

fn newton(opts: &ProveOptions) -> Option<ProofClaim> {
    let (proven, found) = length("newton_raphson", 40.0, opts)?;
    let parts = [
        at_most(proven, found, 0.01),
        at_most(proven, found, 1.0 / 255.0),
    ];
    let (verdict, basis) = verdict(&parts);
    Some(ProofClaim {
        method: "newton_raphson".into(),
        claim: "usable for angles between vertex normals up to 40 degrees (S000 l.35)",
        basis,
        verdict,
        measured: format!(
            "| |N'| - 1 | proven <= {proven:.6}, found {found:.6} up to 40 deg; length criterion \
             (<= 0.01) {}, colour criterion (<= 1/255) {}",
            word(parts[0]),
            word(parts[1])
        ),
        how: "shadelab prove, theta <= 40 deg; the two criteria of method::checks (1 % length, \
              one 8-bit level of a full diffuse term)"
            .into(),
    })
}

fn romanyuk(opts: &ProveOptions) -> Option<ProofClaim> {
    let mut parts = Vec::new();
    let mut text = Vec::new();
    for theta in [90.0, 60.0, 40.0] {
        let (rp, rf) = length("romanyuk_poly", theta, opts)?;
        for lyon in ["lyon_taylor", "lyon_shift"] {
            let (lp, lf) = length(lyon, theta, opts)?;
            let part = if lf >= 8.0 * rp {
                Part::HoldsProven
            } else if lp < 8.0 * rf {
                Part::FailsProven
            } else {
                Part::Undecided
            };
            text.push(format!(
                "{theta} deg vs {lyon}: ratio in [{:.2}, {:.2}] {}",
                lf / rp,
                lp / rf,
                word(part)
            ));
            parts.push(part);
        }
    }
    let (verdict, basis) = verdict(&parts);
    Some(ProofClaim {
        method: "romanyuk_poly".into(),
        claim: "relative error 8x smaller than Lyon's approach (S000 l.79-80)",
        basis,
        verdict,
        measured: text.join("; "),
        how: "shadelab prove: the ratio of the worst length errors lies between Lyon's found / \
              Romanyuk's proven and Lyon's proven / Romanyuk's found; holds when the lower end \
              >= 8, fails when the upper end < 8"
            .into(),
    })
}

fn not_checked(m: &Method, claim: &'static str) -> ProofClaim {
    ProofClaim {
        method: m.name.into(),
        claim,
        basis: "none",
        verdict: Verdict::NotChecked,
        measured: format!("out of reach: {}", covered::out_of_reach(m)),
        how: "shadelab prove covers only the methods that scale the interpolated normal".into(),
    }
}

/// The claims of `methods` that are bounds.
pub fn judge(methods: &[&'static Method], opts: &ProveOptions) -> Vec<ProofClaim> {
    let mut out = Vec::new();
    for m in methods {
        let claim = match m.name {
            "mikami_const" | "mikami_linear" | "mikami_quadratic" => mikami(m.name, opts),
            "newton_raphson" => newton(opts),
            "romanyuk_poly" => romanyuk(opts),
            "segments_k1" | "segments_k2" | "segments_k3" => Some(not_checked(
                m,
                "specular error within 1 - cos^n(theta/2) for end normals 4 deg apart (S002)",
            )),
            "barycentric_quadratic" => Some(not_checked(
                m,
                "the M_ij polynomial's error figures for vertex normals up to 90 deg apart",
            )),
            "dichotomy_poly1" | "dichotomy_poly2" => Some(not_checked(
                m,
                "the inverse-root polynomial's error figures for phi <= 45 deg per halving",
            )),
            _ => None,
        };
        out.extend(claim);
    }
    out
}
