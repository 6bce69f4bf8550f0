//! The HTTP API of `explore` (docs/explore.md "API", version 1) and the page's assets. Every
//! route passes [`guard`] first; the work of a request (a compile, a render, an isa run) runs
//! on blocking threads, never on the server's event loop.
use std::convert::Infallible;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use axum::body::{Body, Bytes};
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use super::edits::Refused;
use super::render::{RenderReply, RenderRequest, SceneInput};
use super::{cost, Server, SIZES, UPLOAD_BYTES};
use crate::auto::ErrorBudget;
use crate::compare::{MethodReport, Metric};
use crate::method::{Method, Precision};
use crate::scene::SceneSource;

/// The page and its assets, embedded in the binary: (path, content type, text).
pub const PAGE: [(&str, &str, &str); 3] = [
    (
        "/",
        "text/html; charset=utf-8",
        include_str!("../../assets/explore/index.html"),
    ),
    (
        "/assets/explore.js",
        "text/javascript; charset=utf-8",
        include_str!("../../assets/explore/explore.js"),
    ),
    (
        "/assets/explore.css",
        "text/css; charset=utf-8",
        include_str!("../../assets/explore/explore.css"),
    ),
];

/// The API's version (docs/explore.md).
pub const VERSION: u32 = 1;

type Shared = Arc<Server>;

/// An answer that is not 200: its status and `{"error": message}`.
#[derive(Debug)]
pub struct Failure(StatusCode, Value);

impl Failure {
    fn new(status: StatusCode, message: impl Into<String>) -> Failure {
        Failure(status, json!({ "error": message.into() }))
    }
    fn bad(message: impl Into<String>) -> Failure {
        Failure::new(StatusCode::BAD_REQUEST, message)
    }
    fn superseded() -> Failure {
        Failure::new(
            StatusCode::CONFLICT,
            "superseded by a newer request of the same tab",
        )
    }
}

impl IntoResponse for Failure {
    fn into_response(self) -> Response {
        (self.0, Json(self.1)).into_response()
    }
}

impl From<crate::error::Error> for Failure {
    fn from(e: crate::error::Error) -> Failure {
        use crate::error::Error as E;
        let status = match &e {
            E::Usage(_) | E::Input { .. } => StatusCode::BAD_REQUEST,
            _ => StatusCode::INTERNAL_SERVER_ERROR,
        };
        Failure::new(status, e.to_string())
    }
}

type Answer<T> = std::result::Result<T, Failure>;

/// The routes, behind the guard.
pub fn router(server: Shared) -> Router {
    let mut r = Router::new();
    for (path, _, _) in PAGE {
        r = r.route(path, get(asset));
    }
    r.route("/api/v1/choices", get(choices))
        .route("/api/v1/check", post(check))
        .route("/api/v1/render", post(render))
        .route("/api/v1/cost", post(cost_stream))
        .route("/api/v1/disasm", post(disasm))
        .route(
            "/api/v1/mesh",
            post(mesh).layer(DefaultBodyLimit::max(UPLOAD_BYTES)),
        )
        // every other body: a method's source and a few fields
        .layer(DefaultBodyLimit::max(super::edits::SOURCE_BYTES * 2))
        .layer(middleware::from_fn_with_state(server.clone(), guard))
        .with_state(server)
}

#[derive(Deserialize)]
struct TokenQuery {
    token: Option<String>,
}

/// The token, the Host and the Origin ([`super::guard`]); the page's first load, with
/// `?token=`, gets the cookie.
async fn guard(
    State(s): State<Shared>,
    Query(q): Query<TokenQuery>,
    request: Request,
    next: Next,
) -> Response {
    if let Err((status, why)) = s.guard.check(request.headers(), q.token.as_deref()) {
        return Failure::new(status, why).into_response();
    }
    let set_cookie = q.token.is_some();
    let mut response = next.run(request).await;
    if set_cookie {
        if let Ok(v) = s.guard.set_cookie().parse() {
            response.headers_mut().insert(header::SET_COOKIE, v);
        }
    }
    response
}

async fn asset(State(s): State<Shared>, request: Request) -> Response {
    let path = request.uri().path();
    let Some((_, kind, text)) = PAGE.iter().find(|(p, _, _)| *p == path) else {
        return Failure::new(StatusCode::NOT_FOUND, "no such page").into_response();
    };
    let text = match &s.assets {
        None => (*text).to_string(),
        Some(dir) => {
            let file = dir.join(
                path.rsplit('/')
                    .next()
                    .filter(|f| !f.is_empty())
                    .unwrap_or("index.html"),
            );
            match std::fs::read_to_string(&file) {
                Ok(t) => t,
                Err(e) => {
                    return Failure::new(StatusCode::NOT_FOUND, format!("{}: {e}", file.display()))
                        .into_response()
                }
            }
        }
    };
    (
        [
            (header::CONTENT_TYPE, *kind),
            (header::CACHE_CONTROL, "no-store"),
        ],
        text,
    )
        .into_response()
}

/// A method in a request: a name of the table (or of `--method-file`), or a source to edit.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum MethodRef {
    Name { name: String },
    Source { source: String },
}

/// A scene in a request.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum SceneRef {
    Scene { scene: String },
    Model { model: String },
    Upload { upload: String },
}

/// Runs `f` on a blocking thread.
async fn blocking<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> Answer<T> {
    tokio::task::spawn_blocking(f).await.map_err(|e| {
        Failure::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("a task died: {e}"),
        )
    })
}

/// The method of `m` (an edit registered on first sight).
async fn method_of(s: &Shared, m: MethodRef) -> Answer<&'static Method> {
    match m {
        MethodRef::Name { name } => crate::method::find(&name).map_err(Failure::from),
        MethodRef::Source { source } => {
            let s = s.clone();
            match blocking(move || s.edits.method(&source)).await? {
                Ok(m) => Ok(m),
                Err(r) => Err(refusal(r)),
            }
        }
    }
}

fn refusal(r: Refused) -> Failure {
    match r {
        Refused::Source(errors) => Failure(
            StatusCode::UNPROCESSABLE_ENTITY,
            json!({
                "error": errors.iter().map(|e| match e.line {
                    Some(l) => format!("line {l}: {}", e.message),
                    None => e.message.clone(),
                }).collect::<Vec<_>>().join("\n"),
                "errors": errors,
            }),
        ),
        Refused::TooLarge(why) => Failure::new(StatusCode::PAYLOAD_TOO_LARGE, why),
        Refused::Internal(e) => Failure::from(e),
    }
}

/// A method's claims as shadelab judges them now (`shadelab list --json`: by proof where the
/// method is provable, [`crate::prove::bounds`]).
fn claims_of(m: &Method) -> Value {
    let judged = crate::prove::bounds::json(m);
    let claims: Vec<Value> = judged["claims"]
        .as_array()
        .map(|cs| {
            cs.iter()
                .map(|c| {
                    json!({"claim": c["claim"], "verdict": c["verdict"], "basis": c["basis"],
                           "measured": c["measured"], "proven_upper": c["proven_upper"]})
                })
                .collect()
        })
        .unwrap_or_default();
    Value::Array(claims)
}

fn method_json(m: &Method, stress: &std::collections::HashMap<String, f64>) -> Value {
    let user = crate::method::user::of(m);
    json!({
        "name": m.name,
        "description": m.description,
        "family": format!("{:?}", m.family),
        "inputs": m.inputs.iter().map(|i| crate::method::user::input_name(*i)).collect::<Vec<_>>(),
        "has_normal": m.has_normal,
        "user": user.is_some(),
        "source": crate::gpu::shaders::method_file_text(m),
        "claims": claims_of(m),
        "stress_valid_angle_deg": stress.get(m.name),
    })
}

async fn choices(State(s): State<Shared>) -> Json<Value> {
    let methods: Vec<Value> = crate::method::all()
        .into_iter()
        // the server's own edits are the page's, not offered as methods
        .filter(|m| !s.edits.holds(m))
        .map(|m| method_json(m, &s.stress_angles))
        .collect();
    let scenes: Vec<Value> = s
        .scenes
        .iter()
        .map(|e| {
            let name = e
                .path
                .file_stem()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            json!({"id": e.id, "kind": if e.model { "model" } else { "scene" }, "name": name})
        })
        .collect();
    let families: Vec<Value> = s
        .families
        .iter()
        .map(|(id, setup)| {
            json!({
                "id": id,
                "vendor": id.split(':').next().unwrap_or(""),
                "set_up": setup.is_ok(),
                "why": setup.as_ref().err(),
            })
        })
        .collect();
    let default_scene = s
        .scenes
        .iter()
        .find(|e| e.id == "torus")
        .or(s.scenes.first())
        .map(|e| e.id.clone());
    Json(json!({
        "version": VERSION,
        "methods": methods,
        "scenes": scenes,
        "families": families,
        "limits": {
            "source_bytes": super::edits::SOURCE_BYTES,
            "upload_bytes": UPLOAD_BYTES,
            "size_min": SIZES.start(),
            "size_max": SIZES.end(),
        },
        "defaults": {
            "method": crate::method::PHONG_EXACT,
            "scene": {"scene": default_scene},
            "size": 256,
            "precision": "f32",
            "budget": "1/255",
        },
    }))
}

#[derive(Deserialize)]
struct CheckBody {
    method: MethodRef,
}

async fn check(State(s): State<Shared>, Json(b): Json<CheckBody>) -> Response {
    match method_of(&s, b.method).await {
        Ok(m) => Json(json!({"ok": true, "name": m.name})).into_response(),
        Err(Failure(StatusCode::UNPROCESSABLE_ENTITY, v)) => {
            Json(json!({"ok": false, "errors": v["errors"]})).into_response()
        }
        Err(f) => f.into_response(),
    }
}

fn precision_of(p: Option<&str>) -> Answer<Precision> {
    match p.unwrap_or("f32") {
        "f32" => Ok(Precision::F32),
        "f16" => Ok(Precision::F16),
        other => Err(Failure::bad(format!("precision {other:?}: f32 or f16"))),
    }
}

#[derive(Deserialize)]
struct RenderBody {
    method: MethodRef,
    scene: SceneRef,
    size: Option<u32>,
    precision: Option<String>,
    budget: Option<String>,
    #[serde(default)]
    tab: String,
    #[serde(default)]
    seq: u64,
}

/// The scene of `r` as a render's input, and the `compare` option that names it.
fn scene_input(s: &Server, r: &SceneRef) -> Answer<(SceneInput, String)> {
    let file = |id: &str, model: bool| {
        s.scenes
            .iter()
            .find(|e| e.id == id && e.model == model)
            .ok_or_else(|| {
                Failure::bad(format!(
                    "no such {}: {id:?}",
                    if model { "model" } else { "scene" }
                ))
            })
    };
    match r {
        SceneRef::Scene { scene } => {
            let e = file(scene, false)?;
            Ok((
                SceneInput::File(SceneSource {
                    scene: Some(e.path.clone()),
                    ..SceneSource::default()
                }),
                format!("--scene {}", e.path.display()),
            ))
        }
        SceneRef::Model { model } => {
            let e = file(model, true)?;
            Ok((
                SceneInput::File(SceneSource {
                    mesh: Some(e.path.clone()),
                    ..SceneSource::default()
                }),
                format!("--mesh {}", e.path.display()),
            ))
        }
        SceneRef::Upload { upload } => {
            let u = s.upload(upload).ok_or_else(|| {
                Failure::bad(format!(
                    "no upload {upload:?} (the server keeps the last {}): send the file again",
                    super::MAX_UPLOADS
                ))
            })?;
            Ok((
                SceneInput::Upload {
                    name: u.name.clone(),
                    bytes: (*u.bytes).clone(),
                },
                format!("--mesh {}", u.name),
            ))
        }
    }
}

/// A finite figure, or null.
fn figure(v: Option<f64>) -> Value {
    v.filter(|x| x.is_finite()).map_or(Value::Null, Value::from)
}

/// The budget's verdict on compare's max |dI| (luminance): within when measured, finite and at
/// most the limit.
fn verdict(r: &MethodReport, budget: ErrorBudget) -> Value {
    let limit = f64::from(budget);
    let max = Metric::MaxAbsError.of(r).filter(|v| v.is_finite());
    let (within, why) = match max {
        _ if r.covered_pixels == 0 => (
            false,
            "no pixel was measured: the budget has no value".to_string(),
        ),
        _ if r.non_finite_pixels > 0 => (
            false,
            crate::compare::non_finite_at(
                r.non_finite_pixels,
                r.covered_pixels + r.non_finite_pixels,
            ),
        ),
        Some(m) if m <= limit => (true, format!("max |dI| {m:.3e} <= {limit:.3e}")),
        Some(m) => (false, format!("max |dI| {m:.3e} > {limit:.3e}")),
        None => (false, "max |dI| has no value".to_string()),
    };
    json!({"limit": limit, "within": within, "why": why})
}

/// The option that makes a method known to a command, and its name: a `--method-file` method
/// by the path it was given; an edit by its id's file name (`edit_<sha>.glsl`, which the page
/// renames to the name it saves the file under), since its copy lives in the server's
/// temporary folder.
fn method_options(s: &Server, m: &Method) -> String {
    match crate::method::user::of(m) {
        Some(u) => {
            let file = if s.edits.holds(m) {
                format!("{}.glsl", m.name)
            } else {
                u.path.clone()
            };
            format!("--method-file {file} --methods {}", m.name)
        }
        None => format!("--methods {}", m.name),
    }
}

fn precision_option(p: Precision) -> &'static str {
    match p {
        Precision::F16 => " --precision f16",
        _ => "",
    }
}

async fn render(State(s): State<Shared>, Json(b): Json<RenderBody>) -> Answer<Json<Value>> {
    let start = Instant::now();
    if !s.newest(&b.tab, "render", b.seq) {
        return Err(Failure::superseded());
    }
    let size = b.size.unwrap_or(256);
    if !SIZES.contains(&size) {
        return Err(Failure::bad(format!(
            "size {size}: {} to {} pixels a side",
            SIZES.start(),
            SIZES.end()
        )));
    }
    let precision = precision_of(b.precision.as_deref())?;
    let budget =
        ErrorBudget::parse(b.budget.as_deref().unwrap_or("1/255")).map_err(Failure::bad)?;
    let method = method_of(&s, b.method).await?;
    let (scene, scene_option) = scene_input(&s, &b.scene)?;
    if !s.newest(&b.tab, "render", b.seq) {
        return Err(Failure::superseded());
    }
    let request = RenderRequest {
        scene,
        size,
        method: method.name.to_string(),
        precision,
    };
    let s2 = s.clone();
    let reply: std::result::Result<RenderReply, crate::child::Failure> = blocking(move || {
        let spawn = crate::child::Spawn {
            exe: s2.exe.clone(),
            driver_env: Vec::new(),
            method_files: crate::method::user::paths_of(&[method]),
            show_stderr: log::log_enabled!(log::Level::Debug),
        };
        s2.renders.call(&spawn, &request, s2.temp.path(), "render")
    })
    .await?;
    let r = reply.map_err(|f| {
        if f.stopped {
            return Failure::new(
                StatusCode::GATEWAY_TIMEOUT,
                format!(
                    "the render of {} was stopped past its deadline or memory cap ({}); the \
                     server goes on",
                    method.name, f.why
                ),
            );
        }
        let status = if f.refused_input {
            StatusCode::BAD_REQUEST
        } else {
            StatusCode::INTERNAL_SERVER_ERROR
        };
        Failure::new(status, f.why)
    })?;
    let m = &r.report;
    use base64::Engine;
    let b64 = |b: &crate::child::Bytes| base64::engine::general_purpose::STANDARD.encode(&b.0);
    Ok(Json(json!({
        "method": method.name,
        "scene": r.scene,
        "triangles": r.triangles,
        "size": size,
        "precision": precision.as_str(),
        "statistics": {
            "max_abs_error": figure(Metric::MaxAbsError.of(m)),
            "p99_abs_error": figure(Metric::P99AbsError.of(m)),
            "mean_abs_error": figure(Metric::MeanAbsError.of(m)),
            "flip_mean": figure(Metric::FlipMean.of(m)),
            "non_finite_pixels": m.non_finite_pixels,
            "covered_pixels": m.covered_pixels,
        },
        "budget": verdict(m, budget),
        "render_png": b64(&r.render_png),
        "heatmap_png": b64(&r.heatmap_png),
        "compare": format!(
            "shadelab compare {scene_option} {} --size {size}x{size}{} --out OUT",
            method_options(&s, method),
            precision_option(precision)
        ),
        "worker_ms": r.elapsed_ms,
        "elapsed_ms": start.elapsed().as_secs_f64() * 1e3,
    })))
}

#[derive(Deserialize)]
struct CostBody {
    method: MethodRef,
    precision: Option<String>,
    #[serde(default)]
    tab: String,
    #[serde(default)]
    seq: u64,
}

fn line(v: &impl Serialize) -> std::result::Result<String, Infallible> {
    Ok(
        serde_json::to_string(v).unwrap_or_else(|e| json!({"error": e.to_string()}).to_string())
            + "\n",
    )
}

async fn cost_stream(State(s): State<Shared>, Json(b): Json<CostBody>) -> Answer<Response> {
    let start = Instant::now();
    if !s.newest(&b.tab, "cost", b.seq) {
        return Err(Failure::superseded());
    }
    let precision = precision_of(b.precision.as_deref())?;
    let method = method_of(&s, b.method).await?;
    let (tx, rx) = tokio::sync::mpsc::channel(64);
    let (tab, seq) = (b.tab, b.seq);
    let s2 = s.clone();
    tokio::task::spawn_blocking(move || {
        let queue = Mutex::new(
            s2.families
                .iter()
                .map(|(id, _)| id.clone())
                .collect::<Vec<_>>(),
        );
        let families = s2.families.len();
        let stopped = std::sync::atomic::AtomicBool::new(false);
        std::thread::scope(|scope| {
            for _ in 0..crate::workers::parallel() {
                scope.spawn(|| loop {
                    if tx.is_closed() || !s2.newest(&tab, "cost", seq) {
                        stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                        break;
                    }
                    let next = queue
                        .lock()
                        .ok()
                        .and_then(|mut q| (!q.is_empty()).then(|| q.remove(0)));
                    let Some(family) = next else { break };
                    let (l, report) = cost::family(&s2.exe, method, &family, precision);
                    if let Some(r) = report {
                        s2.keep_report((family, method.name.to_string(), precision), r);
                    }
                    if tx.blocking_send(line(&l)).is_err() {
                        break;
                    }
                });
            }
        });
        let superseded = stopped.load(std::sync::atomic::Ordering::Relaxed);
        let _ = tx.blocking_send(line(&json!({
            "done": !superseded,
            "superseded": superseded,
            "families": families,
            "elapsed_ms": start.elapsed().as_secs_f64() * 1e3,
            "isa": format!(
                "shadelab isa {}{} --out OUT",
                method_options(&s, method),
                precision_option(precision)
            ),
        })));
    });
    let body = Body::from_stream(tokio_stream::wrappers::ReceiverStream::new(rx));
    Ok((
        [
            (header::CONTENT_TYPE, "application/x-ndjson"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        body,
    )
        .into_response())
}

#[derive(Deserialize)]
struct DisasmBody {
    method: MethodRef,
    family: String,
    precision: Option<String>,
}

async fn disasm(State(s): State<Shared>, Json(b): Json<DisasmBody>) -> Answer<Json<Value>> {
    let precision = precision_of(b.precision.as_deref())?;
    let method = method_of(&s, b.method).await?;
    if !s.families.iter().any(|(id, _)| *id == b.family) {
        return Err(Failure::bad(format!("no such family: {:?}", b.family)));
    }
    let key = (b.family.clone(), method.name.to_string(), precision);
    let report = match s.report(&key) {
        Some(r) => r,
        None => {
            let s2 = s.clone();
            let family = b.family.clone();
            let (l, r) =
                blocking(move || cost::family(&s2.exe, method, &family, precision)).await?;
            let r =
                r.ok_or_else(|| Failure::new(StatusCode::INTERNAL_SERVER_ERROR, l.status.clone()))?;
            s.keep_report(key, r.clone());
            Arc::new(r)
        }
    };
    let text = |name: &str| cost::disassembly(&report, name);
    let m = text(method.name);
    let p = text(crate::method::PHONG_EXACT);
    if m.is_none() {
        let why = report
            .families
            .first()
            .map_or_else(|| "no figures".to_string(), |f| f.status.clone());
        return Err(Failure::new(
            StatusCode::NOT_FOUND,
            format!("{}: no disassembly of {} ({why})", b.family, method.name),
        ));
    }
    Ok(Json(json!({
        "family": b.family,
        "method": {"name": method.name, "text": m},
        "reference": {"name": crate::method::PHONG_EXACT, "text": p},
    })))
}

async fn mesh(State(s): State<Shared>, headers: HeaderMap, body: Bytes) -> Answer<Json<Value>> {
    let name = headers
        .get("x-shadelab-filename")
        .and_then(|v| v.to_str().ok())
        .map(|n| n.rsplit(['/', '\\']).next().unwrap_or(n).to_string())
        .filter(|n| !n.is_empty())
        .ok_or_else(|| Failure::bad("give the file's name in the header X-Shadelab-Filename"))?;
    let bytes = body.to_vec();
    let (name2, bytes2) = (name.clone(), bytes.clone());
    let scene = blocking(move || super::render::upload_scene(&name2, &bytes2)).await??;
    let warnings = scene
        .mesh_report
        .as_ref()
        .map(|r| r.warnings.clone())
        .unwrap_or_default();
    let triangles = scene.mesh.triangle_count();
    drop(scene);
    let id = s.keep_upload(name.clone(), bytes);
    Ok(Json(
        json!({"upload": id, "name": name, "triangles": triangles, "warnings": warnings}),
    ))
}
