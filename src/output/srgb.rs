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
//! stride over the range (docs/history/performance-compare.md gives the run).
//!
//! The lookup reads the clamp off the bit pattern and, inside [0, 1], the steps without a scan
//! (`Direct`: exact because no bucket of 2^16 patterns holds two step starts, checked when
//! built); `get_equals_the_clamped_lookup_on_every_bit_pattern` (ignored) checks it against
//! clamp-then-scan on all 2^32 patterns. [`frame_rgb8`] converts a whole frame (issue 26).
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
    /// The value of 1.0, which every finite input above 1 takes.
    top: u8,
    /// The same steps read without a scan, when every bucket allows it.
    direct: Option<Direct>,
}

/// Buckets of 2^16 bit patterns (`bits >> 16`) over [0, 1].
const BUCKETS: usize = (ONE >> 16) as usize + 1;

/// The steps read without a scan: where each bucket of bit patterns holds at most one step
/// start past its first pattern (true of the sRGB steps: a step is wider than a bucket over
/// all of [0, 1]; [`Direct::new`] checks it), the value at a pattern is the value at its
/// bucket's first pattern, plus one from the next step's start on. One load, one compare,
/// no branch on the data. Its own table of one byte per bucket rather than a reading inside
/// `Steps` (whose bucket index is two bytes per bucket, for the colormaps' 1,284 regions): the
/// reading moved into `Steps` measured about 65 more perf samples of 8,600 in the all-methods
/// compare (review of issue 26), so it stays here.
struct Direct {
    /// Per bucket, the value at its first pattern.
    first: Box<[u8; BUCKETS]>,
    /// `starts[k]`: the first pattern whose value is at least `k` (k in 1..=255), then
    /// `u32::MAX` (past every pattern) at 256.
    starts: [u32; 257],
}

impl Direct {
    /// The direct reading of `starts` (thresholds as in [`Table::build`], `starts[0] = 0`),
    /// `None` when a bucket holds more than one start past its first pattern.
    fn new(thresholds: &[u32], steps: &Steps) -> Option<Direct> {
        let mut starts = [u32::MAX; 257];
        starts[..256].copy_from_slice(thresholds);
        let mut inside = vec![0u8; BUCKETS];
        for &s in &starts[1..256] {
            if s <= ONE && s & 0xffff != 0 {
                inside[(s >> 16) as usize] += 1;
            }
        }
        if inside.iter().any(|&n| n > 1) {
            return None;
        }
        let mut first = Box::new([0u8; BUCKETS]);
        for (k, v) in first.iter_mut().enumerate() {
            *v = steps.index((k as u32) << 16) as u8;
        }
        Some(Direct { first, starts })
    }

    /// The value at the bit pattern `b` (at most [`ONE`]).
    #[inline(always)]
    fn get(&self, b: u32) -> u8 {
        let v = self.first[(b >> 16) as usize];
        v + u8::from(b >= self.starts[usize::from(v) + 1])
    }
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
        Table::from_thresholds(thresholds)
    }

    /// The table of the steps starting at `thresholds` (256, the first at 0).
    fn from_thresholds(thresholds: Vec<u32>) -> Table {
        let steps = Steps::new(thresholds.clone());
        let top = steps.index(ONE) as u8;
        let direct = Direct::new(&thresholds, &steps);
        Table { steps, top, direct }
    }

    /// The value of the input `linear` (any f32): [`Table::get_clamped`]'s, with the clamp read
    /// off the bit pattern. The patterns `0..=ONE` are the f32 in [0, 1] (clamp keeps them);
    /// `ONE + 1 .. 0x7f80_0000` are the finite f32 above 1 (clamped to 1.0); `0x7f80_0000` is
    /// +Inf and the patterns above it NaN (both 0), the sign bit's patterns (negative
    /// numbers, -0.0, -Inf and NaN) all have the value of 0.
    // always: a call per channel was most of its cost in `frame_rgb8` (perf)
    #[inline(always)]
    pub(crate) fn get(&self, linear: f32) -> u8 {
        let b = linear.to_bits();
        if b <= ONE {
            match &self.direct {
                Some(d) => d.get(b),
                None => self.steps.index(b) as u8,
            }
        } else if b < 0x7f80_0000 {
            self.top
        } else {
            self.steps.index(0) as u8
        }
    }

    /// The value of the input `linear` (any f32) by its definition: clamped as the formula
    /// clamps it, then looked up (what [`Table::get`] was; kept as its check).
    #[cfg(test)]
    pub(crate) fn get_clamped(&self, linear: f32) -> u8 {
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

    /// The table of these thresholds with `thresholds[k]` moved by `delta` patterns (a wrong
    /// table, for the checks' teeth).
    #[cfg(test)]
    pub(crate) fn moved(&self, k: usize, delta: i32) -> Table {
        let mut thresholds = self.thresholds()[..256].to_vec();
        thresholds[k] = thresholds[k].wrapping_add_signed(delta);
        Table::from_thresholds(thresholds)
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

/// The 8-bit sRGB colour of linear RGB pixels, 3 bytes per pixel: [`srgb8`] of each channel,
/// with the table fetched once and the pixels collected from an iterator (one allocation for
/// one of known length, no capacity check or zero fill per byte).
pub fn rgb8(rgb: impl Iterator<Item = [f32; 3]>) -> Vec<u8> {
    let t = table();
    // the three lookups written out: `c.map(..)` was not inlined (perf)
    let rgb: Vec<[u8; 3]> = rgb
        .map(|c| [t.get(c[0]), t.get(c[1]), t.get(c[2])])
        .collect();
    rgb.into_flattened()
}

/// [`rgb8`] of a frame's linear RGBA pixels (alpha dropped).
pub fn frame_rgb8(color: &[[f32; 4]]) -> Vec<u8> {
    rgb8(color.iter().map(|p| [p[0], p[1], p[2]]))
}

/// The 8-bit RGBA bytes of a frame's linear RGBA pixels, the bytes `write_png_srgb` encodes:
/// [`srgb8`] of each colour channel and [`crate::output::alpha8`] of alpha, in one pass over
/// the frame (render.png's and, through [`rgb8_of_rgba8`], FLIP's test image: the frame's
/// 16 bytes per pixel are read once for both).
pub fn frame_rgba8(color: &[[f32; 4]]) -> Vec<u8> {
    let t = table();
    let rgba: Vec<[u8; 4]> = color
        .iter()
        .map(|p| {
            let a = crate::output::alpha8(p[3]);
            [t.get(p[0]), t.get(p[1]), t.get(p[2]), a]
        })
        .collect();
    rgba.into_flattened()
}

/// The RGB bytes of RGBA bytes, alpha dropped: [`frame_rgb8`] of a frame from its
/// [`frame_rgba8`].
pub fn rgb8_of_rgba8(rgba: &[u8]) -> Vec<u8> {
    let rgb: Vec<[u8; 3]> = rgba.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
    rgb.into_flattened()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first bit pattern among `inputs` where [`Table::get`] and [`Table::get_clamped`]
    /// disagree.
    fn first_get_mismatch(t: &Table, inputs: impl Iterator<Item = u32>) -> Option<u32> {
        inputs.into_iter().find(|&b| {
            let x = f32::from_bits(b);
            t.get(x) != t.get_clamped(x)
        })
    }

    /// Every bit pattern class `get` tells apart, with its neighbours (0, 1.0, +Inf, the NaN,
    /// -0, -Inf and the negative NaN), and a stride over all 2^32 patterns.
    fn all_probes() -> Vec<u32> {
        let edges = [
            0u32,
            ONE,
            0x7f80_0000,
            0x7fff_ffff,
            0x8000_0000,
            0xff80_0000,
            u32::MAX,
        ];
        let mut v: Vec<u32> = edges
            .iter()
            .flat_map(|&b| b.saturating_sub(3)..=b.saturating_add(3))
            .collect();
        v.extend((0..=u32::MAX).step_by(997));
        v
    }

    #[test]
    fn get_equals_the_clamped_lookup_on_every_class_and_a_stride() {
        let t = table();
        // the sRGB steps are read directly (this test checks that reading)
        assert!(t.direct.is_some());
        let mut at = all_probes();
        at.extend(probes(t));
        assert_eq!(first_get_mismatch(t, at.iter().copied()), None);
        // teeth: a direct reading with one bucket's first value off by one is caught
        let mut wrong = Table::build(srgb8_formula);
        let d = wrong.direct.as_mut().unwrap();
        let k = (t.thresholds()[150] >> 16) as usize;
        d.first[k] -= 1;
        assert!(first_get_mismatch(&wrong, at.iter().copied()).is_some());
        // a bucket holding two step starts is not read directly
        let mut two = vec![ONE + 1; 256];
        (two[1], two[2]) = (0x3e00_0001, 0x3e00_0002);
        two[0] = 0;
        assert!(Direct::new(&two, &Steps::new(two.clone())).is_none());
        two[2] = 0x3e01_0002;
        assert!(Direct::new(&two, &Steps::new(two.clone())).is_some());
        // teeth: a table whose value above 1 is wrong is caught
        let mut wrong = Table::build(srgb8_formula);
        wrong.top -= 1;
        assert!(first_get_mismatch(&wrong, all_probes().into_iter()).is_some());
    }

    /// Every bit pattern (about 4.3e9; seconds in release):
    /// `cargo test --release --locked get_equals_the_clamped_lookup_on_every_bit_pattern -- --ignored`.
    #[test]
    #[ignore]
    fn get_equals_the_clamped_lookup_on_every_bit_pattern() {
        assert_eq!(first_get_mismatch(table(), 0..=u32::MAX), None);
    }

    /// `frame_rgb8` is the formula per channel, alpha dropped, on values of every class, and
    /// `frame_rgba8` the same with `alpha8` of alpha; teeth: a frame with one channel (or one
    /// alpha) changed gives other bytes.
    #[test]
    fn frame_rgb8_is_the_formula_per_channel() {
        let specials = [
            0.0f32,
            -0.0,
            1.0,
            1.5,
            -2.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.003_130_8,
            0.5,
        ];
        let color: Vec<[f32; 4]> = (0..4000u32)
            .map(|i| {
                let x = i as f32 / 3999.0;
                let s = specials[i as usize % specials.len()];
                [x, s, x * x, [0.0, 1.0, f32::NAN][i as usize % 3]]
            })
            .collect();
        let want: Vec<u8> = color
            .iter()
            .flat_map(|p| [p[0], p[1], p[2]].map(srgb8_formula))
            .collect();
        assert!(frame_rgb8(&color) == want);
        let mut other = color.clone();
        other[77][2] = 0.25;
        assert!(frame_rgb8(&other) != want);
        // the RGBA bytes: the same colour with alpha8 of alpha, and their RGB is frame_rgb8's
        let want_rgba: Vec<u8> = color
            .iter()
            .flat_map(|p| {
                let [r, g, b] = [p[0], p[1], p[2]].map(srgb8_formula);
                [r, g, b, crate::output::alpha8(p[3])]
            })
            .collect();
        let rgba = frame_rgba8(&color);
        assert!(rgba == want_rgba);
        assert!(rgb8_of_rgba8(&rgba) == want);
        // teeth: one channel, or one alpha, changed
        assert!(frame_rgba8(&other) != want_rgba);
        assert!(rgb8_of_rgba8(&frame_rgba8(&other)) != want);
        other[77][2] = color[77][2];
        other[78][3] = 0.5;
        assert!(frame_rgba8(&other) != want_rgba);
    }

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
        let t = table().moved(100, 1);
        let at = probes(&t);
        assert!(first_mismatch(&t, at.into_iter()).is_some());
        let t = table().moved(200, -1);
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
