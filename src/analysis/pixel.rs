//! The per-pixel error of a frame against its f64 truth: the one definition `compare` and
//! `verify` share, and the statistics of it.
//!
//! # The error of a pixel
//! The colour error of a pixel is the signed error of its linear Rec. 709 luminance,
//! `dI = L(method) - L(reference)` with `L(c) = 0.2126 r + 0.7152 g + 0.0722 b` ([`LUMINANCE`]),
//! before any 8-bit quantization. Every `*_abs_error` anywhere in the outputs is a statistic of
//! `|dI|`. The per-channel errors (`channels` of compare) are the same difference taken per
//! R, G, B channel, and named as such. The normal error is the angle between the method's shading
//! normal and the reference's, and the length error `||N'| - 1|`.
//!
//! # Which pixels count
//! Every pixel falls in exactly one [`PixelClass`]. Only [`PixelClass::Measured`] pixels enter a
//! statistic, and the same pixels enter every statistic (luminance, channels, normal, FLIP); the
//! other classes are counted ([`PixelCounts`]) and reported:
//! - background: covered by neither; coverage mismatch: covered by only one of the two;
//! - ill-conditioned: the reference is not meaningful there (a screen-space sliver whose weights
//!   the rasterizer extrapolated, see [`crate::truth::ILL_CONDITIONED`], or an f64 reference that is
//!   itself non-finite);
//! - non-finite: NaN or Inf in the method's colour (or normal, for methods with one).
//!
//! A method with any non-finite pixel, ill-conditioned ones included, has every error statistic
//! infinite: NaN output is never a small error ([`PixelErrors::non_finite`]).
use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use crate::analysis::stats::{percentiles, RankHistogram};
use crate::frame::{Frame, IdFrame};
use crate::method::formulas::Lighting;
use crate::method::twins::Shaded;
use crate::method::Method;
use crate::scene::SceneInputs;
use crate::truth::{RefPixel, Truth, Values};

/// Rec. 709 luminance weights of linear RGB.
pub const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// What a pixel is to the statistics (module doc, "Which pixels count").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelClass {
    Background,
    CoverageMismatch,
    /// The reference is not meaningful here; `non_finite` tells whether the method's output is
    /// NaN/Inf as well.
    IllConditioned {
        non_finite: bool,
    },
    NonFinite,
    Measured,
}

/// How many pixels of each class (background not counted).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct PixelCounts {
    /// Pixels in every statistic: covered by both, well-conditioned, finite.
    pub measured: usize,
    /// Pixels covered by only one of method and reference (different geometry, e.g. `trueform`).
    pub coverage_mismatch: usize,
    /// Covered by both, reference not meaningful (left out of every statistic).
    pub ill_conditioned: usize,
    /// Covered by both with NaN or Inf in the method's output, ill-conditioned ones included.
    pub non_finite: usize,
    /// Of `non_finite`, the ill-conditioned pixels.
    pub non_finite_ill_conditioned: usize,
}

/// The class of pixel `i` of `frame` against `reference`.
#[inline]
pub fn classify(
    frame: &Frame,
    has_normal: bool,
    reference: Option<&RefPixel>,
    i: usize,
) -> PixelClass {
    let here = frame.color[i][3] > 0.0;
    let Some(t) = reference else {
        return if here {
            PixelClass::CoverageMismatch
        } else {
            PixelClass::Background
        };
    };
    if !here {
        return PixelClass::CoverageMismatch;
    }
    let non_finite =
        !d3(frame.color[i]).is_finite() || (has_normal && !d3(frame.normal[i]).is_finite());
    let meaningful =
        !t.ill_conditioned && t.color.is_finite() && t.normal.is_none_or(|n| n.is_finite());
    match (meaningful, non_finite) {
        (false, _) => PixelClass::IllConditioned { non_finite },
        (true, true) => PixelClass::NonFinite,
        (true, false) => PixelClass::Measured,
    }
}

/// The per-pixel errors of one method against the reference.
#[derive(Debug, Clone)]
pub struct PixelErrors {
    pub width: u32,
    pub has_normal: bool,
    pub counts: PixelCounts,
    /// Per pixel (row-major): whether it is [`PixelClass::Measured`] (the mask of every statistic).
    pub measured: Vec<bool>,
    /// The R, G, B errors of the measured pixels, accumulated as they are met (the statistics
    /// need no per-pixel copy).
    pub channels: [ChannelSums; 3],
    /// Max ||N'| - 1| over measured pixels (0 without a per-pixel normal).
    pub max_len: f64,
    /// Per pixel: dI where `measured`, 0 elsewhere (see [`PixelErrors::signed_map`]). One f64 per
    /// pixel and no list beside it: 8 bytes per pixel, where an `Option` map (16 per pixel) and
    /// an (x, y, dI) list (16 per measured pixel) were kept before.
    pub(super) signed: Vec<f64>,
    /// Per pixel: the normal angle error where `has_angle`, 0 elsewhere.
    pub(super) angle: Vec<f64>,
    /// Per pixel: measured, with a normal on both sides (methods with a normal).
    pub(super) has_angle: Vec<bool>,
    /// (x, y) of the first non-finite pixel, if any.
    pub first_non_finite: Option<[u32; 2]>,
    /// Running sums over the measured pixels: |dI| (sum, max) and the normal angle (sum, max).
    pub(super) sums: [f64; 4],
    /// What the percentiles and the intensity statistics read besides the maps, gathered as
    /// the scan meets the values (empty without the per-pixel vectors).
    pub(super) ranks: Ranks,
}

/// What [`PixelErrors::intensity_stats`] and [`PixelErrors::angle_percentile`] would otherwise
/// gather in a first pass over the maps, counted by the scan (with the per-pixel vectors) as
/// it writes them: the values are those it stores, so the statistics are the same bits.
#[derive(Debug, Clone, Default)]
pub(super) struct Ranks {
    /// |dI| of every measured pixel.
    pub(super) abs: RankHistogram,
    /// The normal angle of every pixel with one.
    pub(super) angle: RankHistogram,
    /// [`intensity_stats`]' running sums over |dI| in pixel order (the pixel's index).
    pub(super) run: Running<usize>,
}

impl Ranks {
    /// Counts the |dI| `a` of measured pixel `i` (pixels in order).
    #[inline]
    pub(super) fn add_abs(&mut self, i: usize, a: f64) {
        self.abs.add(a);
        self.run.add(i, a);
    }
}

impl PixelErrors {
    /// Nothing counted yet, for a scan of `n` pixels of a frame `width` wide; `store`: with the
    /// per-pixel vectors (zero: nothing measured), otherwise without.
    pub(super) fn empty(width: u32, has_normal: bool, n: usize, store: bool) -> PixelErrors {
        let per_pixel = if store { n } else { 0 };
        let angles = if store && has_normal { n } else { 0 };
        PixelErrors {
            width,
            has_normal,
            counts: PixelCounts::default(),
            measured: vec![false; per_pixel],
            channels: [ChannelSums::default(); 3],
            max_len: 0.0,
            signed: vec![0.0; per_pixel],
            angle: vec![0.0; angles],
            has_angle: vec![false; angles],
            first_non_finite: None,
            sums: [0.0; 4],
            ranks: Ranks::default(),
        }
    }

    /// Per pixel: dI, and whether it is measured (where it is not, dI is 0 and no data).
    pub fn signed_map(&self) -> (&[f64], &[bool]) {
        (&self.signed, &self.measured)
    }

    /// Per pixel: the normal angle error, and whether it has one.
    pub fn angle_map(&self) -> (&[f64], &[bool]) {
        (&self.angle, &self.has_angle)
    }

    /// (x, y, dI) of every measured pixel, in pixel order.
    pub fn errors(&self) -> impl Iterator<Item = (u32, u32, f64)> + '_ {
        let w = self.width as usize;
        // `take`: an exact upper size hint, so that a collector allocates once
        (0..self.measured.len())
            .filter(|&i| self.measured[i])
            .take(self.counts.measured)
            .map(move |i| ((i % w) as u32, (i / w) as u32, self.signed[i]))
    }

    /// The normal angle error of every measured pixel with one, in pixel order: the tests'
    /// oracle of [`PixelErrors::angle_percentile`] (compare reads the percentile only).
    #[cfg(test)]
    pub(crate) fn angles(&self) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.counts.measured);
        v.extend(
            (0..self.has_angle.len())
                .filter(|&i| self.has_angle[i])
                .map(|i| self.angle[i]),
        );
        v
    }

    /// Whether any covered pixel is NaN/Inf: every error statistic is then infinite.
    pub fn non_finite(&self) -> bool {
        self.counts.non_finite > 0
    }

    /// The summary statistics (`verify`'s columns; `compare` reports more of the same fields).
    pub fn stats(&self) -> ErrorStats {
        let n = self.counts.measured;
        // No measured pixel: no error figure exists (NaN, not 0; a limit fails on it).
        let mean = |s: f64| if n > 0 { s / n as f64 } else { f64::NAN };
        let inf = self.non_finite();
        let or_inf = |v: f64| {
            if inf {
                f64::INFINITY
            } else if n == 0 {
                f64::NAN
            } else {
                v
            }
        };
        let normal = |v: f64| self.has_normal.then_some(or_inf(v));
        let [sum_abs, max_abs, sum_angle, max_angle] = self.sums;
        ErrorStats {
            counts: self.counts,
            max_abs_error: or_inf(max_abs),
            mean_abs_error: or_inf(mean(sum_abs)),
            max_normal_angle_deg: normal(max_angle),
            mean_normal_angle_deg: normal(mean(sum_angle)),
            max_normal_length_error: normal(self.max_len),
        }
    }
}

/// A method's error against a reference truth (normally f64 exact Phong): the statistics of
/// |dI| (module doc) and of the normal over the measured pixels, and the counts of the others.
/// Every error is infinite when the method has a non-finite pixel.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ErrorStats {
    pub counts: PixelCounts,
    /// Max and mean over measured pixels of |dI|, the luminance error.
    pub max_abs_error: f64,
    pub mean_abs_error: f64,
    /// Angle between the method's shading normal and the reference's, degrees (`None`
    /// for methods without a per-pixel normal).
    pub max_normal_angle_deg: Option<f64>,
    pub mean_normal_angle_deg: Option<f64>,
    /// Max ||N'| - 1| of the method's normal.
    pub max_normal_length_error: Option<f64>,
}

/// Statistics of `frame` (a method's GPU output, `has_normal` telling whether its normal
/// target is meaningful) against `reference`: `pixel_errors(..).stats()`.
pub fn error_stats(
    frame: &Frame,
    has_normal: bool,
    reference: &impl ReferencePixels,
) -> ErrorStats {
    pixel_errors(frame, has_normal, reference).stats()
}

/// The per-pixel errors of `frame` against `reference` (module doc).
pub fn pixel_errors(
    frame: &Frame,
    has_normal: bool,
    reference: &impl ReferencePixels,
) -> PixelErrors {
    reference.pixel_errors(frame, has_normal)
}

/// A reference the statistics can be taken against: a [`Truth`] (with its bounds, `verify`)
/// or the compact [`Values`] (`compare`); the same f64 values either way.
pub trait ReferencePixels {
    /// Number of pixels, covered or not.
    fn len(&self) -> usize;
    /// Whether there is no pixel at all.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Every pixel in row-major order, `None` on the background.
    fn ref_pixels(&self) -> impl Iterator<Item = Option<RefPixel>> + '_;
    /// [`pixel_errors`] of `frame` against this reference: one pass over [`Self::ref_pixels`]
    /// (a reference with its columns at hand, [`crate::analysis::scan::Prepared`], walks them
    /// instead; the same statistics bit for bit).
    fn pixel_errors(&self, frame: &Frame, has_normal: bool) -> PixelErrors {
        scan(frame, has_normal, self.len(), true, self.ref_pixels())
    }
}

impl ReferencePixels for Truth {
    fn len(&self) -> usize {
        self.pixels.len()
    }
    fn ref_pixels(&self) -> impl Iterator<Item = Option<RefPixel>> + '_ {
        self.pixels.iter().map(|p| p.as_ref().map(|p| p.value()))
    }
}

impl ReferencePixels for Values {
    fn len(&self) -> usize {
        Values::len(self)
    }
    fn ref_pixels(&self) -> impl Iterator<Item = Option<RefPixel>> + '_ {
        self.pixels()
    }
}

/// The statistics of `frame` against another method's f64 twin `other`, evaluated pixel by
/// pixel where `reference` (the run's truth, from the same id pass) covers a pixel: no second
/// truth is stored. The pixels and every definition are those of [`pixel_errors`]; a pixel is
/// ill-conditioned when `reference` says so (the weights are the same) or the twin is
/// non-finite there. `compare` evaluates the twin once per run instead
/// ([`crate::analysis::scan::Twin`]; the same
/// statistics bit for bit).
pub fn stats_against_twin(
    frame: &Frame,
    has_normal: bool,
    reference: &impl ReferencePixels,
    inputs: &SceneInputs,
    ids: &IdFrame,
    other: &Method,
) -> ErrorStats {
    let lighting = inputs.lighting();
    let twin = reference.ref_pixels().enumerate().map(|(i, t)| {
        let t = t?;
        let s = twin_at(inputs, &lighting, ids, other, i);
        Some(RefPixel {
            color: s.color,
            normal: s.normal,
            ..t
        })
    });
    scan(frame, has_normal, reference.len(), false, twin).stats()
}

/// `other` in f64 at pixel `i` of the id pass `ids` (a covered pixel).
pub(crate) fn twin_at(
    inputs: &SceneInputs,
    lighting: &Lighting,
    ids: &IdFrame,
    other: &Method,
    i: usize,
) -> Shaded {
    let w = ids.weights[i];
    let (x, y) = (i as u32 % ids.width, i as u32 / ids.width);
    let frag = inputs.fragment(
        (ids.prim[i] - 1) as usize,
        DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64),
        DVec2::new(x as f64 + 0.5, y as f64 + 0.5),
    );
    other.eval_f64(&frag, lighting)
}

/// One pass over the pixels against `truth(i)`; `store` keeps the per-pixel vectors (errors,
/// angles, maps) that percentiles, heatmaps and FLIP need, otherwise only the counts and sums.
fn scan(
    frame: &Frame,
    has_normal: bool,
    n: usize,
    store: bool,
    truth: impl Iterator<Item = Option<RefPixel>>,
) -> PixelErrors {
    let mut f = PixelErrors::empty(frame.width, has_normal, n, store);
    for (i, t) in truth.take(n).enumerate() {
        let xy = || [i as u32 % frame.width, i as u32 / frame.width];
        let c = &mut f.counts;
        let t = match classify(frame, has_normal, t.as_ref(), i) {
            PixelClass::Background => continue,
            PixelClass::CoverageMismatch => {
                c.coverage_mismatch += 1;
                continue;
            }
            PixelClass::IllConditioned { non_finite } => {
                c.ill_conditioned += 1;
                if non_finite {
                    c.non_finite += 1;
                    c.non_finite_ill_conditioned += 1;
                    f.first_non_finite.get_or_insert_with(xy);
                }
                continue;
            }
            PixelClass::NonFinite => {
                c.non_finite += 1;
                f.first_non_finite.get_or_insert_with(xy);
                continue;
            }
            PixelClass::Measured => match t {
                Some(t) => t,
                None => continue,
            },
        };
        f.counts.measured += 1;
        let col = d3(frame.color[i]);
        let d = col - t.color;
        let e = lum(col) - lum(t.color);
        f.sums[0] += e.abs();
        f.sums[1] = f.sums[1].max(e.abs());
        for k in 0..3 {
            f.channels[k].add(d[k]);
        }
        if store {
            f.measured[i] = true;
            f.signed[i] = e;
            f.ranks.add_abs(i, e.abs());
        }
        if let (true, Some(r)) = (has_normal, t.normal) {
            let nrm = d3(frame.normal[i]);
            let len = nrm.length();
            let cos = if len > 0.0 {
                (nrm.dot(r) / (len * r.length())).clamp(-1.0, 1.0)
            } else {
                -1.0
            };
            let a = cos.acos().to_degrees();
            f.sums[2] += a;
            f.sums[3] = f.sums[3].max(a);
            if store {
                f.angle[i] = a;
                f.has_angle[i] = true;
                f.ranks.angle.add(a);
            }
            f.max_len = f.max_len.max((len - 1.0).abs());
        }
    }
    f
}

/// Statistics of the signed per-pixel luminance error dI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntensityStats {
    pub mean_abs_error: f64,
    pub max_abs_error: f64,
    /// (x, y) of the first pixel with the largest |error| (the first non-finite pixel when there
    /// are any), `None` when there are no pixels.
    pub max_error_pixel: Option<[u32; 2]>,
    pub p50_abs_error: f64,
    pub p95_abs_error: f64,
    pub p99_abs_error: f64,
    pub rmse: f64,
    /// 10 log10(1 / MSE) with peak intensity 1; `None` (null) when the error is exactly 0;
    /// -inf (null in JSON) for a method with non-finite pixels.
    pub psnr_db: Option<f64>,
    /// `None` (null) for a method with non-finite pixels (a NaN is above any threshold).
    pub pixels_above_threshold: Option<usize>,
    pub fraction_above_threshold: f64,
}

impl IntensityStats {
    /// The statistics of a method with non-finite pixels: every error infinite (null in JSON),
    /// `at` the first non-finite pixel.
    pub fn non_finite(at: Option<[u32; 2]>) -> Self {
        let inf = f64::INFINITY;
        IntensityStats {
            mean_abs_error: inf,
            max_abs_error: inf,
            max_error_pixel: at,
            p50_abs_error: inf,
            p95_abs_error: inf,
            p99_abs_error: inf,
            rmse: inf,
            psnr_db: Some(-inf),
            pixels_above_threshold: None,
            fraction_above_threshold: inf,
        }
    }
}

/// Statistics of `errors`: (x, y, signed error) per pixel.
pub fn intensity_stats(
    errors: impl IntoIterator<Item = (u32, u32, f64)>,
    threshold: f64,
) -> IntensityStats {
    let errors = errors.into_iter();
    let capacity = errors.size_hint().1.unwrap_or(0);
    intensity_of(
        errors.map(|(x, y, e)| ([x, y], e)),
        capacity,
        threshold,
        |at| at,
    )
}

impl PixelErrors {
    /// [`intensity_stats`] of [`PixelErrors::errors`], the same statistics bit for bit (the same
    /// errors in the same order through the same operations), without an (x, y) per pixel
    /// (only the largest error's position is turned into one, at the end) and without a copy
    /// of the |dI|s: the scan counted the |dI|s into a [`RankHistogram`] and kept the running
    /// sums ([`Ranks`]); one pass over the map counts those above `threshold` and gathers the
    /// values of the percentiles' buckets.
    ///
    /// That pass skips the mask where it need not read it: the map holds +0 where a pixel is
    /// not measured, and when no measured |dI| shares +0's bucket (so that no percentile
    /// wants it: a wanted bucket has values) and the threshold is at least 0, the zeros of
    /// the other pixels change neither the count nor the values gathered.
    pub fn intensity_stats(&self, threshold: f64) -> IntensityStats {
        let w = self.width as usize;
        let (hist, mut above) = (&self.ranks.abs, 0);
        let ps = [50.0, 95.0, 99.0];
        let mut abs = |e: &f64| {
            let a = e.abs();
            above += usize::from(a > threshold);
            a
        };
        let p = if hist.is_empty() {
            [f64::NAN; 3]
        } else if hist.bucket_count(0.0) == 0 && threshold >= 0.0 {
            hist.percentiles(ps, self.signed.iter().map(abs))
        } else {
            let measured = self.measured.iter().zip(&self.signed).filter(|(&m, _)| m);
            hist.percentiles(ps, measured.map(|(_, e)| abs(e)))
        };
        let run = self.ranks.run;
        run.finish(hist.len(), p, above, |i| [(i % w) as u32, (i / w) as u32])
    }

    /// The nearest-rank percentile `p` of the normal angle errors: `percentile(&mut
    /// self.angles(), p)` bit for bit (the same values; the scan's [`RankHistogram`] of them
    /// and one pass over the map instead of a copy). NaN without any angle: an empty set has
    /// no percentile (null in JSON; a limit on it fails and says why).
    pub fn angle_percentile(&self, p: f64) -> f64 {
        if self.ranks.angle.is_empty() {
            return f64::NAN;
        }
        let angles = (self.angle.iter().zip(&self.has_angle))
            .filter(|(_, &h)| h)
            .map(|(&a, _)| a);
        self.ranks.angle.percentiles([p], angles)[0]
    }
}

/// The running sums of [`intensity_stats`] over |dI|, in the order the errors come.
#[derive(Debug, Clone, Copy)]
pub(super) struct Running<P> {
    sum: f64,
    sq: f64,
    max: f64,
    pub(super) max_at: Option<P>,
}

impl<P> Default for Running<P> {
    fn default() -> Self {
        Running {
            sum: 0.0,
            sq: 0.0,
            max: 0.0,
            max_at: None,
        }
    }
}

impl<P> Running<P> {
    /// Adds |dI| `a` at position `p`.
    #[inline]
    pub(super) fn add(&mut self, p: P, a: f64) {
        self.sum += a;
        self.sq += a * a;
        if self.max_at.is_none() || a > self.max {
            self.max = a;
            self.max_at = Some(p);
        }
    }

    /// The statistics of the `n` errors added, with their 50th, 95th and 99th percentiles
    /// `p`, `above` of them above the threshold; `at` turns the position of the largest
    /// |error| into (x, y).
    fn finish(
        self,
        n: usize,
        p: [f64; 3],
        above: usize,
        at: impl Fn(P) -> [u32; 2],
    ) -> IntensityStats {
        // No measured pixel: no error figure exists. NaN (JSON null), not 0, so that nothing
        // reads as "exact" and every limit fails (compare::exceeded also says why).
        let per = |x: f64| if n > 0 { x / n as f64 } else { f64::NAN };
        let mse = per(self.sq);
        IntensityStats {
            mean_abs_error: per(self.sum),
            max_abs_error: if n > 0 { self.max } else { f64::NAN },
            max_error_pixel: self.max_at.map(at),
            p50_abs_error: p[0],
            p95_abs_error: p[1],
            p99_abs_error: p[2],
            rmse: mse.sqrt(),
            psnr_db: (mse > 0.0).then(|| 10.0 * (1.0 / mse).log10()),
            pixels_above_threshold: Some(above),
            fraction_above_threshold: per(above as f64),
        }
    }
}

/// [`intensity_stats`] of `errors` (position, signed error) in their order; `at` turns the
/// position of the largest |error| into (x, y); `capacity`: how many errors, about.
fn intensity_of<P: Copy>(
    errors: impl Iterator<Item = (P, f64)>,
    capacity: usize,
    threshold: f64,
    at: impl Fn(P) -> [u32; 2],
) -> IntensityStats {
    let mut abs: Vec<f64> = Vec::with_capacity(capacity);
    let (mut run, mut above) = (Running::default(), 0);
    for (p, e) in errors {
        let a = e.abs();
        abs.push(a);
        run.add(p, a);
        above += usize::from(a > threshold);
    }
    let n = abs.len();
    let p = if n > 0 {
        percentiles(&mut abs, [50.0, 95.0, 99.0])
    } else {
        [f64::NAN; 3]
    };
    run.finish(n, p, above, at)
}

/// Per-channel statistics of the signed R, G or B error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelStats {
    pub mean_abs_error: f64,
    pub max_abs_error: f64,
    pub rmse: f64,
}

pub(crate) fn lum(c: DVec3) -> f64 {
    LUMINANCE[0] * c.x + LUMINANCE[1] * c.y + LUMINANCE[2] * c.z
}

pub(crate) fn d3(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

/// Statistics of one channel's signed errors (all infinite when `non_finite`).
/// Running sums of one channel's signed error over the measured pixels.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChannelSums {
    pub n: usize,
    pub sum_abs: f64,
    pub sum_sq: f64,
    pub max_abs: f64,
}

impl ChannelSums {
    /// Adds one pixel's signed error.
    pub fn add(&mut self, e: f64) {
        self.n += 1;
        self.add_but_count(e);
    }

    /// [`ChannelSums::add`] but for `n` (the scan of [`crate::analysis::scan`] sets it once).
    #[inline]
    pub(crate) fn add_but_count(&mut self, e: f64) {
        self.sum_abs += e.abs();
        self.sum_sq += e * e;
        self.max_abs = self.max_abs.max(e.abs());
    }
}

pub(crate) fn channel_stats(v: &ChannelSums, non_finite: bool) -> ChannelStats {
    if non_finite {
        let inf = f64::INFINITY;
        return ChannelStats {
            mean_abs_error: inf,
            max_abs_error: inf,
            rmse: inf,
        };
    }
    // No measured pixel: an empty set has no mean, maximum or RMS (NaN, null in JSON), never
    // the 0 of an exact match.
    if v.n == 0 {
        let nan = f64::NAN;
        return ChannelStats {
            mean_abs_error: nan,
            max_abs_error: nan,
            rmse: nan,
        };
    }
    let n = v.n as f64;
    ChannelStats {
        mean_abs_error: v.sum_abs / n,
        max_abs_error: v.max_abs,
        rmse: (v.sum_sq / n).sqrt(),
    }
}
