//! What `shadelab tune` found, as an input of the answer (`report --tuned DIR/tune.json`): per
//! cost model, the cheapest tuned approximation of the inverse square root that tune proved
//! within its budget and that the model measured cheaper than phong_exact. It does not depend
//! on where the cost models come from: a cell of the answer shows "a tuned approximation beats
//! exact normalisation here" when tune's budget is within the cell's and tune names a winner
//! for the cell's cost model ([`Tuned::win`]).
//!
//! tune.json is read for the fields named here only (`budget`, and per entry of
//! `cost_models`: `model` and `cheapest` with `candidate`, `label`, `ratio`, `colour_bound`),
//! so the rest of its schema (docs/tune.schema.json, on the tune branch) may grow freely.
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::budget::Budget;
use super::models::describe;
use crate::auto::ErrorBudget;
use crate::cost::{CostModel, CostModelId};
use crate::error::{Error, Result};

/// A tuned candidate that beats exact normalisation under one cost model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TunedWin {
    pub cost_model: CostModelId,
    pub candidate: String,
    /// Its form ("minimax degree 2", ...).
    pub label: String,
    /// Its cost over phong_exact's under the model.
    pub ratio: Option<f64>,
    /// Its proven colour error bound.
    pub proven_error: Option<f64>,
}

/// tune's findings (answer.json `summary.tuned`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tuned {
    /// tune.json, relative to the report's folder (copied there).
    pub evidence: String,
    /// The colour error every win is proven within (linear; a bound of the largest channel
    /// error, hence of the luminance error too).
    pub budget: ErrorBudget,
    pub wins: Vec<TunedWin>,
    /// The cost models tune looked at and found no winner for.
    pub none: Vec<CostModelId>,
}

#[derive(Deserialize)]
struct File {
    budget: f64,
    #[serde(default)]
    cost_models: Vec<FileModel>,
}

#[derive(Deserialize)]
struct FileModel {
    model: CostModelId,
    #[serde(default)]
    cheapest: Option<FilePick>,
}

#[derive(Deserialize)]
struct FilePick {
    candidate: String,
    #[serde(default)]
    label: String,
    #[serde(default)]
    ratio: Option<f64>,
    #[serde(default)]
    colour_bound: Option<f64>,
}

impl Tuned {
    /// Reads tune.json's findings from `text` (`evidence`: where the report keeps its copy).
    pub fn parse(text: &str, evidence: &str, path: &Path) -> Result<Tuned> {
        let f: File = serde_json::from_str(text)
            .map_err(|e| Error::input(path, None, format!("not a tune.json: {e}")))?;
        let budget = ErrorBudget::new(f.budget).map_err(|_| {
            Error::input(
                path,
                None,
                format!("tune.json budget {} is not a positive number", f.budget),
            )
        })?;
        let mut t = Tuned {
            evidence: evidence.into(),
            budget,
            wins: Vec::new(),
            none: Vec::new(),
        };
        for m in f.cost_models {
            match m.cheapest {
                Some(p) => t.wins.push(TunedWin {
                    cost_model: m.model,
                    candidate: p.candidate,
                    label: p.label,
                    ratio: p.ratio,
                    proven_error: p.colour_bound,
                }),
                None => t.none.push(m.model),
            }
        }
        Ok(t)
    }

    /// The winner for a cell of budget `b` under model `model`: tune's bound must be within
    /// the cell's limit (a bound of the largest error bounds its 99th percentile too).
    pub fn win(&self, b: &Budget, model: &CostModelId) -> Option<&TunedWin> {
        if self.budget > b.limit {
            return None;
        }
        self.wins.iter().find(|w| w.cost_model == *model)
    }

    /// The clause of the answer's last sentence.
    pub fn sentence(&self, models: &[CostModel]) -> String {
        let ids: Vec<CostModelId> = (self.wins.iter())
            .filter(|w| models.iter().any(|m| m.id == w.cost_model))
            .map(|w| w.cost_model.clone())
            .collect();
        if ids.is_empty() {
            return format!(
                "shadelab tune found no approximation proven within {:.3e} that is cheaper \
                 than phong_exact under these cost models",
                self.budget.get()
            );
        }
        format!(
            "a tuned approximation proven within {:.3e} beats exact normalisation under {} \
             ({} of the {} cost models; shadelab tune)",
            self.budget.get(),
            describe(&ids, models),
            ids.len(),
            models.len()
        )
    }
}
