//! Tests of the statistics, CSV/JSON summaries and limits of `compare`.
use super::*;
use crate::analysis::pixel::*;
use crate::analysis::stats::percentile;
use crate::output::Provenance;
use crate::truth::{Truth, Values};

#[test]
fn identical_images_give_exactly_zero() {
    let e: Vec<_> = (0..100).map(|i| (i % 10, i / 10, 0.0)).collect();
    let s = intensity_stats(e.iter().copied(), 0.01);
    assert_eq!(
        (s.mean_abs_error, s.max_abs_error, s.rmse, s.p99_abs_error),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!(s.psnr_db, None);
    assert_eq!(s.pixels_above_threshold, Some(0));
}

#[test]
fn one_pixel_off_gives_the_known_statistics() {
    let mut e: Vec<_> = (0..100u32).map(|i| (i % 10, i / 10, 0.0)).collect();
    e[37].2 = -0.5; // pixel (7, 3)
    let s = intensity_stats(e.iter().copied(), 0.01);
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
        (Some(1), 0.01)
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
        parse_limit("max_abs_error=0.5", Bound::Above).unwrap(),
        Limit {
            metric: "max_abs_error".into(),
            value: 0.5,
            bound: Bound::Above
        }
    );
    let e = parse_limit("max_error=1", Bound::Above)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown metric \"max_error\"") && e.contains("max_abs_error"),
        "{e}"
    );
    assert!(parse_limit("max_abs_error", Bound::Above).is_err());
    assert!(parse_limit("max_abs_error=abc", Bound::Above).is_err());
}

#[test]
fn limits_refuse_the_wrong_direction() {
    let e = parse_limit("psnr_db=40", Bound::Above)
        .unwrap_err()
        .to_string();
    assert!(e.contains("use --fail-below psnr_db=VALUE"), "{e}");
    let e = parse_limit("max_abs_error=0.1", Bound::Below)
        .unwrap_err()
        .to_string();
    assert!(e.contains("use --fail-above max_abs_error=VALUE"), "{e}");
    assert!(parse_limit("psnr_db=40", Bound::Below).is_ok());
    // every metric is accepted by exactly one of the two flags
    for m in METRICS {
        let above = parse_limit(&format!("{m}=1"), Bound::Above).is_ok();
        let below = parse_limit(&format!("{m}=1"), Bound::Below).is_ok();
        assert!(above != below, "{m}");
    }
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
        intensity: intensity_stats([(0, 0, 0.25)], 0.1),
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
        against_slerp: Some(AgainstReference {
            reference: SLERP_REFERENCE.into(),
            mean_abs_error: 0.5,
            max_abs_error: 1.0,
            max_normal_angle_deg: None,
            mean_normal_angle_deg: None,
        }),
    };
    assert_eq!(csv_row(&r).len(), csv_header().len());
    assert_eq!(r.metric("max_abs_error"), Some(0.25));
    assert_eq!(r.metric("max_normal_angle_deg"), None);
    assert_eq!(r.metric("non_finite_pixels"), Some(0.0));
    assert_eq!(r.metric("covered_pixels"), None, "not a metric");
    let cell = |name: &str| {
        let i = csv_header().iter().position(|h| h == name).unwrap();
        csv_row(&r)[i].clone()
    };
    assert_eq!(cell("max_abs_error"), "2.5e-1");
    assert_eq!(cell("non_finite_pixels"), "0");
    assert_eq!(cell("max_normal_angle_deg"), "");
    assert_eq!(cell("against_slerp_max_abs_error"), "1e0");
    assert_eq!(cell("g_rmse"), "0e0");
    for m in METRICS {
        assert!(
            csv_header().iter().any(|h| h == m),
            "metric {m} missing from the CSV"
        );
    }
}

/// Where a metric table breaks the one-row-per-variant rule: a row out of its variant's place,
/// or a name used twice.
fn metric_table_faults(rows: &[MetricRow]) -> Vec<String> {
    let mut bad = Vec::new();
    for (i, r) in rows.iter().enumerate() {
        if r.metric as usize != i {
            bad.push(format!(
                "{} at row {i}, variant {}",
                r.name, r.metric as usize
            ));
        }
        if rows[..i].iter().any(|q| q.name == r.name) {
            bad.push(format!("{} twice", r.name));
        }
    }
    bad
}

/// Each metric is one row: in its variant's place, named once; by name, each gives the field
/// it names (the CSV cell of a count is an integer), and only psnr_db is higher-is-better.
#[test]
fn metrics_are_one_typed_table() {
    assert_eq!(metric_table_faults(&METRIC_ROWS), Vec::<String>::new());
    assert_eq!(METRICS.len(), METRIC_ROWS.len());
    assert_eq!(HIGHER_IS_BETTER, ["psnr_db"]);
    for r in &METRIC_ROWS {
        assert_eq!(Metric::from_name(r.name), Some(r.metric));
        assert_eq!(r.metric.name(), r.name);
    }
    assert_eq!(Metric::from_name("luminance"), None);
    // Teeth: a swapped and a duplicated row are found.
    let (a, b) = (&METRIC_ROWS[0], &METRIC_ROWS[1]);
    let swapped = [MetricRow { ..*b }, MetricRow { ..*a }];
    assert_eq!(metric_table_faults(&swapped).len(), 2);
    let twice = [
        MetricRow { ..*a },
        MetricRow {
            metric: b.metric,
            ..*a
        },
    ];
    assert_eq!(metric_table_faults(&twice), ["mean_abs_error twice"]);
}

/// A frame of `n` covered pixels with the given colours (normal +z), and its truth: colour
/// `reference`, normal +z, `ill` marking ill-conditioned pixels.
fn synthetic(colors: &[[f32; 3]], reference: DVec3, ill: &[bool]) -> (Frame, Truth) {
    let frame = Frame {
        width: colors.len() as u32,
        height: 1,
        color: colors.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect(),
        normal: vec![[0.0, 0.0, 1.0, 1.0]; colors.len()],
    };
    let pixels = ill
        .iter()
        .map(|&ill| {
            Some(crate::truth::TruthPixel {
                color: reference,
                normal: Some(DVec3::Z),
                color_bound: 1e-6,
                normal_bound: 1e-6,
                // ill-conditioned when K_INTERP * U * amplification > ILL_CONDITIONED
                amplification: if ill { 1e9 } else { 1.0 },
            })
        })
        .collect();
    let truth = Truth {
        width: colors.len() as u32,
        height: 1,
        pixels,
    };
    (frame, truth)
}

/// The statistics a compare run would report for `frame` (no files written).
fn report(frame: &Frame, truth: &Truth) -> MethodReport {
    let m = crate::method::find("phong_exact").unwrap();
    let ref8 = srgb_rgb8(
        truth
            .pixels
            .iter()
            .map(|p| p.map(|p| p.color).unwrap_or(DVec3::ZERO)),
    );
    let opts = CompareOptions {
        images: false,
        ..CompareOptions::default()
    };
    let values = Values::from(truth);
    let a = Analysis {
        reference: &crate::analysis::scan::Prepared::new(&values),
        slerp: None,
        flip: &FlipReference::new(&ref8, frame.width, 1),
        out: Path::new("unused"),
        opts: &opts,
        width: frame.width,
        height: 1,
    };
    a.analyse(Subject::from(m), frame.clone(), drop).unwrap().0
}

#[test]
fn verify_and_compare_report_the_same_luminance_error() {
    // red off by 0.1: luminance off by 0.2126 * 0.1 (the largest channel error would be 0.1)
    let (frame, truth) = synthetic(
        &[[0.5, 0.2, 0.2], [0.4, 0.2, 0.2]],
        DVec3::new(0.4, 0.2, 0.2),
        &[false, false],
    );
    let expected = LUMINANCE[0] * 0.1;
    let verify = error_stats(&frame, true, &truth);
    let compare = report(&frame, &truth);
    crate::testutil::assert_close("verify max", verify.max_abs_error, expected, 1e-8);
    crate::testutil::assert_close(
        "compare max",
        compare.intensity.max_abs_error,
        expected,
        1e-8,
    );
    crate::testutil::assert_close(
        "verify mean",
        verify.mean_abs_error,
        compare.intensity.mean_abs_error,
        1e-15,
    );
    // the per-channel error is reported as such, under its own name
    crate::testutil::assert_close("red", compare.channels[0].max_abs_error, 0.1, 1e-7);
}

#[test]
fn ill_conditioned_pixels_are_left_out_of_every_statistic() {
    // pixel 1 is ill-conditioned and far off: no statistic may pool it, FLIP's mask included
    let (frame, truth) = synthetic(
        &[[0.4; 3], [1.0; 3], [0.4; 3]],
        DVec3::splat(0.4),
        &[false, true, false],
    );
    let f = pixel_errors(&frame, true, &truth);
    assert_eq!(f.measured, vec![true, false, true]);
    assert_eq!((f.counts.measured, f.counts.ill_conditioned), (2, 1));
    let r = report(&frame, &truth);
    assert_eq!((r.covered_pixels, r.ill_conditioned_pixels), (2, 1));
    assert!(r.intensity.max_abs_error < 1e-6 && r.channels[0].max_abs_error < 1e-6);
    // FLIP pools over `measured` too (its filter still spreads the ill pixel to neighbours,
    // as it spreads any pixel's difference, so its value here is not 0)
    assert_eq!(
        error_stats(&frame, true, &truth).max_abs_error,
        r.intensity.max_abs_error
    );
}

#[test]
fn non_finite_pixels_make_every_error_infinite_sort_last_and_fail_every_limit() {
    let nan = f32::NAN;
    for ill in [false, true] {
        // one NaN pixel among exact ones; once well-, once ill-conditioned
        let (frame, truth) = synthetic(
            &[[0.4; 3], [nan; 3], [0.4; 3]],
            DVec3::splat(0.4),
            &[false, ill, false],
        );
        let v = error_stats(&frame, true, &truth);
        assert_eq!(v.counts.non_finite, 1);
        assert_eq!(v.max_abs_error, f64::INFINITY, "verify, ill {ill}");
        assert_eq!(v.mean_abs_error, f64::INFINITY);
        let r = report(&frame, &truth);
        assert_eq!(r.non_finite_pixels, 1);
        assert_eq!(r.intensity.max_error_pixel, Some([1, 0]));
        for m in METRICS.iter().filter(|m| !m.ends_with("_pixels")) {
            let v = r.metric(m).unwrap();
            assert!(v.is_infinite(), "{m} = {v}, ill {ill}");
        }
        // JSON: null beside the count
        let json = serde_json::to_value(&r).unwrap();
        assert!(json["max_abs_error"].is_null() && json["psnr_db"].is_null());
        assert_eq!(json["non_finite_pixels"], 1);
        // every limit on an error metric fails, in either direction
        let mut good = report(
            &synthetic(&[[0.4; 3]; 3], DVec3::splat(0.4), &[false; 3]).0,
            &truth,
        );
        good.name = "good".into();
        let s = summary_of(vec![r.clone(), good]);
        for m in METRICS.iter().filter(|m| !m.ends_with("_pixels")) {
            let bound = if HIGHER_IS_BETTER.contains(m) {
                Bound::Below
            } else {
                Bound::Above
            };
            // a limit every finite value meets
            let v = if bound == Bound::Below { -1e30 } else { 1e30 };
            let l = parse_limit(&format!("{m}={v:e}"), bound).unwrap();
            let over = exceeded(&s, &[l]);
            assert_eq!(over.len(), 1, "{m}: {over:?}");
            assert_eq!(over[0].method, r.name);
        }
        // the table: last, shown as inf with the count
        let t = table(&s);
        let last = t.lines().last().unwrap();
        assert!(
            last.starts_with(&r.name) && last.contains("inf") && last.ends_with(" 1"),
            "{t}"
        );
    }
}

#[test]
fn a_method_that_measures_no_pixel_reports_no_error_and_fails_every_limit() {
    // the method covers none of the reference's three pixels
    let (mut frame, truth) = synthetic(&[[0.4; 3]; 3], DVec3::splat(0.4), &[false; 3]);
    frame.color.iter_mut().for_each(|c| c[3] = 0.0);
    let r = report(&frame, &truth);
    assert_eq!((r.covered_pixels, r.coverage_mismatch_pixels), (0, 3));
    // no figure: NaN (null in JSON), not the 0 of an exact match
    assert!(r.intensity.max_abs_error.is_nan() && r.intensity.mean_abs_error.is_nan());
    assert!(error_stats(&frame, true, &truth).max_abs_error.is_nan());
    let s = summary_of(vec![r]);
    for m in METRICS {
        let bound = if HIGHER_IS_BETTER.contains(m) {
            Bound::Below
        } else {
            Bound::Above
        };
        let v = if bound == Bound::Below { -1e30 } else { 1e30 };
        let over = exceeded(&s, &[parse_limit(&format!("{m}={v:e}"), bound).unwrap()]);
        assert_eq!(over.len(), 1, "{m}: {over:?}");
        assert!(
            over[0].to_string().contains("no pixel measured"),
            "{}",
            over[0]
        );
    }
}

/// An image with no covered pixel (a mesh out of view): the empty set's figures are null, the
/// per-channel ones and the normal's percentile too (they read 0.0, an exact match, and
/// `--fail-above p99_normal_angle_deg=1` said "= 0.000000e0 > 1e0"); the gate names the reason.
#[test]
fn an_image_with_no_covered_pixel_has_no_figure_and_the_gate_says_why() {
    let (mut frame, mut truth) = synthetic(&[[0.4; 3]; 3], DVec3::splat(0.4), &[false; 3]);
    frame.color.iter_mut().for_each(|c| c[3] = 0.0);
    truth.pixels.iter_mut().for_each(|p| *p = None);
    let r = report(&frame, &truth);
    assert_eq!((r.covered_pixels, r.coverage_mismatch_pixels), (0, 0));
    for c in &r.channels {
        assert!(
            c.mean_abs_error.is_nan() && c.max_abs_error.is_nan() && c.rmse.is_nan(),
            "{c:?}"
        );
    }
    assert!(r.p99_normal_angle_deg.unwrap().is_nan());
    // null in summary.json, not 0
    let json = serde_json::to_value(&r).unwrap();
    assert!(json["channels"][0]["mean_abs_error"].is_null(), "{json}");
    assert!(json["p99_normal_angle_deg"].is_null(), "{json}");
    let s = summary_of(vec![r]);
    let l = parse_limit("p99_normal_angle_deg=1", Bound::Above).unwrap();
    let over = exceeded(&s, &[l]);
    assert_eq!(over.len(), 1);
    let said = over[0].to_string();
    assert!(
        said.contains("p99_normal_angle_deg has no value") && said.contains("no pixel measured"),
        "{said}"
    );
    assert!(!said.contains("0.000000e0"), "{said}");
}

/// A method NaN at every pixel covers them all, each NaN: the gate says "non-finite at 3 of 3
/// pixels", not that it covers none of the reference's pixels.
#[test]
fn a_method_nan_at_every_pixel_is_said_to_be_non_finite_there() {
    let (frame, truth) = synthetic(&[[f32::NAN; 3]; 3], DVec3::splat(0.4), &[false; 3]);
    let r = report(&frame, &truth);
    assert_eq!((r.covered_pixels, r.non_finite_pixels), (0, 3));
    let s = summary_of(vec![r]);
    let l = parse_limit("max_abs_error=1", Bound::Above).unwrap();
    let said = exceeded(&s, &[l])[0].to_string();
    assert!(said.contains("non-finite at 3 of 3 pixels"), "{said}");
    assert!(!said.contains("covers none"), "{said}");
}

fn summary_of(methods: Vec<MethodReport>) -> Summary {
    Summary {
        schema_version: SCHEMA_VERSION,
        provenance: Provenance {
            tool: "shadelab".into(),
            version: String::new(),
            git_revision: String::new(),
            device: String::new(),
            driver: String::new(),
            driver_info: String::new(),
            vulkan_api: String::new(),
            mesa_version: None,
            llvm_version: None,
            method_files: Vec::new(),
        },
        engine: crate::engine::EngineKind::Vulkan,
        precision: crate::method::Precision::F32,
        scene: String::new(),
        scene_source: String::new(),
        mesh_input: None,
        triangles: 0,
        width: 1,
        height: 1,
        interpolation: "screen_linear".into(),
        reference: REFERENCE.into(),
        background_pixels: 0,
        threshold: 0.0,
        scale: ScaleMode::Fixed,
        timing: Timing {
            total_ms: 0.0,
            render_ms: 0.0,
            reference_ms: 0.0,
            metrics_ms: 0.0,
            flip_ms: 0.0,
            png_ms: 0.0,
            metric_pixels_per_second: 0.0,
            flip_pixels_per_second: 0.0,
        },
        methods,
        auto: None,
        auto_curve: Vec::new(),
    }
}

/// compare's FLIP (src/analysis/flip/, in Rust, near the differing pixels only) against nv-flip
/// over the whole image, on the shipped fine sphere at 160x120 drawn by the software engine:
/// every method's 8-bit image against the f64 reference gives the same map bit for bit (an
/// image equal to the reference's, nothing computed at all, included). Teeth: the test side
/// computed one pixel short of the filter radius changes the map of at least one method.
#[test]
fn flip_crops_match_the_full_computation_on_a_scene() {
    use crate::analysis::flip::{flip_map_full, map_off_radius_for_test};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sphere_fine.toml");
    let mut scene = crate::scene::load_scene(&path).unwrap();
    (scene.width, scene.height) = (160, 120);
    let methods: Vec<&'static Method> = ["phong_exact", "gouraud", "lyon_taylor", "flat"]
        .iter()
        .map(|n| method::find(n).unwrap())
        .collect();
    let prepared = engine::Ready::new(Engine::Software { threads: 1 }, &scene, &methods).unwrap();
    let (_, ids) = prepared.render(methods[0], true).unwrap();
    let reference = truth::values(prepared.base(), &ids.unwrap(), methods[0]);
    let ref8 = srgb_rgb8(
        reference
            .pixels()
            .map(|p| p.map(|p| p.color).unwrap_or(DVec3::ZERO)),
    );
    let (w, h) = (160, 120);
    let flip_ref = FlipReference::new(&ref8, w, h);
    let (mut short_differs, mut errors) = (false, 0);
    for m in &methods {
        let (frame, _) = prepared.render(m, false).unwrap();
        let test8 = srgb_rgb8(frame.color.iter().map(|&c| d3(c)));
        let bits = |v: Vec<f32>| v.into_iter().map(f32::to_bits).collect::<Vec<_>>();
        let full = bits(flip_map_full(&ref8, &test8, w, h));
        errors += usize::from(full.iter().any(|&b| b != 0));
        assert_eq!(bits(flip_ref.map(&test8)), full, "{}", m.name);
        short_differs |= bits(map_off_radius_for_test(&flip_ref, &test8, -1)) != full;
    }
    // phong_exact may equal the reference at 8 bits (no crop at all); flat and gouraud do not
    assert!(errors >= 2, "only {errors} methods with a FLIP error");
    assert!(
        short_differs,
        "crops of radius r - 1 should miss some error"
    );
}

/// render.png from the frame's RGBA bytes (`frame_rgba8` + `write_png_rgba8`, the fast path)
/// has the bytes of `output::write_png_srgb` of the frame's floats (the straightforward one),
/// and FLIP's test image taken from them is `srgb_rgb8`'s; teeth: a different alpha in the
/// frame gives other bytes.
#[test]
fn render_png_from_the_shared_8_bit_image_is_write_png_srgb() {
    let (w, h) = (7u32, 5u32);
    let color: Vec<[f32; 4]> = (0..w * h)
        .map(|i| {
            let x = i as f32 / (w * h) as f32;
            let a = [0.0, 0.25, 1.0, f32::NAN, 2.0][i as usize % 5];
            [x, x * x, 1.0 - x, a]
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let (fast, plain) = (dir.path().join("fast.png"), dir.path().join("plain.png"));
    let rgba = output::srgb::frame_rgba8(&color);
    output::write_png_rgba8(&fast, w, h, &rgba).unwrap();
    output::write_png_srgb(&plain, w, h, &color).unwrap();
    let bytes = |p: &Path| std::fs::read(p).unwrap();
    assert_eq!(bytes(&fast), bytes(&plain));
    assert_eq!(
        output::srgb::rgb8_of_rgba8(&rgba),
        srgb_rgb8(color.iter().map(|&c| d3(c)))
    );
    let mut other = color.clone();
    other[3][3] = 0.5;
    output::write_png_rgba8(&fast, w, h, &output::srgb::frame_rgba8(&other)).unwrap();
    assert_ne!(bytes(&fast), bytes(&plain));
}

/// `percentiles` (each selection over the part at or above the previous one) gives the bits of
/// `percentile` on a fresh copy, for ascending, repeated and descending percentiles, on values
/// with ties, signed zeros and a wide range. Teeth: the same check against the neighbouring
/// rank fails.
#[test]
fn percentiles_equal_one_selection_each() {
    use crate::analysis::stats::percentiles;
    let mut rng = fastrand::Rng::with_seed(26);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for n in [1usize, 2, 3, 7, 100, 1001, 4096] {
        let values: Vec<f64> = (0..n)
            .map(|i| match i % 5 {
                0 => (rng.u32(0..8) as f64) * 0.25, // ties
                1 => -0.0,
                2 => 0.0,
                _ => rng.f64() * 10f64.powi(rng.i32(-12..3)),
            })
            .collect();
        let ps_sets: [[f64; 3]; 4] = [
            [50.0, 95.0, 99.0],
            [1.0, 1.0, 100.0],
            [99.0, 50.0, 95.0],
            [0.0, 99.9, 12.5],
        ];
        for ps in ps_sets {
            let one = ps.map(|p| percentile(&mut values.clone(), p));
            let all = percentiles(&mut values.clone(), ps);
            assert_eq!(bits(&all), bits(&one), "n {n}, ps {ps:?}");
        }
    }
    assert_eq!(percentiles(&mut [], [50.0, 99.0]), [0.0, 0.0]);
    // teeth: the k-th value differs from the (k+1)-th of distinct values
    let mut v: Vec<f64> = (0..100).map(|i| (i * 37 % 100) as f64).collect();
    let got = percentiles(&mut v.clone(), [50.0, 95.0]);
    assert_ne!(
        bits(&got),
        bits(&[50.0, 96.0].map(|p| percentile(&mut v, p)))
    );
}

/// `f` of the software engine's frames of `methods` on the shipped fine sphere at 160x120,
/// with the run's id pass, truth and scene inputs.
fn with_sphere_frames(
    methods: &[&'static Method],
    f: impl FnOnce(&[Frame], &crate::frame::IdFrame, &Values, &crate::scene::SceneInputs),
) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sphere_fine.toml");
    let mut scene = crate::scene::load_scene(&path).unwrap();
    (scene.width, scene.height) = (160, 120);
    let exact = method::phong_exact();
    let mut all = methods.to_vec();
    all.push(exact);
    let prepared = engine::Ready::new(Engine::Software { threads: 1 }, &scene, &all).unwrap();
    let ids = prepared.render(exact, true).unwrap().1.unwrap();
    let reference = truth::values(prepared.base(), &ids, exact);
    let frames: Vec<Frame> = methods
        .iter()
        .map(|m| prepared.render(m, false).unwrap().0)
        .collect();
    f(&frames, &ids, &reference, prepared.base());
}

/// The slerp twin evaluated once per run (`Twin`, what compare uses) gives the statistics of
/// `stats_against_twin` (evaluated per pixel for each method) bit for bit, for every method
/// judged against slerp, on the fine sphere drawn by the software engine. Teeth: a twin of
/// another method gives other statistics, and a twin of another id pass is refused.
#[test]
fn slerp_twin_once_per_run_gives_the_per_pixel_statistics() {
    let methods: Vec<&'static Method> = method::METHODS
        .iter()
        .filter(|m| m.reference == Reference::PhongAndSlerp)
        .collect();
    assert!(
        methods.len() >= 3,
        "{} methods judged against slerp",
        methods.len()
    );
    let slerp = method::find("slerp").unwrap();
    with_sphere_frames(&methods, |frames, ids, reference, inputs| {
        let twin = Twin::new(inputs, ids, slerp);
        let other = Twin::new(inputs, ids, method::phong_exact());
        let mut others_differ = 0;
        for (m, frame) in methods.iter().zip(frames) {
            let per_pixel = stats_against_twin(frame, m.has_normal, reference, inputs, ids, slerp);
            let once = twin.stats(frame, m.has_normal, reference).unwrap();
            assert!(per_pixel.counts.measured > 10_000, "{}", m.name);
            assert_eq!(format!("{once:?}"), format!("{per_pixel:?}"), "{}", m.name);
            let wrong = other.stats(frame, m.has_normal, reference).unwrap();
            others_differ += usize::from(format!("{wrong:?}") != format!("{per_pixel:?}"));
        }
        assert_eq!(others_differ, methods.len());
        // another id pass: one pixel fewer covered, or another size
        let mut fewer = ids.clone();
        let i = fewer.prim.iter().position(|&p| p != 0).unwrap();
        fewer.prim[i] = 0;
        let m = methods[0];
        let refused = |ids: &crate::frame::IdFrame| {
            Twin::new(inputs, ids, slerp)
                .stats(&frames[0], m.has_normal, reference)
                .is_err()
        };
        assert!(refused(&fewer));
        let mut smaller = ids.clone();
        smaller.prim.pop();
        smaller.weights.pop();
        assert!(refused(&smaller));
        assert!(!refused(ids));
    });
}

/// `PixelErrors::intensity_stats` (compare's) gives `intensity_stats(errors())` (the generic
/// one, verify's tests') bit for bit on real frames, at two thresholds. Teeth: one error moved
/// in magnitude changes the generic statistics, so the comparison sees the last bit.
#[test]
fn intensity_stats_of_the_maps_equal_the_generic_ones() {
    let methods: Vec<&'static Method> = ["flat", "gouraud", "lyon_taylor", "phong_exact"]
        .iter()
        .map(|n| method::find(n).unwrap())
        .collect();
    with_sphere_frames(&methods, |frames, _, reference, _| {
        for (m, frame) in methods.iter().zip(frames) {
            let f = pixel_errors(frame, m.has_normal, reference);
            for threshold in [1.0 / 255.0, 1e-5] {
                let fast = f.intensity_stats(threshold);
                let generic = intensity_stats(f.errors(), threshold);
                assert_eq!(format!("{fast:?}"), format!("{generic:?}"), "{}", m.name);
            }
        }
        let f = pixel_errors(&frames[0], true, reference);
        let mut e: Vec<_> = f.errors().collect();
        let before = format!("{:?}", intensity_stats(e.iter().copied(), 0.01));
        // the largest |error| one ulp larger: max_abs_error moves by that ulp
        let k = (0..e.len())
            .max_by(|&a, &b| e[a].2.abs().total_cmp(&e[b].2.abs()))
            .unwrap();
        e[k].2 = f64::from_bits(e[k].2.to_bits() + 1);
        assert_ne!(
            format!("{:?}", intensity_stats(e.iter().copied(), 0.01)),
            before
        );
    });
}

/// compare's scan over the reference's columns (`Prepared`) gives the generic scan's per-pixel
/// errors (over `Values::pixels`) bit for bit on real frames, for methods with and without a
/// normal. Teeth: one pixel's colour one ulp off changes the errors the comparison sees.
#[test]
fn the_column_scan_gives_the_generic_errors_on_sphere_frames() {
    let methods: Vec<&'static Method> = ["flat", "gouraud", "lyon_taylor", "slerp", "phong_exact"]
        .iter()
        .map(|n| method::find(n).unwrap())
        .collect();
    with_sphere_frames(&methods, |frames, _, reference, _| {
        let prepared = crate::analysis::scan::Prepared::new(reference);
        for (m, frame) in methods.iter().zip(frames) {
            let generic = format!("{:?}", pixel_errors(frame, m.has_normal, reference));
            let columns = format!("{:?}", pixel_errors(frame, m.has_normal, &prepared));
            assert_eq!(columns, generic, "{}", m.name);
            let mut off = frame.clone();
            let errors = pixel_errors(frame, m.has_normal, reference);
            let i = errors.measured.iter().position(|&m| m).unwrap();
            off.color[i][0] = f32::from_bits(off.color[i][0].to_bits() + 1);
            let columns_off = format!("{:?}", pixel_errors(&off, m.has_normal, &prepared));
            assert_ne!(columns_off, generic, "{}", m.name);
        }
    });
}
