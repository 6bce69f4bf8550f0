//! The timed draw's programs as the driver compiled them: the pipelines of
//! [`Renderer::timed_draws`] (same SPIR-V, specialization constants, vertex streams, attachment
//! formats, depth mode), built on a [`crate::gpu::vk::Context::for_executables`] context and
//! queried for their executables. Nothing is recorded or submitted.
use super::*;
use crate::error::{Error, Result};
use crate::gpu::vk::Executable;

impl Renderer {
    /// The executables (vertex and fragment) of the shading pipeline of `shading`'s timed draw
    /// on `gpu`; the depth pre-pass, when [`TIMING_PREPASS`] adds one, is left out.
    pub fn compiled(&self, gpu: &GpuScene, shading: Shading) -> Result<Vec<Executable>> {
        let list = DrawList::whole(gpu, shading);
        let recorded = self.record_list(&list)?;
        let (pipeline, ..) = recorded.last().ok_or_else(|| {
            Error::Internal(format!("{}: the timed draw has no pipeline", list.name()))
        })?;
        pipeline.executables()
    }
}
