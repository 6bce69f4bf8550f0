//! The PLY reader (ASCII, binary little and big endian; Turk's PLY description), on ply-rs-bw
//! for the header grammar and the elements' encodings.
//!
//! Read: the `vertex` element's `x y z` and, when all three are there, `nx ny nz`; the `face`
//! element's `vertex_indices` (or `vertex_index`) lists, triangulated as fans like the OBJ
//! reader's polygons; the `tristrips` element's `vertex_indices` lists (as range-scanner tools
//! write them: strips separated by -1), triangle i of a strip `s` being (s[i], s[i+1], s[i+2])
//! for even i and (s[i+1], s[i], s[i+2]) for odd i, so that all keep the winding of the first
//! (the order of OpenGL's triangle strips); a strip's triangles that repeat a vertex (the joins
//! of strips written as one) draw nothing and are left out. Index lists must hold integers.
//! Every other element and property is skipped, with a note. A file without normals gets smooth
//! normals as an OBJ without normals does ([`super::soup`]), smoothed across vertices at the
//! same position, and the report says so. A UTF-8 byte-order mark before `ply` is skipped.
//!
//! Elements are read one at a time, so an error names the element, its index and, in ASCII,
//! the file's line. Before any element is read, each count the header declares is checked
//! against what is left of the file (a line per ASCII element, the smallest encoding per
//! binary one): a header that lies is refused before it can size anything.
use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{
    ElementDef, Encoding as PlyEncoding, Header, Property, PropertyAccess, PropertyType, ScalarType,
};

use super::mesh_file::{Encoding, Format, MeshInput};
use super::soup::{self, plural, Corner};
use super::{LoadReport, Mesh};
use crate::error::{Error, Result};

/// One element as the parser hands it over: the properties this reader uses.
#[derive(Debug, Default)]
struct Item {
    /// x, y, z, nx, ny, nz; NaN where absent.
    values: [f64; 6],
    /// `vertex_indices` / `vertex_index`.
    list: Option<Vec<i64>>,
}

impl PropertyAccess for Item {
    fn new() -> Self {
        Item {
            values: [f64::NAN; 6],
            list: None,
        }
    }

    fn set_property(&mut self, name: &str, p: Property) {
        let slot = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "nx" => 3,
            "ny" => 4,
            "nz" => 5,
            "vertex_indices" | "vertex_index" => {
                self.list = list(p);
                return;
            }
            _ => return,
        };
        if let Some(v) = scalar(p) {
            self.values[slot] = v;
        }
    }
}

fn scalar(p: Property) -> Option<f64> {
    Some(match p {
        Property::Char(v) => v.into(),
        Property::UChar(v) => v.into(),
        Property::Short(v) => v.into(),
        Property::UShort(v) => v.into(),
        Property::Int(v) => v.into(),
        Property::UInt(v) => v.into(),
        Property::Float(v) => v.into(),
        Property::Double(v) => v,
        _ => return None,
    })
}

fn list(p: Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
        _ => return None,
    })
}

/// Bytes of one binary scalar.
fn size(t: &ScalarType) -> usize {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The fewest bytes one binary element of `def` takes (every list empty).
fn min_binary_size(def: &ElementDef) -> usize {
    def.properties
        .values()
        .map(|p| match &p.data_type {
            PropertyType::Scalar(t) => size(t),
            PropertyType::List(count, _) => size(count),
        })
        .sum()
}

/// Where the reader is in the file, for messages.
struct Cursor<'b> {
    rest: &'b [u8],
    /// 1-based line of the next ASCII line.
    line: usize,
}

/// Reads a PLY file (module doc).
pub fn parse_ply(path: &Path, bytes: &[u8]) -> Result<(Mesh, LoadReport)> {
    let err = |line: Option<usize>, msg: String| Error::input(path, line, msg);
    let parser = Parser::<Item>::new();
    // A byte-order mark is no part of the magic `ply` line (editors on Windows write one).
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut rest = bytes;
    let header = parser.read_header(&mut rest).map_err(|e| {
        err(
            None,
            format!("not a PLY header: {}", one_line(&e.to_string())),
        )
    })?;
    let header_lines = bytes[..bytes.len() - rest.len()]
        .iter()
        .filter(|&&b| b == b'\n')
        .count();
    check_counts(&header, rest).map_err(|m| err(None, m))?;
    check_index_lists(&header).map_err(|m| err(None, m))?;
    let mut cur = Cursor {
        rest,
        line: header_lines + 1,
    };
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut faces: Vec<Vec<i64>> = Vec::new();
    let mut strips: Vec<Vec<i64>> = Vec::new();
    let mut skipped = Vec::new();
    let has_normals = header.elements.get("vertex").is_some_and(|v| {
        ["nx", "ny", "nz"]
            .iter()
            .all(|n| v.properties.contains_key(*n))
    });
    for (name, def) in &header.elements {
        let wanted = matches!(name.as_str(), "vertex" | "face" | "tristrips");
        if !wanted && def.count > 0 {
            skipped.push(format!("{name} ({})", def.count));
        }
        for i in 0..def.count {
            let line = cur.line;
            let item = read_element(&parser, &header, def, &mut cur).map_err(|m| {
                let at = (header.encoding == PlyEncoding::Ascii).then_some(line);
                err(at, format!("{name} element {i}: {m}"))
            })?;
            let at = || (header.encoding == PlyEncoding::Ascii).then_some(line);
            match name.as_str() {
                "vertex" => {
                    let (p, n) = vertex(&item, has_normals)
                        .map_err(|m| err(at(), format!("vertex element {i}: {m}")))?;
                    positions.push(p);
                    normals.extend(n);
                }
                "face" | "tristrips" => {
                    // check_index_lists made sure every element of these has its list.
                    let list = item.list.ok_or_else(|| {
                        err(
                            at(),
                            format!("{name} element {i} has no vertex_indices list"),
                        )
                    })?;
                    if name == "face" {
                        faces.push(list);
                    } else {
                        strips.push(list);
                    }
                }
                _ => {}
            }
        }
    }
    build(path, &header, positions, normals, (faces, strips), skipped)
}

/// The elements whose `vertex_indices` (or `vertex_index`) lists are read.
const INDEXED: [&str; 2] = ["face", "tristrips"];

/// Refuses a `face` or `tristrips` element without an integer index list: a missing one, a
/// scalar, or a list of float or double (which ply-rs would read, and which no index is).
fn check_index_lists(header: &Header) -> std::result::Result<(), String> {
    for name in INDEXED {
        let Some(def) = header.elements.get(name) else {
            continue;
        };
        let prop = ["vertex_indices", "vertex_index"]
            .iter()
            .find_map(|p| def.properties.get(*p).map(|d| (*p, d)));
        let Some((prop, d)) = prop else {
            if def.count == 0 {
                continue;
            }
            return Err(format!(
                "the `{name}` element has no `vertex_indices` (or `vertex_index`) property: write each {name}'s vertices as `property list uchar int vertex_indices`"
            ));
        };
        let fix = "vertex indices must be a list of integers (e.g. `property list uchar int vertex_indices`)";
        match &d.data_type {
            PropertyType::List(_, t @ (ScalarType::Float | ScalarType::Double)) => {
                return Err(format!(
                    "the `{name}` element's `{prop}` is a list of {}: {fix}",
                    type_name(t)
                ))
            }
            PropertyType::Scalar(t) => {
                return Err(format!(
                    "the `{name}` element's `{prop}` is a single {}, not a list: {fix}",
                    type_name(t)
                ))
            }
            PropertyType::List(..) => {}
        }
    }
    Ok(())
}

/// A scalar type as the PLY header spells it.
fn type_name(t: &ScalarType) -> &'static str {
    match t {
        ScalarType::Char => "char",
        ScalarType::UChar => "uchar",
        ScalarType::Short => "short",
        ScalarType::UShort => "ushort",
        ScalarType::Int => "int",
        ScalarType::UInt => "uint",
        ScalarType::Float => "float",
        ScalarType::Double => "double",
    }
}

/// Refuses element counts the rest of the file cannot hold (module doc).
fn check_counts(header: &Header, rest: &[u8]) -> std::result::Result<(), String> {
    let Some(vertex) = header.elements.get("vertex") else {
        return Err("the header declares no `vertex` element: no positions".into());
    };
    for p in ["x", "y", "z"] {
        if !vertex.properties.contains_key(p) {
            return Err(format!(
                "the `vertex` element has no `{p}` property: positions need x, y and z"
            ));
        }
    }
    let mut need: u128 = 0;
    let available = match header.encoding {
        PlyEncoding::Ascii => rest
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .count(),
        _ => rest.len(),
    };
    for (name, def) in &header.elements {
        let each = match header.encoding {
            PlyEncoding::Ascii => 1,
            _ => min_binary_size(def),
        };
        if def.count > 0 && def.properties.is_empty() {
            return Err(format!(
                "element `{name}` declares {} elements but no properties",
                def.count
            ));
        }
        need += def.count as u128 * each as u128;
        if need > available as u128 {
            let unit = if header.encoding == PlyEncoding::Ascii {
                "lines"
            } else {
                "bytes"
            };
            return Err(format!(
                "the header declares more than the file holds: its elements up to `{name}` ({} of them) need at least {need} {unit} of data, and {available} follow the header (a header that lies, or a truncated file)",
                def.count
            ));
        }
    }
    Ok(())
}

/// The next element of `def`: an ASCII line (blank lines skipped) or binary bytes.
fn read_element(
    parser: &Parser<Item>,
    header: &Header,
    def: &ElementDef,
    cur: &mut Cursor,
) -> std::result::Result<Item, String> {
    let eof = || {
        "the file ends inside it, before the elements its header declares (a header that lies, or a truncated file)"
            .to_string()
    };
    match header.encoding {
        PlyEncoding::Ascii => loop {
            if cur.rest.is_empty() {
                return Err(eof());
            }
            let end = cur
                .rest
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(cur.rest.len());
            let raw = &cur.rest[..end];
            cur.rest = &cur.rest[(end + 1).min(cur.rest.len())..];
            cur.line += 1;
            let text = String::from_utf8_lossy(raw);
            if text.trim().is_empty() {
                continue;
            }
            return parser
                .read_ascii_element(&text, def)
                .map_err(|e| one_line(&e.to_string()));
        },
        PlyEncoding::BinaryLittleEndian => parser
            .read_little_endian_element(&mut cur.rest, def)
            .map_err(|e| binary_error(&e, eof)),
        PlyEncoding::BinaryBigEndian => parser
            .read_big_endian_element(&mut cur.rest, def)
            .map_err(|e| binary_error(&e, eof)),
    }
}

/// The crate's binary read error; running out of bytes (its own kind, or wrapped in a list
/// error's message) says so plainly.
fn binary_error(e: &std::io::Error, eof: impl Fn() -> String) -> String {
    let text = e.to_string();
    if e.kind() == std::io::ErrorKind::UnexpectedEof || text.contains("UnexpectedEof") {
        eof()
    } else {
        one_line(&text)
    }
}

/// The crate's multi-line messages on one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A vertex's position and, where the header has them, its normal; both finite in f32 (the
/// header's `x y z` are checked by [`check_counts`]).
fn vertex(
    item: &Item,
    has_normals: bool,
) -> std::result::Result<([f32; 3], Option<[f32; 3]>), String> {
    let get = |k: usize, name: &str| -> std::result::Result<f32, String> {
        let x = item.values[k] as f32;
        if !x.is_finite() {
            return Err(format!(
                "{name} = {} is not a finite f32 number: fix the file",
                item.values[k]
            ));
        }
        Ok(x)
    };
    let p = [get(0, "x")?, get(1, "y")?, get(2, "z")?];
    let n = if has_normals {
        Some([get(3, "nx")?, get(4, "ny")?, get(5, "nz")?])
    } else {
        None
    };
    Ok((p, n))
}

/// Triangulates the faces as fans (the OBJ reader's order) and the strips (module doc), then
/// builds the mesh. `lists` are the `face` and the `tristrips` elements' index lists.
fn build(
    path: &Path,
    header: &Header,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    lists: (Vec<Vec<i64>>, Vec<Vec<i64>>),
    skipped: Vec<String>,
) -> Result<(Mesh, LoadReport)> {
    let err = |msg: String| Error::input(path, None, msg);
    let (faces, strips) = lists;
    let mut tris: Vec<[Corner; 3]> = Vec::new();
    let mut polygons = false;
    let (mut short, mut short_strips) = (0, 0);
    let has_normals = !normals.is_empty();
    let c = |i: i64| Corner {
        position: i as usize,
        normal: has_normals.then_some(i as usize),
    };
    // -1 separates strips; any other index must name a vertex.
    let check = |name: &str, e: usize, list: &[i64], restart: Option<i64>| {
        match list
            .iter()
            .find(|&&i| Some(i) != restart && (i < 0 || i as u64 >= positions.len() as u64))
        {
            Some(bad) => Err(err(format!(
                "{name} element {e}: vertex index {bad} is past the {} vertices{}: the file is damaged; re-export it",
                positions.len(),
                if restart.is_some() { " (-1 separates strips)" } else { "" }
            ))),
            None => Ok(()),
        }
    };
    for (f, list) in faces.iter().enumerate() {
        check("face", f, list, None)?;
        if list.len() < 3 {
            short += 1;
            continue;
        }
        polygons |= list.len() > 3;
        for k in 0..list.len() - 2 {
            tris.push([c(list[0]), c(list[k + 1]), c(list[k + 2])]);
        }
    }
    for (e, list) in strips.iter().enumerate() {
        check("tristrips", e, list, Some(-1))?;
        for s in list.split(|&i| i == -1).filter(|s| !s.is_empty()) {
            if s.len() < 3 {
                short_strips += 1;
            }
            for i in 0..s.len().saturating_sub(2) {
                let t = if i % 2 == 0 {
                    [s[i], s[i + 1], s[i + 2]]
                } else {
                    [s[i + 1], s[i], s[i + 2]]
                };
                // A join: no triangle drawn (not a zero-area face of the mesh).
                if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                    continue;
                }
                tris.push(t.map(c));
            }
        }
    }
    if tris.is_empty() {
        return Err(err(
            "no triangles: the file has no `face` element with 3 or more vertices and no `tristrips` element (a point cloud?)"
                .into(),
        ));
    }
    let wide: Vec<DVec3> = positions
        .iter()
        .map(|p| DVec3::from(p.map(f64::from)))
        .collect();
    let weld = soup::weld(&wide);
    let lists = soup::Lists {
        positions: &wide,
        normals: &normals,
        smooth_as: Some(&weld),
    };
    let a = soup::assemble(path, lists, &tris)?;
    let mut warnings = soup::common_notes(a.dropped, &a.counts);
    if !has_normals {
        warnings.push(
            "no vertex normals (nx ny nz): computed smooth normals, smoothed across vertices at the same position".into(),
        );
    }
    if short > 0 {
        warnings.push(format!(
            "left out {} with fewer than 3 vertices",
            plural(short, "face", "faces")
        ));
    }
    if short_strips > 0 {
        warnings.push(format!(
            "left out {} with fewer than 3 vertices",
            plural(short_strips, "triangle strip", "triangle strips")
        ));
    }
    if !skipped.is_empty() {
        warnings.push(format!("ignored elements: {}", skipped.join(", ")));
    }
    let encoding = match header.encoding {
        PlyEncoding::Ascii => Encoding::Ascii,
        PlyEncoding::BinaryLittleEndian => Encoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian => Encoding::BinaryBigEndian,
    };
    let report = LoadReport {
        triangles: a.mesh.triangle_count(),
        dropped_zero_area: a.dropped,
        computed_normals: a.counts.computed > 0,
        had_quads_or_polygons: polygons,
        warnings,
        input: MeshInput::whole(Format::Ply, encoding),
    };
    Ok((a.mesh, report))
}
