//! The child side of `shadelab isa` on an OpenGL route (nouveau, r600) or OpenGL ES route
//! (panfrost, lima, v3d, vc4): the timed draw's programs (the same SPIR-V as the Vulkan draw,
//! turned into GLSL or GLSL ES by spirv-cross with the draw's specialization constants) and
//! the isolated kernels (where the context has compute shaders: OpenGL 4.3, OpenGL ES 3.1),
//! compiled and linked in an EGL surfaceless context of the driver the environment selects;
//! the vendor reads its compiler's statistics out of the KHR_debug messages. float16 programs
//! only on OpenGL ES drivers whose `mediump` is 16-bit (GLSL ES spells float16 `mediump`:
//! [`glsl::es_precision`]); the OpenGL drivers here have no float16 arithmetic. No
//! disassembly: the drivers send none.
use crate::isa::request::CompiledKind;
use std::collections::BTreeMap;
use std::time::Instant;

use super::request::{ChildReport, ChildRequest, Compiled};
use super::route::{Api, Vendor};
use super::throughput;
use crate::error::{Error, Result};
use crate::gpu::gl::{glsl, GlApi, GlContext, GlInfo, GlStage};
use crate::gpu::shaders;
use crate::gpu::vk::{Executable, StatValue, Statistic};
use crate::method::{self, Precision};
use crate::scene::{Interpolation, SceneInputs};

/// Compiles what `req` asks for on the OpenGL driver the environment selects, refusing a
/// renderer that is not `chip`.
pub fn compile(req: &ChildRequest, vendor: &dyn Vendor, chip: &str) -> Result<ChildReport> {
    let start = Instant::now();
    let es = vendor.api() == Api::OpenGlEs;
    if req.precision != Precision::F32 && !es {
        return Err(Error::Device(format!(
            "{}: the OpenGL route compiles float32 programs only (no float16 arithmetic in \
             these drivers' OpenGL)",
            req.family
        )));
    }
    if !req.probes.is_empty() {
        return Err(Error::Usage(format!(
            "{}: probes are compiled on the Vulkan routes only",
            req.family
        )));
    }
    let ctx = GlContext::surfaceless_api(if es { GlApi::Es } else { GlApi::Core43 })?;
    let info = ctx.info().clone();
    log::debug!(
        "{}: {} created in {:.0} ms",
        req.family,
        info.renderer,
        start.elapsed().as_secs_f64() * 1e3
    );
    vendor
        .check_device(chip, &info.renderer)
        .map_err(|why| Error::Device(format!("{}: {why}", req.family)))?;
    let float16 = es && float16_mediump(&info);
    if req.precision == Precision::F16 && !float16 {
        return Err(Error::Device(format!(
            "{}: {} computes mediump with {} bits of precision, not float16's 10: no float16 \
             arithmetic",
            req.family, info.renderer, info.mediump_bits
        )));
    }
    let cross = |label: &str, spirv: &[u8], spec: &[(u32, u32)]| match info.es {
        Some(v) => glsl::from_spirv_es(label, spirv, spec, glsl::es_version(v)),
        None => glsl::from_spirv(label, spirv, spec),
    };
    // Compute shaders: OpenGL 4.3 and OpenGL ES 3.1.
    let compute = info.es.is_none_or(|v| v >= (3, 1));
    let scene = super::request::scene(req)?;
    let mut inputs: BTreeMap<String, SceneInputs> = BTreeMap::new();
    let mut compiled = Vec::new();
    let mut skipped = Vec::new();
    for name in &req.methods {
        let m = method::find(name)?;
        let key = format!("{:?}", m.geometry);
        let inputs = inputs
            .entry(key)
            .or_insert_with(|| SceneInputs::new(&scene, m.geometry));
        // ESSL 1.00 (OpenGL ES 2.0: VC4, Mali-450) has no noperspective interpolation: there
        // the perspective-correct program of the method compiles, with its colour output alone
        // (no second output without EXT_draw_buffers), as `program` says.
        let interpolation = match info.es {
            Some((2, _)) => Interpolation::Perspective,
            _ => inputs.interpolation,
        };
        let program = shaders::program_name_in(m.name, interpolation, req.precision);
        let spec = crate::gpu::draw_specialization(inputs);
        match compile_draw(&ctx, vendor, &cross, &program, &spec) {
            Ok(executables) => compiled.push(Compiled {
                method: m.name.to_string(),
                executables,
                program,
                kind: CompiledKind::Draw,
                repeat: None,
            }),
            // ESSL 1.00 cannot express some programs (array constructors, gl_VertexID, storage
            // buffers): on OpenGL ES 2.0 a method whose program does not translate or compile
            // is reported as skipped, with the first line of why. Any other failure (a driver
            // that sends no statistics) fails the family, as everywhere.
            Err(Error::Shader(why)) if matches!(info.es, Some((2, _))) => {
                let first = why.lines().next().unwrap_or_default();
                skipped.push(format!("{}: {first}", m.name));
                continue;
            }
            Err(e) => return Err(e),
        }
        if !shaders::has_evaluate_program(m) || !compute || req.draws_only {
            continue;
        }
        let program = shaders::evaluate_program_in(m.name, req.precision);
        for &k in &req.kernel_counts {
            let spec = [(1, k)];
            let (cs, set) = cross(&program, shaders::embedded(&program, "comp")?, &spec)?;
            glsl::check_all_set(&program, &spec, &set)?;
            let (messages, sfu) =
                compile_counted(&ctx, vendor, &program, &[(GlStage::Compute, &cs)])?;
            compiled.push(Compiled {
                method: m.name.to_string(),
                executables: with_sfu(
                    executables(vendor, &program, &messages, &["compute"])?,
                    &sfu,
                ),
                program: program.clone(),
                kind: CompiledKind::Kernel,
                repeat: Some(k),
            });
        }
    }
    Ok(ChildReport {
        family: req.family.clone(),
        device_name: info.renderer,
        driver_name: info.vendor,
        driver_info: info.version,
        api_version: match info.es {
            Some((2, minor)) => {
                format!("OpenGL ES 2.{minor} (perspective-correct programs, colour output alone)")
            }
            Some((major, minor)) => format!("OpenGL ES {major}.{minor}"),
            None => "OpenGL 4.3 core".into(),
        },
        compiled,
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
        float16: Some(float16),
        skipped,
    })
}

/// Our SPIR-V to the context's GLSL: (label, SPIR-V, specialization) -> (source, ids set).
type Cross<'a> = dyn Fn(&str, &[u8], &[(u32, u32)]) -> Result<(String, Vec<u32>)> + 'a;

/// The executables of the timed draw's `program` (vertex and fragment), translated by `cross`
/// with the draw's specialization constants `spec`.
fn compile_draw(
    ctx: &GlContext,
    vendor: &dyn Vendor,
    cross: &Cross<'_>,
    program: &str,
    spec: &[(u32, u32)],
) -> Result<Vec<Executable>> {
    let (vs, mut set) = cross(program, shaders::embedded(program, "vert")?, spec)?;
    let (fs, set_fs) = cross(
        program,
        shaders::embedded(program, shaders::COLOR_ONLY)?,
        spec,
    )?;
    set.extend(set_fs);
    if glsl::has_constants(&vs) || glsl::has_constants(&fs) {
        glsl::check_all_set(program, spec, &set)?;
    }
    let (messages, sfu) = compile_counted(
        ctx,
        vendor,
        program,
        &[(GlStage::Vertex, &vs), (GlStage::Fragment, &fs)],
    )?;
    Ok(with_sfu(
        executables(vendor, program, &messages, &["vertex", "fragment"])?,
        &sfu,
    ))
}

/// Compiles `stages` as one program: the driver's KHR_debug messages and, for a vendor that
/// [`Vendor::counts_sfu_ops`], the special-function operations per stage of the NIR Mesa
/// printed meanwhile (empty otherwise).
fn compile_counted(
    ctx: &GlContext,
    vendor: &dyn Vendor,
    program: &str,
    stages: &[(GlStage, &str)],
) -> Result<(Vec<String>, BTreeMap<String, f64>)> {
    if !vendor.counts_sfu_ops() {
        return Ok((ctx.compile(program, stages)?, BTreeMap::new()));
    }
    let (messages, dump) = super::stderr::capture_text(|| ctx.compile(program, stages))?;
    let messages = messages?;
    let sfu = throughput::sfu_ops_per_stage(&dump);
    Ok((messages, sfu))
}

/// `exes` with each stage's count of special-function operations of `sfu` added as the
/// statistic [`throughput::SFU_KEY`].
fn with_sfu(mut exes: Vec<Executable>, sfu: &BTreeMap<String, f64>) -> Vec<Executable> {
    for e in &mut exes {
        if let Some(&n) = sfu.get(&e.stage) {
            e.statistics.push(Statistic {
                name: throughput::SFU_KEY.into(),
                description: "special-function operations (rcp, rsq, sqrt, exp2, log2, sin, \
                              cos; pow as two) of the NIR Mesa handed the compiler"
                    .into(),
                value: StatValue::Float(n),
            });
        }
    }
    exes
}

/// Whether the context computes `mediump float` in float16: GL's shader precision format
/// gives 10 bits of precision there (float16's mantissa), 23 where mediump is float32.
pub fn float16_mediump(info: &GlInfo) -> bool {
    info.es.is_some() && (1..=10).contains(&info.mediump_bits)
}

/// One executable per stage of `stages` out of the driver's `messages` (the last message of a
/// stage wins: a driver that compiles a stage twice reports the variant it keeps last); an
/// error when a stage has none (the driver printed no statistics: nothing is measured).
pub fn executables(
    vendor: &dyn Vendor,
    program: &str,
    messages: &[String],
    stages: &[&str],
) -> Result<Vec<Executable>> {
    let mut by_stage: BTreeMap<String, Vec<(String, f64)>> = BTreeMap::new();
    for m in messages {
        if let Some((stage, stats)) = vendor.parse_debug_message(m) {
            by_stage.insert(stage, stats);
        }
    }
    stages
        .iter()
        .map(|&stage| {
            let stats = by_stage.remove(stage).ok_or_else(|| {
                Error::Device(format!(
                    "{program}: the driver sent no statistics for the {stage} shader \
                     (messages: {messages:?})"
                ))
            })?;
            Ok(Executable {
                name: stage.into(),
                description: format!("{stage} shader (the driver's shader-db line)"),
                stage: stage.into(),
                subgroup_size: 0,
                statistics: stats
                    .into_iter()
                    .map(|(name, v)| Statistic {
                        name,
                        description: String::new(),
                        value: StatValue::Float(v),
                    })
                    .collect(),
                representations: Vec::new(),
            })
        })
        .collect()
}
