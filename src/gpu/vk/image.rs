//! 2D images used as render targets (colour, normal, ids, depth) and their views.
//! Images are device-local with optimal tiling; results come back through a copy into a
//! [`Buffer`](super::Buffer) (see [`super::commands::OneShot::copy_image_to_buffer`]).
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
}

impl Image {
    pub fn new(ctx: &Arc<Context>, desc: ImageDesc) -> Result<Self> {
        let d = &ctx.device;
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
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage.raw())
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { d.create_image(&info, None) }.vk("vkCreateImage")?;
        let mut this = Image {
            ctx: ctx.clone(),
            raw,
            view: vk::ImageView::null(),
            memory: vk::DeviceMemory::null(),
            desc,
        };
        // SAFETY: raw is live.
        let req = unsafe { d.get_image_memory_requirements(raw) };
        let ty = find_memory_type(
            ctx,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::DEVICE_LOCAL,
        )
        .or_else(|_| {
            find_memory_type(ctx, req.memory_type_bits, vk::MemoryPropertyFlags::empty())
        })?;
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
        Ok(this)
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
