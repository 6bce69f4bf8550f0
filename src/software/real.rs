//! The scalar the software engine computes in (issue 23): [`Real`], implemented for `f32` (the
//! shipped engine, bit for bit) and `half::f16` (the float16 twin of the device's f16
//! programs), and [`V3`], a three-vector of it. Every f16 operation rounds its result to
//! binary16 like the device: `half` computes each operation in f32 and rounds once to f16,
//! which is the correctly rounded f16 result for +, -, *, / and sqrt (binary32 has
//! 24 >= 2 * 11 + 2 significand bits, so the double rounding is innocuous: Figueroa, "When is
//! double rounding innocuous?", SIGNUM 1995); the transcendental functions (pow, sin, cos,
//! acos) are the f32 ones rounded once to f16, as a driver that promotes f16 to f32 computes
//! them.
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use glam::Vec3;
use half::f16;

use crate::method::Precision;

/// A floating-point scalar of the software engine. Literals go through [`Real::of`] (rounded
/// to the type like a GLSL `float16_t` literal).
pub trait Real:
    Copy
    + Send
    + Sync
    + PartialOrd
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + 'static
{
    /// The precision this scalar computes in.
    const PRECISION: Precision;
    const ZERO: Self;
    const ONE: Self;
    /// `x` rounded to this type (exact for f32).
    fn of(x: f32) -> Self;
    /// The value as f32 (exact: every binary16 is a binary32).
    fn f32(self) -> f32;
    fn sqrt(self) -> Self;
    fn powf(self, e: Self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn acos(self) -> Self;
    fn floor(self) -> Self;
    fn abs(self) -> Self;
    fn copysign(self, sign: Self) -> Self;
    fn is_nan(self) -> bool;
    /// `f32::max`/`f32::min` semantics (the other operand when one is NaN).
    fn max(self, o: Self) -> Self;
    fn min(self, o: Self) -> Self;
    /// `f32::clamp` semantics.
    fn clamp(self, lo: Self, hi: Self) -> Self;
}

impl Real for f32 {
    const PRECISION: Precision = Precision::F32;
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    #[inline(always)]
    fn of(x: f32) -> f32 {
        x
    }
    #[inline(always)]
    fn f32(self) -> f32 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn powf(self, e: f32) -> f32 {
        f32::powf(self, e)
    }
    #[inline(always)]
    fn sin(self) -> f32 {
        f32::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> f32 {
        f32::cos(self)
    }
    #[inline(always)]
    fn acos(self) -> f32 {
        f32::acos(self)
    }
    #[inline(always)]
    fn floor(self) -> f32 {
        f32::floor(self)
    }
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn copysign(self, sign: f32) -> f32 {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
    #[inline(always)]
    fn max(self, o: f32) -> f32 {
        f32::max(self, o)
    }
    #[inline(always)]
    fn min(self, o: f32) -> f32 {
        f32::min(self, o)
    }
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> f32 {
        f32::clamp(self, lo, hi)
    }
}

/// One f32 function of an f16, rounded once to f16.
#[inline(always)]
fn via(x: f16, f: impl Fn(f32) -> f32) -> f16 {
    f16::from_f32(f(x.to_f32()))
}

impl Real for f16 {
    const PRECISION: Precision = Precision::F16;
    const ZERO: f16 = f16::ZERO;
    const ONE: f16 = f16::ONE;
    #[inline(always)]
    fn of(x: f32) -> f16 {
        f16::from_f32(x)
    }
    #[inline(always)]
    fn f32(self) -> f32 {
        self.to_f32()
    }
    #[inline(always)]
    fn sqrt(self) -> f16 {
        via(self, f32::sqrt)
    }
    #[inline(always)]
    fn powf(self, e: f16) -> f16 {
        via(self, |x| x.powf(e.to_f32()))
    }
    #[inline(always)]
    fn sin(self) -> f16 {
        via(self, f32::sin)
    }
    #[inline(always)]
    fn cos(self) -> f16 {
        via(self, f32::cos)
    }
    #[inline(always)]
    fn acos(self) -> f16 {
        via(self, f32::acos)
    }
    #[inline(always)]
    fn floor(self) -> f16 {
        via(self, f32::floor)
    }
    #[inline(always)]
    fn abs(self) -> f16 {
        via(self, f32::abs)
    }
    #[inline(always)]
    fn copysign(self, sign: f16) -> f16 {
        via(self, |x| x.copysign(sign.to_f32()))
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f16::is_nan(self)
    }
    #[inline(always)]
    fn max(self, o: f16) -> f16 {
        f16::from_f32(self.to_f32().max(o.to_f32()))
    }
    #[inline(always)]
    fn min(self, o: f16) -> f16 {
        f16::from_f32(self.to_f32().min(o.to_f32()))
    }
    #[inline(always)]
    fn clamp(self, lo: f16, hi: f16) -> f16 {
        f16::from_f32(self.to_f32().clamp(lo.to_f32(), hi.to_f32()))
    }
}

/// A literal of the kernels, rounded to `S` (`c::<S>(0.5)`).
#[inline(always)]
pub fn c<S: Real>(x: f32) -> S {
    S::of(x)
}

/// A three-vector of [`Real`]: the operations of `glam::Vec3` the kernels use, in the same
/// order (so `V3<f32>` gives glam's results bit for bit: `dot` is `x x' + y y' + z z'` left to
/// right, `length` its square root, scalar products and quotients per component).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V3<S> {
    pub x: S,
    pub y: S,
    pub z: S,
}

impl<S: Real> V3<S> {
    pub const fn new(x: S, y: S, z: S) -> Self {
        V3 { x, y, z }
    }
    pub fn splat(v: S) -> Self {
        V3 { x: v, y: v, z: v }
    }
    pub fn zero() -> Self {
        Self::splat(S::ZERO)
    }
    /// An f32 vector rounded to `S` (where the shader first reads an input).
    #[inline(always)]
    pub fn of(v: Vec3) -> Self {
        V3::new(S::of(v.x), S::of(v.y), S::of(v.z))
    }
    /// Back to f32 (exact).
    #[inline(always)]
    pub fn f32(self) -> Vec3 {
        Vec3::new(self.x.f32(), self.y.f32(), self.z.f32())
    }
    #[inline(always)]
    pub fn dot(self, o: Self) -> S {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }
    #[inline(always)]
    pub fn length(self) -> S {
        self.dot(self).sqrt()
    }
    #[inline(always)]
    pub fn map(self, f: impl Fn(S) -> S) -> Self {
        V3::new(f(self.x), f(self.y), f(self.z))
    }
}

impl<S: Real> Add for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<S: Real> AddAssign for V3<S> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<S: Real> Sub for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<S: Real> Neg for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}

/// Per component (glam's `Vec3 * Vec3`).
impl<S: Real> Mul for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

impl<S: Real> Mul<S> for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: S) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<S: Real> Div<S> for V3<S> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: S) -> Self {
        V3::new(self.x / s, self.y / s, self.z / s)
    }
}
