//! A method's kernel: the typed form of its formula that every evaluator dispatches on, never
//! on the method's name. The f64 twin ([`Kernel::eval_f64`], src/method/twins.rs), the
//! software engine's float32 and float16 kernels (src/software/), `stress` (through the twin)
//! and `prove` (through [`Kernel::provable`]) all read it, so a row's kernel is the only place
//! a method says what it computes.
//!
//! A per-pixel method that scales the interpolated normal by a function of its squared length
//! (`N' = k(z) N` or `N' = N / s(z)`, z = N.N) carries that function in its row as a
//! [`Factor`]: the one generic formula, instantiated in every number type the tool computes in
//! ([`Generic`], built by [`formula!`] from a function over [`Real`]). Such a method is its
//! GLSL file and one row; `prove` bounds it, the software engine runs it, the twin evaluates
//! it. A method generated at run time (`tune`) implements [`Factor`] for its own formula and
//! leaks one row the same way (src/method/user.rs leaks the rows of user methods).
use half::f16;

use super::dual::Dual;
use super::interval::Interval;
#[cfg(doc)]
use super::real::Real;
use super::rounded::{Rounded, F16, F32};

/// A scalar formula `f(z)` in every number type it is evaluated in: the f64 truth, the
/// software engine's float32 and float16, `prove`'s intervals and their derivatives, and the
/// program's rounding in float32 and float16 that `tune` proves ([`Rounded`]).
/// Each must be the same formula (the same operations in the same order), which
/// [`Generic`] guarantees by instantiating one generic function.
pub trait Factor: Sync + Send {
    /// The formula's name (its function), for `Debug` and the claims' words.
    fn name(&self) -> &str;
    fn f64(&self, z: f64) -> f64;
    fn f32(&self, z: f32) -> f32;
    fn f16(&self, z: f16) -> f16;
    fn interval(&self, z: Interval) -> Interval;
    fn dual(&self, z: Dual) -> Dual;
    /// The formula as a float32 program computes it, its rounding enclosed. By default the
    /// rounding is not known (the whole line): a proof of it then bounds nothing.
    fn rounded_f32(&self, z: Rounded<F32>) -> Rounded<F32> {
        Rounded::unknown(self.interval(z.v))
    }
    /// [`Factor::rounded_f32`] of a float16 program.
    fn rounded_f16(&self, z: Rounded<F16>) -> Rounded<F16> {
        Rounded::unknown(self.interval(z.v))
    }
    /// The domain of z a generated formula was proven on, outside which it may be anything (a
    /// tuned method's, src/method/tuned.rs): `auto` draws it only inside. None: every z the
    /// method's claims and validity state (every formula of the table).
    fn proven_domain(&self) -> Option<[f64; 2]> {
        None
    }
}

impl std::fmt::Debug for dyn Factor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A [`Factor`] that is one generic function over [`Real`], instantiated in every number type
/// ([`formula!`]).
pub struct Generic {
    pub name: &'static str,
    pub f64: fn(f64) -> f64,
    pub f32: fn(f32) -> f32,
    pub f16: fn(f16) -> f16,
    pub interval: fn(Interval) -> Interval,
    pub dual: fn(Dual) -> Dual,
    pub rounded_f32: fn(Rounded<F32>) -> Rounded<F32>,
    pub rounded_f16: fn(Rounded<F16>) -> Rounded<F16>,
}

/// The [`Generic`] factor of a generic function `fn k<T: Real>(z: T) -> T`:
/// `formula!(formulas::k_newton)`.
#[macro_export]
macro_rules! formula {
    ($f:path) => {
        $crate::method::kernel::Generic {
            name: stringify!($f),
            f64: $f,
            f32: $f,
            f16: $f,
            interval: $f,
            dual: $f,
            rounded_f32: $f,
            rounded_f16: $f,
        }
    };
}
pub use formula;

impl Factor for Generic {
    fn name(&self) -> &str {
        self.name
    }
    #[inline(always)]
    fn f64(&self, z: f64) -> f64 {
        (self.f64)(z)
    }
    #[inline(always)]
    fn f32(&self, z: f32) -> f32 {
        (self.f32)(z)
    }
    #[inline(always)]
    fn f16(&self, z: f16) -> f16 {
        (self.f16)(z)
    }
    fn interval(&self, z: Interval) -> Interval {
        (self.interval)(z)
    }
    fn dual(&self, z: Dual) -> Dual {
        (self.dual)(z)
    }
    fn rounded_f32(&self, z: Rounded<F32>) -> Rounded<F32> {
        (self.rounded_f32)(z)
    }
    fn rounded_f16(&self, z: Rounded<F16>) -> Rounded<F16> {
        (self.rounded_f16)(z)
    }
}

/// A number type a [`Factor`] is evaluated in: picks the factor's instantiation.
pub trait Evaluate: Sized {
    fn of_factor(f: &dyn Factor, z: Self) -> Self;
}

macro_rules! evaluate {
    ($t:ty, $m:ident) => {
        impl Evaluate for $t {
            #[inline(always)]
            fn of_factor(f: &dyn Factor, z: $t) -> $t {
                f.$m(z)
            }
        }
    };
}
evaluate!(f64, f64);
evaluate!(f32, f32);
evaluate!(f16, f16);
evaluate!(Interval, interval);
evaluate!(Dual, dual);
evaluate!(Rounded<F32>, rounded_f32);
evaluate!(Rounded<F16>, rounded_f16);

/// How a [`Scale`]'s function makes the normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// `N' = f(z) N`.
    Times,
    /// `N' = N / f(z)` (Mikami's square root: the division the GLSL does).
    Over,
    /// Exact normalisation: `N / |N|` in f64 (the reference), `N (1 / sqrt(z))` in the engines;
    /// `f` is `1 / sqrt(z)`.
    Exact,
}

/// The scale of [`Kernel::Scaled`]: the normal made from the interpolated one by a function of
/// its squared length.
#[derive(Debug, Clone, Copy)]
pub struct Scale {
    pub factor: &'static dyn Factor,
    pub form: Form,
    /// A range of z on which the factor is exactly `1 / sqrt(z)` algebraically (a guard that
    /// does not act there), so that `prove` knows the length error is 0 on a box inside it
    /// (intervals would leave ~1e-11 of dependency there).
    pub exact_on: Option<(f64, f64)>,
}

impl Scale {
    /// `N' = k(z) N`.
    pub const fn times(k: &'static dyn Factor) -> Scale {
        Scale {
            factor: k,
            form: Form::Times,
            exact_on: None,
        }
    }

    /// `N' = N / s(z)`.
    pub const fn over(s: &'static dyn Factor) -> Scale {
        Scale {
            factor: s,
            form: Form::Over,
            exact_on: None,
        }
    }

    /// `N' = k(z) N` with a `k` exactly `1 / sqrt(z)` on `range` (see [`Scale::exact_on`]).
    pub const fn exact_on(k: &'static dyn Factor, range: (f64, f64)) -> Scale {
        Scale {
            factor: k,
            form: Form::Times,
            exact_on: Some(range),
        }
    }

    /// The factor `k(z)` with `N' = k(z) N` in any number type: `f(z)`, or `1 / f(z)` for
    /// [`Form::Over`] (the same real number as the division the engines do).
    pub fn k<T: Evaluate + super::real::Real>(&self, z: T) -> T {
        let f = T::of_factor(self.factor, z);
        match self.form {
            Form::Times | Form::Exact => f,
            Form::Over => T::c(1.0) / f,
        }
    }
}

/// The kernel of a method: one variant per distinct form of its formula. Every evaluator
/// matches it exhaustively, so a row without a kernel, or a kernel without code, does not
/// compile.
#[derive(Debug, Clone, Copy)]
pub enum Kernel {
    /// One colour per triangle.
    Flat,
    /// The colours lit at the vertices, interpolated.
    VertexColour,
    /// The interpolated normal scaled per pixel by a function of its squared length.
    Scaled(Scale),
    /// The interpolated normal, Hast's half-vector correction against the flat normal.
    HastHalfVector,
    /// A quaternion per vertex interpolated, the normal recovered per pixel.
    Quaternion,
    /// [`Kernel::Quaternion`] in the triangle's frame (+Z the flat normal).
    QuaternionLocal,
    /// The weights interpolated, the quadratic normal field evaluated per pixel (the mid-edge
    /// normals by the paper's formula, or exactly).
    BarycentricQuadratic { exact_mid: bool },
    /// The weights interpolated, the PN quadratic normal evaluated and normalised per pixel.
    PnNormals,
    /// The normal normalised, the specular term read from the cos^n table.
    SpecularLut,
    /// Along the span through the pixel's row.
    Span(SpanKernel),
    /// None: a user method (`--method-file`) exists only as GLSL (no twin, no software
    /// kernel).
    None,
}

impl Kernel {
    /// The scale `prove` bounds: a [`Kernel::Scaled`] method that is not exact normalisation
    /// (the reference, whose error is 0 by definition). None: not covered.
    pub fn provable(&self) -> Option<&Scale> {
        match self {
            Kernel::Scaled(s) if s.form != Form::Exact => Some(s),
            _ => None,
        }
    }

    /// Whether a method has a kernel (a twin, a software form): every method of the table.
    pub fn exists(&self) -> bool {
        !matches!(self, Kernel::None)
    }
}

/// The span kernels of [`Kernel::Span`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpanKernel {
    /// slerp at each pixel's t (the closed form).
    Slerp,
    /// spherical_angular (the engine's Chebyshev recurrence).
    Chebyshev,
    /// G t^2 + P t + Q (by second-order forward differences in the engine).
    Quadratic { approx_mid: bool },
    /// The span's grid filled by halving, with this inverse square root.
    Dichotomy(InvRoot),
    /// 2^k-pixel segments: ends shaded, the colour interpolated (or dichotomy inside with a
    /// root).
    Segments(u32, Option<InvRoot>),
    /// Each cosine's Taylor polynomial.
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

impl InvRoot {
    /// Its formula (src/method/scanline.rs) in `T`.
    pub fn of<T: super::real::Real>(self) -> fn(T) -> T {
        use super::scanline as s;
        match self {
            InvRoot::Exact => s::inv_root_exact,
            InvRoot::Poly1 => s::inv_root_poly1,
            InvRoot::Poly2 => s::inv_root_poly2,
        }
    }
}
