//! The answer as the page's first screen ([`section`]): the answer in words
//! (answer.json `summary.sentences`), the cells that differ from the common answer, per scene
//! the cheapest method within each budget, and the full grid (every budget under every cost
//! model, grouped by vendor) one click away in a `<details>`. Every element carries the data
//! attributes the browser test compares with answer.json (tests/report.rs).
use std::fmt::Write as _;

use super::answer::{self, Answer, Cell};
use super::html::esc;
use super::models::{describe, vendor_of};
use super::summary::{SceneAnswer, SceneBudget};
use crate::cost::{CostKind, CostModel};
use crate::method::PHONG_EXACT;

/// `index.html#x` -> `#x` (the page links to itself), other paths unchanged.
fn href(e: &str) -> String {
    e.strip_prefix("index.html").unwrap_or(e).to_string()
}

/// `text`, linked to `evidence` when there is one.
fn linked(text: &str, evidence: &str) -> String {
    if evidence.is_empty() {
        esc(text)
    } else {
        format!("<a href=\"{}\">{}</a>", esc(&href(evidence)), esc(text))
    }
}

fn choice_html(c: &answer::Choice) -> String {
    let link = linked(&c.method, &c.cost_evidence);
    let err = if c.error_evidence.is_empty() {
        String::new()
    } else {
        format!(
            " <a class=\"err\" href=\"{}\" title=\"its error\">err</a>",
            esc(&href(&c.error_evidence))
        )
    };
    format!(
        "{link} <span class=\"ratio\">{}</span>{err}",
        esc(&answer::ratio_text(c))
    )
}

/// The words naming the scene that decides a cell, linked to the evidence (the counts in
/// the tooltip).
fn binding_html(c: &Cell) -> Option<String> {
    let k = c.binding.as_ref()?;
    let scene = linked(&k.scene, &k.evidence);
    Some(format!(
        "<span class=\"bind\" title=\"{} of the {} methods cheaper than the answer that fail \
         the budget fail it on this scene; the cheapest: {}\">decided by {scene}</span>",
        k.ruled_out,
        k.cheaper_failing,
        esc(&k.cheapest)
    ))
}

/// A cell's note when this run does not resolve it (the whole text in the tooltip).
fn unresolved_html(c: &Cell, m: &CostModel) -> Option<String> {
    if c.unresolved.is_empty() {
        return None;
    }
    Some(format!(
        "<div class=\"unres\" title=\"{}\">unresolved at this size: {} within the budget \
         neither cheaper nor dearer; a larger --size or more --runs resolves it</div>",
        esc(&answer::unresolved_text(&c.unresolved, m)),
        match c.unresolved.len() {
            1 => "1 method".to_string(),
            n => format!("{n} methods"),
        }
    ))
}

/// A tuned winner of a cell.
fn tuned_html(c: &Cell) -> Option<String> {
    let w = c.tuned.as_ref()?;
    Some(format!(
        "<div class=\"tuned\" data-candidate=\"{}\">a tuned approximation beats exact \
         normalisation here: <b>{}</b> ({}) {}</div>",
        esc(&w.candidate),
        esc(&w.candidate),
        esc(&w.label),
        w.ratio.map_or("unmeasured".into(), |r| format!("{r:.3}"))
    ))
}

/// One cell of the grid.
fn cell_html(c: &Cell, m: &CostModel, b: &answer::Budget) -> String {
    let main = if c.nothing_cheaper {
        "<strong class=\"none\">nothing is cheaper than phong_exact</strong>".to_string()
    } else {
        format!("<strong>{}</strong>", choice_html(&c.answer))
    };
    let label = if c.nothing_cheaper { "closest" } else { "then" };
    let ru = c
        .runner_up
        .as_ref()
        .map(|r| format!("{label} {}", choice_html(r)));
    let parts: Vec<String> = ru.into_iter().chain(binding_html(c)).collect();
    let second = if parts.is_empty() {
        String::new()
    } else {
        format!("<div class=\"ru\">{}</div>", parts.join("; "))
    };
    let extra: String = unresolved_html(c, m)
        .into_iter()
        .chain(tuned_html(c))
        .collect();
    format!(
        "<td id=\"{}\" data-budget=\"{}\" data-model=\"{}\" data-method=\"{}\" \
         data-nothing=\"{}\" data-runner-up=\"{}\" data-binding=\"{}\" data-unresolved=\"{}\">\
         {main}{second}{extra}</td>",
        esc(&format!("answer-{}-{}", b.id(), m.id)),
        esc(&b.id()),
        esc(m.id.as_str()),
        esc(&c.answer.method),
        c.nothing_cheaper,
        esc(c.runner_up.as_ref().map_or("", |r| r.method.as_str())),
        esc(c.binding.as_ref().map_or("", |k| k.scene.as_str())),
        c.unresolved.len()
    )
}

/// The group a cost model's row falls under in the grid: the CPU's models, then one per GPU
/// vendor and precision.
fn group_of(m: &CostModel) -> String {
    if m.kind != CostKind::Static {
        return "Timed on this machine's CPU (lavapipe, the software engine)".into();
    }
    let vendor = vendor_of(&m.id).1;
    match m.precision {
        crate::method::Precision::F16 => format!("{vendor} GPUs, float16 programs (static)"),
        _ => format!("{vendor} GPUs (static)"),
    }
}

/// The full grid: one row per cost model (grouped by vendor), one column per budget.
pub fn grid(a: &Answer) -> String {
    let mut h =
        String::from("<table class=\"answer\" id=\"answer-table\"><thead><tr><th>cost model</th>");
    for b in &a.budgets {
        let _ = write!(
            h,
            "<th data-budget=\"{}\">{}</th>",
            esc(&b.id()),
            esc(&b.label())
        );
    }
    h += "</tr></thead><tbody>";
    let mut group = String::new();
    for m in &a.cost_models {
        let g = group_of(m);
        if g != group {
            let _ = write!(
                h,
                "<tr class=\"group\"><th colspan=\"{}\">{}</th></tr>",
                a.budgets.len() + 1,
                esc(&g)
            );
            group = g;
        }
        let _ = write!(
            h,
            "<tr data-model=\"{}\"><th scope=\"row\" title=\"{}\">{}</th>",
            esc(m.id.as_str()),
            esc(&m.description),
            esc(&m.title)
        );
        for b in &a.budgets {
            match a.cell(b, &m.id) {
                Some(c) => h += &cell_html(c, m, b),
                None => h += "<td>-</td>",
            }
        }
        h += "</tr>";
    }
    h + "</tbody></table>"
}

/// The cells that differ from the common answer, one row each.
fn differing(a: &Answer) -> String {
    let d = &a.summary.differing;
    if d.is_empty() {
        return String::new();
    }
    let mut h = String::from(
        "<table class=\"answer differing\" id=\"answer-differing\"><thead><tr><th>cost model\
         </th><th>budget</th><th>answer</th><th>then</th></tr></thead><tbody>",
    );
    for r in d {
        let (Some(c), Some(m), Some(b)) = (
            a.cell(&r.budget, &r.cost_model),
            a.cost_models.iter().find(|m| m.id == r.cost_model),
            a.budgets.iter().find(|b| **b == r.budget),
        ) else {
            continue;
        };
        let main = if c.nothing_cheaper {
            "nothing is cheaper than phong_exact".to_string()
        } else {
            choice_html(&c.answer)
        };
        let then = c.runner_up.as_ref().map_or("-".into(), choice_html);
        let extra: String = unresolved_html(c, m)
            .into_iter()
            .chain(tuned_html(c))
            .collect();
        let _ = write!(
            h,
            "<tr data-budget=\"{}\" data-model=\"{}\" data-method=\"{}\" data-nothing=\"{}\">\
             <th scope=\"row\">{}</th><td>{}</td><td><strong>{main}</strong>{extra}</td>\
             <td>{then}</td></tr>",
            esc(&b.id()),
            esc(m.id.as_str()),
            esc(&c.answer.method),
            c.nothing_cheaper,
            esc(&m.title),
            esc(&b.label())
        );
    }
    h + "</tbody></table>"
}

/// `answer` as the per-scene table shows it: the method (or "nothing cheaper"), its ratios.
fn scene_answer_html(x: &SceneAnswer, of: usize, models: &[CostModel], common: bool) -> String {
    let what = if x.nothing_cheaper {
        "nothing cheaper".to_string()
    } else {
        let range = x.ratio_range.map_or(String::new(), |(l, h)| {
            if (h - l).abs() < 5e-4 {
                format!(" {l:.2}")
            } else {
                format!(" {l:.2}-{h:.2}")
            }
        });
        format!(
            "<b>{}</b><span class=\"ratio\">{range}</span>",
            esc(&x.method)
        )
    };
    let unres = if x.unresolved.is_empty() {
        String::new()
    } else {
        format!(
            "; unresolved under {}",
            esc(&describe(&x.unresolved, models))
        )
    };
    format!(
        "<div class=\"sa{}\" title=\"{}{unres}\">{what} <span class=\"n\">{} of {of}</span></div>",
        if common { " same" } else { "" },
        esc(&describe(&x.cost_models, models)),
        x.cost_models.len()
    )
}

/// Per scene (rows) and budget (columns): the answers of the cost models on that scene alone.
fn per_scene(a: &Answer) -> String {
    let common = &a.summary.common;
    let mut h = String::from(
        "<table class=\"answer scenes\" id=\"answer-scenes\"><thead><tr><th>scene</th>",
    );
    for b in &a.budgets {
        let _ = write!(h, "<th>{}</th>", esc(&b.label()));
    }
    h += "</tr></thead><tbody>";
    let n = a.cost_models.len();
    for s in &a.scenes {
        let _ = write!(h, "<tr><th scope=\"row\">{}</th>", esc(s));
        for b in &a.budgets {
            let Some(sb) = (a.summary.per_scene.iter()).find(|x| x.scene == *s && x.budget == *b)
            else {
                h += "<td>-</td>";
                continue;
            };
            let same = sb.answers.len() == 1
                && sb.answers[0].method == common.method
                && sb.answers[0].nothing_cheaper == common.nothing_cheaper;
            let is_common = |x: &&SceneAnswer| {
                x.method == common.method && x.nothing_cheaper == common.nothing_cheaper
            };
            // What differs from the common answer first, the common answer last, muted.
            let body: String = if same {
                "<span class=\"same\">as everywhere</span>".into()
            } else {
                (sb.answers.iter().filter(|x| !is_common(x)))
                    .chain(sb.answers.iter().filter(is_common))
                    .map(|x| scene_answer_html(x, n, &a.cost_models, is_common(&x)))
                    .collect()
            };
            let _ = write!(
                h,
                "<td data-scene=\"{}\" data-budget=\"{}\" data-answers=\"{}\"{}>{body}</td>",
                esc(s),
                esc(&b.id()),
                esc(&answers_key(sb)),
                if same { " class=\"same\"" } else { "" }
            );
        }
        h += "</tr>";
    }
    h + "</tbody></table>"
}

/// A scene's answers under a budget as the browser test reads them: `method:count` (a `*`
/// after "nothing is cheaper than phong_exact"), comma-separated, the most widespread first.
pub fn answers_key(sb: &SceneBudget) -> String {
    sb.answers
        .iter()
        .map(|x| {
            format!(
                "{}{}:{}",
                x.method,
                if x.nothing_cheaper { "*" } else { "" },
                x.cost_models.len()
            )
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// The answer section: the words, what differs, per scene, the full grid one click away.
pub fn section(a: &Answer) -> String {
    let mut h = String::from(
        "<section id=\"answer\"><h2>Which method to use</h2><div id=\"answer-words\">",
    );
    for (k, s) in a.summary.sentences.iter().enumerate() {
        let _ = write!(h, "<p class=\"sentence\" data-k=\"{k}\">{}</p>", esc(s));
    }
    h += "<p class=\"lede\">Data: <a href=\"answer.json\">answer.json</a>, \
          <a href=\"answer.md\">answer.md</a>; the rule: docs/answer.md.</p></div>";
    h += &differing(a);
    let _ = write!(
        h,
        "<h3>Scene by scene: the cheapest method within each budget</h3><p class=\"lede\">On \
         each scene alone, per budget: the answers of the {} cost models, the most widespread \
         first, with the range of their cost ratios to {PHONG_EXACT} and how many models give \
         each (hover for which); <span class=\"same\">as everywhere</span>: the answer above \
         under every model.</p>",
        a.cost_models.len()
    );
    h += &per_scene(a);
    let _ = write!(
        h,
        "<details id=\"answer-grid\"><summary>The full grid: {} budgets x {} cost models, by \
         vendor (budget met on <em>every</em> scene, no non-finite pixel; the cheapest method \
         measured cheaper than {PHONG_EXACT}, its ratio with its interval in brackets, the \
         runner-up, the scene that decides the cell)</summary>",
        a.budgets.len(),
        a.cost_models.len()
    );
    h += &grid(a);
    h + "</details></section>"
}
