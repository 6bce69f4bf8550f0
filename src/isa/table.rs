//! The children's reports as one table: a row per (family, method, stage) with every statistic
//! the driver gave under a snake_case key of its own name ("Inverse Throughput" ->
//! `inverse_throughput`), the isolated kernel's cost of one evaluation (the difference of its
//! two evaluation counts) and each row's ratio to phong_exact's, with the driver's names and
//! descriptions of its statistics. Per family whether the driver compiled it, and the whole
//! report, are [`super::report`]'s.
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::request::{ChildReport, CompiledKind, RowKind};
use super::throughput::Unit;
use super::Precision;
use crate::error::{Error, Result};
use crate::gpu::vk::{Executable, StatValue};
use crate::method::PHONG_EXACT;

/// A statistic as the driver names and describes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StatName {
    pub key: String,
    pub name: String,
    pub description: String,
}

/// One compiled program's figures.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    pub family: String,
    pub method: String,
    /// "fragment", "vertex" or "compute".
    pub stage: String,
    pub kind: RowKind,
    pub program: String,
    pub statistics: BTreeMap<String, f64>,
    /// This row's statistic over phong_exact's (same family, stage and kind); absent where
    /// phong_exact's is zero.
    pub ratio_to_phong_exact: BTreeMap<String, f64>,
    /// The driver's hashes of the executable (those of both kernels for an evaluation).
    pub hash: Vec<String>,
    /// The unit that bounds this program in its family's throughput model
    /// ([`super::throughput`]); absent where the model lacks a figure it needs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound_unit: Option<Unit>,
}

/// What the figures are, for readers of isa.json: each family's own compiler model, named and
/// described in words by its route (`families[].ranking`).
pub const MODEL_NOTE: &str = "Each family's static model of its compiler, run without the GPU \
(families[].ranking names the statistic that ranks the programs and says in words what it \
models: ACO's inverse throughput, brw's busy cycles of the busier unit, a bound pipe's cycles, a \
weighted issue count). \
Use them to rank programs; they are not timings.";

/// A driver statistic name as a snake_case key.
pub fn key(name: &str) -> String {
    let mut out = String::new();
    for c in name.trim().chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') && !out.is_empty() {
            out.push('_');
        }
    }
    out.trim_end_matches('_').to_string()
}

/// The executable's statistics by key, its hash apart.
fn stats(e: &Executable) -> (BTreeMap<String, f64>, Vec<String>) {
    let mut map = BTreeMap::new();
    let mut hashes = Vec::new();
    for s in &e.statistics {
        let k = key(&s.name);
        // Hashes ("Hash", "Driver pipeline hash") identify code; they are not costs.
        if k == "hash" || k.ends_with("_hash") {
            hashes.push(match s.value {
                StatValue::Uint(u) => format!("{u:x}"),
                StatValue::Int(i) => format!("{i:x}"),
                v => format!("{}", v.as_f64()),
            });
        } else {
            map.insert(k, s.value.as_f64());
        }
    }
    (map, hashes)
}

/// A family's rows, the driver's statistic names, and (path, text) of each disassembly.
pub(super) type FamilyRows = (Vec<Row>, Vec<StatName>, Vec<(String, String)>);

/// The folder of a family's disassembly under asm/: its row key, `:` as `_` (`intel_tgl`).
pub fn asm_dir(family_key: &str) -> String {
    family_key.replace(':', "_")
}

/// Adds the family's model figure to a row's statistics and says which unit bounds the
/// program ([`super::report`] makes it out of the family's vendor).
pub(super) type ApplyModel<'a> = dyn Fn(&mut BTreeMap<String, f64>, RowKind) -> Option<Unit> + 'a;

/// The rows and status of one compiled family, whose rows are keyed `key`; `model` adds each
/// row's throughput model.
pub(super) fn family_rows(
    r: &ChildReport,
    key: &str,
    model: &ApplyModel<'_>,
) -> Result<FamilyRows> {
    let mut rows = Vec::new();
    let mut names: Vec<StatName> = Vec::new();
    let mut asm = Vec::new();
    let mut kernels: BTreeMap<String, Vec<(u32, &Executable)>> = BTreeMap::new();
    let dir = asm_dir(key);
    for c in &r.compiled {
        for e in &c.executables {
            for s in &e.statistics {
                if !names.iter().any(|n| n.name == s.name) {
                    names.push(StatName {
                        key: self::key(&s.name),
                        name: s.name.clone(),
                        description: s.description.clone(),
                    });
                }
            }
            let suffix = c.repeat.map(|k| format!(".repeat{k}")).unwrap_or_default();
            for rep in &e.representations {
                // A second executable of the same stage (Turnip's binning-pass vertex shader
                // beside the vertex shader) gets `.2` before `.s`: one file each.
                let base = format!("asm/{dir}/{}.{}{suffix}", c.method, e.stage);
                let mut path = format!("{base}.s");
                let mut n = 1;
                while asm.iter().any(|(p, _): &(String, String)| *p == path) {
                    n += 1;
                    path = format!("{base}.{n}.s");
                }
                asm.push((path, rep.text.clone()));
            }
            if let Some(k) = c.repeat {
                kernels.entry(c.method.clone()).or_default().push((k, e));
                continue;
            }
            let (mut statistics, hash) = stats(e);
            let kind = if c.kind == CompiledKind::Probe {
                RowKind::Probe
            } else {
                RowKind::Draw
            };
            let bound_unit = model(&mut statistics, kind);
            rows.push(Row {
                family: key.to_string(),
                method: c.method.clone(),
                stage: e.stage.clone(),
                kind,
                program: c.program.clone(),
                statistics,
                ratio_to_phong_exact: BTreeMap::new(),
                hash,
                bound_unit,
            });
        }
    }
    for (method, mut list) in kernels {
        list.sort_by_key(|(k, _)| *k);
        let [(k0, lo), (k1, hi)] = list[..] else {
            return Err(Error::Internal(format!(
                "isa: {method} on {key}: {} kernel executables, expected 2",
                list.len()
            )));
        };
        let ((a, ha), (b, hb)) = (stats(lo), stats(hi));
        let per: f64 = f64::from(k1 - k0);
        let mut statistics = b
            .iter()
            .filter_map(|(k, v)| a.get(k).map(|w| (k.clone(), (v - w) / per)))
            .collect();
        let bound_unit = model(&mut statistics, RowKind::Evaluation);
        rows.push(Row {
            family: key.to_string(),
            program: crate::gpu::shaders::evaluate_program_in(&method, r_precision(r)),
            method,
            stage: hi.stage.clone(),
            kind: RowKind::Evaluation,
            statistics,
            ratio_to_phong_exact: BTreeMap::new(),
            hash: ha.into_iter().chain(hb).collect(),
            bound_unit,
        });
    }
    Ok((rows, names, asm))
}

/// The precision the child compiled its method programs in (from their names).
fn r_precision(r: &ChildReport) -> Precision {
    let f16 = r.compiled.iter().any(|c| c.program.contains(".f16."));
    if f16 {
        Precision::F16
    } else {
        Precision::F32
    }
}

/// The row of (family, method, stage, kind) among `rows`, if any.
pub fn find_row<'a>(
    rows: &'a [Row],
    family: &str,
    method: &str,
    stage: &str,
    kind: RowKind,
) -> Option<&'a Row> {
    rows.iter()
        .find(|r| r.family == family && r.method == method && r.stage == stage && r.kind == kind)
}

/// Fills each row's ratio to phong_exact's row of the same family, stage and kind.
pub fn fill_ratios(rows: &mut [Row]) {
    let bases: Vec<(String, String, RowKind, BTreeMap<String, f64>)> = rows
        .iter()
        .filter(|r| r.method == PHONG_EXACT)
        .map(|r| {
            (
                r.family.clone(),
                r.stage.clone(),
                r.kind,
                r.statistics.clone(),
            )
        })
        .collect();
    for r in rows.iter_mut() {
        let Some((.., base)) = bases
            .iter()
            .find(|(f, s, k, _)| *f == r.family && *s == r.stage && *k == r.kind)
        else {
            continue;
        };
        r.ratio_to_phong_exact = r
            .statistics
            .iter()
            .filter_map(|(k, v)| {
                let b = *base.get(k)?;
                let q = v / b;
                (b != 0.0 && q.is_finite()).then(|| (k.clone(), q))
            })
            .collect();
    }
}

/// "Mesa 22.3.6" out of a driver's version string ("Mesa 22.3.6", "4.3 (Core Profile) Mesa
/// 22.3.6"), or the whole string when it names no Mesa version.
pub fn mesa_version(driver_info: &str) -> Option<String> {
    let words: Vec<&str> = driver_info.split_whitespace().collect();
    match words.iter().position(|w| *w == "Mesa") {
        Some(i) => words.get(i + 1).map(|v| format!("Mesa {v}")),
        None => (!driver_info.trim().is_empty()).then(|| driver_info.trim().to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mesa_version_is_read_from_either_api() {
        assert_eq!(mesa_version("Mesa 22.3.6").as_deref(), Some("Mesa 22.3.6"));
        assert_eq!(
            mesa_version("4.3 (Core Profile) Mesa 22.3.6").as_deref(),
            Some("Mesa 22.3.6")
        );
        assert_eq!(mesa_version("other 1.0").as_deref(), Some("other 1.0"));
        assert_eq!(mesa_version(" "), None);
    }

    #[test]
    fn keys_are_snake_case_driver_names() {
        assert_eq!(key("Inverse Throughput"), "inverse_throughput");
        assert_eq!(key("Spilled VGPRs"), "spilled_vgprs");
        assert_eq!(key("Pre-Sched SGPRs"), "pre_sched_sgprs");
        assert_eq!(key("Code size"), "code_size");
    }

    fn row(method: &str, it: f64) -> Row {
        Row {
            family: "navi21".into(),
            method: method.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            program: method.into(),
            statistics: [("inverse_throughput".to_string(), it)].into(),
            ratio_to_phong_exact: BTreeMap::new(),
            hash: Vec::new(),
            bound_unit: None,
        }
    }

    #[test]
    fn ratios_are_to_phong_exact_and_skip_a_zero_base() {
        let mut rows = vec![
            row(crate::method::vertex_lit_reference().name, 16.0),
            row(PHONG_EXACT, 64.0),
        ];
        fill_ratios(&mut rows);
        assert_eq!(rows[0].ratio_to_phong_exact["inverse_throughput"], 0.25);
        assert_eq!(rows[1].ratio_to_phong_exact["inverse_throughput"], 1.0);
        // Teeth: a zero base gives no ratio (never inf or NaN).
        let mut rows = vec![
            row(crate::method::vertex_lit_reference().name, 16.0),
            row(PHONG_EXACT, 0.0),
        ];
        fill_ratios(&mut rows);
        assert!(rows[0].ratio_to_phong_exact.is_empty());
        // Another family's phong_exact is not a base.
        let mut other = row(PHONG_EXACT, 8.0);
        other.family = "polaris10".into();
        let mut rows = vec![row(crate::method::vertex_lit_reference().name, 16.0), other];
        fill_ratios(&mut rows);
        assert!(rows[0].ratio_to_phong_exact.is_empty());
    }
}
