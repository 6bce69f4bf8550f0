//! The seeds' speed claims as one table, a column per cost model, each named: lavapipe's
//! frame time and isolated cost (this run's paired intervals), the software engine (timed by
//! this run after lavapipe's rounds, its programs paired in their own rounds, written to
//! DIR/software/: [`software_column`]), and per AMD GPU family the static cost
//! (ACO's inverse throughput of the timed draw's fragment shader, `shadelab isa`). One verdict
//! rule for every column ([`factor_verdict`]); a static cost is one deterministic figure, no
//! interval, so it agrees or disagrees, never inconclusive. The op-count claim is judged per
//! family on the compiled instructions ([`crate::isa::claims::op_count`]).
//!
//! Where the static cost comes from ([`StaticCostSource`]): compiled now by `shadelab isa`'s
//! children (after the timed rounds, never during them), read from an isa.json (`--isa`), or
//! skipped (`--no-isa`). A family the driver refuses is a named `not_supported` cell.
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use super::claims::factor_verdict;
use super::software::claims::claim_specs;
use super::MethodTiming;
use crate::error::{Error, Result};
use crate::isa::IsaReport;
use crate::method::Verdict;

/// Where bench's static cost comes from.
#[derive(Debug, Clone, Default)]
pub enum StaticCostSource {
    /// Not asked for (`--no-isa`, and the library's default).
    #[default]
    Skip,
    /// An isa.json of `shadelab isa` (`--isa FILE`).
    File(PathBuf),
    /// Compiled now on [`crate::isa::DEFAULT_FAMILIES`] by `exe`'s children, the timed draw of
    /// `scene` (`None`: isa's default scene).
    Run {
        exe: PathBuf,
        scene: Option<PathBuf>,
    },
}

/// The column names other than the families'.
pub const FRAME_TIME: &str = "lavapipe frame time";
pub const ISOLATED: &str = "lavapipe isolated cost";
pub const SOFTWARE: &str = "software engine";

/// One cell: a measure's ratio `num / den` and its verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cell {
    /// [`FRAME_TIME`], [`ISOLATED`], [`SOFTWARE`] or `isa:<family>`.
    pub measure: String,
    pub ratio: Option<f64>,
    /// The 95% interval (timings); absent for a static cost (one deterministic figure).
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    /// agrees, disagrees, inconclusive, not_supported (the driver refused the family) or
    /// not_measured.
    pub verdict: String,
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
    pub op_count: Vec<crate::isa::claims::OpCountVerdict>,
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
    pub claims: Vec<super::software::SpeedClaim>,
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
            claims: Vec::new(),
        };
    }
    let ms = claim_methods(methods);
    let dir = out.join("software");
    let threads = crate::software::default_threads();
    let sw = super::software::SoftwareOptions {
        rounds: super::RoundsPlan {
            repeat: SOFTWARE_REPEAT,
            warmup: 2,
            until_ci_pct: None,
            max_time_s: super::DEFAULT_MAX_TIME_S,
        },
        threads,
        vulkan_bench: None,
        command_line: Vec::new(),
    };
    eprintln!(
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
            claims: r.claims,
        },
        Err(e) => SoftwareColumn {
            source: format!("not measured: the software engine failed: {e}"),
            claims: Vec::new(),
        },
    }
}

/// The software cell of claim `c` from `sw`'s judged claims.
fn software_cell(sw: &SoftwareColumn, claim: &str, num: &str, den: &str) -> Cell {
    let judged = sw
        .claims
        .iter()
        .find(|c| c.claim == claim && c.num == num && c.den == den)
        .and_then(|c| c.software.as_ref());
    match judged {
        Some(j) => Cell {
            measure: SOFTWARE.into(),
            ratio: Some(j.median).filter(|v| v.is_finite()),
            ci95_low: Some(j.ci95_low).filter(|v| v.is_finite()),
            ci95_high: Some(j.ci95_high).filter(|v| v.is_finite()),
            verdict: j.verdict.as_str().into(),
            note: format!(
                "paired per round in the software engine ({} rounds, {} not finite); {}",
                j.rounds, j.non_finite, sw.source
            ),
        },
        None if sw.claims.is_empty() => not_measured(SOFTWARE, &sw.source),
        None => not_measured(SOFTWARE, "a program of the ratio was not timed"),
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
        StaticCostSource::File(p) => match read(p) {
            Ok(r) => (Some(r), format!("read from {}", p.display())),
            Err(e) => (None, format!("not read: {e}")),
        },
        StaticCostSource::Run { exe, scene } => {
            if !std::path::Path::new(crate::isa::DEFAULT_DRIVER_FILES).is_file() {
                return (
                    None,
                    format!(
                        "not compiled: no RADV ICD at {}",
                        crate::isa::DEFAULT_DRIVER_FILES
                    ),
                );
            }
            let mut ms: Vec<&'static crate::method::Method> = methods.to_vec();
            let exact = crate::method::phong_exact();
            if !ms.iter().any(|m| m.name == exact.name) {
                ms.insert(0, exact);
            }
            let opts = crate::isa::IsaOptions {
                methods: ms,
                families: crate::isa::DEFAULT_FAMILIES.map(String::from).to_vec(),
                driver_files: PathBuf::from(crate::isa::DEFAULT_DRIVER_FILES),
                scene: scene.clone(),
                exe: exe.clone(),
                precision: crate::method::Precision::F32,
                probes: Vec::new(),
            };
            eprintln!(
                "bench: static cost (shadelab isa, {} families)",
                opts.families.len()
            );
            match crate::isa::run(&opts, &|line| eprintln!("isa: {line}")) {
                Ok(r) => (Some(r), "compiled now".into()),
                Err(e) => (None, format!("not compiled: {e}")),
            }
        }
    }
}

fn read(p: &std::path::Path) -> Result<IsaReport> {
    let text = std::fs::read_to_string(p).map_err(|e| Error::io(p, e))?;
    serde_json::from_str(&text).map_err(|e| Error::input(p, None, format!("not an isa.json: {e}")))
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

/// The verdict of a static ratio: [`factor_verdict`] on the degenerate interval [r, r]. A
/// "faster" claim (claimed below 1) needs a ratio strictly below 1: equal cost is not faster.
pub fn static_verdict(ratio: f64, claimed_below: f64) -> Verdict {
    let target = if claimed_below == 1.0 {
        1.0 - f64::EPSILON
    } else {
        claimed_below
    };
    factor_verdict(ratio, ratio, target)
}

/// A ratio interval of `num / den` from two rows' intervals to phong_exact: `num`'s own when
/// `den` is phong_exact (paired), else bounded from the two (not paired).
fn interval(
    a: Option<(f64, f64, f64)>,
    b: Option<(f64, f64, f64)>,
    den_is_exact: bool,
) -> Option<(f64, f64, f64, bool)> {
    let (alo, amid, ahi) = a?;
    if den_is_exact {
        return Some((alo, amid, ahi, true));
    }
    let (blo, bmid, bhi) = b?;
    (blo > 0.0).then(|| (alo / bhi, amid / bmid, ahi / blo, false))
}

fn timed_cell(measure: &str, iv: Option<(f64, f64, f64, bool)>, target: f64) -> Cell {
    match iv.filter(|(lo, _, hi, _)| lo.is_finite() && hi.is_finite()) {
        Some((lo, mid, hi, paired)) => Cell {
            measure: measure.into(),
            ratio: Some(mid),
            ci95_low: Some(lo),
            ci95_high: Some(hi),
            verdict: factor_verdict(lo, hi, target).as_str().into(),
            note: if paired {
                "paired per round"
            } else {
                "bounded from two intervals, not paired"
            }
            .into(),
        },
        None => not_measured(measure, "not measured in this run"),
    }
}

fn not_measured(measure: &str, note: &str) -> Cell {
    Cell {
        measure: measure.into(),
        ratio: None,
        ci95_low: None,
        ci95_high: None,
        verdict: "not_measured".into(),
        note: note.into(),
    }
}

/// The static cell of `num / den` on `family`.
fn static_cell(
    r: &IsaReport,
    family: &str,
    status: &str,
    num: &str,
    den: &str,
    target: f64,
) -> Cell {
    let measure = format!("isa:{family}");
    if !status.starts_with("compiled") {
        return Cell {
            verdict: "not_supported".into(),
            ..not_measured(&measure, status)
        };
    }
    let it = |m: &str| {
        r.row(family, m, "fragment", "draw")
            .and_then(|row| row.statistics.get("inverse_throughput").copied())
    };
    match (it(num), it(den)) {
        (Some(a), Some(b)) if b > 0.0 && a.is_finite() && b.is_finite() => Cell {
            measure,
            ratio: Some(a / b),
            ci95_low: None,
            ci95_high: None,
            verdict: static_verdict(a / b, target).as_str().into(),
            note: format!("fragment shader inverse throughput {a} / {b} busy cycles per wave (ACO's static model)"),
        },
        _ => not_measured(&measure, "a program of the ratio was not compiled"),
    }
}

/// Every seed speed claim whose programs are in `rows`, with a cell per measure.
pub fn table(
    rows: &[MethodTiming],
    isa: Option<&IsaReport>,
    sw: &SoftwareColumn,
) -> Vec<SpeedClaim> {
    let find = |n: &str| rows.iter().find(|r| r.name == n);
    let frame = |r: &MethodTiming| {
        (r.ratio_rounds > 0).then_some((r.ratio_ci95_low, r.ratio_median, r.ratio_ci95_high))
    };
    let iso = |r: &MethodTiming| {
        r.isolated_ratio_to_phong_exact
            .map(|i| (i.ci95_low, i.median, i.ci95_high))
    };
    let mut out = Vec::new();
    for c in claim_specs() {
        let (Some(a), Some(b)) = (find(c.num), find(c.den)) else {
            continue;
        };
        let exact = c.den == crate::method::PHONG_EXACT;
        let mut cells = vec![
            timed_cell(FRAME_TIME, interval(frame(a), frame(b), exact), c.target),
            timed_cell(ISOLATED, interval(iso(a), iso(b), exact), c.target),
            software_cell(sw, &c.claim, c.num, c.den),
        ];
        if let Some(r) = isa {
            for f in &r.families {
                cells.push(static_cell(r, &f.family, &f.status, c.num, c.den, c.target));
            }
        }
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
pub fn op_count_verdict(v: &crate::isa::claims::OpCountVerdict) -> Verdict {
    match v.verdict.as_str() {
        "holds" => Verdict::Agrees,
        "overstated" => Verdict::Disagrees,
        _ => Verdict::Partly,
    }
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
        md += &format!(" {} |", c.measure);
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
                claim: "normalisation costs 3 divisions + 3 multiplications + 2 additions + 1 square root (docs/formulas.md#exact-phong)".into(),
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
/// the static cost from `opts.static_cost`, the speed table, its summary, and the op-count rows
/// added to `claims`.
pub fn judge(
    opts: &super::BenchOptions,
    (scene, out): (&crate::scene::Scene, &std::path::Path),
    methods: &[&'static crate::method::Method],
    rows: &[MethodTiming],
    claims: &mut Vec<super::ClaimCheck>,
) -> (Vec<SpeedClaim>, StaticCost) {
    let sw = software_column(scene, methods, out, opts.software_column);
    let (isa, source) = load(&opts.static_cost, methods);
    let speed = table(rows, isa.as_ref(), &sw);
    let stat = summary(isa.as_ref(), source);
    claims.extend(op_count_checks(&stat));
    (speed, stat)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_static_ratio_agrees_or_disagrees_and_equal_is_not_faster() {
        assert_eq!(static_verdict(0.93, 1.0), Verdict::Agrees);
        assert_eq!(static_verdict(1.0, 1.0), Verdict::Disagrees);
        assert_eq!(static_verdict(1.06, 1.0), Verdict::Disagrees);
        assert_eq!(static_verdict(0.5, 0.5), Verdict::Agrees);
        assert_eq!(static_verdict(0.2, 0.02), Verdict::Disagrees);
        // Not a figure: never sorted as agreeing.
        assert_eq!(static_verdict(f64::NAN, 1.0), Verdict::Inconclusive);
    }

    fn report(families: &[(&str, bool)], costs: &[(&str, f64)]) -> IsaReport {
        let fam = |(f, ok): &(&str, bool)| {
            serde_json::json!({"family": f, "supported": ok,
                "status": if *ok { "compiled".to_string() } else { "not supported by this driver: exit code 1".to_string() },
                "device_name": null, "driver_name": null, "driver_info": null, "elapsed_ms": null,
                "statistics": []})
        };
        let mut rows = Vec::new();
        for (f, ok) in families.iter().filter(|(_, ok)| *ok) {
            let _ = ok;
            for (m, it) in costs {
                rows.push(
                    serde_json::json!({"family": f, "method": m, "stage": "fragment",
                    "kind": "draw", "program": m, "statistics": {"inverse_throughput": it},
                    "ratio_to_phong_exact": {}, "hash": []}),
                );
            }
        }
        serde_json::from_value(serde_json::json!({"version": 1, "precision": "f32",
            "scene": "s", "kernel_counts": [2, 3], "model": "m",
            "families": families.iter().map(fam).collect::<Vec<_>>(),
            "results": rows, "elapsed_s": 0.0}))
        .unwrap()
    }

    /// A refused family is a named not_supported cell; a compiled one is judged by its ratio.
    #[test]
    fn every_family_gets_a_named_cell() {
        let r = report(
            &[("navi21", true), ("bogus", false)],
            &[
                ("phong_exact", 70.0),
                ("newton_raphson", 70.0),
                ("gouraud", 14.0),
            ],
        );
        let rows: Vec<MethodTiming> = Vec::new();
        // No timing row: no claim (the table follows the run's methods).
        assert!(table(&rows, Some(&r), &SoftwareColumn::default()).is_empty());
        let c = static_cell(
            &r,
            "navi21",
            "compiled",
            "newton_raphson",
            "phong_exact",
            1.0,
        );
        assert_eq!(
            (c.measure.as_str(), c.verdict.as_str()),
            ("isa:navi21", "disagrees")
        );
        assert_eq!(c.ratio, Some(1.0));
        assert_eq!(c.ci95_low, None);
        let c = static_cell(&r, "navi21", "compiled", "gouraud", "phong_exact", 1.0);
        assert_eq!(c.verdict, "agrees");
        let c = static_cell(
            &r,
            "bogus",
            &r.families[1].status,
            "gouraud",
            "phong_exact",
            1.0,
        );
        assert_eq!(c.verdict, "not_supported");
        assert!(
            c.note.starts_with("not supported by this driver"),
            "{}",
            c.note
        );
        let c = static_cell(&r, "navi21", "compiled", "slerp", "phong_exact", 1.0);
        assert_eq!(c.verdict, "not_measured");
    }

    /// The software cell carries the software engine's paired interval and its verdict, and
    /// says where it comes from; without a software run it is not_measured and says why.
    #[test]
    fn the_software_cell_is_the_software_engines_verdict() {
        let specs = claim_specs();
        let spec = specs.iter().find(|c| c.num == "newton_raphson").unwrap();
        let names: Vec<String> = ["newton_raphson", "phong_exact"].map(String::from).to_vec();
        // newton_raphson at 0.9 of phong_exact in every round: agrees with "faster".
        let values = vec![vec![9.0, 9.1, 8.9, 9.0, 9.2, 8.8, 9.0, 9.0], vec![10.0; 8]];
        let sw = SoftwareColumn {
            source: "timed now in the software engine: D/software/bench.json".into(),
            claims: super::super::software::judge_claims(&names, &values, None),
        };
        let c = software_cell(&sw, &spec.claim, spec.num, spec.den);
        assert_eq!(
            (c.measure.as_str(), c.verdict.as_str()),
            (SOFTWARE, "agrees")
        );
        assert!((c.ratio.unwrap() - 0.9).abs() < 0.02, "{c:?}");
        assert!(c.ci95_high.unwrap() < 1.0 && c.note.contains("software/bench.json"));
        // Teeth: slower in every round disagrees.
        let slower = vec![vec![11.0; 8], vec![10.0; 8]];
        let sw2 = SoftwareColumn {
            claims: super::super::software::judge_claims(&names, &slower, None),
            ..sw.clone()
        };
        let c = software_cell(&sw2, &spec.claim, spec.num, spec.den);
        assert_eq!(c.verdict, "disagrees");
        // A claim whose programs were not timed, and no run at all.
        let other = specs.iter().find(|c| c.num == "gouraud").unwrap();
        let c = software_cell(&sw, &other.claim, other.num, other.den);
        assert_eq!(c.verdict, "not_measured");
        let none = SoftwareColumn {
            source: "skipped (--no-software)".into(),
            claims: Vec::new(),
        };
        let c = software_cell(&none, &spec.claim, spec.num, spec.den);
        assert_eq!(
            (c.verdict.as_str(), c.note.as_str()),
            ("not_measured", "skipped (--no-software)")
        );
    }

    /// The software column times the claims' programs of the run and phong_exact, nothing else.
    #[test]
    fn the_software_column_times_the_claims_programs() {
        let m = |n| crate::method::find(n).unwrap();
        let ms = claim_methods(&[m("newton_raphson"), m("flat"), m("gouraud")]);
        let names: Vec<&str> = ms.iter().map(|m| m.name).collect();
        assert_eq!(names, ["newton_raphson", "gouraud", "phong_exact"]);
    }
}
