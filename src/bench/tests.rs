//! Tests of the bench statistics and claims.
use crate::analysis::stats::*;
use crate::gpu::Clock;

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
fn order_statistic_confidence_is_exact() {
    // [min, max] of 5 samples: 1 - 2 / 32; of 1 sample: nothing
    assert!((order_statistic_confidence(5, 0) - 0.9375).abs() < 1e-15);
    assert_eq!(order_statistic_confidence(1, 0), 0.0);
    assert_eq!(order_statistic_confidence(0, 0), 0.0);
    // n = 20: l = 6, 1 - 2 P(Bin(20, 1/2) <= 5) = 0.95861...
    assert_eq!(sign_test_rank(20), 6);
    let e = median_ci(&(1..=20).map(f64::from).collect::<Vec<_>>());
    assert!((e.confidence - 0.958610).abs() < 1e-6, "{e:?}");
    assert!(e.confidence >= 0.95);
    assert!(median_ci(&[1.0, 2.0, 3.0, 4.0, 5.0]).confidence < 0.95);
}

/// Synthetic rounds in which the whole machine slows down and speeds up by a factor of two
/// from round to round (drift), while the method is 1 % slower than phong_exact in every
/// round: the separate intervals overlap completely, the paired interval is exactly 1.01.
fn drifting_rounds(ratio: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let phong: Vec<f64> = (0..n)
        .map(|r| 20.0 * (1.0 + (r % 7) as f64 / 7.0))
        .collect();
    let method = phong.iter().map(|p| p * ratio).collect();
    (method, phong)
}

#[test]
fn paired_ratio_sees_through_drift() {
    let (m, p) = drifting_rounds(1.01, 40);
    let r = paired_ratio(&m, &p);
    assert!((r.median - 1.01).abs() < 1e-12, "{r:?}");
    assert!(r.ci95_low > 1.0, "{r:?}");
    assert_eq!((r.rounds, r.non_finite), (40, 0));
    // the separate intervals could not tell them apart
    let (em, ep) = (median_ci(&m), median_ci(&p));
    assert!(em.ci95_low < ep.ci95_high, "{em:?} {ep:?}");
    // teeth: a method whose per-round ratios straddle 1 is not called slower
    let noisy: Vec<f64> = p
        .iter()
        .enumerate()
        .map(|(i, x)| x * if i % 2 == 0 { 1.03 } else { 0.98 })
        .collect();
    let r = paired_ratio(&noisy, &p);
    assert!(r.ci95_low < 1.0 && r.ci95_high > 1.0, "{r:?}");
}

#[test]
fn paired_ratio_counts_non_finite_rounds_and_never_sorts_them() {
    let p = vec![10.0; 12];
    let mut m = vec![11.0; 12];
    m[3] = f64::NAN;
    m[5] = f64::INFINITY;
    let mut p2 = p.clone();
    p2[7] = 0.0; // a zero denominator gives no ratio either
    let r = paired_ratio(&m, &p2);
    assert_eq!((r.rounds, r.non_finite), (9, 3), "{r:?}");
    assert!((r.median - 1.1).abs() < 1e-12 && (r.ci95_high - 1.1).abs() < 1e-12);
    // nothing finite: NaN estimate, never a ratio of 1 or 0
    let r = paired_ratio(&[f64::NAN; 4], &p[..4]);
    assert_eq!((r.rounds, r.non_finite), (0, 4));
    assert!(r.median.is_nan() && r.half_width_pct().is_nan());
}

#[test]
fn half_width_is_the_wider_side_in_percent() {
    let r = RatioEstimate {
        median: 1.0,
        ci95_low: 0.99,
        ci95_high: 1.02,
        rounds: 40,
        non_finite: 0,
        confidence: 0.96,
    };
    assert!((r.half_width_pct() - 2.0).abs() < 1e-9);
}

#[test]
fn paired_pareto_front_dominates_only_beyond_the_paired_interval() {
    // a: low error, slow; b: higher error, 1 % faster in every round; c: b's error, as slow
    // as a or 2 % slower, alternately; d: non-finite error
    let (a, base) = drifting_rounds(1.0, 40);
    let b: Vec<f64> = base.iter().map(|x| x * 0.99).collect();
    let c: Vec<f64> = base
        .iter()
        .enumerate()
        .map(|(i, x)| x * if i % 2 == 0 { 1.02 } else { 1.0 })
        .collect();
    let times = vec![a.clone(), b.clone(), c.clone(), b.clone()];
    let errors = [1.0, 2.0, 2.0, f64::NAN];
    // c is dominated by b (same error, b faster beyond the paired interval): off the front;
    // a and b trade off; d is never on it
    assert_eq!(pareto_front_paired(&errors, &times), vec![0, 1]);
    // teeth: if c had a's error it would stay (c is not slower than a beyond the interval,
    // even though its median is above a's)
    let errors = [1.0, 2.0, 1.0, f64::NAN];
    assert_eq!(pareto_front_paired(&errors, &times), vec![0, 1, 2]);
    // teeth: a method at b's time with a strictly worse error is dominated
    let times = vec![a, b.clone(), b.iter().map(|x| x * 1.05).collect()];
    assert_eq!(pareto_front_paired(&[1.0, 2.0, 3.0], &times), vec![0, 1]);
    assert!(pareto_front_paired(&[], &[]).is_empty());
}

#[test]
fn until_ci_stops_at_the_target_or_the_cap_and_not_before() {
    use super::rounds::{until_ci_stop, Stop};
    assert_eq!(
        until_ci_stop(0.9, 1.0, 5.0, 300.0),
        Some(Stop::TargetReached)
    );
    assert_eq!(
        until_ci_stop(1.0, 1.0, 5.0, 300.0),
        Some(Stop::TargetReached)
    );
    assert_eq!(until_ci_stop(1.1, 1.0, 5.0, 300.0), None);
    assert_eq!(until_ci_stop(1.1, 1.0, 300.0, 300.0), Some(Stop::TimeCap));
    // an interval without a finite ratio is never narrow enough
    assert_eq!(until_ci_stop(f64::NAN, 1.0, 5.0, 300.0), None);
    assert_eq!(until_ci_stop(f64::INFINITY, 1.0, 5.0, 300.0), None);
    assert_eq!(
        until_ci_stop(f64::NAN, 1.0, 301.0, 300.0),
        Some(Stop::TimeCap)
    );
}

#[test]
fn widest_names_the_widest_interval_and_treats_unmeasured_as_infinite() {
    use super::rounds::widest;
    let r = |lo, hi, rounds| RatioEstimate {
        median: 1.0,
        ci95_low: lo,
        ci95_high: hi,
        rounds,
        non_finite: 0,
        confidence: 0.96,
    };
    let names = ["a".to_string(), "b".to_string()];
    let (w, which) = widest(
        &names,
        &[r(0.99, 1.01, 9), r(0.97, 1.0, 9)],
        &[r(1.0, 1.0, 9); 2],
    );
    assert!((w - 3.0).abs() < 1e-9);
    assert_eq!(which, "b against phong_exact");
    let (w, which) = widest(
        &names,
        &[r(1.0, 1.0, 9); 2],
        &[r(1.0, 1.0, 9), r(f64::NAN, f64::NAN, 0)],
    );
    assert!(w.is_infinite());
    assert_eq!(which, "b against its floor");
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
    };
    let no_ts: Vec<_> = (0..9).map(|i| sample(10.0 + i as f64, None)).collect();
    let (e, clock, wall, ts) = super::estimate(&no_ts, Clock::Timestamp);
    assert_eq!((clock, ts), (Clock::Wall, None));
    assert_eq!(e.median, wall);
    let with_ts: Vec<_> = (0..9).map(|i| sample(10.0, Some(5.0 + i as f64))).collect();
    let (e, clock, _, ts) = super::estimate(&with_ts, Clock::Timestamp);
    assert_eq!((clock, Some(e.median)), (Clock::Timestamp, ts));
    assert_eq!(super::estimate(&with_ts, Clock::Wall).1, Clock::Wall);
    // Paired values on the timestamp clock: a round without a timestamp is NaN (counted by
    // the ratios), never its wall time.
    let mixed = [sample(10.0, Some(4.0)), sample(10.0, None)];
    let v = super::rounds::round_values(&mixed, Clock::Timestamp);
    assert_eq!(v[0], 4.0);
    assert!(v[1].is_nan());
    assert_eq!(
        super::rounds::round_values(&mixed, Clock::Wall),
        vec![10.0, 10.0]
    );
}

// ---- claims ---------------------------------------------------------------------------------

use super::claims::*;
use super::{auto_points, MethodTiming};
use crate::analysis::stats::RatioEstimate;
use crate::gpu::spirv::OpCountsDelta;
use crate::method::{Kind, Verdict};

/// A timing row with only the fields the claims read: the medians and the paired ratio
/// interval to phong_exact.
fn row(name: &str, median: f64, ratio: (f64, f64, f64)) -> MethodTiming {
    let (lo, mid, hi) = ratio;
    MethodTiming {
        name: name.into(),
        floor_program: "constant".into(),
        median_ms: median,
        ci95_low_ms: median * 0.9,
        ci95_high_ms: median * 1.1,
        samples: 20,
        clock: crate::gpu::Clock::Timestamp,
        wall_median_ms: median,
        timestamp_median_ms: Some(median),
        covered_pixels: 1000,
        fragment_invocations: None,
        invocations_exact: None,
        overdraw: None,
        ns_per_pixel: 0.0,
        above_floor_ms: 0.0,
        ratio_to_phong_exact: 0.0,
        ratio_above_floor_to_phong_exact: 0.0,
        ratio_median: mid,
        ratio_ci95_low: lo,
        ratio_ci95_high: hi,
        ratio_rounds: 20,
        ratio_non_finite: 0,
        ratio_confidence: 0.96,
        ratio_to_floor_median: f64::NAN,
        ratio_to_floor_ci95_low: f64::NAN,
        ratio_to_floor_ci95_high: f64::NAN,
        ratio_to_floor_non_finite: 0,
        speed_vs_phong_exact: super::Speed::from_ratio(&RatioEstimate {
            median: mid,
            ci95_low: lo,
            ci95_high: hi,
            rounds: 20,
            non_finite: 0,
            confidence: 0.96,
        }),
        static_ops: None,
        static_ops_above_unnormalized: None,
        error: None,
        isolated_ns_per_eval: None,
        isolated_ci95_low_ns: None,
        isolated_ci95_high_ns: None,
        isolated_ratio_to_phong_exact: None,
        isolated_vs_phong_exact: None,
        isolated_k1_max_abs_diff_vs_f64: None,
        runs: None,
        isolated_runs: None,
        run_figures: Vec::new(),
    }
}

#[test]
fn speed_verdict_comes_from_the_paired_interval_only() {
    let phong = row("phong_exact", 1.1, (1.0, 1.0, 1.0));
    let verdict = |ratio| faster_than_exact(&row("newton_raphson", 1.0, ratio), &phong);
    let v = verdict((0.97, 0.98, 0.99));
    assert_eq!(v.verdict, Verdict::Agrees, "{v:?}");
    assert!(v.measured.contains("faster"), "{v:?}");
    assert_eq!(verdict((1.01, 1.02, 1.03)).verdict, Verdict::Disagrees);
    // a faster median whose paired interval contains 1: no measurable difference
    let v = verdict((0.98, 0.99, 1.001));
    assert_eq!(v.verdict, Verdict::Inconclusive, "{v:?}");
    assert!(v.reason.contains("contains 1"), "{v:?}");
    // the separate intervals of the row (median +-10 %) overlap phong_exact's, yet the paired
    // interval decides: the verdict never comes from the separate intervals
    let r = row("newton_raphson", 1.0, (0.95, 0.96, 0.97));
    assert!(r.ci95_high_ms > phong.ci95_low_ms);
    assert_eq!(faster_than_exact(&r, &phong).verdict, Verdict::Agrees);
    // no finite round: inconclusive, said so
    let v = verdict((f64::NAN, f64::NAN, f64::NAN));
    assert_eq!(v.verdict, Verdict::Inconclusive);
    assert!(v.reason.contains("no round"), "{v:?}");
}

#[test]
fn speed_of_a_ratio() {
    use super::Speed;
    let r = |lo, hi, rounds| RatioEstimate {
        median: 1.0,
        ci95_low: lo,
        ci95_high: hi,
        rounds,
        non_finite: 0,
        confidence: 0.96,
    };
    assert_eq!(Speed::from_ratio(&r(0.9, 0.99, 9)), Speed::Faster);
    assert_eq!(Speed::from_ratio(&r(1.01, 1.1, 9)), Speed::Slower);
    assert_eq!(Speed::from_ratio(&r(0.99, 1.01, 9)), Speed::Inconclusive);
    assert_eq!(Speed::from_ratio(&r(1.0, 1.0, 9)), Speed::Inconclusive);
    assert_eq!(
        Speed::from_ratio(&r(f64::NAN, f64::NAN, 0)),
        Speed::Unmeasured
    );
}

#[test]
fn gouraud_50x_verdict_uses_the_paired_interval() {
    let floor = row("constant", 0.1, (0.0, 0.0, 0.0));
    let phong = row("phong_exact", 11.0, (1.0, 1.0, 1.0));
    let _ = (floor, &phong);
    let claim = "Phong shading takes more than 50x longer than Gouraud";
    let verdict = |ratio| {
        super::claims::factor_claim(&row("gouraud", 0.2, ratio), claim, 50.0, Measure::FrameTime)
    };
    // phong / gouraud at least 1 / 0.015 = 66x
    assert_eq!(verdict((0.01, 0.012, 0.015)).verdict, Verdict::Agrees);
    // at most 1 / 0.5 = 2x
    assert_eq!(verdict((0.5, 0.6, 0.7)).verdict, Verdict::Disagrees);
    // median 1 / 0.018 = 55x, but the interval allows 1 / 0.03 = 33x
    let m = verdict((0.015, 0.018, 0.03));
    assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
    assert_eq!(
        verdict((f64::NAN, f64::NAN, f64::NAN)).verdict,
        Verdict::Inconclusive
    );
}

#[test]
fn op_count_verdict_compares_each_count_with_the_claim() {
    let normalization_ops = |d: &OpCountsDelta| {
        let row = crate::method::phong_exact();
        let Kind::OperationCount(Some(ops)) = row.claims[0].kind else {
            panic!("phong_exact's op count")
        };
        op_counts(row.name, row.claims[0].claim, claimed_ops(ops), d)
    };
    let claimed = OpCountsDelta {
        div: 3,
        sqrt: 1,
        mul: 3,
        add: 2,
        ..Default::default()
    };
    assert_eq!(normalization_ops(&claimed).verdict, Verdict::Agrees);
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

// ---- baseline -------------------------------------------------------------------------------

use super::baseline::{self, Change};
use serde_json::json;

/// A synthetic bench.json with the floor and methods given as (name, low, median, high).
fn bench_json(rows: &[(&str, f64, f64, f64)]) -> serde_json::Value {
    let row = |&(n, lo, m, hi): &(&str, f64, f64, f64)| json!({"name": n, "ci95_low_ms": lo, "median_ms": m, "ci95_high_ms": hi});
    json!({
        "scene": "sphere_fine",
        "width": 1024,
        "height": 1024,
        "clock": {"clock": "timestamp"},
        "floor": row(&rows[0]),
        "other_floors": [],
        "methods": rows[1..].iter().map(row).collect::<Vec<_>>(),
    })
}

#[test]
fn baseline_fails_only_beyond_both_intervals_by_more_than_the_limit() {
    let old = bench_json(&[
        ("constant", 19.0, 20.0, 21.0),
        ("phong_exact", 29.0, 30.0, 31.0),
        ("gouraud", 19.0, 20.0, 21.0),
        ("lyon_taylor", 29.0, 30.0, 31.0),
        ("dropped", 1.0, 2.0, 3.0),
    ]);
    let new = bench_json(&[
        ("constant", 19.5, 20.5, 21.5),    // overlapping
        ("phong_exact", 33.0, 34.0, 35.0), // 33 / 31 = +6.5 % beyond both
        ("gouraud", 21.5, 22.0, 22.5),     // 21.5 / 21 = +2.4 % beyond both
        ("lyon_taylor", 20.0, 21.0, 22.0), // faster
        ("added", 1.0, 2.0, 3.0),
    ]);
    let c = baseline::compare(&old, &new, "old/bench.json", Some(5.0));
    assert!(!c.paired && c.note.contains("not paired"));
    let change = |n: &str| c.programs.iter().find(|p| p.name == n).unwrap().change;
    assert_eq!(change("constant"), Change::Indistinguishable);
    assert_eq!(change("phong_exact"), Change::Slower);
    assert_eq!(change("gouraud"), Change::Slower);
    assert_eq!(change("lyon_taylor"), Change::Faster);
    assert_eq!(c.failing, vec!["phong_exact"]);
    assert!(c.exceeded());
    let p = c.programs.iter().find(|p| p.name == "phong_exact").unwrap();
    assert!((p.slower_by_at_least_pct.unwrap() - (33.0 / 31.0 - 1.0) * 100.0).abs() < 1e-9);
    assert!((p.change_pct.unwrap() - (34.0 / 30.0 - 1.0) * 100.0).abs() < 1e-9);
    assert_eq!(c.only_in_baseline, vec!["dropped"]);
    assert_eq!(c.only_in_this_run, vec!["added"]);
    assert!(c.setup_differences.is_empty(), "{:?}", c.setup_differences);
    // teeth: a looser limit passes the same runs; no limit never fails
    let loose = baseline::compare(&old, &new, "old", Some(10.0));
    assert!(loose.failing.is_empty() && !loose.exceeded());
    assert!(!baseline::compare(&old, &new, "old", None).exceeded());
    // a run against itself: nothing slower
    let same = baseline::compare(&old, &old, "old", Some(0.0));
    assert!(!same.exceeded(), "{same:?}");
}

#[test]
fn baseline_counts_programs_it_cannot_compare_and_fails_on_them() {
    let old = bench_json(&[
        ("constant", 19.0, 20.0, 21.0),
        ("phong_exact", 29.0, 30.0, 31.0),
    ]);
    let mut new = bench_json(&[
        ("constant", 19.0, 20.0, 21.0),
        ("phong_exact", 29.0, 30.0, 31.0),
    ]);
    // NaN is written as null by serde_json
    new["methods"][0]["ci95_low_ms"] = serde_json::Value::Null;
    new["width"] = json!(512);
    let c = baseline::compare(&old, &new, "old", Some(5.0));
    assert_eq!(c.not_comparable, vec!["phong_exact"]);
    assert!(c.failing.is_empty());
    assert!(c.exceeded(), "a gate must not pass what it cannot measure");
    assert_eq!(
        c.setup_differences,
        vec!["width: baseline 1024, this run 512"]
    );
    // without --fail-slower it is reported, not failed
    assert!(!baseline::compare(&old, &new, "old", None).exceeded());
}

#[test]
fn baseline_rejects_a_file_that_is_not_a_bench_json() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.json");
    std::fs::write(&p, "{\"methods\": 3}").unwrap();
    let e = baseline::load(&p).unwrap_err().to_string();
    assert!(e.contains("not a bench.json"), "{e}");
    std::fs::write(&p, "{").unwrap();
    let e = baseline::load(&p).unwrap_err().to_string();
    assert!(e.contains("not valid JSON"), "{e}");
    std::fs::write(&p, bench_json(&[("constant", 1.0, 2.0, 3.0)]).to_string()).unwrap();
    assert!(baseline::load(&p).is_ok());
}

#[test]
fn factor_claims_follow_the_ratio_of_each_measure() {
    use super::claims::{factor_claim, Measure};
    use crate::bench::isolated::Interval;
    // frame time: a 2x claim agrees at ratio 0.45 and disagrees at 0.9
    let fast = row("spherical_angular", 1.0, (0.42, 0.45, 0.48));
    let slow = row("spherical_angular", 1.0, (0.88, 0.9, 0.92));
    assert_eq!(
        factor_claim(&fast, "2x", 2.0, Measure::FrameTime).verdict,
        Verdict::Agrees
    );
    assert_eq!(
        factor_claim(&slow, "2x", 2.0, Measure::FrameTime).verdict,
        Verdict::Disagrees
    );
    // an interval that straddles 1/F (speed-up 1.67x to 2.04x, median 1.82x) decides nothing
    let edge = row("spherical_angular", 1.0, (0.49, 0.55, 0.6));
    assert_eq!(
        factor_claim(&edge, "2x", 2.0, Measure::FrameTime).verdict,
        Verdict::Inconclusive
    );
    // the whole interval reaching 1/F (its high end exactly 1/F) agrees
    let reach = row("spherical_angular", 1.0, (0.4, 0.45, 0.5));
    assert_eq!(
        factor_claim(&reach, "2x", 2.0, Measure::FrameTime).verdict,
        Verdict::Agrees
    );
    // isolated cost: unmeasured is not checked (no verdict), measured follows its own interval
    assert_eq!(
        factor_claim(&fast, "2x", 2.0, Measure::IsolatedCost).verdict,
        Verdict::NotChecked
    );
    let mut iso = slow.clone();
    iso.isolated_ratio_to_phong_exact = Some(Interval {
        median: 0.3,
        ci95_low: 0.25,
        ci95_high: 0.35,
    });
    let c = factor_claim(&iso, "2x", 2.0, Measure::IsolatedCost);
    assert_eq!(c.verdict, Verdict::Agrees, "{}", c.measured);
    assert!(c.how.starts_with("measure: isolated cost"));
    assert_eq!(
        factor_claim(&iso, "2x", 2.0, Measure::FrameTime).verdict,
        Verdict::Disagrees,
        "each measure gives its own verdict"
    );
}

#[test]
fn the_isolated_front_needs_separate_intervals() {
    let mut a = row("a", 1.0, (1.0, 1.0, 1.0));
    let mut b = row("b", 1.0, (1.0, 1.0, 1.0));
    (a.isolated_ci95_low_ns, a.isolated_ci95_high_ns) = (Some(9.0), Some(11.0));
    (b.isolated_ci95_low_ns, b.isolated_ci95_high_ns) = (Some(10.0), Some(12.0));
    let rows = vec![a.clone(), b.clone()];
    // b has the larger error but overlapping intervals: not dominated
    let front = crate::bench::isolated::pareto_front(&rows, &[0.1, 0.2]);
    assert_eq!(front, vec!["a", "b"]);
    // separated intervals: b is dominated
    b.isolated_ci95_low_ns = Some(11.5);
    let front = crate::bench::isolated::pareto_front(&[a, b], &[0.1, 0.2]);
    assert_eq!(front, vec!["a"]);
    // a NaN error leaves a method out
    let front = crate::bench::isolated::pareto_front(&rows, &[f64::NAN, 0.2]);
    assert_eq!(front, vec!["b"]);
}

fn auto_summary(name: &str, budget: f64) -> crate::auto::AutoSummary {
    crate::auto::AutoSummary {
        name: name.into(),
        budget,
        margin: 1.0,
        samples_per_triangle: 28,
        triangles: Vec::new(),
        choice_ms: 0.0,
        source: crate::auto::ChoiceSource::Computed,
        grouping: None,
    }
}

#[test]
fn auto_is_beaten_only_by_a_fixed_method_with_no_more_error_and_a_faster_paired_time() {
    let rows = vec![
        row("gouraud", 1.0, (0.4, 0.5, 0.6)),
        row("phong_exact", 2.0, (1.0, 1.0, 1.0)),
        row("auto", 1.5, (0.7, 0.75, 0.8)),
        row("auto_16_255", 0.9, (0.4, 0.45, 0.5)),
    ];
    let rounds = |t: f64| -> Vec<f64> { (0..20).map(|r| t * (1.0 + 0.01 * r as f64)).collect() };
    let values = vec![rounds(1.0), rounds(2.0), rounds(1.5), rounds(0.9)];
    let autos = [
        auto_summary("auto", 1.0 / 255.0),
        auto_summary("auto_16_255", 16.0 / 255.0),
    ];
    // gouraud is faster but has more error: nothing fixed beats auto. auto_16_255 is faster
    // with less error, but it is not a fixed method.
    let errors = [1e-2, 1e-6, 1e-3, 1e-4];
    let p = auto_points(&rows, &errors, &values, &autos);
    assert_eq!(p.len(), 2);
    assert!(p[0].beaten_by.is_empty(), "{:?}", p[0].beaten_by);
    assert_eq!((p[0].ratio_ci95_low, p[0].ratio_ci95_high), (0.7, 0.8));
    // The same gouraud with less error than auto beats it.
    let errors = [1e-4, 1e-6, 1e-3, 1e-2];
    let p = auto_points(&rows, &errors, &values, &autos);
    assert_eq!(p[0].beaten_by, vec!["gouraud".to_string()]);
    // ... but not when its time is indistinguishable from auto's in the paired rounds.
    let values = vec![rounds(1.5), rounds(2.0), rounds(1.5), rounds(0.9)];
    let p = auto_points(&rows, &errors, &values, &autos);
    assert!(p[0].beaten_by.is_empty(), "{:?}", p[0].beaten_by);
    // No error measured (rows without compare's statistics): never within budget.
    assert!(p[0].max_abs_error.is_nan() && !p[0].within_budget);
}

/// One rule for every "k times faster" claim: the Vulkan frame-time and isolated-cost claims
/// and the software engine's judge all follow [`crate::cost::factor_verdict`].
#[test]
fn one_factor_rule_for_every_engine_and_cost_model() {
    use super::claims::{factor_claim, Measure};
    use super::software::judge;
    use crate::bench::isolated::Interval;
    use crate::cost::factor_verdict;
    let target = 0.5; // a 2x claim
    let cases = [
        ((0.30, 0.35, 0.40), Verdict::Agrees),
        ((0.40, 0.45, 0.50), Verdict::Agrees),
        ((0.45, 0.50, 0.55), Verdict::Inconclusive),
        ((0.49, 0.55, 0.60), Verdict::Inconclusive),
        ((0.51, 0.55, 0.60), Verdict::Disagrees),
        ((f64::NAN, 0.4, 0.45), Verdict::Inconclusive),
        ((0.3, 0.4, f64::INFINITY), Verdict::Inconclusive),
        ((-0.2, -0.1, 0.0), Verdict::Inconclusive),
    ];
    for ((lo, mid, hi), want) in cases {
        assert_eq!(factor_verdict(lo, hi, target), want, "[{lo}, {hi}]");
        let r = RatioEstimate {
            median: mid,
            ci95_low: lo,
            ci95_high: hi,
            rounds: 21,
            non_finite: 0,
            confidence: 0.97,
        };
        assert_eq!(judge(&r, target), want, "software [{lo}, {hi}]");
        let mut frame = row("spherical_angular", 1.0, (lo, mid, hi));
        if lo.is_finite() && hi.is_finite() {
            assert_eq!(
                factor_claim(&frame, "2x", 2.0, Measure::FrameTime).verdict,
                want,
                "frame [{lo}, {hi}]"
            );
        }
        frame.isolated_ratio_to_phong_exact = Some(Interval {
            median: mid,
            ci95_low: lo,
            ci95_high: hi,
        });
        assert_eq!(
            factor_claim(&frame, "2x", 2.0, Measure::IsolatedCost).verdict,
            want,
            "isolated [{lo}, {hi}]"
        );
    }
}

/// The |n|^2 range Mikami's GPU bound sees: one at the corners, below it inside a triangle
/// of spread normals, and said in the claim.
#[test]
fn the_mikami_bound_says_the_len2_range_it_saw() {
    use super::claims::interpolated_len2_range;
    let spread = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let (lo, hi) = interpolated_len2_range(&spread).unwrap();
    assert!((hi - 1.0).abs() < 1e-12, "{hi}");
    // the centroid has 1/3; the nearest sampled point (3, 3, 2) / 8 has 22/64
    assert!((lo - 22.0 / 64.0).abs() < 1e-12, "{lo}");
    let same = [[0.0, 0.0, 1.0]; 3];
    assert_eq!(interpolated_len2_range(&same), Some((1.0, 1.0)));
    assert_eq!(interpolated_len2_range(&[]), None);
    assert_eq!(
        interpolated_len2_range(&[[f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
        None
    );
    let mut m = row("mikami_quadratic", 1.0, (0.9, 1.0, 1.1));
    let phong = row("phong_exact", 1.0, (1.0, 1.0, 1.0));
    m.error = Some(crate::compare::MethodReport {
        name: m.name.clone(),
        reference: "phong_f64".into(),
        covered_pixels: 1,
        coverage_mismatch_pixels: 0,
        ill_conditioned_pixels: 0,
        non_finite_pixels: 0,
        intensity: crate::analysis::pixel::intensity_stats([(0, 0, 0.25)], 0.1),
        channels: [0, 1, 2].map(|_| crate::analysis::pixel::ChannelStats {
            mean_abs_error: 0.0,
            max_abs_error: 0.0,
            rmse: 0.0,
        }),
        max_normal_angle_deg: None,
        mean_normal_angle_deg: None,
        p99_normal_angle_deg: None,
        max_normal_length_error: Some(0.001),
        flip_mean: 0.0,
        flip_p95: 0.0,
        files: vec![],
        against_slerp: None,
    });
    let c = claims(&[phong.clone(), m.clone()], Some((lo, hi)));
    let mk = c
        .iter()
        .find(|c| c.method == "mikami_quadratic" && c.claim.contains("1.5 %"));
    let mk = mk.expect("the Mikami bound is judged");
    assert!(mk.measured.contains("[0.3438, 1.0000]"), "{}", mk.measured);
    assert!(mk.measured.contains("never reaches"), "{}", mk.measured);
    let c = claims(&[phong.clone(), m], Some((0.2, 1.0)));
    let mk = c.iter().find(|c| c.claim.contains("1.5 %")).unwrap();
    assert!(!mk.measured.contains("never reaches"), "{}", mk.measured);
}

/// The report hands bench the scene's compare: bench takes its error metrics from it only when
/// it is that scene's, at its size and precision, with every judged row; otherwise it compares
/// again.
#[test]
fn a_compare_is_reused_only_for_its_own_scene_size_precision_and_rows() {
    use crate::method::Precision;
    let ctx = crate::gpu::vk::Context::new(&crate::gpu::vk::ContextDesc::default())
        .expect("lavapipe context");
    let renderer = crate::gpu::Renderer::new(ctx);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/icosphere.toml");
    let mut scene = crate::scene::load_scene(&path).unwrap();
    (scene.width, scene.height) = (24, 24);
    let methods = [
        crate::method::phong_exact(),
        crate::method::phong_unnormalized(),
    ];
    let opts = crate::compare::CompareOptions {
        images: false,
        ..crate::compare::CompareOptions::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let summary = crate::compare::compare(&renderer, &scene, &methods, dir.path(), &opts).unwrap();
    let judged: Vec<&str> = methods.iter().map(|m| m.name).collect();
    assert!(super::untimed::compared_covers(
        &summary,
        Precision::F32,
        &scene,
        &judged
    ));
    // teeth: another size, precision, scene or a row it lacks
    let mut larger = scene.clone();
    larger.width = 32;
    assert!(!super::untimed::compared_covers(
        &summary,
        Precision::F32,
        &larger,
        &judged
    ));
    assert!(!super::untimed::compared_covers(
        &summary,
        Precision::F16,
        &scene,
        &judged
    ));
    let mut other = scene.clone();
    other.name = "another scene".into();
    assert!(!super::untimed::compared_covers(
        &summary,
        Precision::F32,
        &other,
        &judged
    ));
    let more = [judged[0], judged[1], "gouraud"];
    assert!(!super::untimed::compared_covers(
        &summary,
        Precision::F32,
        &scene,
        &more
    ));
}
