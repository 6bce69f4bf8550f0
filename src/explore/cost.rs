//! A cost of `explore`: `shadelab isa` of the method and phong_exact on one family
//! ([`crate::isa::run_with`], the timed draw's programs: the ranking statistic is the draw's
//! fragment program, so the figure is isa's), through the compile store and the compiler
//! workers. One family at a time, so that the page draws each bar as it is ready.
use std::path::PathBuf;

use serde::Serialize;

use crate::isa::{self, store, IsaOptions, IsaReport};
use crate::method::{Method, Precision, PHONG_EXACT};

/// One family's line of `/api/v1/cost`.
#[derive(Debug, Clone, Serialize)]
pub struct CostLine {
    pub family: String,
    pub vendor: String,
    /// `compiled`, or why there is no figure (isa.json's `families[].status`).
    pub status: String,
    /// The ranking statistic over phong_exact's; null without a figure.
    pub ratio: Option<f64>,
    /// What the ranking statistic is, and its unit.
    pub statistic: Option<String>,
    pub unit: Option<String>,
    pub value: Option<f64>,
    pub phong_exact: Option<f64>,
    /// The unit that bounds the program in the family's throughput model.
    pub bound_unit: Option<String>,
    pub from_store: bool,
}

/// The figures of `method` on `family`, and isa's report of them (for its disassembly).
pub fn family(
    exe: &std::path::Path,
    method: &'static Method,
    family: &str,
    precision: Precision,
) -> (CostLine, Option<IsaReport>) {
    let vendor = family.split(':').next().unwrap_or("").to_string();
    let mut line = CostLine {
        family: family.to_string(),
        vendor,
        status: String::new(),
        ratio: None,
        statistic: None,
        unit: None,
        value: None,
        phong_exact: None,
        bound_unit: None,
        from_store: false,
    };
    let mut methods = vec![crate::method::phong_exact()];
    if method.name != PHONG_EXACT {
        methods.push(method);
    }
    let opts = IsaOptions {
        methods,
        families: vec![family.to_string()],
        driver_files: None,
        scene: None,
        exe: PathBuf::from(exe),
        precision,
        probes: Vec::new(),
        store: store::default_store(),
    };
    let report = match isa::run_with(&opts, true, &|_| {}) {
        Ok(r) => r,
        Err(e) => {
            line.status = e.to_string();
            return (line, None);
        }
    };
    let Some(fam) = report.families.first() else {
        line.status = "isa gave no figures of this family".into();
        return (line, None);
    };
    line.status = fam.status.clone();
    line.vendor = fam.vendor.clone();
    line.from_store = fam.source == Some(store::Source::FromStore);
    if let Some(k) = fam.ranking().filter(|_| fam.supported) {
        if let Some(row) = report.row(&fam.family, method.name, &k.stage, k.kind) {
            line.ratio = row
                .ratio_to_phong_exact
                .get(&k.key)
                .copied()
                .filter(|v| v.is_finite());
            line.value = row.statistics.get(&k.key).copied();
            line.bound_unit = row.bound_unit.map(|u| u.name().to_string());
        }
        line.phong_exact = report.ranking_value(&fam.family, PHONG_EXACT);
        line.statistic = Some(k.meaning.clone());
        line.unit = Some(k.unit.clone());
    }
    (line, Some(report))
}

/// The fragment program's disassembly of the timed draw of `method` in `report` (every
/// representation the driver gave, one after the other).
pub fn disassembly(report: &IsaReport, method: &str) -> Option<String> {
    let fam = report.families.first()?;
    let base = format!(
        "asm/{}/{method}.fragment.",
        isa::table::asm_dir(&fam.family)
    );
    let parts: Vec<&str> = report
        .disassembly
        .iter()
        .filter(|(p, _)| {
            p.strip_prefix(&base)
                .is_some_and(|rest| !rest.starts_with("repeat"))
        })
        .map(|(_, t)| t.as_str())
        .collect();
    (!parts.is_empty()).then(|| parts.join("\n"))
}
