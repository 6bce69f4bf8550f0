//! LDR-FLIP's arithmetic in Rust, operation for operation as nv-flip's C++ (nv-flip-sys 0.1.1,
//! `extern/cpp/CPP/image.h` `image<float>::FLIP`, `CPP/color.h`, `common/sharedflip.h`), so
//! that every value is bit for bit nv-flip's: the same f32 operations per pixel in the same
//! order (`a * b` then `+=`, never fused: nv-flip is built for baseline x86-64, without FMA),
//! the constants rounded to f32 as the C++ rounds them, `powf`/`expf`/`sqrtf` through the same
//! libm (`f32::powf`, `f32::exp`, `f32::sqrt`; constant exponents behind `black_box`, so that
//! LLVM cannot turn `powf(x, 0.5)` into `sqrt(x)` as it does for an x it knows is >= 0: the
//! two differ in the last bit now and then), the filter weights built as `setSpatialFilters`
//! and `setFeatureFilter` build them, and the image edge clamped as the C++ clamps it.
//!
//! What differs is only the order of the loops, never the order of a sum: one side (an 8-bit
//! image) is filtered at a time, over an output rectangle, row by row. A source row is turned
//! into YCxCz once (sRGB to linear through a 256-entry table of nv-flip's very function of
//! `v / 255`), edge-replicated into a padded row; the horizontal passes run over that row and
//! the vertical ones over a ring of the last `2R + 1` horizontal rows, both "for each block of
//! 8 pixels, for each tap, for each pixel of the block" ([`convolve`]), so LLVM vectorises
//! across pixels with the sums in registers while every pixel's sum still adds its taps -R..R
//! in order.
//! A row's vertical sums go to [`super::batch`], which turns them into each pixel's side (its
//! filtered Lab after Hunt, its edge and point feature values) and combines a reference side
//! with a test side, in passes over the row. The constants, the colour conversions and the
//! filters' [`Params`] are in [`super::color`], with `side_at` and `flip_value`: the same
//! arithmetic pixel by pixel, the tests' oracle for those passes.

use super::batch::SideRow;
use super::color::Params;
use super::Rect;

/// Planes of the horizontal pass: YCx (x, y), Cz (x, y), then the feature filter's
/// 1st derivative, 2nd derivative and Gaussian of the normalised Y.
pub(crate) const PLANES: usize = 7;

/// The horizontal pass of a whole image, plane by plane, row-major (`w * h` values each).
pub(crate) type Planes = [Vec<f32>; PLANES];

/// What [`filter_side`] filters.
pub(crate) enum Mode<'a> {
    /// Every pixel of `area` (the whole image), keeping the horizontal pass of every row in
    /// the planes (the reference side).
    Reference(&'a mut Planes),
    /// The test side, the reference's horizontal [`Planes`] beside it: only the pixels whose
    /// `wanted` flag is set (row-major over the image) are handed on; a block of a row's
    /// horizontal pass with no `differs` pixel (row-major: where the two images differ)
    /// within `r_row` columns of its own (the radius; the tests give less) in the same row
    /// reads the same source bytes as the reference did there and is copied from it; the
    /// vertical pass runs only for blocks with a wanted pixel.
    Test {
        wanted: &'a [bool],
        differs: &'a [bool],
        r_row: usize,
        reference: &'a Planes,
    },
}

/// Filters one side, the 8-bit RGB image `src` (`w` x `h`), over `area`, and hands each row's
/// sides to `out(y, row)` (a [`SideRow`] over the area's columns; which pixels: [`Mode`]). The
/// image edge is clamped as nv-flip clamps it (the full image's, not the area's). Copying a
/// block of the reference's horizontal pass and skipping a vertical block are exact: every
/// pixel's sums are computed alone (the block only groups pixels), from the same inputs.
pub(crate) fn filter_side(
    p: &Params,
    src: &[u8],
    (w, h): (usize, usize),
    area: Rect,
    mut mode: Mode,
    mut out: impl FnMut(usize, &mut SideRow),
) {
    let r = p.radius();
    let width = area.x1 - area.x0;
    // rows are filtered a whole number of blocks wide (columns past the area, clamped to the
    // image like the rest, are computed and dropped)
    let rw = width.div_ceil(LANES) * LANES;
    let ring_rows = 2 * r + 1;
    // padded row: YCxCz planes and the feature filter's normalised Y, columns x0-r..x0+rw+r
    let pw = rw + 2 * r;
    let mut padded = [(); 4].map(|_| vec![0.0f32; pw]);
    let mut ring = [(); PLANES].map(|_| vec![0.0f32; ring_rows * rw]);
    let mut acc = [(); 8].map(|_| vec![0.0f32; rw]);
    let mut sides = SideRow::new(rw);
    // per block of LANES pixels: horizontal pass computed (else copied), vertical pass needed
    let blocks = rw / LANES;
    let (mut computed, mut needed) = (vec![true; blocks], vec![true; blocks]);
    // the image columns of block `b` (within the image)
    let columns = |b: usize| (area.x0 + b * LANES).min(w)..(area.x0 + (b + 1) * LANES).min(w);
    let (first, last) = (area.y0.saturating_sub(r), (area.y1 + r).min(h));
    let mut next = first;
    for y in area.y0..area.y1 {
        while next < last && next <= y + r {
            let slot = next % ring_rows;
            if let Mode::Test {
                differs,
                r_row,
                reference,
                ..
            } = &mode
            {
                let row = &differs[next * w..(next + 1) * w];
                for (b, c) in computed.iter_mut().enumerate() {
                    // an OR over the block's columns and r_row each side (vectorised)
                    let cols = columns(b);
                    let reach = cols.start.saturating_sub(*r_row)..(cols.end + r_row).min(w);
                    *c = !cols.is_empty() && row[reach].iter().fold(false, |a, &d| a | d);
                    if !*c {
                        copy_block(
                            reference,
                            &mut ring,
                            (next * w, columns(b)),
                            slot * rw + b * LANES,
                        );
                    }
                }
            }
            let row = &src[3 * w * next..3 * w * (next + 1)];
            pad_row(p, row, area.x0, r, &computed, &mut padded);
            horizontal(p, &padded, r, (rw, slot), &computed, &mut ring);
            if let Mode::Reference(keep) = &mut mode {
                for (k, r) in keep.iter_mut().zip(&ring) {
                    k[next * w..(next + 1) * w].copy_from_slice(&r[slot * rw..slot * rw + w]);
                }
            }
            next += 1;
        }
        sides.wanted.clear();
        match &mode {
            Mode::Test { wanted, .. } => {
                wanted_runs(&wanted[y * w + area.x0..y * w + area.x1], &mut sides.wanted);
                // a block is needed where a wanted run meets its columns
                needed.fill(false);
                for s in &sides.wanted {
                    needed[s.start / LANES..=(s.end - 1) / LANES].fill(true);
                }
            }
            Mode::Reference(_) => sides.wanted.extend((width > 0).then_some(0..width)),
        }
        vertical(p, &ring, (y, h), rw, &needed, &mut acc);
        sides.spans.clear();
        sides.spans.extend(
            runs(&needed)
                .map(|s| s.start..s.end.min(width))
                .filter(|s| !s.is_empty()),
        );
        sides.compute(&acc);
        out(y, &mut sides);
    }
}

/// Copies image columns `cols` of row offset `at` (`y * w`) of every reference plane into the
/// ring at `to` (the block's first column).
fn copy_block(
    reference: &Planes,
    ring: &mut Planes,
    (at, cols): (usize, std::ops::Range<usize>),
    to: usize,
) {
    let n = cols.len();
    for (q, p) in ring.iter_mut().zip(reference) {
        q[to..to + n].copy_from_slice(&p[at + cols.start..at + cols.end]);
    }
}

/// The runs of set flags in `row`, ascending, into `out` (cleared by the caller).
fn wanted_runs(row: &[bool], out: &mut Vec<std::ops::Range<usize>>) {
    out.extend(flag_runs(row));
}

/// The runs of consecutive set flags, as pixel ranges (`LANES` pixels a flag).
fn runs(flags: &[bool]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    flag_runs(flags).map(|r| r.start * LANES..r.end * LANES)
}

/// The maximal runs of consecutive set flags in `flags`, ascending, as flag index ranges: the
/// one search behind [`wanted_runs`] (columns) and [`runs`] (blocks).
fn flag_runs(flags: &[bool]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let mut i = 0;
    std::iter::from_fn(move || {
        let start = i + flags[i..].iter().position(|&m| m)?;
        let end = flags[start..]
            .iter()
            .position(|&m| !m)
            .map_or(flags.len(), |e| start + e);
        i = end;
        Some(start..end)
    })
}

/// Source row `row`'s columns `x0 - r .. x0 + width + r` (clamped to the row) in YCxCz and
/// normalised Y (`Y / 116 + 16 / 116` as the feature pass computes it per tap), where a
/// `computed` block's horizontal pass reads them.
// `i` indexes the three padded channels at once (an iterator per channel would not be clearer).
#[allow(clippy::needless_range_loop)]
fn pad_row(
    p: &Params,
    row: &[u8],
    x0: usize,
    r: usize,
    computed: &[bool],
    padded: &mut [Vec<f32>; 4],
) {
    let w = row.len() / 3;
    let one_over_116 = 1.0f32 / 116.0;
    let sixteen_over_116 = 16.0f32 / 116.0;
    for run in runs(computed) {
        for i in run.start..run.end + 2 * r {
            let x = (x0 + i).saturating_sub(r).min(w - 1);
            let c = p.ycxcz(&row[3 * x..3 * x + 3]);
            padded[0][i] = c[0];
            padded[1][i] = c[1];
            padded[2][i] = c[2];
            padded[3][i] = c[0] * one_over_116 + sixteen_over_116;
        }
    }
}

/// Pixels per block of [`convolve`] on the baseline (SSE2) path: its sums stay in registers
/// (eight SSE vectors, enough independent sums to hide the latency of the adds). Rows are
/// filtered a whole number of these blocks wide.
const LANES: usize = 32;
/// Pixels per block on the AVX2 path: eight AVX vectors.
const LANES_AVX2: usize = 64;

/// `out[i] = 0 + weights[0] * rows[0][i] + weights[1] * rows[1][i] + ...`, the taps added in
/// order for every pixel (nv-flip's sum), computed for blocks of pixels at a time: compiled
/// twice, for baseline x86-64 and for AVX2 (without FMA: a product then a sum, each rounded,
/// as in nv-flip), and chosen at run time. Every pixel's sum is the same operations in the same
/// order on both paths and at any block width, so the two give the same bits
/// (`convolve_paths_agree_bit_for_bit`).
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn convolve(out: &mut [f32], rows: &[&[f32]], weights: &[f32]) {
    multiversion::target::match_target! {
        "x86_64+avx2" => {
            let done = convolve_blocks::<LANES_AVX2>(out, rows, weights, 0);
            let done = convolve_blocks::<LANES>(out, rows, weights, done);
            convolve_tail(out, rows, weights, done);
        }
        _ => convolve_portable(out, rows, weights),
    }
}

/// [`convolve`]'s baseline path, whatever the CPU (the tests compare the two paths).
#[inline(always)]
fn convolve_portable(out: &mut [f32], rows: &[&[f32]], weights: &[f32]) {
    let done = convolve_blocks::<LANES>(out, rows, weights, 0);
    convolve_tail(out, rows, weights, done);
}

/// [`convolve`] over the whole blocks of `L` pixels from `from` on; returns where they end.
#[inline(always)]
fn convolve_blocks<const L: usize>(
    out: &mut [f32],
    rows: &[&[f32]],
    weights: &[f32],
    from: usize,
) -> usize {
    let full = from + (out.len() - from) / L * L;
    for i in (from..full).step_by(L) {
        let mut a = [0.0f32; L];
        for (row, &wk) in rows.iter().zip(weights) {
            for (a, &s) in a.iter_mut().zip(&row[i..i + L]) {
                *a += wk * s;
            }
        }
        out[i..i + L].copy_from_slice(&a);
    }
    full
}

/// [`convolve`] pixel by pixel from `from` to the end.
#[inline(always)]
fn convolve_tail(out: &mut [f32], rows: &[&[f32]], weights: &[f32], from: usize) {
    for (i, o) in out.iter_mut().enumerate().skip(from) {
        let mut a = 0.0f32;
        for (row, &wk) in rows.iter().zip(weights) {
            a += wk * row[i];
        }
        *o = a;
    }
}

/// The horizontal passes of one padded row into ring slot `slot` (rows `rw` wide), for the
/// `computed` blocks.
fn horizontal(
    p: &Params,
    padded: &[Vec<f32>; 4],
    r: usize,
    (rw, slot): (usize, usize),
    computed: &[bool],
    ring: &mut Planes,
) {
    let [ycx_x, ycx_y, cz_x, cz_y, f_dx, f_ddx, f_g] = ring;
    let (rs, rf) = (p.spatial_radius, p.feature_radius);
    for run in runs(computed) {
        let row = slot * rw + run.start..slot * rw + run.end;
        let taps = |plane: usize, radius: usize| -> Vec<&[f32]> {
            (0..2 * radius + 1)
                .map(|k| &padded[plane][r - radius + k + run.start..])
                .collect()
        };
        let (y, cx, cz) = (taps(0, rs), taps(1, rs), taps(2, rs));
        convolve(&mut ycx_x[row.clone()], &y, &p.spatial[0]);
        convolve(&mut ycx_y[row.clone()], &cx, &p.spatial[1]);
        convolve(&mut cz_x[row.clone()], &cz, &p.spatial[2]);
        convolve(&mut cz_y[row.clone()], &cz, &p.spatial[3]);
        // featureWeights (x: Gaussian, y: 1st derivative, z: 2nd derivative) of the normalised Y
        let yn = taps(3, rf);
        convolve(&mut f_dx[row.clone()], &yn, &p.feature[1]);
        convolve(&mut f_ddx[row.clone()], &yn, &p.feature[2]);
        convolve(&mut f_g[row], &yn, &p.feature[0]);
    }
}

/// The vertical passes for output row `y` (of `h`) from the ring, for the `needed` blocks:
/// `acc` gets the filtered YCx (x, y), Cz (x, y), and the feature sums dx, ddx, dy, ddy.
fn vertical(
    p: &Params,
    ring: &Planes,
    (y, h): (usize, usize),
    rw: usize,
    needed: &[bool],
    acc: &mut [Vec<f32>; 8],
) {
    let ring_rows = ring[0].len() / rw.max(1);
    let (rs, rf) = (p.spatial_radius, p.feature_radius);
    // the ring offsets of the taps' rows (edge clamped), once per output row
    let offsets = |radius: usize| -> Vec<usize> {
        (0..2 * radius + 1)
            .map(|k| (y + k).saturating_sub(radius).min(h - 1) % ring_rows * rw)
            .collect()
    };
    let (at_s, at_f) = (offsets(rs), offsets(rf));
    for run in runs(needed) {
        let taps = |plane: usize, radius: usize| -> Vec<&[f32]> {
            let at = if radius == rs { &at_s } else { &at_f };
            at.iter()
                .map(|&o| &ring[plane][o + run.start..o + run.end])
                .collect()
        };
        for (c, a) in acc.iter_mut().take(4).enumerate() {
            convolve(&mut a[run.clone()], &taps(c, rs), &p.spatial[c]);
        }
        let [_, _, _, _, dx, ddx, dy, ddy] = acc;
        convolve(&mut dx[run.clone()], &taps(4, rf), &p.feature[0]);
        convolve(&mut ddx[run.clone()], &taps(5, rf), &p.feature[0]);
        let g = taps(6, rf);
        convolve(&mut dy[run.clone()], &g, &p.feature[1]);
        convolve(&mut ddy[run.clone()], &g, &p.feature[2]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `wanted_runs` against the flags: every set flag in exactly one run, in order, runs
    /// maximal (never touching). Teeth: a cleared flag splits or shortens a run.
    #[test]
    fn wanted_runs_are_the_set_flags() {
        let mut rng = fastrand::Rng::with_seed(31);
        for n in [0usize, 1, 2, 7, 64, 300] {
            for share in [0.0, 0.1, 0.5, 0.95, 1.0] {
                let flags: Vec<bool> = (0..n).map(|_| rng.f64() < share).collect();
                let mut runs = Vec::new();
                wanted_runs(&flags, &mut runs);
                let listed: Vec<usize> = runs.iter().flat_map(|r| r.clone()).collect();
                let set: Vec<usize> = (0..n).filter(|&i| flags[i]).collect();
                assert_eq!(listed, set, "{n} flags, share {share}");
                assert!(runs.iter().all(|r| !r.is_empty()));
                assert!(runs.windows(2).all(|p| p[0].end < p[1].start));
                if let Some(&i) = set.get(set.len() / 2) {
                    let mut fewer = flags.clone();
                    fewer[i] = false;
                    let mut other = Vec::new();
                    wanted_runs(&fewer, &mut other);
                    assert_ne!(other, runs, "{n} flags, share {share}");
                }
            }
        }
    }

    /// Random weights and rows of every length around the block widths: the dispatched
    /// [`convolve`] (AVX2 where the CPU has it) gives the portable path's bits.
    #[test]
    fn convolve_paths_agree_bit_for_bit() {
        let mut rng = fastrand::Rng::with_seed(27);
        let mut value = || (rng.f32() - 0.3) * 90.0;
        for taps in [1, 19, 21] {
            let weights: Vec<f32> = (0..taps).map(|_| value() / 40.0).collect();
            for n in [0, 1, 31, 32, 33, 63, 64, 65, 96, 127, 128, 200, 1040] {
                let planes: Vec<Vec<f32>> = (0..taps)
                    .map(|_| (0..n).map(|_| value()).collect())
                    .collect();
                let rows: Vec<&[f32]> = planes.iter().map(|p| &p[..]).collect();
                let (mut fast, mut portable) = (vec![f32::NAN; n], vec![f32::NAN; n]);
                convolve(&mut fast, &rows, &weights);
                convolve_portable(&mut portable, &rows, &weights);
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&fast), bits(&portable), "{taps} taps, {n} pixels");
                // teeth: the same taps summed last to first are other bits somewhere
                if taps > 1 && n >= 32 {
                    let (rev_rows, rev_weights): (Vec<&[f32]>, Vec<f32>) = rows
                        .iter()
                        .rev()
                        .zip(weights.iter().rev())
                        .map(|(r, w)| (*r, *w))
                        .unzip();
                    let mut reversed = vec![0.0; n];
                    convolve_portable(&mut reversed, &rev_rows, &rev_weights);
                    assert_ne!(bits(&reversed), bits(&fast), "{taps} taps, {n} pixels");
                }
            }
        }
    }
}
