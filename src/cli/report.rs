//! `shadelab report`: compare, bench and stress on the given scenes, one offline HTML page.
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};
use crate::report::{self, ReportOptions, ReportScene};

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

/// Where the scenes come from: one of `--scenes`, `--scene`, `--mesh`, and/or `--models`.
pub(super) struct Sources<'a> {
    pub scenes: Option<&'a Path>,
    pub scene: Option<&'a Path>,
    pub mesh: Option<&'a Path>,
    pub models: Option<&'a Path>,
}

/// How every scene is drawn and measured.
pub(super) struct How {
    pub size: (u32, u32),
    pub interpolation: Option<InterpArg>,
    pub full: bool,
    pub runs: Option<usize>,
    /// `--tuned FILE`: tune's findings for the answer.
    pub tuned: Option<PathBuf>,
}

/// (path, is a mesh) of every scene the sources name.
fn inputs(src: &Sources) -> Result<Vec<(PathBuf, bool)>> {
    let given = [
        ("--scenes", src.scenes.is_some()),
        ("--scene", src.scene.is_some()),
        ("--mesh", src.mesh.is_some()),
    ];
    let named: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
    if named.len() > 1 {
        return Err(Error::Usage(format!(
            "{} cannot be used with {}: give one of --scenes DIR, --scene FILE, \
             --mesh FILE (--models DIR may be added to any)",
            named[0], named[1]
        )));
    }
    let mut v: Vec<(PathBuf, bool)> = Vec::new();
    if let Some(d) = src.scenes {
        v.extend(scene_files(d)?.into_iter().map(|f| (f, false)));
    }
    if let Some(f) = src.scene {
        v.push((f.into(), false));
    }
    if let Some(m) = src.mesh {
        v.push((m.into(), true));
    }
    if let Some(d) = src.models {
        v.extend(
            crate::geometry::mesh_files(d, crate::geometry::Depth::Flat, None)?
                .into_iter()
                .map(|f| (f, true)),
        );
    }
    if v.is_empty() {
        return Err(Error::Usage(
            "give one of --scenes DIR, --scene FILE, --mesh FILE, or --models DIR".into(),
        ));
    }
    Ok(v)
}

/// `shadelab report`: its arguments to [`cmd_report`].
pub(super) fn run_report(c: Command) -> Result<ExitCode> {
    let Command::Report {
        scenes,
        scene,
        mesh,
        models,
        runs,
        out,
        methods,
        size,
        interpolation,
        full,
        tuned,
        device,
        ..
    } = c
    else {
        return Err(Error::Internal(
            "run_report called with another command".into(),
        ));
    };
    let src = Sources {
        scenes: scenes.as_deref(),
        scene: scene.as_deref(),
        mesh: mesh.as_deref(),
        models: models.as_deref(),
    };
    let how = How {
        size,
        interpolation,
        full,
        runs,
        tuned,
    };
    cmd_report(&src, &how, &device, &methods, &out)
}

pub(super) fn cmd_report(
    src: &Sources,
    how: &How,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let started = std::time::SystemTime::now();
    // The measurement, decided once (src/bench/schedule.rs).
    let schedule = crate::bench::schedule::Schedule::new(
        crate::bench::schedule::Job::Report { full: how.full },
        &crate::bench::schedule::Given {
            runs: how.runs,
            ..Default::default()
        },
    )?;
    let scenes = inputs(src)?
        .into_iter()
        .map(|(source, is_mesh)| {
            let a = SceneArgs {
                scene: (!is_mesh).then(|| source.clone()),
                mesh: is_mesh.then(|| source.clone()),
                size: Some(how.size),
                interpolation: how.interpolation,
                cull: None,
            };
            Ok(ReportScene {
                scene: load_scene(&a)?,
                load: a.source(),
                source,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let r = renderer(dev)?;
    let opts = ReportOptions {
        full: how.full,
        command_line: command_line(),
        progress: true,
        schedule,
        exe: Some(std::env::current_exe().map_err(|e| Error::io(Path::new("shadelab"), e))?),
        device: crate::gpu::DeviceSpec {
            device: dev.device.clone(),
            validate: dev.validate,
            precision: crate::method::Precision::F32,
        },
        costs: crate::costs::builtin(),
        tuned: how.tuned.clone(),
    };
    let w = report::run(&r, &scenes, &methods, out, &opts)?;
    check_validation(r.context())?;
    // Every cell with -v; the words and the differing cells always.
    log::info!("{}", w.answer.lines().trim_end());
    eprintln!(
        "report: {} scene(s) x {} method(s) in {:.1} s; {} files, {:.1} MB. The answer ({}):",
        scenes.len(),
        w.methods,
        w.seconds,
        w.files,
        w.total_bytes as f64 / 1e6,
        out.join("answer.md").display()
    );
    eprint!("{}", w.answer.terminal());
    if w.total_bytes > report::SIZE_LIMIT_BYTES {
        log::warn!(
            "report: {:.1} MB is over the {} MB size limit of a report (docs/report.md); \
             use a smaller --size or fewer --methods",
            w.total_bytes as f64 / 1e6,
            report::SIZE_LIMIT_BYTES / 1_000_000
        );
    }
    warn_stale(out, started);
    println!("{}", w.index.display());
    Ok(ExitCode::SUCCESS)
}

/// Warns about the files of `out` this run did not write (an earlier report's, into the same
/// folder: its other scenes, methods or --full files), which the page does not link.
fn warn_stale(out: &Path, started: std::time::SystemTime) {
    fn walk(dir: &Path, started: std::time::SystemTime, found: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let Ok(meta) = e.metadata() else { continue };
            if meta.is_dir() {
                walk(&e.path(), started, found);
            } else if meta.modified().is_ok_and(|m| m < started) {
                found.push(e.path());
            }
        }
    }
    let mut stale = Vec::new();
    walk(out, started, &mut stale);
    if stale.is_empty() {
        return;
    }
    stale.sort();
    let shown: Vec<String> = stale
        .iter()
        .take(3)
        .map(|p| p.strip_prefix(out).unwrap_or(p).display().to_string())
        .collect();
    eprintln!(
        "report: warning: {} file(s) in {} are not from this run (an earlier report's: {}{}); \
         the page does not show them: remove them, or write the report into an empty folder",
        stale.len(),
        out.display(),
        shown.join(", "),
        if stale.len() > 3 { ", ..." } else { "" }
    );
}
