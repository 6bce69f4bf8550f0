//! A closed interval of reals with outward rounding: every operation rounds its lower end down
//! and its upper end up by one ulp (`f64::next_down` / `next_up`), so the real result of the
//! operation on any points of its operands lies inside (IEEE +, -, *, /, sqrt are correctly
//! rounded, so one ulp suffices; sin and cos come from the platform's libm, within one ulp on
//! glibc, widened by four). An operation that could produce NaN (0 * inf, a divisor holding 0)
//! gives the whole line, never a NaN bound. Implements [`Real`] so the method formulas run on
//! it unchanged: `prove` bounds a row's formula with it, and a row's kernel carries the
//! formula's interval instantiation ([`super::kernel::Factor`]), which is why it lives here
//! with the other number types (`crate::prove::interval` names it too).
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::real::Real;

/// `[lo, hi]`, lo <= hi (either may be infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

fn down(x: f64) -> f64 {
    x.next_down()
}

fn up(x: f64) -> f64 {
    x.next_up()
}

impl Interval {
    /// The whole real line (the answer where an operation cannot bound its result).
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// `[lo, hi]`; panics on NaN or lo > hi (a programming error).
    pub fn new(lo: f64, hi: f64) -> Interval {
        assert!(lo <= hi, "interval [{lo}, {hi}]");
        Interval { lo, hi }
    }

    /// The point interval of `x`.
    pub fn point(x: f64) -> Interval {
        Interval::new(x, x)
    }

    /// Rounded outward (the result of an operation whose ends were computed to nearest).
    fn outward(lo: f64, hi: f64) -> Interval {
        if lo.is_nan() || hi.is_nan() {
            return Interval::ENTIRE;
        }
        Interval {
            lo: down(lo),
            hi: up(hi),
        }
    }

    pub fn mid(self) -> f64 {
        0.5 * self.lo + 0.5 * self.hi
    }

    pub fn width(self) -> f64 {
        self.hi - self.lo
    }

    pub fn contains(self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// The largest |x| over the interval.
    pub fn mag(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// The two halves at the midpoint.
    pub fn split(self) -> (Interval, Interval) {
        let m = self.mid().clamp(self.lo, self.hi);
        (Interval::new(self.lo, m), Interval::new(m, self.hi))
    }

    /// Grown by `r` (>= 0) on both sides, rounded outward.
    pub fn widen(self, r: f64) -> Interval {
        Interval::outward(self.lo - r, self.hi + r)
    }

    /// `x^2` (tighter than `x * x` where the interval holds 0).
    pub fn sqr(self) -> Interval {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        if self.lo <= 0.0 && self.hi >= 0.0 {
            Interval::outward(0.0, a.max(b)).clamp_lo(0.0)
        } else {
            Interval::outward(a.min(b), a.max(b)).clamp_lo(0.0)
        }
    }

    fn clamp_lo(self, lo: f64) -> Interval {
        Interval {
            lo: self.lo.max(lo),
            hi: self.hi.max(lo),
        }
    }

    fn clamp_unit(self) -> Interval {
        Interval {
            lo: self.lo.clamp(-1.0, 1.0),
            hi: self.hi.clamp(-1.0, 1.0),
        }
    }

    /// `libm(x)` widened by four ulps each way (libm's sin/cos are not correctly rounded).
    fn libm(lo: f64, hi: f64) -> Interval {
        let mut i = Interval::outward(lo, hi);
        for _ in 0..3 {
            i = Interval::outward(i.lo, i.hi);
        }
        i.clamp_unit()
    }

    /// sin: exact monotone bounds within [-pi/2, pi/2] (1 at the top where the interval reaches
    /// past pi/2 but stays below pi); [-1, 1] otherwise.
    pub fn sin(self) -> Interval {
        let half = std::f64::consts::FRAC_PI_2;
        if self.lo >= -1.5 && self.hi <= half {
            Interval::libm(self.lo.sin(), self.hi.sin())
        } else if self.lo >= -1.5 && self.hi <= 3.0 {
            Interval::libm(self.lo.sin().min(self.hi.sin()), 1.0)
        } else {
            Interval::new(-1.0, 1.0)
        }
    }

    /// cos: increasing on [-3, 0], decreasing on [0, 3] (inside [-pi, pi]), 1 at 0; [-1, 1]
    /// outside.
    pub fn cos(self) -> Interval {
        if self.lo < -3.0 || self.hi > 3.0 {
            Interval::new(-1.0, 1.0)
        } else if self.lo >= 0.0 {
            Interval::libm(self.hi.cos(), self.lo.cos())
        } else if self.hi <= 0.0 {
            Interval::libm(self.lo.cos(), self.hi.cos())
        } else {
            Interval::libm(self.lo.cos().min(self.hi.cos()), 1.0)
        }
    }

    /// `x^n` for an integer `n >= 1`, by repeated multiplication.
    pub fn powi(self, n: u32) -> Interval {
        let mut r = self;
        for _ in 1..n {
            r = r * self;
        }
        r
    }

    /// The smallest interval holding both.
    pub fn hull(self, o: Interval) -> Interval {
        Interval {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// `max(self, o)` pointwise.
    pub fn max(self, o: Interval) -> Interval {
        Interval {
            lo: self.lo.max(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, o: Interval) -> Interval {
        Interval::outward(self.lo + o.lo, self.hi + o.hi)
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, o: Interval) -> Interval {
        Interval::outward(self.lo - o.hi, self.hi - o.lo)
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, o: Interval) -> Interval {
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::outward(lo, hi)
    }
}

impl Div for Interval {
    type Output = Interval;
    fn div(self, o: Interval) -> Interval {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            return Interval::ENTIRE;
        }
        let p = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if p.iter().any(|x| x.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Interval::outward(lo, hi)
    }
}

impl Real for Interval {
    fn c(x: f64) -> Interval {
        Interval::point(x)
    }

    /// sqrt of the non-negative part: the formulas take roots of squared lengths, real values
    /// of at least 0 whose enclosure may dip below 0. An interval wholly below 0 gives the
    /// whole line (nothing is claimed there).
    fn sqrt(self) -> Interval {
        if self.hi < 0.0 {
            return Interval::ENTIRE;
        }
        let lo = self.lo.max(0.0);
        Interval::outward(lo.sqrt(), self.hi.sqrt()).clamp_lo(0.0)
    }

    /// Pointwise ([`Interval::max`]).
    fn max(self, o: Interval) -> Interval {
        Interval::max(self, o)
    }

    /// Pointwise.
    fn min(self, o: Interval) -> Interval {
        Interval {
            lo: self.lo.min(o.lo),
            hi: self.hi.min(o.hi),
        }
    }
}
