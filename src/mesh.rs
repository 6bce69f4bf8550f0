//! Triangle meshes: OBJ loading (validated, then parsed by `tobj`), vertex normals, fitting to
//! the unit sphere, procedural generators, and OBJ writing.
//!
//! Owns [`Mesh`], the unindexed triangle soup every renderer path consumes.
//!
//! Invariants of a [`Mesh`] produced here:
//! - `positions.len() == normals.len()` and both are a multiple of 3 (3 corners per triangle);
//! - every normal is finite and unit length (to f32 precision, |n| - 1 < 1e-6);
//! - every triangle has non-zero area by the test in [`is_zero_area`] (OBJ loading drops the
//!   others and counts them in [`LoadReport::dropped_zero_area`]);
//! - computed and generated normals agree with the winding (counter-clockwise seen from the
//!   side they point to); normals given in a file are kept as the file has them;
//! - a mesh returned by [`load_obj`] is fitted by [`fit_unit`] (bounding box centred at the
//!   origin, bounding sphere radius 1); a mesh returned by [`Generator::build`] is not.
//!
//! OBJ loading is two passes over the text. Our own pass validates every statement and reports
//! problems as `file:line` errors (tobj reports neither file nor line). It also writes a
//! normalized copy of the geometry statements that tobj then parses and triangulates: that copy
//! has trailing comments, `l`/`p` elements, texture coordinates, vertex colours and groups
//! removed, because tobj rejects trailing comments and mixed vertex colours, turns an `l` with
//! 3+ points into a triangle, and fills a corner without a normal index with the previous
//! corner's normal. Our pass remembers which corners really had a normal; the two passes are
//! cross-checked corner by corner so a disagreement is an error, never a silently wrong mesh.
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::{Error, Result};
use crate::output::write_atomic;

/// Triangle soup ready for upload: 3 corners per triangle, unindexed, so per-triangle data can
/// ride on vertices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Model-space corner positions; after [`fit_unit`] inside the unit sphere.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normal per corner: given in the file, or computed smooth (angle-weighted).
    pub normals: Vec<[f32; 3]>,
    /// File path or generator description, for messages.
    pub source: String,
}

impl Mesh {
    /// Number of triangles (`positions.len() / 3`).
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }

    /// Axis-aligned bounds `(min, max)` over all positions. An empty mesh gives
    /// `([0.0; 3], [0.0; 3])`.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        if self.positions.is_empty() {
            return ([0.0; 3], [0.0; 3]);
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }
}

/// What [`load_obj`] did to the file's faces, for the user and for tests.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LoadReport {
    /// Triangles in the resulting mesh (after dropping zero-area ones).
    pub triangles: usize,
    /// Triangles dropped because they have zero area (see [`is_zero_area`]).
    pub dropped_zero_area: usize,
    /// True when at least one corner's normal was computed rather than taken from the file.
    pub computed_normals: bool,
    /// True when some face had more than 3 vertices and was triangulated (as a fan).
    pub had_quads_or_polygons: bool,
    /// Human-readable notes, e.g. "dropped 3 zero-area triangles".
    pub warnings: Vec<String>,
}

/// A triangle counts as zero-area when `|cross(p1 - p0, p2 - p0)| <= 1e-12 * L^2`, with `L` its
/// longest edge, computed in f64. Geometrically: its height over the longest edge is at most
/// 1e-12 * L. Positions are f32 (relative precision 6e-8), so this catches exactly collinear or
/// coincident corners (whose cross product in f64 is rounding noise, ~1e-16 * L^2) while every
/// sliver with a real, representable area is kept. A triangle with all corners equal (L = 0)
/// is zero-area.
pub fn is_zero_area(p0: DVec3, p1: DVec3, p2: DVec3) -> bool {
    let cross = (p1 - p0).cross(p2 - p0).length();
    let longest2 = (p1 - p0)
        .length_squared()
        .max((p2 - p1).length_squared())
        .max((p0 - p2).length_squared());
    cross <= 1e-12 * longest2
}

// ---------------------------------------------------------------------------------------------
// OBJ loading
// ---------------------------------------------------------------------------------------------

/// One face corner as the validation pass saw it (0-based, relative indices resolved).
#[derive(Debug, Clone, Copy)]
struct Corner {
    position: usize,
    normal: Option<usize>,
}

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
    normals: Vec<[f32; 3]>,
    texcoord_count: usize,
    faces: Vec<Face>,
    corners: Vec<Corner>,
    had_polygons: bool,
    skipped_elements: usize,
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
///
/// Errors: a missing or unreadable file is [`Error::Io`]; malformed statements, indices out of
/// range (positive, zero or relative), non-finite coordinates and faces with fewer than 3
/// vertices are [`Error::Input`] with the 1-based line; a file that leaves no triangles is
/// [`Error::Input`] without a line.
pub fn load_obj(path: &Path) -> Result<(Mesh, LoadReport)> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    // Lossy: a stray Latin-1 byte in a comment must not reject the file; in a number it turns
    // into U+FFFD and fails number parsing with the line reported.
    let text = String::from_utf8_lossy(&bytes);
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

/// The validation pass: checks every statement, collects positions, normals and faces, and
/// writes the normalized copy for tobj. Errors carry the 1-based line.
fn validate_obj(path: &Path, text: &str) -> Result<Parsed> {
    let mut p = Parsed {
        tobj_text: String::with_capacity(text.len()),
        ..Parsed::default()
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |msg: String| Error::input(path, Some(line), msg);
        // OBJ comments run from '#' to the end of the line; tobj only knows whole-line ones.
        let content = raw.split_once('#').map_or(raw, |(c, _)| c);
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                // x y z, optionally w (tobj divides by it) or r g b (a common extension).
                if args.len() < 3 {
                    return Err(err(format!(
                        "vertex needs 3 coordinates (x y z), found {}: `{}`",
                        args.len(),
                        content.trim()
                    )));
                }
                if !matches!(args.len(), 3 | 4 | 6) {
                    return Err(err(format!(
                        "vertex has {} numbers; expected x y z, optionally followed by w or by r g b",
                        args.len()
                    )));
                }
                let mut xyz = [0f32; 3];
                for (k, tok) in args[..3].iter().enumerate() {
                    xyz[k] = parse_coord(tok, "vertex coordinate", k + 1).map_err(&err)?;
                }
                if args.len() == 4 {
                    let w = parse_coord(args[3], "vertex coordinate", 4).map_err(&err)?;
                    if w == 0.0 {
                        return Err(err(
                            "vertex weight w is 0, which would divide the position by zero".into(),
                        ));
                    }
                    // Same f32 arithmetic as tobj, so the cross-check compares equal values.
                    for c in &mut xyz {
                        *c /= w;
                    }
                    if xyz.iter().any(|c| !c.is_finite()) {
                        return Err(err(format!(
                            "vertex divided by its weight w = {w} is not finite"
                        )));
                    }
                    writeln!(
                        p.tobj_text,
                        "v {} {} {} {}",
                        args[0], args[1], args[2], args[3]
                    )
                    .ok();
                } else {
                    for tok in &args[3..] {
                        parse_coord(tok, "vertex colour component", 1).map_err(&err)?;
                    }
                    writeln!(p.tobj_text, "v {} {} {}", args[0], args[1], args[2]).ok();
                }
                p.positions.push(xyz);
            }
            "vn" => {
                if args.len() != 3 {
                    return Err(err(format!(
                        "normal needs exactly 3 coordinates (x y z), found {}: `{}`",
                        args.len(),
                        content.trim()
                    )));
                }
                let mut n = [0f32; 3];
                for (k, tok) in args.iter().enumerate() {
                    n[k] = parse_coord(tok, "normal coordinate", k + 1).map_err(&err)?;
                }
                writeln!(p.tobj_text, "vn {} {} {}", args[0], args[1], args[2]).ok();
                p.normals.push(n);
            }
            "vt" => {
                if args.is_empty() || args.len() > 3 {
                    return Err(err(format!(
                        "texture coordinate needs 1 to 3 numbers (u [v [w]]), found {}",
                        args.len()
                    )));
                }
                for (k, tok) in args.iter().enumerate() {
                    parse_coord(tok, "texture coordinate", k + 1).map_err(&err)?;
                }
                p.texcoord_count += 1;
            }
            "f" => {
                if args.len() < 3 {
                    return Err(err(format!(
                        "face has {} vertices; a face needs at least 3 (points and lines belong on `p`/`l` statements)",
                        args.len()
                    )));
                }
                let first = p.corners.len();
                p.tobj_text.push('f');
                for tok in &args {
                    let parts: Vec<&str> = tok.split('/').collect();
                    if parts.len() > 3 {
                        return Err(err(format!(
                            "face vertex `{tok}` has {} '/'-separated parts; expected v, v/vt, v//vn or v/vt/vn",
                            parts.len()
                        )));
                    }
                    if parts[0].is_empty() {
                        return Err(err(format!("face vertex `{tok}` has no position index")));
                    }
                    let position =
                        resolve_index(parts[0], p.positions.len(), "", "vertex", "vertices")
                            .map_err(&err)?;
                    if let Some(vt) = parts.get(1).filter(|s| !s.is_empty()) {
                        resolve_index(
                            vt,
                            p.texcoord_count,
                            "texture coordinate ",
                            "texture coordinate",
                            "texture coordinates",
                        )
                        .map_err(&err)?;
                    }
                    let normal = match parts.get(2).filter(|s| !s.is_empty()) {
                        Some(vn) => Some(
                            resolve_index(vn, p.normals.len(), "normal ", "normal", "normals")
                                .map_err(&err)?,
                        ),
                        None => None,
                    };
                    // Absolute indices: tobj's relative-index handling never comes into play.
                    match normal {
                        Some(n) => write!(p.tobj_text, " {}//{}", position + 1, n + 1).ok(),
                        None => write!(p.tobj_text, " {}", position + 1).ok(),
                    };
                    p.corners.push(Corner { position, normal });
                }
                p.tobj_text.push('\n');
                p.had_polygons |= args.len() > 3;
                p.faces.push(Face {
                    first,
                    len: args.len(),
                });
            }
            "l" | "p" => p.skipped_elements += 1,
            // Groups, objects, smoothing groups, materials, free-form geometry: not ours to draw.
            _ => {}
        }
    }
    Ok(p)
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

fn dvec(a: [f32; 3]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Expands tobj's triangles into the soup, cross-checking them against the validation pass,
/// drops zero-area triangles, fills in normals and fits the result.
fn build_from_parsed(
    path: &Path,
    parsed: &Parsed,
    models: &[tobj::Model],
) -> Result<(Mesh, LoadReport)> {
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

    // Source corners of every triangle, in file order: tobj triangulates each face as a fan
    // (0, k+1, k+2) and keeps faces in file order; models follow each other in file order.
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

    // Drop zero-area triangles.
    let mut kept: Vec<[Corner; 3]> = Vec::with_capacity(tri_corners.len());
    for tri in &tri_corners {
        let [a, b, c] = tri.map(|k| dvec(parsed.positions[k.position]));
        if !is_zero_area(a, b, c) {
            kept.push(*tri);
        }
    }
    let dropped = tri_corners.len() - kept.len();
    if kept.is_empty() {
        return Err(Error::input(
            path,
            None,
            format!(
                "no triangles: all {} of the file's triangles have zero area",
                tri_corners.len()
            ),
        ));
    }

    // Given normals, normalized; zero-length ones count as missing.
    let mut zero_given = 0usize;
    let mut given_count = 0usize;
    let given = |c: &Corner, zero_given: &mut usize| -> Option<DVec3> {
        let n = dvec(parsed.normals[c.normal?]);
        let len = n.length();
        if len > 0.0 {
            Some(n / len)
        } else {
            *zero_given += 1;
            None
        }
    };

    // Smooth normals, accumulated per position index, only if some corner needs one.
    let lacks_normal = |c: &Corner| c.normal.is_none_or(|n| parsed.normals[n] == [0.0; 3]);
    let needs_smooth = kept.iter().flatten().any(lacks_normal);
    let mut acc = Vec::new();
    let mut weight = Vec::new();
    if needs_smooth {
        acc = vec![DVec3::ZERO; parsed.positions.len()];
        weight = vec![0f64; parsed.positions.len()];
        for tri in &kept {
            let p = tri.map(|k| dvec(parsed.positions[k.position]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            for j in 0..3 {
                let e1 = p[(j + 1) % 3] - p[j];
                let e2 = p[(j + 2) % 3] - p[j];
                // atan2 stays accurate for angles near 0 and pi, where acos of a dot does not.
                let angle = e1.cross(e2).length().atan2(e1.dot(e2));
                acc[tri[j].position] += n * angle;
                weight[tri[j].position] += angle;
            }
        }
    }

    let mut positions = Vec::with_capacity(kept.len() * 3);
    let mut normals = Vec::with_capacity(kept.len() * 3);
    let mut computed = 0usize;
    let mut cancelled = 0usize;
    for tri in &kept {
        let p = tri.map(|k| dvec(parsed.positions[k.position]));
        for c in tri {
            positions.push(parsed.positions[c.position]);
            let n = match given(c, &mut zero_given) {
                Some(n) => {
                    given_count += 1;
                    n
                }
                None => {
                    computed += 1;
                    let s = acc[c.position];
                    let len = s.length();
                    // Cancellation: neighbouring faces point in (nearly) opposite directions, so
                    // their sum has no meaningful direction. The threshold is relative to the
                    // total corner angle, so small but consistent fans are unaffected.
                    if len > 1e-6 * weight[c.position] && len > 0.0 {
                        s / len
                    } else {
                        cancelled += 1;
                        (p[1] - p[0]).cross(p[2] - p[0]).normalize()
                    }
                }
            };
            normals.push(n.as_vec3().to_array());
        }
    }

    let mut warnings = Vec::new();
    if dropped > 0 {
        warnings.push(format!(
            "dropped {} (height below 1e-12 x longest edge)",
            plural(dropped, "zero-area triangle", "zero-area triangles")
        ));
    }
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
    if zero_given > 0 {
        warnings.push(format!(
            "{} had a zero-length normal in the file; computed smooth normals for them instead",
            plural(zero_given, "face corner", "face corners")
        ));
    }
    if computed > 0 && given_count > 0 {
        warnings.push(format!(
            "{computed} of {} face corners had no usable normal in the file; computed smooth normals for them",
            computed + given_count
        ));
    }
    // Smoothing follows the file's position indices, as the format's topology says; a position
    // written twice (the Utah teapot's patch seams) therefore splits the shading there.
    let mut first_index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut repeated: HashMap<[u32; 3], ()> = HashMap::new();
    for c in kept.iter().flatten().filter(|c| lacks_normal(c)) {
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
    if cancelled > 0 {
        warnings.push(format!(
            "{}: the neighbouring face normals cancel out (two-sided or folded surface), used the face normal",
            plural(cancelled, "face corner", "face corners")
        ));
    }

    let mut mesh = Mesh {
        positions,
        normals,
        source: path.display().to_string(),
    };
    fit_unit(&mut mesh);
    let report = LoadReport {
        triangles: kept.len(),
        dropped_zero_area: dropped,
        computed_normals: computed > 0,
        had_quads_or_polygons: parsed.had_polygons,
        warnings,
    };
    Ok((mesh, report))
}

/// Centres the bounding box at the origin and scales uniformly so the bounding sphere (the
/// largest distance from the centre over all positions) has radius 1. Computed in f64, stored
/// as f32, so the radius is 1 to f32 rounding (about 6e-8). Normals are unchanged (a uniform
/// scale and a translation do not rotate them).
///
/// An empty mesh is left alone; a mesh whose positions all coincide (radius 0) is only moved
/// to the origin, since no scale makes a point into a unit sphere.
pub fn fit_unit(mesh: &mut Mesh) {
    if mesh.positions.is_empty() {
        return;
    }
    let (lo, hi) = mesh.bounds();
    let centre = (dvec(lo) + dvec(hi)) * 0.5;
    let radius = mesh
        .positions
        .iter()
        .map(|&p| (dvec(p) - centre).length())
        .fold(0.0, f64::max);
    let scale = if radius > 0.0 && radius.is_finite() {
        1.0 / radius
    } else {
        1.0
    };
    for p in &mut mesh.positions {
        *p = ((dvec(*p) - centre) * scale).as_vec3().to_array();
    }
}

// ---------------------------------------------------------------------------------------------
// OBJ writing
// ---------------------------------------------------------------------------------------------

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
fn default_header(mesh: &Mesh) -> String {
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

/// Largest triangle count a generator may produce: 8M triangles are 576 MB of f32 soup, well
/// past any useful test mesh (the biggest shared model, the bunny, has 70k).
pub const MAX_GENERATED_TRIANGLES: u64 = 8_000_000;

/// A procedural mesh, built in f64 with exact analytic normals. Serialized (TOML scene files,
/// [`parse_generator_args`]) as `generator = "snake_case_name"` plus the variant's fields.
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(tag = "generator", rename_all = "snake_case", deny_unknown_fields)]
pub enum Generator {
    /// Unit sphere, poles on ±y. `segments` (>= 3) around, `rings` (>= 2) latitude bands; the
    /// pole bands are triangle fans. Normals = positions. `2 * segments * (rings - 1)`
    /// triangles.
    UvSphere { segments: u32, rings: u32 },
    /// Subdivided icosahedron on the unit sphere; `subdivisions` 0..=7 (0 = the icosahedron,
    /// whose neighbouring vertex normals are 63.4 deg apart). Normals = positions.
    /// `20 * 4^subdivisions` triangles.
    Icosphere { subdivisions: u32 },
    /// Torus around the y axis: tube centre circle of `major_radius`, tube of `minor_radius`
    /// (0 < minor < major), `major_segments` x `minor_segments` (each >= 3) quads.
    Torus {
        major_radius: f64,
        minor_radius: f64,
        major_segments: u32,
        minor_segments: u32,
    },
    /// Cube with corners at ±1: 8 shared corners, 12 triangles, each corner normal the
    /// normalized average of its 3 face normals, normalize(±1, ±1, ±1), so the normals of a
    /// face's corners span 70.5-109.5 deg (the "creased solid").
    Cube {},
}

/// The meshes shipped in `scenes/`: (file name, generator). Regenerated by `make scenes`
/// (`SHADELAB_BLESS=1` on the freshness test) and checked by the test `shipped_meshes_are_fresh`.
pub const SHIPPED: &[(&str, Generator)] = &[
    // ~16k triangles: fine enough that interpolated normals barely leave the sphere.
    (
        "sphere_fine.obj",
        Generator::UvSphere {
            segments: 128,
            rings: 64,
        },
    ),
    // 36 deg between neighbouring vertex normals (360/10 around, 180/5 along meridians): the
    // range where cheap normalization methods start to show.
    (
        "sphere_coarse.obj",
        Generator::UvSphere {
            segments: 10,
            rings: 5,
        },
    ),
    (
        "torus.obj",
        Generator::Torus {
            major_radius: 1.0,
            minor_radius: 0.4,
            major_segments: 48,
            minor_segments: 24,
        },
    ),
    ("icosphere.obj", Generator::Icosphere { subdivisions: 0 }),
    ("cube.obj", Generator::Cube {}),
];

/// One line per generator with its CLI keys, for usage errors.
const GENERATOR_USAGE: &str = "uv_sphere segments=INT rings=INT | icosphere subdivisions=INT | \
     torus major_radius=FLOAT minor_radius=FLOAT major_segments=INT minor_segments=INT | cube";

/// Snaps rounding noise of sin/cos at multiples of pi/2 (e.g. cos(pi/2) = 6e-17) to 0, so
/// symmetric meshes are exactly symmetric and the OBJ text has no 20-digit near-zeros.
fn snap(v: DVec3) -> [f32; 3] {
    v.to_array()
        .map(|x| if x.abs() < 1e-12 { 0.0 } else { x as f32 })
}

/// Indexed mesh under construction (f64), expanded to the soup at the end.
#[derive(Default)]
struct Indexed {
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    triangles: Vec<[usize; 3]>,
}

impl Indexed {
    fn vertex(&mut self, p: DVec3, n: DVec3) -> usize {
        self.positions.push(p);
        self.normals.push(n.normalize());
        self.positions.len() - 1
    }

    fn into_mesh(self, source: String) -> Mesh {
        let mut mesh = Mesh {
            source,
            ..Mesh::default()
        };
        for t in &self.triangles {
            for &i in t {
                mesh.positions.push(snap(self.positions[i]));
                mesh.normals.push(snap(self.normals[i]));
            }
        }
        mesh
    }
}

impl Generator {
    /// The CLI/TOML name of the variant (`uv_sphere`, `icosphere`, `torus`, `cube`).
    pub fn name(&self) -> &'static str {
        match self {
            Generator::UvSphere { .. } => "uv_sphere",
            Generator::Icosphere { .. } => "icosphere",
            Generator::Torus { .. } => "torus",
            Generator::Cube {} => "cube",
        }
    }

    /// `name key=value ...`, exactly the arguments [`parse_generator_args`] takes back.
    pub fn describe(&self) -> String {
        match self {
            Generator::UvSphere { segments, rings } => format!("uv_sphere segments={segments} rings={rings}"),
            Generator::Icosphere { subdivisions } => format!("icosphere subdivisions={subdivisions}"),
            Generator::Torus { major_radius, minor_radius, major_segments, minor_segments } => format!(
                "torus major_radius={major_radius} minor_radius={minor_radius} major_segments={major_segments} minor_segments={minor_segments}"
            ),
            Generator::Cube {} => "cube".to_string(),
        }
    }

    /// Number of triangles [`Generator::build`] makes (u64: parameters can overflow usize math).
    pub fn triangle_count(&self) -> u64 {
        match *self {
            Generator::UvSphere { segments, rings } => {
                2 * segments as u64 * (rings as u64).saturating_sub(1)
            }
            Generator::Icosphere { subdivisions } => {
                20u64.saturating_mul(4u64.saturating_pow(subdivisions))
            }
            Generator::Torus {
                major_segments,
                minor_segments,
                ..
            } => 2 * major_segments as u64 * minor_segments as u64,
            Generator::Cube {} => 12,
        }
    }

    /// Checks the parameters; on failure returns the offending key and the rule it breaks.
    pub(crate) fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        let name = self.name();
        match *self {
            Generator::UvSphere { segments, rings } => {
                if segments < 3 {
                    return Err((
                        "segments",
                        format!("{name}: segments must be >= 3 (got {segments})"),
                    ));
                }
                if rings < 2 {
                    return Err(("rings", format!("{name}: rings must be >= 2 (got {rings})")));
                }
            }
            Generator::Icosphere { subdivisions } => {
                if subdivisions > 7 {
                    return Err((
                        "subdivisions",
                        format!("{name}: subdivisions must be <= 7 (got {subdivisions}; 7 already makes 327680 triangles)"),
                    ));
                }
            }
            Generator::Torus {
                major_radius,
                minor_radius,
                major_segments,
                minor_segments,
            } => {
                if !(major_radius.is_finite() && major_radius > 0.0) {
                    return Err((
                        "major_radius",
                        format!("{name}: major_radius must be finite and > 0 (got {major_radius})"),
                    ));
                }
                if !(minor_radius.is_finite() && minor_radius > 0.0) {
                    return Err((
                        "minor_radius",
                        format!("{name}: minor_radius must be finite and > 0 (got {minor_radius})"),
                    ));
                }
                if minor_radius >= major_radius {
                    return Err((
                        "minor_radius",
                        format!(
                            "{name}: minor_radius must be < major_radius (got {minor_radius} >= {major_radius}); a self-intersecting torus has no outward side"
                        ),
                    ));
                }
                if major_segments < 3 {
                    return Err((
                        "major_segments",
                        format!("{name}: major_segments must be >= 3 (got {major_segments})"),
                    ));
                }
                if minor_segments < 3 {
                    return Err((
                        "minor_segments",
                        format!("{name}: minor_segments must be >= 3 (got {minor_segments})"),
                    ));
                }
            }
            Generator::Cube {} => {}
        }
        let n = self.triangle_count();
        if n > MAX_GENERATED_TRIANGLES {
            return Err((
                "generator",
                format!(
                    "{}: would make {n} triangles; the limit is {MAX_GENERATED_TRIANGLES}",
                    self.describe()
                ),
            ));
        }
        Ok(())
    }

    /// Checks the parameters: segments >= 3, rings >= 2, radii finite and > 0, minor < major,
    /// subdivisions <= 7, at most [`MAX_GENERATED_TRIANGLES`]. Violations are
    /// [`Error::Usage`] naming the rule and the value found.
    pub fn validate(&self) -> Result<()> {
        self.check().map_err(|(_, msg)| Error::Usage(msg))
    }

    /// Builds the mesh (not fitted: a unit sphere has radius 1 already, a torus has its outer
    /// radius `major + minor`, the cube its corners at ±1). `source` is `generator <describe>`.
    /// Fails with [`Error::Usage`] when [`Generator::validate`] does.
    pub fn build(&self) -> Result<Mesh> {
        self.validate()?;
        let mut m = Indexed::default();
        match *self {
            Generator::UvSphere { segments, rings } => {
                uv_sphere(&mut m, segments as usize, rings as usize)
            }
            Generator::Icosphere { subdivisions } => icosphere(&mut m, subdivisions),
            Generator::Torus {
                major_radius,
                minor_radius,
                major_segments,
                minor_segments,
            } => torus(
                &mut m,
                major_radius,
                minor_radius,
                major_segments as usize,
                minor_segments as usize,
            ),
            Generator::Cube {} => cube(&mut m),
        }
        Ok(m.into_mesh(format!("generator {}", self.describe())))
    }
}

/// UV sphere: p(theta, phi) = (sin t sin p, cos t, sin t cos p), theta from the north pole.
/// d/dtheta x d/dphi points outward, so (A, A + dtheta, A + dphi) is counter-clockwise seen
/// from outside.
fn uv_sphere(m: &mut Indexed, segments: usize, rings: usize) {
    use std::f64::consts::PI;
    let at = |theta: f64, phi: f64| {
        DVec3::new(
            theta.sin() * phi.sin(),
            theta.cos(),
            theta.sin() * phi.cos(),
        )
    };
    let north = m.vertex(DVec3::Y, DVec3::Y);
    let mut grid = Vec::with_capacity(rings - 1);
    for i in 1..rings {
        let theta = PI * i as f64 / rings as f64;
        let row: Vec<usize> = (0..segments)
            .map(|j| {
                let p = at(theta, 2.0 * PI * j as f64 / segments as f64);
                m.vertex(p, p)
            })
            .collect();
        grid.push(row);
    }
    let south = m.vertex(-DVec3::Y, -DVec3::Y);
    for j in 0..segments {
        let j1 = (j + 1) % segments;
        m.triangles.push([north, grid[0][j], grid[0][j1]]);
        for i in 0..rings - 2 {
            let (a, b, c, d) = (grid[i][j], grid[i + 1][j], grid[i][j1], grid[i + 1][j1]);
            m.triangles.push([a, b, c]);
            m.triangles.push([c, b, d]);
        }
        m.triangles
            .push([grid[rings - 2][j], south, grid[rings - 2][j1]]);
    }
}

/// Icosphere: the icosahedron (vertices (0, ±1, ±phi) and cyclic permutations) with each
/// triangle split into 4 per subdivision, new vertices pushed onto the unit sphere. Midpoints
/// are shared through an edge map, so neighbouring triangles get bit-identical corners.
fn icosphere(m: &mut Indexed, subdivisions: u32) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let base = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ];
    for (x, y, z) in base {
        let p = DVec3::new(x, y, z).normalize();
        m.vertex(p, p);
    }
    let mut tris: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    // Orient every face outward (the icosahedron is convex and centred, so outward = the face
    // normal agrees with the centroid direction); a typo in the table cannot flip a face.
    for tri in &mut tris {
        let [a, b, c] = tri.map(|i| m.positions[i]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            tri.swap(1, 2);
        }
    }
    for _ in 0..subdivisions {
        let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let mut midpoint = |i: usize, j: usize| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    let p = (m.positions[i] + m.positions[j]).normalize();
                    m.vertex(p, p)
                })
            };
            let (ab, bc, ca) = (midpoint(a, b), midpoint(b, c), midpoint(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    m.triangles = tris;
}

/// Torus around y: p(u, v) = ((R + r cos v) sin u, r sin v, (R + r cos v) cos u), normal
/// (cos v sin u, sin v, cos v cos u). d/du x d/dv points out of the tube (for r < R), so
/// (A, A + du, A + dv) is counter-clockwise seen from outside.
fn torus(m: &mut Indexed, major: f64, minor: f64, nu: usize, nv: usize) {
    use std::f64::consts::TAU;
    let mut grid = vec![vec![0usize; nv]; nu];
    for (i, row) in grid.iter_mut().enumerate() {
        let u = TAU * i as f64 / nu as f64;
        for (j, slot) in row.iter_mut().enumerate() {
            let v = TAU * j as f64 / nv as f64;
            let n = DVec3::new(v.cos() * u.sin(), v.sin(), v.cos() * u.cos());
            let centre = DVec3::new(major * u.sin(), 0.0, major * u.cos());
            *slot = m.vertex(centre + minor * n, n);
        }
    }
    for i in 0..nu {
        let i1 = (i + 1) % nu;
        for j in 0..nv {
            let j1 = (j + 1) % nv;
            let (a, b, c, d) = (grid[i][j], grid[i1][j], grid[i][j1], grid[i1][j1]);
            m.triangles.push([a, b, c]);
            m.triangles.push([b, d, c]);
        }
    }
}

/// Cube with corners at ±1, one shared vertex per corner, normal normalize(corner).
fn cube(m: &mut Indexed) {
    let mut corner = [0usize; 8];
    for (k, slot) in corner.iter_mut().enumerate() {
        let p = DVec3::new(
            if k & 1 != 0 { 1.0 } else { -1.0 },
            if k & 2 != 0 { 1.0 } else { -1.0 },
            if k & 4 != 0 { 1.0 } else { -1.0 },
        );
        *slot = m.vertex(p, p);
    }
    // Each face as a loop of 4 corners (bit patterns of the corner index), then oriented so its
    // winding normal points along the face's outward axis.
    let faces: [[usize; 4]; 6] = [
        [0b000, 0b010, 0b110, 0b100], // -x
        [0b001, 0b011, 0b111, 0b101], // +x
        [0b000, 0b001, 0b101, 0b100], // -y
        [0b010, 0b011, 0b111, 0b110], // +y
        [0b000, 0b001, 0b011, 0b010], // -z
        [0b100, 0b101, 0b111, 0b110], // +z
    ];
    for mut f in faces {
        let [a, b, c, d] = f.map(|k| m.positions[corner[k]]);
        let centre = (a + b + c + d) * 0.25;
        if (b - a).cross(c - a).dot(centre) < 0.0 {
            f.reverse();
        }
        let [a, b, c, d] = f.map(|k| corner[k]);
        m.triangles.push([a, b, c]);
        m.triangles.push([a, c, d]);
    }
}

/// Builds a [`Generator`] from a CLI name (`uv_sphere`, `icosphere`, `torus`, `cube`) and
/// `key=value` arguments; every key of the variant is required. Values are integers or floats
/// (an integer is accepted for a float key). The result is validated.
///
/// Errors are [`Error::Usage`]: an unknown name or key, a missing key, a malformed argument or
/// value, or a parameter out of range; each lists the valid generators and keys.
pub fn parse_generator_args(name: &str, kv: &[String]) -> Result<Generator> {
    use serde::Deserialize as _;
    let usage = |msg: String| Error::Usage(format!("{msg}\nvalid generators: {GENERATOR_USAGE}"));
    let mut table = toml::Table::new();
    table.insert("generator".into(), toml::Value::String(name.to_string()));
    for arg in kv {
        let Some((k, v)) = arg.split_once('=') else {
            return Err(usage(format!(
                "generator argument `{arg}` is not of the form key=value"
            )));
        };
        let (k, v) = (k.trim(), v.trim());
        if k == "generator" {
            return Err(usage(format!(
                "`{arg}`: give the generator as the name ({name}), not as a key"
            )));
        }
        let value = if let Ok(i) = v.parse::<i64>() {
            toml::Value::Integer(i)
        } else if let Ok(f) = v.parse::<f64>() {
            toml::Value::Float(f)
        } else {
            return Err(usage(format!(
                "generator argument `{arg}`: `{v}` is not a number"
            )));
        };
        if table.insert(k.to_string(), value).is_some() {
            return Err(usage(format!("generator argument `{k}` is given twice")));
        }
    }
    let g = Generator::deserialize(toml::Value::Table(table))
        .map_err(|e| usage(format!("generator `{name}`: {}", e.message())))?;
    g.validate().map_err(|e| usage(e.to_string()))?;
    Ok(g)
}

/// Builds every [`SHIPPED`] mesh and writes it to `dir/NAME` with [`write_obj`]; returns the
/// paths written, in [`SHIPPED`] order.
pub fn write_shipped(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(SHIPPED.len());
    for (name, generator) in SHIPPED {
        let path = dir.join(name);
        write_obj(&generator.build()?, &path)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::assert_close;
    use std::collections::BTreeMap;

    /// Writes `text` to `name` in a fresh temp dir, keeping the dir alive with the path.
    fn temp_obj(name: &str, text: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().expect("create temp dir");
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("write temp OBJ");
        (dir, path)
    }

    fn load_text(text: &str) -> Result<(Mesh, LoadReport)> {
        let (_dir, path) = temp_obj("t.obj", text);
        load_obj(&path)
    }

    /// Asserts `r` is an input error at `line` whose message contains `needle`.
    #[track_caller]
    fn assert_input_err<T: std::fmt::Debug>(r: Result<T>, line: Option<usize>, needle: &str) {
        match r {
            Err(Error::Input {
                line: l, message, ..
            }) => {
                assert_eq!(
                    l, line,
                    "line of error `{message}`: left = actual, right = expected"
                );
                assert!(
                    message.contains(needle),
                    "message `{message}` does not contain `{needle}`"
                );
            }
            other => panic!(
                "expected an input error at line {line:?} containing `{needle}`, got {other:?}"
            ),
        }
    }

    const UNIT_CUBE: &str = "\
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
";

    #[test]
    fn quads_and_polygons_are_triangulated_as_fans() {
        let (mesh, report) =
            load_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4\nf 1 4 5\n")
                .unwrap();
        assert_eq!(report.triangles, 3, "a quad and a triangle");
        assert!(report.had_quads_or_polygons);
        let (m5, r5) =
            load_text("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n").unwrap();
        assert_eq!(r5.triangles, 3, "a pentagon is 3 fan triangles");
        assert!(r5.had_quads_or_polygons);
        let (_, r3) = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert!(
            !r3.had_quads_or_polygons,
            "a lone triangle needs no triangulation"
        );
        // Fan from the first corner: every triangle of the pentagon starts at vertex 1, which
        // after fitting is the same point in all three.
        let first: Vec<[f32; 3]> = m5.positions.chunks(3).map(|t| t[0]).collect();
        assert!(
            first.iter().all(|p| *p == first[0]),
            "fan corners: {first:?}"
        );
        assert_eq!(mesh.triangle_count(), 3);
    }

    #[test]
    fn missing_normals_are_computed_angle_weighted_per_position() {
        let (mesh, report) = load_text(UNIT_CUBE).unwrap();
        assert!(report.computed_normals);
        assert_eq!(report.triangles, 12);
        // Each cube corner sees 90 deg of each of its 3 faces, however the quads were split,
        // so the angle-weighted normal is exactly the diagonal direction.
        let inv = 1.0 / 3f64.sqrt();
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            for k in 0..3 {
                let expected = p[k].signum() as f64 * inv;
                assert_close(
                    &format!("normal {n:?} at corner {p:?}, axis {k}"),
                    n[k] as f64,
                    expected,
                    1e-6,
                );
            }
        }
    }

    #[test]
    fn texcoord_seams_do_not_split_computed_normals() {
        // Same position 1 used with two different texture coordinates: still one normal.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 1/2 3/3 4/1\n";
        let (mesh, _) = load_text(text).unwrap();
        let origin = mesh.positions[0];
        let normals: Vec<[f32; 3]> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .filter(|(p, _)| **p == origin)
            .map(|(_, n)| *n)
            .collect();
        assert_eq!(normals.len(), 2);
        assert_eq!(
            normals[0], normals[1],
            "both corners at the shared position share one normal"
        );
    }

    #[test]
    fn repeated_positions_are_not_welded_and_say_so() {
        // Vertices 1 and 5 coincide: two fans meeting there keep separate normals.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 0 0\nf 1 2 3\nf 5 4 2\n";
        let (mesh, report) = load_text(text).unwrap();
        assert_ne!(
            mesh.normals[0], mesh.normals[3],
            "per-index smoothing: the two copies differ"
        );
        assert!(
            report
                .warnings
                .iter()
                .any(|w| w.contains("splits at 1 position defined under more than one index")),
            "{:?}",
            report.warnings
        );
    }

    #[test]
    fn given_normals_are_kept_split_and_normalized() {
        // Two triangles sharing an edge, each with its own (non-unit) flat normal: a crease.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 -2\nvn -3 0 0\nf 1//1 3//1 2//1\nf 1//2 4//2 3//2\n";
        let (mesh, report) = load_text(text).unwrap();
        assert!(
            !report.computed_normals,
            "every corner had a normal: {report:?}"
        );
        assert_eq!(
            &mesh.normals[..3],
            &[[0.0, 0.0, -1.0]; 3],
            "first triangle keeps its normal, normalized"
        );
        assert_eq!(
            &mesh.normals[3..],
            &[[-1.0, 0.0, 0.0]; 3],
            "second triangle keeps its split normal"
        );
    }

    #[test]
    fn mixed_files_compute_normals_only_where_missing() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1 0\nvn 0 0 0\nf 1//1 2 3//2\n";
        let (mesh, report) = load_text(text).unwrap();
        assert!(report.computed_normals);
        assert_eq!(mesh.normals[0], [0.0, 1.0, 0.0], "given normal kept");
        assert_eq!(
            mesh.normals[1],
            [0.0, 0.0, 1.0],
            "missing normal computed from the face"
        );
        assert_eq!(
            mesh.normals[2],
            [0.0, 0.0, 1.0],
            "zero-length normal treated as missing"
        );
        assert!(
            report.warnings.iter().any(|w| w.contains("zero-length")),
            "{:?}",
            report.warnings
        );
        assert!(
            report
                .warnings
                .iter()
                .any(|w| w.contains("2 of 3 face corners")),
            "{:?}",
            report.warnings
        );
    }

    #[test]
    fn relative_indices_comments_and_ignored_statements_load() {
        let text = "# header\nmtllib x.mtl\no thing\nv 0 0 0 # trailing comment\nv 1 0 0\nv 0 1 0\nv 0 0 1 1.0\ng part\nusemtl red\ns 1\nf -3 -2 -1\nl 1 2 3\np 1\nf 1 3 4\n";
        let (_, report) = load_text(text).unwrap();
        assert_eq!(report.triangles, 2);
        assert!(
            report
                .warnings
                .iter()
                .any(|w| w.contains("ignored 2 point/line elements")),
            "{:?}",
            report.warnings
        );
    }

    #[test]
    fn crlf_latin1_comments_and_vertex_colours_load() {
        // Windows line endings, a Latin-1 byte in a comment, colours on some vertices only
        // (tobj alone rejects the last), a 1-component texture coordinate.
        let mut bytes = b"# caf".to_vec();
        bytes.push(0xe9);
        bytes.extend_from_slice(
            b"\r\nv 0 0 0 1 0 0\r\nv 1 0 0\r\nv 0 1 0 0 1 0\r\nvt 0.5\r\nf 1/1 2/1 3/1\r\n",
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("w.obj");
        std::fs::write(&path, &bytes).unwrap();
        let (mesh, report) = load_obj(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(report.triangles, 1);
        assert_eq!(mesh.normals[0], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn vertex_weight_divides_the_position() {
        let (mesh, _) = load_text("v 0 0 0\nv 2 0 0 2\nv 0 4 0 2\nf 1 2 3\n").unwrap();
        // (0,0,0), (1,0,0), (0,2,0): bbox centre (0.5, 1, 0), radius |(0.5, 1)| = sqrt(1.25).
        let r = 1.25f64.sqrt();
        assert_close(
            "x of the weighted vertex",
            mesh.positions[1][0] as f64,
            0.5 / r,
            1e-6,
        );
        assert_close(
            "y of the weighted vertex",
            mesh.positions[2][1] as f64,
            1.0 / r,
            1e-6,
        );
    }

    #[test]
    fn malformed_files_report_file_and_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("v 1 2\n", 1, "vertex needs 3 coordinates (x y z), found 2"),
            ("v 0 0 0\nv 1 x 0\n", 2, "vertex coordinate 2 is `x`, which is not a number"),
            ("v nan 0 0\n", 1, "vertex coordinate 1 is `nan`, which is not a finite number"),
            ("v 0 0 inf\n", 1, "not a finite number"),
            ("v 1e39 0 0\n", 1, "beyond the f32 range"),
            ("v 0 0 0 0\n", 1, "weight w is 0"),
            ("v 0 0 0 1 1\n", 1, "vertex has 5 numbers"),
            ("\n\nvn 0 0\n", 3, "normal needs exactly 3 coordinates (x y z), found 2"),
            ("vn 0 0 NaN\n", 1, "not a finite number"),
            ("vt a b\n", 1, "texture coordinate 1 is `a`, which is not a number"),
            ("vt\n", 1, "texture coordinate needs 1 to 3 numbers"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "face index 4 is past the 3 vertices defined so far"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "face index 0 is invalid: OBJ indices start at 1"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -1 -2\n",
                4,
                "relative face index -4 points before the first vertex: only 3 vertices are defined so far",
            ),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//5 3//1\n", 5, "face normal index 5 is past the 1 normals defined so far"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-2 2//1 3//1\n", 5, "relative face normal index -2"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", 5, "face texture coordinate index 2 is past the 1 texture coordinates"),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "face has 2 vertices; a face needs at least 3"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", 4, "has 4 '/'-separated parts"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 a 3\n", 4, "face index `a` is not an integer"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n", 4, "has no position index"),
            // Forward references: the vertex is defined, but only after the face.
            ("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", 3, "face index 3 is past the 2 vertices defined so far"),
        ];
        for (text, line, needle) in cases {
            let (_dir, path) = temp_obj("bad.obj", text);
            let r = load_obj(&path);
            if let Err(e) = &r {
                assert!(
                    e.to_string()
                        .starts_with(&format!("{}:{line}: ", path.display())),
                    "display of {text:?}: {e}"
                );
            }
            assert_input_err(r, Some(*line), needle);
        }
    }

    #[test]
    fn empty_and_missing_files_are_errors() {
        assert_input_err(
            load_text("# nothing\nv 0 0 0\n"),
            None,
            "no triangles: the file has no faces",
        );
        assert_input_err(load_text(""), None, "no triangles");
        assert_input_err(
            load_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n"),
            None,
            "no triangles: all 2 of the file's triangles have zero area",
        );
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("nope.obj");
        match load_obj(&missing) {
            Err(e @ Error::Io { .. }) => {
                let s = e.to_string();
                assert!(
                    s.contains("nope.obj") && s.contains("No such file or directory"),
                    "message: {s}"
                );
            }
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

    #[test]
    fn zero_area_triangles_are_dropped_and_counted() {
        let text = "\
v 0 0 0
v 1 0 0
v 0 1 0
v 2 0 0
v 1e-7 1 0
f 1 2 3
f 1 2 4
f 1 1 3
f 2 2 2
f 1 3 5
";
        // f 1 2 4: collinear; f 1 1 3: two corners equal; f 2 2 2: a point; f 1 3 5: a sliver
        // whose height (1e-7) is far above 1e-12 x its longest edge, so it is kept.
        let (mesh, report) = load_text(text).unwrap();
        assert_eq!(report.dropped_zero_area, 3, "{report:?}");
        assert_eq!(report.triangles, 2);
        assert_eq!(mesh.triangle_count(), 2);
        assert!(
            report
                .warnings
                .iter()
                .any(|w| w.starts_with("dropped 3 zero-area triangles")),
            "{:?}",
            report.warnings
        );
        assert!(is_zero_area(DVec3::ZERO, DVec3::X, DVec3::X * 2.0));
        assert!(
            !is_zero_area(DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-9, 0.0)),
            "a 1e-9 sliver is real"
        );
        assert!(is_zero_area(DVec3::ONE, DVec3::ONE, DVec3::ONE));
    }

    #[test]
    fn fit_unit_centres_and_scales_to_radius_one() {
        let mut mesh = Mesh {
            positions: vec![[10.0, 20.0, 30.0], [14.0, 20.0, 30.0], [10.0, 23.0, 30.0]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            source: "test".into(),
        };
        fit_unit(&mut mesh);
        let (lo, hi) = mesh.bounds();
        for k in 0..3 {
            assert_close(
                &format!("bbox centre axis {k}"),
                (lo[k] + hi[k]) as f64,
                0.0,
                1e-6,
            );
        }
        let r = mesh
            .positions
            .iter()
            .map(|&p| dvec(p).length())
            .fold(0.0, f64::max);
        assert_close("bounding sphere radius", r, 1.0, 1e-6);
        // Single point: moved to the origin, not scaled to infinity.
        let mut point = Mesh {
            positions: vec![[3.0, 3.0, 3.0]; 3],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            source: String::new(),
        };
        fit_unit(&mut point);
        assert_eq!(point.positions, vec![[0.0; 3]; 3]);
        let mut empty = Mesh::default();
        fit_unit(&mut empty);
        assert_eq!(empty.bounds(), ([0.0; 3], [0.0; 3]));
    }

    /// Test generators: the shipped ones plus other parameters.
    fn all_generators() -> Vec<Generator> {
        let mut g: Vec<Generator> = SHIPPED.iter().map(|(_, g)| g.clone()).collect();
        g.extend([
            Generator::UvSphere {
                segments: 3,
                rings: 2,
            },
            Generator::Icosphere { subdivisions: 2 },
            Generator::Torus {
                major_radius: 2.0,
                minor_radius: 1.9,
                major_segments: 3,
                minor_segments: 5,
            },
        ]);
        g
    }

    /// The point each corner's normal should point away from.
    fn inner_point(g: &Generator, p: DVec3) -> DVec3 {
        match *g {
            Generator::Torus { major_radius, .. } => {
                DVec3::new(p.x, 0.0, p.z).normalize() * major_radius
            }
            _ => DVec3::ZERO,
        }
    }

    #[test]
    fn generator_normals_are_unit_outward_and_agree_with_the_winding() {
        for g in all_generators() {
            let mesh = g.build().unwrap();
            assert_eq!(
                mesh.triangle_count() as u64,
                g.triangle_count(),
                "{}",
                g.describe()
            );
            assert_eq!(mesh.positions.len(), mesh.normals.len());
            for (t, (ps, ns)) in mesh
                .positions
                .chunks(3)
                .zip(mesh.normals.chunks(3))
                .enumerate()
            {
                let p = [dvec(ps[0]), dvec(ps[1]), dvec(ps[2])];
                let winding = (p[1] - p[0]).cross(p[2] - p[0]);
                assert!(
                    !is_zero_area(p[0], p[1], p[2]),
                    "{}: triangle {t} has zero area",
                    g.describe()
                );
                for k in 0..3 {
                    let n = dvec(ns[k]);
                    assert_close(
                        &format!("{}: |normal| at triangle {t}", g.describe()),
                        n.length(),
                        1.0,
                        1e-6,
                    );
                    let out = n.dot(p[k] - inner_point(&g, p[k]));
                    assert!(
                        out > 0.0,
                        "{}: triangle {t} corner {k} normal {n} points inward ({out})",
                        g.describe()
                    );
                    let agree = winding.normalize().dot(n);
                    assert!(
                        agree > 0.0,
                        "{}: triangle {t} is wound clockwise seen from outside (dot {agree})",
                        g.describe()
                    );
                }
            }
        }
    }

    #[test]
    fn sphere_normals_equal_positions() {
        for g in [
            Generator::UvSphere {
                segments: 10,
                rings: 5,
            },
            Generator::Icosphere { subdivisions: 1 },
        ] {
            let mesh = g.build().unwrap();
            for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
                assert_close(
                    &format!("{}: normal {n:?} vs position {p:?}", g.describe()),
                    (dvec(*p) - dvec(*n)).length(),
                    0.0,
                    1e-7,
                );
            }
        }
    }

    /// Angle (deg) between the normals at the two ends of every distinct edge.
    fn edge_angles(mesh: &Mesh) -> Vec<(DVec3, DVec3, f64)> {
        type Key = ([u32; 3], [u32; 3]);
        let mut edges: BTreeMap<Key, (DVec3, DVec3, f64)> = BTreeMap::new();
        for (ps, ns) in mesh.positions.chunks(3).zip(mesh.normals.chunks(3)) {
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                let (a, b) = (ps[i].map(f32::to_bits), ps[j].map(f32::to_bits));
                let key = (a.min(b), a.max(b));
                let angle = dvec(ns[i]).angle_between(dvec(ns[j])).to_degrees();
                edges.insert(key, (dvec(ps[i]), dvec(ps[j]), angle));
            }
        }
        edges.into_values().collect()
    }

    fn shipped(name: &str) -> Mesh {
        let g = &SHIPPED.iter().find(|(n, _)| *n == name).unwrap().1;
        g.build().unwrap()
    }

    #[test]
    fn shipped_meshes_have_the_stated_normal_spreads() {
        // Coarse sphere: grid neighbours along a meridian are 180/5 = 36 deg apart; along a
        // parallel, 36 deg of longitude is 34.2 deg of normal angle at the rings next to the
        // equator. Both must lie in the 30-45 deg band the scene is meant to exercise.
        let coarse = edge_angles(&shipped("sphere_coarse.obj"));
        let azimuth = |p: DVec3| p.x.atan2(p.z);
        let meridian: Vec<f64> = coarse
            .iter()
            .filter(|(a, b, _)| {
                a.y.abs() > 0.9999 || b.y.abs() > 0.9999 || (azimuth(*a) - azimuth(*b)).abs() < 1e-6
            })
            .map(|e| e.2)
            .collect();
        let parallel: Vec<f64> = coarse
            .iter()
            .filter(|(a, b, _)| (a.y - b.y).abs() < 1e-6)
            .map(|e| e.2)
            .collect();
        assert_eq!(meridian.len(), 50, "10 segments x 5 rings meridian edges");
        for a in &meridian {
            assert_close("coarse sphere meridian neighbour angle", *a, 36.0, 1e-3);
        }
        let widest_parallel = parallel.iter().copied().fold(0.0, f64::max);
        assert!(
            (30.0..=45.0).contains(&widest_parallel),
            "coarse sphere parallel neighbour angle {widest_parallel}"
        );

        let fine = edge_angles(&shipped("sphere_fine.obj"));
        let widest = fine.iter().map(|e| e.2).fold(0.0, f64::max);
        assert!(
            widest < 4.0,
            "fine sphere: widest neighbour angle {widest} deg"
        );

        // Icosahedron: every edge joins normals 63.43 deg apart (acos(1/sqrt 5)).
        let ico = edge_angles(&shipped("icosphere.obj"));
        assert_eq!(ico.len(), 30);
        for (_, _, a) in &ico {
            assert!(*a > 60.0, "icosahedron neighbour angle {a}");
            assert_close(
                "icosahedron neighbour angle",
                *a,
                (1.0 / 5f64.sqrt()).acos().to_degrees(),
                1e-4,
            );
        }

        // Cube: corners joined by a cube edge are acos(1/3) = 70.53 deg apart; the face
        // diagonals (split lines of the quads) acos(-1/3) = 109.47 deg.
        let cube = edge_angles(&shipped("cube.obj"));
        let along: Vec<f64> = cube
            .iter()
            .filter(|(a, b, _)| ((*a - *b).length() - 2.0).abs() < 1e-9)
            .map(|e| e.2)
            .collect();
        assert_eq!(along.len(), 12, "12 cube edges");
        for a in &along {
            assert_close(
                "cube adjacent-corner angle",
                *a,
                (1.0f64 / 3.0).acos().to_degrees(),
                1e-4,
            );
        }
        for (a, b, ang) in cube
            .iter()
            .filter(|(a, b, _)| ((*a - *b).length() - 2.0).abs() >= 1e-9)
        {
            assert_close(
                &format!("cube diagonal {a} - {b}"),
                *ang,
                (-1.0f64 / 3.0).acos().to_degrees(),
                1e-4,
            );
        }
    }

    #[test]
    fn obj_text_round_trips_through_the_loader() {
        for g in all_generators() {
            let built = g.build().unwrap();
            let text = obj_text(&built, "round trip\n\nsecond line");
            assert_eq!(
                text,
                obj_text(&built, "round trip\n\nsecond line"),
                "deterministic"
            );
            assert!(
                text.starts_with("# round trip\n#\n# second line\n"),
                "header: {}",
                &text[..60.min(text.len())]
            );
            let (loaded, report) = load_text(&text).unwrap();
            assert!(
                !report.computed_normals && report.dropped_zero_area == 0,
                "{}: {report:?}",
                g.describe()
            );
            let mut fitted = built.clone();
            fit_unit(&mut fitted);
            assert_eq!(loaded.triangle_count(), fitted.triangle_count());
            for (i, ((pa, pb), (na, nb))) in loaded
                .positions
                .iter()
                .zip(&fitted.positions)
                .zip(loaded.normals.iter().zip(&fitted.normals))
                .enumerate()
            {
                assert_close(
                    &format!("{}: position {i}", g.describe()),
                    (dvec(*pa) - dvec(*pb)).length(),
                    0.0,
                    1e-6,
                );
                assert_close(
                    &format!("{}: normal {i}", g.describe()),
                    (dvec(*na) - dvec(*nb)).length(),
                    0.0,
                    1e-6,
                );
            }
        }
    }

    #[test]
    fn obj_text_deduplicates_vertices() {
        let cube = Generator::Cube {}.build().unwrap();
        let text = obj_text(&cube, "");
        let count = |kw: &str| {
            text.lines()
                .filter(|l| l.split_whitespace().next() == Some(kw))
                .count()
        };
        assert_eq!(
            (count("v"), count("vn"), count("f")),
            (8, 8, 12),
            "cube text:\n{text}"
        );
    }

    #[test]
    fn write_obj_writes_a_loadable_file_with_a_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/ico.obj");
        let mesh = Generator::Icosphere { subdivisions: 1 }.build().unwrap();
        write_obj(&mesh, &path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with("# written by shadelab from: generator icosphere subdivisions=1\n"),
            "{}",
            &text[..80]
        );
        let (loaded, _) = load_obj(&path).unwrap();
        assert_eq!(loaded.triangle_count(), 80);
    }

    #[test]
    fn generator_parameters_are_validated() {
        let cases = [
            (
                Generator::UvSphere {
                    segments: 2,
                    rings: 4,
                },
                "segments must be >= 3 (got 2)",
            ),
            (
                Generator::UvSphere {
                    segments: 3,
                    rings: 1,
                },
                "rings must be >= 2 (got 1)",
            ),
            (
                Generator::Icosphere { subdivisions: 8 },
                "subdivisions must be <= 7 (got 8",
            ),
            (
                Generator::Torus {
                    major_radius: 1.0,
                    minor_radius: 0.0,
                    major_segments: 3,
                    minor_segments: 3,
                },
                "minor_radius must be finite and > 0",
            ),
            (
                Generator::Torus {
                    major_radius: f64::NAN,
                    minor_radius: 0.1,
                    major_segments: 3,
                    minor_segments: 3,
                },
                "major_radius must be finite and > 0",
            ),
            (
                Generator::Torus {
                    major_radius: 1.0,
                    minor_radius: 1.0,
                    major_segments: 3,
                    minor_segments: 3,
                },
                "minor_radius must be < major_radius",
            ),
            (
                Generator::Torus {
                    major_radius: 1.0,
                    minor_radius: 0.5,
                    major_segments: 2,
                    minor_segments: 3,
                },
                "major_segments must be >= 3",
            ),
            (
                Generator::Torus {
                    major_radius: 1.0,
                    minor_radius: 0.5,
                    major_segments: 3,
                    minor_segments: 2,
                },
                "minor_segments must be >= 3",
            ),
            (
                Generator::UvSphere {
                    segments: 100_000,
                    rings: 100_000,
                },
                "the limit is 8000000",
            ),
        ];
        for (g, needle) in cases {
            match g.build() {
                Err(Error::Usage(msg)) => assert!(
                    msg.contains(needle),
                    "{g:?}: message `{msg}` lacks `{needle}`"
                ),
                other => {
                    panic!("{g:?}: expected a usage error containing `{needle}`, got {other:?}")
                }
            }
        }
    }

    #[test]
    fn generator_args_parse_and_round_trip_through_describe() {
        for g in all_generators() {
            let desc = g.describe();
            let mut words = desc.split_whitespace();
            let name = words.next().unwrap();
            let kv: Vec<String> = words.map(str::to_string).collect();
            assert_eq!(parse_generator_args(name, &kv).unwrap(), g, "from `{desc}`");
        }
        let torus = parse_generator_args(
            "torus",
            &[
                "major_radius=2".into(),
                "minor_radius=0.5".into(),
                "major_segments=8".into(),
                "minor_segments=6".into(),
            ],
        )
        .unwrap();
        assert_eq!(
            torus,
            Generator::Torus {
                major_radius: 2.0,
                minor_radius: 0.5,
                major_segments: 8,
                minor_segments: 6
            }
        );
    }

    #[test]
    fn generator_arg_errors_list_the_valid_choices() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let cases: Vec<(&str, Vec<String>, &str)> = vec![
            ("sphere", vec![], "unknown variant `sphere`, expected one of `uv_sphere`, `icosphere`, `torus`, `cube`"),
            ("uv_sphere", s(&["segments=8", "rigns=4"]), "unknown field `rigns`, expected `segments` or `rings`"),
            ("uv_sphere", s(&["segments=8"]), "missing field `rings`"),
            ("uv_sphere", s(&["segments=8", "rings"]), "`rings` is not of the form key=value"),
            ("uv_sphere", s(&["segments=8", "rings=x"]), "`x` is not a number"),
            ("uv_sphere", s(&["segments=8", "rings=4.5"]), "invalid type: floating point `4.5`, expected u32"),
            ("uv_sphere", s(&["segments=8", "rings=-4"]), "rings"),
            ("uv_sphere", s(&["segments=8", "segments=9"]), "given twice"),
            ("uv_sphere", s(&["segments=2", "rings=4"]), "segments must be >= 3"),
            ("cube", s(&["size=2"]), "unknown field `size`"),
        ];
        for (name, kv, needle) in cases {
            match parse_generator_args(name, &kv) {
                Err(Error::Usage(msg)) => {
                    assert!(
                        msg.contains(needle),
                        "{name} {kv:?}: `{msg}` lacks `{needle}`"
                    );
                    assert!(
                        msg.contains("valid generators: uv_sphere segments=INT rings=INT"),
                        "{name} {kv:?}: `{msg}`"
                    );
                }
                other => panic!(
                    "{name} {kv:?}: expected a usage error containing `{needle}`, got {other:?}"
                ),
            }
        }
    }

    /// `SHADELAB_MODELS` (unless empty: the Makefile exports it empty when there are no
    /// models), else `../shared/models` beside the crate; `None` with a message when the folder
    /// is absent, so the caller skips (same rule as `tests/support.rs`).
    fn models_dir() -> Option<PathBuf> {
        let dir = match std::env::var_os("SHADELAB_MODELS") {
            Some(d) if !d.is_empty() => PathBuf::from(d),
            _ => Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/models"),
        };
        if dir.is_dir() {
            Some(dir)
        } else {
            eprintln!(
                "skipping shared_models_load: no models folder at {} (set SHADELAB_MODELS)",
                dir.display()
            );
            None
        }
    }

    #[test]
    fn shared_models_load() {
        let Some(dir) = models_dir() else { return };
        // (file, triangles from the README, normals computed?, needed triangulation?)
        let models = [
            ("spot.obj", 5856, true, false),
            ("teapot.obj", 6320, true, false),
            ("fandisk.obj", 12946, true, false),
            ("stanford-bunny.obj", 69451, true, false),
            // 500 faces of which 468 quads: 32 + 2 * 468 triangles.
            ("suzanne.obj", 968, false, true),
        ];
        for (name, triangles, computed, polygons) in models {
            let path = dir.join(name);
            let (mesh, report) = load_obj(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(
                report.triangles + report.dropped_zero_area,
                triangles,
                "{name}: {report:?}"
            );
            // A real model loses at most a few degenerate triangles, never a visible part.
            assert!(
                report.dropped_zero_area * 100 <= triangles,
                "{name}: dropped {} of {triangles}",
                report.dropped_zero_area
            );
            assert_eq!(mesh.triangle_count(), report.triangles, "{name}");
            assert_eq!(
                report.computed_normals, computed,
                "{name}: computed normals"
            );
            assert_eq!(
                report.had_quads_or_polygons, polygons,
                "{name}: triangulated"
            );
            for (i, n) in mesh.normals.iter().enumerate() {
                assert!(
                    n.iter().all(|c| c.is_finite()),
                    "{name}: normal {i} = {n:?}"
                );
                assert_close(
                    &format!("{name}: |normal {i}|"),
                    dvec(*n).length(),
                    1.0,
                    1e-6,
                );
            }
            let r = mesh
                .positions
                .iter()
                .map(|&p| dvec(p).length())
                .fold(0.0, f64::max);
            assert_close(&format!("{name}: fitted radius"), r, 1.0, 1e-6);
            eprintln!(
                "{name}: {} triangles, {} dropped, warnings {:?}",
                report.triangles, report.dropped_zero_area, report.warnings
            );
        }
    }

    /// Checks `scenes/*.obj` against the generators; `SHADELAB_BLESS=1` rewrites them instead
    /// (that is what `make scenes` runs). A missing file is stale, never an automatic pass.
    #[test]
    fn shipped_meshes_are_fresh() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        if std::env::var("SHADELAB_BLESS").as_deref() == Ok("1") {
            let written = write_shipped(&dir).unwrap();
            eprintln!("SHADELAB_BLESS=1: wrote {written:?}");
            return;
        }
        for (name, g) in SHIPPED {
            let mesh = g.build().unwrap();
            let expected = obj_text(&mesh, &default_header(&mesh));
            let actual = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
            assert!(
                actual == expected,
                "scenes/{name} is stale: run `make scenes`"
            );
        }
    }
}
