//! The table of shading methods: the single source of truth for the CLI (`shadelab list`), the
//! shader variants (src/shaders.rs), the vertex streams a run uploads (src/render.rs), the f64
//! twins (src/formulas.rs) and every output. Identifiers are snake_case and appear unchanged in
//! file names, CLI arguments, CSV and JSON.
pub mod formulas;
pub mod scanline;
pub mod table;
#[cfg(test)]
mod tests;
pub mod twins;

pub use table::METHODS;
pub use twins::*;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::method::formulas::Lighting;
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
    /// The span through the fragment's row (FORMULAS.md 1.6): the triangle's window-space
    /// corners and unit vertex normals (`flat` varyings), and `gl_FragCoord`.
    ScanlineSpan,
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
            Input::ScanlineSpan => &["ATTR_CORNERS", "IN_CORNERS", "ATTR_WINDOW", "IN_WINDOW"],
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
