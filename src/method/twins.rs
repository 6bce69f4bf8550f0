//! The f64 twins: what a method sees at one pixel ([`Fragment`]), what it returns
//! ([`Shaded`]), and each [`Kernel`]'s evaluation in f64 ([`Kernel::eval_f64`]) from the
//! generic formulas of [`super::formulas`] and [`super::scanline`]: the truth every engine is
//! judged against.
use std::sync::OnceLock;

use glam::{DVec2, DVec3};

use super::kernel::{Form, Kernel, Scale, SpanKernel};
use crate::method::formulas::{self as f, Lighting};
use crate::method::scanline::{self, corners};
/// What the f64 twin of a method sees at one pixel: the interpolation weights the rasterizer
/// used and the triangle's data exactly as uploaded (f32 values widened to f64).
#[derive(Debug, Clone, Copy)]
pub struct Fragment {
    /// Interpolation weights of corners 0, 1, 2.
    pub weights: DVec3,
    /// The pixel centre in window space (`gl_FragCoord.xy`: Vulkan origin top-left, +0.5).
    pub pixel: DVec2,
    /// The triangle's window-space corners as uploaded (the scanline methods' span ends).
    pub window: [DVec2; 3],
    /// Unit view-space vertex normals of the three corners.
    pub corner_normals: [DVec3; 3],
    /// Unit flat normal of the triangle, view space.
    pub flat_normal: DVec3,
    /// PN mid-edge normals n110, n011, n101, view space.
    pub pn_mids: [DVec3; 3],
}

impl Fragment {
    /// The interpolated normal `N = sum w_i N_i` (docs/formulas.md#notation).
    pub fn interpolated_normal(&self) -> DVec3 {
        self.interpolate(self.corner_normals)
    }

    /// Linear interpolation of per-corner values with the weights.
    pub fn interpolate(&self, v: [DVec3; 3]) -> DVec3 {
        v[0] * self.weights.x + v[1] * self.weights.y + v[2] * self.weights.z
    }

    /// The span through the pixel's row.
    fn span(&self) -> scanline::Span {
        scanline::span_at(self.pixel.y, corners(self.window), self.corner_normals)
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

    /// A colour without a shading normal.
    fn colour(color: DVec3) -> Self {
        Shaded {
            color,
            normal: None,
        }
    }
}

impl Kernel {
    /// The method in f64 at one pixel. Panics for [`Kernel::None`] (a user method has no f64
    /// twin: callers ask `Method::twin` first).
    pub fn eval_f64(&self, fr: &Fragment, l: &Lighting) -> Shaded {
        match *self {
            Kernel::Flat => Shaded::lit(fr.flat_normal, l),
            Kernel::VertexColour => {
                Shaded::colour(fr.interpolate(fr.corner_normals.map(|n| l.shade(n))))
            }
            Kernel::Scaled(s) => Shaded::lit(scaled(&s, fr.interpolated_normal()), l),
            Kernel::HastHalfVector => {
                Shaded::lit(f::hbb(fr.interpolated_normal(), fr.flat_normal), l)
            }
            Kernel::Quaternion => {
                let q = fr.corner_normals.map(f::quat_from_normal);
                Shaded::lit(f::normal_from_quat(fr.interpolate(q)), l)
            }
            Kernel::QuaternionLocal => quaternion_local(fr, l),
            Kernel::BarycentricQuadratic { exact_mid } => {
                let n = fr.corner_normals;
                let mids = if exact_mid {
                    f::bary_mids(&n, f::m_ij_exact)
                } else {
                    f::bary_mids(&n, f::m_ij)
                };
                Shaded::lit(f::bary_quad(&n, &mids, fr.weights), l)
            }
            Kernel::PnNormals => {
                let n = f::pn_normal(&fr.corner_normals, &fr.pn_mids, fr.weights);
                Shaded::lit(f::normalize_exact(n), l)
            }
            Kernel::SpecularLut => {
                let n = f::normalize_exact(fr.interpolated_normal());
                Shaded {
                    color: l.shade_lut(n, specular_table()),
                    normal: Some(n),
                }
            }
            Kernel::Span(k) => span(k, fr, l),
            Kernel::None => {
                panic!("a user method has no f64 twin; the caller must ask Method::twin() first")
            }
        }
    }
}

/// The normal of a [`Kernel::Scaled`] method: `k(z) N`, `N / s(z)`, or `N / |N|` (z = N.N).
fn scaled(s: &Scale, n: DVec3) -> DVec3 {
    match s.form {
        Form::Times => n * s.factor.f64(n.length_squared()),
        Form::Over => n / s.factor.f64(n.length_squared()),
        Form::Exact => f::normalize_exact(n),
    }
}

/// The span kernels in f64.
fn span(k: SpanKernel, fr: &Fragment, l: &Lighting) -> Shaded {
    let along = |interpolate: fn(DVec3, DVec3, f64) -> DVec3| {
        let (a, b, t) = scanline::span_ends(fr.pixel, fr.window, fr.corner_normals);
        Shaded::lit(interpolate(a, b, t), l)
    };
    match k {
        SpanKernel::Slerp => along(scanline::slerp),
        SpanKernel::Chebyshev => along(scanline::spherical_angular),
        SpanKernel::Quadratic { approx_mid } => along(if approx_mid {
            |a, b, t| scanline::quadratic(a, b, scanline::mid_approx(a, b), t)
        } else {
            |a, b, t| scanline::quadratic(a, b, scanline::mid_exact(a, b), t)
        }),
        SpanKernel::Dichotomy(root) => {
            let sp = fr.span();
            let t = scanline::span_t(&sp, fr.pixel.x);
            let (a, b) = (f::normalize_exact(sp.na), f::normalize_exact(sp.nb));
            let k = scanline::levels(sp.xb - sp.xa);
            Shaded::lit(scanline::dichotomy(a, b, t, k, root.of()), l)
        }
        SpanKernel::Segments(k, root) => segments(fr, l, k, root.map(|r| r.of())),
        SpanKernel::BishopWeimer => {
            let (a, b, c, o) = scanline::plane_normal(corners(fr.window), fr.corner_normals);
            let p = fr.pixel - DVec2::from(o);
            Shaded::colour(l.shade_cosines(|_, v| scanline::taylor_cosine(v, a, b, c, p)))
        }
        SpanKernel::HastEuler => {
            let sp = fr.span();
            let t = scanline::span_t(&sp, fr.pixel.x);
            Shaded::colour(l.shade_cosines(|_, v| scanline::euler_cosine(v, &sp, t)))
        }
    }
}

/// The unit normal at a digital segment's end: the span's Phong normal there (extrapolated
/// past the span's end for the last segment), the start normal where that passes through 0.
fn segment_end(sp: &scanline::Span, x: f64) -> DVec3 {
    let n = scanline::span_normal(sp, x);
    f::normalize_exact(if n.length_squared() > 1e-12 { n } else { sp.na })
}

/// Digital segments of 2^k pixels (docs/formulas.md#digital-segments): exact Phong at the segment's
/// ends; inside, the colour interpolated linearly (`inv_root` None), or the normal by dichotomy
/// with `inv_root`.
fn segments(fr: &Fragment, lit: &Lighting, k: u32, inv_root: Option<fn(f64) -> f64>) -> Shaded {
    let sp = fr.span();
    let (xl, xp, v) = scanline::segment(&sp, fr.pixel.x, k);
    let (nl, np) = (segment_end(&sp, xl), segment_end(&sp, xp));
    let t = f64::from(v) / f64::from(1u32 << k);
    match inv_root {
        Some(f) => Shaded::lit(scanline::dichotomy(nl, np, t, k, f), lit),
        None => {
            let (il, ip) = (lit.shade(nl), lit.shade(np));
            Shaded::colour(il * (1.0 - t) + ip * t)
        }
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
