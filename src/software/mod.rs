//! The software engine (`--engine software`, issue 13): a scanline rasterizer in Rust, float32
//! (or float16, the twin of the device's f16 programs: [`render_at`]),
//! multi-threaded over bands of rows, with the Vulkan pipeline's conventions ([`raster`]), in
//! which every method runs in the incremental form the seeds describe ([`spans`]), evaluating the
//! generic formulas of [`crate::method::formulas`] and [`crate::method::scanline`] in f32 (or
//! f16: [`crate::method::real`]). It returns the same [`Frame`] and [`IdFrame`]
//! as [`crate::gpu::Renderer::render`], so the f64 truth, `verify` and `compare` judge it the
//! same way.
//!
//! Limits: screen-linear interpolation only (a perspective scene is refused); no clipping (a
//! triangle crossing the near plane is refused); `trueform` draws its PN tessellation on the
//! CPU like any mesh.
pub mod raster;
pub mod spans;
#[cfg(test)]
mod tests;

use glam::Vec3;
use half::f16;

use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::method::formulas::{self as f, Lighting};
use crate::method::kernel::{Evaluate, Form as ScaleForm, Kernel, Scale, SpanKernel};
use crate::method::real::{Float, V3};
use crate::method::{specular_table, Method, Precision, Property};
use crate::scene::{Interpolation, Params, SceneInputs, MAX_LIGHTS};
pub use raster::Targets;
use raster::{draw_into, Shader, Tri};
use spans::{n4, stepped, Along, SpanShader};

/// The engine's scalar: a [`Float`] whose window positions are f32, as the rasterizer's (f32,
/// and f16 for the float16 twin).
pub trait Scalar: Float<Pos = f32> + Evaluate {}
impl<T: Float<Pos = f32> + Evaluate> Scalar for T {}

/// How a method runs in the software engine: `scanline` when it has an incremental form along
/// the span, otherwise its per-pixel form (the interpolated vector stepped, the formula applied).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Form {
    pub scanline: bool,
    /// A recurrence whose float32 rounding accumulates along the span (judged with
    /// [`drift_allowance`] on top of the per-pixel float32 bound).
    pub drifts: bool,
    pub form: &'static str,
}

/// The float32 drift a recurrence may accumulate `n` steps into its span, on values of unit
/// size (normals, cosines). The Chebyshev recurrence amplifies an error made k steps back by at
/// most k + 1 (|U_k(cos phi)| <= k + 1) and second-order forward differences add each step's
/// rounding of the first difference to every later value, so at most 4 roundings a step give
/// `4 u (n + 1)^2`; the seeds (closed form or polynomial at the span's first pixel, budgeted
/// like a formula: `K_FORMULA = 32` roundings, twice for value and step) carried along add
/// `64 u (n + 1)`.
pub fn drift_allowance(n: f64) -> f64 {
    drift_allowance_at(n, Precision::F32)
}

/// [`drift_allowance`] for a recurrence computed in `precision` (its unit roundoff u; the
/// count of roundings is the same).
pub fn drift_allowance_at(n: f64, precision: Precision) -> f64 {
    let u = precision.unit_roundoff();
    u * (4.0 * (n + 1.0) * (n + 1.0) + 64.0 * (n + 1.0))
}

/// The form `method` takes in the software engine: the scanline flag and the drift from the
/// row's properties ([`Property::SoftwareSpanForm`], [`Property::DriftsWithSpanLength`]), the
/// words from its kernel ([`SoftwareKernel`], matched exhaustively).
pub fn form_of(method: &Method) -> Form {
    Form {
        scanline: method.has(Property::SoftwareSpanForm),
        drifts: method.has(Property::DriftsWithSpanLength),
        form: kernel_words(method.kernel),
    }
}

/// [`form_of`] the method named `name`; a name that is not in the table has no form (neither
/// flag, and words that say so).
pub fn form(name: &str) -> Form {
    crate::method::find(name).map_or(
        Form {
            scanline: false,
            drifts: false,
            form: "not a method of the table",
        },
        form_of,
    )
}

/// What a kernel does, in words (`software_forms` of `shadelab list --json`).
pub fn kernel_words(k: Kernel) -> &'static str {
    use Kernel as K;
    match k {
        K::Flat => "one colour per triangle",
        K::VertexColour => "vertex colours, the colour stepped by forward differences",
        K::Span(SpanKernel::Slerp) => "per-pixel form along the span: t stepped, sin per pixel (its recurrence is spherical_angular)",
        K::Span(SpanKernel::Chebyshev) => "Chebyshev recurrence N(k+1) = 2 cos(phi) N(k) - N(k-1), seeded by the closed form",
        K::Span(SpanKernel::Quadratic { .. }) => "G t^2 + P t + Q by second-order forward differences",
        K::Span(SpanKernel::Dichotomy(_)) => "the span's grid m/2^K filled by halving, one midpoint per grid point",
        K::Span(SpanKernel::Segments(_, None)) => "segment ends shaded once, colour stepped by (I_p - I_l)/2^k, last segment extrapolated",
        K::Span(SpanKernel::Segments(_, Some(_))) => "segment ends normalised, normals inside by halving",
        K::Span(SpanKernel::BishopWeimer) => "Taylor polynomial per cosine by forward differences (2 additions per cosine per pixel)",
        K::Span(SpanKernel::HastEuler) => "Euler integration per cosine with the end-error correction (2 additions per cosine per pixel)",
        K::Quaternion | K::QuaternionLocal => "per-pixel form: quaternion stepped by forward differences, normal recovered per pixel",
        K::BarycentricQuadratic { .. } | K::PnNormals => "per-pixel form: weights stepped by forward differences, quadratic evaluated per pixel",
        K::Scaled(_) | K::HastHalfVector | K::SpecularLut => "per-pixel form: normal stepped by forward differences, then the method's normalisation",
        K::None => "none: a user method (--method-file) exists only as GLSL",
    }
}

/// Threads the engine uses by default: all the machine offers.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Renders `method` on `inputs` (which must be its geometry: [`SceneInputs::new`] with
/// `method.geometry`) on `threads` threads; with `with_ids`, also the id frame (triangle + 1
/// and the screen-linear weights at each pixel centre that passed the depth test).
pub fn render(
    inputs: &SceneInputs,
    method: &Method,
    threads: usize,
    with_ids: bool,
) -> Result<(Frame, Option<IdFrame>)> {
    render_at(inputs, method, threads, with_ids, Precision::F32)
}

/// [`render`] computing in `precision`: float32 (the shipped engine), or float16, the twin of
/// the device's f16 programs (every operation of the method and the lighting rounded to
/// binary16, [`real`]).
pub fn render_at(
    inputs: &SceneInputs,
    method: &Method,
    threads: usize,
    with_ids: bool,
    precision: Precision,
) -> Result<(Frame, Option<IdFrame>)> {
    let mut targets = Targets::new(inputs.width, inputs.height, true, with_ids);
    render_into_at(inputs, method, threads, &mut targets, precision)?;
    Ok(targets.into_frames())
}

/// [`render`] into kept targets (cleared by the draw; of the inputs' size), which allocates no
/// image: a timed draw (`bench --engine software`) keeps one set, without a normal target.
pub fn render_into(
    inputs: &SceneInputs,
    method: &Method,
    threads: usize,
    targets: &mut Targets,
) -> Result<()> {
    render_into_at(inputs, method, threads, targets, Precision::F32)
}

/// [`render_into`] computing in `precision`.
pub fn render_into_at(
    inputs: &SceneInputs,
    method: &Method,
    threads: usize,
    targets: &mut Targets,
    precision: Precision,
) -> Result<()> {
    if inputs.interpolation == Interpolation::Perspective {
        return Err(Error::Usage(format!(
            "the software engine interpolates screen-linearly only; {} asks for perspective: \
             use --interpolation screen-linear or --engine vulkan",
            method.name
        )));
    }
    if inputs.geometry != method.geometry {
        return Err(Error::Internal(format!(
            "{} draws {:?}, the inputs hold {:?}",
            method.name, method.geometry, inputs.geometry
        )));
    }
    if (targets.width, targets.height) != (inputs.width, inputs.height) {
        return Err(Error::Internal(format!(
            "software targets {}x{} for a {}x{} scene",
            targets.width, targets.height, inputs.width, inputs.height
        )));
    }
    if !method.kernel.exists() {
        return Err(Error::Usage(format!(
            "{} is a user method (--method-file): the software engine has no kernel for it; \
             use --engine vulkan",
            method.name
        )));
    }
    let tris = raster::setup(inputs)?;
    match precision {
        Precision::F32 => dispatch::<f32>(inputs, method, threads, targets, &tris),
        Precision::F16 => dispatch::<f16>(inputs, method, threads, targets, &tris),
    }
    Ok(())
}

/// The lighting as uploaded, each value rounded to `S` where read (`count` lights).
pub fn lighting<S: Scalar>(p: &Params, count: u32) -> Lighting<V3<S>> {
    let v = |v: [f32; 4]| V3::<S>::of(Vec3::new(v[0], v[1], v[2]));
    let count = (count as usize).min(MAX_LIGHTS);
    let lights: Vec<_> = (0..count)
        .map(|i| (v(p.light_dir[i]), v(p.light_color[i]), v(p.half_vec[i])))
        .collect();
    Lighting::new(
        v(p.ambient),
        v(p.diffuse),
        v(p.specular),
        S::of(p.specular[3]),
        &lights,
    )
}

/// The method's kernel in scalar `S`.
fn dispatch<S: Scalar>(
    inputs: &SceneInputs,
    method: &Method,
    threads: usize,
    targets: &mut Targets,
    tris: &[Tri],
) {
    let d = Draw {
        targets,
        tris,
        lit: lighting::<S>(&inputs.params, inputs.light_count),
        threads,
    };
    use Kernel as K;
    match method.kernel {
        K::Span(k) => {
            let lit = d.lit;
            d.run(SpanShader {
                along: along(k),
                lit,
            })
        }
        K::Flat => flat(d),
        K::VertexColour => vertex_colour(d),
        K::Scaled(s) => scaled_by(d, s),
        K::HastHalfVector => hast_half_vector(d),
        K::Quaternion => quaternion(d),
        K::QuaternionLocal => quaternion_local(d),
        K::BarycentricQuadratic { exact_mid } => barycentric_quadratic(d, exact_mid),
        K::PnNormals => pn_normals(d),
        K::SpecularLut => specular_lut(d),
        // Refused by render_into_at before the draw.
        K::None => {}
    }
}

/// One draw: the targets, the set-up triangles, the lighting and the threads.
struct Draw<'a, S: Scalar> {
    targets: &'a mut Targets,
    tris: &'a [Tri],
    lit: Lighting<V3<S>>,
    threads: usize,
}

impl<S: Scalar> Draw<'_, S> {
    fn run<H: Shader>(self, s: H) {
        draw_into(self.targets, self.tris, &s, self.threads);
    }
}

/// The span kernel's shader state.
fn along<S: Scalar>(k: SpanKernel) -> Along<S> {
    match k {
        SpanKernel::Slerp => Along::Slerp,
        SpanKernel::Chebyshev => Along::Chebyshev,
        SpanKernel::Quadratic { approx_mid } => Along::Quadratic { approx_mid },
        SpanKernel::Dichotomy(r) => Along::Dichotomy(r.of()),
        SpanKernel::Segments(k, r) => Along::Segments(k, r.map(|r| r.of())),
        SpanKernel::BishopWeimer => Along::BishopWeimer,
        SpanKernel::HastEuler => Along::HastEuler,
    }
}

/// [`Kernel::Scaled`]: the row's factor of the squared length, `N k(z)` (or `N / s(z)`).
fn scaled_by<S: Scalar>(d: Draw<S>, s: Scale) {
    let k = move |z: S| S::of_factor(s.factor, z);
    match s.form {
        ScaleForm::Times | ScaleForm::Exact => scaled(d, k),
        ScaleForm::Over => divided(d, k),
    }
}

fn normal(t: &Tri) -> ([Vec3; 3], ()) {
    (t.n, ())
}

/// The f32 colour of an `S` colour (exact).
#[inline(always)]
fn out<S: Scalar>(c: V3<S>) -> Vec3 {
    c.f32()
}

fn flat<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| {
            let n = V3::<S>::of(t.flat);
            ([Vec3::ZERO; 3], (out(lit.shade(n)), n))
        },
        |_, c: &(Vec3, V3<S>)| (c.0, n4(c.1)),
    ))
}

fn vertex_colour<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| (t.n.map(|n| out(lit.shade(V3::of(n)))), ()),
        |c, _: &()| (c, [0.0; 4]),
    ))
}

fn scaled<S: Scalar>(d: Draw<S>, k: impl Fn(S) -> S + Copy + Sync) {
    let lit = d.lit;
    d.run(stepped(normal, move |v: Vec3, _: &()| {
        let v = V3::<S>::of(v);
        let m = v * k(v.dot(v));
        (out(lit.shade(m)), n4(m))
    }))
}

fn divided<S: Scalar>(d: Draw<S>, s: impl Fn(S) -> S + Copy + Sync) {
    let lit = d.lit;
    d.run(stepped(normal, move |v: Vec3, _: &()| {
        let v = V3::<S>::of(v);
        let m = v / s(v.dot(v));
        (out(lit.shade(m)), n4(m))
    }))
}

fn hast_half_vector<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| (t.n, V3::<S>::of(t.flat)),
        move |v, flat: &V3<S>| {
            let m = f::hbb(V3::of(v), *flat);
            (out(lit.shade(m)), n4(m))
        },
    ))
}

fn quaternion<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| (t.n.map(|n| f::quat_from_normal(V3::<S>::of(n)).f32()), ()),
        move |q, _: &()| {
            let m = f::normal_from_quat(V3::<S>::of(q));
            (out(lit.shade(m)), n4(m))
        },
    ))
}

fn quaternion_local<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| {
            let flat = V3::<S>::of(t.flat);
            let (tt, b) = f::onb(flat);
            let q = t.n.map(|v| {
                let v = V3::<S>::of(v);
                f::quat_from_normal(V3::new(v.dot(tt), v.dot(b), v.dot(flat))).f32()
            });
            (q, (tt, b, flat))
        },
        move |q, fr: &(V3<S>, V3<S>, V3<S>)| {
            let l = f::normal_from_quat(V3::<S>::of(q));
            let m = fr.0 * l.x + fr.1 * l.y + fr.2 * l.z;
            (out(lit.shade(m)), n4(m))
        },
    ))
}

fn barycentric_quadratic<S: Scalar>(d: Draw<S>, exact_mid: bool) {
    let lit = d.lit;
    d.run(stepped(
        move |t: &Tri| {
            let n = t.n.map(V3::<S>::of);
            let mids = if exact_mid {
                f::bary_mids(&n, f::m_ij_exact)
            } else {
                f::bary_mids(&n, f::m_ij)
            };
            ([Vec3::X, Vec3::Y, Vec3::Z], (n, mids))
        },
        move |c, q: &([V3<S>; 3], [V3<S>; 3])| {
            let m = f::bary_quad(&q.0, &q.1, V3::of(c));
            (out(lit.shade(m)), n4(m))
        },
    ))
}

fn pn_normals<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    d.run(stepped(
        |t: &Tri| {
            (
                [Vec3::X, Vec3::Y, Vec3::Z],
                (t.n.map(V3::<S>::of), t.pn.map(V3::<S>::of)),
            )
        },
        move |c, q: &([V3<S>; 3], [V3<S>; 3])| {
            let m = f::normalize_exact(f::pn_normal(&q.0, &q.1, V3::of(c)));
            (out(lit.shade(m)), n4(m))
        },
    ))
}

fn specular_lut<S: Scalar>(d: Draw<S>) {
    let lit = d.lit;
    let table = specular_table();
    d.run(stepped(normal, move |v, _: &()| {
        let m = f::normalize_exact(V3::<S>::of(v));
        (out(lit.shade_lut(m, table)), n4(m))
    }))
}
