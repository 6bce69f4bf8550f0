//! `shadelab report` as a person sees it: a small report (one small scene whose name holds HTML
//! specials, a few methods, 48 px) generated once by the built binary under the validation
//! layer; its links checked without a browser; then loaded over file:// in headless Chromium,
//! which must report no JavaScript or console error and no failed resource, run the page's
//! script (sorting, viewer), and paint a screenshot that is not blank. Each check is also run on
//! a page broken on purpose, which it must reject.
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use shadelab::report::links::broken_links;

use crate::support::*;

mod claims;
mod first_screen;
mod size_limit;

/// The methods asked for; the report adds phong_exact and phong_unnormalized (bench's refs).
const ASKED: &str = "gouraud,slerp";
const SHOWN: [&str; 4] = ["gouraud", "phong_exact", "phong_unnormalized", "slerp"];
/// A scene name that breaks the page unless every string is escaped: unescaped, the `<img>`
/// would be a failed resource load in the browser test and the raw text would show below.
const EVIL_NAME: &str = r#"<img src="nope.png"> & "quotes" 'too'"#;

/// The report folder, generated once for all the tests of this file (in target/, kept for a
/// person to open after a failure).
fn report_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("report-test");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("tiny.toml");
        std::fs::write(
            &scene,
            format!(
                "name = {}\n[mesh]\ngenerator = \"icosphere\"\nsubdivisions = 1\n",
                toml_string(EVIL_NAME)
            ),
        )
        .unwrap();
        let out = dir.join("out");
        // a file of an earlier report in the folder (another scene): named in a warning
        let stale = out.join("scenes/earlier/render.png");
        std::fs::create_dir_all(stale.parent().unwrap()).unwrap();
        std::fs::write(&stale, b"an earlier report's render").unwrap();
        let (code, stdout, stderr) = run(&[
            "report",
            "--scene",
            scene.to_str().unwrap(),
            "--methods",
            ASKED,
            "--size",
            "48x48",
            "--validate",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "report failed:\n{stderr}");
        let index = out.join("index.html");
        assert_eq!(stdout.trim(), index.display().to_string(), "{stderr}");
        // The answer in a few lines: the words and the differing cells after the totals; each
        // job's progress and every cell's line only with -v.
        let answer: Vec<&str> = (stderr.lines())
            .skip_while(|l| !l.starts_with("report: 1 scene(s)"))
            .collect();
        assert!(
            (2..=15).contains(&answer.len()) && answer[0].contains("The answer ("),
            "{stderr}"
        );
        // (a per-cell line starts with `answer: `; "Missing from this answer: ..." is words)
        assert!(
            !stderr.lines().any(|l| l.starts_with("answer: ")) && !stderr.contains("bench: run"),
            "{stderr}"
        );
        // (the warning was not there before: the earlier report's files stayed silently)
        assert!(
            stderr.contains("1 file(s) in")
                && stderr.contains("are not from this run")
                && stderr.contains("scenes/earlier/render.png"),
            "{stderr}"
        );
        out
    })
}

fn toml_string(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// The ids of the page's top-level `<section>` elements, in order (a scene's parts are
/// sections inside its section: not in the navigation).
fn top_level_section_ids(body: &str) -> Vec<String> {
    let mut depth = 0usize;
    let mut ids = Vec::new();
    let mut rest = body;
    while let Some(i) = [rest.find("<section"), rest.find("</section>")]
        .into_iter()
        .flatten()
        .min()
    {
        if rest[i..].starts_with("</section>") {
            depth = depth.saturating_sub(1);
            rest = &rest[i + 10..];
            continue;
        }
        let tag = &rest[i..i + rest[i..].find('>').unwrap_or(0)];
        if depth == 0 {
            let id = tag.split("id=\"").nth(1).and_then(|x| x.split('"').next());
            ids.push(id.unwrap_or("").to_string());
        }
        depth += 1;
        rest = &rest[i + 8..];
    }
    ids
}

fn index_html() -> String {
    std::fs::read_to_string(report_dir().join("index.html")).unwrap()
}

/// What a page lacks for `methods` of scene `id`: the method's section with its viewer (render
/// and reference) and heatmaps, its row in the metric table, its validity map.
fn missing_parts(html: &str, id: &str, methods: &[&str]) -> Vec<String> {
    let mut missing = Vec::new();
    for m in methods {
        let start = format!("<article class=\"method\" id=\"{id}--{m}\"");
        let Some(i) = html.find(&start) else {
            missing.push(format!("{m}: no section"));
            continue;
        };
        let section = &html[i..i + html[i..].find("</article>").unwrap_or(0)];
        for part in [
            "class=\"px v-ref\"".to_string(),
            "class=\"px v-mth\"".to_string(),
            format!("{m}/render.png"),
            format!("{m}/error_abs.png"),
            format!("{m}/error_signed.png"),
        ] {
            if !section.contains(&part) {
                missing.push(format!("{m}: no {part}"));
            }
        }
        if !html.contains(&format!("<tr data-method=\"{m}\" ")) {
            missing.push(format!("{m}: no row in the metric table"));
        }
        if !html.contains(&format!("validity/{m}.png")) {
            missing.push(format!("{m}: no validity map"));
        }
    }
    missing
}

#[test]
fn report_links_resolve_and_every_method_has_its_parts() {
    let dir = report_dir();
    let html = index_html();
    let broken = broken_links(&dir.join("index.html")).unwrap();
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    assert_eq!(
        missing_parts(&html, "scene-tiny", &SHOWN),
        Vec::<String>::new()
    );
    // One list of sections: every section of the page is in the navigation, in page order
    // (the static cost's section included), and the navigation names nothing else on the page.
    let (nav, body) = html.split_once("<main>").unwrap();
    let ids: Vec<&str> = nav
        .split("href=\"#")
        .skip(1)
        .map(|x| x.split('"').next().unwrap())
        .collect();
    assert!(ids.contains(&"isa") && ids.contains(&"answer"), "{ids:?}");
    let at: Vec<usize> = ids
        .iter()
        .map(|id| {
            body.find(&format!("<section id=\"{id}\""))
                .or_else(|| body.find(&format!("<section class=\"scene\" id=\"{id}\"")))
                .unwrap_or(usize::MAX)
        })
        .collect();
    assert!(
        at.iter().all(|&a| a < usize::MAX),
        "a nav entry without its section: {ids:?}"
    );
    assert!(
        at.windows(2).all(|w| w[0] < w[1]),
        "not in page order: {ids:?}"
    );
    assert_eq!(
        top_level_section_ids(body),
        ids,
        "the page's sections and its navigation"
    );
    // Escaped everywhere: the raw name never appears, the escaped one does.
    assert!(!html.contains(EVIL_NAME));
    assert!(html
        .contains("&lt;img src=&quot;nope.png&quot;&gt; &amp; &quot;quotes&quot; &#39;too&#39;"));
    // Nothing from the network.
    for needle in ["http://", "https://", "//fonts", "@import"] {
        assert!(!html.contains(needle), "the page names {needle}");
    }
    for part in [
        "id=\"scene-tiny--metrics\"",
        "id=\"scene-tiny--claims\"",
        "pareto.png",
        "error_vs_angle.png",
        "error_vs_shininess.png",
        "id=\"stress--claims\"",
        "id=\"provenance\"",
        "id=\"plan\"",
        "id=\"skips\"",
        "skips/skips.json",
        "git revision",
        "Mesa",
        "LLVM",
        "command line",
    ] {
        assert!(html.contains(part), "the page lacks {part}");
    }

    // The skips row of the scene: computed from its skips.json (the icosphere is closed and
    // culled; the default draw has fewer fragments: half or fewer as lavapipe 22.3.6 counts
    // them, whole pixel blocks; 1530 of 1892 as 25.0.7 counts them, after early depth).
    let skips: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("scenes/tiny/skips/skips.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(skips["culls"], true);
    let rows = skips["rows"].as_array().unwrap();
    let inv = |r: &serde_json::Value| r["fragment_invocations"].as_u64().unwrap();
    let default = rows.iter().find(|r| r["is_default"] == true).unwrap();
    assert!(inv(default) < inv(&rows[0]), "{skips}");
    let shown = format!(
        "<td>{}</td><td>{}</td><td>{:.3} [",
        inv(&rows[0]),
        inv(default),
        default["ratio_to_none"]["median"].as_f64().unwrap()
    );
    assert!(html.contains(&shown), "the skips table lacks {shown}");

    // Teeth: a page with a dangling image, a missing anchor or a method without its section
    // or row fails the same checks.
    let broken_page = dir.join("broken.html");
    std::fs::write(
        &broken_page,
        html.replace("gouraud/render.png", "gouraud/gone.png")
            .replace("href=\"#stress\"", "href=\"#nowhere\""),
    )
    .unwrap();
    let found = broken_links(&broken_page).unwrap();
    std::fs::remove_file(&broken_page).unwrap();
    assert!(
        found.iter().any(|b| b.contains("gouraud/gone.png"))
            && found.iter().any(|b| b.contains("#nowhere")),
        "{found:?}"
    );
    let cut = html.replace("<tr data-method=\"slerp\" ", "<tr ");
    assert_eq!(
        missing_parts(&cut, "scene-tiny", &SHOWN),
        vec!["slerp: no row in the metric table".to_string()]
    );
    assert_eq!(missing_parts(&html, "scene-tiny", &["flat"]).len(), 1);
}

/// Headless Chromium, or `None` with a `SKIPPED` line (a failure under
/// `SHADELAB_REQUIRE_BROWSER=1`, which CI sets), like [`models_dir`].
fn chromium() -> Option<PathBuf> {
    let found = ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            std::env::var_os("PATH").and_then(|p| {
                std::env::split_paths(&p)
                    .map(|d| d.join(name))
                    .find(|f| f.is_file())
            })
        });
    if found.is_none() {
        let test = std::thread::current()
            .name()
            .unwrap_or("a test")
            .to_string();
        if std::env::var("SHADELAB_REQUIRE_BROWSER").as_deref() == Ok("1") {
            panic!("{test}: SHADELAB_REQUIRE_BROWSER=1 but no chromium on PATH (scripts/install-deps.sh test)");
        }
        use std::io::Write as _;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED: {test}: no chromium on PATH (scripts/install-deps.sh test installs it)"
        );
    }
    found
}

/// Runs headless Chromium on `page` with `args`, killed after two minutes; returns stdout.
fn headless(browser: &Path, page: &Path, args: &[&str]) -> String {
    headless_sized(browser, page, "1280,1600", args)
}

/// [`headless`] in a window of `size` (`W,H`).
fn headless_sized(browser: &Path, page: &Path, size: &str, args: &[&str]) -> String {
    let profile = tempfile::tempdir().unwrap();
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--disable-gpu",
            "--no-sandbox",
            "--no-first-run",
            "--hide-scrollbars",
        ])
        .arg(format!("--window-size={size}"))
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start chromium");
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut s).ok();
        s
    });
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish on {} in 120 s", page.display());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    reader.join().unwrap()
}

/// Injected first into <head> of a test copy: records script errors, failed resource loads
/// (error events captured at the window), console.error calls and, after `load`, every image
/// that did not decode, whether report.js ran, built every viewer and sorts a column; writes it
/// all as JSON into <pre id="probe">, which --dump-dom prints.
const PROBE: &str = r#"<script>
window.__probe = {errors: []};
window.addEventListener("error", function (e) {
  var t = e.target;
  window.__probe.errors.push(t && t !== window ? "failed to load " + (t.src || t.href) : "script error: " + e.message);
}, true);
window.addEventListener("unhandledrejection", function (e) { window.__probe.errors.push("rejection: " + e.reason); });
(function () { var ce = console.error; console.error = function () {
  window.__probe.errors.push("console.error: " + Array.prototype.join.call(arguments, " ")); ce.apply(console, arguments); }; })();
window.addEventListener("load", function () {
  var p = window.__probe;
  p.images = document.images.length;
  p.broken_images = Array.prototype.filter.call(document.images, function (i) { return !(i.complete && i.naturalWidth > 0); }).map(function (i) { return i.src; });
  p.js = document.documentElement.getAttribute("data-report-js");
  p.viewers = document.querySelectorAll(".viewer").length;
  p.viewers_built = document.querySelectorAll(".viewer.js .stage img.v-mth").length;
  var t = document.querySelector("table.metrics");
  p.sorted = null;
  if (t) {
    var heads = t.tHead.rows[t.tHead.rows.length - 1].cells, col = -1;
    for (var i = 0; i < heads.length; i++) if (heads[i].textContent === "mean_abs_error") col = i;
    var b = col >= 0 ? heads[col].querySelector("button") : null;
    if (b) {
      b.click(); b.click();
      var v = Array.prototype.map.call(t.tBodies[0].rows, function (r) { return Number(r.cells[col].getAttribute("data-v")); });
      p.sorted = v.every(function (x, k) { return k === 0 || v[k - 1] >= x; }) && v.length > 1;
    }
  }
  var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(p);
  document.body.appendChild(pre);
});
</script>"#;

/// Loads `page` with the probe (images eager, so `load` waits for every one) and returns the
/// probe's record.
fn probe(browser: &Path, page: &Path) -> serde_json::Value {
    probe_with(browser, page, PROBE, "1280,1600")
}

/// Loads `page` with `script` injected first into <head>, in a window of `size`, and returns
/// what the script wrote into <pre id="probe">.
fn probe_with(browser: &Path, page: &Path, script: &str, size: &str) -> serde_json::Value {
    let html = std::fs::read_to_string(page).unwrap();
    // One file per script: the browser tests run in parallel on the same report.
    let probed = page.with_file_name(format!("probe-{}.html", script.len()));
    std::fs::write(
        &probed,
        html.replacen("<head>", &format!("<head>{script}"), 1)
            .replace(" loading=\"lazy\"", ""),
    )
    .unwrap();
    let dom = headless_sized(browser, &probed, size, &["--dump-dom"]);
    std::fs::remove_file(&probed).unwrap();
    let start = dom.find("<pre id=\"probe\">").unwrap_or_else(|| {
        panic!(
            "no probe output in the DOM of {}:\n{dom:.2000}",
            page.display()
        )
    }) + "<pre id=\"probe\">".len();
    let end = start + dom[start..].find("</pre>").unwrap();
    let json = dom[start..end]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    serde_json::from_str(&json).unwrap_or_else(|e| panic!("probe JSON {json}: {e}"))
}

/// Distinct colours of a PNG.
fn distinct_colours(png: &Path) -> usize {
    let img = image::open(png).unwrap().to_rgb8();
    let mut seen = std::collections::HashSet::new();
    for p in img.pixels() {
        seen.insert(p.0);
    }
    seen.len()
}

#[test]
fn report_loads_in_a_browser_without_errors_and_is_not_blank() {
    let Some(browser) = chromium() else { return };
    let dir = report_dir();
    let index = dir.join("index.html");
    let p = probe(&browser, &index);
    assert_eq!(p["errors"], serde_json::json!([]), "{p}");
    assert_eq!(p["broken_images"], serde_json::json!([]), "{p}");
    assert_eq!(p["js"], "ready", "report.js did not run: {p}");
    assert_eq!(p["viewers"].as_u64(), Some(SHOWN.len() as u64), "{p}");
    assert_eq!(p["viewers_built"], p["viewers"], "{p}");
    assert_eq!(
        p["sorted"], true,
        "sorting mean_abs_error descending failed: {p}"
    );
    // reference + per method render, reference again, 2-3 heatmaps; charts; validity maps.
    assert!(
        p["images"].as_u64().unwrap() > 4 * SHOWN.len() as u64,
        "{p}"
    );

    // Teeth: a copy with a missing image, a missing stylesheet and a script error is rejected.
    let bad = dir.join("broken.browser.html");
    std::fs::write(
        &bad,
        std::fs::read_to_string(&index).unwrap().replacen(
            "</body>",
            "<img src=\"no/such.png\"><link rel=\"stylesheet\" href=\"none.css\"><script>no_such_function();</script></body>",
            1,
        ),
    )
    .unwrap();
    let q = probe(&browser, &bad);
    std::fs::remove_file(&bad).unwrap();
    let errors = q["errors"].to_string();
    assert!(
        errors.contains("no/such.png")
            && errors.contains("none.css")
            && errors.contains("no_such_function"),
        "{q}"
    );
    assert_eq!(q["broken_images"].as_array().unwrap().len(), 1, "{q}");

    // The screenshot: saved beside the report, and not blank.
    let shot = dir.join("screenshot.png");
    let _ = std::fs::remove_file(&shot);
    headless(
        &browser,
        &index,
        &[&format!("--screenshot={}", shot.display())],
    );
    let colours = distinct_colours(&shot);
    eprintln!("screenshot: {} ({colours} colours)", shot.display());
    // Text, the renders and the heatmaps give thousands; a blank page gives 1.
    assert!(
        colours > 200,
        "{} looks blank: {colours} colours",
        shot.display()
    );
    // Teeth: a blank page's screenshot fails the same bound.
    let blank = dir.join("blank.html");
    std::fs::write(&blank, "<!DOCTYPE html><html><body></body></html>").unwrap();
    let blank_shot = dir.join("blank.png");
    headless(
        &browser,
        &blank,
        &[&format!("--screenshot={}", blank_shot.display())],
    );
    assert!(distinct_colours(&blank_shot) <= 200);
}

#[test]
fn report_needs_exactly_one_source() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (code, _, stderr) = run(&["report", "--out", out]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("--scenes"), "{stderr}");
    let (code, _, stderr) = run(&[
        "report",
        "--scene",
        "scenes/cube.toml",
        "--mesh",
        "scenes/cube.obj",
        "--out",
        out,
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}

/// The disassembly folders under a report's `dir` (isa/asm, isa-f16/asm) that exist.
fn disassembly_dirs(dir: &Path) -> Vec<PathBuf> {
    ["isa/asm", "isa-f16/asm"]
        .iter()
        .map(|d| dir.join(d))
        .filter(|d| d.exists())
        .collect()
}

/// The default report leaves the static cost's disassembly to `--full` (tens of MB over every
/// family): no asm/ folder, isa.json lists none, yet every family's figures are there.
#[test]
fn report_leaves_the_disassembly_to_full() {
    let dir = report_dir();
    assert_eq!(disassembly_dirs(dir), Vec::<PathBuf>::new());
    for f in ["isa/isa.json", "isa-f16/isa.json"] {
        let isa = read_json(dir.join(f));
        assert_eq!(isa["asm"], serde_json::json!([]), "{f}");
        assert!(!isa["results"].as_array().unwrap().is_empty(), "{f}");
    }
    // Teeth: a folder holding isa/asm is found.
    let t = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(t.path().join("isa/asm/amd_navi21")).unwrap();
    assert_eq!(disassembly_dirs(t.path()), vec![t.path().join("isa/asm")]);
}

#[test]
fn report_writes_an_answer_that_matches_its_schema() {
    let dir = report_dir();
    let answer = read_json(dir.join("answer.json"));
    assert_schema(&answer, "docs/answer.schema.json", "/cells/0", "answer");
    assert_schema(&answer, "docs/answer.schema.json", "/cells/0", "binding");
    assert_schema(
        &answer,
        "docs/answer.schema.json",
        "/cost_models/0",
        "precision",
    );
    assert_schema(
        &answer,
        "docs/answer.schema.json",
        "/checks/0",
        "failing_scenes",
    );
    // Every budget under every cost model this run measured (frame time across runs,
    // isolated cost, the software engine).
    let models: Vec<&str> = answer["cost_models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        models[..3],
        ["lavapipe_frame", "lavapipe_isolated", "software"]
    );
    // Then each GPU family isa compiled, float32 then float16 (static: no interval).
    let families = |f: &str| -> Vec<String> {
        let isa = read_json(dir.join(f));
        isa["families"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|x| x["supported"] == true)
            .map(|x| x["family"].as_str().unwrap().to_string())
            .collect()
    };
    let mut isa: Vec<String> = families("isa/isa.json")
        .iter()
        .map(|f| format!("isa:{f}"))
        .collect();
    isa.extend(
        families("isa-f16/isa.json")
            .iter()
            .map(|f| format!("isa:{f}:f16")),
    );
    assert!(
        isa.len() >= 8 && isa.iter().any(|m| m.ends_with(":f16")),
        "{isa:?}"
    );
    assert_eq!(models[3..], isa[..]);
    assert_eq!(answer["cells"].as_array().unwrap().len(), 6 * models.len());
    // The frame figures come from 5 fresh-process runs (bench.json `runs`).
    let bench = read_json(dir.join("scenes/tiny/bench/bench.json"));
    assert_eq!(bench["runs"]["count"], 5, "{}", bench["runs"]);
    let precision = |model: &serde_json::Value| {
        answer["cost_models"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == *model)
            .unwrap()["precision"]
            .clone()
    };
    // The rule on this run's own figures: an answer other than phong_exact meets its budget
    // in its model's precision and is measured cheaper; phong_exact meets every float32 budget.
    for c in answer["cells"].as_array().unwrap() {
        let method = c["answer"]["method"].as_str().unwrap();
        let p = precision(&c["cost_model"]);
        let m = answer["cost_models"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["name"] == c["cost_model"])
            .unwrap();
        if m["kind"] == "static" {
            assert!(m["figures"]
                .as_array()
                .unwrap()
                .iter()
                .all(|f| f["ci95_low"].is_null()));
        }
        let check = answer["checks"]
            .as_array()
            .unwrap()
            .iter()
            .find(|k| k["method"] == method && k["budget"] == c["budget"] && k["precision"] == p)
            .unwrap();
        if method != "phong_exact" || p == "f32" {
            assert_eq!(check["meets"], true, "{c}\n{check}");
        }
        assert_eq!(c["nothing_cheaper"], method == "phong_exact", "{c}");
        if method != "phong_exact" {
            assert_eq!(c["answer"]["verdict"], "agrees", "{c}");
        }
    }
    // The float16 errors come from compare of the float16 programs.
    let half = read_json(dir.join("scenes/tiny/compare-f16/summary.json"));
    assert_eq!(half["precision"], "f16", "{}", half["precision"]);
    let md = std::fs::read_to_string(dir.join("answer.md")).unwrap();
    assert!(
        md.contains("| cost model |") && md.contains("max |dI| <= 1/255"),
        "{md}"
    );
}

/// `--models DIR` adds every OBJ of the folder as a scene (alone here), and the answer covers
/// it; a folder without an OBJ is a usage error. With `-v` the report prints every cell.
#[test]
fn report_models_adds_every_obj_of_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let models = dir.path().join("models");
    std::fs::create_dir_all(&models).unwrap();
    std::fs::copy("scenes/icosphere.obj", models.join("ball.obj")).unwrap();
    std::fs::copy("scenes/cube.obj", models.join("box.OBJ")).unwrap();
    std::fs::write(models.join("notes.txt"), "not a mesh").unwrap();
    let out = dir.path().join("out");
    // -v: every cell's line and the jobs' progress, which the default leaves out.
    let (code, _, stderr) = run(&[
        "-v",
        "report",
        "--models",
        models.to_str().unwrap(),
        "--methods",
        "gouraud",
        "--size",
        "32x32",
        "--runs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("answer: ") && stderr.contains("bench: "),
        "{stderr}"
    );
    let answer = read_json(out.join("answer.json"));
    // The most triangles first: the icosphere before the 12-triangle cube.
    assert_eq!(answer["scenes"], serde_json::json!(["ball", "box"]));
    for id in ["ball", "box"] {
        // bench's error metrics are the scene's compare statistics (taken, not drawn again),
        // without the compare's image files
        let bench = read_json(out.join(format!("scenes/{id}/bench/bench.json")));
        let summary = read_json(out.join(format!("scenes/{id}/compare/summary.json")));
        for row in bench["methods"].as_array().unwrap() {
            let mut compared = (summary["methods"].as_array().unwrap().iter())
                .find(|r| r["name"] == row["name"])
                .unwrap_or_else(|| panic!("{id}: no compare row for {}", row["name"]))
                .clone();
            assert!(
                !compared["files"].as_array().unwrap().is_empty(),
                "{compared}"
            );
            compared["files"] = serde_json::json!([]);
            assert_eq!(row["error"], compared, "{id}");
        }
        // the clock is checked once, with the first scene, and said so in the later ones
        let reason = bench["clock"]["reason"].as_str().unwrap();
        assert_eq!(
            reason.starts_with("checked once for this report, with scene ball: "),
            id == "box",
            "{id}: {reason}"
        );
    }
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let (code, _, stderr) = run(&[
        "report",
        "--models",
        empty.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("no mesh files (.obj, .gltf, .glb or .ply)"),
        "{stderr}"
    );
}
