//! OBJ loading: triangulation, indices, comments, weights, malformed and empty files,
//! zero-area triangles, fitting to the unit sphere.
use super::*;

#[test]
fn quads_and_polygons_are_triangulated_as_fans() {
    let (mesh, report) =
        load_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\nf 1 2 3 4\nf 1 4 5\n").unwrap();
    assert_eq!(report.triangles, 3, "a quad and a triangle");
    assert!(report.had_quads_or_polygons);
    let (m5, r5) = load_text("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n").unwrap();
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

/// Found by tests/fuzz.rs (tests/data/fuzz/obj/cube-vertex-at-i32-min.obj): one vertex moved
/// far away leaves the triangles that do not use it smaller than f32 resolution once fitted.
/// They are dropped and counted like any zero-area triangle, and the rest is refitted.
#[test]
fn triangles_that_collapse_when_fitted_are_dropped() {
    let text =
        "v -2147483648 0 0\nv 0 0 0\nv 0 1 0\nv 0 0 1\nv 0 1e-9 0\nv 0 0 1e-9\nf 1 3 4\nf 2 5 6\n";
    let (mesh, report) = load_text(text).unwrap();
    assert_eq!((report.triangles, report.dropped_zero_area), (1, 1));
    assert_eq!(mesh.triangle_count(), 1);
    assert!(
        report.warnings[0].contains("dropped 1 zero-area triangle"),
        "{:?}",
        report.warnings
    );
    let t = &mesh.positions;
    assert!(!is_zero_area(
        DVec3::from_array(t[0].map(f64::from)),
        DVec3::from_array(t[1].map(f64::from)),
        DVec3::from_array(t[2].map(f64::from))
    ));
}

/// A UTF-8 byte-order mark is not part of the first statement: `v 9 9 9` stays the first
/// vertex, so `f 1 2 3` takes it. (Read as part of the keyword, the mark made the line an
/// unknown statement and the face took the next three vertices: the mesh without `v 9 9 9`.)
#[test]
fn a_byte_order_mark_does_not_shift_indices() {
    let text = "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(text.as_bytes());
    let (with_bom, _) = parse_obj(Path::new("bom.obj"), &bom).unwrap();
    let (plain, _) = parse_obj(Path::new("plain.obj"), text.as_bytes()).unwrap();
    assert_eq!(with_bom.positions, plain.positions);
    // Teeth: the mesh the old reader made (the last three vertices) is another one.
    let (shifted, _) =
        parse_obj(Path::new("s.obj"), b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_ne!(with_bom.positions, shifted.positions);
}

/// Junk before a keyword is an error at its line, never an ignored statement; a keyword the
/// specification does not have is ignored with a warning that names it.
#[test]
fn leading_junk_is_refused_and_unknown_keywords_named() {
    let junk = |prefix: &str| format!("v 0 0 0\n{prefix}v 9 9 9\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    for prefix in ["\u{feff}", "\u{1}", "\u{200b}", "\u{fffd}"] {
        assert_input_err(load_text(&junk(prefix)), Some(2), "no OBJ keyword has");
    }
    let (_, report) = load_text(&junk("x")).unwrap();
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("1 statement") && w.contains("`xv` at line 2")),
        "{:?}",
        report.warnings
    );
    // the specification's own statements pass silently
    let (_, report) = load_text(&junk("")).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
}

/// A file that is not OBJ text is named as what it is, with the formats the reader takes
/// (they used to read as text "with no faces").
#[test]
fn binary_and_other_formats_are_named() {
    let utf16: Vec<u8> = "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
        .encode_utf16()
        .flat_map(u16::to_le_bytes)
        .collect();
    let no_mark = utf16[2..].to_vec();
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\n".to_vec();
    let glb = b"glTF\x02\x00\x00\x00".to_vec();
    let json = b"  {\"asset\": {\"version\": \"2.0\"}}".to_vec();
    for (bytes, what) in [
        (utf16, "UTF-16"),
        (no_mark, "NUL bytes"),
        (ply, "PLY"),
        (glb, "binary glTF"),
        (json, "JSON"),
    ] {
        let e = parse_obj(Path::new("m.obj"), &bytes)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(what) && e.contains("reads Wavefront OBJ"),
            "{what}: {e}"
        );
    }
}

/// Old Mac OS files end their lines with a lone CR (the cube's 6 faces were "no faces": the
/// whole file one line), and OBJ continues a statement on the next line after a `\`
/// (Wavefront's appendix B1), which gave "face has 2 vertices". Both are the plain file's mesh,
/// and errors keep the line a statement starts on.
#[test]
fn lone_cr_line_ends_and_backslash_continuations_give_the_plain_files_mesh() {
    let (plain, _) = load_text(UNIT_CUBE).unwrap();
    let cr = UNIT_CUBE.replace('\n', "\r");
    // A vertex and a face continued over lines (one with a comment after the `\`), and a
    // comment ending in `\`, which continues nothing (the comment runs to the end of its line).
    let continued = UNIT_CUBE
        .replacen("v 1 1 0\n", "v 1 \\\n1 0\n", 1)
        .replacen("f 1 4 3 2\n", "f 1 \\ # first corner\n4 \\\n  3 2\n", 1)
        .replacen("v 0 0 0\n", "# saved in C:\\models\\\nv 0 0 0\n", 1);
    for (what, text) in [
        ("lone CR", cr.clone()),
        ("continued", continued.clone()),
        ("continued, CRLF", continued.replace('\n', "\r\n")),
        ("continued, lone CR", continued.replace('\n', "\r")),
    ] {
        let (mesh, report) = load_text(&text).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(mesh.positions, plain.positions, "{what}");
        assert_eq!(mesh.normals, plain.normals, "{what}");
        assert_eq!(report.triangles, 12, "{what}");
    }
    // Lines are counted at every line end, a lone CR included; a statement's error is at the
    // line it starts on, and the lines after a continued one keep their numbers.
    let cases: &[(&str, usize, &str)] = &[
        (
            "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 4\r",
            4,
            "face index 4 is past",
        ),
        (
            "v 0 0 0\r\rv 1 0 0\r\nv 0 1 0\nf 1 2 4\n",
            5,
            "face index 4 is past",
        ),
        (
            "v 0 0 0\nv 1 \\\n0 0\nv 0 1 0\nf 1 2 4\n",
            5,
            "face index 4 is past",
        ),
        ("v 0 0 0\nv 1 0 0\nf 1 \\\n2\n", 3, "face has 2 vertices"),
        ("v 0 0 0\rv 1 x \\\r0\r", 2, "vertex coordinate 2 is `x`"),
    ];
    for (text, line, needle) in cases {
        assert_input_err(load_text(text), Some(*line), needle);
    }
}
