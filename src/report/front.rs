//! The report's first screen: the inputs of [`super::answer`] taken from a run (errors per scene
//! from compare, float32 and float16; one cost model per measurement: lavapipe frame time
//! across runs, lavapipe isolated cost, the software engine, and per GPU family of `isa` the
//! static cost of the float32 and the float16 programs), the answer table at the top of
//! index.html (one row per cost model, one column per budget), and the papers' claims as one
//! matrix (claim x where it was measured), each verdict linked to its row.
use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::answer::{self, Answer, SceneError};
use super::html::{esc, method_anchor};
use super::ReportData;
use crate::bench::cost::TimedScene;
use crate::bench::software::cost::SoftwareScene;
use crate::cost::{Evidence, Registry};
use crate::method::Precision;

/// The id of a method's row in a scene's metric table (the bench figures of the cost models).
pub fn row_anchor(scene: &str, method: &str) -> String {
    format!("scene-{scene}--row-{method}")
}

/// The id of claim `k` of a scene's bench claims.
pub fn claim_anchor(scene: &str, k: usize) -> String {
    format!("scene-{scene}--claim-{k}")
}

/// Every method's error on every scene (compare), the input of the budget checks.
pub fn scene_errors(d: &ReportData) -> Vec<SceneError> {
    let mut v = Vec::new();
    for s in &d.scenes {
        let f16 = s.summary_f16.as_ref().map(|x| (x, Precision::F16));
        for (sum, precision) in std::iter::once((&s.summary, Precision::F32)).chain(f16) {
            for m in &sum.methods {
                let evidence = match precision {
                    Precision::F32 => format!("index.html#{}", method_anchor(&s.id, &m.name)),
                    Precision::F16 => format!("{}/summary.json", s.compare_f16_dir),
                };
                let metrics: BTreeMap<String, Option<f64>> = ["max_abs_error", "p99_abs_error"]
                    .iter()
                    .map(|k| (k.to_string(), m.metric(k)))
                    .collect();
                v.push(SceneError {
                    scene: s.id.clone(),
                    method: m.name.clone(),
                    precision,
                    covered_pixels: m.covered_pixels,
                    non_finite_pixels: m.non_finite_pixels,
                    metrics,
                    evidence,
                });
            }
        }
    }
    v
}

/// What this run measured, as the cost sources read it: each scene's bench and software
/// timings, and `isa`'s reports (float32, float16).
pub fn evidence(d: &ReportData) -> Evidence {
    let mut ev = Evidence::new();
    for s in &d.scenes {
        ev.push(TimedScene {
            scene: s.id.clone(),
            methods: s.bench.methods.clone(),
            link: |scene, method| format!("index.html#{}", row_anchor(scene, method)),
        });
        if let Some(sw) = &s.software {
            ev.push(SoftwareScene {
                scene: s.id.clone(),
                evidence: format!("{}/bench.json", s.software_dir),
                bench: sw.clone(),
            });
        }
    }
    for c in super::isa::compiled(&d.isa) {
        ev.push(c);
    }
    ev
}

/// The answer of a run under the cost models of `costs`.
pub fn answer_of(d: &ReportData, costs: &Registry) -> Answer {
    let scenes: Vec<String> = d.scenes.iter().map(|s| s.id.clone()).collect();
    let mut methods: Vec<String> = Vec::new();
    for s in &d.scenes {
        for m in &s.summary.methods {
            if !methods.contains(&m.name) {
                methods.push(m.name.clone());
            }
        }
    }
    answer::answer(
        &scenes,
        &methods,
        &scene_errors(d),
        costs.models(&evidence(d)),
    )
}

/// `index.html#x` -> `#x` (the page links to itself), other paths unchanged.
fn href(e: &str) -> String {
    e.strip_prefix("index.html").unwrap_or(e).to_string()
}

/// `text`, linked to `evidence` when there is one.
fn linked(text: &str, evidence: &str) -> String {
    if evidence.is_empty() {
        esc(text)
    } else {
        format!("<a href=\"{}\">{}</a>", esc(&href(evidence)), esc(text))
    }
}

fn choice_html(c: &answer::Choice) -> String {
    let link = linked(&c.method, &c.cost_evidence);
    let err = if c.error_evidence.is_empty() {
        String::new()
    } else {
        format!(
            " <a class=\"err\" href=\"{}\" title=\"its error\">err</a>",
            esc(&href(&c.error_evidence))
        )
    };
    format!(
        "{link} <span class=\"ratio\">{}</span>{err}",
        esc(&answer::ratio_text(c))
    )
}

/// The words naming the scene that decides a cell, linked to the evidence (the counts in
/// the tooltip).
fn binding_html(c: &answer::Cell) -> Option<String> {
    let k = c.binding.as_ref()?;
    let scene = linked(&k.scene, &k.evidence);
    Some(format!(
        "<span class=\"bind\" title=\"{} of the {} methods cheaper than the answer that fail \
         the budget fail it on this scene; the cheapest: {}\">decided by {scene}</span>",
        k.ruled_out,
        k.cheaper_failing,
        esc(&k.cheapest)
    ))
}

/// The answer table (first on the page): one row per cost model, one column per budget.
pub fn answer_table(a: &Answer) -> String {
    let mut h = String::from(
        "<section id=\"answer\"><h2>Which method to use</h2><p class=\"lede\">Per cost model \
         and error budget (luminance |dI| against exact Phong in f64 on <em>every</em> scene, no \
         non-finite pixel; float16 rows: the float16 programs' errors): the cheapest method \
         measured cheaper than phong_exact with its cost ratio (below 1 is cheaper, interval in \
         brackets), the runner-up, and the scene that decides the cell. Data: \
         <a href=\"answer.json\">answer.json</a>, <a href=\"answer.md\">answer.md</a>.</p>\
         <table class=\"answer\" id=\"answer-table\"><thead><tr><th>cost model</th>",
    );
    for b in &a.budgets {
        let _ = write!(
            h,
            "<th data-budget=\"{}\">{}</th>",
            esc(&b.id),
            esc(&b.label)
        );
    }
    h += "</tr></thead><tbody>";
    for m in &a.cost_models {
        let _ = write!(
            h,
            "<tr data-model=\"{}\"><th scope=\"row\" title=\"{}\">{}</th>",
            esc(m.id.as_str()),
            esc(&m.description),
            esc(&m.title)
        );
        for b in &a.budgets {
            let Some(c) = a.cell(&b.id, m.id.as_str()) else {
                h += "<td>-</td>";
                continue;
            };
            let main = if c.nothing_cheaper {
                "<strong class=\"none\">nothing is cheaper than phong_exact</strong>".to_string()
            } else {
                format!("<strong>{}</strong>", choice_html(&c.answer))
            };
            let label = if c.nothing_cheaper { "closest" } else { "then" };
            let ru = c
                .runner_up
                .as_ref()
                .map(|r| format!("{label} {}", choice_html(r)));
            let parts: Vec<String> = ru.into_iter().chain(binding_html(c)).collect();
            let second = if parts.is_empty() {
                String::new()
            } else {
                format!("<div class=\"ru\">{}</div>", parts.join("; "))
            };
            let _ = write!(
                h,
                "<td id=\"{}\" data-budget=\"{}\" data-model=\"{}\" data-method=\"{}\" \
                 data-nothing=\"{}\" data-runner-up=\"{}\" data-binding=\"{}\">{main}{second}</td>",
                esc(&format!("answer-{}-{}", b.id, m.id)),
                esc(&b.id),
                esc(m.id.as_str()),
                esc(&c.answer.method),
                c.nothing_cheaper,
                esc(c.runner_up.as_ref().map_or("", |r| r.method.as_str())),
                esc(c.binding.as_ref().map_or("", |k| k.scene.as_str()))
            );
        }
        h += "</tr>";
    }
    h + "</tbody></table></section>"
}

/// One claim's verdicts per source: (verdict, basis, anchor or file).
type ClaimRow = BTreeMap<usize, (String, String, String)>;

/// The papers' claims as one matrix: each claim (method, text) against each place that
/// measured it (lavapipe bench per scene, the software engine per scene, stress).
pub fn claims_matrix(d: &ReportData) -> String {
    let mut sources: Vec<String> = Vec::new();
    let mut rows: BTreeMap<(String, String), ClaimRow> = BTreeMap::new();
    let mut put = |sources: &mut Vec<String>,
                   src: String,
                   m: &str,
                   c: &str,
                   v: (&str, String),
                   at: String| {
        let col = sources.iter().position(|s| *s == src).unwrap_or_else(|| {
            sources.push(src);
            sources.len() - 1
        });
        rows.entry((m.to_string(), c.to_string()))
            .or_default()
            .insert(col, (v.0.to_string(), v.1, at));
    };
    for s in &d.scenes {
        let src = format!("lavapipe: {}", s.id);
        for (k, c) in s.bench.claims.iter().enumerate() {
            let at = format!("#{}", claim_anchor(&s.id, k));
            put(
                &mut sources,
                src.clone(),
                &c.method,
                &c.claim,
                (c.verdict.as_str(), basis_text(&c.evidence)),
                at,
            );
        }
    }
    for s in &d.scenes {
        let Some(sw) = &s.software else { continue };
        let src = format!("software: {}", s.id);
        for c in &sw.claims {
            let Some(j) = &c.software else { continue };
            let at = format!("{}/claims.md", s.software_dir);
            put(
                &mut sources,
                src.clone(),
                &c.num,
                &c.claim,
                (j.verdict.as_str(), "measured".into()),
                at,
            );
        }
    }
    for (k, c) in d.stress.claims.iter().enumerate() {
        let at = format!("#stress--claim-{k}");
        put(
            &mut sources,
            "stress".into(),
            &c.method,
            &c.claim,
            (c.verdict.as_str(), "found".into()),
            at,
        );
    }
    let mut h = String::from(
        "<section id=\"claims\"><h2>The papers' claims</h2><p>Each claim against each place \
         that measured it; a verdict links to its measurement (the claim's row, with what was \
         measured and the rule), with its basis: proven (a proven upper bound beside the \
         value found), found (the worst sampled value only) or measured (not a bound).</p><div class=\"scroll\"><table class=\"sortable matrix\" \
         id=\"claims-matrix\"><thead><tr><th>method</th><th>claim</th>",
    );
    for s in &sources {
        let _ = write!(h, "<th>{}</th>", esc(s));
    }
    h += "</tr></thead><tbody>";
    for ((m, c), cells) in &rows {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td>",
            esc(m),
            super::formulas::cite(c)
        );
        for k in 0..sources.len() {
            match cells.get(&k) {
                Some((v, basis, at)) => {
                    let _ = write!(
                        h,
                        "<td class=\"verdict v-{}\"><a href=\"{}\">{}</a> <small>{}</small></td>",
                        esc(v),
                        esc(at),
                        esc(v),
                        esc(basis)
                    );
                }
                None => h += "<td class=\"na\">-</td>",
            }
        }
        h += "</tr>";
    }
    h + "</tbody></table></div></section>"
}

/// A claim's basis for the matrix: "proven <= x, found y" for a proven bound, "found y" for a
/// found one, each with what the figures are of (`quantity`), "measured" otherwise.
fn basis_text(e: &crate::method::Evidence) -> String {
    let num = |x: Option<f64>| x.map_or("null".into(), |v| format!("{v:.3e}"));
    let of = e
        .quantity
        .map_or(String::new(), |q| format!(" ({})", q.as_str()));
    match e.basis {
        crate::method::Basis::Proven => {
            format!(
                "proven <= {}, found {}{of}",
                num(e.proven_upper),
                num(e.found)
            )
        }
        crate::method::Basis::Found => format!("found {}{of}", num(e.found)),
        crate::method::Basis::Measured => "measured".into(),
    }
}

/// The scene a report shows first: the most telling one, a curved mesh (the most triangles
/// first; the cube, flat-faced with 12 triangles, last). Stable: equal counts keep their order.
pub fn order_scenes(scenes: &mut [super::ReportScene]) {
    scenes.sort_by_key(|s| std::cmp::Reverse(s.scene.mesh.triangle_count()));
}
