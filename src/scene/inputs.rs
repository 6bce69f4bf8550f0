//! Everything the GPU receives for a scene, computed once in f64 and rounded to f32 once
//! ([`SceneInputs`], [`Params`]). The truth widens the same rounded values back to f64, so GPU
//! and CPU start from bit-identical inputs.
use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};

use crate::geometry::Mesh;
use crate::method::formulas::{self, Lighting};
use crate::method::{Fragment, Geometry};
use crate::scene::{Interpolation, Scene, MAX_LIGHTS};

/// The uniform block of every program; twin of `Params` in glsl/common.glsl (std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Params {
    pub mvp: [[f32; 4]; 4],
    pub ambient: [f32; 4],
    pub diffuse: [f32; 4],
    pub specular: [f32; 4],
    pub light_dir: [[f32; 4]; MAX_LIGHTS],
    pub light_color: [[f32; 4]; MAX_LIGHTS],
    pub half_vec: [[f32; 4]; MAX_LIGHTS],
    pub const_color: [f32; 4],
}
/// Everything the GPU may receive for a scene, as f32, computed once in f64.
pub struct SceneInputs {
    pub width: u32,
    pub height: u32,
    pub interpolation: Interpolation,
    pub geometry: Geometry,
    /// Model-space positions, 3 corners per triangle.
    pub positions: Vec<[f32; 3]>,
    /// Unit view-space vertex normals per corner.
    pub view_normals: Vec<[f32; 3]>,
    /// Unit view-space flat normal per triangle, oriented like the sum of its vertex normals.
    pub flat_normals: Vec<[f32; 3]>,
    /// PN mid-edge normals (n110, n011, n101) per triangle, view space.
    pub pn_mids: Vec<[[f32; 3]; 3]>,
    /// Window-space position (x, y in pixels; Vulkan origin top-left, pixel centres at +0.5) per
    /// corner, computed in f64 from the f32 MVP and positions and rounded to f32: the span ends of
    /// the scanline methods (docs/formulas.md#scanline-emulation). Meaningless for a corner in
    /// front of the near plane ([`SceneInputs::near_clipped`]).
    pub window: Vec<[f32; 2]>,
    pub params: Params,
    pub light_count: u32,
    /// Back-face culling of every pass of this geometry (method, floor and id pass alike):
    /// the window-space winding of the front faces, or None for no culling.
    pub cull_front: Option<Winding>,
}

/// A window-space winding, as Vulkan's front-face state names it (framebuffer coordinates,
/// y down: the sign of `-1/2 sum(x_i y_(i+1) - x_(i+1) y_i)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Winding {
    CounterClockwise,
    Clockwise,
}

/// Triangles whose winding agrees with their vertex normals' sum, and those against it.
#[derive(Default)]
struct FacingCount {
    with: usize,
    against: usize,
}

impl FacingCount {
    fn add(&mut self, p: [DVec3; 3], normal_sum: DVec3) {
        if (p[1] - p[0]).cross(p[2] - p[0]).dot(normal_sum) >= 0.0 {
            self.with += 1;
        } else {
            self.against += 1;
        }
    }
}

fn f4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn f3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

fn d3(v: [f32; 3]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

fn widen(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// The PN-tessellated version of a mesh (model space): `level^2` sub-triangles per triangle.
fn tessellate(mesh: &Mesh, level: u32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let cap = mesh.positions.len() * (level * level) as usize;
    let (mut positions, mut normals) = (Vec::with_capacity(cap), Vec::with_capacity(cap));
    for (p, n) in mesh
        .positions
        .chunks_exact(3)
        .zip(mesh.normals.chunks_exact(3))
    {
        let p = [d3(p[0]), d3(p[1]), d3(p[2])];
        let n = [d3(n[0]), d3(n[1]), d3(n[2])];
        for (sp, sn) in formulas::pn_tessellate(p, n, level) {
            positions.extend(sp.map(f3));
            normals.extend(sn.map(f3));
        }
    }
    (positions, normals)
}

impl SceneInputs {
    /// Transforms the scene in f64: MVP, view-space normals (normal matrix = inverse transpose of
    /// the view's upper 3x3; the mesh is already in its fitted model space), flat and PN mid-edge
    /// normals from view-space positions, light directions and half vectors with the viewer at
    /// infinity (V = +Z in view space, docs/formulas.md#lighting-model). `geometry` selects the
    /// scene's triangles or their PN tessellation.
    pub fn new(scene: &Scene, geometry: Geometry) -> Self {
        let view = scene.camera.view();
        let proj = scene
            .camera
            .projection(scene.width as f64 / scene.height as f64);
        let mvp = (proj * view).to_cols_array_2d();
        let rot = DMat3::from_mat4(view);
        let normal_matrix = rot.inverse().transpose();
        let (positions, model_normals) = match geometry {
            Geometry::Mesh => (scene.mesh.positions.clone(), scene.mesh.normals.clone()),
            Geometry::PnTessellated(level) => tessellate(&scene.mesh, level),
        };
        let view_n: Vec<DVec3> = model_normals
            .iter()
            .map(|&n| (normal_matrix * d3(n)).normalize_or_zero())
            .collect();
        let view_p: Vec<DVec3> = positions
            .iter()
            .map(|&p| view.transform_point3(d3(p)))
            .collect();
        let mut facing = FacingCount::default();
        for (p, n) in view_p.chunks_exact(3).zip(view_n.chunks_exact(3)) {
            facing.add([p[0], p[1], p[2]], n[0] + n[1] + n[2]);
        }
        let mut flat_normals = Vec::with_capacity(positions.len() / 3);
        let mut pn_mids = Vec::with_capacity(positions.len() / 3);
        for (p, n) in view_p.chunks_exact(3).zip(view_n.chunks_exact(3)) {
            let p = [p[0], p[1], p[2]];
            let n = [n[0], n[1], n[2]];
            let mut flat = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if flat.dot(n[0] + n[1] + n[2]) < 0.0 {
                flat = -flat;
            }
            flat_normals.push(f3(flat));
            pn_mids.push(formulas::pn_mid_normals(p, n).map(f3));
        }
        let mut params = Params {
            mvp: mvp.map(|c| c.map(|x| x as f32)),
            ambient: f4(scene.material.ambient, 0.0),
            diffuse: f4(scene.material.diffuse, 0.0),
            specular: f4(scene.material.specular, scene.material.shininess),
            light_dir: [[0.0; 4]; MAX_LIGHTS],
            light_color: [[0.0; 4]; MAX_LIGHTS],
            half_vec: [[0.0; 4]; MAX_LIGHTS],
            const_color: [0.8, 0.8, 0.8, 1.0],
        };
        for (i, light) in scene.lights.iter().take(MAX_LIGHTS).enumerate() {
            let l = (rot * light.direction).normalize();
            let h = (l + DVec3::Z).normalize_or_zero();
            params.light_dir[i] = f4(l, 0.0);
            params.light_color[i] = f4(light.color, 0.0);
            params.half_vec[i] = f4(h, 0.0);
        }
        let mut inputs = SceneInputs {
            width: scene.width,
            height: scene.height,
            interpolation: scene.interpolation,
            geometry,
            positions,
            view_normals: view_n.into_iter().map(f3).collect(),
            flat_normals,
            pn_mids,
            window: Vec::new(),
            params,
            light_count: scene.lights.len().min(MAX_LIGHTS) as u32,
            cull_front: None,
        };
        inputs.window = inputs
            .clip_corners()
            .map(|c| {
                let w = inputs.to_window(c);
                [w.x as f32, w.y as f32]
            })
            .collect();
        let topo = crate::geometry::topology(&Mesh {
            positions: inputs.positions.clone(),
            normals: Vec::new(),
            source: String::new(),
        });
        if super::culls_back(scene.cull, &topo, facing.with, facing.against) {
            inputs.cull_front = Some(inputs.front_winding(&view_p));
        }
        inputs
    }

    /// The window-space winding of the triangles whose winding side (the side their
    /// vertex normals point to, for a mesh wound like its normals) faces the eye: the majority
    /// over the triangles in front of the near plane.
    fn front_winding(&self, view_p: &[DVec3]) -> Winding {
        let (mut ccw, mut cw) = (0usize, 0usize);
        for (t, p) in view_p.chunks_exact(3).enumerate() {
            let g = (p[1] - p[0]).cross(p[2] - p[0]);
            if g.dot(-p[0]) <= 0.0 {
                continue; // its winding side faces away
            }
            let w = [0, 1, 2].map(|k| self.window[3 * t + k]);
            let area: f64 = -0.5
                * (0..3)
                    .map(|i| {
                        let (a, b) = (w[i], w[(i + 1) % 3]);
                        f64::from(a[0]) * f64::from(b[1]) - f64::from(b[0]) * f64::from(a[1])
                    })
                    .sum::<f64>();
            if area > 0.0 {
                ccw += 1;
            } else if area < 0.0 {
                cw += 1;
            }
        }
        if ccw >= cw {
            Winding::CounterClockwise
        } else {
            Winding::Clockwise
        }
    }

    /// Clip-space position of every corner, in f64 from the uploaded f32 MVP and positions.
    pub fn clip_corners(&self) -> impl Iterator<Item = DVec4> + '_ {
        let m = DMat4::from_cols_array_2d(&self.params.mvp.map(|c| c.map(|x| x as f64)));
        self.positions
            .iter()
            .map(move |p| m * DVec4::new(p[0] as f64, p[1] as f64, p[2] as f64, 1.0))
    }

    /// Window-space x, y (pixels) of a clip-space position (Vulkan viewport, y down).
    pub fn to_window(&self, c: DVec4) -> DVec2 {
        let (w, h) = (self.width as f64, self.height as f64);
        DVec2::new((c.x / c.w * 0.5 + 0.5) * w, (c.y / c.w * 0.5 + 0.5) * h)
    }

    /// The first triangle with a corner in front of the near plane (Vulkan clip z < 0, or w <= 0),
    /// if any. The rasterizer clips such a triangle, so its window corners are not the ends of its
    /// spans: the scanline methods refuse the scene (docs/formulas.md#scanline-emulation, hazard).
    pub fn near_clipped(&self) -> Option<usize> {
        self.clip_corners()
            .position(|c| c.z < 0.0 || c.w <= 0.0)
            .map(|i| i / 3)
    }

    /// The lighting exactly as uploaded, widened to f64, for the truth evaluator.
    pub fn lighting(&self) -> Lighting {
        let p = &self.params;
        let lights: Vec<_> = (0..self.light_count as usize)
            .map(|i| {
                (
                    widen(p.light_dir[i]),
                    widen(p.light_color[i]),
                    widen(p.half_vec[i]),
                )
            })
            .collect();
        Lighting::new(
            widen(p.ambient),
            widen(p.diffuse),
            widen(p.specular),
            p.specular[3] as f64,
            &lights,
        )
    }

    /// What the f64 twin of a method sees in triangle `t` at `weights`, at the pixel whose
    /// centre is `pixel` (window space, as `gl_FragCoord.xy`).
    pub fn fragment(&self, t: usize, weights: DVec3, pixel: DVec2) -> Fragment {
        let w = |k: usize| {
            let v = self.window[3 * t + k];
            DVec2::new(v[0] as f64, v[1] as f64)
        };
        Fragment {
            weights,
            pixel,
            window: [w(0), w(1), w(2)],
            corner_normals: [0, 1, 2].map(|k| d3(self.view_normals[3 * t + k])),
            flat_normal: d3(self.flat_normals[t]),
            pn_mids: self.pn_mids[t].map(d3),
        }
    }

    /// The same inputs with the triangles in the order `order` (a permutation of the triangle
    /// indices): `auto` draws each method's triangles as one contiguous range.
    pub fn permuted(&self, order: &[usize]) -> SceneInputs {
        let corners = |v: &[[f32; 3]]| -> Vec<[f32; 3]> {
            order
                .iter()
                .flat_map(|&t| [v[3 * t], v[3 * t + 1], v[3 * t + 2]])
                .collect()
        };
        SceneInputs {
            width: self.width,
            height: self.height,
            interpolation: self.interpolation,
            geometry: self.geometry,
            positions: corners(&self.positions),
            view_normals: corners(&self.view_normals),
            flat_normals: order.iter().map(|&t| self.flat_normals[t]).collect(),
            pn_mids: order.iter().map(|&t| self.pn_mids[t]).collect(),
            window: order
                .iter()
                .flat_map(|&t| {
                    [
                        self.window[3 * t],
                        self.window[3 * t + 1],
                        self.window[3 * t + 2],
                    ]
                })
                .collect(),
            params: self.params,
            light_count: self.light_count,
            cull_front: self.cull_front,
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }

    /// The three vertex normals of triangle `t` (view space, float32 as uploaded), in f64.
    pub fn vertex_normals(&self, t: usize) -> [DVec3; 3] {
        [0, 1, 2].map(|k| {
            let v = self.view_normals[3 * t + k];
            DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
        })
    }
}
