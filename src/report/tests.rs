//! Unit tests of the report without a device: escaping, numbers, dates, ids, the link checker
//! (with teeth: each kind of broken link must be flagged).
use super::html::{esc, number};
use super::links::{attribute_values, broken_in};
use super::*;

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
    let good = r##"<link href="b.css"><img src="sub%20dir/a.png"><a href="#top">t</a>
        <a href="b.css#frag">f</a><div id="top"></div>"##;
    assert_eq!(broken_in(good, dir.path()), Vec::<String>::new());
    for (bad, why) in [
        (r#"<img src="sub dir/missing.png">"#, "no file"),
        (r##"<a href="#nowhere">x</a>"##, "no element with id"),
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
    let n = super::html::row_numbers(&row);
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
