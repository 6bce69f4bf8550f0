//! The table of shading methods: the single source of truth for the CLI (`shadelab list`), the
//! shader variants (src/shaders.rs), the f64 twins (src/formulas.rs) and every output.
//! Identifiers are snake_case and appear unchanged in file names, CLI arguments, CSV and JSON.
use glam::DVec3;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::formulas;

/// A per-fragment input a method needs from the pipeline (becomes a varying and a vertex stream).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Input {
    /// The linearly interpolated (not unit) view-space vertex normal.
    InterpolatedNormal,
}

impl Input {
    /// The GLSL define that declares this input's varying (glsl/common.glsl).
    pub fn define(self) -> &'static str {
        match self {
            Input::InterpolatedNormal => "IN_NORMAL",
        }
    }
}

/// What the f64 twin of a method sees at one pixel: the interpolation weights the rasterizer
/// used and the triangle's corner data exactly as uploaded (f32 values widened to f64).
#[derive(Debug, Clone, Copy)]
pub struct Fragment {
    /// Interpolation weights of corners 0, 1, 2.
    pub weights: DVec3,
    /// Unit view-space vertex normals of the three corners.
    pub corner_normals: [DVec3; 3],
}

impl Fragment {
    /// The interpolated normal `N = sum w_i N_i` (FORMULAS.md 1.1).
    pub fn interpolated_normal(&self) -> DVec3 {
        self.corner_normals[0] * self.weights.x
            + self.corner_normals[1] * self.weights.y
            + self.corner_normals[2] * self.weights.z
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
    /// The range in which the paper says it is valid.
    pub validity: &'static str,
    /// Numerical claims the papers make about it (checked by tests and `bench`).
    pub claims: &'static [&'static str],
    /// The GLSL file under glsl/methods/ that defines `vec3 methodNormal()`.
    #[serde(skip)]
    pub glsl: &'static str,
    /// The same formula in f64: the shading normal at a fragment.
    #[serde(skip)]
    pub normal_f64: fn(&Fragment) -> DVec3,
}

/// Every method, in presentation order.
pub static METHODS: &[Method] = &[
    Method {
        name: "phong_exact",
        description: "Phong with exact normalization N/|N|: the reference",
        citation: "Phong 1975; S002 l.104-150, S004 l.83-94 (FORMULAS.md 2.3)",
        inputs: &[Input::InterpolatedNormal],
        validity: "any non-zero interpolated normal",
        claims: &["normalization costs 3 divisions + 3 multiplications + 2 additions + 1 square root (S004 l.159-163)"],
        glsl: "methods/phong_exact.glsl",
        normal_f64: |f| formulas::normalize_exact(f.interpolated_normal()),
    },
    Method {
        name: "phong_unnormalized",
        description: "Phong without normalization: the cost floor and an error ceiling",
        citation: "baseline (FORMULAS.md 1.3)",
        inputs: &[Input::InterpolatedNormal],
        validity: "exact only where the interpolated normal has unit length (at vertices)",
        claims: &[],
        glsl: "methods/phong_unnormalized.glsl",
        normal_f64: |f| f.interpolated_normal(),
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
        }
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
}
