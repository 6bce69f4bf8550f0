//! The mesh-input seam: glTF 2.0 and PLY beside OBJ. Hand-checked files of tests/data/gltf and
//! tests/data/ply (written by tests/data/gltf/make.py, each value chosen by hand) against world
//! positions and normals worked out here; the same file in every encoding gives the same mesh;
//! every bad file is exit 2 naming the file and the object; scenes, report, tune and corpus
//! take the new formats. The converter test (glTF from CesiumGS's obj2gltf of the shared
//! models) is in [`converted`].
mod converted;

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use shadelab::geometry::{
    self, fit_unit, load_mesh, Encoding, Format, LoadReport, Mesh, NormalSource,
};

use crate::support::*;

fn data(rel: &str) -> PathBuf {
    root().join("tests/data").join(rel)
}

fn load(rel: &str) -> (Mesh, LoadReport) {
    load_mesh(&data(rel)).unwrap_or_else(|e| panic!("{e}"))
}

/// The fitted mesh of world-space triangles given corner by corner (what a reader must give
/// for them): [`fit_unit`] applied to exactly these positions.
fn fitted(tris: &[[[f64; 3]; 3]], normals: &[[f64; 3]]) -> Mesh {
    let mut m = Mesh {
        positions: tris
            .iter()
            .flatten()
            .map(|p| DVec3::from(*p).as_vec3().to_array())
            .collect(),
        normals: normals
            .iter()
            .map(|n| DVec3::from(*n).normalize().as_vec3().to_array())
            .collect(),
        source: String::new(),
    };
    fit_unit(&mut m);
    m
}

/// Largest componentwise difference of two lists of vectors of the same length.
fn max_diff(a: &[[f32; 3]], b: &[[f32; 3]]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (Vec3::from(*x) - Vec3::from(*y)).abs().max_element())
        .fold(0.0, f32::max)
}

/// The world triangles of tests/data/gltf/nodes.gltf's default scene, in drawing order (the
/// scene's nodes depth first), each worked out by hand from the node's transform.
fn nodes_expected() -> Mesh {
    let z = [0.0, 0.0, 1.0];
    // The non-uniform scale (1, 1, 4) takes the tilted triangle's face normal (0, -1, 1) to
    // the inverse transpose's (0, -1, 1/4), i.e. (0, -4, 1): the new face's normal.
    let tilted = [0.0, -4.0, 1.0];
    let tris = [
        // node 0: scale 2, rotation 90 deg about z ((x, y) -> (-y, x)), translation (3, 0, 0)
        [[3.0, 0.0, 0.0], [3.0, 2.0, 0.0], [1.0, 0.0, 0.0]],
        // node 2 under node 1: (0, 5, 0) + 3 * ((1, 0, 0) + p)
        [[3.0, 5.0, 0.0], [6.0, 5.0, 0.0], [3.0, 8.0, 0.0]],
        // node 3: scale (1, 1, 4), translation (0, 0, 6)
        [[0.0, 0.0, 6.0], [1.0, 0.0, 6.0], [0.0, 1.0, 10.0]],
        // node 4: no normals in the file; one flat triangle, so the computed normal is +z
        [[-3.0, 0.0, 0.0], [-2.0, 0.0, 0.0], [-3.0, 1.0, 0.0]],
        // node 5: the strip v0 v1 v2 v3 is (v0, v1, v2), (v1, v3, v2), translated (0, -5, 0)
        [[0.0, -5.0, 0.0], [1.0, -5.0, 0.0], [0.0, -4.0, 0.0]],
        [[1.0, -5.0, 0.0], [1.0, -4.0, 0.0], [0.0, -4.0, 0.0]],
        // node 6: x mirrored, z - 6; a mirror reverses the winding: corners 0, 2, 1
        [[0.0, 0.0, -6.0], [0.0, 1.0, -6.0], [-1.0, 0.0, -6.0]],
    ];
    let mut normals = vec![z; 6];
    normals.extend([tilted; 3]);
    normals.extend([z; 12]);
    fitted(&tris, &normals)
}

#[test]
fn gltf_node_transforms_match_the_hand_computed_world_triangles() {
    let (mesh, report) = load("gltf/nodes.gltf");
    let want = nodes_expected();
    assert_eq!(mesh.triangle_count(), 7, "{report:?}");
    // f32 positions of a fit to the unit sphere: a few ulps (6e-8 each) of slack.
    let (dp, dn) = (
        max_diff(&mesh.positions, &want.positions),
        max_diff(&mesh.normals, &want.normals),
    );
    assert!(dp < 1e-6 && dn < 1e-6, "positions {dp}, normals {dn}");
    // Teeth: the naive normal transform (the matrix itself, not its inverse transpose) gives
    // (0, -1, 4) on the non-uniform node, far from the file's correct (0, -4, 1).
    let naive = DVec3::new(0.0, -1.0, 4.0).normalize().as_vec3();
    assert!((naive - Vec3::from(mesh.normals[6])).length() > 0.5);
    // What was drawn: the default scene (1, "main", not the first) and its parts.
    let input = &report.input;
    assert_eq!(
        (input.format, input.encoding),
        (Format::Gltf, Encoding::Json)
    );
    let scene = input.scene.as_ref().expect("a scene");
    assert_eq!(
        (scene.scene.index, scene.scene.name.as_deref()),
        (1, Some("main"))
    );
    let nodes: Vec<usize> = input
        .parts
        .iter()
        .filter_map(|p| p.node.as_ref().map(|n| n.index))
        .collect();
    assert_eq!(nodes, [0, 2, 3, 4, 5, 6]);
    let computed: Vec<usize> = input
        .parts
        .iter()
        .filter(|p| p.normals == NormalSource::Computed)
        .map(|p| p.mesh.index)
        .collect();
    assert_eq!(computed, [1]);
    assert!(report.computed_normals);
    let notes = report.warnings.join("\n");
    assert!(
        notes.contains("mesh 3 \"strip\" primitive 1: left out, it draws Lines"),
        "{notes}"
    );
    assert!(
        notes.contains("without NORMAL: computed smooth normals"),
        "{notes}"
    );
}

#[test]
fn a_gltf_its_glb_and_its_external_buffer_give_the_same_mesh() {
    let (a, ra) = load("gltf/nodes.gltf");
    let (b, rb) = load("gltf/nodes.glb");
    // external.gltf's buffer is "external buffer.bin", written "external%20buffer.bin".
    let (c, rc) = load("gltf/external.gltf");
    assert_eq!(
        (a.positions.clone(), a.normals.clone()),
        (b.positions, b.normals)
    );
    assert_eq!((a.positions, a.normals), (c.positions, c.normals));
    assert_eq!(rb.input.encoding, Encoding::Glb);
    assert_eq!(ra.input.parts, rc.input.parts);
}

#[test]
fn quantized_integers_morph_targets_and_fans_are_read() {
    // KHR_mesh_quantization: SHORT positions (0, 0, 0), (100, 0, 0), (0, 100, 0), BYTE
    // normalized normals 127 -> 1 and -128 -> -1 (max(c / 127, -1)).
    let (mesh, report) = load("gltf/quantized.gltf");
    let want = fitted(
        &[[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 100.0, 0.0]]],
        &[[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
    );
    assert_eq!(
        (mesh.positions, mesh.normals),
        (want.positions, want.normals)
    );
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("KHR_materials_unlit")),
        "{report:?}"
    );
    // A sparse morph target moves vertex 2 by (0, 0, 1) at weight 0.5; the fan v0..v3 at
    // z = -2 is (v1, v2, v0), (v2, v3, v0) (glTF 2.0 section 3.7.2.1).
    let (mesh, report) = load("gltf/morph.gltf");
    let tris = [
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
        [[1.0, 0.0, -2.0], [1.0, 1.0, -2.0], [0.0, 0.0, -2.0]],
        [[1.0, 1.0, -2.0], [0.0, 1.0, -2.0], [0.0, 0.0, -2.0]],
    ];
    let want = fitted(&tris, &[[0.0, 0.0, 1.0]; 9]);
    assert!(
        max_diff(&mesh.positions, &want.positions) < 1e-6,
        "{:?}",
        mesh.positions
    );
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("1 of 1 morph target applied")),
        "{report:?}"
    );
}

/// scenes/icosphere.obj without its normals: the OBJ the icosphere PLYs (shared vertices, no
/// normals) must equal.
fn icosphere_without_normals(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("scenes/icosphere.obj")).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with("v ") {
            out += &format!("{line}\n");
        } else if let Some(f) = line.strip_prefix("f ") {
            let idx: Vec<&str> = f
                .split_whitespace()
                .map(|c| c.split('/').next().unwrap())
                .collect();
            out += &format!("f {}\n", idx.join(" "));
        }
    }
    let path = dir.join("ico.obj");
    std::fs::write(&path, out).unwrap();
    path
}

#[test]
fn every_ply_encoding_gives_the_mesh_of_the_same_obj() {
    let (cube, _) = load_mesh(&root().join("scenes/cube.obj")).unwrap();
    for enc in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let (m, r) = load(&format!("ply/cube_{enc}.ply"));
        assert_eq!(
            (&m.positions, &m.normals),
            (&cube.positions, &cube.normals),
            "{enc}"
        );
        assert!(!r.computed_normals, "{enc}");
        assert!(
            r.warnings.iter().any(|w| w == "ignored elements: edge (1)"),
            "{enc}: {r:?}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let (ico, _) = load_mesh(&icosphere_without_normals(dir.path())).unwrap();
    for f in [
        "ply/icosphere_ascii.ply",
        "ply/icosphere_binary_big_endian.ply",
    ] {
        let (m, r) = load(f);
        assert_eq!(
            (&m.positions, &m.normals),
            (&ico.positions, &ico.normals),
            "{f}"
        );
        assert!(r.computed_normals, "{f}");
        assert!(
            r.warnings.iter().any(|w| w.contains("no vertex normals")),
            "{f}: {r:?}"
        );
    }
    // One 4-vertex face: a fan of 2 triangles, as the OBJ reader's polygons.
    let (m, r) = load("ply/square_ascii.ply");
    assert_eq!(m.triangle_count(), 2);
    assert!(r.had_quads_or_polygons);
}

#[test]
fn a_scene_file_names_any_mesh_file() {
    let dir = tempfile::tempdir().unwrap();
    let glb = data("gltf/nodes.glb");
    let short = dir.path().join("short.toml");
    std::fs::write(&short, format!("mesh = {:?}\n", glb.display().to_string())).unwrap();
    let table = dir.path().join("table.toml");
    std::fs::write(
        &table,
        format!("[mesh]\nfile = {:?}\n", glb.display().to_string()),
    )
    .unwrap();
    let a = shadelab::scene::load_scene(&short).unwrap_or_else(|e| panic!("{e}"));
    let b = shadelab::scene::load_scene(&table).unwrap_or_else(|e| panic!("{e}"));
    let c = shadelab::scene::scene_for_mesh(&glb).unwrap();
    assert_eq!(a.mesh.positions, c.mesh.positions);
    assert_eq!(b.mesh.positions, c.mesh.positions);
    assert_eq!(a.mesh_report.unwrap().input.encoding, Encoding::Glb);
}

/// A copy of `rel` in `dir` under `name`, with `edit` applied to its bytes.
fn edited(dir: &Path, rel: &str, name: &str, edit: impl Fn(Vec<u8>) -> Vec<u8>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, edit(std::fs::read(data(rel)).unwrap())).unwrap();
    path
}

/// nodes.gltf with its buffer's bytes changed by `edit` (re-encoded in its data URI).
fn with_buffer(bytes: Vec<u8>, edit: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    use base64::Engine as _;
    let engine = base64::engine::general_purpose::STANDARD;
    let text = String::from_utf8(bytes).unwrap();
    let (head, rest) = text.split_once("base64,").unwrap();
    let (b64, tail) = rest.split_once('"').unwrap();
    let mut buf = engine.decode(b64).unwrap();
    edit(&mut buf);
    format!("{head}base64,{}\"{tail}", engine.encode(buf)).into_bytes()
}

fn replace(bytes: Vec<u8>, from: &str, to: &str) -> Vec<u8> {
    let s = String::from_utf8(bytes).unwrap();
    assert!(s.contains(from), "{from:?} not in the file");
    s.replacen(from, to, 1).into_bytes()
}

#[test]
fn every_bad_file_is_exit_2_naming_the_file_and_the_object() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let glb = std::fs::read(data("gltf/nodes.glb")).unwrap();
    std::fs::copy(data("gltf/external.gltf"), d.join("lonely.gltf")).unwrap();
    let cases: Vec<(PathBuf, Vec<&str>)> = vec![
        (
            edited(d, "gltf/nodes.glb", "cut.glb", |b| {
                b[..b.len() / 2].to_vec()
            }),
            vec![
                "truncated .glb",
                "its header says 2636 bytes",
                "export or download it again",
            ],
        ),
        (
            d.join("lonely.gltf"),
            vec![
                "buffer 0: cannot read its file",
                "external buffer.bin",
                "keep the .bin files beside the .gltf",
            ],
        ),
        (
            edited(d, "gltf/nodes.gltf", "range.gltf", |b| {
                replace(b, "\"count\": 3,", "\"count\": 300,")
            }),
            vec![
                "mesh 0 \"tri\" primitive 0: POSITION: accessor 0",
                "out of range",
            ],
        ),
        (
            edited(d, "gltf/nodes.gltf", "nan.gltf", |b| {
                with_buffer(b, |buf| buf[0..4].copy_from_slice(&f32::NAN.to_le_bytes()))
            }),
            vec![
                "mesh 0 \"tri\" primitive 0: POSITION of vertex 0",
                "not finite",
            ],
        ),
        (
            // The indices of mesh 0 are u16 0, 1, 2 at byte 72 of the buffer: make the last 9.
            edited(d, "gltf/nodes.gltf", "index.gltf", |b| {
                with_buffer(b, |buf| buf[76] = 9)
            }),
            vec!["mesh 0 \"tri\" primitive 0: index 9", "past its 3 vertices"],
        ),
        (
            edited(d, "gltf/nodes.gltf", "draco.gltf", |b| {
                replace(
                    b,
                    "\"asset\": {",
                    "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"],\n \"asset\": {",
                )
            }),
            vec![
                "requires 1 extension (KHR_draco_mesh_compression)",
                "export it without it",
            ],
        ),
        (
            edited(d, "gltf/nodes.gltf", "cycle.gltf", |b| {
                replace(
                    b,
                    "\"children\": [\n    2\n   ]",
                    "\"children\": [\n    1\n   ]",
                )
            }),
            vec!["node 1 is reached twice from scene 1"],
        ),
        (
            edited(d, "ply/cube_ascii.ply", "lies.ply", |b| {
                replace(b, "element vertex 36", "element vertex 40")
            }),
            vec![
                "the header declares more than the file holds",
                "a header that lies",
            ],
        ),
        (
            edited(d, "ply/cube_binary_little_endian.ply", "short.ply", |b| {
                b[..b.len() - 20].to_vec()
            }),
            vec![
                "face element 11: the file ends inside it",
                "a truncated file",
            ],
        ),
        (
            edited(d, "ply/square_ascii.ply", "face.ply", |b| {
                replace(b, "4 0 1 2 3", "4 0 1 2 7")
            }),
            vec!["face element 0: vertex index 7 is past the 4 vertices"],
        ),
        (
            edited(d, "ply/square_ascii.ply", "nan.ply", |b| {
                replace(b, "1.0 0.0 0.0", "1e39 0.0 0.0")
            }),
            vec![":12: vertex element 1: x = inf is not a finite f32 number"],
        ),
        (
            edited(d, "gltf/morph.gltf", "v1.gltf", |b| {
                replace(b, "\"version\": \"2.0\"", "\"version\": \"1.0\"")
            }),
            vec!["its asset.version is \"1.0\"; shadelab reads glTF 2.0"],
        ),
        (
            edited(d, "ply/square_ascii.ply", "weird.stl", |b| {
                replace(b, "ply\n", "solid\n")
            }),
            vec!["not a mesh file shadelab reads: give .obj, .gltf, .glb or .ply"],
        ),
    ];
    assert!(glb.starts_with(b"glTF"));
    let out = d.join("out");
    for (file, needles) in &cases {
        let (code, _, err) = run(&[
            "compare",
            "--mesh",
            file.to_str().unwrap(),
            "--size",
            "16x16",
            "--methods",
            "phong_exact",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{}: {err}", file.display());
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(file.to_str().unwrap()),
            "names the file: {err}"
        );
        for n in needles {
            assert!(err.contains(n), "{}: lacks {n:?}: {err}", file.display());
        }
    }
    // Teeth: the untouched files are read (exit 0).
    for f in [
        "gltf/nodes.gltf",
        "gltf/nodes.glb",
        "ply/cube_ascii.ply",
        "ply/square_ascii.ply",
    ] {
        let (code, _, err) = run(&[
            "compare",
            "--mesh",
            data(f).to_str().unwrap(),
            "--size",
            "16x16",
            "--methods",
            "phong_exact",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{f}: {err}");
    }
}

#[test]
fn compare_states_the_gltf_scene_and_primitives_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let glb = data("gltf/nodes.glb");
    let (code, _, err) = run(&[
        "compare",
        "--mesh",
        glb.to_str().unwrap(),
        "--size",
        "32x32",
        "--methods",
        "phong_exact",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("scene 1 \"main\" (the default scene)"),
        "{err}"
    );
    let summary = read_json(out.join("summary.json"));
    assert_schema(
        &summary,
        "docs/summary.schema.json",
        "/mesh_input",
        "format",
    );
    let input = &summary["mesh_input"];
    assert_eq!(input["format"], "gltf");
    assert_eq!(input["encoding"], "glb");
    assert_eq!(input["scene"]["name"], "main");
    assert_eq!(input["parts"].as_array().unwrap().len(), 6);
    assert_eq!(input["parts"][3]["normals"], "computed");
}

/// A folder of the four formats: cube.obj (shipped), nodes.gltf, nodes.glb, cube_ascii.ply.
fn mixed_folder(dir: &Path) -> PathBuf {
    let m = dir.join("meshes");
    std::fs::create_dir_all(&m).unwrap();
    std::fs::copy(root().join("scenes/cube.obj"), m.join("cube.obj")).unwrap();
    for f in ["gltf/nodes.gltf", "gltf/nodes.glb", "ply/cube_ascii.ply"] {
        let p = data(f);
        std::fs::copy(&p, m.join(p.file_name().unwrap())).unwrap();
    }
    std::fs::write(m.join("notes.txt"), "not a mesh").unwrap();
    m
}

#[test]
fn mesh_files_lists_every_format_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let m = mixed_folder(dir.path());
    let files = geometry::mesh_files(&m, geometry::Depth::Flat, None).unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        ["cube.obj", "cube_ascii.ply", "nodes.glb", "nodes.gltf"]
    );
    let e = geometry::mesh_files(dir.path(), geometry::Depth::Flat, None).unwrap_err();
    assert!(
        e.to_string()
            .contains("no mesh files (.obj, .gltf, .glb or .ply)"),
        "{e}"
    );
    assert_eq!(
        geometry::mesh_files(dir.path(), geometry::Depth::Recursive, None).unwrap(),
        files
    );
}

#[test]
fn corpus_reads_a_folder_of_mixed_formats() {
    let dir = tempfile::tempdir().unwrap();
    let m = mixed_folder(dir.path());
    let out = dir.path().join("corpus");
    let (code, _, err) = run(&[
        "corpus",
        m.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "32x32",
        "--methods",
        "phong_exact,gouraud",
    ]);
    assert_eq!(code, 0, "{err}");
    for id in ["cube.obj", "cube_ascii.ply", "nodes.glb", "nodes.gltf"] {
        let r = read_json(out.join("meshes").join(id).join("result.json"));
        assert_eq!(r["status"], "ok", "{id}: {r}");
        assert_eq!(r["summary"]["scene_source"], id, "{r}");
    }
    let gltf = read_json(out.join("meshes/nodes.gltf/result.json"));
    assert_eq!(gltf["summary"]["mesh_input"]["scene"]["index"], 1, "{gltf}");
}

/// `report --models DIR` with a mix of .obj, .gltf, .glb and .ply: a scene each, and the
/// report's provenance names each mesh's format (and for glTF the scene drawn).
#[test]
fn report_models_takes_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let m = mixed_folder(dir.path());
    let out = dir.path().join("out");
    let (code, _, err) = run(&[
        "report",
        "--models",
        m.to_str().unwrap(),
        "--methods",
        "gouraud",
        "--size",
        "32x32",
        "--runs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let answer = read_json(out.join("answer.json"));
    let mut scenes: Vec<String> = answer["scenes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap().to_string())
        .collect();
    scenes.sort();
    assert_eq!(scenes.len(), 4, "{scenes:?}");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for needle in [
        "OBJ (text)",
        "PLY (ASCII)",
        "glTF 2.0 (.glb binary), scene 1 &quot;main&quot; (the default scene)",
        "glTF 2.0 (.gltf JSON)",
    ] {
        assert!(html.contains(needle), "the provenance lacks {needle:?}");
    }
}

/// `tune --mesh M.gltf` tunes the glTF's triangles like an OBJ's.
#[test]
fn tune_takes_a_gltf_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t");
    let gltf = data("gltf/nodes.gltf");
    let (code, stdout, err) = run(&[
        "tune",
        "--mesh",
        gltf.to_str().unwrap(),
        "--size",
        "64x64",
        "--cost-model",
        "isa:amd:navi21",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{err}");
    let r = read_json(out.join("tune.json"));
    assert_eq!(r["cost_models"][0]["model"], "isa:amd:navi21", "{r}");
}
