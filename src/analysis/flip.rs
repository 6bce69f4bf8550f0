//! FLIP (NVIDIA's perceptual image difference, through the nv-flip crate) over covered pixels,
//! computed only where it can differ from zero.
//!
//! # Why the crops are exact
//! FLIP's value at a pixel is a pointwise function of the two images filtered by kernels of
//! finite support (the CSF filter and the edge/point detectors, both separable, radius
//! [`filter_radius`], clamped at the image border): it reads the input pixels within Chebyshev
//! distance `r` of it and nothing else (no global normalisation in LDR-FLIP). Where the two
//! 8-bit images agree over that whole neighbourhood, every filtered value is the same on both
//! sides and the pixel's FLIP is exactly +0.0 (HyAB of equal colours is 0, `0^q = 0`).
//! So for a set `B` of differing pixels (a rectangle), the nv-flip computation over the crop
//! `B + 2r` (clipped to the image) gives, at every pixel of `B + r`, the very value of the
//! full-image computation: each such pixel's neighbourhood lies inside the crop, the crop's edge
//! coincides with the image's wherever the filters clamp, and the same float operations run in
//! the same order. Pixels farther than `r` from every differing pixel are +0.0.
//! [`flip_map`] groups the differing pixels into rectangles (grid cells of the size that
//! minimises the pixels computed, or one bounding box) and fills the map from their crops;
//! tests check it bit for bit against [`flip_map_full`] (the whole image at once).
use glam::DVec3;

use crate::analysis::stats::percentile;
use crate::output;

pub(crate) fn srgb_rgb8(color: impl Iterator<Item = DVec3>) -> Vec<u8> {
    let mut rgb = Vec::with_capacity(3 * color.size_hint().0);
    for c in color {
        rgb.extend_from_slice(&[c.x, c.y, c.z].map(|v| output::srgb8(v as f32)));
    }
    rgb
}

/// The pixels per degree every FLIP of the tool uses (nv-flip's default: a 0.7 m viewing
/// distance from a 0.7 m wide 4K monitor).
const PPD: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// The radius in pixels of FLIP's widest filter at `ppd`, as the C++ reference computes it:
/// the spatial (CSF) filter's `ceil(3 sqrt(max b / (2 pi^2)) ppd)` with the largest scale
/// parameter b = 0.04, and the feature filter's `ceil(3 * 0.5 * 0.082 * ppd)` (10 and 9 at
/// the default 67.02 pixels per degree). Tests check that crops of this radius are exact and
/// one pixel less is not.
pub(crate) fn filter_radius(ppd: f32) -> usize {
    let pi_sq = (std::f64::consts::PI * std::f64::consts::PI) as f32;
    let spatial = (3.0f32 * (0.04f32 / (2.0 * pi_sq)).sqrt() * ppd).ceil();
    let feature = (3.0f32 * (0.5f32 * 0.082 * ppd)).ceil();
    spatial.max(feature) as usize
}

/// A pixel rectangle, ends exclusive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Rect {
    x0: usize,
    y0: usize,
    x1: usize,
    y1: usize,
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

/// The bounding boxes of the pixels where the two RGB8 images differ, per `CELL` x `CELL` cell
/// (row-major cells; `None` where the cell has none), and the number of cell columns.
fn differing_cells(
    reference: &[u8],
    test: &[u8],
    w: usize,
    h: usize,
) -> (Vec<Option<Rect>>, usize) {
    let cw = w.div_ceil(CELL);
    let mut cells = vec![None; cw * h.div_ceil(CELL)];
    for y in 0..h {
        let row = 3 * w * y..3 * w * (y + 1);
        let (a, b) = (&reference[row.clone()], &test[row]);
        if a == b {
            continue;
        }
        for x in 0..w {
            if a[3 * x..3 * x + 3] != b[3 * x..3 * x + 3] {
                let c = &mut cells[(y / CELL) * cw + x / CELL];
                let px = Rect {
                    x0: x,
                    y0: y,
                    x1: x + 1,
                    y1: y + 1,
                };
                *c = Some(Rect::union(*c, px));
            }
        }
    }
    (cells, cw)
}

/// The rectangles whose crops [`flip_map`] computes: the differing pixels' boxes in cells of
/// `CELL * 2^k` pixels (k = 0..5), or their one bounding box, whichever computes the fewest
/// pixels (crop areas `box + 2r`, summed).
fn regions(reference: &[u8], test: &[u8], w: usize, h: usize, r: usize) -> Vec<Rect> {
    let (mut cells, mut cw) = differing_cells(reference, test, w, h);
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

/// nv-flip's map of the whole image at once (the straightforward computation).
pub(crate) fn flip_map_full(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(r, t, PPD).to_vec()
}

/// The FLIP map of two RGB8 images, equal bit for bit to [`flip_map_full`] (module doc),
/// computed over crops around the differing pixels only.
pub(crate) fn flip_map(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    flip_map_with_radius(reference, test, width, height, filter_radius(PPD))
}

/// [`flip_map`] with crops for a filter radius of `r` (exact for `r >= filter_radius`; the
/// tests give a smaller one to see the map change).
fn flip_map_with_radius(
    reference: &[u8],
    test: &[u8],
    width: u32,
    height: u32,
    r: usize,
) -> Vec<f32> {
    let (w, h) = (width as usize, height as usize);
    let mut map = vec![0.0f32; w * h];
    for b in regions(reference, test, w, h, r) {
        let crop = b.grow(2 * r, w, h);
        let valid = b.grow(r, w, h);
        let (cw, ch) = (crop.x1 - crop.x0, crop.y1 - crop.y0);
        let cut = |img: &[u8]| -> Vec<u8> {
            (crop.y0..crop.y1)
                .flat_map(|y| &img[3 * (y * w + crop.x0)..3 * (y * w + crop.x1)])
                .copied()
                .collect()
        };
        let part = flip_map_full(&cut(reference), &cut(test), cw as u32, ch as u32);
        for y in valid.y0..valid.y1 {
            let from = (y - crop.y0) * cw + (valid.x0 - crop.x0);
            map[y * w + valid.x0..y * w + valid.x1]
                .copy_from_slice(&part[from..from + (valid.x1 - valid.x0)]);
        }
    }
    map
}

/// [`flip_map`] with crops for a radius `delta` pixels off the filter's (tests elsewhere).
#[cfg(test)]
pub(crate) fn filter_radius_map_for_test(
    reference: &[u8],
    test: &[u8],
    width: u32,
    height: u32,
    delta: isize,
) -> Vec<f32> {
    let r = filter_radius(PPD).saturating_add_signed(delta);
    flip_map_with_radius(reference, test, width, height, r)
}

/// Mean and p95 (nearest rank) of a FLIP map over the `mask` pixels, in pixel order.
pub(crate) fn pool(map: &[f32], mask: &[bool]) -> (f64, f64) {
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

/// FLIP between two RGB8 images, pooled (mean, p95) over `mask` pixels.
pub(crate) fn flip(
    reference: &[u8],
    test: &[u8],
    width: u32,
    height: u32,
    mask: &[bool],
) -> (f64, f64) {
    pool(&flip_map(reference, test, width, height), mask)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth RGB8 image (gradients and a disc), so that the filters see structure.
    fn image(w: usize, h: usize) -> Vec<u8> {
        let mut v = Vec::with_capacity(3 * w * h);
        for y in 0..h {
            for x in 0..w {
                let (dx, dy) = (x as f64 - w as f64 / 2.0, y as f64 / 1.3 - h as f64 / 2.6);
                let disc = if dx * dx + dy * dy < (w * w) as f64 / 9.0 {
                    90.0
                } else {
                    0.0
                };
                v.push((x * 255 / w) as u8);
                v.push(((y * 200 / h) as f64 + disc * 0.5) as u8);
                v.push((40.0 + disc) as u8);
            }
        }
        v
    }

    fn bits(map: &[f32]) -> Vec<u32> {
        map.iter().map(|v| v.to_bits()).collect()
    }

    /// `image` with the pixels `at` changed (by a step that varies per pixel).
    fn changed(base: &[u8], w: usize, at: &[(usize, usize)]) -> Vec<u8> {
        let mut t = base.to_vec();
        for (k, &(x, y)) in at.iter().enumerate() {
            let o = 3 * (y * w + x) + k % 3;
            t[o] = t[o].wrapping_add(1 + (k as u8 % 7) * 30);
        }
        t
    }

    /// Differences at the corners, on every edge, isolated inside, in a cluster, and dense:
    /// the crops give the full computation's map bit for bit (and so the same pooled figures).
    #[test]
    fn crops_give_the_full_map_bit_for_bit() {
        let (w, h) = (150usize, 97usize);
        let base = image(w, h);
        let mut rng = fastrand::Rng::with_seed(26);
        let dense: Vec<_> = (0..w * h / 3)
            .map(|_| (rng.usize(..w), rng.usize(..h)))
            .collect();
        let cases: Vec<(&str, Vec<(usize, usize)>)> = vec![
            ("none", vec![]),
            (
                "corners",
                vec![(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)],
            ),
            (
                "edges",
                vec![(70, 0), (0, 40), (w - 1, 51), (33, h - 1), (1, 1)],
            ),
            ("isolated", vec![(40, 30), (100, 70), (75, 12), (12, 80)]),
            (
                "cluster",
                (60..75)
                    .flat_map(|x| (40..48).map(move |y| (x, y)))
                    .collect(),
            ),
            ("dense", dense),
        ];
        let mask: Vec<bool> = (0..w * h).map(|i| i % 5 != 0).collect();
        for (name, at) in cases {
            let test = changed(&base, w, &at);
            let full = flip_map_full(&base, &test, w as u32, h as u32);
            let fast = flip_map(&base, &test, w as u32, h as u32);
            assert_eq!(
                bits(&fast),
                bits(&full),
                "{name}: crops differ from the full map"
            );
            let (a, b) = (pool(&fast, &mask), pool(&full, &mask));
            assert_eq!(
                (a.0.to_bits(), a.1.to_bits()),
                (b.0.to_bits(), b.1.to_bits())
            );
            if !at.is_empty() {
                assert!(
                    full.iter().any(|&v| v > 0.0),
                    "{name}: no FLIP error at all"
                );
            }
        }
    }

    /// Teeth: crops one pixel too small (radius r - 1) give a different map where the
    /// differences sit near the crop edges.
    #[test]
    fn crops_too_small_change_the_map() {
        let (w, h) = (120usize, 90usize);
        let base = image(w, h);
        let test = changed(&base, w, &[(60, 45), (5, 5), (119, 30)]);
        let r = filter_radius(PPD);
        let full = flip_map_full(&base, &test, w as u32, h as u32);
        let small = flip_map_with_radius(&base, &test, w as u32, h as u32, r - 1);
        assert_ne!(bits(&small), bits(&full));
    }

    /// A one-pixel difference reaches no farther than the radius (on black, grey and light
    /// grounds, up and down): what the crops rely on. That it reaches as far as the radius on
    /// some image is `crops_too_small_change_the_map`.
    #[test]
    fn a_one_pixel_difference_stays_within_the_filter_radius() {
        let (w, h) = (61usize, 61usize);
        let r = filter_radius(PPD);
        let c = 30;
        for (ground, pixel) in [(0u8, 255u8), (128, 0), (128, 140), (200, 60)] {
            let base = vec![ground; 3 * w * h];
            let mut test = base.clone();
            test[3 * (c * w + c)..3 * (c * w + c) + 3].copy_from_slice(&[pixel; 3]);
            let full = flip_map_full(&base, &test, w as u32, h as u32);
            let reach = (0..w * h)
                .filter(|&i| full[i] != 0.0)
                .map(|i| (i % w).abs_diff(c).max((i / w).abs_diff(c)))
                .max();
            assert!(
                reach.is_some_and(|d| d <= r),
                "ground {ground}, pixel {pixel}: reach {reach:?}, radius {r}"
            );
        }
    }

    /// The region choice: isolated pixels get crops of their own, a dense image one box.
    #[test]
    fn regions_box_isolated_pixels_alone_and_dense_ones_together() {
        let (w, h) = (200usize, 200usize);
        let base = image(w, h);
        let sparse = changed(&base, w, &[(10, 10), (150, 20), (100, 180)]);
        let r = regions(&base, &sparse, w, h, 10);
        assert_eq!(r.len(), 3, "{r:?}");
        assert!(r.iter().all(|b| b.area() == 1), "{r:?}");
        let all: Vec<_> = (0..w).flat_map(|x| (0..h).map(move |y| (x, y))).collect();
        let dense = changed(&base, w, &all);
        let r = regions(&base, &dense, w, h, 10);
        assert_eq!(
            r,
            vec![Rect {
                x0: 0,
                y0: 0,
                x1: w,
                y1: h
            }]
        );
        assert!(regions(&base, &base, w, h, 10).is_empty());
    }
}
