//! The glTF 2.0 reader (`.gltf` with its buffers beside it or in data URIs, `.glb`), on the
//! `gltf` crate's JSON types.
//!
//! What is drawn: the default scene (else the first; a file without scenes draws each mesh once,
//! untransformed), every primitive of every mesh its nodes place, at the node's world
//! transform, in f64 until the fit to the unit sphere (so that it cancels a translation of
//! the file's whatever its size: [`Soup`]); normals by the inverse transpose
//! ([`nodes::normal_matrix`]), renormalised.
//! Triangles, strips and fans are read (strips and fans as glTF 2.0 section 3.7.2.1 orders
//! them); points and lines are left out with a note. Positions and normals may be floats or,
//! with `KHR_mesh_quantization`, (normalized) integers. A primitive without normals gets smooth
//! normals as an OBJ without normals does ([`crate::geometry::soup`]), smoothed across vertices
//! at the same position, and the report says so (the glTF specification asks for flat normals
//! there; smooth ones are what a study of normal interpolation needs). Morph targets are
//! applied at their default weights; a skinned mesh is drawn in its bind pose (its vertices as
//! stored), with a note. Extensions: `KHR_mesh_quantization` is read; those that only change
//! appearance (materials, textures, lights, variants) are ignored with a note; any other in
//! `extensionsRequired` is refused, naming it; any other only used is ignored with a note.
//!
//! Every problem is an [`Error::Input`] naming the file and the object (mesh, primitive,
//! accessor, buffer, node), with what to do.
mod accessor;
mod document;
mod nodes;

use std::path::Path;

use ::gltf::json;
use glam::DVec3;
use json::mesh::{Mode, Semantic};
use json::validation::Checked;

use super::mesh_file::{Encoding, Format, MeshInput, Named, NormalSource, Part, ReadFile};
use super::soup::{self, plural, Corner};
use super::{LoadReport, Mesh, MAX_COORDINATE};
use crate::error::{Error, Result};
use accessor::Buffers;
use nodes::{Placement, World};

/// Most triangles a file may draw (4,194,304): 60 times the largest shared model (the Stanford
/// bunny, 69,451), and a bound that keeps a small file placing a large mesh many times from
/// exhausting memory (its corner list stays under 200 MB).
pub const MAX_TRIANGLES: usize = 1 << 22;

/// Extensions read.
const READ: &[&str] = &["KHR_mesh_quantization"];
/// Extensions that only change appearance (the scene's own material and light are used):
/// ignored with a note, even when required.
const APPEARANCE: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_dispersion",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_iridescence",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_variants",
    "KHR_materials_volume",
    "KHR_texture_basisu",
    "KHR_texture_transform",
    "KHR_xmp_json_ld",
    "EXT_texture_avif",
    "EXT_texture_webp",
    "MSFT_texture_dds",
];

/// The container: the JSON document and the `.glb`'s BIN chunk.
struct Container<'b> {
    json: &'b [u8],
    blob: Option<&'b [u8]>,
    encoding: Encoding,
}

/// Splits a `.glb` (glTF 2.0 section 4.4: a 12-byte header, a JSON chunk, an optional BIN
/// chunk) or takes a `.gltf`'s bytes as JSON (a UTF-8 byte order mark skipped).
fn container(bytes: &[u8]) -> std::result::Result<Container<'_>, String> {
    if !bytes.starts_with(b"glTF") {
        let json = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        return Ok(Container {
            json,
            blob: None,
            encoding: Encoding::Json,
        });
    }
    let u32_at = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let cut = |what: &str| {
        format!(
            "truncated .glb: {what} (the file has {} bytes); the file was cut short: export or download it again",
            bytes.len()
        )
    };
    let version = u32_at(4).ok_or_else(|| cut("no room for its 12-byte header"))?;
    if version != 2 {
        return Err(format!(
            "a .glb of container version {version}; shadelab reads glTF 2.0 (version 2)"
        ));
    }
    let length = u32_at(8).ok_or_else(|| cut("no room for its 12-byte header"))? as usize;
    if length > bytes.len() {
        return Err(cut(&format!("its header says {length} bytes")));
    }
    // The chunks are read from the whole file, so that a length field short of them (in a
    // file that holds them whole) is named as what it is, not as a file cut short.
    let chunk = |at: usize,
                 kind: &[u8; 4],
                 name: &str|
     -> std::result::Result<Option<(&[u8], usize)>, String> {
        if at >= bytes.len() || (at >= length && bytes.get(at + 4..at + 8) != Some(kind)) {
            return Ok(None);
        }
        let len = u32_at(at)
            .filter(|_| at + 8 <= bytes.len())
            .ok_or_else(|| cut(&format!("its {name} chunk header is incomplete")))?
            as usize;
        if &bytes[at + 4..at + 8] != kind {
            return Err(format!(
                "the .glb's chunk at byte {at} is {:?}, expected {name}",
                String::from_utf8_lossy(&bytes[at + 4..at + 8])
            ));
        }
        let end = at + 8 + len;
        bytes
            .get(at + 8..end)
            .map(|c| Some((c, end)))
            .ok_or_else(|| cut(&format!("its {name} chunk says {len} bytes")))
    };
    let (json, json_end) = chunk(12, b"JSON", "JSON")?.ok_or_else(|| cut("no JSON chunk"))?;
    // Chunks are padded to 4 bytes (section 4.4.3.1).
    let bin_at = 12 + 8 + json.len().div_ceil(4) * 4;
    let bin = chunk(bin_at, b"BIN\0", "BIN")?;
    let need = bin.map_or(json_end, |(_, end)| end);
    if need > length {
        return Err(format!(
            "the .glb's header says {length} bytes but its chunks need {need}: the length field is wrong (the file holds its chunks whole, {} bytes); re-export the file",
            bytes.len()
        ));
    }
    let blob = bin.map(|(b, _)| b);
    Ok(Container {
        json,
        blob,
        encoding: Encoding::Glb,
    })
}

/// Reads a glTF 2.0 file (module doc). `read` reads the files its buffers name, resolved
/// against `path`'s folder.
pub fn parse_gltf(path: &Path, bytes: &[u8], read: ReadFile) -> Result<(Mesh, LoadReport)> {
    let err = |msg: String| Error::input(path, None, msg);
    let c = container(bytes).map_err(err)?;
    let root: json::Root = document::parse(c.json).map_err(|e| {
        if let Some(v) = asset_version(c.json).filter(|v| !v.starts_with("2.")) {
            return err(format!(
                "a glTF {v} file; shadelab reads glTF 2.0: convert it first (e.g. import and export it in Blender)"
            ));
        }
        let msg = format!("not a glTF 2.0 document: {e}");
        match c.encoding {
            Encoding::Json => Error::input(path, Some(e.line().max(1)), msg),
            _ => err(format!("{msg} (in the .glb's JSON chunk)")),
        }
    })?;
    if let Some(v) = Some(&root.asset.version).filter(|v| !v.starts_with("2.")) {
        return Err(err(format!(
            "its asset.version is {v:?}; shadelab reads glTF 2.0 (\"2.0\")"
        )));
    }
    let mut notes = extension_notes(&root).map_err(err)?;
    let (scene, placements) = nodes::placements(&root).map_err(err)?;
    let mut buffers = Buffers::new(&root, c.blob, path, bytes.len(), read);
    let mut soup = Soup::default();
    let mut parts = Vec::new();
    for p in &placements {
        read_placement(&root, &mut buffers, p, &mut soup, &mut parts, &mut notes).map_err(err)?;
    }
    if soup.triangles.is_empty() {
        return Err(err(match &scene {
            Some(s) => format!(
                "no triangles: scene {} places no mesh with triangle primitives; pick a file with meshes",
                s.scene
            ),
            None => "no triangles: the file has no scene and no mesh with triangle primitives".into(),
        }));
    }
    finish(path, soup, scene, parts, c.encoding, notes)
}

/// `asset.version` of a JSON document that did not parse as glTF 2.0 (a glTF 1.0 file, whose
/// objects are maps, fails there first).
fn asset_version(json: &[u8]) -> Option<String> {
    let v: serde_json::Value = serde_json::from_slice(json).ok()?;
    v.get("asset")?.get("version")?.as_str().map(str::to_owned)
}

/// The corners of every primitive read so far: positions in world space less `origin`, in
/// f64 until the fit.
#[derive(Default)]
struct Soup {
    /// The first placement's translation (its two parts, [`nodes::World`]): subtracted from
    /// every world position, so that a single placement's vertices are its linear part times
    /// the model positions, whatever its translation, and the others keep their offsets from
    /// it.
    origin: Option<(DVec3, DVec3)>,
    positions: Vec<DVec3>,
    normals: Vec<[f32; 3]>,
    triangles: Vec<[Corner; 3]>,
}

/// The notes on the file's extensions (module doc); an error for a required one not read.
fn extension_notes(root: &json::Root) -> std::result::Result<Vec<String>, String> {
    let refused: Vec<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|e| !READ.contains(e) && !APPEARANCE.contains(e))
        .collect();
    if !refused.is_empty() {
        return Err(format!(
            "the file requires {} ({}), which shadelab does not read; export it without {} (e.g. Blender, or gltf-transform)",
            plural(refused.len(), "extension", "extensions"),
            refused.join(", "),
            if refused.len() == 1 { "it" } else { "them" },
        ));
    }
    let mut notes = Vec::new();
    let appearance: Vec<&str> = root
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|e| APPEARANCE.contains(e))
        .collect();
    if !appearance.is_empty() {
        notes.push(format!(
            "ignored {} ({}): appearance only; the scene's own material and light are used",
            plural(appearance.len(), "extension", "extensions"),
            appearance.join(", ")
        ));
    }
    let other: Vec<&str> = root
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|e| !READ.contains(e) && !APPEARANCE.contains(e))
        .collect();
    if !other.is_empty() {
        notes.push(format!(
            "ignored {} ({}): used but not required; read the core glTF data they fall back to",
            plural(other.len(), "extension", "extensions"),
            other.join(", ")
        ));
    }
    if !root.animations.is_empty() {
        notes.push(format!(
            "ignored {}: drawn in the nodes' own transforms",
            plural(root.animations.len(), "animation", "animations")
        ));
    }
    Ok(notes)
}

/// A primitive's vertex data in model space.
struct Vertices {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
}

/// Reads the primitives of the mesh `p` places into `soup`, one [`Part`] each.
fn read_placement(
    root: &json::Root,
    buffers: &mut Buffers,
    p: &Placement,
    soup: &mut Soup,
    parts: &mut Vec<Part>,
    notes: &mut Vec<String>,
) -> std::result::Result<(), String> {
    let mesh = root.meshes.get(p.mesh).ok_or_else(|| {
        let at = p
            .node
            .as_ref()
            .map(|n| format!("node {n} places "))
            .unwrap_or_default();
        format!(
            "{at}mesh {}, but the file has {} meshes",
            p.mesh,
            root.meshes.len()
        )
    })?;
    let named = Named {
        index: p.mesh,
        name: mesh.name.clone(),
    };
    let mut world = p.world;
    if let Some(skin) = p.skin {
        notes.push(format!(
            "node {}: skin {skin} ignored, mesh {named} drawn in its bind pose (its vertices as stored)",
            p.node.as_ref().map_or(String::new(), ToString::to_string)
        ));
        // glTF 2.0 section 3.7.3.1: a skinned mesh's node transform is not applied.
        world = None;
    }
    for (pi, prim) in mesh.primitives.iter().enumerate() {
        let at = format!("mesh {named} primitive {pi}");
        let mode = match prim.mode {
            Checked::Valid(m) => m,
            Checked::Invalid => return Err(format!("{at}: its mode is not one glTF 2.0 defines")),
        };
        if matches!(
            mode,
            Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
        ) {
            notes.push(format!(
                "{at}: left out, it draws {mode:?} (only triangles, strips and fans are drawn)"
            ));
            continue;
        }
        let weights = p.weights.as_ref().or(mesh.weights.as_ref());
        let v = vertices(buffers, prim, weights, notes, &at)?;
        let corners = match prim.indices {
            Some(i) => buffers
                .indices(i.value())
                .map_err(|e| format!("{at}: indices: {e}"))?,
            None => (0..v.positions.len() as u32).collect(),
        };
        if let Some((k, &bad)) = corners
            .iter()
            .enumerate()
            .find(|(_, &c)| c as usize >= v.positions.len())
        {
            return Err(format!(
                "{at}: index {bad} (element {k} of accessor {}) is past its {} vertices: the file is damaged; re-export it",
                prim.indices.map_or(0, |i| i.value()),
                v.positions.len()
            ));
        }
        let tris = triangles(mode, &corners);
        if soup.triangles.len() + tris.len() > MAX_TRIANGLES {
            return Err(format!(
                "{at}: the scene draws more than {MAX_TRIANGLES} triangles, shadelab's limit; draw fewer (decimate the mesh, or keep one node)"
            ));
        }
        parts.push(Part {
            node: p.node.clone(),
            mesh: named.clone(),
            primitive: pi,
            triangles: tris.len(),
            normals: if v.normals.is_some() {
                NormalSource::File
            } else {
                NormalSource::Computed
            },
        });
        place(soup, v, &tris, world.as_ref());
    }
    Ok(())
}

/// The triangles of `corners` drawn in `mode` (glTF 2.0 section 3.7.2.1): lists by threes (a
/// remainder left out), strips alternating their order so every triangle keeps the winding,
/// fans around the first vertex.
fn triangles(mode: Mode, corners: &[u32]) -> Vec<[u32; 3]> {
    let n = corners.len();
    match mode {
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                let (a, b) = if i % 2 == 0 {
                    (i + 1, i + 2)
                } else {
                    (i + 2, i + 1)
                };
                [corners[i], corners[a], corners[b]]
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [corners[i], corners[i + 1], corners[0]])
            .collect(),
        _ => corners
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
    }
}

/// A primitive's positions and normals, morph targets applied at `weights`, checked finite.
fn vertices(
    buffers: &mut Buffers,
    prim: &json::mesh::Primitive,
    weights: Option<&Vec<f32>>,
    notes: &mut Vec<String>,
    at: &str,
) -> std::result::Result<Vertices, String> {
    let attr = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
    let pa = attr(Semantic::Positions)
        .ok_or_else(|| format!("{at} has no POSITION attribute: a primitive needs positions"))?;
    let mut positions = buffers
        .vecs::<3>(pa)
        .map_err(|e| format!("{at}: POSITION: {e}"))?;
    let mut normals = match attr(Semantic::Normals) {
        Some(na) => {
            let n = buffers
                .vecs::<3>(na)
                .map_err(|e| format!("{at}: NORMAL: {e}"))?;
            if n.len() != positions.len() {
                return Err(format!(
                    "{at}: POSITION accessor {pa} has {} but NORMAL accessor {na} has {}: they must match (a vertex has one of each); the file is damaged, re-export it",
                    plural(positions.len(), "element", "elements"),
                    n.len()
                ));
            }
            Some(n)
        }
        None => None,
    };
    let targets = prim.targets.as_deref().unwrap_or_default();
    let active: Vec<(usize, f32)> = match weights {
        Some(w) if w.len() != targets.len() => {
            return Err(format!(
                "{at}: {} morph weights for {} morph targets",
                w.len(),
                targets.len()
            ))
        }
        Some(w) => w
            .iter()
            .copied()
            .enumerate()
            .filter(|&(_, w)| w != 0.0)
            .collect(),
        None => Vec::new(),
    };
    if !targets.is_empty() {
        notes.push(format!(
            "{at}: {} of {} applied at the default weights",
            active.len(),
            plural(targets.len(), "morph target", "morph targets")
        ));
    }
    for (t, w) in active {
        let target = &targets[t];
        let mut add =
            |acc: Option<json::Index<json::Accessor>>, to: &mut Vec<[f32; 3]>, what: &str| {
                let Some(a) = acc else { return Ok(()) };
                let d = buffers
                    .vecs::<3>(a.value())
                    .map_err(|e| format!("{at}: morph target {t} {what}: {e}"))?;
                if d.len() != to.len() {
                    return Err(format!(
                        "{at}: morph target {t} {what} has {} elements for {} vertices",
                        d.len(),
                        to.len()
                    ));
                }
                for (v, d) in to.iter_mut().zip(&d) {
                    *v = std::array::from_fn(|k| v[k] + w * d[k]);
                }
                Ok(())
            };
        add(target.positions, &mut positions, "POSITION")?;
        if let Some(n) = normals.as_mut() {
            add(target.normals, n, "NORMAL")?;
        }
    }
    for (what, list) in [("POSITION", Some(&positions)), ("NORMAL", normals.as_ref())] {
        if let Some((i, v)) = list
            .into_iter()
            .flatten()
            .enumerate()
            .find(|(_, v)| !v.iter().all(|c| c.is_finite()))
        {
            return Err(format!(
                "{at}: {what} of vertex {i} is {v:?}, not finite: fix the exporter's output"
            ));
        }
    }
    Ok(Vertices { positions, normals })
}

/// Appends a primitive to the soup at `world` (positions in f64 relative to the soup's origin,
/// rounded to f32 once, by the fit; normals by the normal matrix; a mirroring transform
/// reverses each triangle to keep its winding).
fn place(soup: &mut Soup, v: Vertices, tris: &[[u32; 3]], world: Option<&World>) {
    let base = soup.positions.len();
    let nbase = soup.normals.len();
    let has_normals = v.normals.is_some();
    let (t, r) = world.map_or((DVec3::ZERO, DVec3::ZERO), |w| (w.translation, w.residual));
    let (ot, or) = *soup.origin.get_or_insert((t, r));
    // Exact for the first placement (zero); for others their offset from it, its large parts
    // cancelling first.
    let offset = (t - ot) + (r - or);
    let model = v.positions.iter().map(|p| DVec3::from(p.map(f64::from)));
    match world {
        // Untransformed at the origin: the file's positions as they are (-0 kept).
        None if offset == DVec3::ZERO => {
            soup.positions.extend(model);
            soup.normals.extend(v.normals.iter().flatten());
        }
        None => {
            soup.positions.extend(model.map(|p| p + offset));
            soup.normals.extend(v.normals.iter().flatten());
        }
        Some(w) => {
            let nm = nodes::normal_matrix(&w.linear);
            soup.positions.extend(model.map(|p| w.linear * p + offset));
            soup.normals.extend(v.normals.iter().flatten().map(|n| {
                let t = nm * DVec3::from(n.map(f64::from));
                // A normal the transform collapses stays zero: computed instead (soup).
                let len = t.length();
                if len > 0.0 && len.is_finite() {
                    (t / len).as_vec3().to_array()
                } else {
                    [0.0; 3]
                }
            }));
        }
    }
    let mirror = world.is_some_and(|w| nodes::mirrors(&w.linear));
    for t in tris {
        let t = if mirror { [t[0], t[2], t[1]] } else { *t };
        soup.triangles.push(t.map(|i| Corner {
            position: base + i as usize,
            normal: has_normals.then_some(nbase + i as usize),
        }));
    }
}

/// The fitted mesh of the soup and its report.
fn finish(
    path: &Path,
    soup: Soup,
    scene: Option<super::mesh_file::DrawnScene>,
    parts: Vec<Part>,
    encoding: Encoding,
    mut notes: Vec<String>,
) -> Result<(Mesh, LoadReport)> {
    // Node scales multiplied along a chain can take positions past what the fit computes in.
    if let Some(p) = soup
        .positions
        .iter()
        .find(|p| !p.is_finite() || p.abs().max_element() > MAX_COORDINATE)
    {
        return Err(Error::input(
            path,
            None,
            format!(
                "a node's transform takes a position to {:?}, past {MAX_COORDINATE:e} (the nodes' scales multiplied along their chain): fix the nodes' scales",
                p.to_array()
            ),
        ));
    }
    let weld = soup::weld(&soup.positions);
    let lists = soup::Lists {
        positions: &soup.positions,
        normals: &soup.normals,
        smooth_as: Some(&weld),
    };
    let a = soup::assemble(path, lists, &soup.triangles)?;
    let mut warnings = soup::common_notes(a.dropped, &a.counts);
    let computed: Vec<String> = parts
        .iter()
        .filter(|p| p.normals == NormalSource::Computed)
        .map(|p| format!("mesh {} primitive {}", p.mesh, p.primitive))
        .collect();
    if !computed.is_empty() {
        warnings.push(format!(
            "{} without NORMAL: computed smooth normals, smoothed across vertices at the same position ({})",
            plural(computed.len(), "primitive", "primitives"),
            computed.join(", ")
        ));
    }
    warnings.append(&mut notes);
    let report = LoadReport {
        triangles: a.mesh.triangle_count(),
        dropped_zero_area: a.dropped,
        computed_normals: a.counts.computed > 0,
        had_quads_or_polygons: false,
        warnings,
        input: MeshInput {
            format: Format::Gltf,
            encoding,
            scene,
            parts,
        },
    };
    Ok((a.mesh, report))
}
