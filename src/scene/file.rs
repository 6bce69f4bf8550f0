//! The TOML scene file: parsing with spans, validation with `file:line` errors, and the
//! scene for a bare mesh file ([`scene_for_mesh`]).
use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;
use serde::Deserialize;
use toml::Spanned;

use super::*;
use crate::error::{Error, Result};
use crate::geometry::{fit_unit, load_mesh, Generator, LoadReport, Mesh};

/// A scene for a bare mesh file (`--mesh FILE`: OBJ, glTF 2.0 or PLY): the fitted mesh,
/// [`fit_camera`] at [`DEFAULT_FOV_Y_DEG`], the default light and material, 512 x 512,
/// screen-linear interpolation. Named after the file stem. Errors are [`load_mesh`]'s.
pub fn scene_for_mesh(path: &Path) -> Result<Scene> {
    let (mesh, report) = load_mesh(path)?;
    Ok(scene_for_loaded(file_stem(path), mesh, report))
}

/// [`scene_for_mesh`] of a mesh already read (an upload to `explore`, never on the disk).
pub fn scene_for_loaded(name: String, mesh: Mesh, report: LoadReport) -> Scene {
    let (width, height) = (DEFAULT_IMAGE_SIZE, DEFAULT_IMAGE_SIZE);
    Scene {
        name,
        mesh,
        mesh_report: Some(report),
        camera: fit_camera(DEFAULT_FOV_Y_DEG, width as f64 / height as f64),
        lights: vec![DirectionalLight::default()],
        material: Material::default(),
        width,
        height,
        interpolation: Interpolation::default(),
        cull: Cull::default(),
    }
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned())
}

// ---------------------------------------------------------------------------------------------
// The TOML file as written, every value with its byte span for error lines.
// ---------------------------------------------------------------------------------------------
type Vec3 = Spanned<[f64; 3]>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    name: Option<String>,
    mesh: Option<Spanned<MeshField>>,
    camera: Option<Spanned<CameraFile>>,
    light: Option<Spanned<Vec<Spanned<LightFile>>>>,
    material: Option<MaterialFile>,
    image: Option<ImageFile>,
    render: Option<RenderFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    eye: Option<Vec3>,
    target: Option<Vec3>,
    up: Option<Vec3>,
    fov_y_deg: Option<Spanned<f64>>,
    near: Option<Spanned<f64>>,
    far: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    #[serde(rename = "type")]
    kind: Option<Spanned<String>>,
    // Optional here so that a missing one is reported at its own [[light]] (toml points serde's
    // "missing field" at the first one).
    direction: Option<Vec3>,
    color: Option<Vec3>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialFile {
    ambient: Option<Vec3>,
    diffuse: Option<Vec3>,
    specular: Option<Vec3>,
    shininess: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ImageFile {
    width: Option<Spanned<u32>>,
    height: Option<Spanned<u32>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderFile {
    interpolation: Option<Interpolation>,
    cull: Option<Cull>,
}

/// `mesh = "FILE"`, or the `[mesh]` table. The table is kept generic: `file` (or `obj`) and
/// the generators' keys share it, which serde's `flatten` cannot combine with
/// `deny_unknown_fields`.
enum MeshField {
    File(String),
    Table(BTreeMap<Spanned<String>, Spanned<toml::Value>>),
}

impl<'de> Deserialize<'de> for MeshField {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Either;
        impl<'de> serde::de::Visitor<'de> for Either {
            type Value = MeshField;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a mesh file path (mesh = \"FILE\") or a [mesh] table")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<MeshField, E> {
                Ok(MeshField::File(v.to_owned()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> std::result::Result<MeshField, A::Error> {
                BTreeMap::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(MeshField::Table)
            }
        }
        d.deserialize_any(Either)
    }
}

/// Turns byte offsets into `file:line` errors.
struct Source<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    /// 1-based line of byte `offset`.
    fn line(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        1 + self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    fn at<T>(&self, spanned: &Spanned<T>, msg: impl Into<String>) -> Error {
        Error::input(self.path, Some(self.line(spanned.span().start)), msg)
    }

    fn toml_error(&self, e: &toml::de::Error) -> Error {
        // Multi-line parser messages ("invalid string\nexpected ...") read better on one line.
        let msg = e.message().trim().replace('\n', "; ");
        Error::input(self.path, e.span().map(|s| self.line(s.start)), msg)
    }
}

pub(crate) fn dvec(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// A vector's value, checked finite.
fn finite_vec(src: &Source, v: &Vec3, key: &str) -> Result<DVec3> {
    let d = dvec(*v.get_ref());
    if !d.is_finite() {
        return Err(src.at(
            v,
            format!("{key} = {:?} must be finite (no nan or inf)", v.get_ref()),
        ));
    }
    Ok(d)
}

/// `v` scaled to unit length, and its length, without overflow: glam's `normalize` squares the
/// components, so a finite `[0, -1e308, 1]` came out as `[0, -0, 0]` (found by the fuzz
/// harness). Dividing by the largest component first keeps the squares finite. `None` for zero.
fn unit_and_length(v: DVec3) -> Option<(DVec3, f64)> {
    let m = v.abs().max_element();
    (m > 0.0).then(|| {
        let s = v / m;
        (s.normalize(), m * s.length())
    })
}

/// A colour: finite, every channel >= 0; `default` when absent.
fn colour(src: &Source, v: &Option<Vec3>, key: &str, default: DVec3) -> Result<DVec3> {
    let Some(v) = v else { return Ok(default) };
    let c = finite_vec(src, v, key)?;
    if c.min_element() < 0.0 {
        return Err(src.at(
            v,
            format!(
                "{key} = {:?} has a negative channel; colours must be >= 0",
                v.get_ref()
            ),
        ));
    }
    Ok(c)
}

/// Loads a scene file (format in the module doc). The mesh is loaded relative to the scene
/// file's folder and fitted to the unit sphere.
///
/// Errors: an unreadable scene or mesh file is [`Error::Io`] naming the path (for the mesh, the
/// resolved one); TOML syntax, unknown keys, wrong types and values out of range are
/// [`Error::Input`] with the scene file's line; mesh problems are [`load_mesh`]'s errors,
/// naming the mesh file and the line or object.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_scene(path, &text, &load_mesh)
}

/// Reads a mesh file named by a scene file (given the path joined to the scene's folder).
pub type MeshLoader<'a> = &'a dyn Fn(&Path) -> Result<(Mesh, LoadReport)>;

/// [`load_scene`] on text already read: `path` names the file in messages and gives the folder
/// the mesh file is relative to; `load` reads that file ([`load_mesh`] for a real scene; the
/// fuzz harness in tests/fuzz.rs passes one that never touches the disk). Errors as
/// [`load_scene`]'s.
pub fn parse_scene(path: &Path, text: &str, load: MeshLoader) -> Result<Scene> {
    let src = Source { path, text };
    let file: SceneFile = toml::from_str(text).map_err(|e| src.toml_error(&e))?;

    let Some(mesh_field) = &file.mesh else {
        return Err(Error::input(
            path,
            None,
            "no mesh: add `mesh = \"FILE\"` (an .obj, .gltf, .glb or .ply file) or a [mesh] table with `generator = \"NAME\"` and its parameters",
        ));
    };
    let (mesh, mesh_report) = match mesh_field.get_ref() {
        MeshField::File(rel) => {
            let (mesh, report) = mesh_file(&src, mesh_field, rel, load)?;
            (mesh, Some(report))
        }
        MeshField::Table(t) => mesh_table(&src, mesh_field.span(), t, load)?,
    };

    let (width, height) = image_size(&src, file.image.as_ref())?;
    let camera = camera(&src, file.camera.as_ref(), width as f64 / height as f64)?;
    let lights = lights(&src, file.light.as_ref())?;
    let material = material(&src, file.material.as_ref())?;
    let interpolation = file
        .render
        .as_ref()
        .and_then(|r| r.interpolation)
        .unwrap_or_default();
    let cull = file
        .render
        .as_ref()
        .and_then(|r| r.cull)
        .unwrap_or_default();

    Ok(Scene {
        name: file.name.unwrap_or_else(|| file_stem(path)),
        mesh,
        mesh_report,
        camera,
        lights,
        material,
        width,
        height,
        interpolation,
        cull,
    })
}

type MeshTable = BTreeMap<Spanned<String>, Spanned<toml::Value>>;

/// The mesh file `rel` (relative to the scene file's folder), read by `load`; an empty path is
/// an error at `at`.
fn mesh_file<T>(
    src: &Source,
    at: &Spanned<T>,
    rel: &str,
    load: MeshLoader,
) -> Result<(Mesh, LoadReport)> {
    if rel.trim().is_empty() {
        return Err(src.at(
            at,
            "the mesh file path is empty: give an .obj, .gltf, .glb or .ply file relative to the scene file",
        ));
    }
    let dir = src.path.parent().unwrap_or(Path::new(""));
    load(&dir.join(rel))
}

/// `[mesh]`: exactly one of `file` (or its older name `obj`), alone, or `generator` (with its
/// parameters).
fn mesh_table(
    src: &Source,
    span: std::ops::Range<usize>,
    entries: &MeshTable,
    load: MeshLoader,
) -> Result<(Mesh, Option<LoadReport>)> {
    let table = Spanned::new(span, ());
    let find = |key: &str| entries.iter().find(|(k, _)| k.get_ref() == key);
    let file = find("file").or_else(|| find("obj"));
    if let (Some((a, _)), Some((b, _))) = (find("file"), find("obj")) {
        let second = if a.span().start > b.span().start {
            a
        } else {
            b
        };
        return Err(src.at(
            second,
            "[mesh] has both `file` and `obj` (the same key, two names); keep `file`",
        ));
    }
    match (file, find("generator")) {
        (Some(_), Some((g, _))) => Err(src.at(g, "[mesh] has both a mesh file and `generator`; keep one")),
        (None, None) => Err(src.at(
            &table,
            "[mesh] needs `file = \"FILE\"` (an .obj, .gltf, .glb or .ply file, relative to the scene file) or `generator = \"NAME\"` with its parameters",
        )),
        (Some((key, value)), None) => {
            if let Some((k, _)) = entries.iter().find(|(k, _)| k != &key) {
                return Err(src.at(
                    k,
                    format!("unknown field `{}` in [mesh]: with `{}`, no other key is allowed", k.get_ref(), key.get_ref()),
                ));
            }
            let Some(rel) = value.get_ref().as_str() else {
                return Err(src.at(value, format!("`{}` must be a string path, found {}", key.get_ref(), value.get_ref().type_str())));
            };
            let (mesh, report) = mesh_file(src, value, rel, load)?;
            Ok((mesh, Some(report)))
        }
        (None, Some((gkey, _))) => {
            let generator = parse_generator(src, &table, entries, gkey)?;
            let mut mesh = generator.build().map_err(|e| src.at(gkey, e.to_string()))?;
            fit_unit(&mut mesh);
            Ok((mesh, None))
        }
    }
}

/// Deserializes the `[mesh]` table as a [`Generator`], pointing errors at the key at fault.
/// Serde reports problems inside an internally tagged enum without a position, so the key is
/// found from the message (unknown field), or by deserializing each key alone next to the
/// tag and seeing which one reproduces the error (wrong type or value).
fn parse_generator(
    src: &Source,
    table: &Spanned<()>,
    entries: &MeshTable,
    gkey: &Spanned<String>,
) -> Result<Generator> {
    let plain = |only: Option<&str>| -> toml::Value {
        toml::Value::Table(
            entries
                .iter()
                .filter(|(k, _)| {
                    only.is_none_or(|o| k.get_ref() == o || k.get_ref() == "generator")
                })
                .map(|(k, v)| (k.get_ref().clone(), v.get_ref().clone()))
                .collect(),
        )
    };
    let key_span = |name: &str| {
        entries
            .iter()
            .find(|(k, _)| k.get_ref() == name)
            .map(|(k, _)| k)
    };
    match Generator::deserialize(plain(None)) {
        Ok(g) => {
            if let Err((key, msg)) = g.check() {
                return Err(src.at(key_span(key).unwrap_or(gkey), msg));
            }
            Ok(g)
        }
        Err(e) => {
            let msg = e.message().to_string();
            if let Some(name) = msg
                .strip_prefix("unknown field `")
                .and_then(|r| r.split('`').next())
            {
                return Err(src.at(key_span(name).unwrap_or(gkey), format!("{msg} (in [mesh])")));
            }
            if msg.starts_with("missing field") {
                return Err(src.at(table, format!("[mesh] generator: {msg}")));
            }
            for (k, _) in entries.iter().filter(|(k, _)| k.get_ref() != "generator") {
                if let Err(alone) = Generator::deserialize(plain(Some(k.get_ref()))) {
                    if alone.message() == msg {
                        return Err(src.at(k, format!("`{}`: {msg}", k.get_ref())));
                    }
                }
            }
            // Unknown generator name, or `generator` not a string.
            Err(src.at(gkey, format!("[mesh] generator: {msg}")))
        }
    }
}

/// `[image]`: both of width and height (each 1 to [`MAX_IMAGE_SIZE`]) or neither (the
/// default square); one alone is an error at its line.
fn image_size(src: &Source, image: Option<&ImageFile>) -> Result<(u32, u32)> {
    let check = |v: &Option<Spanned<u32>>, key: &str| -> Result<u32> {
        let Some(v) = v else {
            return Ok(DEFAULT_IMAGE_SIZE);
        };
        let n = *v.get_ref();
        // The device may allow less than MAX_IMAGE_SIZE: the renderer checks that itself.
        if !(1..=MAX_IMAGE_SIZE).contains(&n) {
            return Err(src.at(
                v,
                format!("image {key} = {n} is out of range: it must be 1 to {MAX_IMAGE_SIZE}"),
            ));
        }
        Ok(n)
    };
    let Some(i) = image else {
        return Ok((DEFAULT_IMAGE_SIZE, DEFAULT_IMAGE_SIZE));
    };
    let size = (check(&i.width, "width")?, check(&i.height, "height")?);
    // Half a size is refused: `width = 64` alone rendered 64 x 512 without a word.
    let half = match (&i.width, &i.height) {
        (Some(w), None) => Some((w, "width", "height")),
        (None, Some(h)) => Some((h, "height", "width")),
        _ => None,
    };
    if let Some((given, key, other)) = half {
        return Err(src.at(
            given,
            format!(
                "[image] gives {key} = {} but no {other}: give both ({DEFAULT_IMAGE_SIZE} x \
                 {DEFAULT_IMAGE_SIZE} is the default only when both are left out)",
                given.get_ref()
            ),
        ));
    }
    Ok(size)
}

/// `[camera]`: missing keys come from [`fit_camera`] with the given (or default) fov.
fn camera(src: &Source, cam: Option<&Spanned<CameraFile>>, aspect: f64) -> Result<Camera> {
    let Some(cam) = cam else {
        return Ok(fit_camera(DEFAULT_FOV_Y_DEG, aspect));
    };
    let c = cam.get_ref();
    let fov = match &c.fov_y_deg {
        Some(f) => {
            let v = *f.get_ref();
            if !(v > 0.0 && v < 180.0) {
                return Err(src.at(f, format!("fov_y_deg = {v} is out of range: it must be between 0 and 180 degrees (exclusive)")));
            }
            v
        }
        None => DEFAULT_FOV_Y_DEG,
    };
    let fitted = fit_camera(fov, aspect);
    let get = |v: &Option<Vec3>, key: &str, default: DVec3| match v {
        Some(v) => finite_vec(src, v, key),
        None => Ok(default),
    };
    let eye = get(&c.eye, "eye", fitted.eye)?;
    let target = get(&c.target, "target", fitted.target)?;
    let up = get(&c.up, "up", fitted.up)?;
    // Point errors at the key the user wrote, else at [camera].
    let at_key = |v: &Option<Vec3>, msg: String| match v {
        Some(v) => src.at(v, msg),
        None => src.at(cam, msg),
    };
    let view = target - eye;
    if view.length() <= 1e-9 {
        return Err(at_key(
            &c.eye,
            format!("eye {eye} and target {target} coincide: the camera has no view direction"),
        ));
    }
    let parallel = match (unit_and_length(view), unit_and_length(up)) {
        (Some((v, _)), Some((u, _))) => v.cross(u).length() < 1e-6,
        _ => true,
    };
    if parallel {
        return Err(at_key(
            &c.up,
            format!(
                "up {up} is zero or parallel to the view direction {}: pick an up vector across it",
                unit_and_length(view).map_or(view, |(v, _)| v)
            ),
        ));
    }
    let clip = |v: &Option<Spanned<f64>>, key: &str| -> Result<Option<f64>> {
        match v {
            Some(s) if !(s.get_ref().is_finite() && *s.get_ref() > 0.0) => {
                Err(src.at(s, format!("{key} = {} must be finite and > 0", s.get_ref())))
            }
            Some(s) => Ok(Some(*s.get_ref())),
            None => Ok(None),
        }
    };
    let camera = Camera {
        eye,
        target,
        up,
        fov_y_deg: fov,
        near: clip(&c.near, "near")?,
        far: clip(&c.far, "far")?,
    };
    let (near, far) = camera.near_far();
    // Finite inputs can still overflow on the way (the pattern the fuzz harness found in light
    // directions; these cases found by review): eye and target 1e308 apart, near * far past
    // f64, a field of view whose tangent is subnormal, an `up` whose cross product with the
    // view direction overflows (glam then normalizes it to zero: finite, but no rotation).
    if !(view_is_orthonormal(&camera) && camera.projection(aspect).is_finite()) {
        return Err(src.at(
            cam,
            format!(
                "the camera's view or projection overflows (eye {eye}, target {target}, up {up}, fov_y_deg = {fov}, near = {near}, far = {far}): use values nearer the unit-sphere scene"
            ),
        ));
    }
    if far <= near {
        let msg = format!("far = {far} must be greater than near = {near}");
        return Err(match (&c.far, &c.near) {
            (Some(f), _) => src.at(f, msg),
            (None, Some(n)) => src.at(n, msg),
            (None, None) => src.at(cam, msg),
        });
    }
    Ok(camera)
}

/// The camera's view matrix is finite and its rotation rows are unit length.
fn view_is_orthonormal(camera: &Camera) -> bool {
    let v = camera.view();
    v.is_finite() && (0..3).all(|i| (v.row(i).truncate().length() - 1.0).abs() < 1e-9)
}

fn lights(
    src: &Source,
    lights: Option<&Spanned<Vec<Spanned<LightFile>>>>,
) -> Result<Vec<DirectionalLight>> {
    let Some(list) = lights else {
        return Ok(vec![DirectionalLight::default()]);
    };
    if list.get_ref().is_empty() {
        return Err(src.at(
            list,
            "`light` is empty: a scene needs at least one light (omit it for the default light)",
        ));
    }
    if list.get_ref().len() > MAX_LIGHTS {
        let extra = &list.get_ref()[MAX_LIGHTS];
        return Err(src.at(
            extra,
            format!(
                "too many lights: {} given, at most {MAX_LIGHTS} are supported",
                list.get_ref().len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(list.get_ref().len());
    for l in list.get_ref() {
        let light = l.get_ref();
        if let Some(kind) = &light.kind {
            if kind.get_ref() != "directional" {
                return Err(src.at(
                    kind,
                    format!(
                        "light type `{}` is not supported: the only type is \"directional\" (point lights are not supported yet)",
                        kind.get_ref()
                    ),
                ));
            }
        }
        let Some(dir) = &light.direction else {
            return Err(src.at(
                l,
                "[[light]] is missing `direction` (towards the light, e.g. [-0.4, 0.5, 1.0])",
            ));
        };
        let d = finite_vec(src, dir, "direction")?;
        let Some((direction, _)) = unit_and_length(d).filter(|&(_, len)| len > 1e-12) else {
            return Err(src.at(
                dir,
                format!(
                    "direction = {:?} has no direction: give a vector towards the light",
                    dir.get_ref()
                ),
            ));
        };
        let color = colour(src, &light.color, "color", DVec3::ONE)?;
        out.push(DirectionalLight { direction, color });
    }
    Ok(out)
}

fn material(src: &Source, m: Option<&MaterialFile>) -> Result<Material> {
    let d = Material::default();
    let Some(m) = m else { return Ok(d) };
    let shininess = match &m.shininess {
        Some(s) => {
            let v = *s.get_ref();
            if !(v.is_finite() && v >= 0.0) {
                return Err(src.at(s, format!("shininess = {v} must be finite and >= 0")));
            }
            v
        }
        None => d.shininess,
    };
    Ok(Material {
        ambient: colour(src, &m.ambient, "ambient", d.ambient)?,
        diffuse: colour(src, &m.diffuse, "diffuse", d.diffuse)?,
        specular: colour(src, &m.specular, "specular", d.specular)?,
        shininess,
    })
}
