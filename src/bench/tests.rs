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

// ---- claims ---------------------------------------------------------------------------------

use super::claims::*;
use super::MethodTiming;
use crate::gpu::spirv::OpCountsDelta;
use crate::method::Verdict;

/// A timing row with only the fields the claims read.
fn row(name: &str, low: f64, median: f64, high: f64) -> MethodTiming {
    MethodTiming {
        name: name.into(),
        median_ms: median,
        ci95_low_ms: low,
        ci95_high_ms: high,
        samples: 20,
        clock: "timestamp".into(),
        wall_median_ms: median,
        timestamp_median_ms: Some(median),
        covered_pixels: 1000,
        fragment_invocations: None,
        invocations_exact: None,
        ns_per_pixel: 0.0,
        above_floor_ms: 0.0,
        ratio_to_phong_exact: 0.0,
        ratio_above_floor_to_phong_exact: 0.0,
        static_ops: None,
        static_ops_above_unnormalized: None,
        error: None,
    }
}

#[test]
fn speed_verdict_is_inconclusive_when_the_intervals_overlap() {
    let phong = row("phong_exact", 1.0, 1.1, 1.2);
    let verdict = |lo, med, hi| faster_than_exact(&row("newton_raphson", lo, med, hi), &phong);
    assert_eq!(verdict(0.5, 0.6, 0.9).verdict, Verdict::Agrees);
    assert_eq!(verdict(1.3, 1.4, 1.5).verdict, Verdict::Disagrees);
    // faster median, but the intervals overlap: no measurable difference
    let overlap = verdict(0.8, 0.9, 1.05);
    assert_eq!(overlap.verdict, Verdict::Inconclusive, "{overlap:?}");
    assert!(overlap.reason.contains("overlap"), "{overlap:?}");
    // slower median, overlapping too
    assert_eq!(verdict(1.15, 1.25, 1.3).verdict, Verdict::Inconclusive);
}

#[test]
fn gouraud_50x_verdict_uses_both_intervals() {
    let floor = row("constant", 0.1, 0.1, 0.1);
    let phong = row("phong_exact", 10.0, 11.0, 12.0);
    let verdict = |lo, med, hi| phong_50x_gouraud(&phong, &row("gouraud", lo, med, hi), &floor);
    // 10 / 0.15 = 66x at the least
    assert_eq!(verdict(0.1, 0.12, 0.15).verdict, Verdict::Agrees);
    // 12 / 1 = 12x at the most
    assert_eq!(verdict(1.0, 1.1, 1.2).verdict, Verdict::Disagrees);
    // median ratio 11 / 0.2 = 55x, but the intervals allow 10 / 0.3 = 33x
    let m = verdict(0.15, 0.2, 0.3);
    assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
}

#[test]
fn op_count_verdict_compares_each_count_with_the_claim() {
    assert_eq!(
        normalization_ops(&NORMALIZATION_CLAIM).verdict,
        Verdict::Agrees
    );
    // what the compiler emits for normalize(v): the same dot product, then one inverse square
    // root and 3 multiplications
    let rsqrt = OpCountsDelta {
        mul: 6,
        add: 2,
        inverse_sqrt: 1,
        ..Default::default()
    };
    let m = normalization_ops(&rsqrt);
    assert_eq!(m.verdict, Verdict::Partly, "{m:?}");
    assert!(
        m.measured
            .contains("differs in div 0 (claimed 3), mul 6 (claimed 3), sqrt 0 (claimed 1), inverse_sqrt 1 (claimed 0)"),
        "{m:?}"
    );
    // nothing in common with the claim
    let m = normalization_ops(&OpCountsDelta {
        inverse_sqrt: 1,
        ..Default::default()
    });
    assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
}
