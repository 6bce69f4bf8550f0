//! The child side of `shadelab isa`: one process per GPU family, started by [`super::run`]
//! with RADV's null device selected in its environment (so that a driver crash takes down the
//! child only). It builds the timed draw's pipelines and the isolated kernels on that device,
//! reads back what the compiler made of them and prints one [`ChildReport`] as JSON on stdout.
//! Nothing is ever submitted: the null device compiles, it cannot execute.
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::gpu::evaluate::Kernel;
use crate::gpu::shaders::has_evaluate_program;
use crate::gpu::vk::{
    Buffer, BufferDesc, BufferUsage, ComputePipeline, Context, ContextDesc, DescriptorSet,
    Executable, ShaderModule,
};
use crate::gpu::{Renderer, Shading};
use crate::isa::vendor::{Api, Vendor};
use crate::method::{self, Method};
use crate::scene::Scene;

/// The scene whose timed draw is compiled when none is given: the shipped generated torus
/// (one directional light, specular on, screen-linear), so no mesh file is needed.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/torus_generated.toml");
/// Its name in reports.
pub const DEFAULT_SCENE_NAME: &str = "scenes/torus_generated.toml";

impl crate::child::Job for ChildRequest {
    const NAME: &'static str = "isa_family";
    type Reply = ChildReport;
}

/// What a child is asked to compile.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChildRequest {
    pub family: String,
    pub methods: Vec<String>,
    /// Scene file; `None`: [`DEFAULT_SCENE`].
    pub scene: Option<PathBuf>,
    /// The two evaluation counts of the isolated kernel (glsl/evaluate.comp `REPEAT`).
    pub kernel_counts: [u32; 2],
    /// Extra compute programs (SPIR-V files, one storage buffer at binding 0), compiled as
    /// they are: the probes of the tests.
    pub probes: Vec<PathBuf>,
    /// The precision of the method programs (issue 23; absent: f32).
    #[serde(default)]
    pub precision: crate::method::Precision,
}

/// One compiled program.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Compiled {
    pub method: String,
    /// SPIR-V program name (spirv/<program>.<stage>.spv), or the probe's file name.
    pub program: String,
    /// "draw" (the timed draw's pipeline), "kernel" (glsl/evaluate.comp) or "probe".
    pub kind: String,
    /// The kernel's evaluation count (`REPEAT`); `None` for draws and probes.
    pub repeat: Option<u32>,
    pub executables: Vec<Executable>,
}

/// What one child prints.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChildReport {
    pub family: String,
    pub device_name: String,
    pub driver_name: String,
    /// The driver's version string ("Mesa 22.3.6" on Debian 12).
    pub driver_info: String,
    pub api_version: String,
    pub compiled: Vec<Compiled>,
    pub elapsed_ms: f64,
    /// Whether the device compiles float16 arithmetic (Vulkan's shaderFloat16); absent from
    /// the OpenGL route, whose vendors say it themselves.
    #[serde(default)]
    pub float16: Option<bool>,
    /// Methods the driver's shading language cannot express, each with why (OpenGL ES 2.0's
    /// ESSL 1.00 has no array constructors, gl_VertexID or storage buffers); empty elsewhere.
    #[serde(default)]
    pub skipped: Vec<String>,
}

/// Keeps only the disassembly among the representations (ACO's "Assembly"; NIR and ACO IR are
/// large and not asked for), so that the report stays small; none where the driver has none.
fn keep_disassembly(mut exes: Vec<Executable>) -> Vec<Executable> {
    for e in &mut exes {
        // Mesa 22.3 answers GFX6 (tahiti) with "Shader disassembly is not supported in the
        // current configuration.": no disassembly, not a program.
        e.representations.retain(|r| {
            r.name.to_lowercase().contains("assembl") && !r.text.contains("is not supported")
        });
    }
    exes
}

/// Loads the request's scene.
pub(crate) fn scene(req: &ChildRequest) -> Result<Scene> {
    match &req.scene {
        Some(p) => crate::scene::load_scene(p),
        None => crate::scene::parse_scene(
            Path::new(DEFAULT_SCENE_NAME),
            DEFAULT_SCENE,
            &crate::geometry::load_obj,
        ),
    }
}

/// Compiles everything `req` asks for on the device the environment selects (the parent sets
/// it: [`super::vendor::Vendor::child_env`]), through the vendor's API; a device that is not
/// the family asked for (a software fallback) is refused, an error.
pub fn compile(req: &ChildRequest) -> Result<ChildReport> {
    let (vendor, chip) = super::vendor::resolve(&req.family).map_err(Error::Usage)?;
    match vendor.api() {
        Api::Vulkan { device } => compile_vulkan(req, vendor, &chip, device),
        Api::OpenGl | Api::OpenGlEs => super::gl_child::compile(req, vendor, &chip),
    }
}

/// [`compile`] on a Vulkan device whose name contains `device`.
fn compile_vulkan(
    req: &ChildRequest,
    vendor: &dyn Vendor,
    chip: &str,
    device: &str,
) -> Result<ChildReport> {
    let start = Instant::now();
    let ctx = Context::for_executables(&ContextDesc {
        device: Some(device.into()),
        validate: false,
    })?;
    let info = ctx.info().clone();
    vendor
        .check_device(chip, &info.name)
        .map_err(|why| Error::Device(format!("{}: {why}", req.family)))?;
    let keep = |exes| keep_disassembly(vendor.merge_executables(exes));
    // A driver that prints its compiler's statistics on stderr: each compile caught alone.
    let caught = |program: &str, compile: &dyn Fn() -> Result<Vec<Executable>>| {
        if !vendor.statistics_on_stderr() {
            return compile();
        }
        let is_stats = |l: &str| vendor.parse_debug_message(l).is_some();
        let (exes, lines) = super::stderr::capture(is_stats, compile)?;
        super::stderr::merge(vendor, program, exes?, &lines)
    };
    let methods: Vec<&'static Method> = req
        .methods
        .iter()
        .map(|m| method::find(m))
        .collect::<Result<_>>()?;
    let mut compiled = Vec::new();
    if !methods.is_empty() {
        // A family without float16 arithmetic (before Vega) fails here, reported as such.
        let r = Renderer::new(ctx.clone()).with_precision(req.precision)?;
        let scene = scene(req)?;
        let prepared = r.prepare(&scene, &methods)?;
        for m in &methods {
            let gpu = prepared.for_method(m);
            let program = crate::gpu::shaders::program_name_in(
                m.name,
                gpu.inputs.interpolation,
                req.precision,
            );
            let exes = caught(&program, &|| r.compiled(gpu, Shading::Method(m)))?;
            compiled.push(Compiled {
                method: m.name.to_string(),
                program,
                kind: "draw".into(),
                repeat: None,
                executables: keep(exes),
            });
            if !has_evaluate_program(m) {
                continue;
            }
            let program = crate::gpu::shaders::evaluate_program_in(m.name, req.precision);
            for &k in &req.kernel_counts {
                let exes = caught(&program, &|| {
                    Kernel::with_precision(&ctx, m, k, req.precision)?.executables()
                })?;
                compiled.push(Compiled {
                    method: m.name.to_string(),
                    program: program.clone(),
                    kind: "kernel".into(),
                    repeat: Some(k),
                    executables: keep(exes),
                });
            }
        }
    }
    for p in &req.probes {
        let mut c = probe(&ctx, p)?;
        c.executables = keep(c.executables);
        compiled.push(c);
    }
    Ok(ChildReport {
        family: req.family.clone(),
        device_name: info.name,
        driver_name: info.driver_name,
        driver_info: info.driver_info,
        api_version: info.api_version,
        compiled,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        float16: Some(info.shader_float16),
        skipped: Vec::new(),
    })
}

/// A probe: a compute program reading and writing one storage buffer at binding 0.
fn probe(ctx: &std::sync::Arc<Context>, path: &Path) -> Result<Compiled> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let module = ShaderModule::new(ctx, &name, &bytes)?;
    let buffer = Buffer::new(
        ctx,
        BufferDesc {
            size: 4096,
            usage: BufferUsage::Storage,
        },
    )?;
    let set = DescriptorSet::new(ctx, &[(0, &buffer)])?;
    let pipeline = ComputePipeline::new(ctx, &module, &set, &[])?;
    Ok(Compiled {
        method: name.trim_end_matches(".spv").to_string(),
        program: name,
        kind: "probe".into(),
        repeat: None,
        executables: pipeline.executables()?,
    })
}
