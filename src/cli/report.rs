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

// `shadelab report` (its help is the variant's doc comment).
#[derive(Args, Debug)]
#[command(group(ArgGroup::new("source").required(true).multiple(true).args(["scenes", "scene", "mesh", "models"])))]
pub(super) struct ReportArgs {
    /// Every scene file (*.toml) of DIR.
    #[arg(long, value_name = "DIR")]
    scenes: Option<PathBuf>,
    /// One scene file (TOML).
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// One mesh file, .obj, .gltf, .glb or .ply (camera fitted, default light and material).
    #[arg(long, value_name = "FILE")]
    mesh: Option<PathBuf>,
    /// Every mesh file (.obj, .gltf, .glb, .ply) of DIR as one more scene each (camera fitted),
    /// alone or added to --scenes / --scene / --mesh; the answer covers them.
    #[arg(long, value_name = "DIR")]
    models: Option<PathBuf>,
    /// Bench runs per scene, each a fresh process of this binary (`bench --runs`): the
    /// frame-time and isolated-cost verdicts come from the interval across runs (1: one
    /// run in this process; default 5).
    #[arg(long, value_name = "N", value_parser = count::<1, 100>)]
    runs: Option<usize>,
    /// Output directory (index.html and everything it shows).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Comma-separated method identifiers, or `all` (phong_exact and phong_unnormalized,
    /// the references of bench's ratios, are always included).
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Image size of every scene (the default keeps the page of the shipped scenes under
    /// 50 MB).
    #[arg(long, value_name = "WxH", value_parser = parse_size, default_value = "256x256")]
    size: (u32, u32),
    /// Interpolation of the varyings, overriding the scenes'.
    #[arg(long, value_enum)]
    interpolation: Option<InterpArg>,
    /// Bench's long setting (40 timed draws after 3 warm-ups; stress refined 8 rounds)
    /// instead of the short one (10 after 2; 2 rounds), and the static cost's disassembly
    /// and isolated kernels (DIR/isa/asm/: tens of MB).
    #[arg(long)]
    full: bool,
    /// The tune.json of `shadelab tune`: its winners show in the answer's cells ("a tuned
    /// approximation beats exact normalisation here") and in its words (copied to
    /// DIR/tune/tune.json).
    #[arg(long, value_name = "FILE.json")]
    tuned: Option<PathBuf>,
    #[command(flatten)]
    device: DeviceArgs,
    #[command(flatten)]
    pub(super) store: StoreArgs,
}

impl ReportArgs {
    /// What report writes and reads ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        let folder_of = super::checks::folder_of;
        let (scene, mesh) = (&self.scene, &self.mesh);
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("index.html"),
            inputs: [scene, mesh, &self.tuned]
                .into_iter()
                .filter_map(|p| p.as_deref())
                .collect(),
            // the folders of --scene and --mesh hold the report's inputs too
            input_dirs: [&self.scenes, &self.models]
                .into_iter()
                .filter_map(|p| p.as_deref())
                .chain(
                    [scene, mesh]
                        .into_iter()
                        .filter_map(|p| p.as_deref().map(folder_of)),
                )
                .collect(),
            ..Default::default()
        }
    }
}

/// `shadelab report`: its arguments to [`cmd_report`].
pub(super) fn run_report(a: ReportArgs) -> Result<ExitCode> {
    let ReportArgs {
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
    } = a;
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
