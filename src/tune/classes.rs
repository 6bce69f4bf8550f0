//! The answer for `auto`: triangles in classes by their smallest z ([`super::domain::
//! CLASS_EDGES`]), and per class and cost model the cheapest candidate proven within the budget
//! over that class's own domain. Each class refits the same forms (same operations, other
//! coefficients) on [the class's smallest z, 1]; a form's cost is the one measured for the
//! mesh's file of that form (the compiled code does not depend on the coefficients' values,
//! only on the operations: tests/tune.rs compiles two coefficient sets and compares them).
use serde::Serialize;

use super::candidate::{Candidate, Family};
use super::choose::{self, Row};
use super::domain::{widened, MeshDomain, CLASS_EDGES};
use super::proof::{Lights, ProofEffort};
use crate::cost::CostModel;

/// How `auto` draws the classes' answers (tune.json `auto`).
pub const AUTO_NEEDS: &str = "per class and cost model, an answer that is a fitted form is \
     written as a method file (methods/classes/, one per class and form: its float32 \
     coefficients fitted on the class's domain, its `// shadelab-tuned:` line naming that proven \
     domain of z). Given to `--method-file` (a folder means every .glsl below it), each is a \
     tuned row, an auto candidate; `auto` orders its candidates by the chosen cost model and \
     draws a tuned row on a triangle only when the triangle's exact range of z (its smallest \
     N.N of the interpolated vertex normals, its longest normal, widened by the inputs' float32 \
     rounding) lies inside the row's proven domain, and its sampled colour error keeps the \
     budget there too. One program per class file; the costs are the files' own";

/// One class's answer under one cost model.
#[derive(Debug, Clone, Serialize)]
pub struct ClassAnswer {
    pub model: crate::cost::CostModelId,
    /// The form (`minimax d2`, `newton k1 seed d0`, a paper's name); null: none is cheaper
    /// than phong_exact within the budget here.
    pub form: Option<String>,
    /// Its float32 coefficients fitted on the class's domain, lowest degree first.
    pub coeffs: Vec<f64>,
    pub colour_bound: Option<f64>,
    /// The form's ratio to phong_exact under the model (its mesh-level file's).
    pub ratio: Option<f64>,
    /// The method file of the form with the class's coefficients (under the output folder,
    /// `methods/classes/ID.glsl`); null when the answer is none.
    pub file: Option<String>,
    /// The class's candidate answered (its file is written from it).
    #[serde(skip)]
    pub candidate: Option<Candidate>,
}

/// One class of triangles.
#[derive(Debug, Clone, Serialize)]
pub struct Class {
    /// The class holds the triangles whose smallest z lies in [z_from, z_to).
    pub z_from: f64,
    pub z_to: f64,
    pub triangles: usize,
    /// Covered pixels of those triangles at the render size.
    pub pixels: usize,
    /// The smallest z of its triangles (exact).
    pub z_min: f64,
    /// The proven domain of the class (widened as the mesh's).
    pub domain: [f64; 2],
    pub answers: Vec<ClassAnswer>,
}

/// The classes of `md` that hold triangles, each with its forms fitted and proven on its own
/// domain, not answered yet ([`Fitted::answer`]).
pub fn fit(md: &MeshDomain, lights: &Lights, b: &ProofEffort) -> Vec<Fitted> {
    let mut out = Vec::new();
    for (i, &from) in CLASS_EDGES.iter().enumerate() {
        let to = CLASS_EDGES.get(i + 1).copied().unwrap_or(f64::INFINITY);
        let inside = |z: f64| z >= from && z < to;
        let tris: Vec<usize> = (0..md.per_triangle.len())
            .filter(|&t| inside(md.per_triangle[t]))
            .collect();
        if tris.is_empty() {
            continue;
        }
        let z_min = tris
            .iter()
            .map(|&t| md.per_triangle[t])
            .fold(f64::INFINITY, f64::min);
        let pixels = md
            .per_pixel
            .iter()
            .filter(|p| inside(md.per_triangle[p.0 as usize]))
            .count();
        let dom = widened(z_min, md.largest_normal_length);
        let (cands, _) = super::fit_all("class", dom.lo, dom.hi);
        let rows = super::prove_all(cands, dom, lights, None, b);
        out.push(Fitted {
            class: Class {
                z_from: from,
                z_to: to.min(1.0),
                triangles: tris.len(),
                pixels,
                z_min,
                domain: [dom.lo, dom.hi],
                answers: Vec::new(),
            },
            rows,
        });
    }
    out
}

/// A class with its forms proven on its domain.
#[derive(Debug, Clone)]
pub struct Fitted {
    pub class: Class,
    pub rows: Vec<Row>,
}

impl Fitted {
    /// Whether the form `label` is proven within `budget` in `precision` on this class.
    pub fn within(&self, label: &str, precision: crate::method::Precision, budget: f64) -> bool {
        self.rows.iter().any(|r| {
            r.candidate.label() == label && r.bound(precision).is_some_and(|b| b.within(budget))
        })
    }

    /// The class answered for every model of `models` with the costs of the mesh's `rows`.
    pub fn answer(mut self, rows: &[Row], models: &[CostModel], budget: f64) -> Class {
        self.class.answers = models
            .iter()
            .map(|m| answer(&self.rows, rows, m, budget))
            .collect();
        self.class
    }
}

/// The cheapest form of `class_rows` proven within the budget whose mesh-level row (same
/// label) model `m` measured cheaper than phong_exact.
fn answer(class_rows: &[Row], rows: &[Row], m: &CostModel, budget: f64) -> ClassAnswer {
    let best = class_rows
        .iter()
        .filter(|r| r.candidate.family != Family::Reference)
        .filter(|r| r.bound(m.precision).is_some_and(|b| b.within(budget)))
        .filter_map(|r| {
            let mesh = rows
                .iter()
                .find(|x| x.candidate.label() == r.candidate.label())?;
            let f = m.figure(&mesh.candidate.id)?;
            f.cheaper().then_some((r, f.ratio.unwrap_or(f64::INFINITY)))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match best {
        Some((r, ratio)) => ClassAnswer {
            model: m.id.clone(),
            form: Some(r.candidate.label()),
            coeffs: r.candidate.coeffs.clone(),
            colour_bound: r.bound(m.precision).and_then(|b| b.colour),
            ratio: Some(ratio),
            file: None,
            candidate: Some(r.candidate.clone()),
        },
        None => ClassAnswer {
            model: m.id.clone(),
            form: None,
            coeffs: Vec::new(),
            colour_bound: None,
            ratio: None,
            file: None,
            candidate: None,
        },
    }
}

/// The classes as text: per class, its triangles and pixels and per model its form.
pub fn table(classes: &[Class]) -> String {
    let mut s = String::from("per class of triangles (by their smallest z), for auto:\n");
    for c in classes {
        let forms: Vec<String> = c
            .answers
            .iter()
            .map(|a| {
                format!(
                    "{} {}",
                    a.model,
                    a.form.as_deref().map_or("none".to_string(), |f| format!(
                        "{f} ({})",
                        choose::num(a.ratio)
                    ))
                )
            })
            .collect();
        s += &format!(
            "  z_min in [{}, {}): {} triangles, {} pixels, domain [{:.6}, {:.7}]: {}\n",
            c.z_from,
            c.z_to,
            c.triangles,
            c.pixels,
            c.domain[0],
            c.domain[1],
            forms.join("; ")
        );
    }
    s
}
