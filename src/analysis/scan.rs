//! The scan of [`crate::analysis::pixel`] over a reference kept as columns ([`Values`], the
//! slerp [`Twin`]): `compare`'s path, once per method over every pixel.
//!
//! It is the generic scan (`pixel::scan` over `Option<RefPixel>`s, `verify`'s path and this
//! one's oracle in the tests) with the same f64 operations in the same order per pixel, and
//! with what depends on the reference alone computed once per run ([`Constants`]): the
//! reference's luminance `lum(t.color)`, its normal's length `t.normal.length()` (the very
//! same expressions, evaluated once instead of once per method) and whether its values are
//! finite. The classes of the pixels are those of [`crate::analysis::pixel::classify`],
//! decided from the columns without building a `RefPixel`.
use glam::DVec3;

use crate::analysis::pixel::{d3, lum, twin_at, ErrorStats, PixelErrors, ReferencePixels};
use crate::analysis::stats::RankHistogram;
use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::method::Method;
use crate::scene::SceneInputs;
use crate::truth::{RefPixel, Values};

/// Per covered pixel of a reference, what the scan would otherwise compute for every method.
#[derive(Debug, Clone)]
pub(crate) struct Constants {
    /// `lum(color)`.
    lum: Vec<f64>,
    /// `normal.length()` (0 where there is no normal).
    normal_len: Vec<f64>,
    /// The colour is finite, and so is the normal where there is one.
    finite: Vec<bool>,
}

impl Constants {
    /// The constants of the columns `color` and `normal` (`has_normal(k)`: whether covered
    /// pixel k has a normal).
    pub(crate) fn new(
        color: &[DVec3],
        normal: &[DVec3],
        has_normal: impl Fn(usize) -> bool,
    ) -> Self {
        let finite = (0..color.len())
            .map(|k| color[k].is_finite() && (!has_normal(k) || normal[k].is_finite()))
            .collect();
        Constants {
            lum: color.iter().map(|&c| lum(c)).collect(),
            normal_len: normal.iter().map(|n| n.length()).collect(),
            finite,
        }
    }
}

/// A reference as the scan reads it: which pixels it covers and, per covered pixel in pixel
/// order, its colour, normal and [`Constants`]; `has_normal(k)` and `ill_conditioned(k)` of
/// covered pixel k.
pub(crate) struct Columns<'a, H, I> {
    pub covered: &'a [bool],
    pub color: &'a [DVec3],
    pub normal: &'a [DVec3],
    pub constants: &'a Constants,
    pub has_normal: H,
    pub ill_conditioned: I,
}

/// [`Values`] with its [`Constants`]: the reference of a `compare` run, prepared once for the
/// statistics of every method. [`crate::analysis::pixel::pixel_errors`] against it gives the
/// same errors as against the `Values` themselves, bit for bit, in one pass over the columns.
#[derive(Debug, Clone)]
pub struct Prepared<'a> {
    values: &'a Values,
    constants: Constants,
}

impl<'a> Prepared<'a> {
    /// Computes the constants of `values` (one pass over its covered pixels).
    pub fn new(values: &'a Values) -> Self {
        let constants = Constants::new(values.colors(), values.normals(), |k| values.has_normal(k));
        Prepared { values, constants }
    }

    /// The values it was prepared from.
    pub fn values(&self) -> &'a Values {
        self.values
    }
}

impl ReferencePixels for Prepared<'_> {
    fn len(&self) -> usize {
        self.values.len()
    }
    fn ref_pixels(&self) -> impl Iterator<Item = Option<RefPixel>> + '_ {
        self.values.pixels()
    }
    fn pixel_errors(&self, frame: &Frame, has_normal: bool) -> PixelErrors {
        let v = self.values;
        let columns = Columns {
            covered: v.covered(),
            color: v.colors(),
            normal: v.normals(),
            constants: &self.constants,
            has_normal: |k| v.has_normal(k),
            ill_conditioned: |k| v.ill_conditioned(k),
        };
        scan_columns::<true, _, _>(frame, has_normal, &columns)
    }
}

/// Another method's f64 twin (`compare`: exact slerp along the span) at every pixel an id pass
/// covers, evaluated once per run and kept for every method judged against it (seven of the
/// built-in methods), where [`crate::analysis::pixel::stats_against_twin`] evaluates it again for each: 49 bytes per
/// covered pixel and 17 of scan constants (about 49 MB at 1024x1024 on the fine sphere). The values are those
/// `stats_against_twin` computes (the same function of the same fragment), so
/// [`Twin::stats`] gives its statistics bit for bit.
#[derive(Debug, Clone)]
pub struct Twin {
    /// Per covered pixel of the reference, in pixel order.
    color: Vec<DVec3>,
    /// Per covered pixel: the normal where `has_normal`, zero elsewhere.
    normal: Vec<DVec3>,
    has_normal: Vec<bool>,
    /// What the scan reads per covered pixel of the twin, computed once ([`Constants`]).
    constants: Constants,
    /// Pixels of the reference, covered or not.
    len: usize,
}

impl Twin {
    /// `other` at every pixel the id pass `ids` covers: the pixels its truth covers.
    pub fn new(inputs: &SceneInputs, ids: &IdFrame, other: &Method) -> Twin {
        let lighting = inputs.lighting();
        let covered = ids.covered();
        let (mut color, mut normal, mut has_normal) = (
            Vec::with_capacity(covered),
            Vec::with_capacity(covered),
            Vec::with_capacity(covered),
        );
        for (i, &prim) in ids.prim.iter().enumerate() {
            if prim != 0 {
                let s = twin_at(inputs, &lighting, ids, other, i);
                color.push(s.color);
                normal.push(s.normal.unwrap_or(DVec3::ZERO));
                has_normal.push(s.normal.is_some());
            }
        }
        let constants = Constants::new(&color, &normal, |k| has_normal[k]);
        Twin {
            color,
            normal,
            has_normal,
            constants,
            len: ids.prim.len(),
        }
    }

    /// [`crate::analysis::pixel::stats_against_twin`] of `frame` against this twin (bit for bit: the scan of
    /// [`crate::analysis::scan`] over the twin's columns); `reference` is the truth of the same
    /// id pass (an error if it covers other pixels than the twin: a different size or covered
    /// count).
    pub fn stats(&self, frame: &Frame, has_normal: bool, reference: &Values) -> Result<ErrorStats> {
        if reference.len() != self.len {
            return Err(Error::Internal(format!(
                "a twin of {} pixels against a reference of {}",
                self.len,
                reference.len()
            )));
        }
        if reference.colors().len() != self.color.len() {
            return Err(Error::Internal(format!(
                "a twin of {} covered pixels against a reference covering {}",
                self.color.len(),
                reference.colors().len()
            )));
        }
        let columns = Columns {
            covered: reference.covered(),
            color: &self.color,
            normal: &self.normal,
            constants: &self.constants,
            has_normal: |k| self.has_normal[k],
            ill_conditioned: |k| reference.ill_conditioned(k),
        };
        Ok(scan_columns::<false, _, _>(frame, has_normal, &columns).stats())
    }
}

/// Whether the R, G and B of `v` are finite: `d3(v).is_finite()` (f32 -> f64 keeps finiteness).
#[inline]
fn finite3(v: [f32; 4]) -> bool {
    v[0].is_finite() && v[1].is_finite() && v[2].is_finite()
}

/// Pixels per block of [`scan_columns`]: the cosines of a block's normal angles wait in a
/// buffer of this size ([`Cosines`], 28 KB on the stack, and 8 KB more while it drains) for
/// their `acos`, and the block's |dI|s (8 KB) for their histogram.
const BLOCK: usize = 1024;

/// The normal angles of one block, waiting for their `acos`, in pixel order: per angle the
/// dot products `nrm.dot(r)` and `nrm.dot(nrm)` of the method's normal `nrm` and the
/// reference's `r`, `r.length()`, and the pixel.
struct Cosines {
    dot: [f64; BLOCK],
    square: [f64; BLOCK],
    ref_len: [f64; BLOCK],
    at: [u32; BLOCK],
    len: usize,
}

impl Cosines {
    /// Queues one pixel's angle.
    #[inline]
    fn push(&mut self, dot: f64, square: f64, ref_len: f64, at: usize) {
        let j = self.len;
        (self.dot[j], self.square[j], self.ref_len[j]) = (dot, square, ref_len);
        self.at[j] = at as u32;
        self.len += 1;
    }

    /// The queued angles in order: `len = square.sqrt()` (glam's `length`), the clamped
    /// cosine `dot / (len * ref_len)` (-1 at length 0), `acos().to_degrees()` into the angle's
    /// running sum and max (`sums[2]`, `sums[3]`) and into `maps` when given (the scan's
    /// per-pixel vectors: the angle map, the has-angle mask and the angles' histogram);
    /// `|len - 1|` into `max_len`. Then empties. The lengths and
    /// cosines in a loop of their own, which vectorises (the same IEEE sqrt and division per
    /// lane), the `acos` calls in a tight loop apart from the scan: the scan's loop has no
    /// call in it, so its accumulators stay in registers.
    fn drain(&mut self, sums: &mut [f64; 4], max_len: &mut f64, mut maps: Option<AngleMaps>) {
        let m = self.len;
        let mut len_error = [0.0f64; BLOCK];
        // in place: `dot` becomes the clamped cosine
        cosines(
            &mut self.dot[..m],
            &self.square[..m],
            &self.ref_len[..m],
            &mut len_error[..m],
        );
        // each cosine becomes its angle, for the histogram after the calls
        let angles = self.dot[..m].iter_mut().zip(&len_error[..m]);
        for ((cos, &len_error), &at) in angles.zip(&self.at[..m]) {
            *max_len = max_len.max(len_error);
            let a = cos.acos().to_degrees();
            *cos = a;
            sums[2] += a;
            sums[3] = sums[3].max(a);
            if let Some((angle, has_angle, _)) = &mut maps {
                angle[at as usize] = a;
                has_angle[at as usize] = true;
            }
        }
        if let Some((_, _, hist)) = maps {
            hist.add_all(&self.dot[..m]);
        }
        self.len = 0;
    }
}

/// What [`Cosines::drain`] writes besides the sums: [`PixelErrors`]' angle map, has-angle mask
/// and histogram of the angles.
type AngleMaps<'a> = (&'a mut [f64], &'a mut [bool], &'a mut RankHistogram);

/// Per queued angle ([`Cosines::drain`]): `dot` becomes the clamped cosine, `len_error`
/// `|len - 1|`; the expressions of `pixel::scan` on the same values. Compiled for AVX2 too
/// and chosen at run time (no FMA: the same bits).
#[multiversion::multiversion(targets("x86_64+avx2"))]
fn cosines(dot: &mut [f64], square: &[f64], ref_len: &[f64], len_error: &mut [f64]) {
    let n = dot.len();
    let (square, ref_len, len_error) = (&square[..n], &ref_len[..n], &mut len_error[..n]);
    for j in 0..n {
        let len = square[j].sqrt();
        dot[j] = if len > 0.0 {
            (dot[j] / (len * ref_len[j])).clamp(-1.0, 1.0)
        } else {
            -1.0
        };
        len_error[j] = (len - 1.0).abs();
    }
}

/// The generic scan (`pixel::scan`) of `frame` against the reference `r`, from its columns:
/// the same classes, the same operations per measured pixel in the same order, the same
/// [`PixelErrors`]; `STORE`: keep the per-pixel vectors (a constant: the scan without them,
/// the slerp twin's, has no branch on it).
///
/// The pixels go in blocks of [`BLOCK`]: per block, every statistic but the normal angle, and
/// the angle's clamped cosine into [`Cosines`]; then the block's `acos`s in pixel order
/// ([`Cosines::drain`]). The angle's sum and max see the same angles in the same order as in
/// the generic scan, every other accumulator the same values in the same order: the same bits.
pub(crate) fn scan_columns<const STORE: bool, H, I>(
    frame: &Frame,
    has_normal: bool,
    r: &Columns<'_, H, I>,
) -> PixelErrors
where
    H: Fn(usize) -> bool,
    I: Fn(usize) -> bool,
{
    let store = STORE;
    let n = r.covered.len();
    assert!(n <= u32::MAX as usize, "pixel index of {n} pixels in a u32");
    let mut f = PixelErrors::empty(frame.width, has_normal, n, store);
    let c = r.constants;
    let (mut sums, mut max_len) = ([0.0f64; 4], 0.0f64);
    let mut channels = f.channels;
    let mut counts = f.counts;
    // with `store`: |dI|'s running sums, and the block's |dI|s for its histogram (f.ranks.abs)
    let (mut run, mut abs, mut abs_len) = (f.ranks.run, [0.0f64; BLOCK], 0);
    let mut cosines = Cosines {
        dot: [0.0; BLOCK],
        square: [0.0; BLOCK],
        ref_len: [0.0; BLOCK],
        at: [0; BLOCK],
        len: 0,
    };
    let mut k = 0; // the covered pixel's index in the columns
    for start in (0..n).step_by(BLOCK) {
        let end = n.min(start + BLOCK);
        let block = frame.color[start..end].iter().zip(&r.covered[start..end]);
        for (i, (&color, &covered)) in (start..).zip(block) {
            let here = color[3] > 0.0;
            if !covered {
                counts.coverage_mismatch += usize::from(here);
                continue;
            }
            let t = k;
            k += 1;
            if !here {
                counts.coverage_mismatch += 1;
                continue;
            }
            let non_finite = !finite3(color) || (has_normal && !finite3(frame.normal[i]));
            let meaningful = !(r.ill_conditioned)(t) && c.finite[t];
            if !meaningful || non_finite {
                if meaningful {
                    counts.non_finite += 1;
                } else {
                    counts.ill_conditioned += 1;
                    counts.non_finite += usize::from(non_finite);
                    counts.non_finite_ill_conditioned += usize::from(non_finite);
                }
                if non_finite && f.first_non_finite.is_none() {
                    f.first_non_finite = Some([i as u32 % frame.width, i as u32 / frame.width]);
                }
                continue;
            }
            counts.measured += 1;
            let col = d3(color);
            let d = col - r.color[t];
            let e = lum(col) - c.lum[t];
            sums[0] += e.abs();
            sums[1] = sums[1].max(e.abs());
            for j in 0..3 {
                channels[j].add_but_count(d[j]);
            }
            if store {
                f.measured[i] = true;
                f.signed[i] = e;
                abs[abs_len] = e.abs();
                abs_len += 1;
                run.add(i, e.abs());
            }
            if has_normal && (r.has_normal)(t) {
                let nrm = d3(frame.normal[i]);
                cosines.push(nrm.dot(r.normal[t]), nrm.dot(nrm), c.normal_len[t], i);
            }
        }
        f.ranks.abs.add_all(&abs[..abs_len]);
        abs_len = 0;
        let maps = store.then_some((&mut f.angle[..], &mut f.has_angle[..], &mut f.ranks.angle));
        cosines.drain(&mut sums, &mut max_len, maps);
    }
    // every channel counts the measured pixels
    channels.iter_mut().for_each(|c| c.n = counts.measured);
    (f.sums, f.max_len, f.channels, f.counts) = (sums, max_len, channels, counts);
    f.ranks.run = run;
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::pixel::{intensity_stats, pixel_errors, Running};
    use crate::analysis::stats::{percentile, RankHistogram};
    use crate::truth::{Truth, TruthPixel};

    /// A reference and a frame of `n` pixels with every class of pixel and every kind of value
    /// a scan meets: background on either side, ill-conditioned references, non-finite colours
    /// and normals on either side, missing, zero and signed-zero normals, ties.
    fn random_case(rng: &mut fastrand::Rng, n: usize) -> (Truth, Frame) {
        let value = |rng: &mut fastrand::Rng| match rng.u32(0..20) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => -0.0,
            3 => 0.5,
            _ => rng.f64() * 2.0 - 0.5,
        };
        let vec3 = |rng: &mut fastrand::Rng| DVec3::new(value(rng), value(rng), value(rng));
        let mut pixels = Vec::with_capacity(n);
        let mut color = Vec::with_capacity(n);
        let mut normal = Vec::with_capacity(n);
        for _ in 0..n {
            pixels.push(rng.bool().then(|| TruthPixel {
                color: vec3(rng),
                normal: match rng.u32(0..4) {
                    0 => None,
                    1 => Some(DVec3::ZERO),
                    _ => Some(vec3(rng)),
                },
                color_bound: f64::NAN,
                normal_bound: f64::NAN,
                // 1e9: ill-conditioned (values.rs's test)
                amplification: if rng.u32(0..5) == 0 { 1e9 } else { 1.0 },
            }));
            let c = vec3(rng);
            let alpha = if rng.u32(0..4) == 0 { 0.0 } else { 1.0 };
            color.push([c.x as f32, c.y as f32, c.z as f32, alpha]);
            let m = if rng.u32(0..6) == 0 {
                DVec3::ZERO
            } else {
                vec3(rng)
            };
            normal.push([m.x as f32, m.y as f32, m.z as f32, 1.0]);
        }
        let (width, height) = (7, (n as u32).div_ceil(7));
        let truth = Truth {
            width,
            height,
            pixels,
        };
        let frame = Frame {
            width,
            height,
            color,
            normal,
        };
        (truth, frame)
    }

    /// The scan over the columns gives the generic scan's errors (over the same `Values`, and
    /// over the `Truth` they come from) bit for bit: every count, sum, per-pixel vector and the
    /// first non-finite pixel, with and without normals, on random references and frames.
    /// `intensity_stats` and `angle_percentile` of those errors (from the maps) equal the
    /// generic `intensity_stats` of `errors()` and `percentile` of a copy of `angles()`.
    /// The histograms of |dI| and of the angles that the scan counts ([`PixelErrors`]' `ranks`)
    /// equal those of the maps' values.
    /// Teeth: a constant 2^20 ulps off, or a pixel's finiteness flipped, shows in the errors;
    /// a histogram one value short differs, and so do the statistics of a largest |dI| moved.
    #[test]
    fn the_column_scan_gives_the_generic_errors() {
        let mut rng = fastrand::Rng::with_seed(27);
        let (mut measured_cases, mut perturbed_differ, mut ranks_differ) = (0, [0, 0], [0, 0]);
        let mut mask_needed = [0, 0];
        for round in 0..200 {
            // 2500: more than two blocks of `BLOCK` pixels
            let n = [0, 1, 2, 7, 63, 700, 2500][round % 7];
            let (truth, frame) = random_case(&mut rng, n);
            let values = Values::from(&truth);
            for has_normal in [true, false] {
                let generic = format!("{:?}", pixel_errors(&frame, has_normal, &values));
                let over_truth = format!("{:?}", pixel_errors(&frame, has_normal, &truth));
                let mut prepared = Prepared::new(&values);
                let columns = format!("{:?}", pixel_errors(&frame, has_normal, &prepared));
                assert_eq!(columns, generic, "round {round}, normals {has_normal}");
                assert_eq!(over_truth, generic, "round {round}");
                // teeth, on the first measured pixel (if any)
                let errors = pixel_errors(&frame, has_normal, &prepared);
                // the percentiles from the maps (RankHistogram) against a copy's selection
                for p in [0.0, 50.0, 99.0, 100.0] {
                    // an empty set has no percentile: NaN (null in JSON)
                    let mut angles = errors.angles();
                    let want = if angles.is_empty() {
                        f64::NAN
                    } else {
                        percentile(&mut angles, p)
                    };
                    assert_eq!(errors.angle_percentile(p).to_bits(), want.to_bits());
                }
                // thresholds that skip the mask and that read it; then with exact zeros measured
                // (every third measured pixel), which make the mask needed
                let mut zeros = errors.clone();
                let (mut hist, mut run) = (RankHistogram::default(), Running::default());
                for (j, i) in (0..n).filter(|&i| zeros.measured[i]).enumerate() {
                    if j % 3 == 0 {
                        zeros.signed[i] = 0.0;
                    }
                    hist.add(zeros.signed[i].abs());
                    run.add(i, zeros.signed[i].abs());
                }
                (zeros.ranks.abs, zeros.ranks.run) = (hist, run);
                for e in [&errors, &zeros] {
                    for t in [0.1, 0.0, -1.0, f64::NAN] {
                        let want = intensity_stats(e.errors(), t);
                        assert_eq!(format!("{:?}", e.intensity_stats(t)), format!("{want:?}"));
                    }
                }
                // teeth: with zeros measured, the whole map's zeros are not the measured ones
                if zeros.counts.measured > 0 && zeros.counts.measured < n {
                    let all = zeros.signed.iter().map(|e| e.abs());
                    let h = &zeros.ranks.abs;
                    let r = std::panic::catch_unwind(|| h.percentiles([0.0], all));
                    mask_needed[0] += 1;
                    mask_needed[1] += usize::from(r.is_err());
                }
                // the histograms the scan counted are those of the maps' values
                let (mut abs, mut angle) = (RankHistogram::default(), RankHistogram::default());
                errors.errors().for_each(|(_, _, e)| abs.add(e.abs()));
                errors.angles().into_iter().for_each(|a| angle.add(a));
                assert!(errors.ranks.abs == abs && errors.ranks.angle == angle);
                let Some(i) = errors.measured.iter().position(|&m| m) else {
                    continue;
                };
                measured_cases += 1;
                // teeth: a histogram one value short, or the largest |dI| at the next pixel
                let mut short = RankHistogram::default();
                errors
                    .errors()
                    .skip(1)
                    .for_each(|(_, _, e)| short.add(e.abs()));
                ranks_differ[0] += usize::from(short != errors.ranks.abs);
                let mut off = errors.clone();
                off.ranks.run.max_at = off.ranks.run.max_at.map(|i| i + 1);
                let (a, b) = (off.intensity_stats(0.1), errors.intensity_stats(0.1));
                ranks_differ[1] += usize::from(format!("{a:?}") != format!("{b:?}"));
                let k = values.covered()[..i].iter().filter(|&&c| c).count();
                let c = &mut prepared.constants;
                c.lum[k] = f64::from_bits(c.lum[k].to_bits() + (1 << 20));
                let ulp = format!("{:?}", pixel_errors(&frame, has_normal, &prepared));
                perturbed_differ[0] += usize::from(ulp != generic);
                prepared.constants.finite[k] = false;
                let flag = format!("{:?}", pixel_errors(&frame, has_normal, &prepared));
                perturbed_differ[1] += usize::from(flag != generic);
            }
        }
        // most of the 400 cases measure a pixel; the flag changes every one of them, the ulps
        // nearly all (dI = lum(col) - lum rounds them away where |lum| << |dI|)
        assert!(measured_cases > 100, "{measured_cases}");
        assert_eq!(perturbed_differ[1], measured_cases);
        assert_eq!(ranks_differ, [measured_cases; 2]);
        assert!(
            mask_needed[0] > 100 && mask_needed[1] == mask_needed[0],
            "{mask_needed:?}"
        );
        assert!(
            perturbed_differ[0] * 10 > measured_cases * 9,
            "{perturbed_differ:?}"
        );
    }
}
