//! Tests of the method table: names, inputs, f64 twins against the formulas.
use glam::{DVec2, DVec3};

use super::*;

#[test]
fn names_are_unique_snake_case_and_have_glsl_files() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (i, m) in METHODS.iter().enumerate() {
        assert!(
            m.name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'),
            "{} is not snake_case",
            m.name
        );
        assert!(
            METHODS[..i].iter().all(|o| o.name != m.name),
            "duplicate method {}",
            m.name
        );
        assert!(
            root.join("glsl").join(m.glsl).is_file(),
            "{}: glsl/{} missing",
            m.name,
            m.glsl
        );
        assert!(!m.inputs.is_empty(), "{} needs no input", m.name);
    }
}

#[test]
fn every_identifier_of_the_issue_is_present() {
    let want = [
        "flat",
        "gouraud",
        "phong_exact",
        "phong_unnormalized",
        "safe_normalize",
        "filament_clamp",
        "newton_raphson",
        "lyon_taylor",
        "lyon_shift",
        "hast_half_vector",
        "mikami_const",
        "mikami_linear",
        "mikami_quadratic",
        "romanyuk_poly",
        "quaternion",
        "quaternion_local",
        "barycentric_quadratic",
        "barycentric_quadratic_exact_mid",
        "pn_normals",
        "trueform",
        "specular_lut",
        "slerp",
        "spherical_angular",
        "quadratic_scanline",
        "quadratic_scanline_approx_mid",
        "dichotomy_exact",
        "dichotomy_poly1",
        "dichotomy_poly2",
        "segments_k1",
        "segments_k2",
        "segments_k3",
        "segments_k2_poly1",
        "segments_k2_poly2",
        "segments_k3_poly1",
        "segments_k3_poly2",
        "bishop_weimer",
        "hast_euler",
    ];
    let have: Vec<_> = METHODS.iter().map(|m| m.name).collect();
    assert_eq!(have, want);
}

#[test]
fn find_reports_valid_names() {
    assert_eq!(find("phong_exact").unwrap().name, "phong_exact");
    let e = find("phong_exakt").unwrap_err().to_string();
    assert!(
        e.contains("unknown method \"phong_exakt\"") && e.contains("phong_exact"),
        "{e}"
    );
}

/// At a vertex (one weight 1) every normalization method reproduces the vertex normal up to
/// its own factor at z = 1, and the colour methods reproduce the vertex colour.
#[test]
fn methods_are_consistent_at_vertices() {
    let n0 = DVec3::new(0.3, 0.2, 1.0).normalize();
    let frag = Fragment {
        weights: DVec3::X,
        // The pixel on corner 0, so the scanline methods' span ends there too.
        pixel: DVec2::new(10.0, 10.0),
        window: [
            DVec2::new(10.0, 10.0),
            DVec2::new(30.0, 12.0),
            DVec2::new(15.0, 40.0),
        ],
        corner_normals: [n0, DVec3::Y, DVec3::X],
        flat_normal: DVec3::new(0.2, 0.3, 1.0).normalize(),
        pn_mids: [DVec3::Z; 3],
    };
    let lit = Lighting::new(
        DVec3::splat(0.1),
        DVec3::splat(0.6),
        DVec3::splat(0.3),
        20.0,
        &[(
            DVec3::new(0.0, 0.6, 0.8),
            DVec3::ONE,
            DVec3::new(0.0, 0.316, 0.949).normalize(),
        )],
    );
    let exact = lit.shade(n0);
    // Not exact at a vertex by construction: flat (one normal per triangle), the Mikami and
    // Romanyuk factors (k(1) != 1), Bishop-Weimer (a Taylor polynomial about the centroid).
    for m in METHODS.iter().filter(|m| {
        !matches!(
            m.name,
            "flat"
                | "mikami_const"
                | "mikami_linear"
                | "mikami_quadratic"
                | "romanyuk_poly"
                | "bishop_weimer"
        )
    }) {
        let s = m.eval_f64(&frag, &lit);
        assert!(
            (s.color - exact).abs().max_element() < 1e-3,
            "{}: {} vs {exact}",
            m.name,
            s.color
        );
        assert_eq!(s.normal.is_some(), m.has_normal, "{}", m.name);
    }
}

#[test]
fn properties_agree_with_the_columns_they_summarise() {
    let references: Vec<_> = with_property(Property::ExactReference)
        .map(|m| m.name)
        .collect();
    assert_eq!(references, [PHONG_EXACT], "exactly one exact reference");
    assert_eq!(phong_exact().name, PHONG_EXACT);
    for m in METHODS {
        assert_eq!(
            m.has(Property::NeedsSpanCorners),
            m.inputs.contains(&Input::ScanlineSpan),
            "{}: needs_span_corners must match its inputs",
            m.name
        );
        assert_eq!(
            m.has(Property::InterpolatesAngles),
            m.reference == Reference::PhongAndSlerp,
            "{}: interpolates_angles must match its reference",
            m.name
        );
        assert!(
            !m.has(Property::DriftsWithSpanLength) || m.has(Property::SoftwareSpanForm),
            "{}: only a span form can drift with the span's length",
            m.name
        );
        let mut seen = m.properties.to_vec();
        seen.dedup();
        assert_eq!(
            seen.len(),
            m.properties.len(),
            "{}: a property twice",
            m.name
        );
    }
    // `yours` and `tuned` hold only the methods of `--method-file` (none in the table).
    for family in Family::ALL
        .into_iter()
        .filter(|f| !matches!(f, Family::Yours | Family::Tuned))
    {
        let n = METHODS.iter().filter(|m| m.family == family).count();
        assert!(
            (1..=9).contains(&n),
            "{}: {n} methods (a chart panel holds 1..=9)",
            family.as_str()
        );
    }
    assert!(METHODS
        .iter()
        .all(|m| !matches!(m.family, Family::Yours | Family::Tuned) && m.twin().is_some()));
    // The papers' square-root-free methods (docs/formulas.md#exact-phong) are all per-pixel
    // forms.
    for m in with_property(Property::SqrtFree) {
        assert!(
            m.inputs.iter().all(|i| !matches!(i, Input::ScanlineSpan)),
            "{}",
            m.name
        );
    }
}

/// The method names a row's claims refer to that are not rows (a speed factor's `than`, an
/// error ratio's `than`).
fn unknown_names(m: &Method) -> Vec<String> {
    let mut out = Vec::new();
    for c in m.claims {
        let names: &[&str] = match &c.kind {
            Kind::Speed { than, .. } => std::slice::from_ref(than),
            Kind::ErrorBound(Bound::TimesSmaller { than, .. }) => than,
            _ => &[],
        };
        for n in names {
            if find(n).is_err() {
                out.push(format!("{}: {} names {n}", m.name, c.claim));
            }
        }
    }
    out
}

#[test]
fn every_method_a_claim_compares_with_is_a_row() {
    let bad: Vec<String> = METHODS.iter().flat_map(unknown_names).collect();
    assert!(bad.is_empty(), "{bad:?}");
    // teeth: a speed claim against a method that is not a row is found
    let wrong = Method {
        claims: &[Claim {
            claim: "faster than nothing",
            kind: Kind::Speed {
                factor: 2.0,
                than: "no_such_method",
            },
            basis: Basis::Measured,
            check: Check::Elsewhere,
        }],
        ..*phong_exact()
    };
    assert_eq!(unknown_names(&wrong).len(), 1);
}
