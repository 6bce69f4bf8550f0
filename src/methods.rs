//! The table of shading methods: the single source of truth for the CLI (`shadelab list`), the
//! shader variants (src/shaders.rs), the vertex streams a run uploads (src/render.rs), the f64
//! twins (src/formulas.rs) and every output. Identifiers are snake_case and appear unchanged in
//! file names, CLI arguments, CSV and JSON.
use std::sync::OnceLock;

use glam::DVec3;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::formulas::{self as f, Lighting};

/// A per-fragment input a method needs from the pipeline. Each becomes GLSL defines (the
/// vertex streams it reads, `ATTR_*`, and the varyings it declares, `IN_*`, in
/// glsl/common.glsl); a run uploads only the streams its methods need.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Input {
    /// The linearly interpolated (not unit) view-space vertex normal.
    InterpolatedNormal,
    /// The triangle's unit flat normal (a `flat` varying).
    FlatNormal,
    /// Interpolation weights of the three corners (a one-hot varying).
    Barycentrics,
    /// The triangle's three unit vertex normals (`flat` varyings).
    CornerNormals,
    /// The PN triangle's mid-edge normals n110, n011, n101 (`flat`, set up on the CPU in f64).
    PnMidNormals,
    /// Gouraud: the colour lit at each vertex, interpolated.
    VertexColor,
    /// A quaternion per vertex (view space), interpolated.
    Quaternion,
    /// A quaternion per vertex in a per-triangle frame whose +Z is the flat normal.
    QuaternionLocal,
    /// The cos^n lookup table (a storage buffer).
    SpecularLut,
}

impl Input {
    /// The GLSL defines this input needs in both stages.
    pub fn defines(self) -> &'static [&'static str] {
        match self {
            Input::InterpolatedNormal => &["ATTR_NORMAL", "IN_NORMAL"],
            Input::FlatNormal => &["ATTR_FLAT", "IN_FLAT"],
            Input::Barycentrics => &["IN_BARY"],
            Input::CornerNormals => &["ATTR_CORNERS", "IN_CORNERS"],
            Input::PnMidNormals => &["ATTR_PN", "IN_PN"],
            Input::VertexColor => &["ATTR_NORMAL", "IN_COLOR"],
            Input::Quaternion => &["ATTR_NORMAL", "IN_QUAT"],
            Input::QuaternionLocal => &["ATTR_NORMAL", "ATTR_FLAT", "IN_QUAT", "QUAT_LOCAL"],
            Input::SpecularLut => &["USE_LUT"],
        }
    }
}

/// The geometry a method draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Geometry {
    /// The scene's triangles as they are.
    Mesh,
    /// Every triangle replaced by its PN patch tessellated at this level (level^2 sub-triangles).
    PnTessellated(u32),
}

/// Which exact reference a method is judged against (FORMULAS.md 1.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reference {
    /// Exact Phong: linear interpolation, then normalization.
    Phong,
    /// Angle-based methods: exact Phong and exact slerp (the scanline family, later).
    PhongAndSlerp,
}

/// A numerical claim of the papers and what this project measured.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Claim {
    /// The claim, with its source (seed file and line).
    pub claim: &'static str,
    /// The project's measurement and the command or test that produced it.
    pub measured: &'static str,
    /// `agrees`, `disagrees`, `partly` or `not_checked`.
    pub verdict: &'static str,
}

/// What the f64 twin of a method sees at one pixel: the interpolation weights the rasterizer
/// used and the triangle's data exactly as uploaded (f32 values widened to f64).
#[derive(Debug, Clone, Copy)]
pub struct Fragment {
    /// Interpolation weights of corners 0, 1, 2.
    pub weights: DVec3,
    /// Unit view-space vertex normals of the three corners.
    pub corner_normals: [DVec3; 3],
    /// Unit flat normal of the triangle, view space.
    pub flat_normal: DVec3,
    /// PN mid-edge normals n110, n011, n101, view space.
    pub pn_mids: [DVec3; 3],
}

impl Fragment {
    /// The interpolated normal `N = sum w_i N_i` (FORMULAS.md 1.1).
    pub fn interpolated_normal(&self) -> DVec3 {
        self.interpolate(self.corner_normals)
    }

    /// Linear interpolation of per-corner values with the weights.
    pub fn interpolate(&self, v: [DVec3; 3]) -> DVec3 {
        v[0] * self.weights.x + v[1] * self.weights.y + v[2] * self.weights.z
    }
}

/// The result of a method at a pixel: colour, and the shading normal where it has one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shaded {
    pub color: DVec3,
    pub normal: Option<DVec3>,
}

impl Shaded {
    /// Lit with the shared lighting model (glsl/shading.glsl).
    pub fn lit(normal: DVec3, lighting: &Lighting) -> Self {
        Shaded {
            color: lighting.shade(normal),
            normal: Some(normal),
        }
    }
}

/// One shading method.
#[derive(Debug, Serialize)]
pub struct Method {
    /// Identifier (snake_case), used everywhere.
    pub name: &'static str,
    /// One line.
    pub description: &'static str,
    /// Paper and seed file/line (FORMULAS.md section).
    pub citation: &'static str,
    /// Pipeline inputs it needs; only these varyings and vertex streams are set up.
    pub inputs: &'static [Input],
    /// The geometry it draws.
    pub geometry: Geometry,
    /// Whether it produces a per-pixel shading normal (normal metrics are null otherwise).
    pub has_normal: bool,
    /// The reference it is judged against.
    pub reference: Reference,
    /// The range in which the paper says it is valid.
    pub validity: &'static str,
    /// Numerical claims the papers make about it, with the project's measurement.
    pub claims: &'static [Claim],
    /// The GLSL file under glsl/ that defines `methodNormal()` or `methodColor()`.
    pub glsl: &'static str,
    /// The same method in f64 at one pixel.
    #[serde(skip)]
    pub eval_f64: fn(&Fragment, &Lighting) -> Shaded,
}

fn scalar(frag: &Fragment, lit: &Lighting, k: fn(f64) -> f64) -> Shaded {
    let n = frag.interpolated_normal();
    Shaded::lit(n * k(n.length_squared()), lit)
}

fn mikami(frag: &Fragment, lit: &Lighting, beta: fn(f64) -> f64) -> Shaded {
    let n = frag.interpolated_normal();
    let z = n.length_squared();
    Shaded::lit(n / f::mikami_sqrt(z, beta(z)), lit)
}

fn gouraud(frag: &Fragment, lit: &Lighting) -> Shaded {
    let c = frag.corner_normals.map(|n| lit.shade(n));
    Shaded {
        color: frag.interpolate(c),
        normal: None,
    }
}

fn quaternion_local(frag: &Fragment, lit: &Lighting) -> Shaded {
    let n = frag.flat_normal;
    let (t, b) = f::onb(n);
    let q = frag
        .corner_normals
        .map(|v| f::quat_from_normal(DVec3::new(v.dot(t), v.dot(b), v.dot(n))));
    let l = f::normal_from_quat(frag.interpolate(q));
    Shaded::lit(t * l.x + b * l.y + n * l.z, lit)
}

/// The cos^n table, built once (formulas::specular_lut).
pub fn specular_table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| f::specular_lut(f::LUT_ROWS, f::LUT_SAMPLES))
}

fn specular_lut(frag: &Fragment, lit: &Lighting) -> Shaded {
    let n = f::normalize_exact(frag.interpolated_normal());
    let mut c = lit.ambient;
    for &(l, color, h) in &lit.lights {
        let d = n.dot(l).max(0.0);
        let s = n.dot(h).max(0.0);
        let sp = f::lut_lookup(
            specular_table(),
            f::LUT_ROWS,
            f::LUT_SAMPLES,
            lit.shininess,
            s,
        );
        c += color * (lit.diffuse * d + lit.specular * sp);
    }
    Shaded {
        color: c,
        normal: Some(n),
    }
}

const N: &[Input] = &[Input::InterpolatedNormal];

/// Every method, in presentation order.
pub static METHODS: &[Method] = &[
    Method {
        name: "flat",
        description: "flat (one-tone) shading: one unit polygon normal per triangle",
        citation: "S002 l.43-55, S004 l.18-24 (FORMULAS.md 2.1)",
        inputs: &[Input::FlatNormal],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "any non-degenerate triangle",
        claims: &[],
        glsl: "methods/flat.glsl",
        eval_f64: |fr, l| Shaded::lit(fr.flat_normal, l),
    },
    Method {
        name: "gouraud",
        description: "Gouraud: lighting at the vertices, colour interpolated",
        citation: "Gouraud 1971; S002 l.57-102, S004 l.26-48 (FORMULAS.md 2.2)",
        inputs: &[Input::VertexColor],
        geometry: Geometry::Mesh,
        has_normal: false,
        reference: Reference::Phong,
        validity: "any mesh; misses highlights inside triangles",
        claims: &[Claim {
            claim: "Phong shading of an average triangle takes more than 50x longer than Gouraud (S002 l.151-153)",
            measured: "a timing claim: checked by `shadelab bench` (bench milestone)",
            verdict: "not_checked",
        }],
        glsl: "methods/gouraud.glsl",
        eval_f64: gouraud,
    },
    Method {
        name: "phong_exact",
        description: "Phong with exact normalization N/|N|: the reference",
        citation: "Phong 1975; S002 l.104-150, S004 l.83-94 (FORMULAS.md 2.3)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "any non-zero interpolated normal",
        claims: &[Claim {
            claim: "normalization costs 3 divisions + 3 multiplications + 2 additions + 1 square root (S004 l.159-163)",
            measured: "an operation count: checked against the SPIR-V by `shadelab bench` (bench milestone)",
            verdict: "not_checked",
        }],
        glsl: "methods/phong_exact.glsl",
        eval_f64: |fr, l| Shaded::lit(f::normalize_exact(fr.interpolated_normal()), l),
    },
    Method {
        name: "phong_unnormalized",
        description: "Phong without normalization: the cost floor and an error ceiling",
        citation: "baseline (FORMULAS.md 1.3)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "exact only where the interpolated normal has unit length (at vertices)",
        claims: &[],
        glsl: "methods/phong_unnormalized.glsl",
        eval_f64: |fr, l| Shaded::lit(fr.interpolated_normal(), l),
    },
    Method {
        name: "newton_raphson",
        description: "one Newton-Raphson step for 1/sqrt(z) from 1: N (3 - z)/2",
        citation: "S. Cutler (NVIDIA) via C. Everitt; S000 l.33-38, S004 l.167-172 (FORMULAS.md 2.4)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "angle between vertex normals <= 40 degrees (S000 l.35)",
        claims: &[
            Claim {
                claim: "usable for angles between vertex normals up to 40 (degrees assumed) (S000 l.35)",
                measured: "length error at the edge midpoint -0.535 % at 40 deg, -2.57 % at 60 deg (formulas tests)",
                verdict: "agrees",
            },
            Claim {
                claim: "S004 l.169 prints N (3 - N.N)/3",
                measured: "k(1) = 2/3 with /3; /2 gives k(1) = 1 (formulas tests): a seed typo",
                verdict: "disagrees",
            },
        ],
        glsl: "methods/newton_raphson.glsl",
        eval_f64: |fr, l| scalar(fr, l, f::k_newton),
    },
    Method {
        name: "lyon_taylor",
        description: "Lyon: 2nd-degree Taylor series of 1/sqrt(z) about 1",
        citation: "R. Lyon, Apple TR #43 (1993); S000 l.45-50, S004 l.174-183 (FORMULAS.md 2.5)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "z = N.N near 1 (small angles between vertex normals)",
        claims: &[Claim {
            claim: "the approximation error is large (S004 l.181-183)",
            measured: "length error at the edge midpoint -0.0524 % at 40 deg, -0.542 % at 60 deg, -4.98 % at 90 deg (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/lyon_taylor.glsl",
        eval_f64: |fr, l| scalar(fr, l, f::k_lyon2),
    },
    Method {
        name: "lyon_shift",
        description: "Lyon, shift-friendly form: 1 + ((1 - z) + (1 - z)^2)/2",
        citation: "S000 l.52-53 (FORMULAS.md 2.6)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "z = N.N near 1",
        claims: &[],
        glsl: "methods/lyon_shift.glsl",
        eval_f64: |fr, l| scalar(fr, l, f::k_lyon_shift),
    },
    Method {
        name: "hast_half_vector",
        description: "Hast-Barrera-Bengtsson: reflect the flat normal about H = n + N, no square root",
        citation: "Hast, Barrera, Bengtsson, WSCG 2001; S000 l.55-63 (FORMULAS.md 2.7)",
        inputs: &[Input::InterpolatedNormal, Input::FlatNormal],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "vertex normals not opposite to the flat normal (H.H > 0)",
        claims: &[Claim {
            claim: "normalization without a square root (S000 l.55-63)",
            measured: "|N'| = 1 exactly; angle error 0.24 deg (40 deg, flat normal on the bisector) to 10.3 deg (90 deg, flat = vertex normal) (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/hast_half_vector.glsl",
        eval_f64: |fr, l| Shaded::lit(f::hbb(fr.interpolated_normal(), fr.flat_normal), l),
    },
    Method {
        name: "mikami_const",
        description: "Mikami nonlinear-IIR square root, first iteration, beta = 0.64",
        citation: "Mikami, Kobayashi, Yokoyama, IEEE TSP 1992; S000 l.65-75 (FORMULAS.md 2.8)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "z = N.N in [0.25, 1]",
        claims: &[Claim {
            claim: "maximum normalised relative error <= 1.5 % (S000 l.74)",
            measured: "1.15 % on z in [0.25, 1]; +0.487 % at z = 1 (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/mikami_const.glsl",
        eval_f64: |fr, l| mikami(fr, l, f::beta_const),
    },
    Method {
        name: "mikami_linear",
        description: "Mikami first iteration, beta = 1.07 - 0.62 z",
        citation: "S000 l.65-75 (FORMULAS.md 2.8)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "z = N.N in [0.25, 1]",
        claims: &[Claim {
            claim: "maximum normalised relative error <= 1.5 % (S000 l.74)",
            measured: "0.23 % on z in [0.25, 1]; -0.154 % at z = 1 (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/mikami_linear.glsl",
        eval_f64: |fr, l| mikami(fr, l, f::beta_linear),
    },
    Method {
        name: "mikami_quadratic",
        description: "Mikami first iteration, beta = 0.763 z^2 - 1.57 z + 1.31",
        citation: "S000 l.65-75 (FORMULAS.md 2.8)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "z = N.N in [0.25, 1]",
        claims: &[Claim {
            claim: "maximum normalised relative error <= 1.5 % (S000 l.74)",
            measured: "0.080 % on z in [0.25, 1]; +0.024 % at z = 1 (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/mikami_quadratic.glsl",
        eval_f64: |fr, l| mikami(fr, l, f::beta_quadratic),
    },
    Method {
        name: "romanyuk_poly",
        description: "Romanyuk-Romanyuk-Pavlyk polynomial k(z) = 0.822 z^2 - 2.046 z + 2.227",
        citation: "O. V. Romanyuk, O. N. Romanyuk, T. M. Pavlyk; S000 l.78-82 (FORMULAS.md 2.9)",
        inputs: N,
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "angle between vertex normals <= 90 degrees (z in [0.5, 1], the fit range)",
        claims: &[Claim {
            claim: "relative error 8x smaller than Lyon's approach (S000 l.79-80)",
            measured: "theta <= 90 deg: 0.351 % vs Lyon shift 2.77 % (7.9x) and Lyon 2nd degree 4.98 % (14.2x); theta <= 60 deg: 0.300 %, worse than Lyon shift 0.176 % (formulas tests)",
            verdict: "partly",
        }],
        glsl: "methods/romanyuk_poly.glsl",
        eval_f64: |fr, l| scalar(fr, l, f::k_romanyuk),
    },
    Method {
        name: "quaternion",
        description: "quaternion interpolation in view space, normal recovered without a square root",
        citation: "A. Hast, WSCG 2005; S000 l.183-203 (FORMULAS.md 2.14)",
        inputs: &[Input::Quaternion],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "vertex normals away from -Z in view space (n_z > -1)",
        claims: &[Claim {
            claim: "no square root needed (S000 l.187)",
            measured: "|N'| = 1 exactly; angle vs normalize(lerp) 0.24 / 0.85 / 3.17 deg at 40 / 60 / 90 deg for a pair symmetric about +Z; grows away from +Z (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/quaternion.glsl",
        eval_f64: |fr, l| {
            let q = fr.corner_normals.map(f::quat_from_normal);
            Shaded::lit(f::normal_from_quat(fr.interpolate(q)), l)
        },
    },
    Method {
        name: "quaternion_local",
        description: "quaternion interpolation in a per-triangle frame whose +Z is the flat normal (= hast_half_vector with per-vertex normalised half vectors)",
        citation: "FORMULAS.md 2.14 (recommended variant of Hast's method)",
        inputs: &[Input::QuaternionLocal, Input::FlatNormal],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "vertex normals within 180 degrees of the flat normal",
        claims: &[],
        glsl: "methods/quaternion_local.glsl",
        eval_f64: quaternion_local,
    },
    Method {
        name: "barycentric_quadratic",
        description: "quadratic triangle with polynomial mid-edge normals M_ij",
        citation: "Barrera, Hast, Bengtsson, WSCG 2006; S000 l.205-213 (FORMULAS.md 2.15)",
        inputs: &[Input::CornerNormals, Input::Barycentrics],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "angle between vertex normals <= 90 degrees (the M_ij polynomial's fit range)",
        claims: &[],
        glsl: "methods/barycentric_quadratic.glsl",
        eval_f64: |fr, l| Shaded::lit(f::bary_quad(fr.corner_normals, fr.weights, f::m_ij), l),
    },
    Method {
        name: "barycentric_quadratic_exact_mid",
        description: "quadratic triangle with exact mid-edge normals normalize(N_i + N_j)",
        citation: "S000 l.205-213 (FORMULAS.md 2.15)",
        inputs: &[Input::CornerNormals, Input::Barycentrics],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "vertex normals not opposite",
        claims: &[],
        glsl: "methods/barycentric_quadratic_exact_mid.glsl",
        eval_f64: |fr, l| Shaded::lit(f::bary_quad(fr.corner_normals, fr.weights, f::m_ij_exact), l),
    },
    Method {
        name: "pn_normals",
        description: "quadratic normal field of curved PN triangles, per fragment on the flat geometry",
        citation: "Vlachos, Peters, Boyd, Mitchell, I3D 2001; S004 l.50-64 (FORMULAS.md 2.19)",
        inputs: &[Input::CornerNormals, Input::PnMidNormals, Input::Barycentrics],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "any mesh with smooth vertex normals",
        claims: &[],
        glsl: "methods/pn_normals.glsl",
        eval_f64: |fr, l| Shaded::lit(f::normalize_exact(f::pn_normal(fr.corner_normals, fr.pn_mids, fr.weights)), l),
    },
    Method {
        name: "trueform",
        description: "ATI TrueForm: 9 PN sub-triangles per triangle (level 3), Gouraud on the result",
        citation: "S004 l.50-64 (FORMULAS.md 2.19)",
        inputs: &[Input::VertexColor],
        geometry: Geometry::PnTessellated(3),
        has_normal: false,
        reference: Reference::Phong,
        validity: "any mesh with smooth vertex normals",
        claims: &[Claim {
            claim: "9 sub-triangles per triangle: 2 extra vertices per edge + 1 centre (S004 l.54-59)",
            measured: "level-3 tessellation: 10 vertices, 9 triangles (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/trueform.glsl",
        eval_f64: gouraud,
    },
    Method {
        name: "specular_lut",
        description: "exact normal; specular cos^n from a 2-D table indexed by (N.H, n)",
        citation: "S004 l.197-204, ref [16] (FORMULAS.md 2.20)",
        inputs: &[Input::InterpolatedNormal, Input::SpecularLut],
        geometry: Geometry::Mesh,
        has_normal: true,
        reference: Reference::Phong,
        validity: "integer shininess 1..255 (rounded and clamped otherwise)",
        claims: &[Claim {
            claim: "tables for n = 1..255 need more than 4 MB (S004 l.201-203)",
            measured: "255 x 8192 cosines x 16 bit = 4.18 MB; this table: 255 x 4096 x 32 bit = 4.18 MB (formulas tests)",
            verdict: "agrees",
        }],
        glsl: "methods/specular_lut.glsl",
        eval_f64: specular_lut,
    },
];

/// Looks a method up by identifier; the error lists the valid ones.
pub fn find(name: &str) -> Result<&'static Method> {
    METHODS.iter().find(|m| m.name == name).ok_or_else(|| {
        Error::Usage(format!(
            "unknown method {name:?}; valid methods: {} (see `shadelab list`)",
            METHODS
                .iter()
                .map(|m| m.name)
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })
}

#[cfg(test)]
mod tests {
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
            corner_normals: [n0, DVec3::Y, DVec3::X],
            flat_normal: DVec3::new(0.2, 0.3, 1.0).normalize(),
            pn_mids: [DVec3::Z; 3],
        };
        let lit = Lighting {
            ambient: DVec3::splat(0.1),
            diffuse: DVec3::splat(0.6),
            specular: DVec3::splat(0.3),
            shininess: 20.0,
            lights: vec![(
                DVec3::new(0.0, 0.6, 0.8),
                DVec3::ONE,
                DVec3::new(0.0, 0.316, 0.949).normalize(),
            )],
        };
        let exact = lit.shade(n0);
        for m in METHODS.iter().filter(|m| {
            !matches!(
                m.name,
                "flat" | "mikami_const" | "mikami_linear" | "mikami_quadratic" | "romanyuk_poly"
            )
        }) {
            let s = (m.eval_f64)(&frag, &lit);
            assert!(
                (s.color - exact).abs().max_element() < 1e-3,
                "{}: {} vs {exact}",
                m.name,
                s.color
            );
            assert_eq!(s.normal.is_some(), m.has_normal, "{}", m.name);
        }
    }
}
