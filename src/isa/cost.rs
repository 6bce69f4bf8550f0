//! The static cost of each GPU family as a [`CostSource`]: per family `isa` compiled, the
//! ranking statistic of the timed draw's fragment program over phong_exact's in the same
//! precision (deterministic, no interval); on demand (`auto --cost-model isa:FAMILY`), the
//! family compiled now by one child.
use std::collections::BTreeMap;

use super::{IsaOptions, IsaReport};
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

/// The statistic that ranks programs on `family` (its key in a row's `statistics`, its stage
/// and kind) and what it is, as the family's vendor declares it.
pub fn ranking(r: &IsaReport, family: &str) -> Option<(super::route::Ranking, Measure)> {
    let k = r.family(family)?.ranking()?;
    let measure = Measure {
        statistic: k.meaning.clone(),
        unit: k.unit.clone(),
    };
    Some((k, measure))
}

/// A figure's note: the family and precision of its program, and where it keeps fewer waves
/// resident than phong_exact ([`super::occupancy`]), that ratio: its latency is hidden less
/// well than the model, which prices throughput, assumes.
fn note(fam: &str, precision: Precision, ratio_to_phong_exact: &BTreeMap<String, f64>) -> String {
    let mut note = format!("{fam}, {} fragment program", precision.as_str());
    if super::occupancy::fewer_waves(ratio_to_phong_exact) == Some(true) {
        let w = ratio_to_phong_exact[super::occupancy::WAVES_KEY];
        note += &format!("; fewer waves resident than phong_exact ({w:.2} of its)");
    }
    note
}

/// The models of one report: one per family the driver compiled.
fn models_of(r: &IsaReport, evidence: &str) -> Vec<CostModel> {
    let f16 = r.precision == Precision::F16;
    r.supported()
        .into_iter()
        .filter_map(|fam| {
            let (k, measure) = ranking(r, fam)?;
            let key = k.key.as_str();
            let figures = r
                .results
                .iter()
                .filter(|x| x.family == fam && x.stage == k.stage && x.kind == k.kind)
                .map(|x| {
                    let ratio = x
                        .ratio_to_phong_exact
                        .get(key)
                        .copied()
                        .filter(|v| v.is_finite());
                    CostFigure {
                        method: x.method.clone(),
                        value: x.statistics.get(key).copied().filter(|v| v.is_finite()),
                        ratio,
                        ci95_low: None,
                        ci95_high: None,
                        verdict: static_cheaper(ratio),
                        evidence: evidence.into(),
                        note: note(fam, r.precision, &x.ratio_to_phong_exact),
                    }
                })
                .collect();
            let compiler = r.family(fam).and_then(|f| f.compiler()).map_or_else(
                || "a Mesa compiler".to_string(),
                |c| {
                    format!(
                        "{} ({}{})",
                        c.driver,
                        c.mesa_version.unwrap_or_else(|| "Mesa".into()),
                        if c.production {
                            ", the vendor's production Linux compiler"
                        } else {
                            ", Mesa's own compiler for this hardware"
                        }
                    )
                },
            );
            Some(CostModel {
                id: CostModelId::isa(fam, r.precision),
                title: if f16 {
                    format!("{fam} float16 (static)")
                } else {
                    format!("{fam} (static)")
                },
                kind: CostKind::Static,
                description: format!(
                    "{compiler}, without the GPU (shadelab isa{}): the {} of the draw's \
                     fragment program on {fam}, over phong_exact's in the same precision; \
                     deterministic, no interval{}",
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
            })
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
        Some("isa:FAMILY or isa:FAMILY:f16 (a family of `shadelab isa`: isa:amd:navi21, isa:intel:tgl, isa:nvidia:nv162; a bare chip is AMD's)")
    }

    /// Every vendor's default families, float32 then float16 programs (a family whose driver
    /// does not compile float16 is left out when that is known without a child).
    fn on_demand_ids(&self) -> Vec<CostModelId> {
        let families = super::families(&super::route::default_family_ids()).unwrap_or_default();
        Precision::ALL
            .iter()
            .flat_map(|&p| {
                families
                    .iter()
                    .filter(move |f| p == Precision::F32 || f.vendor.float16(f.chip) != Some(false))
                    .map(move |f| CostModelId::isa(&f.id(), p))
            })
            .collect()
    }

    fn measures(&self, id: &CostModelId) -> bool {
        family_of(id).is_some()
    }

    /// Compiles `methods` for the family now (one child), their timed draws alone where the
    /// family's model is ranked by the draw's fragment program (every route's
    /// [`super::route::Ranking`] today): the isolated kernels `isa` also compiles would be
    /// compiled and dropped. A family the driver does not compile is a usage error: the user
    /// asked for that model. The model comes back under the family's id (`isa:navi21` asked,
    /// `isa:amd:navi21` answered).
    fn measure(
        &self,
        id: &CostModelId,
        methods: &[&'static Method],
        _ev: &Evidence,
    ) -> Result<CostModel> {
        let (family, precision) = family_of(id)
            .ok_or_else(|| Error::Usage(format!("--cost-model {id}: not a GPU family")))?;
        let exe = std::env::current_exe()
            .map_err(|e| Error::Device(format!("cannot find shadelab's own binary: {e}")))?;
        let opts = IsaOptions {
            families: vec![family.clone()],
            ..IsaOptions::every_family(methods, precision, exe)
        };
        let draws_only = super::route::resolve(&family)
            .map(|(vendor, _)| vendor.ranking().kind == super::request::RowKind::Draw)
            .unwrap_or(false);
        let report = super::run_with(&opts, draws_only, &|_| {}).map_err(|e| match e {
            // an unknown chip, say: named with the model asked for
            Error::Usage(m) => Error::Usage(format!("--cost-model {id}: {m}")),
            other => other,
        })?;
        match report.families.iter().find(|f| f.family == family) {
            Some(s) if s.supported => {}
            Some(s) => return Err(Error::Usage(format!("--cost-model {id}: {}", s.status))),
            None => {
                return Err(Error::Usage(format!(
                    "--cost-model {id}: the family was not compiled"
                )))
            }
        }
        let want = CostModelId::isa(&family, precision);
        models_of(&report, "")
            .into_iter()
            .find(|m| m.id == want)
            .ok_or_else(|| Error::Internal(format!("isa: no model {want} in the child's report")))
    }
}

/// The family id (`vendor:chip`) and precision of an `isa:FAMILY` (float32) or
/// `isa:FAMILY:f16` id, FAMILY a family id or a bare AMD chip ([`CostModelId::gpu_family`]);
/// `None` for anything else.
fn family_of(id: &CostModelId) -> Option<(String, Precision)> {
    let (vendor, chip) = super::route::resolve(&id.gpu_family()?).ok()?;
    Some((format!("{}:{chip}", vendor.prefix()), id.precision()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_name_a_family_and_a_precision() {
        let id = |s: &str| CostModelId::parse(s).unwrap();
        let f = |s: &str| family_of(&id(s));
        assert_eq!(f("isa:navi21"), Some(("amd:navi21".into(), Precision::F32)));
        assert_eq!(
            f("isa:amd:navi21:f16"),
            Some(("amd:navi21".into(), Precision::F16))
        );
        assert_eq!(
            f("isa:intel:tgl"),
            Some(("intel:tgl".into(), Precision::F32))
        );
        for bad in ["isa:navi21:f64", "lavapipe_isolated", "isa:nosuch:chip:f16"] {
            assert_eq!(f(bad), None, "{bad}");
        }
        let ids = StaticCost.on_demand_ids();
        assert!(
            ids.len() > crate::isa::route::amd::DEFAULT_CHIPS.len(),
            "{ids:?}"
        );
        assert!(ids.iter().all(|i| family_of(i).is_some()), "{ids:?}");
        assert!(ids.contains(&id("isa:amd:navi21:f16")), "{ids:?}");
    }
}
