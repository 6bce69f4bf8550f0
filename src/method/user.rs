//! User methods (issue 28): a GLSL file given with `--method-file PATH.glsl` becomes a method
//! row like the built-in ones. This module owns the file's parsing (its id, the inputs it
//! declares, its entry point), the process-wide registry of user rows ([`all`] is the built-in
//! table followed by them) and the refusals (a clashing id, an unknown or undeclared input).
//!
//! A user row has no f64 twin and no software kernel: [`Method::twin`] is `None` and its
//! kernel is [`Kernel::None`], which the software engine refuses. A file written by `shadelab
//! tune` is the exception: its `// shadelab-tuned:` line ([`super::tuned`]) states its formula,
//! the file's code must be the code that line generates (else it is refused, exit 2), and its
//! row is [`Family::Tuned`] with the formula as its kernel (a twin, a software form, a proof).
//! A row made in code with its file ([`prepare_row`]: a method generated at run time, a
//! test's) has the kernel and claims of its row, like a row of the table. Their programs
//! are compiled before registration ([`crate::gpu::shaders::register_user`]) from
//! the GLSL embedded in the binary, so it runs outside the repository too.
//!
//! Child processes (bench's fresh runs, isa's one process per GPU family) see the same
//! methods: their request carries the files ([`paths`], [`crate::child`]).
use std::path::{Path, PathBuf};
use std::sync::RwLock;

use serde::Serialize;
use sha2::{Digest, Sha256};

use super::{Family, Geometry, Input, Kernel, Method, Reference, METHODS};
use crate::error::{Error, Result};

/// The marker of the declaration line.
pub const INPUTS_MARKER: &str = "// shadelab-inputs:";

/// How many first lines may hold the declaration.
const DECLARATION_LINES: usize = 20;

/// Every input by its name in `shadelab list --json` (serde's snake_case of [`Input`]).
pub const INPUT_NAMES: [(&str, Input); 10] = [
    ("interpolated_normal", Input::InterpolatedNormal),
    ("flat_normal", Input::FlatNormal),
    ("barycentrics", Input::Barycentrics),
    ("corner_normals", Input::CornerNormals),
    ("pn_mid_normals", Input::PnMidNormals),
    ("vertex_color", Input::VertexColor),
    ("quaternion", Input::Quaternion),
    ("quaternion_local", Input::QuaternionLocal),
    ("specular_lut", Input::SpecularLut),
    ("scanline_span", Input::ScanlineSpan),
];

/// GLSL identifiers that exist only when an input is declared (glsl/common.glsl), and the input
/// that declares them: how an "undeclared identifier" compile error is traced to a missing
/// declaration.
pub const IDENTIFIERS: [(&str, Input); 17] = [
    ("vNormal", Input::InterpolatedNormal),
    ("vBary", Input::Barycentrics),
    ("vFlat", Input::FlatNormal),
    ("vN0", Input::CornerNormals),
    ("vN1", Input::CornerNormals),
    ("vN2", Input::CornerNormals),
    ("vPn01", Input::PnMidNormals),
    ("vPn12", Input::PnMidNormals),
    ("vPn20", Input::PnMidNormals),
    ("vColor", Input::VertexColor),
    ("vQuat", Input::Quaternion),
    ("vW0", Input::ScanlineSpan),
    ("vW1", Input::ScanlineSpan),
    ("vW2", Input::ScanlineSpan),
    ("lut", Input::SpecularLut),
    ("LUT_ROWS", Input::SpecularLut),
    ("LUT_SAMPLES", Input::SpecularLut),
];

/// The name of an input in `shadelab list --json`.
pub fn input_name(input: Input) -> &'static str {
    INPUT_NAMES
        .iter()
        .find(|(_, i)| *i == input)
        .map_or("?", |(n, _)| n)
}

/// A registered user method: its row and where it came from (written into every run's JSON).
#[derive(Debug, Serialize)]
pub struct UserMethod {
    /// The method row (`family: yours`).
    #[serde(skip)]
    pub method: &'static Method,
    /// The method's id (the file stem).
    pub name: &'static str,
    /// The file as given (made absolute).
    pub path: String,
    /// SHA-256 of the file's bytes, hex.
    pub sha256: String,
    /// The file's text, compiled in place of glsl/methods/<name>.glsl.
    #[serde(skip)]
    pub source: String,
    /// 1-based line of the `// shadelab-inputs:` declaration.
    #[serde(skip)]
    pub declaration_line: usize,
    /// The tuned form of a file written by `shadelab tune` (its `// shadelab-tuned:` line).
    #[serde(skip)]
    pub tuned: Option<&'static super::tuned::Tuned>,
}

static REGISTRY: RwLock<Vec<&'static UserMethod>> = RwLock::new(Vec::new());

/// The registered user methods, in registration order.
pub fn registered() -> Vec<&'static UserMethod> {
    REGISTRY.read().map(|r| r.clone()).unwrap_or_default()
}

/// The user method of this row, if it is one.
pub fn of(m: &Method) -> Option<&'static UserMethod> {
    registered().into_iter().find(|u| u.name == m.name)
}

/// Every method: the built-in table, then the user methods.
pub fn all() -> Vec<&'static Method> {
    let mut v: Vec<&'static Method> = METHODS.iter().collect();
    v.extend(registered().iter().map(|u| u.method));
    v
}

/// What a file declares, before compilation.
#[derive(Debug, Clone, PartialEq)]
pub struct Parsed {
    pub name: String,
    pub inputs: Vec<Input>,
    pub declaration_line: usize,
    /// `methodNormal()` (true) or `methodColor()` under `#define METHOD_COLOR` (false).
    pub has_normal: bool,
}

fn usage(path: &Path, what: String) -> Error {
    Error::Usage(format!("{}: {what}", path.display()))
}

/// Whether `s` is a snake_case identifier: a lowercase letter, then lowercase letters, digits
/// and single underscores, not ending in one.
pub fn is_snake_case(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty()
        && b[0].is_ascii_lowercase()
        && b.iter()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == b'_')
        && !s.contains("__")
        && !s.ends_with('_')
}

/// Parses a method file's text (`path` names it in errors): the id from the stem, the inputs
/// from the declaration line, the entry point.
pub fn parse(path: &Path, text: &str) -> Result<Parsed> {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    if path.extension().and_then(|e| e.to_str()) != Some("glsl") {
        return Err(usage(path, "a method file's name ends in .glsl".into()));
    }
    if !is_snake_case(stem) {
        return Err(usage(path, format!("the method's id is the file stem, {stem:?}, which is not snake_case (lowercase letters, digits, single underscores): rename the file")));
    }
    if METHODS.iter().any(|m| m.name == stem) || stem == "auto" || stem == "all" {
        return Err(usage(path, format!("the method's id {stem:?} (the file stem) is the name of a built-in method: rename the file")));
    }
    let Some((idx, list)) = text
        .lines()
        .take(DECLARATION_LINES)
        .enumerate()
        .find_map(|(i, l)| l.trim().strip_prefix(INPUTS_MARKER).map(|r| (i, r)))
    else {
        return Err(usage(path, format!("no `{INPUTS_MARKER} NAME, ...` line in the first {DECLARATION_LINES} lines; declare the inputs the method reads, e.g. `{INPUTS_MARKER} interpolated_normal` (inputs: {})", valid_inputs())));
    };
    let mut inputs = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((_, input)) = INPUT_NAMES.iter().find(|(n, _)| *n == name) else {
            return Err(usage(
                path,
                format!(
                    "line {}: unknown input {name:?}; valid inputs: {}",
                    idx + 1,
                    valid_inputs()
                ),
            ));
        };
        if !inputs.contains(input) {
            inputs.push(*input);
        }
    }
    let code: String = text
        .lines()
        .map(strip_comment)
        .collect::<Vec<_>>()
        .join("\n");
    let color = code.contains("methodColor(");
    let normal = code.contains("methodNormal(");
    if color == normal {
        return Err(usage(path, "define exactly one of `real3 methodNormal()` (the shading normal; `#define METHOD_SHADE` and `real3 methodShade(real3 N)` to light it yourself) and `real3 methodColor()` (with `#define METHOD_COLOR`), as glsl/methods/ does".into()));
    }
    if color && !code.contains("METHOD_COLOR") {
        return Err(usage(path, "a file that defines methodColor() needs `#define METHOD_COLOR` before it (glsl/method_main.glsl)".into()));
    }
    Ok(Parsed {
        name: stem.to_string(),
        inputs,
        declaration_line: idx + 1,
        has_normal: normal,
    })
}

fn strip_comment(line: &str) -> &str {
    line.split_once("//").map_or(line, |(a, _)| a)
}

fn valid_inputs() -> String {
    INPUT_NAMES.map(|(n, _)| n).join(", ")
}

/// A compile error of a user's programs, told in the user's words: the identifier of an input
/// the file did not declare names that input and the line to add; otherwise shaderc's message
/// (it reads `PATH:LINE: error: ...`).
pub fn explain_compile_error(u: &Parsed, path: &Path, message: &str) -> Error {
    for (ident, input) in IDENTIFIERS {
        if u.inputs.contains(&input) {
            continue;
        }
        if message.contains(&format!("'{ident}' : undeclared identifier")) {
            let mut names: Vec<&str> = u.inputs.iter().map(|i| input_name(*i)).collect();
            names.push(input_name(input));
            return usage(path, format!("reads `{ident}`, which belongs to the input {} that the file does not declare; make line {} `{INPUTS_MARKER} {}`", input_name(input), u.declaration_line, names.join(", ")));
        }
    }
    Error::Usage(format!(
        "{} does not compile:\n{}",
        path.display(),
        message.trim_end()
    ))
}

fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// The registered files' paths, in registration order: what a child process is given
/// ([`crate::child::Envelope::method_files`]).
pub fn paths() -> Vec<PathBuf> {
    registered()
        .iter()
        .map(|u| PathBuf::from(&u.path))
        .collect()
}

/// The files of the user methods among `methods`, in registration order: what a child that
/// compiles only `methods` needs (a process that registered many files, `tune` over a folder
/// of meshes, hands each child only its own).
pub fn paths_of(methods: &[&Method]) -> Vec<PathBuf> {
    registered()
        .iter()
        .filter(|u| methods.iter().any(|m| m.name == u.name))
        .map(|u| PathBuf::from(&u.path))
        .collect()
}

/// `paths` with each folder replaced by every `.glsl` file below it (recursively, sorted by
/// path): `--method-file DIR`. A folder without one is an error (exit 2).
pub fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
        let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
        for entry in rd {
            let p = entry.map_err(|e| Error::io(dir, e))?.path();
            if p.is_dir() {
                walk(&p, out)?;
            } else if p.extension().and_then(|e| e.to_str()) == Some("glsl") {
                out.push(p);
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    for p in paths {
        if !p.is_dir() {
            out.push(p.clone());
            continue;
        }
        let mut found = Vec::new();
        walk(p, &mut found)?;
        if found.is_empty() {
            return Err(usage(p, "is a folder with no .glsl file below it".into()));
        }
        found.sort();
        out.extend(found);
    }
    Ok(out)
}

/// Whether the file at the absolute path `abs` is registered already.
pub fn is_registered(abs: &Path) -> bool {
    registered().iter().any(|u| Path::new(&u.path) == abs)
}

/// Reads and checks the file at the absolute path `path` and makes its row (not registered
/// yet: its programs are compiled first, by [`crate::gpu::shaders::register_user`]).
pub fn prepare(path: &Path) -> Result<(&'static UserMethod, Parsed)> {
    let (bytes, text, parsed) = read(path)?;
    let sha256 = sha256_hex(&bytes);
    prepare_text(path, &sha256, text, parsed)
}

/// The row of the file at `path` whose bytes hash to `sha256`, from its `text` and
/// declaration.
fn prepare_text(
    path: &Path,
    sha256: &str,
    text: String,
    parsed: Parsed,
) -> Result<(&'static UserMethod, Parsed)> {
    let path_str = leak(path.display().to_string());
    if let Some(tuned) = super::tuned::Tuned::of_text(&text) {
        let tuned = tuned.map_err(|why| usage(path, why))?;
        if !tuned.matches(&text) {
            return Err(usage(
                path,
                format!(
                    "its code differs from its {} line (the code that line generates: \
                     docs/tune.md); delete that line to use it as your own method",
                    super::tuned::TUNED_MARKER
                ),
            ));
        }
        let method = tuned.clone().row(leak(parsed.name.clone()), path_str);
        let tuned: &'static super::tuned::Tuned = Box::leak(Box::new(tuned));
        let u = user_method(method, path_str, sha256, text, &parsed, Some(tuned));
        return Ok((u, parsed));
    }
    let method: &'static Method = Box::leak(Box::new(Method {
        name: leak(parsed.name.clone()),
        description: leak(format!("your method, from {path_str}")),
        citation: path_str,
        inputs: Box::leak(parsed.inputs.clone().into_boxed_slice()),
        family: Family::Yours,
        properties: &[],
        geometry: Geometry::Mesh,
        has_normal: parsed.has_normal,
        reference: Reference::Phong,
        validity: "unknown (a user method: see stress's validity map)",
        claims: &[],
        glsl: path_str,
        kernel: Kernel::None,
    }));
    Ok((
        user_method(method, path_str, sha256, text, &parsed, None),
        parsed,
    ))
}

/// A method row made in code with its GLSL file at the absolute path `path` (not registered
/// yet: [`crate::gpu::shaders::register_row`] compiles and registers it). The row is the
/// method, kernel and claims included, as a row of the table is: a method generated at run
/// time, or a test's, is its file and this one row. The file must declare the row's id (its
/// stem), its inputs and its entry point (a normal exactly when the row has one).
pub fn prepare_row(path: &Path, row: &'static Method) -> Result<(&'static UserMethod, Parsed)> {
    let (bytes, text, parsed) = read(path)?;
    if parsed.name != row.name || parsed.inputs != row.inputs || parsed.has_normal != row.has_normal
    {
        return Err(usage(
            path,
            format!(
                "declares {} with inputs {:?} (normal: {}), its row {} with {:?} (normal: {}): \
                 make them agree",
                parsed.name, parsed.inputs, parsed.has_normal, row.name, row.inputs, row.has_normal
            ),
        ));
    }
    let path_str = leak(path.display().to_string());
    Ok((
        user_method(row, path_str, &sha256_hex(&bytes), text, &parsed, None),
        parsed,
    ))
}

/// The file's bytes, text and declaration, refused when its id is registered already.
fn read(path: &Path) -> Result<(Vec<u8>, String, Parsed)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let text =
        String::from_utf8(bytes.clone()).map_err(|_| usage(path, "is not UTF-8 text".into()))?;
    // A UTF-8 byte-order mark (as some Windows editors write) is not text of the file: the
    // declaration is still line 1, and the compiler never sees the mark. The checksum stays
    // that of the bytes.
    let text = match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    };
    let parsed = parse(path, &text)?;
    if let Some(other) = registered().iter().find(|u| u.name == parsed.name) {
        return Err(usage(
            path,
            format!(
                "its id {:?} (the file stem) is also the id of {}: rename one",
                parsed.name, other.path
            ),
        ));
    }
    Ok((bytes, text, parsed))
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn user_method(
    method: &'static Method,
    path: &'static str,
    sha256: &str,
    source: String,
    parsed: &Parsed,
    tuned: Option<&'static super::tuned::Tuned>,
) -> &'static UserMethod {
    Box::leak(Box::new(UserMethod {
        method,
        name: method.name,
        path: path.to_string(),
        sha256: sha256.to_string(),
        source,
        declaration_line: parsed.declaration_line,
        tuned,
    }))
}

/// Registers the file at the absolute path `path` from what a parent read and checked of it
/// (its text, without a byte-order mark, and the SHA-256 of its bytes), in place of a method of
/// the same id: a compiler worker's copy of its parent's method ([`crate::workers`]), whose
/// programs come with it. Its declaration and tuned line are read again (no file is read, no
/// proof run, nothing compiled).
pub fn adopt(path: &Path, sha256: &str, text: &str) -> Result<&'static UserMethod> {
    let parsed = parse(path, text)?;
    let (u, _) = prepare_text(path, sha256, text.to_string(), parsed)?;
    let mut reg = REGISTRY
        .write()
        .map_err(|_| Error::Internal("the user-method registry is poisoned".into()))?;
    reg.retain(|r| r.name != u.name);
    reg.push(u);
    Ok(u)
}

/// Registers a prepared method whose programs compiled: [`all`] and [`super::find`] see it from
/// now on, and every run's provenance names its file.
pub fn add(u: &'static UserMethod) -> Result<()> {
    REGISTRY
        .write()
        .map_err(|_| Error::Internal("the user-method registry is poisoned".into()))?
        .push(u);
    use crate::output::provenance::{record_method_file, MethodFile};
    record_method_file(MethodFile {
        name: u.name.to_string(),
        path: u.path.clone(),
        sha256: u.sha256.clone(),
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A method file that starts with a UTF-8 byte-order mark reads as the same file without
    /// it (it said "no `// shadelab-inputs:` line in the first 20 lines" of line 1's
    /// declaration), and the text handed to the compiler has no mark.
    #[test]
    fn a_byte_order_mark_before_the_declaration_is_not_part_of_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let text = "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() { return normalize(interpolatedNormal()); }\n";
        let plain = dir.path().join("bom_plain.glsl");
        let bom = dir.path().join("bom_marked.glsl");
        std::fs::write(&plain, text).unwrap();
        std::fs::write(&bom, [b"\xEF\xBB\xBF".as_slice(), text.as_bytes()].concat()).unwrap();
        let (_, plain_text, plain_parsed) = read(&plain).unwrap();
        let (bytes, bom_text, bom_parsed) = read(&bom).unwrap();
        assert_eq!(bom_text, plain_text);
        assert!(!bom_text.starts_with('\u{feff}'));
        assert_eq!(bom_parsed.declaration_line, 1);
        assert_eq!(
            (bom_parsed.inputs, bom_parsed.has_normal),
            (plain_parsed.inputs, plain_parsed.has_normal)
        );
        assert_eq!(
            bytes.len(),
            text.len() + 3,
            "the checksum is of the file's bytes"
        );
    }

    fn p(name: &str) -> PathBuf {
        PathBuf::from(format!("/x/{name}"))
    }

    #[test]
    fn input_names_are_the_list_json_names() {
        for (name, input) in INPUT_NAMES {
            assert_eq!(serde_json::to_value(input).unwrap(), name);
        }
        assert_eq!(input_name(Input::Barycentrics), "barycentrics");
    }

    #[test]
    fn parses_declaration_and_entry_point() {
        let t = "// two steps\n// shadelab-inputs: interpolated_normal, flat_normal\nreal3 methodNormal() { return R3(vNormal); }\n";
        let u = parse(&p("two_steps.glsl"), t).unwrap();
        assert_eq!(u.name, "two_steps");
        assert_eq!(u.inputs, vec![Input::InterpolatedNormal, Input::FlatNormal]);
        assert_eq!(u.declaration_line, 2);
        assert!(u.has_normal);
        let c = "// shadelab-inputs: vertex_color\n#define METHOD_COLOR\nreal3 methodColor() { return R3(vColor); }\n";
        assert!(!parse(&p("mine.glsl"), c).unwrap().has_normal);
    }

    #[test]
    fn refuses_bad_names_inputs_and_entry_points() {
        let ok = "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() { return R3(vNormal); }\n";
        for bad in [
            "phong_exact.glsl",
            "Mine.glsl",
            "a__b.glsl",
            "auto.glsl",
            "mine.frag",
        ] {
            assert!(parse(&p(bad), ok).is_err(), "{bad} accepted");
        }
        let e = parse(
            &p("m.glsl"),
            "// shadelab-inputs: normal\nreal3 methodNormal();",
        )
        .unwrap_err();
        assert!(e.to_string().contains("interpolated_normal"), "{e}");
        assert!(parse(&p("m.glsl"), "real3 methodNormal() {}").is_err());
        let neither = "// shadelab-inputs: interpolated_normal\nreal3 f() {}";
        assert!(parse(&p("m.glsl"), neither).is_err());
        let commented =
            "// shadelab-inputs: vertex_color\n// methodNormal() was here\nreal3 methodColor() {}";
        assert!(parse(&p("m.glsl"), commented).is_err(), "no METHOD_COLOR");
    }

    /// A folder is every .glsl file below it, sorted; a file stays itself; a folder without
    /// one is refused.
    #[test]
    fn a_folder_is_every_glsl_file_below_it() {
        let d = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(d.path().join("b/c")).unwrap();
        for f in ["b/c/z.glsl", "a.glsl", "notes.txt"] {
            std::fs::write(d.path().join(f), "").unwrap();
        }
        let one = p("one.glsl");
        let got = expand(&[d.path().to_path_buf(), one.clone()]).unwrap();
        assert_eq!(
            got,
            vec![d.path().join("a.glsl"), d.path().join("b/c/z.glsl"), one]
        );
        let empty = tempfile::tempdir().unwrap();
        let e = expand(&[empty.path().to_path_buf()]).unwrap_err();
        assert!(e.to_string().contains("no .glsl file below it"), "{e}");
    }

    #[test]
    fn an_undeclared_identifier_names_its_input() {
        let u = parse(
            &p("m.glsl"),
            "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() { return R3(vFlat); }",
        )
        .unwrap();
        let msg = "/x/m.glsl:2: error: 'vFlat' : undeclared identifier\n";
        let e = explain_compile_error(&u, &p("m.glsl"), msg).to_string();
        assert!(e.contains("flat_normal") && e.contains("line 1"), "{e}");
        let other = explain_compile_error(
            &u,
            &p("m.glsl"),
            "/x/m.glsl:2: error: 'foo' : undeclared identifier",
        )
        .to_string();
        assert!(
            other.contains("/x/m.glsl:2: error") && !other.contains("flat_normal"),
            "{other}"
        );
    }
}
