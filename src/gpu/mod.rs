//! The GPU layer: Vulkan objects ([`vk`], the only user of `ash`), the SPIR-V programs
//! ([`shaders`], [`spirv`]), the offscreen renderer ([`renderer`]) and its timed draws ([`timing`]).
pub mod renderer;
pub mod shaders;
pub mod spirv;
pub mod timing;
pub mod vk;

pub use renderer::*;
pub use timing::*;
