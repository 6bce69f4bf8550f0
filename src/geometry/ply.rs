//! The PLY reader (ASCII, binary little and big endian; Turk's PLY description), on ply-rs-bw
//! for the header grammar and the elements' encodings.
//!
//! Read: the `vertex` element's `x y z` and, when all three are there, `nx ny nz`; the `face`
//! element's `vertex_indices` (or `vertex_index`) lists, triangulated as fans like the OBJ
//! reader's polygons. Every other element and property is skipped, with a note. A file without
//! normals gets smooth normals as an OBJ without normals does ([`super::soup`]), smoothed across
//! vertices at the same position, and the report says so.
//!
//! Elements are read one at a time, so an error names the element, its index and, in ASCII,
//! the file's line. Before any element is read, each count the header declares is checked
//! against what is left of the file (a line per ASCII element, the smallest encoding per
//! binary one): a header that lies is refused before it can size anything.
use std::path::Path;

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
    let mut cur = Cursor {
        rest,
        line: header_lines + 1,
    };
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut faces: Vec<Vec<i64>> = Vec::new();
    let mut skipped = Vec::new();
    let has_normals = header.elements.get("vertex").is_some_and(|v| {
        ["nx", "ny", "nz"]
            .iter()
            .all(|n| v.properties.contains_key(*n))
    });
    for (name, def) in &header.elements {
        let wanted = matches!(name.as_str(), "vertex" | "face");
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
                "face" => faces.push(item.list.ok_or_else(|| {
                    err(at(), format!("face element {i} has no vertex_indices list"))
                })?),
                _ => {}
            }
        }
    }
    build(path, &header, positions, normals, faces, skipped)
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

/// Triangulates the faces as fans (the OBJ reader's order) and builds the mesh.
fn build(
    path: &Path,
    header: &Header,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    faces: Vec<Vec<i64>>,
    skipped: Vec<String>,
) -> Result<(Mesh, LoadReport)> {
    let err = |msg: String| Error::input(path, None, msg);
    let mut tris: Vec<[Corner; 3]> = Vec::new();
    let mut polygons = false;
    let mut short = 0;
    let has_normals = !normals.is_empty();
    for (f, list) in faces.iter().enumerate() {
        if let Some(&bad) = list
            .iter()
            .find(|&&i| i < 0 || i as u64 >= positions.len() as u64)
        {
            return Err(err(format!(
                "face element {f}: vertex index {bad} is past the {} vertices: the file is damaged; re-export it",
                positions.len()
            )));
        }
        if list.len() < 3 {
            short += 1;
            continue;
        }
        polygons |= list.len() > 3;
        let c = |k: usize| Corner {
            position: list[k] as usize,
            normal: has_normals.then_some(list[k] as usize),
        };
        for k in 0..list.len() - 2 {
            tris.push([c(0), c(k + 1), c(k + 2)]);
        }
    }
    if tris.is_empty() {
        return Err(err(
            "no triangles: the file has no `face` element with 3 or more vertices (a point cloud?)"
                .into(),
        ));
    }
    let weld = soup::weld(&positions);
    let lists = soup::Lists {
        positions: &positions,
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
