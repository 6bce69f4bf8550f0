//! The Rust FLIP against nv-flip (the oracle, whole image at once) bit for bit, with teeth: a
//! perturbed pixels-per-degree or a radius one pixel short must change the map.
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

/// An RGB8 image of uniform noise.
fn noise(rng: &mut fastrand::Rng, w: usize, h: usize) -> Vec<u8> {
    (0..3 * w * h).map(|_| rng.u8(..)).collect()
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

/// The Rust map of `test` against `reference` equals nv-flip's bit for bit.
fn assert_same_as_nv_flip(reference: &[u8], test: &[u8], w: usize, h: usize, name: &str) {
    let ours = FlipReference::new(reference, w as u32, h as u32).map(test);
    let full = flip_map_full(reference, test, w as u32, h as u32);
    let differ = (0..w * h).find(|&i| ours[i].to_bits() != full[i].to_bits());
    assert!(
        differ.is_none(),
        "{name} ({w}x{h}): pixel {differ:?} is {:?}, nv-flip {:?}",
        differ.map(|i| ours[i]),
        differ.map(|i| full[i])
    );
}

/// Noise against noise (FLIP everywhere) and noise against itself with scattered changes, at
/// sizes down to smaller than the filters (21 and 19 pixels wide) and non-square ones.
#[test]
fn noise_images_give_nv_flips_map_bit_for_bit() {
    let mut rng = fastrand::Rng::with_seed(2626);
    for (w, h) in [
        (1, 1),
        (2, 3),
        (7, 1),
        (1, 9),
        (5, 4),
        (17, 9),
        (23, 61),
        (64, 48),
        (131, 37),
    ] {
        let a = noise(&mut rng, w, h);
        let b = noise(&mut rng, w, h);
        assert_same_as_nv_flip(&a, &b, w, h, "noise vs noise");
        let at: Vec<_> = (0..(w * h).div_ceil(20))
            .map(|_| (rng.usize(..w), rng.usize(..h)))
            .collect();
        assert_same_as_nv_flip(&a, &changed(&a, w, &at), w, h, "noise, scattered");
        assert_same_as_nv_flip(&a, &a, w, h, "noise vs itself");
    }
}

/// Every channel of most pixels one step (1 LSB) up or down: the smallest differences.
#[test]
fn dense_one_lsb_differences_give_nv_flips_map_bit_for_bit() {
    let mut rng = fastrand::Rng::with_seed(1);
    let (w, h) = (96usize, 71usize);
    for base in [image(w, h), noise(&mut rng, w, h), vec![128u8; 3 * w * h]] {
        let test: Vec<u8> = base
            .iter()
            .map(|&v| match rng.u8(..3) {
                0 => v.saturating_add(1),
                1 => v.saturating_sub(1),
                _ => v,
            })
            .collect();
        assert_same_as_nv_flip(&base, &test, w, h, "1 LSB");
    }
}

/// Differences at the corners, on every edge, isolated inside, in a cluster, and dense: the
/// map computed near the differing pixels only is nv-flip's whole-image map bit for bit (and
/// so the pooled figures are the same).
#[test]
fn single_pixels_at_corners_and_edges_give_nv_flips_map_bit_for_bit() {
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
    let reference = FlipReference::new(&base, w as u32, h as u32);
    for (name, at) in cases {
        let test = changed(&base, w, &at);
        let full = flip_map_full(&base, &test, w as u32, h as u32);
        let ours = reference.map(&test);
        let differ = (0..w * h).find(|&i| ours[i].to_bits() != full[i].to_bits());
        assert!(
            differ.is_none(),
            "{name}: pixel {differ:?} is {:?}, nv-flip {:?}",
            differ.map(|i| ours[i]),
            differ.map(|i| full[i])
        );
        let (a, b) = (pool(&ours, &mask), pool(&full, &mask));
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

/// Teeth: filters built for a pixels-per-degree 1 % off (other weights, same radii) give a
/// map that is not nv-flip's, so the bit-for-bit checks can fail.
#[test]
fn a_perturbed_pixels_per_degree_is_not_nv_flip() {
    let (w, h) = (64usize, 48usize);
    let base = image(w, h);
    let test = changed(&base, w, &[(30, 20), (0, 0), (63, 47), (10, 40)]);
    let full = flip_map_full(&base, &test, w as u32, h as u32);
    let exact = FlipReference::with_ppd(&base, w as u32, h as u32, PPD).map(&test);
    assert_eq!(bits(&exact), bits(&full));
    let off = FlipReference::with_ppd(&base, w as u32, h as u32, PPD * 1.01);
    assert_eq!(off.params.radius(), exact_radius());
    assert_ne!(bits(&off.map(&test)), bits(&full));
}

fn exact_radius() -> usize {
    Params::new(PPD).radius()
}

/// Teeth: the test side computed one pixel short of the radius (r - 1) gives a different map
/// where the differences sit near the image edges and inside.
#[test]
fn a_radius_one_short_changes_the_map() {
    let (w, h) = (120usize, 90usize);
    let base = image(w, h);
    let test = changed(&base, w, &[(60, 45), (5, 5), (119, 30)]);
    let full = flip_map_full(&base, &test, w as u32, h as u32);
    let reference = FlipReference::new(&base, w as u32, h as u32);
    assert_eq!(
        bits(&map_off_radius_for_test(&reference, &test, 0)),
        bits(&full)
    );
    assert_ne!(
        bits(&map_off_radius_for_test(&reference, &test, -1)),
        bits(&full)
    );
}

/// The local pixels-per-degree is nv-flip's default.
#[test]
fn ppd_is_nv_flips_default() {
    assert_eq!(PPD.to_bits(), nv_flip::DEFAULT_PIXELS_PER_DEGREE.to_bits());
}

/// A one-pixel difference reaches no farther than the radius (on black, grey and light
/// grounds, up and down): what computing near the differing pixels relies on. That it reaches
/// as far as the radius on some image is `a_radius_one_short_changes_the_map`.
#[test]
fn a_one_pixel_difference_stays_within_the_filter_radius() {
    let (w, h) = (61usize, 61usize);
    let r = exact_radius();
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

/// The region choice: isolated pixels get regions of their own, a dense image one box.
#[test]
fn regions_box_isolated_pixels_alone_and_dense_ones_together() {
    let (w, h) = (200usize, 200usize);
    let base = image(w, h);
    let sparse = changed(&base, w, &[(10, 10), (150, 20), (100, 180)]);
    let r = regions(&Differences::new(&base, &sparse, w, h), w, h, 10);
    assert_eq!(r.len(), 3, "{r:?}");
    assert!(r.iter().all(|b| b.area() == 1), "{r:?}");
    let all: Vec<_> = (0..w).flat_map(|x| (0..h).map(move |y| (x, y))).collect();
    let dense = changed(&base, w, &all);
    let r = regions(&Differences::new(&base, &dense, w, h), w, h, 10);
    assert_eq!(
        r,
        vec![Rect {
            x0: 0,
            y0: 0,
            x1: w,
            y1: h
        }]
    );
    assert!(regions(&Differences::new(&base, &base, w, h), w, h, 10).is_empty());
}

/// `near_differences` against the definition (a differing pixel within Chebyshev distance r),
/// pixel by pixel, on scattered differences including the corners, and on differences in
/// every row (the ring of row counts reused all the way down); a radius one less gives other
/// ones (teeth).
#[test]
fn near_differences_is_the_chebyshev_neighbourhood() {
    let (w, h, r) = (53usize, 37usize, 4usize);
    let base = image(w, h);
    let scattered = vec![(0, 0), (52, 36), (20, 10), (21, 30), (45, 3)];
    let every_row: Vec<_> = (0..h).map(|y| ((y * 7) % w, y)).collect();
    for at in [scattered, every_row] {
        let test = changed(&base, w, &at);
        let d = Differences::new(&base, &test, w, h);
        let near = near_differences(&d, w, h, r);
        for y in 0..h {
            for x in 0..w {
                let want = at
                    .iter()
                    .any(|&(ax, ay)| ax.abs_diff(x).max(ay.abs_diff(y)) <= r);
                assert_eq!(near[y * w + x], want, "({x}, {y})");
            }
        }
        assert_ne!(near_differences(&d, w, h, r - 1), near);
    }
}

/// Teeth of the copy of the reference's horizontal pass: with the rows' differences counted
/// within 0 columns instead of the radius, a block beside a difference in its row (one box:
/// two segments in rows 45 and 46) is copied although it reads a differing pixel, and the map
/// is no longer nv-flip's; with the radius it is.
#[test]
fn copying_the_reference_rows_too_close_to_a_difference_changes_the_map() {
    let (w, h) = (128usize, 90usize);
    let base = image(w, h);
    let at: Vec<_> = (30..=50)
        .map(|x| (x, 45))
        .chain((60..=80).map(|x| (x, 46)))
        .collect();
    let test = changed(&base, w, &at);
    let full = flip_map_full(&base, &test, w as u32, h as u32);
    let reference = FlipReference::new(&base, w as u32, h as u32);
    let r = exact_radius();
    assert_eq!(
        regions(&Differences::new(&base, &test, w, h), w, h, r).len(),
        1
    );
    assert_eq!(bits(&reference.map_within(&test, r, r)), bits(&full));
    assert_ne!(bits(&reference.map_within(&test, r, 0)), bits(&full));
}

fn pooled_bits((mean, p95): (f64, f64)) -> (u64, u64) {
    (mean.to_bits(), p95.to_bits())
}

/// `pool` (the +0.0 values counted, not collected) against `pool_collected` bit for bit: maps
/// mostly +0.0, with -0.0, positives, infinities and NaNs of both signs, under masks of every
/// density, and the cases where the sign of a zero sum shows (only -0.0 values; -0.0 and
/// +0.0). Teeth: a map one subnormal step away at one pixel gives other bits.
#[test]
fn pool_skipping_zeros_is_the_collected_pool_bit_for_bit() {
    let mut rng = fastrand::Rng::with_seed(95);
    let special = [
        -0.0f32,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -f32::NAN,
        -1.5,
        f32::from_bits(1),
    ];
    for n in [0usize, 1, 2, 3, 19, 20, 21, 100, 1000, 4096] {
        for (zero_share, special_share) in
            [(0.0, 0.0), (0.5, 0.0), (0.9, 0.01), (1.0, 0.0), (0.3, 0.3)]
        {
            let map: Vec<f32> = (0..n)
                .map(|_| {
                    let u = rng.f64();
                    if u < zero_share {
                        0.0
                    } else if u < zero_share + special_share {
                        special[rng.usize(..special.len())]
                    } else {
                        rng.f32() * 1.2
                    }
                })
                .collect();
            for density in [0.0, 0.3, 1.0] {
                let mask: Vec<bool> = (0..n).map(|_| rng.f64() < density).collect();
                assert_eq!(
                    pooled_bits(pool(&map, &mask)),
                    pooled_bits(pool_collected(&map, &mask)),
                    "{n} pixels, zeros {zero_share}, special {special_share}, mask {density}"
                );
            }
        }
    }
    let all = vec![true; 4];
    for map in [
        [-0.0f32; 4],
        [-0.0, 0.0, -0.0, -0.0],
        [0.0, -0.0, -0.0, -0.0],
        [0.0; 4],
    ] {
        assert_eq!(
            pooled_bits(pool(&map, &all)),
            pooled_bits(pool_collected(&map, &all)),
            "{map:?}"
        );
    }
    // 38 zeros and two 0.25: the p95 (index 37) is the last zero, the subnormal once nudged
    let map: Vec<f32> = (0..40).map(|i| if i < 2 { 0.25 } else { 0.0 }).collect();
    let mask = vec![true; 40];
    let mut nudged = map.clone();
    nudged[5] = f32::from_bits(1);
    assert_ne!(
        pooled_bits(pool(&nudged, &mask)),
        pooled_bits(pool_collected(&map, &mask))
    );
}

/// `differing_cells` as it was: every differing pixel's one-pixel box joined into its cell,
/// comparing the two images pixel by pixel (the oracle of the segment-per-row version).
fn differing_cells_pixel_by_pixel(
    reference: &[u8],
    test: &[u8],
    w: usize,
    h: usize,
) -> (Vec<Option<Rect>>, usize) {
    let cw = w.div_ceil(CELL);
    let mut cells = vec![None; cw * h.div_ceil(CELL)];
    for y in 0..h {
        for x in 0..w {
            let i = 3 * (y * w + x);
            if reference[i..i + 3] != test[i..i + 3] {
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

/// The shared pixel compare and the cells' row segments against the pixel-by-pixel boxes, on
/// images of sizes that are and are not multiples of the cell, with a few to most pixels
/// changed in one channel each (every channel's change must count). Teeth: one more changed
/// pixel, in a cell without differences, gives other cells.
#[test]
fn differing_cells_are_the_pixel_by_pixel_boxes() {
    let mut rng = fastrand::Rng::with_seed(29);
    for (w, h) in [(1usize, 1usize), (8, 8), (13, 5), (37, 29), (64, 17)] {
        let base = noise(&mut rng, w, h);
        for share in [0.0, 0.01, 0.1, 0.6] {
            let mut test = base.clone();
            for i in 0..w * h {
                if rng.f64() < share {
                    let o = 3 * i + rng.usize(..3);
                    test[o] = test[o].wrapping_add(rng.u8(1..));
                }
            }
            let d = Differences::new(&base, &test, w, h);
            let oracle = differing_cells_pixel_by_pixel(&base, &test, w, h);
            assert_eq!(differing_cells(&d, w, h), oracle, "{w}x{h}, share {share}");
            // teeth: a pixel changed in a cell without differences (its first pixel)
            let (cells, cw) = &oracle;
            if let Some(c) = cells.iter().position(Option::is_none) {
                let (x, y) = ((c % cw) * CELL, (c / cw) * CELL);
                let mut more = test.clone();
                more[3 * (y * w + x) + 2] ^= 0x10;
                let d_more = Differences::new(&base, &more, w, h);
                assert_ne!(
                    differing_cells(&d_more, w, h),
                    oracle,
                    "{w}x{h}, share {share}"
                );
            }
        }
    }
}

/// `window_counts` against its definition at every column, for widths below, at and above
/// the window (`2r + 1`), radius 0 included. Teeth: the counts of one radius more differ.
#[test]
fn window_counts_are_the_clamped_window() {
    let mut rng = fastrand::Rng::with_seed(30);
    for w in [0usize, 1, 2, 5, 9, 20, 21, 22, 40, 100] {
        for r in [0usize, 1, 3, 10, 12] {
            let mut prefix = vec![0u32; w + 1];
            for x in 0..w {
                prefix[x + 1] = prefix[x] + u32::from(rng.bool());
            }
            let mut out = vec![u32::MAX; w];
            window_counts(&prefix, r, &mut out);
            let at = |r: usize, x: usize| prefix[(x + r + 1).min(w)] - prefix[x.saturating_sub(r)];
            let want: Vec<u32> = (0..w).map(|x| at(r, x)).collect();
            assert_eq!(out, want, "w {w}, r {r}");
            let wider: Vec<u32> = (0..w).map(|x| at(r + 1, x)).collect();
            if prefix[w] > 0 && prefix[w] < w as u32 && w > 2 * r + 2 {
                assert_ne!(out, wider, "w {w}, r {r}");
            }
        }
    }
}
