//! `auto`'s choice: per triangle, the cheapest method (in a given cost order) whose f64 error on
//! that triangle stays within an error budget, judged before drawing from the triangle's vertex
//! normals and the scene's lighting (lights, H, shininess) at a grid of barycentric samples.
use glam::DVec3;

use crate::scene::SceneInputs;

/// The sampled error is doubled before it is compared with the budget: the samples may miss
/// the peak between them.
pub const AUTO_MARGIN: f64 = 1.0;
/// Subdivisions of the barycentric sample grid per triangle edge ((n+1)(n+2)/2 samples).
pub const AUTO_GRID: usize = 6;

/// What `auto` needs: the candidates cheapest first (the last is the fallback) and the budget.
#[derive(Debug, Clone)]
pub struct AutoSpec {
    /// `auto` for the run's budget; `auto_<k>_255` and the like for a point of the budget curve
    /// ([`curve_name`]).
    pub name: String,
    pub order: Vec<&'static crate::method::Method>,
    /// Max abs colour error, linear.
    pub budget: f64,
}

/// The budgets of `auto`'s curve on bench's Pareto chart (issue 12): 1/1024, 1/255, 4/255,
/// 16/255.
pub const CURVE_BUDGETS: [f64; 4] = [1.0 / 1024.0, 1.0 / 255.0, 4.0 / 255.0, 16.0 / 255.0];

/// The name of `auto` at `budget` on the curve, an identifier like a method's:
/// `auto_<k>_255` or `auto_1_<k>` when the budget is k/255 or 1/k (to 1e-9), else
/// `auto_<budget in millionths>e_6`.
pub fn curve_name(budget: f64) -> String {
    let near = |a: f64| (a - a.round()).abs() < 1e-9 * a.abs().max(1.0);
    let k = budget * 255.0;
    if near(k) && k.round() >= 1.0 {
        return format!("auto_{}_255", k.round() as u64);
    }
    let inv = 1.0 / budget;
    if near(inv) && inv.round() >= 1.0 {
        return format!("auto_1_{}", inv.round() as u64);
    }
    format!("auto_{}e_6", (budget * 1e6).round() as u64)
}

/// What `auto` chose for a scene, for the outputs.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AutoSummary {
    /// `auto`, or [`curve_name`] for a point of bench's budget curve.
    #[serde(default = "auto_name")]
    pub name: String,
    pub budget: f64,
    pub margin: f64,
    pub samples_per_triangle: usize,
    /// (method, triangles), cheapest first.
    pub triangles: Vec<(String, usize)>,
    /// Time to choose, ms.
    pub choice_ms: f64,
}

impl AutoSummary {
    /// The summary of `pick` (indices into `spec.order`).
    pub fn new(spec: &AutoSpec, pick: &[usize], choice_ms: f64) -> Self {
        AutoSummary {
            name: spec.name.clone(),
            budget: spec.budget,
            margin: AUTO_MARGIN,
            samples_per_triangle: (AUTO_GRID + 1) * (AUTO_GRID + 2) / 2,
            triangles: spec
                .order
                .iter()
                .enumerate()
                .map(|(i, m)| (m.name.to_string(), pick.iter().filter(|&&k| k == i).count()))
                .collect(),
            choice_ms,
        }
    }
}

fn auto_name() -> String {
    "auto".into()
}

/// The per-triangle choice: index into `order` for every triangle of `inputs`.
pub fn choose(
    inputs: &SceneInputs,
    order: &[&'static crate::method::Method],
    budget: f64,
) -> Vec<usize> {
    let lighting = inputs.lighting();
    let n = AUTO_GRID;
    let weights: Vec<DVec3> = (0..=n)
        .flat_map(|i| (0..=n - i).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
            DVec3::new(1.0 - a - b, a, b)
        })
        .collect();
    let tris = inputs.triangle_count();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = tris.div_ceil(threads).max(1);
    let pick = |t: usize| -> usize {
        let frags: Vec<_> = weights
            .iter()
            .map(|&w| inputs.fragment(t, w, glam::DVec2::ZERO))
            .collect();
        let exact: Vec<DVec3> = frags
            .iter()
            .map(|f| {
                lighting.shade(crate::method::formulas::normalize_exact(
                    f.interpolated_normal(),
                ))
            })
            .collect();
        order
            .iter()
            .position(|m| {
                frags.iter().zip(&exact).all(|(f, e)| {
                    let c = (m.eval_f64)(f, &lighting).color;
                    let err = (c - *e).abs().max_element();
                    err.is_finite() && err * (1.0 + AUTO_MARGIN) <= budget
                })
            })
            .unwrap_or(order.len() - 1)
    };
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..tris)
            .step_by(chunk)
            .map(|start| {
                let pick = &pick;
                s.spawn(move || {
                    (start..(start + chunk).min(tris))
                        .map(pick)
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    })
}
