//! The f64 twins' interface: what a method sees at one pixel ([`Fragment`]), what it returns
//! ([`Shaded`]), and the glue that turns the formulas of [`super::formulas`] into a shaded pixel.
use std::sync::OnceLock;

use glam::{DVec2, DVec3};

use crate::method::formulas::{self as f, Lighting};
use crate::method::scanline;
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
pub(crate) fn scalar(frag: &Fragment, lit: &Lighting, k: fn(f64) -> f64) -> Shaded {
    let n = frag.interpolated_normal();
    Shaded::lit(n * k(n.length_squared()), lit)
}

pub(crate) fn mikami(frag: &Fragment, lit: &Lighting, beta: fn(f64) -> f64) -> Shaded {
    let n = frag.interpolated_normal();
    let z = n.length_squared();
    Shaded::lit(n / f::mikami_sqrt(z, beta(z)), lit)
}

/// A scanline method that interpolates between the unit span-end normals at the pixel's span
/// fraction t (docs/formulas.md#slerp, docs/formulas.md#spherical-angular-interpolation,
/// docs/formulas.md#quadratic-interpolation-along-the-span).
pub(crate) fn along_span(
    frag: &Fragment,
    lit: &Lighting,
    interpolate: fn(DVec3, DVec3, f64) -> DVec3,
) -> Shaded {
    let (a, b, t) = scanline::span_ends(frag.pixel, frag.window, frag.corner_normals);
    Shaded::lit(interpolate(a, b, t), lit)
}

/// Dichotomy (docs/formulas.md#dichotomy) between the unit span-end normals with the inverse root
/// `f`, as many levels as the span has pixels to the next power of two.
pub(crate) fn dichotomy(frag: &Fragment, lit: &Lighting, f: fn(f64) -> f64) -> Shaded {
    let sp = scanline::span_at(frag.pixel.y, frag.window, frag.corner_normals);
    let t = scanline::span_t(&sp, frag.pixel.x);
    let (a, b) = (f::normalize_exact(sp.na), f::normalize_exact(sp.nb));
    let k = scanline::levels(sp.xb - sp.xa);
    Shaded::lit(scanline::dichotomy(a, b, t, k, f), lit)
}

/// Bishop-Weimer (docs/formulas.md#bishop-weimer-taylor-shading): each cosine from the Taylor
/// polynomial of the screen-linear normal about the corners' centroid.
pub(crate) fn bishop_weimer(frag: &Fragment, lit: &Lighting) -> Shaded {
    let (a, b, c, o) = scanline::plane_normal(frag.window, frag.corner_normals);
    let p = frag.pixel - o;
    Shaded {
        color: lit.shade_cosines(|v| scanline::taylor_cosine(v, a, b, c, p)),
        normal: None,
    }
}

/// Hast's Euler integration along the span (docs/formulas.md#hast-euler-integration,
/// reconstruction).
pub(crate) fn hast_euler(frag: &Fragment, lit: &Lighting) -> Shaded {
    let sp = scanline::span_at(frag.pixel.y, frag.window, frag.corner_normals);
    let t = scanline::span_t(&sp, frag.pixel.x);
    Shaded {
        color: lit.shade_cosines(|v| scanline::euler_cosine(v, &sp, t)),
        normal: None,
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
pub(crate) fn segments(
    frag: &Fragment,
    lit: &Lighting,
    k: u32,
    inv_root: Option<fn(f64) -> f64>,
) -> Shaded {
    let sp = scanline::span_at(frag.pixel.y, frag.window, frag.corner_normals);
    let (xl, xp, v) = scanline::segment(&sp, frag.pixel.x, k);
    let (nl, np) = (segment_end(&sp, xl), segment_end(&sp, xp));
    let t = f64::from(v) / f64::from(1u32 << k);
    match inv_root {
        Some(f) => Shaded::lit(scanline::dichotomy(nl, np, t, k, f), lit),
        None => {
            let (il, ip) = (lit.shade(nl), lit.shade(np));
            Shaded {
                color: il * (1.0 - t) + ip * t,
                normal: None,
            }
        }
    }
}

pub(crate) fn gouraud(frag: &Fragment, lit: &Lighting) -> Shaded {
    let c = frag.corner_normals.map(|n| lit.shade(n));
    Shaded {
        color: frag.interpolate(c),
        normal: None,
    }
}

pub(crate) fn quaternion_local(frag: &Fragment, lit: &Lighting) -> Shaded {
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

pub(crate) fn specular_lut(frag: &Fragment, lit: &Lighting) -> Shaded {
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
