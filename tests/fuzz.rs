//! Fuzzing the readers of untrusted input (issue 10, "Bad input, fuzzed"; OBJ, scene, replay,
//! glTF, PLY): every target in
//! [`TARGETS`] must turn any bytes into a value or an error, never a panic, within 1 s and
//! without sizing an allocation from a number in the file.
//!
//! The engine ([`engine`]) and the mutations ([`mutate`]) are this crate's own: the mutations
//! need to know lines, tokens and numbers, and the smoke run below must run on the stable
//! toolchain inside `cargo test`. `scripts/fuzz.sh` runs [`full_run`] (1,000,000 inputs by
//! default); [`smoke_run`] runs 20,000 with every `cargo test`.
//!
//! Adding a reader is one entry in [`TARGETS`]: its name, the kind of text it reads (for
//! excerpts and file extensions), where its seed files are, and a function from bytes to
//! `Result`. The function should also assert the reader's documented guarantees on what it
//! accepts: a broken guarantee is a panic, which the engine reports like any other.
//!
//! A failing input found by a run is written to `target/tmp/fuzz/`; keep it as a regression
//! file in `tests/data/fuzz/TARGET/` (also a seed, so later runs mutate around it) once the
//! reader is fixed: [`kept_failing_inputs_stay_fixed`] replays them all.
pub(crate) mod engine;
mod mutate;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

use shadelab::geometry::{self, LoadReport, Mesh};
use shadelab::scene::{self, MAX_IMAGE_SIZE, MAX_LIGHTS};
use shadelab::{Error, Result};

use engine::{run_target, Config, FailureKind, Limits, Report};

/// The kind of text a target reads: picks the excerpting of big seeds and the extension of
/// saved inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Syntax {
    Obj,
    Toml,
    /// The replay reader of `stress --replay CASE.json`.
    Json,
    /// glTF 2.0: a `.gltf`'s JSON or a `.glb` (the reader tells them by their magic bytes).
    Gltf,
    /// PLY, ASCII or binary.
    Ply,
}

impl Syntax {
    fn extension(self) -> &'static str {
        match self {
            Syntax::Obj => "obj",
            Syntax::Toml => "toml",
            Syntax::Json => "json",
            Syntax::Gltf => "gltf",
            Syntax::Ply => "ply",
        }
    }
}

/// Where seed files are: `(folder, extension)`.
#[derive(Debug, Clone, Copy)]
pub enum Seeds {
    /// A folder of this repository.
    Repo(&'static str, &'static str),
    /// The folder an environment variable names, if set (`SHADELAB_MODELS`: the shared models
    /// are read where they are, never copied into the repository).
    Env(&'static str, &'static str),
}

/// One reader under test.
pub struct Target {
    pub name: &'static str,
    pub syntax: Syntax,
    pub seeds: &'static [Seeds],
    /// The reader on one input: `Ok` when it accepts it (after checking its guarantees).
    pub parse: fn(&[u8]) -> Result<()>,
}

/// The readers under test. A new one is one line here.
#[rustfmt::skip]
pub const TARGETS: &[Target] = &[
    Target { name: "obj", syntax: Syntax::Obj, seeds: &[Seeds::Repo("scenes", "obj"), Seeds::Env("SHADELAB_MODELS", "obj"), Seeds::Repo("tests/data/fuzz/obj", "obj")], parse: fuzz_obj },
    Target { name: "replay", syntax: Syntax::Json, seeds: &[Seeds::Repo("tests/data/fuzz/replay", "json")], parse: fuzz_replay },
    Target { name: "scene", syntax: Syntax::Toml, seeds: &[Seeds::Repo("scenes", "toml"), Seeds::Repo("tests/data/fuzz/scene", "toml")], parse: fuzz_scene },
    Target { name: "gltf", syntax: Syntax::Gltf, seeds: &[Seeds::Repo("tests/data/gltf", "gltf"), Seeds::Repo("tests/data/gltf", "glb"), Seeds::Repo("tests/data/fuzz/gltf", "gltf")], parse: fuzz_gltf },
    Target { name: "ply", syntax: Syntax::Ply, seeds: &[Seeds::Repo("tests/data/ply", "ply"), Seeds::Repo("tests/data/fuzz/ply", "ply")], parse: fuzz_ply },
];

/// The name inputs get in error messages.
const FUZZ_PATH: &str = "fuzz/input";

/// An `Error::Input` about the input itself names a line inside it (or none). Lines end at
/// "\r\n", "\n" or a lone "\r" (the OBJ reader counts a lone CR, the others never count more).
fn check_error_line(e: &Error, text: &[u8]) {
    if let Error::Input {
        path,
        line: Some(line),
        ..
    } = e
    {
        if path == Path::new(FUZZ_PATH) {
            let crlf = text.windows(2).filter(|w| w == b"\r\n").count();
            let ends = text.iter().filter(|&&b| b == b'\n' || b == b'\r').count();
            let lines = ends - crlf + 1;
            assert!(
                (1..=lines).contains(line),
                "error names line {line} of a {lines}-line input: {e}"
            );
        }
    }
}

/// The [`Mesh`] invariants of src/geometry/mod.rs, plus the fit of [`geometry::fit_unit`].
fn check_mesh(mesh: &Mesh) {
    assert_eq!(mesh.positions.len(), mesh.normals.len());
    assert!(
        !mesh.positions.is_empty() && mesh.positions.len() % 3 == 0,
        "{} corners",
        mesh.positions.len()
    );
    for t in mesh.positions.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| glam::DVec3::from_array(t[k].map(f64::from)));
        assert!(!geometry::is_zero_area(a, b, c), "zero-area triangle {t:?}");
    }
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        assert!(
            p.iter().all(|c| c.is_finite() && c.abs() <= 1.0 + 1e-5),
            "position {p:?} outside the unit sphere"
        );
        let len = n.iter().map(|&c| c as f64 * c as f64).sum::<f64>().sqrt();
        // The module's bound, |n| - 1 < 1e-6 (f32 rounding of an f64 unit vector is 6e-8).
        assert!((len - 1.0).abs() < 1e-6, "normal {n:?} has length {len}");
    }
}

fn fuzz_obj(bytes: &[u8]) -> Result<()> {
    let (mesh, report) = geometry::parse_obj(Path::new(FUZZ_PATH), bytes)
        .inspect_err(|e| check_error_line(e, bytes))?;
    check_mesh(&mesh);
    assert_eq!(report.triangles, mesh.triangle_count());
    Ok(())
}

/// glTF: `.gltf` JSON or `.glb` bytes. A buffer file the input names is never read from the
/// disk (a fuzzed input must not reach it): every file inside the input's folder reads as
/// [`fuzz_buffer`], and the reader asking for one outside it breaks the buffer URI rule
/// ([`geometry::input::BUFFER_RULE`]).
fn fuzz_gltf(bytes: &[u8]) -> Result<()> {
    let read = |p: &Path| {
        assert!(
            inside_fuzz_folder(p),
            "the glTF reader asked for {}, outside the input's folder",
            p.display()
        );
        Ok(fuzz_buffer())
    };
    let (mesh, report) = geometry::gltf::parse_gltf(Path::new(FUZZ_PATH), bytes, &read)
        .inspect_err(|e| check_error_line(e, bytes))?;
    check_mesh(&mesh);
    assert_eq!(report.triangles, mesh.triangle_count());
    let drawn: usize = report.input.parts.iter().map(|p| p.triangles).sum();
    assert_eq!(
        drawn,
        report.triangles + report.dropped_zero_area,
        "{report:?}"
    );
    Ok(())
}

/// What every buffer file inside a fuzzed `.gltf`'s folder holds: a triangle's positions
/// (0, 0, 0), (1, 0, 0), (0, 1, 0), its normals (0, 0, 1) and its u16 indices 0, 1, 2, padded to
/// 80 bytes, as tests/data/fuzz/gltf/buffer-uri-seed.gltf describes.
fn fuzz_buffer() -> Vec<u8> {
    let floats = [
        0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1., 0., 0., 1f32,
    ];
    let mut b: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    b.extend([0u16, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    b
}

/// Whether `p` lies inside the folder of [`FUZZ_PATH`] as written: no `..` climbing above it,
/// not absolute (the reader must refuse those before reading; links are the disk reader's).
fn inside_fuzz_folder(p: &Path) -> bool {
    use std::path::Component;
    let folder = Path::new(FUZZ_PATH).parent().expect("a folder");
    let Ok(rel) = p.strip_prefix(folder) else {
        return false;
    };
    let mut depth = 0usize;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            _ => return false,
        }
    }
    true
}

fn fuzz_ply(bytes: &[u8]) -> Result<()> {
    let (mesh, report) = geometry::ply::parse_ply(Path::new(FUZZ_PATH), bytes)
        .inspect_err(|e| check_error_line(e, bytes))?;
    check_mesh(&mesh);
    assert_eq!(report.triangles, mesh.triangle_count());
    Ok(())
}

/// The mesh every `obj = ...` of a fuzzed scene gets: the shipped cube, read once (the OBJ
/// reader is its own target; reading from disk a million times would test the disk).
fn cube() -> &'static (Mesh, LoadReport) {
    static CUBE: OnceLock<(Mesh, LoadReport)> = OnceLock::new();
    CUBE.get_or_init(|| {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/cube.obj");
        geometry::load_obj(&path).expect("scenes/cube.obj loads")
    })
}

/// `stress --replay`: a case it accepts names a method and builds a case whose device inputs
/// are finite numbers.
fn fuzz_replay(bytes: &[u8]) -> Result<()> {
    let r = shadelab::stress::replay::parse(Path::new(FUZZ_PATH), bytes)?;
    assert!(shadelab::method::find(&r.method).is_ok(), "{}", r.method);
    let case = shadelab::cases::Case::new(r.spec);
    let gpu = shadelab::gpu::evaluate::GpuCase::new(&case.fragment, &case.lighting)?;
    let words: &[f32] = bytemuck::cast_slice(std::slice::from_ref(&gpu));
    assert!(words.iter().all(|x| x.is_finite()), "{:?}", r.spec);
    Ok(())
}

fn fuzz_scene(bytes: &[u8]) -> Result<()> {
    // load_scene reads with read_to_string, which rejects invalid UTF-8 the same way.
    let text =
        std::str::from_utf8(bytes).map_err(|e| Error::input(FUZZ_PATH, None, e.to_string()))?;
    let s = scene::parse_scene(Path::new(FUZZ_PATH), text, &|_| Ok(cube().clone()))
        .inspect_err(|e| check_error_line(e, bytes))?;
    // The Scene invariants of src/scene/mod.rs.
    check_mesh(&s.mesh);
    assert!((1..=MAX_LIGHTS).contains(&s.lights.len()));
    for l in &s.lights {
        assert!(
            l.direction.is_finite() && (l.direction.length() - 1.0).abs() < 1e-12,
            "{l:?}"
        );
        assert!(l.color.is_finite() && l.color.min_element() >= 0.0, "{l:?}");
    }
    let m = &s.material;
    for c in [m.ambient, m.diffuse, m.specular] {
        assert!(c.is_finite() && c.min_element() >= 0.0, "{m:?}");
    }
    assert!(m.shininess.is_finite() && m.shininess >= 0.0, "{m:?}");
    assert!((1..=MAX_IMAGE_SIZE).contains(&s.width) && (1..=MAX_IMAGE_SIZE).contains(&s.height));
    let c = &s.camera;
    assert!(
        c.eye.is_finite() && c.target.is_finite() && c.up.is_finite(),
        "{c:?}"
    );
    assert!(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0, "{c:?}");
    let (near, far) = c.near_far();
    assert!(
        near.is_finite() && far.is_finite() && 0.0 < near && near < far,
        "{c:?}"
    );
    Ok(())
}

fn out_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz")
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    match std::env::var(name) {
        Ok(v) => v
            .parse()
            .unwrap_or_else(|_| panic!("{name}={v} is not a valid value")),
        Err(_) => default,
    }
}

/// Runs `targets`, `inputs` split evenly, and prints one summary line each and a total.
fn run_all(targets: &[&Target], inputs: u64, seed: u64) -> Vec<Report> {
    let per = inputs.div_ceil(targets.len() as u64);
    let cfg = Config {
        inputs: per,
        seed,
        limits: Limits::default(),
        out_dir: out_dir(),
    };
    let reports: Vec<Report> = targets.iter().map(|t| run_target(t, &cfg)).collect();
    for r in &reports {
        println!("fuzz: {}", r.summary());
        for f in &r.failures {
            println!(
                "fuzz:   {}: {:?} from {} saved as {:?}",
                r.target, f.kind, f.origin, f.saved
            );
        }
    }
    let total: u64 = reports.iter().map(|r| r.inputs).sum();
    let secs: f64 = reports.iter().map(|r| r.elapsed.as_secs_f64()).sum();
    let panics: usize = reports.iter().map(Report::panics).sum();
    let slow: usize = reports.iter().map(Report::slow).sum();
    let greedy: usize = reports.iter().map(Report::greedy).sum();
    let worst = reports
        .iter()
        .max_by_key(|r| r.slowest)
        .expect("at least one target");
    println!(
        "fuzz: total {total} inputs in {secs:.1} s (seed {seed}), {panics} panics, {slow} over 1 s, {greedy} over the allocation limit; slowest input {:.3} s ({}: {}, {} bytes)",
        worst.slowest.as_secs_f64(),
        worst.target,
        worst.slowest_origin,
        worst.slowest_len
    );
    reports
}

fn assert_clean(reports: &[Report]) {
    let failures: Vec<String> = reports
        .iter()
        .flat_map(|r| {
            r.failures.iter().map(move |f| {
                format!(
                    "{}: {:?} ({}) saved as {:?}",
                    r.target, f.kind, f.origin, f.saved
                )
            })
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} failing inputs:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The run of scripts/fuzz.sh: `SHADELAB_FUZZ_INPUTS` (default 1,000,000) inputs in total,
/// `SHADELAB_FUZZ_SEED` (default 10), `SHADELAB_FUZZ_TARGETS` (comma-separated names, default
/// all). About a minute on one core; not part of `cargo test`.
#[test]
#[ignore = "about a minute: run by scripts/fuzz.sh"]
fn full_run() {
    let inputs = env_or("SHADELAB_FUZZ_INPUTS", 1_000_000u64);
    let seed = env_or("SHADELAB_FUZZ_SEED", 10u64);
    let names = env_or("SHADELAB_FUZZ_TARGETS", String::new());
    let targets: Vec<&Target> = TARGETS
        .iter()
        .filter(|t| names.is_empty() || names.split(',').any(|n| n == t.name))
        .collect();
    assert!(
        !targets.is_empty(),
        "SHADELAB_FUZZ_TARGETS={names} names no target"
    );
    assert_clean(&run_all(&targets, inputs, seed));
}

/// The same harness on 20,000 inputs (a second or two), so every `cargo test` fuzzes a little.
#[test]
fn smoke_run() {
    let targets: Vec<&Target> = TARGETS.iter().collect();
    let reports = run_all(&targets, 20_000, 1);
    assert_clean(&reports);
    for r in &reports {
        // The mutants must get past the first checks, or the run proves little.
        assert!(
            r.accepted * 20 > r.inputs,
            "{}: only {} of {} accepted",
            r.target,
            r.accepted,
            r.inputs
        );
    }
}

/// Every kept failing input now gives an error or a sound value: no panic, no broken
/// guarantee, < 1 s.
#[test]
fn kept_failing_inputs_stay_fixed() {
    for t in TARGETS {
        let kept: Vec<Seeds> = t
            .seeds
            .iter()
            .copied()
            .filter(|s| matches!(s, Seeds::Repo(dir, _) if dir.starts_with("tests/data/fuzz/")))
            .collect();
        for path in mutate::seed_files(&kept) {
            let bytes = std::fs::read(&path).unwrap();
            let t0 = std::time::Instant::now();
            let result = std::panic::catch_unwind(|| (t.parse)(&bytes));
            let dt = t0.elapsed();
            assert!(
                result.is_ok(),
                "{}: {} panics again",
                t.name,
                path.display()
            );
            assert!(
                dt < Duration::from_secs(1),
                "{}: {} takes {dt:?}",
                t.name,
                path.display()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The glTF buffer URI rule, over chosen and random URIs: in memory and on the disk.
// ---------------------------------------------------------------------------------------------
/// Pieces random buffer URIs are made of: traversal (plain and %-encoded), separators, schemes,
/// bad escapes, and the names of [`UriTree`]'s files (a link out, a FIFO, /dev/zero, a folder).
const URI_PIECES: &[&str] = &[
    "..",
    ".",
    "%2E%2E",
    "%2e%2E",
    ".%2E",
    "%2E.",
    "%2e",
    "a",
    "sub",
    "buffer.bin",
    "outside.bin",
    "link.bin",
    "up",
    "fifo.bin",
    "zero.bin",
    "/",
    "//",
    "%2F",
    "%2f",
    "%5C",
    "\\",
    "%",
    "%zz",
    "%00",
    "file:",
    "file://",
    "data:",
    "C:",
    "~",
    " ",
    "%20",
    "\u{e9}",
];

/// URIs that leave the `.gltf`'s folder or name what is not a regular file, in every form.
const ESCAPING_URIS: &[&str] = &[
    "../buffer.bin",
    "../../outside.bin",
    "sub/../../outside.bin",
    "..%2Foutside.bin",
    "..%2F..%2Foutside.bin",
    "%2E%2E/outside.bin",
    "%2e%2e%2foutside.bin",
    "../../../../../../etc/passwd",
    "/etc/passwd",
    "%2Fetc%2Fpasswd",
    "file:///etc/passwd",
    "file:../outside.bin",
];

/// `n` URIs of 1 to 8 [`URI_PIECES`], from `seed`.
fn random_uris(seed: u64, n: usize) -> Vec<String> {
    let mut rng = fastrand::Rng::with_seed(seed);
    (0..n)
        .map(|_| {
            (0..rng.usize(1..=8))
                .map(|_| URI_PIECES[rng.usize(0..URI_PIECES.len())])
                .collect()
        })
        .collect()
}

/// tests/data/fuzz/gltf/buffer-uri-seed.gltf with its buffer at `uri`.
fn gltf_with_uri(uri: &str) -> Vec<u8> {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz/gltf/buffer-uri-seed.gltf");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    doc["buffers"][0]["uri"] = uri.into();
    doc.to_string().into_bytes()
}

/// In memory: whatever the URI, the reader is only asked for files inside the input's folder
/// (as written), and every form of escape is refused naming the rule.
#[test]
fn gltf_buffer_uris_never_reach_outside_the_folder() {
    let asked = std::cell::RefCell::new(Vec::new());
    let read = |p: &Path| {
        asked.borrow_mut().push(p.to_path_buf());
        Ok(fuzz_buffer())
    };
    let parse =
        |uri: &str| geometry::gltf::parse_gltf(Path::new(FUZZ_PATH), &gltf_with_uri(uri), &read);
    for uri in ESCAPING_URIS {
        let e = parse(uri).expect_err(uri).to_string();
        assert!(e.contains(geometry::input::BUFFER_RULE), "{uri}: {e}");
    }
    assert!(asked.borrow().is_empty(), "{:?}", asked.borrow());
    for uri in [
        "buffer.bin",
        "sub/../buffer.bin",
        "sub%2F..%2Fbuffer.bin",
        "./a/buffer.bin",
    ] {
        parse(uri).unwrap_or_else(|e| panic!("{uri}: {e}"));
    }
    let mut accepted = 0;
    for uri in random_uris(7, 5000) {
        accepted += usize::from(parse(&uri).is_ok());
    }
    let outside: Vec<_> = asked
        .borrow()
        .iter()
        .filter(|p| !inside_fuzz_folder(p))
        .cloned()
        .collect();
    assert!(outside.is_empty(), "read outside the folder: {outside:?}");
    // The random URIs reach the reader often enough for the check to mean something.
    assert!(accepted > 100, "only {accepted} of 5000 random URIs read");
}

/// The folder a `.gltf` on the disk names its buffer in: `root/f/m.gltf` beside `buffer.bin`
/// and `sub/buffer.bin` (good buffers), a link to `root/outside.bin` (a good buffer, outside)
/// and one to `root`, a FIFO, a link to /dev/zero.
struct UriTree {
    _dir: tempfile::TempDir,
    folder: PathBuf,
}

impl UriTree {
    fn new() -> UriTree {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().canonicalize().unwrap();
        let folder = root.join("f");
        std::fs::create_dir_all(folder.join("sub")).unwrap();
        for p in [
            root.join("outside.bin"),
            folder.join("buffer.bin"),
            folder.join("sub/buffer.bin"),
        ] {
            std::fs::write(p, fuzz_buffer()).unwrap();
        }
        std::os::unix::fs::symlink(root.join("outside.bin"), folder.join("link.bin")).unwrap();
        std::os::unix::fs::symlink(&root, folder.join("up")).unwrap();
        std::os::unix::fs::symlink("/dev/zero", folder.join("zero.bin")).unwrap();
        let fifo = std::ffi::CString::new(folder.join("fifo.bin").to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path; mkfifo only creates the file.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
        UriTree { _dir: dir, folder }
    }

    /// load_mesh of the folder's `m.gltf` with its buffer at `uri`, from another thread; a
    /// failure when it takes more than 10 s (a read that blocks).
    fn load(&self, uri: &str) -> Result<(Mesh, LoadReport)> {
        let path = self.folder.join("m.gltf");
        std::fs::write(&path, gltf_with_uri(uri)).unwrap();
        let (send, recv) = std::sync::mpsc::channel();
        // A reply after the deadline has no one to go to: dropped.
        std::thread::spawn(move || drop(send.send(geometry::load_mesh(&path))));
        recv.recv_timeout(Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("{uri}: still reading after 10 s"))
    }
}

/// On the disk: the chosen escapes and special files are refused naming the rule, none
/// blocks, and a random URI is read only when it names a regular file inside the folder once
/// %-decoded and its links resolved.
#[test]
fn gltf_buffer_uris_on_the_disk_read_only_regular_files_inside_the_folder() {
    let t = UriTree::new();
    let special = [
        "link.bin",
        "up/outside.bin",
        "fifo.bin",
        "zero.bin",
        "sub",
        ".",
    ];
    for uri in ESCAPING_URIS.iter().chain(&special) {
        let e = t
            .load(uri)
            .err()
            .unwrap_or_else(|| panic!("{uri}: read"))
            .to_string();
        assert!(e.contains(geometry::input::BUFFER_RULE), "{uri}: {e}");
    }
    let inside = t.folder.canonicalize().unwrap();
    for uri in random_uris(11, 1500) {
        if t.load(&uri).is_ok() {
            let decoded = percent_decoded(&uri);
            let real = t.folder.join(&decoded).canonicalize().unwrap();
            assert!(
                real.starts_with(&inside) && std::fs::metadata(&real).unwrap().is_file(),
                "{uri:?} read {}",
                real.display()
            );
        }
    }
}

/// `%XX` escapes of `s` decoded (the URIs the disk test read decode cleanly).
fn percent_decoded(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            out.push(u8::from_str_radix(&s[i + 1..i + 3], 16).unwrap());
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).unwrap()
}

// ---------------------------------------------------------------------------------------------
// Teeth: the engine reports what it is there to catch.
// ---------------------------------------------------------------------------------------------
/// A reader that panics on a NaN (one of the extremes the mutations write), takes 1.1 s on
/// the first "-inf" and allocates 300 MiB on "1e308".
fn flawed(bytes: &[u8]) -> Result<()> {
    let text = String::from_utf8_lossy(bytes);
    if text.contains("NaN") {
        panic!("deliberate panic on NaN");
    }
    // Once per process, or the test would sleep through every "-inf".
    static SLEPT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    if text.contains("-inf") && !SLEPT.swap(true, std::sync::atomic::Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(1100));
    }
    if text.contains("1e308") {
        let big = vec![0u8; 300 << 20];
        std::hint::black_box(&big);
    }
    Err(Error::input(FUZZ_PATH, None, "flawed"))
}

#[test]
fn the_engine_catches_panics_slow_and_greedy_inputs() {
    let target = Target {
        name: "flawed",
        syntax: Syntax::Toml,
        seeds: &[Seeds::Repo("scenes", "toml")],
        parse: flawed,
    };
    let cfg = Config {
        inputs: 3000,
        seed: 3,
        limits: Limits::default(),
        out_dir: out_dir().join("teeth"),
    };
    let r = run_target(&target, &cfg);
    println!("{}", r.summary());
    assert!(r.panics() > 0, "{r:?}");
    let panic = r
        .failures
        .iter()
        .find(|f| matches!(f.kind, FailureKind::Panic(_)))
        .unwrap();
    let FailureKind::Panic(msg) = &panic.kind else {
        unreachable!()
    };
    assert!(
        msg.starts_with("deliberate panic on NaN at tests/fuzz.rs:"),
        "{msg}"
    );
    let saved = std::fs::read_to_string(panic.saved.as_ref().expect("saved")).unwrap();
    assert!(
        saved.contains("NaN"),
        "the saved input is the one that panicked: {saved}"
    );
    assert!(
        r.slow() > 0 && r.slowest >= Duration::from_millis(1100),
        "{r:?}"
    );
    assert!(r.greedy() > 0 && r.largest_alloc >= 300 << 20, "{r:?}");
    assert_eq!(r.inputs, 3000, "the run goes on after a failure");
    assert!(r.summary().contains(" panics, "), "{}", r.summary());
}
