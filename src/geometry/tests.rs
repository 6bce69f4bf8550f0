//! Tests of OBJ loading, normals, fitting, writing and the generators.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::{Error, Result};
use crate::geometry::*;
use crate::testutil::assert_close;

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
        other => {
            panic!("expected an input error at line {line:?} containing `{needle}`, got {other:?}")
        }
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
            "the limit is 1000000",
        ),
        // Found by tests/fuzz.rs: 1e39 is past f32, the positions became infinite.
        (
            Generator::Torus {
                major_radius: 1e39,
                minor_radius: 0.5,
                major_segments: 3,
                minor_segments: 3,
            },
            "major_radius must be at most 1e30 (got 1e39)",
        ),
        (
            Generator::Torus {
                major_radius: 1.0,
                minor_radius: 1e-20,
                major_segments: 3,
                minor_segments: 3,
            },
            "minor_radius must be at least 1e-4 x major_radius (got 1e-20 for 1e0)",
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
        (
            "sphere",
            vec![],
            "unknown variant `sphere`, expected one of `uv_sphere`, `icosphere`, `torus`, `cube`",
        ),
        (
            "uv_sphere",
            s(&["segments=8", "rigns=4"]),
            "unknown field `rigns`, expected `segments` or `rings`",
        ),
        ("uv_sphere", s(&["segments=8"]), "missing field `rings`"),
        (
            "uv_sphere",
            s(&["segments=8", "rings"]),
            "`rings` is not of the form key=value",
        ),
        (
            "uv_sphere",
            s(&["segments=8", "rings=x"]),
            "`x` is not a number",
        ),
        (
            "uv_sphere",
            s(&["segments=8", "rings=4.5"]),
            "invalid type: floating point `4.5`, expected u32",
        ),
        ("uv_sphere", s(&["segments=8", "rings=-4"]), "rings"),
        ("uv_sphere", s(&["segments=8", "segments=9"]), "given twice"),
        (
            "uv_sphere",
            s(&["segments=2", "rings=4"]),
            "segments must be >= 3",
        ),
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
            other => {
                panic!("{name} {kv:?}: expected a usage error containing `{needle}`, got {other:?}")
            }
        }
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
