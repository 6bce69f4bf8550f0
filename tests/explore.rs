//! `shadelab explore` through its API, with a real HTTP client (ureq) against the binary
//! started on a free port of 127.0.0.1: its figures are compare's and isa's, a broken GLSL gives
//! its line, an upload gives the figures of the same file by path, the guard refuses what it
//! must, a newer request supersedes an older one, a hung render costs its cell only, and kill -9
//! leaves no worker. Every loop is bounded in count and time.
use std::io::{BufRead, BufReader, Read};
use std::process::{Child, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use serde_json::{json, Value};

use crate::hostile::{children_seen, kill_and_check_children_gone};
use crate::isa::families_ready;
use crate::support::{bin, read_json, root};

/// A running `shadelab explore`, killed when dropped.
pub(crate) struct Server {
    pub(crate) child: Child,
    pub(crate) base: String,
    pub(crate) token: String,
    agent: ureq::Agent,
}

impl Server {
    /// Starts the server (`--models tests/data/gltf` and `extra`) and reads its URL (60 s at
    /// most).
    pub(crate) fn start(extra: &[&str]) -> Server {
        let mut child = bin()
            .args(["explore", "--models", "tests/data/gltf"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start shadelab explore");
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut line = String::new();
            let _ = BufReader::new(stdout).read_line(&mut line);
            let _ = tx.send(line);
        });
        let url = rx
            .recv_timeout(Duration::from_secs(60))
            .expect("explore printed no URL in 60 s");
        let url = url.trim();
        let (base, token) = url
            .split_once("/?token=")
            .unwrap_or_else(|| panic!("not a URL with a token: {url:?}"));
        assert!(
            base.starts_with("http://127.0.0.1:"),
            "{base}: not loopback"
        );
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(300)))
            .build()
            .into();
        Server {
            child,
            base: base.to_string(),
            token: token.to_string(),
            agent,
        }
    }

    /// POSTs `body` (JSON) with the token: status and the reply (JSON, or the lines of a
    /// stream as an array).
    pub(crate) fn post(&self, path: &str, body: &Value) -> (u16, Value) {
        let mut r = self
            .agent
            .post(format!("{}{path}", self.base))
            .header("X-Shadelab-Token", &self.token)
            .send_json(body)
            .unwrap_or_else(|e| panic!("POST {path}: {e}"));
        let status = r.status().as_u16();
        let text = r.body_mut().read_to_string().unwrap();
        (status, parse(&text))
    }

    pub(crate) fn get(&self, path: &str, headers: &[(&str, &str)]) -> (u16, String) {
        let mut req = self.agent.get(format!("{}{path}", self.base));
        for (k, v) in headers {
            req = req.header(*k, *v);
        }
        let mut r = req.call().unwrap_or_else(|e| panic!("GET {path}: {e}"));
        (r.status().as_u16(), r.body_mut().read_to_string().unwrap())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A reply's JSON, or a stream's lines as an array.
fn parse(text: &str) -> Value {
    serde_json::from_str(text).unwrap_or_else(|_| {
        Value::Array(
            text.lines()
                .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
                .collect(),
        )
    })
}

const FAMILY: &str = "amd:navi21";

/// A method file's text: newton_raphson's step written out, with `extra` at its end.
fn source(body: &str) -> String {
    format!(
        "// shadelab-inputs: interpolated_normal\nreal3 methodNormal() {{\n    real3 n = R3(vNormal);\n{body}\n}}\n"
    )
}

/// The render of `/api/v1/render` and compare's summary.json of the same method, scene, size
/// and precision hold the same figures; an upload of a glTF gives the figures of the same file
/// given by path.
#[test]
fn a_render_is_compares_figures_and_an_upload_is_the_file_by_path() {
    let s = Server::start(&[]);
    let dir = tempfile::tempdir().unwrap();
    for (method, precision) in [("newton_raphson", "f32"), ("lyon_taylor", "f16")] {
        let (status, r) = s.post(
            "/api/v1/render",
            &json!({"method": {"name": method}, "scene": {"scene": "cube"}, "size": 64,
                    "precision": precision, "budget": "1/255"}),
        );
        assert_eq!(status, 200, "{r}");
        let out = dir.path().join(format!("{method}-{precision}"));
        let (code, _, err) = crate::support::run(&[
            "compare",
            "--scene",
            "scenes/cube.toml",
            "--methods",
            method,
            "--size",
            "64x64",
            "--precision",
            precision,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let summary = read_json(out.join("summary.json"));
        let m = &summary["methods"][0];
        for key in [
            "max_abs_error",
            "p99_abs_error",
            "mean_abs_error",
            "flip_mean",
            "non_finite_pixels",
            "covered_pixels",
        ] {
            assert_eq!(r["statistics"][key], m[key], "{method} {precision}: {key}");
            assert!(
                r["statistics"][key].is_number(),
                "{method}: {key} is {}",
                r["statistics"][key]
            );
        }
        let within = m["max_abs_error"].as_f64().unwrap() <= 1.0 / 255.0;
        assert_eq!(r["budget"]["within"], within, "{r}");
        assert!(r["compare"]
            .as_str()
            .unwrap()
            .contains(&format!("--methods {method}")));
        for image in ["render_png", "heatmap_png"] {
            let b64 = r[image].as_str().unwrap();
            use base64::Engine;
            let png = base64::engine::general_purpose::STANDARD
                .decode(b64)
                .unwrap();
            assert_eq!(&png[1..4], b"PNG", "{image}");
        }
    }
    // the same glTF by path (a model of --models) and uploaded
    let glb = root().join("tests/data/gltf/nodes.glb");
    let mut r = s
        .agent
        .post(format!("{}/api/v1/mesh", s.base))
        .header("X-Shadelab-Token", &s.token)
        .header("X-Shadelab-Filename", "nodes.glb")
        .send(&std::fs::read(&glb).unwrap()[..])
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let up: Value = parse(&r.body_mut().read_to_string().unwrap());
    assert!(up["triangles"].as_u64().unwrap() > 0, "{up}");
    let ask = |scene: Value| {
        s.post(
            "/api/v1/render",
            &json!({"method": {"name": "newton_raphson"}, "scene": scene, "size": 64}),
        )
    };
    let (a, by_path) = ask(json!({"model": "nodes.glb"}));
    let (b, uploaded) = ask(json!({"upload": up["upload"]}));
    assert_eq!((a, b), (200, 200), "{by_path} {uploaded}");
    assert_eq!(by_path["statistics"], uploaded["statistics"]);
    assert_eq!(by_path["render_png"], uploaded["render_png"]);
    // teeth: another scene does not give those figures
    let (_, other) = ask(json!({"scene": "cube"}));
    assert_ne!(other["statistics"], by_path["statistics"]);
    // a broken upload is the reader's error, 400
    let mut bad = s
        .agent
        .post(format!("{}/api/v1/mesh", s.base))
        .header("X-Shadelab-Token", &s.token)
        .header("X-Shadelab-Filename", "broken.obj")
        .send(&b"v 0 0 0\nf 1 2 3\n"[..])
        .unwrap();
    assert_eq!(
        bad.status().as_u16(),
        400,
        "{}",
        bad.body_mut().read_to_string().unwrap()
    );
}

/// The cost stream's ratio on a family is isa.json's ratio of the same method and precision,
/// for a method of the table and for an edited one; a line per family set up, then the end.
#[test]
fn a_cost_is_isas_ratio_for_a_method_and_an_edit() {
    if !families_ready(
        "explore::a_cost_is_isas_ratio",
        &[FAMILY],
        "SHADELAB_REQUIRE_VENDORS",
    ) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // a method given by `--method-file` is offered by name, as any of the table's
    let theirs = dir.path().join("theirs.glsl");
    std::fs::write(&theirs, source("    return n * inversesqrt(dot(n, n));")).unwrap();
    let s = Server::start(&["--method-file", theirs.to_str().unwrap()]);
    let edit =
        source("    real z = dot(n, n);\n    return n * (R(0.5) * (R(3.0) - z)) * R(1.0001);");
    let file = dir.path().join("mine.glsl");
    std::fs::write(&file, &edit).unwrap();
    for (method, asked, precision) in [
        ("newton_raphson", json!({"name": "newton_raphson"}), "f32"),
        ("newton_raphson", json!({"name": "newton_raphson"}), "f16"),
        ("mine", json!({"source": edit}), "f32"),
        ("theirs", json!({"name": "theirs"}), "f32"),
    ] {
        let (status, lines) = s.post(
            "/api/v1/cost",
            &json!({"method": asked, "precision": precision}),
        );
        assert_eq!(status, 200, "{lines}");
        let lines = lines.as_array().unwrap();
        let last = lines.last().unwrap();
        assert_eq!(last["done"], true, "{last}");
        assert_eq!(lines.len() - 1, last["families"].as_u64().unwrap() as usize);
        let ours = lines.iter().find(|l| l["family"] == FAMILY).unwrap();
        assert_eq!(ours["status"], "compiled", "{ours}");
        let out = dir.path().join(format!("isa-{method}-{precision}"));
        let mut args = vec![
            "isa",
            "--methods",
            method,
            "--families",
            FAMILY,
            "--precision",
            precision,
            "--out",
            out.to_str().unwrap(),
        ];
        let f = file.to_str().unwrap();
        let t = theirs.to_str().unwrap();
        match method {
            "mine" => drop(args.splice(0..0, ["--method-file", f])),
            "theirs" => {
                // the command line the page shows names the file where it is
                let shown = last["isa"].as_str().unwrap();
                assert!(shown.contains(&format!("--method-file {t} ")), "{shown}");
                drop(args.splice(0..0, ["--method-file", t]));
            }
            _ => {}
        }
        let (code, _, err) = crate::support::run(&args);
        assert_eq!(code, 0, "{err}");
        let isa = read_json(out.join("isa.json"));
        let fam = &isa["families"][0];
        let key = fam["ranking"]["key"].as_str().unwrap();
        let row = isa["results"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["method"] == method && r["stage"] == "fragment" && r["kind"] == "draw")
            .unwrap();
        assert_eq!(
            ours["ratio"], row["ratio_to_phong_exact"][key],
            "{method} {precision}"
        );
        assert_eq!(
            ours["value"], row["statistics"][key],
            "{method} {precision}"
        );
        assert!(ours["ratio"].is_number());
    }
    // the disassembly of the last compile, beside phong_exact's
    let (status, d) = s.post(
        "/api/v1/disasm",
        &json!({"method": {"source": edit}, "family": FAMILY, "precision": "f32"}),
    );
    assert_eq!(status, 200, "{d}");
    let (m, p) = (
        d["method"]["text"].as_str().unwrap(),
        d["reference"]["text"].as_str().unwrap(),
    );
    assert!(!m.is_empty() && !p.is_empty());
    assert_ne!(m, p, "the edit's program is phong_exact's");
}

/// A source that does not compile gives its errors at their lines (the undeclared identifier
/// on line 5 of the source; an undeclared input at its declaration line), and the same source
/// mended compiles.
#[test]
fn a_broken_method_gives_its_line() {
    let s = Server::start(&[]);
    let broken = source("    real z = dot(n, n);\n    return n * (R(0.5) * (R(3.0) - zz));");
    let (status, r) = s.post("/api/v1/check", &json!({"method": {"source": broken}}));
    assert_eq!(status, 200, "{r}");
    assert_eq!(r["ok"], false, "{r}");
    let e = &r["errors"][0];
    assert_eq!(e["line"], 5, "{r}");
    assert!(e["message"].as_str().unwrap().contains("zz"), "{r}");
    assert!(
        !e["message"].as_str().unwrap().contains("/tmp"),
        "the server's path leaks: {r}"
    );
    // the render of it is refused with the same errors, 422
    let (status, r2) = s.post(
        "/api/v1/render",
        &json!({"method": {"source": broken}, "scene": {"scene": "cube"}, "size": 64}),
    );
    assert_eq!(status, 422, "{r2}");
    assert_eq!(r2["errors"], r["errors"]);
    let undeclared = source("    return normalize(R3(vBary));");
    let (_, u) = s.post("/api/v1/check", &json!({"method": {"source": undeclared}}));
    assert_eq!(u["errors"][0]["line"], 1, "{u}");
    // teeth: mended, it compiles
    let mended = broken.replace("zz", "z");
    let (_, ok) = s.post("/api/v1/check", &json!({"method": {"source": mended}}));
    assert_eq!(ok["ok"], true, "{ok}");
    assert!(ok["name"].as_str().unwrap().starts_with("edit_"));
}

/// No token: 401 (the page and the API); a foreign Origin or Host: 403; the token in the URL
/// sets the cookie, and the cookie alone is enough afterwards.
#[test]
fn the_guard_wants_the_token_our_host_and_our_origin() {
    let s = Server::start(&[]);
    assert_eq!(s.get("/", &[]).0, 401);
    assert_eq!(s.get("/api/v1/choices", &[]).0, 401);
    assert_eq!(
        s.get("/api/v1/choices", &[("X-Shadelab-Token", "0123")]).0,
        401
    );
    let t = s.token.as_str();
    let (ok, body) = s.get("/api/v1/choices", &[("X-Shadelab-Token", t)]);
    assert_eq!(ok, 200, "{body}");
    let session: Value = serde_json::from_str(&body).unwrap();
    assert_eq!(session["version"], 1);
    assert!(session["methods"].as_array().unwrap().len() >= 37);
    let (code, _) = s.get(
        "/api/v1/choices",
        &[("X-Shadelab-Token", t), ("Origin", "http://evil.example")],
    );
    assert_eq!(code, 403);
    let ours = s.base.clone();
    let (code, _) = s.get(
        "/api/v1/choices",
        &[("X-Shadelab-Token", t), ("Origin", &ours)],
    );
    assert_eq!(code, 200);
    let (code, _) = s.get(
        "/api/v1/choices",
        &[("X-Shadelab-Token", t), ("Host", "evil.example")],
    );
    assert_eq!(code, 403, "a foreign Host (DNS rebinding) answered");
    // the page's first load sets the cookie; the cookie then opens the API
    let r = s
        .agent
        .get(format!("{}/?token={t}", s.base))
        .call()
        .unwrap();
    assert_eq!(r.status().as_u16(), 200);
    let cookie = r
        .headers()
        .get("set-cookie")
        .unwrap()
        .to_str()
        .unwrap()
        .to_string();
    assert!(
        cookie.contains("HttpOnly") && cookie.contains("SameSite=Strict"),
        "{cookie}"
    );
    let pair = cookie.split(';').next().unwrap();
    assert_eq!(s.get("/api/v1/choices", &[("Cookie", pair)]).0, 200);
}

/// A request older than its tab's newest is 409; another tab is not affected.
#[test]
fn a_newer_request_of_a_tab_supersedes_an_older_one() {
    let s = Server::start(&[]);
    let ask = |tab: &str, seq: u64| {
        s.post(
            "/api/v1/render",
            &json!({"method": {"name": "flat"}, "scene": {"scene": "cube"}, "size": 64, "tab": tab, "seq": seq}),
        )
        .0
    };
    assert_eq!(ask("a", 5), 200);
    assert_eq!(ask("a", 3), 409);
    assert_eq!(ask("b", 1), 200, "another tab was superseded");
    assert_eq!(ask("a", 6), 200);
}

/// A method that does not end in any useful time costs its render the deadline, with a message
/// saying so; the server stays up and renders the next one. llvmpipe stops any loop after 65535
/// iterations (gallivm's `LP_MAX_TGSI_LOOP_ITERATIONS`, src/gallium/auxiliary/gallivm/
/// lp_bld_limits.h), so the loop runs its 65535 steps at each of the ~300,000 pixels of a
/// 1024x1024 cube: minutes of lavapipe, past the 5 s deadline.
#[test]
fn a_hung_render_costs_its_cell_and_the_server_goes_on() {
    let s = Server::start(&["--deadline", "5"]);
    let hang = source(
        "    real3 m = n;\n    int k = int(n.x * 0.0) + 2000000000;\n    for (int i = 0; i < k; i++) { m = m * R(0.9999999) + n * R(1e-7); }\n    return normalize(m);",
    );
    let started = std::time::Instant::now();
    let (status, r) = s.post(
        "/api/v1/render",
        &json!({"method": {"source": hang}, "scene": {"scene": "cube"}, "size": 1024}),
    );
    assert!(started.elapsed() < Duration::from_secs(60), "no deadline");
    assert_eq!(status, 504, "{r}");
    assert!(r["error"].as_str().unwrap().contains("deadline"), "{r}");
    let (status, r) = s.post(
        "/api/v1/render",
        &json!({"method": {"name": "phong_exact"}, "scene": {"scene": "cube"}, "size": 64}),
    );
    assert_eq!(status, 200, "{r}");
}

/// kill -9 of the server while its workers render and compile leaves none of them running.
#[test]
fn a_killed_server_leaves_no_worker() {
    let mut s = Server::start(&[]);
    let (base, token) = (s.base.clone(), s.token.clone());
    std::thread::spawn(move || {
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(120)))
            .build()
            .into();
        let body = json!({"method": {"source": source("    return normalize(n) * R(0.999);")}, "precision": "f32"});
        if let Ok(mut r) = agent
            .post(format!("{base}/api/v1/cost"))
            .header("X-Shadelab-Token", &token)
            .send_json(&body)
        {
            let mut sink = String::new();
            let _ = r.body_mut().as_reader().read_to_string(&mut sink);
        }
    });
    let workers = children_seen(&mut s.child, " child ", Duration::from_secs(120));
    kill_and_check_children_gone(&mut s.child, &workers);
}
