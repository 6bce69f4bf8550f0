//! lavapipe's two cost models as [`CostSource`]s: the frame time of the whole draw
//! ([`LavapipeFrame`], bench's paired ratio to phong_exact, across runs) and the cost of one
//! evaluation of the per-fragment code apart from rasterization ([`LavapipeIsolated`], also
//! measured on demand for `auto`). Both read the [`TimedScene`]s a run puts in its evidence.
use std::sync::Arc;

use super::isolated::Comparison;
use super::{MethodTiming, Speed};
use crate::cost::{
    CostFigure, CostKind, CostModel, CostModelId, CostSource, Evidence, Measure, LAVAPIPE_FRAME,
    LAVAPIPE_ISOLATED,
};
use crate::error::Result;
use crate::gpu::vk::Context;
use crate::method::{self, Method, Precision, Verdict};

/// One scene's bench timings, as a run hands them to the cost sources.
#[derive(Debug, Clone)]
pub struct TimedScene {
    /// The scene's id in the run's outputs.
    pub scene: String,
    pub methods: Vec<MethodTiming>,
    /// Where a method's figures are shown (scene, method) -> path relative to the output folder.
    pub link: fn(&str, &str) -> String,
}

impl Speed {
    /// As the verdict of "cheaper than phong_exact" (too noisy cannot decide).
    pub fn verdict(self) -> Verdict {
        match self {
            Speed::Faster => Verdict::Agrees,
            Speed::Slower => Verdict::Disagrees,
            Speed::Inconclusive | Speed::TooNoisy => Verdict::Inconclusive,
            Speed::Unmeasured => Verdict::NotChecked,
        }
    }
}

impl Comparison {
    /// As the verdict of "cheaper than phong_exact".
    pub fn verdict(self) -> Verdict {
        match self {
            Comparison::Cheaper => Verdict::Agrees,
            Comparison::Dearer => Verdict::Disagrees,
            Comparison::Indistinguishable | Comparison::TooNoisy => Verdict::Inconclusive,
        }
    }
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// "Cheaper on every scene": disagrees when one scene disagrees, agrees when all agree, else
/// inconclusive.
fn on_every_scene(vs: impl IntoIterator<Item = Verdict>) -> Verdict {
    let vs: Vec<Verdict> = vs.into_iter().collect();
    if vs.contains(&Verdict::Disagrees) {
        Verdict::Disagrees
    } else if !vs.is_empty() && vs.iter().all(|v| *v == Verdict::Agrees) {
        Verdict::Agrees
    } else {
        Verdict::Inconclusive
    }
}

/// Per method, the figure of the scene where its ratio is largest (the conservative one), with
/// the verdict over every scene that measured it ([`on_every_scene`]).
pub fn worst_over_scenes(per_scene: Vec<CostFigure>) -> Vec<CostFigure> {
    let mut by: std::collections::BTreeMap<String, (CostFigure, Vec<Verdict>)> =
        std::collections::BTreeMap::new();
    for f in per_scene {
        match by.get_mut(&f.method) {
            None => {
                let v = vec![f.verdict];
                by.insert(f.method.clone(), (f, v));
            }
            Some((w, vs)) => {
                vs.push(f.verdict);
                let larger = match (f.ratio, w.ratio) {
                    (Some(a), Some(b)) => a > b,
                    (None, _) => true,
                    _ => false,
                };
                if larger {
                    *w = f;
                }
            }
        }
    }
    let mut out: Vec<CostFigure> = by
        .into_values()
        .map(|(mut f, vs)| {
            let n = vs.len();
            f.verdict = if f.ratio.is_some() {
                on_every_scene(vs)
            } else {
                Verdict::NotChecked
            };
            if n > 1 {
                f.note = format!("{} (the largest ratio of {n} scenes)", f.note);
            }
            f
        })
        .collect();
    // By method name, as the answer has always listed them.
    out.sort_by(|a, b| a.method.cmp(&b.method));
    out
}

/// lavapipe's frame time: bench's paired median ratio per scene, the scene with the largest.
pub struct LavapipeFrame;

impl CostSource for LavapipeFrame {
    fn name(&self) -> &'static str {
        LAVAPIPE_FRAME
    }

    fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        let mut per = Vec::new();
        for s in ev.all::<TimedScene>() {
            for r in &s.methods {
                if r.floor_program == r.name || r.name.ends_with("_control") || r.error.is_none() {
                    continue;
                }
                let across = r.runs.as_ref().map_or(String::new(), |x| {
                    format!(", {} runs, coverage {:.4}", x.count, x.confidence)
                });
                per.push(CostFigure {
                    method: r.name.clone(),
                    value: finite(r.median_ms),
                    ratio: finite(r.ratio_median),
                    ci95_low: finite(r.ratio_ci95_low),
                    ci95_high: finite(r.ratio_ci95_high),
                    verdict: r.speed_vs_phong_exact.verdict(),
                    evidence: (s.link)(&s.scene, &r.name),
                    note: format!("scene {}{across}", s.scene),
                });
            }
        }
        if per.is_empty() {
            return Vec::new();
        }
        vec![CostModel {
            id: CostModelId::of(LAVAPIPE_FRAME),
            title: "lavapipe frame time".into(),
            kind: CostKind::Interval,
            measure: Measure {
                statistic: "frame time of the whole draw on lavapipe".into(),
                unit: "ms".into(),
            },
            description: "frame time of the whole draw on lavapipe (Vulkan on the CPU), paired \
                          median ratio to phong_exact; with bench runs, the interval across \
                          fresh-process runs and cheaper only beyond phong_exact_control's \
                          spread; the scene with the largest ratio, cheaper only on every scene"
                .into(),
            precision: Precision::F32,
            figures: worst_over_scenes(per),
            pairs: Vec::new(),
        }]
    }
}

/// lavapipe's isolated cost per evaluation: measured once per run (it does not depend on the
/// scene), and on demand for `auto` (the device's context in the evidence).
pub struct LavapipeIsolated;

const ISOLATED_TITLE: &str = "lavapipe isolated cost";
const ISOLATED_DESCRIPTION: &str = "cost of one evaluation of the method's per-fragment code \
     on lavapipe, apart from rasterization (compute kernels, slope per evaluation), paired ratio \
     to phong_exact across runs";

fn isolated_measure() -> Measure {
    Measure {
        statistic: "lavapipe isolated kernel, slope per evaluation".into(),
        unit: "ns per evaluation".into(),
    }
}

impl CostSource for LavapipeIsolated {
    fn name(&self) -> &'static str {
        LAVAPIPE_ISOLATED
    }

    fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        let Some(s) = ev
            .all::<TimedScene>()
            .find(|s| s.methods.iter().any(|r| r.isolated_ns_per_eval.is_some()))
        else {
            return Vec::new();
        };
        let figures = s
            .methods
            .iter()
            .filter(|r| r.isolated_ns_per_eval.is_some() && !r.name.ends_with("_control"))
            .map(|r| {
                let reference = r.name == method::PHONG_EXACT;
                let (ratio, lo, hi) = match (&r.isolated_ratio_to_phong_exact, reference) {
                    (Some(i), _) => (finite(i.median), finite(i.ci95_low), finite(i.ci95_high)),
                    (None, true) => (Some(1.0), None, None),
                    (None, false) => (None, None, None),
                };
                CostFigure {
                    method: r.name.clone(),
                    value: r.isolated_ns_per_eval.filter(|v| v.is_finite()),
                    ratio,
                    ci95_low: lo,
                    ci95_high: hi,
                    verdict: r
                        .isolated_vs_phong_exact
                        .map_or(Verdict::NotChecked, Comparison::verdict),
                    evidence: (s.link)(&s.scene, &r.name),
                    note: format!(
                        "measured once (scene {}): it does not depend on the scene",
                        s.scene
                    ),
                }
            })
            .collect();
        vec![isolated_model(figures)]
    }

    fn on_demand(&self) -> Option<&'static str> {
        Some(LAVAPIPE_ISOLATED)
    }

    fn on_demand_ids(&self) -> Vec<CostModelId> {
        vec![CostModelId::of(LAVAPIPE_ISOLATED)]
    }

    fn measures(&self, id: &CostModelId) -> bool {
        id == LAVAPIPE_ISOLATED
    }

    /// 7 rounds after 1 warm-up at 4,096 invocations: a few seconds, enough to order auto's
    /// handful of candidates (their costs differ by far more than the rounds' noise).
    fn measure(
        &self,
        _id: &CostModelId,
        methods: &[&'static Method],
        ev: &Evidence,
    ) -> Result<CostModel> {
        let ctx = ev.one::<Arc<Context>>().ok_or_else(|| {
            crate::error::Error::Internal(
                "lavapipe_isolated: no Vulkan context to measure on".into(),
            )
        })?;
        let opts = super::isolated::IsolatedOptions {
            rounds: 7,
            warmup: 1,
            invocations: 4096,
            ..Default::default()
        };
        let costs = super::isolated::measure(ctx, methods, &opts, &|_| {})?;
        let reference = costs
            .iter()
            .find(|c| c.name == method::PHONG_EXACT)
            .map(|c| c.ns_per_eval.median);
        let figures = methods
            .iter()
            .map(|m| {
                let c = costs.iter().find(|c| c.name == m.name);
                let value = c.map(|c| c.ns_per_eval.median).filter(|v| v.is_finite());
                // The paired ratio per round (the verdict's), else the ratio of the medians.
                let paired = c.and_then(|c| c.ratio_to_phong_exact.as_ref());
                CostFigure {
                    method: m.name.to_string(),
                    value,
                    ratio: paired
                        .map(|i| i.median)
                        .or_else(|| value.zip(reference).map(|(v, r)| v / r))
                        .filter(|v| v.is_finite()),
                    ci95_low: paired.and_then(|i| finite(i.ci95_low)),
                    ci95_high: paired.and_then(|i| finite(i.ci95_high)),
                    verdict: c
                        .and_then(|c| c.versus_phong_exact)
                        .map_or(Verdict::NotChecked, Comparison::verdict),
                    evidence: String::new(),
                    note: "measured now".into(),
                }
            })
            .collect();
        Ok(isolated_model(figures))
    }
}

fn isolated_model(figures: Vec<CostFigure>) -> CostModel {
    CostModel {
        id: CostModelId::of(LAVAPIPE_ISOLATED),
        title: ISOLATED_TITLE.into(),
        kind: CostKind::Interval,
        measure: isolated_measure(),
        description: ISOLATED_DESCRIPTION.into(),
        precision: Precision::F32,
        figures,
        pairs: Vec::new(),
    }
}
