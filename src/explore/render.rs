//! A render of `explore`: `shadelab compare` of one method on one scene, size and precision
//! (the same code, [`crate::compare::compare`]), done in a worker process ([`crate::workers`]:
//! a GLSL infinite loop or a driver hang costs the request its deadline, never the server). The
//! worker keeps its Vulkan context from request to request; the reply carries compare's
//! statistics of the method and its two images (the render and the |dI| heatmap with its
//! colorbar), as compare writes them.
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::child::Bytes;
use crate::compare::{self, CompareOptions, MethodReport};
use crate::error::{Error, Result};
use crate::gpu::vk::{Context, ContextDesc};
use crate::gpu::Renderer;
use crate::method::Precision;
use crate::scene::{Scene, SceneSource};

/// Where a render's scene comes from.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SceneInput {
    /// A scene file or a mesh file on the disk (a file of `--scenes` or `--models`).
    File(SceneSource),
    /// A mesh sent to the server: its name (for its format and messages) and bytes, read in
    /// memory; a glTF's other files are refused ([`NO_OTHER_FILES`]).
    Upload { name: String, bytes: Bytes },
}

/// Why an uploaded glTF cannot name a buffer file.
pub const NO_OTHER_FILES: &str = "an uploaded mesh is one file: its glTF buffers must be \
embedded (a .glb, or data: URIs)";

impl SceneInput {
    /// The scene at `size` x `size` pixels.
    pub fn load(&self, size: u32) -> Result<Scene> {
        match self {
            SceneInput::File(s) => SceneSource {
                size: Some((size, size)),
                ..s.clone()
            }
            .load(),
            SceneInput::Upload { name, bytes } => {
                let mut scene = upload_scene(name, &bytes.0)?;
                scene.width = size;
                scene.height = size;
                Ok(scene)
            }
        }
    }
}

/// The scene of an uploaded mesh file (named `name`), read from `bytes` alone.
pub fn upload_scene(name: &str, bytes: &[u8]) -> Result<Scene> {
    let path = Path::new(name);
    let refuse = |_: &Path| -> std::io::Result<Vec<u8>> {
        Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            NO_OTHER_FILES,
        ))
    };
    let (mesh, report) = crate::geometry::parse_mesh(path, bytes, &refuse)?;
    let stem = path.file_stem().map_or_else(
        || "upload".to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    Ok(crate::scene::scene_for_loaded(stem, mesh, report))
}

/// What a render worker is asked: child job `explore_render`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RenderRequest {
    pub scene: SceneInput,
    /// Pixels a side.
    pub size: u32,
    pub method: String,
    pub precision: Precision,
}

impl crate::child::Job for RenderRequest {
    const NAME: &'static str = "explore_render";
    type Reply = RenderReply;
}

/// A render's figures and images.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RenderReply {
    /// compare's statistics of the method (summary.json's `methods[]` entry).
    pub report: MethodReport,
    pub scene: String,
    pub triangles: usize,
    /// render.png, as compare writes it.
    pub render_png: Bytes,
    /// error_abs.png: |dI| on compare's fixed scale, with its colorbar.
    pub heatmap_png: Bytes,
    /// The worker's time for the request.
    pub elapsed_ms: f64,
}

/// The worker's Vulkan context (lavapipe), made on its first render.
fn context() -> Result<Arc<Context>> {
    static CONTEXT: Mutex<Option<Arc<Context>>> = Mutex::new(None);
    let mut c = CONTEXT
        .lock()
        .map_err(|_| Error::Internal("explore: the render context is poisoned".into()))?;
    if let Some(ctx) = c.as_ref() {
        return Ok(ctx.clone());
    }
    let ctx = Context::new(&ContextDesc {
        device: None,
        validate: false,
    })?;
    *c = Some(ctx.clone());
    Ok(ctx)
}

/// Does the render (in the worker).
pub fn render(r: &RenderRequest) -> Result<RenderReply> {
    let start = Instant::now();
    let scene = r.scene.load(r.size)?;
    let method = crate::method::find(&r.method)?;
    let renderer = Renderer::new(context()?).with_precision(r.precision)?;
    let out = crate::cleanup::TempDir::new("explore-render")
        .map_err(|e| Error::io(std::env::temp_dir(), e))?;
    let summary = compare::compare(
        &renderer,
        &scene,
        &[method],
        out.path(),
        &CompareOptions::default(),
    )?;
    let report = summary
        .methods
        .into_iter()
        .find(|m| m.name == r.method)
        .ok_or_else(|| Error::Internal(format!("compare gave no figures of {}", r.method)))?;
    let read = |file: &str| {
        let p = out.path().join(&r.method).join(file);
        std::fs::read(&p).map(Bytes).map_err(|e| Error::io(&p, e))
    };
    Ok(RenderReply {
        render_png: read("render.png")?,
        heatmap_png: read("error_abs.png")?,
        report,
        scene: scene.name.clone(),
        triangles: scene.mesh.triangle_count(),
        elapsed_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}
