//! The only code in shadelab that touches `ash`. Everything outside `vk` speaks in project types.
//!
//! Objects are RAII wrappers: each owns its raw handle plus an `Arc<Context>` and destroys the
//! handle in `Drop`, so the device outlives every object made from it.
//!
//! **Synchronisation invariant:** every submission ([`commands::OneShot::submit`]) waits on its
//! fence before returning. No GPU work is ever in flight when control returns to the caller, so
//! any wrapper may be dropped at any time without further synchronisation. (kajiya and wgpu-hal
//! defer destruction because they keep frames in flight; an offscreen tool does not need to.)
//!
//! Module map: [`context`] instance/device/queue selection and validation messages;
//! [`memory`] buffers and memory-type choice; [`image`] render targets and readback;
//! [`pipeline`] shader modules, descriptor sets, graphics pipelines (dynamic rendering) and
//! compute pipelines;
//! [`executables`] what the driver compiled a pipeline into (statistics, disassembly);
//! [`commands`] one-shot and reusable command buffers, synchronous submit;
//! [`queries`] timestamp query pools and their arithmetic; [`conv`] the project's names for
//! formats, usages and clear values, and their one conversion to `ash`.
pub mod commands;
pub mod context;
pub mod conv;
pub mod executables;
pub mod image;
pub mod memory;
pub mod pipeline;
pub mod queries;

pub use commands::{ColorTarget, OneShot, Recorded};
pub use context::{Context, ContextDesc, DeviceInfo};
pub use conv::{BufferUsage, Clear, Format, FrontFace, ImageUsage};
pub use executables::{Executable, Representation, StatValue, Statistic};
pub use image::{Image, ImageDesc};
pub use memory::{Buffer, BufferDesc};
pub use pipeline::{
    ComputePipeline, DepthMode, DescriptorSet, GraphicsPipeline, PipelineDesc, ShaderModule,
    VertexStream,
};
pub use queries::QueryPool;
