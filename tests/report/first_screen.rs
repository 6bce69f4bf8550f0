//! The report's first screen in a 1400x900 window: the answer in words (checked against facts
//! derived here from answer.json's cells, not only against `summary.sentences`), the cells that
//! differ from the common answer, the per-scene answers, the full grid behind one click, no
//! text clipped; and every chart panel: at most 8 series, every text inside its view box, every
//! data point on its axes where its value lies on them and on an edge with a marker (and its
//! value in the legend) where it does not. Each check is run on a broken copy too.
use super::{chromium, index_html, probe_with, report_dir};
use crate::support::read_json;

/// Injected into a copy of the page: the answer section's parts (their data attributes, text,
/// whether each lies wholly inside the first screen), the answer's elements whose text is cut
/// (overflow hidden, or past the window's right edge), and per SVG panel its axes, texts
/// outside the view box, series and data points.
const FIRST_SCREEN: &str = r##"<script>
window.addEventListener("load", function () {
  var W = window.innerWidth, H = window.innerHeight;
  function seen(e) { var r = e.getBoundingClientRect();
    return r.height > 0 && r.top >= 0 && r.left >= 0 && r.bottom <= H && r.right <= W; }
  function attr(e, n) { return e.getAttribute(n); }
  var p = {width: W, height: H, sentences: [], differing: [], scenes: [], cells: [], clipped: [], panels: []};
  document.querySelectorAll("#answer-words p.sentence").forEach(function (s) {
    p.sentences.push({text: s.textContent, visible: seen(s)});
  });
  document.querySelectorAll("#answer-differing tbody tr").forEach(function (tr) {
    p.differing.push({budget: attr(tr, "data-budget"), model: attr(tr, "data-model"),
      method: attr(tr, "data-method"), nothing: attr(tr, "data-nothing"), text: tr.textContent,
      visible: seen(tr)});
  });
  document.querySelectorAll("#answer-scenes td[data-scene]").forEach(function (td) {
    p.scenes.push({scene: attr(td, "data-scene"), budget: attr(td, "data-budget"),
      answers: attr(td, "data-answers"), text: td.textContent});
  });
  var grid = document.querySelector("details#answer-grid");
  p.grid_closed = !!grid && !grid.open;
  document.querySelectorAll("#answer-table tbody td").forEach(function (td) {
    p.cells.push({budget: attr(td, "data-budget"), model: attr(td, "data-model"),
      method: attr(td, "data-method"), nothing: attr(td, "data-nothing"),
      runner_up: attr(td, "data-runner-up"), binding: attr(td, "data-binding"), text: td.textContent});
  });
  document.querySelectorAll("#answer *").forEach(function (e) {
    if (!e.getClientRects().length) return;
    var own = Array.prototype.some.call(e.childNodes, function (n) { return n.nodeType === 3 && n.textContent.trim(); });
    if (!own) return;
    var cs = getComputedStyle(e), r = e.getBoundingClientRect();
    var cut = (cs.overflowX !== "visible" && e.scrollWidth > e.clientWidth + 1) ||
              (cs.overflowY !== "visible" && e.scrollHeight > e.clientHeight + 1);
    if (cut || r.right > W + 0.5 || r.left < -0.5) p.clipped.push(e.tagName + ": " + e.textContent.slice(0, 60));
  });
  document.querySelectorAll("svg").forEach(function (svg) {
    var vb = svg.viewBox.baseVal, out = [], pts = [];
    svg.querySelectorAll("text").forEach(function (t) {
      var b = t.getBBox();
      if (b.x < vb.x || b.y < vb.y || b.x + b.width > vb.x + vb.width || b.y + b.height > vb.y + vb.height)
        out.push(t.textContent + " at " + [b.x, b.y, b.width, b.height].map(Math.round).join(","));
    });
    svg.querySelectorAll(".pt").forEach(function (e) {
      var b = e.getBBox(), g = e.closest("g.series"), lg = g ? g.querySelector("text.lg") : null;
      pts.push({y: attr(e, "data-y"), off: e.classList.contains("off"), cy: b.y + b.height / 2,
        legend: lg ? lg.textContent : ""});
    });
    p.panels.push({title: attr(svg, "aria-label"), has_view_box: !!attr(svg, "viewBox"),
      series: svg.querySelectorAll("g.series").length, outside: out, points: pts,
      y_min: attr(svg, "data-y-min"), y_max: attr(svg, "data-y-max"),
      top: attr(svg, "data-top"), bottom: attr(svg, "data-bottom")});
  });
  var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(p);
  document.body.appendChild(pre);
});
</script>"##;

type Json = serde_json::Value;

fn arr(v: &Json) -> Vec<Json> {
    v.as_array().cloned().unwrap_or_default()
}

/// A cell's answer as a key: (method, nothing cheaper).
fn key(c: &Json) -> (String, bool) {
    (
        c["answer"]["method"].as_str().unwrap_or("?").to_string(),
        c["nothing_cheaper"].as_bool().unwrap_or(false),
    )
}

/// The answer most of `cells` give (ties: the first met), and how many give it.
fn common(cells: &[Json]) -> ((String, bool), usize) {
    let mut counts: Vec<((String, bool), usize)> = Vec::new();
    for c in cells {
        match counts.iter_mut().find(|(k, _)| *k == key(c)) {
            Some((_, n)) => *n += 1,
            None => counts.push((key(c), 1)),
        }
    }
    let mut best = ((String::new(), true), 0);
    for (k, n) in counts {
        if n > best.1 {
            best = (k, n);
        }
    }
    best
}

/// `method:count` per answer of `cells` (a `*` after "nothing is cheaper"), the most
/// widespread first, as a per-scene cell's `data-answers` holds them.
fn answers_key(cells: &[&Json]) -> String {
    let mut groups: Vec<((String, bool), usize)> = Vec::new();
    for c in cells {
        match groups.iter_mut().find(|(k, _)| *k == key(c)) {
            Some((_, n)) => *n += 1,
            None => groups.push((key(c), 1)),
        }
    }
    groups.sort_by_key(|g| std::cmp::Reverse(g.1));
    let keys: Vec<String> = groups
        .iter()
        .map(|((m, n), k)| format!("{m}{}:{k}", if *n { "*" } else { "" }))
        .collect();
    keys.join(",")
}

/// What the words say wrongly or fail to say, derived from answer.json's cells: the common
/// answer and where it holds, the scenes, the unresolved cells; and each sentence on the
/// first screen, uncut.
fn sentence_mismatches(page: &Json, answer: &Json) -> Vec<String> {
    let mut out = Vec::new();
    let cells = arr(&answer["cells"]);
    let shown: Vec<String> = arr(&page["sentences"])
        .iter()
        .map(|s| s["text"].as_str().unwrap_or("").to_string())
        .collect();
    if !(1..=3).contains(&shown.len()) {
        out.push(format!("{} sentences", shown.len()));
    }
    let written: Vec<String> = arr(&answer["summary"]["sentences"])
        .iter()
        .map(|s| s.as_str().unwrap_or("").to_string())
        .collect();
    if shown != written {
        out.push(format!("sentences {shown:?}, answer.json {written:?}"));
    }
    let first = shown.first().cloned().unwrap_or_default();
    let ((method, nothing), n) = common(&cells);
    let what = if nothing {
        "Nothing is cheaper than phong_exact".to_string()
    } else {
        format!("{method} is the cheapest method")
    };
    let (budgets, models) = (
        arr(&answer["budgets"]).len(),
        arr(&answer["cost_models"]).len(),
    );
    let where_ = if n == cells.len() {
        format!("every one of the {budgets} error budgets")
    } else {
        format!("in {n} of the {} cells", cells.len())
    };
    if !first.starts_with(&what) || !first.contains(&where_) {
        out.push(format!("first sentence {first:?}: not {what:?} {where_:?}"));
    }
    if n == cells.len() && !first.contains(&format!("every one of the {models} cost models")) {
        out.push(format!(
            "first sentence {first:?}: not under all {models} models"
        ));
    }
    let scenes = arr(&answer["scenes"]).len();
    if scenes > 1 && !shown.iter().any(|s| s.starts_with("Scene by scene")) {
        out.push("no sentence on the scenes".into());
    }
    let unresolved = cells
        .iter()
        .filter(|c| !arr(&c["unresolved"]).is_empty())
        .count();
    let said = format!("unresolved at this size in {unresolved} of");
    if unresolved > 0 && !shown.iter().any(|s| s.contains(&said)) {
        out.push(format!("no sentence says {said:?}"));
    }
    for s in arr(&page["sentences"]) {
        if s["visible"] != true {
            out.push(format!("sentence not on the first screen: {}", s["text"]));
        }
    }
    out
}

/// What differs between the page's differing-cells table and per-scene table and the cells
/// of answer.json that differ from the common answer (per scene: on a one-scene report, the
/// cells themselves; otherwise `summary.per_scene`).
fn differing_mismatches(page: &Json, answer: &Json) -> Vec<String> {
    let mut out = Vec::new();
    let cells = arr(&answer["cells"]);
    let (common, _) = common(&cells);
    let differ: Vec<&Json> = cells.iter().filter(|c| key(c) != common).collect();
    let rows = arr(&page["differing"]);
    if rows.len() != differ.len() {
        out.push(format!(
            "{} differing cells shown, {} in answer.json",
            rows.len(),
            differ.len()
        ));
    }
    for c in &differ {
        let (b, m) = (&c["budget"], &c["cost_model"]);
        match rows.iter().find(|r| r["budget"] == *b && r["model"] == *m) {
            None => out.push(format!("{b} x {m}: differs, not among the differing cells")),
            Some(r) if r["method"] != c["answer"]["method"] => {
                out.push(format!("{b} x {m}: differing row says {}", r["method"]))
            }
            Some(r) if r["visible"] != true && r == &rows[0] => out.push(format!(
                "{b} x {m}: the first differing cell is not on the first screen"
            )),
            Some(_) => {}
        }
    }
    let shown = arr(&page["scenes"]);
    let one_scene = arr(&answer["scenes"]).len() == 1;
    for sb in arr(&answer["summary"]["per_scene"]) {
        let (s, b) = (&sb["scene"], &sb["budget"]);
        let want = if one_scene {
            answers_key(
                &cells
                    .iter()
                    .filter(|c| c["budget"] == *b)
                    .collect::<Vec<_>>(),
            )
        } else {
            let keys: Vec<String> = arr(&sb["answers"])
                .iter()
                .map(|a| {
                    let star = if a["nothing_cheaper"] == true {
                        "*"
                    } else {
                        ""
                    };
                    let n = arr(&a["cost_models"]).len();
                    format!("{}{star}:{n}", a["method"].as_str().unwrap_or("?"))
                })
                .collect();
            keys.join(",")
        };
        match shown.iter().find(|t| t["scene"] == *s && t["budget"] == *b) {
            Some(t) if t["answers"] == want.as_str() => {}
            Some(t) => out.push(format!(
                "{s} x {b}: per scene {}, want {want}",
                t["answers"]
            )),
            None => out.push(format!("{s} x {b}: no per-scene cell")),
        }
    }
    out
}

/// What differs between the full grid (`page["cells"]`) and answer.json's cells: each cell's
/// method, "nothing is cheaper", runner-up, ratio and deciding scene; and whether the grid is
/// folded (one click away).
fn grid_mismatches(page: &Json, answer: &Json) -> Vec<String> {
    let mut out = Vec::new();
    let shown = arr(&page["cells"]);
    let cells = arr(&answer["cells"]);
    if page["grid_closed"] != true {
        out.push("the full grid is not folded in a closed <details>".into());
    }
    if shown.len() != cells.len() {
        out.push(format!(
            "{} cells shown, {} in answer.json",
            shown.len(),
            cells.len()
        ));
    }
    for c in &cells {
        let (b, m) = (&c["budget"], &c["cost_model"]);
        let Some(td) = shown.iter().find(|t| t["budget"] == *b && t["model"] == *m) else {
            out.push(format!("{b} x {m}: not in the grid"));
            continue;
        };
        let text = td["text"].as_str().unwrap_or("");
        let nothing = c["nothing_cheaper"].as_bool().unwrap_or(false);
        let runner = c["runner_up"]["method"].as_str().unwrap_or("");
        if td["method"] != c["answer"]["method"]
            || td["nothing"].as_str() != Some(if nothing { "true" } else { "false" })
        {
            out.push(format!("{b} x {m}: page {td}, answer.json {}", c["answer"]));
        }
        if td["runner_up"] != runner || !text.contains(runner) {
            out.push(format!("{b} x {m}: runner-up {runner} not shown: {text}"));
        }
        let claim = if nothing {
            "nothing is cheaper than phong_exact".to_string()
        } else {
            let method = c["answer"]["method"].as_str().unwrap_or("?");
            match c["answer"]["ratio"].as_f64() {
                Some(r) => format!("{method} {r:.3}"),
                None => format!("{method} unmeasured"),
            }
        };
        if !text.contains(&claim) {
            out.push(format!("{b} x {m}: {claim:?} not in {text:?}"));
        }
        let binding = c["binding"]["scene"].as_str().unwrap_or("");
        let named = binding.is_empty() || text.contains(&format!("decided by {binding}"));
        if td["binding"] != binding || !named {
            out.push(format!(
                "{b} x {m}: deciding scene {binding:?} not shown: {text}"
            ));
        }
        if !arr(&c["unresolved"]).is_empty() && !text.contains("unresolved at this size") {
            out.push(format!("{b} x {m}: unresolved, not said: {text}"));
        }
    }
    out
}

/// Everything the first screen's answer gets wrong against `answer` (answer.json).
fn answer_mismatches(page: &Json, answer: &Json) -> Vec<String> {
    let mut out = sentence_mismatches(page, answer);
    out.extend(differing_mismatches(page, answer));
    out.extend(grid_mismatches(page, answer));
    for c in arr(&page["clipped"]) {
        out.push(format!("text cut: {c}"));
    }
    out
}

/// A number from an SVG attribute (`nan` for the non-finite).
fn num(v: &Json) -> f64 {
    v.as_str().and_then(|s| s.parse().ok()).unwrap_or(f64::NAN)
}

/// A panel's data points against its axes: on the axis at its value's height, or, beyond it,
/// on the edge with a marker and the legend's note (▲ above, ▼ below, × not finite).
fn point_problems(p: &Json) -> Vec<String> {
    let mut out = Vec::new();
    let (lo, hi, top, bottom) = (
        num(&p["y_min"]),
        num(&p["y_max"]),
        num(&p["top"]),
        num(&p["bottom"]),
    );
    for pt in arr(&p["points"]) {
        let y = num(&pt["y"]);
        let cy = pt["cy"].as_f64().unwrap_or(f64::NAN);
        let off = pt["off"] == true;
        let legend = pt["legend"].as_str().unwrap_or("");
        let on_axis = y.is_finite() && y >= lo * (1.0 - 1e-9) && y <= hi * (1.0 + 1e-9);
        if on_axis {
            let want =
                bottom - (y.log10() - lo.log10()) / (hi.log10() - lo.log10()) * (bottom - top);
            if off || (cy - want).abs() > 1.5 {
                out.push(format!(
                    "{}: point {y:e} drawn at {cy:.1} (off {off}), its height {want:.1}",
                    p["title"]
                ));
            }
            continue;
        }
        let (edge, mark) = match () {
            _ if !y.is_finite() => (top, '\u{d7}'),
            _ if y > hi => (top, '\u{25b2}'),
            _ => (bottom, '\u{25bc}'),
        };
        if !off || (cy - edge).abs() > 8.0 || !legend.contains(mark) {
            out.push(format!(
                "{}: point {y:e} beyond the axis [{lo:e}, {hi:e}] without its marker (off {off}, at {cy:.1}, edge {edge}, legend {legend:?})",
                p["title"]
            ));
        }
    }
    out
}

/// Panels with text outside their view box, without a view box, with more than 8 series, or
/// with a point drawn wrongly against their axes.
fn chart_problems(page: &Json) -> Vec<String> {
    let mut out = Vec::new();
    for p in arr(&page["panels"]) {
        if p["has_view_box"] != true {
            out.push(format!("{}: no viewBox", p["title"]));
        }
        if p["series"].as_u64().unwrap_or(0) > 8 {
            out.push(format!("{}: {} series", p["title"], p["series"]));
        }
        for t in arr(&p["outside"]) {
            out.push(format!("{}: text outside the view box: {t}", p["title"]));
        }
        out.extend(point_problems(&p));
    }
    out
}

/// `html` with the answer's first sentence replaced by `words`, cut to 300 px.
fn with_first_sentence(html: &str, words: &str) -> String {
    let open = "<p class=\"sentence\" data-k=\"0\">";
    let i = html.find(open).expect("a first sentence") + open.len();
    let j = i + html[i..].find("</p>").unwrap();
    format!(
        "{}<p class=\"sentence\" data-k=\"0\" style=\"width:300px;white-space:nowrap;overflow:hidden\">{words}{}",
        &html[..i - open.len()],
        &html[j..]
    )
}

#[test]
fn first_screen_shows_the_answer_and_charts_stay_readable() {
    let Some(browser) = chromium() else { return };
    let dir = report_dir();
    let page = probe_with(&browser, &dir.join("index.html"), FIRST_SCREEN, "1400,900");
    let answer = read_json(dir.join("answer.json"));
    assert_eq!(
        answer_mismatches(&page, &answer),
        Vec::<String>::new(),
        "{page}"
    );
    assert!(
        !arr(&page["sentences"]).is_empty() && !arr(&page["scenes"]).is_empty(),
        "{page}"
    );
    assert!(arr(&page["panels"]).len() >= 2, "{page}");
    assert!(
        arr(&page["panels"])
            .iter()
            .any(|p| !arr(&p["points"]).is_empty()),
        "{page}"
    );
    assert_eq!(chart_problems(&page), Vec::<String>::new());

    // Teeth: a tampered answer.json (another method, a flipped "nothing is cheaper") fails the
    // grid, the differing cells and the per-scene answers.
    let mut tampered = answer.clone();
    tampered["cells"][0]["answer"]["method"] = "gouraud_tampered".into();
    let flip = !tampered["cells"][1]["nothing_cheaper"].as_bool().unwrap();
    tampered["cells"][1]["nothing_cheaper"] = flip.into();
    let bad = answer_mismatches(&page, &tampered);
    for want in ["gouraud_tampered", "differing cells shown", "per scene"] {
        assert!(bad.iter().any(|m| m.contains(want)), "{want}: {bad:?}");
    }
    // Every cell flipped to another common answer fails the first sentence.
    let mut other = answer.clone();
    for c in other["cells"].as_array_mut().unwrap() {
        c["answer"]["method"] = "slerp".into();
        c["nothing_cheaper"] = false.into();
    }
    let bad = sentence_mismatches(&page, &other);
    assert!(
        bad.iter().any(|m| m.contains("slerp is the cheapest")),
        "{bad:?}"
    );
    // The answer pushed below the first screen, and a first sentence reworded and cut, fail.
    let html = index_html();
    let low = dir.join("low.html");
    let pushed_html = with_first_sentence(
        &html.replacen(
            "<section id=\"answer\">",
            "<div style=\"height:1200px\"></div><section id=\"answer\">",
            1,
        ),
        "Something else entirely, and much too long to fit three hundred pixels of width",
    );
    std::fs::write(&low, pushed_html).unwrap();
    let pushed = probe_with(&browser, &low, FIRST_SCREEN, "1400,900");
    std::fs::remove_file(&low).unwrap();
    let bad = answer_mismatches(&pushed, &answer);
    for want in ["not on the first screen", "first sentence", "text cut"] {
        assert!(bad.iter().any(|m| m.contains(want)), "{want}: {bad:?}");
    }
    // A text outside its panel, a panel of 9 series, a point beyond its axis without a marker
    // and one on the axis drawn at the wrong height fail the chart check.
    let nine = "<g class=\"series\"></g>".repeat(9);
    let broken = dir.join("charts.broken.html");
    std::fs::write(
        &broken,
        html.replacen(
            "</main>",
            &format!(
                "<svg class=\"panel\" aria-label=\"bad\" viewBox=\"0 0 100 300\" width=\"100\" \
                 height=\"300\" data-y-min=\"1e-4\" data-y-max=\"1e0\" data-top=\"30\" \
                 data-bottom=\"240\"><text x=\"80\" y=\"20\">far outside the box</text>{nine}\
                 <g class=\"series\"><circle class=\"pt\" data-y=\"1e5\" cx=\"50\" cy=\"100\" r=\"2\"/>\
                 <circle class=\"pt\" data-y=\"1e-2\" cx=\"50\" cy=\"40\" r=\"2\"/>\
                 <text class=\"lg\" x=\"1\" y=\"290\">s</text></g></svg></main>"
            ),
            1,
        ),
    )
    .unwrap();
    let b = probe_with(&browser, &broken, FIRST_SCREEN, "1400,900");
    std::fs::remove_file(&broken).unwrap();
    let found = chart_problems(&b);
    for want in [
        "far outside the box",
        "10 series",
        "1e5 beyond the axis",
        "point 1e-2 drawn",
    ] {
        assert!(found.iter().any(|f| f.contains(want)), "{want}: {found:?}");
    }
}
