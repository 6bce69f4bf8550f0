//! shadelab: fast-Phong shading methods rendered through Vulkan, diffed against an f64 truth.
//!
//! This is the short form of ARCHITECTURE.md (at the repository's top), which adds why each
//! seam below is where it is; docs/layout.md lists every folder.
//!
//! # Layers
//! Each layer uses only the layers below it (checked by `layers_point_one_way` in tests/layout.rs):
//!
//! | layer | modules | owns |
//! |---|---|---|
//! | command line | [`cli`] | clap types, one file per command, exit codes |
//! | report | [`report`], [`corpus`], [`explore`] | the main job: compare, bench and stress per scene, one offline HTML page; a mesh corpus in shards, merged; a local page where a method is edited and its error and cost follow |
//! | jobs | [`compare`], [`bench`], [`verify`], [`stress`], [`plan`], [`isa`], [`prove`], [`costs`], [`tune`] | a run over methods: statistics, heatmaps, timing, claims; GPU against its own f64 twin; sweeps of each method's input domain; the programs compiled for the GPU families of every vendor without the GPUs (RADV's null device, Mesa's drm-shims; a vendor per file in [`isa::route`]); proven error bounds by interval branch-and-bound; the inverse square root tuned to a mesh, proven and costed |
//! | judgement | [`analysis`], [`truth`], [`cases`], [`cost`], [`auto`] | per-pixel error (one definition), statistics; f64 truth and bound; the cases of the sweeps, shared by the jobs that sweep; cost models (one type family, their sources' interface and registry, the verdict rules); `auto`'s budget, candidates and per-triangle choice |
//! | device | [`gpu`], [`software`], [`engine`] | [`gpu::vk`] (the only user of `ash`), [`gpu::gl`] (the only user of EGL and OpenGL), shaders, SPIR-V, renderer, timed draws; the software scanline engine (same frames, each method in its incremental span form); the choice between the two, shared by the jobs that render |
//! | data | [`scene`], [`frame`] | scene file, camera, the f64 -> f32 inputs of a draw; read-back images |
//! | definitions | [`method`], [`geometry`] | the method table, f64 formulas and twins; meshes |
//! | base | [`output`], [`error`], [`child`], [`cleanup`], [`memory`], [`parallel`] | atomic files, PNG/NPY, figures, provenance; the error type; the protocol of shadelab's child processes (one typed request, one typed reply); what a run leaves behind (temporary files and children removed on exit, on SIGINT/SIGTERM, and by the next run after a SIGKILL); the memory a job needs at an image size, checked before allocating; work split over every core |
//!
//! # Data flow
//! scene file -> [`scene::Scene`] -> [`scene::SceneInputs`] (f64, rounded to f32 once) ->
//! [`gpu::Renderer`] -> [`frame::Frame`] + [`frame::IdFrame`] -> [`truth::evaluate`] (the same
//! inputs in f64 at the rasterizer's weights) -> [`analysis::pixel`] -> [`compare`] / [`bench`]
//! -> files in the output folder -> [`report`] (index.html over those files).
//!
//! # Where things go
//! - a method: a GLSL file in glsl/methods/, a row in [`method::table`], its f64 formula in
//!   [`method::formulas`] (per pixel) or [`method::scanline`] (along the span, with
//!   glsl/scanline.glsl), its twin in [`method::twins`], its claims' checks in
//!   [`method::checks`] / [`method::scanline_checks`] (docs/methods.md "How to add a method");
//! - a metric: [`analysis`] computes it, [`compare::summary`] reports it;
//! - a command: a file in src/cli/, calling a job of the layer below;
//! - a cost model: a [`cost::CostSource`] beside the job that measures it, one line in
//!   [`costs::builtin`]; a GPU vendor for `isa`: a file of [`isa::route`], one line in its
//!   `VENDORS`;
//! - a setting of bench's or the report's measurement: [`bench::schedule::Schedule`] (its table of
//!   defaults is tested there);
//! - a child process: a [`child::Job`] (one typed request, one typed reply), dispatched in
//!   src/cli/child.rs;
//! - a section of the HTML report: a function in [`report::sections::SECTIONS`] (links stay
//!   relative; [`report::links`] checks them).
//!
//! # Lifetimes and synchronisation
//! Vulkan objects own an `Arc` of their [`gpu::vk::Context`]; every submission waits on its fence,
//! so nothing is in flight when a call returns (see [`gpu::vk`]).
pub mod analysis;
pub mod auto;
pub mod bench;
pub mod cases;
pub mod child;
pub mod cleanup;
pub mod cli;
pub mod compare;
pub mod corpus;
pub mod cost;
pub mod costs;
pub mod engine;
pub mod error;
pub mod explore;
pub mod frame;
pub mod geometry;
pub mod gpu;
pub mod isa;
pub mod memory;
pub mod method;
pub mod output;
pub mod parallel;
pub mod plan;
pub mod prove;
pub mod report;
pub mod scene;
pub mod software;
pub mod stress;
#[cfg(test)]
mod testutil;
pub mod truth;
pub mod tune;
pub mod verify;
pub mod workers;

pub use error::{Error, Result};
