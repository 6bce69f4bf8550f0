//! Which renderer draws the frames the jobs judge: the Vulkan pipeline (lavapipe) or the
//! software scanline engine (src/software/). `compare` and `verify` render through [`Ready`]
//! and `bench`'s software timing names its [`Engine::provenance`]; everything after the frames
//! (the f64 truth at the engine's own weights, the statistics, FLIP, the heatmaps,
//! summary.json) is shared, so the two engines are judged the same way and only these few calls
//! differ.
use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::gpu::{Prepared, Renderer, Shading};
use crate::method::Method;
use crate::output::provenance::{cpu_model, Provenance};
use crate::scene::{Scene, SceneInputs};
use crate::software;

/// How a frame is rendered.
#[derive(Clone, Copy)]
pub enum Engine<'a> {
    /// The Vulkan pipeline of this renderer.
    Vulkan(&'a Renderer),
    /// [`software::render`] on `threads` threads.
    Software { threads: usize },
}

/// Which engine drew a result: `engine` of summary.json and bench.json, spelt `vulkan` or
/// `software`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EngineKind {
    Vulkan,
    Software,
}

impl EngineKind {
    pub fn as_str(self) -> &'static str {
        match self {
            EngineKind::Vulkan => "vulkan",
            EngineKind::Software => "software",
        }
    }
}

impl std::fmt::Display for EngineKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Engine<'_> {
    /// Which engine this is.
    pub fn kind(&self) -> EngineKind {
        match self {
            Engine::Vulkan(_) => EngineKind::Vulkan,
            Engine::Software { .. } => EngineKind::Software,
        }
    }

    /// The engine's name in outputs and messages ([`EngineKind`]).
    pub fn name(&self) -> &'static str {
        self.kind().as_str()
    }

    /// Where a result came from: the Vulkan device, or the software engine on this CPU (no
    /// Vulkan API, no Mesa or LLVM involved).
    pub fn provenance(&self) -> Provenance {
        match self {
            Engine::Vulkan(r) => r.provenance(),
            Engine::Software { threads } => Provenance::new(
                &format!("shadelab software engine on {}", cpu_model()),
                "software",
                &format!("src/software, {threads} threads"),
                "none",
            ),
        }
    }

    /// Whether this engine's image of `m` drifts along the span, so that its bound must widen
    /// with the distance from the span's start: the software engine's recurrences
    /// ([`software::Form::drifts`]); the Vulkan pipeline evaluates each pixel afresh.
    pub fn drifts(&self, m: &Method) -> bool {
        match self {
            Engine::Vulkan(_) => false,
            Engine::Software { .. } => software::form_of(m).drifts,
        }
    }
}

/// A scene made ready for an engine: the inputs of every geometry the methods draw, the
/// scene's own triangles first.
pub(crate) enum Ready<'a> {
    Vulkan(&'a Renderer, Prepared),
    Software {
        threads: usize,
        inputs: Vec<SceneInputs>,
    },
}

impl<'a> Ready<'a> {
    pub fn new(engine: Engine<'a>, scene: &Scene, methods: &[&Method]) -> Result<Self> {
        match engine {
            Engine::Vulkan(r) => Ok(Ready::Vulkan(r, r.prepare(scene, methods)?)),
            Engine::Software { threads } => {
                let mut inputs = vec![SceneInputs::new(scene, crate::method::Geometry::Mesh)];
                for m in methods {
                    if !inputs.iter().any(|i| i.geometry == m.geometry) {
                        inputs.push(SceneInputs::new(scene, m.geometry));
                    }
                }
                Ok(Ready::Software { threads, inputs })
            }
        }
    }

    /// The inputs of the scene's own triangles (the reference geometry).
    pub fn base(&self) -> &SceneInputs {
        match self {
            Ready::Vulkan(_, p) => &p.base().inputs,
            Ready::Software { inputs, .. } => &inputs[0],
        }
    }

    /// The inputs `m` is drawn from (its geometry's).
    pub fn inputs(&self, m: &Method) -> Result<&SceneInputs> {
        match self {
            Ready::Vulkan(_, p) => Ok(&p.for_method(m).inputs),
            Ready::Software { inputs, .. } => inputs
                .iter()
                .find(|i| i.geometry == m.geometry)
                .ok_or_else(|| {
                    Error::Internal(format!("{}: its geometry was not prepared", m.name))
                }),
        }
    }

    /// Renders `m` (with the id frame when `with_ids`).
    pub fn render(&self, m: &Method, with_ids: bool) -> Result<(Frame, Option<IdFrame>)> {
        self.render_into(m, with_ids, None)
    }

    /// [`Ready::render`] reading the frame back into `recycled`'s vectors (Vulkan; the
    /// software engine draws into its own targets and drops it): the same frame.
    pub fn render_into(
        &self,
        m: &Method,
        with_ids: bool,
        recycled: Option<Frame>,
    ) -> Result<(Frame, Option<IdFrame>)> {
        match self {
            Ready::Vulkan(r, p) => r.render_with_into(
                p.for_method(m),
                Shading::Method(m),
                with_ids,
                true,
                recycled,
            ),
            Ready::Software { threads, .. } => {
                software::render(self.inputs(m)?, m, *threads, with_ids)
            }
        }
    }
}
