//! From indexed triangles to the fitted [`Mesh`] every reader returns: zero-area triangles
//! dropped, each corner's normal taken from the file or computed smooth, the result fitted to
//! the unit sphere. One definition for every format ([`super::mesh_file::Format`]), so an OBJ and a
//! glTF or PLY file of the same triangles give the same mesh.
//!
//! A reader hands over its positions and normals as lists and its triangles as [`Corner`]s
//! indexing them. Smooth normals are accumulated per *position index*: the OBJ reader passes
//! the file's own `v` indices (the format's topology); the glTF and PLY readers pass indices
//! of distinct positions (bit-identical coordinates welded), because their vertices are split
//! wherever any attribute differs (texture seams) and carry no topology of their own.
use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::{dvec, fit, fit_unit, is_zero_area, Mesh};
use crate::error::{Error, Result};

/// One triangle corner: an index into the position list and, where the file gave one, into the
/// normal list.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Corner {
    pub position: usize,
    pub normal: Option<usize>,
}

/// Positions and normals a reader found; [`Corner`]s index them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lists<'a> {
    /// In f64 until the fit (glTF world positions; OBJ and PLY widen their f32 ones exactly).
    pub positions: &'a [DVec3],
    pub normals: &'a [[f32; 3]],
    /// The smoothing index of each position ([`weld`]); `None`: the position index itself.
    pub smooth_as: Option<&'a [usize]>,
}

impl Lists<'_> {
    /// The index computed normals are accumulated under for position `p`.
    fn smoothing_index(&self, p: usize) -> usize {
        self.smooth_as.map_or(p, |w| w[p])
    }
}

/// How the corners' normals were found, for the load report's warnings.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct NormalCounts {
    /// Taken from the file.
    pub given: usize,
    /// Given in the file with zero length (computed instead).
    pub zero_given: usize,
    /// Computed (smooth, or the face normal where the smooth one cancels out).
    pub computed: usize,
    /// Computed where the neighbouring face normals cancel out: the face normal.
    pub cancelled: usize,
}

/// What [`assemble`] made of a reader's triangles.
pub(crate) struct Assembled {
    pub mesh: Mesh,
    /// The triangles kept (non-zero area in the file's coordinates), in file order.
    pub kept: Vec<[Corner; 3]>,
    /// Zero-area triangles dropped, in the file's coordinates and once fitted.
    pub dropped: usize,
    pub counts: NormalCounts,
}

/// The fitted triangle soup of `tris` (file order kept): drops the zero-area ones
/// ([`is_zero_area`]; none left is an error), fills in each corner's normal ([`corner_normals`])
/// and fits the result ([`fit_unit`]), dropping what the fit collapses.
pub(crate) fn assemble(path: &Path, lists: Lists, tris: &[[Corner; 3]]) -> Result<Assembled> {
    let kept: Vec<[Corner; 3]> = tris
        .iter()
        .filter(|tri| {
            let [a, b, c] = tri.map(|k| lists.positions[k.position]);
            !is_zero_area(a, b, c)
        })
        .copied()
        .collect();
    if kept.is_empty() {
        return Err(Error::input(
            path,
            None,
            format!(
                "no triangles: all {} of the file's triangles have zero area",
                tris.len()
            ),
        ));
    }
    let (wide, mut mesh, counts) = corner_normals(path, lists, &kept);
    mesh.positions = fit(&wide);
    let dropped = tris.len() - kept.len() + fit_dropping_collapsed(path, &mut mesh, tris.len())?;
    Ok(Assembled {
        mesh,
        kept,
        dropped,
        counts,
    })
}

/// Whether a corner lacks a usable normal in the file (none, or of zero length).
pub(crate) fn lacks_normal(lists: Lists, c: &Corner) -> bool {
    c.normal.is_none_or(|n| lists.normals[n] == [0.0; 3])
}

/// Smooth normals accumulated per position index over `kept` (weighted by corner angle), and
/// the total corner angle per position; empty when every corner has a usable normal.
fn smooth_normals(lists: Lists, kept: &[[Corner; 3]]) -> (Vec<DVec3>, Vec<f64>) {
    let needs_smooth = kept.iter().flatten().any(|c| lacks_normal(lists, c));
    let mut acc = Vec::new();
    let mut weight = Vec::new();
    if needs_smooth {
        acc = vec![DVec3::ZERO; lists.positions.len()];
        weight = vec![0f64; lists.positions.len()];
        for tri in kept {
            let p = tri.map(|k| lists.positions[k.position]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            for j in 0..3 {
                let e1 = p[(j + 1) % 3] - p[j];
                let e2 = p[(j + 2) % 3] - p[j];
                // atan2 stays accurate for angles near 0 and pi, where acos of a dot does not.
                let angle = e1.cross(e2).length().atan2(e1.dot(e2));
                let s = lists.smoothing_index(tri[j].position);
                acc[s] += n * angle;
                weight[s] += angle;
            }
        }
    }
    (acc, weight)
}

/// The triangle soup of `kept`: its corners' positions (f64, not yet fitted; the mesh's own
/// are left empty), and each corner's normal, given (normalised; a zero-length one counts as
/// missing) or computed smooth: the angle-weighted sum of the face normals around the same
/// position index; where those cancel out (two-sided sheets), the corner's own face normal.
fn corner_normals(
    path: &Path,
    lists: Lists,
    kept: &[[Corner; 3]],
) -> (Vec<DVec3>, Mesh, NormalCounts) {
    let mut counts = NormalCounts::default();
    let given = |c: &Corner, zero_given: &mut usize| -> Option<DVec3> {
        let n = dvec(lists.normals[c.normal?]);
        let len = n.length();
        if len > 0.0 {
            Some(n / len)
        } else {
            *zero_given += 1;
            None
        }
    };
    let (acc, weight) = smooth_normals(lists, kept);
    let mut positions = Vec::with_capacity(kept.len() * 3);
    let mut normals = Vec::with_capacity(kept.len() * 3);
    for tri in kept {
        let p = tri.map(|k| lists.positions[k.position]);
        for c in tri {
            positions.push(lists.positions[c.position]);
            let n = match given(c, &mut counts.zero_given) {
                Some(n) => {
                    counts.given += 1;
                    n
                }
                None => {
                    counts.computed += 1;
                    let k = lists.smoothing_index(c.position);
                    let s = acc[k];
                    let len = s.length();
                    // Cancellation: neighbouring faces point in (nearly) opposite directions, so
                    // their sum has no meaningful direction. The threshold is relative to the
                    // total corner angle, so small but consistent fans are unaffected.
                    if len > 1e-6 * weight[k] && len > 0.0 {
                        s / len
                    } else {
                        counts.cancelled += 1;
                        (p[1] - p[0]).cross(p[2] - p[0]).normalize()
                    }
                }
            };
            normals.push(n.as_vec3().to_array());
        }
    }
    let mesh = Mesh {
        positions: Vec::new(),
        normals,
        source: path.display().to_string(),
    };
    (positions, mesh, counts)
}

/// Drops the triangles of `mesh` (fitted from f64 by [`fit`]) that the fit's rounding to f32
/// collapsed, refitting what is left; returns how many. `triangles` (the file's count) is for
/// the message when none is left.
fn fit_dropping_collapsed(path: &Path, mesh: &mut Mesh, triangles: usize) -> Result<usize> {
    // Fitting rounds to f32 in the fitted frame: beside a far-away vertex, a triangle with an
    // area in the file's coordinates can collapse (found by the fuzz harness: one cube vertex
    // moved to x = -2147483648). Drop those too and refit; a refit only happens when something
    // was dropped, so other meshes keep their bits. Each round drops at least one triangle;
    // the bound keeps an adversarial file linear.
    let mut dropped = 0;
    for _ in 0..4 {
        let collapsed = drop_zero_area(mesh);
        if collapsed == 0 {
            break;
        }
        dropped += collapsed;
        if mesh.positions.is_empty() {
            return Err(Error::input(
                path,
                None,
                format!(
                    "no triangles: all {triangles} of the file's triangles have zero area once fitted to the unit sphere (a vertex far from the others?)",
                ),
            ));
        }
        fit_unit(mesh);
    }
    Ok(dropped)
}

/// Removes the triangles of `mesh` that [`is_zero_area`] rejects; returns how many.
fn drop_zero_area(mesh: &mut Mesh) -> usize {
    let keep: Vec<bool> = mesh
        .positions
        .chunks_exact(3)
        .map(|t| !is_zero_area(dvec(t[0]), dvec(t[1]), dvec(t[2])))
        .collect();
    for list in [&mut mesh.positions, &mut mesh.normals] {
        let mut corner = 0;
        list.retain(|_| {
            corner += 1;
            keep[(corner - 1) / 3]
        });
    }
    keep.iter().filter(|&&k| !k).count()
}

/// `n` and the noun, singular or plural.
pub(crate) fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The notes every reader gives: dropped triangles, zero-length normals, normals computed
/// beside given ones, normals where the neighbours cancel out.
pub(crate) fn common_notes(dropped: usize, counts: &NormalCounts) -> Vec<String> {
    let NormalCounts {
        given,
        zero_given,
        computed,
        cancelled,
    } = *counts;
    let mut notes = Vec::new();
    if dropped > 0 {
        notes.push(format!(
            "dropped {} (height below 1e-12 x longest edge)",
            plural(dropped, "zero-area triangle", "zero-area triangles")
        ));
    }
    if zero_given > 0 {
        notes.push(format!(
            "{} had a zero-length normal in the file; computed smooth normals for them instead",
            plural(zero_given, "face corner", "face corners")
        ));
    }
    if computed > 0 && given > 0 {
        notes.push(format!(
            "{computed} of {} face corners had no usable normal in the file; computed smooth normals for them",
            computed + given
        ));
    }
    if cancelled > 0 {
        notes.push(format!(
            "{}: the neighbouring face normals cancel out (two-sided or folded surface), used the face normal",
            plural(cancelled, "face corner", "face corners")
        ));
    }
    notes
}

/// The smoothing index of each position: equal positions (the same coordinates, -0 and +0
/// alike) share the index of the first of them (for the glTF and PLY readers, module doc).
/// The count of distinct positions is the largest index + 1.
pub(crate) fn weld(positions: &[DVec3]) -> Vec<usize> {
    let mut first: HashMap<[u64; 3], usize> = HashMap::with_capacity(positions.len());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let key = p.to_array().map(|c| (c + 0.0).to_bits());
            *first.entry(key).or_insert(i)
        })
        .collect()
}
