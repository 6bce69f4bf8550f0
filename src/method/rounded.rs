//! A number type for proving what a program computes in float32 or float16, not only the real
//! formula it stands for: [`Rounded`] carries an enclosure of the exact value of the formula
//! (`v`) and an enclosure of the difference between the program's value and it (`e`), both
//! outward-rounded [`Interval`]s. It implements [`Real`], so a formula's one generic function
//! runs on it unchanged: tune's candidates, and the rows' factors ([`super::kernel::Factor`]),
//! which tune proves beside them.
//!
//! What a program may do to each operation (the Vulkan precision rules for SPIR-V): +, - and *
//! are correctly rounded in the implementation's rounding mode, round to nearest even or toward
//! zero, so within one ulp, `|fl(x) - x| <= ULP |x|` with ULP = 2^-23 (binary32) or 2^-10
//! (binary16); a division within 2.5 ulp (OpFDiv), a square root as `1 / inversesqrt` (2 ulp,
//! then the division): [`Format::DIV_ULPS`], [`Format::SQRT_ULPS`]; results and operands below
//! the smallest normal may be flushed to zero: [`Format::TINY`] absolute per operation. A
//! fused multiply-add rounds once where the formula rounds twice: the two roundings' bound
//! covers it. What the model does not cover: a compiler that reassociates the formula (the
//! bound is for the order of operations the formula and its GLSL file share).
//!
//! A constant enters as the formula writes it (`v`) and as the program holds it: the literal
//! rounded to the format, round to nearest (glslang folds `float16_t(0.822)` so), its
//! difference in `e`. The tuned candidates' coefficients are float32 values, exact in the
//! float32 programs.
use std::marker::PhantomData;
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::Interval;
use super::real::Real;
use super::Precision;

/// A floating-point format a program computes in.
pub trait Format: Copy + std::fmt::Debug + 'static {
    /// One ulp relative: the largest relative error of a correctly rounded +, -, * in either
    /// rounding mode Vulkan allows (to nearest even, toward zero).
    const ULP: f64;
    /// Ulps of a division (Vulkan: 2.5 ulp), rounded up.
    const DIV_ULPS: f64 = 3.0;
    /// Ulps of a square root computed as `1 / inversesqrt(x)` (2 ulp, then 2.5), rounded up.
    const SQRT_ULPS: f64 = 5.0;
    /// The smallest positive normal: the absolute error of a flush to zero.
    const TINY: f64;
    const PRECISION: Precision;
    /// `x` rounded to the format, to nearest even (a literal as the compiler folds it).
    fn round(x: f64) -> f64;
}

/// IEEE binary32.
#[derive(Debug, Clone, Copy)]
pub struct F32;

/// IEEE binary16.
#[derive(Debug, Clone, Copy)]
pub struct F16;

impl Format for F32 {
    const ULP: f64 = 1.0 / 8_388_608.0; // 2^-23
    const TINY: f64 = 1.1754943508222875e-38; // 2^-126
    const PRECISION: Precision = Precision::F32;
    fn round(x: f64) -> f64 {
        f64::from(x as f32)
    }
}

impl Format for F16 {
    const ULP: f64 = 1.0 / 1024.0; // 2^-10
    const TINY: f64 = 6.103515625e-05; // 2^-14
    const PRECISION: Precision = Precision::F16;
    fn round(x: f64) -> f64 {
        f64::from(half::f16::from_f64(x).to_f32())
    }
}

/// The exact value of a formula and the program's error against it, both enclosed.
#[derive(Debug, Clone, Copy)]
pub struct Rounded<F: Format> {
    /// Encloses the formula's exact value.
    pub v: Interval,
    /// Encloses (the program's value) - (the exact value).
    pub e: Interval,
    _f: PhantomData<F>,
}

fn sym(r: f64) -> Interval {
    Interval::new(-r, r)
}

impl<F: Format> Rounded<F> {
    /// An input whose exact value lies in `v` and whose value in the program differs from it by
    /// something in `e`.
    pub fn input(v: Interval, e: Interval) -> Self {
        Rounded {
            v,
            e,
            _f: PhantomData,
        }
    }

    /// A value whose exact value lies in `v` and whose program's error is not known (the whole
    /// line): what a formula without a rounded form gives ([`super::kernel::Factor`]).
    pub fn unknown(v: Interval) -> Self {
        Rounded::input(v, Interval::ENTIRE)
    }

    /// Encloses the program's value.
    pub fn computed(self) -> Interval {
        self.v + self.e
    }

    /// The error of rounding a result enclosed by `x`, `ulps` ulps.
    fn rounding(x: Interval, ulps: f64) -> Interval {
        sym((ulps * F::ULP * x.mag() + F::TINY).next_up())
    }

    fn with(v: Interval, e: Interval) -> Self {
        // An unbounded error is the whole line, never NaN.
        let e = if e.lo.is_nan() || e.hi.is_nan() {
            Interval::ENTIRE
        } else {
            e
        };
        Rounded::input(v, e)
    }
}

impl<F: Format> Add for Rounded<F> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        let s = self.computed() + o.computed();
        Self::with(self.v + o.v, self.e + o.e + Self::rounding(s, 1.0))
    }
}

impl<F: Format> Sub for Rounded<F> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        let s = self.computed() - o.computed();
        Self::with(self.v - o.v, self.e - o.e + Self::rounding(s, 1.0))
    }
}

impl<F: Format> Neg for Rounded<F> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::with(-self.v, -self.e)
    }
}

impl<F: Format> Mul for Rounded<F> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        // (v1 + e1)(v2 + e2) - v1 v2 = v1 e2 + v2 e1 + e1 e2
        let p = self.computed() * o.computed();
        let e = self.v * o.e + o.v * self.e + self.e * o.e + Self::rounding(p, 1.0);
        Self::with(self.v * o.v, e)
    }
}

impl<F: Format> Div for Rounded<F> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        // (v1 + e1)/(v2 + e2) - v1/v2 = (e1 v2 - v1 e2) / (v2 (v2 + e2))
        let q = self.computed() / o.computed();
        let d = (self.e * o.v - self.v * o.e) / (o.v * o.computed());
        Self::with(self.v / o.v, d + Self::rounding(q, F::DIV_ULPS))
    }
}

impl<F: Format> Real for Rounded<F> {
    fn c(x: f64) -> Self {
        Rounded::input(Interval::point(x), Interval::point(F::round(x) - x))
    }

    fn sqrt(self) -> Self {
        // sqrt(v + e) - sqrt(v) = e / (sqrt(v + e) + sqrt(v))
        let (r, rc) = (self.v.sqrt(), self.computed().sqrt());
        let d = self.e / (r + rc);
        Self::with(r, d + Self::rounding(rc, F::SQRT_ULPS))
    }

    /// Exact in every format (no rounding): the program's value is the larger computed one,
    /// its difference from the larger exact one enclosed by the two enclosures' difference.
    fn max(self, o: Self) -> Self {
        let v = Real::max(self.v, o.v);
        Self::with(v, Real::max(self.computed(), o.computed()) - v)
    }

    /// As [`Real::max`].
    fn min(self, o: Self) -> Self {
        let v = Real::min(self.v, o.v);
        Self::with(v, Real::min(self.computed(), o.computed()) - v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64) -> Rounded<F32> {
        Rounded::input(Interval::point(x), Interval::point(0.0))
    }

    /// Horner in f32 with the device's operations (round to nearest, no fma).
    fn horner_f32(c: &[f32], z: f32) -> f32 {
        c.iter().rev().fold(0.0f32, |a, &k| a * z + k)
    }

    /// The enclosure holds what float32 computes, and the rounding it allows is of the order
    /// of an ulp per operation, not more.
    #[test]
    fn encloses_float32_horner_and_is_tight() {
        let c: [f32; 4] = [3.123_456_7, -4.765_432, 3.333_333_3, -0.987_654_3];
        let mut rng = fastrand::Rng::with_seed(7);
        for _ in 0..2000 {
            let z = f64::from(0.3 + 0.7 * rng.f32());
            let r = c
                .iter()
                .rev()
                .fold(p(0.0), |a, &k| a * p(z) + Rounded::c(f64::from(k)));
            let exact = c.iter().rev().fold(0.0, |a, &k| a * z + f64::from(k));
            let got = f64::from(horner_f32(&c, z as f32));
            assert!(r.v.contains(exact), "{r:?} {exact}");
            assert!(r.computed().contains(got), "{r:?} {got}");
            // 3 multiplications and 3 additions of values up to ~5: a few ulps of 5
            assert!(r.e.mag() < 12.0 * 5.0 * F32::ULP, "{:?}", r.e);
        }
        // teeth: without the rounding term the enclosure misses float32's value somewhere
        let z = 0.7f32;
        let exact = c
            .iter()
            .rev()
            .fold(0.0, |a, &k| a * f64::from(z) + f64::from(k));
        assert_ne!(exact, f64::from(horner_f32(&c, z)));
    }

    #[test]
    fn a_constant_carries_its_rounding_to_the_format() {
        let r: Rounded<F16> = Rounded::c(0.822);
        let held = f64::from(half::f16::from_f64(0.822).to_f32());
        assert_eq!(r.v, Interval::point(0.822));
        assert!(r.computed().contains(held) && r.e.mag() > 1e-5, "{r:?}");
        let exact: Rounded<F32> = Rounded::c(0.5);
        assert_eq!(exact.e, Interval::point(0.0));
    }

    /// max and min carry both enclosures: the exact larger value and the computed one.
    #[test]
    fn max_and_min_enclose_float32() {
        let (a, b) = (p(0.3) * p(0.1), p(0.03));
        let (af, bf) = (0.3f32 * 0.1f32, 0.03f32);
        let (hi, lo) = (Real::max(a, b), Real::min(a, b));
        assert!(hi.v.contains(0.03) && lo.v.contains(0.03), "{hi:?} {lo:?}");
        assert!(hi.computed().contains(f64::from(af.max(bf))), "{hi:?}");
        assert!(lo.computed().contains(f64::from(af.min(bf))), "{lo:?}");
        // teeth: the product's rounding is carried (float32's 0.3 * 0.1 is not 0.03)
        assert!(hi.e.mag() > 0.0, "{hi:?}");
    }

    #[test]
    fn division_and_square_root_enclose_float32() {
        let mut rng = fastrand::Rng::with_seed(9);
        for _ in 0..2000 {
            let (a, b) = (0.1 + rng.f64(), 0.1 + rng.f64());
            let (af, bf) = (a as f32, b as f32);
            let (ra, rb) = (p(f64::from(af)), p(f64::from(bf)));
            assert!((ra / rb).computed().contains(f64::from(af / bf)));
            assert!(ra.sqrt().computed().contains(f64::from(af.sqrt())));
            assert!((ra / rb).v.contains(f64::from(af) / f64::from(bf)));
        }
    }
}
