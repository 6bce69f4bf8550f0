//! The software engine (`--engine software`, issue 13): a scanline rasterizer in Rust, float32,
//! multi-threaded over bands of rows, with the Vulkan pipeline's conventions ([`raster`]), in
//! which every method runs in the incremental form the seeds describe ([`spans`], with the f32
//! twins of the f64 formulas in [`formulas`]). It returns the same [`Frame`] and [`IdFrame`]
//! as [`crate::gpu::Renderer::render`], so the f64 truth, `verify` and `compare` judge it the
//! same way.
//!
//! Limits: screen-linear interpolation only (a perspective scene is refused); no clipping (a
//! triangle crossing the near plane is refused); `trueform` draws its PN tessellation on the
//! CPU like any mesh.
pub mod formulas;
pub mod raster;
pub mod spans;
#[cfg(test)]
mod tests;

use glam::Vec3;

use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::method::{specular_table, Method};
use crate::scene::{Interpolation, SceneInputs};
use formulas::{self as f, Lighting32};
pub use raster::Targets;
use raster::{draw_into, Shader, Tri};
use spans::{n4, stepped, Along, SpanShader};

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
    let u = 1.0 / 16_777_216.0;
    u * (4.0 * (n + 1.0) * (n + 1.0) + 64.0 * (n + 1.0))
}

/// The form `method` takes in the software engine.
pub fn form(method: &str) -> Form {
    let (scanline, form) = match method {
        "flat" => (false, "one colour per triangle"),
        "gouraud" | "trueform" => (true, "vertex colours, the colour stepped by forward differences"),
        "slerp" => (false, "per-pixel form along the span: t stepped, sin per pixel (its recurrence is spherical_angular)"),
        "spherical_angular" => (true, "Chebyshev recurrence N(k+1) = 2 cos(phi) N(k) - N(k-1), seeded by the closed form"),
        "quadratic_scanline" | "quadratic_scanline_approx_mid" => (true, "G t^2 + P t + Q by second-order forward differences"),
        "dichotomy_exact" | "dichotomy_poly1" | "dichotomy_poly2" => (true, "the span's grid m/2^K filled by halving, one midpoint per grid point"),
        "segments_k1" | "segments_k2" | "segments_k3" => (true, "segment ends shaded once, colour stepped by (I_p - I_l)/2^k, last segment extrapolated"),
        "segments_k2_poly1" | "segments_k2_poly2" | "segments_k3_poly1" | "segments_k3_poly2" => (true, "segment ends normalised, normals inside by halving"),
        "bishop_weimer" => (true, "Taylor polynomial per cosine by forward differences (2 additions per cosine per pixel)"),
        "hast_euler" => (true, "Euler integration per cosine with the end-error correction (2 additions per cosine per pixel)"),
        "quaternion" | "quaternion_local" => (false, "per-pixel form: quaternion stepped by forward differences, normal recovered per pixel"),
        "barycentric_quadratic" | "barycentric_quadratic_exact_mid" | "pn_normals" => (false, "per-pixel form: weights stepped by forward differences, quadratic evaluated per pixel"),
        _ => (false, "per-pixel form: normal stepped by forward differences, then the method's normalisation"),
    };
    let drifts = matches!(
        method,
        "spherical_angular"
            | "quadratic_scanline"
            | "quadratic_scanline_approx_mid"
            | "bishop_weimer"
            | "hast_euler"
    );
    Form {
        scanline,
        drifts,
        form,
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
    let mut targets = Targets::new(inputs.width, inputs.height, true, with_ids);
    render_into(inputs, method, threads, &mut targets)?;
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
    let tris = raster::setup(inputs)?;
    let lit = Lighting32::new(&inputs.params, inputs.light_count);
    fn run<S: Shader>(targets: &mut Targets, t: &[Tri], s: S, n: usize) -> Result<()> {
        draw_into(targets, t, &s, n);
        Ok(())
    }
    let normal = |t: &Tri| (t.n, ());
    let span = |along| SpanShader { along, lit };
    macro_rules! scalar {
        ($k:expr) => {{
            run(
                targets,
                &tris,
                stepped(normal, move |v: Vec3, _: &()| {
                    let m = v * $k(v.dot(v));
                    (lit.shade(m), n4(m))
                }),
                threads,
            )
        }};
    }
    macro_rules! mikami {
        ($beta:expr) => {{
            run(
                targets,
                &tris,
                stepped(normal, move |v: Vec3, _: &()| {
                    let z = v.dot(v);
                    let m = v / f::mikami_sqrt(z, $beta(z));
                    (lit.shade(m), n4(m))
                }),
                threads,
            )
        }};
    }
    macro_rules! along {
        ($a:expr) => {
            run(targets, &tris, span($a), threads)
        };
    }
    match method.name {
        "flat" => {
            let s = stepped(
                |t: &Tri| ([Vec3::ZERO; 3], (lit.shade(t.flat), t.flat)),
                |_, d: &(Vec3, Vec3)| (d.0, n4(d.1)),
            );
            run(targets, &tris, s, threads)
        }
        "gouraud" | "trueform" => {
            let s = stepped(
                |t: &Tri| (t.n.map(|n| lit.shade(n)), ()),
                |c, _: &()| (c, [0.0; 4]),
            );
            run(targets, &tris, s, threads)
        }
        "phong_exact" => scalar!(|z: f32| 1.0 / z.sqrt()),
        "phong_unnormalized" => scalar!(|_: f32| 1.0),
        "newton_raphson" => scalar!(f::k_newton),
        "lyon_taylor" => scalar!(f::k_lyon2),
        "lyon_shift" => scalar!(f::k_lyon_shift),
        "romanyuk_poly" => scalar!(f::k_romanyuk),
        "mikami_const" => mikami!(f::beta_const),
        "mikami_linear" => mikami!(f::beta_linear),
        "mikami_quadratic" => mikami!(f::beta_quadratic),
        "hast_half_vector" => {
            let s = stepped(
                |t: &Tri| (t.n, t.flat),
                move |v, flat: &Vec3| {
                    let m = f::hbb(v, *flat);
                    (lit.shade(m), n4(m))
                },
            );
            run(targets, &tris, s, threads)
        }
        "quaternion" => {
            let s = stepped(
                |t: &Tri| (t.n.map(f::quat_from_normal), ()),
                move |q, _: &()| {
                    let m = f::normal_from_quat(q);
                    (lit.shade(m), n4(m))
                },
            );
            run(targets, &tris, s, threads)
        }
        "quaternion_local" => {
            let s = stepped(
                |t: &Tri| {
                    let (tt, b) = f::onb(t.flat);
                    let q = t.n.map(|v| {
                        f::quat_from_normal(Vec3::new(v.dot(tt), v.dot(b), v.dot(t.flat)))
                    });
                    (q, (tt, b, t.flat))
                },
                move |q, fr: &(Vec3, Vec3, Vec3)| {
                    let l = f::normal_from_quat(q);
                    let m = fr.0 * l.x + fr.1 * l.y + fr.2 * l.z;
                    (lit.shade(m), n4(m))
                },
            );
            run(targets, &tris, s, threads)
        }
        "barycentric_quadratic" | "barycentric_quadratic_exact_mid" => {
            let mid = if method.name == "barycentric_quadratic" {
                f::m_ij
            } else {
                f::m_ij_exact
            };
            let s = stepped(
                move |t: &Tri| {
                    let n = t.n;
                    (
                        [Vec3::X, Vec3::Y, Vec3::Z],
                        (n, [mid(n[0], n[1]), mid(n[1], n[2]), mid(n[2], n[0])]),
                    )
                },
                move |c, d: &([Vec3; 3], [Vec3; 3])| {
                    let m = f::bary_quad(&d.0, &d.1, c);
                    (lit.shade(m), n4(m))
                },
            );
            run(targets, &tris, s, threads)
        }
        "pn_normals" => {
            let s = stepped(
                |t: &Tri| ([Vec3::X, Vec3::Y, Vec3::Z], (t.n, t.pn)),
                move |c, d: &([Vec3; 3], [Vec3; 3])| {
                    let m = f::normalize_exact(f::pn_normal(&d.0, &d.1, c));
                    (lit.shade(m), n4(m))
                },
            );
            run(targets, &tris, s, threads)
        }
        "specular_lut" => {
            let table = specular_table();
            let (rows, samples) = (
                crate::method::formulas::LUT_ROWS,
                crate::method::formulas::LUT_SAMPLES,
            );
            let s = stepped(normal, move |v, _: &()| {
                let m = f::normalize_exact(v);
                let mut c = lit.ambient;
                for i in 0..lit.count {
                    let d = m.dot(lit.dirs[2 * i]).max(0.0);
                    let s = m.dot(lit.dirs[2 * i + 1]).max(0.0);
                    let sp = f::lut_lookup(table, rows, samples, lit.shininess, s);
                    c += lit.colors[i] * (lit.diffuse * d + lit.specular * sp);
                }
                (c, n4(m))
            });
            run(targets, &tris, s, threads)
        }
        "slerp" => along!(Along::Slerp),
        "spherical_angular" => along!(Along::Chebyshev),
        "quadratic_scanline" => along!(Along::Quadratic { approx_mid: false }),
        "quadratic_scanline_approx_mid" => along!(Along::Quadratic { approx_mid: true }),
        "dichotomy_exact" => along!(Along::Dichotomy(f::inv_root_exact)),
        "dichotomy_poly1" => along!(Along::Dichotomy(f::inv_root_poly1)),
        "dichotomy_poly2" => along!(Along::Dichotomy(f::inv_root_poly2)),
        "segments_k1" => along!(Along::Segments(1, None)),
        "segments_k2" => along!(Along::Segments(2, None)),
        "segments_k3" => along!(Along::Segments(3, None)),
        "segments_k2_poly1" => along!(Along::Segments(2, Some(f::inv_root_poly1))),
        "segments_k2_poly2" => along!(Along::Segments(2, Some(f::inv_root_poly2))),
        "segments_k3_poly1" => along!(Along::Segments(3, Some(f::inv_root_poly1))),
        "segments_k3_poly2" => along!(Along::Segments(3, Some(f::inv_root_poly2))),
        "bishop_weimer" => along!(Along::BishopWeimer),
        "hast_euler" => along!(Along::HastEuler),
        other => Err(Error::Usage(format!(
            "the software engine has no form for method {other:?}"
        ))),
    }
}
