//! The child side of `shadelab isa`: one process per GPU family, started by [`super::run`]
//! with RADV's null device selected in its environment (so that a driver crash takes down the
//! child only). It builds the timed draw's pipelines and the isolated kernels on that device,
//! reads back what the compiler made of them and prints one [`ChildReport`] as JSON on stdout.
//! Nothing is ever submitted: the null device compiles, it cannot execute.
use std::path::Path;
use std::time::Instant;

use super::request::{scene, ChildReport, ChildRequest, Compiled};
use crate::error::{Error, Result};
use crate::gpu::evaluate::Kernel;
use crate::gpu::shaders::has_evaluate_program;
use crate::gpu::vk::{
    Buffer, BufferDesc, BufferUsage, ComputePipeline, Context, ContextDesc, DescriptorSet,
    Executable, ShaderModule,
};
use crate::gpu::{Renderer, Shading};
use crate::isa::route::{Api, Vendor};
use crate::method::{self, Method};

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

/// Compiles everything `req` asks for on the device the environment selects (the parent sets
/// it: [`super::route::Vendor::child_env`]), through the vendor's API; a device that is not
/// the family asked for (a software fallback) is refused, an error.
pub fn compile(req: &ChildRequest) -> Result<ChildReport> {
    let (vendor, chip) = super::route::resolve(&req.family).map_err(Error::Usage)?;
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
            if !has_evaluate_program(m) || req.draws_only {
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
