//! Tests of `auto`: the budget type (every accepted and refused form, one message), the error it
//! bounds, the candidates' order, the budget curve's names, the per-triangle choice, the cost
//! model's names and the grouping's fallback to one program.
use glam::DVec3;

use super::*;
use crate::method::Geometry;

fn find(name: &str) -> &'static Method {
    method::find(name).unwrap()
}

fn torus() -> SceneInputs {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
    let scene = crate::scene::load_scene(&path).unwrap();
    SceneInputs::new(&scene, Geometry::Mesh)
}

/// Numbers and fractions, spaces around them, are budgets; the value is the number's.
#[test]
fn a_budget_is_a_number_or_a_fraction() {
    let ok = |s: &str| {
        ErrorBudget::parse(s)
            .unwrap_or_else(|e| panic!("{s}: {e}"))
            .get()
    };
    assert_eq!(ok("4/255"), 4.0 / 255.0);
    assert_eq!(ok(" 4 / 255 "), 4.0 / 255.0);
    assert_eq!(ok("1/1024"), 1.0 / 1024.0);
    assert_eq!(ok("0.0039"), 0.0039);
    assert_eq!(ok("1e-3"), 1e-3);
    assert_eq!(ok("16"), 16.0);
    assert_eq!(
        "4/255".parse::<ErrorBudget>().unwrap(),
        ErrorBudget::parse("4/255").unwrap()
    );
    assert_eq!(ErrorBudget::DEFAULT.get(), 1.0 / 255.0);
    assert_eq!(ErrorBudget::new(0.5).unwrap().get(), 0.5);
}

/// Zero, negatives, non-finite values, division by zero and anything that is not a number are
/// refused, every one with the same message naming the input.
#[test]
fn a_budget_that_is_not_finite_and_positive_is_refused_with_one_message() {
    for s in [
        "0", "0/255", "-1/255", "-0.1", "1/0", "0/0", "inf", "NaN", "-inf", "", "/", "4/", "/255",
        "abc", "4/255/2", "1e999", "0x10",
    ] {
        let e = ErrorBudget::parse(s).expect_err(s);
        assert_eq!(
            e,
            format!(
                "{s:?} is not an error budget: expected a colour error > 0 (linear), a number \
                 or a fraction like 4/255 (1/255 = 0.0039)"
            )
        );
    }
    for v in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = ErrorBudget::new(v).expect_err("refused");
        assert!(e.contains("is not an error budget"), "{e}");
    }
}

#[test]
fn a_budget_list_is_budgets_separated_by_commas_or_none() {
    let l = ErrorBudget::parse_list("1/1024,1/255, 4/255").unwrap();
    let v: Vec<f64> = l.iter().map(|b| b.get()).collect();
    assert_eq!(v, [1.0 / 1024.0, 1.0 / 255.0, 4.0 / 255.0]);
    assert!(ErrorBudget::parse_list("none").unwrap().is_empty());
    let e = ErrorBudget::parse_list("1/255,0").unwrap_err();
    assert_eq!(e, ErrorBudget::parse("0").unwrap_err());
}

/// The error a budget bounds is the largest channel's; a non-finite channel is an infinite
/// error (it never fits a budget).
#[test]
fn the_error_a_budget_bounds_is_the_largest_channel_error() {
    assert_eq!(colour_error([0.1, 0.3, 0.2]), 0.3);
    assert_eq!(colour_error([0.0, 0.0, 0.0]), 0.0);
    for bad in [f64::NAN, f64::INFINITY] {
        assert_eq!(colour_error([0.1, bad, 0.2]), f64::INFINITY);
        assert_eq!(colour_error([bad, 0.1, 0.2]), f64::INFINITY);
    }
}

/// Cheapest first, an unmeasured (NaN) cost last among the others, phong_exact last whatever
/// it costs; a cost list of the wrong length is an error.
#[test]
fn candidates_are_ordered_by_cost_with_the_fallback_last() {
    let order = order_by_cost(|ms| {
        Ok(ms
            .iter()
            .map(|m| match m.name {
                "gouraud" => 3.0,
                "flat" => f64::NAN,
                "phong_unnormalized" => 1.0,
                "newton_raphson" => 2.0,
                _ => 0.5,
            })
            .collect())
    })
    .unwrap();
    let names: Vec<&str> = order.iter().map(|(m, _)| m.name).collect();
    assert_eq!(
        names,
        [
            "phong_unnormalized",
            "newton_raphson",
            "gouraud",
            "flat",
            method::PHONG_EXACT
        ]
    );
    assert_eq!(order[3].1, f64::INFINITY);
    assert!(order_by_cost(|_| Ok(vec![1.0])).is_err());
    let spec = AutoSpec::new(ErrorBudget::DEFAULT, &order);
    assert_eq!(spec.order.last().map(|m| m.name), Some(method::PHONG_EXACT));
}

/// The curve adds one spec per other budget, named by it; the run's own budget and repeats
/// are not added twice.
#[test]
fn the_budget_curve_adds_each_other_budget_once() {
    let spec = AutoSpec::new(ErrorBudget::DEFAULT, &[(method::phong_exact(), 1.0)]);
    let curve = ErrorBudget::parse_list("1/1024,1/255,4/255,4/255").unwrap();
    let names: Vec<String> = spec
        .with_curve(&curve)
        .into_iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(names, ["auto", "auto_1_1024", "auto_4_255"]);
}

#[test]
fn split_methods_takes_auto_out_of_a_list() {
    assert_eq!(
        split_methods("flat, auto,gouraud"),
        ("flat,gouraud".into(), true)
    );
    assert_eq!(
        split_methods("flat,gouraud"),
        ("flat,gouraud".into(), false)
    );
    assert_eq!(split_methods("auto"), (String::new(), true));
}

/// The summary counts the triangles per candidate, in the spec's order.
#[test]
fn the_summary_counts_the_choice() {
    let inputs = torus();
    let spec = spec_with_costs(&[1.0, 2.0, 3.0]);
    let (pick, s) = choose_summarised(&inputs, &spec, Cache::Bypass);
    assert_eq!(s.source, ChoiceSource::Computed);
    let total: usize = s.triangles.iter().map(|(_, k)| k).sum();
    assert_eq!(total, inputs.triangle_count());
    for (i, (name, k)) in s.triangles.iter().enumerate() {
        assert_eq!(name, spec.order[i].name);
        assert_eq!(*k, pick.iter().filter(|&&p| p == i).count());
    }
    assert!(
        s.line().starts_with("auto (budget 3.922e-3, chosen in"),
        "{}",
        s.line()
    );
}

fn order() -> Vec<&'static Method> {
    vec![
        find("gouraud"),
        find("newton_raphson"),
        method::phong_exact(),
    ]
}

/// The budget decides: a tiny budget leaves mostly phong_exact (the fallback), a huge one
/// takes the cheapest everywhere, and 1/255 mixes; every choice but the fallback keeps its
/// sampled error within half the budget.
#[test]
fn auto_chooses_the_cheapest_method_within_the_budget() {
    let inputs = torus();
    let ms = order();
    let all = |pick: &[usize], k: usize| pick.iter().all(|&i| i == k);
    // a tiny budget: exact Phong, but where a cheaper method is exact too (triangles in
    // shadow, lit by the ambient term alone)
    let tiny = choose(&inputs, &ms, 1e-12);
    assert!(tiny.iter().filter(|&&k| k == 2).count() > tiny.len() / 2);
    assert!(
        all(&choose(&inputs, &ms, 10.0), 0),
        "anything passes a huge budget"
    );
    let pick = choose(&inputs, &ms, 1.0 / 255.0);
    assert_eq!(pick.len(), inputs.triangle_count());
    let used: std::collections::BTreeSet<usize> = pick.iter().copied().collect();
    assert!(
        used.len() >= 2,
        "the torus needs more than one method: {used:?}"
    );
    let lighting = inputs.lighting();
    for (t, &k) in pick.iter().enumerate().filter(|(_, &k)| k < 2) {
        for w in [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::splat(1.0 / 3.0),
            DVec3::new(0.5, 0.5, 0.0),
        ] {
            let f = inputs.fragment(t, w, glam::DVec2::ZERO);
            let e = lighting.shade(crate::method::formulas::normalize_exact(
                f.interpolated_normal(),
            ));
            let err = (ms[k].eval_f64(&f, &lighting).color - e)
                .abs()
                .max_element();
            assert!(
                err * 2.0 <= 1.0 / 255.0 + 1e-12,
                "triangle {t}: {} {err}",
                ms[k].name
            );
        }
    }
}

#[test]
fn auto_curve_names_are_identifiers_that_tell_the_budget() {
    assert_eq!(curve_name(4.0 / 255.0), "auto_4_255");
    assert_eq!(curve_name(1.0 / 1024.0), "auto_1_1024");
    assert_eq!(curve_name(0.002), "auto_1_500");
    assert_eq!(curve_name(0.0123), "auto_12300e_6");
    for b in [4.0 / 255.0, 1.0 / 1024.0, 0.0123, 0.5] {
        let n = curve_name(b);
        assert!(
            n.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'),
            "{n}"
        );
    }
}

/// `auto` over [`order`] at 1/255 with these costs (gouraud, newton_raphson, phong_exact).
fn spec_with_costs(costs: &[f64]) -> AutoSpec {
    AutoSpec {
        name: "auto".into(),
        order: order(),
        budget: ErrorBudget::new(1.0 / 255.0).unwrap(),
        costs: costs.to_vec(),
        cost_model: crate::cost::CostModelId::parse("test").unwrap(),
    }
}

/// When the extra programs save less than a switch costs (every candidate as dear as the next)
/// the torus is drawn with one program, however many the per-triangle choice used: drawing
/// the choice as it is (the behaviour before) fails this. Where the cheap program saves much
/// (gouraud at a tenth of the cost) the grouping is kept. Every triangle stays within budget.
#[test]
fn grouping_falls_back_to_one_program_when_the_switches_cost_more() {
    let inputs = torus();
    let ms = order();
    let chosen = choose(&inputs, &ms, 1.0 / 255.0);
    let programs = |p: &[usize]| p.iter().collect::<std::collections::BTreeSet<_>>().len();
    assert!(
        programs(&chosen) >= 2,
        "the torus needs two programs or more"
    );
    let budget = 1.0 / 255.0;
    let check_budget = |pick: &[usize]| {
        for (k, m) in ms.iter().enumerate() {
            let tris: Vec<usize> = (0..pick.len()).filter(|&t| pick[t] == k).collect();
            assert!(within_budget(&inputs, m, &tris, budget), "{}", m.name);
        }
    };
    // Equal costs: nothing to save, one program.
    let flat = spec_with_costs(&[1.0, 1.0, 1.0]);
    let (pick, s) = choose_summarised(&inputs, &flat, Cache::Bypass);
    let g = s.grouping.clone().unwrap();
    assert_eq!(programs(&pick), 1, "{}", s.line());
    assert_eq!((g.programs_drawn, g.switches), (1, 0));
    assert_eq!(g.programs_chosen, programs(&chosen));
    assert_eq!(g.decision, "one program");
    assert!(!g.merged.is_empty() && g.kept.is_empty());
    check_budget(&pick);
    // Cheap gouraud, newton_raphson as dear as phong_exact: gouraud kept (if it saves more
    // than a switch), newton_raphson merged.
    let cheap = spec_with_costs(&[0.1, 1.0, 1.0]);
    let (pick, s) = choose_summarised(&inputs, &cheap, Cache::Bypass);
    let g = s.grouping.clone().unwrap();
    let gouraud_area: f64 = {
        let areas = window_areas(&inputs);
        let total: f64 = areas.iter().sum();
        (0..chosen.len())
            .filter(|&t| chosen[t] == 0)
            .map(|t| areas[t])
            .sum::<f64>()
            * 0.9
            / total
    };
    assert!(
        gouraud_area > SWITCH_COST,
        "the torus's gouraud share {gouraud_area}"
    );
    assert_eq!(g.decision, "grouped", "{}", s.line());
    assert!(
        g.kept.iter().any(|(m, _, _)| m == "gouraud"),
        "{}",
        s.line()
    );
    assert!(
        !pick.contains(&1),
        "newton_raphson saves nothing: {}",
        s.line()
    );
    assert_eq!(g.switches, programs(&pick) - 1);
    check_budget(&pick);
}

/// The one program is the dearest chosen when it keeps the budget everywhere, else the
/// fallback; a non-finite cost leaves the choice as it is.
#[test]
fn settle_picks_the_single_program_and_refuses_non_finite_costs() {
    let spec = spec_with_costs(&[1.0, 1.0, 1.0]);
    let areas = [1.0; 4];
    let mut pick = vec![0, 1, 0, 1];
    let g = settle(&spec, &areas, &mut pick, &|_, _| true);
    assert_eq!(g.single, "newton_raphson");
    assert_eq!(pick, [1, 1, 1, 1]);
    let mut pick = vec![0, 1, 0, 1];
    let g = settle(&spec, &areas, &mut pick, &|k, _| k == 2);
    assert_eq!(g.single, method::PHONG_EXACT);
    assert_eq!(pick, [2, 2, 2, 2]);
    let nan = spec_with_costs(&[f64::NAN, 1.0, 1.0]);
    let mut pick = vec![0, 1, 0, 1];
    let g = settle(&nan, &areas, &mut pick, &|_, _| true);
    assert!(g.decision.starts_with("not judged"), "{}", g.decision);
    assert_eq!(pick, [0, 1, 0, 1]);
    // Savings above the switch cost keep the group.
    let cheap = spec_with_costs(&[0.0, 1.0, 1.0]);
    let mut pick = vec![0, 1, 0, 1];
    let g = settle(&cheap, &areas, &mut pick, &|_, _| true);
    assert_eq!(pick, [0, 1, 0, 1]);
    assert_eq!(g.kept, vec![("gouraud".to_string(), 2, 0.5)]);
}

fn ratio(median: f64, low: f64, high: f64, rounds: usize) -> crate::analysis::stats::RatioEstimate {
    crate::analysis::stats::RatioEstimate {
        median,
        ci95_low: low,
        ci95_high: high,
        rounds,
        non_finite: 0,
        confidence: 0.95,
    }
}

/// The frame check decides: a grouping the model keeps (cheap gouraud on the torus) is drawn
/// only when its measured interval lies wholly below one program's frame. A grouping that
/// measured as dear (suzanne's 1.030 [1.024, 1.041]) or inconclusive, or whose interval is
/// not finite or empty, comes out as one program on every triangle, still within budget, and
/// the summary says so; one that measured cheaper (the fine sphere's 0.733 [0.714, 0.760])
/// keeps its groups. Ignoring the measurement (the behaviour before) fails the first case.
#[test]
fn the_frame_check_keeps_the_grouping_only_when_it_measured_cheaper() {
    let inputs = torus();
    let cheap = spec_with_costs(&[0.1, 1.0, 1.0]);
    let programs = |p: &[usize]| p.iter().collect::<std::collections::BTreeSet<_>>().len();
    let settled = || {
        let (pick, s) = choose_summarised(&inputs, &cheap, Cache::Bypass);
        assert_eq!(s.grouping.as_ref().unwrap().decision, "grouped");
        assert!(programs(&pick) >= 2);
        (pick, s)
    };
    let predicted = settled().1.grouping.unwrap().predicted_saving();
    assert!(predicted > SWITCH_COST, "{predicted}");
    let cases = [
        (ratio(1.030, 1.024, 1.041, 30), false),
        (ratio(0.99, 0.97, 1.01, 16), false),
        (ratio(f64::NAN, f64::NAN, f64::NAN, 16), false),
        (ratio(0.5, 0.4, 0.6, 0), false),
        (ratio(0.733, 0.714, 0.760, 30), true),
    ];
    for (r, keep) in cases {
        let (mut pick, mut s) = settled();
        let before = pick.clone();
        let check = FrameCheck::measured(&r, predicted);
        assert_eq!(check.grouped, keep, "{r:?}");
        assert_eq!(apply_frame_check(&cheap, &mut pick, &mut s, check), keep);
        let g = s.grouping.clone().unwrap();
        assert!(g.frame.is_some(), "the check is in the summary");
        let drawn: usize = s.triangles.iter().map(|(_, k)| k).sum();
        assert_eq!(drawn, pick.len());
        if keep {
            assert_eq!(pick, before);
            assert_eq!(g.decision, "grouped");
            assert!(
                s.line().contains("grouping kept (measured cheaper)"),
                "{}",
                s.line()
            );
        } else {
            assert_eq!(programs(&pick), 1, "{}", s.line());
            assert!(pick.iter().all(|&k| k == g.single_index(&cheap).unwrap()));
            assert_eq!((g.programs_drawn, g.switches), (1, 0));
            assert_eq!(g.decision, "one program (frame check)");
            assert!(g.kept.is_empty() && !g.merged.is_empty());
            assert!(s
                .line()
                .contains("one program (the grouping did not measure cheaper)"));
            let single = g.single_index(&cheap).unwrap();
            assert!(within_budget(
                &inputs,
                cheap.order[single],
                &(0..pick.len()).collect::<Vec<_>>(),
                1.0 / 255.0
            ));
        }
    }
    // A parent run's decision is drawn as given, and said to be the parent's.
    let (mut pick, mut s) = settled();
    assert!(!apply_frame_check(
        &cheap,
        &mut pick,
        &mut s,
        FrameCheck::given(false, predicted)
    ));
    assert!(s.line().contains("parent run"), "{}", s.line());
    // The summary survives its JSON (a given check has no ratio: null, not NaN).
    let back: AutoSummary = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
    assert_eq!(back, s);
}

/// A tuned row (unregistered: only its row) of newton_raphson's seed `(3 - z)/2` and three
/// Newton steps, accurate to ~1e-9 on the torus, proven (by this test's word) on `domain`.
fn tuned_row(name: &'static str, domain: [f64; 2]) -> &'static Method {
    use crate::method::tuned::{Tuned, TunedForm};
    Tuned {
        form: TunedForm::Newton,
        steps: 3,
        coeffs: vec![1.5, -0.5],
        domain,
        length_error: None,
    }
    .row(name, "/nowhere/tuned.glsl")
}

/// The proof licenses a tuned row, the samples do not: on the torus a tuned row whose proven
/// domain starts at the median of the triangles' smallest z is drawn on no triangle whose
/// range of z reaches below it, although its samples pass there (the same formula proven on
/// [0, 2] is drawn on every triangle), and on the triangles inside it it is drawn (the
/// cheapest, first in the order).
#[test]
fn auto_never_draws_a_tuned_row_below_its_proven_domain() {
    use crate::geometry::zdomain::triangle_z_range;
    let inputs = torus();
    let lows: Vec<f64> = (0..inputs.triangle_count())
        .map(|t| triangle_z_range(inputs.vertex_normals(t)).lo)
        .collect();
    let mut sorted = lows.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    assert!(sorted[0] < median, "the torus has triangles of different z");
    let budget = 1.0 / 255.0;
    let everywhere = tuned_row("tuned_everywhere", [0.0, 2.0]);
    let pick = choose(&inputs, &[everywhere, method::phong_exact()], budget);
    assert!(
        pick.iter().all(|&k| k == 0),
        "its samples pass on every triangle"
    );
    let half = tuned_row("tuned_half", [median, 2.0]);
    let pick = choose(&inputs, &[half, method::phong_exact()], budget);
    let (mut below, mut drawn) = (0, 0);
    for (t, &k) in pick.iter().enumerate() {
        if lows[t] < median {
            assert_eq!(k, 1, "triangle {t}: z from {} below {median}", lows[t]);
            below += 1;
        } else {
            assert_eq!(k, 0, "triangle {t} is inside the domain");
            drawn += 1;
        }
    }
    assert!(below > 0 && drawn > 0, "{below} {drawn}");
    // the grouping's merges ask the same question
    let outside: Vec<usize> = (0..lows.len()).filter(|&t| lows[t] < median).collect();
    assert!(!within_budget(&inputs, half, &outside, budget));
    assert!(within_budget(&inputs, everywhere, &outside, budget));
    // the upper end counts too: a domain ending below the normals' |n|^2
    let short = tuned_row("tuned_short", [0.0, 0.99]);
    let pick = choose(&inputs, &[short, method::phong_exact()], budget);
    assert!(
        pick.iter().all(|&k| k == 1),
        "no triangle's z ends below 0.99"
    );
}
