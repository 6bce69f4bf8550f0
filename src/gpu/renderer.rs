//! Scene + method -> float images (colour and shading normal) and the id pass for the f64
//! truth. Uploads only the vertex streams the methods of a run read.
use std::sync::{Arc, Mutex};

use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::gpu::readback::{read_back, record_read, take_pixels};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Buffer, BufferDesc, BufferUsage, Clear, ColorTarget, Context, DepthMode, DescriptorSet, Format,
    FrontFace, GraphicsPipeline, Image, ImageDesc, OneShot, PipelineDesc, ShaderModule,
    VertexStream,
};
use crate::method::{specular_table, Geometry, Input, Method, Precision};
use crate::output::Provenance;
use crate::scene::Scene;
use crate::scene::{SceneInputs, Winding};

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
    /// locations 9..=11, ATTR_WINDOW
    Window(usize),
}

impl Stream {
    fn location(self) -> u32 {
        match self {
            Stream::Normal => 1,
            Stream::Flat => 2,
            Stream::Corner(k) => 3 + k as u32,
            Stream::PnMid(k) => 6 + k as u32,
            Stream::Window(k) => 9 + k as u32,
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
                "ATTR_WINDOW" => out.extend((0..3).map(Stream::Window)),
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
/// The uploaded scene for one geometry: positions, the streams its methods need, the uniform
/// block and (when a method needs it) the specular table.
pub struct GpuScene {
    pub inputs: SceneInputs,
    positions: Buffer,
    streams: Vec<(Stream, Buffer)>,
    _ubo: Buffer,
    _lut: Option<Buffer>,
    pub(super) set: DescriptorSet,
}

type Bindings<'a> = (Vec<VertexStream>, Vec<(u32, &'a Buffer)>);

impl GpuScene {
    /// The vertex streams and buffers a draw with `shading` binds; an error when the method
    /// draws another geometry or a stream it reads was not uploaded.
    pub(super) fn buffers(&self, shading: Shading) -> Result<Bindings<'_>> {
        let f3 = |location| VertexStream {
            location,
            format: Format::Rgb32Float,
            stride: 12,
        };
        let mut streams = vec![f3(0)];
        let mut buffers = vec![(0, &self.positions)];
        if let Some(m) = shading.method() {
            if m.geometry != self.inputs.geometry {
                return Err(Error::Internal(format!(
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
                        Error::Internal(format!(
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
        self.for_geometry(m.geometry).unwrap_or(&self.scenes[0])
    }

    /// The upload of one geometry, if this run has it.
    pub fn for_geometry(&self, g: Geometry) -> Option<&GpuScene> {
        self.scenes.iter().find(|s| s.inputs.geometry == g)
    }

    /// The geometries uploaded, the scene's own triangles first.
    pub fn geometries(&self) -> Vec<Geometry> {
        self.scenes.iter().map(|s| s.inputs.geometry).collect()
    }

    /// The upload of the scene's own triangles (the reference geometry).
    pub fn base(&self) -> &GpuScene {
        &self.scenes[0]
    }
}

/// The targets of a method pass: RGBA32F colour, RGBA32F shading normal, D32 depth.
pub(crate) struct Targets {
    color: Image,
    /// The shading normal; None when nothing reads it (a timed draw).
    normal: Option<Image>,
    depth: Image,
}

impl Targets {
    pub(super) fn with_normal(ctx: &Arc<Context>, w: u32, h: u32, normal: bool) -> Result<Self> {
        Self::new(ctx, w, h, normal, false)
    }

    /// The targets, with colour (and normal) targets the host reads in place when `host`
    /// ([`ImageDesc::host_color`]; the caller checks the device supports them).
    fn new(ctx: &Arc<Context>, w: u32, h: u32, normal: bool, host: bool) -> Result<Self> {
        let desc = if host {
            ImageDesc::host_color(w, h, COLOR)
        } else {
            ImageDesc::color(w, h, COLOR)
        };
        Ok(Targets {
            color: Image::new(ctx, desc)?,
            normal: normal.then(|| Image::new(ctx, desc)).transpose()?,
            depth: Image::new(ctx, ImageDesc::depth(w, h))?,
        })
    }

    /// The normal target of targets made with one.
    fn normal(&self) -> Result<&Image> {
        self.normal
            .as_ref()
            .ok_or_else(|| Error::Internal("these targets have no normal target".into()))
    }

    /// Begins a rendering scope that clears every target to zero (far depth).
    pub(super) fn begin(&self, cmd: &mut OneShot) {
        let clear = Clear::Float([0.0; 4]);
        let colors: Vec<ColorTarget> = std::iter::once(&self.color)
            .chain(&self.normal)
            .map(|image| ColorTarget { image, clear })
            .collect();
        cmd.begin_rendering(&colors, Some(&self.depth));
    }
}

/// A method pass's targets and read-back buffers, kept from one render to the next of the
/// same size and layout: every render clears its targets (or finds them zero: host targets,
/// zeroed as they are read) and overwrites the buffers whole, so reusing them gives the same
/// bytes, without allocating (and the kernel zeroing) about 70 MB of fresh pages per frame at
/// 1024x1024. Host targets (read in place) have no read-back buffers.
struct Pass {
    key: (u32, u32, bool),
    targets: Targets,
    color_buf: Option<Buffer>,
    normal_buf: Option<Buffer>,
}

/// RGBA float pixels, row by row.
type Pixels = Vec<[f32; 4]>;

impl Pass {
    /// The rendered colour and normal pixels (no normal target: none), read into the memory of
    /// `recycled` when there is one ([`take_pixels`]: in place from host targets, zeroing them
    /// for the next render, else from the read-back buffers).
    fn take_pixels(&mut self, recycled: Option<Frame>) -> Result<(Pixels, Pixels)> {
        let (old_color, old_normal) = recycled.map_or_else(Default::default, Frame::into_pixels);
        let color = take_pixels(&mut self.targets.color, self.color_buf.as_ref(), old_color)?;
        let normal = match self.targets.normal.as_mut() {
            Some(img) => take_pixels(img, self.normal_buf.as_ref(), old_normal)?,
            None => Vec::new(),
        };
        Ok((color, normal))
    }
}

/// Renders scenes offscreen on one device.
pub struct Renderer {
    pub(super) ctx: Arc<Context>,
    /// The precision of the method programs it draws (the id pass and the constant floor are
    /// float32 always).
    precision: Precision,
    /// The last method pass's targets, for the next render of the same size.
    kept: Mutex<Option<Pass>>,
    /// Whether method passes render into host targets read in place, where the device can
    /// (else optimal-tiling targets copied into read-back buffers).
    in_place: bool,
}

pub(crate) const COLOR: Format = Format::Rgba32Float;

/// The colour attachments of a method pass: colour, and the normal target when there is one.
pub(super) fn color_formats(normal: bool) -> &'static [Format] {
    if normal {
        &[COLOR, COLOR]
    } else {
        &[COLOR]
    }
}
pub(crate) const PRIM: Format = Format::R32Uint;

impl Renderer {
    pub fn new(ctx: Arc<Context>) -> Self {
        Renderer {
            ctx,
            precision: Precision::F32,
            kept: Mutex::new(None),
            in_place: true,
        }
    }

    /// This renderer with the fallback read-back forced: method passes render into
    /// optimal-tiling targets copied into read-back buffers, as on a device without linear
    /// colour targets. The frames are the same, bit for bit (tests compare the two).
    pub fn copying_targets(mut self) -> Self {
        self.in_place = false;
        self
    }

    /// Whether a method pass of `width` x `height` reads its targets in place (no copy by the
    /// driver): unless [`Renderer::copying_targets`], where the device supports linear colour
    /// targets of that size.
    pub fn reads_in_place(&self, width: u32, height: u32) -> bool {
        self.in_place && self.ctx.linear_color_target(COLOR, width, height)
    }

    /// The renderer drawing the methods' programs in `precision`; an error (exit 2) when the
    /// device cannot run them (float16 without `shaderFloat16`).
    pub fn with_precision(mut self, precision: Precision) -> Result<Self> {
        self.ctx.require_precision(precision)?;
        self.precision = precision;
        Ok(self)
    }

    /// The precision of the method programs.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// Where results rendered here come from: this device and its driver.
    pub fn provenance(&self) -> Provenance {
        let i = self.ctx.info();
        Provenance::new(&i.name, &i.driver_name, &i.driver_info, &i.api_version)
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

    /// Uploads one geometry with the streams `methods` read. The scanline methods need every
    /// corner in front of the near plane (their span ends are the unclipped window corners):
    /// a scene with a clipped triangle is refused for them, naming the triangle.
    fn upload(&self, inputs: SceneInputs, methods: &[&Method]) -> Result<GpuScene> {
        let scanline: Vec<&str> = methods
            .iter()
            .filter(|m| m.inputs.contains(&Input::ScanlineSpan))
            .map(|m| m.name)
            .collect();
        if let (Some(t), false) = (inputs.near_clipped(), scanline.is_empty()) {
            return Err(Error::Usage(format!(
                "triangle {t} crosses the near plane (or lies behind the eye); the scanline \
                 methods ({}) take their span ends from unclipped window corners: move the \
                 camera back or the near plane closer",
                scanline.join(", ")
            )));
        }
        let defines: Vec<&str> = methods.iter().flat_map(|m| method_defines(m)).collect();
        let usage = BufferUsage::Vertex;
        let positions = Buffer::with_data(&self.ctx, usage, &inputs.positions)?;
        let streams = Stream::for_defines(&defines)
            .into_iter()
            .map(|s| Ok((s, Buffer::with_data(&self.ctx, usage, &inputs.stream(s))?)))
            .collect::<Result<Vec<_>>>()?;
        let ubo = Buffer::with_data(&self.ctx, BufferUsage::Uniform, &[inputs.params])?;
        let lut = if defines.contains(&"USE_LUT") {
            Some(Buffer::with_data(
                &self.ctx,
                BufferUsage::Storage,
                specular_table(),
            )?)
        } else {
            None
        };
        let mut bindings = vec![(0, &ubo)];
        if let Some(l) = &lut {
            bindings.push((1, l));
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

    pub(super) fn pipeline(
        &self,
        gpu: &GpuScene,
        program: &str,
        streams: &[VertexStream],
        colors: &[Format],
    ) -> Result<GraphicsPipeline> {
        self.pipeline_with(gpu, program, streams, colors, DepthMode::Less, true)
    }

    /// [`Renderer::pipeline`] with a depth mode and colour writes on or off (the depth
    /// pre-pass and the pass after it).
    pub(super) fn pipeline_with(
        &self,
        gpu: &GpuScene,
        program: &str,
        streams: &[VertexStream],
        colors: &[Format],
        depth: DepthMode,
        color_write: bool,
    ) -> Result<GraphicsPipeline> {
        let vs = ShaderModule::new(&self.ctx, program, shaders::embedded(program, "vert")?)?;
        // A pass without the normal target gets the program without the normal output.
        let stage = shaders::fragment_stage(colors.len());
        let fs = ShaderModule::new(&self.ctx, program, shaders::embedded(program, stage)?)?;
        GraphicsPipeline::new(
            &self.ctx,
            &PipelineDesc {
                vertex: &vs,
                fragment: &fs,
                streams,
                color_formats: colors,
                depth_format: Some(Format::Depth32Float),
                descriptors: Some(&gpu.set),
                specialization: &draw_specialization(&gpu.inputs),
                cull_front: gpu.inputs.cull_front.map(|w| match w {
                    Winding::CounterClockwise => FrontFace::CounterClockwise,
                    Winding::Clockwise => FrontFace::Clockwise,
                }),
                depth,
                color_write,
            },
        )
    }

    pub(super) fn program(&self, gpu: &GpuScene, shading: Shading) -> String {
        match shading.method() {
            Some(m) => shaders::program_name_in(m.name, gpu.inputs.interpolation, self.precision),
            None => shaders::program_name("constant", gpu.inputs.interpolation),
        }
    }

    /// The targets and read-back buffers of a method pass of `w` x `h` (with the normal target
    /// or not): the kept ones when they fit, new ones otherwise (the kept ones freed first).
    fn pass(&self, w: u32, h: u32, with_normal: bool) -> Result<Pass> {
        let key = (w, h, with_normal);
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(pass) = kept.filter(|p| p.key == key) {
            return Ok(pass);
        }
        let host = self.reads_in_place(w, h);
        let targets = Targets::new(&self.ctx, w, h, with_normal, host)?;
        let buffers = |image: Option<&Image>| match image {
            Some(img) if !host => self.readback(img).map(Some),
            _ => Ok(None),
        };
        let color_buf = buffers(Some(&targets.color))?;
        let normal_buf = buffers(targets.normal.as_ref())?;
        Ok(Pass {
            key,
            targets,
            color_buf,
            normal_buf,
        })
    }

    /// A host-visible buffer the size of `img`, for reading it back.
    fn readback(&self, img: &Image) -> Result<Buffer> {
        Buffer::new(
            &self.ctx,
            BufferDesc {
                size: img.byte_size(),
                usage: BufferUsage::Readback,
            },
        )
    }

    /// Renders one frame and reads back colour and normal; with `with_ids`, also runs the id
    /// pass (same geometry, same vertex code) and reads back triangle ids and weights.
    pub fn render(
        &self,
        gpu: &GpuScene,
        shading: Shading,
        with_ids: bool,
    ) -> Result<(Frame, Option<IdFrame>)> {
        self.render_with(gpu, shading, with_ids, true)
    }

    /// [`Renderer::render`] with or without the normal target: without it (a PNG and nothing
    /// else asked for) the shader's second output has no attachment and the frame's `normal`
    /// is empty.
    pub fn render_with(
        &self,
        gpu: &GpuScene,
        shading: Shading,
        with_ids: bool,
        with_normal: bool,
    ) -> Result<(Frame, Option<IdFrame>)> {
        self.render_with_into(gpu, shading, with_ids, with_normal, None)
    }

    /// [`Renderer::render_with`] reading the frame back into the vectors of `recycled`, a frame
    /// its user is done with (of any size and content: [`read_back_into`]), instead of fresh
    /// ones. The frame is the same, bit for bit; `compare` hands its frames back this way.
    pub fn render_with_into(
        &self,
        gpu: &GpuScene,
        shading: Shading,
        with_ids: bool,
        with_normal: bool,
        recycled: Option<Frame>,
    ) -> Result<(Frame, Option<IdFrame>)> {
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let n = gpu.inputs.positions.len() as u32;
        let (streams, buffers) = gpu.buffers(shading)?;
        let colors = color_formats(with_normal);
        let pipeline = self.pipeline(gpu, &self.program(gpu, shading), &streams, colors)?;
        let mut pass = self.pass(w, h, with_normal)?;
        let (targets, color_buf, normal_buf) = (&pass.targets, &pass.color_buf, &pass.normal_buf);
        let (color, normal, depth) = (&targets.color, targets.normal.as_ref(), &targets.depth);
        let clear = Clear::Float([0.0; 4]);

        let mut cmd = OneShot::begin(&self.ctx)?;
        targets.begin(&mut cmd);
        cmd.draw(&pipeline, Some(&gpu.set), &buffers, n);
        cmd.end_rendering();
        record_read(&mut cmd, color, color_buf.as_ref())?;
        if let Some(img) = normal {
            record_read(&mut cmd, img, normal_buf.as_ref())?;
        }

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
            let bary_buf = self.readback(&bary)?;
            let prim_buf = self.readback(&prim)?;
            cmd.begin_rendering(
                &[
                    ColorTarget {
                        image: &bary,
                        clear,
                    },
                    ColorTarget {
                        image: &prim,
                        clear: Clear::Uint([0; 4]),
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
        // The work is done (synchronous submit): the pipeline goes, the pass's targets and
        // buffers stay for the next render of the same size.
        drop(pipeline);
        let (color, normal) = pass.take_pixels(recycled)?;
        *self.kept.lock().unwrap_or_else(|e| e.into_inner()) = Some(pass);
        let frame = Frame {
            width: w,
            height: h,
            color,
            normal,
        };
        let ids = id_objects.map(|(_, bary, prim, bary_buf, prim_buf)| IdFrame {
            width: w,
            height: h,
            weights: read_back(&bary_buf.bytes()[..bary.byte_size() as usize]),
            prim: read_back(&prim_buf.bytes()[..prim.byte_size() as usize]),
        });
        Ok((frame, ids))
    }
}

/// `auto` uploaded: the scene's triangles grouped by the method chosen for each, every group's
/// vertex streams, and the groups as (method, first vertex, vertex count).
pub struct AutoScene {
    pub gpu: GpuScene,
    pub groups: Vec<(&'static Method, u32, u32)>,
}

impl Renderer {
    /// Uploads `scene` for `auto`: triangle t drawn with `order[pick[t]]`.
    pub fn prepare_auto(
        &self,
        scene: &Scene,
        order: &[&'static Method],
        pick: &[usize],
    ) -> Result<AutoScene> {
        self.ctx.check_image_size(scene.width, scene.height)?;
        let inputs = SceneInputs::new(scene, Geometry::Mesh);
        if pick.len() != inputs.triangle_count() || pick.iter().any(|&k| k >= order.len()) {
            return Err(Error::Internal(format!(
                "auto: {} choices for {} triangles",
                pick.len(),
                inputs.triangle_count()
            )));
        }
        if let Some(m) = order.iter().find(|m| m.geometry != Geometry::Mesh) {
            return Err(Error::Usage(format!(
                "auto: {} draws its own geometry and cannot be a candidate",
                m.name
            )));
        }
        let mut perm: Vec<usize> = (0..pick.len()).collect();
        perm.sort_by_key(|&t| pick[t]);
        let mut groups = Vec::new();
        let mut first = 0u32;
        for (k, m) in order.iter().enumerate() {
            let n = 3 * pick.iter().filter(|&&p| p == k).count() as u32;
            if n > 0 {
                groups.push((*m, first, n));
            }
            first += n;
        }
        let gpu = self.upload(inputs.permuted(&perm), order)?;
        Ok(AutoScene { gpu, groups })
    }

    /// Uploads the scene's own triangles for `methods` in the order `order` gives (a
    /// permutation of the triangle indices, e.g. front to back).
    pub fn prepare_permuted(
        &self,
        scene: &Scene,
        methods: &[&Method],
        order: &dyn Fn(&SceneInputs) -> Vec<usize>,
    ) -> Result<GpuScene> {
        self.ctx.check_image_size(scene.width, scene.height)?;
        if let Some(m) = methods.iter().find(|m| m.geometry != Geometry::Mesh) {
            return Err(Error::Usage(format!(
                "{} draws its own geometry: it cannot be drawn in another triangle order",
                m.name
            )));
        }
        let inputs = SceneInputs::new(scene, Geometry::Mesh);
        let perm = order(&inputs);
        let mut check = perm.clone();
        check.sort_unstable();
        if check != (0..inputs.triangle_count()).collect::<Vec<_>>() {
            return Err(Error::Internal(
                "prepare_permuted: the order is not a permutation of the triangles".into(),
            ));
        }
        self.upload(inputs.permuted(&perm), methods)
    }

    /// Renders `auto`: one pipeline per group, each drawing its range, in one pass.
    pub fn render_auto(&self, a: &AutoScene) -> Result<Frame> {
        self.render_auto_into(a, None)
    }

    /// [`Renderer::render_auto`] reading back into the vectors of `recycled`, as
    /// [`Renderer::render_with_into`] does.
    pub fn render_auto_into(&self, a: &AutoScene, recycled: Option<Frame>) -> Result<Frame> {
        let gpu = &a.gpu;
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        // The image carries the normal too (compare reads it), whatever timing does.
        let mut list = a.draw_list();
        list.normal = true;
        let draws = self.record_list(&list)?;
        let mut pass = self.pass(w, h, true)?;
        let (targets, color_buf, normal_buf) = (&pass.targets, &pass.color_buf, &pass.normal_buf);
        let mut cmd = OneShot::begin(&self.ctx)?;
        targets.begin(&mut cmd);
        for (p, buffers, first, count) in &draws {
            cmd.draw_range(p, Some(&gpu.set), buffers, *first, *count);
        }
        cmd.end_rendering();
        record_read(&mut cmd, &targets.color, color_buf.as_ref())?;
        record_read(&mut cmd, targets.normal()?, normal_buf.as_ref())?;
        cmd.submit()?;
        drop(draws);
        // (the normal target exists: `targets.normal()?` above)
        let (color, normal) = pass.take_pixels(recycled)?;
        let frame = Frame {
            width: w,
            height: h,
            color,
            normal,
        };
        *self.kept.lock().unwrap_or_else(|e| e.into_inner()) = Some(pass);
        Ok(frame)
    }
}

impl AutoScene {
    /// The groups as one draw list (for timing and counting like any program).
    pub fn draw_list(&self) -> crate::gpu::DrawList<'_> {
        crate::gpu::DrawList {
            gpu: &self.gpu,
            parts: self
                .groups
                .iter()
                .map(|&(m, first, count)| (Shading::Method(m), first, count))
                .collect(),
            prepass: crate::gpu::TIMING_PREPASS,
            normal: crate::gpu::TIMING_NORMAL_TARGET,
        }
    }
}

impl SceneInputs {
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
            Stream::Window(k) => per_triangle(&|t| {
                let w = self.window[3 * t + k];
                [w[0], w[1], 0.0]
            }),
        }
    }
}

/// The specialization constants of a draw of `inputs` (glsl/common.glsl: 0 the light count,
/// 2 whether the specular term is on): the Vulkan pipelines' and the OpenGL route's
/// (`shadelab isa`) alike.
pub fn draw_specialization(inputs: &SceneInputs) -> [(u32, u32); 2] {
    [
        (0, inputs.light_count),
        (
            2,
            u32::from(inputs.params.specular[..3].iter().any(|&k| k != 0.0)),
        ),
    ]
}
