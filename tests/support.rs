//! Helpers shared by the integration tests.
use std::path::{Path, PathBuf};
use std::sync::Arc;

use shadelab::gpu::vk::{Context, ContextDesc};
use shadelab::gpu::Renderer;
use shadelab::scene::{self, Scene};

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A renderer on lavapipe with the validation layer on.
pub fn validated_renderer() -> Renderer {
    let ctx = Context::new(&ContextDesc {
        device: None,
        validate: true,
    })
    .expect("lavapipe with validation");
    assert!(ctx.validating());
    Renderer::new(ctx)
}

/// Fails the test if the validation layer said anything.
pub fn assert_validation_clean(ctx: &Arc<Context>) {
    let msgs = ctx.validation_messages();
    assert!(
        msgs.is_empty(),
        "{} validation message(s):\n{}",
        msgs.len(),
        msgs.join("\n")
    );
}

/// Every shipped scene of scenes/ (the file stems).
pub const SHIPPED_SCENES: &[&str] = &[
    "cube",
    "icosphere",
    "sphere_coarse",
    "sphere_fine",
    "torus",
    "torus_generated",
];

/// A shipped scene at a small size.
pub fn shipped_scene(name: &str, size: u32) -> Scene {
    let mut s = scene::load_scene(&root().join("scenes").join(format!("{name}.toml")))
        .expect("shipped scene loads");
    s.width = size;
    s.height = size;
    s
}

/// The real-world models folder: `SHADELAB_MODELS` (unless empty: the Makefile exports it
/// empty when there are no models), else ../shared/models when present.
///
/// When it is absent: with `SHADELAB_REQUIRE_MODELS=1` (CI sets it) the calling test fails;
/// otherwise `None`, and a `SKIPPED: <test>` line goes straight to the terminal (not through
/// `eprintln!`, which the test harness captures and hides for a passing test), so a skip never
/// reads as a pass.
pub fn models_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os("SHADELAB_MODELS") {
        Some(d) if !d.is_empty() => PathBuf::from(d),
        _ => root().join("../shared/models"),
    };
    if dir.is_dir() {
        return Some(dir);
    }
    let test = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let why = format!(
        "no models folder at {} (set SHADELAB_MODELS)",
        dir.display()
    );
    if std::env::var("SHADELAB_REQUIRE_MODELS").as_deref() == Ok("1") {
        panic!("{test}: SHADELAB_REQUIRE_MODELS=1 but {why}");
    }
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED: {test}: {why}");
    None
}

/// The built binary.
pub fn bin() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_shadelab"));
    c.current_dir(root());
    // No disk cache of `auto`'s choice from the tests (the unit tests cover it).
    c.env("SHADELAB_CACHE_DIR", "");
    c
}

/// Runs the binary; returns (exit code, stdout, stderr).
pub fn run(args: &[&str]) -> (i32, String, String) {
    let out = bin().args(args).output().expect("run shadelab");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The mesh files of the models folder, sorted (`None`, with a message, when it is absent).
pub fn model_files() -> Option<Vec<PathBuf>> {
    let dir = models_dir()?;
    shadelab::geometry::mesh_files(&dir, shadelab::geometry::Depth::Flat, None).ok()
}

/// The JSON file at `path`, parsed (panics with the path on a missing or malformed file).
pub fn read_json(path: impl AsRef<Path>) -> serde_json::Value {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The validator of a schema file of docs/ (e.g. `docs/bench.schema.json`).
pub fn schema_validator(file: &str) -> jsonschema::Validator {
    jsonschema::validator_for(&read_json(root().join(file))).unwrap()
}

/// Checks `value` against the schema file `file` of docs/, listing every error, and that the
/// check has teeth: `value` without `field` of the object at `pointer` (a JSON pointer, e.g.
/// `/methods/0`) must fail it. The one schema check of every output file's test.
pub fn assert_schema(value: &serde_json::Value, file: &str, pointer: &str, field: &str) {
    let validator = schema_validator(file);
    let errors: Vec<String> = validator
        .iter_errors(value)
        .map(|e| format!("{e} at {}", e.instance_path()))
        .collect();
    assert!(
        errors.is_empty(),
        "the output does not match {file}:\n{}",
        errors.join("\n")
    );
    let mut broken = value.clone();
    let removed = broken
        .pointer_mut(pointer)
        .and_then(|o| o.as_object_mut())
        .and_then(|o| o.remove(field));
    assert!(
        removed.is_some(),
        "{pointer}/{field} is not in the output: the teeth would bite nothing"
    );
    assert!(
        !validator.is_valid(&broken),
        "{file}: the schema check has no teeth (the output without {pointer}/{field} passes)"
    );
}

/// Runs test `test` of this test binary alone (`--exact`), with `env` added: how a test checks
/// what another test does when a folder or a compiler is missing (skip, or fail when required).
pub fn rerun_test(test: &str, env: &[(&str, &std::ffi::OsStr)]) -> std::process::Output {
    let mut cmd = std::process::Command::new(std::env::current_exe().unwrap());
    cmd.args(["--exact", test, "--test-threads=1"]);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().unwrap()
}
