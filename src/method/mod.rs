//! The table of shading methods: the single source of truth for the CLI (`shadelab list`), the
//! shader variants (src/gpu/shaders.rs), the vertex streams a run uploads (src/gpu/renderer.rs),
//! the f64 twins (src/method/) and every output. Identifiers are snake_case and appear unchanged in
//! file names, CLI arguments, CSV and JSON.
pub mod checks;
pub mod formulas;
pub mod precision;
pub mod real;
pub mod scanline;
pub mod scanline_checks;
pub mod table;
#[cfg(test)]
mod tests;
pub mod twins;
pub mod user;
mod worst;

pub use precision::Precision;
pub use table::METHODS;
pub use twins::*;
pub use user::all;

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
    /// The span through the fragment's row (docs/formulas.md#scanline-emulation): the triangle's
    /// window-space corners and unit vertex normals (`flat` varyings), and `gl_FragCoord`.
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

/// Which exact reference a method is judged against (docs/formulas.md#the-two-references).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reference {
    /// Exact Phong: linear interpolation, then normalization.
    Phong,
    /// Angle-interpolating methods: exact Phong, and exact slerp along the span (`compare`
    /// reports both, so a reader sees how much of the error is the angle-proportional spacing).
    PhongAndSlerp,
}

/// The family a method belongs to: how it gets its shading normal (or colour). Charts draw one
/// panel per family, so a family stays small enough to read (at most 9 methods).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// The exact reference and the baselines every method sits between (flat, Gouraud,
    /// unnormalised Phong, exact Phong), and exact normalisation with the guards engines add
    /// for float16 (Unity's SafeNormalize, Filament's mediump clamp).
    Reference,
    /// The interpolated normal, normalised (or its lighting corrected) per pixel without an exact
    /// square root: Newton-Raphson, Taylor and polynomial fits, Mikami, Hast, a cos^n table.
    PerPixelNormalisation,
    /// Something other than the normal interpolated across the triangle: quaternions,
    /// quadratic normal fields over the triangle, TrueForm's vertex colours.
    VertexAttribute,
    /// Along the scanline span: angle interpolation, quadratic and Taylor forms, dichotomy.
    Scanline,
    /// Combined methods: exact shading at the ends of 2^k-pixel digital segments, interpolation
    /// between them.
    DigitalSegments,
    /// The user's own methods (`--method-file`, src/method/user.rs): no f64 twin, no software
    /// kernel.
    Yours,
}

impl Family {
    /// Every family, in presentation order.
    pub const ALL: [Family; 6] = [
        Family::Reference,
        Family::PerPixelNormalisation,
        Family::VertexAttribute,
        Family::Scanline,
        Family::DigitalSegments,
        Family::Yours,
    ];

    /// The snake_case name, as in the JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Reference => "reference",
            Family::PerPixelNormalisation => "per_pixel_normalisation",
            Family::VertexAttribute => "vertex_attribute",
            Family::Scanline => "scanline",
            Family::DigitalSegments => "digital_segments",
            Family::Yours => "yours",
        }
    }
}

/// A property of a method that code used to infer from its name. Each is a column of the table,
/// so a new method states it once and every consumer (claims, the software engine, stress,
/// tests) reads it from the row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Property {
    /// The exact reference every method is measured against ([`PHONG_EXACT`]).
    ExactReference,
    /// Avoids the square root and division of exact normalisation (both surveys,
    /// docs/formulas.md#exact-phong): each is claimed faster than exact normalisation.
    SqrtFree,
    /// Interpolates the angle between the span's end normals, not the normal itself (judged
    /// against exact slerp as well as exact Phong, [`Reference::PhongAndSlerp`]).
    InterpolatesAngles,
    /// Steps along the span incrementally, so its rounding error grows with the span's length
    /// (the software engine's drift allowance applies).
    DriftsWithSpanLength,
    /// Reads the span through the fragment's row: the triangle's window-space corners and unit
    /// vertex normals ([`Input::ScanlineSpan`]).
    NeedsSpanCorners,
    /// The software engine runs it in its incremental span form (the others run per pixel there).
    SoftwareSpanForm,
}

/// The identifier of the exact reference, [`Property::ExactReference`]. Use this constant, never
/// the literal, so the reference is named in one place.
pub const PHONG_EXACT: &str = "phong_exact";

/// The exact reference's row.
pub fn phong_exact() -> &'static Method {
    find(PHONG_EXACT).expect("the method table has phong_exact")
}

/// The methods with `property`, in table order.
pub fn with_property(property: Property) -> impl Iterator<Item = &'static Method> {
    METHODS.iter().filter(move |m| m.has(property))
}

/// The kernel the software engine (src/software/) runs for a method: one variant per distinct
/// incremental or per-pixel form. The engine matches it exhaustively, so a row without a kernel,
/// or a kernel without code, does not compile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SoftwareKernel {
    /// One colour per triangle.
    Flat,
    /// The colours lit at the vertices, stepped along the span.
    VertexColour,
    /// The interpolated normal stepped, scaled per pixel by a function of its squared length.
    Scaled(Scale),
    /// The interpolated normal stepped, divided by Mikami's square-root approximation.
    Mikami(MikamiBeta),
    /// The interpolated normal stepped, Hast's half-vector correction against the flat normal.
    HastHalfVector,
    /// A quaternion per vertex stepped, the normal recovered per pixel.
    Quaternion,
    /// [`SoftwareKernel::Quaternion`] in the triangle's frame (+Z the flat normal).
    QuaternionLocal,
    /// The weights stepped, the quadratic normal field evaluated per pixel (the mid-edge
    /// normals by the paper's formula, or exactly).
    BarycentricQuadratic { exact_mid: bool },
    /// The weights stepped, the PN quadratic normal evaluated and normalised per pixel.
    PnNormals,
    /// The normal stepped and normalised, the specular term read from the cos^n table.
    SpecularLut,
    /// Along the span through the pixel's row.
    Span(SpanKernel),
    /// None: a user method (`--method-file`) exists only as GLSL; the engine refuses it.
    None,
}

/// The scale of [`SoftwareKernel::Scaled`]: 1/|v| exactly, 1, or an approximation of 1/|v|.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Exact,
    Unnormalised,
    NewtonRaphson,
    LyonTaylor,
    LyonShift,
    RomanyukPoly,
    /// Unity's SafeNormalize: 1/sqrt(max(z, HALF_MIN)).
    SafeNormalize,
    /// Filament's mediump clamp before normalising: 1/sqrt(min(z, 65504)).
    FilamentClamp,
}

/// Mikami's beta (the square root's correction) of [`SoftwareKernel::Mikami`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MikamiBeta {
    Const,
    Linear,
    Quadratic,
}

/// The span kernels of [`SoftwareKernel::Span`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpanKernel {
    /// slerp at each pixel's t (the closed form).
    Slerp,
    /// spherical_angular's Chebyshev recurrence.
    Chebyshev,
    /// G t^2 + P t + Q by second-order forward differences.
    Quadratic { approx_mid: bool },
    /// The span's grid filled by halving, with this inverse square root.
    Dichotomy(InvRoot),
    /// 2^k-pixel segments: ends shaded, the colour stepped (or dichotomy inside with a root).
    Segments(u32, Option<InvRoot>),
    /// Each cosine's Taylor polynomial by forward differences.
    BishopWeimer,
    /// Each cosine by Euler steps with the end-error correction.
    HastEuler,
}

/// The inverse square root of the dichotomy and segment kernels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InvRoot {
    Exact,
    Poly1,
    Poly2,
}

/// A verdict on a claim, computed from a measurement (never written by hand).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The measurement supports the claim.
    Agrees,
    /// Some of the claim holds and some does not (each part is named in `measured`).
    Partly,
    /// The measurement contradicts the claim.
    Disagrees,
    /// The measurement cannot decide (e.g. overlapping 95% intervals).
    Inconclusive,
    /// Not measured by the code that writes it (the reason is in `how`).
    NotChecked,
}

impl Verdict {
    /// The snake_case name, as in the JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Agrees => "agrees",
            Verdict::Partly => "partly",
            Verdict::Disagrees => "disagrees",
            Verdict::Inconclusive => "inconclusive",
            Verdict::NotChecked => "not_checked",
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What a claim's verdict rests on (docs/proof.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// A bound judged by proof (`shadelab prove`'s branch-and-bound): agrees only when the
    /// proven upper bound supports the claim, disagrees when a found (real) point contradicts
    /// it, else inconclusive.
    Proven,
    /// A bound judged by the worst case found at sampled points only (a sweep or stress's
    /// grid): the true maximum may be larger, so an `agrees` is not a proof.
    Found,
    /// Not a bound over a domain: a timing, a count, a GPU image, a property of a formula.
    Measured,
}

impl Basis {
    pub fn as_str(self) -> &'static str {
        match self {
            Basis::Proven => "proven",
            Basis::Found => "found",
            Basis::Measured => "measured",
        }
    }
}

/// What a claim's `proven_upper` and `found` are figures of: their kind and unit, so that a
/// reader compares them with the claim in the claim's own terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// A relative error as a fraction (0.01 is 1 %): a length error |k(z)|N| - 1| or
    /// ||N'| - 1|, a normalised relative error, a relative intensity error.
    RelativeError,
    /// An absolute error, in the unit of the approximated value (an inverse root, a cosine,
    /// the components of a unit vector).
    AbsoluteError,
    /// The ratio of one method's worst relative error to another's (Romanyuk's / Lyon's): no
    /// unit; the claim "8x smaller" is a ratio <= 1/8.
    ErrorRatio,
}

impl Quantity {
    pub fn as_str(self) -> &'static str {
        match self {
            Quantity::RelativeError => "relative_error",
            Quantity::AbsoluteError => "absolute_error",
            Quantity::ErrorRatio => "error_ratio",
        }
    }
}

/// The evidence beside a verdict: its basis, and for a bound the proven upper bound of the
/// bounded quantity next to the largest value found at a real point (None where not given),
/// with what they are figures of.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Evidence {
    pub basis: Basis,
    pub proven_upper: Option<f64>,
    pub found: Option<f64>,
    /// The kind and unit of `proven_upper` and `found` (None: not a bound, no figures).
    pub quantity: Option<Quantity>,
}

impl Evidence {
    /// Not a bound.
    pub const MEASURED: Evidence = Evidence {
        basis: Basis::Measured,
        proven_upper: None,
        found: None,
        quantity: None,
    };

    /// A bound judged by the worst sampled value `found` (None when non-finite), a figure of
    /// `quantity`.
    pub fn found(found: f64, quantity: Quantity) -> Evidence {
        Evidence {
            basis: Basis::Found,
            proven_upper: None,
            found: found.is_finite().then_some(found),
            quantity: Some(quantity),
        }
    }
}

/// What a check measured, its verdict and how it was measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Measurement {
    /// The measured figures.
    pub measured: String,
    /// Derived from `measured` by the rule stated in `how`.
    pub verdict: Verdict,
    /// The sweep or command that measured it and the rule that turns it into the verdict.
    pub how: String,
    /// Proven, found or measured, with the figures.
    #[serde(flatten)]
    pub evidence: Evidence,
}

/// A numerical claim of the papers and the check that measures it.
///
/// Serialising a claim (`shadelab list --json`) runs its check, so the JSON holds `claim`,
/// `measured`, `verdict`, `basis`, `proven_upper`, `found`, `quantity` and `how` as measured at
/// that moment.
#[derive(Debug, Clone, Copy)]
pub struct Claim {
    /// The claim, with its source (`docs/formulas.md#<anchor>`).
    pub claim: &'static str,
    /// Measures the claim (an f64 sweep of the formula, see [`checks`]) and derives the verdict.
    pub check: fn() -> Measurement,
}

impl Serialize for Claim {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        serialize_claim(self.claim, &(self.check)(), s)
    }
}

/// A claim's 8 keys: its text and a measurement of it (the table's own check here, the proof
/// overlay in `crate::prove::bounds::Judged`).
pub fn serialize_claim<S: serde::Serializer>(
    claim: &str,
    m: &Measurement,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = s.serialize_struct("Claim", 8)?;
    st.serialize_field("claim", claim)?;
    st.serialize_field("measured", &m.measured)?;
    st.serialize_field("verdict", &m.verdict)?;
    st.serialize_field("basis", &m.evidence.basis)?;
    st.serialize_field("proven_upper", &m.evidence.proven_upper)?;
    st.serialize_field("found", &m.evidence.found)?;
    st.serialize_field("quantity", &m.evidence.quantity)?;
    st.serialize_field("how", &m.how)?;
    st.end()
}
/// One shading method.
#[derive(Debug, Serialize)]
pub struct Method {
    /// Identifier (snake_case), used everywhere.
    pub name: &'static str,
    /// One line.
    pub description: &'static str,
    /// The publication, then its section of docs/formulas.md (`docs/formulas.md#<anchor>`).
    pub citation: &'static str,
    /// Pipeline inputs it needs; only these varyings and vertex streams are set up.
    pub inputs: &'static [Input],
    /// Its family (one chart panel each).
    pub family: Family,
    /// What code must know about it beyond its inputs (serialised as snake_case strings).
    pub properties: &'static [Property],
    /// The geometry it draws.
    pub geometry: Geometry,
    /// Whether it produces a per-pixel shading normal (normal metrics are null otherwise).
    pub has_normal: bool,
    /// The reference it is judged against.
    pub reference: Reference,
    /// The range in which the paper says it is valid.
    pub validity: &'static str,
    /// Numerical claims the papers make about it, each with the check that measures it.
    pub claims: &'static [Claim],
    /// The GLSL file under glsl/ that defines `methodNormal()` or `methodColor()`.
    pub glsl: &'static str,
    /// The same method in f64 at one pixel.
    #[serde(skip)]
    pub eval_f64: fn(&Fragment, &Lighting) -> Shaded,
    /// The kernel the software engine runs for it (its words and flags: `software_forms` of
    /// `shadelab list --json`).
    #[serde(skip)]
    pub software: SoftwareKernel,
}
impl Method {
    /// Whether the row lists `property`.
    pub fn has(&self, property: Property) -> bool {
        self.properties.contains(&property)
    }

    /// Its f64 twin; `None` for a user method (`--method-file`), which exists only as GLSL.
    pub fn twin(&self) -> Option<fn(&Fragment, &Lighting) -> Shaded> {
        (self.family != Family::Yours).then_some(self.eval_f64)
    }

    /// An error (exit 2) naming the method when it has no f64 twin, for `what` (a command or
    /// check that needs one).
    pub fn require_twin(&self, what: &str) -> Result<fn(&Fragment, &Lighting) -> Shaded> {
        self.twin().ok_or_else(|| {
            Error::Usage(format!(
                "{what} needs the method's f64 twin, and {} is a user method (--method-file) \
                 without one; leave it out (compare, stress, bench, isa and report judge it \
                 against exact Phong)",
                self.name
            ))
        })
    }
}

/// The `eval_f64` of a user method's row: never called (consumers ask [`Method::twin`]).
pub(crate) fn no_twin(_: &Fragment, _: &Lighting) -> Shaded {
    panic!("a user method has no f64 twin; the caller must ask Method::twin() first")
}

/// Looks a method up by identifier; the error lists the valid ones.
pub fn find(name: &str) -> Result<&'static Method> {
    let all = all();
    all.iter().find(|m| m.name == name).copied().ok_or_else(|| {
        Error::Usage(format!(
            "unknown method {name:?}; valid methods: {} (see `shadelab list`)",
            all.iter().map(|m| m.name).collect::<Vec<_>>().join(", ")
        ))
    })
}
