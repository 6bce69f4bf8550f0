//! glTF reading: documents built here (one mesh, its buffer in a data URI, a file beside the
//! `.gltf` or a `.glb`'s BIN chunk) under node transforms, URIs and containers that must be
//! read, or refused with a message naming the object and the rule.
use super::*;
use crate::geometry::input::BUFFER_RULE;
use base64::Engine as _;
use serde_json::{json, Value};

/// A document of one indexed triangle mesh (mesh 0, primitive 0): accessor 0 its positions,
/// 1 its indices, 2 its normals when given. `nodes` and `scenes` are the document's.
struct Doc {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    indices: Vec<u32>,
    nodes: Value,
    scenes: Value,
}

impl Doc {
    /// `mesh`'s triangles, unindexed (corner k is vertex k), without normals, in a scene of one
    /// node placing it untransformed.
    fn of(mesh: &Mesh) -> Doc {
        Doc {
            positions: mesh.positions.clone(),
            normals: None,
            indices: (0..mesh.positions.len() as u32).collect(),
            nodes: json!([{ "mesh": 0 }]),
            scenes: json!([{ "nodes": [0] }]),
        }
    }

    /// A unit right triangle in z = 0 with normals +z.
    fn triangle() -> Doc {
        Doc {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            normals: Some(vec![[0.0, 0.0, 1.0]; 3]),
            indices: vec![0, 1, 2],
            nodes: json!([{ "mesh": 0 }]),
            scenes: json!([{ "nodes": [0] }]),
        }
    }

    /// The buffer's bytes: positions, indices, normals.
    fn bin(&self) -> Vec<u8> {
        let mut b: Vec<u8> = Vec::new();
        b.extend(
            self.positions
                .iter()
                .flatten()
                .flat_map(|c| c.to_le_bytes()),
        );
        b.extend(self.indices.iter().flat_map(|i| i.to_le_bytes()));
        b.extend(
            self.normals
                .iter()
                .flatten()
                .flatten()
                .flat_map(|c| c.to_le_bytes()),
        );
        b
    }

    /// The JSON document; `buffer` is buffer 0's object without its `byteLength`.
    fn json(&self, buffer: Value) -> Value {
        let np = self.positions.len() * 12;
        let ni = self.indices.len() * 4;
        let mut views = vec![
            json!({ "buffer": 0, "byteOffset": 0, "byteLength": np }),
            json!({ "buffer": 0, "byteOffset": np, "byteLength": ni }),
        ];
        let mut accessors = vec![
            json!({ "bufferView": 0, "componentType": 5126, "count": self.positions.len(), "type": "VEC3" }),
            json!({ "bufferView": 1, "componentType": 5125, "count": self.indices.len(), "type": "SCALAR" }),
        ];
        let mut attributes = json!({ "POSITION": 0 });
        if let Some(n) = &self.normals {
            views.push(json!({ "buffer": 0, "byteOffset": np + ni, "byteLength": n.len() * 12 }));
            accessors.push(
                json!({ "bufferView": 2, "componentType": 5126, "count": n.len(), "type": "VEC3" }),
            );
            attributes["NORMAL"] = json!(2);
        }
        let mut buffer = buffer;
        buffer["byteLength"] = json!(self.bin().len());
        json!({
            "asset": { "version": "2.0" },
            "buffers": [buffer],
            "bufferViews": views,
            "accessors": accessors,
            "meshes": [{ "primitives": [{ "attributes": attributes, "indices": 1 }] }],
            "nodes": self.nodes,
            "scenes": self.scenes,
        })
    }

    /// The `.gltf` text with the buffer in a data URI.
    fn gltf(&self) -> String {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(self.bin())
        );
        self.json(json!({ "uri": uri })).to_string()
    }

    /// The `.glb` bytes (glTF 2.0 section 4.4): header, JSON chunk, BIN chunk, each chunk
    /// padded to 4 bytes.
    fn glb(&self) -> Vec<u8> {
        let mut js = self.json(json!({})).to_string().into_bytes();
        js.resize(js.len().div_ceil(4) * 4, b' ');
        let mut bin = self.bin();
        bin.resize(bin.len().div_ceil(4) * 4, 0);
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend((12 + 8 + js.len() + 8 + bin.len()).to_le_bytes()[..4].iter());
        out.extend((js.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(js);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }
}

/// Reads a glTF document from bytes; buffer files are never read.
fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport)> {
    let none = |_: &Path| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
    crate::geometry::gltf::parse_gltf(Path::new("m.gltf"), bytes, &none)
}

#[test]
fn a_normal_count_unlike_the_position_count_names_both_accessors_and_counts() {
    let mut doc = Doc::triangle();
    doc.normals = Some(vec![[0.0, 0.0, 1.0]; 2]);
    assert_input_err(
        read(doc.gltf().as_bytes()),
        None,
        "mesh 0 primitive 0: POSITION accessor 0 has 3 elements but NORMAL accessor 2 has 2: they must match",
    );
}

/// A whole `.glb` whose header's length field is smaller than its chunks was "truncated: the
/// file was cut short"; it says the field is wrong. A file really cut short still says so.
#[test]
fn a_glb_length_field_short_of_its_chunks_is_named_wrong_not_truncated() {
    let glb = Doc::triangle().glb();
    assert!(read(&glb).is_ok());
    let with_length = |n: u32| {
        let mut b = glb.clone();
        b[8..12].copy_from_slice(&n.to_le_bytes());
        b
    };
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let all = glb.len();
    // Inside the JSON chunk; at the JSON chunk's end, leaving the BIN chunk out; at 0.
    for n in [40, 12 + 8 + json_len, 0] {
        assert_input_err(
            read(&with_length(n as u32)),
            None,
            &format!(
                ".glb's header says {n} bytes but its chunks need {all}: the length field is wrong"
            ),
        );
    }
    // Cut short with the header unchanged; cut inside the BIN chunk's header or its data
    // with the length field rewritten to match the cut file.
    let bin_at = 12 + 8 + json_len;
    let cases: [(Vec<u8>, &str); 4] = [
        (glb[..all - 8].to_vec(), "truncated .glb: its header says"),
        (
            b"glTF\x02\x00\x00\x00\x10\x00\x00\x00".to_vec(),
            "truncated .glb",
        ),
        (
            glb[..bin_at + 4].to_vec(),
            "truncated .glb: its BIN chunk header is incomplete",
        ),
        (
            glb[..all - 8].to_vec(),
            "truncated .glb: its BIN chunk says",
        ),
    ];
    for (k, (mut b, needle)) in cases.into_iter().enumerate() {
        if k >= 2 {
            let n = b.len() as u32;
            b[8..12].copy_from_slice(&n.to_le_bytes());
        }
        let e = read(&b).unwrap_err().to_string();
        assert!(
            e.contains(needle) && e.contains("cut short"),
            "{needle}: {e}"
        );
        assert!(!e.contains("length field"), "{e}");
    }
}

/// `extras` may be any JSON value (glTF 2.0 section 3.12, "Application-specific data"; the
/// schema's `extras` has no type), not only an object: each was "not a glTF 2.0 document".
#[test]
fn extras_of_every_json_type_are_accepted_wherever_extras_may_be() {
    let doc = Doc::triangle();
    let (want, _) = read(doc.gltf().as_bytes()).unwrap();
    for extras in [
        json!(1.5),
        json!("a note"),
        json!([1, "two", null]),
        json!(null),
        json!(true),
        json!({ "k": [] }),
    ] {
        let mut v: Value = serde_json::from_str(&doc.gltf()).unwrap();
        v["extras"] = extras.clone();
        v["asset"]["extras"] = extras.clone();
        for list in [
            "buffers",
            "bufferViews",
            "accessors",
            "meshes",
            "nodes",
            "scenes",
        ] {
            for o in v[list].as_array_mut().unwrap() {
                o["extras"] = extras.clone();
            }
        }
        v["meshes"][0]["primitives"][0]["extras"] = extras.clone();
        let (got, _) = read(v.to_string().as_bytes()).unwrap_or_else(|e| panic!("{extras}: {e}"));
        assert_eq!(got.positions, want.positions, "{extras}");
    }
}

/// A scene's `nodes` is optional (glTF 2.0 section 5.26: not in the required list); a scene
/// `{}` was "not a glTF 2.0 document: missing field `nodes`". The scene drawn is chosen as
/// before (the default, else the first): an empty one has no geometry and says so, another
/// one is drawn, and an error elsewhere in the file keeps its line.
#[test]
fn a_scene_without_nodes_is_a_scene_that_places_nothing() {
    let mut doc = Doc::triangle();
    doc.scenes = json!([{}]);
    assert_input_err(
        read(doc.gltf().as_bytes()),
        None,
        "no triangles: scene 0 places no mesh with triangle primitives",
    );
    doc.scenes = json!([{ "name": "empty", "extras": 3 }, { "nodes": [0] }]);
    let mut v: Value = serde_json::from_str(&doc.gltf()).unwrap();
    v["scene"] = json!(1);
    let (mesh, report) = read(v.to_string().as_bytes()).unwrap();
    assert_eq!(mesh.triangle_count(), 1);
    assert_eq!(report.input.scene.unwrap().scene.index, 1);
    // Pretty-printed, with an accessor whose count is a string: the error's line is that
    // accessor's line of the file.
    v["accessors"][1]["count"] = json!("three");
    let text = serde_json::to_string_pretty(&v).unwrap();
    let line = 1 + text[..text.find("\"count\": \"three\"").unwrap()]
        .matches('\n')
        .count();
    match read(text.as_bytes()) {
        Err(Error::Input {
            line: Some(l),
            message,
            ..
        }) => {
            assert!(message.contains("not a glTF 2.0 document"), "{message}");
            assert!(!message.contains("nodes"), "{message}");
            assert_eq!(l, line, "the error's line and the accessor's");
        }
        other => panic!("{other:?}"),
    }
}

/// A folder tree for the buffer URI rule: `root/outside.bin` (a good buffer, outside), and
/// `root/a/b/` the `.gltf`'s folder with `sub/inside.bin` (a good buffer, inside).
struct Tree {
    _dir: tempfile::TempDir,
    root: PathBuf,
    folder: PathBuf,
    doc: Doc,
}

impl Tree {
    fn new() -> Tree {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().canonicalize().unwrap();
        let folder = root.join("a/b");
        std::fs::create_dir_all(folder.join("sub")).unwrap();
        let doc = Doc::triangle();
        std::fs::write(root.join("outside.bin"), doc.bin()).unwrap();
        std::fs::write(folder.join("sub/inside.bin"), doc.bin()).unwrap();
        Tree {
            _dir: dir,
            root,
            folder,
            doc,
        }
    }

    /// Loads `m.gltf` of the folder, its buffer at `uri`, from another thread: `None` when it
    /// takes more than 10 s (a read that blocks).
    fn load(&self, uri: &str) -> Option<Result<(Mesh, LoadReport)>> {
        let path = self.folder.join("m.gltf");
        std::fs::write(&path, self.doc.json(json!({ "uri": uri })).to_string()).unwrap();
        let (send, recv) = std::sync::mpsc::channel();
        // A reply after the deadline has no one to go to: dropped.
        std::thread::spawn(move || drop(send.send(load_mesh(&path))));
        recv.recv_timeout(std::time::Duration::from_secs(10)).ok()
    }

    #[track_caller]
    fn refused(&self, uri: &str, needles: &[&str]) {
        let e = match self.load(uri) {
            None => panic!("{uri}: still reading after 10 s"),
            Some(Ok(_)) => panic!("{uri}: read"),
            Some(Err(e)) => e.to_string(),
        };
        for n in needles
            .iter()
            .chain(&[format!("{uri:?}").as_str(), BUFFER_RULE])
        {
            assert!(e.contains(n), "{uri}: {n:?} not in: {e}");
        }
    }
}

/// The rule (docs/scenes.md): a buffer is read from a regular file inside the `.gltf`'s folder
/// (or a folder under it), its URI taken after %-decoding and its links resolved. Each of
/// these was read (the last as "the data is cut short": /etc/passwd).
#[test]
fn a_buffer_uri_outside_the_gltf_folder_is_refused() {
    let t = Tree::new();
    for uri in [
        "sub/inside.bin",
        "%73ub/inside.bin",
        "./sub/../sub/inside.bin",
    ] {
        let (mesh, _) = t
            .load(uri)
            .unwrap()
            .unwrap_or_else(|e| panic!("{uri}: {e}"));
        assert_eq!(mesh.triangle_count(), 1);
    }
    let outside = "leads outside the .gltf's folder";
    t.refused("../../outside.bin", &[outside]);
    t.refused("sub/../../../outside.bin", &[outside]);
    t.refused(
        "..%2F..%2Foutside.bin",
        &[outside, "\"../../outside.bin\" once %-decoded"],
    );
    t.refused("%2E%2E/%2e%2e/outside.bin", &[outside]);
    t.refused("../../../../../../etc/passwd", &[outside]);
    let abs = t.root.join("outside.bin").display().to_string();
    t.refused(&abs, &["an absolute path"]);
    t.refused(&format!("file://{abs}"), &["a file: URI"]);
    t.refused(&format!("file:{abs}"), &["a file: URI"]);
    // A link beside the .gltf to a file outside, and a link to a folder outside.
    std::os::unix::fs::symlink(t.root.join("outside.bin"), t.folder.join("link.bin")).unwrap();
    std::os::unix::fs::symlink(&t.root, t.folder.join("up")).unwrap();
    t.refused(
        "link.bin",
        &[&format!("resolves to {abs}, outside the .gltf's folder")],
    );
    t.refused(
        "up/outside.bin",
        &[&format!("resolves to {abs}, outside the .gltf's folder")],
    );
    // A link inside the folder to a file inside it is read.
    std::os::unix::fs::symlink("sub/inside.bin", t.folder.join("in.bin")).unwrap();
    assert!(t.load("in.bin").unwrap().is_ok());
}

/// A FIFO blocked the read for ever (a directory and a device were refused, a FIFO was not);
/// anything but a regular file is refused before it is read, link or not.
#[test]
fn a_buffer_uri_naming_anything_but_a_regular_file_is_refused_without_blocking() {
    let t = Tree::new();
    let fifo = std::ffi::CString::new(t.folder.join("fifo.bin").to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path; mkfifo only creates the file.
    assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
    std::os::unix::fs::symlink("fifo.bin", t.folder.join("to-fifo.bin")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", t.folder.join("zero.bin")).unwrap();
    t.refused("fifo.bin", &["a FIFO, not a regular file"]);
    t.refused("to-fifo.bin", &["a FIFO, not a regular file"]);
    t.refused("sub", &["a folder, not a regular file"]);
    t.refused(
        "zero.bin",
        &["resolves to /dev/zero, outside the .gltf's folder"],
    );
}

/// Largest componentwise difference of two lists of the same length.
fn max_diff(a: &[[f32; 3]], b: &[[f32; 3]]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (x[k] - y[k]).abs()))
        .fold(0.0, f32::max)
}

/// The fit to the unit sphere cancels any translation and uniform scale, so a node far from
/// the origin draws the untranslated mesh. World positions were rounded to f32 before the fit:
/// 1e5 moved every vertex by up to 1/128 of the sphere's size, 1e7 dropped most triangles as
/// zero-area, 1e30 left one point. The world transform is now composed and the soup fitted in
/// f64 (translations summed exactly), rounded to f32 once.
#[test]
fn a_far_node_translation_or_a_large_scale_gives_the_untranslated_fitted_mesh() {
    // 144 triangles, no normals in the file (computed from the world positions).
    let sphere = Generator::UvSphere {
        segments: 12,
        rings: 7,
    }
    .build()
    .unwrap();
    let mut doc = Doc::of(&sphere);
    let (want, report) = read(doc.gltf().as_bytes()).unwrap();
    assert_eq!((report.triangles, report.dropped_zero_area), (144, 0));
    // One f32 step at 1 (the fitted radius): each of the two roundings, in f64 and to f32.
    let tol = f32::EPSILON;
    let check = |doc: &Doc, what: &str, want: &Mesh| {
        let (got, r) = read(doc.gltf().as_bytes()).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(
            (r.triangles, r.dropped_zero_area),
            (144, 0),
            "{what}: {r:?}"
        );
        let (dp, dn) = (
            max_diff(&got.positions, &want.positions),
            max_diff(&got.normals, &want.normals),
        );
        assert!(
            dp <= tol && dn <= tol,
            "{what}: positions {dp}, normals {dn}"
        );
    };
    for node in [
        json!({ "translation": [1e5, -2e5, 3e5] }),
        json!({ "translation": [1e7, 1e7, -1e7] }),
        json!({ "translation": [1e30, 0, -1e30] }),
        json!({ "scale": [1e30, 1e30, 1e30] }),
        json!({ "scale": [1e-30, 1e-30, 1e-30], "translation": [1e20, 0, 0] }),
        json!({ "matrix": [1e20, 0, 0, 0, 0, 1e20, 0, 0, 0, 0, 1e20, 0, 3e37, 1e30, 5, 1] }),
    ] {
        let mut n = node.clone();
        n["mesh"] = json!(0);
        doc.nodes = json!([n]);
        check(&doc, &node.to_string(), &want);
    }
    // Two children of a node 1e30 away, 3 apart: the same as without the parent's translation
    // (each child's offset survives the parent's, a sum f64 alone would round away).
    doc.nodes = json!([
        { "children": [1, 2] },
        { "mesh": 0 },
        { "mesh": 0, "translation": [3, 0, 0] },
    ]);
    let (near, r) = read(doc.gltf().as_bytes()).unwrap();
    assert_eq!(r.triangles, 288);
    doc.nodes[0]["translation"] = json!([1e30, -1e30, 1e30]);
    let (far, r) = read(doc.gltf().as_bytes()).unwrap();
    assert_eq!((r.triangles, r.dropped_zero_area), (288, 0), "{r:?}");
    let dp = max_diff(&far.positions, &near.positions);
    assert!(dp <= tol, "children of a far node: positions {dp}");
}
