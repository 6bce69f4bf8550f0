//! The number type the per-pixel formulas of [`super::formulas`] are written over: f64 (the
//! twins, bit-identical to the plain f64 code they replaced) and the outward-rounded interval of
//! `crate::prove` (the same formula bounded over a box of inputs: one formula, no second copy).
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Arithmetic a formula may use. A constant is written `T::c(0.5)`: for f64 it is the literal,
/// for an interval the point interval of that f64 value (the formula as the f64 code has it).
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `x`.
    fn c(x: f64) -> Self;
    /// The square root.
    fn sqrt(self) -> Self;
}

impl Real for f64 {
    #[inline]
    fn c(x: f64) -> f64 {
        x
    }
    #[inline]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}
