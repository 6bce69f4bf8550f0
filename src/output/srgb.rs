//! The sRGB transfer function to 8 bits: [`srgb8_formula`] (the definition, one `powf` per
//! value) and [`srgb8`], the same function read from a table of its 255 steps (issue 26: the
//! `powf` of every channel of every frame was 13 % of `compare`'s CPU).
//!
//! Why the table is exact: over the f32 in [0, 1] (the formula clamps everything else there) the
//! formula is a non-decreasing step function of the input, so it is known exactly from the
//! smallest input of each step (`thresholds[k]`: the first f32 whose value is `k`, found by
//! bisection over the bit patterns, which order the non-negative f32 as their values do). The
//! table is built at run time from the formula itself, with the `powf` of the machine it runs
//! on. The formula is non-decreasing in exact arithmetic and each f32 step after `powf`
//! (multiplication by a positive constant, addition, truncation) is monotone, so only `powf`
//! could break it; `srgb8_table_equals_formula_on_every_f32` (ignored: about 10^9 inputs)
//! checks every f32 in [0, 1], and the suite checks the neighbourhood of every step and a
//! stride over the range (docs/performance-compare.md gives the run).
use std::sync::OnceLock;

use crate::output::steps::{Steps, ONE};

/// sRGB transfer function of a linear value, clamped to [0, 1] (NaN and Inf become 0), as 8
/// bits: the definition.
pub fn srgb8_formula(linear: f32) -> u8 {
    let x = clamp01(linear);
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

fn clamp01(linear: f32) -> f32 {
    if linear.is_finite() {
        linear.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The steps of [`srgb8_formula`] over the bit patterns of [0, 1].
pub(crate) struct Table {
    /// Step `k` starts at the first bit pattern whose value is at least `k` (k in 1..=255;
    /// step 0 at 0): the step's index is the value.
    steps: Steps,
}

impl Table {
    /// Built from `f`, a non-decreasing function of the bit patterns 0..=ONE.
    pub(crate) fn build(f: impl Fn(f32) -> u8) -> Table {
        let mut thresholds = vec![0u32; 256];
        for (k, t) in thresholds.iter_mut().enumerate().skip(1) {
            // the first b in [0, ONE + 1) with f(b) >= k (ONE + 1 when none)
            let (mut lo, mut hi) = (0u32, ONE + 1);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if usize::from(f(f32::from_bits(mid))) >= k {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            *t = lo;
        }
        Table {
            steps: Steps::new(thresholds),
        }
    }

    /// The value of the input `linear` (any f32).
    #[inline]
    pub(crate) fn get(&self, linear: f32) -> u8 {
        // -0.0 has the sign bit set and the value of +0.0
        let b = clamp01(linear).to_bits() & 0x7fff_ffff;
        self.steps.index(b) as u8
    }

    /// `thresholds[k]`: the first bit pattern whose value is at least `k` (k in 1..=255);
    /// `thresholds[0]` is 0 and `thresholds[256]` is past every input.
    #[cfg(test)]
    pub(crate) fn thresholds(&self) -> &[u32] {
        self.steps.starts()
    }

    #[cfg(test)]
    pub(crate) fn thresholds_mut(&mut self) -> &mut [u32] {
        self.steps.starts_mut()
    }
}

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Table::build(srgb8_formula))
}

/// sRGB transfer function of a linear value, clamped to [0, 1] (NaN and Inf become 0), as 8
/// bits: [`srgb8_formula`]'s value, read from its table of steps.
#[inline]
pub fn srgb8(linear: f32) -> u8 {
    table().get(linear)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first input (bits) where `t` and the formula disagree among `inputs`.
    fn first_mismatch(t: &Table, inputs: impl Iterator<Item = u32>) -> Option<u32> {
        inputs
            .into_iter()
            .find(|&b| t.get(f32::from_bits(b)) != srgb8_formula(f32::from_bits(b)))
    }

    /// Every step's first input and its neighbours, a stride over [0, 1], and the inputs the
    /// formula clamps.
    fn probes(t: &Table) -> Vec<u32> {
        let mut v: Vec<u32> = t.thresholds()[1..256]
            .iter()
            .flat_map(|&b| b.saturating_sub(3)..=(b + 3).min(ONE))
            .collect();
        v.extend((0..=ONE).step_by(1009));
        for x in [
            -0.0f32,
            -1.0,
            1.5,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE,
            0.003_130_8,
        ] {
            v.push(x.to_bits());
        }
        v
    }

    #[test]
    fn srgb8_table_equals_formula_at_every_step_and_on_a_stride() {
        let t = table();
        assert_eq!(first_mismatch(t, probes(t).into_iter()), None);
        // the steps are 255 distinct inputs in order, the last at or below 1.0
        let th = t.thresholds();
        assert!(th[1..256].windows(2).all(|w| w[0] < w[1]));
        assert!(th[255] <= ONE);
        assert_eq!(srgb8(0.5), 188);
        assert_eq!(srgb8(-0.0), 0);
        assert_eq!(srgb8(f32::NAN), 0);
        assert_eq!(srgb8(7.0), 255);
    }

    #[test]
    fn a_table_with_one_step_moved_by_one_input_is_caught() {
        let mut t = Table::build(srgb8_formula);
        t.thresholds_mut()[100] += 1;
        let at = probes(&t);
        assert!(first_mismatch(&t, at.into_iter()).is_some());
        let mut t = Table::build(srgb8_formula);
        t.thresholds_mut()[200] -= 1;
        let at = probes(&t);
        assert!(first_mismatch(&t, at.into_iter()).is_some());
    }

    /// Every f32 in [0, 1] (about 1.07e9 inputs; tens of seconds in release):
    /// `cargo test --release --locked srgb8_table_equals_formula_on_every_f32 -- --ignored`.
    #[test]
    #[ignore]
    fn srgb8_table_equals_formula_on_every_f32() {
        assert_eq!(first_mismatch(table(), 0..=ONE), None);
    }
}
