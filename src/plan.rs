//! `shadelab plan`: what a scene needs, measured before anything is drawn. The mesh's topology
//! (closed and consistently oriented: back faces can be culled), the spread of each triangle's
//! vertex normals (which methods' measured validity ranges it stays inside), the triangles'
//! size and facing on screen, the lighting, and what the renderer will skip for it.
use std::sync::OnceLock;

use glam::DVec3;
use serde::Serialize;

use crate::analysis::stats::{histogram, percentile};
use crate::cases::grid::{self, Grid, Sweep};
use crate::cases::Case;
use crate::geometry::{topology, Topology};
use crate::method::{Geometry, METHODS};
use crate::scene::{Cull, Scene, SceneInputs};

/// Version of the plan JSON.
pub const SCHEMA_VERSION: u32 = 1;

/// A distribution: max, median, 99th percentile and a histogram.
#[derive(Debug, Clone, Serialize)]
pub struct Distribution {
    pub max: f64,
    pub p50: f64,
    pub p99: f64,
    /// (lower edge, upper edge, count); the last bin is closed.
    pub histogram: Vec<(f64, f64, usize)>,
}

fn distribution(values: &[f64], edges: &[f64]) -> Distribution {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let max = v.iter().copied().fold(0.0, f64::max);
    let histogram = histogram(&v, edges);
    Distribution {
        max,
        p50: percentile(&mut v, 50.0),
        p99: percentile(&mut v, 99.0),
        histogram,
    }
}

/// How a method's measured validity range compares with the scene.
#[derive(Debug, Clone, Serialize)]
pub struct MethodFit {
    pub name: String,
    /// `stress`'s f64 angle sweep (facing cases, threshold 1/255): the largest angle between
    /// vertex normals up to which the method's own formula stays within 1/255 (null: none).
    pub max_valid_angle_deg: Option<f64>,
    /// Triangles whose vertex normals spread wider than that.
    pub triangles_beyond: usize,
    /// No triangle beyond it.
    pub inside: bool,
}

/// Something the renderer skips (or would skip) for this scene, and why.
#[derive(Debug, Clone, Serialize)]
pub struct Skip {
    pub what: String,
    pub applies: bool,
    pub why: String,
}

/// The plan of a scene.
#[derive(Debug, Clone, Serialize)]
pub struct Plan {
    pub schema_version: u32,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub topology: Topology,
    pub closed_and_oriented: bool,
    /// Triangles whose winding (geometric normal) points the same way as their vertex normals'
    /// sum, and the opposite way.
    pub winding_with_normals: usize,
    pub winding_against_normals: usize,
    /// Max angle between two vertex normals of a triangle, degrees.
    pub normal_angle_deg: Distribution,
    /// Facing on screen (from the view-space geometric normal and the eye).
    pub back_facing: usize,
    pub front_facing: usize,
    /// Triangles with a corner in front of the near plane.
    pub near_clipped: usize,
    /// Window-space area of each triangle, pixels.
    pub area_px: Distribution,
    pub sub_pixel_triangles: usize,
    pub lights: usize,
    pub specular: bool,
    pub shininess: f64,
    /// The specular table of `specular_lut` holds this shininess exactly (an integer 1..255).
    pub shininess_in_table: bool,
    pub methods: Vec<MethodFit>,
    /// The cull mode the renderer uses for it (`cull` in the scene, `auto` by default).
    pub cull: Cull,
    pub skips: Vec<Skip>,
    /// The per-triangle choice of `auto` at an error budget (null when not asked for).
    pub auto: Option<AutoChoice>,
}

/// The choice of `auto` ([`crate::auto`]): per triangle, the cheapest candidate whose f64 error
/// on that triangle ([`crate::auto::colour_error`], max over a barycentric grid of samples,
/// against exact Phong with the scene's lighting), times 1 + margin, stays within the budget.
#[derive(Debug, Clone, Serialize)]
pub struct AutoChoice {
    pub budget: f64,
    pub margin: f64,
    pub samples_per_triangle: usize,
    /// The candidates cheapest first, with the isolated cost (ns per evaluation, median) that
    /// ordered them.
    pub order: Vec<(String, f64)>,
    /// Triangles per candidate, in `order`.
    pub triangles: Vec<(String, usize)>,
    /// Time to choose (the cost measurement excluded), ms.
    pub choice_ms: f64,
    /// Time to measure the candidates' isolated costs, ms.
    pub cost_ms: f64,
}

/// Threshold of the validity ranges, linear colour.
pub const THRESHOLD: f64 = 1.0 / 255.0;

/// Each method's f64 max valid angle from the facing cases of stress's angle sweep (every
/// other pixel), computed once per process.
pub fn validity_ranges() -> &'static Vec<(&'static str, Option<f64>)> {
    static RANGES: OnceLock<Vec<(&'static str, Option<f64>)>> = OnceLock::new();
    RANGES.get_or_init(|| {
        let specs: Vec<_> = Grid::specs()
            .into_iter()
            .filter(|(k, s)| *k == Sweep::Angle && s.elevation_deg < 90.0 && s.pixel % 2 == 0)
            .collect();
        let cases: Vec<Case> = specs.iter().map(|(_, s)| Case::new(*s)).collect();
        let gpu = Vec::new();
        let g = Grid {
            kinds: vec![Sweep::Angle; cases.len()],
            cases,
            gpu,
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let per = METHODS.len().div_ceil(threads);
        std::thread::scope(|s| {
            let handles: Vec<_> = METHODS
                .chunks(per)
                .map(|ms| {
                    let g = &g;
                    s.spawn(move || {
                        ms.iter()
                            .map(|m| {
                                let errs: Vec<_> = g
                                    .cases
                                    .iter()
                                    .map(|c| {
                                        let r = m.eval_f64(&c.fragment, &c.lighting);
                                        crate::cases::errors(c, r.color, r.normal)
                                    })
                                    .collect();
                                (m.name, grid::max_valid_angle(g, &errs, THRESHOLD))
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().unwrap_or_default())
                .collect()
        })
    })
}

fn d3(v: [f32; 3]) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

/// The candidates of `auto` ordered by isolated cost measured now on `ctx` (cheapest first,
/// [`crate::auto::order_by_cost`]), with the costs (ns per evaluation, median).
pub fn auto_order(
    ctx: &std::sync::Arc<crate::gpu::vk::Context>,
) -> crate::error::Result<Vec<(&'static crate::method::Method, f64)>> {
    let ev = crate::cost::Evidence::new().with(ctx.clone());
    let id = crate::cost::CostModelId::of(crate::cost::LAVAPIPE_ISOLATED);
    Ok(crate::auto::order_by_model(&crate::costs::builtin(), &id, &ev)?.0)
}

/// The plan with `auto`'s choice at `budget`, its candidates ordered by `order`
/// ([`auto_order`]); the choice is computed now (not cached) to time it.
pub fn plan_with_auto(
    scene: &Scene,
    order: &[(&'static crate::method::Method, f64)],
    budget: crate::auto::ErrorBudget,
    cost_ms: f64,
) -> Plan {
    let mut p = plan(scene);
    let inputs = SceneInputs::new(scene, Geometry::Mesh);
    let spec = crate::auto::AutoSpec::new(budget, order);
    let (_, s) = crate::auto::choose_summarised(&inputs, &spec, crate::auto::Cache::Bypass);
    p.auto = Some(AutoChoice {
        budget: s.budget,
        margin: s.margin,
        samples_per_triangle: s.samples_per_triangle,
        order: order
            .iter()
            .map(|(m, c)| (m.name.to_string(), *c))
            .collect(),
        triangles: s.triangles,
        choice_ms: s.choice_ms,
        cost_ms,
    });
    p
}

/// What the renderer skips for a scene culled as `cull` says (`culls`: whether it does), and why.
fn skips(cull: Cull, culls: bool, topo: &Topology, back: usize) -> Vec<Skip> {
    let mut skips = vec![Skip {
        what: "back faces".into(),
        applies: culls,
        why: match (cull, topo.closed_and_oriented()) {
            (Cull::None, _) => "cull = \"none\" in the scene".into(),
            (Cull::Back, _) => "cull = \"back\" in the scene".into(),
            (Cull::Auto, true) if culls => format!(
                "the mesh is closed and consistently oriented: the {back} back-facing triangles \
                 are hidden by front faces; culled in every pass (the id pass too)"
            ),
            (Cull::Auto, true) => "closed and oriented, but its winding disagrees with its \
                                   vertex normals on most triangles: not culled"
                .into(),
            (Cull::Auto, false) => format!(
                "not closed or not consistently oriented ({} boundary, {} non-manifold, {} \
                 inconsistent edges): a back face may be visible, nothing is culled",
                topo.boundary_edges, topo.non_manifold_edges, topo.inconsistent_edges
            ),
        },
    }];
    let normal = crate::gpu::TIMING_NORMAL_TARGET;
    skips.push(Skip {
        what: "normal target".into(),
        applies: !normal,
        why: if normal {
            "drawn in every pass".into()
        } else {
            "drawn only when read: compare and verify read it, `render` only with --normals; \
             timed draws (bench, skips) leave it out"
                .into()
        },
    });
    let prepass = crate::gpu::TIMING_PREPASS;
    skips.push(Skip {
        what: "occluded fragments (depth pre-pass or front-to-back order)".into(),
        applies: prepass,
        why: if prepass {
            "a depth-only pre-pass draws every triangle first; the shading pass tests \
             LESS_OR_EQUAL"
                .into()
        } else {
            "not skipped by default: `shadelab skips` times a depth pre-pass and \
             front-to-back order against the default draw of this scene, paired"
                .into()
        },
    });
    skips
}

/// Measures what `scene` needs.
pub fn plan(scene: &Scene) -> Plan {
    let topo = topology(&scene.mesh);
    let inputs = SceneInputs::new(scene, Geometry::Mesh);
    let n = inputs.triangle_count();
    let view = scene.camera.view();
    let mut angles = Vec::with_capacity(n);
    let mut areas = Vec::with_capacity(n);
    let (mut with, mut against, mut back, mut front) = (0, 0, 0, 0);
    for t in 0..n {
        let vn = [0, 1, 2].map(|k| d3(inputs.view_normals[3 * t + k]));
        let max_angle = [(0, 1), (1, 2), (0, 2)]
            .iter()
            .map(|&(a, b)| vn[a].angle_between(vn[b]).to_degrees())
            .fold(0.0, f64::max);
        angles.push(max_angle);
        let p = [0, 1, 2].map(|k| view.transform_point3(d3(inputs.positions[3 * t + k])));
        let g = (p[1] - p[0]).cross(p[2] - p[0]);
        if g.dot(vn[0] + vn[1] + vn[2]) >= 0.0 {
            with += 1;
        } else {
            against += 1;
        }
        // the eye is at the origin of view space
        if g.dot(-p[0]) < 0.0 {
            back += 1;
        } else {
            front += 1;
        }
        let w = [0, 1, 2].map(|k| inputs.window[3 * t + k]);
        let area = 0.5
            * ((f64::from(w[1][0]) - f64::from(w[0][0]))
                * (f64::from(w[2][1]) - f64::from(w[0][1]))
                - (f64::from(w[2][0]) - f64::from(w[0][0]))
                    * (f64::from(w[1][1]) - f64::from(w[0][1])))
            .abs();
        areas.push(area);
    }
    let near_clipped = inputs
        .clip_corners()
        .collect::<Vec<_>>()
        .chunks(3)
        .filter(|c| c.iter().any(|c| c.z < 0.0 || c.w <= 0.0))
        .count();
    let normal_angle_deg = distribution(
        &angles,
        &[0.0, 1.0, 2.0, 4.0, 8.0, 15.0, 30.0, 45.0, 60.0, 90.0, 180.0],
    );
    let methods = validity_ranges()
        .iter()
        .map(|&(name, max)| {
            let beyond = angles
                .iter()
                .filter(|&&a| max.is_none_or(|m| a > m))
                .count();
            MethodFit {
                name: name.into(),
                max_valid_angle_deg: max,
                triangles_beyond: beyond,
                inside: beyond == 0,
            }
        })
        .collect();
    let m = &scene.material;
    let specular = m.specular.max_element() > 0.0;
    let cull = scene.cull;
    let culls = crate::scene::culls_back(cull, &topo, with, against);
    let skips = skips(cull, culls, &topo, back);
    Plan {
        schema_version: SCHEMA_VERSION,
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: n,
        closed_and_oriented: topo.closed_and_oriented(),
        topology: topo,
        winding_with_normals: with,
        winding_against_normals: against,
        normal_angle_deg,
        back_facing: back,
        front_facing: front,
        near_clipped,
        sub_pixel_triangles: areas.iter().filter(|&&a| a < 1.0).count(),
        area_px: distribution(
            &areas,
            &[0.0, 1.0, 4.0, 16.0, 64.0, 256.0, 1024.0, 4096.0, f64::MAX],
        ),
        lights: scene.lights.len(),
        specular,
        shininess: m.shininess,
        shininess_in_table: m.shininess.fract() == 0.0 && (1.0..=255.0).contains(&m.shininess),
        methods,
        cull,
        skips,
        auto: None,
    }
}

impl Plan {
    /// The plan as text.
    pub fn text(&self) -> String {
        let mut s = format!(
            "scene {}: {} triangles at {}x{}\n",
            self.scene, self.triangles, self.width, self.height
        );
        let t = &self.topology;
        s += &format!(
            "mesh: {} vertices, {} edges; closed and consistently oriented: {} ({} boundary, {} non-manifold, {} inconsistent edges, {} degenerate triangles); winding with / against the vertex normals: {} / {}\n",
            t.vertices, t.edges, if self.closed_and_oriented { "yes" } else { "no" },
            t.boundary_edges, t.non_manifold_edges, t.inconsistent_edges, t.degenerate_triangles,
            self.winding_with_normals, self.winding_against_normals
        );
        let d = &self.normal_angle_deg;
        s += &format!(
            "angle between a triangle's vertex normals (degrees): max {:.2}, p99 {:.2}, median {:.2}\n",
            d.max, d.p99, d.p50
        );
        for (lo, hi, n) in &d.histogram {
            s += &format!("  {lo:>5} - {hi:<5} {n}\n");
        }
        let a = &self.area_px;
        s += &format!(
            "on screen: {} front-facing, {} back-facing, {} near-clipped; area (px) median {:.1}, p99 {:.1}, max {:.1}; {} under one pixel\n",
            self.front_facing, self.back_facing, self.near_clipped, a.p50, a.p99, a.max,
            self.sub_pixel_triangles
        );
        s += &format!(
            "lighting: {} light(s), specular {} (n = {}{})\n",
            self.lights,
            if self.specular { "on" } else { "off" },
            self.shininess,
            if self.shininess_in_table {
                ", in specular_lut's table"
            } else {
                ", not a table row"
            }
        );
        s += "methods whose f64 formula stays within 1/255 at every triangle's spread (stress's angle sweep):\n";
        for m in &self.methods {
            s += &format!(
                "  {:<32} valid to {:>7}  {}\n",
                m.name,
                m.max_valid_angle_deg
                    .map_or("none".into(), |a| format!("{a} deg")),
                if m.inside {
                    "inside".to_string()
                } else {
                    format!("{} triangles beyond", m.triangles_beyond)
                }
            );
        }
        if let Some(a) = &self.auto {
            s += &format!(
                "auto at an error budget of {:.6} (sampled f64 error x {} <= budget, {} samples per triangle; chosen in {:.0} ms, costs measured in {:.0} ms):\n",
                a.budget, 1.0 + a.margin, a.samples_per_triangle, a.choice_ms, a.cost_ms
            );
            for ((name, n), (_, cost)) in a.triangles.iter().zip(&a.order) {
                s += &format!("  {name:<20} {n:>8} triangles  ({cost:.2} ns per evaluation)\n");
            }
        }
        for k in &self.skips {
            s += &format!(
                "skip {}: {} ({})\n",
                k.what,
                if k.applies { "yes" } else { "no" },
                k.why
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn torus() -> Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
        crate::scene::load_scene(&path).unwrap()
    }

    #[test]
    fn plan_reads_the_topology_and_the_spread() {
        let p = plan(&torus());
        assert!(p.closed_and_oriented);
        assert_eq!(p.triangles, 2304);
        // Facing counted independently of the product's view-space test: by the sign of each
        // triangle's window-space area (the winding on screen). Which sign is "back" depends on
        // the winding convention, so either count may match; a torus shows both sides.
        let inputs = SceneInputs::new(&torus(), Geometry::Mesh);
        let negative = (0..p.triangles)
            .filter(|&t| {
                let w = [0, 1, 2].map(|k| inputs.window[3 * t + k].map(f64::from));
                (w[1][0] - w[0][0]) * (w[2][1] - w[0][1])
                    - (w[2][0] - w[0][0]) * (w[1][1] - w[0][1])
                    < 0.0
            })
            .count();
        assert!(
            p.back_facing == negative || p.back_facing == p.triangles - negative,
            "back {} front {}, negative window area {negative}",
            p.back_facing,
            p.front_facing
        );
        assert!(p.back_facing > 0 && p.front_facing > 0, "{p:?}");
        assert_eq!(p.front_facing + p.back_facing, p.triangles);
        let spread = p.normal_angle_deg.max;
        assert!(spread > 10.0 && spread < 20.0, "{spread}");
        let n: usize = p.normal_angle_deg.histogram.iter().map(|h| h.2).sum();
        assert_eq!(n, p.triangles, "every triangle in one bin");
        assert!(p.skips[0].applies, "a closed torus is culled");
        let normal = p.skips.iter().find(|k| k.what == "normal target").unwrap();
        assert_eq!(normal.applies, !crate::gpu::TIMING_NORMAL_TARGET);
        let exact = p
            .methods
            .iter()
            .find(|m| m.name == crate::method::PHONG_EXACT)
            .unwrap();
        assert!(exact.inside);
    }
}
