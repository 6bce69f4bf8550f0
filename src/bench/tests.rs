//! Tests of the bench statistics and claims.
use crate::analysis::stats::*;

#[test]
fn median_ci_matches_the_order_statistics_table() {
    // n = 100: the 95% interval of the median is [x(40), x(61)] (binomial table)
    let v: Vec<f64> = (1..=100).map(|x| x as f64).collect();
    let e = median_ci(&v);
    assert_eq!(
        (e.median, e.ci95_low, e.ci95_high, e.samples),
        (50.5, 40.0, 61.0, 100)
    );
    // n = 10: [x(2), x(9)]
    let v: Vec<f64> = (1..=10).map(|x| x as f64).collect();
    let e = median_ci(&v);
    assert_eq!((e.median, e.ci95_low, e.ci95_high), (5.5, 2.0, 9.0));
    // n = 5: no 95% rank exists -> [min, max]
    let e = median_ci(&[3.0, 1.0, 2.0, 5.0, 4.0]);
    assert_eq!((e.median, e.ci95_low, e.ci95_high), (3.0, 1.0, 5.0));
    // order does not matter, NaN ignored
    let e = median_ci(&[2.0, f64::NAN, 1.0, 3.0]);
    assert_eq!((e.median, e.samples), (2.0, 3));
}

#[test]
fn binomial_cdf_is_exact_for_small_n() {
    assert!((binomial_half_cdf(4, 0) - 1.0 / 16.0).abs() < 1e-15);
    assert!((binomial_half_cdf(4, 1) - 5.0 / 16.0).abs() < 1e-15);
    assert!((binomial_half_cdf(4, 4) - 1.0).abs() < 1e-15);
}

#[test]
fn pareto_front_keeps_only_non_dominated_points() {
    let pts = [
        (1.0, 5.0),
        (2.0, 3.0),
        (3.0, 4.0),
        (4.0, 1.0),
        (2.0, 3.0),
        (0.5, f64::NAN),
    ];
    // (3, 4) is dominated by (2, 3); the two (2, 3) tie and both stay; NaN is never on it
    assert_eq!(pareto_front(&pts), vec![0, 1, 3, 4]);
    assert!(pareto_front(&[]).is_empty());
}

#[test]
fn least_squares_slope() {
    assert!((least_squares(&[1.0, 2.0, 3.0], &[3.0, 5.0, 7.0]) - 2.0).abs() < 1e-12);
    assert!(least_squares(&[1.0, 1.0], &[1.0, 2.0]).is_nan());
}

/// A run whose clock check chose timestamps but whose samples have none reports the wall clock
/// under its own name (it was labelled "timestamp" before).
#[test]
fn wall_clock_fallback_is_labelled_wall() {
    let sample = |wall_ms, timestamp_ms| crate::gpu::Sample {
        wall_ms,
        timestamp_ms,
        fragment_invocations: None,
    };
    let no_ts: Vec<_> = (0..9).map(|i| sample(10.0 + i as f64, None)).collect();
    let (e, clock, wall, ts) = super::estimate(&no_ts, "timestamp");
    assert_eq!((clock, ts), ("wall", None));
    assert_eq!(e.median, wall);
    let with_ts: Vec<_> = (0..9).map(|i| sample(10.0, Some(5.0 + i as f64))).collect();
    let (e, clock, _, ts) = super::estimate(&with_ts, "timestamp");
    assert_eq!((clock, Some(e.median)), ("timestamp", ts));
    assert_eq!(super::estimate(&with_ts, "wall").1, "wall");
}
