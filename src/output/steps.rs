//! A step function of the f32 in [0, 1], by bit pattern: the sorted bit patterns where each
//! step starts, with a bucket index so that a lookup scans only the few steps that start
//! inside one bucket. The lookup shared by [`crate::output::srgb8`]'s table (src/output/srgb.rs)
//! and the heatmap colormaps' colour regions (src/output/colormap.rs).

/// The bit pattern of 1.0f32: the f32 in [0, 1] are the bit patterns `0..=ONE`.
pub(crate) const ONE: u32 = 0x3f80_0000;
/// The default buckets: the bit patterns with the same `bits >> BUCKET_SHIFT`, 0x3f81 buckets
/// over [0, 1], 1/128 of an octave each.
const BUCKET_SHIFT: u32 = 16;

/// The steps: per step its first bit pattern, and per bucket the step of its first pattern.
pub(crate) struct Steps {
    /// The first bit pattern of each step, non-decreasing from 0, then `u32::MAX` as a sentinel.
    starts: Vec<u32>,
    /// Per bucket, the step of its first bit pattern.
    first: Vec<u16>,
    /// A bucket is the bit patterns with the same `bits >> shift`.
    shift: u32,
}

impl Steps {
    /// The steps starting at `starts` (non-decreasing, the first at 0; a step no pattern
    /// reaches starts where the next one does; at most `u16::MAX` steps), in the default
    /// buckets.
    pub(crate) fn new(starts: Vec<u32>) -> Steps {
        Steps::with_shift(starts, BUCKET_SHIFT)
    }

    /// [`Steps::new`] with buckets of `2^shift` bit patterns: finer buckets (a smaller shift)
    /// hold fewer steps each, so a lookup scans fewer, for a larger index (`(ONE >> shift) + 1`
    /// entries of 2 bytes). The step found is the same at any shift.
    pub(crate) fn with_shift(mut starts: Vec<u32>, shift: u32) -> Steps {
        assert!(starts.first() == Some(&0), "no step at 0");
        assert!(starts.windows(2).all(|w| w[0] <= w[1]), "unsorted");
        assert!(starts.len() <= u16::MAX as usize, "too many steps");
        assert!(shift < 32, "a shift of {shift} bits");
        let first = (0..=ONE >> shift)
            .map(|k| (starts.partition_point(|&s| s <= k << shift) - 1) as u16)
            .collect();
        starts.push(u32::MAX);
        Steps {
            starts,
            first,
            shift,
        }
    }

    /// The step of the bit pattern `bits` (at most [`ONE`]): the last one starting at or
    /// before it.
    #[inline]
    pub(crate) fn index(&self, bits: u32) -> usize {
        let mut i = usize::from(self.first[(bits >> self.shift) as usize]);
        // at most a few steps: a bucket spans few of them
        while self.starts[i + 1] <= bits {
            i += 1;
        }
        i
    }

    /// Step `i`'s first bit pattern and the next step's (`u32::MAX` after the last step).
    #[inline]
    pub(crate) fn bounds(&self, i: usize) -> (u32, u32) {
        (self.starts[i], self.starts[i + 1])
    }

    /// The steps' first bit patterns, then the sentinel `u32::MAX`.
    #[cfg(test)]
    pub(crate) fn starts(&self) -> &[u32] {
        &self.starts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step of `bits` by definition: the last start at or before it.
    fn by_definition(starts: &[u32], bits: u32) -> usize {
        starts.partition_point(|&s| s <= bits) - 1
    }

    #[test]
    fn index_is_the_last_start_at_or_before_the_pattern_at_any_shift() {
        let mut rng = fastrand::Rng::with_seed(26);
        // clustered starts (several in one default bucket, repeated ones), like the colormaps'
        let mut starts = vec![0u32];
        for _ in 0..600 {
            let base = rng.u32(0..=ONE);
            for k in 0..rng.u32(1..6) {
                starts.push((base + k * rng.u32(0..3000)).min(ONE));
            }
        }
        starts.sort_unstable();
        let mut probes: Vec<u32> = starts
            .iter()
            .flat_map(|&s| [s.saturating_sub(1), s, (s + 1).min(ONE)])
            .collect();
        probes.extend((0..20_000).map(|_| rng.u32(0..=ONE)));
        probes.extend([0, ONE]);
        for shift in [8, 12, 16, 20] {
            let steps = Steps::with_shift(starts.clone(), shift);
            for &b in &probes {
                assert_eq!(
                    steps.index(b),
                    by_definition(&starts, b),
                    "shift {shift}, {b:#x}"
                );
            }
        }
        // Teeth: a bucket index one step too far (the scan only goes forward) finds other steps.
        let mut wrong = Steps::with_shift(starts.clone(), 12);
        let last = wrong.starts.len() - 2;
        for f in wrong.first.iter_mut() {
            *f = (usize::from(*f) + 1).min(last) as u16;
        }
        assert!(probes
            .iter()
            .any(|&b| wrong.index(b) != by_definition(&starts, b)));
    }
}
