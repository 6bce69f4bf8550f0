//! `shadelab verify`: parses, runs [`crate::verify::verify`], prints its table and verdict.
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::method;

pub(super) fn cmd_verify(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    against: Option<&str>,
    precision: method::Precision,
) -> Result<ExitCode> {
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
