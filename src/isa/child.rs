//! The child side of `shadelab isa`: one process per GPU family, started by [`super::run`]
//! with RADV's null device selected in its environment (so that a driver crash takes down the
//! child only). It builds the timed draw's pipelines and the isolated kernels on that device,
//! reads back what the compiler made of them and prints one [`ChildReport`] as JSON on stdout.
//! Nothing is ever submitted: the null device compiles, it cannot execute.
use crate::isa::request::CompiledKind;
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
    compile_on(vendor, &chip, req)
}

/// [`compile`] on `vendor`'s `chip`: through the Mesa driver its [`Api`] names, or its own
/// compiler ([`Api::Own`]).
fn compile_on(vendor: &dyn Vendor, chip: &str, req: &ChildRequest) -> Result<ChildReport> {
    match vendor.api() {
        Api::Vulkan { device } => compile_vulkan(req, vendor, chip, device),
        Api::OpenGl | Api::OpenGlEs => super::gl_child::compile(req, vendor, chip),
        Api::Own => vendor.compile_own(req, chip),
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
    log::debug!(
        "{}: {} created in {:.0} ms",
        req.family,
        info.name,
        start.elapsed().as_secs_f64() * 1e3
    );
    vendor
        .check_device(chip, &info.name)
        .map_err(|why| Error::Device(format!("{}: {why}", req.family)))?;
    let keep = |exes| keep_disassembly(vendor.merge_executables(chip, exes));
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
                kind: CompiledKind::Draw,
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
                    kind: CompiledKind::Kernel,
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
        kind: CompiledKind::Probe,
        repeat: None,
        executables: pipeline.executables()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::vk::{StatValue, Statistic};
    use crate::isa::route::{Compiler, Ranking, Setup};
    use crate::method::Precision;
    use crate::scene::Interpolation;

    /// A route outside Mesa: Khronos' SPIR-V as the "compiler", its instruction count the
    /// statistic. Nothing of it is in [`crate::isa::route`]'s code: the seam is all it needs.
    struct SpirvWords;

    fn instructions(words: &[u8]) -> u64 {
        let word = |i: usize| u32::from_le_bytes(words[4 * i..4 * i + 4].try_into().unwrap());
        let (mut i, mut n) = (5, 0);
        while 4 * i < words.len() {
            i += (word(i) >> 16).max(1) as usize;
            n += 1;
        }
        n
    }

    impl Vendor for SpirvWords {
        fn prefix(&self) -> &'static str {
            "spirv"
        }
        fn name(&self) -> &'static str {
            "SPIR-V"
        }
        fn default_chips(&self) -> &'static [&'static str] {
            &["words"]
        }
        fn known_chips(&self) -> Vec<&'static str> {
            vec!["words"]
        }
        fn api(&self) -> Api {
            Api::Own
        }
        fn compiler(&self) -> Compiler {
            Compiler {
                driver: "none (the SPIR-V itself)".into(),
                api: "own".into(),
                mesa_version: None,
                production: false,
                note: "a test route".into(),
            }
        }
        fn ranking(&self) -> Ranking {
            Ranking {
                key: "instructions".into(),
                stage: "fragment".into(),
                kind: crate::isa::request::RowKind::Draw,
                unit: "instructions".into(),
                meaning: "SPIR-V instructions".into(),
            }
        }
        fn required_statistics(&self) -> &'static [&'static str] {
            &["instructions"]
        }
        fn float16(&self, _chip: &str) -> Option<bool> {
            Some(false)
        }
        fn setup(&self, _: Option<&Path>) -> std::result::Result<Setup, String> {
            Ok(Setup::default())
        }
        fn setup_command(&self) -> &'static str {
            "nothing"
        }
        fn child_env(
            &self,
            _: &str,
            _: &Setup,
            _: Option<&Path>,
        ) -> std::result::Result<Vec<(String, String)>, String> {
            Ok(Vec::new())
        }
        fn check_device(&self, _: &str, _: &str) -> std::result::Result<(), String> {
            Ok(())
        }
        fn compile_own(&self, req: &ChildRequest, chip: &str) -> Result<ChildReport> {
            let mut compiled = Vec::new();
            for name in &req.methods {
                let m = method::find(name)?;
                let program = crate::gpu::shaders::program_name_in(
                    m.name,
                    Interpolation::ScreenLinear,
                    req.precision,
                );
                let spirv = crate::gpu::shaders::embedded(&program, "frag")?;
                compiled.push(Compiled {
                    method: m.name.to_string(),
                    program,
                    kind: CompiledKind::Draw,
                    repeat: None,
                    executables: vec![Executable {
                        name: "fragment".into(),
                        description: String::new(),
                        stage: "fragment".into(),
                        subgroup_size: 1,
                        statistics: vec![Statistic {
                            name: "instructions".into(),
                            description: "SPIR-V instructions".into(),
                            value: StatValue::Uint(instructions(spirv)),
                        }],
                        representations: Vec::new(),
                    }],
                });
            }
            Ok(ChildReport {
                family: format!("spirv:{chip}"),
                device_name: chip.into(),
                driver_name: "none".into(),
                driver_info: String::new(),
                api_version: String::new(),
                compiled,
                elapsed_ms: 0.0,
                float16: Some(false),
                skipped: Vec::new(),
            })
        }
    }

    fn request(methods: &[&str]) -> ChildRequest {
        ChildRequest {
            family: "spirv:words".into(),
            methods: methods.iter().map(|m| m.to_string()).collect(),
            scene: None,
            kernel_counts: [1, 2],
            probes: Vec::new(),
            precision: Precision::F32,
            draws_only: true,
        }
    }

    fn count(r: &ChildReport, method: &str) -> f64 {
        let c = r.compiled.iter().find(|c| c.method == method).unwrap();
        c.executables[0].statistics[0].value.as_f64()
    }

    #[test]
    fn a_route_outside_mesa_compiles_through_its_own_compiler() {
        let names = [crate::method::PHONG_EXACT, "newton_raphson"];
        let r = compile_on(&SpirvWords, "words", &request(&names)).unwrap();
        assert_eq!(r.compiled.len(), 2);
        // the figures are the programs' own: newton_raphson's program is longer
        assert!(count(&r, "newton_raphson") > count(&r, crate::method::PHONG_EXACT));
        assert!(count(&r, crate::method::PHONG_EXACT) > 10.0);
    }

    /// A Mesa route has no compiler of its own: asking it is an error, not an empty reply.
    #[test]
    fn a_mesa_route_has_no_compiler_of_its_own() {
        let amd = &crate::isa::route::amd::Amd;
        let e = amd
            .compile_own(&request(&["gouraud"]), "navi21")
            .unwrap_err();
        assert!(e.to_string().contains("no compiler of its own"), "{e}");
    }
}
