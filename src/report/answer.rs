//! The report's answer (DIR/answer.json, DIR/answer.md, the first table of index.html, printed
//! by `shadelab report`): for each error budget and each cost model the run measured, the
//! cheapest method that meets the budget on every scene of the report, its cost relative to
//! phong_exact, and the runner-up. Schema: docs/answer.schema.json.
//!
//! A cost model is a [`CostModel`] of [`crate::cost`] (an id, a kind `interval` or `static`,
//! one figure per method with its verdict), whatever its source, so other measurements plug in
//! as more rows without touching the rule. The rule ([`answer`]):
//! - a method meets a budget when, on every scene, it was measured, covered pixels, has no
//!   non-finite pixel and its metric (largest or p99 |dI| of the luminance, compare) is finite
//!   and at most the limit; anything else fails, with the reason shown;
//! - it is cheaper than phong_exact under a cost model when that model says so: an interval
//!   model's verdict (the whole interval below 1, beyond the control's noise floor), a static
//!   model's figure below phong_exact's;
//! - the answer is the qualifying cheaper method with the lowest ratio, the runner-up the next
//!   one; with none, the answer is phong_exact and the text says "nothing is cheaper than
//!   phong_exact" (the runner-up is then the qualifying method with the lowest ratio, not
//!   measured cheaper).
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

pub use super::budget::{budgets, Budget};
pub use super::cell::{ratio_text, Binding, Cell, Choice};
use super::summary::Summary;
use super::tuned::Tuned;
use crate::compare::Metric;
use crate::cost::{CostFigure, CostKind, CostModel, CostModelId};
use crate::method::{Precision, Verdict, PHONG_EXACT};

/// answer.json `schema_version` (2: `summary`, cells' `unresolved` and `tuned`).
pub const SCHEMA_VERSION: u32 = 2;

/// One method's error on one scene (compare's summary), the input of the budget check.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    pub scene: String,
    pub method: String,
    /// The precision the method's program computed in.
    pub precision: Precision,
    pub covered_pixels: usize,
    pub non_finite_pixels: usize,
    /// Each metric's value (`None`: the metric does not apply).
    pub metrics: BTreeMap<Metric, Option<f64>>,
    /// Where the measurement is shown, relative to the report folder.
    pub evidence: String,
}

/// Whether one method meets one budget on every scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BudgetCheck {
    pub method: String,
    #[serde(with = "super::budget::as_id")]
    pub budget: Budget,
    /// The precision of the errors checked.
    #[serde(default)]
    pub precision: Precision,
    pub meets: bool,
    /// The largest value over the scenes (null when some value is not finite or missing).
    pub worst: Option<f64>,
    pub worst_scene: String,
    /// The scenes where it fails, in the report's order.
    #[serde(default)]
    pub failing_scenes: Vec<String>,
    /// Why it fails (empty when it meets the budget).
    pub why: String,
    pub evidence: String,
}

/// DIR/answer.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Answer {
    pub schema_version: u32,
    pub scenes: Vec<String>,
    pub errors_from: String,
    pub budgets: Vec<Budget>,
    pub cost_models: Vec<CostModel>,
    pub checks: Vec<BudgetCheck>,
    pub cells: Vec<Cell>,
    /// The answer in words, what differs, and per scene ([`super::summary`]).
    pub summary: Summary,
}

/// Whether `method` meets `b` over `errors` (every scene of `scenes`).
pub fn check(
    method: &str,
    b: &Budget,
    scenes: &[String],
    errors: &[SceneError],
    precision: Precision,
) -> BudgetCheck {
    let mut c = BudgetCheck {
        method: method.into(),
        budget: *b,
        precision,
        meets: true,
        worst: Some(f64::NEG_INFINITY),
        worst_scene: String::new(),
        failing_scenes: Vec::new(),
        why: String::new(),
        evidence: String::new(),
    };
    let fail = |c: &mut BudgetCheck, s: &String, why: String| {
        c.meets = false;
        if !c.failing_scenes.contains(s) {
            c.failing_scenes.push(s.clone());
        }
        if !c.why.is_empty() {
            c.why += "; ";
        }
        c.why += &why;
    };
    for s in scenes {
        let found = errors
            .iter()
            .find(|e| &e.scene == s && e.method == method && e.precision == precision);
        let Some(e) = found else {
            c.worst = None;
            fail(&mut c, s, format!("not measured on {s}"));
            continue;
        };
        if c.evidence.is_empty() {
            c.evidence = e.evidence.clone();
        }
        // non-finite first: a method NaN at every pixel covers them all, each NaN
        if e.non_finite_pixels > 0 {
            c.worst = None;
            c.worst_scene = s.clone();
            c.evidence = e.evidence.clone();
            let at = crate::compare::non_finite_at(e.non_finite_pixels, e.covered_pixels);
            fail(&mut c, s, format!("{at} on {s}"));
            continue;
        }
        if e.covered_pixels == 0 {
            c.worst = None;
            fail(&mut c, s, format!("no covered pixel on {s}"));
            continue;
        }
        match e.metrics.get(&b.metric).copied().flatten() {
            Some(v) if v.is_finite() => {
                if c.worst.is_some_and(|w| v > w) {
                    c.worst = Some(v);
                    c.worst_scene = s.clone();
                    c.evidence = e.evidence.clone();
                }
                if v > b.limit.get() {
                    fail(&mut c, s, format!("{} {v:.3e} on {s}", b.metric));
                }
            }
            v => {
                c.worst = None;
                c.worst_scene = s.clone();
                c.evidence = e.evidence.clone();
                let shown = v.map_or("missing".to_string(), |x| x.to_string());
                fail(&mut c, s, format!("{} {shown} on {s}", b.metric));
            }
        }
    }
    if c.worst == Some(f64::NEG_INFINITY) {
        c.worst = None;
    }
    c
}

fn choice(m: &str, fig: Option<&CostFigure>, chk: Option<&BudgetCheck>) -> Choice {
    Choice {
        method: m.into(),
        ratio: fig.and_then(|f| f.ratio),
        ci95_low: fig.and_then(|f| f.ci95_low),
        ci95_high: fig.and_then(|f| f.ci95_high),
        verdict: fig.map_or(Verdict::NotChecked, |f| f.verdict),
        worst_error: chk.and_then(|c| c.worst),
        cost_evidence: fig.map_or(String::new(), |f| f.evidence.clone()),
        error_evidence: chk.map_or(String::new(), |c| c.evidence.clone()),
    }
}

/// The scene that decides a cell: among the methods `m` measures cheaper than the answer
/// (ratio below `answer_ratio`) that fail the budget, the scene ruling out the most of them
/// (ties: the report's scene order); `None` when no such method fails.
fn binding(
    m: &CostModel,
    answer_ratio: Option<f64>,
    checks: &[&BudgetCheck],
    scenes: &[String],
) -> Option<Binding> {
    let mut failing: Vec<(&CostFigure, &BudgetCheck)> = m
        .figures
        .iter()
        .filter(|f| f.method != PHONG_EXACT && f.cheaper())
        .filter(|f| match (f.ratio, answer_ratio) {
            (Some(r), Some(a)) => r.is_finite() && r < a,
            (Some(r), None) => r.is_finite(),
            (None, _) => false,
        })
        .filter_map(|f| {
            let c = checks.iter().find(|c| c.method == f.method && !c.meets)?;
            Some((f, *c))
        })
        .collect();
    failing.sort_by(|a, b| {
        a.0.ratio
            .partial_cmp(&b.0.ratio)
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let count = |s: &String| {
        failing
            .iter()
            .filter(|(_, c)| c.failing_scenes.contains(s))
            .count()
    };
    let mut best: Option<(&String, usize)> = None;
    for s in scenes {
        let n = count(s);
        if n > 0 && best.is_none_or(|(_, k)| n > k) {
            best = Some((s, n));
        }
    }
    let (scene, ruled_out) = best?;
    let (cheapest, chk) = failing
        .iter()
        .find(|(_, c)| c.failing_scenes.contains(scene))?;
    Some(Binding {
        scene: scene.clone(),
        ruled_out,
        cheaper_failing: failing.len(),
        cheapest: cheapest.method.clone(),
        evidence: if chk.worst_scene == *scene {
            chk.evidence.clone()
        } else {
            String::new()
        },
    })
}

/// The cell's sentence.
fn cell_text(b: &Budget, m: &CostModel, c: &Cell) -> String {
    let mut t = if c.nothing_cheaper {
        let close = c.runner_up.as_ref().map_or(
            " (no other method meets the budget on every scene)".to_string(),
            |r| {
                format!(
                    " (closest: {} at {}, {})",
                    r.method,
                    ratio_text(r),
                    r.verdict_words()
                )
            },
        );
        format!(
            "{}, {}: nothing is cheaper than phong_exact{close}",
            b.label(),
            m.title
        )
    } else {
        format!(
            "{}, {}: {} at {} of phong_exact; runner-up {} at {}{}",
            b.label(),
            m.title,
            c.answer.method,
            ratio_text(&c.answer),
            c.runner_up
                .as_ref()
                .map_or("-".into(), |r| r.method.clone()),
            c.runner_up.as_ref().map_or("-".into(), ratio_text),
            if c.separated { "" } else { " (not told apart)" }
        )
    };
    if let Some(k) = &c.binding {
        t += &format!(
            "; decided by {}: it rules out {} of the {} cheaper methods that fail (cheapest {})",
            k.scene, k.ruled_out, k.cheaper_failing, k.cheapest
        );
    }
    if !c.unresolved.is_empty() {
        t += &format!("; {}", unresolved_text(&c.unresolved, m));
    }
    if let Some(w) = &c.tuned {
        t += &format!(
            "; a tuned approximation beats exact normalisation here: {} ({}) at {} of \
             phong_exact, proven within {} (shadelab tune)",
            w.candidate,
            w.label,
            w.ratio.map_or("unmeasured".into(), |r| format!("{r:.3}")),
            w.proven_error
                .map_or("unknown".into(), |e| format!("{e:.3e}"))
        );
    }
    t
}

/// What would resolve an interval model's cell: longer draws or more runs (docs/answer.md
/// "Unresolved cells").
pub const RESOLVE_HINT: &str = "a larger --size (longer draws: the fixed cost of a submission \
     and the machine's noise weigh less) or more --runs narrows the intervals";

/// "unresolved at this size: ..." for the methods `names` of model `m`.
pub fn unresolved_text(names: &[String], m: &CostModel) -> String {
    let shown: Vec<String> = names
        .iter()
        .take(3)
        .map(|n| match m.figure(n) {
            Some(f) => format!("{n} {}", ratio_text(&choice(n, Some(f), None))),
            None => n.clone(),
        })
        .collect();
    let more = if names.len() > 3 {
        format!(" and {} more", names.len() - 3)
    } else {
        String::new()
    };
    format!(
        "unresolved at this size: {} {} within the budget {} neither measured cheaper nor \
         dearer ({}{more}); {RESOLVE_HINT}",
        names.len(),
        if names.len() == 1 {
            "method"
        } else {
            "methods"
        },
        if names.len() == 1 { "is" } else { "are" },
        shown.join(", ")
    )
}

/// The methods of `ranked` (qualifying, with a ratio) that model `m` does not tell from the
/// answer: inconclusive, with an interval reaching below the answer's ratio (1 for
/// phong_exact). Interval models only: a static figure is never inconclusive.
fn unresolved_of(
    m: &CostModel,
    ranked: &[&CostFigure],
    answer: &Choice,
    nothing: bool,
) -> Vec<String> {
    if m.kind != CostKind::Interval {
        return Vec::new();
    }
    let bar = if nothing {
        1.0
    } else {
        answer.ratio.unwrap_or(1.0)
    };
    ranked
        .iter()
        .filter(|f| f.method != answer.method && f.verdict == Verdict::Inconclusive)
        .filter(|f| f.ci95_low.or(f.ratio).is_some_and(|l| l < bar))
        .map(|f| f.method.clone())
        .collect()
}

/// One cell of the answer: budget `b` under cost model `m` (`checks`: every method's check of
/// `b` at the model's precision).
fn cell(b: &Budget, m: &CostModel, checks: &[&BudgetCheck], scenes: &[String]) -> Cell {
    let meets = |name: &str| checks.iter().any(|c| c.method == name && c.meets);
    let chk = |name: &str| checks.iter().find(|c| c.method == name).copied();
    // Qualifying methods with a finite ratio, cheapest first (ties by name, for stability).
    let mut ranked: Vec<&CostFigure> = m
        .figures
        .iter()
        .filter(|f| f.method != PHONG_EXACT && meets(&f.method))
        .filter(|f| f.ratio.is_some_and(f64::is_finite))
        .collect();
    ranked.sort_by(|a, c| {
        a.ratio
            .partial_cmp(&c.ratio)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then_with(|| a.method.cmp(&c.method))
    });
    let qualifying = checks.iter().filter(|c| c.meets).count();
    let cheaper: Vec<&CostFigure> = ranked.iter().copied().filter(|f| f.cheaper()).collect();
    let exact = m.figures.iter().find(|f| f.method == PHONG_EXACT);
    let (answer, runner_up, nothing) = match cheaper.as_slice() {
        [] => (
            choice(PHONG_EXACT, exact, chk(PHONG_EXACT)),
            ranked
                .first()
                .map(|f| choice(&f.method, Some(f), chk(&f.method))),
            true,
        ),
        [first, rest @ ..] => {
            let next = rest
                .first()
                .map(|f| choice(&f.method, Some(f), chk(&f.method)))
                .unwrap_or_else(|| choice(PHONG_EXACT, exact, chk(PHONG_EXACT)));
            (
                choice(&first.method, Some(first), chk(&first.method)),
                Some(next),
                false,
            )
        }
    };
    let separated = match (&runner_up, m.kind) {
        (Some(r), CostKind::Interval) => {
            answer.ci95_high.zip(r.ci95_low).is_some_and(|(h, l)| h < l)
        }
        (Some(r), CostKind::Static) => answer.ratio.zip(r.ratio).is_some_and(|(a, r)| a < r),
        (None, _) => false,
    };
    let answer_ratio = if nothing { None } else { answer.ratio };
    let unresolved = unresolved_of(m, &ranked, &answer, nothing);
    let mut c = Cell {
        budget: *b,
        cost_model: m.id.clone(),
        binding: binding(m, answer_ratio, checks, scenes),
        answer,
        runner_up,
        nothing_cheaper: nothing,
        qualifying,
        separated,
        unresolved,
        tuned: None,
        text: String::new(),
    };
    c.text = cell_text(b, m, &c);
    c
}

/// What an answer is made of.
pub struct Inputs<'a> {
    /// The scenes, in the report's order.
    pub scenes: &'a [String],
    pub methods: &'a [String],
    pub errors: &'a [SceneError],
    /// The cost models over every scene.
    pub models: Vec<CostModel>,
    /// Per scene, the same models measured on that scene alone (the scene-independent ones
    /// unchanged); a scene not listed takes `models`.
    pub scene_models: Vec<(String, Vec<CostModel>)>,
    /// What `shadelab tune` found, when the report was given it.
    pub tuned: Option<Tuned>,
    /// The cost models the run lost, with why ([`super::summary::Missing`]).
    pub missing: Vec<super::summary::Missing>,
}

/// Every method's check of every budget in every precision `models` need.
fn checks_of(
    scenes: &[String],
    methods: &[String],
    errors: &[SceneError],
    models: &[CostModel],
    budgets: &[Budget],
) -> Vec<BudgetCheck> {
    let mut precisions: Vec<Precision> = models.iter().map(|m| m.precision).collect();
    precisions.push(Precision::F32);
    precisions.sort();
    precisions.dedup();
    let mut checks: Vec<BudgetCheck> = Vec::new();
    for p in precisions {
        for m in methods {
            for b in budgets {
                checks.push(check(m, b, scenes, errors, p));
            }
        }
    }
    checks
}

/// Every cell (budgets x models, budget-major).
fn cells_of(
    budgets: &[Budget],
    models: &[CostModel],
    checks: &[BudgetCheck],
    scenes: &[String],
    tuned: Option<&Tuned>,
) -> Vec<Cell> {
    budgets
        .iter()
        .flat_map(|b| models.iter().map(move |m| (b, m)))
        .map(|(b, m)| {
            let of: Vec<&BudgetCheck> = checks
                .iter()
                .filter(|c| c.budget == *b && c.precision == m.precision)
                .collect();
            let mut c = cell(b, m, &of, scenes);
            if let Some(w) = tuned.and_then(|t| t.win(b, &m.id)) {
                c.tuned = Some(w.clone());
                c.text = cell_text(b, m, &c);
            }
            c
        })
        .collect()
}

/// The answer over `scenes` from the errors and the cost models (the same models for every
/// scene, no tune findings).
pub fn answer(
    scenes: &[String],
    methods: &[String],
    errors: &[SceneError],
    models: Vec<CostModel>,
) -> Answer {
    answer_with(Inputs {
        scenes,
        methods,
        errors,
        models,
        scene_models: Vec::new(),
        tuned: None,
        missing: Vec::new(),
    })
}

/// The answer of `i`: the cells over every scene, then per scene, then the words.
pub fn answer_with(i: Inputs) -> Answer {
    let budgets = budgets();
    let checks = checks_of(i.scenes, i.methods, i.errors, &i.models, &budgets);
    let cells = cells_of(&budgets, &i.models, &checks, i.scenes, i.tuned.as_ref());
    let mut per_scene = Vec::new();
    for s in i.scenes {
        let one = std::slice::from_ref(s);
        let models = (i.scene_models.iter())
            .find(|(x, _)| x == s)
            .map_or(&i.models, |(_, m)| m);
        let checks = checks_of(one, i.methods, i.errors, models, &budgets);
        let cells = cells_of(&budgets, models, &checks, one, None);
        for b in &budgets {
            let of: Vec<Cell> = cells.iter().filter(|c| c.budget == *b).cloned().collect();
            per_scene.push(super::summary::scene_budget(s, *b, &of));
        }
    }
    let summary = super::summary::summarize(
        &cells, &budgets, i.scenes, &i.models, per_scene, i.tuned, i.missing,
    );
    Answer {
        schema_version: SCHEMA_VERSION,
        scenes: i.scenes.to_vec(),
        errors_from: "compare: |dI| of the linear luminance against exact Phong in f64, over \
                      the covered pixels of each scene (Vulkan pipeline; a float32 cost model \
                      takes the float32 programs' errors, a float16 one the float16 \
                      programs'); a budget is met only on every scene, with no non-finite \
                      pixel"
            .into(),
        budgets,
        cost_models: i.models,
        checks,
        cells,
        summary,
    }
}

impl Answer {
    /// The cell of budget `b` under model `m`.
    pub fn cell(&self, b: &Budget, m: &CostModelId) -> Option<&Cell> {
        self.cells
            .iter()
            .find(|c| c.budget == *b && c.cost_model == *m)
    }
}
