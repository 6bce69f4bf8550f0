//! FLIP (NVIDIA's perceptual image difference, LDR) of a method's 8-bit image against the
//! reference's, in Rust ([`kernel`]: nv-flip's C++ operation for operation, bit for bit), with
//! the reference's half computed once per run ([`FlipReference`]) and the test's half only
//! where FLIP can differ from zero.
//!
//! # Why computing near the differing pixels only is exact
//! FLIP's value at a pixel is a pointwise function of the two images filtered by kernels of
//! finite support (the CSF filter and the edge/point detectors, both separable, radius
//! [`color::Params::radius`] at most, clamped at the image border): it reads the input pixels
//! within Chebyshev distance `r` of it and nothing else (no global normalisation in LDR-FLIP).
//! Where the two 8-bit images agree over that whole neighbourhood, every filtered value is the
//! same on both sides and the pixel's FLIP is exactly +0.0 (HyAB of equal colours is 0,
//! `0^q = 0`). So for a set `B` of differing pixels (a rectangle), the test side is filtered
//! over `B + r` (clipped to the image, edges clamped as for the whole image) and every pixel
//! farther than `r` from every differing pixel is +0.0. [`FlipReference::map`] groups the
//! differing pixels into rectangles ([`regions`]: grid cells of the size that minimises the
//! pixels computed, or one bounding box); the tests check the map bit for bit against nv-flip
//! over the whole image (`flip_map_full`, the oracle, a dev-dependency).
mod batch;
mod color;
mod kernel;

use batch::SidePlanes;
use color::Params;
use glam::DVec3;
use kernel::{Mode, Planes};

#[cfg(test)]
use crate::analysis::stats::percentile;
use crate::analysis::stats::rank_index;
use crate::output;

/// The 8-bit sRGB image of f64 linear colours, narrowed to f32 as every image of the tool is
/// ([`output::srgb::rgb8`]).
pub(crate) fn srgb_rgb8(color: impl Iterator<Item = DVec3>) -> Vec<u8> {
    output::srgb::rgb8(color.map(|c| c.as_vec3().to_array()))
}

/// The pixels per degree every FLIP of the tool uses: nv-flip's default
/// (`nv_flip::DEFAULT_PIXELS_PER_DEGREE`, 67, checked by a test), a 0.7 m viewing distance
/// from a 0.7 m wide 4K monitor.
const PPD: f32 = 67.0;

/// A pixel rectangle, ends exclusive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Rect {
    pub(crate) x0: usize,
    pub(crate) y0: usize,
    pub(crate) x1: usize,
    pub(crate) y1: usize,
}

impl Rect {
    fn grow(self, r: usize, w: usize, h: usize) -> Rect {
        Rect {
            x0: self.x0.saturating_sub(r),
            y0: self.y0.saturating_sub(r),
            x1: (self.x1 + r).min(w),
            y1: (self.y1 + r).min(h),
        }
    }
    fn area(&self) -> usize {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }
    fn union(a: Option<Rect>, b: Rect) -> Rect {
        match a {
            None => b,
            Some(a) => Rect {
                x0: a.x0.min(b.x0),
                y0: a.y0.min(b.y0),
                x1: a.x1.max(b.x1),
                y1: a.y1.max(b.y1),
            },
        }
    }
}

/// Finest grid cell (pixels) in which the differing pixels are boxed.
const CELL: usize = 8;

/// Where the RGB8 images `a` and `b` (`w` x `h`) differ: per pixel (row-major; rows equal in
/// both images keep `false`), and per row whether any pixel does. The one pixel compare that
/// [`differing_cells`] and [`near_differences`] share.
struct Differences {
    pixels: Vec<bool>,
    rows: Vec<bool>,
}

impl Differences {
    fn new(a: &[u8], b: &[u8], w: usize, h: usize) -> Differences {
        let mut pixels = vec![false; w * h];
        let rows: Vec<bool> = (0..h)
            .map(|y| a[3 * w * y..3 * w * (y + 1)] != b[3 * w * y..3 * w * (y + 1)])
            .collect();
        for y in (0..h).filter(|&y| rows[y]) {
            let (ra, rb) = (
                &a[3 * w * y..3 * w * (y + 1)],
                &b[3 * w * y..3 * w * (y + 1)],
            );
            let px = ra.chunks_exact(3).zip(rb.chunks_exact(3));
            for (d, (p, q)) in pixels[y * w..(y + 1) * w].iter_mut().zip(px) {
                *d = ((p[0] ^ q[0]) | (p[1] ^ q[1]) | (p[2] ^ q[2])) != 0;
            }
        }
        Differences { pixels, rows }
    }
}

/// The bounding boxes of the differing pixels per `CELL` x `CELL` cell (row-major cells;
/// `None` where the cell has none), and the number of cell columns. A row's pixels in a cell
/// enter as one segment, its first to its last differing pixel (the union of their one-pixel
/// boxes: `differing_cells_pixel_by_pixel`, the tests' oracle).
fn differing_cells(d: &Differences, w: usize, h: usize) -> (Vec<Option<Rect>>, usize) {
    let cw = w.div_ceil(CELL);
    let mut cells = vec![None; cw * h.div_ceil(CELL)];
    for y in (0..h).filter(|&y| d.rows[y]) {
        let row = &d.pixels[y * w..(y + 1) * w];
        for (cx, chunk) in row.chunks(CELL).enumerate() {
            if let Some(first) = chunk.iter().position(|&d| d) {
                let last = chunk.iter().rposition(|&d| d).unwrap_or(first);
                let c = &mut cells[(y / CELL) * cw + cx];
                let segment = Rect {
                    x0: cx * CELL + first,
                    y0: y,
                    x1: cx * CELL + last + 1,
                    y1: y + 1,
                };
                *c = Some(Rect::union(*c, segment));
            }
        }
    }
    (cells, cw)
}

/// The rectangles near which [`FlipReference::map`] filters the test side: the differing
/// pixels' boxes in cells of `CELL * 2^k` pixels (k = 0..5), or their one bounding box,
/// whichever reads the fewest pixels (areas `box + 2r`, the pixels the filters of `box + r`
/// read, summed).
fn regions(d: &Differences, w: usize, h: usize, r: usize) -> Vec<Rect> {
    let (mut cells, mut cw) = differing_cells(d, w, h);
    let cost = |rects: &[Option<Rect>]| -> usize {
        rects
            .iter()
            .flatten()
            .map(|b| b.grow(2 * r, w, h).area())
            .sum()
    };
    let mut best: Vec<Rect> = cells.iter().flatten().copied().collect();
    let mut best_cost = cost(&cells);
    // Coarser grids: merge 2 x 2 cells at a time; the last step (one cell) is the bounding box.
    while cells.len() > 1 {
        let ch = cells.len() / cw;
        let (nw, nh) = (cw.div_ceil(2), ch.div_ceil(2));
        let mut merged = vec![None; nw * nh];
        for (i, c) in cells.iter().enumerate() {
            if let Some(c) = c {
                let m = &mut merged[(i / cw / 2) * nw + (i % cw) / 2];
                *m = Some(Rect::union(*m, *c));
            }
        }
        (cells, cw) = (merged, nw);
        let c = cost(&cells);
        if c < best_cost {
            best_cost = c;
            best = cells.iter().flatten().copied().collect();
        }
    }
    best
}

/// The reference's half of FLIP, computed once per compare run and shared read-only by the
/// workers: per pixel its filtered Lab after Hunt and its edge and point feature values, and
/// its horizontal filter pass (7 planes, 28 bytes a pixel: the test side copies it where its
/// row reads the same bytes).
pub(crate) struct FlipReference {
    params: Params,
    ref8: Vec<u8>,
    width: usize,
    height: usize,
    sides: SidePlanes,
    horizontal: Planes,
}

impl FlipReference {
    /// The reference side of the RGB8 image `ref8` (`width` x `height`).
    pub(crate) fn new(ref8: &[u8], width: u32, height: u32) -> FlipReference {
        FlipReference::with_ppd(ref8, width, height, PPD)
    }

    /// [`FlipReference::new`] at another pixels-per-degree (the tests' teeth).
    fn with_ppd(ref8: &[u8], width: u32, height: u32, ppd: f32) -> FlipReference {
        let (w, h) = (width as usize, height as usize);
        assert_eq!(
            ref8.len(),
            3 * w * h,
            "FLIP reference: not a {w}x{h} RGB8 image"
        );
        let params = Params::new(ppd);
        let mut sides = SidePlanes::new(w * h);
        let mut horizontal = [(); kernel::PLANES].map(|_| vec![0.0f32; w * h]);
        if w > 0 && h > 0 {
            let all = Rect {
                x0: 0,
                y0: 0,
                x1: w,
                y1: h,
            };
            let mode = Mode::Reference(&mut horizontal);
            kernel::filter_side(&params, ref8, (w, h), all, mode, |y, row| {
                sides.store(y * w, w, row)
            });
        }
        FlipReference {
            params,
            ref8: ref8.to_vec(),
            width: w,
            height: h,
            sides,
            horizontal,
        }
    }

    /// The FLIP map of the RGB8 image `test` against the reference, equal bit for bit to
    /// nv-flip's over the whole image (module doc), the test side computed only within the
    /// filter radius of the pixels where the two images differ.
    pub(crate) fn map(&self, test: &[u8]) -> Vec<f32> {
        let r = self.params.radius();
        self.map_within(test, r, r)
    }

    /// [`FlipReference::map`] computing the test side within `r` of the differing pixels and
    /// copying the reference's horizontal pass where no pixel within `r_row` in the row differs
    /// (exact for radii `>= radius`; the tests give smaller ones to see the map change).
    fn map_within(&self, test: &[u8], r: usize, r_row: usize) -> Vec<f32> {
        let (w, h) = (self.width, self.height);
        assert_eq!(
            test.len(),
            self.ref8.len(),
            "FLIP: test image of another size"
        );
        let mut map = vec![0.0f32; w * h];
        let differences = Differences::new(&self.ref8, test, w, h);
        let near = near_differences(&differences, w, h, r);
        for b in regions(&differences, w, h, r) {
            let area = b.grow(r, w, h);
            let mode = Mode::Test {
                wanted: &near,
                differs: &differences.pixels,
                r_row,
                reference: &self.horizontal,
            };
            kernel::filter_side(&self.params, test, (w, h), area, mode, |y, row| {
                let at = y * w + area.x0;
                row.flip(&self.params, &self.sides, at, &mut map[at..(y + 1) * w]);
            });
        }
        map
    }
}

/// Per pixel (row-major), whether a differing pixel lies within Chebyshev distance `r` of
/// it: FLIP can be non-zero there only (module doc). Running counts along each differing row
/// (the differing pixels within `r` columns), then a window of `2r + 1` rows down each column;
/// a row's counts live in a ring of `2r + 1` rows, from its entry to its exit of the window.
fn near_differences(d: &Differences, w: usize, h: usize, r: usize) -> Vec<bool> {
    let ring_rows = 2 * r + 1;
    let mut counts = vec![0u32; ring_rows * w];
    let mut prefix = vec![0u32; w + 1];
    let differs = &d.rows;
    // an output row with no differing row in its window stays false
    let mut near = vec![false; w * h];
    let mut window = vec![0u32; w];
    let mut active = 0usize;
    for y in 0..h + r {
        // the row leaving the window first: the entering one takes its ring slot
        if let Some(gone) = y.checked_sub(ring_rows).filter(|&g| g < h && differs[g]) {
            active -= 1;
            let slot = gone % ring_rows * w;
            for (c, v) in window.iter_mut().zip(&counts[slot..slot + w]) {
                *c -= v;
            }
        }
        if y < h && differs[y] {
            active += 1;
            let mut count = 0u32;
            for (p, &f) in prefix[1..].iter_mut().zip(&d.pixels[y * w..(y + 1) * w]) {
                count += u32::from(f);
                *p = count;
            }
            let slot = y % ring_rows * w;
            window_counts(&prefix, r, &mut counts[slot..slot + w]);
            for (c, v) in window.iter_mut().zip(&counts[slot..slot + w]) {
                *c += v;
            }
        }
        if y >= r && active > 0 {
            let out = y - r;
            for (n, &c) in near[out * w..(out + 1) * w].iter_mut().zip(&window) {
                *n = c > 0;
            }
        }
    }
    near
}

/// `out[x] = prefix[min(x + r + 1, w)] - prefix[max(x - r, 0)]` (`w = out.len()`, `prefix`
/// `w + 1` running counts): the count within `r` columns of `x`. The columns whose window
/// is clipped by neither end in one subtraction of shifted slices (vectorised), the rest one
/// by one; the same integers either way.
fn window_counts(prefix: &[u32], r: usize, out: &mut [u32]) {
    let w = out.len();
    let at = |x: usize| prefix[(x + r + 1).min(w)] - prefix[x.saturating_sub(r)];
    // interior: x >= r and x + r + 1 <= w
    let start = r.min(w);
    let end = w.saturating_sub(r).max(start);
    for (x, o) in out.iter_mut().enumerate().take(start) {
        *o = at(x);
    }
    if end > start {
        let (hi, lo) = (
            &prefix[start + r + 1..end + r + 1],
            &prefix[start - r..end - r],
        );
        for ((o, &a), &b) in out[start..end].iter_mut().zip(hi).zip(lo) {
            *o = a - b;
        }
    }
    for (x, o) in out.iter_mut().enumerate().skip(end) {
        *o = at(x);
    }
}

/// Mean and p95 (nearest rank, by `f64::total_cmp`) of a FLIP map over the `mask` pixels, the
/// sum in pixel order: bit for bit those of the masked values collected whole
/// ([`pool_collected`], the tests compare the two), without collecting the +0.0 values, most
/// of a map.
///
/// Why skipping +0.0 is exact. The sum: every other value is added in pixel order, starting
/// from the same neutral element (`Iterator::sum`), then `+ 0.0` if any +0.0 was skipped. A
/// skipped `s + 0.0` is `s` for any `s` but a zero (a NaN or an infinity stays itself), and
/// turns -0.0 into +0.0; after that the sum can never be -0.0 again (in round-to-nearest a sum
/// is -0.0 only when both terms are), so the two sums agree bit for bit where they are not
/// zeros, and where they are zeros the collected one is +0.0 as soon as a +0.0 was added,
/// which the final `+ 0.0` gives. The rank: `total_cmp` orders by bits, so the k-th smallest
/// value is one value whatever the method; +0.0 sits after every value with the sign bit set
/// and before every other, so with `neg` of those and `zeros` +0.0s the k-th is the k-th of
/// the rest for `k < neg`, +0.0 for `k < neg + zeros`, and else the `(k - zeros)`-th of the
/// rest.
///
/// The pixels go by chunks of [`POOL_CHUNK`]: a chunk whose values are all +0.0 only counts
/// its masked pixels (a vectorised test and sum); any other goes pixel by pixel as before, so
/// the rest is collected in pixel order all the same. `rest` gets its exact length up front
/// (a first vectorised count), not grown push by push.
pub(crate) fn pool(map: &[f32], mask: &[bool]) -> (f64, f64) {
    let (map, mask) = (
        &map[..map.len().min(mask.len())],
        &mask[..map.len().min(mask.len())],
    );
    let nonzero = map
        .iter()
        .zip(mask)
        .map(|(e, &m)| usize::from(m & (e.to_bits() != 0)))
        .sum::<usize>();
    let mut zeros = 0usize;
    let mut rest: Vec<f64> = Vec::with_capacity(nonzero);
    for (es, ms) in map.chunks(POOL_CHUNK).zip(mask.chunks(POOL_CHUNK)) {
        if es.iter().fold(0u32, |a, e| a | e.to_bits()) == 0 {
            zeros += ms.iter().map(|&m| usize::from(m)).sum::<usize>();
            continue;
        }
        for (&e, _) in es.iter().zip(ms).filter(|(_, &m)| m) {
            if e.to_bits() == 0 {
                zeros += 1;
            } else {
                rest.push(e as f64);
            }
        }
    }
    let n = rest.len() + zeros;
    if n == 0 {
        return (0.0, 0.0);
    }
    let mut sum = rest.iter().sum::<f64>();
    if zeros > 0 {
        sum += 0.0;
    }
    let k = rank_index(n, 95.0);
    let neg = rest.iter().filter(|v| v.is_sign_negative()).count();
    let p95 = if k < neg {
        *rest.select_nth_unstable_by(k, f64::total_cmp).1
    } else if k < neg + zeros {
        0.0
    } else {
        *rest.select_nth_unstable_by(k - zeros, f64::total_cmp).1
    };
    (sum / n as f64, p95)
}

/// Pixels per chunk of [`pool`]'s zero test.
const POOL_CHUNK: usize = 32;

/// [`pool`] as it was: every masked value collected, summed in pixel order and selected from
/// (the tests' check of the shortcut).
#[cfg(test)]
fn pool_collected(map: &[f32], mask: &[bool]) -> (f64, f64) {
    let mut v: Vec<f64> = map
        .iter()
        .zip(mask)
        .filter(|(_, &m)| m)
        .map(|(&e, _)| e as f64)
        .collect();
    let mean = if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    };
    (mean, percentile(&mut v, 95.0))
}

/// nv-flip's map of the whole image at once: the oracle the Rust FLIP is checked against.
#[cfg(test)]
pub(crate) fn flip_map_full(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(r, t, PPD).to_vec()
}

/// [`FlipReference::map`] computing the test side `delta` pixels off the filter radius
/// (tests elsewhere: too small a radius must change the map).
#[cfg(test)]
pub(crate) fn map_off_radius_for_test(
    reference: &FlipReference,
    test: &[u8],
    delta: isize,
) -> Vec<f32> {
    let r = reference.params.radius().saturating_add_signed(delta);
    reference.map_within(test, r, r)
}

/// FLIP of the RGB8 image `test` against the reference, pooled (mean, p95) over `mask` pixels.
pub(crate) fn flip(reference: &FlipReference, test: &[u8], mask: &[bool]) -> (f64, f64) {
    pool(&reference.map(test), mask)
}

#[cfg(test)]
mod tests;
