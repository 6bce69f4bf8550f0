//! The glTF scene graph: which scene is drawn (the default scene, else the first), each node's
//! world transform (glTF 2.0 section 3.5.3: a `matrix`, or T * R * S, parent times child), and
//! the matrix that carries normals (the cofactor of the upper 3x3, the inverse transpose up to
//! a positive scale, which stays defined when a scale is zero).
use ::gltf::json;
use glam::{DMat3, DMat4, DQuat, DVec3};

use crate::geometry::mesh_file::{DrawnScene, Named, SceneChoice};

/// A mesh placed by a node (or, in a file without scenes, each mesh once at the identity).
pub(super) struct Placement {
    pub node: Option<Named>,
    pub mesh: usize,
    /// Model to world; `None`: the identity (positions kept bit for bit).
    pub world: Option<DMat4>,
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
    let mut stack: Vec<(usize, Option<DMat4>)> = scene
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
            (None, l) => l,
            (Some(p), None) => Some(p),
            (Some(p), Some(l)) => Some(p * l),
        };
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

/// The matrix that carries normals under `world`: the cofactor matrix of its upper 3x3 (equal
/// to det * inverse transpose), negated when the determinant is negative so that it keeps the
/// normals' side; for a singular matrix (a zero scale) it still maps normals onto the flattened
/// surface's normal.
pub(super) fn normal_matrix(world: &DMat4) -> DMat3 {
    let m = DMat3::from_mat4(*world);
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    // Columns of the cofactor matrix: cross products of the other two columns.
    let cof = DMat3::from_cols(b.cross(c), c.cross(a), a.cross(b));
    if m.determinant() < 0.0 {
        -cof
    } else {
        cof
    }
}

/// Whether `world` mirrors (negative determinant): its triangles' winding flips (glTF 2.0
/// section 3.7.4), so they are reordered to stay counter-clockwise from the front.
pub(super) fn mirrors(world: &DMat4) -> bool {
    DMat3::from_mat4(*world).determinant() < 0.0
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
        let n = normal_matrix(&world);
        let it = DMat3::from_mat4(world).inverse().transpose();
        for v in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 2.0, -3.0)] {
            let (a, b) = ((n * v).normalize(), (it * v).normalize());
            assert!((a - b).length() < 1e-12, "{a} vs {b}");
        }
        // A mirror: still the inverse transpose's direction.
        let mirror = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        assert!(mirrors(&mirror));
        let v = (normal_matrix(&mirror) * DVec3::new(1.0, 1.0, 0.0)).normalize();
        let want = DVec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((v - want).length() < 1e-12, "{v}");
    }
}
