//! Tests of the statistics, CSV/JSON summaries and limits of `compare`.
use super::*;
use crate::analysis::pixel::*;

#[test]
fn identical_images_give_exactly_zero() {
    let e: Vec<_> = (0..100).map(|i| (i % 10, i / 10, 0.0)).collect();
    let s = intensity_stats(&e, 0.01);
    assert_eq!(
        (s.mean_abs_error, s.max_abs_error, s.rmse, s.p99_abs_error),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!(s.psnr_db, None);
    assert_eq!(s.pixels_above_threshold, 0);
}

#[test]
fn one_pixel_off_gives_the_known_statistics() {
    let mut e: Vec<_> = (0..100u32).map(|i| (i % 10, i / 10, 0.0)).collect();
    e[37].2 = -0.5; // pixel (7, 3)
    let s = intensity_stats(&e, 0.01);
    assert_eq!(s.max_abs_error, 0.5);
    assert_eq!(s.max_error_pixel, Some([7, 3]));
    assert!((s.mean_abs_error - 0.005).abs() < 1e-15);
    assert!((s.rmse - 0.05).abs() < 1e-15);
    // nearest rank: p99 of 100 values is the 99th smallest = 0, p100 would be 0.5
    assert_eq!(s.p99_abs_error, 0.0);
    assert_eq!(s.p50_abs_error, 0.0);
    assert!((s.psnr_db.unwrap() - 10.0 * (1.0f64 / 0.0025).log10()).abs() < 1e-12);
    assert_eq!(
        (s.pixels_above_threshold, s.fraction_above_threshold),
        (1, 0.01)
    );
}

#[test]
fn percentiles_are_nearest_rank() {
    let mut v: Vec<f64> = (1..=10).map(|x| x as f64).collect();
    assert_eq!(percentile(&mut v, 50.0), 5.0);
    assert_eq!(percentile(&mut v, 95.0), 10.0);
    assert_eq!(percentile(&mut v, 10.0), 1.0);
    assert_eq!(percentile(&mut v, 0.0), 1.0);
    assert_eq!(percentile(&mut [], 50.0), 0.0);
}

#[test]
fn limits_parse_and_reject_unknown_metrics() {
    assert_eq!(
        parse_limit("max_abs_error=0.5").unwrap(),
        ("max_abs_error".into(), 0.5)
    );
    let e = parse_limit("max_error=1").unwrap_err().to_string();
    assert!(
        e.contains("unknown metric \"max_error\"") && e.contains("max_abs_error"),
        "{e}"
    );
    assert!(parse_limit("max_abs_error").is_err());
    assert!(parse_limit("max_abs_error=abc").is_err());
}

#[test]
fn csv_rows_match_the_header() {
    let r = MethodReport {
        name: "x".into(),
        reference: REFERENCE.into(),
        covered_pixels: 1,
        coverage_mismatch_pixels: 0,
        ill_conditioned_pixels: 0,
        non_finite_pixels: 0,
        intensity: intensity_stats(&[(0, 0, 0.25)], 0.1),
        channels: [0, 1, 2].map(|_| ChannelStats {
            mean_abs_error: 0.0,
            max_abs_error: 0.0,
            rmse: 0.0,
        }),
        max_normal_angle_deg: None,
        mean_normal_angle_deg: None,
        p99_normal_angle_deg: None,
        max_normal_length_error: None,
        flip_mean: 0.0,
        flip_p95: 0.0,
        files: vec![],
    };
    assert_eq!(csv_row(&r).len(), csv_header().len());
    assert_eq!(r.metric("max_abs_error"), Some(0.25));
    assert_eq!(r.metric("max_normal_angle_deg"), None);
    for m in METRICS {
        assert!(
            csv_header().iter().any(|h| h == m),
            "metric {m} missing from the CSV"
        );
    }
}
