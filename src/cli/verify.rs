//! `shadelab verify`: parses, runs [`crate::verify::verify`], prints its table and verdict.
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::method;

// `shadelab verify` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct VerifyArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Judge every method against this method's f64 formula instead of its own (teeth checks).
    #[arg(long, value_name = "METHOD")]
    against: Option<String>,
    /// Precision of the programs: f16 judges them by the float16 bound (u = 2^-11) and,
    /// on Vulkan, against the software engine's float16 twin.
    #[arg(long, default_value = "f32", value_parser = parse_precision())]
    precision: crate::method::Precision,
}

pub(super) fn cmd_verify(a: &VerifyArgs) -> Result<ExitCode> {
    let VerifyArgs {
        scene: scene_args,
        device: dev,
        methods: list,
        against,
        precision,
    } = a;
    let (against, precision) = (against.as_deref(), *precision);
    let methods = select_methods(list)?;
    let against = against.map(method::find).transpose()?;
    for m in methods.iter().chain(against.iter()) {
        m.require_twin("verify")?;
    }
    let scene = load_scene(scene_args)?;
    if dev.engine == EngineArg::Software {
        let threads = crate::software::default_threads();
        let report =
            crate::verify::verify_software_at(&scene, &methods, against, threads, precision)?;
        print!("{}", report.table());
        return verdict(&report);
    }
    let r = renderer(dev)?.with_precision(precision)?;
    let report = crate::verify::verify_at(
        crate::engine::Engine::Vulkan(&r),
        &scene,
        &methods,
        against,
        precision,
    )?;
    print!("{}", report.table());
    check_validation(r.context())?;
    verdict(&report)
}

fn verdict(report: &crate::verify::VerifyReport) -> Result<ExitCode> {
    if report.passed() {
        return Ok(ExitCode::SUCCESS);
    }
    eprintln!(
        "outside the {} bound of {} formula (or of the float16 twin): {}",
        report.precision,
        report.judged_by(),
        report.failures().join("; ")
    );
    Ok(ExitCode::from(EXIT_THRESHOLD))
}
