//! Scene + method -> float images (colour and shading normal), the id pass for the f64 truth,
//! and per-frame timing.
//!
//! All geometry set-up is computed in f64 on the CPU ([`SceneInputs`]) and rounded to f32 once
//! for upload. The same rounded values, widened back to f64, are what the truth evaluator
//! (src/truth.rs) uses, so GPU and CPU start from bit-identical inputs.
use std::sync::Arc;
use std::time::Duration;

use ash::vk as avk;
use glam::{DMat3, DVec3};

use crate::error::Result;
use crate::formulas::Lighting;
use crate::methods::{Input, Method};
use crate::scene::{Interpolation, Scene, MAX_LIGHTS};
use crate::shaders;
use crate::vk::commands::ColorTarget;
use crate::vk::{
    Buffer, BufferDesc, Context, DescriptorSet, GraphicsPipeline, Image, ImageDesc, OneShot,
    PipelineDesc, ShaderModule, VertexStream,
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
}

impl Shading<'_> {
    /// Name used in reports (`constant` for the floor).
    pub fn name(&self) -> &str {
        match self {
            Shading::Method(m) => m.name,
            Shading::Constant => "constant",
        }
    }
    fn needs(&self, input: Input) -> bool {
        match self {
            Shading::Method(m) => m.inputs.contains(&input),
            Shading::Constant => false,
        }
    }
}

/// Everything the GPU receives for a scene, as f32, computed once in f64.
pub struct SceneInputs {
    pub width: u32,
    pub height: u32,
    pub interpolation: Interpolation,
    /// Model-space positions, 3 corners per triangle.
    pub positions: Vec<[f32; 3]>,
    /// Unit view-space vertex normals per corner.
    pub view_normals: Vec<[f32; 3]>,
    pub params: Params,
    pub light_count: u32,
}

fn f4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

fn widen(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

impl SceneInputs {
    /// Transforms the scene in f64: MVP, view-space normals (normal matrix = inverse transpose
    /// of the view's upper 3x3; the mesh is already in its fitted model space), light directions
    /// and half vectors with the viewer at infinity (V = +Z in view space, FORMULAS.md 1.2).
    pub fn new(scene: &Scene) -> Self {
        let view = scene.camera.view();
        let proj = scene
            .camera
            .projection(scene.width as f64 / scene.height as f64);
        let mvp = (proj * view).to_cols_array_2d();
        let rot = DMat3::from_mat4(view);
        let normal_matrix = rot.inverse().transpose();
        let view_normals = scene
            .mesh
            .normals
            .iter()
            .map(|n| {
                let v = (normal_matrix * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64))
                    .normalize_or_zero();
                [v.x as f32, v.y as f32, v.z as f32]
            })
            .collect();
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
            positions: scene.mesh.positions.clone(),
            view_normals,
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

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }
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

/// The uploaded scene: vertex streams and the uniform block.
pub struct GpuScene {
    pub inputs: SceneInputs,
    positions: Buffer,
    normals: Buffer,
    _ubo: Buffer,
    set: DescriptorSet,
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

    /// Uploads a scene. Checks the image size against the device limit first.
    pub fn upload(&self, scene: &Scene) -> Result<GpuScene> {
        self.ctx.check_image_size(scene.width, scene.height)?;
        let inputs = SceneInputs::new(scene);
        let usage = avk::BufferUsageFlags::VERTEX_BUFFER;
        let positions = Buffer::with_data(&self.ctx, usage, &inputs.positions)?;
        let normals = Buffer::with_data(&self.ctx, usage, &inputs.view_normals)?;
        let ubo = Buffer::with_data(
            &self.ctx,
            avk::BufferUsageFlags::UNIFORM_BUFFER,
            &[inputs.params],
        )?;
        let set = DescriptorSet::new(&self.ctx, &[(0, avk::DescriptorType::UNIFORM_BUFFER, &ubo)])?;
        Ok(GpuScene {
            inputs,
            positions,
            normals,
            _ubo: ubo,
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

    fn streams<'a>(
        &self,
        gpu: &'a GpuScene,
        shading: Shading,
    ) -> (Vec<VertexStream>, Vec<(u32, &'a Buffer)>) {
        let f3 = |location| VertexStream {
            location,
            format: avk::Format::R32G32B32_SFLOAT,
            stride: 12,
        };
        let mut streams = vec![f3(0)];
        let mut buffers = vec![(0, &gpu.positions)];
        if shading.needs(Input::InterpolatedNormal) {
            streams.push(f3(1));
            buffers.push((1, &gpu.normals));
        }
        (streams, buffers)
    }

    fn program(&self, gpu: &GpuScene, shading: Shading) -> String {
        let base = match shading {
            Shading::Method(m) => m.name,
            Shading::Constant => "constant",
        };
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
        let (streams, buffers) = self.streams(gpu, shading);
        let pipeline =
            self.pipeline(gpu, &self.program(gpu, shading), &streams, &[COLOR, COLOR])?;
        let color = Image::new(&self.ctx, ImageDesc::color(w, h, COLOR))?;
        let normal = Image::new(&self.ctx, ImageDesc::color(w, h, COLOR))?;
        let depth = Image::new(&self.ctx, ImageDesc::depth(w, h))?;
        let readback = |img: &Image| {
            Buffer::new(
                &self.ctx,
                BufferDesc {
                    size: img.byte_size(),
                    usage: avk::BufferUsageFlags::TRANSFER_DST,
                },
            )
        };
        let color_buf = readback(&color)?;
        let normal_buf = readback(&normal)?;
        let clear = avk::ClearColorValue { float32: [0.0; 4] };

        let mut cmd = OneShot::begin(&self.ctx)?;
        cmd.begin_rendering(
            &[
                ColorTarget {
                    image: &color,
                    clear,
                },
                ColorTarget {
                    image: &normal,
                    clear,
                },
            ],
            Some(&depth),
        );
        cmd.draw(&pipeline, Some(&gpu.set), &buffers, n);
        cmd.end_rendering();
        cmd.copy_image_to_buffer(&color, &color_buf);
        cmd.copy_image_to_buffer(&normal, &normal_buf);

        let mut id_objects = None;
        if with_ids {
            let (id_streams, id_buffers) = self.streams(gpu, Shading::Constant);
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
                Some(&depth),
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

    /// Times the draw alone (clear + draw into the colour and normal targets, no readback):
    /// `warmup` submissions are discarded (the first includes lavapipe's shader JIT), then
    /// `repeats` submit-to-fence wall times are returned.
    pub fn time_draw(
        &self,
        gpu: &GpuScene,
        shading: Shading,
        warmup: usize,
        repeats: usize,
    ) -> Result<Vec<Duration>> {
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let (streams, buffers) = self.streams(gpu, shading);
        let pipeline =
            self.pipeline(gpu, &self.program(gpu, shading), &streams, &[COLOR, COLOR])?;
        let color = Image::new(&self.ctx, ImageDesc::color(w, h, COLOR))?;
        let normal = Image::new(&self.ctx, ImageDesc::color(w, h, COLOR))?;
        let depth = Image::new(&self.ctx, ImageDesc::depth(w, h))?;
        let clear = avk::ClearColorValue { float32: [0.0; 4] };
        let mut cmd = OneShot::begin(&self.ctx)?;
        cmd.begin_rendering(
            &[
                ColorTarget {
                    image: &color,
                    clear,
                },
                ColorTarget {
                    image: &normal,
                    clear,
                },
            ],
            Some(&depth),
        );
        cmd.draw(
            &pipeline,
            Some(&gpu.set),
            &buffers,
            gpu.inputs.positions.len() as u32,
        );
        cmd.end_rendering();
        let mut times = cmd.submit_repeated(warmup + repeats)?;
        Ok(times.split_off(warmup.min(times.len())))
    }
}
