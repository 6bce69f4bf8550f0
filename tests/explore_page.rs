//! The explorer's page in headless Chromium, driven as a user drives it (WebDriver through
//! chromedriver): it loads, the user picks a method and types an edit of it into the editor,
//! and the page's render statistics and every family's cost bar, once shown, are the API's for
//! the same source. A broken copy of the page (served with `--assets`) fails the same check.
//! The check's screenshot is docs/explore.png.
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{json, Value};

use crate::explore::Server;
use crate::support::root;

/// chromium and chromedriver, or `None` with a `SKIPPED` line (a failure under
/// `SHADELAB_REQUIRE_BROWSER=1`, which CI sets).
fn browser(test: &str) -> Option<(PathBuf, PathBuf)> {
    let find = |names: &[&str]| {
        names.iter().find_map(|name| {
            std::env::var_os("PATH").and_then(|p| {
                std::env::split_paths(&p)
                    .map(|d| d.join(name))
                    .find(|f| f.is_file())
            })
        })
    };
    let chromium = find(&["chromium", "chromium-browser", "google-chrome"]);
    let driver = find(&["chromedriver"]);
    match (chromium, driver) {
        (Some(c), Some(d)) => Some((c, d)),
        _ => {
            let msg = format!(
                "{test}: no chromium and chromedriver on PATH (scripts/install-deps.sh test installs them)"
            );
            if std::env::var("SHADELAB_REQUIRE_BROWSER").as_deref() == Ok("1") {
                panic!("SHADELAB_REQUIRE_BROWSER=1 but {msg}");
            }
            use std::io::Write as _;
            let _ = writeln!(std::io::stderr(), "SKIPPED: {msg}");
            None
        }
    }
}

/// chromedriver on a free port of 127.0.0.1, killed when dropped.
struct Driver {
    child: Child,
    url: String,
}

impl Driver {
    fn start(driver: &Path) -> Driver {
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let child = Command::new(driver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromedriver");
        let url = format!("http://127.0.0.1:{port}");
        let start = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "chromedriver did not listen in 30 s"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        Driver { child, url }
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The edit the user types: newton_raphson's step with one more factor.
const EDIT: &str = "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {\nreal z = dot(R3(vNormal), R3(vNormal));\nreturn R3(vNormal) * (R(0.5) * (R(3.0) - z)) * R(1.001);\n}\n";

/// Waits (at most `within`) until `script` (a JavaScript expression) is true on the page.
async fn until(c: &Client, script: &str, within: Duration) -> Result<(), String> {
    let start = Instant::now();
    loop {
        let v = c
            .execute(&format!("return !!({script});"), vec![])
            .await
            .map_err(|e| e.to_string())?;
        if v == Value::Bool(true) {
            return Ok(());
        }
        if start.elapsed() > within {
            let state = c
                .execute("return document.body.dataset.state + ' ' + document.body.innerText.slice(0, 600);", vec![])
                .await
                .unwrap_or_default();
            return Err(format!("not true in {within:?}: {script} (page: {state})"));
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// What the page shows once done: the |dI| statistics and each family's float32 ratio.
async fn shown(c: &Client) -> Result<Value, String> {
    c.execute(
        r#"const stats = {};
           for (const tr of document.querySelectorAll('#stats tr[data-stat]')) {
             const a = tr.querySelector('td.a');
             stats[tr.dataset.stat] = a ? a.dataset.value : null;
           }
           const costs = {};
           for (const row of document.querySelectorAll('#costs .cost-row')) {
             costs[row.dataset.family] = row.dataset.ratioF32;
           }
           return {stats, costs, render: document.getElementById('render').naturalWidth};"#,
        vec![],
    )
    .await
    .map_err(|e| e.to_string())
}

/// Loads the page of `s`, picks newton_raphson, types [`EDIT`] in its place, waits for the
/// results and compares them with the API's for the same source; the screenshot to `shot`.
async fn check(
    s: &Server,
    chromium: &Path,
    driver: &Driver,
    shot: Option<&Path>,
) -> Result<(), String> {
    let mut caps = serde_json::Map::new();
    caps.insert(
        "goog:chromeOptions".into(),
        json!({"binary": chromium, "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
               "--window-size=1400,1100", "--hide-scrollbars"]}),
    );
    let connector = hyper_util::client::legacy::connect::HttpConnector::new();
    let c = ClientBuilder::new(connector)
        .capabilities(caps)
        .connect(&driver.url)
        .await
        .map_err(|e| format!("chromedriver: {e}"))?;
    let result = async {
        c.goto(&format!("{}/?token={}", s.base, s.token)).await.map_err(|e| e.to_string())?;
        until(&c, "document.getElementById('method') && document.getElementById('method').options.length >= 37", Duration::from_secs(60)).await?;
        c.execute("const m = document.getElementById('method'); m.value = 'newton_raphson'; m.dispatchEvent(new Event('change', {bubbles: true}));", vec![])
            .await
            .map_err(|e| e.to_string())?;
        let editor = c.find(Locator::Id("source")).await.map_err(|e| e.to_string())?;
        editor.clear().await.map_err(|e| e.to_string())?;
        editor.send_keys(EDIT).await.map_err(|e| e.to_string())?;
        until(
            &c,
            "document.body.dataset.state === 'done' && document.getElementById('costs').dataset.done === 'true'",
            Duration::from_secs(180),
        )
        .await?;
        let typed: Value = c
            .execute("return document.getElementById('source').value;", vec![])
            .await
            .map_err(|e| e.to_string())?;
        let page = shown(&c).await?;
        if let Some(p) = shot {
            let png = c.screenshot().await.map_err(|e| e.to_string())?;
            std::fs::write(p, png).map_err(|e| e.to_string())?;
        }
        Ok::<_, String>((typed, page))
    }
    .await;
    let _ = c.close().await;
    let (typed, page) = result?;
    // the API, asked for the same source
    let source = typed.as_str().ok_or("no source")?;
    let (status, r) = s.post(
        "/api/v1/render",
        &json!({"method": {"source": source}, "scene": {"scene": "torus"}, "size": 256, "precision": "f32"}),
    );
    if status != 200 {
        return Err(format!("the API's render: {status} {r}"));
    }
    let (_, lines) = s.post(
        "/api/v1/cost",
        &json!({"method": {"source": source}, "precision": "f32"}),
    );
    if page["render"].as_u64() != Some(256) {
        return Err(format!("no 256-pixel render on the page: {page}"));
    }
    for key in [
        "max_abs_error",
        "p99_abs_error",
        "mean_abs_error",
        "flip_mean",
    ] {
        let want = r["statistics"][key]
            .as_f64()
            .ok_or(format!("API {key}: {r}"))?;
        let got: f64 = page["stats"][key]
            .as_str()
            .and_then(|v| v.parse().ok())
            .ok_or(format!("the page shows no {key}: {page}"))?;
        if got != want {
            return Err(format!("{key}: the page shows {got}, the API {want}"));
        }
    }
    let mut compared = 0;
    for l in lines.as_array().ok_or("no cost lines")? {
        let Some(family) = l["family"].as_str() else {
            continue;
        };
        let shown = page["costs"][family].as_str().unwrap_or("MISSING");
        let want = l["ratio"]
            .as_f64()
            .map(|r| r.to_string())
            .unwrap_or_default();
        let same = match (shown.parse::<f64>(), l["ratio"].as_f64()) {
            (Ok(a), Some(b)) => a == b,
            _ => shown == want,
        };
        if !same {
            return Err(format!(
                "{family}: the page's float32 ratio {shown:?}, the API's {want:?}"
            ));
        }
        compared += 1;
    }
    if compared == 0 {
        return Err("no family to compare".into());
    }
    Ok(())
}

fn runtime() -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap()
}

#[test]
fn the_page_shows_the_apis_figures_of_what_the_user_typed_and_a_broken_page_fails() {
    let test = "explore_page::the_page_shows_the_apis_figures";
    let Some((chromium, driver)) = browser(test) else {
        return;
    };
    let d = Driver::start(&driver);
    let rt = runtime();
    let s = Server::start(&[]);
    let shot = root().join("docs/explore.png");
    rt.block_on(check(&s, &chromium, &d, Some(&shot)))
        .unwrap_or_else(|e| panic!("{e}"));
    let png = std::fs::read(&shot).unwrap();
    assert!(
        png.len() > 20_000,
        "a blank screenshot: {} bytes",
        png.len()
    );
    drop(s);

    // teeth: the same page, but it draws each family's figure instead of its ratio
    let broken = tempfile::tempdir().unwrap();
    for f in ["index.html", "explore.js", "explore.css"] {
        std::fs::copy(root().join("assets/explore").join(f), broken.path().join(f)).unwrap();
    }
    let js = broken.path().join("explore.js");
    let text = std::fs::read_to_string(&js).unwrap();
    let wrong = "const ratio = typeof line.value === 'number' ? line.value : null;";
    let bug = text.replacen(
        "const ratio = typeof line.ratio === 'number' && Number.isFinite(line.ratio) ? line.ratio : null;",
        wrong,
        1,
    );
    assert_ne!(bug, text, "the line to break is not in explore.js any more");
    std::fs::write(&js, bug).unwrap();
    let s = Server::start(&["--assets", broken.path().to_str().unwrap()]);
    let e = rt
        .block_on(check(&s, &chromium, &d, None))
        .expect_err("a page that shows each family's figure as its ratio passed");
    assert!(e.contains("float32 ratio"), "{e}");
}
