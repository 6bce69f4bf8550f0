//! The heatmaps' two colormaps, matplotlib's magma and ColorBrewer's RdBu, as exact twins of
//! `colorous` 1.0's `MAGMA` and `RED_BLUE` that do a fraction of their work (issue 26: the
//! spline was 7.9 % of `compare`'s CPU).
//!
//! `colorous::Gradient::eval_continuous(t)` clamps `t` to [0, 1], converts it to f32 and
//! evaluates a uniform cubic B-spline through the gradient's control colours
//! (`colorous::interpolate::spline`: 256 colours for magma, the 11 of `eleven` for RdBu), one
//! channel at a time through a function pointer, re-reading the control colours and
//! recomputing the segment and its weights per channel. [`Colormap::rgb`] runs the same f32
//! operations in the same order on the same values, once per pixel instead of once per channel:
//! - the segment `floor(t * n) as usize`, capped at `n - 1`, is `(t * n) as usize`: a cast
//!   truncates, equal to floor for non-negative values, and both saturate to 0 for negative and
//!   NaN inputs, so the two agree on every f32;
//! - the segment's four control values per channel (with colorous's mirrored ends
//!   `2 v1 - v2`, `2 v2 - v1`) and its knot `i as f32 / n as f32` are computed once, by the same
//!   expressions, when the table is built;
//! - the weights `1 - 3t + 3t² - t³`, `4 - 6t² + 3t³`, `1 + 3t + 3t² - 3t³`, `t³` are the same
//!   left-to-right sums for every channel, then `(w0 v0 + w1 v1 + w2 v2 + w3 v3) / 6` and the
//!   saturating `as u8`. Rust does not contract `a * b + c` into a fused multiply-add.
//!
//! [`Colormap::rgb`] itself does less still: over [0, 1] it looks the colour up in [`Changes`],
//! regions of constant colour generated from this spline by an exhaustive scan of the f32
//! (table26), and only evaluates the spline in the regions where the colour flickers and
//! outside [0, 1].
//!
//! Checked against colorous itself: the suite on a stride of the f32 in [0, 1], every segment
//! boundary and its neighbours, NaN and the clamped ends; `every_f32_in_0_1_matches_colorous`
//! (ignored; scripts/heatmap_colors_exhaustive.sh runs it) on every f32 in [0, 1], through the
//! region lookup; the regions against the spline by the suite. The control
//! colours below are colorous 1.0.16's (src/sequential_multi.rs `MAGMA`, src/diverging.rs
//! `RED_BLUE.eleven`; Apache-2.0), which the checks confirm.
use std::sync::OnceLock;

use crate::output::steps::{Steps, ONE};

/// A colormap of the heatmaps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colormap {
    /// matplotlib's magma (colorous `MAGMA`), for magnitudes.
    Magma,
    /// ColorBrewer's RdBu, red to blue (colorous `RED_BLUE`), for signed values.
    RedBlue,
}

impl Colormap {
    /// The colour at `t`, exactly `colorous`'s `eval_continuous(t as f64)` for every f32 `t`
    /// in [0, 1] (NaN gives colorous's colour of NaN, the bottom of the first segment's cubic
    /// evaluated at NaN: [0, 0, 0]).
    #[inline]
    pub fn rgb(self, t: f32) -> [u8; 3] {
        self.changes().rgb(t)
    }

    /// The colorous gradient this colormap reproduces.
    pub fn colorous(self) -> colorous::Gradient {
        match self {
            Colormap::Magma => colorous::MAGMA,
            Colormap::RedBlue => colorous::RED_BLUE,
        }
    }

    /// The spline's segments (the reference, and the colour outside [0, 1]), built on first
    /// use.
    pub(crate) fn table(self) -> &'static Table {
        static MAGMA_TABLE: OnceLock<Table> = OnceLock::new();
        static RED_BLUE_TABLE: OnceLock<Table> = OnceLock::new();
        match self {
            Colormap::Magma => MAGMA_TABLE.get_or_init(|| Table::new(&MAGMA)),
            Colormap::RedBlue => RED_BLUE_TABLE.get_or_init(|| Table::new(&RED_BLUE)),
        }
    }

    /// The colour's change points over [0, 1] (generated, see [`Changes`]), indexed on first
    /// use.
    pub(crate) fn changes(self) -> &'static Changes {
        static MAGMA_CHANGES: OnceLock<Changes> = OnceLock::new();
        static RED_BLUE_CHANGES: OnceLock<Changes> = OnceLock::new();
        match self {
            Colormap::Magma => {
                MAGMA_CHANGES.get_or_init(|| Changes::new(&changes::MAGMA, Colormap::Magma.table()))
            }
            Colormap::RedBlue => RED_BLUE_CHANGES
                .get_or_init(|| Changes::new(&changes::RED_BLUE, Colormap::RedBlue.table())),
        }
    }
}

/// The generated change points (scripts/colormap_changes.sh writes them).
#[path = "colormap_changes.rs"]
mod changes;

/// The buckets of [`Changes`]' region lookup: 2^12 bit patterns each (2048 per octave, an index
/// of 520 KB per colormap). Regions are at least 512 patterns long, so a bucket holds at most 8
/// region starts, and most none: the lookup's forward scan rarely runs (with the default 2^16,
/// RdBu's regions near t = 0.5 made it scan a few steps per pixel, its exit unpredictable).
const REGION_SHIFT: u32 = 12;

/// The colour of a region that [`Changes`] leaves to the spline, in the generated tables.
pub(crate) const SPLINE: u32 = u32::MAX;

/// The colour of the spline as a function of the f32 `t` in [0, 1], which is piecewise
/// constant, as regions of bit patterns: a run of at least 512 patterns of one colour is a
/// region of that colour, what lies between such runs a region left to the spline ([`SPLINE`]:
/// f32 rounding makes a channel flicker between two values from one bit pattern to the next
/// where the spline is near an integer, as magma's red is for t above about 0.8; magma has
/// 2.6 million pieces, RdBu 1438). Stored: the sorted bit patterns where a region starts, each
/// region's colour, and per bucket of bit patterns the region its first pattern lies in. A
/// lookup goes to its bucket's region and scans forward over the few regions that start inside
/// the bucket. The regions are generated by an exhaustive scan of every f32 in [0, 1] with
/// [`Table::rgb`] (scripts/colormap_changes.sh), so the lookup is the spline on every one of
/// them; outside [0, 1] (negative, -0, NaN, > 1) it is the spline itself.
pub(crate) struct Changes {
    /// The regions, by their first bit patterns.
    regions: Steps,
    /// Each region's colour, `None` where it is the spline's.
    colors: Vec<Option<[u8; 3]>>,
    spline: &'static Table,
}

impl Changes {
    /// The lookup over `points` ((first bit pattern, colour 0xRRGGBB or [`SPLINE`]) of each
    /// region, sorted, the first at 0), with `spline` outside [0, 1] and in [`SPLINE`] regions.
    pub(crate) fn new(points: &[(u32, u32)], spline: &'static Table) -> Changes {
        assert!(points.windows(2).all(|w| w[0].0 < w[1].0), "unsorted");
        let colors = points
            .iter()
            .map(|&(_, c)| (c != SPLINE).then_some([(c >> 16) as u8, (c >> 8) as u8, c as u8]))
            .collect();
        Changes {
            regions: Steps::with_shift(points.iter().map(|p| p.0).collect(), REGION_SHIFT),
            colors,
            spline,
        }
    }

    /// The colour at `t`: [`Table::rgb`]'s on every f32.
    #[inline]
    pub(crate) fn rgb(&self, t: f32) -> [u8; 3] {
        let bits = t.to_bits();
        if bits > ONE {
            return self.spline.rgb(t);
        }
        let i = self.regions.index(bits);
        match self.colors[i] {
            Some(c) => c,
            None => self.spline.rgb(t),
        }
    }

    /// The spline's colour at `t`: [`Changes::rgb`]'s in a region without a colour of its own
    /// and outside [0, 1].
    #[inline]
    pub(crate) fn spline_rgb(&self, t: f32) -> [u8; 3] {
        self.spline.rgb(t)
    }

    /// The region of the bit pattern `bits` (at most [`ONE`]): its first pattern, the pattern
    /// past its end (at most `ONE + 1`: only f32 in [0, 1]), and its colour, `None` where the
    /// spline computes it. Every pattern of a region with a colour has that colour, so a
    /// caller may keep the region and reuse the colour for the patterns inside it.
    #[inline]
    pub(crate) fn region(&self, bits: u32) -> (u32, u32, Option<[u8; 3]>) {
        let i = self.regions.index(bits);
        let (start, end) = self.regions.bounds(i);
        (start, end.min(ONE + 1), self.colors[i])
    }
}

/// One spline segment: its knot `i / n` and its four control values per channel, `v[k][c]`
/// (c = r, g, b and a zero lane, so that the four channels are one vector operation).
#[derive(Clone, Copy)]
struct Segment {
    knot: f32,
    v: [[f32; 4]; 4],
}

/// The segments of a B-spline through `n + 1` control colours.
pub(crate) struct Table {
    n: f32,
    segments: Vec<Segment>,
}

impl Table {
    /// The segments of colorous's spline through `colors` (0xRRGGBB, at least 2).
    pub(crate) fn new(colors: &[u32]) -> Table {
        let n = colors.len() - 1;
        let channel = |i: usize, c: usize| ((colors[i] >> (16 - 8 * c)) & 0xff) as u8 as f32;
        let segments = (0..n)
            .map(|i| {
                // colorous `interpolate::basis`, with the same mirrored ends
                let controls = |c: usize| {
                    let v1 = channel(i, c);
                    let v2 = channel(i + 1, c);
                    let v0 = if i > 0 {
                        channel(i - 1, c)
                    } else {
                        2.0 * v1 - v2
                    };
                    let v3 = if i < n - 1 {
                        channel(i + 2, c)
                    } else {
                        2.0 * v2 - v1
                    };
                    [v0, v1, v2, v3]
                };
                let rgb = [controls(0), controls(1), controls(2)];
                let v = [0, 1, 2, 3].map(|k| [rgb[0][k], rgb[1][k], rgb[2][k], 0.0]);
                Segment {
                    knot: i as f32 / n as f32,
                    v,
                }
            })
            .collect();
        Table {
            n: n as f32,
            segments,
        }
    }

    /// The segment colorous picks for `t`: `floor(t * n) as usize` capped at `n - 1` (see the
    /// module doc for why the truncating cast is the same on every f32).
    #[inline]
    pub(crate) fn segment_of(&self, t: f32) -> usize {
        ((t * self.n) as usize).min(self.segments.len() - 1)
    }

    #[inline]
    pub(crate) fn rgb(&self, t: f32) -> [u8; 3] {
        self.rgb_in(self.segment_of(t), t)
    }

    /// The colour at `t` evaluated on segment `i`.
    #[inline]
    pub(crate) fn rgb_in(&self, i: usize, t: f32) -> [u8; 3] {
        let s = &self.segments[i];
        let t1 = (t - s.knot) * self.n;
        let t2 = t1 * t1;
        let t3 = t2 * t1;
        let w = [
            1.0 - 3.0 * t1 + 3.0 * t2 - t3,
            4.0 - 6.0 * t2 + 3.0 * t3,
            1.0 + 3.0 * t1 + 3.0 * t2 - 3.0 * t3,
            t3,
        ];
        let mut out = [0f32; 4];
        for (c, o) in out.iter_mut().enumerate() {
            *o = (w[0] * s.v[0][c] + w[1] * s.v[1][c] + w[2] * s.v[2][c] + w[3] * s.v[3][c]) / 6.0;
        }
        [out[0] as u8, out[1] as u8, out[2] as u8]
    }
}

/// colorous 1.0.16 `MAGMA` (src/sequential_multi.rs): 256 control colours.
#[rustfmt::skip]
pub(crate) const MAGMA: [u32; 256] = [
    0x000004, 0x010005, 0x010106, 0x010108, 0x020109, 0x02020b, 0x02020d, 0x03030f,
    0x030312, 0x040414, 0x050416, 0x060518, 0x06051a, 0x07061c, 0x08071e, 0x090720,
    0x0a0822, 0x0b0924, 0x0c0926, 0x0d0a29, 0x0e0b2b, 0x100b2d, 0x110c2f, 0x120d31,
    0x130d34, 0x140e36, 0x150e38, 0x160f3b, 0x180f3d, 0x19103f, 0x1a1042, 0x1c1044,
    0x1d1147, 0x1e1149, 0x20114b, 0x21114e, 0x221150, 0x241253, 0x251255, 0x271258,
    0x29115a, 0x2a115c, 0x2c115f, 0x2d1161, 0x2f1163, 0x311165, 0x331067, 0x341069,
    0x36106b, 0x38106c, 0x390f6e, 0x3b0f70, 0x3d0f71, 0x3f0f72, 0x400f74, 0x420f75,
    0x440f76, 0x451077, 0x471078, 0x491078, 0x4a1079, 0x4c117a, 0x4e117b, 0x4f127b,
    0x51127c, 0x52137c, 0x54137d, 0x56147d, 0x57157e, 0x59157e, 0x5a167e, 0x5c167f,
    0x5d177f, 0x5f187f, 0x601880, 0x621980, 0x641a80, 0x651a80, 0x671b80, 0x681c81,
    0x6a1c81, 0x6b1d81, 0x6d1d81, 0x6e1e81, 0x701f81, 0x721f81, 0x732081, 0x752181,
    0x762181, 0x782281, 0x792282, 0x7b2382, 0x7c2382, 0x7e2482, 0x802582, 0x812581,
    0x832681, 0x842681, 0x862781, 0x882781, 0x892881, 0x8b2981, 0x8c2981, 0x8e2a81,
    0x902a81, 0x912b81, 0x932b80, 0x942c80, 0x962c80, 0x982d80, 0x992d80, 0x9b2e7f,
    0x9c2e7f, 0x9e2f7f, 0xa02f7f, 0xa1307e, 0xa3307e, 0xa5317e, 0xa6317d, 0xa8327d,
    0xaa337d, 0xab337c, 0xad347c, 0xae347b, 0xb0357b, 0xb2357b, 0xb3367a, 0xb5367a,
    0xb73779, 0xb83779, 0xba3878, 0xbc3978, 0xbd3977, 0xbf3a77, 0xc03a76, 0xc23b75,
    0xc43c75, 0xc53c74, 0xc73d73, 0xc83e73, 0xca3e72, 0xcc3f71, 0xcd4071, 0xcf4070,
    0xd0416f, 0xd2426f, 0xd3436e, 0xd5446d, 0xd6456c, 0xd8456c, 0xd9466b, 0xdb476a,
    0xdc4869, 0xde4968, 0xdf4a68, 0xe04c67, 0xe24d66, 0xe34e65, 0xe44f64, 0xe55064,
    0xe75263, 0xe85362, 0xe95462, 0xea5661, 0xeb5760, 0xec5860, 0xed5a5f, 0xee5b5e,
    0xef5d5e, 0xf05f5e, 0xf1605d, 0xf2625d, 0xf2645c, 0xf3655c, 0xf4675c, 0xf4695c,
    0xf56b5c, 0xf66c5c, 0xf66e5c, 0xf7705c, 0xf7725c, 0xf8745c, 0xf8765c, 0xf9785d,
    0xf9795d, 0xf97b5d, 0xfa7d5e, 0xfa7f5e, 0xfa815f, 0xfb835f, 0xfb8560, 0xfb8761,
    0xfc8961, 0xfc8a62, 0xfc8c63, 0xfc8e64, 0xfc9065, 0xfd9266, 0xfd9467, 0xfd9668,
    0xfd9869, 0xfd9a6a, 0xfd9b6b, 0xfe9d6c, 0xfe9f6d, 0xfea16e, 0xfea36f, 0xfea571,
    0xfea772, 0xfea973, 0xfeaa74, 0xfeac76, 0xfeae77, 0xfeb078, 0xfeb27a, 0xfeb47b,
    0xfeb67c, 0xfeb77e, 0xfeb97f, 0xfebb81, 0xfebd82, 0xfebf84, 0xfec185, 0xfec287,
    0xfec488, 0xfec68a, 0xfec88c, 0xfeca8d, 0xfecc8f, 0xfecd90, 0xfecf92, 0xfed194,
    0xfed395, 0xfed597, 0xfed799, 0xfed89a, 0xfdda9c, 0xfddc9e, 0xfddea0, 0xfde0a1,
    0xfde2a3, 0xfde3a5, 0xfde5a7, 0xfde7a9, 0xfde9aa, 0xfdebac, 0xfcecae, 0xfceeb0,
    0xfcf0b2, 0xfcf2b4, 0xfcf4b6, 0xfcf6b8, 0xfcf7b9, 0xfcf9bb, 0xfcfbbd, 0xfcfdbf,
];

/// colorous 1.0.16 `RED_BLUE.eleven` (src/diverging.rs), the colours its spline runs through.
#[rustfmt::skip]
pub(crate) const RED_BLUE: [u32; 11] = [
    0x67001f, 0xb2182b, 0xd6604d, 0xf4a582, 0xfddbc7, 0xf7f7f7, 0xd1e5f0, 0x92c5de, 0x4393c3,
    0x2166ac, 0x053061,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The suite's stride over those bit patterns (a prime, so every segment and every low
    /// mantissa pattern is visited; about 2.1 million inputs per colormap).
    const STRIDE: u32 = 509;

    type Candidate<'a> = &'a (dyn Fn(f32) -> [u8; 3] + Sync);

    /// The first input (of `bits`, as f32) where `candidate` differs from colorous's
    /// `gradient`, with both colours; `None` when they agree on all of them.
    fn first_mismatch(
        candidate: Candidate,
        gradient: colorous::Gradient,
        bits: impl Iterator<Item = u32>,
    ) -> Option<(f32, [u8; 3], [u8; 3])> {
        bits.map(f32::from_bits).find_map(|t| {
            let c = gradient.eval_continuous(t as f64);
            let want = [c.r, c.g, c.b];
            let got = candidate(t);
            (got != want).then_some((t, got, want))
        })
    }

    /// [`first_mismatch`] over `0..=ONE` with `stride`, split over the machine's threads.
    fn sweep(
        candidate: Candidate,
        gradient: colorous::Gradient,
        stride: u32,
    ) -> Option<(f32, [u8; 3], [u8; 3])> {
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u32;
        let steps = ONE / stride + 1;
        let per = steps.div_ceil(threads);
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..threads)
                .map(|k| {
                    let (a, b) = (k * per, ((k + 1) * per).min(steps));
                    s.spawn(move || first_mismatch(candidate, gradient, (a..b).map(|j| j * stride)))
                })
                .collect();
            handles.into_iter().find_map(|h| h.join().unwrap())
        })
    }

    /// Every place where the segment changes, and its neighbours: each knot `i / n` and the
    /// first f32 whose `t * n` reaches `i` (found by bisection: `t * n` is non-decreasing in
    /// t), each +- 16 bit patterns, clipped to [0, 1].
    fn boundaries(colors: &[u32]) -> Vec<u32> {
        let n = colors.len() - 1;
        let mut out = Vec::new();
        for i in 0..=n {
            let knot = (i as f32 / n as f32).to_bits();
            let (mut lo, mut hi) = (0u32, ONE + 1);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if ((f32::from_bits(mid) * n as f32) as usize) < i {
                    lo = mid + 1;
                } else {
                    hi = mid;
                }
            }
            for b in [knot, lo] {
                out.extend(b.saturating_sub(16)..=(b + 16).min(ONE));
            }
        }
        out
    }

    fn both() -> [(Colormap, &'static [u32]); 2] {
        [(Colormap::Magma, &MAGMA), (Colormap::RedBlue, &RED_BLUE)]
    }

    #[test]
    fn equals_colorous_on_a_stride_of_0_1() {
        for (map, _) in both() {
            let got = sweep(&|t| map.rgb(t), map.colorous(), STRIDE);
            assert_eq!(got, None, "{map:?}: (t, ours, colorous)");
        }
    }

    #[test]
    fn equals_colorous_at_every_segment_boundary() {
        for (map, colors) in both() {
            let bits = boundaries(colors);
            assert!(bits.len() > 60 * colors.len(), "{}", bits.len());
            let got = first_mismatch(&|t| map.rgb(t), map.colorous(), bits.into_iter());
            assert_eq!(got, None, "{map:?}: (t, ours, colorous)");
        }
    }

    #[test]
    fn equals_colorous_at_the_ends_and_on_nan() {
        for (map, _) in both() {
            for t in [
                0.0f32,
                -0.0,
                1.0,
                f32::NAN,
                f32::MIN_POSITIVE,
                1e-45,
                0.999_999_94,
            ] {
                let c = map.colorous().eval_continuous(t as f64);
                assert_eq!(map.rgb(t), [c.r, c.g, c.b], "{map:?} at {t}");
            }
        }
        // NaN lands on the first segment and its cubic is NaN: black, as in colorous.
        assert_eq!(Colormap::Magma.rgb(f32::NAN), [0, 0, 0]);
    }

    /// Teeth: the same sweeps find a wrong control colour and a rounded segment index.
    #[test]
    fn the_checks_fail_on_a_wrong_colormap() {
        let mut wrong = MAGMA;
        wrong[100] ^= 0x00_10_00; // one control colour's green off by 16
        let table = Table::new(&wrong);
        assert!(sweep(&|t| table.rgb(t), colorous::MAGMA, STRIDE).is_some());
        let bits = boundaries(&MAGMA).into_iter();
        assert!(first_mismatch(&|t| table.rgb(t), colorous::MAGMA, bits).is_some());

        for (map, colors) in both() {
            let table = Table::new(colors);
            let n = (colors.len() - 1) as f32;
            let rounded =
                |t: f32| table.rgb_in(((t * n).round() as usize).min(colors.len() - 2), t);
            assert!(
                sweep(&rounded, map.colorous(), STRIDE).is_some(),
                "{map:?}: round instead of floor went unnoticed"
            );
        }
        // and the other colormap's colours are not this one's
        let table = Table::new(&RED_BLUE);
        assert!(sweep(&|t| table.rgb(t), colorous::MAGMA, STRIDE).is_some());
    }

    /// The pieces of `spline`'s colour over the bit patterns `0..=ONE`, as [`Changes::new`]
    /// takes them: every bit pattern whose colour differs from the previous one's (and 0),
    /// with its colour 0xRRGGBB. Scans every pattern, split over the machine's threads.
    fn scan_changes(spline: &Table) -> Vec<(u32, u32)> {
        let threads = std::thread::available_parallelism().map_or(2, |n| n.get()) as u32;
        let per = (ONE + 1).div_ceil(threads);
        let rgb = |b: u32| {
            let [r, g, b] = spline.rgb(f32::from_bits(b));
            (r as u32) << 16 | (g as u32) << 8 | b as u32
        };
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..threads)
                .map(|k| {
                    let (a, b) = (k * per, ((k + 1) * per).min(ONE + 1));
                    s.spawn(move || {
                        let mut last = if a == 0 { u32::MAX } else { rgb(a - 1) };
                        let mut out = Vec::new();
                        for bits in a..b {
                            let c = rgb(bits);
                            if c != last {
                                out.push((bits, c));
                                last = c;
                            }
                        }
                        out
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().unwrap())
                .collect()
        })
    }

    /// The regions of [`Changes`] over `pieces` (as [`scan_changes`] gives them): each piece of
    /// at least `min_run` bit patterns is a region of its colour, the pieces between them one
    /// [`SPLINE`] region.
    fn regions(pieces: &[(u32, u32)], min_run: u32) -> Vec<(u32, u32)> {
        let ends = pieces.iter().skip(1).map(|p| p.0).chain([ONE + 1]);
        let mut out: Vec<(u32, u32)> = Vec::new();
        for (&(start, color), end) in pieces.iter().zip(ends) {
            let color = if end - start >= min_run {
                color
            } else {
                SPLINE
            };
            if out.last().is_none_or(|r| r.1 != SPLINE || color != SPLINE) {
                out.push((start, color));
            }
        }
        out
    }

    /// The generated source of src/output/colormap_changes.rs for these regions.
    fn changes_source(maps: &[(&str, Vec<(u32, u32)>)]) -> String {
        let mut out = String::from(
            "//! The heatmap colormaps' colour regions over [0, 1] (see `Changes` in\n\
             //! src/output/colormap.rs): per colormap, (the first f32 bit pattern of a region,\n\
             //! its colour 0xRRGGBB, or 0xffffffff where the spline computes it), sorted; a\n\
             //! region ends where the next starts.\n\
             // @generated by scripts/colormap_changes.sh; do not edit\n",
        );
        for (name, points) in maps {
            out += &format!(
                "\n#[rustfmt::skip]\npub(crate) const {name}: [(u32, u32); {}] = [\n",
                points.len()
            );
            for line in points.chunks(4) {
                out += "   ";
                for (b, c) in line {
                    out += &format!(" (0x{b:08x}, 0x{c:06x}),");
                }
                out += "\n";
            }
            out += "];\n";
        }
        out
    }

    /// Writes src/output/colormap_changes.rs from an exhaustive scan of the spline:
    /// scripts/colormap_changes.sh runs `write_colormap_changes -- --ignored`.
    #[test]
    #[ignore]
    fn write_colormap_changes() {
        let maps: Vec<_> = [("MAGMA", Colormap::Magma), ("RED_BLUE", Colormap::RedBlue)]
            .into_iter()
            .map(|(name, map)| {
                let pieces = scan_changes(map.table());
                let points = regions(&pieces, 512);
                let spline = points.iter().filter(|p| p.1 == SPLINE).count();
                eprintln!(
                    "{name}: {} pieces, {} regions ({spline} left to the spline)",
                    pieces.len(),
                    points.len()
                );
                (name, points)
            })
            .collect();
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/src/output/colormap_changes.rs"
        );
        std::fs::write(path, changes_source(&maps)).unwrap();
        eprintln!("wrote {path}");
    }

    /// The first of `bits` where `changes` and `spline` give different colours.
    fn first_difference(
        changes: &Changes,
        spline: &Table,
        bits: impl Iterator<Item = u32>,
    ) -> Option<(u32, [u8; 3], [u8; 3])> {
        bits.map(|b| {
            (
                b,
                changes.rgb(f32::from_bits(b)),
                spline.rgb(f32::from_bits(b)),
            )
        })
        .find(|(_, a, b)| a != b)
    }

    /// Every change point of `points` and its +- 1..3 neighbours, clipped to [0, 1].
    fn around_changes(points: &[(u32, u32)]) -> Vec<u32> {
        let near = |b: u32| b.saturating_sub(3)..=(b + 3).min(ONE);
        points.iter().flat_map(|&(b, _)| near(b)).collect()
    }

    fn generated() -> [(Colormap, &'static [(u32, u32)]); 2] {
        [
            (Colormap::Magma, &changes::MAGMA),
            (Colormap::RedBlue, &changes::RED_BLUE),
        ]
    }

    #[test]
    fn change_table_equals_the_spline_on_a_stride_and_around_every_change() {
        for (map, points) in generated() {
            assert!(points.len() > 300, "{map:?}: {} regions", points.len());
            let (c, s) = (map.changes(), map.table());
            let stride = (0..=ONE / STRIDE).map(|j| j * STRIDE);
            assert_eq!(
                first_difference(c, s, stride),
                None,
                "{map:?}: (bits, table, spline)"
            );
            let near = around_changes(points).into_iter();
            assert_eq!(
                first_difference(c, s, near),
                None,
                "{map:?}: (bits, table, spline)"
            );
            let ends = [
                0.0f32,
                -0.0,
                1.0,
                f32::NAN,
                -f32::NAN,
                -1e-45,
                1.000_000_1,
                2.0,
                -3.0,
            ];
            for t in ends {
                assert_eq!(
                    c.rgb(t).map(u32::from),
                    s.rgb(t).map(u32::from),
                    "{map:?} at {t}"
                );
            }
        }
    }

    /// Teeth: a change point between two coloured regions moved by one bit pattern either way,
    /// or one region's colour off by one, is found by the checks above.
    #[test]
    fn change_table_checks_fail_on_a_wrong_table() {
        for (map, points) in generated() {
            let s = map.table();
            let k = (points.len() / 2..points.len())
                .find(|&k| points[k - 1].1 != SPLINE && points[k].1 != SPLINE)
                .unwrap();
            for wrong in [
                points[k].0 - 1, // the piece starts one bit pattern early
                points[k].0 + 1, // or late
            ] {
                let mut moved = points.to_vec();
                moved[k].0 = wrong;
                let c = Changes::new(&moved, s);
                let near = around_changes(points).into_iter();
                assert!(
                    first_difference(&c, s, near).is_some(),
                    "{map:?}: moved to {wrong:x}"
                );
            }
            let mut recoloured = points.to_vec();
            recoloured[k].1 ^= 0x01;
            let c = Changes::new(&recoloured, s);
            let near = around_changes(points).into_iter();
            assert!(
                first_difference(&c, s, near).is_some(),
                "{map:?}: recoloured"
            );
        }
    }

    /// [`Changes::region`] of a pattern holds it, ends by `ONE + 1`, is the region of each of
    /// its patterns, and its colour is the spline's at the pattern and at both ends; checked
    /// around every change and on a stride. Teeth: a region one pattern longer holds a
    /// pattern of another colour.
    #[test]
    fn regions_hold_their_patterns_and_one_colour() {
        for (map, points) in generated() {
            let (c, s) = (map.changes(), map.table());
            let stride = (0..=ONE / STRIDE).map(|j| j * STRIDE);
            let (mut coloured, mut longer_differs) = (0, false);
            for b in around_changes(points).into_iter().chain(stride) {
                let (start, end, colour) = c.region(b);
                assert!(start <= b && b < end && end <= ONE + 1, "{map:?} {b:#x}");
                assert_eq!(c.region(start), (start, end, colour), "{map:?} {b:#x}");
                assert_eq!(c.region(end - 1), (start, end, colour), "{map:?} {b:#x}");
                let Some(colour) = colour else { continue };
                coloured += 1;
                for p in [start, b, end - 1] {
                    assert_eq!(s.rgb(f32::from_bits(p)), colour, "{map:?} {p:#x}");
                }
                longer_differs |= end <= ONE && s.rgb(f32::from_bits(end)) != colour;
            }
            assert!(coloured > 1000 && longer_differs, "{map:?}: {coloured}");
        }
    }

    /// Every f32 in [0, 1] (about 1.07e9 inputs per colormap), [`Colormap::rgb`] (the region
    /// lookup, and the spline in its spline regions) against colorous, over all cores:
    /// scripts/heatmap_colors_exhaustive.sh runs
    /// `cargo test --release --locked every_f32_in_0_1_matches_colorous -- --ignored`.
    #[test]
    #[ignore]
    fn every_f32_in_0_1_matches_colorous() {
        for (map, _) in both() {
            let got = sweep(&|t| map.rgb(t), map.colorous(), 1);
            assert_eq!(got, None, "{map:?}: (t, ours, colorous)");
            eprintln!(
                "{map:?}: all {} f32 in [0, 1] equal colorous's",
                ONE as u64 + 1
            );
        }
    }
}
