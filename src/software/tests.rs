//! Unit tests of the software engine (the drift measurement, which needs the f64 truth of a
//! higher layer, is in tests/software.rs).
use super::*;
use crate::method::{self, Geometry, METHODS};

/// Whether a row's properties agree with its software kernel: the incremental span kernels
/// (and Gouraud's stepped colours) are its span form, slerp's closed form per pixel is not; the
/// recurrences whose rounding grows along the span drift. `None` when they agree.
fn form_mismatch(m: &Method) -> Option<String> {
    use Kernel as K;
    let span_form = match m.kernel {
        K::VertexColour => true,
        K::Span(SpanKernel::Slerp) => false,
        K::Span(_) => true,
        K::Flat
        | K::Scaled(_)
        | K::HastHalfVector
        | K::Quaternion
        | K::QuaternionLocal
        | K::BarycentricQuadratic { .. }
        | K::PnNormals
        | K::SpecularLut
        | K::None => false,
    };
    let drifts = matches!(
        m.kernel,
        K::Span(
            SpanKernel::Chebyshev
                | SpanKernel::Quadratic { .. }
                | SpanKernel::BishopWeimer
                | SpanKernel::HastEuler
        )
    );
    let f = form_of(m);
    (f.scanline != span_form || f.drifts != drifts).then(|| {
        format!(
            "{}: kernel {:?} is span form {span_form}, drifts {drifts}; the row says {} and {}",
            m.name, m.kernel, f.scanline, f.drifts
        )
    })
}

/// Every row's kernel agrees with its properties and has words; the flags come from the row.
#[test]
fn forms_follow_each_rows_kernel_and_properties() {
    let bad: Vec<String> = METHODS.iter().filter_map(form_mismatch).collect();
    assert!(bad.is_empty(), "{bad:?}");
    for m in METHODS {
        assert!(!form_of(m).form.is_empty(), "{}", m.name);
        assert_eq!(form(m.name).form, form_of(m).form);
    }
    assert!(form("spherical_angular").scanline && form("spherical_angular").drifts);
    assert!(!form(method::PHONG_EXACT).scanline);
    // Teeth: a row whose properties disagree with its kernel is found, both ways.
    let cheb = method::find("spherical_angular").unwrap();
    let no_props = Method {
        properties: &[],
        ..*cheb
    };
    assert!(form_mismatch(&no_props).is_some());
    let exact = method::phong_exact();
    let claims_span = Method {
        properties: &[Property::SoftwareSpanForm],
        ..*exact
    };
    assert!(form_mismatch(&claims_span).is_some());
    let wrong_kernel = Method {
        kernel: Kernel::Span(SpanKernel::HastEuler),
        ..*exact
    };
    assert!(form_mismatch(&wrong_kernel).is_some());
    // A name outside the table has no form.
    assert!(form("auto").form.contains("not a method"));
}

/// Every row's kernel draws (the dispatch is typed: nothing falls to a default), and the kernel
/// is the row's own: swapping in another method's kernel changes the pixels.
#[test]
fn every_kernel_draws_and_the_kernel_decides_the_pixels() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
    let mut scene = crate::scene::load_scene(&path).unwrap();
    (scene.width, scene.height) = (48, 48);
    let mesh = SceneInputs::new(&scene, Geometry::Mesh);
    let draw = |m: &Method| {
        let pn;
        let inputs = if m.geometry == Geometry::Mesh {
            &mesh
        } else {
            pn = SceneInputs::new(&scene, m.geometry);
            &pn
        };
        render(inputs, m, 2, false).unwrap().0
    };
    for m in METHODS {
        let frame = draw(m);
        let lit = frame.color.iter().filter(|p| p[3] == 1.0).count();
        assert!(lit > 100, "{}: {lit} covered pixels", m.name);
        assert!(
            frame.color.iter().flatten().all(|v| v.is_finite()),
            "{}: non-finite pixels",
            m.name
        );
    }
    let exact = method::phong_exact();
    let as_newton = Method {
        kernel: method::find("newton_raphson").unwrap().kernel,
        ..*exact
    };
    assert_ne!(draw(exact).color, draw(&as_newton).color);
}
