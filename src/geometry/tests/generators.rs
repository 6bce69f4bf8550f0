//! The procedural generators: outward unit normals, parameters and their errors, the shipped
//! meshes' normal spreads and freshness.
use super::*;

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
            "unknown variant `sphere`, expected one of `uv_sphere`, `icosphere`, `torus`, `cube`, `random_normals`, `opposite_normals`",
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

/// The stress grids: 2 cells^2 triangles in z = 0 wound counter-clockwise from +z, unit corner
/// normals (random ones in the hemisphere z > 0; the second corner of an opposite-normals
/// triangle within `tilt_deg` of the first one reversed), the same mesh for the same seed and
/// another for another seed, parameters validated and round-tripped through `describe`.
#[test]
fn stress_grids_have_the_stated_normals() {
    let random = Generator::RandomNormals { cells: 5, seed: 3 };
    let opposite = Generator::OppositeNormals {
        cells: 5,
        seed: 3,
        tilt_deg: 10.0,
    };
    for g in [&random, &opposite] {
        let m = g.build().unwrap();
        assert_eq!(m.triangle_count() as u64, g.triangle_count());
        assert_eq!(m.triangle_count(), 50);
        for (ps, ns) in m.positions.chunks(3).zip(m.normals.chunks(3)) {
            let p: Vec<DVec3> = ps.iter().map(|&v| DVec3::from(v.map(f64::from))).collect();
            let n: Vec<DVec3> = ns.iter().map(|&v| DVec3::from(v.map(f64::from))).collect();
            assert!(p
                .iter()
                .all(|v| v.z == 0.0 && v.x.abs() <= 1.0 && v.y.abs() <= 1.0));
            assert!((p[1] - p[0]).cross(p[2] - p[0]).z > 0.0, "{p:?}");
            assert!(n.iter().all(|v| (v.length() - 1.0).abs() < 1e-6), "{n:?}");
            assert!(n[0].z > 0.0 && n[2].z > 0.0, "{n:?}");
            match g {
                Generator::OppositeNormals { .. } => {
                    let deg = n[0].dot(n[1]).clamp(-1.0, 1.0).acos().to_degrees();
                    assert!(deg >= 170.0 - 1e-3, "{deg}");
                }
                _ => assert!(n[1].z > 0.0),
            }
        }
        let again = g.build().unwrap();
        assert_eq!(m.normals, again.normals);
        let desc = g.describe();
        let mut words = desc.split_whitespace();
        let name = words.next().unwrap();
        let kv: Vec<String> = words.map(str::to_string).collect();
        assert_eq!(&parse_generator_args(name, &kv).unwrap(), g);
    }
    let other = Generator::RandomNormals { cells: 5, seed: 4 }
        .build()
        .unwrap();
    assert_ne!(other.normals, random.build().unwrap().normals);
    // the tilt is used: with none, the second corner is exactly the first reversed
    let none = Generator::OppositeNormals {
        cells: 2,
        seed: 1,
        tilt_deg: 0.0,
    };
    for n in none.build().unwrap().normals.chunks(3) {
        assert!((0..3).all(|k| (n[0][k] + n[1][k]).abs() < 1e-6), "{n:?}");
    }
    for (g, key) in [
        (Generator::RandomNormals { cells: 0, seed: 1 }, "cells"),
        (
            Generator::OppositeNormals {
                cells: 2,
                seed: 1,
                tilt_deg: 181.0,
            },
            "tilt_deg",
        ),
        (
            Generator::OppositeNormals {
                cells: 2,
                seed: 1,
                tilt_deg: f64::NAN,
            },
            "tilt_deg",
        ),
        (
            Generator::RandomNormals {
                cells: 800,
                seed: 1,
            },
            "generator",
        ),
    ] {
        assert_eq!(g.check().unwrap_err().0, key, "{g:?}");
    }
}
