//! `shadelab demo`: the quick start's report, `report --scenes scenes --out out/report`, as a
//! command of the installed binary.
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::report::{cmd_report, How, Sources};
use super::{DeviceArgs, StoreArgs};
use crate::error::Result;

/// The size of the demo's report: the report's default (its page under the 50 MB budget).
const SIZE: (u32, u32) = (256, 256);

// `shadelab demo` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct DemoArgs {
    /// The scene files (*.toml) of this folder.
    #[arg(long, default_value = "scenes")]
    scenes: PathBuf,
    /// Output directory of the report.
    #[arg(long, default_value = "out/report")]
    out: PathBuf,
    #[command(flatten)]
    device: DeviceArgs,
    #[command(flatten)]
    pub(super) store: StoreArgs,
}

impl DemoArgs {
    /// What demo writes and reads ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            input_dirs: vec![&self.scenes],
            ..Default::default()
        }
    }
}

pub(super) fn cmd_demo(a: &DemoArgs) -> Result<ExitCode> {
    let (scenes_dir, out, dev) = (a.scenes.as_path(), a.out.as_path(), &a.device);
    let src = Sources {
        scenes: Some(scenes_dir),
        scene: None,
        mesh: None,
        models: None,
    };
    let how = How {
        size: SIZE,
        interpolation: None,
        full: false,
        runs: None,
        tuned: None,
    };
    cmd_report(&src, &how, dev, "all", out)
}
