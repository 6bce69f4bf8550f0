//! The contract under hostile but fair input (issue 49's probes): no wrong figure at exit 0, no
//! crash, nothing left behind. One test per probe, each run on the built binary and each shown
//! to fail on the build before the fix (`SHADELAB_TEST_BIN=/path/to/old/shadelab` runs the
//! same probes on another build; the tests that also call the library need this one). The slow
//! probes (a full disk, a read-only folder, kills at set moments) are scripts/hostile.sh's.
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support::*;

/// The binary under test: `SHADELAB_TEST_BIN` when set (an older build, to watch a probe
/// fail), else this build's.
fn shadelab() -> Command {
    let mut c = match std::env::var_os("SHADELAB_TEST_BIN").filter(|v| !v.is_empty()) {
        Some(b) => {
            let mut c = Command::new(b);
            c.current_dir(root()).env("SHADELAB_CACHE_DIR", "");
            c
        }
        None => bin(),
    };
    c.stdin(Stdio::null());
    c
}

/// Runs the binary with `env`, killed after `limit` (an old build that would run for years):
/// (exit code, -1 for a signal or the limit; stdout; stderr).
fn run_limited(args: &[&str], env: &[(&str, &str)], limit: Duration) -> (i32, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let (o, e) = (dir.path().join("out"), dir.path().join("err"));
    let mut c = shadelab();
    c.args(args)
        .stdout(std::fs::File::create(&o).unwrap())
        .stderr(std::fs::File::create(&e).unwrap());
    for (k, v) in env {
        c.env(k, v);
    }
    let mut child = c.spawn().expect("run shadelab");
    let start = Instant::now();
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code().unwrap_or(-1);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break -1;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
    (code, read(&o), read(&e))
}

/// [`run_limited`] within a minute, without extra environment.
fn go(args: &[&str]) -> (i32, String, String) {
    run_limited(args, &[], Duration::from_secs(60))
}

/// Exit 2 and `needle` in the error (and no panic, no backtrace).
#[track_caller]
fn refused(args: &[&str], needle: &str) -> String {
    let (code, out, err) = go(args);
    assert_eq!(code, 2, "{args:?}: stdout {out}\nstderr {err}");
    assert!(err.contains(needle), "{args:?}: {needle:?} not in:\n{err}");
    assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "{err}"
    );
    err
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A scene file in `dir` whose camera looks away from the shipped cube: no pixel covered.
fn looking_away(dir: &Path) -> PathBuf {
    let away = dir.join("away.toml");
    std::fs::write(
        &away,
        format!(
            "[mesh]\nobj = \"{}\"\n[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 6.0]\n",
            root().join("scenes/cube.obj").display()
        ),
    )
    .unwrap();
    away
}

/// Every file below `dir` whose name starts with `.shadelab-` (a temporary file).
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return found;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            found.extend(temporaries(&p));
        } else if e.file_name().to_string_lossy().starts_with(".shadelab-") {
            found.push(p);
        }
    }
    found
}

/// Probe 1. A UTF-8 byte-order mark made the first statement unknown and shifted every index:
/// the mesh lost `v 9 9 9`, exit 0. Now the file renders as the same file without the mark.
#[test]
fn an_obj_with_a_byte_order_mark_is_the_same_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let text = "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (plain, bom) = (dir.path().join("plain.obj"), dir.path().join("bom.obj"));
    std::fs::write(&plain, text).unwrap();
    std::fs::write(&bom, [b"\xEF\xBB\xBF".as_slice(), text.as_bytes()].concat()).unwrap();
    let png = |mesh: &Path, name: &str| {
        let out = dir.path().join(name);
        let (code, _, err) = go(&[
            "render",
            "--mesh",
            s(mesh),
            "--size",
            "32x32",
            "--out",
            s(&out),
        ]);
        assert_eq!(code, 0, "{err}");
        std::fs::read(out).unwrap()
    };
    assert_eq!(png(&bom, "bom.png"), png(&plain, "plain.png"));
    // and a binary glTF is read as one, by its magic bytes (here a header cut short says so)
    let glb = dir.path().join("m.glb");
    std::fs::write(&glb, b"glTF\x02\x00\x00\x00\x10\x00\x00\x00").unwrap();
    let out = dir.path().join("x.png");
    refused(
        &["render", "--mesh", s(&glb), "--out", s(&out)],
        "truncated .glb",
    );
}

/// Probe 2. A tuned file whose line's domain was edited to [0, 100] was accepted as proven and
/// auto drew it where it was never proven (non-finite pixels, exit 0). Now the line is proven
/// again when the file is loaded: the file as tune wrote it is accepted, the edited one refused.
#[test]
fn a_tuned_file_with_an_edited_domain_is_refused() {
    use shadelab::method::tuned::{Tuned, TunedForm};
    let dir = tempfile::tempdir().unwrap();
    // tune's newton k1 seed d1 for sphere_coarse
    let mut t = Tuned {
        form: TunedForm::Newton,
        steps: 1,
        coeffs: vec![f64::from(1.5775199f32), f64::from(-0.57940733f32)],
        domain: [0.8181351227401077, 1.0000005513794614],
        length_error: None,
    };
    t.length_error = Some(shadelab::tune::check::line_bound(&t));
    let write = |name: &str, t: &Tuned| {
        let p = dir.path().join(format!("{name}.glsl"));
        std::fs::write(&p, format!("{}\n{}", t.line(), t.code())).unwrap();
        p
    };
    let good = write("tuned_as_written", &t);
    let edited = write(
        "tuned_edited",
        &Tuned {
            domain: [0.0, 100.0],
            ..t.clone()
        },
    );
    let out = dir.path().join("c");
    let compare = |file: &Path| {
        go(&[
            "--method-file",
            s(file),
            "compare",
            "--scene",
            "scenes/sphere_coarse.toml",
            "--size",
            "64x64",
            "--methods",
            "auto",
            "--out",
            s(&out),
        ])
    };
    let (code, _, err) = compare(&good);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = compare(&edited);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("tuned_edited.glsl") && err.contains("not proven on its domain"),
        "{err}"
    );
}

/// Probe 2, its pixels: with the file as tune wrote it, auto still draws the form at the
/// sliver pixels whose rasterizer weights leave their triangle (sphere_coarse at 128x128 has
/// two, where the interpolated normal is ~1e9 long and the polynomial overflows). Those
/// non-finite pixels were written at exit 0; now they fail the run (exit 1, a line naming
/// them), in compare and in render.
#[test]
fn non_finite_pixels_of_auto_fail_the_run() {
    use shadelab::method::tuned::{Tuned, TunedForm};
    let dir = tempfile::tempdir().unwrap();
    // tune's minimax d2 for sphere_coarse (its line, 2026-11-28)
    let mut t = Tuned {
        form: TunedForm::Minimax,
        steps: 0,
        coeffs: vec![
            f64::from(1.9718021f32),
            f64::from(-1.451024f32),
            f64::from(0.47930086f32),
        ],
        domain: [0.8181351227401077, 1.0000005513794614],
        length_error: None,
    };
    t.length_error = Some(shadelab::tune::check::line_bound(&t));
    let file = dir.path().join("sphere_coarse_minimax2.glsl");
    std::fs::write(&file, format!("{}\n{}", t.line(), t.code())).unwrap();
    let common = ["--scene", "scenes/sphere_coarse.toml", "--size", "128x128"];
    let mut compare = vec!["--method-file", s(&file), "compare", "--methods", "auto"];
    compare.extend(common);
    let out = dir.path().join("c");
    compare.extend(["--out", s(&out)]);
    let (code, stdout, err) = go(&compare);
    let bad = read_json(out.join("summary.json"))["methods"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "auto")
        .unwrap()["non_finite_pixels"]
        .as_u64()
        .unwrap();
    if bad == 0 {
        // another driver's rasterizer may draw no sliver pixel here: then exit 0 is right
        assert_eq!(code, 0, "{err}");
        eprintln!("note: no non-finite pixel of auto on this driver (Mesa 22.3.6 draws 2)");
        return;
    }
    assert_eq!(code, 1, "{stdout}\n{err}");
    assert!(
        err.contains(&format!(
            "threshold exceeded: auto: {bad} non-finite pixel(s)"
        )),
        "{err}"
    );
    let mut render = vec!["--method-file", s(&file), "render", "--method", "auto"];
    render.extend(common);
    let png = dir.path().join("a.png");
    render.extend(["--out", s(&png)]);
    let (code, _, err) = go(&render);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("non-finite pixel(s)") && png.is_file(),
        "{err}"
    );
}

/// Probe 3. Unknown chips exited 0 with "0 compiled" (isa) or died of a child's SIGABRT
/// (--cost-model); now each is refused before any child starts, naming the known chips.
#[test]
fn unknown_chips_are_refused_with_the_known_ones() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("isa");
    for (family, vendor) in [
        ("nonsense", "amd"),
        ("amd:nonsense", "amd"),
        ("intel:nonsense", "intel"),
    ] {
        let err = refused(
            &[
                "isa",
                "--methods",
                "phong_exact",
                "--families",
                family,
                "--out",
                s(&out),
            ],
            &format!("unknown chip 'nonsense' for {vendor}; known: "),
        );
        assert!(!out.join("isa.json").exists(), "{err}");
    }
    refused(
        &[
            "render",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "16x16",
            "--method",
            "auto",
            "--cost-model",
            "isa:amd:nonsense",
            "--out",
            s(&dir.path().join("a.png")),
        ],
        "unknown chip 'nonsense' for amd; known: tahiti",
    );
}

/// Probe 4. `[image] width = 64` alone rendered 64x512 without a word.
#[test]
fn half_an_image_size_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("half.toml");
    std::fs::write(
        &scene,
        format!(
            "[mesh]\nobj = \"{}\"\n[image]\nwidth = 64\n",
            root().join("scenes/cube.obj").display()
        ),
    )
    .unwrap();
    let png = dir.path().join("h.png");
    refused(
        &["render", "--scene", s(&scene), "--out", s(&png)],
        &format!(
            "{}:4: [image] gives width = 64 but no height",
            scene.display()
        ),
    );
    assert!(!png.exists());
}

/// Probe 5. Absurd counts aborted allocating 8 TB (`--runs 99999999999`: exit 134 with a
/// backtrace) or were accepted and would run for years; each is now exit 2 giving its bound.
#[test]
fn absurd_counts_are_refused_with_their_bound() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b");
    let scene = ["--scene", "scenes/cube.toml", "--size", "16x16"];
    for (flag, value, bound) in [
        ("--runs", "99999999999", "from 1 to 100"),
        ("--runs", "1e9", "from 1 to 100"),
        ("--repeat", "99999999999", "from 1 to 100000"),
        ("--isolated-rounds", "99999999999", "from 0 to 10000"),
        ("--warmup", "99999999999", "from 0 to 1000"),
        ("--threads", "99999999999", "from 0 to 1024"),
        ("--max-time", "1e300", "at most 86400"),
    ] {
        let mut args = vec!["bench"];
        args.extend(scene);
        args.extend([flag, value, "--out", s(&out)]);
        let (code, _, err) = run_limited(&args, &[], Duration::from_secs(20));
        assert_eq!(code, 2, "{flag} {value}: {err}");
        assert!(err.contains(bound), "{flag} {value}: {err}");
    }
    for args in [
        vec![
            "skips",
            "--scene",
            "scenes/cube.toml",
            "--repeat",
            "99999999999",
            "--out",
            s(&out),
        ],
        vec!["stress", "--refine", "99999999999", "--out", s(&out)],
        vec![
            "report",
            "--scene",
            "scenes/cube.toml",
            "--runs",
            "1000",
            "--out",
            s(&out),
        ],
        vec![
            "corpus",
            "scenes",
            "--bench",
            "--runs",
            "1000",
            "--out",
            s(&out),
        ],
        vec![
            "render",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "0x0",
            "--out",
            "x.png",
        ],
        vec![
            "render",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "99999x8",
            "--out",
            "x.png",
        ],
    ] {
        let (code, _, err) = run_limited(&args, &[], Duration::from_secs(20));
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(" to "), "{args:?} names no bound: {err}");
    }
}

/// Probe 6. isa wrote its disassembly in place (a full disk left 0-byte .s files): now
/// through the atomic writer, which replaces a file rather than writing into it, as the
/// hard link shows (a plain write changed the linked file too).
#[test]
fn the_disassembly_is_replaced_not_written_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("isa");
    let args = [
        "isa",
        "--methods",
        "phong_exact",
        "--families",
        "navi21",
        "--out",
        s(&out),
    ];
    let (code, _, err) = go(&args);
    assert_eq!(code, 0, "{err}");
    let asm = out.join("asm/amd_navi21");
    let file = std::fs::read_dir(&asm)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|x| x == "s"))
        .expect("a disassembly file");
    let precious = dir.path().join("precious.txt");
    std::fs::write(&precious, "not a disassembly").unwrap();
    std::fs::remove_file(&file).unwrap();
    std::fs::hard_link(&precious, &file).unwrap();
    let (code, _, err) = go(&args);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read_to_string(&precious).unwrap(),
        "not a disassembly"
    );
    assert!(std::fs::metadata(&file).unwrap().len() > 0);
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
}

/// Probe 7. compare that failed at summary.csv left a complete summary.json (and a failed
/// re-run left the last run's): a script took the failure for a success. The marker is now
/// removed when a run starts and written last.
#[test]
fn a_failed_run_leaves_no_completion_marker() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let args = [
        "compare",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "16x16",
        "--methods",
        "gouraud",
        "--out",
        s(&out),
    ];
    let (code, _, err) = go(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.join("summary.json").is_file());
    // summary.csv cannot be written: a folder holds its name
    std::fs::remove_file(out.join("summary.csv")).unwrap();
    std::fs::create_dir(out.join("summary.csv")).unwrap();
    std::fs::write(out.join("summary.csv").join("x"), "").unwrap();
    let (code, _, err) = go(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("summary.csv"), "{err}");
    assert!(
        !out.join("summary.json").exists(),
        "the failed run left a summary.json"
    );
    assert!(temporaries(&out).is_empty(), "{:?}", temporaries(&out));
}

/// Probe 8. `render --out s/good.toml` replaced its own scene with a PNG, exit 0; an --out
/// naming an existing file said "File exists (os error 17)"; a report into the folder of its
/// scenes mixed its files with them.
#[test]
fn outputs_never_replace_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("good.toml");
    let obj = dir.path().join("cube.obj");
    std::fs::copy(root().join("scenes/cube.obj"), &obj).unwrap();
    let text = "[mesh]\nobj = \"cube.obj\"\n";
    std::fs::write(&scene, text).unwrap();
    refused(
        &["render", "--scene", s(&scene), "--out", s(&scene)],
        "that is an input of this command",
    );
    refused(
        &["render", "--scene", s(&scene), "--out", s(&obj)],
        "that is an input of this command",
    );
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), text);
    assert_eq!(
        std::fs::read(&obj).unwrap(),
        std::fs::read(root().join("scenes/cube.obj")).unwrap()
    );
    let err = refused(
        &["compare", "--scene", s(&scene), "--out", s(&obj)],
        "--out takes a folder",
    );
    assert!(!err.contains("os error 17"), "{err}");
    refused(
        &["report", "--scenes", s(dir.path()), "--out", s(dir.path())],
        "that is the folder of this command's inputs",
    );
    refused(
        &["report", "--scene", s(&scene), "--out", s(dir.path())],
        "that is the folder of this command's inputs",
    );
}

/// The processes whose parent is `pid` (from /proc).
fn children_of(pid: u32) -> Vec<u32> {
    let mut out = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Some(p) = e.file_name().to_str().and_then(|n| n.parse::<u32>().ok()) else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{p}/stat")) else {
            continue;
        };
        let ppid = stat
            .rsplit_once(')')
            .and_then(|(_, r)| r.split_whitespace().nth(1))
            .and_then(|v| v.parse::<u32>().ok());
        if ppid == Some(pid) {
            out.push(p);
        }
    }
    out
}

/// Whether process `pid` still runs (not gone, not a zombie).
pub(crate) fn running(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| {
            s.rsplit_once(')')
                .map(|(_, r)| r.trim_start().starts_with('Z'))
        })
        .is_some_and(|zombie| !zombie)
}

fn cmdline(pid: u32) -> String {
    std::fs::read(format!("/proc/{pid}/cmdline"))
        .map(|b| String::from_utf8_lossy(&b).replace('\0', " "))
        .unwrap_or_default()
}

/// The children of `parent` whose command line contains `pattern`, as soon as there is one;
/// fails when `parent` ends first or none comes within `within`.
pub(crate) fn children_seen(
    parent: &mut std::process::Child,
    pattern: &str,
    within: Duration,
) -> Vec<u32> {
    let start = Instant::now();
    loop {
        let kids: Vec<u32> = children_of(parent.id())
            .into_iter()
            .filter(|&c| cmdline(c).contains(pattern))
            .collect();
        if !kids.is_empty() {
            return kids;
        }
        assert!(
            parent.try_wait().unwrap().is_none(),
            "the parent ended before a child {pattern:?} was seen"
        );
        assert!(
            start.elapsed() < within,
            "no child {pattern:?} in {within:?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Kills `parent` (SIGKILL) and fails when any of `children` still runs 0.2 s later.
pub(crate) fn kill_and_check_children_gone(parent: &mut std::process::Child, children: &[u32]) {
    parent.kill().unwrap();
    parent.wait().unwrap();
    // Children that die with their parent are gone at once; an orphan goes on compiling its
    // family (0.1 to 1 s), so 0.2 s tells them apart (the contract allows a second).
    std::thread::sleep(Duration::from_millis(200));
    let alive: Vec<String> = children
        .iter()
        .filter(|&&c| running(c))
        .map(|&c| format!("{c}: {}", cmdline(c)))
        .collect();
    assert!(alive.is_empty(), "still running 0.2 s later: {alive:?}");
}

/// Probe 9 and "Done when": kill -9 of `report` during its static-cost phase left its
/// compiler children running and their request/reply folder in the temporary folder for good.
/// Now the children die with it (within a second), and the next run removes what it left, in
/// the temporary folder and in the output folder.
#[test]
fn a_killed_report_leaves_no_process_and_its_files_go_with_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let out = dir.path().join("report");
    let mut report = shadelab()
        .args([
            "report",
            "--scene",
            "scenes/cube.toml",
            "--methods",
            "gouraud",
            "--size",
            "32x32",
            "--runs",
            "1",
            "--out",
            s(&out),
        ])
        .env("TMPDIR", &tmp)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = report.id();
    // the static cost: a child compiling a GPU family (`shadelab child --worker`)
    let children = children_seen(&mut report, " child ", Duration::from_secs(300));
    kill_and_check_children_gone(&mut report, &children);
    // what the killed run left: its request/reply folder, and a temporary file in its output
    let left = |d: &Path| -> Vec<String> {
        std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("shadelab-"))
            .collect()
    };
    assert!(
        !left(&tmp).is_empty(),
        "the killed run left no request folder to remove"
    );
    std::fs::create_dir_all(out.join("scenes")).unwrap();
    let planted = out.join("scenes").join(format!(".shadelab-{pid}-99.tmp"));
    std::fs::write(&planted, vec![0u8; 4096]).unwrap();
    // the next run of any command into the same output folder
    let (code, _, err) = run_limited(
        &[
            "compare",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "16x16",
            "--methods",
            "gouraud",
            "--out",
            s(&out),
        ],
        &[("TMPDIR", s(&tmp))],
        Duration::from_secs(60),
    );
    assert_eq!(code, 0, "{err}");
    assert!(left(&tmp).is_empty(), "{:?}", left(&tmp));
    assert!(
        !planted.exists(),
        "the killed run's temporary file outlived the next run"
    );
}

/// Probe 9, the signals: SIGTERM and Ctrl-C (SIGINT) killed a run and left its temporary
/// files; now each is handled: temporary files removed, exit 143 or 130 with a line.
#[test]
fn sigterm_and_sigint_clean_up_and_exit_with_their_code() {
    for (sig, code, name) in [
        (libc::SIGTERM, 143, "SIGTERM"),
        (libc::SIGINT, 130, "SIGINT"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("c");
        let err = dir.path().join("err");
        let mut c = shadelab();
        // A test run from a background job (`cmd &` in a script, as the Debian 13 check runs
        // make test) inherits SIGINT ignored, and a program keeps an ignored SIGINT ignored as
        // a shell's background job must; Ctrl-C is the interactive case: default disposition.
        // SAFETY: signal() is async-signal-safe; nothing else runs between fork and exec.
        unsafe {
            std::os::unix::process::CommandExt::pre_exec(&mut c, || {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                Ok(())
            });
        }
        let mut c = c
            .args([
                "compare",
                "--scene",
                "scenes/sphere_fine.toml",
                "--size",
                "2048x2048",
                "--methods",
                "gouraud,phong_unnormalized,newton_raphson",
                "--out",
                s(&out),
            ])
            .env("TMPDIR", dir.path())
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&err).unwrap())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(800));
        assert!(
            c.try_wait().unwrap().is_none(),
            "{name}: finished before the signal"
        );
        // SAFETY: a signal to the child this test started.
        unsafe { libc::kill(c.id() as libc::pid_t, sig) };
        let status = c.wait().unwrap();
        let text = std::fs::read_to_string(&err).unwrap();
        assert_eq!(status.code(), Some(code), "{name}: {status:?}\n{text}");
        assert!(text.contains(&format!("stopped by {name}")), "{text}");
        assert!(
            temporaries(dir.path()).is_empty(),
            "{:?}",
            temporaries(dir.path())
        );
        assert!(!out.join("summary.json").exists());
    }
}

/// Probe 10. 16384x16384 (the size cap) was accepted although compare needs about 48 GB; it
/// failed late ("vkBindImageMemory failed: ERROR_OUT_OF_DEVICE_MEMORY") or not at all on a
/// big machine. Now the estimate is checked first: here against a 1 GB allowance
/// (SHADELAB_MEMORY), so that the probe is the same on every machine.
#[test]
fn an_image_that_does_not_fit_is_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let (code, _, err) = run_limited(
        &[
            "compare",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "4096x4096",
            "--methods",
            "gouraud",
            "--out",
            s(&out),
        ],
        &[("SHADELAB_MEMORY", "1G")],
        Duration::from_secs(60),
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("compare at 4096x4096 needs about 3.1 GB") && err.contains("1.1 GB available"),
        "{err}"
    );
    assert!(err.contains("lower the image size"), "{err}");
    let (code, _, err) = run_limited(
        &[
            "render",
            "--scene",
            "scenes/cube.toml",
            "--size",
            "16384x16384",
            "--out",
            s(&dir.path().join("r.png")),
        ],
        &[("SHADELAB_MEMORY", "1G")],
        Duration::from_secs(60),
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("a draw at 16384x16384 needs about 19.4 GB"),
        "{err}"
    );
}

/// The unclear messages: `--methods ''` exited 0 with no methods; a repeated method gave
/// duplicate rows; a method that covers no pixel reported flip_mean 0.0; a 1e300 coefficient
/// was "inf".
#[test]
fn unclear_messages_are_clear() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c");
    let base = [
        "compare",
        "--scene",
        "scenes/cube.toml",
        "--size",
        "16x16",
        "--out",
        s(&out),
    ];
    let with = |methods: &str| {
        let mut a = base.to_vec();
        a.extend(["--methods", methods]);
        go(&a)
    };
    let (code, _, err) = with("");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no method given"), "{err}");
    let (code, _, err) = with("gouraud,gouraud");
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("names gouraud more than once"), "{err}");
    let summary = read_json(out.join("summary.json"));
    let names: Vec<&str> = summary["methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["gouraud"]);
    // a camera that looks away from the mesh: no pixel covered, no FLIP
    let away = looking_away(dir.path());
    let (code, stdout, err) = go(&[
        "compare",
        "--scene",
        s(&away),
        "--size",
        "16x16",
        "--methods",
        "gouraud",
        "--out",
        s(&out),
    ]);
    assert_eq!(code, 0, "{err}");
    let m = &read_json(out.join("summary.json"))["methods"][0];
    assert_eq!(m["covered_pixels"], 0);
    assert!(m["flip_mean"].is_null() && m["flip_p95"].is_null(), "{m}");
    assert!(
        stdout.contains("n/a") && stdout.contains("no pixel covered"),
        "{stdout}"
    );
    // a coefficient beyond float32's range
    let huge = dir.path().join("huge.glsl");
    std::fs::write(
        &huge,
        "// shadelab-tuned: {\"form\":\"minimax\",\"steps\":0,\"coeffs\":[\"1e300\"],\"domain\":[\"0.5\",\"1\"],\"length_error\":\"0.1\"}\n\
         // shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    real3 n = R3(vNormal);\n    return n * R(1e300);\n}\n",
    )
    .unwrap();
    let err = refused(
        &["--method-file", s(&huge), "list"],
        "\"1e300\" is beyond float32's range",
    );
    assert!(err.contains("3.4028235e38"), "{err}");
}

// --- Wrong figures at exit 0, misleading messages (the second round of probes) -------------

/// An image with no covered pixel: summary.json's per-channel figures and the normal's 99th
/// percentile are null (they read 0.0), and a limit on one says that there is no value and
/// why (it said "= 0.000000e0 > 1e0").
#[test]
fn an_image_with_no_covered_pixel_reports_null_and_the_gate_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let (away, out) = (looking_away(dir.path()), dir.path().join("c"));
    let (code, _, err) = go(&[
        "compare",
        "--scene",
        s(&away),
        "--size",
        "16x16",
        "--methods",
        "phong_exact",
        "--fail-above",
        "p99_normal_angle_deg=1",
        "--out",
        s(&out),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("p99_normal_angle_deg has no value") && err.contains("no pixel measured"),
        "{err}"
    );
    assert!(!err.contains("0.000000e0"), "{err}");
    let m = &read_json(out.join("summary.json"))["methods"][0];
    assert_eq!(m["covered_pixels"], 0);
    for c in m["channels"].as_array().unwrap() {
        for k in ["mean_abs_error", "max_abs_error", "rmse"] {
            assert!(c[k].is_null(), "{k}: {m}");
        }
    }
    assert!(m["p99_normal_angle_deg"].is_null(), "{m}");
}

/// A method NaN at every pixel fails, and the reason says so: "non-finite at N of N pixels",
/// not "the method covers none of the reference's pixels".
#[test]
fn a_method_nan_everywhere_is_said_to_be_non_finite_at_every_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let nan = dir.path().join("nan_everywhere.glsl");
    std::fs::write(
        &nan,
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\n    real3 n = R3(vNormal);\n    return n * sqrt(R(-1.0) - dot(n, n));\n}\n",
    )
    .unwrap();
    let out = dir.path().join("c");
    let (code, _, err) = go(&[
        "--method-file",
        s(&nan),
        "compare",
        "--scene",
        "scenes/sphere_coarse.toml",
        "--size",
        "32x32",
        "--methods",
        "nan_everywhere",
        "--fail-above",
        "max_abs_error=1",
        "--out",
        s(&out),
    ]);
    assert_eq!(code, 1, "{err}");
    let m = &read_json(out.join("summary.json"))["methods"][0];
    let n = m["non_finite_pixels"].as_u64().unwrap();
    assert!(n > 0 && m["covered_pixels"] == 0, "{m}");
    assert!(
        err.contains(&format!("non-finite at {n} of {n} pixels")),
        "{err}"
    );
    assert!(!err.contains("covers none"), "{err}");
}

/// A family named twice is compiled and reported once, with a note (two identical columns).
#[test]
fn a_family_named_twice_is_reported_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("isa");
    let store = dir.path().join("store");
    let (code, _, err) = run_limited(
        &[
            "isa",
            "--families",
            "amd:navi21,AMD:navi21",
            "--methods",
            "phong_exact",
            "--out",
            s(&out),
        ],
        &[("SHADELAB_STORE", s(&store))],
        Duration::from_secs(120),
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("names amd:navi21 more than once"), "{err}");
    let isa = read_json(out.join("isa.json"));
    let families: Vec<&str> = isa["families"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["family"].as_str().unwrap())
        .collect();
    assert_eq!(families, ["amd:navi21"]);
}

/// A compile store whose bad entries cannot be removed (a folder where an entry would be,
/// which even root cannot unlink; a read-only store the common case): `cache --verify` said
/// "removed" and exited 0, `cache --prune` said "removed 0 entries". Now each says what is
/// still there and exits 2. And an entry that never ends (a link to /dev/zero) or blocks (a
/// FIFO) is refused at once and removed, never read.
#[test]
fn a_store_entry_that_cannot_be_removed_is_said_to_be_kept() {
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("store");
    std::fs::create_dir(&store).unwrap();
    let stuck = store.join(format!("{}.entry", "f".repeat(64)));
    std::fs::create_dir(&stuck).unwrap();
    std::fs::write(stuck.join("inside"), b"x").unwrap();
    let zero = store.join(format!("{}.entry", "e".repeat(64)));
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let fifo = store.join(format!("{}.entry", "d".repeat(64)));
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let env = [("SHADELAB_STORE", s(&store))];
    let limit = Duration::from_secs(30);
    let (code, out, err) = run_limited(&["cache", "--verify"], &env, limit);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        out.contains(&format!("NOT removed {}", stuck.display()))
            && out.contains("0 sound, 2 removed, 1 could not be removed")
            && err.contains("could not be removed"),
        "{out}{err}"
    );
    assert!(
        out.contains("a symbolic link") && out.contains("a FIFO"),
        "{out}"
    );
    assert!(stuck.exists() && zero.symlink_metadata().is_err() && !fifo.exists());
    let (code, out, err) = run_limited(&["cache", "--prune"], &env, limit);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        out.contains("removed 0 entries") && out.contains("1 could not be removed"),
        "{out}"
    );
    assert!(
        err.contains(&format!("could not remove {}", stuck.display())),
        "{err}"
    );
    // teeth: once it can go, it goes and the commands succeed
    std::fs::remove_dir_all(&stuck).unwrap();
    std::fs::write(&stuck, b"junk").unwrap();
    let (code, out, err) = run_limited(&["cache", "--verify"], &env, limit);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("0 sound, 1 removed\n"), "{out}");
}
