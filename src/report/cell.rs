//! One cell of the answer ([`Cell`]: an error budget under a cost model) as answer.json
//! writes it: the method chosen and the runner-up ([`Choice`]), the scene that decides it
//! ([`Binding`]), the methods this run does not tell from the answer, and tune's winner.
use serde::{Deserialize, Serialize};

use super::budget::Budget;
use super::tuned::TunedWin;
use crate::cost::CostModelId;
use crate::method::Verdict;

/// A method chosen for a cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Choice {
    pub method: String,
    pub ratio: Option<f64>,
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    /// The verdict of "cheaper than phong_exact" under the cell's model.
    pub verdict: Verdict,
    /// Its worst error under the budget's metric over the scenes.
    pub worst_error: Option<f64>,
    pub cost_evidence: String,
    pub error_evidence: String,
}

/// One cell: a budget under a cost model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    #[serde(with = "super::budget::as_id")]
    pub budget: Budget,
    pub cost_model: CostModelId,
    /// The cheapest qualifying method measured cheaper than phong_exact, or phong_exact.
    pub answer: Choice,
    pub runner_up: Option<Choice>,
    pub nothing_cheaper: bool,
    /// Methods meeting the budget on every scene (phong_exact included).
    pub qualifying: usize,
    /// Whether the answer's interval lies wholly below the runner-up's (an interval model;
    /// static: the figures differ). False: the two are not told apart by this measurement.
    pub separated: bool,
    /// The scene that decides the cell, when a method this model measures cheaper than the
    /// answer fails the budget: the scene ruling out the most of them.
    pub binding: Option<Binding>,
    /// Interval models: the methods within the budget whose interval does not tell them from
    /// the answer (neither measured cheaper nor dearer, yet possibly cheaper): the cell is
    /// unresolved by this run, and its text says what would resolve it. Empty: resolved.
    #[serde(default)]
    pub unresolved: Vec<String>,
    /// A tuned approximation (`shadelab tune`) proven within the budget and cheaper than
    /// phong_exact under the cell's model, when the report read tune's findings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tuned: Option<TunedWin>,
    /// The cell as one sentence.
    pub text: String,
}

/// The scene that keeps cheaper methods out of a cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Binding {
    pub scene: String,
    /// Methods cheaper than the answer (under the cell's model) that fail the budget on it.
    pub ruled_out: usize,
    /// Methods cheaper than the answer that fail the budget on some scene.
    pub cheaper_failing: usize,
    /// The cheapest of those it rules out, and its error there.
    pub cheapest: String,
    pub evidence: String,
}

impl Choice {
    /// Whether the cell's model measured it cheaper than phong_exact.
    pub fn cheaper(&self) -> bool {
        self.verdict == Verdict::Agrees
    }

    /// Its verdict in the words of a cost.
    pub fn verdict_words(&self) -> &'static str {
        crate::cost::verdict_words(self.verdict)
    }
}

/// A ratio for a cell's text: `0.873 [0.85, 0.90]` or `0.873`.
pub fn ratio_text(c: &Choice) -> String {
    let r = c.ratio.map_or("unmeasured".into(), |r| format!("{r:.3}"));
    match (c.ci95_low, c.ci95_high) {
        (Some(l), Some(h)) => format!("{r} [{l:.3}, {h:.3}]"),
        _ => r,
    }
}
