//! The answer per cost model: the cheapest candidate that is proven within the budget (in the
//! model's precision) and that the model measured cheaper than phong_exact, or the statement
//! that none is, with the candidate that came closest. A candidate enters only by proof: its
//! sampled error (the pixels' z) is shown beside, never consulted.
use serde::Serialize;

use super::candidate::{Candidate, Family};
use super::proof::Bound;
use crate::cost::{verdict_words, CostModel, CostModelId};
use crate::method::Precision;
use crate::method::Verdict;

/// One candidate with what was proven and measured about it.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    #[serde(flatten)]
    pub candidate: Candidate,
    /// One per precision (float32, float16).
    pub bounds: Vec<Bound>,
    /// The real formula's largest length error over the covered pixels' z (sampled; null
    /// without pixels).
    pub sampled_length_error: Option<f64>,
    /// Its method file, relative to the output folder (null for a paper's: the table's, and
    /// for a candidate not costed).
    pub file: Option<String>,
    /// Why the candidate was measured by no cost model (its program not proven on the
    /// domain); absent when it was costed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_costed: Option<String>,
    /// The precisions in which it is not proven within the budget on the mesh's domain nor
    /// (its form) on any class's: no model of those precisions costed it, for none could
    /// answer with it. Absent when empty.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub outside_budget_in: Vec<Precision>,
    /// Per cost model: its ratio to phong_exact and the verdict of "cheaper".
    pub costs: Vec<RowCost>,
}

/// A candidate's figure under one cost model.
#[derive(Debug, Clone, Serialize)]
pub struct RowCost {
    pub model: CostModelId,
    pub ratio: Option<f64>,
    /// Written as its words: cheaper, not cheaper, inconclusive, unmeasured.
    #[serde(serialize_with = "crate::cost::as_words")]
    pub verdict: Verdict,
}

impl Row {
    /// The bound in `p`.
    pub fn bound(&self, p: Precision) -> Option<&Bound> {
        self.bounds.iter().find(|b| b.precision == p)
    }
}

/// A candidate as an answer names it.
#[derive(Debug, Clone, Serialize)]
pub struct Pick {
    pub candidate: String,
    pub label: String,
    pub ratio: Option<f64>,
    /// Written as its words ([`verdict_words`]).
    #[serde(serialize_with = "crate::cost::as_words")]
    pub verdict: Verdict,
    /// The proven colour bound in the model's precision (null: not provable).
    pub colour_bound: Option<f64>,
    pub within_budget: bool,
}

/// The answer under one cost model.
#[derive(Debug, Clone, Serialize)]
pub struct Answer {
    pub model: CostModelId,
    pub title: String,
    pub precision: Precision,
    /// Why the model has no figures (it could not be measured), else null.
    pub error: Option<String>,
    /// The cheapest candidate proven within the budget and cheaper than phong_exact.
    pub cheapest: Option<Pick>,
    /// When none is: the cheapest proven within the budget, else the most accurate of those
    /// measured cheaper.
    pub closest: Option<Pick>,
    /// The answer in words.
    pub statement: String,
}

fn pick(r: &Row, m: &CostModel, budget: f64) -> Pick {
    let f = m.figure(&r.candidate.id);
    let b = r.bound(m.precision);
    Pick {
        candidate: r.candidate.id.clone(),
        label: r.candidate.label(),
        ratio: f.and_then(|f| f.ratio),
        verdict: f.map_or(Verdict::NotChecked, |f| f.verdict),
        colour_bound: b.and_then(|b| b.colour),
        within_budget: b.is_some_and(|b| b.within(budget)),
    }
}

fn ratio_key(p: &Pick) -> f64 {
    p.ratio.unwrap_or(f64::INFINITY)
}

/// The answer of model `m` over `rows` at `budget`.
pub fn answer(rows: &[Row], m: &CostModel, budget: f64) -> Answer {
    // phong_exact is the yardstick, never an answer
    let picks: Vec<Pick> = rows
        .iter()
        .filter(|r| r.candidate.family != Family::Reference)
        .map(|r| pick(r, m, budget))
        .collect();
    let cheaper = |p: &&Pick| m.figure(&p.candidate).is_some_and(|f| f.cheaper());
    let best = picks
        .iter()
        .filter(|p| p.within_budget)
        .filter(cheaper)
        .min_by(|a, b| ratio_key(a).total_cmp(&ratio_key(b)))
        .cloned();
    let (closest, statement) = match &best {
        Some(p) => (
            None,
            format!(
                "{} ({}): proven colour error {} within the budget, {} than phong_exact (ratio {})",
                p.candidate,
                p.label,
                num(p.colour_bound),
                verdict_words(p.verdict),
                num(p.ratio)
            ),
        ),
        None => {
            let within = picks
                .iter()
                .filter(|p| p.within_budget)
                .min_by(|a, b| ratio_key(a).total_cmp(&ratio_key(b)));
            let accurate = picks.iter().filter(cheaper).min_by(|a, b| {
                let k = |p: &Pick| p.colour_bound.unwrap_or(f64::INFINITY);
                k(a).total_cmp(&k(b))
            });
            let closest = within.or(accurate).cloned();
            let why = match (&closest, within.is_some()) {
                (Some(c), true) => format!(
                    "; closest: {} ({}), proven within the budget but {} (ratio {})",
                    c.candidate,
                    c.label,
                    verdict_words(c.verdict),
                    num(c.ratio)
                ),
                (Some(c), false) => format!(
                    "; closest: {} ({}), cheaper (ratio {}) but its proven colour error {} \
                     exceeds the budget",
                    c.candidate,
                    c.label,
                    num(c.ratio),
                    num(c.colour_bound)
                ),
                (None, _) => String::new(),
            };
            (
                closest,
                format!("none is cheaper than phong_exact within the budget{why}"),
            )
        }
    };
    Answer {
        model: m.id.clone(),
        title: m.title.clone(),
        precision: m.precision,
        error: None,
        cheapest: best,
        closest,
        statement,
    }
}

/// The answer of a model that could not be measured (`why`).
pub fn unmeasured(id: &CostModelId, why: &str) -> Answer {
    Answer {
        model: id.clone(),
        title: id.to_string(),
        precision: id.precision(),
        error: Some(why.to_string()),
        cheapest: None,
        closest: None,
        statement: format!("not measured: {why}"),
    }
}

/// A figure in an answer's words (`n/a` when absent; small ones in scientific notation).
pub fn num(x: Option<f64>) -> String {
    match x {
        None => "n/a".into(),
        Some(v) if v == 0.0 || v.abs() >= 1e-2 => format!("{v:.4}"),
        Some(v) => format!("{v:.3e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::{CostFigure, CostKind, CostModelId, Measure};
    use crate::method::Verdict;
    use crate::prove::interval::Interval;
    use crate::tune::proof::{prove, sampled_length_error, Lights, ProofEffort};

    fn model(ratios: &[(&str, f64)]) -> CostModel {
        CostModel {
            id: CostModelId::of("lavapipe_isolated"),
            title: "t".into(),
            kind: CostKind::Static,
            measure: Measure {
                statistic: "s".into(),
                unit: "u".into(),
            },
            description: String::new(),
            precision: Precision::F32,
            figures: ratios
                .iter()
                .map(|&(m, r)| CostFigure {
                    method: m.into(),
                    value: Some(r),
                    ratio: Some(r),
                    ci95_low: None,
                    ci95_high: None,
                    verdict: crate::cost::rule::static_cheaper(Some(r)),
                    evidence: String::new(),
                    note: String::new(),
                })
                .collect(),
            pairs: Vec::new(),
        }
    }

    fn row(c: Candidate, z: Interval, pixels: &[f64]) -> Row {
        let lights = Lights {
            colours: vec![[1.0; 3]],
            diffuse: [0.75, 0.55, 0.35],
            specular: [0.5; 3],
            shininess: 50.0,
        };
        let b = prove(&c, Precision::F32, z, &lights, &ProofEffort::default());
        Row {
            sampled_length_error: Some(sampled_length_error(&c, pixels.iter().copied())),
            candidate: c,
            bounds: vec![b],
            file: None,
            not_costed: None,
            outside_budget_in: Vec::new(),
            costs: Vec::new(),
        }
    }

    /// Teeth: a candidate fitted to the pixels' z (what sampling sees) is within the budget by
    /// its sampled error but not by its proof over the mesh's domain; it is the cheapest, and
    /// it is never chosen. The proven one is, and without it the answer says none is.
    #[test]
    fn a_candidate_over_the_budget_by_proof_is_never_chosen() {
        let budget = 1.0 / 255.0;
        let domain = Interval::new(0.5, 1.0);
        let pixels: Vec<f64> = (0..=1000)
            .map(|i| 0.97 + 0.03 * f64::from(i) / 1000.0)
            .collect();
        let sampled = row(
            Candidate::minimax("fits_pixels".into(), 1, 0.97, 1.0).unwrap(),
            domain,
            &pixels,
        );
        let proven = row(
            Candidate::minimax("fits_domain".into(), 4, 0.5, 1.0).unwrap(),
            domain,
            &pixels,
        );
        // the premise: sampled within the budget (through the same slope), proven not
        let e = sampled.sampled_length_error.unwrap();
        let lights_slope = 0.75 + 0.5 * 50.0 * 1.01;
        assert!(e * lights_slope < budget, "{e}");
        assert!(!sampled.bounds[0].within(budget), "{:?}", sampled.bounds[0]);
        assert!(proven.bounds[0].within(budget), "{:?}", proven.bounds[0]);
        let m = model(&[("fits_pixels", 0.5), ("fits_domain", 0.9)]);
        let a = answer(&[sampled.clone(), proven], &m, budget);
        assert_eq!(a.cheapest.unwrap().candidate, "fits_domain");
        let a = answer(&[sampled], &m, budget);
        assert!(a.cheapest.is_none());
        assert!(
            a.statement.starts_with("none is cheaper than phong_exact"),
            "{}",
            a.statement
        );
        assert_eq!(a.closest.unwrap().candidate, "fits_pixels");
    }

    /// Within the budget but not cheaper is not an answer either; the closest is named.
    #[test]
    fn within_the_budget_but_dearer_is_none() {
        let domain = Interval::new(0.5, 1.0);
        let r = row(
            Candidate::minimax("m4".into(), 4, 0.5, 1.0).unwrap(),
            domain,
            &[],
        );
        let m = model(&[("m4", 1.1)]);
        let a = answer(&[r], &m, 1.0 / 255.0);
        assert!(a.cheapest.is_none() && a.closest.as_ref().unwrap().within_budget);
        assert!(a.statement.contains("closest: m4"), "{}", a.statement);
        assert_eq!(m.figures[0].verdict, Verdict::Disagrees);
    }

    /// phong_exact's own row (the reference, proven within the budget, ratio 1) is the
    /// yardstick: never the answer, nor the closest, even when it is the least dear.
    #[test]
    fn the_reference_is_never_the_answer() {
        let domain = Interval::new(0.5, 1.0);
        let m4 = row(
            Candidate::minimax("m4".into(), 4, 0.5, 1.0).unwrap(),
            domain,
            &[],
        );
        let exact = row(Candidate::reference(), domain, &[]);
        assert!(exact.bounds[0].within(1.0 / 255.0), "{:?}", exact.bounds[0]);
        let m = model(&[("m4", 1.1), (crate::method::PHONG_EXACT, 1.0)]);
        let a = answer(&[exact, m4], &m, 1.0 / 255.0);
        assert!(a.cheapest.is_none(), "{a:?}");
        assert_eq!(a.closest.unwrap().candidate, "m4");
    }
}
