//! Scene + method -> float images (colour and shading normal), the id pass for the f64 truth,
//! and per-frame timing.
//!
//! All geometry set-up is computed in f64 on the CPU ([`SceneInputs`]) and rounded to f32 once
//! for upload. The same rounded values, widened back to f64, are what the truth evaluator
//! (src/truth.rs) uses, so GPU and CPU start from bit-identical inputs.
use std::sync::Arc;

use ash::vk as avk;
use glam::{DMat3, DVec3};

use crate::error::{Error, Result};
use crate::formulas::{self, Lighting};
use crate::mesh::Mesh;
use crate::methods::{specular_table, Fragment, Geometry, Method};
use crate::scene::{Interpolation, Scene, MAX_LIGHTS};
use crate::shaders;
use crate::vk::commands::ColorTarget;
use crate::vk::queries::timestamp_delta_ns;
use crate::vk::{
    Buffer, BufferDesc, Context, DescriptorSet, GraphicsPipeline, Image, ImageDesc, OneShot,
    PipelineDesc, QueryPool, Recorded, ShaderModule, VertexStream,
};

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

/// What a draw shades with: a method, or the constant-colour floor.
#[derive(Debug, Clone, Copy)]
pub enum Shading<'a> {
    Method(&'a Method),
    /// The same draw with a constant colour: the cost floor.
    Constant,
    /// A method's exact program under another name (`<method>_control`): a benchmark control
    /// that must time like the method itself.
    Control(&'a Method),
}

impl Shading<'_> {
    /// Name used in reports (`constant` for the floor, `<method>_control` for a control).
    pub fn name(&self) -> String {
        match self {
            Shading::Method(m) => m.name.to_string(),
            Shading::Constant => "constant".to_string(),
            Shading::Control(m) => format!("{}_control", m.name),
        }
    }

    /// The method whose program and inputs this draw uses, if any.
    pub fn method(&self) -> Option<&Method> {
        match *self {
            Shading::Method(m) | Shading::Control(m) => Some(m),
            Shading::Constant => None,
        }
    }
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
    pub params: Params,
    pub light_count: u32,
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
    /// Transforms the scene in f64: MVP, view-space normals (normal matrix = inverse transpose
    /// of the view's upper 3x3; the mesh is already in its fitted model space), flat and PN
    /// mid-edge normals from view-space positions, light directions and half vectors with the
    /// viewer at infinity (V = +Z in view space, FORMULAS.md 1.2). `geometry` selects the
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
        SceneInputs {
            width: scene.width,
            height: scene.height,
            interpolation: scene.interpolation,
            geometry,
            positions,
            view_normals: view_n.into_iter().map(f3).collect(),
            flat_normals,
            pn_mids,
            params,
            light_count: scene.lights.len().min(MAX_LIGHTS) as u32,
        }
    }

    /// The lighting exactly as uploaded, widened to f64, for the truth evaluator.
    pub fn lighting(&self) -> Lighting {
        let p = &self.params;
        Lighting {
            ambient: widen(p.ambient),
            diffuse: widen(p.diffuse),
            specular: widen(p.specular),
            shininess: p.specular[3] as f64,
            lights: (0..self.light_count as usize)
                .map(|i| {
                    (
                        widen(p.light_dir[i]),
                        widen(p.light_color[i]),
                        widen(p.half_vec[i]),
                    )
                })
                .collect(),
        }
    }

    /// What the f64 twin of a method sees in triangle `t` at `weights`.
    pub fn fragment(&self, t: usize, weights: DVec3) -> Fragment {
        Fragment {
            weights,
            corner_normals: [0, 1, 2].map(|k| d3(self.view_normals[3 * t + k])),
            flat_normal: d3(self.flat_normals[t]),
            pn_mids: self.pn_mids[t].map(d3),
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }

    /// Per-corner data of a stream, ready to upload.
    fn stream(&self, s: Stream) -> Vec<[f32; 3]> {
        let per_triangle = |f: &dyn Fn(usize) -> [f32; 3]| -> Vec<[f32; 3]> {
            (0..self.positions.len()).map(|i| f(i / 3)).collect()
        };
        match s {
            Stream::Normal => self.view_normals.clone(),
            Stream::Flat => per_triangle(&|t| self.flat_normals[t]),
            Stream::Corner(k) => per_triangle(&|t| self.view_normals[3 * t + k]),
            Stream::PnMid(k) => per_triangle(&|t| self.pn_mids[t][k]),
        }
    }
}

/// A vertex stream beyond the positions (location 0); see glsl/shade.vert.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stream {
    /// location 1, ATTR_NORMAL
    Normal,
    /// location 2, ATTR_FLAT
    Flat,
    /// locations 3..=5, ATTR_CORNERS
    Corner(usize),
    /// locations 6..=8, ATTR_PN
    PnMid(usize),
}

impl Stream {
    fn location(self) -> u32 {
        match self {
            Stream::Normal => 1,
            Stream::Flat => 2,
            Stream::Corner(k) => 3 + k as u32,
            Stream::PnMid(k) => 6 + k as u32,
        }
    }

    /// The streams a set of GLSL defines reads.
    fn for_defines(defines: &[&str]) -> Vec<Stream> {
        let mut out = Vec::new();
        for d in defines {
            match *d {
                "ATTR_NORMAL" => out.push(Stream::Normal),
                "ATTR_FLAT" => out.push(Stream::Flat),
                "ATTR_CORNERS" => out.extend((0..3).map(Stream::Corner)),
                "ATTR_PN" => out.extend((0..3).map(Stream::PnMid)),
                _ => {}
            }
        }
        out.sort_by_key(|s| s.location());
        out.dedup();
        out
    }
}

fn method_defines(m: &Method) -> Vec<&'static str> {
    m.inputs
        .iter()
        .flat_map(|i| i.defines().iter().copied())
        .collect()
}

/// A float image read back from the GPU, row-major from the top-left pixel.
#[derive(Debug, Clone)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear colour; alpha 1 on covered pixels, 0 on the background.
    pub color: Vec<[f32; 4]>,
    /// Shading normal the method used; w 1 where the method has a per-pixel normal.
    pub normal: Vec<[f32; 4]>,
}

impl Frame {
    /// Number of covered (non-background) pixels.
    pub fn covered(&self) -> usize {
        self.color.iter().filter(|c| c[3] > 0.0).count()
    }
}

/// The id pass: per pixel, the triangle index + 1 (0 = background) and the interpolation
/// weights the rasterizer used.
#[derive(Debug, Clone)]
pub struct IdFrame {
    pub width: u32,
    pub height: u32,
    pub prim: Vec<u32>,
    pub weights: Vec<[f32; 4]>,
}

/// The uploaded scene for one geometry: positions, the streams its methods need, the uniform
/// block and (when a method needs it) the specular table.
pub struct GpuScene {
    pub inputs: SceneInputs,
    positions: Buffer,
    streams: Vec<(Stream, Buffer)>,
    _ubo: Buffer,
    _lut: Option<Buffer>,
    set: DescriptorSet,
}

type Bindings<'a> = (Vec<VertexStream>, Vec<(u32, &'a Buffer)>);

impl GpuScene {
    /// The vertex streams and buffers a draw with `shading` binds; an error when the method
    /// draws another geometry or a stream it reads was not uploaded.
    fn buffers(&self, shading: Shading) -> Result<Bindings<'_>> {
        let f3 = |location| VertexStream {
            location,
            format: avk::Format::R32G32B32_SFLOAT,
            stride: 12,
        };
        let mut streams = vec![f3(0)];
        let mut buffers = vec![(0, &self.positions)];
        if let Some(m) = shading.method() {
            if m.geometry != self.inputs.geometry {
                return Err(Error::Usage(format!(
                    "{} draws {:?}, this upload holds {:?}",
                    m.name, m.geometry, self.inputs.geometry
                )));
            }
            for s in Stream::for_defines(&method_defines(m)) {
                let buf = self
                    .streams
                    .iter()
                    .find(|(k, _)| *k == s)
                    .map(|(_, b)| b)
                    .ok_or_else(|| {
                        Error::Usage(format!(
                            "{}: vertex stream {s:?} was not uploaded (prepare with this method)",
                            m.name
                        ))
                    })?;
                streams.push(f3(s.location()));
                buffers.push((s.location(), buf));
            }
        }
        Ok((streams, buffers))
    }
}

/// The uploads one run needs: one [`GpuScene`] per geometry its methods draw, the scene's own
/// triangles first.
pub struct Prepared {
    scenes: Vec<GpuScene>,
}

impl Prepared {
    /// The upload a method draws from.
    pub fn for_method(&self, m: &Method) -> &GpuScene {
        self.scenes
            .iter()
            .find(|g| g.inputs.geometry == m.geometry)
            .unwrap_or(&self.scenes[0])
    }

    /// The upload of the scene's own triangles (the reference geometry).
    pub fn base(&self) -> &GpuScene {
        &self.scenes[0]
    }
}

/// The targets of a method pass: RGBA32F colour, RGBA32F shading normal, D32 depth.
struct Targets {
    color: Image,
    normal: Image,
    depth: Image,
}

impl Targets {
    fn new(ctx: &Arc<Context>, w: u32, h: u32) -> Result<Self> {
        Ok(Targets {
            color: Image::new(ctx, ImageDesc::color(w, h, COLOR))?,
            normal: Image::new(ctx, ImageDesc::color(w, h, COLOR))?,
            depth: Image::new(ctx, ImageDesc::depth(w, h))?,
        })
    }

    /// Begins a rendering scope that clears all three targets to zero (far depth).
    fn begin(&self, cmd: &mut OneShot) {
        let clear = avk::ClearColorValue { float32: [0.0; 4] };
        cmd.begin_rendering(
            &[
                ColorTarget {
                    image: &self.color,
                    clear,
                },
                ColorTarget {
                    image: &self.normal,
                    clear,
                },
            ],
            Some(&self.depth),
        );
    }
}

/// Renders scenes offscreen on one device.
pub struct Renderer {
    ctx: Arc<Context>,
}

const COLOR: avk::Format = avk::Format::R32G32B32A32_SFLOAT;
const PRIM: avk::Format = avk::Format::R32_UINT;

impl Renderer {
    pub fn new(ctx: Arc<Context>) -> Self {
        Renderer { ctx }
    }

    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// Uploads a scene for `methods`: the scene's own triangles always (the reference and the
    /// id pass need them), a PN tessellation when a method draws one, and on each only the
    /// vertex streams those methods read. Checks the image size against the device limit.
    pub fn prepare(&self, scene: &Scene, methods: &[&Method]) -> Result<Prepared> {
        self.ctx.check_image_size(scene.width, scene.height)?;
        let mut geometries = vec![Geometry::Mesh];
        for m in methods {
            if !geometries.contains(&m.geometry) {
                geometries.push(m.geometry);
            }
        }
        let scenes = geometries
            .into_iter()
            .map(|g| {
                let ms: Vec<&Method> = methods
                    .iter()
                    .copied()
                    .filter(|m| m.geometry == g)
                    .collect();
                self.upload(SceneInputs::new(scene, g), &ms)
            })
            .collect::<Result<_>>()?;
        Ok(Prepared { scenes })
    }

    /// Uploads one geometry with the streams `methods` read.
    fn upload(&self, inputs: SceneInputs, methods: &[&Method]) -> Result<GpuScene> {
        let defines: Vec<&str> = methods.iter().flat_map(|m| method_defines(m)).collect();
        let usage = avk::BufferUsageFlags::VERTEX_BUFFER;
        let positions = Buffer::with_data(&self.ctx, usage, &inputs.positions)?;
        let streams = Stream::for_defines(&defines)
            .into_iter()
            .map(|s| Ok((s, Buffer::with_data(&self.ctx, usage, &inputs.stream(s))?)))
            .collect::<Result<Vec<_>>>()?;
        let ubo = Buffer::with_data(
            &self.ctx,
            avk::BufferUsageFlags::UNIFORM_BUFFER,
            &[inputs.params],
        )?;
        let lut = if defines.contains(&"USE_LUT") {
            Some(Buffer::with_data(
                &self.ctx,
                avk::BufferUsageFlags::STORAGE_BUFFER,
                specular_table(),
            )?)
        } else {
            None
        };
        let mut bindings = vec![(0, avk::DescriptorType::UNIFORM_BUFFER, &ubo)];
        if let Some(l) = &lut {
            bindings.push((1, avk::DescriptorType::STORAGE_BUFFER, l));
        }
        let set = DescriptorSet::new(&self.ctx, &bindings)?;
        Ok(GpuScene {
            inputs,
            positions,
            streams,
            _ubo: ubo,
            _lut: lut,
            set,
        })
    }

    fn pipeline(
        &self,
        gpu: &GpuScene,
        program: &str,
        streams: &[VertexStream],
        colors: &[avk::Format],
    ) -> Result<GraphicsPipeline> {
        let vs = ShaderModule::new(&self.ctx, program, shaders::embedded(program, "vert")?)?;
        let fs = ShaderModule::new(&self.ctx, program, shaders::embedded(program, "frag")?)?;
        GraphicsPipeline::new(
            &self.ctx,
            &PipelineDesc {
                vertex: &vs,
                fragment: &fs,
                streams,
                color_formats: colors,
                depth_format: Some(avk::Format::D32_SFLOAT),
                descriptors: Some(&gpu.set),
                specialization: &[(0, gpu.inputs.light_count)],
            },
        )
    }

    fn program(&self, gpu: &GpuScene, shading: Shading) -> String {
        let base = shading.method().map(|m| m.name).unwrap_or("constant");
        shaders::program_name(base, gpu.inputs.interpolation)
    }

    /// Renders one frame and reads back colour and normal; with `with_ids`, also runs the id
    /// pass (same geometry, same vertex code) and reads back triangle ids and weights.
    pub fn render(
        &self,
        gpu: &GpuScene,
        shading: Shading,
        with_ids: bool,
    ) -> Result<(Frame, Option<IdFrame>)> {
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let n = gpu.inputs.positions.len() as u32;
        let (streams, buffers) = gpu.buffers(shading)?;
        let pipeline =
            self.pipeline(gpu, &self.program(gpu, shading), &streams, &[COLOR, COLOR])?;
        let targets = Targets::new(&self.ctx, w, h)?;
        let (color, normal, depth) = (&targets.color, &targets.normal, &targets.depth);
        let readback = |img: &Image| {
            Buffer::new(
                &self.ctx,
                BufferDesc {
                    size: img.byte_size(),
                    usage: avk::BufferUsageFlags::TRANSFER_DST,
                },
            )
        };
        let color_buf = readback(color)?;
        let normal_buf = readback(normal)?;
        let clear = avk::ClearColorValue { float32: [0.0; 4] };

        let mut cmd = OneShot::begin(&self.ctx)?;
        targets.begin(&mut cmd);
        cmd.draw(&pipeline, Some(&gpu.set), &buffers, n);
        cmd.end_rendering();
        cmd.copy_image_to_buffer(color, &color_buf);
        cmd.copy_image_to_buffer(normal, &normal_buf);

        let mut id_objects = None;
        if with_ids {
            let (id_streams, id_buffers) = gpu.buffers(Shading::Constant)?;
            let id_pipeline = self.pipeline(
                gpu,
                &shaders::program_name("ids", gpu.inputs.interpolation),
                &id_streams,
                &[COLOR, PRIM],
            )?;
            let bary = Image::new(&self.ctx, ImageDesc::color(w, h, COLOR))?;
            let prim = Image::new(&self.ctx, ImageDesc::color(w, h, PRIM))?;
            let bary_buf = readback(&bary)?;
            let prim_buf = readback(&prim)?;
            cmd.begin_rendering(
                &[
                    ColorTarget {
                        image: &bary,
                        clear,
                    },
                    ColorTarget {
                        image: &prim,
                        clear: avk::ClearColorValue { uint32: [0; 4] },
                    },
                ],
                Some(depth),
            );
            cmd.draw(&id_pipeline, Some(&gpu.set), &id_buffers, n);
            cmd.end_rendering();
            cmd.copy_image_to_buffer(&bary, &bary_buf);
            cmd.copy_image_to_buffer(&prim, &prim_buf);
            id_objects = Some((id_pipeline, bary, prim, bary_buf, prim_buf));
        }
        cmd.submit()?;

        let frame = Frame {
            width: w,
            height: h,
            color: bytemuck::pod_collect_to_vec(&color_buf.bytes()[..color.byte_size() as usize]),
            normal: bytemuck::pod_collect_to_vec(
                &normal_buf.bytes()[..normal.byte_size() as usize],
            ),
        };
        let ids = id_objects.map(|(_, bary, prim, bary_buf, prim_buf)| IdFrame {
            width: w,
            height: h,
            weights: bytemuck::pod_collect_to_vec(&bary_buf.bytes()[..bary.byte_size() as usize]),
            prim: bytemuck::pod_collect_to_vec(&prim_buf.bytes()[..prim.byte_size() as usize]),
        });
        Ok((frame, ids))
    }

    /// Records, once, the draw of every shading into shared targets (clear + draw into the
    /// colour and normal targets, no readback), each bracketed by timestamps, for repeated
    /// submission by a benchmark. All shadings must draw the same geometry as `gpu`.
    ///
    /// Timestamp placement (measured in ../shared/TOOLCHAIN.md on Mesa 22.3): a
    /// TOP_OF_PIPE/BOTTOM_OF_PIPE pair around the draw reports ~0.2 ms for ~20 ms of work,
    /// because a timestamp's value is latched when the *next* flush runs. Two BOTTOM_OF_PIPE
    /// writes before the rendering and two after it, reading the first of each pair, track the
    /// submit-to-fence wall clock; `bench` re-checks that on every run.
    pub fn timed_draws(&self, gpu: &GpuScene, shadings: &[Shading]) -> Result<TimedDraws> {
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let targets = Targets::new(&self.ctx, w, h)?;
        let bottom = avk::PipelineStageFlags2::BOTTOM_OF_PIPE;
        let mut draws = Vec::new();
        for s in shadings {
            let (streams, buffers) = gpu.buffers(*s)?;
            let pipeline = self.pipeline(gpu, &self.program(gpu, *s), &streams, &[COLOR, COLOR])?;
            let pool = QueryPool::timestamps(&self.ctx, 4)?;
            let stats = QueryPool::fragment_invocations(&self.ctx)?;
            let mut cmd = OneShot::begin(&self.ctx)?;
            cmd.reset_queries(&pool);
            if let Some(q) = &stats {
                cmd.reset_queries(q);
            }
            cmd.timestamp(&pool, 0, bottom);
            cmd.timestamp(&pool, 1, bottom);
            targets.begin(&mut cmd);
            if let Some(q) = &stats {
                cmd.begin_query(q);
            }
            cmd.draw(
                &pipeline,
                Some(&gpu.set),
                &buffers,
                gpu.inputs.positions.len() as u32,
            );
            if let Some(q) = &stats {
                cmd.end_query(q);
            }
            cmd.end_rendering();
            cmd.timestamp(&pool, 2, bottom);
            cmd.timestamp(&pool, 3, bottom);
            draws.push((cmd.finish()?, pool, stats, pipeline));
        }
        let info = self.ctx.info();
        Ok(TimedDraws {
            draws,
            _targets: targets,
            valid_bits: info.timestamp_valid_bits,
            period_ns: info.timestamp_period_ns,
        })
    }
}

/// One timed submission: the submit-to-fence wall time and the timestamp interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub wall_ms: f64,
    /// `None` when the queue has no timestamps.
    pub timestamp_ms: Option<f64>,
    /// Fragment-shader invocations reported by a pipeline-statistics query (`None` when the
    /// device has none). Not necessarily the covered pixels: Mesa 22.3 counts whole blocks.
    pub fragment_invocations: Option<u64>,
}

/// Draws recorded by [`Renderer::timed_draws`], ready to be submitted in any order.
pub struct TimedDraws {
    draws: Vec<(Recorded, QueryPool, Option<QueryPool>, GraphicsPipeline)>,
    _targets: Targets,
    valid_bits: u32,
    period_ns: f32,
}

impl TimedDraws {
    /// Submits draw `i` once and waits for it.
    pub fn run(&self, i: usize) -> Result<Sample> {
        let (cmd, pool, stats, _) = &self.draws[i];
        let wall = cmd.submit()?;
        let t = pool.results()?;
        let fragment_invocations = match stats {
            Some(q) => q.results()?.first().copied(),
            None => None,
        };
        Ok(Sample {
            wall_ms: wall.as_secs_f64() * 1e3,
            timestamp_ms: timestamp_delta_ns(t[0], t[2], self.valid_bits, self.period_ns)
                .map(|ns| ns / 1e6),
            fragment_invocations,
        })
    }

    /// Number of recorded draws.
    pub fn len(&self) -> usize {
        self.draws.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.draws.is_empty()
    }
}
