//! Test-only helpers shared by the unit tests of every module.

/// Approx-eq that prints both sides (glam tests/support/macros.rs style).
#[track_caller]
pub fn assert_close(what: &str, actual: f64, expected: f64, tol: f64) {
    let diff = (actual - expected).abs();
    assert!(
        diff <= tol,
        "{what}: actual {actual:.12}, expected {expected:.12}, |diff| {diff:.3e} > tol {tol:.1e}"
    );
}
