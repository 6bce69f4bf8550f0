//! The corpus tables of `shadelab merge`: per method the distribution of error over the meshes
//! (median, p90 and max of the largest |dI| and of p99 |dI|; the share of meshes within each
//! budget), the worst meshes with their worst pixel, and the answer over the corpus (per
//! budget and cost model, the cheapest method within the budget on every mesh), written as
//! corpus.json (docs/corpus.schema.json), corpus.csv and index.html. A non-finite error counts
//! as infinite: it is never within a budget and sorts worst.
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use serde::Serialize;

use super::merge::{Merged, ShardDir};
use crate::analysis::stats::percentile;
use crate::auto::ErrorBudget;
use crate::bench::per_machine::MeshTiming;
use crate::compare::Metric;
use crate::cost::{CostModel, Evidence, Registry};
use crate::error::{Error, Result};
use crate::method::Precision;
use crate::output::write_atomic;
use crate::report::answer::{self, Answer, SceneError};
use crate::report::budget;

/// The summary metrics judged against the budgets: the answer's ([`budget::METRICS`]).
pub const METRICS: [Metric; 2] = budget::METRICS;

/// The budgets of the tables, the answer's fractions ([`budget::FRACTIONS`]): the largest
/// colour error a method may make (linear), each with its name in corpus.json (`1/255`).
pub fn budgets() -> Vec<(String, ErrorBudget)> {
    (budget::FRACTIONS.iter())
        .map(|&f| (budget::fraction_text(f), budget::limit_of(f)))
        .collect()
}
/// Worst meshes listed per method.
pub const WORST: usize = 5;

/// One metric's distribution over the meshes (null in JSON where infinite).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Distribution {
    pub metric: Metric,
    pub median: f64,
    pub p90: f64,
    pub max: f64,
    /// Meshes where the method had non-finite pixels (counted as infinite).
    pub non_finite_meshes: usize,
    /// Per budget (`1/255`...), the share of meshes whose metric is within it.
    pub share_within: BTreeMap<String, f64>,
}

/// A mesh among a method's worst.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WorstMesh {
    pub id: String,
    pub max_abs_error: f64,
    pub p99_abs_error: f64,
    /// (x, y) of the worst pixel in the mesh's image.
    pub max_error_pixel: Option<[u32; 2]>,
}

/// One method over the corpus.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodTable {
    pub name: String,
    pub meshes: usize,
    pub distributions: Vec<Distribution>,
    pub worst: Vec<WorstMesh>,
}

/// One value per method and mesh.
type Figures = Vec<(String, Vec<(String, f64, f64, Option<[u32; 2]>)>)>;

/// Per method, per ok mesh: (id, max, p99, worst pixel); non-finite or null is infinite.
fn figures(meshes: &[Merged]) -> Figures {
    let mut out: Figures = Vec::new();
    for m in meshes.iter().filter(|m| m.result.status == "ok") {
        let Some(s) = &m.result.summary else { continue };
        for row in s["methods"].as_array().into_iter().flatten() {
            let name = row["name"].as_str().unwrap_or("?").to_string();
            let nf = row[Metric::NonFinitePixels.name()].as_u64().unwrap_or(0) > 0;
            let val = |k: Metric| match row[k.name()].as_f64() {
                Some(v) if !nf && v.is_finite() => v,
                _ => f64::INFINITY,
            };
            let px = row["max_error_pixel"]
                .as_array()
                .and_then(|a| Some([a.first()?.as_u64()? as u32, a.get(1)?.as_u64()? as u32]));
            let fig = (m.result.id.clone(), val(METRICS[0]), val(METRICS[1]), px);
            match out.iter_mut().find(|(n, _)| *n == name) {
                Some((_, v)) => v.push(fig),
                None => out.push((name, vec![fig])),
            }
        }
    }
    out
}

fn distribution(metric: Metric, mut v: Vec<f64>) -> Distribution {
    let n = v.len().max(1) as f64;
    Distribution {
        metric,
        non_finite_meshes: v.iter().filter(|x| !x.is_finite()).count(),
        share_within: budgets()
            .into_iter()
            .map(|(b, e)| {
                let within = v.iter().filter(|x| **x <= e.get()).count();
                (b, within as f64 / n)
            })
            .collect(),
        median: percentile(&mut v, 50.0),
        p90: percentile(&mut v, 90.0),
        max: v.iter().copied().fold(0.0, f64::max),
    }
}

/// The per-method tables.
pub fn method_tables(meshes: &[Merged]) -> Vec<MethodTable> {
    figures(meshes)
        .into_iter()
        .map(|(name, v)| {
            let mut worst: Vec<WorstMesh> = v
                .iter()
                .map(|(id, max, p99, px)| WorstMesh {
                    id: id.clone(),
                    max_abs_error: *max,
                    p99_abs_error: *p99,
                    max_error_pixel: *px,
                })
                .collect();
            worst.sort_by(|a, b| {
                b.max_abs_error
                    .total_cmp(&a.max_abs_error)
                    .then(a.id.cmp(&b.id))
            });
            worst.truncate(WORST);
            MethodTable {
                meshes: v.len(),
                distributions: vec![
                    distribution(METRICS[0], v.iter().map(|f| f.1).collect()),
                    distribution(METRICS[1], v.iter().map(|f| f.2).collect()),
                ],
                worst,
                name,
            }
        })
        .collect()
}

/// What the corpus measured, as the cost sources read it: each mesh's bench ratios with its
/// machine, and the shards' `isa` report.
pub fn evidence(meshes: &[Merged], isa: Option<&crate::isa::cost::Compiled>) -> Evidence {
    let mut ev = Evidence::new();
    if let Some(c) = isa {
        ev.push(c.clone());
    }
    for m in meshes {
        let Some(ratios) = m.timing["bench_ratio_median"].as_object() else {
            continue;
        };
        ev.push(MeshTiming {
            machine: m.machine.clone(),
            mesh: m.result.id.clone(),
            ratios: ratios
                .iter()
                .map(|(n, r)| (n.clone(), r.as_f64().unwrap_or(f64::INFINITY)))
                .collect(),
        });
    }
    ev
}

/// Every ok mesh's error per method, as the report's budget check reads a scene's.
pub fn mesh_errors(meshes: &[Merged], precision: Precision) -> Vec<SceneError> {
    let mut v = Vec::new();
    for m in meshes.iter().filter(|m| m.result.status == "ok") {
        let Some(s) = &m.result.summary else { continue };
        for row in s["methods"].as_array().into_iter().flatten() {
            let count = |k: &str| row[k].as_u64().unwrap_or(0) as usize;
            v.push(SceneError {
                scene: m.result.id.clone(),
                method: row["name"].as_str().unwrap_or("?").to_string(),
                precision,
                covered_pixels: count("covered_pixels"),
                non_finite_pixels: count(Metric::NonFinitePixels.name()),
                metrics: METRICS
                    .iter()
                    .map(|k| (*k, row[k.name()].as_f64()))
                    .collect(),
                evidence: format!("meshes/{}/result.json", m.result.id),
            });
        }
    }
    v
}

/// The answer over the corpus: the report's rule ([`crate::report::answer::answer`]) with the
/// ok meshes as the scenes (a budget is met only on every one of them).
pub fn answer_of(meshes: &[Merged], precision: Precision, models: Vec<CostModel>) -> Answer {
    let errors = mesh_errors(meshes, precision);
    let scenes: Vec<String> = meshes
        .iter()
        .filter(|m| m.result.status == "ok")
        .map(|m| m.result.id.clone())
        .collect();
    let mut methods: Vec<String> = Vec::new();
    for e in &errors {
        if !methods.contains(&e.method) {
            methods.push(e.method.clone());
        }
    }
    answer::answer(&scenes, &methods, &errors, models)
}

/// corpus.json.
#[derive(Debug, Serialize)]
pub struct CorpusReport {
    pub schema_version: u32,
    pub config: super::Config,
    pub config_hash: String,
    pub meshes: usize,
    pub failed: Vec<FailedMesh>,
    pub shards: Vec<ShardInfo>,
    /// Whether the shards ran on more than one machine (time kept apart per machine).
    pub mixed_machines: bool,
    pub machines: Vec<String>,
    pub isa: String,
    pub methods: Vec<MethodTable>,
    /// The report's answer over the meshes (docs/answer.schema.json).
    pub answer: Answer,
}

/// A mesh that failed, with its error.
#[derive(Debug, Serialize)]
pub struct FailedMesh {
    pub id: String,
    pub error: String,
}

/// A shard in corpus.json.
#[derive(Debug, Serialize)]
pub struct ShardInfo {
    pub k: usize,
    pub n: usize,
    pub dir: String,
    pub machine: String,
}

/// Builds corpus.json's content from the checked shards and their meshes, with the cost models
/// of `costs`.
pub fn report(
    shards: &[ShardDir],
    meshes: &[Merged],
    isa: Option<&crate::isa::cost::Compiled>,
    costs: &Registry,
) -> CorpusReport {
    let first = &shards[0].manifest;
    let methods = method_tables(meshes);
    let models = costs.models(&evidence(meshes, isa));
    let precision = first.config.precision;
    let mut machines: Vec<String> = shards.iter().map(|s| s.manifest.machine.key()).collect();
    machines.sort();
    machines.dedup();
    CorpusReport {
        schema_version: super::SCHEMA_VERSION,
        config: first.config.clone(),
        config_hash: first.config_hash.clone(),
        meshes: meshes.len(),
        failed: meshes
            .iter()
            .filter(|m| m.result.status != "ok")
            .map(|m| FailedMesh {
                id: m.result.id.clone(),
                error: m.result.error.clone().unwrap_or_default(),
            })
            .collect(),
        shards: shards
            .iter()
            .map(|s| ShardInfo {
                k: s.manifest.shard.k,
                n: s.manifest.shard.n,
                dir: s.dir.display().to_string(),
                machine: s.manifest.machine.key(),
            })
            .collect(),
        mixed_machines: machines.len() > 1,
        machines,
        isa: isa.map_or_else(
            || "unavailable (no shard has isa/isa.json)".into(),
            |c| c.evidence.clone(),
        ),
        answer: answer_of(meshes, precision, models),
        methods,
    }
}

fn num(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        "inf".into()
    }
}

/// corpus.csv: one line per method and metric.
fn csv(w: &mut dyn Write, r: &CorpusReport) -> std::io::Result<()> {
    write!(w, "method,metric,meshes,median,p90,max,non_finite_meshes")?;
    for (b, _) in budgets() {
        write!(w, ",within_{}", b.replace('/', "_"))?;
    }
    writeln!(w)?;
    for t in &r.methods {
        for d in &t.distributions {
            write!(
                w,
                "{},{},{},{},{},{},{}",
                t.name,
                d.metric,
                t.meshes,
                num(d.median),
                num(d.p90),
                num(d.max),
                d.non_finite_meshes
            )?;
            for (b, _) in budgets() {
                write!(w, ",{}", d.share_within.get(&b).copied().unwrap_or(0.0))?;
            }
            writeln!(w)?;
        }
    }
    Ok(())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// index.html: the answer, the distributions and the failures, one offline page.
fn html(w: &mut dyn Write, r: &CorpusReport) -> std::io::Result<()> {
    writeln!(
        w,
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>shadelab corpus</title>"
    )?;
    writeln!(w, "<style>body{{font-family:sans-serif;margin:2em}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}td:first-child{{text-align:left}}</style></head><body>")?;
    writeln!(
        w,
        "<h1>Corpus: {} meshes, {} failed, {}x{}</h1>",
        r.meshes,
        r.failed.len(),
        r.config.width,
        r.config.height
    )?;
    if r.mixed_machines {
        writeln!(
            w,
            "<p><b>Shards ran on {} machines</b>: error merged, time kept per machine.</p>",
            r.machines.len()
        )?;
    }
    writeln!(
        w,
        "{}",
        crate::report::first_screen::section(&r.answer).replace(
            "<h2>Which method to use</h2>",
            "<h2>Answer: which method to use</h2>"
        )
    )?;
    writeln!(w, "<h2>Error over meshes</h2><table><tr><th>method</th><th>metric</th><th>median</th><th>p90</th><th>max</th><th>non-finite</th>")?;
    for (b, _) in budgets() {
        write!(w, "<th>within {b}</th>")?;
    }
    writeln!(w, "<th>worst mesh (pixel)</th></tr>")?;
    for t in &r.methods {
        for d in &t.distributions {
            let worst = t.worst.first().map_or(String::new(), |m| {
                format!("{} {:?}", m.id, m.max_error_pixel.unwrap_or_default())
            });
            write!(w, "<tr><td>{}</td><td>{}</td><td>{:.3e}</td><td>{:.3e}</td><td>{:.3e}</td><td>{}</td>", esc(&t.name), d.metric, d.median, d.p90, d.max, d.non_finite_meshes)?;
            for (b, _) in budgets() {
                let s = d.share_within.get(&b).copied().unwrap_or(0.0);
                write!(w, "<td>{:.0}%</td>", s * 100.0)?;
            }
            writeln!(w, "<td>{}</td></tr>", esc(&worst))?;
        }
    }
    writeln!(w, "</table><h2>Failed meshes</h2><ul>")?;
    for f in &r.failed {
        writeln!(w, "<li>{}: {}</li>", esc(&f.id), esc(&f.error))?;
    }
    writeln!(w, "</ul></body></html>")
}

/// Writes each mesh's result.json (as the shard wrote it), corpus.csv, index.html and, last (the
/// merge's completion marker), corpus.json into `out`.
pub fn write(out: &Path, r: &CorpusReport, meshes: &[Merged]) -> Result<()> {
    for m in meshes {
        crate::output::write_bytes_atomic(
            &out.join("meshes").join(&m.result.id).join("result.json"),
            &m.bytes,
        )?;
    }
    write_atomic(&out.join("corpus.csv"), |w| csv(w, r))?;
    write_atomic(&out.join("index.html"), |w| html(w, r))?;
    let mut json = serde_json::to_vec_pretty(r).map_err(|e| Error::output("corpus.json", e))?;
    json.push(b'\n');
    crate::output::write_bytes_atomic(&out.join("corpus.json"), &json)
}
