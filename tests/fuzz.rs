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

/// glTF: `.gltf` JSON or `.glb` bytes. A buffer file the input names is never read (a fuzzed
/// input must not reach the disk): it is missing, which the reader reports as an error.
fn fuzz_gltf(bytes: &[u8]) -> Result<()> {
    let missing = |_: &Path| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
    let (mesh, report) = geometry::gltf::parse_gltf(Path::new(FUZZ_PATH), bytes, &missing)
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
