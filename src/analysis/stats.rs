//! Statistics: percentiles, the median with a distribution-free 95% interval, paired ratios
//! with the same interval, the Pareto front over paired times, least squares.
use serde::Serialize;

/// Nearest-rank percentile of `values` (unsorted; reordered in place): the smallest value such
/// that at least `p` percent of the values are at most it, in the order of `f64::total_cmp`.
/// 0 for an empty slice.
pub fn percentile(values: &mut [f64], p: f64) -> f64 {
    percentiles(values, [p])[0]
}

/// Counts of `values` over the bins of `edges` (ascending): (lower edge, upper edge, count),
/// each bin [a, b) and the last one closed.
pub fn histogram(values: &[f64], edges: &[f64]) -> Vec<(f64, f64, usize)> {
    edges
        .windows(2)
        .enumerate()
        .map(|(i, e)| {
            let last = i + 2 == edges.len();
            let n = values
                .iter()
                .filter(|&&x| x >= e[0] && (x < e[1] || (last && x <= e[1])))
                .count();
            (e[0], e[1], n)
        })
        .collect()
}

/// The 0-based index of the nearest-rank `p` percentile among `n` > 0 sorted values.
pub(crate) fn rank_index(n: usize, p: f64) -> usize {
    let rank = ((p / 100.0) * n as f64).ceil().max(1.0) as usize;
    rank.min(n) - 1
}

/// Turns each f64 into its key of `f64::total_cmp` (the same bit flip std's `total_cmp` makes
/// on both sides of every comparison: the bits as i64, the 63 low bits inverted when the sign
/// bit is set), in place; the integer order of the keys is the order of `total_cmp`. The flip
/// is its own inverse: applied twice it gives back the same bits.
fn flip_total_order_keys(keys: &mut [i64]) {
    for k in keys {
        *k = total_order_flip(*k);
    }
}

/// One key of [`flip_total_order_keys`]: the 63 low bits of `b` inverted when its sign bit is
/// set (its own inverse).
#[inline]
fn total_order_flip(b: i64) -> i64 {
    b ^ (((b >> 63) as u64) >> 1) as i64
}

/// [`percentile`] of `values` at each of `ps` (nearest rank in the order of `f64::total_cmp`),
/// selected on the integer keys of that order: `values` are turned into their keys in place,
/// each selection after the first runs over the part at or above the previous one only (after
/// selecting index k, `keys[..k]` are all at most `keys[k..]`, so the k'-th smallest for k' >= k
/// is the (k' - k)-th of `keys[k..]`; a rank below the previous one selects over the whole
/// slice again), and the keys are turned back. Keys are equal only for equal bits, so the k-th
/// smallest value is the same bits however it is found. 0 for each when `values` is empty.
pub fn percentiles<const N: usize>(values: &mut [f64], ps: [f64; N]) -> [f64; N] {
    let keys: &mut [i64] = bytemuck::cast_slice_mut(values);
    flip_total_order_keys(keys);
    let mut lo = 0;
    let out = ps.map(|p| {
        if keys.is_empty() {
            return 0.0;
        }
        let k = rank_index(keys.len(), p);
        if k < lo {
            lo = 0;
        }
        let mut v = [*keys[lo..].select_nth_unstable(k - lo).1];
        lo = k;
        flip_total_order_keys(&mut v);
        f64::from_bits(v[0] as u64)
    });
    flip_total_order_keys(keys);
    out
}

/// The key of `x` in the order of `f64::total_cmp` as a u64 (its unsigned order is that order):
/// the key of [`flip_total_order_keys`] with the sign bit turned over.
#[inline]
fn total_key(x: f64) -> u64 {
    total_order_flip(x.to_bits() as i64) as u64 ^ (1 << 63)
}

/// The f64 of a [`total_key`].
fn from_total_key(k: u64) -> f64 {
    f64::from_bits(total_order_flip((k ^ (1 << 63)) as i64) as u64)
}

/// Bits of a [`total_key`] below its bucket in a [`RankHistogram`]: 2^16 buckets, the sign,
/// the exponent and 4 bits of the mantissa (16 buckets per octave).
const BUCKET_SHIFT: u32 = 48;

/// Values counted per bucket of their [`total_key`], for nearest-rank percentiles without a
/// copy of the values: [`RankHistogram::percentiles`] finds the bucket each rank falls into
/// and, in a second pass over the same values, selects among the values of those buckets
/// only. The k-th smallest key is the same bits however it is found, so the result is
/// [`percentiles`]'s bit for bit (tested against it).
#[derive(Clone, PartialEq)]
pub struct RankHistogram {
    counts: Vec<u32>,
    n: usize,
}

impl Default for RankHistogram {
    fn default() -> Self {
        RankHistogram {
            counts: vec![0; 1 << (64 - BUCKET_SHIFT)],
            n: 0,
        }
    }
}

/// The count and the non-empty buckets (bucket, count), not 2^16 numbers.
impl std::fmt::Debug for RankHistogram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let buckets = (self.counts.iter().enumerate()).filter(|(_, &c)| c != 0);
        f.debug_struct("RankHistogram")
            .field("n", &self.n)
            .field("buckets", &buckets.collect::<Vec<_>>())
            .finish()
    }
}

impl RankHistogram {
    /// Counts `x`.
    #[inline]
    pub fn add(&mut self, x: f64) {
        self.counts[(total_key(x) >> BUCKET_SHIFT) as usize] += 1;
        self.n += 1;
    }

    /// Counts every value of `xs` (`add` of each, in a loop of its own: the scan of
    /// [`crate::analysis::scan`] counts a block of values at a time).
    pub fn add_all(&mut self, xs: &[f64]) {
        let counts: &mut [u32; 1 << (64 - BUCKET_SHIFT)] =
            (&mut self.counts[..]).try_into().expect("2^16 buckets");
        for &x in xs {
            counts[(total_key(x) >> BUCKET_SHIFT) as usize] += 1;
        }
        self.n += xs.len();
    }

    /// How many counted values share the bucket of `x`.
    pub fn bucket_count(&self, x: f64) -> usize {
        self.counts[(total_key(x) >> BUCKET_SHIFT) as usize] as usize
    }

    /// How many values were counted.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether no value was counted.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// [`percentiles`] of the counted values at each of `ps`; `values` must yield the counted
    /// values again (in any order; panics when a wanted bucket comes out short). 0 for each
    /// when nothing was counted.
    pub fn percentiles<const N: usize>(
        &self,
        ps: [f64; N],
        values: impl Iterator<Item = f64>,
    ) -> [f64; N] {
        if self.n == 0 {
            return [0.0; N];
        }
        // per percentile: its bucket and its rank among that bucket's values
        let wanted = ps.map(|p| {
            let mut k = rank_index(self.n, p);
            let mut b = 0;
            while k >= self.counts[b] as usize {
                k -= self.counts[b] as usize;
                b += 1;
            }
            (b, k)
        });
        // slot[b]: 1 + the index of bucket b's list among the wanted ones, 0 if not wanted
        let mut slot = vec![0u8; self.counts.len()];
        let mut lists: Vec<Vec<u64>> = Vec::with_capacity(N);
        for &(b, _) in &wanted {
            if slot[b] == 0 {
                lists.push(Vec::with_capacity(self.counts[b] as usize));
                slot[b] = lists.len() as u8;
            }
        }
        for x in values {
            let key = total_key(x);
            let s = slot[(key >> BUCKET_SHIFT) as usize];
            if s != 0 {
                lists[s as usize - 1].push(key);
            }
        }
        wanted.map(|(b, k)| {
            let list = &mut lists[slot[b] as usize - 1];
            assert_eq!(list.len(), self.counts[b] as usize, "values differ");
            from_total_key(*list.select_nth_unstable(k).1)
        })
    }
}

/// A median with its 95% confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    pub median: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    pub samples: usize,
    /// The exact coverage of `[ci95_low, ci95_high]` for a continuous distribution:
    /// 1 - 2 P(Bin(n, 1/2) < l). At least 0.95 from 6 samples on; below that the interval is
    /// [min, max] and covers less (5 samples: 0.9375; 1 sample: 0).
    pub confidence: f64,
}

/// P(X <= k) for X ~ Binomial(n, 1/2).
pub(crate) fn binomial_half_cdf(n: usize, k: usize) -> f64 {
    // log C(n, i) iteratively; exact enough for n up to millions.
    let mut log_c = 0.0f64;
    let mut sum = 0.0;
    let log_half_n = n as f64 * 0.5f64.ln();
    for i in 0..=k.min(n) {
        if i > 0 {
            log_c += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        sum += (log_c + log_half_n).exp();
    }
    sum.min(1.0)
}

/// The 1-based rank l of the sign-test interval of the median of n samples: the largest l
/// with P(Bin(n, 1/2) < l) <= 2.5 %; 0 when none exists (n < 6).
pub(crate) fn sign_test_rank(n: usize) -> usize {
    let mut l = 0usize;
    for k in 1..=n / 2 {
        if binomial_half_cdf(n, k - 1) <= 0.025 {
            l = k;
        } else {
            break;
        }
    }
    l
}

/// The coverage of [x(l), x(n+1-l)] (l = 0 read as 1: [min, max]) for the median of a
/// continuous distribution: 1 - 2 P(Bin(n, 1/2) <= l - 1). 0 for n = 0.
pub fn order_statistic_confidence(n: usize, l: usize) -> f64 {
    if n == 0 {
        return 0.0;
    }
    (1.0 - 2.0 * binomial_half_cdf(n, l.max(1) - 1)).max(0.0)
}

/// Median and distribution-free 95% confidence interval from order statistics (the interval
/// that inverts the sign test): [x(l), x(n+1-l)] (1-based, sorted) with l the largest rank
/// such that P(Bin(n, 1/2) < l) <= 2.5 %. With fewer than 6 samples no such rank exists and the
/// interval is [min, max], whose coverage `confidence` states. Non-finite samples are left
/// out (count them with [`non_finite`] where that matters).
pub fn median_ci(samples: &[f64]) -> Estimate {
    let mut v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return Estimate {
            median: f64::NAN,
            ci95_low: f64::NAN,
            ci95_high: f64::NAN,
            samples: 0,
            confidence: 0.0,
        };
    }
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    let l = sign_test_rank(n); // 1-based rank; 0 = none
    let (lo, hi) = if l == 0 {
        (v[0], v[n - 1])
    } else {
        (v[l - 1], v[n - l])
    };
    Estimate {
        median,
        ci95_low: lo,
        ci95_high: hi,
        samples: n,
        confidence: order_statistic_confidence(n, l),
    }
}

/// The number of non-finite values (NaN, +-inf) in `v`.
pub fn non_finite(v: &[f64]) -> usize {
    v.iter().filter(|x| !x.is_finite()).count()
}

/// The median of paired ratios `num[r] / den[r]` (one per round) with its sign-test 95%
/// interval. A round whose ratio is not a finite number (a non-finite time, or a denominator
/// at or below zero) is counted in `non_finite` and left out of the median, never sorted in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RatioEstimate {
    pub median: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    /// Rounds with a finite ratio (the sample size of the interval).
    pub rounds: usize,
    /// Rounds whose ratio could not be formed.
    pub non_finite: usize,
    /// Exact coverage of the interval (see [`Estimate::confidence`]).
    pub confidence: f64,
}

impl RatioEstimate {
    /// The larger distance from the median to an end of the interval, in percent of the
    /// median (the "+-" of the interval); NaN when there is no finite ratio.
    pub fn half_width_pct(&self) -> f64 {
        if self.rounds == 0 || self.median <= 0.0 {
            return f64::NAN;
        }
        (self.median - self.ci95_low).max(self.ci95_high - self.median) / self.median * 100.0
    }
}

/// Paired ratios of two series of the same rounds (`num` and `den` the same length; the
/// shorter one decides). See [`RatioEstimate`].
pub fn paired_ratio(num: &[f64], den: &[f64]) -> RatioEstimate {
    let ratios: Vec<f64> = num
        .iter()
        .zip(den)
        .map(|(&a, &b)| {
            if a.is_finite() && b.is_finite() && b > 0.0 {
                a / b
            } else {
                f64::NAN
            }
        })
        .collect();
    let e = median_ci(&ratios);
    RatioEstimate {
        median: e.median,
        ci95_low: e.ci95_low,
        ci95_high: e.ci95_high,
        rounds: e.samples,
        non_finite: non_finite(&ratios),
        confidence: e.confidence,
    }
}

/// The Pareto front of (time, error) points when time is known only through paired rounds:
/// `times[i][r]` is point i's time in round r. Point i is dominated only when some j has an
/// error at most i's and the sign-test 95% interval of the per-round ratio time_i / time_j lies
/// entirely above 1 (i is slower than j beyond the interval); overlapping times never dominate.
/// Points with a non-finite error are never on the front.
pub fn pareto_front_paired(errors: &[f64], times: &[Vec<f64>]) -> Vec<usize> {
    (0..errors.len())
        .filter(|&i| errors[i].is_finite() && dominators(errors, times, i).is_empty())
        .collect()
}

/// The points that dominate point i by the rule of [`pareto_front_paired`]: an error at most
/// i's and i slower than each beyond the paired interval.
pub fn dominators(errors: &[f64], times: &[Vec<f64>], i: usize) -> Vec<usize> {
    (0..errors.len())
        .filter(|&j| {
            j != i
                && errors[j].is_finite()
                && errors[j] <= errors[i]
                && paired_ratio(&times[i], &times[j]).ci95_low > 1.0
        })
        .collect()
}

pub(crate) fn least_squares(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The percentile before the integer keys (the code it replaces, kept as the oracle):
    /// one selection by `f64::total_cmp`.
    fn oracle(values: &mut [f64], p: f64) -> f64 {
        if values.is_empty() {
            return 0.0;
        }
        let k = rank_index(values.len(), p);
        *values.select_nth_unstable_by(k, f64::total_cmp).1
    }

    /// A deliberately wrong selection for the teeth: the raw bits as i64, without the flip of
    /// the negative values (it orders -1 below -2).
    fn raw_bits(values: &mut [f64], p: f64) -> f64 {
        if values.is_empty() {
            return 0.0;
        }
        let k = rank_index(values.len(), p);
        let keys: &mut [i64] = bytemuck::cast_slice_mut(values);
        f64::from_bits(*keys.select_nth_unstable(k).1 as u64)
    }

    fn random_values(rng: &mut fastrand::Rng, n: usize, signs: bool) -> Vec<f64> {
        let pool = [
            0.0,
            -0.0,
            1.0,
            0.5,
            f64::INFINITY,
            f64::NAN,
            -f64::NAN,
            1e-310,
        ];
        (0..n)
            .map(|_| {
                let v = match rng.u32(0..4) {
                    0 => pool[rng.usize(..pool.len())],
                    1 => (rng.u32(0..5) as f64) * 0.25, // ties
                    _ => rng.f64() * 10.0,
                };
                if signs && rng.bool() {
                    -v
                } else {
                    v
                }
            })
            .collect()
    }

    /// `RankHistogram::percentiles` gives `percentiles`' bits (the oracle, on a copy) on the
    /// values of `random_values` (ties, both zeros, both NaNs, infinities, subnormals, signed
    /// or not) and on values crowded into one bucket, for sizes 0-4099; `total_key` orders
    /// as `total_cmp` and `from_total_key` inverts it. Teeth: a histogram that misses one value
    /// (a rank off by one) disagrees with the oracle.
    #[test]
    fn rank_histogram_percentiles_equal_the_selection() {
        let mut rng = fastrand::Rng::with_seed(28);
        let ps = [50.0, 95.0, 99.0, 0.0, 100.0, 37.5];
        let mut wrong = 0;
        for round in 0..400 {
            let n = [0, 1, 2, 3, 10, 100, 1000, 4099][round % 8];
            let mut values = random_values(&mut rng, n, round % 2 == 1);
            if round % 4 == 2 {
                // crowded: one bucket (the same top 16 bits) with a few values elsewhere
                for v in values.iter_mut().skip(3) {
                    *v = 1.0 + rng.f64() * 1e-3;
                }
            }
            let mut h = RankHistogram::default();
            values.iter().for_each(|&x| h.add(x));
            let want = percentiles(&mut values.clone(), ps).map(f64::to_bits);
            let got = h.percentiles(ps, values.iter().copied()).map(f64::to_bits);
            assert_eq!(got, want, "n {n}, round {round}");
            for w in values.windows(2) {
                assert_eq!(
                    total_key(w[0]).cmp(&total_key(w[1])),
                    w[0].total_cmp(&w[1]),
                    "{w:?}"
                );
                assert_eq!(from_total_key(total_key(w[0])).to_bits(), w[0].to_bits());
            }
            // teeth: one value fewer in the counts (and in the second pass)
            if n > 1 {
                let mut short = RankHistogram::default();
                values[1..].iter().for_each(|&x| short.add(x));
                let off = short.percentiles(ps, values[1..].iter().copied());
                wrong += usize::from(off.map(f64::to_bits) != want);
            }
        }
        assert!(wrong > 100, "{wrong}");
        let h = RankHistogram::default();
        assert_eq!(h.percentiles([50.0], std::iter::empty()), [0.0]);
    }

    /// `percentile` and `percentiles` give the bits of one `total_cmp` selection each (the
    /// oracle, on a fresh copy), on random values with ties, zeros of both signs, NaNs of both
    /// signs, infinities and subnormals, non-negative only (the |dI|, angles and FLIP values
    /// of compare) and of both signs; one element and empty too; the slice keeps its values
    /// (reordered). Teeth: the raw bits without the flip disagree with the oracle.
    #[test]
    fn percentiles_on_integer_keys_equal_the_total_cmp_selection() {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let sorted_bits = |v: &[f64]| {
            let mut b = bits(v);
            b.sort_unstable();
            b
        };
        let mut rng = fastrand::Rng::with_seed(26);
        let ps = [50.0, 95.0, 99.0, 0.0, 100.0, 37.5];
        let mut wrong = 0;
        for round in 0..400 {
            let n = [0, 1, 2, 3, 10, 100, 1000, 4099][round % 8];
            let signs = round % 2 == 1;
            let values = random_values(&mut rng, n, signs);
            let expected = ps.map(|p| oracle(&mut values.clone(), p).to_bits());
            let mut v = values.clone();
            let got = percentiles(&mut v, ps).map(f64::to_bits);
            assert_eq!(got, expected, "n {n}, signs {signs}");
            assert_eq!(
                sorted_bits(&v),
                sorted_bits(&values),
                "n {n}: not a reordering"
            );
            for (p, e) in ps.iter().zip(expected) {
                assert_eq!(
                    percentile(&mut values.clone(), *p).to_bits(),
                    e,
                    "n {n} p {p}"
                );
                wrong += usize::from(raw_bits(&mut values.clone(), *p).to_bits() != e);
            }
        }
        assert!(wrong > 100, "{wrong}");
        assert_eq!(percentiles(&mut [], [50.0, 99.0]), [0.0, 0.0]);
        assert_eq!(percentile(&mut [-0.0], 50.0).to_bits(), (-0.0f64).to_bits());
    }
}
