//! Whether `auto`'s grouping pays: each extra program (one more pipeline and draw range in the
//! pass, a program switch) must save more shading work than it costs, or its triangles are
//! drawn with the one program every triangle can take. `auto` must never cost more than
//! drawing everything with one program (issue 22: suzanne drew at 1.103x phong_exact's frame,
//! four programs where half the triangles needed phong_exact).
//!
//! The model: a triangle's shading work is its window-space area (a proxy for its fragments)
//! times its program's cost per fragment in the run's cost model ([`super::CostModel`]); a
//! program switch costs [`SWITCH_COST`] of the whole frame's shading work with the one program.
//! A group is kept when moving it to the one program would add more than that.
use serde::{Deserialize, Serialize};

use super::AutoSpec;
use crate::scene::SceneInputs;

/// The cost of one extra program, as a share of the frame's shading work drawn with the one
/// program. Calibrated on lavapipe from the skips table (README "Skip", `scripts/bench.sh
/// skip`): suzanne's four programs drew at 1.103x the frame of one, ~3.4 % of the frame per
/// extra program, and shading is only part of a frame, hence 5 % of the shading work.
pub const SWITCH_COST: f64 = 0.05;

/// What the grouping decided, for the outputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Grouping {
    /// The cost model whose costs were compared (`lavapipe`, `isa:navi21`).
    pub cost_model: String,
    /// Programs (groups with triangles) of the per-triangle choice, and drawn after merging.
    pub programs_chosen: usize,
    pub programs_drawn: usize,
    /// Program switches in the drawn choice (`programs_drawn - 1`).
    pub switches: usize,
    /// [`SWITCH_COST`].
    pub switch_cost: f64,
    /// The one program every triangle can take within the budget.
    pub single: String,
    /// Per kept group other than `single`: (method, triangles, predicted saving as a share of
    /// the frame's shading work with `single`).
    pub kept: Vec<(String, usize, f64)>,
    /// Per group moved to `single`: (method, triangles, predicted saving it would have made).
    pub merged: Vec<(String, usize, f64)>,
    /// "grouped", "one program", or why the costs could not be compared ("not judged: ...").
    pub decision: String,
}

/// Window-space area of each triangle, pixels (front and back faces alike).
pub fn window_areas(inputs: &SceneInputs) -> Vec<f64> {
    (0..inputs.triangle_count())
        .map(|t| {
            let w = [0, 1, 2].map(|k| inputs.window[3 * t + k].map(f64::from));
            0.5 * ((w[1][0] - w[0][0]) * (w[2][1] - w[0][1])
                - (w[2][0] - w[0][0]) * (w[1][1] - w[0][1]))
                .abs()
        })
        .collect()
}

/// Applies the rule to `pick` (indices into `spec.order`, rewritten in place) with the areas
/// `areas` and the costs `spec.costs`; `within(method index, triangles)` says whether that
/// method keeps the budget on those triangles ([`super::within_budget`]).
pub fn settle(
    spec: &AutoSpec,
    areas: &[f64],
    pick: &mut [usize],
    within: &dyn Fn(usize, &[usize]) -> bool,
) -> Grouping {
    let n = spec.order.len();
    let members = |pick: &[usize], k: usize| -> Vec<usize> {
        (0..pick.len()).filter(|&t| pick[t] == k).collect()
    };
    let used: Vec<usize> = (0..n).filter(|&k| pick.contains(&k)).collect();
    let name = |k: usize| spec.order[k].name.to_string();
    let mut g = Grouping {
        cost_model: spec.cost_model.clone(),
        programs_chosen: used.len(),
        programs_drawn: used.len(),
        switches: used.len().saturating_sub(1),
        switch_cost: SWITCH_COST,
        single: used.last().map_or_else(String::new, |&k| name(k)),
        kept: Vec::new(),
        merged: Vec::new(),
        decision: "one program".into(),
    };
    let Some(&top) = used.last() else {
        return g;
    };
    if used.len() == 1 {
        return g;
    }
    // The one program: the dearest chosen if it keeps the budget everywhere, else the
    // fallback (last in the order, phong_exact, exact by definition).
    let lower: Vec<usize> = (0..pick.len()).filter(|&t| pick[t] != top).collect();
    let single = if within(top, &lower) { top } else { n - 1 };
    g.single = name(single);
    let cost = |k: usize| spec.costs.get(k).copied().unwrap_or(f64::NAN);
    if used.iter().chain([&single]).any(|&k| !cost(k).is_finite()) {
        g.decision =
            "not judged: a cost of the chosen programs is not finite; drawn as chosen".into();
        return g;
    }
    let c_single = cost(single).max(0.0);
    let area = |t: usize| {
        areas
            .get(t)
            .copied()
            .filter(|a| a.is_finite())
            .unwrap_or(0.0)
    };
    let total: f64 = (0..pick.len()).map(|t| area(t) * c_single).sum();
    for &k in used.iter().filter(|&&k| k != single) {
        let tris = members(pick, k);
        let saved: f64 = tris
            .iter()
            .map(|&t| area(t) * (c_single - cost(k).max(0.0)))
            .sum();
        let share = if total > 0.0 { saved / total } else { 0.0 };
        if share > SWITCH_COST {
            g.kept.push((name(k), tris.len(), share));
        } else {
            for &t in &tris {
                pick[t] = single;
            }
            g.merged.push((name(k), tris.len(), share));
        }
    }
    g.programs_drawn = (0..n).filter(|&k| pick.contains(&k)).count();
    g.switches = g.programs_drawn.saturating_sub(1);
    g.decision = if g.programs_drawn > 1 {
        "grouped"
    } else {
        "one program"
    }
    .into();
    g
}

/// [`settle`] on `inputs` with the choice's own budget test.
pub fn settle_on(inputs: &SceneInputs, spec: &AutoSpec, pick: &mut [usize]) -> Grouping {
    let areas = window_areas(inputs);
    let within = |k: usize, tris: &[usize]| {
        super::within_budget(inputs, spec.order[k], tris, spec.budget.get())
    };
    settle(spec, &areas, pick, &within)
}

impl Grouping {
    /// One line for stderr.
    pub fn line(&self) -> String {
        let share = |v: &[(String, usize, f64)]| {
            v.iter()
                .map(|(m, k, s)| format!("{m} {k} ({:.1} %)", 100.0 * s))
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "{} by {}: {} of {} chosen programs drawn ({} switches; a switch costs {:.0} % of \
             the frame's shading with {}); kept {}; moved to {}: {}",
            self.decision,
            self.cost_model,
            self.programs_drawn,
            self.programs_chosen,
            self.switches,
            100.0 * self.switch_cost,
            self.single,
            if self.kept.is_empty() {
                "none".into()
            } else {
                share(&self.kept)
            },
            self.single,
            if self.merged.is_empty() {
                "none".into()
            } else {
                share(&self.merged)
            },
        )
    }
}
