//! Scenes: the TOML scene format, its validation, and the camera matrices (f64).
//!
//! Owns [`Scene`] (mesh + camera + lights + material + image size + interpolation mode) and
//! [`Camera`]'s view and projection. Invariants of a [`Scene`] built here:
//! - the mesh is fitted to the unit sphere ([`fit_unit`]): bounding box centred at the origin,
//!   bounding sphere radius 1, so camera positions in scene files live in that space whatever
//!   the OBJ's own units;
//! - 1 to [`MAX_LIGHTS`] lights, each direction unit length;
//! - every number finite, colours >= 0, width and height in `1..=`[`MAX_IMAGE_SIZE`].
//!
//! # Scene format
//!
//! ```toml
//! name = "coarse sphere"          # optional, default: the file stem
//!
//! [mesh]                          # required: exactly one of `obj` or `generator`
//! obj = "sphere_coarse.obj"       # path relative to the scene file
//! # or a procedural generator with all of its parameters, e.g.
//! # generator = "torus", major_radius = 1.0, minor_radius = 0.4, major_segments = 48, minor_segments = 24
//! # generator = "uv_sphere", segments = 10, rings = 5
//! # generator = "icosphere", subdivisions = 0
//! # generator = "cube"
//!
//! [camera]                        # optional; every key defaults to the fitted camera
//! eye = [0.0, 0.8, 3.0]           #   default: on normalize(0, 0.3, 1), far enough that the
//! target = [0.0, 0.0, 0.0]        #   unit sphere fills the view with ~5% margin
//! up = [0.0, 1.0, 0.0]
//! fov_y_deg = 35.0                # vertical field of view, in (0, 180)
//! # near = 1.5                    # clip planes; default |eye - target| -/+ 1.5
//! # far = 5.0                     #   (near at least 0.01)
//!
//! [[light]]                       # 1 to 4 lights; default: one white light from [-0.4, 0.5, 1]
//! type = "directional"            # optional; the only type (point lights are not supported yet)
//! direction = [-0.4, 0.5, 1.0]    # world space, from the surface TOWARDS the light; normalized
//! color = [1.0, 1.0, 1.0]         # optional, default white
//!
//! [material]                      # optional; these are the defaults
//! ambient = [0.08, 0.08, 0.08]
//! diffuse = [0.75, 0.55, 0.35]
//! specular = [0.5, 0.5, 0.5]
//! shininess = 50.0                # Phong exponent, >= 0
//!
//! [image]                         # optional; default 512 x 512
//! width = 512
//! height = 512
//!
//! [render]
//! interpolation = "screen_linear" # default (GLSL noperspective), or "perspective"
//! ```
//!
//! Meshes, OBJ or generated, are fitted to the unit sphere on load. Unknown keys, wrong types
//! and values out of range are errors naming `file:line`.
use std::collections::BTreeMap;
use std::path::Path;

use glam::{DMat4, DVec3, DVec4};
use serde::Deserialize;
use toml::Spanned;

use crate::error::{Error, Result};
use crate::mesh::{fit_unit, load_obj, Generator, LoadReport, Mesh};

/// Most lights a scene may have (the shaders' uniform arrays have this size).
pub const MAX_LIGHTS: usize = 4;
/// Largest width or height a scene file may ask for. The device's real limit (often 16384
/// too, but lower on some) is checked by the renderer when it creates the images.
pub const MAX_IMAGE_SIZE: u32 = 16384;
/// Vertical field of view of the fitted camera, degrees.
pub const DEFAULT_FOV_Y_DEG: f64 = 35.0;
/// Width and height when a scene does not say.
pub const DEFAULT_IMAGE_SIZE: u32 = 512;

/// How the rasterizer interpolates vertex outputs across a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Linear in screen space (GLSL `noperspective`), `"screen_linear"`: the default, and
    /// what the normalization papers assume.
    #[default]
    ScreenLinear,
    /// Perspective-correct (GLSL `smooth`), `"perspective"`.
    Perspective,
}

/// A perspective camera in the fitted (unit-sphere) model space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub target: DVec3,
    /// Need not be unit or orthogonal to the view direction, only not parallel to it.
    pub up: DVec3,
    /// Vertical field of view, degrees, in (0, 180).
    pub fov_y_deg: f64,
    /// Near clip distance; `None` = `max(0.01, |eye - target| - 1.5)` (see [`Camera::near_far`]).
    pub near: Option<f64>,
    /// Far clip distance; `None` = `|eye - target| + 1.5`.
    pub far: Option<f64>,
}

/// A light at infinity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalLight {
    /// Unit, world space, pointing from the surface TOWARDS the light.
    pub direction: DVec3,
    /// Linear RGB, >= 0.
    pub color: DVec3,
}

/// Phong material, linear RGB.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    /// Phong exponent, finite and >= 0.
    pub shininess: f64,
}

/// Everything one render needs besides the shading method.
#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    /// Fitted to the unit sphere.
    pub mesh: Mesh,
    /// What loading the OBJ did; `None` for a generated mesh.
    pub mesh_report: Option<LoadReport>,
    pub camera: Camera,
    /// 1 to [`MAX_LIGHTS`].
    pub lights: Vec<DirectionalLight>,
    pub material: Material,
    pub width: u32,
    pub height: u32,
    pub interpolation: Interpolation,
}

impl Default for DirectionalLight {
    /// White, from the upper left in front: direction normalize(-0.4, 0.5, 1).
    fn default() -> Self {
        DirectionalLight {
            direction: DVec3::new(-0.4, 0.5, 1.0).normalize(),
            color: DVec3::ONE,
        }
    }
}

impl Default for Material {
    /// A warm orange-brown with a grey highlight of exponent 50.
    fn default() -> Self {
        Material {
            ambient: DVec3::splat(0.08),
            diffuse: DVec3::new(0.75, 0.55, 0.35),
            specular: DVec3::splat(0.5),
            shininess: 50.0,
        }
    }
}

impl Scene {
    /// `width / height`.
    pub fn aspect(&self) -> f64 {
        self.width as f64 / self.height as f64
    }
}

/// The camera that frames the unit sphere: eye on the direction normalize(0, 0.3, 1) (a little
/// above the equator, looking at the origin, +y up), at the distance where the sphere's
/// silhouette fills the narrower of the vertical and horizontal fields of view up to a 5%
/// margin (its radius on the image plane is 1/1.05 of the half-extent). Clip planes default.
///
/// A non-finite or non-positive `aspect` is taken as 1, and `fov_y_deg` is clamped to
/// [0.001, 179.9] degrees, so the result is always a usable camera.
pub fn fit_camera(fov_y_deg: f64, aspect: f64) -> Camera {
    let fov = if fov_y_deg.is_finite() {
        fov_y_deg.clamp(1e-3, 179.9)
    } else {
        DEFAULT_FOV_Y_DEG
    };
    let aspect = if aspect.is_finite() && aspect > 0.0 {
        aspect
    } else {
        1.0
    };
    let tan_y = (fov.to_radians() * 0.5).tan();
    let tan_half = tan_y.min(tan_y * aspect);
    // A sphere of radius 1 at distance d has a circular silhouette of radius 1/sqrt(d^2 - 1) on
    // the image plane at distance 1; set that to tan_half / 1.05 and solve for d.
    let silhouette = tan_half / 1.05;
    let distance = (1.0 + 1.0 / (silhouette * silhouette)).sqrt();
    Camera {
        eye: DVec3::new(0.0, 0.3, 1.0).normalize() * distance,
        target: DVec3::ZERO,
        up: DVec3::Y,
        fov_y_deg: fov,
        near: None,
        far: None,
    }
}

impl Camera {
    /// `|eye - target|`.
    pub fn distance(&self) -> f64 {
        (self.eye - self.target).length()
    }

    /// The clip distances: the explicit ones, else `near = max(0.01, distance - 1.5)` and
    /// `far = distance + 1.5`, which enclose the fitted unit-sphere mesh with 0.5 to spare
    /// when the camera looks at it.
    pub fn near_far(&self) -> (f64, f64) {
        let d = self.distance();
        (
            self.near.unwrap_or((d - 1.5).max(0.01)),
            self.far.unwrap_or(d + 1.5),
        )
    }

    /// Right-handed look-at view matrix: camera at the origin looking down -z, +y up, +x right.
    /// Assumes `eye != target` and `up` not parallel to the view direction (scene loading
    /// checks both); otherwise the result contains NaN.
    pub fn view(&self) -> DMat4 {
        let f = (self.target - self.eye).normalize();
        let s = f.cross(self.up).normalize();
        let u = s.cross(f);
        DMat4::from_cols(
            DVec4::new(s.x, u.x, -f.x, 0.0),
            DVec4::new(s.y, u.y, -f.y, 0.0),
            DVec4::new(s.z, u.z, -f.z, 0.0),
            DVec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        )
    }

    /// Perspective projection from the right-handed view space into Vulkan clip space: depth
    /// 0 at `near` and 1 at `far`, and y flipped so that view +y lands at the top of the window
    /// (smaller framebuffer y) with an ordinary positive-height viewport. `aspect` is
    /// width / height.
    pub fn projection(&self, aspect: f64) -> DMat4 {
        let (near, far) = self.near_far();
        let t = (self.fov_y_deg.to_radians() * 0.5).tan();
        DMat4::from_cols(
            DVec4::new(1.0 / (aspect * t), 0.0, 0.0, 0.0),
            DVec4::new(0.0, -1.0 / t, 0.0, 0.0),
            DVec4::new(0.0, 0.0, far / (near - far), -1.0),
            DVec4::new(0.0, 0.0, near * far / (near - far), 0.0),
        )
    }
}

/// A scene for a bare OBJ (`--mesh FILE.obj`): the fitted mesh, [`fit_camera`] at
/// [`DEFAULT_FOV_Y_DEG`], the default light and material, 512 x 512, screen-linear
/// interpolation. Named after the file stem. Errors are [`load_obj`]'s.
pub fn scene_for_mesh(path: &Path) -> Result<Scene> {
    let (mesh, report) = load_obj(path)?;
    let (width, height) = (DEFAULT_IMAGE_SIZE, DEFAULT_IMAGE_SIZE);
    Ok(Scene {
        name: file_stem(path),
        mesh,
        mesh_report: Some(report),
        camera: fit_camera(DEFAULT_FOV_Y_DEG, width as f64 / height as f64),
        lights: vec![DirectionalLight::default()],
        material: Material::default(),
        width,
        height,
        interpolation: Interpolation::default(),
    })
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
    /// Kept generic: `obj` and the generators' keys share the table, which serde's `flatten`
    /// cannot combine with `deny_unknown_fields`.
    mesh: Option<Spanned<BTreeMap<Spanned<String>, Spanned<toml::Value>>>>,
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

fn dvec(a: [f64; 3]) -> DVec3 {
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
/// Errors: an unreadable scene or OBJ file is [`Error::Io`] naming the path (for the OBJ, the
/// resolved one); TOML syntax, unknown keys, wrong types and values out of range are
/// [`Error::Input`] with the scene file's line; OBJ problems are [`load_obj`]'s errors, naming
/// the OBJ file and line.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let src = Source { path, text: &text };
    let file: SceneFile = toml::from_str(&text).map_err(|e| src.toml_error(&e))?;

    let Some(mesh_table) = &file.mesh else {
        return Err(Error::input(
            path,
            None,
            "no [mesh] table: add one with `obj = \"FILE.obj\"` or `generator = \"NAME\"` and its parameters",
        ));
    };
    let (mesh, mesh_report) = load_mesh(&src, mesh_table)?;

    let (width, height) = image_size(&src, file.image.as_ref())?;
    let camera = camera(&src, file.camera.as_ref(), width as f64 / height as f64)?;
    let lights = lights(&src, file.light.as_ref())?;
    let material = material(&src, file.material.as_ref())?;
    let interpolation = file
        .render
        .and_then(|r| r.interpolation)
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
    })
}

type MeshTable = Spanned<BTreeMap<Spanned<String>, Spanned<toml::Value>>>;

/// `[mesh]`: exactly one of `obj` (alone) or `generator` (with its parameters).
fn load_mesh(src: &Source, table: &MeshTable) -> Result<(Mesh, Option<LoadReport>)> {
    let entries = table.get_ref();
    let find = |key: &str| entries.iter().find(|(k, _)| k.get_ref() == key);
    match (find("obj"), find("generator")) {
        (Some(_), Some((g, _))) => Err(src.at(g, "[mesh] has both `obj` and `generator`; keep one")),
        (None, None) => Err(src.at(
            table,
            "[mesh] needs `obj = \"FILE.obj\"` (relative to the scene file) or `generator = \"NAME\"` with its parameters",
        )),
        (Some((_, obj)), None) => {
            if let Some((k, _)) = entries.iter().find(|(k, _)| k.get_ref() != "obj") {
                return Err(src.at(
                    k,
                    format!("unknown field `{}` in [mesh]: with `obj`, no other key is allowed", k.get_ref()),
                ));
            }
            let Some(rel) = obj.get_ref().as_str() else {
                return Err(src.at(obj, format!("`obj` must be a string path, found {}", obj.get_ref().type_str())));
            };
            let dir = src.path.parent().unwrap_or(Path::new(""));
            let (mesh, report) = load_obj(&dir.join(rel))?;
            Ok((mesh, Some(report)))
        }
        (None, Some((gkey, _))) => {
            let generator = parse_generator(src, table, gkey)?;
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
fn parse_generator(src: &Source, table: &MeshTable, gkey: &Spanned<String>) -> Result<Generator> {
    let entries = table.get_ref();
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
    match image {
        None => Ok((DEFAULT_IMAGE_SIZE, DEFAULT_IMAGE_SIZE)),
        Some(i) => Ok((check(&i.width, "width")?, check(&i.height, "height")?)),
    }
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
    if up.length() == 0.0 || view.normalize().cross(up.normalize()).length() < 1e-6 {
        return Err(at_key(
            &c.up,
            format!(
                "up {up} is zero or parallel to the view direction {}: pick an up vector across it",
                view.normalize()
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
        if d.length() <= 1e-12 {
            return Err(src.at(
                dir,
                "direction = [0, 0, 0] has no direction: give a vector towards the light",
            ));
        }
        let color = colour(src, &light.color, "color", DVec3::ONE)?;
        out.push(DirectionalLight {
            direction: d.normalize(),
            color,
        });
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{write_obj, SHIPPED};
    use crate::testutil::assert_close;
    use std::path::PathBuf;

    /// Clip -> window coordinates (x, y in pixels, y down; depth) for a `w` x `h` viewport.
    fn to_window(clip: DVec4, w: f64, h: f64) -> DVec3 {
        let ndc = clip.truncate() / clip.w;
        DVec3::new((ndc.x + 1.0) * 0.5 * w, (ndc.y + 1.0) * 0.5 * h, ndc.z)
    }

    fn project(cam: &Camera, aspect: f64, p: DVec3) -> DVec4 {
        cam.projection(aspect) * cam.view() * p.extend(1.0)
    }

    fn scenes_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
    }

    #[test]
    fn projection_centres_the_target_and_puts_up_on_top() {
        let cam = Camera {
            eye: DVec3::new(1.0, 2.0, 5.0),
            target: DVec3::new(0.2, -0.1, 0.3),
            up: DVec3::Y,
            fov_y_deg: 40.0,
            near: None,
            far: None,
        };
        let (w, h) = (640.0, 480.0);
        let c = to_window(project(&cam, w / h, cam.target), w, h);
        assert_close("target window x", c.x, w / 2.0, 1e-9);
        assert_close("target window y", c.y, h / 2.0, 1e-9);
        let above = to_window(project(&cam, w / h, cam.target + DVec3::Y * 0.1), w, h);
        assert!(
            above.y < c.y,
            "world +y must be higher in the image: y {} vs centre {}",
            above.y,
            c.y
        );
        // Camera right (f x up) goes to larger window x.
        let right = (cam.target - cam.eye).cross(cam.up).normalize();
        let r = to_window(project(&cam, w / h, cam.target + right * 0.1), w, h);
        assert!(
            r.x > c.x,
            "camera right must be right in the image: x {} vs centre {}",
            r.x,
            c.x
        );
    }

    #[test]
    fn projection_depth_is_zero_at_near_and_one_at_far() {
        for (near, far) in [(None, None), (Some(0.5), Some(20.0))] {
            let cam = Camera {
                eye: DVec3::new(0.0, 1.0, 4.0),
                target: DVec3::ZERO,
                up: DVec3::Y,
                fov_y_deg: 35.0,
                near,
                far,
            };
            let (n, f) = cam.near_far();
            let dir = (cam.target - cam.eye).normalize();
            let dn = to_window(project(&cam, 1.0, cam.eye + dir * n), 1.0, 1.0).z;
            let df = to_window(project(&cam, 1.0, cam.eye + dir * f), 1.0, 1.0).z;
            assert_close(&format!("depth at near = {n}"), dn, 0.0, 1e-12);
            assert_close(&format!("depth at far = {f}"), df, 1.0, 1e-12);
        }
        let cam = fit_camera(35.0, 1.0);
        let d = cam.distance();
        assert_eq!(cam.near_far(), ((d - 1.5).max(0.01), d + 1.5));
    }

    #[test]
    fn view_puts_the_eye_at_the_origin_looking_down_minus_z() {
        let cam = fit_camera(35.0, 1.0);
        let v = cam.view();
        let eye = v.transform_point3(cam.eye);
        assert_close("eye in view space", eye.length(), 0.0, 1e-12);
        let t = v.transform_point3(cam.target);
        assert_close("target x", t.x, 0.0, 1e-12);
        assert_close("target y", t.y, 0.0, 1e-12);
        assert_close("target z", t.z, -cam.distance(), 1e-12);
    }

    #[test]
    fn fitted_camera_frames_the_unit_sphere_with_five_percent_margin() {
        for aspect in [1.0, 2.0, 0.5] {
            let cam = fit_camera(35.0, aspect);
            assert_close(
                "eye direction",
                cam.eye
                    .normalize()
                    .dot(DVec3::new(0.0, 0.3, 1.0).normalize()),
                1.0,
                1e-12,
            );
            // Tangent points of the silhouette: in view space, the sphere (centre at distance
            // d on -z) touches the cone at half-angle asin(1/d); measure its extent in NDC.
            let d = cam.distance();
            let half = (1.0 / d).asin();
            let (w, h) = (1000.0 * aspect, 1000.0);
            let proj = cam.projection(aspect);
            let ndc = |p: DVec3| {
                let c = proj * p.extend(1.0);
                c.truncate() / c.w
            };
            let rx = ndc(DVec3::new(half.sin(), 0.0, -half.cos()) * (d * half.cos())).x;
            let ry = -ndc(DVec3::new(0.0, half.sin(), -half.cos()) * (d * half.cos())).y;
            let fill = rx.max(ry);
            assert_close(
                &format!("silhouette extent in the narrower axis, aspect {aspect}"),
                fill,
                1.0 / 1.05,
                1e-9,
            );
            assert!(
                rx <= 1.0 / 1.05 + 1e-9 && ry <= 1.0 / 1.05 + 1e-9,
                "aspect {aspect}: rx {rx}, ry {ry}, image {w}x{h}"
            );
        }
    }

    #[test]
    fn every_shipped_scene_loads() {
        let dir = scenes_dir();
        let mut found = Vec::new();
        for entry in std::fs::read_dir(&dir).expect("scenes/ exists") {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(
                    (scene.width, scene.height),
                    (256, 256),
                    "{}",
                    path.display()
                );
                assert_eq!(scene.lights.len(), 1, "{}", path.display());
                assert!(
                    scene.material.shininess >= 20.0,
                    "{}: a visible highlight",
                    path.display()
                );
                assert_eq!(
                    scene.interpolation,
                    Interpolation::ScreenLinear,
                    "{}",
                    path.display()
                );
                // Every corner of the fitted mesh is inside the view frustum and clip range.
                let aspect = scene.aspect();
                let (near, far) = scene.camera.near_far();
                let r = scene
                    .mesh
                    .positions
                    .iter()
                    .map(|p| dvec(p.map(|x| x as f64)).length())
                    .fold(0.0, f64::max);
                assert_close(&format!("{}: fitted radius", path.display()), r, 1.0, 1e-6);
                assert!(
                    near < scene.camera.distance() - 1.0 && far > scene.camera.distance() + 1.0,
                    "{}: clip range",
                    path.display()
                );
                let mut extent = 0f64;
                for p in &scene.mesh.positions {
                    let c = project(&scene.camera, aspect, dvec(p.map(|x| x as f64)));
                    let n = c.truncate() / c.w;
                    assert!(
                        n.x.abs() < 1.0 && n.y.abs() < 1.0 && (0.0..1.0).contains(&n.z),
                        "{}: {p:?} outside",
                        path.display()
                    );
                    extent = extent.max(n.x.abs()).max(n.y.abs());
                }
                assert!(
                    extent > 0.7,
                    "{}: the object should fill most of the frame (extent {extent})",
                    path.display()
                );
                found.push(path.file_name().unwrap().to_string_lossy().into_owned());
            }
        }
        found.sort();
        let expected = [
            "cube.toml",
            "icosphere.toml",
            "sphere_coarse.toml",
            "sphere_fine.toml",
            "torus.toml",
            "torus_generated.toml",
        ];
        assert_eq!(
            found, expected,
            "left = scenes found, right = the shipped set"
        );
    }

    #[test]
    fn shipped_scenes_reference_the_shipped_meshes() {
        for (obj, g) in SHIPPED {
            let toml = scenes_dir().join(obj.replace(".obj", ".toml"));
            let scene = load_scene(&toml).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(
                scene.mesh.triangle_count() as u64,
                g.triangle_count(),
                "{}",
                toml.display()
            );
            assert!(
                scene.mesh_report.is_some(),
                "{} loads an OBJ",
                toml.display()
            );
        }
        // The inline generator builds the same torus as torus.obj.
        let a = load_scene(&scenes_dir().join("torus.toml")).unwrap();
        let b = load_scene(&scenes_dir().join("torus_generated.toml")).unwrap();
        assert!(b.mesh_report.is_none());
        assert_eq!(a.mesh.triangle_count(), b.mesh.triangle_count());
        for (i, (p, q)) in a.mesh.positions.iter().zip(&b.mesh.positions).enumerate() {
            for k in 0..3 {
                assert_close(
                    &format!("torus corner {i} axis {k}"),
                    p[k] as f64,
                    q[k] as f64,
                    1e-6,
                );
            }
        }
    }

    #[test]
    fn scene_for_mesh_frames_a_generated_obj() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ico.obj");
        write_obj(
            &Generator::Icosphere { subdivisions: 1 }.build().unwrap(),
            &path,
        )
        .unwrap();
        let scene = scene_for_mesh(&path).unwrap();
        assert_eq!(scene.name, "ico");
        assert_eq!(scene.mesh.triangle_count(), 80);
        assert_eq!(scene.mesh_report.as_ref().map(|r| r.triangles), Some(80));
        assert_eq!(scene.camera, fit_camera(DEFAULT_FOV_Y_DEG, 1.0));
        assert_eq!(
            (scene.width, scene.height),
            (DEFAULT_IMAGE_SIZE, DEFAULT_IMAGE_SIZE)
        );
        assert_eq!(scene.lights, vec![DirectionalLight::default()]);
        match scene_for_mesh(&dir.path().join("missing.obj")) {
            Err(Error::Io { path, .. }) => {
                assert!(path.ends_with("missing.obj"), "{}", path.display())
            }
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

    /// Writes `text` as `x.toml` in a temp dir (with a small OBJ beside it) and loads it.
    fn load_text(text: &str) -> (tempfile::TempDir, PathBuf, Result<Scene>) {
        let dir = tempfile::tempdir().unwrap();
        write_obj(
            &Generator::Cube {}.build().unwrap(),
            &dir.path().join("cube.obj"),
        )
        .unwrap();
        let path = dir.path().join("x.toml");
        std::fs::write(&path, text).unwrap();
        let r = load_scene(&path);
        (dir, path, r)
    }

    #[test]
    fn minimal_scene_gets_the_defaults() {
        let (_d, _p, r) = load_text("[mesh]\nobj = \"cube.obj\"\n");
        let s = r.unwrap();
        assert_eq!(s.name, "x");
        assert_eq!(s.camera, fit_camera(DEFAULT_FOV_Y_DEG, 1.0));
        assert_eq!(s.lights, vec![DirectionalLight::default()]);
        assert_eq!(s.material, Material::default());
        assert_eq!(
            (s.width, s.height, s.interpolation),
            (512, 512, Interpolation::ScreenLinear)
        );
        assert_eq!(s.mesh.triangle_count(), 12);
    }

    #[test]
    fn full_scene_is_read_and_normalized() {
        let text = r#"name = "all keys"
[mesh]
generator = "uv_sphere"
segments = 8
rings = 4
[camera]
eye = [0, 0, 4]
target = [0.0, 0.0, 0.0]
up = [0.0, 2.0, 0.0]
fov_y_deg = 30.0
near = 2.0
far = 6
[[light]]
type = "directional"
direction = [0.0, 0.0, 2.0]
color = [1.0, 0.5, 0.25]
[[light]]
direction = [1.0, 0.0, 0.0]
[material]
shininess = 8.0
[image]
width = 320
height = 200
[render]
interpolation = "perspective"
"#;
        let (_d, _p, r) = load_text(text);
        let s = r.unwrap();
        assert_eq!(s.name, "all keys");
        assert_eq!(s.mesh.triangle_count(), 48);
        assert!(s.mesh_report.is_none());
        assert_eq!(s.camera.eye, DVec3::new(0.0, 0.0, 4.0));
        assert_eq!(s.camera.near_far(), (2.0, 6.0));
        assert_eq!(s.lights.len(), 2);
        assert_eq!(s.lights[0].direction, DVec3::Z, "normalized on load");
        assert_eq!(s.lights[0].color, DVec3::new(1.0, 0.5, 0.25));
        assert_eq!(s.lights[1].color, DVec3::ONE);
        assert_eq!(s.material.shininess, 8.0);
        assert_eq!(s.material.diffuse, Material::default().diffuse);
        assert_eq!(
            (s.width, s.height, s.interpolation),
            (320, 200, Interpolation::Perspective)
        );
        // Only fov given: the rest of the camera is fitted for that fov and the image aspect.
        let (_d, _p, r) = load_text("[mesh]\nobj = \"cube.obj\"\n[camera]\nfov_y_deg = 50\n[image]\nwidth = 100\nheight = 50\n");
        assert_eq!(r.unwrap().camera, fit_camera(50.0, 2.0));
    }

    #[test]
    fn bad_scenes_report_file_and_line() {
        const MESH: &str = "[mesh]\nobj = \"cube.obj\"\n"; // lines 1-2
        let cases: Vec<(String, Option<usize>, &str)> = vec![
            (format!("{MESH}[image]\nwidht = 3\n"), Some(4), "unknown field `widht`, expected `width` or `height`"),
            (format!("{MESH}[image]\nwidth = \"big\"\n"), Some(4), "invalid type: string \"big\", expected u32"),
            (format!("{MESH}[image]\nwidth = 0\n"), Some(4), "image width = 0 is out of range: it must be 1 to 16384"),
            (format!("{MESH}[image]\nheight = 20000\n"), Some(4), "image height = 20000 is out of range"),
            (format!("{MESH}[image]\nheight = -2\n"), Some(4), "invalid value: integer `-2`, expected u32"),
            (format!("colour = 1\n{MESH}"), Some(1), "unknown field `colour`, expected one of `name`, `mesh`"),
            (format!("nmae = \"x\"\n{MESH}"), Some(1), "unknown field `nmae`"),
            (format!("{MESH}[camera]\neye = [1, 2]\n"), Some(4), "invalid length 2, expected an array of length 3"),
            (format!("{MESH}[camera]\nfov_y_deg = 180\n"), Some(4), "fov_y_deg = 180 is out of range"),
            (format!("{MESH}[camera]\nfov_y_deg = 0.0\n"), Some(4), "fov_y_deg = 0 is out of range"),
            (format!("{MESH}[camera]\neye = [0, 0, 0]\n"), Some(4), "coincide: the camera has no view direction"),
            (format!("{MESH}[camera]\neye = [0, 3, 0]\n\nup = [0, -1, 0]\n"), Some(6), "parallel to the view direction"),
            (format!("{MESH}[camera]\neye = [0, 3, 0]\n"), Some(3), "parallel to the view direction"),
            (format!("{MESH}[camera]\neye = [0, nan, 3]\n"), Some(4), "eye = [0.0, NaN, 3.0] must be finite"),
            (format!("{MESH}[camera]\nnear = 5.0\nfar = 4.0\n"), Some(5), "far = 4 must be greater than near = 5"),
            (format!("{MESH}[camera]\nnear = -1\n"), Some(4), "near = -1 must be finite and > 0"),
            (format!("{MESH}[[light]]\ntype = \"point\"\ndirection = [0, 0, 1]\n"), Some(4), "light type `point` is not supported"),
            (format!("{MESH}[[light]]\ndirection = [0, 0, 1]\n[[light]]\ncolor = [1, 1, 1]\n"), Some(5), "[[light]] is missing `direction`"),
            (format!("{MESH}[[light]]\ndirection = [0, 0, 0]\n"), Some(4), "has no direction"),
            (format!("{MESH}[[light]]\ndirection = [0, 0, 1]\ncolor = [1, -1, 1]\n"), Some(5), "color = [1.0, -1.0, 1.0] has a negative channel"),
            (format!("light = []\n{MESH}"), Some(1), "at least one light"),
            (format!("{MESH}{}", "[[light]]\ndirection = [0, 0, 1]\n".repeat(5)), Some(11), "too many lights: 5 given, at most 4"),
            (format!("{MESH}[material]\nshininess = -1\n"), Some(4), "shininess = -1 must be finite and >= 0"),
            (format!("{MESH}[material]\nshininess = inf\n"), Some(4), "shininess = inf must be finite"),
            (format!("{MESH}[material]\n\ndiffuse = [0.5, 0.5, -0.1]\n"), Some(5), "has a negative channel"),
            (format!("{MESH}[material]\nspecular = [0.5, 0.5, inf]\n"), Some(4), "must be finite"),
            (format!("{MESH}[render]\ninterpolation = \"linear\"\n"), Some(4), "unknown variant `linear`, expected `screen_linear` or `perspective`"),
            (format!("{MESH}[image]\nwidth = 3\nwidth = 4\n"), Some(5), "duplicate key"),
            (format!("{MESH}[image]\nwidth = [3\n"), Some(4), "unclosed array"),
            ("[image]\nwidth = 3\n".to_string(), None, "no [mesh] table"),
            ("[mesh]\n\n".to_string(), Some(1), "[mesh] needs `obj = \"FILE.obj\"`"),
            ("[mesh]\nobj = \"cube.obj\"\ngenerator = \"cube\"\n".to_string(), Some(3), "has both `obj` and `generator`"),
            ("[mesh]\nobj = \"cube.obj\"\nscale = 2\n".to_string(), Some(3), "unknown field `scale` in [mesh]"),
            ("[mesh]\nobj = 3\n".to_string(), Some(2), "`obj` must be a string path, found integer"),
            ("[mesh]\ngenerator = \"sphere\"\n".to_string(), Some(2), "unknown variant `sphere`, expected one of `uv_sphere`"),
            ("[mesh]\ngenerator = \"uv_sphere\"\nsegments = 8\nrigns = 4\n".to_string(), Some(4), "unknown field `rigns`, expected `segments` or `rings`"),
            ("\n[mesh]\ngenerator = \"uv_sphere\"\nsegments = 8\n".to_string(), Some(2), "missing field `rings`"),
            ("[mesh]\ngenerator = \"uv_sphere\"\nrings = \"4\"\nsegments = 8\n".to_string(), Some(3), "`rings`: invalid type: string \"4\", expected u32"),
            ("[mesh]\ngenerator = \"torus\"\nmajor_radius = 1.0\nminor_radius = 2.0\nmajor_segments = 8\nminor_segments = 8\n".to_string(), Some(4), "minor_radius must be < major_radius"),
            ("[mesh]\ngenerator = \"uv_sphere\"\nsegments = 8\nrings = 1\n".to_string(), Some(4), "rings must be >= 2 (got 1)"),
        ];
        for (text, line, needle) in &cases {
            let (_d, path, r) = load_text(text);
            match r {
                Err(e @ Error::Input { .. }) => {
                    let Error::Input {
                        line: l, message, ..
                    } = &e
                    else {
                        unreachable!()
                    };
                    assert_eq!(
                        l, line,
                        "line for `{message}` in:\n{text}\nleft = actual, right = expected"
                    );
                    assert!(
                        message.contains(needle),
                        "message `{message}` lacks `{needle}` for:\n{text}"
                    );
                    let prefix = match line {
                        Some(n) => format!("{}:{n}: ", path.display()),
                        None => format!("{}: ", path.display()),
                    };
                    assert!(
                        e.to_string().starts_with(&prefix),
                        "display `{e}` should start with `{prefix}`"
                    );
                }
                other => panic!(
                    "expected an input error containing `{needle}` for:\n{text}\ngot {other:?}"
                ),
            }
        }
    }

    #[test]
    fn missing_files_are_io_errors_naming_the_resolved_path() {
        let (dir, _p, r) = load_text("[mesh]\nobj = \"meshes/none.obj\"\n");
        match r {
            Err(Error::Io { path, source }) => {
                assert_eq!(path, dir.path().join("meshes/none.obj"));
                assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
            }
            other => panic!("expected an I/O error, got {other:?}"),
        }
        match load_scene(&dir.path().join("absent.toml")) {
            Err(Error::Io { path, .. }) => assert!(path.ends_with("absent.toml")),
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

    #[test]
    fn obj_errors_inside_scenes_name_the_obj_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
        std::fs::write(dir.path().join("s.toml"), "[mesh]\nobj = \"bad.obj\"\n").unwrap();
        match load_scene(&dir.path().join("s.toml")) {
            Err(Error::Input {
                path,
                line,
                message,
            }) => {
                assert!(path.ends_with("bad.obj"), "{}", path.display());
                assert_eq!(line, Some(3));
                assert!(
                    message.contains("face index 3 is past the 2 vertices"),
                    "{message}"
                );
            }
            other => panic!("expected an OBJ input error, got {other:?}"),
        }
    }
}
