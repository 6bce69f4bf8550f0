//! The claims matrix as a person sees it in a 1400x900 window: the claim column readable (at
//! least 300 px) and no claim text cut; where every place that gave a verdict gives the same
//! one, one merged cell with a link to each measurement; where they differ, a cell per place;
//! every link of the matrix resolving. Checked on the report's own matrix against its JSON files
//! (bench.json, the software engine's bench.json, stress.json), and on a matrix of 13 places in
//! the same page, made by the report's code from measurements written here, which holds both a
//! merged and a split row whatever this run measured. Each check is run on a broken copy too.
use std::path::Path;

use shadelab::method::Verdict;
use shadelab::report::front::matrix::{matrix, Measured, Place};
use shadelab::report::links::{attribute_values, broken_in};

use super::{chromium, index_html, probe_with, report_dir};
use crate::support::read_json;

/// Injected into a copy of the page: the matrix's place headings, and per row its method and
/// claim, the claim cell's width and whether its text is cut (overflowing the cell, or outside
/// the window or the table's scrolling box), and each cell (merged or not, its span, its
/// verdicts, how many places it speaks for, its links).
const CLAIMS: &str = r##"<script>
window.addEventListener("load", function () {
  var W = window.innerWidth, p = {width: W, places: [], rows: []};
  var t = document.getElementById("claims-matrix");
  if (t) {
    t.querySelectorAll("thead th.place").forEach(function (th) { p.places.push(th.textContent); });
    var box = t.closest(".scroll").getBoundingClientRect();
    t.querySelectorAll("tbody tr").forEach(function (tr) {
      var c = tr.querySelector("th.claim"), r = c.getBoundingClientRect();
      var cut = c.scrollWidth > c.clientWidth + 1 || c.scrollHeight > c.clientHeight + 1 ||
        r.left < Math.max(0, box.left) - 0.5 || r.right > Math.min(W, box.right) + 0.5;
      var cells = [];
      tr.querySelectorAll("td").forEach(function (td) {
        cells.push({merged: td.classList.contains("merged"), span: td.colSpan,
          verdict: td.getAttribute("data-verdict"), places: td.getAttribute("data-places"),
          links: td.querySelectorAll("a[href]").length,
          cut: td.scrollWidth > td.clientWidth + 1});
      });
      p.rows.push({method: tr.getAttribute("data-method"), claim: tr.getAttribute("data-claim"),
        claim_width: r.width, claim_cut: cut, text: c.textContent, cells: cells});
    });
  }
  var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(p);
  document.body.appendChild(pre);
});
</script>"##;

type Json = serde_json::Value;

/// The least width of the claim column a claim reads in (about 45 characters a line at the
/// matrix's 12 px; the column used to be about 80 px, ten lines a claim).
const READABLE_PX: f64 = 300.0;

/// What the matrix must show: its place columns, and per claim (method, text) the verdicts of
/// each place (none where it did not measure the claim).
#[derive(Debug, Clone)]
struct Expected {
    places: Vec<String>,
    rows: Vec<(String, String, Vec<Vec<String>>)>,
}

impl Expected {
    fn new(measured: &[(String, String, String, String)]) -> Self {
        let mut places: Vec<String> = Vec::new();
        for (p, ..) in measured {
            if !places.contains(p) {
                places.push(p.clone());
            }
        }
        let mut rows: Vec<(String, String, Vec<Vec<String>>)> = Vec::new();
        for (p, m, c, v) in measured {
            let k = places.iter().position(|x| x == p).unwrap();
            let i = match rows.iter().position(|r| r.0 == *m && r.1 == *c) {
                Some(i) => i,
                None => {
                    rows.push((m.clone(), c.clone(), vec![Vec::new(); places.len()]));
                    rows.len() - 1
                }
            };
            rows[i].2.resize(places.len(), Vec::new());
            rows[i].2[k].push(v.clone());
        }
        for r in &mut rows {
            r.2.resize(places.len(), Vec::new());
        }
        Expected { places, rows }
    }
}

/// The rule, written again from its statement: the places with a verdict other than
/// `not_checked`; one merged cell (first..=last of them, the verdict) when there are two or more
/// and every such verdict is the same.
fn expected_merge(verdicts: &[Vec<String>]) -> Option<(usize, usize, usize, String)> {
    let given = |k: usize| verdicts[k].iter().filter(|v| *v != "not_checked");
    let counted: Vec<usize> = (0..verdicts.len())
        .filter(|&k| given(k).next().is_some())
        .collect();
    let first = given(*counted.first()?).next()?.clone();
    let same = counted.iter().all(|&k| given(k).all(|v| *v == first));
    (counted.len() >= 2 && same)
        .then(|| (counted[0], counted[counted.len() - 1], counted.len(), first))
}

/// What the page's matrix (`page`, the probe's record) gets wrong against `want`.
fn matrix_problems(page: &Json, want: &Expected) -> Vec<String> {
    let mut out = Vec::new();
    let arr = |v: &Json| v.as_array().cloned().unwrap_or_default();
    let heads: Vec<String> = arr(&page["places"])
        .iter()
        .map(|h| h.as_str().unwrap_or("").to_string())
        .collect();
    if heads != want.places {
        out.push(format!("place columns {heads:?}, want {:?}", want.places));
    }
    let rows = arr(&page["rows"]);
    if rows.len() != want.rows.len() {
        out.push(format!("{} rows, want {}", rows.len(), want.rows.len()));
    }
    for (method, claim, verdicts) in &want.rows {
        let name = format!("{method}: {claim:.50}");
        let Some(r) = rows
            .iter()
            .find(|r| r["method"] == method.as_str() && r["claim"] == claim.as_str())
        else {
            out.push(format!("{name}: no row"));
            continue;
        };
        let width = r["claim_width"].as_f64().unwrap_or(0.0);
        if width < READABLE_PX {
            out.push(format!("{name}: claim column {width:.0} px"));
        }
        if r["claim_cut"] != false {
            out.push(format!("{name}: claim text cut"));
        }
        let cells = arr(&r["cells"]);
        for c in cells.iter().filter(|c| c["cut"] != false) {
            out.push(format!("{name}: text cut in a cell {c}"));
        }
        let verdict_of = |c: &Json| c["verdict"].as_str().unwrap_or("").to_string();
        let merged: Vec<&Json> = cells.iter().filter(|c| c["merged"] == true).collect();
        let (places, ok_cells) = match expected_merge(verdicts) {
            Some((first, last, n, v)) => {
                let span = last - first + 1;
                match merged.as_slice() {
                    [m] if m["span"] == span
                        && verdict_of(m) == v
                        && m["places"] == n.to_string().as_str()
                        && m["links"].as_u64().unwrap_or(0) as usize
                            >= verdicts[first..=last].iter().map(Vec::len).sum() => {}
                    _ => out.push(format!(
                        "{name}: all {n} places give {v}: want one merged cell over {span} columns, see {}",
                        r["cells"]
                    )),
                }
                let outside: Vec<usize> = (0..first).chain(last + 1..verdicts.len()).collect();
                (outside, cells.len() == verdicts.len() - span + 1)
            }
            None => {
                if !merged.is_empty() {
                    out.push(format!(
                        "{name}: places differ ({verdicts:?}), yet one merged cell: {}",
                        r["cells"]
                    ));
                }
                ((0..verdicts.len()).collect(), cells.len() == verdicts.len())
            }
        };
        if !ok_cells {
            out.push(format!("{name}: {} cells for {verdicts:?}", cells.len()));
            continue;
        }
        let singles: Vec<&Json> = cells.iter().filter(|c| c["merged"] != true).collect();
        for (k, c) in places.iter().zip(singles) {
            let want_v = verdicts[*k].join(" ");
            let links = c["links"].as_u64().unwrap_or(0) as usize;
            if verdict_of(c) != want_v || links != verdicts[*k].len() {
                out.push(format!(
                    "{name}: {} shows {c}, want {want_v:?}",
                    want.places[*k]
                ));
            }
        }
    }
    out
}

/// The report's claims as its JSON files hold them, per place: (place, method, claim, verdict).
fn report_claims(dir: &Path, scenes: &[String]) -> Vec<(String, String, String, String)> {
    let mut out = Vec::new();
    let s = |v: &Json| v.as_str().unwrap_or("").to_string();
    for id in scenes {
        let bench = read_json(dir.join(format!("scenes/{id}/bench/bench.json")));
        for c in bench["claims"].as_array().unwrap() {
            let place = format!("lavapipe: {id}");
            out.push((place, s(&c["method"]), s(&c["claim"]), s(&c["verdict"])));
        }
    }
    for id in scenes {
        let path = dir.join(format!("scenes/{id}/software/bench.json"));
        if !path.exists() {
            continue;
        }
        for c in read_json(path)["claims"].as_array().unwrap() {
            if c["software"].is_object() {
                let v = s(&c["software"]["verdict"]);
                out.push((format!("software: {id}"), s(&c["num"]), s(&c["claim"]), v));
            }
        }
    }
    for c in read_json(dir.join("stress/stress.json"))["claims"]
        .as_array()
        .unwrap()
    {
        out.push((
            "stress".into(),
            s(&c["method"]),
            s(&c["claim"]),
            s(&c["verdict"]),
        ));
    }
    out
}

/// The `<section id="claims">` of `html`.
fn claims_section(html: &str) -> &str {
    let i = html
        .find("<section id=\"claims\">")
        .expect("a claims section");
    &html[i..i + html[i..].find("</section>").unwrap() + "</section>".len()]
}

/// Each link of the matrix in `html` (the page in `dir`) that does not resolve, and each claim
/// row without a link to the formulas page.
fn matrix_link_problems(html: &str, dir: &Path) -> Vec<String> {
    let section = claims_section(html);
    let hrefs = attribute_values(section, "href");
    let mut out: Vec<String> = broken_in(html, dir)
        .into_iter()
        .filter(|b| {
            hrefs
                .iter()
                .any(|h| b.starts_with(&format!("href=\"{h}\"")))
        })
        .collect();
    for row in section.split("<tr data-method=").skip(1) {
        let claim = row.split("</th>").next().unwrap_or("");
        if !claim.contains("<a href=\"formulas.html#") {
            out.push(format!("a claim without its source: {claim:.120}"));
        }
    }
    out
}

fn verdict(v: &str) -> Verdict {
    serde_json::from_value(Json::String(v.into())).unwrap()
}

/// Measurements written here: the places of a six-scene run (lavapipe and the software engine
/// per scene, stress) and the longest claims of the method table, in rows that merge (every
/// place agrees; some places measured; a `not_checked` among them) and rows that do not (one
/// place differs; a single place).
fn made_up() -> Vec<Measured> {
    let scenes = [
        "sphere_fine",
        "torus",
        "torus_generated",
        "sphere_coarse",
        "icosphere",
        "cube",
    ];
    let mut claims: Vec<(&str, &str)> = shadelab::method::METHODS
        .iter()
        .flat_map(|m| m.claims.iter().map(move |c| (m.name, c.claim)))
        .collect();
    claims.sort_by_key(|c| std::cmp::Reverse(c.1.len()));
    let place = |engine: &str, scene: Option<&str>| Place {
        engine: engine.into(),
        scene: scene.map(String::from),
    };
    let mut places: Vec<Place> = Vec::new();
    for e in ["lavapipe", "software"] {
        places.extend(scenes.iter().map(|s| place(e, Some(s))));
    }
    places.push(place("stress", None));
    // per row, the verdict of each of the 13 places ("" where it did not measure the claim)
    let a = "agrees";
    let d = "disagrees";
    let rows: [[&str; 13]; 5] = [
        [a; 13],
        [d, d, d, d, d, d, d, d, d, "inconclusive", d, d, ""],
        [
            "partly", "partly", "partly", "partly", "partly", "partly", "", "", "", "", "", "",
            "partly",
        ],
        ["", "", "", "", "", "", "", "", "", "", "", "", d],
        [a, a, a, a, a, a, "", "", "", "", "", "not_checked", ""],
    ];
    let mut out = Vec::new();
    for (r, (method, claim)) in rows.iter().zip(claims) {
        for (p, v) in places.iter().zip(r).filter(|(_, v)| !v.is_empty()) {
            out.push(Measured {
                method: method.into(),
                claim: claim.into(),
                place: p.clone(),
                verdict: verdict(v),
                basis: "found 1.151e-2 (relative_error)".into(),
                link: "#claims".into(),
                detail: "made up by the test".into(),
            });
        }
    }
    out
}

/// The made-up measurements as [`Expected`] rows.
fn made_up_expected(m: &[Measured]) -> Expected {
    let rows: Vec<(String, String, String, String)> = m
        .iter()
        .map(|x| {
            (
                x.place.name(),
                x.method.clone(),
                x.claim.clone(),
                x.verdict.as_str().to_string(),
            )
        })
        .collect();
    Expected::new(&rows)
}

/// `html` with its claims section replaced by `section`.
fn with_section(html: &str, section: &str) -> String {
    html.replacen(claims_section(html), section, 1)
}

/// Loads `html` (written beside the report as `name`) with the probe at 1400x900.
fn probe_page(browser: &Path, name: &str, html: &str) -> Json {
    let page = report_dir().join(name);
    std::fs::write(&page, html).unwrap();
    let p = probe_with(browser, &page, CLAIMS, "1400,900");
    std::fs::remove_file(&page).unwrap();
    p
}

#[test]
fn every_link_of_the_claims_matrix_resolves() {
    let dir = report_dir();
    let html = index_html();
    let section = claims_section(&html);
    assert!(
        attribute_values(section, "href").len() >= 2 && section.contains("formulas.html#"),
        "{section}"
    );
    assert_eq!(matrix_link_problems(&html, dir), Vec::<String>::new());
    // Teeth: a link to a missing anchor of the formulas page, to a missing row, to a file
    // outside the report, and a claim without its citation are found.
    let first = section
        .split("href=\"formulas.html#")
        .nth(1)
        .and_then(|x| x.split('"').next())
        .unwrap();
    let broken = with_section(
        &html,
        &section
            .replacen(
                &format!("formulas.html#{first}\""),
                "formulas.html#nowhere\"",
                1,
            )
            .replacen("href=\"#scene-", "href=\"#nothing-", 1)
            .replacen("</table>", "</table><a href=\"../shared/x.md\">x</a>", 1),
    );
    let uncited = with_section(
        &html,
        &section.replace("<a href=\"formulas.html#", "<a data-href=\"formulas.html#"),
    );
    let mut found = matrix_link_problems(&broken, dir);
    found.extend(matrix_link_problems(&uncited, dir));
    for want in [
        "#nowhere",
        "#nothing-",
        "../shared/x.md",
        "without its source",
    ] {
        assert!(found.iter().any(|f| f.contains(want)), "{want}: {found:?}");
    }
}

#[test]
fn claims_matrix_reads_merges_agreement_and_splits_differences() {
    let Some(browser) = chromium() else { return };
    let dir = report_dir();
    let html = index_html();
    let scenes: Vec<String> = read_json(dir.join("answer.json"))["scenes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap().to_string())
        .collect();
    // The report's own matrix against its JSON files.
    let own = Expected::new(&report_claims(dir, &scenes));
    assert!(!own.rows.is_empty(), "no claims in the report");
    let page = probe_page(&browser, "claims.own.html", &html);
    assert_eq!(matrix_problems(&page, &own), Vec::<String>::new(), "{page}");

    // 13 places, rows that merge and rows that do not, in the same page.
    let made = made_up();
    let want = made_up_expected(&made);
    let merges = want.rows.iter().filter(|r| expected_merge(&r.2).is_some());
    assert_eq!(merges.count(), 3, "{want:?}");
    let full = with_section(&html, &matrix(&made));
    let page = probe_page(&browser, "claims.made.html", &full);
    assert_eq!(
        matrix_problems(&page, &want),
        Vec::<String>::new(),
        "{page}"
    );

    // Teeth: the claim column narrowed back, or its text cut, fails; so does a merged cell
    // where the places differ, and separate cells where they agree (the expectation flipped).
    let narrow = full.replacen(
        "</head>",
        "<style>table.matrix th.claim{min-width:0;width:80px;max-width:80px}</style></head>",
        1,
    );
    let found = matrix_problems(&probe_page(&browser, "claims.narrow.html", &narrow), &want);
    assert!(
        found.iter().any(|f| f.contains("claim column")),
        "{found:?}"
    );
    let cut = full.replacen(
        "</head>",
        "<style>table.matrix th.claim{white-space:nowrap;overflow:hidden}</style></head>",
        1,
    );
    let found = matrix_problems(&probe_page(&browser, "claims.cut.html", &cut), &want);
    assert!(
        found.iter().any(|f| f.contains("claim text cut")),
        "{found:?}"
    );
    let mut flipped = want.clone();
    flipped.rows[0].2[3] = vec!["inconclusive".into()];
    flipped.rows[1].2[9] = vec!["disagrees".into()];
    let found = matrix_problems(&page, &flipped);
    for w in ["places differ", "want one merged cell"] {
        assert!(found.iter().any(|f| f.contains(w)), "{w}: {found:?}");
    }
}
