//! The GPU layer: Vulkan objects ([`vk`], the only user of `ash`), the SPIR-V programs
//! ([`shaders`], [`spirv`]), the offscreen renderer ([`renderer`]) and its read-back
//! (`readback`), its timed draws ([`timing`]), methods evaluated on buffers of cases
//! ([`evaluate`]), and the timed draw's programs as a driver compiled them ([`compiled`], for
//! `shadelab isa`), the Vulkan drivers found by the loader's rules ([`icd`]). [`gl`] is the only user of EGL and OpenGL (khronos-egl, glow): the
//! OpenGL-only drivers' compilers, for `shadelab isa`.
pub mod compiled;
pub mod device;
pub mod evaluate;
pub mod gl;
pub mod icd;
mod readback;
pub mod renderer;
pub mod shaders;
pub mod spirv;
pub mod timing;
pub mod vk;

pub use device::DeviceSpec;
pub use renderer::*;
pub use timing::*;
