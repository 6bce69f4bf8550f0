//! 2D images used as render targets (colour, normal, ids, depth) and their views.
//! Most images are device-local with optimal tiling; their results come back through a copy
//! into a [`Buffer`](super::Buffer) (see [`super::commands::OneShot::copy_image_to_buffer`]).
//! A host colour target ([`ImageUsage::HostColorTarget`]) is linear, host-visible and mapped:
//! the host reads it in place ([`Image::take_rows`]), with no copy by the driver.
use std::sync::Arc;

use ash::vk;

use super::conv::VkContext;
use super::memory::find_memory_type;
use super::{Context, Format, ImageUsage};
use crate::error::Result;

/// How to create an [`Image`].
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub format: Format,
    pub usage: ImageUsage,
}

impl ImageDesc {
    /// A colour target that can be read back.
    pub fn color(width: u32, height: u32, format: Format) -> Self {
        ImageDesc {
            width,
            height,
            format,
            usage: ImageUsage::ColorTarget,
        }
    }

    /// A colour target the host reads in place (check [`Context::linear_color_target`]
    /// first).
    pub fn host_color(width: u32, height: u32, format: Format) -> Self {
        ImageDesc {
            width,
            height,
            format,
            usage: ImageUsage::HostColorTarget,
        }
    }

    /// A depth target (D32_SFLOAT).
    pub fn depth(width: u32, height: u32) -> Self {
        ImageDesc {
            width,
            height,
            format: Format::Depth32Float,
            usage: ImageUsage::DepthTarget,
        }
    }

    /// Bytes per texel of the formats shadelab uses.
    pub fn texel_size(&self) -> u64 {
        self.format.texel_size()
    }

    pub(crate) fn aspect(&self) -> vk::ImageAspectFlags {
        if self.format.is_depth() {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        }
    }
}

/// An image with its memory and a full view.
pub struct Image {
    ctx: Arc<Context>,
    pub(crate) raw: vk::Image,
    pub(crate) view: vk::ImageView,
    memory: vk::DeviceMemory,
    pub desc: ImageDesc,
    /// A host colour target's mapped memory (null otherwise).
    mapped: *mut u8,
    /// Where a host colour target's texels lie in `mapped` (offset, row pitch).
    layout: vk::SubresourceLayout,
}

// SAFETY: the mapped pointer is only dereferenced through `take_rows` (&mut self) and while no
// GPU work is in flight (synchronous submits); everything else is plain handles.
unsafe impl Send for Image {}
// SAFETY: as above; &self methods never touch the mapped memory.
unsafe impl Sync for Image {}

impl Image {
    /// Creates an image with its memory and view. A host colour target is created linear in
    /// host-visible memory, mapped, zeroed and moved to GENERAL layout (one submit), so that it
    /// is zero whenever no render is in flight: [`Image::take_rows`] zeroes what it reads.
    pub fn new(ctx: &Arc<Context>, desc: ImageDesc) -> Result<Self> {
        let d = &ctx.device;
        let host = desc.usage == ImageUsage::HostColorTarget;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format.raw())
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(if host {
                vk::ImageTiling::LINEAR
            } else {
                vk::ImageTiling::OPTIMAL
            })
            .usage(desc.usage.raw())
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(if host {
                vk::ImageLayout::PREINITIALIZED
            } else {
                vk::ImageLayout::UNDEFINED
            });
        // SAFETY: valid device and create info.
        let raw = unsafe { d.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut this = Image {
            ctx: ctx.clone(),
            raw,
            view: vk::ImageView::null(),
            memory: vk::DeviceMemory::null(),
            desc,
            mapped: std::ptr::null_mut(),
            layout: vk::SubresourceLayout::default(),
        };
        // SAFETY: raw is live.
        let req = unsafe { d.get_image_memory_requirements(raw) };
        let ty = if host {
            let visible =
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            find_memory_type(ctx, req.memory_type_bits, visible)?
        } else {
            find_memory_type(
                ctx,
                req.memory_type_bits,
                vk::MemoryPropertyFlags::DEVICE_LOCAL,
            )
            .or_else(|_| {
                find_memory_type(ctx, req.memory_type_bits, vk::MemoryPropertyFlags::empty())
            })?
        };
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(ty);
        // SAFETY: valid allocate info.
        this.memory = unsafe { d.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: fresh memory sized by the requirements.
        unsafe { d.bind_image_memory(raw, this.memory, 0) }.vk("vkBindImageMemory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format.raw())
            .subresource_range(Self::range(&desc));
        // SAFETY: image is bound to memory.
        this.view = unsafe { d.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        if host {
            this.map_zeroed(req.size)?;
        }
        Ok(this)
    }

    /// Maps a host colour target's memory, zeroes all of it, and moves the image from
    /// PREINITIALIZED to GENERAL (contents kept).
    fn map_zeroed(&mut self, size: u64) -> Result<()> {
        let d = &self.ctx.device;
        let sub = vk::ImageSubresource {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            array_layer: 0,
        };
        // SAFETY: a linear image, bound to memory.
        self.layout = unsafe { d.get_image_subresource_layout(self.raw, sub) };
        let row = self.desc.width as u64 * self.desc.texel_size();
        let rows_end =
            self.layout.offset + self.layout.row_pitch * (self.desc.height as u64 - 1) + row;
        if self.layout.row_pitch < row || rows_end > size {
            return Err(crate::error::Error::Internal(format!(
                "linear image layout {:?} does not hold {}x{} texels of {row} bytes a row",
                self.layout, self.desc.width, self.desc.height
            )));
        }
        // SAFETY: host-visible memory, mapped once for the image's lifetime.
        self.mapped =
            unsafe { d.map_memory(self.memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
                .vk("vkMapMemory")? as *mut u8;
        // SAFETY: the mapping covers the whole allocation of `size` bytes; no GPU work uses it.
        unsafe { std::ptr::write_bytes(self.mapped, 0, size as usize) };
        let mut cmd = super::OneShot::begin(&self.ctx)?;
        cmd.host_target_to_general(self);
        cmd.submit()?;
        Ok(())
    }

    /// Whether this is a host colour target (read in place with [`Image::take_rows`]).
    pub fn is_host_target(&self) -> bool {
        !self.mapped.is_null()
    }

    /// Hands each row of a host colour target to `row` (its `width x texel` bytes, top row
    /// first) and zeroes it after: the image is zero again when this returns, as a render that
    /// loads instead of clearing needs ([`super::OneShot::begin_rendering`]). Call only after
    /// the render's submit returned (and its host-read barrier, `make_host_readable`). An
    /// error for an image that is not a host target.
    pub fn take_rows(&mut self, mut row: impl FnMut(&[u8])) -> Result<()> {
        if self.mapped.is_null() {
            return Err(crate::error::Error::Internal(
                "take_rows: not a host colour target".into(),
            ));
        }
        let len = (self.desc.width as u64 * self.desc.texel_size()) as usize;
        for y in 0..self.desc.height as u64 {
            let at = (self.layout.offset + y * self.layout.row_pitch) as usize;
            // SAFETY: map_zeroed checked that every row lies inside the mapped allocation;
            // &mut self and the synchronous submits give exclusive host access.
            let bytes = unsafe { std::slice::from_raw_parts_mut(self.mapped.add(at), len) };
            row(bytes);
            bytes.fill(0);
        }
        Ok(())
    }

    pub(crate) fn range(desc: &ImageDesc) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: desc.aspect(),
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        }
    }

    /// Bytes needed to read the whole image back.
    pub fn byte_size(&self) -> u64 {
        self.desc.width as u64 * self.desc.height as u64 * self.desc.texel_size()
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: no GPU work in flight; handles owned by self.
        unsafe {
            if !self.mapped.is_null() {
                self.ctx.device.unmap_memory(self.memory);
            }
            if self.view != vk::ImageView::null() {
                self.ctx.device.destroy_image_view(self.view, None);
            }
            self.ctx.device.destroy_image(self.raw, None);
            if self.memory != vk::DeviceMemory::null() {
                self.ctx.device.free_memory(self.memory, None);
            }
        }
    }
}
