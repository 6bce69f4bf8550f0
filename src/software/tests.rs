//! Unit tests of the software engine (the drift measurement, which needs the f64 truth of a
//! higher layer, is in tests/software.rs).
use super::*;

#[test]
fn forms_name_every_method() {
    for m in crate::method::METHODS {
        assert!(!form(m.name).form.is_empty(), "{}", m.name);
    }
    assert!(form("spherical_angular").scanline && form("spherical_angular").drifts);
    assert!(!form("phong_exact").scanline);
}
