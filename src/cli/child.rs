//! `shadelab child REQUEST.json` (hidden): one job of a parent shadelab process, by the
//! protocol of [`crate::child`]: a bench run (`bench_run`) or one GPU family of `isa`
//! (`isa_family`). The reply goes to the file the request names.
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;

use crate::child::{self, Job};
use crate::error::{Error, Result};

// `shadelab child` (hidden; its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct ChildArgs {
    #[arg(value_name = "REQUEST.json", required_unless_present = "worker")]
    pub(super) request: Option<PathBuf>,
    /// Serve requests from stdin, one per line, until it closes: a compiler worker
    /// (src/workers/).
    #[arg(long, conflicts_with = "request")]
    pub(super) worker: bool,
}

pub(super) fn cmd(args: &ChildArgs) -> Result<ExitCode> {
    match &args.request {
        Some(file) if !args.worker => cmd_child(file),
        _ => {
            crate::workers::serve::serve(&worker_job)?;
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// A worker's job `name` on `request`.
fn worker_job(name: &str, request: serde_json::Value) -> Result<serde_json::Value> {
    match name {
        crate::isa::ChildRequest::NAME => {
            let r: crate::isa::ChildRequest = serde_json::from_value(request)
                .map_err(|e| Error::Usage(format!("worker {name}: not its request: {e}")))?;
            let report = crate::isa::child::compile(&r)?;
            serde_json::to_value(report).map_err(|e| Error::output("the worker's reply", e))
        }
        crate::explore::render::RenderRequest::NAME => {
            let r: crate::explore::render::RenderRequest = serde_json::from_value(request)
                .map_err(|e| Error::Usage(format!("worker {name}: not its request: {e}")))?;
            let reply = crate::explore::render::render(&r)?;
            serde_json::to_value(reply).map_err(|e| Error::output("the worker's reply", e))
        }
        other => Err(Error::Usage(format!(
            "unknown worker job {other:?} (a worker serves {} and {})",
            crate::isa::ChildRequest::NAME,
            crate::explore::render::RenderRequest::NAME
        ))),
    }
}

pub(super) fn cmd_child(file: &Path) -> Result<ExitCode> {
    let env = child::read(file)?;
    // The parent's verbosity (a level this shadelab does not know keeps the default).
    if let Ok(level) = env.log_level.parse() {
        log::set_max_level(level);
    }
    // Before anything resolves a method set: the parent's method files (a tuned one proven
    // again, as the parent did).
    // A file that does not load is the request's input refused, said as such (not a driver
    // that failed).
    let start = std::time::Instant::now();
    let loaded = crate::tune::check::check_files(&env.method_files)
        .and_then(|()| crate::gpu::shaders::register_user(&env.method_files));
    log::debug!(
        "child {}: {} method files checked and compiled in {:.0} ms",
        env.job,
        env.method_files.len(),
        start.elapsed().as_secs_f64() * 1e3
    );
    if let Err(e) = loaded {
        child::refuse(&env, &e)?;
        return Err(e);
    }
    match env.job.as_str() {
        crate::bench::runs::RunRequest::NAME => child::serve(env, bench_run)?,
        crate::isa::ChildRequest::NAME => child::serve(env, |r: crate::isa::ChildRequest| {
            crate::isa::child::compile(&r)
        })?,
        crate::explore::render::RenderRequest::NAME => {
            child::serve(env, |r: crate::explore::render::RenderRequest| {
                crate::explore::render::render(&r)
            })?
        }
        other => {
            return Err(Error::Usage(format!(
                "{}: unknown child job {other:?} (expected bench_run or isa_family)",
                file.display()
            )))
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// One measurement run of a bench of several runs: the same scene, device, methods and schedule
/// as the parent, with its clock, seed and `auto`'s decisions.
fn bench_run(req: crate::bench::runs::RunRequest) -> Result<crate::bench::runs::RunFigures> {
    let renderer = req.device.renderer()?;
    let scene = req.scene.load()?;
    let methods = req
        .methods
        .iter()
        .map(|m| crate::method::find(m))
        .collect::<Result<Vec<_>>>()?;
    let opts = crate::bench::BenchOptions {
        schedule: req.schedule,
        auto: req.auto,
        runs: crate::bench::Runs::Child(req.context),
        ..crate::bench::BenchOptions::default()
    };
    crate::bench::measure_run(&renderer, &scene, &methods, &opts)
}
