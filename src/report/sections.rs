//! The page as a list of sections: [`SECTIONS`] is the one table that makes both the body of
//! index.html and its navigation, in order. A new section is a function here that returns its
//! [`Section`]s (a scene gives one each), and one entry of the table.
use std::fmt::Write as _;

use super::html::{esc, Dims};
use super::ReportData;

/// One section of the page.
pub struct Section {
    /// Its element id (the navigation links to `#id`).
    pub id: String,
    /// Its name in the navigation.
    pub nav: String,
    /// The `<section>` itself.
    pub html: String,
}

impl Section {
    fn new(id: &str, nav: &str, html: String) -> Vec<Section> {
        vec![Section {
            id: id.into(),
            nav: nav.into(),
            html,
        }]
    }
}

/// What makes some sections of the page.
type Sections = fn(&ReportData, Dims) -> Vec<Section>;

/// The page's sections, in order.
pub const SECTIONS: [Sections; 9] = [
    |d, _| Section::new("answer", "answer", super::first_screen::section(&d.answer)),
    |d, _| Section::new("charts", "charts", super::svg::charts_section(d)),
    |d, _| Section::new("claims", "claims", super::front::claims_matrix(d)),
    |d, dims| {
        d.scenes
            .iter()
            .map(|s| Section {
                id: format!("scene-{}", s.id),
                nav: s.summary.scene.clone(),
                html: super::body::scene_section(s, dims),
            })
            .collect()
    },
    |d, dims| Section::new("stress", "stress", super::body::stress_section(d, dims)),
    |d, _| Section::new("plan", "plan", super::body::plan_section(d)),
    |d, _| Section::new("skips", "skips", super::body::skips_section(d)),
    |d, _| {
        Section::new(
            "isa",
            "static cost",
            super::isa::section(&d.isa, &d.methods),
        )
    },
    |d, _| {
        Section::new(
            "provenance",
            "provenance",
            super::body::provenance_section(d),
        )
    },
];

/// The whole page: the navigation and the body of [`SECTIONS`], then the link to the
/// formulas page. `dims` gives an image's size (for width/height attributes; `None` leaves
/// them out).
pub fn page(d: &ReportData, dims: Dims) -> String {
    let sections: Vec<Section> = SECTIONS.iter().flat_map(|f| f(d, dims)).collect();
    let mut h = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>shadelab report</title><link rel=\"stylesheet\" href=\"report.css\">\
         <script src=\"report.js\" defer></script></head><body>",
    );
    h += "<header><h1>shadelab report</h1><nav><ul>";
    for s in &sections {
        let _ = write!(
            h,
            "<li><a href=\"#{}\">{}</a></li>",
            esc(&s.id),
            esc(&s.nav)
        );
    }
    let _ = write!(
        h,
        "<li><a href=\"{}\">formulas and sources</a></li></ul></nav></header><main>",
        super::formulas::PAGE
    );
    for s in &sections {
        h += &s.html;
    }
    h + "</main></body></html>\n"
}
