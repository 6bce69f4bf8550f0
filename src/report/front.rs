//! The inputs of [`super::answer`] taken from a run (errors per scene from compare, float32 and
//! float16; one cost model per measurement: lavapipe frame time across runs, lavapipe isolated
//! cost, the software engine, and per GPU family of `isa` the static cost of the float32 and
//! the float16 programs; the same per scene alone; tune's findings), and the papers' claims as
//! one matrix (claim x where it was measured), each verdict linked to its row. The answer's
//! HTML is [`super::first_screen`].
use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::answer::{self, Answer, SceneError};
use super::html::{esc, method_anchor};
use super::ReportData;
use crate::bench::cost::TimedScene;
use crate::bench::software::cost::SoftwareScene;
use crate::cost::{CostModel, Evidence, Registry};
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
    evidence_of(d, None)
}

/// [`evidence`] of scene `only` alone (without `isa`'s reports, which do not depend on the
/// scene), or of every scene.
fn evidence_of(d: &ReportData, only: Option<&str>) -> Evidence {
    let mut ev = Evidence::new();
    for s in d.scenes.iter().filter(|s| only.is_none_or(|o| o == s.id)) {
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
    if only.is_none() {
        for c in super::isa::compiled(&d.isa) {
            ev.push(c);
        }
    }
    ev
}

/// The models of `all` as measured on scene `id` alone: a model its own evidence makes (the
/// frame times) from it, the others (the isolated cost, the static costs: they do not depend
/// on the scene) as they are.
fn models_of_scene(
    d: &ReportData,
    id: &str,
    costs: &Registry,
    all: &[CostModel],
) -> Vec<CostModel> {
    let own = costs.models(&evidence_of(d, Some(id)));
    all.iter()
        .map(|m| {
            own.iter()
                .find(|o| o.id == m.id)
                .cloned()
                .unwrap_or_else(|| m.clone())
        })
        .collect()
}

/// The answer of a run under the cost models of `costs`, over every scene and per scene, with
/// tune's findings when the run has them.
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
    let models = costs.models(&evidence(d));
    let scene_models = scenes
        .iter()
        .map(|s| (s.clone(), models_of_scene(d, s, costs, &models)))
        .collect();
    answer::answer_with(answer::Inputs {
        scenes: &scenes,
        methods: &methods,
        errors: &scene_errors(d),
        models,
        scene_models,
        tuned: d.tuned.clone(),
    })
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
