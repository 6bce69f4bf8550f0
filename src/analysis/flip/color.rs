//! nv-flip's colour arithmetic and parameters (nv-flip-sys 0.1.1, `extern/cpp/CPP/color.h`,
//! `common/sharedflip.h`), operation for operation as the C++ (see [`super::kernel`] for the
//! rules every value follows): the constants, the colour space conversions, the filters of
//! [`Params`], and the pixel-by-pixel oracles ([`side_at`], [`flip_value`]) the tests hold the
//! row passes of [`super::batch`] to. What both the filtering ([`super::kernel`]) and the
//! row passes read, so neither needs the other's file for it.

// The literals are nv-flip's as written in its headers (then rounded to f32 as there).
#![allow(clippy::excessive_precision, clippy::approx_constant)]

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
    pub(super) spatial: [Vec<f32>; 4],
    /// `setFeatureFilter`: the Gaussian, its 1st and 2nd derivative.
    pub(super) feature: [Vec<f32>; 3],
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
    pub(super) fn ycxcz(&self, p: &[u8]) -> [f32; 3] {
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
