//! The table of shading methods: the single source of truth for the CLI (`shadelab list`), the
//! shader variants (src/gpu/shaders.rs), the vertex streams a run uploads (src/gpu/renderer.rs),
//! the f64 twins (src/method/) and every output. Identifiers are snake_case and appear unchanged in
//! file names, CLI arguments, CSV and JSON.
pub mod checks;
pub mod dual;
pub mod formulas;
pub mod interval;
pub mod kernel;
pub mod linalg;
pub mod precision;
pub mod real;
pub mod rounded;
pub mod scanline;
pub mod scanline_checks;
pub mod table;
#[cfg(test)]
mod tests;
pub mod tuned;
pub mod twins;
pub mod user;
mod worst;

pub use kernel::{Form, InvRoot, Kernel, Scale, SpanKernel};
pub use precision::Precision;
pub use table::{METHODS, PHONG_EXACT};
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
    /// Methods fitted by `shadelab tune` (a `--method-file` with its `// shadelab-tuned:` line,
    /// src/method/tuned.rs): a polynomial seed and Newton steps, with f64 twin, software kernel
    /// and proof like a row of the table.
    Tuned,
}

impl Family {
    /// Every family, in presentation order.
    pub const ALL: [Family; 7] = [
        Family::Reference,
        Family::PerPixelNormalisation,
        Family::VertexAttribute,
        Family::Scanline,
        Family::DigitalSegments,
        Family::Yours,
        Family::Tuned,
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
            Family::Tuned => "tuned",
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
    /// `auto` may choose it (`crate::auto::candidates`): a cheap method, or the exact
    /// reference as the fallback.
    AutoCandidate,
    /// A scale of the squared length that is not exact normalisation anywhere (its kernel a
    /// [`Kernel::Scaled`] `N' = k(z) N` or `N / s(z)`): `tune` proves and costs it as a
    /// baseline beside the approximations it fits (`crate::tune::candidate::papers`), from the
    /// row's own factor.
    TuneBaseline,
    /// The interpolated normal used as it comes, unnormalised: the cost floor of exact
    /// normalisation and a ceiling of the error (the report's second reference, the op-count
    /// claim's baseline: [`phong_unnormalized`]).
    Unnormalized,
    /// Exact slerp along the span: the second reference of the angle-interpolating methods
    /// ([`Reference::PhongAndSlerp`], [`slerp_reference`]).
    SlerpReference,
    /// Lighting at the vertices, colour interpolated: the cheapest shading that lights, drawn
    /// beside phong_exact by bench's sweeps ([`vertex_lit_reference`]).
    VertexLitReference,
}

/// The exact reference's row.
pub fn phong_exact() -> &'static Method {
    find(PHONG_EXACT).expect("the method table has phong_exact")
}

/// The unnormalised reference's row, [`Property::Unnormalized`]: its name is spelled in its
/// row alone.
pub fn phong_unnormalized() -> &'static Method {
    with_property(Property::Unnormalized)
        .next()
        .expect("the method table has the unnormalised reference")
}

/// The second reference of the angle-interpolating methods, [`Property::SlerpReference`].
pub fn slerp_reference() -> &'static Method {
    with_property(Property::SlerpReference)
        .next()
        .expect("the method table has the slerp reference")
}

/// The vertex-lit reference, [`Property::VertexLitReference`].
pub fn vertex_lit_reference() -> &'static Method {
    with_property(Property::VertexLitReference)
        .next()
        .expect("the method table has the vertex-lit reference")
}

/// The methods with `property`, in table order.
pub fn with_property(property: Property) -> impl Iterator<Item = &'static Method> {
    METHODS.iter().filter(move |m| m.has(property))
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

/// What a claim states, typed: its kind, its figure and its criterion. Every layer that judges
/// claims (`list`, `prove`, `stress`, `bench` in both engines, the report through them) reads
/// the rows' claims by their kind: none keeps a list of its own.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    /// A bound on an error ([`Bound`]): judged by the claim's check (sampled, or proven where
    /// the method's kernel is provable).
    ErrorBound(Bound),
    /// A validity range: the method is usable for vertex normals up to `up_to_deg` degrees
    /// apart, by `criteria`. `shadelab stress` judges it on the device; the check judges it
    /// in f64 where it can.
    Validity { up_to_deg: f64, criteria: Criteria },
    /// A speed factor: `factor` times faster than the method `than`. `shadelab bench` judges
    /// it in both engines.
    Speed { factor: f64, than: &'static str },
    /// An operation count: with the counts, `shadelab bench` counts the SPIR-V of the method
    /// minus the unnormalised baseline; without, a cost statement (bench's isolated cost).
    OperationCount(Option<Ops>),
    /// A property of a formula or of what the tool builds (unit length, a printed formula, an
    /// equality, a count).
    Property,
}

/// Operations an [`Kind::OperationCount`] claims (in floating-point instructions per pixel).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ops {
    pub div: u32,
    pub mul: u32,
    pub add: u32,
    pub sqrt: u32,
}

/// The figure of a [`Kind::ErrorBound`].
#[derive(Debug, Clone, Copy)]
pub enum Bound {
    /// A scaled method's length error `|k(z) sqrt(z) - 1|` is at most `at_most` (a fraction)
    /// for `z = N.N` in `[z.0, z.1]`.
    Length { at_most: f64, z: (f64, f64) },
    /// A scaled method's worst length error is at least `factor` times smaller than each of
    /// the methods `than`'s, for vertex normals up to each of `angles_deg` apart (edges and
    /// interior of a triangle).
    TimesSmaller {
        factor: f64,
        than: &'static [&'static str],
        angles_deg: &'static [f64],
    },
    /// Another bound: its figure and rule are the check's (stated in its `how`).
    Other,
}

/// The criteria a [`Kind::Validity`] claim is judged by (docs/stress.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criteria {
    /// The colour criterion alone: every facing case up to the claimed angle finite and within
    /// one 8-bit level (`max_valid_angle_deg`).
    Colour,
    /// The length criterion (the worst ||N| - 1| up to the claimed angle within
    /// `checks::VISIBLE_LENGTH_ERROR_PCT`) beside the colour criterion: both hold agrees,
    /// neither disagrees, one partly.
    LengthAndColour,
    /// Valid up to the angle and not beyond: within the colour threshold from 60 degrees up to
    /// it, above it from it to 30 degrees beyond ("accuracy collapses beyond").
    CollapsesBeyond,
}

/// A numerical claim of the papers, typed, and the check that measures it.
///
/// Serialising a claim (`shadelab list --json`, through `crate::prove::bounds::json`) runs its
/// check, so the JSON holds `claim`, `measured`, `verdict`, `basis`, `proven_upper`, `found`, `quantity`
/// and `how` as measured at that moment.
#[derive(Debug, Clone, Copy)]
pub struct Claim {
    /// The claim, with its source (`docs/formulas.md#<anchor>`).
    pub claim: &'static str,
    /// What it states, with its figure and criterion.
    pub kind: Kind,
    /// How it can be judged: proven (an interval bound of the row's kernel), found (sampled
    /// in f64 or on the device) or measured (a timing, a count, a property). The check's
    /// evidence has this basis (a test checks it).
    pub basis: Basis,
    /// What measures it and derives the verdict.
    pub check: Check,
}

/// What measures a claim (`crate::prove::bounds::judge` runs it).
#[derive(Debug, Clone, Copy)]
pub enum Check {
    /// An f64 check of this layer ([`checks`], [`scanline_checks`]): a sweep of the row's
    /// formula, a property of it.
    Sampled(fn(&Method, &Claim) -> Measurement),
    /// The proof's check of the claim's kind on the row's kernel (`crate::prove::bounds`: a
    /// scaled method's length bound, validity by both criteria, error ratio): an interval
    /// bound beside the f64 sweep where the kernel is provable, the sweep alone where not.
    Proof,
    /// No formula measures it: `not_checked`, naming the command that judges it from the row
    /// ([`checks::judged_elsewhere`]).
    Elsewhere,
}

impl Claim {
    /// The claim of `m` judged by a check of this layer; `None` for [`Check::Proof`] (the
    /// proof is a layer above: `crate::prove::bounds::judge` judges every claim).
    pub fn judge_without_proof(&self, m: &Method) -> Option<Measurement> {
        match self.check {
            Check::Sampled(f) => Some(f(m, self)),
            Check::Elsewhere => Some(checks::judged_elsewhere(m, self)),
            Check::Proof => None,
        }
    }
}

/// A claim's 8 keys: its text and a measurement of it.
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
    /// Numerical claims the papers make about it, typed, each with the check that measures it
    /// (in JSON through `crate::prove::bounds::json`, judged now).
    #[serde(skip)]
    pub claims: &'static [Claim],
    /// The GLSL file under glsl/ that defines `methodNormal()` or `methodColor()`.
    pub glsl: &'static str,
    /// Its formula, typed ([`Kernel`]): what the f64 twin evaluates, the software engine runs
    /// and `prove` bounds (its words and flags: `software_forms` of `shadelab list --json`).
    #[serde(skip)]
    pub kernel: Kernel,
}
impl Method {
    /// Whether the row lists `property`.
    pub fn has(&self, property: Property) -> bool {
        self.properties.contains(&property)
    }

    /// The method in f64 at one pixel ([`Kernel::eval_f64`]). Panics for a user method
    /// (`--method-file`), which has no twin: ask [`Method::twin`] first.
    pub fn eval_f64(&self, frag: &Fragment, lighting: &Lighting) -> Shaded {
        self.kernel.eval_f64(frag, lighting)
    }

    /// Whether it has an f64 twin: `None` for a user method (`--method-file`), which exists only
    /// as GLSL; else the method itself (call [`Method::eval_f64`]): a tuned file (`shadelab
    /// tune`'s, with its line) has one.
    pub fn twin(&self) -> Option<&Method> {
        (self.family != Family::Yours && self.kernel.exists()).then_some(self)
    }

    /// An error (exit 2) naming the method when it has no f64 twin, for `what` (a command or
    /// check that needs one).
    pub fn require_twin(&self, what: &str) -> Result<&Method> {
        self.twin().ok_or_else(|| {
            Error::Usage(format!(
                "{what} needs the method's f64 twin, and {} is a user method (--method-file) \
                 without one (only a file written by shadelab tune, with its `// \
                 shadelab-tuned:` line, has one); leave it out (compare, stress, bench, isa and \
                 report judge it against exact Phong)",
                self.name
            ))
        })
    }
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
