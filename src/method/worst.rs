//! The reduction every claim check applies to its sweep: the worst finite value and the count
//! of non-finite points, so that a formula returning NaN can never read as "error 0".

/// The reduction of a sweep: the finite value of largest magnitude (signed) and how many of
/// its points were not finite. Every check reduces its sweep with this, so a formula that
/// returns NaN or inf at any point cannot read as "error 0": [`Worst::within`] fails and the
/// measured text says how many points were non-finite.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Worst {
    /// The finite value of largest magnitude (0 when there is none).
    pub finite: f64,
    /// Points that were NaN or infinite.
    pub non_finite: usize,
    /// Points seen.
    pub points: usize,
}

impl Worst {
    /// The reduction of `values`.
    pub fn of(values: impl Iterator<Item = f64>) -> Worst {
        let mut w = Worst::default();
        values.for_each(|v| w.push(v));
        w
    }

    /// Adds one point.
    pub fn push(&mut self, v: f64) {
        self.points += 1;
        if !v.is_finite() {
            self.non_finite += 1;
        } else if v.abs() > self.finite.abs() {
            self.finite = v;
        }
    }

    /// The signed worst value; NaN when any point was not finite.
    pub fn value(&self) -> f64 {
        if self.non_finite > 0 {
            f64::NAN
        } else {
            self.finite
        }
    }

    /// Every point finite and |worst| <= `limit`.
    pub fn within(&self, limit: f64) -> bool {
        self.non_finite == 0 && self.finite.abs() <= limit
    }

    /// `""`, or `" (k of n points non-finite)"` to append to a measured figure.
    pub fn note(&self) -> String {
        if self.non_finite == 0 {
            String::new()
        } else {
            format!(
                " ({} of {} points non-finite)",
                self.non_finite, self.points
            )
        }
    }
}

/// The signed value of largest magnitude of a sweep (0 for an empty one), NaN when any value
/// is not finite ([`Worst::value`]).
#[cfg(test)]
pub(crate) fn worst(values: impl Iterator<Item = f64>) -> f64 {
    Worst::of(values).value()
}
