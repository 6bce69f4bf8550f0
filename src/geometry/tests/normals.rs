//! Normals: computed (angle-weighted, per position index) where the file has none, given ones
//! kept split and normalised.
use super::*;

#[test]
fn missing_normals_are_computed_angle_weighted_per_position() {
    let (mesh, report) = load_text(UNIT_CUBE).unwrap();
    assert!(report.computed_normals);
    assert_eq!(report.triangles, 12);
    // Each cube corner sees 90 deg of each of its 3 faces, however the quads were split,
    // so the angle-weighted normal is exactly the diagonal direction.
    let inv = 1.0 / 3f64.sqrt();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        for k in 0..3 {
            let expected = p[k].signum() as f64 * inv;
            assert_close(
                &format!("normal {n:?} at corner {p:?}, axis {k}"),
                n[k] as f64,
                expected,
                1e-6,
            );
        }
    }
}

#[test]
fn texcoord_seams_do_not_split_computed_normals() {
    // Same position 1 used with two different texture coordinates: still one normal.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 1/2 3/3 4/1\n";
    let (mesh, _) = load_text(text).unwrap();
    let origin = mesh.positions[0];
    let normals: Vec<[f32; 3]> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .filter(|(p, _)| **p == origin)
        .map(|(_, n)| *n)
        .collect();
    assert_eq!(normals.len(), 2);
    assert_eq!(
        normals[0], normals[1],
        "both corners at the shared position share one normal"
    );
}

#[test]
fn repeated_positions_are_not_welded_and_say_so() {
    // Vertices 1 and 5 coincide: two fans meeting there keep separate normals.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 0 0\nf 1 2 3\nf 5 4 2\n";
    let (mesh, report) = load_text(text).unwrap();
    assert_ne!(
        mesh.normals[0], mesh.normals[3],
        "per-index smoothing: the two copies differ"
    );
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("splits at 1 position defined under more than one index")),
        "{:?}",
        report.warnings
    );
}

#[test]
fn given_normals_are_kept_split_and_normalized() {
    // Two triangles sharing an edge, each with its own (non-unit) flat normal: a crease.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 -2\nvn -3 0 0\nf 1//1 3//1 2//1\nf 1//2 4//2 3//2\n";
    let (mesh, report) = load_text(text).unwrap();
    assert!(
        !report.computed_normals,
        "every corner had a normal: {report:?}"
    );
    assert_eq!(
        &mesh.normals[..3],
        &[[0.0, 0.0, -1.0]; 3],
        "first triangle keeps its normal, normalized"
    );
    assert_eq!(
        &mesh.normals[3..],
        &[[-1.0, 0.0, 0.0]; 3],
        "second triangle keeps its split normal"
    );
}

#[test]
fn mixed_files_compute_normals_only_where_missing() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1 0\nvn 0 0 0\nf 1//1 2 3//2\n";
    let (mesh, report) = load_text(text).unwrap();
    assert!(report.computed_normals);
    assert_eq!(mesh.normals[0], [0.0, 1.0, 0.0], "given normal kept");
    assert_eq!(
        mesh.normals[1],
        [0.0, 0.0, 1.0],
        "missing normal computed from the face"
    );
    assert_eq!(
        mesh.normals[2],
        [0.0, 0.0, 1.0],
        "zero-length normal treated as missing"
    );
    assert!(
        report.warnings.iter().any(|w| w.contains("zero-length")),
        "{:?}",
        report.warnings
    );
    assert!(
        report
            .warnings
            .iter()
            .any(|w| w.contains("2 of 3 face corners")),
        "{:?}",
        report.warnings
    );
}
