//! `shadelab report`: compare, bench and stress on the given scenes, one offline HTML page.
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};
use crate::report::{self, ReportOptions, ReportScene};

/// What the page of the shipped scenes may weigh, everything under DIR included (issue 14).
const PAGE_BUDGET_BYTES: u64 = 50_000_000;

/// The scene files (*.toml) of a folder, sorted (an error when there is none).
pub(super) fn scene_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(Error::Usage(format!(
            "no scene files (*.toml) in {}",
            dir.display()
        )));
    }
    Ok(files)
}

/// The command line as typed, each argument quoted where a shell would need it.
fn command_line() -> String {
    std::env::args()
        .map(|a| {
            if !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./=,:@%+".contains(c))
            {
                a
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Where the scenes come from: exactly one of `--scenes`, `--scene`, `--mesh`.
pub(super) struct Sources<'a> {
    pub scenes: Option<&'a Path>,
    pub scene: Option<&'a Path>,
    pub mesh: Option<&'a Path>,
}

pub(super) fn cmd_report(
    src: &Sources,
    size: (u32, u32),
    interpolation: Option<InterpArg>,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
    full: bool,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let args = |scene: Option<PathBuf>, mesh: Option<PathBuf>| SceneArgs {
        scene,
        mesh,
        size: Some(size),
        interpolation,
        cull: None,
    };
    let inputs: Vec<(PathBuf, SceneArgs)> = match (src.scenes, src.scene, src.mesh) {
        (Some(d), None, None) => scene_files(d)?
            .into_iter()
            .map(|f| (f.clone(), args(Some(f), None)))
            .collect(),
        (None, Some(f), None) => vec![(f.into(), args(Some(f.into()), None))],
        (None, None, Some(m)) => vec![(m.into(), args(None, Some(m.into())))],
        _ => {
            return Err(Error::Usage(
                "give exactly one of --scenes DIR, --scene FILE, --mesh FILE.obj".into(),
            ))
        }
    };
    let scenes = inputs
        .into_iter()
        .map(|(source, a)| {
            Ok(ReportScene {
                source,
                scene: load_scene(&a)?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let r = renderer(dev)?;
    let opts = ReportOptions {
        full,
        command_line: command_line(),
        progress: true,
    };
    let w = report::run(&r, &scenes, &methods, out, &opts)?;
    check_validation(r.context())?;
    eprintln!(
        "report: {} scene(s) x {} method(s) in {:.1} s; {} files, {:.1} MB in total",
        scenes.len(),
        w.methods,
        w.seconds,
        w.files,
        w.total_bytes as f64 / 1e6
    );
    if w.total_bytes > PAGE_BUDGET_BYTES {
        eprintln!(
            "report: warning: {:.1} MB is over the {} MB budget of a report (README); \
             use a smaller --size or fewer --methods",
            w.total_bytes as f64 / 1e6,
            PAGE_BUDGET_BYTES / 1_000_000
        );
    }
    println!("{}", w.index.display());
    Ok(ExitCode::SUCCESS)
}
