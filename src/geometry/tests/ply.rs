//! PLY reading: files written here (ASCII and binary little endian, faces or triangle strips)
//! that must give the same mesh, and headers that must be refused naming what is wrong.
use super::*;

/// How a PLY file written by [`ply`] holds its triangles.
enum Faces<'a> {
    /// A `face` element: one `vertex_indices` list per face.
    Lists(&'a [Vec<i32>]),
    /// A `tristrips` element of one `vertex_indices` list: the strips, -1 between them (as
    /// range-scanner tools write it).
    Strips(&'a [Vec<i32>]),
}

/// A PLY file of `positions` (`vertex` x y z float) and `faces`, in `format` (`ascii` or
/// `binary_little_endian`), its lists of `index` type (`int`, `float`, ...).
fn ply(format: &str, positions: &[[f32; 3]], faces: Faces, index: &str) -> Vec<u8> {
    let (element, lists): (&str, Vec<Vec<i32>>) = match faces {
        Faces::Lists(l) => ("face", l.to_vec()),
        Faces::Strips(s) => ("tristrips", vec![s.join(&-1)]),
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement {element} {}\nproperty list int {index} vertex_indices\nend_header\n",
        positions.len(),
        lists.len()
    )
    .into_bytes();
    let ascii = format == "ascii";
    for p in positions {
        if ascii {
            out.extend(format!("{} {} {}\n", p[0], p[1], p[2]).bytes());
        } else {
            out.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        }
    }
    for l in &lists {
        if ascii {
            let items: Vec<String> = l.iter().map(i32::to_string).collect();
            out.extend(format!("{} {}\n", l.len(), items.join(" ")).bytes());
        } else {
            out.extend((l.len() as i32).to_le_bytes());
            for &i in l {
                match index {
                    "float" => out.extend((i as f32).to_le_bytes()),
                    _ => out.extend(i.to_le_bytes()),
                }
            }
        }
    }
    out
}

fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport)> {
    crate::geometry::ply::parse_ply(Path::new("m.ply"), bytes)
}

/// A 5 x 4 grid of vertices (column c, row r at index 5 r + c) over a height field with bumps,
/// so that every computed normal depends on the neighbouring triangles' winding.
fn bumpy_grid() -> Vec<[f32; 3]> {
    (0..4)
        .flat_map(|r| {
            (0..5).map(move |c| {
                let z = 0.1 * ((c * 7 + r * 3) % 5) as f32;
                [c as f32, r as f32, z]
            })
        })
        .collect()
}

/// One strip per row of cells of [`bumpy_grid`]: the vertices of rows r + 1 and r
/// alternating, which make counter-clockwise triangles seen from +z.
fn grid_strips() -> Vec<Vec<i32>> {
    (0..3)
        .map(|r| (0..5).flat_map(|c| [5 * (r + 1) + c, 5 * r + c]).collect())
        .collect()
}

/// Triangle i of a strip: (s[i], s[i+1], s[i+2]) for even i, (s[i+1], s[i], s[i+2]) for odd
/// i, so that every triangle keeps the strip's first winding; those that repeat a vertex (a
/// strip's joins) left out.
fn strip_triangles(strips: &[Vec<i32>]) -> Vec<Vec<i32>> {
    let mut out = Vec::new();
    for s in strips {
        for i in 0..s.len().saturating_sub(2) {
            let t = if i % 2 == 0 {
                vec![s[i], s[i + 1], s[i + 2]]
            } else {
                vec![s[i + 1], s[i], s[i + 2]]
            };
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                out.push(t);
            }
        }
    }
    out
}

#[test]
fn triangle_strips_give_the_mesh_of_the_same_triangles_written_as_faces() {
    let positions = bumpy_grid();
    let strips = grid_strips();
    let faces = strip_triangles(&strips);
    assert_eq!(faces.len(), 24);
    // The same strips joined into one by repeating a vertex (two triangles with a repeated
    // index between rows, drawing nothing), as strip-making tools also write them.
    let mut joined = strips[0].clone();
    for s in &strips[1..] {
        // An even number of vertices so far keeps the next strip's winding.
        assert_eq!(joined.len() % 2, 0);
        joined.extend([*joined.last().unwrap(), s[0]]);
        joined.extend(s);
    }
    for format in ["ascii", "binary_little_endian"] {
        let (want, _) = read(&ply(format, &positions, Faces::Lists(&faces), "int")).unwrap();
        // Counter-clockwise from +z: every computed normal points up.
        assert!(
            want.normals.iter().all(|n| n[2] > 0.5),
            "{:?}",
            want.normals
        );
        for s in [strips.clone(), vec![joined.clone()]] {
            let (got, report) = read(&ply(format, &positions, Faces::Strips(&s), "int"))
                .unwrap_or_else(|e| panic!("{format}: {e}"));
            assert_eq!(got.positions, want.positions, "{format}");
            assert_eq!(got.normals, want.normals, "{format}");
            assert_eq!(report.triangles, 24, "{format}");
        }
    }
}

#[test]
fn a_byte_order_mark_before_the_header_gives_the_same_mesh() {
    let positions = bumpy_grid();
    let faces = strip_triangles(&grid_strips());
    for format in ["ascii", "binary_little_endian"] {
        let plain = ply(format, &positions, Faces::Lists(&faces), "int");
        let bom = [b"\xEF\xBB\xBF".as_slice(), &plain].concat();
        let (want, _) = read(&plain).unwrap();
        let (got, _) = read(&bom).unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_eq!(
            got,
            Mesh {
                source: got.source.clone(),
                ..want
            }
        );
        // Told by its first bytes too, whatever its name.
        let none = |_: &Path| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
        let (_, r) = parse_mesh(Path::new("m.obj"), &bom, &none).unwrap();
        assert_eq!(r.input.format, Format::Ply);
    }
    // Line numbers after the header are those of the file without the mark: the header is 9
    // lines, so vertex 1 is line 11.
    let plain = ply("ascii", &positions, Faces::Lists(&faces), "int");
    let text = String::from_utf8(plain)
        .unwrap()
        .replacen("\n1 0 ", "\n1 x ", 1);
    let bom = [b"\xEF\xBB\xBF".as_slice(), text.as_bytes()].concat();
    for bytes in [text.as_bytes(), &bom] {
        assert_input_err(read(bytes), Some(11), "vertex element 1");
    }
}

#[test]
fn float_vertex_indices_are_refused_as_not_an_integer_list() {
    let positions = bumpy_grid();
    let faces = strip_triangles(&grid_strips());
    for format in ["ascii", "binary_little_endian"] {
        assert_input_err(
            read(&ply(format, &positions, Faces::Lists(&faces), "float")),
            None,
            "the `face` element's `vertex_indices` is a list of float: vertex indices must be a list of integers (e.g. `property list uchar int vertex_indices`)",
        );
    }
}
