//! Unit tests of the report without a device: escaping, numbers, dates, ids, the link checker
//! (with teeth: each kind of broken link must be flagged).
use super::html::{esc, number};
use super::links::{attribute_values, broken_in};
use super::*;

/// The charts' error axes and their off-scale markers (tests/svg_axes.rs).
mod svg_axes;

#[test]
fn escaping_covers_every_special_character() {
    assert_eq!(
        esc(r#"<img src=x onerror="a('b')"> & co"#),
        "&lt;img src=x onerror=&quot;a(&#39;b&#39;)&quot;&gt; &amp; co"
    );
    assert_eq!(esc("plain_name 1.5"), "plain_name 1.5");
}

#[test]
fn numbers_show_non_finite_and_missing_as_such() {
    assert_eq!(number(None), (String::new(), "n/a".into()));
    assert_eq!(
        number(Some(f64::INFINITY)),
        ("Infinity".into(), "inf".into())
    );
    assert_eq!(
        number(Some(f64::NEG_INFINITY)),
        ("-Infinity".into(), "-inf".into())
    );
    assert_eq!(number(Some(f64::NAN)), ("NaN".into(), "NaN".into()));
    assert_eq!(number(Some(42.0)).1, "42");
    assert_eq!(number(Some(0.012345)).1, "0.01235");
    assert_eq!(number(Some(12.3456)).1, "12.35");
    assert_eq!(number(Some(3.2e-6)).1, "3.200e-6");
    // The key keeps full precision for sorting.
    assert_eq!(number(Some(3.2e-6)).0.parse::<f64>().unwrap(), 3.2e-6);
}

#[test]
fn utc_dates_match_known_instants() {
    assert_eq!(format_utc(0), "1970-01-01 00:00 UTC");
    // 2000-02-29 12:34:56 UTC (a leap day) = 951827696.
    assert_eq!(format_utc(951_827_696), "2000-02-29 12:34 UTC");
    // 2024-12-31 23:59 UTC = 1735689599.
    assert_eq!(format_utc(1_735_689_599), "2024-12-31 23:59 UTC");
}

#[test]
fn scene_ids_are_safe_and_unique() {
    assert_eq!(scene_id("sphere_fine", &[]), "sphere_fine");
    assert_eq!(scene_id("a b/<c>", &[]), "a_b__c_");
    assert_eq!(scene_id("", &[]), "scene");
    let taken = vec!["x".to_string(), "x-2".to_string()];
    assert_eq!(scene_id("x", &taken), "x-3");
}

#[test]
fn attributes_are_found_whole_and_unescaped() {
    let html = r#"<a href="a&amp;b.html">x</a><img data-src="no.png" src='y.png'><p id="p1">"#;
    assert_eq!(attribute_values(html, "href"), vec!["a&b.html"]);
    assert_eq!(attribute_values(html, "src"), vec!["y.png"]);
    assert_eq!(attribute_values(html, "id"), vec!["p1"]);
}

/// The link checker passes a good page and flags each kind of bad link (teeth).
#[test]
fn link_checker_flags_every_kind_of_broken_link() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("sub dir")).unwrap();
    std::fs::write(dir.path().join("sub dir/a.png"), b"x").unwrap();
    std::fs::write(dir.path().join("b.css"), b"x").unwrap();
    std::fs::write(dir.path().join("c.html"), r#"<h2 id="there">x</h2>"#).unwrap();
    let good = r##"<link href="b.css"><img src="sub%20dir/a.png"><a href="#top">t</a>
        <a href="b.css#frag">f</a><a href="c.html#there">c</a><div id="top"></div>"##;
    assert_eq!(broken_in(good, dir.path()), Vec::<String>::new());
    for (bad, why) in [
        (r#"<img src="sub dir/missing.png">"#, "no file"),
        (r##"<a href="#nowhere">x</a>"##, "no element with id"),
        (
            r##"<a href="c.html#nowhere">x</a>"##,
            "c.html has no element with id",
        ),
        (
            r#"<script src="https://cdn.example/x.js"></script>"#,
            "not a relative path",
        ),
        (
            r#"<link href="//fonts.example/f.css">"#,
            "not a relative path",
        ),
        (r#"<img src="/etc/passwd">"#, "not a relative path"),
        (r#"<img src="../b.css">"#, "leaves the report"),
        (
            r#"<img src="data:image/png;base64,AAAA">"#,
            "not a relative path",
        ),
    ] {
        let found = broken_in(bad, dir.path());
        assert!(
            found.len() == 1 && found[0].contains(why),
            "{bad}: expected one {why:?}, got {found:?}"
        );
    }
}

/// A NaN figure stays a number (shown "NaN", styled non-finite) where JSON would write null and
/// the column would read "n/a" or be dropped; a field that does not apply stays absent ("n/a").
#[test]
fn bench_numbers_keep_nan_apart_from_does_not_apply() {
    #[derive(serde::Serialize)]
    struct Row {
        name: String,
        median_ms: f64,
        ratio: f64,
        overdraw: Option<f64>,
        samples: usize,
    }
    let row = Row {
        name: "m".into(),
        median_ms: 1.5,
        ratio: f64::NAN,
        overdraw: None,
        samples: 3,
    };
    let n = super::body::row_numbers(&row);
    assert_eq!(n.get("median_ms"), Some(&1.5));
    assert!(n.get("ratio").is_some_and(|v| v.is_nan()), "{n:?}");
    assert_eq!(n.get("overdraw"), None);
    assert_eq!(n.get("samples"), Some(&3.0));
    // the old JSON route lost the NaN: the column of a NaN in every row was dropped
    let json = serde_json::to_value(&row).unwrap();
    assert!(json["ratio"].is_null());
    // shown as such, styled
    assert!(super::html::num_td(Some(f64::NAN)).contains("class=\"nonfinite\">NaN<"));
    assert!(super::html::num_td(None).contains("class=\"na\">n/a<"));
}

mod answer_rule {
    use super::super::answer::*;
    use crate::compare::Metric;
    use crate::cost::{CostFigure, CostKind, CostModel, CostModelId, Measure};
    use crate::method::{Precision, Verdict};
    use std::collections::BTreeMap;

    /// The cell of budget `b` (its id) under model `m` (its id).
    fn cell<'a>(a: &'a Answer, b: &str, m: &str) -> Option<&'a Cell> {
        a.cell(
            &Budget::parse_id(b).unwrap(),
            &CostModelId::parse(m).unwrap(),
        )
    }

    fn err(scene: &str, method: &str, max: f64, p99: f64) -> SceneError {
        let mut metrics = BTreeMap::new();
        metrics.insert(Metric::MaxAbsError, Some(max));
        metrics.insert(Metric::P99AbsError, Some(p99));
        SceneError {
            scene: scene.into(),
            method: method.into(),
            precision: Precision::F32,
            covered_pixels: 100,
            non_finite_pixels: 0,
            metrics,
            evidence: format!("index.html#scene-{scene}--{method}"),
        }
    }

    fn fig(method: &str, ratio: f64, lo: f64, hi: f64) -> CostFigure {
        CostFigure {
            method: method.into(),
            value: None,
            ratio: Some(ratio),
            ci95_low: Some(lo),
            ci95_high: Some(hi),
            verdict: if hi < 1.0 {
                Verdict::Agrees
            } else {
                Verdict::Inconclusive
            },
            evidence: format!("index.html#row-{method}"),
            note: String::new(),
        }
    }

    fn model(figures: Vec<CostFigure>) -> CostModel {
        CostModel {
            id: CostModelId::parse("m").unwrap(),
            title: "model".into(),
            kind: CostKind::Interval,
            measure: Measure {
                statistic: "time".into(),
                unit: "ms".into(),
            },
            description: String::new(),
            precision: Precision::F32,
            figures,
            pairs: Vec::new(),
        }
    }

    fn scenes() -> Vec<String> {
        vec!["a".into(), "b".into()]
    }

    fn names() -> Vec<String> {
        ["phong_exact", "fast", "faster", "rough"]
            .map(String::from)
            .to_vec()
    }

    /// Errors: phong_exact ~0, fast 1e-4 / 2e-3 (1/255 = 3.9e-3), faster 3e-3, rough 0.1.
    fn errors() -> Vec<SceneError> {
        let mut v = Vec::new();
        for s in ["a", "b"] {
            v.push(err(s, "phong_exact", 1e-6, 1e-7));
            v.push(err(s, "fast", if s == "b" { 2e-3 } else { 1e-4 }, 1e-5));
            v.push(err(s, "faster", 3e-3, 1e-3));
            v.push(err(s, "rough", 0.1, 0.05));
        }
        v
    }

    fn figures() -> Vec<CostFigure> {
        vec![
            fig("phong_exact", 1.0, 1.0, 1.0),
            fig("fast", 0.9, 0.85, 0.95),
            fig("faster", 0.7, 0.65, 0.75),
            fig("rough", 0.2, 0.1, 0.3),
        ]
    }

    #[test]
    fn the_cheapest_method_meeting_the_budget_on_every_scene_wins() {
        let a = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
        let c = cell(&a, "max_1_255", "m").unwrap();
        assert_eq!(c.answer.method, "faster");
        assert_eq!(c.runner_up.as_ref().unwrap().method, "fast");
        assert!(!c.nothing_cheaper && c.separated);
        assert_eq!(c.qualifying, 3);
        // 1/1024 = 9.8e-4: fast fails on scene b alone, faster everywhere.
        let c = cell(&a, "max_1_1024", "m").unwrap();
        assert!(c.nothing_cheaper, "{c:?}");
        assert_eq!(c.answer.method, "phong_exact");
        assert!(
            c.text.contains("nothing is cheaper than phong_exact"),
            "{}",
            c.text
        );
        let fast = a
            .checks
            .iter()
            .find(|k| k.method == "fast" && k.budget.id() == "max_1_1024")
            .unwrap();
        assert!(!fast.meets && fast.why.contains("on b"), "{fast:?}");
        assert_eq!(fast.worst, Some(2e-3));
        // 4/255 = 0.0157: rough (0.1) still fails, so faster wins again; p99 4/255 too.
        assert_eq!(cell(&a, "max_4_255", "m").unwrap().answer.method, "faster");
        assert_eq!(a.budgets.len(), 6);
        assert_eq!(a.cells.len(), 6);
    }

    /// Teeth: a NaN metric, non-finite pixels, a missing scene or no covered pixel each fail
    /// the budget (never "no error"), and the method drops out of the answer.
    #[test]
    fn non_finite_or_missing_errors_fail_every_budget() {
        let base = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
        assert_eq!(
            cell(&base, "p99_4_255", "m").unwrap().answer.method,
            "faster"
        );
        type Break = Box<dyn Fn(&mut SceneError)>;
        let broken: [(&str, Break); 4] = [
            (
                "NaN",
                Box::new(|e| {
                    e.metrics.insert(Metric::P99AbsError, Some(f64::NAN));
                }),
            ),
            ("non-finite pixels", Box::new(|e| e.non_finite_pixels = 3)),
            ("no covered pixel", Box::new(|e| e.covered_pixels = 0)),
            (
                "missing",
                Box::new(|e| {
                    e.metrics.insert(Metric::P99AbsError, None);
                }),
            ),
        ];
        for (what, f) in broken {
            let mut errs = errors();
            let e = errs
                .iter_mut()
                .find(|e| e.method == "faster" && e.scene == "b")
                .unwrap();
            f(e);
            let a = answer(&scenes(), &names(), &errs, vec![model(figures())]);
            let k = a
                .checks
                .iter()
                .find(|k| k.method == "faster" && k.budget.id() == "p99_4_255")
                .unwrap();
            assert!(!k.meets, "{what}: {k:?}");
            assert_eq!(k.worst, None, "{what}");
            assert_eq!(
                cell(&a, "p99_4_255", "m").unwrap().answer.method,
                "fast",
                "{what}"
            );
        }
        // NaN at every pixel (none measured, all non-finite): said as such, not "no covered
        // pixel"
        let mut errs = errors();
        let e = errs
            .iter_mut()
            .find(|e| e.method == "faster" && e.scene == "b")
            .unwrap();
        (e.non_finite_pixels, e.covered_pixels) = (e.covered_pixels, 0);
        let n = e.non_finite_pixels;
        let a = answer(&scenes(), &names(), &errs, vec![model(figures())]);
        let k = a
            .checks
            .iter()
            .find(|k| k.method == "faster" && k.budget.id() == "max_4_255")
            .unwrap();
        assert!(
            !k.meets
                && k.why
                    .contains(&format!("non-finite at {n} of {n} pixels on b")),
            "{k:?}"
        );
        assert!(!k.why.contains("no covered pixel"), "{k:?}");
        let mut errs = errors();
        errs.retain(|e| !(e.method == "faster" && e.scene == "a"));
        let a = answer(&scenes(), &names(), &errs, vec![model(figures())]);
        let k = a
            .checks
            .iter()
            .find(|k| k.method == "faster" && k.budget.id() == "max_4_255")
            .unwrap();
        assert!(!k.meets && k.why.contains("not measured on a"), "{k:?}");
    }

    /// A method not measured cheaper is never the answer, however low its median; a static
    /// model (an `isa` family, float16) plugs in as a row and is judged by its figure.
    #[test]
    fn only_measured_cheaper_methods_answer_and_static_rows_plug_in() {
        let mut figs = figures();
        figs[2] = fig("faster", 0.7, 0.5, 1.1);
        let a = answer(&scenes(), &names(), &errors(), vec![model(figs.clone())]);
        let c = cell(&a, "max_1_255", "m").unwrap();
        assert_eq!(c.answer.method, "fast");
        assert_eq!(c.runner_up.as_ref().unwrap().method, "phong_exact");
        figs[1] = fig("fast", 0.9, 0.8, 1.2);
        let a = answer(&scenes(), &names(), &errors(), vec![model(figs)]);
        let c = cell(&a, "max_1_255", "m").unwrap();
        assert!(c.nothing_cheaper);
        assert_eq!(c.runner_up.as_ref().unwrap().method, "faster");
        let isa = CostModel {
            id: CostModelId::parse("isa:rdna3").unwrap(),
            title: "RDNA3 (static)".into(),
            kind: CostKind::Static,
            measure: Measure {
                statistic: "instructions per fragment".into(),
                unit: "instructions".into(),
            },
            description: "instructions per fragment / phong_exact's".into(),
            precision: Precision::F32,
            figures: ["phong_exact", "fast", "faster"]
                .iter()
                .zip([1.0, 0.6, 1.3])
                .map(|(m, r)| CostFigure {
                    method: m.to_string(),
                    value: None,
                    ratio: Some(r),
                    ci95_low: None,
                    ci95_high: None,
                    verdict: crate::cost::rule::static_cheaper(Some(r)),
                    evidence: "isa/isa.json".into(),
                    note: String::new(),
                })
                .collect(),
            pairs: Vec::new(),
        };
        let a = answer(&scenes(), &names(), &errors(), vec![model(figures()), isa]);
        let c = cell(&a, "max_1_255", "isa:rdna3").unwrap();
        assert_eq!(c.answer.method, "fast");
        assert_eq!(ratio_text(&c.answer), "0.600");
        assert!(a.markdown().contains("RDNA3 (static)"));
        assert_eq!(a.lines().lines().count(), 12);
        let json = serde_json::to_string(&a).unwrap();
        let back: Answer = serde_json::from_str(&json).unwrap();
        assert_eq!(back, a);
    }

    /// The cell names the scene that keeps cheaper methods out (the cube of the shipped
    /// scenes): the one ruling out the most of them, with the cheapest it rules out.
    #[test]
    fn a_cell_names_the_scene_that_decides_it() {
        let a = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
        // max 1/1024: fast (0.9) fails on b only, faster (0.7) and rough (0.2) on a and b.
        let c = cell(&a, "max_1_1024", "m").unwrap();
        let k = c.binding.as_ref().expect("a binding scene");
        assert_eq!(
            (k.scene.as_str(), k.ruled_out, k.cheaper_failing),
            ("b", 3, 3)
        );
        assert_eq!(k.cheapest, "rough");
        assert!(c.text.contains("decided by b"), "{}", c.text);
        // Teeth: when scene a alone breaks fast's budget (b within it), a rules out all three.
        let mut errs = errors();
        for e in errs.iter_mut().filter(|e| e.method == "fast") {
            e.metrics.insert(
                Metric::MaxAbsError,
                Some(if e.scene == "a" { 2e-3 } else { 1e-4 }),
            );
        }
        let a2 = answer(&scenes(), &names(), &errs, vec![model(figures())]);
        assert_eq!(
            cell(&a2, "max_1_1024", "m")
                .unwrap()
                .binding
                .as_ref()
                .unwrap()
                .scene,
            "a"
        );
        // Without the failing scene b in the report, max 1/1024 has an answer: fast.
        let only_a = answer(&scenes()[..1], &names(), &errors(), vec![model(figures())]);
        let c = cell(&only_a, "max_1_1024", "m").unwrap();
        assert_eq!(c.answer.method, "fast");
        // max 4/255: rough (cheaper than the answer faster) fails on both: a decides (first).
        let c = cell(&a, "max_4_255", "m").unwrap();
        assert_eq!(c.binding.as_ref().unwrap().cheapest, "rough");
        // Nothing cheaper fails: no binding scene.
        let mut figs = figures();
        figs[3] = fig("rough", 1.2, 1.1, 1.3);
        let a3 = answer(&scenes(), &names(), &errors(), vec![model(figs)]);
        assert_eq!(cell(&a3, "max_4_255", "m").unwrap().binding, None);
    }

    /// A float16 cost model is judged on the float16 errors: a method that meets a budget in
    /// float32 but not in float16 is not its answer, and without float16 errors nothing
    /// qualifies.
    #[test]
    fn a_float16_model_takes_the_float16_errors() {
        let mut f16 = model(figures());
        f16.id = CostModelId::isa("x", Precision::F16);
        f16.precision = Precision::F16;
        let mut errs = errors();
        let mut halves: Vec<SceneError> = errors()
            .into_iter()
            .map(|mut e| {
                e.precision = Precision::F16;
                e
            })
            .collect();
        // In float16, faster errs by 1e-2 on a (over 1/255).
        for e in halves
            .iter_mut()
            .filter(|e| e.method == "faster" && e.scene == "a")
        {
            e.metrics.insert(Metric::MaxAbsError, Some(1e-2));
        }
        errs.extend(halves);
        let a = answer(
            &scenes(),
            &names(),
            &errs,
            vec![model(figures()), f16.clone()],
        );
        assert_eq!(cell(&a, "max_1_255", "m").unwrap().answer.method, "faster");
        assert_eq!(
            cell(&a, "max_1_255", "isa:x:f16").unwrap().answer.method,
            "fast"
        );
        assert!(a.checks.iter().any(|k| k.precision == Precision::F16));
        // Teeth: with no float16 error at all, every float16 check fails.
        let a = answer(&scenes(), &names(), &errors(), vec![f16]);
        let c = cell(&a, "max_4_255", "isa:x:f16").unwrap();
        assert!(c.nothing_cheaper && c.qualifying == 0, "{c:?}");
    }

    /// The answer in words and tune's findings (tests/answer_rule/words.rs).
    mod words;

    #[test]
    fn panels_never_hold_more_than_eight_series() {
        use super::super::svg::{panels, Series, MAX_SERIES};
        use crate::method::Family;
        let s = |n: usize| -> Vec<Series> {
            (0..n)
                .map(|k| Series {
                    name: format!("m{k}"),
                    points: vec![(1.0, Some(0.1), None)],
                })
                .collect()
        };
        let p = panels(vec![
            (Family::Reference, s(4)),
            (Family::Scanline, s(9)),
            (Family::VertexAttribute, s(0)),
            (Family::DigitalSegments, s(17)),
        ]);
        let sizes: Vec<usize> = p.iter().map(|(_, v)| v.len()).collect();
        assert_eq!(sizes, vec![4, 5, 4, 6, 6, 5]);
        assert!(sizes.iter().all(|&n| n <= MAX_SERIES));
        assert_eq!(p[1].0, "scanline (1 of 2)");
    }
}

/// Every citation the method table prints (each method's citation and claims) is a link of the
/// report that resolves in its copy of docs/formulas.md; a citation of a missing section does
/// not (teeth).
#[test]
fn the_reports_citations_resolve_in_its_copy_of_formulas_md() {
    use super::formulas::{cite, page, PAGE, SOURCE};
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join(PAGE), page(SOURCE)).unwrap();
    let mut html = String::new();
    for m in crate::method::METHODS {
        html += &cite(m.citation);
        for c in m.claims {
            html += &cite(c.claim);
        }
    }
    let links = attribute_values(&html, "href");
    assert!(links.len() > 60, "{} links", links.len());
    assert!(
        links.iter().all(|l| l.starts_with("formulas.html#")),
        "{links:?}"
    );
    assert_eq!(broken_in(&html, dir.path()), Vec::<String>::new());
    let wrong = cite(&["x (docs/formulas.md", "#no-such-section)"].concat());
    let found = broken_in(&wrong, dir.path());
    assert!(
        found.len() == 1 && found[0].contains("has no element with id \"no-such-section\""),
        "{found:?}"
    );
}

/// A cost model's vendor as a sentence names it: the vendor's own name for every `isa` family
/// (the id's prefix written as is, "broadcom", was the bug), the source's first word otherwise.
#[test]
fn cost_models_name_their_vendor_as_a_person_does() {
    use super::models::vendor_of;
    let vendor_of = |id: &str| vendor_of(&crate::cost::CostModelId::parse(id).unwrap());
    for (id, key, shown) in [
        ("isa:broadcom:vc4", "broadcom", "Broadcom"),
        ("isa:nvidia:nvc0", "nvidia", "NVIDIA"),
        ("isa:amd:navi21:f16", "amd", "AMD"),
        ("isa:arm:g610", "arm", "Arm"),
        ("lavapipe_frame", "lavapipe", "lavapipe"),
    ] {
        assert_eq!(vendor_of(id), (key.to_string(), shown.to_string()), "{id}");
    }
    // every vendor of isa is named by its own name, none by its id
    for v in crate::isa::route::VENDORS {
        let id = format!("isa:{}:{}", v.prefix(), v.default_chips()[0]);
        assert_eq!(vendor_of(&id).1, v.name(), "{id}");
    }
}
