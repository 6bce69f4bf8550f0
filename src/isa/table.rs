//! The children's reports as one table: a row per (family, method, stage) with every statistic
//! the driver gave under a snake_case key of its own name ("Inverse Throughput" ->
//! `inverse_throughput`), the isolated kernel's cost of one evaluation (the difference of its
//! two evaluation counts), each row's ratio to phong_exact's, and per family whether the
//! driver compiled it, with the driver's names and descriptions of its statistics.
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::vendor::{self, Compiler, Family, Ranking};
use super::{ChildOutcome, IsaOptions, Precision, KERNEL_COUNTS};
use crate::error::{Error, Result};
use crate::gpu::vk::{Executable, StatValue};
use crate::method::PHONG_EXACT;

/// The statistics every row must carry (the schema requires them).
pub const REQUIRED: [&str; 8] = [
    "instructions",
    "code_size",
    "vgprs",
    "sgprs",
    "spilled_vgprs",
    "spilled_sgprs",
    "latency",
    "inverse_throughput",
];

/// A statistic as the driver names and describes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StatName {
    pub key: String,
    pub name: String,
    pub description: String,
}

/// One family: compiled, or not supported by this driver (and what happened), or its vendor's
/// route not set up. What a cost model needs is read generically from here: the vendor, the
/// family id, the ranking statistic and the compiler (fields absent from isa.json files
/// written before other vendors: [`FamilyStatus::ranking`] and [`FamilyStatus::compiler`]
/// then answer from the vendor registry).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FamilyStatus {
    /// The key of this family's rows: AMD's bare chip name (`navi21`), else the id.
    pub family: String,
    /// `<vendor>:<chip>` (`amd:navi21`, `intel:tgl`, `nvidia:nv162`, `terascale:cayman`).
    #[serde(default)]
    pub id: String,
    /// The vendor prefix ("amd", "intel", "nvidia", "terascale").
    #[serde(default)]
    pub vendor: String,
    pub supported: bool,
    /// "compiled", "not supported by this driver: <signal / exit code, stderr tail>", or
    /// "not set up: <why>; run <command>".
    pub status: String,
    /// The command that sets this family's route up, when it is not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub setup_command: Option<String>,
    /// The statistic that ranks this family's programs, its unit and meaning.
    #[serde(default)]
    pub ranking: Option<Ranking>,
    /// Who compiled (driver, API, Mesa version, production compiler or Mesa's own).
    #[serde(default)]
    pub compiler: Option<Compiler>,
    /// Whether the driver compiles float16 arithmetic for this family (Vulkan: the device's
    /// shaderFloat16; the OpenGL route: no); absent where unknown (not compiled).
    #[serde(default)]
    pub float16: Option<bool>,
    pub device_name: Option<String>,
    pub driver_name: Option<String>,
    /// The driver's version string, e.g. "Mesa 22.3.6".
    pub driver_info: Option<String>,
    pub elapsed_ms: Option<f64>,
    /// The statistics the driver reported, in its order, with its names and descriptions.
    pub statistics: Vec<StatName>,
}

/// One compiled program's figures.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Row {
    pub family: String,
    pub method: String,
    /// "fragment", "vertex" or "compute".
    pub stage: String,
    /// "draw": the timed draw's pipeline; "evaluation": one evaluation of the isolated kernel
    /// (its statistics at the higher count minus the lower); "probe": a program given as is.
    pub kind: String,
    pub program: String,
    pub statistics: BTreeMap<String, f64>,
    /// This row's statistic over phong_exact's (same family, stage and kind); absent where
    /// phong_exact's is zero.
    pub ratio_to_phong_exact: BTreeMap<String, f64>,
    /// The driver's hashes of the executable (those of both kernels for an evaluation).
    pub hash: Vec<String>,
}

/// Everything `shadelab isa` found.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct IsaReport {
    pub version: u32,
    pub precision: Precision,
    pub scene: String,
    pub kernel_counts: [u32; 2],
    pub model: String,
    pub families: Vec<FamilyStatus>,
    pub results: Vec<Row>,
    pub elapsed_s: f64,
    /// Disassembly files written under asm/ (relative to the output folder).
    #[serde(default)]
    pub asm: Vec<String>,
    /// Charts written (relative paths), or why there are none.
    #[serde(default)]
    pub charts: Vec<String>,
    #[serde(default)]
    pub charts_note: Option<String>,
    /// Per family, Spearman's rank correlation with lavapipe's isolated cost (`--bench`).
    #[serde(default)]
    pub spearman: Vec<super::rank::Correlation>,
    /// Per family, the op-count claim judged on the compiled instructions.
    #[serde(default)]
    pub op_count: Vec<super::claims::OpCountVerdict>,
    /// (relative path, text) of each disassembly, written by [`super::files`].
    #[serde(skip)]
    pub disassembly: Vec<(String, String)>,
    /// The user methods' files (`--method-file`): id, path, SHA-256; absent without one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub method_files: Vec<crate::output::provenance::MethodFile>,
}

/// What the figures are, for readers of isa.json.
pub const MODEL_NOTE: &str = "ACO's static model on RADV's null device (Mesa): latency = issue \
plus stall cycles, inverse_throughput = estimated busy cycles to execute one wave; loops \
weighted x8, divergent branches 0.75. Use them to rank programs; they are not timings.";

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
type FamilyRows = (Vec<Row>, Vec<StatName>, Vec<(String, String)>);

/// The folder of a family's disassembly under asm/: its row key, `:` as `_` (`intel_tgl`).
pub fn asm_dir(family_key: &str) -> String {
    family_key.replace(':', "_")
}

/// The rows and status of one compiled family, whose rows are keyed `key`.
fn family_rows(r: &super::ChildReport, key: &str) -> Result<FamilyRows> {
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
                asm.push((
                    format!("asm/{dir}/{}.{}{suffix}.s", c.method, e.stage),
                    rep.text.clone(),
                ));
            }
            if let Some(k) = c.repeat {
                kernels.entry(c.method.clone()).or_default().push((k, e));
                continue;
            }
            let (statistics, hash) = stats(e);
            rows.push(Row {
                family: key.to_string(),
                method: c.method.clone(),
                stage: e.stage.clone(),
                kind: if c.kind == "probe" { "probe" } else { "draw" }.into(),
                program: c.program.clone(),
                statistics,
                ratio_to_phong_exact: BTreeMap::new(),
                hash,
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
        let statistics = b
            .iter()
            .filter_map(|(k, v)| a.get(k).map(|w| (k.clone(), (v - w) / per)))
            .collect();
        rows.push(Row {
            family: key.to_string(),
            program: crate::gpu::shaders::evaluate_program_in(&method, r_precision(r)),
            method,
            stage: hi.stage.clone(),
            kind: "evaluation".into(),
            statistics,
            ratio_to_phong_exact: BTreeMap::new(),
            hash: ha.into_iter().chain(hb).collect(),
        });
    }
    Ok((rows, names, asm))
}

/// The precision the child compiled its method programs in (from their names).
fn r_precision(r: &super::ChildReport) -> Precision {
    let f16 = r.compiled.iter().any(|c| c.program.contains(".f16."));
    if f16 {
        Precision::F16
    } else {
        Precision::F32
    }
}

/// Fills each row's ratio to phong_exact's row of the same family, stage and kind.
pub fn fill_ratios(rows: &mut [Row]) {
    let bases: Vec<(String, String, String, BTreeMap<String, f64>)> = rows
        .iter()
        .filter(|r| r.method == PHONG_EXACT)
        .map(|r| {
            (
                r.family.clone(),
                r.stage.clone(),
                r.kind.clone(),
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

/// The status of `family` with everything but what its child said.
fn status(family: &Family, supported: bool, status: String) -> FamilyStatus {
    FamilyStatus {
        family: family.id(),
        id: family.id(),
        vendor: family.vendor.prefix().into(),
        supported,
        status,
        setup_command: None,
        ranking: Some(family.vendor.ranking()),
        compiler: Some(family.vendor.compiler()),
        float16: family.vendor.float16(family.chip),
        device_name: None,
        driver_name: None,
        driver_info: None,
        elapsed_ms: None,
        statistics: Vec::new(),
    }
}

/// The report of every child's outcome.
pub fn report(
    opts: &IsaOptions,
    outcomes: Vec<(Family, ChildOutcome)>,
    elapsed_s: f64,
) -> Result<IsaReport> {
    let mut families = Vec::new();
    let mut results = Vec::new();
    let mut disassembly = Vec::new();
    for (family, outcome) in outcomes {
        match outcome {
            ChildOutcome::Compiled(r) => {
                let (rows, names, asm) = family_rows(&r, &family.id())?;
                results.extend(rows);
                disassembly.extend(asm);
                let text = if r.skipped.is_empty() {
                    "compiled".to_string()
                } else {
                    format!(
                        "compiled, {} method(s) skipped: {}",
                        r.skipped.len(),
                        r.skipped.join("; ")
                    )
                };
                let mut f = status(&family, true, text);
                if let Some(c) = f.compiler.as_mut() {
                    c.mesa_version = mesa_version(&r.driver_info);
                }
                f.float16 = f.float16.or(r.float16);
                f.device_name = Some(r.device_name);
                f.driver_name = Some(r.driver_name);
                f.driver_info = Some(r.driver_info);
                f.elapsed_ms = Some(r.elapsed_ms);
                f.statistics = names;
                families.push(f);
            }
            ChildOutcome::Failed(why) => families.push(status(
                &family,
                false,
                format!("not supported by this driver: {why}"),
            )),
            ChildOutcome::NotSetUp(why) => {
                let command = family.vendor.setup_command_for(family.chip);
                let mut f = status(&family, false, format!("not set up: {why}; run {command}"));
                f.setup_command = Some(command.into());
                f.float16 = None;
                families.push(f);
            }
        }
    }
    fill_ratios(&mut results);
    let mut report = IsaReport {
        version: 1,
        precision: opts.precision,
        scene: opts
            .scene
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_else(|| super::child::DEFAULT_SCENE_NAME.to_string()),
        kernel_counts: KERNEL_COUNTS,
        model: MODEL_NOTE.into(),
        families,
        results,
        elapsed_s,
        asm: disassembly.iter().map(|(p, _)| p.clone()).collect(),
        charts: Vec::new(),
        charts_note: None,
        spearman: Vec::new(),
        op_count: Vec::new(),
        disassembly,
        method_files: crate::output::provenance::method_files(),
    };
    report.op_count = super::claims::op_count(&report);
    Ok(report)
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

impl FamilyStatus {
    /// The family's vendor and chip, from `id` (or `family` in an older isa.json).
    pub fn resolve(&self) -> Option<(&'static dyn vendor::Vendor, String)> {
        let id = if self.id.is_empty() {
            &self.family
        } else {
            &self.id
        };
        vendor::resolve(id).ok()
    }

    /// The statistic that ranks this family's programs.
    pub fn ranking(&self) -> Option<Ranking> {
        self.ranking
            .clone()
            .or_else(|| Some(self.resolve()?.0.ranking()))
    }

    /// Who compiled this family's programs.
    pub fn compiler(&self) -> Option<Compiler> {
        self.compiler
            .clone()
            .or_else(|| Some(self.resolve()?.0.compiler()))
    }
}

impl IsaReport {
    /// The status of the family whose rows are keyed `family`.
    pub fn family(&self, family: &str) -> Option<&FamilyStatus> {
        self.families.iter().find(|f| f.family == family)
    }

    /// `method`'s figure on `family`'s ranking statistic (the fragment shader of the timed
    /// draw: ACO's inverse throughput, Intel's cycles, nouveau's instructions, ...).
    pub fn ranking_value(&self, family: &str, method: &str) -> Option<f64> {
        let r = self.family(family)?.ranking()?;
        self.row(family, method, &r.stage, &r.kind)?
            .statistics
            .get(&r.key)
            .copied()
    }

    /// `method`'s ranking figure over phong_exact's, same family.
    pub fn ranking_ratio(&self, family: &str, method: &str) -> Option<f64> {
        let r = self.family(family)?.ranking()?;
        self.row(family, method, &r.stage, &r.kind)?
            .ratio_to_phong_exact
            .get(&r.key)
            .copied()
    }

    /// The row of (family, method, stage, kind), if any.
    pub fn row(&self, family: &str, method: &str, stage: &str, kind: &str) -> Option<&Row> {
        self.results.iter().find(|r| {
            r.family == family && r.method == method && r.stage == stage && r.kind == kind
        })
    }

    /// The families the driver compiled.
    pub fn supported(&self) -> Vec<&str> {
        self.families
            .iter()
            .filter(|f| f.supported)
            .map(|f| f.family.as_str())
            .collect()
    }

    /// The text table: per method and family, the fragment shader's and one evaluation's
    /// ranking statistic over phong_exact's, then each family's statistic.
    pub fn text_table(&self) -> String {
        let fams = self.supported();
        let mut methods: Vec<&str> = Vec::new();
        for r in &self.results {
            if r.kind != "probe" && !methods.contains(&r.method.as_str()) {
                methods.push(&r.method);
            }
        }
        let mut s = String::from(
            "ranking statistic / phong_exact's (each family's static model, not a timing; the \
             statistics are listed below): fragment shader of the timed draw | one evaluation \
             of the isolated kernel\n",
        );
        s += &format!("{:<30}", "method");
        for f in &fams {
            s += &format!(" {f:>17}");
        }
        s += "\n";
        let cell = |r: Option<&Row>, key: &str| {
            r.and_then(|r| r.ratio_to_phong_exact.get(key))
                .map_or("  -  ".to_string(), |v| format!("{v:.3}"))
        };
        for m in methods {
            s += &format!("{m:<30}");
            for f in &fams {
                let key = self
                    .family(f)
                    .and_then(FamilyStatus::ranking)
                    .map_or(String::new(), |r| r.key);
                let a = cell(self.row(f, m, "fragment", "draw"), &key);
                let b = cell(self.row(f, m, "compute", "evaluation"), &key);
                s += &format!(" {:>17}", format!("{a}|{b}"));
            }
            s += "\n";
        }
        for f in self.families.iter().filter(|f| f.supported) {
            if let (Some(r), Some(c)) = (f.ranking(), f.compiler()) {
                s += &format!(
                    "{}: {} ({}; {}, {}{}): {}\n",
                    f.family,
                    r.key,
                    r.unit,
                    c.driver,
                    c.mesa_version.as_deref().unwrap_or("Mesa ?"),
                    if c.production {
                        ", the vendor's production compiler"
                    } else {
                        ", Mesa's own compiler, not the vendor's"
                    },
                    r.meaning
                );
            }
        }
        for v in &self.op_count {
            s += &format!(
                "{}: op-count claim ({} operations for exact normalisation): {}; compiled: {} \
                 extra instructions {:?}, inverse throughput x{:.3} over phong_unnormalized\n",
                v.family,
                v.claimed_operations,
                v.verdict,
                v.extra_instructions,
                v.extra_by_class,
                v.inverse_throughput_ratio
            );
        }
        for c in &self.spearman {
            let rho = c.spearman.map_or("undefined".into(), |r| format!("{r:.3}"));
            s += &format!(
                "{}: Spearman rho {rho} over {} methods ({})\n",
                c.family, c.methods, c.measure
            );
        }
        for f in self.families.iter().filter(|f| !f.supported) {
            s += &format!("{}: {}\n", f.family, f.status);
        }
        s
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
            kind: "draw".into(),
            program: method.into(),
            statistics: [("inverse_throughput".to_string(), it)].into(),
            ratio_to_phong_exact: BTreeMap::new(),
            hash: Vec::new(),
        }
    }

    #[test]
    fn ratios_are_to_phong_exact_and_skip_a_zero_base() {
        let mut rows = vec![row("gouraud", 16.0), row(PHONG_EXACT, 64.0)];
        fill_ratios(&mut rows);
        assert_eq!(rows[0].ratio_to_phong_exact["inverse_throughput"], 0.25);
        assert_eq!(rows[1].ratio_to_phong_exact["inverse_throughput"], 1.0);
        // Teeth: a zero base gives no ratio (never inf or NaN).
        let mut rows = vec![row("gouraud", 16.0), row(PHONG_EXACT, 0.0)];
        fill_ratios(&mut rows);
        assert!(rows[0].ratio_to_phong_exact.is_empty());
        // Another family's phong_exact is not a base.
        let mut other = row(PHONG_EXACT, 8.0);
        other.family = "polaris10".into();
        let mut rows = vec![row("gouraud", 16.0), other];
        fill_ratios(&mut rows);
        assert!(rows[0].ratio_to_phong_exact.is_empty());
    }
}
