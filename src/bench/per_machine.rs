//! bench timings over a corpus of meshes as a [`CostSource`]: per machine, bench's paired frame-time ratio
//! to phong_exact over the meshes timed there (the median as the figure, cheaper only when the
//! ratio is below 1 on every mesh that timed the method; no interval across meshes).
use crate::analysis::stats::percentile;
use crate::cost::{CostFigure, CostKind, CostModel, CostModelId, CostSource, Evidence, Measure};
use crate::method::{Precision, Verdict};

/// One mesh's bench ratios to phong_exact (timing.json `bench_ratio_median`), with the machine
/// that timed them.
#[derive(Debug, Clone)]
pub struct MeshTiming {
    pub machine: String,
    pub mesh: String,
    /// (method, paired median ratio to phong_exact); non-finite: unmeasured.
    pub ratios: Vec<(String, f64)>,
}

/// Per method (in first-seen order), its ratio on each mesh.
type Ratios = Vec<(String, Vec<f64>)>;

/// bench's frame time per machine over a corpus's meshes.
pub struct BenchPerMachine;

impl CostSource for BenchPerMachine {
    fn name(&self) -> &'static str {
        "bench"
    }

    fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        let mut per: Vec<(String, Ratios)> = Vec::new();
        for t in ev.all::<MeshTiming>() {
            let idx = match per.iter().position(|(k, _)| *k == t.machine) {
                Some(i) => i,
                None => {
                    per.push((t.machine.clone(), Vec::new()));
                    per.len() - 1
                }
            };
            for (name, r) in &t.ratios {
                let list = &mut per[idx].1;
                match list.iter_mut().find(|(n, _)| n == name) {
                    Some((_, v)) => v.push(*r),
                    None => list.push((name.clone(), vec![*r])),
                }
            }
        }
        per.into_iter()
            .map(|(machine, list)| CostModel {
                id: CostModelId::slug("bench", &machine),
                title: format!("bench on {machine}"),
                kind: CostKind::Interval,
                measure: Measure {
                    statistic: "bench's paired frame-time ratio, median over the meshes".into(),
                    unit: "ratio to phong_exact".into(),
                },
                description: "bench's paired frame-time ratio to phong_exact per mesh: the \
                              median over the meshes, cheaper only when below 1 on every mesh \
                              (no interval across meshes)"
                    .into(),
                precision: Precision::F32,
                figures: list.into_iter().map(figure).collect(),
                pairs: Vec::new(),
            })
            .collect()
    }
}

fn figure((method, mut v): (String, Vec<f64>)) -> CostFigure {
    let all = v.iter().all(|r| r.is_finite() && *r < 1.0);
    let count = v.len();
    let med = percentile(&mut v, 50.0);
    CostFigure {
        method,
        value: None,
        ratio: med.is_finite().then_some(med),
        ci95_low: None,
        ci95_high: None,
        verdict: if all {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        evidence: String::new(),
        note: format!(
            "median over {count} meshes; {}",
            if all {
                "faster on every mesh"
            } else {
                "not faster on every mesh"
            }
        ),
    }
}
