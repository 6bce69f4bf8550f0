//! OBJ reading (a validating pass with `file:line` errors, then tobj, cross-checked) and OBJ
//! writing (deduplicated, shortest round-trip floats, atomic).
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use super::soup::{self, lacks_normal, plural, Corner};
use super::*;
use crate::error::{Error, Result};
use crate::output::write_atomic;

/// One `f` statement: `corners[first..first + len]`.
#[derive(Debug, Clone, Copy)]
struct Face {
    first: usize,
    len: usize,
}
/// Result of the validation pass.
#[derive(Debug, Default)]
struct Parsed {
    positions: Vec<[f32; 3]>,
    /// `positions` widened to f64 (exactly), for [`soup`].
    wide: Vec<DVec3>,
    normals: Vec<[f32; 3]>,
    texcoord_count: usize,
    faces: Vec<Face>,
    corners: Vec<Corner>,
    had_polygons: bool,
    skipped_elements: usize,
    /// Statements whose keyword the OBJ specification does not have, and the first (line,
    /// keyword).
    unknown_statements: usize,
    first_unknown: Option<(usize, String)>,
    /// Normalized copy of the geometry statements for tobj (see the module doc).
    tobj_text: String,
}
/// Loads a Wavefront OBJ file into a fitted triangle soup.
///
/// - Faces with more than 3 vertices are triangulated as fans (tobj's triangulation).
/// - Normals given in the file are kept per corner (split normals included) and normalized;
///   a zero-length given normal counts as missing.
/// - Corners without a normal get a smooth normal: the angle-weighted sum of the face normals
///   of the non-degenerate triangles around the same *position index* (so texture-coordinate
///   seams do not split the shading). Where those face normals cancel out (two-sided sheets),
///   the corner takes its own face normal and a warning says how often that happened.
/// - Zero-area triangles ([`is_zero_area`]) are dropped and counted.
/// - The result is fitted with [`fit_unit`].
/// - `l` and `p` elements, groups, materials and smoothing groups are ignored; texture
///   coordinates and vertex colours are validated, then ignored.
/// - Lines end at "\r\n", "\n" or a lone "\r" (old Mac OS files); a statement whose line ends
///   with `\` (outside a comment) continues on the next line.
///
/// Errors: a missing or unreadable file is [`Error::Io`]; malformed statements, indices out of
/// range (positive, zero or relative), non-finite coordinates and faces with fewer than 3
/// vertices are [`Error::Input`] with the 1-based line; a file that leaves no triangles is
/// [`Error::Input`] without a line.
pub fn load_obj(path: &Path) -> Result<(Mesh, LoadReport)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_obj(path, &bytes)
}
/// [`load_obj`] on bytes already read: `path` only names the file in messages and in the mesh's
/// `source`. Errors as [`load_obj`]'s, except that it never returns [`Error::Io`]. This is the
/// entry point the fuzz harness (tests/fuzz.rs) drives.
pub fn parse_obj(path: &Path, bytes: &[u8]) -> Result<(Mesh, LoadReport)> {
    let bytes = text_bytes(path, bytes)?;
    // Lossy: a stray Latin-1 byte in a comment must not reject the file; in a number it turns
    // into U+FFFD and fails number parsing with the line reported.
    let text = String::from_utf8_lossy(bytes);
    let parsed = validate_obj(path, &text)?;
    if parsed.faces.is_empty() {
        return Err(Error::input(
            path,
            None,
            "no triangles: the file has no faces (`f` statements)",
        ));
    }
    let tobj_models = run_tobj(path, &parsed.tobj_text)?;
    build_from_parsed(path, &parsed, &tobj_models)
}
/// The formats the reader takes, for the refusal of anything else.
const FORMATS_READ: &str = "shadelab reads Wavefront OBJ meshes (text, ASCII or UTF-8)";

/// The OBJ text of `bytes`: without a UTF-8 byte-order mark (which would otherwise make the
/// first statement an unknown one and shift every later index), and refused when it is not
/// text at all: UTF-16 (its mark, or NUL bytes), binary glTF, PLY, JSON or other binary data,
/// named as such (the bytes of such a file used to read as a text with no `f` statement).
fn text_bytes<'a>(path: &Path, bytes: &'a [u8]) -> Result<&'a [u8]> {
    let what = if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        Some("UTF-16 text")
    } else if bytes.starts_with(b"glTF") {
        Some("binary glTF (.glb)")
    } else if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
        Some("PLY")
    } else if bytes.trim_ascii_start().starts_with(b"{") {
        Some("JSON (a .gltf?)")
    } else if bytes.iter().take(1 << 16).any(|&b| b == 0) {
        Some("binary data or UTF-16 text (it holds NUL bytes)")
    } else {
        None
    };
    if let Some(what) = what {
        return Err(Error::input(
            path,
            None,
            format!("this is {what}, not an OBJ file: {FORMATS_READ}; convert it to OBJ"),
        ));
    }
    Ok(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes))
}

/// The statements of the OBJ specification (Wavefront's "Object Files (.obj)", appendix B1 of
/// the Advanced Visualizer manual) that the reader ignores: anything else is counted and
/// named in a warning, and a keyword holding a character no keyword has (a stray byte-order
/// mark, a control character, U+FFFD of an undecodable byte) is an error at its line, so that
/// leading junk never silently turns a `v` into an ignored statement.
const IGNORED_KEYWORDS: [&str; 33] = [
    "vp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "g",
    "s",
    "mg",
    "o",
    "bevel",
    "c_interp",
    "d_interp",
    "lod",
    "usemtl",
    "mtllib",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "maplib",
    "usemap",
    "call",
    "csh",
];

/// Parses `tok` as an f32 coordinate that must be finite.
fn parse_coord(tok: &str, what: &str, which: usize) -> std::result::Result<f32, String> {
    match tok.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!(
            "{what} {which} is `{tok}`, which is not a finite number (NaN, infinity or beyond the f32 range)"
        )),
        Err(_) => Err(format!("{what} {which} is `{tok}`, which is not a number")),
    }
}
/// Resolves a 1-based or negative (relative) OBJ index against the `count` elements defined so
/// far; returns the 0-based index or a message naming the problem.
fn resolve_index(
    raw: &str,
    count: usize,
    kind: &str,
    singular: &str,
    plural: &str,
) -> std::result::Result<usize, String> {
    let idx: i64 = raw
        .parse()
        .map_err(|_| format!("face {kind}index `{raw}` is not an integer"))?;
    if idx > 0 {
        let i = (idx - 1) as usize;
        if i >= count {
            return Err(format!(
                "face {kind}index {idx} is past the {count} {plural} defined so far"
            ));
        }
        Ok(i)
    } else if idx == 0 {
        Err(format!(
            "face {kind}index 0 is invalid: OBJ indices start at 1 (negative ones count back from the last {singular})"
        ))
    } else {
        let r = count as i64 + idx;
        if r < 0 {
            return Err(format!(
                "relative face {kind}index {idx} points before the first {singular}: only {count} {plural} are defined so far"
            ));
        }
        Ok(r as usize)
    }
}
/// The lines of `text`, each ended by "\r\n", "\n" or a lone "\r" (the line end of old Mac OS
/// files, where `str::lines` sees one line), without its end.
fn physical_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = text;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        let (line, next) = match rest.find(['\r', '\n']) {
            Some(i) if rest[i..].starts_with("\r\n") => (&rest[..i], &rest[i + 2..]),
            Some(i) => (&rest[..i], &rest[i + 1..]),
            None => (rest, ""),
        };
        rest = next;
        Some(line)
    })
}

/// Calls `each` with every statement of `text` and the 1-based line it starts on: comments
/// (`#` to the end of the line) removed, and a line whose remaining content ends with `\`
/// joined to the next (the OBJ line continuation; a `\` inside a comment continues nothing).
/// A file ending inside a continued statement gives that statement as it is.
fn for_each_statement(text: &str, mut each: impl FnMut(usize, &str) -> Result<()>) -> Result<()> {
    let mut pending: Option<(usize, String)> = None;
    for (i, raw) in physical_lines(text).enumerate() {
        // OBJ comments run from '#' to the end of the line; tobj only knows whole-line ones.
        let content = raw.split_once('#').map_or(raw, |(c, _)| c);
        let (start, joined) = match pending.take() {
            Some((start, mut acc)) => {
                acc.push(' ');
                acc.push_str(content);
                (start, std::borrow::Cow::Owned(acc))
            }
            None => (i + 1, std::borrow::Cow::Borrowed(content)),
        };
        if let Some(head) = joined.trim_end().strip_suffix('\\') {
            pending = Some((start, head.to_string()));
            continue;
        }
        each(start, &joined)?;
    }
    match pending {
        Some((start, acc)) => each(start, &acc),
        None => Ok(()),
    }
}

/// The validation pass: checks every statement, collects positions, normals and faces, and
/// writes the normalized copy for tobj. Errors carry the 1-based line a statement starts on.
fn validate_obj(path: &Path, text: &str) -> Result<Parsed> {
    let mut p = Parsed {
        tobj_text: String::with_capacity(text.len()),
        ..Parsed::default()
    };
    for_each_statement(text, |line, content| {
        let err = |msg: String| Error::input(path, Some(line), msg);
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else {
            return Ok(());
        };
        let args: Vec<&str> = words.collect();
        match keyword {
            "v" => p.vertex(&args, content).map_err(err)?,
            "vn" => p.normal(&args, content).map_err(err)?,
            "vt" => p.texcoord(&args).map_err(err)?,
            "f" => p.face(&args).map_err(err)?,
            "l" | "p" => p.skipped_elements += 1,
            // Groups, objects, smoothing groups, materials, free-form geometry: not ours to draw.
            k if IGNORED_KEYWORDS.contains(&k) => {}
            k if !k.chars().all(|c| c.is_ascii_graphic()) => {
                return Err(err(format!(
                    "statement `{}` starts with characters no OBJ keyword has ({}): remove them",
                    k.escape_debug(),
                    k.chars()
                        .filter(|c| !c.is_ascii_graphic())
                        .map(|c| format!("U+{:04X}", c as u32))
                        .collect::<Vec<_>>()
                        .join(" ")
                )))
            }
            k => {
                p.unknown_statements += 1;
                p.first_unknown.get_or_insert((line, k.to_string()));
            }
        }
        Ok(())
    })?;
    Ok(p)
}

/// The statements of the validation pass, each checked and recorded; an error is the message
/// for the statement's line.
impl Parsed {
    /// The lists the corners index, smoothed per `v` index (the module doc of [`soup`]).
    fn lists(&self) -> soup::Lists<'_> {
        soup::Lists {
            positions: &self.wide,
            normals: &self.normals,
            smooth_as: None,
        }
    }

    /// `v`: x y z, optionally w (tobj divides by it) or r g b (a common extension).
    fn vertex(&mut self, args: &[&str], content: &str) -> std::result::Result<(), String> {
        if args.len() < 3 {
            return Err(format!(
                "vertex needs 3 coordinates (x y z), found {}: `{}`",
                args.len(),
                content.trim()
            ));
        }
        if !matches!(args.len(), 3 | 4 | 6) {
            return Err(format!(
                "vertex has {} numbers; expected x y z, optionally followed by w or by r g b",
                args.len()
            ));
        }
        let mut xyz = [0f32; 3];
        for (k, tok) in args[..3].iter().enumerate() {
            xyz[k] = parse_coord(tok, "vertex coordinate", k + 1)?;
        }
        if args.len() == 4 {
            let w = parse_coord(args[3], "vertex coordinate", 4)?;
            if w == 0.0 {
                return Err("vertex weight w is 0, which would divide the position by zero".into());
            }
            // Same f32 arithmetic as tobj, so the cross-check compares equal values.
            for c in &mut xyz {
                *c /= w;
            }
            if xyz.iter().any(|c| !c.is_finite()) {
                return Err(format!(
                    "vertex divided by its weight w = {w} is not finite"
                ));
            }
            writeln!(
                self.tobj_text,
                "v {} {} {} {}",
                args[0], args[1], args[2], args[3]
            )
            .ok();
        } else {
            for tok in &args[3..] {
                parse_coord(tok, "vertex colour component", 1)?;
            }
            writeln!(self.tobj_text, "v {} {} {}", args[0], args[1], args[2]).ok();
        }
        self.positions.push(xyz);
        self.wide.push(dvec(xyz));
        Ok(())
    }

    /// `vn`: x y z.
    fn normal(&mut self, args: &[&str], content: &str) -> std::result::Result<(), String> {
        if args.len() != 3 {
            return Err(format!(
                "normal needs exactly 3 coordinates (x y z), found {}: `{}`",
                args.len(),
                content.trim()
            ));
        }
        let mut n = [0f32; 3];
        for (k, tok) in args.iter().enumerate() {
            n[k] = parse_coord(tok, "normal coordinate", k + 1)?;
        }
        writeln!(self.tobj_text, "vn {} {} {}", args[0], args[1], args[2]).ok();
        self.normals.push(n);
        Ok(())
    }

    /// `vt`: u [v [w]], validated and counted (for the face indices), then ignored.
    fn texcoord(&mut self, args: &[&str]) -> std::result::Result<(), String> {
        if args.is_empty() || args.len() > 3 {
            return Err(format!(
                "texture coordinate needs 1 to 3 numbers (u [v [w]]), found {}",
                args.len()
            ));
        }
        for (k, tok) in args.iter().enumerate() {
            parse_coord(tok, "texture coordinate", k + 1)?;
        }
        self.texcoord_count += 1;
        Ok(())
    }

    /// `f`: at least 3 corners, each v, v/vt, v//vn or v/vt/vn.
    fn face(&mut self, args: &[&str]) -> std::result::Result<(), String> {
        if args.len() < 3 {
            return Err(format!(
                "face has {} vertices; a face needs at least 3 (points and lines belong on `p`/`l` statements)",
                args.len()
            ));
        }
        let first = self.corners.len();
        self.tobj_text.push('f');
        for tok in args {
            let parts: Vec<&str> = tok.split('/').collect();
            if parts.len() > 3 {
                return Err(format!(
                    "face vertex `{tok}` has {} '/'-separated parts; expected v, v/vt, v//vn or v/vt/vn",
                    parts.len()
                ));
            }
            if parts[0].is_empty() {
                return Err(format!("face vertex `{tok}` has no position index"));
            }
            let position = resolve_index(parts[0], self.positions.len(), "", "vertex", "vertices")?;
            if let Some(vt) = parts.get(1).filter(|s| !s.is_empty()) {
                resolve_index(
                    vt,
                    self.texcoord_count,
                    "texture coordinate ",
                    "texture coordinate",
                    "texture coordinates",
                )?;
            }
            let normal = match parts.get(2).filter(|s| !s.is_empty()) {
                Some(vn) => Some(resolve_index(
                    vn,
                    self.normals.len(),
                    "normal ",
                    "normal",
                    "normals",
                )?),
                None => None,
            };
            // Absolute indices: tobj's relative-index handling never comes into play.
            match normal {
                Some(n) => write!(self.tobj_text, " {}//{}", position + 1, n + 1).ok(),
                None => write!(self.tobj_text, " {}", position + 1).ok(),
            };
            self.corners.push(Corner { position, normal });
        }
        self.tobj_text.push('\n');
        self.had_polygons |= args.len() > 3;
        self.faces.push(Face {
            first,
            len: args.len(),
        });
        Ok(())
    }
}
/// Runs tobj on the normalized text; tobj errors carry no line (our pass should have caught
/// everything tobj rejects, so reaching this is unexpected).
fn run_tobj(path: &Path, text: &str) -> Result<Vec<tobj::Model>> {
    // `..Default::default()` covers tobj's feature-gated fields (`merge_identical_points`,
    // `reorder_data`) should another crate in the graph enable those features.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let mut reader = text.as_bytes();
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| Error::input(path, None, format!("tobj could not load the file: {e}")))?;
    Ok(models)
}
/// Expands tobj's triangles into the soup, cross-checking them against the validation pass,
/// then drops zero-area triangles, fills in normals and fits the result ([`soup::assemble`]).
fn build_from_parsed(
    path: &Path,
    parsed: &Parsed,
    models: &[tobj::Model],
) -> Result<(Mesh, LoadReport)> {
    let tri_corners = triangle_corners(path, parsed, models)?;
    let lists = parsed.lists();
    let a = soup::assemble(path, lists, &tri_corners)?;
    let warnings = load_warnings(parsed, &a);
    let report = LoadReport {
        triangles: a.mesh.triangle_count(),
        dropped_zero_area: a.dropped,
        computed_normals: a.counts.computed > 0,
        had_quads_or_polygons: parsed.had_polygons,
        warnings,
        input: MeshInput::whole(Format::Obj, Encoding::Text),
    };
    Ok((a.mesh, report))
}

/// The source corners of every triangle tobj made, in file order, after checking that tobj's
/// triangles are the validation pass's: tobj triangulates each face as a fan (0, k+1, k+2) and
/// keeps faces in file order; models follow each other in file order.
fn triangle_corners(
    path: &Path,
    parsed: &Parsed,
    models: &[tobj::Model],
) -> Result<Vec<[Corner; 3]>> {
    let expected: usize = parsed.faces.iter().map(|f| f.len - 2).sum();
    let got: usize = models.iter().map(|m| m.mesh.indices.len() / 3).sum();
    let mismatch = |what: String| {
        Error::input(
            path,
            None,
            format!("internal error: tobj and the validation pass disagree ({what}); please report this file"),
        )
    };
    if got != expected {
        return Err(mismatch(format!(
            "{got} triangles from tobj, {expected} expected"
        )));
    }

    let mut tri_corners: Vec<[Corner; 3]> = Vec::with_capacity(expected);
    for f in &parsed.faces {
        let c = &parsed.corners[f.first..f.first + f.len];
        for k in 0..f.len - 2 {
            tri_corners.push([c[0], c[k + 1], c[k + 2]]);
        }
    }
    let mut t = 0usize;
    for m in models {
        let mesh = &m.mesh;
        for (k, &local) in mesh.indices.iter().enumerate() {
            let corner = tri_corners[t + k / 3][k % 3];
            let l = local as usize * 3;
            let tp = mesh
                .positions
                .get(l..l + 3)
                .ok_or_else(|| mismatch("position index out of range".into()))?;
            if tp != parsed.positions[corner.position] {
                return Err(mismatch(format!("position of triangle {}", t + k / 3 + 1)));
            }
            if let Some(n) = corner.normal {
                let ni = *mesh
                    .normal_indices
                    .get(k)
                    .ok_or_else(|| mismatch("missing normal index".into()))?
                    as usize
                    * 3;
                let tn = mesh
                    .normals
                    .get(ni..ni + 3)
                    .ok_or_else(|| mismatch("normal index out of range".into()))?;
                if tn != parsed.normals[n] {
                    return Err(mismatch(format!("normal of triangle {}", t + k / 3 + 1)));
                }
            }
        }
        t += mesh.indices.len() / 3;
    }
    Ok(tri_corners)
}

/// The load report's notes: the common ones ([`soup::common_notes`]), ignored elements, and
/// positions written under more than one index.
fn load_warnings(parsed: &Parsed, a: &soup::Assembled) -> Vec<String> {
    let lists = parsed.lists();
    let mut warnings = soup::common_notes(a.dropped, &a.counts);
    if parsed.skipped_elements > 0 {
        warnings.push(format!(
            "ignored {}: only faces are drawn",
            plural(
                parsed.skipped_elements,
                "point/line element (`p`/`l`)",
                "point/line elements (`p`/`l`)"
            )
        ));
    }
    if let Some((line, k)) = &parsed.first_unknown {
        warnings.push(format!(
            "ignored {} with a keyword OBJ does not have (the first `{k}` at line {line})",
            plural(parsed.unknown_statements, "statement", "statements")
        ));
    }
    // Smoothing follows the file's position indices, as the format's topology says; a position
    // written twice (the Utah teapot's patch seams) therefore splits the shading there.
    let mut first_index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut repeated: HashMap<[u32; 3], ()> = HashMap::new();
    for c in a.kept.iter().flatten().filter(|c| lacks_normal(lists, c)) {
        let key = parsed.positions[c.position].map(f32::to_bits);
        if *first_index.entry(key).or_insert(c.position) != c.position {
            repeated.insert(key, ());
        }
    }
    if !repeated.is_empty() {
        warnings.push(format!(
            "computed normals are smoothed per vertex index, so the shading splits at {} defined under more than one index (weld the mesh to smooth across them)",
            plural(repeated.len(), "position", "positions")
        ));
    }
    warnings
}
/// The OBJ text for `mesh`: `header` as `#` comment lines, then `v` and `vn` lists and
/// `f v//vn` faces. Positions and normals are deduplicated separately by exact bit pattern (so
/// identical (position, normal) pairs share both entries and the file stays small), in order of
/// first use. Floats use Rust's shortest round-trip formatting, so loading the text gives back
/// exactly the same f32 values. Deterministic: the same mesh gives the same text.
pub fn obj_text(mesh: &Mesh, header: &str) -> String {
    fn key(a: [f32; 3]) -> [u32; 3] {
        a.map(f32::to_bits)
    }
    let mut out = String::new();
    for line in header.lines() {
        if line.is_empty() {
            out.push_str("#\n");
        } else {
            writeln!(out, "# {line}").ok();
        }
    }
    let mut pos_ids: HashMap<[u32; 3], usize> = HashMap::new();
    let mut nrm_ids: HashMap<[u32; 3], usize> = HashMap::new();
    let mut pos_list = Vec::new();
    let mut nrm_list = Vec::new();
    let mut corners = Vec::with_capacity(mesh.positions.len());
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let pi = *pos_ids.entry(key(*p)).or_insert_with(|| {
            pos_list.push(*p);
            pos_list.len()
        });
        let ni = *nrm_ids.entry(key(*n)).or_insert_with(|| {
            nrm_list.push(*n);
            nrm_list.len()
        });
        corners.push((pi, ni));
    }
    for p in &pos_list {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).ok();
    }
    for n in &nrm_list {
        writeln!(out, "vn {} {} {}", n[0], n[1], n[2]).ok();
    }
    for tri in corners.chunks_exact(3) {
        writeln!(
            out,
            "f {}//{} {}//{} {}//{}",
            tri[0].0, tri[0].1, tri[1].0, tri[1].1, tri[2].0, tri[2].1
        )
        .ok();
    }
    out
}
/// The header [`write_obj`] puts on a file: names the generator (the mesh's `source`).
pub(crate) fn default_header(mesh: &Mesh) -> String {
    format!(
        "written by shadelab from: {}\n{} triangles; regenerate shipped meshes with `make scenes`",
        mesh.source,
        mesh.triangle_count()
    )
}
/// Writes `mesh` as OBJ ([`obj_text`] with a header naming its source) through
/// [`write_atomic`], so an interrupted write never leaves a truncated file.
pub fn write_obj(mesh: &Mesh, path: &Path) -> Result<()> {
    let text = obj_text(mesh, &default_header(mesh));
    write_atomic(path, |w| w.write_all(text.as_bytes()))
}

// ---------------------------------------------------------------------------------------------
// Procedural generators
// ---------------------------------------------------------------------------------------------
