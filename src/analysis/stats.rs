//! Statistics: percentiles, the median with a distribution-free 95% interval, the Pareto front,
//! least squares.
use serde::Serialize;

/// Nearest-rank percentile of `values` (unsorted; reordered in place): the smallest value such
/// that at least `p` percent of the values are at most it. 0 for an empty slice.
pub fn percentile(values: &mut [f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((p / 100.0) * values.len() as f64).ceil().max(1.0) as usize;
    let k = rank.min(values.len()) - 1;
    *values.select_nth_unstable_by(k, f64::total_cmp).1
}
/// A median with its 95% confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    pub median: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    pub samples: usize,
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

/// Median and distribution-free 95% confidence interval from order statistics: the interval
/// [x(l), x(n+1-l)] (1-based, sorted) with l the largest rank such that P(Bin(n, 1/2) < l) <=
/// 2.5 %. With fewer than 6 samples no such rank exists and the interval is [min, max].
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
        };
    }
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    let mut l = 0usize; // 1-based rank; 0 = none
    for k in 1..=n / 2 {
        if binomial_half_cdf(n, k - 1) <= 0.025 {
            l = k;
        } else {
            break;
        }
    }
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
    }
}

/// Indices of the points not dominated by any other (smaller-or-equal in both coordinates and
/// smaller in one). Points with a non-finite coordinate are never on the front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (x, y) = points[i];
            x.is_finite()
                && y.is_finite()
                && !points.iter().enumerate().any(|(j, &(a, b))| {
                    j != i && a.is_finite() && b.is_finite() && a <= x && b <= y && (a < x || b < y)
                })
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
