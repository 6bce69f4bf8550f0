//! Triangle meshes: reading OBJ, glTF 2.0 and PLY files through one seam ([`input::load_mesh`],
//! a reader per format: [`obj`], [`gltf`], [`ply`]), vertex normals, fitting to the unit
//! sphere, procedural generators, and OBJ writing.
//!
//! Owns [`Mesh`], the unindexed triangle soup every renderer path consumes.
//!
//! Invariants of a [`Mesh`] produced here:
//! - `positions.len() == normals.len()` and both are a multiple of 3 (3 corners per triangle);
//! - every normal is finite and unit length (to f32 precision, |n| - 1 < 1e-6);
//! - every triangle has non-zero area by the test in [`is_zero_area`] (reading drops the
//!   others and counts them in [`LoadReport::dropped_zero_area`]; every reader does, through
//!   [`soup`]);
//! - computed and generated normals agree with the winding (counter-clockwise seen from the
//!   side they point to); normals given in a file are kept as the file has them;
//! - a mesh returned by [`load_mesh`] (any reader) is fitted by [`fit_unit`] (bounding box
//!   centred at the origin, bounding sphere radius 1); a mesh returned by [`Generator::build`]
//!   is not.
//!
//! OBJ loading is two passes over the text. Our own pass validates every statement and reports
//! problems as `file:line` errors (tobj reports neither file nor line). It also writes a
//! normalized copy of the geometry statements that tobj then parses and triangulates: that copy
//! has trailing comments, `l`/`p` elements, texture coordinates, vertex colours and groups
//! removed, because tobj rejects trailing comments and mixed vertex colours, turns an `l` with
//! 3+ points into a triangle, and fills a corner without a normal index with the previous
//! corner's normal. Our pass remembers which corners really had a normal; the two passes are
//! cross-checked corner by corner so a disagreement is an error, never a silently wrong mesh.
pub mod generators;
pub mod gltf;
pub mod input;
pub mod mesh_file;
pub mod obj;
pub mod ply;
pub(crate) mod soup;
#[cfg(test)]
mod tests;
pub mod topology;
pub mod zdomain;

pub use generators::*;
pub use input::{
    load_mesh, mesh_files, parse_mesh, Depth, Encoding, Format, MeshInput, NormalSource,
};
pub use obj::*;
pub use topology::{topology, Topology};

use glam::DVec3;

/// Triangle soup ready for upload: 3 corners per triangle, unindexed, so per-triangle data can
/// ride on vertices.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    /// Model-space corner positions; after [`fit_unit`] inside the unit sphere.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normal per corner: given in the file, or computed smooth (angle-weighted).
    pub normals: Vec<[f32; 3]>,
    /// File path or generator description, for messages.
    pub source: String,
}

impl Mesh {
    /// Number of triangles (`positions.len() / 3`).
    pub fn triangle_count(&self) -> usize {
        self.positions.len() / 3
    }

    /// Axis-aligned bounds `(min, max)` over all positions. An empty mesh gives
    /// `([0.0; 3], [0.0; 3])`.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        if self.positions.is_empty() {
            return ([0.0; 3], [0.0; 3]);
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }
}
/// What a reader ([`load_mesh`]) did to the file's faces, for the user and for tests.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LoadReport {
    /// Triangles in the resulting mesh (after dropping zero-area ones).
    pub triangles: usize,
    /// Triangles dropped because they have zero area (see [`is_zero_area`]).
    pub dropped_zero_area: usize,
    /// True when at least one corner's normal was computed rather than taken from the file.
    pub computed_normals: bool,
    /// True when some face had more than 3 vertices and was triangulated (as a fan).
    pub had_quads_or_polygons: bool,
    /// Human-readable notes, e.g. "dropped 3 zero-area triangles".
    pub warnings: Vec<String>,
    /// What was read and drawn: format, encoding, and for glTF the scene and its parts.
    pub input: MeshInput,
}
/// A triangle counts as zero-area when `|cross(p1 - p0, p2 - p0)| <= 1e-12 * L^2`, with `L` its
/// longest edge, computed in f64. Geometrically: its height over the longest edge is at most
/// 1e-12 * L. Positions are f32 (relative precision 6e-8), so this catches exactly collinear or
/// coincident corners (whose cross product in f64 is rounding noise, ~1e-16 * L^2) while every
/// sliver with a real, representable area is kept. A triangle with all corners equal (L = 0)
/// is zero-area.
pub fn is_zero_area(p0: DVec3, p1: DVec3, p2: DVec3) -> bool {
    let cross = (p1 - p0).cross(p2 - p0).length();
    let longest2 = (p1 - p0)
        .length_squared()
        .max((p2 - p1).length_squared())
        .max((p0 - p2).length_squared());
    cross <= 1e-12 * longest2
}

// ---------------------------------------------------------------------------------------------
// Fitting
// ---------------------------------------------------------------------------------------------
fn dvec(a: [f32; 3]) -> DVec3 {
    DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64)
}
/// Centres the bounding box at the origin and scales uniformly so the bounding sphere (the
/// largest distance from the centre over all positions) has radius 1. Computed in f64, stored
/// as f32, so the radius is 1 to f32 rounding (about 6e-8). Normals are unchanged (a uniform
/// scale and a translation do not rotate them).
///
/// An empty mesh is left alone; a mesh whose positions all coincide (radius 0) is only moved
/// to the origin, since no scale makes a point into a unit sphere.
pub fn fit_unit(mesh: &mut Mesh) {
    let wide: Vec<DVec3> = mesh.positions.iter().map(|&p| dvec(p)).collect();
    mesh.positions = fit(&wide);
}

/// [`fit_unit`] of f64 positions, rounded to f32 once, after the fit: the readers' soup is
/// f64 until here, so that the fit cancels a translation or scale of the file's (a glTF node
/// 1e30 away) instead of f32 rounding it into the shape. For f32 positions (widened exactly)
/// the same bits as fitting them in place. Finite positions whose squares stay inside f64
/// (the readers' bound, [`MAX_COORDINATE`]) give finite results.
pub(crate) fn fit(positions: &[DVec3]) -> Vec<[f32; 3]> {
    let Some(&first) = positions.first() else {
        return Vec::new();
    };
    let (lo, hi) = positions
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let centre = (lo + hi) * 0.5;
    let radius = positions
        .iter()
        .map(|&p| (p - centre).length())
        .fold(0.0, f64::max);
    let scale = if radius > 0.0 && radius.is_finite() {
        1.0 / radius
    } else {
        1.0
    };
    positions
        .iter()
        .map(|&p| ((p - centre) * scale).as_vec3().to_array())
        .collect()
}

/// The largest coordinate magnitude a reader hands to the fit (1e150): squared lengths
/// ([`is_zero_area`], the fit's radius) stay inside f64 (1.8e308). f32 positions are far
/// below it; a glTF chain of node scales can pass it, and is refused.
pub(crate) const MAX_COORDINATE: f64 = 1e150;

// ---------------------------------------------------------------------------------------------
// OBJ writing
// ---------------------------------------------------------------------------------------------
