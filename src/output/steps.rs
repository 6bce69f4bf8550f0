//! A step function of the f32 in [0, 1], by bit pattern: the sorted bit patterns where each
//! step starts, with a bucket index so that a lookup scans only the few steps that start
//! inside one bucket. The lookup shared by [`crate::output::srgb8`]'s table (src/output/srgb.rs)
//! and the heatmap colormaps' colour regions (src/output/colormap.rs).

/// The bit pattern of 1.0f32: the f32 in [0, 1] are the bit patterns `0..=ONE`.
pub(crate) const ONE: u32 = 0x3f80_0000;
/// The buckets are the bit patterns with the same `bits >> BUCKET_SHIFT`: 0x3f81 buckets over
/// [0, 1], 1/256 of an octave each.
const BUCKET_SHIFT: u32 = 16;

/// The steps: per step its first bit pattern, and per bucket the step of its first pattern.
pub(crate) struct Steps {
    /// The first bit pattern of each step, non-decreasing from 0, then `u32::MAX` as a sentinel.
    starts: Vec<u32>,
    /// Per bucket, the step of its first bit pattern.
    first: Vec<u16>,
}

impl Steps {
    /// The steps starting at `starts` (non-decreasing, the first at 0; a step no pattern
    /// reaches starts where the next one does; at most `u16::MAX` steps).
    pub(crate) fn new(mut starts: Vec<u32>) -> Steps {
        assert!(starts.first() == Some(&0), "no step at 0");
        assert!(starts.windows(2).all(|w| w[0] <= w[1]), "unsorted");
        assert!(starts.len() <= u16::MAX as usize, "too many steps");
        let first = (0..=ONE >> BUCKET_SHIFT)
            .map(|k| (starts.partition_point(|&s| s <= k << BUCKET_SHIFT) - 1) as u16)
            .collect();
        starts.push(u32::MAX);
        Steps { starts, first }
    }

    /// The step of the bit pattern `bits` (at most [`ONE`]): the last one starting at or
    /// before it.
    #[inline]
    pub(crate) fn index(&self, bits: u32) -> usize {
        let mut i = usize::from(self.first[(bits >> BUCKET_SHIFT) as usize]);
        // at most a few steps: a bucket spans few of them
        while self.starts[i + 1] <= bits {
            i += 1;
        }
        i
    }

    /// The steps' first bit patterns, then the sentinel `u32::MAX`.
    #[cfg(test)]
    pub(crate) fn starts(&self) -> &[u32] {
        &self.starts
    }
}
