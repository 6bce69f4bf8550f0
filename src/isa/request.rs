//! What a child of `shadelab isa` is asked ([`ChildRequest`]) and what it prints
//! ([`ChildReport`]): the one request and the one reply of the `isa_family` job of
//! [`crate::child`]'s protocol, shared by the Vulkan route ([`super::child`]), the OpenGL
//! routes ([`super::gl_child`]) and the parent that reads them ([`super::report`]).
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::gpu::vk::Executable;
use crate::scene::Scene;

/// The scene whose timed draw is compiled when none is given: the shipped generated torus
/// (one directional light, specular on, screen-linear), so no mesh file is needed.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/torus_generated.toml");
/// Its name in reports.
pub const DEFAULT_SCENE_NAME: &str = "scenes/torus_generated.toml";

impl crate::child::Job for ChildRequest {
    const NAME: &'static str = "isa_family";
    type Reply = ChildReport;
}

/// What a child is asked to compile.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChildRequest {
    pub family: String,
    pub methods: Vec<String>,
    /// Scene file; `None`: [`DEFAULT_SCENE`].
    pub scene: Option<PathBuf>,
    /// The two evaluation counts of the isolated kernel (glsl/evaluate.comp `REPEAT`).
    pub kernel_counts: [u32; 2],
    /// Extra compute programs (SPIR-V files, one storage buffer at binding 0), compiled as
    /// they are: the probes of the tests.
    pub probes: Vec<PathBuf>,
    /// The precision of the method programs (issue 23; absent: f32).
    #[serde(default)]
    pub precision: crate::method::Precision,
    /// The timed draw's programs only, no isolated kernel (`isa --calibrate`'s micro-kernels
    /// are draws); absent: false.
    #[serde(default)]
    pub draws_only: bool,
}

/// What a child compiled: spelt `draw`, `kernel` or `probe` in its reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CompiledKind {
    /// The timed draw's pipeline.
    Draw,
    /// An isolated kernel (glsl/evaluate.comp) at one evaluation count.
    Kernel,
    /// A program given as is (`isa --probe`).
    Probe,
}

/// What a row of isa's figures is: spelt `draw`, `evaluation` or `probe` in isa.json and
/// isa.csv.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RowKind {
    /// The timed draw's pipeline.
    Draw,
    /// One evaluation of the isolated kernel (its statistics at the higher count minus the
    /// lower).
    Evaluation,
    /// A program given as is.
    Probe,
}

impl RowKind {
    pub fn as_str(self) -> &'static str {
        match self {
            RowKind::Draw => "draw",
            RowKind::Evaluation => "evaluation",
            RowKind::Probe => "probe",
        }
    }
}

impl std::fmt::Display for RowKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One compiled program.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Compiled {
    pub method: String,
    /// SPIR-V program name (spirv/<program>.<stage>.spv), or the probe's file name.
    pub program: String,
    pub kind: CompiledKind,
    /// The kernel's evaluation count (`REPEAT`); `None` for draws and probes.
    pub repeat: Option<u32>,
    pub executables: Vec<Executable>,
}

/// What one child prints.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChildReport {
    pub family: String,
    pub device_name: String,
    pub driver_name: String,
    /// The driver's version string ("Mesa 22.3.6" on Debian 12).
    pub driver_info: String,
    pub api_version: String,
    pub compiled: Vec<Compiled>,
    pub elapsed_ms: f64,
    /// Whether the device compiles float16 arithmetic (Vulkan's shaderFloat16); absent from
    /// the OpenGL route, whose vendors say it themselves.
    #[serde(default)]
    pub float16: Option<bool>,
    /// Methods the driver's shading language cannot express, each with why (OpenGL ES 2.0's
    /// ESSL 1.00 has no array constructors, gl_VertexID or storage buffers); empty elsewhere.
    #[serde(default)]
    pub skipped: Vec<String>,
}

/// Loads the request's scene.
pub(crate) fn scene(req: &ChildRequest) -> Result<Scene> {
    match &req.scene {
        Some(p) => crate::scene::load_scene(p),
        None => crate::scene::parse_scene(
            Path::new(DEFAULT_SCENE_NAME),
            DEFAULT_SCENE,
            &crate::geometry::load_mesh,
        ),
    }
}
