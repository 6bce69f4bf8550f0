//! The seeds' speed claims as one table, a column per cost model of the run's
//! [`crate::cost::Registry`]: lavapipe's frame time and isolated cost (this run's paired
//! intervals), the software engine (timed by this run after lavapipe's rounds, its programs
//! paired in their own rounds, written to DIR/software/: [`software_column`]), and per GPU
//! family the static cost (`shadelab isa`). Each cell is [`CostModel::ratio`] judged by one rule
//! ([`crate::cost::factor_verdict`]); a static cost is one deterministic figure, no interval,
//! so it agrees or disagrees, never inconclusive. The op-count claim is judged per family on
//! the compiled instructions ([`crate::isa::op_count`]).
//!
//! Where the static cost comes from ([`StaticCostSource`]): compiled now by `shadelab isa`'s
//! children (after the timed rounds, never during them), read from an isa.json (`--isa`), or
//! skipped (`--no-isa`). A family the driver refuses is a named `not_supported` cell.
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::software::speed::claim_specs;
use super::MethodTiming;
use crate::cost::{CostModel, CostModelId, Evidence};
use crate::isa::IsaReport;
use crate::method::{Verdict, PHONG_EXACT};

/// Where bench's static cost comes from.
#[derive(Debug, Clone, Default)]
pub enum StaticCostSource {
    /// Not asked for (`--no-isa`, and the library's default).
    #[default]
    Skip,
    /// An isa.json of `shadelab isa` (`--isa FILE`).
    File(PathBuf),
    /// Compiled now on every family of every vendor by `exe`'s children, the timed draw of
    /// `scene` (`None`: isa's default scene).
    Run {
        exe: PathBuf,
        scene: Option<PathBuf>,
    },
}

/// One cell: a cost model's ratio `num / den` and its verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    pub cost_model: CostModelId,
    pub ratio: Option<f64>,
    /// The 95% interval (timings); absent for a static cost (one deterministic figure).
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    /// agrees, disagrees, inconclusive, or not_checked (a program of the ratio was not
    /// measured by the model).
    pub verdict: Verdict,
    pub note: String,
}

/// One speed claim with a cell per measure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedClaim {
    pub claim: String,
    pub num: String,
    pub den: String,
    /// The claim holds when `num / den` is at most this (1 / the claimed factor).
    pub claimed_below: f64,
    pub cells: Vec<Cell>,
}

/// What bench.json says of the static cost: where it came from and each family's status.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticCost {
    /// "compiled now", "read from <path>", or "skipped (--no-isa)".
    pub source: String,
    pub model: String,
    /// (family, status): "compiled" or "not supported by this driver: ...".
    pub families: Vec<(String, String)>,
    /// The op-count claim per family, judged on the compiled instructions.
    pub op_count: Vec<crate::isa::op_count::OpCountVerdict>,
}

/// Rounds of the software engine's column in a Vulkan bench (after 2 warm-up renders each),
/// whatever the Vulkan rounds: 21 rounds give a sign-test 95% interval between the 6th and
/// 16th ratios.
pub const SOFTWARE_REPEAT: usize = 21;

/// The software engine's column of a Vulkan bench: its judged claims and where they come from.
#[derive(Debug, Clone, Default)]
pub struct SoftwareColumn {
    /// "timed now: DIR/software/bench.json (...)", "skipped (--no-software)", or why not.
    pub source: String,
    /// The software bench, when it ran.
    pub bench: Option<super::software::SoftwareBench>,
}

/// The programs of the speed claims among `methods` (phong_exact always): what the software
/// column times.
pub fn claim_methods(
    methods: &[&'static crate::method::Method],
) -> Vec<&'static crate::method::Method> {
    let specs = claim_specs();
    let named = |n: &str| specs.iter().any(|c| c.num == n || c.den == n);
    let mut out: Vec<&'static crate::method::Method> = methods
        .iter()
        .copied()
        .filter(|m| named(m.name) && m.name != crate::method::PHONG_EXACT)
        .collect();
    out.push(crate::method::phong_exact());
    out
}

/// Times the claims' programs among `methods` in the software engine (`bench --engine
/// software`'s rounds, [`SOFTWARE_REPEAT`] of them) into `out`/software/, when `on`; a failure
/// is the column's `source`, never fatal to the bench (its timings are already taken).
pub fn software_column(
    scene: &crate::scene::Scene,
    methods: &[&'static crate::method::Method],
    out: &std::path::Path,
    on: bool,
) -> SoftwareColumn {
    if !on {
        return SoftwareColumn {
            source: "skipped (--no-software)".into(),
            bench: None,
        };
    }
    let ms = claim_methods(methods);
    let dir = out.join("software");
    let threads = crate::software::default_threads();
    let sw = super::software::SoftwareOptions {
        rounds: super::RoundsSchedule {
            repeat: SOFTWARE_REPEAT,
            warmup: 2,
            until_ci_pct: None,
            max_time_s: super::DEFAULT_MAX_TIME_S,
        },
        threads,
        vulkan_bench: None,
        command_line: Vec::new(),
    };
    log::info!(
        "bench: the software engine's column: {} programs, {SOFTWARE_REPEAT} rounds",
        ms.len()
    );
    match super::software::bench(scene, &ms, &dir, &sw, None) {
        Ok(r) => SoftwareColumn {
            source: format!(
                "timed now in the software engine: {} ({} programs, {} rounds, {threads}                  threads, {:.1} s)",
                dir.join("bench.json").display(),
                ms.len(),
                r.rounds.rounds,
                r.total_s
            ),
            bench: Some(r),
        },
        Err(e) => SoftwareColumn {
            source: format!("not measured: the software engine failed: {e}"),
            bench: None,
        },
    }
}

/// The static report, or why there is none (a failure to compile or read is reported, never
/// fatal to the bench: its timings are already taken).
pub fn load(
    src: &StaticCostSource,
    methods: &[&'static crate::method::Method],
) -> (Option<IsaReport>, String) {
    match src {
        StaticCostSource::Skip => (None, "skipped (--no-isa)".into()),
        StaticCostSource::File(p) => match crate::isa::files::read(p) {
            Ok(r) => (Some(r), format!("read from {}", p.display())),
            Err(e) => (None, format!("not read: {e}")),
        },
        StaticCostSource::Run { exe, scene } => {
            let opts = crate::isa::IsaOptions {
                scene: scene.clone(),
                ..crate::isa::IsaOptions::every_family(
                    methods,
                    crate::method::Precision::F32,
                    exe.clone(),
                )
            };
            log::info!(
                "bench: static cost (shadelab isa, {} families)",
                opts.families.len()
            );
            match crate::isa::run(&opts, &|line| log::info!("isa: {line}")) {
                Ok(r) => (Some(r), "compiled now".into()),
                Err(e) => (None, format!("not compiled: {e}")),
            }
        }
    }
}

/// [`StaticCost`] of `report` (or of none).
pub fn summary(report: Option<&IsaReport>, source: String) -> StaticCost {
    StaticCost {
        source,
        model: crate::isa::table::MODEL_NOTE.into(),
        families: report.map_or_else(Vec::new, |r| {
            r.families
                .iter()
                .map(|f| (f.family.clone(), f.status.clone()))
                .collect()
        }),
        op_count: report.map_or_else(Vec::new, |r| r.op_count.clone()),
    }
}

/// Every seed speed claim whose programs `models` measured, with a cell per model.
pub fn table(models: &[CostModel]) -> Vec<SpeedClaim> {
    let mut out = Vec::new();
    for c in claim_specs() {
        let measured = |m: &str| models.iter().any(|x| x.figure(m).is_some());
        if !(measured(c.num) && measured(c.den)) {
            continue;
        }
        let cells = models
            .iter()
            .map(|m| match m.ratio(c.num, c.den, PHONG_EXACT) {
                Some(r) => Cell {
                    cost_model: m.id.clone(),
                    ratio: Some(r.median),
                    ci95_low: r.interval.map(|i| i.0),
                    ci95_high: r.interval.map(|i| i.1),
                    verdict: r.verdict(c.target),
                    note: r.note,
                },
                None => Cell {
                    cost_model: m.id.clone(),
                    ratio: None,
                    ci95_low: None,
                    ci95_high: None,
                    verdict: Verdict::NotChecked,
                    note: "a program of the ratio was not measured".into(),
                },
            })
            .collect();
        out.push(SpeedClaim {
            claim: c.claim,
            num: c.num.into(),
            den: c.den.into(),
            claimed_below: c.target,
            cells,
        });
    }
    out
}

/// The op-count verdict on the compiled instructions, as a claims verdict: the instructions
/// exact normalisation adds hold the claim's 9 operations of its classes (agrees), fewer
/// (disagrees: overstated), or as many of other classes (partly).
pub fn op_count_verdict(v: &crate::isa::op_count::OpCountVerdict) -> Verdict {
    v.verdict.verdict()
}

/// claims.md's speed table: a row per claim, a column per measure.
pub fn markdown(claims: &[SpeedClaim], stat: Option<&StaticCost>) -> String {
    let Some(first) = claims.first() else {
        return String::new();
    };
    let mut md = String::from(
        "\n## Speed claims, every cost model\n\nEach cell: the ratio `num / den` and its verdict \
         by one rule (agrees when the ratio, its whole 95% interval for a timing, is at most the \
         claimed value; disagrees when above; inconclusive when a timing's interval straddles \
         it). A static cost (`isa:<family>`, ACO's inverse throughput of the fragment shader \
         on RADV's null device, busy cycles per wave, not a timing) is one deterministic \
         figure: it agrees or disagrees; equal cost is not faster.\n",
    );
    if let Some(s) = stat {
        md += &format!("Static cost: {}.\n", s.source);
    }
    md += "\n| claim | ratio | claimed below |";
    for c in &first.cells {
        md += &format!(" {} |", c.cost_model);
    }
    md += "\n|---|---|---|";
    md += &"---|".repeat(first.cells.len());
    md += "\n";
    for c in claims {
        md += &format!(
            "| {} | {} / {} | {:.4} |",
            c.claim.replace('|', "/"),
            c.num,
            c.den,
            c.claimed_below
        );
        for cell in &c.cells {
            md += &match (cell.ratio, cell.ci95_low, cell.ci95_high) {
                (Some(r), Some(lo), Some(hi)) => {
                    format!(" {r:.3} [{lo:.3}, {hi:.3}] {} |", cell.verdict)
                }
                (Some(r), _, _) => format!(" {r:.3} {} |", cell.verdict),
                _ => format!(" {} |", cell.verdict),
            };
        }
        md += "\n";
    }
    if let Some(s) = stat.filter(|s| !s.op_count.is_empty()) {
        md += "\nThe op-count claim (\"3 divisions + 3 multiplications + 2 additions + 1 square \
               root\") on the compiled instructions (phong_exact's fragment shader minus \
               phong_unnormalized's):\n\n| family | extra instructions | by class | inverse throughput ratio | verdict |\n|---|---|---|---|---|\n";
        for v in &s.op_count {
            let classes: Vec<String> = v
                .extra_by_class
                .iter()
                .filter(|(_, n)| **n != 0)
                .map(|(k, n)| format!("{k} {n}"))
                .collect();
            md += &format!(
                "| {} | {} (claimed {}) | {} | {:.3} | {} ({}) |\n",
                v.family,
                v.extra_instructions,
                v.claimed_operations,
                classes.join(", "),
                v.inverse_throughput_ratio,
                op_count_verdict(v).as_str(),
                v.verdict
            );
        }
    }
    md
}

/// The op-count claim per family as rows of the claims list (beside the SPIR-V count's row).
pub fn op_count_checks(s: &StaticCost) -> Vec<super::ClaimCheck> {
    // the claim as phong_exact's row states it (its counts are src/isa/op_count.rs's CLAIMED)
    let row = crate::method::phong_exact();
    let Some(claim) = row
        .claims
        .iter()
        .find(|c| matches!(c.kind, crate::method::Kind::OperationCount(Some(_))))
    else {
        return Vec::new();
    };
    s.op_count
        .iter()
        .map(|v| {
            let classes: Vec<String> = v
                .extra_by_class
                .iter()
                .filter(|(_, n)| **n != 0)
                .map(|(k, n)| format!("{n} {k}"))
                .collect();
            super::ClaimCheck {
                evidence: crate::method::Evidence::MEASURED,
                method: crate::method::PHONG_EXACT.into(),
                claim: claim.claim.into(),
                measured: format!(
                    "isa:{}: phong_exact's fragment shader has {} vector ALU instructions more than phong_unnormalized's ({}), claimed {} operations; inverse throughput x{:.3}",
                    v.family,
                    v.extra_instructions,
                    classes.join(", "),
                    v.claimed_operations,
                    v.inverse_throughput_ratio
                ),
                verdict: op_count_verdict(v),
                how: "measure: the compiled instructions of RADV's null device (ACO disassembly, shadelab isa), phong_exact's fragment shader minus phong_unnormalized's, counted per operation class; agrees when at least the 9 claimed operations are there with every claimed class, disagrees when fewer, partly when as many in other classes".into(),
                reason: "the GPU compiler turns the normalisation into one reciprocal square root and multiplications (fused multiply-adds): no division".into(),
            }
        })
        .collect()
}

/// The software column (timed now on `scene`, into `out`/software/, unless `--no-software`),
/// the static cost from `opts.static_cost`, the cost models of `opts.costs` over this run's
/// timings (`rows`), the speed table, its summary, and the op-count rows added to `claims`.
pub fn judge(
    opts: &super::BenchOptions,
    (scene, out): (&crate::scene::Scene, &std::path::Path),
    methods: &[&'static crate::method::Method],
    rows: &[MethodTiming],
    claims: &mut Vec<super::ClaimCheck>,
) -> (Vec<SpeedClaim>, StaticCost) {
    let sw = software_column(scene, methods, out, opts.software_column);
    let (isa, source) = load(&opts.static_cost, methods);
    let name = scene.name.clone();
    let mut ev = Evidence::new().with(super::cost::TimedScene {
        scene: name.clone(),
        methods: rows.to_vec(),
        link: |_, _| "bench.json".into(),
    });
    if let Some(b) = &sw.bench {
        ev.push(super::software::cost::SoftwareScene {
            scene: name,
            evidence: "software/bench.json".into(),
            bench: b.clone(),
        });
    }
    if let Some(r) = &isa {
        ev.push(crate::isa::cost::Compiled {
            report: r.clone(),
            evidence: "isa.json".into(),
        });
    }
    let speed = table(&opts.costs.models(&ev));
    let stat = summary(isa.as_ref(), source);
    claims.extend(op_count_checks(&stat));
    (speed, stat)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::{CostSource, Evidence};

    fn report(families: &[(&str, bool)], costs: &[(&str, f64)]) -> IsaReport {
        let fam = |(f, ok): &(&str, bool)| {
            serde_json::json!({"family": f, "supported": ok,
                "status": if *ok { "compiled".to_string() } else { "not supported by this driver: exit code 1".to_string() },
                "device_name": null, "driver_name": null, "driver_info": null, "elapsed_ms": null,
                "statistics": []})
        };
        let mut rows = Vec::new();
        for (f, _) in families.iter().filter(|(_, ok)| *ok) {
            for (m, it) in costs {
                rows.push(
                    serde_json::json!({"family": f, "method": m, "stage": "fragment",
                    "kind": "draw", "program": m, "statistics": {"inverse_throughput": it},
                    "ratio_to_phong_exact": {}, "hash": []}),
                );
            }
        }
        let mut r: IsaReport = serde_json::from_value(serde_json::json!({"version": 1,
            "precision": "f32", "scene": "s", "kernel_counts": [2, 3], "model": "m",
            "families": families.iter().map(fam).collect::<Vec<_>>(),
            "results": rows, "elapsed_s": 0.0}))
        .unwrap();
        crate::isa::table::fill_ratios(&mut r.results);
        r
    }

    fn cell<'a>(t: &'a [SpeedClaim], num: &str, model: &str) -> &'a Cell {
        let c = t
            .iter()
            .find(|c| c.num == num && c.den == PHONG_EXACT)
            .unwrap_or_else(|| panic!("no claim of {num}: {t:?}"));
        c.cells
            .iter()
            .find(|c| c.cost_model == *model)
            .unwrap_or_else(|| panic!("no {model} cell: {c:?}"))
    }

    /// A compiled family is a column judged by its static ratio (equal cost is not faster); a
    /// refused family is no column (bench.json's static_cost names it); a program a model did
    /// not measure is not_checked.
    #[test]
    fn every_compiled_family_is_a_column_judged_by_its_ratio() {
        let r = report(
            &[("amd:navi21", true), ("amd:bogus", false)],
            &[
                (PHONG_EXACT, 70.0),
                ("newton_raphson", 70.0),
                // 1/70 of phong_exact: within even the "50 times faster" claim.
                ("gouraud", 1.0),
            ],
        );
        let ev = Evidence::new().with(crate::isa::cost::Compiled {
            report: r,
            evidence: "isa.json".into(),
        });
        let models = crate::isa::cost::StaticCost.models(&ev);
        assert_eq!(models.len(), 1, "the refused family is no model");
        let t = table(&models);
        let c = cell(&t, "newton_raphson", "isa:amd:navi21");
        assert_eq!((c.ratio, c.verdict), (Some(1.0), Verdict::Disagrees));
        assert_eq!(c.ci95_low, None);
        assert_eq!(
            cell(&t, "gouraud", "isa:amd:navi21").verdict,
            Verdict::Agrees
        );
        // No model measured slerp: its claims are not in the table at all.
        assert!(t.iter().all(|c| c.num != "slerp"), "{t:?}");
        // Teeth: without any model there is no claim.
        assert!(table(&[]).is_empty());
    }

    /// The software column's pairs (timed against each other in the same rounds) are judged
    /// by their own interval; slower in every round disagrees.
    #[test]
    fn a_pair_timed_together_is_judged_by_its_own_interval() {
        let specs = claim_specs();
        let spec = specs.iter().find(|c| c.num == "newton_raphson").unwrap();
        let names: Vec<String> = ["newton_raphson", PHONG_EXACT].map(String::from).to_vec();
        let model = |values: Vec<Vec<f64>>| {
            let claims = super::super::software::judge_claims(&names, &values, None);
            let mut m = crate::isa::cost::StaticCost.models(&Evidence::new());
            assert!(m.is_empty());
            let pairs = super::super::software::cost::pairs("s", &claims);
            let fig = |n: &str| crate::cost::CostFigure {
                method: n.into(),
                value: None,
                ratio: Some(1.0),
                ci95_low: Some(0.5),
                ci95_high: Some(1.5),
                verdict: Verdict::Inconclusive,
                evidence: String::new(),
                note: String::new(),
            };
            m.push(crate::cost::CostModel {
                id: crate::cost::CostModelId::of(crate::cost::SOFTWARE),
                title: "software engine".into(),
                kind: crate::cost::CostKind::Interval,
                measure: crate::cost::Measure {
                    statistic: "frame time".into(),
                    unit: "ms".into(),
                },
                description: String::new(),
                precision: crate::method::Precision::F32,
                figures: vec![fig("newton_raphson"), fig(PHONG_EXACT)],
                pairs,
            });
            m
        };
        // newton_raphson at 0.9 of phong_exact in every round: agrees with "faster".
        let faster = vec![vec![9.0, 9.1, 8.9, 9.0, 9.2, 8.8, 9.0, 9.0], vec![10.0; 8]];
        let t = table(&model(faster));
        let c = cell(&t, spec.num, crate::cost::SOFTWARE);
        assert_eq!(c.verdict, Verdict::Agrees, "{c:?}");
        assert!((c.ratio.unwrap() - 0.9).abs() < 0.02, "{c:?}");
        assert!(c.ci95_high.unwrap() < 1.0 && c.note.contains("paired per round"));
        // Teeth: slower in every round disagrees (the figures alone would say inconclusive).
        let t = table(&model(vec![vec![11.0; 8], vec![10.0; 8]]));
        assert_eq!(
            cell(&t, spec.num, crate::cost::SOFTWARE).verdict,
            Verdict::Disagrees
        );
    }

    /// The software column times the claims' programs of the run and phong_exact, nothing else.
    #[test]
    fn the_software_column_times_the_claims_programs() {
        let m = |n| crate::method::find(n).unwrap();
        let ms = claim_methods(&[m("newton_raphson"), m("flat"), m("gouraud")]);
        let names: Vec<&str> = ms.iter().map(|m| m.name).collect();
        assert_eq!(names, ["newton_raphson", "gouraud", PHONG_EXACT]);
    }
}
