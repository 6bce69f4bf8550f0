//! Shader programs: which GLSL each program compiles from, the shaderc compile (`shadelab
//! shaders`, `make spirv`), the freshness manifest of spirv/, and the SPIR-V embedded in the
//! binary by build.rs.
//!
//! A *program* is a vertex + fragment pair named `<name>.<interpolation>` (files
//! `spirv/<program>.vert.spv` and `spirv/<program>.frag.spv`), or a compute shader named
//! `<name>.evaluate` (`spirv/<program>.comp.spv`). Every method of [`crate::method::METHODS`] gets
//! one program per interpolation mode, plus the internal `ids` program (triangle index and weights
//! for the f64 truth) and `constant` (the cost floor); every method that draws the mesh as it is
//! also gets an `evaluate` program: glsl/evaluate.comp, the same method code run on a buffer of
//! cases (`shadelab stress`).
//!
//! Precision (issue 23): every method program exists twice, float32 (`<name>.<interpolation>`,
//! `<name>.evaluate`) and float16 (`<name>.f16.<interpolation>`, `<name>.f16.evaluate`), compiled
//! from the same GLSL with the define `SHADELAB_F16` (the vocabulary of glsl/common.glsl).
//! [`F16_UNAVAILABLE`] lists the methods without a float16 program and why (none today).
//!
//! Freshness: spirv/manifest.json records a SHA-256 over every file of glsl/ and the program
//! table (names + defines), and the SHA-256 of each .spv. [`check_fresh`] recomputes both, so a
//! GLSL edit without `make spirv`, or a hand-edited .spv, fails the test suite.
use std::collections::BTreeMap;
use std::path::Path;

use sha2::{Digest, Sha256};

use crate::error::{Error, Result};
use crate::method::{Precision, METHODS};
use crate::scene::Interpolation;

include!(concat!(env!("OUT_DIR"), "/spirv_table.rs"));

/// The command that regenerates spirv/.
pub const REGENERATE: &str = "make spirv";

/// One vertex + fragment program and how to compile it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Program {
    /// `<name>.<interpolation>`.
    pub name: String,
    /// The stages: (file tag `vert` / `frag` / `comp`, source under glsl/).
    pub stages: Vec<(&'static str, &'static str)>,
    /// The file under glsl/ that `#include "method.glsl"` resolves to, for method programs.
    pub method_file: Option<&'static str>,
    /// Preprocessor defines for both stages (name, value).
    pub defines: Vec<(String, String)>,
}

/// The file-name tag and GLSL qualifier of an interpolation mode.
pub fn interpolation_tag(i: Interpolation) -> (&'static str, &'static str) {
    match i {
        Interpolation::ScreenLinear => ("screen_linear", "noperspective"),
        Interpolation::Perspective => ("perspective", "smooth"),
    }
}

const MODES: [Interpolation; 2] = [Interpolation::ScreenLinear, Interpolation::Perspective];

/// The program name of a method's float32 compute program (glsl/evaluate.comp).
pub fn evaluate_program(method: &str) -> String {
    evaluate_program_in(method, Precision::F32)
}

/// The program name of a method's compute program in a precision.
pub fn evaluate_program_in(method: &str, precision: Precision) -> String {
    format!("{}evaluate", precision_prefix(method, precision))
}

/// `<base>.` in float32, `<base>.f16.` in float16.
fn precision_prefix(base: &str, precision: Precision) -> String {
    match precision {
        Precision::F32 => format!("{base}."),
        Precision::F16 => format!("{base}.f16."),
    }
}

/// Methods that have no float16 program, with the reason: (method, why). Empty: every method's
/// GLSL compiles in the float16 vocabulary (window positions stay float32 by rule 4 of
/// glsl/common.glsl, so the scanline methods are expressible too).
pub const F16_UNAVAILABLE: &[(&str, &str)] = &[];

/// Whether `method` has programs in `precision` (a user method whose file does not compile in
/// float16 has none, [`compile_user`]).
pub fn has_precision(method: &str, precision: Precision) -> bool {
    precision == Precision::F32
        || !(F16_UNAVAILABLE.iter().any(|(m, _)| *m == method)
            || RUNTIME_NO_F16
                .read()
                .is_ok_and(|no| no.iter().any(|(m, _)| m == method)))
}

/// The define that selects the float16 vocabulary (glsl/common.glsl).
const F16_DEFINE: &str = "SHADELAB_F16";

/// Whether a method has a compute program: those that draw the mesh as it is (a method that
/// tessellates shades other geometry than the case describes).
pub fn has_evaluate_program(m: &crate::method::Method) -> bool {
    m.geometry == crate::method::Geometry::Mesh
}

fn method_defines(m: &crate::method::Method, defines: &mut Vec<(String, String)>) {
    for input in m.inputs {
        for d in input.defines() {
            if !defines.iter().any(|(k, _)| k == d) {
                defines.push((d.to_string(), "1".to_string()));
            }
        }
    }
}

/// A method's stages: the vertex program, the fragment program of a pass with a normal target
/// (`frag`), and the one of a pass without (`color.frag`: the timed draws and what `shadelab
/// isa` compiles write the colour alone, having no attachment for the normal).
const GRAPHICS: [(&str, &str); 3] = [
    ("vert", "shade.vert"),
    ("frag", "shade.frag"),
    (COLOR_ONLY, "shade_color.frag"),
];

/// The stage tag of the fragment program without the normal output.
pub const COLOR_ONLY: &str = "color.frag";

/// The fragment stage for a pass with `colors` attachments: with the normal's or without.
pub fn fragment_stage(colors: usize) -> &'static str {
    if colors >= 2 {
        "frag"
    } else {
        COLOR_ONLY
    }
}

/// The program name of a method or internal program (`ids`, `constant`) in a mode (float32).
pub fn program_name(base: &str, interp: Interpolation) -> String {
    program_name_in(base, interp, Precision::F32)
}

/// The program name of a method in a mode and precision (`ids` and `constant` are float32 only).
pub fn program_name_in(base: &str, interp: Interpolation, precision: Precision) -> String {
    format!(
        "{}{}",
        precision_prefix(base, precision),
        interpolation_tag(interp).0
    )
}

fn f16_defines(mut defines: Vec<(String, String)>) -> Vec<(String, String)> {
    defines.push((F16_DEFINE.to_string(), "1".to_string()));
    defines
}

/// A method's graphics programs in one mode: float16 (when it has it), then float32.
fn graphics_programs(m: &crate::method::Method, mode: Interpolation) -> Vec<Program> {
    let mut defines = vec![("INTERP".to_string(), interpolation_tag(mode).1.to_string())];
    method_defines(m, &mut defines);
    let mut out = Vec::new();
    if has_precision(m.name, Precision::F16) {
        out.push(Program {
            name: program_name_in(m.name, mode, Precision::F16),
            stages: GRAPHICS.to_vec(),
            method_file: Some(m.glsl),
            defines: f16_defines(defines.clone()),
        });
    }
    out.push(Program {
        name: program_name(m.name, mode),
        stages: GRAPHICS.to_vec(),
        method_file: Some(m.glsl),
        defines,
    });
    out
}

/// A method's compute programs (glsl/evaluate.comp): float16 (when it has it), then float32.
fn evaluate_programs(m: &crate::method::Method) -> Vec<Program> {
    let mut defines = Vec::new();
    method_defines(m, &mut defines);
    let mut out = Vec::new();
    if has_precision(m.name, Precision::F16) {
        out.push(Program {
            name: evaluate_program_in(m.name, Precision::F16),
            stages: vec![("comp", "evaluate.comp")],
            method_file: Some(m.glsl),
            defines: f16_defines(defines.clone()),
        });
    }
    out.push(Program {
        name: evaluate_program(m.name),
        stages: vec![("comp", "evaluate.comp")],
        method_file: Some(m.glsl),
        defines,
    });
    out
}

/// Every program, in a stable order.
pub fn programs() -> Vec<Program> {
    let mut out = Vec::new();
    for mode in MODES {
        let qualifier = interpolation_tag(mode).1.to_string();
        let with = |extra: &[(&str, &str)]| {
            let mut d = vec![("INTERP".to_string(), qualifier.clone())];
            d.extend(extra.iter().map(|(k, v)| (k.to_string(), v.to_string())));
            d
        };
        for m in METHODS {
            out.extend(graphics_programs(m, mode));
        }
        out.push(Program {
            name: program_name("ids", mode),
            stages: vec![("vert", "shade.vert"), ("frag", "ids.frag")],
            method_file: None,
            defines: with(&[("IN_BARY", "1"), ("IN_PRIM", "1")]),
        });
        out.push(Program {
            name: program_name("constant", mode),
            stages: vec![
                ("vert", "shade.vert"),
                ("frag", "constant.frag"),
                (COLOR_ONLY, "constant_color.frag"),
            ],
            method_file: None,
            defines: with(&[]),
        });
    }
    for m in METHODS.iter().filter(|m| has_evaluate_program(m)) {
        out.extend(evaluate_programs(m));
    }
    out
}

/// Compiles every program from `glsl_dir`: returns (file name, SPIR-V bytes), sorted by name.
pub fn compile_all(glsl_dir: &Path) -> Result<Vec<(String, Vec<u8>)>> {
    let compiler = new_compiler()?;
    let mut out = Vec::new();
    for p in programs() {
        let read = |name: &str| {
            let path = match (name, p.method_file) {
                ("method.glsl", Some(m)) => glsl_dir.join(m),
                _ => glsl_dir.join(name),
            };
            std::fs::read_to_string(&path)
                .map(|text| (path.display().to_string(), text))
                .map_err(|e| format!("{}: {e}", path.display()))
        };
        out.extend(compile_program(&compiler, &p, &read)?);
    }
    out.sort();
    Ok(out)
}

fn new_compiler() -> Result<shaderc::Compiler> {
    shaderc::Compiler::new()
        .map_err(|e| Error::Shader(format!("cannot start the shaderc compiler: {e}")))
}

/// Resolves a file name of glsl/ (and `method.glsl`, the program's method file) to (the name
/// messages use, its text).
type Reader<'a> = dyn Fn(&str) -> std::result::Result<(String, String), String> + 'a;

/// Compiles one program's stages with the options every program shares (Vulkan 1.3,
/// optimised, the program's defines): (file name `<program>.<stage>.spv`, SPIR-V bytes).
fn compile_program(
    compiler: &shaderc::Compiler,
    p: &Program,
    read: &Reader<'_>,
) -> Result<Vec<(String, Vec<u8>)>> {
    let mut out = Vec::new();
    for &(stage, file) in &p.stages {
        let kind = match stage {
            "vert" => shaderc::ShaderKind::Vertex,
            s if s.ends_with("frag") => shaderc::ShaderKind::Fragment,
            _ => shaderc::ShaderKind::Compute,
        };
        let (main_name, source) = read(file).map_err(Error::Shader)?;
        let mut opts = shaderc::CompileOptions::new()
            .map_err(|e| Error::Shader(format!("shaderc options: {e}")))?;
        opts.set_target_env(
            shaderc::TargetEnv::Vulkan,
            shaderc::EnvVersion::Vulkan1_3 as u32,
        );
        opts.set_optimization_level(shaderc::OptimizationLevel::Performance);
        for (k, v) in &p.defines {
            opts.add_macro_definition(k, Some(v));
        }
        opts.set_include_callback(|name, _ty, _from, _depth| {
            read(name).map(|(resolved_name, content)| shaderc::ResolvedInclude {
                resolved_name,
                content,
            })
        });
        let artifact = compiler
            .compile_into_spirv(&source, kind, &main_name, "main", Some(&opts))
            .map_err(|e| Error::Shader(format!("{} ({main_name}): {e}", p.name)))?;
        out.push((
            format!("{}.{stage}.spv", p.name),
            artifact.as_binary_u8().to_vec(),
        ));
    }
    Ok(out)
}

/// SPIR-V compiled at run time (user methods): (method, file name, bytes), found by
/// [`embedded`] after the files built into the binary.
static RUNTIME_SPIRV: std::sync::RwLock<Vec<(String, String, &'static [u8])>> =
    std::sync::RwLock::new(Vec::new());

/// A user method's programs as [`compile_user`] made them: what a parent hands its compiler
/// workers ([`crate::workers`]) so that no worker compiles the GLSL again.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RuntimePrograms {
    /// (file name, SPIR-V): `<program>.<stage>.spv`.
    pub files: Vec<(String, crate::child::Bytes)>,
    /// Why the method has no float16 programs (shaderc's first message line), if it has none.
    pub no_f16: Option<String>,
}

/// The programs [`compile_user`] registered for user method `method`.
pub fn runtime_programs(method: &str) -> Result<RuntimePrograms> {
    let reg = RUNTIME_SPIRV.read().map_err(|_| poisoned())?;
    let files = reg
        .iter()
        .filter(|(m, _, _)| m == method)
        .map(|(_, f, b)| (f.clone(), crate::child::Bytes(b.to_vec())))
        .collect();
    let no = RUNTIME_NO_F16.read().map_err(|_| poisoned())?;
    let no_f16 = no.iter().find(|(m, _)| m == method).map(|(_, w)| w.clone());
    Ok(RuntimePrograms { files, no_f16 })
}

/// Registers `programs` as user method `method`'s, in place of any it had: a worker's copy of
/// what its parent compiled ([`runtime_programs`]).
pub fn adopt_programs(method: &str, programs: &RuntimePrograms) -> Result<()> {
    let mut reg = RUNTIME_SPIRV.write().map_err(|_| poisoned())?;
    reg.retain(|(m, _, _)| m != method);
    for (file, bytes) in &programs.files {
        let bytes: &'static [u8] = Box::leak(bytes.0.clone().into_boxed_slice());
        reg.push((method.to_string(), file.clone(), bytes));
    }
    let mut no = RUNTIME_NO_F16.write().map_err(|_| poisoned())?;
    no.retain(|(m, _)| m != method);
    if let Some(why) = &programs.no_f16 {
        no.push((method.to_string(), why.clone()));
    }
    Ok(())
}

/// Reads, checks, compiles and registers user method files (`--method-file`; a folder means
/// every .glsl file below it, [`crate::method::user::expand`]; a path already registered is
/// skipped): each becomes a method row ([`crate::method::user`]; a tuned row for a file of
/// `shadelab tune`) once its float32 programs compile. A compile error is reported against the
/// user's file (exit 2), an undeclared input by name.
pub fn register_user(paths: &[std::path::PathBuf]) -> Result<()> {
    use crate::method::user;
    for p in &user::expand(paths)? {
        let abs = std::path::absolute(p).map_err(|e| Error::io(p, e))?;
        if user::is_registered(&abs) {
            continue;
        }
        let (u, parsed) = user::prepare(&abs)?;
        compile_user(u).map_err(|e| match e {
            Error::Shader(msg) => user::explain_compile_error(&parsed, &abs, &msg),
            other => other,
        })?;
        user::add(u)?;
    }
    Ok(())
}

/// Registers `row`, a method made in code, with its GLSL file `path`: its programs compiled
/// like a user method's ([`compile_user`]), then [`crate::method::find`] and every command see
/// it, its kernel and claims as the row states them ([`crate::method::user::prepare_row`]).
pub fn register_row(path: &std::path::Path, row: &'static crate::method::Method) -> Result<()> {
    use crate::method::user;
    let abs = std::path::absolute(path).map_err(|e| Error::io(path, e))?;
    let (u, parsed) = user::prepare_row(&abs, row)?;
    compile_user(u).map_err(|e| match e {
        Error::Shader(msg) => user::explain_compile_error(&parsed, &abs, &msg),
        other => other,
    })?;
    user::add(u)
}

/// User methods whose float16 programs do not compile (their file is not written in the
/// precision vocabulary of glsl/common.glsl): (method, shaderc's first message line).
static RUNTIME_NO_F16: std::sync::RwLock<Vec<(String, String)>> =
    std::sync::RwLock::new(Vec::new());

/// A user method's programs: the programs a built-in method with its inputs gets (both
/// interpolations and precisions, and glsl/evaluate.comp), compiled with the same options from
/// the GLSL embedded in the binary, the user's file standing for `method.glsl` (so shaderc's
/// messages read `PATH:LINE: error`). Registered for [`embedded`]. A float32 error is the
/// caller's error; a float16 one only leaves the method without float16 programs (a warning
/// now, an error naming it from [`embedded`] when a float16 run asks for one).
pub fn compile_user(u: &crate::method::user::UserMethod) -> Result<()> {
    let compiler = new_compiler()?;
    let read = |name: &str| {
        if name == "method.glsl" {
            return Ok((u.path.clone(), u.source.clone()));
        }
        EMBEDDED_GLSL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, text)| (format!("glsl/{n}"), text.to_string()))
            .ok_or_else(|| format!("glsl/{name} is not built into this binary"))
    };
    let f16_prefix = precision_prefix(u.name, Precision::F16);
    let (f16, f32): (Vec<Program>, Vec<Program>) = method_programs(u.method)
        .into_iter()
        .partition(|p| p.name.starts_with(&f16_prefix));
    let mut compiled = Vec::new();
    for p in &f32 {
        compiled.extend(compile_program(&compiler, p, &read)?);
    }
    let mut half = Vec::new();
    for p in &f16 {
        match compile_program(&compiler, p, &read) {
            Ok(c) => half.extend(c),
            Err(e) => {
                let why = e.to_string();
                let line = why.lines().find(|l| l.contains(": error")).unwrap_or(&why);
                log::warn!(
                    "{}: no float16 programs (--precision f16 refuses it): {line}",
                    u.path
                );
                let mut no = RUNTIME_NO_F16.write().map_err(|_| poisoned())?;
                no.push((u.name.to_string(), line.to_string()));
                half.clear();
                break;
            }
        }
    }
    compiled.extend(half);
    let mut reg = RUNTIME_SPIRV.write().map_err(|_| poisoned())?;
    for (name, bytes) in compiled {
        reg.push((
            u.name.to_string(),
            name,
            Box::leak(bytes.into_boxed_slice()),
        ));
    }
    Ok(())
}

fn poisoned() -> Error {
    Error::Internal("a runtime shader registry is poisoned".into())
}

/// Why a user method has no program `program` (a float16 one whose file does not compile in
/// float16), if that is why.
fn no_f16_reason(program: &str) -> Option<Error> {
    let no = RUNTIME_NO_F16.read().ok()?;
    let (m, why) = no
        .iter()
        .find(|(m, _)| program.starts_with(&precision_prefix(m, Precision::F16)))?;
    Some(Error::Usage(format!(
        "{m} has no float16 programs: its file does not compile in the float16 vocabulary of \
         glsl/common.glsl ({why}); write it with real/R()/R3() (docs/your-method.md) or run \
         it in float32"
    )))
}

/// The programs of one method, in [`programs`]' order within each group.
fn method_programs(m: &crate::method::Method) -> Vec<Program> {
    let mut out = Vec::new();
    for mode in MODES {
        out.extend(graphics_programs(m, mode));
    }
    if has_evaluate_program(m) {
        out.extend(evaluate_programs(m));
    }
    out
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 over every file of `glsl_dir` (sorted relative paths + contents) and the program table.
pub fn source_hash(glsl_dir: &Path) -> Result<String> {
    let mut files = Vec::new();
    collect_files(glsl_dir, glsl_dir, &mut files)?;
    files.sort();
    let mut h = Sha256::new();
    for rel in &files {
        let path = glsl_dir.join(rel);
        let bytes = std::fs::read(&path).map_err(|e| Error::io(&path, e))?;
        h.update(rel.as_bytes());
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    for p in programs() {
        h.update(format!("{p:?}\n").as_bytes());
    }
    Ok(hex(&h.finalize()))
}

fn collect_files(root: &Path, dir: &Path, out: &mut Vec<String>) -> Result<()> {
    let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    for entry in rd {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let path = entry.path();
        if path.is_dir() {
            collect_files(root, &path, out)?;
        } else if let Ok(rel) = path.strip_prefix(root) {
            out.push(rel.to_string_lossy().replace('\\', "/"));
        }
    }
    Ok(())
}

/// The manifest written beside the .spv files.
#[derive(Debug, serde::Serialize, serde::Deserialize, PartialEq)]
pub struct Manifest {
    /// [`source_hash`] of glsl/ when the files were generated.
    pub source_hash: String,
    /// SHA-256 of each .spv file.
    pub files: BTreeMap<String, String>,
}

/// Compiles everything and writes `spirv_dir` (stale .spv files removed) and its manifest.
pub fn write_spirv(glsl_dir: &Path, spirv_dir: &Path) -> Result<usize> {
    let compiled = compile_all(glsl_dir)?;
    std::fs::create_dir_all(spirv_dir).map_err(|e| Error::io(spirv_dir, e))?;
    let mut files = BTreeMap::new();
    for (name, bytes) in &compiled {
        crate::output::write_bytes_atomic(&spirv_dir.join(name), bytes)?;
        files.insert(name.clone(), hex(&Sha256::digest(bytes)));
    }
    let rd = std::fs::read_dir(spirv_dir).map_err(|e| Error::io(spirv_dir, e))?;
    for entry in rd.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.ends_with(".spv") && !files.contains_key(&name) {
            std::fs::remove_file(entry.path()).map_err(|e| Error::io(entry.path(), e))?;
        }
    }
    let manifest = Manifest {
        source_hash: source_hash(glsl_dir)?,
        files,
    };
    let json = serde_json::to_string_pretty(&manifest)
        .map_err(|e| Error::output("spirv/manifest.json", e))?
        + "\n";
    crate::output::write_bytes_atomic(&spirv_dir.join("manifest.json"), json.as_bytes())?;
    Ok(compiled.len())
}

/// Checks that `spirv_dir` was generated from the current `glsl_dir` and program table and that
/// no .spv was edited, added or removed since. The error says what is stale and to run
/// [`REGENERATE`].
pub fn check_fresh(glsl_dir: &Path, spirv_dir: &Path) -> Result<()> {
    let stale = |why: String| Error::Shader(format!("spirv/ is stale: {why}; run `{REGENERATE}`"));
    let path = spirv_dir.join("manifest.json");
    let text = std::fs::read_to_string(&path)
        .map_err(|_| stale("spirv/manifest.json is missing".into()))?;
    let manifest: Manifest = serde_json::from_str(&text)
        .map_err(|e| stale(format!("spirv/manifest.json is unreadable ({e})")))?;
    if manifest.source_hash != source_hash(glsl_dir)? {
        return Err(stale(
            "glsl/ or the program table changed since spirv/ was generated".into(),
        ));
    }
    let mut expected = Vec::new();
    for p in programs() {
        for (stage, _) in &p.stages {
            expected.push(format!("{}.{stage}.spv", p.name));
        }
    }
    for name in &expected {
        let Some(hash) = manifest.files.get(name) else {
            return Err(stale(format!("{name} is not in the manifest")));
        };
        let bytes = std::fs::read(spirv_dir.join(name))
            .map_err(|_| stale(format!("spirv/{name} is missing")))?;
        if &hex(&Sha256::digest(&bytes)) != hash {
            return Err(stale(format!(
                "spirv/{name} differs from the generated file"
            )));
        }
    }
    if manifest.files.len() != expected.len() {
        return Err(stale(
            "the manifest lists programs that no longer exist".into(),
        ));
    }
    Ok(())
}

/// The SPIR-V of `<program>.<stage>.spv` (stage `vert`, `frag` or `comp`): built into the
/// binary, or compiled at run time for a user method ([`compile_user`]).
pub fn embedded(program: &str, stage: &str) -> Result<&'static [u8]> {
    let file = format!("{program}.{stage}.spv");
    let runtime = || {
        RUNTIME_SPIRV
            .read()
            .ok()
            .and_then(|r| r.iter().find(|(_, n, _)| *n == file).map(|(_, _, b)| *b))
    };
    EMBEDDED_SPIRV
        .iter()
        .find(|(n, _)| *n == file)
        .map(|(_, b)| *b)
        .or_else(runtime)
        .ok_or_else(|| {
            if let Some(e) = no_f16_reason(program) {
                return e;
            }
            Error::Shader(format!(
                "spirv/{file} was not built into this binary; run `{REGENERATE}` and rebuild"
            ))
        })
}

/// `m`'s GLSL as a method file (docs/your-method.md): a user method's text, or a built-in
/// method's glsl/methods/ source with its `// shadelab-inputs:` line first (what `explore`
/// offers to edit). `None` for a row without a source of its own.
pub fn method_file_text(m: &crate::method::Method) -> Option<String> {
    use crate::method::user;
    if let Some(u) = user::of(m) {
        return Some(u.source.clone());
    }
    let file = m.glsl.strip_prefix("methods/")?;
    let (_, text) = EMBEDDED_METHOD_GLSL.iter().find(|(n, _)| *n == file)?;
    let inputs: Vec<&str> = m.inputs.iter().map(|i| user::input_name(*i)).collect();
    Some(format!(
        "{} {}\n{text}",
        user::INPUTS_MARKER,
        inputs.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_names_are_unique() {
        let ps = programs();
        for (i, p) in ps.iter().enumerate() {
            assert!(
                ps[..i].iter().all(|o| o.name != p.name),
                "duplicate program {}",
                p.name
            );
        }
        assert!(ps.iter().any(|p| p.name == "phong_exact.screen_linear"));
        assert!(ps.iter().any(|p| p.name == "ids.perspective"));
        assert!(ps.iter().any(|p| p.name == "phong_exact.f16.screen_linear"));
        assert!(ps.iter().any(|p| p.name == "phong_exact.f16.evaluate"));
        assert!(!ps.iter().any(|p| p.name == "ids.f16.perspective"));
    }
}
