//! The body of the page below the answer and the claims, built from [`ReportData`]: a section
//! per scene (the metrics, bench's table and claims, each method's images), stress, plan,
//! skips and provenance. Every piece of text passes through [`esc`].
use std::fmt::Write as _;

use super::html::{esc, figure, method_anchor, num_td, number, Dims};
use super::*;
use crate::compare::{MethodReport, Metric, METRICS};

/// `shadelab plan` per scene: the figures that decide what is skipped, and the whole text.
pub(super) fn plan_section(d: &ReportData) -> String {
    let mut h = String::from(
        "<section id=\"plan\"><h2>Plan</h2><p>What each scene needs, measured before \
         drawing (<code>shadelab plan</code>): topology (back faces are culled only on closed, \
         consistently oriented meshes), the spread of each triangle's vertex normals against \
         every method's measured validity range, facing and size on screen.</p>\
         <table><thead><tr><th>scene</th><th>triangles</th><th>closed and oriented</th>\
         <th>back faces culled</th><th>back-facing</th><th>normal spread max / p99 (deg)</th>\
         <th>under one pixel</th><th>methods inside their range</th><th>JSON</th></tr></thead><tbody>",
    );
    for s in &d.scenes {
        let p = &s.plan;
        let inside = p.methods.iter().filter(|m| m.inside).count();
        let _ = write!(
            h,
            "<tr><td><a href=\"#scene-{}\">{}</a></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{:.2} / {:.2}</td><td>{}</td><td>{} of {}</td><td><a href=\"{}\">plan.json</a></td></tr>",
            esc(&s.id),
            esc(&p.scene),
            p.triangles,
            if p.closed_and_oriented { "yes" } else { "no" },
            if p.skips.first().is_some_and(|k| k.applies) { "yes" } else { "no" },
            p.back_facing,
            p.normal_angle_deg.max,
            p.normal_angle_deg.p99,
            p.sub_pixel_triangles,
            inside,
            p.methods.len(),
            esc(&s.plan_json)
        );
    }
    h += "</tbody></table>";
    for s in &d.scenes {
        let _ = write!(
            h,
            "<details><summary>{}</summary><pre>{}</pre></details>",
            esc(&s.plan.scene),
            esc(&s.plan.text())
        );
    }
    h += "</section>";
    h
}

/// `shadelab skips` per scene: phong_exact before and after each skip, paired per round.
pub(super) fn skips_section(d: &ReportData) -> String {
    let mut h = String::from(
        "<section id=\"skips\"><h2>Skips</h2><p>What each skip saves (<code>shadelab \
         skips</code>): phong_exact drawn as milestone 1 drew it (<em>none</em>: no culling, a \
         normal target), the renderer's default (culling where the mesh allows it, no normal \
         target), and the default with a depth pre-pass, with the triangles sorted front to \
         back, and <code>auto</code> at 1/255, all in the same interleaved rounds. Ratios are \
         medians of per-round ratios with sign-test 95% intervals; a verdict is faster or slower \
         only when the whole interval is on one side of 1.</p>\
         <table><thead><tr><th>scene</th><th>culled</th><th>fragment invocations none</th>\
         <th>default</th><th>default / none</th><th>pre-pass / default</th>\
         <th>front to back / default</th><th>auto / default</th><th>JSON</th></tr></thead><tbody>",
    );
    let ratio = |r: Option<&crate::bench::skips::SkipRow>, to_none: bool| match r {
        None => "n/a".to_string(),
        Some(r) => {
            let (x, v) = if to_none {
                (&r.ratio_to_none, r.speed_vs_none)
            } else {
                (&r.ratio_to_default, r.speed_vs_default)
            };
            format!(
                "{:.3} [{:.3}, {:.3}] {}",
                x.median,
                x.ci95_low,
                x.ci95_high,
                v.as_str()
            )
        }
    };
    for s in &d.scenes {
        let k = &s.skips;
        let row = |f: &dyn Fn(&crate::bench::skips::Variant) -> bool| {
            k.rows.iter().find(|r| f(&r.variant))
        };
        let none = k.rows.first();
        let default = k.rows.iter().find(|r| r.is_default);
        let inv = |r: Option<&crate::bench::skips::SkipRow>| {
            r.and_then(|r| r.fragment_invocations)
                .map_or("n/a".into(), |n| n.to_string())
        };
        let _ = write!(
            h,
            "<tr><td><a href=\"#scene-{}\">{}</a></td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{}</td><td>{}</td><td>{}</td><td>{}</td><td><a href=\"{}/skips.json\">skips.json</a></td></tr>",
            esc(&s.id),
            esc(&k.scene),
            if k.culls { "yes" } else { "no" },
            inv(none),
            inv(default),
            esc(&ratio(default, true)),
            esc(&ratio(row(&|v| v.prepass && !v.auto), false)),
            esc(&ratio(row(&|v| v.front_to_back && !v.auto), false)),
            esc(&ratio(row(&|v| v.auto), false)),
            esc(&s.skips_dir)
        );
    }
    h += "</tbody></table></section>";
    h
}

/// What each heatmap of compare shows, by its file stem.
fn heatmap_caption(file: &str) -> String {
    let stem = file
        .rsplit('/')
        .next()
        .unwrap_or(file)
        .trim_end_matches(".png");
    match stem {
        "error_abs" => "|luminance error| against the reference (log scale)".into(),
        "error_signed" => "signed luminance error, method minus reference".into(),
        "error_angle" => "angle between the method's and the exact normal (degrees)".into(),
        other => other.replace('_', " "),
    }
}

/// The numeric fields at the top level of a serialised row. Taken through TOML, which keeps
/// NaN and inf as numbers where JSON writes null: a NaN figure stays NaN (shown "NaN"), a field
/// that does not apply (`None`) is absent (shown "n/a"). Should TOML refuse the row, the JSON
/// numbers (non-finite ones then lost to null) are the fallback.
pub(crate) fn row_numbers(row: &impl serde::Serialize) -> std::collections::BTreeMap<String, f64> {
    if let Ok(toml::Value::Table(t)) = toml::Value::try_from(row) {
        return t
            .into_iter()
            .filter_map(|(k, v)| match v {
                toml::Value::Float(f) => Some((k, f)),
                toml::Value::Integer(i) => Some((k, i as f64)),
                _ => None,
            })
            .collect();
    }
    match serde_json::to_value(row) {
        Ok(serde_json::Value::Object(map)) => map
            .into_iter()
            .filter_map(|(k, v)| v.as_f64().map(|f| (k, f)))
            .collect(),
        _ => Default::default(),
    }
}

/// The bench columns: every key at the top level of a bench.json row that holds a number in
/// some row, NaN included (so fields bench adds later appear here without a change, and a
/// column that is NaN in every row is shown, not dropped), sorted by name.
fn bench_columns(scene: &SceneResult) -> Vec<String> {
    let mut keys = std::collections::BTreeSet::new();
    for row in &scene.bench.methods {
        keys.extend(row_numbers(row).into_keys());
    }
    keys.into_iter().collect()
}

fn bench_value(scene: &SceneResult, method: &str, key: &str) -> Option<f64> {
    let row = scene.bench.methods.iter().find(|r| r.name == method)?;
    row_numbers(row).get(key).copied()
}

fn sortable_head(groups: &[(&str, usize)], columns: &[String]) -> String {
    let mut h = String::from("<thead><tr>");
    for (label, span) in groups {
        let _ = write!(
            h,
            "<th colspan=\"{span}\" class=\"group\">{}</th>",
            esc(label)
        );
    }
    h += "</tr><tr>";
    for c in columns {
        let _ = write!(h, "<th scope=\"col\">{}</th>", esc(c));
    }
    h + "</tr></thead>"
}

/// The metric table of one scene: every compare metric and every bench number per method.
fn metric_table(s: &SceneResult) -> String {
    let bench_cols = bench_columns(s);
    let mut columns = vec!["method".to_string()];
    columns.extend(METRICS.iter().map(|m| m.to_string()));
    columns.extend(bench_cols.iter().cloned());
    let mut t = format!(
        "<div class=\"scroll\"><table class=\"sortable metrics\" id=\"{}\">",
        esc(&format!("scene-{}--metrics", s.id))
    );
    t += &sortable_head(
        &[
            ("", 1),
            ("error against the reference (compare)", METRICS.len()),
            ("run time (bench)", bench_cols.len()),
        ],
        &columns,
    );
    t += "<tbody>";
    for m in &s.summary.methods {
        let _ = write!(
            t,
            "<tr data-method=\"{}\" id=\"{}\"><th scope=\"row\"><a href=\"#{}\">{}</a></th>",
            esc(&m.name),
            esc(&super::front::row_anchor(&s.id, &m.name)),
            esc(&method_anchor(&s.id, &m.name)),
            esc(&m.name)
        );
        for k in METRICS {
            t += &num_td(m.metric(k));
        }
        for k in &bench_cols {
            t += &num_td(bench_value(s, &m.name, k));
        }
        t += "</tr>";
    }
    t + "</tbody></table></div>"
}

fn verdict_td(v: &str) -> String {
    format!(
        "<td class=\"verdict {}\">{}</td>",
        esc(&format!("v-{v}")),
        esc(v)
    )
}

/// A method name linked to `anchor` when that id exists on the page, plain text otherwise.
fn method_link(name: &str, anchor: Option<String>) -> String {
    match anchor {
        Some(a) => format!("<a href=\"#{}\">{}</a>", esc(&a), esc(name)),
        None => esc(name),
    }
}

fn bench_claims(s: &SceneResult) -> String {
    let mut t = format!(
        "<div class=\"scroll\"><table class=\"sortable claims\" id=\"{}\">",
        esc(&format!("scene-{}--claims", s.id))
    );
    let cols: Vec<String> = ["method", "claim", "verdict", "measured", "how", "why"]
        .map(String::from)
        .to_vec();
    t += &sortable_head(&[("the papers' claims, measured by bench", 6)], &cols);
    t += "<tbody>";
    let known = |n: &str| s.summary.methods.iter().any(|m| m.name == n);
    for (k, c) in s.bench.claims.iter().enumerate() {
        let anchor = known(&c.method).then(|| method_anchor(&s.id, &c.method));
        let _ = write!(
            t,
            "<tr id=\"{}\"><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&super::front::claim_anchor(&s.id, k)),
            method_link(&c.method, anchor),
            super::formulas::cite(&c.claim),
            verdict_td(c.verdict.as_str()),
            esc(&c.measured),
            esc(&c.how),
            esc(&c.reason)
        );
    }
    t + "</tbody></table></div>"
}

/// One method of one scene: the viewer (method and reference at the same spot) and heatmaps.
fn method_section(s: &SceneResult, m: &MethodReport, reference: &str, dims: Dims) -> String {
    let anchor = method_anchor(&s.id, &m.name);
    let file = |f: &str| format!("{}/{}", s.compare_dir, f);
    let render = m.files.iter().find(|f| f.ends_with("render.png"));
    let mut h = format!(
        "<article class=\"method\" id=\"{}\" data-method=\"{}\"><h4>{} <a class=\"up\" href=\"#{}\">table</a></h4>",
        esc(&anchor),
        esc(&m.name),
        esc(&m.name),
        esc(&format!("scene-{}--metrics", s.id))
    );
    let (_, mean) = number(Metric::MeanAbsError.of(m));
    let (_, p99) = number(Metric::P99AbsError.of(m));
    let _ = write!(
        h,
        "<p class=\"figures\">mean |dI| {}, p99 |dI| {}, non-finite pixels {}</p>",
        esc(&mean),
        esc(&p99),
        m.non_finite_pixels
    );
    h += "<div class=\"method-body\">";
    if let Some(r) = render {
        let _ = write!(
            h,
            "<div class=\"viewer\">{}{}</div>",
            figure(reference, "reference: exact Phong in f64", "px v-ref", dims),
            figure(&file(r), &format!("{}: render", m.name), "px v-mth", dims)
        );
    }
    h += "<div class=\"heatmaps\">";
    for f in m.files.iter().filter(|f| !f.ends_with("render.png")) {
        h += &figure(&file(f), &heatmap_caption(f), "px heat", dims);
    }
    h + "</div></div></article>"
}

pub(super) fn scene_section(s: &SceneResult, dims: Dims) -> String {
    let sum = &s.summary;
    let reference = format!("{}/reference.png", s.compare_dir);
    let mut h = format!(
        "<section class=\"scene\" id=\"{}\"><h2>Scene {}</h2>",
        esc(&format!("scene-{}", s.id)),
        esc(&sum.scene)
    );
    let _ = write!(
        h,
        "<p>{} &middot; {} triangles &middot; {}&times;{} &middot; {} interpolation &middot; {} background pixels. Data: \
         <a href=\"{c}/summary.json\">summary.json</a>, <a href=\"{c}/summary.csv\">summary.csv</a>, \
         <a href=\"{b}/bench.json\">bench.json</a>, <a href=\"{b}/bench.csv\">bench.csv</a>, \
         <a href=\"{b}/claims.md\">claims.md</a>, software engine: \
         <a href=\"{sw}/bench.json\">bench.json</a>.</p>",
        esc(&s.source),
        sum.triangles,
        sum.width,
        sum.height,
        esc(&sum.interpolation),
        sum.background_pixels,
        c = esc(&s.compare_dir),
        b = esc(&s.bench_dir),
        sw = esc(&s.software_dir)
    );
    h += &figure(
        &reference,
        "reference: exact Phong evaluated in f64 at the rasterizer's weights",
        "px",
        dims,
    );
    let b = &s.bench;
    let _ = write!(
        h,
        "<h3>Metrics</h3><p>Errors are of the linear luminance against the reference, over the \
         covered pixels (docs/compare.md); <code>inf</code> marks a method with non-finite \
         pixels, <code>n/a</code> a metric that does not apply. Times: median of {} timed draws \
         after {} warm-ups ({} clock), constant-colour floor {} ms. Click a column to sort.</p>",
        b.repeat,
        b.warmup,
        esc(b.clock.clock.as_str()),
        esc(&number(Some(b.floor.median_ms)).1)
    );
    h += &metric_table(s);
    h += "<h3>Run time against error</h3>";
    if let Some(c) = super::svg::scene_cost_chart(s) {
        h += &c.html(
            "This scene: each method's lavapipe frame time relative to phong_exact (with its \
             interval) against its max |dI|; dashed: the budgets and the ratio 1. One panel per \
             method family, the same axes in every panel.",
        );
    }
    let files: Vec<String> = s
        .pareto_charts
        .iter()
        .map(|c| {
            format!(
                "<a href=\"{}\">{}</a>",
                esc(c),
                esc(c.rsplit('/').next().unwrap_or(c))
            )
        })
        .collect();
    if !files.is_empty() {
        let _ = write!(
            h,
            "<p>bench's own charts (every method in one plot): {}.</p>",
            files.join(", ")
        );
    }
    h += "<h3>Methods</h3><p>Each method beside the reference (with JavaScript: on top of \
          it, with a slider, a flip button and zoom; nearest-pixel scaling) and its heatmaps.</p>";
    for m in &sum.methods {
        h += &method_section(s, m, &reference, dims);
    }
    let count = |v: &str| {
        s.bench
            .claims
            .iter()
            .filter(|c| c.verdict.as_str() == v)
            .count()
    };
    let _ = write!(
        h,
        "<details open><summary><h3>Claims</h3> {} claims: {} agree, {} partly, {} disagree, {} \
         inconclusive, {} not checked</summary>",
        s.bench.claims.len(),
        count("agrees"),
        count("partly"),
        count("disagrees"),
        count("inconclusive"),
        count("not_checked")
    );
    h += &bench_claims(s);
    h += "</details>";
    h + "</section>"
}

pub(super) fn stress_section(d: &ReportData, dims: Dims) -> String {
    let r = &d.stress;
    let dir = &d.stress_dir;
    let mut h = format!(
        "<section id=\"stress\"><h2>Stress: each method over its input domain</h2><p>{} cases \
         per method, threshold {} (max abs colour error, linear), {:.1} s. Data: \
         <a href=\"{}/stress.json\">stress.json</a>.</p><p>stress's own charts (every method in \
         one plot): ",
        r.cases_per_method,
        esc(&number(Some(r.threshold)).1),
        r.seconds,
        esc(dir)
    );
    for (f, cap) in [
        (
            "error_vs_angle",
            "worst error against the angle between vertex normals",
        ),
        ("error_vs_shininess", "worst error against the shininess"),
    ] {
        let _ = write!(
            h,
            "<a href=\"{}\">{}</a> ",
            esc(&format!("{dir}/{f}.png")),
            esc(cap)
        );
    }
    h += "</p>";
    h += "<p>Worst error against the angle between the vertex normals: \
          <a href=\"#chart-stress\">at the top of the page</a>.</p>";
    if let Some(c) = super::svg::stress_chart(d, super::svg::Sweep::Shininess) {
        h += &c.html(
            "stress: worst error on the device against log2 of the shininess, the vertex \
             normals 15 degrees apart; dashed: the threshold. One panel per family, the same \
             axes in every panel; the numbered marker ends each line.",
        );
    }
    let cols: Vec<String> = [
        "method",
        "cases",
        "non_finite_cases",
        "non_finite_cases_f64",
        "worst_abs_error",
        "worst_finite_abs_error",
        "worst_abs_error_f64",
        "max_valid_angle_deg",
        "max_valid_angle_deg_f64",
    ]
    .map(String::from)
    .to_vec();
    h += "<div class=\"scroll\"><table class=\"sortable\" id=\"stress--table\">";
    h += &sortable_head(&[("stress.json per method", cols.len())], &cols);
    h += "<tbody>";
    for m in &r.methods {
        // stress.json writes a worst error of null when a case was non-finite: shown as inf
        // (non-finite), on the device and in f64 alike, never as n/a (does not apply).
        let worst = if m.non_finite_cases > 0 {
            Some(f64::INFINITY)
        } else {
            m.worst_abs_error
        };
        let worst_f64 = if m.non_finite_cases_f64 > 0 {
            Some(f64::INFINITY)
        } else {
            m.worst_abs_error_f64
        };
        let _ = write!(
            h,
            "<tr><th scope=\"row\"><a href=\"#{}\">{}</a></th>{}{}{}{}{}{}{}{}</tr>",
            esc(&format!("stress--{}", m.name)),
            esc(&m.name),
            num_td(Some(m.cases as f64)),
            num_td(Some(m.non_finite_cases as f64)),
            num_td(Some(m.non_finite_cases_f64 as f64)),
            num_td(worst),
            num_td(m.worst_finite_abs_error),
            num_td(worst_f64),
            num_td(m.max_valid_angle_deg),
            num_td(m.max_valid_angle_deg_f64),
        );
    }
    h += "</tbody></table></div><h3>Validity claims</h3>";
    let cols: Vec<String> = ["method", "claim", "verdict", "measured", "how"]
        .map(String::from)
        .to_vec();
    h += "<div class=\"scroll\"><table class=\"sortable claims\" id=\"stress--claims\">";
    h += &sortable_head(
        &[("the papers' validity claims, measured by stress", 5)],
        &cols,
    );
    h += "<tbody>";
    for (k, c) in r.claims.iter().enumerate() {
        let known = r.methods.iter().any(|m| m.name == c.method);
        let _ = write!(
            h,
            "<tr id=\"stress--claim-{k}\"><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td></tr>",
            method_link(&c.method, known.then(|| format!("stress--{}", c.method))),
            super::formulas::cite(&c.claim),
            verdict_td(c.verdict.as_str()),
            esc(&c.measured),
            esc(&c.how)
        );
    }
    h += "</tbody></table></div><h3>Validity maps</h3><p>Worst device error per (angle between \
          vertex normals, elevation) cell; grey: NaN/Inf.</p><div class=\"validity\">";
    for m in &r.methods {
        let _ = write!(
            h,
            "<div id=\"{}\">{}</div>",
            esc(&format!("stress--{}", m.name)),
            figure(
                &format!("{dir}/validity/{}.png", m.name),
                &m.name,
                "px",
                dims
            )
        );
    }
    h + "</div></section>"
}

pub(super) fn provenance_section(d: &ReportData) -> String {
    let run = &d.run;
    let mut rows: Vec<(&str, String)> = Vec::new();
    if let Some(s) = d.scenes.first() {
        let p = &s.summary.provenance;
        rows.push(("tool", format!("{} {}", p.tool, p.version)));
        rows.push(("git revision", p.git_revision.clone()));
        rows.push(("device", p.device.clone()));
        rows.push(("driver", format!("{} ({})", p.driver, p.driver_info)));
        rows.push(("Vulkan API", p.vulkan_api.clone()));
        let opt = |o: &Option<String>| o.clone().unwrap_or_else(|| "unknown".into());
        rows.push(("Mesa", opt(&p.mesa_version)));
        rows.push(("LLVM", opt(&p.llvm_version)));
    }
    rows.push(("CPU", run.cpu_model.clone()));
    rows.push((
        "threads",
        format!(
            "{} available; LP_NUM_THREADS={}",
            run.available_threads,
            run.lp_num_threads.as_deref().unwrap_or("unset")
        ),
    ));
    rows.push(("command line", run.command_line.clone()));
    rows.push(("date", run.date_utc.clone()));
    rows.push((
        "settings",
        format!(
            "{}: bench {} run(s) (each a fresh process), {} timed draws after {} warm-ups per \
             program and run; stress {} refinement rounds",
            if run.full { "full" } else { "short" },
            run.bench_runs,
            run.bench_repeat,
            run.bench_warmup,
            run.stress_refine
        ),
    ));
    rows.push(("jobs' run time", format!("{:.1} s", run.seconds)));
    // What each scene's mesh file gave: format, and for glTF the scene and primitives drawn.
    let meshes: Vec<(String, String)> = d
        .scenes
        .iter()
        .filter_map(|s| {
            let m = s.summary.mesh_input.as_ref()?;
            Some((
                format!("mesh of {}", s.summary.scene),
                format!("{}: {}", s.summary.scene_source, m.describe()),
            ))
        })
        .collect();
    rows.extend(meshes.iter().map(|(k, v)| (k.as_str(), v.clone())));
    let mut h =
        String::from("<section id=\"provenance\"><h2>Provenance</h2><table class=\"prov\"><tbody>");
    for (k, v) in rows {
        let _ = write!(
            h,
            "<tr><th scope=\"row\">{}</th><td>{}</td></tr>",
            esc(k),
            esc(&v)
        );
    }
    h + "</tbody></table></section>"
}
