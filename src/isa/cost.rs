//! The static cost of each GPU family as a [`CostSource`]: per family `isa` compiled, the
//! ranking statistic of the timed draw's fragment program over phong_exact's in the same
//! precision (deterministic, no interval); on demand (`auto --cost-model isa:FAMILY`), the
//! family compiled now by one child.
use std::path::PathBuf;

use super::{IsaOptions, IsaReport, DEFAULT_DRIVER_FILES};
use crate::cost::rule::static_cheaper;
use crate::cost::{CostFigure, CostKind, CostModel, CostModelId, CostSource, Evidence, Measure};
use crate::error::{Error, Result};
use crate::method::{Method, Precision};

/// An `isa` report as a run hands it to the cost sources, with the path of its isa.json
/// relative to the output folder.
#[derive(Debug, Clone)]
pub struct Compiled {
    pub report: IsaReport,
    pub evidence: String,
}

/// The statistic that ranks programs on `family` (its key in a row's `statistics`) and what
/// it is.
pub fn ranking(r: &IsaReport, family: &str) -> (String, Measure) {
    match r.family(family).and_then(|f| f.ranking()) {
        // AMD, as before other vendors: the same words.
        Some(k) if k.key == "inverse_throughput" => (
            k.key,
            Measure {
                statistic: "ACO inverse throughput of the draw's fragment shader".into(),
                unit: "busy cycles per wave".into(),
            },
        ),
        Some(k) => (
            k.key,
            Measure {
                statistic: k.meaning,
                unit: k.unit,
            },
        ),
        None => (
            "inverse_throughput".into(),
            Measure {
                statistic: "ACO inverse throughput of the draw's fragment shader".into(),
                unit: "busy cycles per wave".into(),
            },
        ),
    }
}

/// The models of one report: one per family the driver compiled.
fn models_of(r: &IsaReport, evidence: &str) -> Vec<CostModel> {
    let f16 = r.precision == Precision::F16;
    r.supported()
        .into_iter()
        .map(|fam| {
            let (key, measure) = ranking(r, fam);
            let figures = r
                .results
                .iter()
                .filter(|x| x.family == fam && x.stage == "fragment" && x.kind == "draw")
                .map(|x| {
                    let ratio = x
                        .ratio_to_phong_exact
                        .get(&key)
                        .copied()
                        .filter(|v| v.is_finite());
                    CostFigure {
                        method: x.method.clone(),
                        value: x.statistics.get(&key).copied().filter(|v| v.is_finite()),
                        ratio,
                        ci95_low: None,
                        ci95_high: None,
                        verdict: static_cheaper(ratio),
                        evidence: evidence.into(),
                        note: format!("{fam}, {} fragment program", r.precision.as_str()),
                    }
                })
                .collect();
            CostModel {
                id: CostModelId::isa(fam, r.precision),
                title: if f16 {
                    format!("{fam} float16 (static)")
                } else {
                    format!("{fam} (static)")
                },
                kind: CostKind::Static,
                description: format!(
                    "ACO's static model on RADV's null device (shadelab isa{}): the {} on \
                     {fam}, over phong_exact's in the same precision; deterministic, no \
                     interval{}",
                    if f16 { " --precision f16" } else { "" },
                    measure.statistic,
                    if f16 {
                        "; the budgets are checked on the float16 programs' errors (compare \
                         in float16)"
                    } else {
                        ""
                    }
                ),
                measure,
                precision: r.precision,
                figures,
                pairs: Vec::new(),
            }
        })
        .collect()
}

/// Every GPU family `isa` compiled.
pub struct StaticCost;

impl CostSource for StaticCost {
    fn name(&self) -> &'static str {
        "isa"
    }

    fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        ev.all::<Compiled>()
            .flat_map(|c| models_of(&c.report, &c.evidence))
            .collect()
    }

    fn on_demand(&self) -> Option<&'static str> {
        Some("isa:FAMILY (a Mesa chip name, e.g. isa:navi21; see shadelab isa)")
    }

    fn measures(&self, id: &CostModelId) -> bool {
        family_of(id).is_some()
    }

    /// Compiles `methods` for the family now (one child with the system's RADV); a family the
    /// driver does not compile is a usage error: the user asked for that model.
    fn measure(
        &self,
        id: &CostModelId,
        methods: &[&'static Method],
        _ev: &Evidence,
    ) -> Result<CostModel> {
        let family = family_of(id).unwrap_or_default();
        let exe = std::env::current_exe()
            .map_err(|e| Error::Device(format!("cannot find shadelab's own binary: {e}")))?;
        let opts = IsaOptions {
            methods: methods.to_vec(),
            families: vec![family.to_string()],
            driver_files: PathBuf::from(DEFAULT_DRIVER_FILES),
            scene: None,
            exe,
            precision: Precision::F32,
            probes: Vec::new(),
        };
        let report = super::run(&opts, &|_| {})?;
        match report.families.iter().find(|f| f.family == family) {
            Some(s) if s.supported => {}
            Some(s) => return Err(Error::Usage(format!("--cost-model {id}: {}", s.status))),
            None => {
                return Err(Error::Usage(format!(
                    "--cost-model {id}: the family was not compiled"
                )))
            }
        }
        models_of(&report, "")
            .into_iter()
            .find(|m| &m.id == id)
            .ok_or_else(|| Error::Internal(format!("isa: no model {id} in the child's report")))
    }
}

/// The family of a float32 `isa:FAMILY` id.
fn family_of(id: &CostModelId) -> Option<&str> {
    let f = id.as_str().strip_prefix("isa:")?;
    (!f.is_empty() && !f.contains(':')).then_some(f)
}
