//! `shadelab skips`: what skipping saves on one scene ([`crate::bench::skips`]).
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};

// `shadelab skips` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct SkipsCmd {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// Output directory (skips.json, skips.md).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Interleaved rounds (each draws every row once; at most 100000).
    #[arg(long, default_value_t = 30, value_parser = count::<1, 100_000>)]
    repeat: usize,
    /// Discarded submissions per row (the first includes lavapipe's shader JIT; at most 1000).
    #[arg(long, default_value_t = 3, value_parser = count::<0, 1000>)]
    warmup: usize,
    #[command(flatten)]
    error_budget: BudgetArgs,
}

impl SkipsCmd {
    /// What skips reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            marker: Some("skips.json"),
            dir: Some(("--out", &self.out)),
            inputs: self.scene.files(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_skips(k: SkipsCmd) -> Result<ExitCode> {
    if k.device.engine == EngineArg::Software {
        return Err(Error::Usage(
            "skips measures the Vulkan renderer's draws: use --engine vulkan".into(),
        ));
    }
    let scene = load_scene(&k.scene)?;
    let r = renderer(&k.device)?;
    let opts = crate::bench::skips::SkipOptions {
        repeat: k.repeat,
        warmup: k.warmup,
        auto: auto_spec(&r, &k.error_budget)?,
        command_line: std::env::args().collect(),
        clock: None,
    };
    let report = crate::bench::skips::skips(&r, &scene, &k.out, &opts)?;
    print!("{}", report.markdown());
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}
