//! The inputs of [`super::answer`] taken from a run (errors per scene from compare, float32 and
//! float16; one cost model per measurement: lavapipe frame time across runs, lavapipe isolated
//! cost, the software engine, and per GPU family of `isa` the static cost of the float32 and
//! the float16 programs; the same per scene alone; tune's findings), and the papers' claims as
//! measured in each place, the input of the claims matrix ([`claims`]). The answer's HTML is
//! [`super::first_screen`].
use std::collections::BTreeMap;

pub mod matrix;
use matrix::{Measured, Place};

use super::answer::{self, Answer, SceneError};
use super::budget::METRICS;
use super::html::method_anchor;
use super::ReportData;
use crate::bench::cost::TimedScene;
use crate::bench::software::cost::SoftwareScene;
use crate::compare::Metric;
use crate::cost::{CostModel, CostModelId, Evidence, Registry};
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
                let metrics: BTreeMap<Metric, Option<f64>> =
                    METRICS.iter().map(|k| (*k, k.of(m))).collect();
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
        missing: missing_models(d),
    })
}

/// The static cost models this run lost: every family `isa` did not compile (a route not set
/// up, a family the driver refused), or all of them when isa did not run, with why.
pub fn missing_models(d: &ReportData) -> Vec<super::summary::Missing> {
    use super::summary::Missing;
    match &d.isa.f32 {
        Ok((r, _)) => r
            .families
            .iter()
            .filter(|f| !f.supported)
            .map(|f| Missing {
                cost_model: CostModelId::isa(&f.id, Precision::F32),
                why: f.status.clone(),
            })
            .collect(),
        Err(why) => vec![Missing {
            cost_model: CostModelId::of("isa"),
            why: format!("no static cost model: {why}"),
        }],
    }
}

/// Every claim as measured in each place (lavapipe bench per scene, the software engine per
/// scene, stress), each linked to its measurement, in that order.
pub fn claims_measured(d: &ReportData) -> Vec<Measured> {
    let place = |engine: &str, scene: Option<&str>| Place {
        engine: engine.into(),
        scene: scene.map(String::from),
    };
    let mut out = Vec::new();
    for s in &d.scenes {
        for (k, c) in s.bench.claims.iter().enumerate() {
            out.push(Measured {
                method: c.method.clone(),
                claim: c.claim.clone(),
                place: place("lavapipe", Some(&s.id)),
                verdict: c.verdict,
                basis: basis_text(&c.evidence, &c.how),
                link: format!("#{}", claim_anchor(&s.id, k)),
                detail: c.measured.clone(),
            });
        }
    }
    for s in &d.scenes {
        let Some(sw) = &s.software else { continue };
        for c in &sw.claims {
            let Some(j) = &c.software else { continue };
            out.push(Measured {
                method: c.num.clone(),
                claim: c.claim.clone(),
                place: place("software", Some(&s.id)),
                verdict: j.verdict,
                basis: "measured".into(),
                link: format!("{}/claims.md", s.software_dir),
                detail: format!(
                    "{} / {} per round: median {:.4}, 95% interval [{:.4}, {:.4}]",
                    c.num, c.den, j.median, j.ci95_low, j.ci95_high
                ),
            });
        }
    }
    for (k, c) in d.stress.claims.iter().enumerate() {
        out.push(Measured {
            method: c.method.clone(),
            claim: c.claim.clone(),
            place: place("stress", None),
            verdict: c.verdict,
            basis: "found".into(),
            link: format!("#stress--claim-{k}"),
            detail: c.measured.clone(),
        });
    }
    out
}

/// The papers' claims as one matrix ([`matrix::matrix`]): each claim (method, claim text)
/// against each place that measured it, one merged cell where every place agrees.
pub fn claims_matrix(d: &ReportData) -> String {
    matrix::matrix(&claims_measured(d))
}

/// A claim's basis for the matrix: "proven <= x, found y" for a proven bound, "found y" for a
/// found one, each with what the figures are of (`quantity`), "measured" otherwise, with the
/// measure its `how` names when it is one of bench's two timings (a speed claim is judged by
/// each: the matrix shows both).
fn basis_text(e: &crate::method::Evidence, how: &str) -> String {
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
        crate::method::Basis::Measured => {
            let timing = [
                ("measure: paired frame time", "measured: frame time"),
                ("measure: isolated cost", "measured: isolated cost"),
            ];
            timing
                .iter()
                .find(|(by, _)| how.starts_with(by))
                .map_or("measured", |(_, basis)| basis)
                .into()
        }
    }
}

/// The scene a report shows first: the most telling one, a curved mesh (the most triangles
/// first; the cube, flat-faced with 12 triangles, last). Stable: equal counts keep their order.
pub fn order_scenes(scenes: &mut [super::ReportScene]) {
    scenes.sort_by_key(|s| std::cmp::Reverse(s.scene.mesh.triangle_count()));
}
