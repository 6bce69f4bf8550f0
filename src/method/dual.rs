//! Forward-mode derivatives over intervals: `Dual { v, d }` carries an enclosure of a value and
//! of its derivative with respect to one input, so a formula written over [`Real`] gives its
//! derivative's range too. [`mean_value`] uses it for the mean-value form
//! `f(Z) in f(m) + f'(Z) (Z - m)`, whose overestimation shrinks with the square of the width
//! (the naive enclosure's only linearly: `k(z) sqrt(z) - 1` cancels to nearly 0 near z = 1).
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::interval::Interval;
use super::real::Real;

/// A value and its derivative, both enclosed.
#[derive(Debug, Clone, Copy)]
pub struct Dual {
    pub v: Interval,
    pub d: Interval,
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: -self.d,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        let q = self.v / o.v;
        Dual {
            v: q,
            d: (self.d - q * o.d) / o.v,
        }
    }
}

impl Real for Dual {
    fn c(x: f64) -> Dual {
        Dual {
            v: Interval::point(x),
            d: Interval::point(0.0),
        }
    }

    fn sqrt(self) -> Dual {
        let r = self.v.sqrt();
        Dual {
            v: r,
            d: self.d / (Interval::point(2.0) * r),
        }
    }

    /// The operand that is the larger on the whole box (its value and derivative); where the
    /// two overlap, the pointwise max with an unknown derivative (the kink may lie inside).
    fn max(self, o: Dual) -> Dual {
        if self.v.lo >= o.v.hi {
            self
        } else if o.v.lo >= self.v.hi {
            o
        } else {
            Dual {
                v: Real::max(self.v, o.v),
                d: Interval::ENTIRE,
            }
        }
    }

    /// As [`Dual::max`], the smaller.
    fn min(self, o: Dual) -> Dual {
        -((-self).max(-o))
    }
}

/// The enclosure of `f` over `z`: the naive one intersected with the mean-value form about the
/// midpoint (`f` must be the same generic formula in both instantiations).
pub fn mean_value(
    z: Interval,
    f_interval: impl Fn(Interval) -> Interval,
    f_dual: impl Fn(Dual) -> Dual,
) -> Interval {
    let naive = f_interval(z);
    let m = z.mid();
    let at_m = f_interval(Interval::point(m));
    let slope = f_dual(Dual {
        v: z,
        d: Interval::point(1.0),
    })
    .d;
    let mv = at_m + slope * (z - Interval::point(m));
    if mv.lo.is_nan() || mv.hi.is_nan() {
        return naive;
    }
    Interval {
        lo: naive.lo.max(mv.lo),
        hi: naive.hi.min(mv.hi),
    }
}
