//! Whether `auto`'s grouping pays: each extra program (one more pipeline and draw range in the
//! pass, a program switch) must save more shading work than it costs, or its triangles are
//! drawn with the one program every triangle can take. `auto` must never cost more than
//! drawing everything with one program (issue 22: suzanne drew at 1.103x phong_exact's frame,
//! four programs where half the triangles needed phong_exact).
//!
//! The model: a triangle's shading work is its window-space area (a proxy for its fragments)
//! times its program's cost per fragment in the run's cost model ([`crate::cost::CostModel`]); a
//! program switch costs [`SWITCH_COST`] of the whole frame's shading work with the one program.
//! A group is kept when moving it to the one program would add more than that.
use serde::{Deserialize, Serialize};

use crate::cost::CostModelId;

use super::AutoSpec;
use crate::scene::SceneInputs;

/// The cost of one extra program, as a share of the frame's shading work drawn with the one
/// program. Calibrated on lavapipe from the skips table (`scripts/bench.sh skip`; the figure
/// is in docs/history/figures-2026-11-27.md): suzanne's four programs drew at 1.103x the frame
/// of one, ~3.4 % of the frame per extra program, and shading is only part of a frame, hence
/// 5 % of the shading work.
pub const SWITCH_COST: f64 = 0.05;

/// What the grouping decided, for the outputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Grouping {
    /// The cost model whose costs were compared (`lavapipe_isolated`, `isa:amd:navi21`).
    pub cost_model: CostModelId,
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
    /// "grouped", "one program", "one program (frame check)" (the model kept groups, the
    /// frame did not measure cheaper), or why the costs could not be compared ("not judged:
    /// ...").
    pub decision: String,
    /// The frame check of a grouping the model kept ([`FrameCheck`]); absent when one program
    /// was drawn anyway or nothing timed it (`plan`).
    #[serde(default)]
    pub frame: Option<FrameCheck>,
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
        frame: None,
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
        ) + &self
            .frame
            .as_ref()
            .map_or_else(String::new, |f| format!("; {}", f.line()))
    }
}

/// The frame check: `auto`'s grouped draw timed against the one program ([`Grouping::single`])
/// in the same interleaved rounds of the run's device (src/auto/frame.rs). The model
/// above prices the formulas, not the frame (rasterisation, interpolation, the framebuffer and
/// each pipeline switch cost the same whatever the formula), so it can promise a saving the
/// frame does not show; the grouping is drawn only when the measured interval says it is
/// cheaper.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameCheck {
    /// "measured now" (this process timed both draws), or "the parent run's" (a run of a
    /// `bench --runs N` draws what its parent measured, so every run times the same draw).
    pub source: String,
    /// What was timed: the whole submission of each draw, wall clock.
    pub clock: crate::gpu::Clock,
    /// Rounds with a finite ratio, and rounds without one (counted, never sorted in).
    pub rounds: usize,
    pub non_finite: usize,
    /// The grouped frame over the one program's, per round: median and sign-test 95% interval
    /// (null when not measured in this process, or not finite).
    pub ratio_median: Option<f64>,
    pub ratio_ci95_low: Option<f64>,
    pub ratio_ci95_high: Option<f64>,
    /// The model's predicted saving of the kept groups, a share of the shading work with the
    /// one program (the sum of `Grouping::kept`'s shares), beside what the frame showed.
    pub predicted_saving: f64,
    /// Whether the grouping is drawn: its whole interval below 1.
    pub grouped: bool,
}

impl FrameCheck {
    /// The check of a measured ratio (`grouped frame / one program's frame` per round): the
    /// grouping is kept only when the whole interval lies below 1; an unmeasured or
    /// non-finite interval keeps one program (never sorted as cheaper).
    pub fn measured(r: &crate::analysis::stats::RatioEstimate, predicted_saving: f64) -> Self {
        let finite = r.rounds > 0 && r.ci95_low.is_finite() && r.ci95_high.is_finite();
        FrameCheck {
            source: "measured now".into(),
            clock: crate::gpu::Clock::Wall,
            rounds: r.rounds,
            non_finite: r.non_finite,
            ratio_median: Some(r.median).filter(|v| v.is_finite()),
            ratio_ci95_low: Some(r.ci95_low).filter(|v| v.is_finite()),
            ratio_ci95_high: Some(r.ci95_high).filter(|v| v.is_finite()),
            predicted_saving,
            grouped: finite && r.ci95_high < 1.0,
        }
    }

    /// The decision of a parent run (`grouped`), not measured here.
    pub fn given(grouped: bool, predicted_saving: f64) -> Self {
        FrameCheck {
            source: "the parent run's".into(),
            clock: crate::gpu::Clock::Wall,
            rounds: 0,
            non_finite: 0,
            ratio_median: None,
            ratio_ci95_low: None,
            ratio_ci95_high: None,
            predicted_saving,
            grouped,
        }
    }

    /// One clause for the summary line.
    pub fn line(&self) -> String {
        let f = |v: Option<f64>| v.map_or_else(|| "not finite".into(), |v| format!("{v:.3}"));
        let measured = if self.source == "measured now" {
            format!(
                "grouped / one program {} [{}, {}] over {} rounds ({} not finite), \
                 the model predicted {:.1} % less shading",
                f(self.ratio_median),
                f(self.ratio_ci95_low),
                f(self.ratio_ci95_high),
                self.rounds,
                self.non_finite,
                100.0 * self.predicted_saving
            )
        } else {
            "drawn as the parent run decided".into()
        };
        format!(
            "frame check ({}): {}: {}",
            self.source,
            measured,
            if self.grouped {
                "grouping kept (measured cheaper)"
            } else {
                "one program (the grouping did not measure cheaper)"
            }
        )
    }
}

impl Grouping {
    /// The sum of the kept groups' predicted savings.
    pub fn predicted_saving(&self) -> f64 {
        self.kept.iter().map(|(_, _, s)| s).sum()
    }

    /// The index of [`Grouping::single`] in `spec.order`.
    pub fn single_index(&self, spec: &AutoSpec) -> Option<usize> {
        spec.order.iter().position(|m| m.name == self.single)
    }
}

/// Applies `check` to a settled choice: when the grouping did not measure cheaper, every
/// triangle of `pick` is drawn with the one program and the summary says so (triangles per
/// method, programs drawn, switches, decision). Returns whether the grouping is kept.
pub fn apply_frame_check(
    spec: &AutoSpec,
    pick: &mut [usize],
    summary: &mut super::AutoSummary,
    check: FrameCheck,
) -> bool {
    let Some(g) = summary.grouping.as_mut() else {
        return true;
    };
    let single = g.single_index(spec);
    let keep = check.grouped || single.is_none();
    if let (false, Some(s)) = (keep, single) {
        pick.iter_mut().for_each(|k| *k = s);
        g.merged.append(&mut g.kept);
        g.programs_drawn = 1;
        g.switches = 0;
        g.decision = "one program (frame check)".into();
    }
    g.frame = Some(check);
    summary.triangles = super::AutoSummary::new(spec, pick, 0.0, summary.source).triangles;
    keep
}
