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
//! with a test side, in passes over the row; `side_at` and `flip_value` here are the same
//! arithmetic pixel by pixel, the tests' oracle for those passes.

// The literals are nv-flip's as written in its headers (then rounded to f32 as there).
#![allow(clippy::excessive_precision, clippy::approx_constant)]

use super::batch::SideRow;
use super::Rect;

/// `FLIP::PI` (sharedflip.h), an f32.
const PI: f32 = 3.141_592_653_589_79;
/// `FLIPConstants` (sharedflip.h).
pub(crate) const GQC: f32 = 0.7;
const GPC: f32 = 0.4;
pub(crate) const GPT: f32 = 0.95;
const GW: f32 = 0.082;
pub(crate) const GQF: f32 = 0.5;
/// `DEFAULT_ILLUMINANT` and `INV_DEFAULT_ILLUMINANT` (color.h).
pub(crate) const ILLUMINANT: [f32; 3] = [0.950_428_545, 1.0, 1.088_900_371];
pub(crate) const INV_ILLUMINANT: [f32; 3] = [1.052_156_925, 1.0, 0.918_357_670];

/// `color3::LinearRGB2XYZ`'s matrix, each entry an f32 quotient of f32 literals as in color.h.
pub(crate) const RGB_TO_XYZ: [[f32; 3]; 3] = [
    [
        10135552.0f32 / 24577794.0f32,
        8788810.0f32 / 24577794.0f32,
        4435075.0f32 / 24577794.0f32,
    ],
    [
        2613072.0f32 / 12288897.0f32,
        8788810.0f32 / 12288897.0f32,
        887015.0f32 / 12288897.0f32,
    ],
    [
        1425312.0f32 / 73733382.0f32,
        8788810.0f32 / 73733382.0f32,
        70074185.0f32 / 73733382.0f32,
    ],
];
/// `color3::XYZ2LinearRGB`'s matrix.
pub(crate) const XYZ_TO_RGB: [[f32; 3]; 3] = [
    [3.241_003_275, -1.537_398_934, -0.498_615_861],
    [-0.969_224_334, 1.875_930_071, 0.041_554_224],
    [0.055_639_423, -0.204_011_202, 1.057_148_933],
];

/// `m * v` as color.h writes it: `a1 * x + a2 * y + a3 * z`, left to right.
#[inline]
pub(crate) fn mat(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|r| r[0] * v[0] + r[1] * v[1] + r[2] * v[2])
}

/// `color3::sRGB2LinearRGB` of one channel.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// `XYZ2CIELab`'s constants (color.h), computed in f32 as there.
const DELTA: f32 = 6.0 / 29.0;
const DELTA_SQUARE: f32 = DELTA * DELTA;
pub(crate) const DELTA_CUBE: f32 = DELTA * DELTA_SQUARE;
pub(crate) const FACTOR: f32 = 1.0 / (3.0 * DELTA_SQUARE);
pub(crate) const TERM: f32 = 4.0 / 29.0;

/// `color3::XYZ2CIELab` (D65).
fn xyz_to_lab(xyz: [f32; 3]) -> [f32; 3] {
    let v = [0, 1, 2].map(|i| {
        let v = xyz[i] * INV_ILLUMINANT[i];
        if v > DELTA_CUBE {
            v.powf(std::hint::black_box(1.0 / 3.0))
        } else {
            FACTOR * v + TERM
        }
    });
    [
        116.0 * v[1] - 16.0,
        500.0 * (v[0] - v[1]),
        200.0 * (v[1] - v[2]),
    ]
}

/// `color3::Hunt` applied to a Lab colour's a and b (color.h; `FLIP::computeColorDifference`).
fn hunt(lab: [f32; 3]) -> [f32; 3] {
    [lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]]
}

/// `color3::HyAB`.
fn hyab(a: &[f32; 3], b: &[f32; 3]) -> f32 {
    let (da, db) = (a[1] - b[1], a[2] - b[2]);
    (a[0] - b[0]).abs() + (da * da + db * db).sqrt()
}

/// `Min(Max(v, 0), 1)` with nv-flip's macros (`x > y ? x : y`).
#[inline]
pub(crate) fn clamp01(v: f32) -> f32 {
    let m = if v > 0.0 { v } else { 0.0 };
    if m > 1.0 {
        1.0
    } else {
        m
    }
}

/// The filters and constants of FLIP at a pixels-per-degree value.
#[derive(Debug, Clone)]
pub(crate) struct Params {
    /// Spatial (CSF) filter radius, `calculateSpatialFilterRadius`.
    pub(crate) spatial_radius: usize,
    /// Feature filter radius, `ceil(3 * 0.5 * gw * ppd)`.
    pub(crate) feature_radius: usize,
    /// `setSpatialFilters`: YCx's x and y weights, Cz's x and y weights.
    spatial: [Vec<f32>; 4],
    /// `setFeatureFilter`: the Gaussian, its 1st and 2nd derivative.
    feature: [Vec<f32>; 3],
    pub(crate) cmax: f32,
    pub(crate) pccmax: f32,
    /// `linear[v]`: nv-flip's linear value of the 8-bit channel value `v` (`v / 255` to linear).
    linear: [f32; 256],
}

/// `Gaussian(x2, a, b)` of sharedflip.h.
fn gaussian_ab(x2: f32, a: f32, b: f32) -> f32 {
    let pi_sq = PI * PI;
    a * (PI / b).sqrt() * (-pi_sq * x2 / b).exp()
}

/// `GaussianSqrt(x2, a, b)` of sharedflip.h.
fn gaussian_sqrt(x2: f32, a: f32, b: f32) -> f32 {
    let pi_sq = PI * PI;
    (a * (PI / b).sqrt()).sqrt() * (-pi_sq * x2 / b).exp()
}

impl Params {
    pub(crate) fn new(ppd: f32) -> Params {
        let pi_sq = PI * PI;
        // GaussianConstants: the largest scale parameter is b1.z = 0.04.
        let b_max = 0.0047f32.max(0.0053).max(0.04).max(1.0e-5).max(0.025);
        let spatial_radius = (3.0 * (b_max / (2.0 * pi_sq)).sqrt() * ppd).ceil() as usize;
        let spatial = spatial_filters(ppd, spatial_radius);
        let (feature_radius, feature) = feature_filter(ppd);
        // color3::computeMaxDistance(gqc)
        let lab = |rgb| hunt(xyz_to_lab(mat(&RGB_TO_XYZ, rgb)));
        let (green, blue) = (lab([0.0, 1.0, 0.0]), lab([0.0, 0.0, 1.0]));
        let cmax = hyab(&green, &blue).powf(GQC);
        let mut linear = [0.0f32; 256];
        for (v, l) in linear.iter_mut().enumerate() {
            *l = srgb_to_linear(v as f32 / 255.0);
        }
        Params {
            spatial_radius,
            feature_radius,
            spatial,
            feature,
            cmax,
            pccmax: GPC * cmax,
            linear,
        }
    }

    /// The widest of the two filters' radii: how far a pixel's FLIP reads.
    pub(crate) fn radius(&self) -> usize {
        self.spatial_radius.max(self.feature_radius)
    }

    /// nv-flip's YCxCz of an 8-bit sRGB pixel (`image::sRGB2YCxCz`).
    fn ycxcz(&self, p: &[u8]) -> [f32; 3] {
        let rgb = [p[0], p[1], p[2]].map(|v| self.linear[v as usize]);
        let xyz = mat(&RGB_TO_XYZ, rgb);
        let v = [0, 1, 2].map(|i| xyz[i] * INV_ILLUMINANT[i]);
        [
            116.0 * v[1] - 16.0,
            500.0 * (v[0] - v[1]),
            200.0 * (v[1] - v[2]),
        ]
    }
}

/// `setSpatialFilters`: the normalised YCx (x, y) and Cz (x, y) weights of width `2r + 1`.
fn spatial_filters(ppd: f32, r: usize) -> [Vec<f32>; 4] {
    let delta_x = 1.0 / ppd;
    let width = 2 * r + 1;
    let mut raw = [(); 4].map(|_| Vec::with_capacity(width));
    let (mut sum_y, mut sum_cx, mut sum_cz1, mut sum_cz2) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for x in 0..width {
        let ix = (x as i32 - r as i32) as f32 * delta_x;
        let ix2 = ix * ix;
        let g = [
            gaussian_ab(ix2, 1.0, 0.0047),
            gaussian_ab(ix2, 1.0, 0.0053),
            gaussian_sqrt(ix2, 34.1, 0.04),
            gaussian_sqrt(ix2, 13.5, 0.025),
        ];
        sum_y += g[0];
        sum_cx += g[1];
        sum_cz1 += g[2];
        sum_cz2 += g[3];
        for (v, g) in raw.iter_mut().zip(g) {
            v.push(g);
        }
    }
    let (norm_y, norm_cx) = (1.0 / sum_y, 1.0 / sum_cx);
    let norm_cz = 1.0 / (sum_cz1 * sum_cz1 + sum_cz2 * sum_cz2).sqrt();
    let [y, cx, cz1, cz2] = raw;
    let scale = |v: Vec<f32>, n: f32| v.into_iter().map(|w| w * n).collect();
    [
        scale(y, norm_y),
        scale(cx, norm_cx),
        scale(cz1, norm_cz),
        scale(cz2, norm_cz),
    ]
}

/// `setFeatureFilter`: the radius and the normalised Gaussian, 1st and 2nd derivative weights.
fn feature_filter(ppd: f32) -> (usize, [Vec<f32>; 3]) {
    let std_dev = 0.5 * GW * ppd;
    let radius = (3.0 * std_dev).ceil() as usize;
    let width = 2 * radius + 1;
    let (mut g_sum, mut dg_neg, mut dg_pos, mut ddg_neg, mut ddg_pos) =
        (0.0f32, 0.0, 0.0, 0.0, 0.0);
    let mut raw = Vec::with_capacity(width);
    for x in 0..width {
        let xx = (x as i32 - radius as i32) as f32;
        let g = (-(xx * xx) / (2.0 * std_dev * std_dev)).exp();
        g_sum += g;
        let dg = -xx * g;
        if dg > 0.0 {
            dg_pos += dg;
        } else {
            dg_neg -= dg;
        }
        let ddg = (xx * xx / (std_dev * std_dev) - 1.0) * g;
        if ddg > 0.0 {
            ddg_pos += ddg;
        } else {
            ddg_neg -= ddg;
        }
        raw.push([g, dg, ddg]);
    }
    let mut out = [(); 3].map(|_| Vec::with_capacity(width));
    for [g, dg, ddg] in raw {
        out[0].push(g / g_sum);
        out[1].push(dg / if dg > 0.0 { dg_pos } else { dg_neg });
        out[2].push(ddg / if ddg > 0.0 { ddg_pos } else { ddg_neg });
    }
    (radius, out)
}

/// What one side (reference or test) contributes to a pixel's FLIP: its spatially filtered
/// colour in Lab after the Hunt adjustment, and its edge and point feature values.
#[cfg(test)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Side {
    pub(crate) lab: [f32; 3],
    pub(crate) edge: f32,
    pub(crate) point: f32,
}

/// A pixel's FLIP from its two sides: `computeColorDifference`'s end and
/// `computeFeatureDifferenceAndFinalError`'s (the tests' oracle of `batch::SideRow::flip`).
#[cfg(test)]
pub(crate) fn flip_value(p: &Params, reference: &Side, test: &Side) -> f32 {
    let mut color = hyab(&reference.lab, &test.lab).powf(std::hint::black_box(GQC));
    if color < p.pccmax {
        color *= GPT / p.pccmax;
    } else {
        color = GPT + ((color - p.pccmax) / (p.cmax - p.pccmax)) * (1.0 - GPT);
    }
    let normalization = 1.0 / 2.0f32.sqrt();
    let edge = (reference.edge - test.edge).abs();
    let point = (reference.point - test.point).abs();
    // powf(x, 0.5) as nv-flip calls it: LLVM would turn `x.powf(0.5)` of an x it knows to be
    // >= 0 into sqrt, which differs from glibc's powf in the last bit now and then (found by
    // the noise tests), so the exponent is hidden from the optimiser
    let feature =
        (normalization * if edge > point { edge } else { point }).powf(std::hint::black_box(GQF));
    color.powf(1.0 - feature)
}

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

/// Pixel `i` of the vertical sums as a [`Side`]: YCxCz to XYZ to linear RGB, clamped, to XYZ,
/// Lab and Hunt; the edge and point values from the feature sums (the tests' oracle of
/// `batch::SideRow::compute`).
#[cfg(test)]
pub(crate) fn side_at(acc: &[Vec<f32>; 8], i: usize) -> Side {
    let ycxcz = [acc[0][i], acc[1][i], acc[2][i] + acc[3][i]];
    // color3::YCxCz2XYZ
    let yy = (ycxcz[0] + 16.0) / 116.0;
    let (cx, cz) = (ycxcz[1] / 500.0, ycxcz[2] / 200.0);
    let xyz = [yy + cx, yy, yy - cz];
    let xyz = [0, 1, 2].map(|c| xyz[c] * ILLUMINANT[c]);
    let rgb = mat(&XYZ_TO_RGB, xyz).map(clamp01);
    let lab = hunt(xyz_to_lab(mat(&RGB_TO_XYZ, rgb)));
    let (dx, ddx, dy, ddy) = (acc[4][i], acc[5][i], acc[6][i], acc[7][i]);
    Side {
        lab,
        edge: (dx * dx + dy * dy).sqrt(),
        point: (ddx * ddx + ddy * ddy).sqrt(),
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
