//! What the command line is checked for before anything runs: counts and sizes within their
//! bounds (clap's value parsers: a value out of range is exit 2 with the bound, before anything
//! is allocated), method lists, and output paths against inputs ([`check_paths`]: no output
//! replaces an input file, an output folder is a folder and not the folder of a report's
//! inputs).
use std::path::{Path, PathBuf};

use super::Command;
use crate::error::{Error, Result};
use crate::method::{self, Method};

/// A whole number from `MIN` to `MAX` (clap's value parser of every count flag).
pub(super) fn count<const MIN: usize, const MAX: usize>(s: &str) -> Result<usize, String> {
    match s.trim().parse::<u128>() {
        Ok(n) if (MIN as u128..=MAX as u128).contains(&n) => Ok(n as usize),
        _ => Err(format!(
            "{s:?} is not a count from {MIN} to {MAX} (the bound keeps a run to hours, not years)"
        )),
    }
}

/// [`count`] as a u32 (`--threads`).
pub(super) fn count_u32<const MIN: usize, const MAX: usize>(s: &str) -> Result<u32, String> {
    count::<MIN, MAX>(s).map(|n| n as u32)
}

/// A number of seconds in (0, [`MAX_SECONDS`]] (`--max-time`).
pub(super) fn seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= MAX_SECONDS => Ok(v),
        _ => Err(format!(
            "{s:?} is not a number of seconds above 0 and at most {MAX_SECONDS} (a day)"
        )),
    }
}

/// The longest time budget a flag takes: a day.
pub const MAX_SECONDS: f64 = 86_400.0;

/// A percentage, finite and >= 0 (`--until-ci`, which bench also wants above 0, and
/// `--fail-slower`): not a count, so any size is harmless (a huge `--until-ci` stops at once;
/// `--max-time` bounds how long it may go on).
pub(super) fn percent(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("{s:?} is not a percentage: a finite number >= 0")),
    }
}

/// `WIDTHxHEIGHT`, each 1 to [`crate::scene::MAX_IMAGE_SIZE`].
pub(super) fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let max = crate::scene::MAX_IMAGE_SIZE;
    let bad = || format!("expected WIDTHxHEIGHT such as 512x512, each 1 to {max}, got {s:?}");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=max).contains(n))
            .ok_or_else(bad)
    };
    Ok((parse(w)?, parse(h)?))
}

/// `--threshold` of compare and stress: a colour error, finite and >= 0 (a number or a fraction
/// like 1/255), validated here once.
pub(super) fn parse_threshold(s: &str) -> std::result::Result<f64, String> {
    let num = |x: &str| x.trim().parse::<f64>().ok();
    let v = match s.trim().split_once('/') {
        Some((a, b)) => num(a).zip(num(b)).map(|(a, b)| a / b),
        None => num(s),
    };
    v.filter(|v| v.is_finite() && *v >= 0.0).ok_or_else(|| {
        format!("{s:?} is not a threshold: expected a colour error >= 0 (linear), a number or a fraction like 1/255")
    })
}

/// `--methods`: at least one name (an empty list ran nothing and exited 0).
pub(super) fn method_list(s: &str) -> std::result::Result<String, String> {
    if s.split(',').all(|p| p.trim().is_empty()) {
        return Err(
            "no method given: name methods separated by commas (`shadelab list`), or `all`".into(),
        );
    }
    Ok(s.to_string())
}

/// The methods of a list (or `all`), each once: a name given twice is measured once, with a
/// note.
/// `all` stands for every method wherever it appears in the list (`all,all` or
/// `phong_exact,all`), so it is one name among the others, never an unknown method.
pub(super) fn select_methods(list: &str) -> Result<Vec<&'static Method>> {
    if list == "all" {
        return Ok(method::all());
    }
    let mut out: Vec<&'static Method> = Vec::new();
    let mut all_named = false;
    for s in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let named = if s == "all" {
            if std::mem::replace(&mut all_named, true) {
                eprintln!("shadelab: note: --methods names all more than once");
            }
            method::all()
        } else {
            vec![method::find(s)?]
        };
        for m in named {
            if !out.iter().any(|o| o.name == m.name) {
                out.push(m);
            } else if s != "all" {
                eprintln!(
                    "shadelab: note: --methods names {} more than once; it is measured once",
                    m.name
                );
            }
        }
    }
    Ok(out)
}

/// `--families` of `isa`: the ids of a comma-separated list, lower case, each once (a family
/// named twice is compiled and reported once, with a note, as `--methods` does); `all` is
/// `None` (every family set up).
pub(super) fn family_list(list: &str) -> Option<Vec<String>> {
    if list.trim() == "all" {
        return None;
    }
    let mut out: Vec<String> = Vec::new();
    for f in list.split(',').map(|s| s.trim().to_lowercase()) {
        if f.is_empty() {
            continue;
        }
        if out.contains(&f) {
            eprintln!(
                "shadelab: note: --families names {f} more than once; it is compiled and \
                 reported once"
            );
        } else {
            out.push(f);
        }
    }
    Some(out)
}

/// What a command writes and reads, for [`check_paths`].
#[derive(Default)]
pub(super) struct Io<'a> {
    /// Output files, by flag.
    pub files: Vec<(&'static str, &'a Path)>,
    /// The output folder, by flag.
    pub dir: Option<(&'static str, &'a Path)>,
    /// The file of `dir` that marks a run complete (written last, removed when a run starts).
    pub marker: Option<&'static str>,
    /// Input files (the method files are added for every command).
    pub inputs: Vec<&'a Path>,
    /// Folders holding what the command reads (a report's scenes and models and the folders
    /// of its scene or mesh file, a corpus, merge's shards): the output folder may not be one.
    pub input_dirs: Vec<&'a Path>,
}

/// The same file (or folder): the same inode where both exist, else the same absolute path.
fn same(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => std::path::absolute(a).ok() == std::path::absolute(b).ok(),
    }
}

/// The folder holding `file` (`.` for a bare name).
pub(super) fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Refuses outputs that would replace or mix with inputs: an output file that is an input
/// (`render --out s/good.toml` replaced its own scene with a PNG), two outputs naming one
/// file, an output folder that is a file (it said "File exists (os error 17)"), or the
/// folder of a report's, corpus's or merge's inputs. Run before anything is read or written.
pub(super) fn check_outputs(io: &Io, method_files: &[PathBuf]) -> Result<()> {
    let inputs: Vec<&Path> = io
        .inputs
        .iter()
        .copied()
        .chain(method_files.iter().map(PathBuf::as_path))
        .collect();
    for (i, (flag, out)) in io.files.iter().enumerate() {
        if let Some(input) = inputs.iter().find(|i| same(out, i)) {
            return Err(Error::Usage(format!(
                "{flag} {}: that is an input of this command ({}): writing it would replace \
                 it; name another file",
                out.display(),
                input.display()
            )));
        }
        if out.is_dir() {
            return Err(Error::Usage(format!(
                "{flag} {}: that is a folder; name a file in it",
                out.display()
            )));
        }
        if let Some((other, _)) = io.files[..i].iter().find(|(_, o)| same(out, o)) {
            return Err(Error::Usage(format!(
                "{flag} {} and {other} name the same file; give each its own",
                out.display()
            )));
        }
    }
    let Some((flag, dir)) = io.dir else {
        return Ok(());
    };
    if dir.exists() && !dir.is_dir() {
        let what = if inputs.iter().any(|i| same(dir, i)) {
            "an input file of this command"
        } else {
            "a file"
        };
        return Err(Error::Usage(format!(
            "{flag} {}: that is {what}, and {flag} takes a folder (created if missing): name \
             another folder, or remove the file",
            dir.display()
        )));
    }
    if let Some(f) = io.input_dirs.iter().find(|f| same(dir, f)) {
        return Err(Error::Usage(format!(
            "{flag} {}: that is the folder of this command's inputs ({}); its outputs would \
             mix with them: name another folder",
            dir.display(),
            f.display()
        )));
    }
    Ok(())
}

/// The outputs and inputs of `command` ([`Io`]).
pub(super) fn io_of(command: &Command) -> Io<'_> {
    match command {
        Command::Render(a) => a.io(),
        Command::Compare(a) => a.io(),
        Command::Bench(b) => b.io(),
        Command::Skips(k) => k.io(),
        Command::Stress(a) => a.io(),
        Command::Mesh(a) => a.io(),
        Command::Demo(a) => a.io(),
        Command::Report(a) => a.io(),
        Command::Tune(a) => a.io(),
        Command::Isa(a) => a.io(),
        Command::Prove(a) => a.io(),
        Command::Corpus(a) => a.io(),
        Command::Merge(a) => a.io(),
        _ => Io::default(),
    }
}

/// Refuses outputs of `render` that name the OBJ its scene file reads (known once the scene
/// is read).
pub(super) fn not_the_mesh(
    files: &[(&'static str, Option<&Path>)],
    scene: &crate::scene::Scene,
) -> Result<()> {
    let io = Io {
        files: files.iter().filter_map(|&(f, p)| Some((f, p?))).collect(),
        inputs: vec![Path::new(&scene.mesh.source)],
        ..Io::default()
    };
    check_outputs(&io, &[])
}

/// What every command does before it runs: no output replaces an input ([`check_paths`]);
/// the method files registered (before anything resolves a method set or starts a thread or a
/// child), a tuned file's line proven again before its code is compiled; the temporary
/// folders of runs killed before they could clean up removed; in the output folder, what killed
/// runs left removed and the completion marker of the last run removed (a run that fails from
/// here on leaves none).
pub(super) fn before_running(cli: &super::Cli) -> Result<()> {
    let marker = check_paths(cli)?;
    crate::tune::check::check_files(&cli.method_file)?;
    crate::gpu::shaders::register_user(&cli.method_file)?;
    if !matches!(cli.command, Command::Child(_)) {
        crate::cleanup::sweep_temp_dir();
    }
    if let Some(m) = &marker {
        crate::cleanup::sweep_tree(m.parent().unwrap_or(Path::new(".")));
        crate::output::remove_marker(m)?;
    }
    Ok(())
}

/// [`check_outputs`] of the parsed command line; the path of its completion marker.
pub(super) fn check_paths(cli: &super::Cli) -> Result<Option<PathBuf>> {
    let io = io_of(&cli.command);
    check_outputs(&io, &cli.method_file)?;
    Ok(io.dir.zip(io.marker).map(|((_, d), m)| d.join(m)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `all` is one name of the list wherever it stands (`--methods all,all` said 'unknown
    /// method "all"'), and a family named twice is one family (`isa --families
    /// amd:navi21,amd:navi21` gave two identical columns).
    #[test]
    fn all_and_a_name_given_twice_select_each_method_once() {
        let names =
            |l: &str| -> Vec<&str> { select_methods(l).unwrap().iter().map(|m| m.name).collect() };
        let every: Vec<&str> = method::all().iter().map(|m| m.name).collect();
        assert_eq!(names("all,all"), every);
        assert_eq!(names(" all , all "), every);
        let mut gouraud_first = vec!["gouraud"];
        gouraud_first.extend(every.iter().filter(|n| **n != "gouraud"));
        assert_eq!(names("gouraud,all"), gouraud_first);
        assert!(select_methods("all,nonsense").is_err());
        assert_eq!(
            family_list("amd:navi21, AMD:navi21,intel:tgl"),
            Some(vec!["amd:navi21".to_string(), "intel:tgl".to_string()])
        );
        assert_eq!(family_list(" all "), None);
    }

    #[test]
    fn counts_are_bounded_and_say_their_bound() {
        assert_eq!(count::<1, 100>("5"), Ok(5));
        for bad in ["0", "101", "99999999999", "1e9", "-1", "", "x"] {
            let why = count::<1, 100>(bad).unwrap_err();
            assert!(why.contains("from 1 to 100"), "{bad}: {why}");
        }
        assert_eq!(parse_size("64x32"), Ok((64, 32)));
        for bad in ["0x5", "16385x16", "64", "64x"] {
            assert!(parse_size(bad).unwrap_err().contains("1 to 16384"), "{bad}");
        }
        assert!(seconds("1e300").is_err() && seconds("0").is_err() && seconds("60").is_ok());
        assert!(percent("5").is_ok() && percent("nan").is_err() && percent("-1").is_err());
        assert!(method_list("").is_err() && method_list(" , ").is_err());
        assert_eq!(method_list("a,b").as_deref(), Ok("a,b"));
    }

    fn render<'a>(out: &'a Path, float: Option<&'a Path>, scene: &'a Path) -> Io<'a> {
        Io {
            files: [("--out", Some(out)), ("--float", float)]
                .into_iter()
                .filter_map(|(f, p)| Some((f, p?)))
                .collect(),
            inputs: vec![scene],
            ..Io::default()
        }
    }

    fn folder<'a>(out: &'a Path, scene: &'a Path, input_dirs: Vec<&'a Path>) -> Io<'a> {
        Io {
            dir: Some(("--out", out)),
            inputs: vec![scene],
            input_dirs,
            ..Io::default()
        }
    }

    #[test]
    fn outputs_never_replace_inputs() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("good.toml");
        std::fs::write(&scene, "x").unwrap();
        let png = dir.path().join("a.png");
        let err = |io: Io| check_outputs(&io, &[]).unwrap_err().to_string();
        assert!(check_outputs(&render(&png, None, &scene), &[]).is_ok());
        let why = err(render(&scene, None, &scene));
        assert!(why.contains("is an input of this command"), "{why}");
        // the same file by another spelling
        let other = dir.path().join(".").join("good.toml");
        assert!(check_outputs(&render(&other, None, &scene), &[]).is_err());
        let why = err(render(&png, Some(&png), &scene));
        assert!(why.contains("name the same file"), "{why}");
        // a method file is an input of every command
        assert!(check_outputs(&render(&png, None, &scene), std::slice::from_ref(&png)).is_err());
        // an output folder that is a file, or the folder of a report's inputs
        let why = err(folder(&scene, &scene, vec![]));
        assert!(
            why.contains("takes a folder") && !why.contains("os error"),
            "{why}"
        );
        let why = err(folder(dir.path(), &scene, vec![dir.path()]));
        assert!(why.contains("folder of this command's inputs"), "{why}");
        let sub = dir.path().join("out");
        assert!(check_outputs(&folder(&sub, &scene, vec![dir.path()]), &[]).is_ok());
        // without input folders (compare), the inputs' folder is a valid output folder
        assert!(check_outputs(&folder(dir.path(), &scene, vec![]), &[]).is_ok());
    }
}
