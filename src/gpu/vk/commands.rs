//! One-shot command buffers: record, submit, wait. [`OneShot::submit`] blocks on a fence, which
//! is the invariant the whole `vk` module relies on (see `vk/mod.rs`).
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;

use super::conv::VkContext;
use super::{
    Buffer, Clear, ComputePipeline, Context, DescriptorSet, GraphicsPipeline, Image, QueryPool,
};
use crate::error::Result;

/// A primary command buffer being recorded; consumed by [`OneShot::submit`].
pub struct OneShot {
    ctx: Arc<Context>,
    cb: vk::CommandBuffer,
}

/// A colour attachment for [`OneShot::begin_rendering`] and its clear value.
pub struct ColorTarget<'a> {
    pub image: &'a Image,
    pub clear: Clear,
}

impl OneShot {
    /// Allocates a command buffer from the context's pool and begins recording.
    pub fn begin(ctx: &Arc<Context>) -> Result<Self> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(ctx.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let _q = ctx.lock_queue()?;
        // SAFETY: the pool is only used under queue_lock (command pools are externally synchronised).
        let cb = unsafe { ctx.device.allocate_command_buffers(&info) }
            .vk("vkAllocateCommandBuffers")?[0];
        let this = OneShot {
            ctx: ctx.clone(),
            cb,
        };
        // Not ONE_TIME_SUBMIT: benchmarks submit the same buffer repeatedly.
        let begin = vk::CommandBufferBeginInfo::default();
        // SAFETY: fresh command buffer.
        unsafe { ctx.device.begin_command_buffer(cb, &begin) }.vk("vkBeginCommandBuffer")?;
        Ok(this)
    }

    fn image_barrier(&self, image: &Image, from: vk::ImageLayout, to: vk::ImageLayout) {
        self.barrier(
            image,
            (from, to),
            stage_access(from, true),
            stage_access(to, false),
        );
    }

    /// An image memory barrier with explicit stages and accesses (source, destination).
    fn barrier(
        &self,
        image: &Image,
        (from, to): (vk::ImageLayout, vk::ImageLayout),
        (src_stage, src_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
        (dst_stage, dst_access): (vk::PipelineStageFlags2, vk::AccessFlags2),
    ) {
        let barrier = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(src_stage)
            .src_access_mask(src_access)
            .dst_stage_mask(dst_stage)
            .dst_access_mask(dst_access)
            .old_layout(from)
            .new_layout(to)
            .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
            .image(image.raw)
            .subresource_range(Image::range(&image.desc))];
        let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
        // SAFETY: recording state; image alive until submit returns.
        unsafe { self.ctx.device.cmd_pipeline_barrier2(self.cb, &dep) };
    }

    /// Moves a fresh host colour target from PREINITIALIZED to GENERAL, its layout for good
    /// (the host's zeroes kept).
    pub(crate) fn host_target_to_general(&mut self, image: &Image) {
        self.barrier(
            image,
            (vk::ImageLayout::PREINITIALIZED, vk::ImageLayout::GENERAL),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_WRITE),
            stage_access(vk::ImageLayout::GENERAL, false),
        );
    }

    /// Makes a host colour target's rendering visible to the host (read after
    /// [`submit`](Self::submit) returns, with [`Image::take_rows`]).
    pub fn make_host_readable(&mut self, image: &Image) {
        let general = vk::ImageLayout::GENERAL;
        self.barrier(
            image,
            (general, general),
            (
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
    }

    /// Transitions the targets (contents discarded), begins dynamic rendering with clears, and
    /// sets a full-image viewport and scissor. A host colour target stays in GENERAL layout and
    /// keeps its contents; it is zero whenever no render is in flight ([`Image::take_rows`]
    /// zeroes what it reads), so a clear to zero bits is a load there: no clear by the driver
    /// (lavapipe fills a 16-byte texel with one `memcpy` call per pixel).
    pub fn begin_rendering(&mut self, colors: &[ColorTarget], depth: Option<&Image>) {
        let (w, h) = match (colors.first(), depth) {
            (Some(c), _) => (c.image.desc.width, c.image.desc.height),
            (None, Some(d)) => (d.desc.width, d.desc.height),
            (None, None) => (1, 1),
        };
        for c in colors {
            if c.image.is_host_target() {
                let general = vk::ImageLayout::GENERAL;
                let src = stage_access(vk::ImageLayout::UNDEFINED, true);
                let dst = stage_access(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, false);
                self.barrier(c.image, (general, general), src, dst);
            } else {
                self.image_barrier(
                    c.image,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                );
            }
        }
        if let Some(d) = depth {
            self.image_barrier(
                d,
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            );
        }
        let color_infos: Vec<_> = colors
            .iter()
            .map(|c| {
                let host = c.image.is_host_target();
                let (layout, load) = match (host, host && c.clear.is_zero_bits()) {
                    (_, true) => (vk::ImageLayout::GENERAL, vk::AttachmentLoadOp::LOAD),
                    (true, false) => (vk::ImageLayout::GENERAL, vk::AttachmentLoadOp::CLEAR),
                    (false, _) => (
                        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                        vk::AttachmentLoadOp::CLEAR,
                    ),
                };
                vk::RenderingAttachmentInfo::default()
                    .image_view(c.image.view)
                    .image_layout(layout)
                    .load_op(load)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: c.clear.raw(),
                    })
            })
            .collect();
        let depth_info = depth.map(|d| {
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: 1.0,
                        stencil: 0,
                    },
                })
        });
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: w,
                height: h,
            },
        };
        let mut info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color_infos);
        if let Some(di) = depth_info.as_ref() {
            info = info.depth_attachment(di);
        }
        let d = &self.ctx.device;
        // SAFETY: recording state; attachments transitioned above and alive until submit returns.
        unsafe {
            d.cmd_begin_rendering(self.cb, &info);
            d.cmd_set_viewport(
                self.cb,
                0,
                &[vk::Viewport {
                    x: 0.0,
                    y: 0.0,
                    width: w as f32,
                    height: h as f32,
                    min_depth: 0.0,
                    max_depth: 1.0,
                }],
            );
            d.cmd_set_scissor(self.cb, 0, &[area]);
        }
    }

    /// Binds `pipeline`, its descriptor set and one vertex buffer per stream (binding i = `buffers[i]`),
    /// then draws `vertex_count` vertices.
    pub fn draw(
        &mut self,
        pipeline: &GraphicsPipeline,
        set: Option<&DescriptorSet>,
        buffers: &[(u32, &Buffer)],
        vertex_count: u32,
    ) {
        self.draw_range(pipeline, set, buffers, 0, vertex_count);
    }

    /// [`draw`](Self::draw) of the vertices `first..first + count` only.
    pub fn draw_range(
        &mut self,
        pipeline: &GraphicsPipeline,
        set: Option<&DescriptorSet>,
        buffers: &[(u32, &Buffer)],
        first: u32,
        count: u32,
    ) {
        let d = &self.ctx.device;
        // SAFETY: recording inside a rendering scope; all objects alive until submit returns.
        unsafe {
            d.cmd_bind_pipeline(self.cb, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
            if let Some(s) = set {
                d.cmd_bind_descriptor_sets(
                    self.cb,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipeline.layout,
                    0,
                    &[s.raw],
                    &[],
                );
            }
            for &(binding, buf) in buffers {
                d.cmd_bind_vertex_buffers(self.cb, binding, &[buf.raw], &[0]);
            }
            d.cmd_draw(self.cb, count, 1, first, 0);
        }
    }

    /// Binds a compute pipeline and its set, dispatches `groups` work groups along x, and makes
    /// the shader's writes visible to the host (read after [`submit`](Self::submit) returns).
    pub fn dispatch(&mut self, pipeline: &ComputePipeline, set: &DescriptorSet, groups: u32) {
        let d = &self.ctx.device;
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
        // SAFETY: recording outside a rendering scope; all objects alive until submit returns.
        unsafe {
            d.cmd_bind_pipeline(self.cb, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
            d.cmd_bind_descriptor_sets(
                self.cb,
                vk::PipelineBindPoint::COMPUTE,
                pipeline.layout,
                0,
                &[set.raw],
                &[],
            );
            d.cmd_dispatch(self.cb, groups, 1, 1);
            d.cmd_pipeline_barrier2(self.cb, &dep);
        }
    }

    /// Ends the rendering scope begun by [`begin_rendering`](Self::begin_rendering).
    pub fn end_rendering(&mut self) {
        // SAFETY: a rendering scope is open.
        unsafe { self.ctx.device.cmd_end_rendering(self.cb) };
    }

    /// Resets every query of `pool` (outside a rendering scope).
    pub fn reset_queries(&mut self, pool: &QueryPool) {
        // SAFETY: recording state, outside rendering; the pool outlives the submission.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(self.cb, pool.raw, 0, pool.count)
        };
    }

    /// Writes a timestamp into query `index` of `pool` once all earlier work has completed
    /// (BOTTOM_OF_PIPE; why the renderer writes these in pairs: `gpu::timing`).
    pub fn timestamp(&mut self, pool: &QueryPool, index: u32) {
        let stage = vk::PipelineStageFlags2::BOTTOM_OF_PIPE;
        // SAFETY: recording state; the query was reset earlier in this command buffer.
        unsafe {
            self.ctx
                .device
                .cmd_write_timestamp2(self.cb, stage, pool.raw, index)
        };
    }

    /// Begins query 0 of `pool` (inside the rendering scope, ended before it closes).
    pub fn begin_query(&mut self, pool: &QueryPool) {
        // SAFETY: recording state; the query was reset earlier in this command buffer.
        unsafe {
            self.ctx
                .device
                .cmd_begin_query(self.cb, pool.raw, 0, vk::QueryControlFlags::empty())
        };
    }

    /// Ends query 0 of `pool`.
    pub fn end_query(&mut self, pool: &QueryPool) {
        // SAFETY: the query is active in this command buffer.
        unsafe { self.ctx.device.cmd_end_query(self.cb, pool.raw, 0) };
    }

    /// Copies a colour target (after rendering) into `dst`, tightly packed, and makes the copy
    /// visible to the host.
    pub fn copy_image_to_buffer(&mut self, image: &Image, dst: &Buffer) {
        self.image_barrier(
            image,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        );
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: image.desc.width,
                height: image.desc.height,
                depth: 1,
            },
        };
        let host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        let dep = vk::DependencyInfo::default().memory_barriers(&host);
        let d = &self.ctx.device;
        // SAFETY: image in TRANSFER_SRC layout, dst large enough (caller sizes it by byte_size).
        unsafe {
            d.cmd_copy_image_to_buffer(
                self.cb,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst.raw,
                &[region],
            );
            d.cmd_pipeline_barrier2(self.cb, &dep);
        }
    }

    /// Ends recording, submits, and waits for completion. Returns the submit-to-fence wall time.
    pub fn submit(self) -> Result<Duration> {
        // SAFETY: recording state.
        unsafe { self.ctx.device.end_command_buffer(self.cb) }.vk("vkEndCommandBuffer")?;
        self.submit_once()
    }

    /// Ends recording and keeps the command buffer for repeated submission.
    pub fn finish(self) -> Result<Recorded> {
        // SAFETY: recording state.
        unsafe { self.ctx.device.end_command_buffer(self.cb) }.vk("vkEndCommandBuffer")?;
        Ok(Recorded { inner: self })
    }

    /// Submits under the queue lock and waits on a fence.
    fn submit_once(&self) -> Result<Duration> {
        let _queue = self.ctx.lock_queue()?;
        let d = &self.ctx.device;
        // SAFETY: valid device.
        let fence =
            unsafe { d.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
        let cbs = [self.cb];
        let submit = vk::SubmitInfo::default().command_buffers(&cbs);
        let result = {
            let start = Instant::now();
            // SAFETY: the queue is used under queue_lock; we wait on the fence before anything
            // referenced by the command buffer can be dropped.
            unsafe { d.queue_submit(self.ctx.queue, &[submit], fence) }
                .vk("vkQueueSubmit")
                .and_then(|_| {
                    unsafe { d.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences")
                })
                .map(|_| start.elapsed())
        };
        // SAFETY: the fence is signalled (or the submit failed and it was never used).
        unsafe { d.destroy_fence(fence, None) };
        result
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        if let Ok(_q) = self.ctx.queue_lock.lock() {
            // SAFETY: submit() waited for completion (or the buffer was never submitted).
            unsafe {
                self.ctx
                    .device
                    .free_command_buffers(self.ctx.command_pool, &[self.cb])
            };
        }
    }
}

/// Stage and access masks for a layout on the source (`src = true`) or destination side.
fn stage_access(layout: vk::ImageLayout, src: bool) -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
    match layout {
        // Contents are discarded, but the previous pass (or the previous submission of a
        // repeated benchmark buffer) may still write the image: wait for all of it.
        vk::ImageLayout::UNDEFINED if src => (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::MEMORY_WRITE,
        ),
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL => (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            if src {
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE
            } else {
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ
            },
        ),
        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL => (
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
        ),
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL => (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        ),
        _ => (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE,
        ),
    }
}

/// A finished command buffer that can be submitted any number of times (each submission waits
/// for completion before returning, like every submit here).
pub struct Recorded {
    inner: OneShot,
}

impl Recorded {
    /// Submits and waits; returns the submit-to-fence wall time.
    pub fn submit(&self) -> Result<Duration> {
        self.inner.submit_once()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::vk::ContextDesc;

    /// A thread that panics while holding the queue lock poisons it; the next submission must
    /// fail with a message rather than go on without the lock.
    #[test]
    fn poisoned_queue_lock_fails_the_submit() {
        let ctx = Context::new(&ContextDesc::default()).expect("lavapipe context");
        let cmd = OneShot::begin(&ctx).expect("begin");
        let poisoner = ctx.clone();
        let _ = std::thread::spawn(move || {
            let _held = poisoner.queue_lock.lock().unwrap();
            panic!("deliberate panic while holding the queue lock");
        })
        .join();
        assert!(ctx.queue_lock.is_poisoned());
        let err = cmd
            .submit()
            .expect_err("submit under a poisoned lock must fail");
        assert!(err.to_string().contains("poisoned"), "{err}");
    }
}
