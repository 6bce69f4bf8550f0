//! The glTF scene graph: which scene is drawn (the default scene, else the first), each node's
//! world transform (glTF 2.0 section 3.5.3: a `matrix`, or T * R * S, parent times child), and
//! the matrix that carries normals (the cofactor of the upper 3x3, the inverse transpose up to
//! a positive scale, which stays defined when a scale is zero).
//!
//! A world transform is kept as its linear part and its translation, the translation an
//! unevaluated sum of two f64 vectors (each parent's translation plus the rounding error of
//! adding its child's, Knuth's TwoSum): the reader places vertices relative to the first
//! placement's translation, so that a node 1e30 from the origin keeps its children's offsets
//! from each other, and the fit to the unit sphere cancels the rest.
use ::gltf::json;
use glam::{DMat3, DMat4, DQuat, DVec3};

use crate::geometry::mesh_file::{DrawnScene, Named, SceneChoice};

/// Model to world: `linear * p + (translation + residual)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct World {
    pub linear: DMat3,
    pub translation: DVec3,
    /// What rounding took from `translation` when the parents' translations were added.
    pub residual: DVec3,
}

impl World {
    /// The affine transform of `m` (glTF's last row, 0 0 0 1, is not read).
    fn of(m: &DMat4) -> World {
        World {
            linear: DMat3::from_mat4(*m),
            translation: m.w_axis.truncate(),
            residual: DVec3::ZERO,
        }
    }

    /// `self` after `local`: a parent's world transform times its child's local one.
    fn then(&self, local: &World) -> World {
        let (translation, error) = two_sum(self.translation, self.linear * local.translation);
        World {
            linear: self.linear * local.linear,
            translation,
            residual: self.residual + self.linear * local.residual + error,
        }
    }

    pub fn is_finite(&self) -> bool {
        self.linear.is_finite() && self.translation.is_finite() && self.residual.is_finite()
    }
}

/// `a + b` and the exact error of its rounding, componentwise (Knuth's TwoSum: no comparison,
/// exact for finite sums that do not overflow).
fn two_sum(a: DVec3, b: DVec3) -> (DVec3, DVec3) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// A mesh placed by a node (or, in a file without scenes, each mesh once at the identity).
pub(super) struct Placement {
    pub node: Option<Named>,
    pub mesh: usize,
    /// Model to world; `None`: the identity (positions kept bit for bit).
    pub world: Option<World>,
    /// The node's skin, ignored (the mesh is drawn in its bind pose).
    pub skin: Option<usize>,
    /// The node's morph weights, overriding the mesh's.
    pub weights: Option<Vec<f32>>,
}

/// The scene drawn and the meshes it places, depth first in the order the file lists nodes;
/// with no scene at all, every mesh once, untransformed.
///
/// Errors: a node index out of range, a node reached twice (glTF requires disjoint strict
/// trees: a cycle, two parents, or listed twice), a transform that is not finite.
pub(super) fn placements(
    root: &json::Root,
) -> Result<(Option<DrawnScene>, Vec<Placement>), String> {
    let chosen = match root.scene {
        Some(s) => Some((s.value(), SceneChoice::Default)),
        None if !root.scenes.is_empty() => Some((0, SceneChoice::First)),
        None => None,
    };
    let Some((si, choice)) = chosen else {
        let all = (0..root.meshes.len())
            .map(|mesh| Placement {
                node: None,
                mesh,
                world: None,
                skin: None,
                weights: None,
            })
            .collect();
        return Ok((None, all));
    };
    let scene = root.scenes.get(si).ok_or_else(|| {
        format!(
            "the default scene is scene {si}, but the file has {} scenes",
            root.scenes.len()
        )
    })?;
    let drawn = DrawnScene {
        scene: Named {
            index: si,
            name: scene.name.clone(),
        },
        choice,
    };
    let mut seen = vec![false; root.nodes.len()];
    let mut out = Vec::new();
    // An explicit stack, not recursion: a deep chain of nodes must not overflow the stack.
    let mut stack: Vec<(usize, Option<World>)> = scene
        .nodes
        .iter()
        .rev()
        .map(|n| (n.value(), None))
        .collect();
    while let Some((ni, parent)) = stack.pop() {
        let node = root.nodes.get(ni).ok_or_else(|| {
            format!(
                "scene {si} reaches node {ni}, but the file has {} nodes",
                root.nodes.len()
            )
        })?;
        if std::mem::replace(&mut seen[ni], true) {
            return Err(format!(
                "node {ni} is reached twice from scene {si} (a cycle, two parents, or listed twice); glTF requires the nodes to form trees"
            ));
        }
        let local = local_transform(node).map_err(|e| format!("node {ni}: {e}"))?;
        let world = match (parent, local) {
            (None, l) => l.as_ref().map(World::of),
            (Some(p), None) => Some(p),
            (Some(p), Some(l)) => Some(p.then(&World::of(&l))),
        };
        if world.is_some_and(|w| !w.is_finite()) {
            return Err(format!(
                "node {ni}: its world transform (its own times its parents') is not finite: fix the nodes' scales"
            ));
        }
        if let Some(mesh) = node.mesh {
            out.push(Placement {
                node: Some(Named {
                    index: ni,
                    name: node.name.clone(),
                }),
                mesh: mesh.value(),
                world,
                skin: node.skin.map(|s| s.value()),
                weights: node.weights.clone(),
            });
        }
        for c in node.children.iter().flatten().rev() {
            stack.push((c.value(), world));
        }
    }
    Ok((Some(drawn), out))
}

/// The node's own transform; `None` for the identity (no matrix, no TRS, or an identity one).
fn local_transform(node: &json::Node) -> Result<Option<DMat4>, String> {
    let m = if let Some(m) = node.matrix {
        // Column-major, as glTF stores it.
        DMat4::from_cols_array(&m.map(f64::from))
    } else {
        let t = node
            .translation
            .map_or(DVec3::ZERO, |t| DVec3::from(t.map(f64::from)));
        let s = node
            .scale
            .map_or(DVec3::ONE, |s| DVec3::from(s.map(f64::from)));
        let r = match node.rotation {
            Some(q) => {
                let [x, y, z, w] = q.0.map(f64::from);
                let q = DQuat::from_xyzw(x, y, z, w);
                // glTF requires unit quaternions; renormalise what rounding left.
                if !(q.is_finite() && q.length() > 0.0) {
                    return Err(format!(
                        "its rotation {:?} is not a rotation (zero or not finite)",
                        [x, y, z, w]
                    ));
                }
                q.normalize()
            }
            None => DQuat::IDENTITY,
        };
        DMat4::from_scale_rotation_translation(s, r, t)
    };
    if !m.is_finite() {
        return Err("its transform is not finite".into());
    }
    Ok((m != DMat4::IDENTITY).then_some(m))
}

/// The matrix that carries normals under `linear` (a world transform's linear part): its
/// cofactor matrix (equal to det * inverse transpose), negated when the determinant is negative
/// so that it keeps the normals' side; for a singular matrix (a zero scale) it still maps
/// normals onto the flattened surface's normal.
pub(super) fn normal_matrix(linear: &DMat3) -> DMat3 {
    let m = *linear;
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    // Columns of the cofactor matrix: cross products of the other two columns.
    let cof = DMat3::from_cols(b.cross(c), c.cross(a), a.cross(b));
    if m.determinant() < 0.0 {
        -cof
    } else {
        cof
    }
}

/// Whether `linear` mirrors (negative determinant): its triangles' winding flips (glTF 2.0
/// section 3.7.4), so they are reordered to stay counter-clockwise from the front.
pub(super) fn mirrors(linear: &DMat3) -> bool {
    linear.determinant() < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_normal_matrix_is_the_inverse_transpose_up_to_a_positive_scale() {
        let world = DMat4::from_scale_rotation_translation(
            DVec3::new(2.0, 0.5, 3.0),
            DQuat::from_rotation_y(0.7),
            DVec3::new(1.0, -2.0, 0.5),
        );
        let n = normal_matrix(&DMat3::from_mat4(world));
        let it = DMat3::from_mat4(world).inverse().transpose();
        for v in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 2.0, -3.0)] {
            let (a, b) = ((n * v).normalize(), (it * v).normalize());
            assert!((a - b).length() < 1e-12, "{a} vs {b}");
        }
        // A mirror: still the inverse transpose's direction.
        let mirror = DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
        assert!(mirrors(&mirror));
        let v = (normal_matrix(&mirror) * DVec3::new(1.0, 1.0, 0.0)).normalize();
        let want = DVec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((v - want).length() < 1e-12, "{v}");
    }

    #[test]
    fn a_far_parent_keeps_its_childs_translation_in_the_residual() {
        let far = World::of(&DMat4::from_translation(DVec3::new(1e30, 0.0, -1e30)));
        let child = World::of(&DMat4::from_translation(DVec3::new(3.0, 0.5, 0.0)));
        let w = far.then(&child);
        // 1e30 + 3 is 1e30 in f64; the 3 is the sum's rounding error, kept (0 + 0.5 is exact).
        assert_eq!(w.translation, DVec3::new(1e30, 0.5, -1e30));
        assert_eq!(w.residual, DVec3::new(3.0, 0.0, 0.0));
        // Near the origin nothing is lost, and the residual stays zero.
        let near = World::of(&DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0))).then(&child);
        assert_eq!(
            (near.translation, near.residual),
            (DVec3::new(4.0, 2.5, 3.0), DVec3::ZERO)
        );
    }
}
