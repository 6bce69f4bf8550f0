//! Scenes: the TOML scene format, its validation, and the camera matrices (f64).
//!
//! Owns [`Scene`] (mesh + camera + lights + material + image size + interpolation mode) and
//! [`Camera`]'s view and projection. Invariants of a [`Scene`] built here:
//! - the mesh is fitted to the unit sphere ([`fit_unit`](crate::geometry::fit_unit)): bounding box centred at the origin,
//!   bounding sphere radius 1, so camera positions in scene files live in that space whatever
//!   the OBJ's own units;
//! - 1 to [`MAX_LIGHTS`] lights, each direction unit length;
//! - every number finite, colours >= 0, width and height in `1..=`[`MAX_IMAGE_SIZE`].
//!
//! # Scene format
//!
//! ```toml
//! name = "coarse sphere"          # optional, default: the file stem
//! mesh = "sphere_coarse.obj"      # a mesh file relative to the scene file (.obj, .gltf, .glb,
//!                                 # .ply), or a [mesh] table with `file` (`obj`) or `generator`:
//! # [mesh]
//! # file = "sphere_coarse.obj"
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
//! Meshes, read ([`crate::geometry::load_mesh`]) or generated, are fitted to the unit sphere on
//! load. Unknown keys, wrong types
//! and values out of range are errors naming `file:line`.

pub mod camera;
pub mod file;
mod inputs;
pub mod source;
#[cfg(test)]
mod tests;

pub use camera::*;
pub use file::*;
pub use inputs::*;
pub use source::SceneSource;

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{LoadReport, Mesh};
/// Most lights a scene may have (the shaders' uniform arrays have this size; the lighting
/// formula's, [`crate::method::formulas::Lighting`], own it).
pub use crate::method::formulas::MAX_LIGHTS;
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

/// Back-face culling (`cull` in the scene's `[render]` table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Cull {
    /// Cull back faces when the mesh is closed and consistently oriented (then no back face is
    /// ever visible), else nothing: the default.
    #[default]
    Auto,
    /// Always cull back faces.
    Back,
    /// Never cull.
    None,
}

/// Whether back faces are culled: `Back` always, `None` never, `Auto` when `topo` is closed and
/// consistently oriented and the winding agrees with the vertex normals on most triangles
/// (`with` against `against`; an inside-out winding is not trusted).
pub fn culls_back(
    cull: Cull,
    topo: &crate::geometry::Topology,
    with: usize,
    against: usize,
) -> bool {
    match cull {
        Cull::Back => true,
        Cull::None => false,
        Cull::Auto => topo.closed_and_oriented() && with >= against,
    }
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
    pub cull: Cull,
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

    /// What the mesh reader has to say: which file and, for glTF and PLY, what of it was drawn
    /// (`log::info!`), then each warning (`log::warn!`).
    pub fn log_mesh_notes(&self) {
        let Some(report) = &self.mesh_report else {
            return;
        };
        let source = &self.mesh.source;
        if report.input.format != crate::geometry::Format::Obj {
            log::info!("read {source}: {}", report.input.describe());
        }
        for w in &report.warnings {
            log::warn!("{source}: {w}");
        }
    }
}
