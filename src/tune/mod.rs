//! `shadelab tune`: the best approximation of the inverse square root for a mesh's own angles,
//! proven and costed (docs/tune.md).
//!
//! 1. The domain ([`domain`]): per triangle the exact smallest z = N.N of its interpolated
//!    vertex normals, the mesh's [z_min, 1], the distribution of z (and of the dichotomy's
//!    factor) over the pixels it covers; or, for `--max-angle`, `prove`'s triangle (or edge)
//!    domain.
//! 2. The candidates ([`candidate`]): minimax polynomials of degree 0..4 for relative error on
//!    the domain (Remez, certified by equioscillation: [`remez`]), seeds with one or two Newton
//!    steps fitted for the error after the steps, and the papers' methods.
//! 3. Proven ([`proof`]): each candidate's length and colour error over the domain in float32
//!    and float16, rounding of coefficients and arithmetic included ([`rounded`]); within the
//!    budget only by proof.
//! 4. Costed through the registry of cost models ([`crate::costs`]): each candidate written
//!    as a method file, registered as a user method, measured by every model measured on
//!    demand; per model the cheapest proven within the budget and cheaper than phong_exact
//!    ([`choose`]), per class of triangles by z_min too ([`classes`]).
//! 5. The papers' published fits against the best of their degree ([`refit`]).
//!
//! Output: tune.json (docs/tune.schema.json), a table, the candidates' method files.
pub mod candidate;
pub mod check;
pub mod choose;
pub mod classes;
pub mod domain;
pub mod method_file;
mod output;
pub mod proof;
pub mod refit;
pub mod remez;

use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use self::candidate::{Candidate, Family};
use self::choose::{Answer, Row, RowCost};
use self::domain::MeshDomain;
pub use self::output::{table, write};
use self::proof::{Lights, ProofEffort};
use crate::auto::ErrorBudget;
use crate::cost::{CostModel, CostModelId, Evidence, IdKind, Registry};
use crate::engine::{Engine, Ready};
use crate::error::{Error, Result};
use crate::frame::IdFrame;
use crate::method::{self, Geometry, Method, Precision};
use crate::prove::interval::Interval;
use crate::scene::{Interpolation, Material, Scene, SceneInputs};

/// Version of tune.json (docs/tune.schema.json).
pub const SCHEMA_VERSION: u32 = 2;

/// Options of a run.
#[derive(Debug, Clone)]
pub struct TuneOptions {
    pub budget: ErrorBudget,
    /// The cost models to measure; empty: every model the registry measures on demand.
    pub cost_models: Vec<CostModelId>,
    pub proof: ProofEffort,
    /// Threads of the software engine's id pass.
    pub threads: usize,
    /// Progress lines on stderr.
    pub progress: bool,
}

/// What is tuned for.
pub enum Source<'a> {
    /// A mesh or a scene: its triangles, drawn at its render size.
    Scene {
        scene: &'a Scene,
        kind: &'static str,
        path: String,
    },
    /// Every triangle (or edge) whose vertex normals are pairwise at most this far apart.
    Angle {
        max_angle_deg: f64,
        domain: crate::prove::Domain,
    },
}

/// Where the candidates come from, as tune.json states it.
#[derive(Debug, Clone, Serialize)]
pub struct SourceInfo {
    /// mesh, scene or max_angle.
    pub kind: &'static str,
    pub path: Option<String>,
    pub max_angle_deg: Option<f64>,
    /// For max_angle: the domain of `prove` (triangle or edge).
    pub domain: Option<crate::prove::Domain>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// The renderer of the id pass (software or vulkan).
    pub engine: Option<&'static str>,
}

/// The domain the candidates are fitted on and proven over.
#[derive(Debug, Clone, Serialize)]
pub struct DomainInfo {
    pub z_range: [f64; 2],
    pub how: String,
    pub mesh: Option<MeshDomain>,
}

/// Seconds per step.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Timings {
    pub domain_s: f64,
    pub candidates_s: f64,
    pub files_s: f64,
    pub costs_s: f64,
    pub classes_s: f64,
    pub total_s: f64,
}

/// tune.json.
#[derive(Debug, Clone, Serialize)]
pub struct TuneReport {
    pub schema_version: u32,
    pub name: String,
    pub source: SourceInfo,
    /// The colour error budget (linear).
    pub budget: f64,
    pub domain: DomainInfo,
    pub lights: Lights,
    pub candidates: Vec<Row>,
    /// Candidates that could not be fitted, and why.
    pub skipped: Vec<String>,
    /// The answer in words where the domain makes the question moot: every interpolated
    /// normal is of unit length to float32's rounding, so no normalisation is needed
    /// ([`moot`]); null otherwise.
    pub note: Option<String>,
    pub cost_models: Vec<Answer>,
    pub classes: Vec<classes::Class>,
    /// How `auto` draws the classes' files (docs/tune.md).
    pub auto: &'static str,
    pub papers: Vec<refit::Refit>,
    pub timings: Timings,
}

/// The forms every run fits: (family, degree, Newton steps).
pub const FORMS: [(Family, usize, u32); 10] = [
    (Family::Minimax, 0, 0),
    (Family::Minimax, 1, 0),
    (Family::Minimax, 2, 0),
    (Family::Minimax, 3, 0),
    (Family::Minimax, 4, 0),
    (Family::Newton, 0, 1),
    (Family::Newton, 1, 1),
    (Family::Newton, 2, 1),
    (Family::Newton, 0, 2),
    (Family::Newton, 1, 2),
];

/// The method id of a form for `prefix` (`spot_minimax3`, `spot_newton1_seed2`).
pub fn form_id(prefix: &str, family: Family, d: usize, steps: u32) -> String {
    match family {
        Family::Newton => format!("{prefix}_newton{steps}_seed{d}"),
        _ => format!("{prefix}_minimax{d}"),
    }
}

/// float32's unit roundoff, 2^-24: a fit whose relative error is below it is as accurate as
/// float32 can hold 1/sqrt(z).
const F32_UNIT_ROUNDOFF: f64 = 1.0 / (1u64 << 24) as f64;

/// Every form fitted on [lo, hi] (lo at least 1e-3: 1/sqrt(z) has no relative fit at 0), then
/// the papers and phong_exact; the forms that cannot be fitted, with why.
///
/// A domain supports the degrees up to the first whose minimax fit is within float32's
/// rounding ([`F32_UNIT_ROUNDOFF`]): past it a polynomial (a minimax one, or a Newton seed) can
/// be no more accurate in float32, and on a narrow domain its coefficients grow as the inverse
/// powers of the width (a planar mesh, z in [0.999999, 1.0000004]: colour errors of 4e115
/// were proven for degree 3), so those forms are listed as not fitted, with why.
pub fn fit_all(prefix: &str, lo: f64, hi: f64) -> (Vec<Candidate>, Vec<String>) {
    let lo = lo.max(1e-3).min(hi - 1e-9);
    let (mut out, mut skipped) = (Vec::new(), Vec::new());
    // the lowest minimax degree within float32's rounding, and its error
    let mut enough: Option<(usize, f64)> = None;
    for (family, d, steps) in FORMS {
        let id = form_id(prefix, family, d, steps);
        if let Some((e, err)) = enough.filter(|&(e, _)| d > e) {
            skipped.push(format!(
                "{id}: the degree-{e} minimax fit is already within float32's rounding on z \
                 in [{lo:.9}, {hi:.9}] (relative error {err:.2e} <= 2^-24): a higher degree \
                 cannot be more accurate in float32, and its coefficients would only be \
                 ill-conditioned on a domain this narrow"
            ));
            continue;
        }
        let c = match family {
            Family::Newton => Candidate::newton(id.clone(), d, steps, lo, hi),
            _ => Candidate::minimax(id.clone(), d, lo, hi),
        };
        match c {
            Ok(c) => {
                let err = c.remez.as_ref().map(|r| r.upper);
                if let (Family::Minimax, None, Some(err)) = (family, enough, err) {
                    if err <= F32_UNIT_ROUNDOFF {
                        enough = Some((d, err));
                    }
                }
                out.push(c)
            }
            Err(why) => skipped.push(format!("{id}: {why}")),
        }
    }
    out.extend(candidate::papers());
    out.push(Candidate::reference());
    (out, skipped)
}

/// How far from 1 (2^-21, four float32 ulps of 1 above it, eight below) an interpolated
/// normal's z = N.N may be for the normal to count as of unit length to float32's rounding.
const UNIT_TO_ROUNDING: f64 = 1.0 / (1u64 << 21) as f64;

/// The answer in words when every interpolated normal is of unit length to float32's rounding
/// (its smallest and largest z = N.N before the inputs' widening, `z_lo` and `z_hi`, within
/// [`UNIT_TO_ROUNDING`] of 1: a planar mesh, or one whose vertex normals are all equal): then
/// no normalisation is needed and phong_unnormalized is exact there. None otherwise.
pub fn moot(z_lo: f64, z_hi: f64) -> Option<String> {
    ((1.0 - z_lo).abs() <= UNIT_TO_ROUNDING && (z_hi - 1.0).abs() <= UNIT_TO_ROUNDING).then(|| {
        format!(
            "no normalisation is needed here: every interpolated normal is of unit length to \
             float32's rounding (N.N in [{z_lo:.9}, {z_hi:.9}], within 2^-21 of 1: its vertex \
             normals are equal or nearly so), so phong_unnormalized is exact on this mesh and \
             costs least of the methods that shade with the normal"
        )
    })
}

/// An identifier made of `name`: lower case, runs of other characters one `_`, starting with
/// a letter (`stanford-bunny` -> `stanford_bunny`, `90deg` -> `m_90deg`).
pub fn prefix_of(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars().map(|c| c.to_ascii_lowercase()) {
        if c.is_ascii_alphanumeric() {
            s.push(c);
        } else if !s.is_empty() && !s.ends_with('_') {
            s.push('_');
        }
    }
    let s = s.trim_end_matches('_').to_string();
    if s.starts_with(|c: char| c.is_ascii_lowercase()) {
        s
    } else {
        format!("m_{s}")
    }
}

/// The lighting of a scene as the device receives it (float32 values).
fn lights_of(material: &Material, colours: Vec<[f64; 3]>) -> Lights {
    let f = |v: glam::DVec3| [v.x, v.y, v.z].map(|x| f64::from(x as f32));
    Lights {
        colours: colours
            .into_iter()
            .map(|c| c.map(|x| f64::from(x as f32)))
            .collect(),
        diffuse: f(material.diffuse),
        specular: f(material.specular),
        shininess: material.shininess,
    }
}

/// The id pass of `scene` at its render size: the software engine for screen-linear
/// interpolation, else the Vulkan renderer of the context in `ev`.
fn id_frame(scene: &Scene, ev: &Evidence, threads: usize) -> Result<(IdFrame, &'static str)> {
    let exact = method::phong_exact();
    let renderer;
    let engine = if scene.interpolation == Interpolation::ScreenLinear {
        Engine::Software { threads }
    } else {
        let ctx = ev
            .one::<std::sync::Arc<crate::gpu::vk::Context>>()
            .ok_or_else(|| {
                Error::Device("perspective interpolation: the id pass needs a Vulkan device".into())
            })?;
        renderer = crate::gpu::Renderer::new(ctx.clone());
        Engine::Vulkan(&renderer)
    };
    let ready = Ready::new(engine, scene, &[exact])?;
    let (_, ids) = ready.render(exact, true)?;
    let ids = ids.ok_or_else(|| Error::Internal("the id pass returned no id frame".into()))?;
    Ok((ids, engine.name()))
}

/// The domain, the lighting and the pixels' z of `source`.
fn domain_of(
    source: &Source,
    ev: &Evidence,
    threads: usize,
) -> Result<(String, SourceInfo, DomainInfo, Lights)> {
    match source {
        Source::Angle {
            max_angle_deg,
            domain,
        } => {
            let z = domain.z_range(*max_angle_deg);
            let light = crate::scene::DirectionalLight::default().color;
            Ok((
                format!("angle{}_{}", max_angle_deg.round(), domain.as_str()),
                SourceInfo {
                    kind: "max_angle",
                    path: None,
                    max_angle_deg: Some(*max_angle_deg),
                    domain: Some(*domain),
                    width: None,
                    height: None,
                    engine: None,
                },
                DomainInfo {
                    z_range: [z.lo, z.hi],
                    how: format!(
                        "prove's {} domain up to {max_angle_deg} deg: {}",
                        domain.as_str(),
                        domain.description()
                    ),
                    mesh: None,
                },
                lights_of(&Material::default(), vec![[light.x, light.y, light.z]]),
            ))
        }
        Source::Scene { scene, kind, path } => {
            let inputs = SceneInputs::new(scene, Geometry::Mesh);
            let (ids, engine) = id_frame(scene, ev, threads)?;
            let md = domain::of_mesh(&inputs, &ids);
            let colours = scene
                .lights
                .iter()
                .map(|l| [l.color.x, l.color.y, l.color.z])
                .collect();
            Ok((
                scene.name.clone(),
                SourceInfo {
                    kind,
                    path: Some(path.clone()),
                    max_angle_deg: None,
                    domain: None,
                    width: Some(scene.width),
                    height: Some(scene.height),
                    engine: Some(engine),
                },
                DomainInfo {
                    z_range: md.z_range,
                    how: "every triangle's exact smallest N.N of its interpolated float32 vertex \
                          normals (a quadratic over the triangle, minimised exactly), the \
                          smallest over the mesh up to the largest |n|^2, |N| widened by the \
                          inputs' float32 rounding as prove's (2.5e-7)"
                        .into(),
                    mesh: Some(md),
                },
                lights_of(&scene.material, colours),
            ))
        }
    }
}

/// Proves every candidate in both precisions over `z`; the sampled error over `pixels`.
pub fn prove_all(
    cands: Vec<Candidate>,
    z: Interval,
    lights: &Lights,
    pixels: Option<&[f64]>,
    b: &ProofEffort,
) -> Vec<Row> {
    cands
        .into_iter()
        .map(|c| Row {
            bounds: Precision::ALL
                .iter()
                .map(|&p| proof::prove(&c, p, z, lights, b))
                .collect(),
            sampled_length_error: pixels
                .map(|zs| proof::sampled_length_error(&c, zs.iter().copied())),
            file: None,
            not_costed: None,
            outside_budget_in: Vec::new(),
            costs: Vec::new(),
            candidate: c,
        })
        .collect()
}

/// The header lines of a candidate's method file: where it comes from and what is proven.
fn file_header(r: &Row, name: &str, budget: f64) -> Vec<String> {
    let mut h = vec![format!(
        "fitted for {name} on z in [{:.9}, {:.9}]",
        r.candidate.fitted_on.map_or(0.0, |f| f[0]),
        r.candidate.fitted_on.map_or(0.0, |f| f[1])
    )];
    for b in &r.bounds {
        h.push(format!(
            "{}: proven length error {}, colour error {} ({} the budget {budget:.6})",
            b.precision,
            choose::num(b.length_error),
            choose::num(b.colour),
            if b.within(budget) {
                "within"
            } else {
                "NOT within"
            }
        ));
    }
    h
}

/// Writes the tuned candidates' method files (proven on `domain`) into `out`/methods/ and
/// registers them as tuned rows (compiled now). A candidate whose float32 program is not
/// proven on `domain` (its length error not bounded below 1, as every loader checks again:
/// [`check::verify`]) gets no file and is costed nowhere: it is marked `not_costed` with why,
/// so it costs that candidate alone, never a cost model that would be handed a file its
/// compiler's child refuses.
fn write_and_register(
    rows: &mut [Row],
    name: &str,
    budget: f64,
    domain: Interval,
    out: &Path,
) -> Result<()> {
    let paths = write_files(rows, name, budget, domain, out)?;
    crate::gpu::shaders::register_user(&paths)
}

/// The files of [`write_and_register`], written and checked as every loader checks them (what
/// passes here loads in every child), not registered: their paths.
fn write_files(
    rows: &mut [Row],
    name: &str,
    budget: f64,
    domain: Interval,
    out: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let dir = out.join("methods");
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let mut paths = Vec::new();
    for r in rows.iter_mut() {
        let header = file_header(r, name, budget);
        let on = [domain.lo, domain.hi];
        if let Some(why) = method_file::tuned(&r.candidate, on).and_then(|t| unproven(&t)) {
            r.not_costed = Some(why);
            continue;
        }
        if let Some(text) = method_file::glsl(&r.candidate, &header, on) {
            let p = dir.join(format!("{}.glsl", r.candidate.id));
            crate::output::write_bytes_atomic(&p, text.as_bytes())?;
            r.file = Some(format!("methods/{}.glsl", r.candidate.id));
            paths.push(p);
        }
    }
    check::check_files(&paths)?;
    Ok(paths)
}

/// Costs the candidates of `rows` that can change an answer ([`mark_outside_budget`]) on
/// every cost model of `opts` (each model the candidates of its precision): the answer per
/// model and the models measured.
fn cost_all(
    registry: &Registry,
    opts: &TuneOptions,
    ev: &Evidence,
    rows: &mut [Row],
    fitted: &[classes::Fitted],
    budget: f64,
) -> Result<(Vec<Answer>, Vec<CostModel>)> {
    let ids = if opts.cost_models.is_empty() {
        registry.on_demand_ids()
    } else {
        opts.cost_models.clone()
    };
    let precisions: Vec<Precision> = [Precision::F32, Precision::F16]
        .into_iter()
        .filter(|p| ids.iter().any(|id| id.precision() == *p))
        .collect();
    mark_outside_budget(rows, fitted, &precisions, budget);
    let mut by_precision = Vec::new();
    for p in [Precision::F32, Precision::F16] {
        let mut methods = vec![method::phong_exact()];
        for r in rows.iter().filter(|r| costed_in(r, p)) {
            methods.push(method::find(&r.candidate.id)?);
        }
        by_precision.push((p, methods));
    }
    let methods_of = |id: &CostModelId| {
        by_precision
            .iter()
            .find(|(p, _)| *p == id.precision())
            .map(|(_, m)| m.clone())
            .unwrap_or_default()
    };
    let measured = measure_all(registry, &ids, &methods_of, ev, opts.progress);
    let models: Vec<CostModel> = measured
        .iter()
        .filter_map(|(_, m)| m.as_ref().ok().cloned())
        .collect();
    for r in rows.iter_mut() {
        r.costs = models
            .iter()
            .map(|m| {
                let f = m.figure(&r.candidate.id);
                RowCost {
                    model: m.id.clone(),
                    ratio: f.and_then(|f| f.ratio),
                    verdict: f.map_or(crate::method::Verdict::NotChecked, |f| f.verdict),
                }
            })
            .collect();
    }
    let answers = measured
        .iter()
        .map(|(id, m)| match m {
            Ok(m) => choose::answer(rows, m, budget),
            Err(e) => choose::unmeasured(id, e),
        })
        .collect();
    Ok((answers, models))
}

/// Whether row `r` is costed by the models of precision `p`: a candidate (a paper's method
/// or one with a method file) not marked outside the budget in `p`.
fn costed_in(r: &Row, p: Precision) -> bool {
    r.candidate.family != Family::Reference
        && r.not_costed.is_none()
        && !r.outside_budget_in.contains(&p)
}

/// Marks the candidates that cannot change an answer in a precision of `precisions`: not
/// proven within `budget` there, on the mesh's domain nor (its form) on any class's of
/// `fitted` (the class answers take the mesh file's cost of a form). Such a candidate is costed
/// by no model of that precision (`outside_budget_in`); one outside in every precision is not
/// costed at all (`not_costed`), compiled nowhere.
fn mark_outside_budget(
    rows: &mut [Row],
    fitted: &[classes::Fitted],
    precisions: &[Precision],
    budget: f64,
) {
    for r in rows.iter_mut() {
        if r.candidate.family == Family::Reference || r.not_costed.is_some() {
            continue;
        }
        let label = r.candidate.label();
        let outside: Vec<Precision> = precisions
            .iter()
            .copied()
            .filter(|&p| {
                !r.bound(p).is_some_and(|b| b.within(budget))
                    && !fitted.iter().any(|c| c.within(&label, p, budget))
            })
            .collect();
        if !precisions.is_empty() && outside.len() == precisions.len() {
            let bounds: Vec<String> = precisions
                .iter()
                .map(|&p| {
                    let b = r.bound(p).and_then(|b| b.colour);
                    format!("{} in {p}", choose::num(b))
                })
                .collect();
            r.not_costed = Some(format!(
                "not costed: outside the budget: its proven colour error ({}) exceeds {} on \
                 the mesh's domain and its form's on every class's, so no answer can name it",
                bounds.join(", "),
                choose::num(Some(budget))
            ));
        }
        r.outside_budget_in = outside;
    }
}

/// Why a tuned form is not proven on its line's domain (the loaders' rule, [`check::verify`]),
/// or None when it is.
fn unproven(t: &crate::method::tuned::Tuned) -> Option<String> {
    let [lo, hi] = t.domain;
    match t.length_error {
        Some(b) if b < 1.0 => None,
        b => Some(format!(
            "not costed: its float32 program is not proven on z in [{lo:.9}, {hi:.9}] (its \
             length error there is bounded by {} only; a method file needs a bound below 1)",
            b.map_or("nothing finite".to_string(), |b| format!("{b:.3e}"))
        )),
    }
}

/// Writes each class answer that is a fitted form as a method file proven on the class's
/// domain, `out`/methods/classes/PREFIX_zI_FORM.glsl (I the class's index in
/// [`domain::CLASS_EDGES`]; the same form of one class is one file whatever the models), and
/// names it in the answer.
fn write_class_files(
    classes: &mut [classes::Class],
    prefix: &str,
    name: &str,
    budget: f64,
    out: &Path,
) -> Result<()> {
    let dir = out.join("methods").join("classes");
    let mut written: Vec<String> = Vec::new();
    for c in classes.iter_mut() {
        let i = domain::CLASS_EDGES
            .iter()
            .position(|&e| e == c.z_from)
            .unwrap_or(0);
        let models: Vec<(CostModelId, String)> = c
            .answers
            .iter()
            .filter_map(|a| Some((a.model.clone(), a.form.clone()?)))
            .collect();
        for a in c.answers.iter_mut() {
            let Some(cand) = &a.candidate else { continue };
            let Some(d) = cand.degree else { continue };
            let id = form_id(&format!("{prefix}_z{i}"), cand.family, d, cand.steps);
            let file = format!("methods/classes/{id}.glsl");
            a.file = Some(file.clone());
            if written.contains(&id) {
                continue;
            }
            let label = cand.label();
            let chosen: Vec<&str> = models
                .iter()
                .filter(|(_, f)| *f == label)
                .map(|(m, _)| m.as_str())
                .collect();
            let header = vec![
                format!(
                    "class of {name}'s triangles whose smallest z lies in [{}, {}): {} \
                     triangles, fitted and proven on z in [{:.9}, {:.9}]",
                    c.z_from, c.z_to, c.triangles, c.domain[0], c.domain[1]
                ),
                format!(
                    "the cheapest form proven within the budget {budget:.6} there under: {}",
                    chosen.join(", ")
                ),
            ];
            let cand = Candidate {
                id: id.clone(),
                ..cand.clone()
            };
            if let Some(text) = method_file::glsl(&cand, &header, c.domain) {
                std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
                crate::output::write_bytes_atomic(&out.join(&file), text.as_bytes())?;
                written.push(id);
            }
        }
    }
    Ok(())
}

/// Measures every model of `ids` on `methods`: the timed ones (lavapipe's) first and alone,
/// the others (through the compiler workers) as many at a time as [`crate::workers::parallel`].
fn measure_all(
    registry: &Registry,
    ids: &[CostModelId],
    methods: &(dyn Fn(&CostModelId) -> Vec<&'static Method> + Sync),
    ev: &Evidence,
    progress: bool,
) -> Vec<(CostModelId, std::result::Result<CostModel, String>)> {
    let one = |id: &CostModelId| {
        let t = Instant::now();
        let r = registry
            .measure(id, &methods(id), ev)
            .map_err(|e| e.to_string());
        if progress {
            log::info!("tune: {id} measured in {:.1} s", t.elapsed().as_secs_f64());
        }
        (id.clone(), r)
    };
    let timed = |id: &CostModelId| *id.kind() == IdKind::Lavapipe;
    let mut out: Vec<_> = ids.iter().filter(|i| timed(i)).map(one).collect();
    let rest: Vec<&CostModelId> = ids.iter().filter(|i| !timed(i)).collect();
    let queue = std::sync::Mutex::new(rest.iter().rev().copied().collect::<Vec<_>>());
    let done = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..crate::workers::parallel() {
            s.spawn(|| {
                while let Some(id) = queue.lock().ok().and_then(|mut q| q.pop()) {
                    let r = one(id);
                    if let Ok(mut d) = done.lock() {
                        d.push(r);
                    }
                }
            });
        }
    });
    let mut rest_done = done.into_inner().unwrap_or_default();
    rest_done.sort_by_key(|(id, _)| ids.iter().position(|i| i == id));
    out.extend(rest_done);
    out
}

/// Runs `tune` on one source, writing the method files into `out`.
pub fn run(
    source: &Source,
    opts: &TuneOptions,
    registry: &Registry,
    ev: &Evidence,
    out: &Path,
) -> Result<TuneReport> {
    if let Some(id) = opts.cost_models.iter().find(|id| !registry.knows(id)) {
        return Err(Error::Usage(format!(
            "--cost-model {id}: no cost model of that id is measured on demand; expected one \
             of: {}",
            registry.on_demand().join(", ")
        )));
    }
    let start = Instant::now();
    let mut timings = Timings::default();
    let (name, info, dom, lights) = domain_of(source, ev, opts.threads)?;
    let z = Interval::new(dom.z_range[0], dom.z_range[1]);
    timings.domain_s = start.elapsed().as_secs_f64();
    if opts.progress {
        log::info!(
            "tune: {name}: z in [{:.6}, {:.7}] ({:.1} s)",
            z.lo,
            z.hi,
            timings.domain_s
        );
    }
    let t = Instant::now();
    let prefix = prefix_of(&name);
    let (cands, skipped) = fit_all(&prefix, z.lo, z.hi);
    let pixels: Option<Vec<f64>> = dom
        .mesh
        .as_ref()
        .map(|m| m.per_pixel.iter().map(|p| p.1).collect());
    let mut rows = prove_all(cands, z, &lights, pixels.as_deref(), &opts.proof);
    timings.candidates_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let budget = opts.budget.get();
    write_and_register(&mut rows, &name, budget, z, out)?;
    timings.files_s = t.elapsed().as_secs_f64();
    // The classes' forms, proven first: a form within the budget on a class is costed.
    let t = Instant::now();
    let fitted = match &dom.mesh {
        Some(md) => classes::fit(md, &lights, &opts.proof),
        None => Vec::new(),
    };
    let fit_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let (answers, models) = cost_all(registry, opts, ev, &mut rows, &fitted, budget)?;
    timings.costs_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mut classes: Vec<classes::Class> = fitted
        .into_iter()
        .map(|f| f.answer(&rows, &models, budget))
        .collect();
    write_class_files(&mut classes, &prefix, &name, budget, out)?;
    timings.classes_s = fit_s + t.elapsed().as_secs_f64();
    let papers = refit::all().map_err(|e| Error::Internal(format!("tune: re-fit: {e}")))?;
    let note = match &dom.mesh {
        Some(m) => moot(m.z_min, m.largest_normal_length * m.largest_normal_length),
        None => moot(z.lo, z.hi),
    };
    timings.total_s = start.elapsed().as_secs_f64();
    Ok(TuneReport {
        schema_version: SCHEMA_VERSION,
        name,
        source: info,
        budget,
        domain: dom,
        lights,
        candidates: rows,
        skipped,
        note,
        cost_models: answers,
        classes,
        auto: classes::AUTO_NEEDS,
        papers,
        timings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planar mesh's domain (z in [0.999999444, 1.000000444], what tune found on one) gets the
    /// fits it supports: degree 1 is within float32's rounding there, so degrees 2 to 4 and the
    /// Newton seed of degree 2 are not fitted, each with why (their coefficients, ill-conditioned,
    /// gave proven colour errors of 4e115). Teeth: a wide domain fits every form.
    /// A candidate proven within the budget (mesh-wide, or its form on a class) is costed; one
    /// outside it in every precision is marked "not costed: outside the budget" and costed
    /// nowhere. Teeth: the budget set just below a costed candidate's bound puts it outside.
    #[test]
    fn only_candidates_within_the_budget_are_costed() {
        let z = Interval::new(0.8, 1.0000005);
        let lights = lights_of(&Material::default(), vec![[1.0; 3]]);
        let (cands, _) = fit_all("b", z.lo, z.hi);
        let mut rows = prove_all(cands, z, &lights, None, &ProofEffort::default());
        for r in &mut rows {
            r.file = Some(format!("methods/{}.glsl", r.candidate.id));
        }
        let colour = |r: &Row| r.bound(Precision::F32).and_then(|b| b.colour);
        let mut bounds: Vec<f64> = rows.iter().filter_map(colour).collect();
        bounds.sort_by(f64::total_cmp);
        // a budget between the bounds: some candidates within, some outside
        let budget = bounds[bounds.len() / 2];
        let f32_only = [Precision::F32];
        let marked = |budget: f64, fitted: &[classes::Fitted]| {
            let mut rs = rows.clone();
            mark_outside_budget(&mut rs, fitted, &f32_only, budget);
            rs
        };
        let rs = marked(budget, &[]);
        for r in rs
            .iter()
            .filter(|r| r.candidate.family != Family::Reference)
        {
            let within = colour(r).is_some_and(|c| c <= budget);
            assert_eq!(costed_in(r, Precision::F32), within, "{}", r.candidate.id);
            if !within {
                let why = r.not_costed.as_deref().unwrap();
                assert!(why.starts_with("not costed: outside the budget"), "{why}");
            }
        }
        assert!(rs.iter().any(|r| r.not_costed.is_some()));
        assert!(rs.iter().any(|r| costed_in(r, Precision::F32)));
        // teeth: just below a costed candidate's bound, it is outside
        let edge = rows.iter().position(|r| colour(r) == Some(budget)).unwrap();
        let below = marked(budget * (1.0 - 1e-9), &[]);
        assert!(costed_in(&marked(budget, &[])[edge], Precision::F32));
        assert!(!costed_in(&below[edge], Precision::F32));
        // a class on which the form is within the budget keeps it costed
        let class = classes::Fitted {
            class: classes::Class {
                z_from: 0.99,
                z_to: 1.0,
                triangles: 1,
                pixels: 1,
                z_min: 0.99,
                domain: [0.99, 1.0000005],
                answers: Vec::new(),
            },
            rows: rows
                .iter()
                .map(|r| {
                    let mut c = r.clone();
                    for b in &mut c.bounds {
                        b.colour = Some(0.0);
                    }
                    c
                })
                .collect(),
        };
        let kept = marked(budget * (1.0 - 1e-9), std::slice::from_ref(&class));
        assert!(kept
            .iter()
            .filter(|r| r.candidate.family != Family::Reference)
            .all(|r| costed_in(r, Precision::F32)));
    }

    #[test]
    fn a_narrow_domain_gets_the_degrees_it_supports() {
        let ids = |c: &[Candidate]| -> Vec<String> {
            c.iter()
                .filter(|c| c.degree.is_some())
                .map(|c| c.id.clone())
                .collect()
        };
        let (c, skipped) = fit_all("p", 0.999999444, 1.000000444);
        assert_eq!(
            ids(&c),
            [
                "p_minimax0",
                "p_minimax1",
                "p_newton1_seed0",
                "p_newton1_seed1",
                "p_newton2_seed0",
                "p_newton2_seed1"
            ]
        );
        assert_eq!(skipped.len(), 4, "{skipped:?}");
        for (s, id) in
            skipped
                .iter()
                .zip(["p_minimax2", "p_minimax3", "p_minimax4", "p_newton1_seed2"])
        {
            assert!(
                s.starts_with(id) && s.contains("within float32's rounding"),
                "{s}"
            );
        }
        let (c, skipped) = fit_all("p", 0.5, 1.0);
        assert_eq!(ids(&c).len(), FORMS.len(), "{skipped:?}");
        assert!(skipped.is_empty(), "{skipped:?}");
    }

    /// A form whose float32 program is not proven on its domain gets no method file and is
    /// costed nowhere, with the reason; a proven one gets its file (teeth).
    #[test]
    fn a_candidate_not_proven_gets_no_file_and_says_why() {
        let z = Interval::new(0.999999444, 1.000000444);
        let good = Candidate::minimax("p_minimax1".into(), 1, z.lo, z.hi).unwrap();
        // coefficients of the size an ill-conditioned fit on this width gives
        let bad = Candidate {
            id: "p_minimax3".into(),
            degree: Some(3),
            coeffs: [1e20, -3e20, 3e20, -1e20_f64]
                .iter()
                .map(|&c: &f64| f64::from(c as f32))
                .collect(),
            ..good.clone()
        };
        let lights = lights_of(&Material::default(), vec![[1.0; 3]]);
        let mut rows = prove_all(vec![good, bad], z, &lights, None, &ProofEffort::default());
        let dir = tempfile::tempdir().unwrap();
        write_files(&mut rows, "p", 1.0 / 255.0, z, dir.path()).unwrap();
        assert_eq!(rows[0].file.as_deref(), Some("methods/p_minimax1.glsl"));
        assert!(rows[0].not_costed.is_none());
        assert!(rows[1].file.is_none());
        let why = rows[1].not_costed.as_deref().unwrap();
        assert!(
            why.contains("not proven on z in") && why.contains("bounded by"),
            "{why}"
        );
        assert!(!dir.path().join("methods/p_minimax3.glsl").exists());
    }

    /// The answer says no normalisation is needed only where every interpolated normal is of
    /// unit length to float32's rounding.
    #[test]
    fn no_normalisation_is_needed_only_at_unit_length() {
        let note = moot(0.999999944, 0.999999944).unwrap();
        assert!(note.contains("phong_unnormalized is exact"), "{note}");
        assert!(moot(1.0 - 1e-6, 1.0).is_none());
        assert!(moot(0.8, 1.0).is_none());
        assert!(moot(1.0, 1.0 + 1e-6).is_none());
    }
}
