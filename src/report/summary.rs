//! The answer in words (answer.json `summary`, the first lines of index.html): computed from the
//! answer's cells, never written by hand.
//!
//! - [`Common`]: the answer most cells (budget x cost model, over every scene) give, and the
//!   cells that differ from it ([`Summary::differing`]);
//! - per scene ([`SceneBudget`]): for each budget, the answers of the cost models on that scene
//!   alone (a real mesh allows what the 12-triangle cube forbids), grouped by answer;
//! - the interval models' cells this run cannot resolve ([`Cell::unresolved`]);
//! - what `shadelab tune` found, when the report was given its output ([`super::tuned`]);
//! - [`Summary::sentences`]: sentences saying what holds everywhere, then what differs, then
//!   the cost models this run lost ([`Summary::missing`], each with why). The browser test derives the same facts from answer.json's cells and checks the
//!   page against them.
use serde::{Deserialize, Serialize};

use super::budget::Budget;
use super::cell::Cell;
use super::models::{and_list, describe, scope};
use super::tuned::Tuned;
use crate::cost::{CostModel, CostModelId};
use crate::method::PHONG_EXACT;

/// The answer most cells give.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Common {
    pub method: String,
    pub nothing_cheaper: bool,
    /// How many cells give it, of how many.
    pub cells: usize,
    pub of: usize,
}

/// A cell named by its budget and cost model, with its answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CellRef {
    #[serde(with = "super::budget::as_id")]
    pub budget: Budget,
    pub cost_model: CostModelId,
    pub method: String,
    pub nothing_cheaper: bool,
}

/// One answer on one scene under a budget, and the cost models that give it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneAnswer {
    pub method: String,
    pub nothing_cheaper: bool,
    /// The cost models giving this answer on the scene, in the answer's model order.
    pub cost_models: Vec<CostModelId>,
    /// The smallest and largest ratio to phong_exact among them (null for phong_exact).
    pub ratio_range: Option<(f64, f64)>,
    /// Those of `cost_models` whose cell on this scene is unresolved (interval models).
    #[serde(default)]
    pub unresolved: Vec<CostModelId>,
}

/// A scene under a budget: its answers, the most widespread first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneBudget {
    pub scene: String,
    #[serde(with = "super::budget::as_id")]
    pub budget: Budget,
    pub answers: Vec<SceneAnswer>,
}

/// answer.json `summary`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub common: Common,
    /// The cells whose answer is not the common one, in the answer's cell order.
    pub differing: Vec<CellRef>,
    /// Per scene (the report's order) and budget.
    pub per_scene: Vec<SceneBudget>,
    /// The cells of interval models that this run's intervals do not resolve.
    pub unresolved: Vec<CellRef>,
    /// `shadelab tune`'s findings, when the report read them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tuned: Option<Tuned>,
    /// The cost models this run meant to have and lost (a compiler route not set up, a family
    /// the driver refused), each with why; the last sentence names them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub missing: Vec<Missing>,
    /// One to four sentences: what holds across every cost model and scene, then what differs,
    /// then what this run cannot resolve, then the cost models it lost ([`Summary::missing`]).
    pub sentences: Vec<String>,
}

/// A cost model the answer lacks: its id (`isa:amd:navi21`) and why it is missing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Missing {
    pub cost_model: CostModelId,
    pub why: String,
}

/// The sentence naming the lost cost models, grouped by their reason: "Missing from this
/// answer: 6 cost models (isa:amd:tahiti, ...): not set up: ...".
pub fn missing_sentence(missing: &[Missing]) -> Option<String> {
    if missing.is_empty() {
        return None;
    }
    let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
    for m in missing {
        match groups.iter_mut().find(|(w, _)| *w == m.why) {
            Some((_, ids)) => ids.push(m.cost_model.as_str()),
            None => groups.push((&m.why, vec![m.cost_model.as_str()])),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(why, ids)| {
            let n = ids.len();
            let s = if n == 1 { "" } else { "s" };
            format!("{n} cost model{s} ({}): {why}", ids.join(", "))
        })
        .collect();
    Some(if groups.len() == 1 {
        format!("Missing from this answer: {}.", parts[0])
    } else {
        format!(
            "Missing from this answer, {} cost model{} in all: {}.",
            missing.len(),
            if missing.len() == 1 { "" } else { "s" },
            parts.join("; ")
        )
    })
}

/// What a cell answers, as a key.
fn key(c: &Cell) -> (String, bool) {
    (c.answer.method.clone(), c.nothing_cheaper)
}

/// The most frequent answer of `cells` (ties: the first met).
pub fn common(cells: &[Cell]) -> Common {
    let mut counts: Vec<((String, bool), usize)> = Vec::new();
    for c in cells {
        match counts.iter_mut().find(|(k, _)| *k == key(c)) {
            Some((_, n)) => *n += 1,
            None => counts.push((key(c), 1)),
        }
    }
    let best = counts
        .iter()
        .enumerate()
        .max_by(|(i, a), (j, b)| a.1.cmp(&b.1).then(j.cmp(i)))
        .map(|(_, x)| x.clone());
    let ((method, nothing_cheaper), n) = best.unwrap_or(((PHONG_EXACT.into(), true), 0));
    Common {
        method,
        nothing_cheaper,
        cells: n,
        of: cells.len(),
    }
}

fn cell_ref(c: &Cell) -> CellRef {
    CellRef {
        budget: c.budget,
        cost_model: c.cost_model.clone(),
        method: c.answer.method.clone(),
        nothing_cheaper: c.nothing_cheaper,
    }
}

/// Groups one scene's cells under one budget by answer, the most widespread first (ties: the
/// answer's first cost model).
pub fn scene_budget(scene: &str, budget: Budget, cells: &[Cell]) -> SceneBudget {
    let mut answers: Vec<SceneAnswer> = Vec::new();
    for c in cells {
        let ratio = if c.nothing_cheaper {
            None
        } else {
            c.answer.ratio
        };
        let unresolved = !c.unresolved.is_empty();
        let found = answers
            .iter_mut()
            .find(|a| a.method == c.answer.method && a.nothing_cheaper == c.nothing_cheaper);
        let a = match found {
            Some(a) => a,
            None => {
                answers.push(SceneAnswer {
                    method: c.answer.method.clone(),
                    nothing_cheaper: c.nothing_cheaper,
                    cost_models: Vec::new(),
                    ratio_range: None,
                    unresolved: Vec::new(),
                });
                answers.last_mut().expect("just pushed")
            }
        };
        a.cost_models.push(c.cost_model.clone());
        if unresolved {
            a.unresolved.push(c.cost_model.clone());
        }
        if let Some(r) = ratio.filter(|r| r.is_finite()) {
            a.ratio_range = Some(a.ratio_range.map_or((r, r), |(l, h)| (l.min(r), h.max(r))));
        }
    }
    answers.sort_by_key(|a| std::cmp::Reverse(a.cost_models.len()));
    SceneBudget {
        scene: scene.into(),
        budget,
        answers,
    }
}

/// The sentence of what holds over every scene: the common answer and where it holds.
fn first_sentence(
    c: &Common,
    budgets: &[Budget],
    scenes: &[String],
    models: &[CostModel],
) -> String {
    let what = if c.nothing_cheaper {
        format!("Nothing is cheaper than {PHONG_EXACT}")
    } else {
        format!("{} is the cheapest method", c.method)
    };
    let scenes_said = match scenes.len() {
        1 => format!("on the one scene ({})", scenes[0]),
        n => format!("on all {n} scenes together"),
    };
    if c.cells == c.of {
        format!(
            "{what} within every one of the {} error budgets, {scenes_said}, under every one \
             of the {} cost models: {}.",
            budgets.len(),
            models.len(),
            scope(models)
        )
    } else {
        format!(
            "{what} in {} of the {} cells (error budget x cost model), {scenes_said}; the {} \
             that differ are listed below (cost models: {}).",
            c.cells,
            c.of,
            c.of - c.cells,
            scope(models)
        )
    }
}

/// The sentence of what differs scene by scene: for each scene where some cost model answers
/// otherwise than the common answer under some budget, the most widespread such answer.
fn scene_sentence(
    c: &Common,
    per_scene: &[SceneBudget],
    scenes: &[String],
    models: &[CostModel],
) -> String {
    let limit = |s: &SceneBudget| s.budget.limit.get();
    // Per scene, the (budget, answer) pairs that differ from the common answer.
    let mut differ: Vec<&str> = Vec::new();
    let mut widest: Option<(&SceneBudget, &SceneAnswer)> = None;
    for s in scenes {
        let mut any = false;
        for sb in per_scene.iter().filter(|x| x.scene == *s) {
            for a in &sb.answers {
                if a.method == c.method && a.nothing_cheaper == c.nothing_cheaper {
                    continue;
                }
                any = true;
                // The answer most models give, then the tightest budget, then the first scene.
                let wider = widest.is_none_or(|(wb, wa)| {
                    a.cost_models
                        .len()
                        .cmp(&wa.cost_models.len())
                        .then_with(|| limit(wb).total_cmp(&limit(sb)))
                        .is_gt()
                });
                if wider {
                    widest = Some((sb, a));
                }
            }
        }
        if any {
            differ.push(s);
        }
    }
    let Some((sb, a)) = widest else {
        return "Scene by scene the answer is the same on every scene.".into();
    };
    let label = sb.budget.label();
    let what = if a.nothing_cheaper {
        format!("nothing is cheaper than {PHONG_EXACT} within {label}")
    } else {
        format!("{} is cheaper within {label}", a.method)
    };
    let on = match differ.as_slice() {
        [one] => format!("on {one} alone"),
        many => format!(
            "on {} of the {} scenes ({})",
            many.len(),
            scenes.len(),
            and_list(many)
        ),
    };
    format!(
        "Scene by scene the answer differs {on}; most widely on {}, where {what} under {} of \
         the {} cost models (the answers per scene follow).",
        sb.scene,
        a.cost_models.len(),
        models.len()
    )
}

/// The sentence of what this run could not resolve, and of what tune found.
fn last_sentence(
    unresolved: &[CellRef],
    cells: &[Cell],
    models: &[CostModel],
    tuned: Option<&Tuned>,
) -> Option<String> {
    let mut parts = Vec::new();
    if !unresolved.is_empty() {
        let mut ids: Vec<CostModelId> = unresolved.iter().map(|u| u.cost_model.clone()).collect();
        ids.sort();
        ids.dedup();
        let total: usize = cells.iter().filter(|c| ids.contains(&c.cost_model)).count();
        let named: Vec<String> = describe(&ids, models)
            .split("; ")
            .map(String::from)
            .collect();
        let named: Vec<&str> = named.iter().map(String::as_str).collect();
        parts.push(format!(
            "the {} {} unresolved at this size in {} of {} {} cells: in each, a method within \
             the budget is measured neither cheaper nor dearer than {PHONG_EXACT}, and the \
             cell says what would resolve it",
            and_list(&named),
            if ids.len() == 1 {
                "model is"
            } else {
                "models are"
            },
            unresolved.len(),
            if ids.len() == 1 { "its" } else { "their" },
            total
        ));
    }
    if let Some(t) = tuned {
        parts.push(t.sentence(models));
    }
    if parts.is_empty() {
        return None;
    }
    let mut s = parts.join("; ");
    if let Some(first) = s.get(..1) {
        s = first.to_uppercase() + &s[1..];
    }
    Some(s + ".")
}

/// The summary of `cells` over `scenes`, with the per-scene groups `per_scene` and tune's
/// findings.
pub fn summarize(
    cells: &[Cell],
    budgets: &[Budget],
    scenes: &[String],
    models: &[CostModel],
    per_scene: Vec<SceneBudget>,
    tuned: Option<Tuned>,
    missing: Vec<Missing>,
) -> Summary {
    let common = common(cells);
    let differing: Vec<CellRef> = cells
        .iter()
        .filter(|c| key(c) != (common.method.clone(), common.nothing_cheaper))
        .map(cell_ref)
        .collect();
    let unresolved: Vec<CellRef> = cells
        .iter()
        .filter(|c| !c.unresolved.is_empty())
        .map(cell_ref)
        .collect();
    let mut sentences = vec![first_sentence(&common, budgets, scenes, models)];
    if scenes.len() > 1 {
        sentences.push(scene_sentence(&common, &per_scene, scenes, models));
    }
    sentences.extend(last_sentence(&unresolved, cells, models, tuned.as_ref()));
    sentences.extend(missing_sentence(&missing));
    Summary {
        common,
        differing,
        per_scene,
        unresolved,
        tuned,
        missing,
        sentences,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lost_cost_models_are_named_with_their_reason() {
        let m = |id: &str, why: &str| Missing {
            cost_model: CostModelId::parse(id).unwrap(),
            why: why.into(),
        };
        let amd = "not set up: no Vulkan ICD manifest names libvulkan_radeon.so";
        let s = missing_sentence(&[
            m("isa:amd:tahiti", amd),
            m("isa:amd:navi21", amd),
            m("isa:intel:mtl", "not set up: run make compilers"),
        ])
        .unwrap();
        assert!(s.contains("3 cost models in all"), "{s}");
        assert!(
            s.contains(&format!(
                "2 cost models (isa:amd:tahiti, isa:amd:navi21): {amd}"
            )),
            "{s}"
        );
        assert!(s.contains("1 cost model (isa:intel:mtl)"), "{s}");
        // One reason: said once, without a total that repeats the group's count.
        let one = missing_sentence(&[m("isa:amd:tahiti", amd), m("isa:amd:navi21", amd)]).unwrap();
        assert_eq!(
            one,
            format!(
                "Missing from this answer: 2 cost models (isa:amd:tahiti, isa:amd:navi21): {amd}."
            )
        );
        // Teeth: nothing lost, nothing said.
        assert_eq!(missing_sentence(&[]), None);
    }
}
