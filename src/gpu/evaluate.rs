//! A method on a buffer of cases, without rasterization: glsl/evaluate.comp runs the method's
//! fragment code (glsl/method_main.glsl) once per case, with the inputs the vertex stage and the
//! rasterizer would give it. `shadelab stress` evaluates thousands of cases per submission this
//! way instead of one render per case.
use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Buffer, BufferDesc, BufferUsage, ComputePipeline, Context, DescriptorSet, OneShot, Recorded,
    ShaderModule,
};
use crate::method::formulas::Lighting;
use crate::method::{specular_table, Fragment, Input, Method, Precision};

/// One case as glsl/evaluate.comp reads it (`struct Case`, std430: every member a vec4).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuCase {
    pub weights: [f32; 4],
    pub pixel: [f32; 4],
    pub window: [[f32; 4]; 3],
    pub normals: [[f32; 4]; 3],
    pub flat_normal: [f32; 4],
    pub pn: [[f32; 4]; 3],
    pub light_dir: [f32; 4],
    pub half_vec: [f32; 4],
    pub light_color: [f32; 4],
    pub ambient: [f32; 4],
    pub diffuse: [f32; 4],
    /// rgb k_s, w shininess.
    pub specular: [f32; 4],
}

fn v4(v: DVec3) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, 0.0]
}

impl GpuCase {
    /// The case of a fragment lit by the first light of `lit` (values rounded to f32).
    pub fn new(frag: &Fragment, lit: &Lighting) -> Result<Self> {
        let &(l, color, h) = lit.lights().first().ok_or_else(|| {
            Error::Internal("a stress case needs one light; the lighting has none".into())
        })?;
        let mut specular = v4(lit.specular);
        specular[3] = lit.shininess as f32;
        Ok(GpuCase {
            weights: v4(frag.weights),
            pixel: [frag.pixel.x as f32, frag.pixel.y as f32, 0.0, 0.0],
            window: frag.window.map(|w| [w.x as f32, w.y as f32, 0.0, 0.0]),
            normals: frag.corner_normals.map(v4),
            flat_normal: v4(frag.flat_normal),
            pn: frag.pn_mids.map(v4),
            light_dir: v4(l),
            half_vec: v4(h),
            light_color: v4(color),
            ambient: v4(lit.ambient),
            diffuse: v4(lit.diffuse),
            specular,
        })
    }
}

/// What the device computed for one case: the colour and, where the method has one, the
/// shading normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluated {
    pub color: [f32; 3],
    pub normal: Option<[f32; 3]>,
}

/// A method's compute program, ready to evaluate batches of cases.
pub struct Kernel {
    ctx: Arc<Context>,
    /// Evaluations per invocation (glsl/evaluate.comp `REPEAT`; 1 for stress).
    repeat: u32,
    pipeline: Option<(ComputePipeline, DescriptorSet)>,
    _module: ShaderModule,
    cases: Buffer,
    results: Buffer,
    lut: Option<Buffer>,
    capacity: usize,
}

/// Cases per dispatch: 64 invocations per work group (glsl/evaluate.comp `local_size_x`).
const GROUP: usize = 64;
/// Cases per submission at most (304 bytes each: 20 MB per full batch).
const MAX_BATCH: usize = 1 << 16;

impl Kernel {
    /// The compute program of `m`; an error for methods without one (see
    /// [`shaders::has_evaluate_program`]).
    pub fn new(ctx: &Arc<Context>, m: &Method) -> Result<Self> {
        Kernel::with_repeat(ctx, m, 1)
    }

    /// The compute program of `m` evaluating it `repeat` times per case in a dependency chain
    /// (0: loading and storing the case only); the results of `repeat` > 1 are sums, for timing.
    pub fn with_repeat(ctx: &Arc<Context>, m: &Method, repeat: u32) -> Result<Self> {
        Kernel::with_precision(ctx, m, repeat, Precision::F32)
    }

    /// [`Kernel::with_repeat`] with the program of `precision` (an error, exit 2, when the
    /// device cannot run it).
    pub fn with_precision(
        ctx: &Arc<Context>,
        m: &Method,
        repeat: u32,
        precision: Precision,
    ) -> Result<Self> {
        ctx.require_precision(precision)?;
        if !shaders::has_evaluate_program(m) {
            return Err(Error::Usage(format!(
                "{} draws its own geometry ({:?}): it has no per-case compute program",
                m.name, m.geometry
            )));
        }
        let program = shaders::evaluate_program_in(m.name, precision);
        let module = ShaderModule::new(ctx, &program, shaders::embedded(&program, "comp")?)?;
        let lut = if m.inputs.contains(&Input::SpecularLut) {
            Some(Buffer::with_data(
                ctx,
                BufferUsage::Storage,
                specular_table(),
            )?)
        } else {
            None
        };
        // The pipeline is created at the first batch's size (a pipeline per size: created here
        // at one work group's size, the first batch would compile a second one).
        Ok(Kernel {
            ctx: ctx.clone(),
            repeat,
            pipeline: None,
            _module: module,
            cases: Buffer::new(ctx, storage(0))?,
            results: Buffer::new(ctx, storage(0))?,
            lut,
            capacity: 0,
        })
    }

    /// Makes room for `n` cases: new buffers, descriptor set and pipeline when it grows (the
    /// shader runs `cases.length()` invocations, so the buffer's size is the dispatch size).
    fn reserve(&mut self, n: usize) -> Result<()> {
        let n = n.div_ceil(GROUP) * GROUP;
        if n == self.capacity {
            return Ok(());
        }
        self.pipeline = None;
        let case_bytes = std::mem::size_of::<GpuCase>() as u64;
        self.cases = Buffer::new(&self.ctx, storage(n as u64 * case_bytes))?;
        self.results = Buffer::new(&self.ctx, storage(n as u64 * 32))?;
        let mut bindings = vec![(0, &self.cases), (2, &self.results)];
        if let Some(l) = &self.lut {
            bindings.push((1, l));
        }
        let set = DescriptorSet::new(&self.ctx, &bindings)?;
        let pipeline = ComputePipeline::new(&self.ctx, &self._module, &set, &[(1, self.repeat)])?;
        self.pipeline = Some((pipeline, set));
        self.capacity = n;
        Ok(())
    }

    /// Evaluates every case (one submission per `capacity` cases).
    pub fn run(&mut self, cases: &[GpuCase]) -> Result<Vec<Evaluated>> {
        if cases.is_empty() {
            return Ok(Vec::new());
        }
        // Sized to the batch (at most MAX_BATCH), so that a small batch does not run a large
        // buffer's stale cases; a new size costs a new pipeline (its JIT, tens of ms).
        self.reserve(cases.len().min(MAX_BATCH))?;
        let mut out = Vec::with_capacity(cases.len());
        for chunk in cases.chunks(self.capacity) {
            let bytes: &[u8] = bytemuck::cast_slice(chunk);
            self.cases.bytes_mut()[..bytes.len()].copy_from_slice(bytes);
            // Cases past the chunk are stale: evaluated and ignored.
            let (pipeline, set) = self
                .pipeline
                .as_ref()
                .ok_or_else(|| Error::Internal("compute kernel without a pipeline".into()))?;
            let mut cmd = OneShot::begin(&self.ctx)?;
            cmd.dispatch(pipeline, set, (self.capacity / GROUP) as u32);
            cmd.submit()?;
            let results: &[[f32; 4]] =
                bytemuck::cast_slice(&self.results.bytes()[..chunk.len() * 32]);
            out.extend(results.chunks_exact(2).map(|r| Evaluated {
                color: [r[0][0], r[0][1], r[0][2]],
                normal: (r[1][3] == 1.0).then_some([r[1][0], r[1][1], r[1][2]]),
            }));
        }
        Ok(out)
    }
}

impl Kernel {
    /// What the driver compiled this kernel's compute pipeline into (a context made by
    /// [`Context::for_executables`]; `shadelab isa`).
    pub fn executables(&mut self) -> Result<Vec<crate::gpu::vk::Executable>> {
        if self.pipeline.is_none() {
            self.reserve(GROUP)?;
        }
        let (pipeline, _) = self
            .pipeline
            .as_ref()
            .ok_or_else(|| Error::Internal("compute kernel without a pipeline".into()))?;
        pipeline.executables()
    }

    /// Uploads `cases` (at most one batch) and records their dispatch once, for repeated
    /// timed submissions ([`Recorded::submit`] returns the submit-to-fence wall time).
    pub fn record(&mut self, cases: &[GpuCase]) -> Result<Recorded> {
        if cases.is_empty() || cases.len() > MAX_BATCH {
            return Err(Error::Internal(format!(
                "a recorded dispatch takes 1..={MAX_BATCH} cases, not {}",
                cases.len()
            )));
        }
        self.reserve(cases.len())?;
        let bytes: &[u8] = bytemuck::cast_slice(cases);
        self.cases.bytes_mut()[..bytes.len()].copy_from_slice(bytes);
        let (pipeline, set) = self
            .pipeline
            .as_ref()
            .ok_or_else(|| Error::Internal("compute kernel without a pipeline".into()))?;
        let mut cmd = OneShot::begin(&self.ctx)?;
        cmd.dispatch(pipeline, set, (self.capacity / GROUP) as u32);
        cmd.finish()
    }
}

fn storage(size: u64) -> BufferDesc {
    BufferDesc {
        size,
        usage: BufferUsage::Storage,
    }
}
