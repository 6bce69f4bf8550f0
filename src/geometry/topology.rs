//! A triangle soup's topology: corners welded by their exact positions, then every edge
//! counted with its direction. A mesh is *closed* when every edge is shared by exactly two
//! triangles, and *consistently oriented* when those two run along it in opposite directions;
//! only then does back-face culling remove nothing visible.
use std::collections::HashMap;

use serde::Serialize;

use super::Mesh;

/// What [`topology`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Topology {
    /// Distinct positions after welding bit-identical corners.
    pub vertices: usize,
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges of exactly one triangle (holes, borders).
    pub boundary_edges: usize,
    /// Edges of three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges of two triangles running along it in the same direction (flipped neighbours).
    pub inconsistent_edges: usize,
    /// Triangles with two equal corners (no area; no edges counted for them).
    pub degenerate_triangles: usize,
}

impl Topology {
    /// Every edge shared by exactly two triangles.
    pub fn closed(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0 && self.edges > 0
    }

    /// Closed, and every shared edge runs in opposite directions in its two triangles.
    pub fn closed_and_oriented(&self) -> bool {
        self.closed() && self.inconsistent_edges == 0
    }
}

/// The topology of `mesh` (3 corners per triangle).
pub fn topology(mesh: &Mesh) -> Topology {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut id = |p: [f32; 3]| {
        let n = ids.len() as u32;
        *ids.entry(p.map(|x| (x + 0.0).to_bits())).or_insert(n)
    };
    // (low, high) -> (triangles running low -> high, triangles running high -> low)
    let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    let mut degenerate = 0;
    for tri in mesh.positions.chunks_exact(3) {
        let v = [id(tri[0]), id(tri[1]), id(tri[2])];
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            degenerate += 1;
            continue;
        }
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                e.0 += 1;
            } else {
                e.1 += 1;
            }
        }
    }
    let mut t = Topology {
        vertices: ids.len(),
        edges: edges.len(),
        boundary_edges: 0,
        non_manifold_edges: 0,
        inconsistent_edges: 0,
        degenerate_triangles: degenerate,
    };
    for &(f, b) in edges.values() {
        match f + b {
            1 => t.boundary_edges += 1,
            2 if f != 1 => t.inconsistent_edges += 1,
            2 => {}
            _ => t.non_manifold_edges += 1,
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(tris: &[[[f32; 3]; 3]]) -> Mesh {
        Mesh {
            positions: tris.iter().flatten().copied().collect(),
            normals: vec![[0.0, 0.0, 1.0]; tris.len() * 3],
            source: "test".into(),
        }
    }

    /// A tetrahedron with outward (consistent) winding.
    fn tetra() -> Vec<[[f32; 3]; 3]> {
        let (a, b, c, d) = (
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        );
        vec![[a, c, b], [a, b, d], [a, d, c], [b, c, d]]
    }

    #[test]
    fn a_tetrahedron_is_closed_and_oriented_and_breaking_it_shows() {
        let t = topology(&mesh(&tetra()));
        assert!(t.closed_and_oriented(), "{t:?}");
        assert_eq!((t.vertices, t.edges), (4, 6));
        // one face flipped: closed, three inconsistent edges
        let mut flipped = tetra();
        flipped[0].swap(1, 2);
        let t = topology(&mesh(&flipped));
        assert!(t.closed() && !t.closed_and_oriented());
        assert_eq!(t.inconsistent_edges, 3);
        // one face removed: three boundary edges
        let t = topology(&mesh(&tetra()[1..]));
        assert_eq!(t.boundary_edges, 3);
        assert!(!t.closed());
        // a face repeated: three non-manifold edges
        let mut twice = tetra();
        twice.push(twice[0]);
        let t = topology(&mesh(&twice));
        assert_eq!(t.non_manifold_edges, 3);
        // a degenerate triangle is counted apart
        let mut deg = tetra();
        deg.push([[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]]);
        assert_eq!(topology(&mesh(&deg)).degenerate_triangles, 1);
    }
}
