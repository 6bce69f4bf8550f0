//! The software engine (src/software/) against the Vulkan pipeline and against the f64 twins,
//! one module per topic:
//!
//! - `engines`: software against Vulkan (coverage, colours), every method against its f64 twin
//!   on the shipped scenes, kept targets, refusals.
//! - `drift`: the recurrences' float32 drift along long spans against derived bounds.
//! - `outputs`: compare and bench with `--engine software` (summary.json, bench.json, claims).
//! - `models`: `verify --engine software` on every shared model at 64, 128 and 256.
//! - `loops`: the span and pixel loops allocate nothing.
//! - `stress_meshes`: `verify --engine software` on grids of random and nearly opposite corner
//!   normals.
//! - `half`: the float16 engine (rounding, the float16 bound on every scene and model, the twin check).
//! - `golden`: the float32 frames bit-identical to the engine before the generic kernels.
mod drift;
mod engines;
mod golden;
mod half;
mod loops;
mod models;
mod outputs;
mod stress_meshes;
