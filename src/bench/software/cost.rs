//! The software engine's frame time as a [`CostSource`]: the paired median ratio to
//! phong_exact per scene (the scene with the largest ratio), and the seeds' claim pairs timed
//! against each other in the same rounds.
use super::SoftwareBench;
use crate::cost::{
    CostFigure, CostKind, CostModel, CostModelId, CostSource, Evidence, Measure, PairFigure,
    SOFTWARE,
};
use crate::method::{Precision, Verdict};

/// One scene's software bench, as a run hands it to the cost sources.
#[derive(Debug, Clone)]
pub struct SoftwareScene {
    pub scene: String,
    /// Its bench.json, relative to the output folder.
    pub evidence: String,
    pub bench: SoftwareBench,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The claims' pairs the software engine timed against each other in the same rounds.
pub fn pairs(scene: &str, claims: &[super::speed::SpeedClaim]) -> Vec<PairFigure> {
    claims
        .iter()
        .filter_map(|c| {
            let j = c.software.as_ref()?;
            Some(PairFigure {
                num: c.num.clone(),
                den: c.den.clone(),
                median: finite(j.median),
                ci95_low: finite(j.ci95_low),
                ci95_high: finite(j.ci95_high),
                note: format!(
                    "paired per round in the software engine ({} rounds, {} not finite; scene \
                     {scene})",
                    j.rounds, j.non_finite
                ),
            })
        })
        .collect()
}

/// The software engine's frame time.
pub struct SoftwareEngine;

impl CostSource for SoftwareEngine {
    fn name(&self) -> &'static str {
        SOFTWARE
    }

    fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        let mut per = Vec::new();
        let mut pairs = Vec::new();
        for s in ev.all::<SoftwareScene>() {
            for r in &s.bench.methods {
                let verdict = if !r.ratio_median.is_finite() {
                    Verdict::NotChecked
                } else if r.ratio_ci95_high < 1.0 {
                    Verdict::Agrees
                } else if r.ratio_ci95_low > 1.0 {
                    Verdict::Disagrees
                } else {
                    Verdict::Inconclusive
                };
                per.push(CostFigure {
                    method: r.name.clone(),
                    value: finite(r.median_ms),
                    ratio: finite(r.ratio_median),
                    ci95_low: finite(r.ratio_ci95_low),
                    ci95_high: finite(r.ratio_ci95_high),
                    verdict,
                    evidence: s.evidence.clone(),
                    note: format!("scene {}, {} rounds", s.scene, s.bench.repeat),
                });
            }
            pairs.extend(self::pairs(&s.scene, &s.bench.claims));
        }
        if per.is_empty() && pairs.is_empty() {
            return Vec::new();
        }
        vec![CostModel {
            id: CostModelId::of(SOFTWARE),
            title: "software engine".into(),
            kind: CostKind::Interval,
            measure: Measure {
                statistic: "frame time of shadelab's scanline engine".into(),
                unit: "ms".into(),
            },
            description: "frame time of shadelab's scanline engine (float32, incremental span \
                          forms, all cores), paired median ratio to phong_exact per round with \
                          its sign-test interval; the scene with the largest ratio"
                .into(),
            precision: Precision::F32,
            figures: crate::bench::cost::worst_over_scenes(per),
            pairs,
        }]
    }
}
