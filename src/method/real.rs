//! The number types every method formula is written over: one generic function per formula
//! ([`super::formulas`], [`super::scanline`]), evaluated in each type the tool computes in.
//!
//! - [`Real`]: the arithmetic a formula may use (+, -, *, /, negation, constants, square root,
//!   max and min). Implemented for `f64` (the f64 truth: the twins, stress, the claims' sweeps),
//!   `f32` (the software engine, bit for bit the shipped engine), `half::f16` (the float16 twin
//!   of the device's f16 programs) and the outward-rounded interval `prove` bounds with, and
//!   its derivative ([`super::interval::Interval`], [`super::dual::Dual`]: the same formula
//!   bounded over a box of inputs). A formula over [`Real`] alone runs in all five, which is
//!   what makes a method provable.
//! - [`Float`]: a [`Real`] that is one point, not a box: comparisons, the transcendental
//!   functions, floor and friends (`f64`, `f32`, `f16`). Formulas with branches (zero-length
//!   guards, the span's clamps) are written over it.
//! - [`Vector`]: a three-vector of a [`Real`], with glam's `DVec3` as the f64 one (so the f64
//!   truth keeps its type) and [`V3`] for the others. Every operation is per component in
//!   glam's order (`dot` is `x x' + y y' + z z'` left to right), so a formula gives glam's f64
//!   results bit for bit and [`V3<f32>`] gives `glam::Vec3`'s.
//!
//! Constants are written `T::c(0.5)`: the f64 value rounded to the working precision. f32
//! rounds it once (`x as f32`), as glslang rounds a float literal of the float32 programs (it
//! parses the literal to double, then converts); f16 goes through that f32 value, as the
//! float16 programs' literals do; an interval takes the point interval of the f64 value (the
//! formula as the f64 truth has it). A test checks that every constant of the formulas rounds
//! to the same f32 as its decimal literal.
//!
//! Every f16 operation rounds its result to binary16 like the device: `half` computes each
//! operation in f32 and rounds once to f16, which is the correctly rounded f16 result for
//! +, -, *, / and sqrt (binary32 has 24 >= 2 * 11 + 2 significand bits, so the double rounding
//! is innocuous: Figueroa, "When is double rounding innocuous?", SIGNUM 1995); the
//! transcendental functions (pow, sin, cos, acos) are the f32 ones rounded once to f16, as a
//! driver that promotes f16 to f32 computes them.
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use glam::{DVec3, Vec3};
use half::f16;

/// Arithmetic a formula may use.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `x` rounded to this type's precision (see the module's doc).
    fn c(x: f64) -> Self;
    /// The square root.
    fn sqrt(self) -> Self;
    /// The larger of the two (`f64::max` semantics for a point: the other operand when one is
    /// NaN; pointwise for an interval).
    fn max(self, o: Self) -> Self;
    /// The smaller of the two (as [`Real::max`]).
    fn min(self, o: Self) -> Self;
}

/// A [`Real`] that is a point: what formulas with branches need.
pub trait Float: Real + PartialOrd + Send + Sync + std::fmt::Debug + AddAssign + 'static {
    const ZERO: Self;
    const ONE: Self;
    /// Whether the scanline formulas refine `acos` by one Newton step on sin, as
    /// glsl/scanline.glsl does for Mesa's low-degree `acos` (the float programs), or take
    /// libm's `acos` as it is (the f64 truth).
    const REFINED_ACOS: bool;
    /// The type window positions are in: f64 for the f64 truth, f32 for the engines (as the
    /// rasterizer's, in both precisions).
    type Pos: Float<Pos = Self::Pos>;
    /// A position's value in this type (rounded where narrower).
    fn of_pos(p: Self::Pos) -> Self;
    /// This value as a position (exact: a position type is at least as wide).
    fn to_pos(self) -> Self::Pos;
    /// An f32 value in this type (rounded to f16, exact for f32 and f64).
    fn of(x: f32) -> Self;
    /// The value as f32 (exact for f16 and f32; rounded for f64).
    fn f32(self) -> f32;
    /// A count as this type (`n as f64`, `n as f32`).
    fn of_usize(n: usize) -> Self;
    /// `self as usize` (truncation, saturating).
    fn to_usize(self) -> usize;
    /// `x`, or `half` in float16 where `x` is below its range (GLSL's `BY_PRECISION(x, half)`).
    fn by_precision(x: f64, _half: f64) -> Self {
        Self::c(x)
    }
    fn powf(self, e: Self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn acos(self) -> Self;
    fn floor(self) -> Self;
    fn abs(self) -> Self;
    fn copysign(self, sign: Self) -> Self;
    fn is_nan(self) -> bool;
    /// `f32::clamp` semantics.
    fn clamp(self, lo: Self, hi: Self) -> Self;
}

/// The `Real` and `Float` impls of a primitive float type (`f64`, `f32`), each operation the
/// type's own.
macro_rules! primitive {
    ($t:ty, $refined:expr, $c:expr, $acos:expr) => {
        impl Real for $t {
            #[inline(always)]
            fn c(x: f64) -> $t {
                $c(x)
            }
            #[inline(always)]
            fn sqrt(self) -> $t {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn max(self, o: $t) -> $t {
                <$t>::max(self, o)
            }
            #[inline(always)]
            fn min(self, o: $t) -> $t {
                <$t>::min(self, o)
            }
        }

        impl Float for $t {
            const ZERO: $t = 0.0;
            const ONE: $t = 1.0;
            const REFINED_ACOS: bool = $refined;
            type Pos = $t;
            #[inline(always)]
            fn of_pos(p: $t) -> $t {
                p
            }
            #[inline(always)]
            fn to_pos(self) -> $t {
                self
            }
            #[inline(always)]
            fn of(x: f32) -> $t {
                x as $t
            }
            #[inline(always)]
            fn f32(self) -> f32 {
                self as f32
            }
            #[inline(always)]
            fn of_usize(n: usize) -> $t {
                n as $t
            }
            #[inline(always)]
            fn to_usize(self) -> usize {
                self as usize
            }
            #[inline(always)]
            fn powf(self, e: $t) -> $t {
                <$t>::powf(self, e)
            }
            #[inline(always)]
            fn sin(self) -> $t {
                <$t>::sin(self)
            }
            #[inline(always)]
            fn cos(self) -> $t {
                <$t>::cos(self)
            }
            #[inline(always)]
            fn acos(self) -> $t {
                $acos(self)
            }
            #[inline(always)]
            fn floor(self) -> $t {
                <$t>::floor(self)
            }
            #[inline(always)]
            fn abs(self) -> $t {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn copysign(self, sign: $t) -> $t {
                <$t>::copysign(self, sign)
            }
            #[inline(always)]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline(always)]
            fn clamp(self, lo: $t, hi: $t) -> $t {
                <$t>::clamp(self, lo, hi)
            }
        }
    };
}

primitive!(f64, false, |x: f64| x, f64::acos);
primitive!(f32, true, |x: f64| x as f32, acos_f32);

/// `acos` of an f32, the engines' own: libm's f64 `acos` rounded once to f32. The platform's
/// `acosf` is not the same function everywhere (glibc 2.41 made it correctly rounded, 2.36's
/// returns other bits for some inputs: the software engine's golden frames changed between
/// Debian 12 and 13); the f64 function is within one f64 ulp of the exact value on both, so its
/// rounding to f32 is the correctly rounded result except where the exact value lies within an
/// f64 ulp of a midpoint between two f32 (tests/software/golden.rs holds the frames this gives).
#[inline(always)]
pub fn acos_f32(x: f32) -> f32 {
    f64::from(x).acos() as f32
}

/// One f32 function of an f16, rounded once to f16.
#[inline(always)]
fn via(x: f16, f: impl Fn(f32) -> f32) -> f16 {
    f16::from_f32(f(x.to_f32()))
}

impl Real for f16 {
    #[inline(always)]
    fn c(x: f64) -> f16 {
        f16::from_f32(x as f32)
    }
    #[inline(always)]
    fn sqrt(self) -> f16 {
        via(self, f32::sqrt)
    }
    #[inline(always)]
    fn max(self, o: f16) -> f16 {
        f16::from_f32(self.to_f32().max(o.to_f32()))
    }
    #[inline(always)]
    fn min(self, o: f16) -> f16 {
        f16::from_f32(self.to_f32().min(o.to_f32()))
    }
}

impl Float for f16 {
    const ZERO: f16 = f16::ZERO;
    const ONE: f16 = f16::ONE;
    const REFINED_ACOS: bool = true;
    type Pos = f32;
    #[inline(always)]
    fn of_pos(p: f32) -> f16 {
        f16::from_f32(p)
    }
    #[inline(always)]
    fn to_pos(self) -> f32 {
        self.to_f32()
    }
    #[inline(always)]
    fn of(x: f32) -> f16 {
        f16::from_f32(x)
    }
    #[inline(always)]
    fn f32(self) -> f32 {
        self.to_f32()
    }
    #[inline(always)]
    fn of_usize(n: usize) -> f16 {
        f16::from_f32(n as f32)
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self.to_f32() as usize
    }
    #[inline(always)]
    fn by_precision(_x: f64, half: f64) -> f16 {
        Self::c(half)
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
        // The engines' own f32 acos ([`acos_f32`]), rounded once to f16.
        via(self, acos_f32)
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
    fn clamp(self, lo: f16, hi: f16) -> f16 {
        f16::from_f32(self.to_f32().clamp(lo.to_f32(), hi.to_f32()))
    }
}

/// A three-vector of a [`Real`]: the operations a formula uses, per component.
pub trait Vector:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<Output = Self>
    + Mul<<Self as Vector>::S, Output = Self>
    + Div<<Self as Vector>::S, Output = Self>
    + AddAssign
{
    /// The scalar.
    type S: Real;
    fn new(x: Self::S, y: Self::S, z: Self::S) -> Self;
    fn x(self) -> Self::S;
    fn y(self) -> Self::S;
    fn z(self) -> Self::S;
    /// `x x' + y y' + z z'`, left to right.
    #[inline(always)]
    fn dot(self, o: Self) -> Self::S {
        (self.x() * o.x()) + (self.y() * o.y()) + (self.z() * o.z())
    }
    /// The square root of [`Vector::dot`] with itself.
    #[inline(always)]
    fn length(self) -> Self::S {
        self.dot(self).sqrt()
    }
    /// Every component `v`.
    #[inline(always)]
    fn splat(v: Self::S) -> Self {
        Self::new(v, v, v)
    }
}

/// The scalar of a vector type.
pub type Scalar<V> = <V as Vector>::S;

/// The position type of a vector type's scalar ([`Float::Pos`]).
pub type Pos<V> = <<V as Vector>::S as Float>::Pos;

/// The f64 truth's vector.
impl Vector for DVec3 {
    type S = f64;
    #[inline(always)]
    fn new(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }
    #[inline(always)]
    fn x(self) -> f64 {
        self.x
    }
    #[inline(always)]
    fn y(self) -> f64 {
        self.y
    }
    #[inline(always)]
    fn z(self) -> f64 {
        self.z
    }
    #[inline(always)]
    fn dot(self, o: DVec3) -> f64 {
        DVec3::dot(self, o)
    }
    #[inline(always)]
    fn length(self) -> f64 {
        DVec3::length(self)
    }
}

/// A three-vector of [`Real`] `S`: the engines' vectors (f32, f16) and intervals'.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V3<S> {
    pub x: S,
    pub y: S,
    pub z: S,
}

impl<S: Real> Vector for V3<S> {
    type S = S;
    #[inline(always)]
    fn new(x: S, y: S, z: S) -> Self {
        V3 { x, y, z }
    }
    #[inline(always)]
    fn x(self) -> S {
        self.x
    }
    #[inline(always)]
    fn y(self) -> S {
        self.y
    }
    #[inline(always)]
    fn z(self) -> S {
        self.z
    }
}

impl<S: Real> V3<S> {
    pub const fn new(x: S, y: S, z: S) -> Self {
        V3 { x, y, z }
    }
    /// `x x' + y y' + z z'` ([`Vector::dot`]).
    #[inline(always)]
    pub fn dot(self, o: Self) -> S {
        Vector::dot(self, o)
    }
    #[inline(always)]
    pub fn length(self) -> S {
        Vector::length(self)
    }
    pub fn zero() -> Self {
        Self::splat(S::c(0.0))
    }
    pub fn splat(v: S) -> Self {
        V3 { x: v, y: v, z: v }
    }
    #[inline(always)]
    pub fn map(self, f: impl Fn(S) -> S) -> Self {
        V3::new(f(self.x), f(self.y), f(self.z))
    }
}

impl<S: Float> V3<S> {
    /// An f32 vector rounded to `S` (where the shader first reads an input).
    #[inline(always)]
    pub fn of(v: Vec3) -> Self {
        V3::new(S::of(v.x), S::of(v.y), S::of(v.z))
    }
    /// Back to f32 (exact for f16 and f32).
    #[inline(always)]
    pub fn f32(self) -> Vec3 {
        Vec3::new(self.x.f32(), self.y.f32(), self.z.f32())
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every constant of the formulas (src/method/formulas.rs, scanline.rs) rounds to the same
    /// f32 through f64 (`Real::c`) as its decimal literal does directly (Rust's f32 literals
    /// are correctly rounded): the double rounding of glslang's literals changes none of them,
    /// so the software engine computes with the constants it computed with as f32 literals.
    #[test]
    fn every_formula_constant_rounds_to_its_f32_literal() {
        // the literals as the formulas write them (2^-14 spelled out in full)
        #[rustfmt::skip]
        #[allow(clippy::excessive_precision)]
        let pairs: [(f64, f32); 29] = [
            (0.5, 0.5), (3.0, 3.0), (1.0, 1.0), (0.375, 0.375), (0.822, 0.822),
            (2.046, 2.046), (2.227, 2.227), (2.0 / 3.0, 2.0 / 3.0), (0.35, 0.35), (0.64, 0.64),
            (1.07, 1.07), (0.62, 0.62), (0.763, 0.763), (1.57, 1.57), (1.31, 1.31),
            (2.0, 2.0), (0.103, 0.103), (0.306, 0.306), (0.705, 0.705), (4.0, 4.0),
            (0.07, 0.07), (0.014253, 0.014253), (0.118922, 0.118922), (0.680850, 0.680850),
            (6.103515625e-05, 6.103515625e-05), (65504.0, 65504.0), (8.0, 8.0), (1e-8, 1e-8),
            (0.001953125, 0.001953125),
        ];
        for (x, lit) in pairs {
            assert_eq!(<f32 as Real>::c(x).to_bits(), lit.to_bits(), "{x}");
            assert_eq!(<f16 as Real>::c(x), f16::from_f32(lit), "{x}");
        }
        // teeth: a decimal just above the midpoint 1 + 2^-24 of two f32 neighbours rounds up
        // as an f32 literal, but to the midpoint as an f64 and then to even (1.0) as an f32:
        // the double rounding this test would see
        #[allow(clippy::excessive_precision)]
        let (x, lit) = (
            1.000_000_059_604_644_775_390_625_000_01f64,
            1.000_000_059_604_644_775_390_625_000_01f32,
        );
        assert_ne!(<f32 as Real>::c(x).to_bits(), lit.to_bits());
    }

    #[test]
    fn v3_f32_gives_glams_results_and_dvec3_its_own() {
        let (a, b) = (Vec3::new(0.3, -1.7, 2.9), Vec3::new(1.1, 0.4, -0.6));
        let (va, vb) = (V3::<f32>::of(a), V3::<f32>::of(b));
        assert_eq!(va.dot(vb).to_bits(), a.dot(b).to_bits());
        assert_eq!(va.length().to_bits(), a.length().to_bits());
        assert_eq!(((va + vb) * 2.5).f32(), (a + b) * 2.5);
        let d = DVec3::new(0.3, -1.7, 2.9);
        assert_eq!(Vector::length(d).to_bits(), d.length().to_bits());
    }
}
