//! `shadelab demo`: the quick start's report, `report --scenes scenes --out out/report`, as a
//! command of the installed binary.
use std::path::Path;
use std::process::ExitCode;

use super::report::{cmd_report, How, Sources};
use super::DeviceArgs;
use crate::error::Result;

/// The size of the demo's report: the report's default (its page under the 50 MB budget).
const SIZE: (u32, u32) = (256, 256);

pub(super) fn cmd_demo(scenes_dir: &Path, out: &Path, dev: &DeviceArgs) -> Result<ExitCode> {
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
