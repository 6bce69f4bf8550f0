//! Everything `shadelab isa` found ([`IsaReport`], isa.json): per family whether the driver
//! compiled it, with who compiled and the statistic that ranks its programs
//! ([`FamilyStatus`]), the rows of [`super::table`], and what was judged on them: the op-count
//! claim ([`super::op_count`]) and the rank correlation with lavapipe ([`super::rank`]).
use crate::isa::request::RowKind;
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::op_count::{op_count, OpCountVerdict};
use super::rank::Correlation;
use super::route::{self, Compiler, Family, Ranking};
use super::table::{family_rows, fill_ratios, find_row, mesa_version, Row, StatName, MODEL_NOTE};
use super::{ChildOutcome, IsaOptions, Precision, KERNEL_COUNTS};
use crate::error::Result;

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
    /// How long the child took to compile (for figures read from the store: when they were
    /// compiled).
    pub elapsed_ms: Option<f64>,
    /// The statistics the driver reported, in its order, with its names and descriptions.
    pub statistics: Vec<StatName>,
    /// SHA-256 of the compiler's identity (driver, API, the route's environment and the build
    /// ids of its files: [`super::identity::CompilerIdentity`]); absent where nothing
    /// compiled and in isa.json files written before the compile store.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compiler_id: Option<String>,
    /// Whether the figures were compiled now or read from the compile store.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<super::store::Source>,
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
    pub spearman: Vec<Correlation>,
    /// Per family, the op-count claim judged on the compiled instructions.
    #[serde(default)]
    pub op_count: Vec<OpCountVerdict>,
    /// (relative path, text) of each disassembly, written by [`super::files`].
    #[serde(skip)]
    pub disassembly: Vec<(String, String)>,
    /// The user methods' files (`--method-file`): id, path, SHA-256; absent without one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub method_files: Vec<crate::output::provenance::MethodFile>,
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
        compiler_id: None,
        source: None,
    }
}

/// Adds `family`'s model figure to `statistics` (under the ranking key, when the compiler has
/// no statistic of that name) and, to a compiled program's (not an evaluation's differences),
/// its occupancy ([`super::occupancy`]); says which unit bounds the program.
fn apply_model(
    family: &Family,
    statistics: &mut BTreeMap<String, f64>,
    kind: super::request::RowKind,
) -> Option<super::throughput::Unit> {
    if kind != super::request::RowKind::Evaluation {
        if let Some(o) = family.vendor.occupancy(family.chip, statistics) {
            o.write(statistics);
        }
    }
    let model = family.vendor.model(family.chip, statistics)?;
    statistics
        .entry(family.vendor.ranking().key)
        .or_insert(model.cycles);
    Some(model.bound)
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
            ChildOutcome::Compiled(r, provenance) => {
                let apply =
                    |stats: &mut BTreeMap<String, f64>, kind| apply_model(&family, stats, kind);
                let (rows, names, asm) = family_rows(&r, &family.id(), &apply)?;
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
                f.compiler_id = Some(provenance.compiler_id);
                f.source = Some(provenance.source);
                families.push(f);
            }
            ChildOutcome::Failed(why) => families.push(status(
                &family,
                false,
                format!("not supported by this driver: {why}"),
            )),
            ChildOutcome::Stopped(why) => families.push(status(
                &family,
                false,
                format!("not compiled: its compiler worker was stopped: {why}"),
            )),
            ChildOutcome::Refused(why) => families.push(status(
                &family,
                false,
                format!("not compiled: the request's input was refused before compiling: {why}"),
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
            .unwrap_or_else(|| super::request::DEFAULT_SCENE_NAME.to_string()),
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
    report.op_count = op_count(&report.results, &report.disassembly, &report.supported());
    Ok(report)
}

impl FamilyStatus {
    /// The family's vendor and chip, from `id` (or `family` in an older isa.json).
    pub fn resolve(&self) -> Option<(&'static dyn route::Vendor, String)> {
        let id = if self.id.is_empty() {
            &self.family
        } else {
            &self.id
        };
        route::resolve(id).ok()
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
        self.row(family, method, &r.stage, r.kind)?
            .statistics
            .get(&r.key)
            .copied()
    }

    /// `method`'s ranking figure over phong_exact's, same family.
    pub fn ranking_ratio(&self, family: &str, method: &str) -> Option<f64> {
        let r = self.family(family)?.ranking()?;
        self.row(family, method, &r.stage, r.kind)?
            .ratio_to_phong_exact
            .get(&r.key)
            .copied()
    }

    /// The row of (family, method, stage, kind), if any.
    pub fn row(&self, family: &str, method: &str, stage: &str, kind: RowKind) -> Option<&Row> {
        find_row(&self.results, family, method, stage, kind)
    }

    /// Per compiled family, Spearman's rho between its ranking statistic of one kernel
    /// evaluation and lavapipe's isolated cost in `bench` (a bench.json): [`super::rank`].
    pub fn against_bench(&self, bench: &serde_json::Value) -> Result<Vec<Correlation>> {
        let families: Vec<(&str, String)> = self
            .supported()
            .into_iter()
            .map(|f| {
                let key = self.family(f).and_then(FamilyStatus::ranking);
                (f, key.map_or(String::new(), |r| r.key))
            })
            .collect();
        super::rank::against_bench(&self.results, &families, bench)
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
            if r.kind != RowKind::Probe && !methods.contains(&r.method.as_str()) {
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
                let a = cell(self.row(f, m, "fragment", RowKind::Draw), &key);
                let b = cell(self.row(f, m, "compute", RowKind::Evaluation), &key);
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
