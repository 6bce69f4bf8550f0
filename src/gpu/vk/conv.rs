//! The project's names for the Vulkan values the renderer chooses, and their one conversion to
//! `ash` (as wgpu-hal's `conv.rs`): code outside `gpu::vk` never spells a `vk::` constant.
use ash::vk;

use crate::error::{Error, Result};

/// Texel formats of images and vertex streams.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// RGBA 32-bit float: colour, normal and weight targets.
    Rgba32Float,
    /// RGB 32-bit float: vertex streams.
    Rgb32Float,
    /// One 32-bit unsigned integer: the triangle-id target.
    R32Uint,
    /// 32-bit float depth.
    Depth32Float,
}

impl Format {
    pub(crate) fn raw(self) -> vk::Format {
        match self {
            Format::Rgba32Float => vk::Format::R32G32B32A32_SFLOAT,
            Format::Rgb32Float => vk::Format::R32G32B32_SFLOAT,
            Format::R32Uint => vk::Format::R32_UINT,
            Format::Depth32Float => vk::Format::D32_SFLOAT,
        }
    }

    /// Bytes per texel.
    pub fn texel_size(self) -> u64 {
        match self {
            Format::Rgba32Float => 16,
            Format::Rgb32Float => 12,
            Format::R32Uint | Format::Depth32Float => 4,
        }
    }

    pub(crate) fn is_depth(self) -> bool {
        self == Format::Depth32Float
    }
}

/// What an image is used for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageUsage {
    /// Rendered into as a colour attachment, then copied out.
    ColorTarget,
    /// Depth attachment only.
    DepthTarget,
    /// A colour attachment the host reads in place: LINEAR tiling, host-visible memory,
    /// rendered in GENERAL layout (see [`super::Image::take_rows`]).
    HostColorTarget,
}

impl ImageUsage {
    pub(crate) fn raw(self) -> vk::ImageUsageFlags {
        match self {
            ImageUsage::ColorTarget => {
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
            }
            ImageUsage::DepthTarget => vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            ImageUsage::HostColorTarget => vk::ImageUsageFlags::COLOR_ATTACHMENT,
        }
    }
}

/// What a buffer is used for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BufferUsage {
    Vertex,
    Uniform,
    Storage,
    /// The destination of an image copy, read on the host.
    Readback,
}

impl BufferUsage {
    pub(crate) fn raw(self) -> vk::BufferUsageFlags {
        match self {
            BufferUsage::Vertex => vk::BufferUsageFlags::VERTEX_BUFFER,
            BufferUsage::Uniform => vk::BufferUsageFlags::UNIFORM_BUFFER,
            BufferUsage::Storage => vk::BufferUsageFlags::STORAGE_BUFFER,
            BufferUsage::Readback => vk::BufferUsageFlags::TRANSFER_DST,
        }
    }

    /// The descriptor type a buffer of this usage binds as, if any.
    pub(crate) fn descriptor_type(self) -> Option<vk::DescriptorType> {
        match self {
            BufferUsage::Uniform => Some(vk::DescriptorType::UNIFORM_BUFFER),
            BufferUsage::Storage => Some(vk::DescriptorType::STORAGE_BUFFER),
            BufferUsage::Vertex | BufferUsage::Readback => None,
        }
    }
}

/// The clear value of a colour target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Clear {
    Float([f32; 4]),
    Uint([u32; 4]),
}

impl Clear {
    /// Whether every bit of the clear value is zero (+0.0 or 0 in every channel): the
    /// contents of a target that [`super::Image::take_rows`] left.
    pub fn is_zero_bits(self) -> bool {
        match self {
            Clear::Float(v) => v.iter().all(|x| x.to_bits() == 0),
            Clear::Uint(v) => v.iter().all(|&x| x == 0),
        }
    }

    pub(crate) fn raw(self) -> vk::ClearColorValue {
        match self {
            Clear::Float(float32) => vk::ClearColorValue { float32 },
            Clear::Uint(uint32) => vk::ClearColorValue { uint32 },
        }
    }
}

/// Attaches the name of the Vulkan entry point to an `ash` result.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan {
            call,
            result: format!("{result:?}"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_all_zero_bits_clears_count_as_zero() {
        assert!(Clear::Float([0.0; 4]).is_zero_bits());
        assert!(Clear::Uint([0; 4]).is_zero_bits());
        // Teeth: -0.0 compares equal to 0.0 but is not zero bits, so a host target holding
        // zeroes must still be cleared to it; any non-zero channel too.
        assert!(!Clear::Float([0.0, 0.0, 0.0, -0.0]).is_zero_bits());
        assert!(!Clear::Float([0.0, 1.0, 0.0, 0.0]).is_zero_bits());
        assert!(!Clear::Uint([0, 0, 7, 0]).is_zero_bits());
    }

    #[test]
    fn vulkan_error_names_the_call() {
        let r: std::result::Result<(), vk::Result> = Err(vk::Result::ERROR_OUT_OF_HOST_MEMORY);
        let e = r.vk("vkCreateImage").unwrap_err();
        assert_eq!(
            e.to_string(),
            "Vulkan call vkCreateImage failed: ERROR_OUT_OF_HOST_MEMORY"
        );
    }

    #[test]
    fn texel_sizes_match_the_vulkan_formats() {
        // The byte sizes of the formats as the Vulkan spec defines them (table "Compatible formats").
        for (f, bytes) in [
            (Format::Rgba32Float, 16),
            (Format::Rgb32Float, 12),
            (Format::R32Uint, 4),
            (Format::Depth32Float, 4),
        ] {
            assert_eq!(f.texel_size(), bytes, "{f:?} as {:?}", f.raw());
        }
    }

    #[test]
    fn only_uniform_and_storage_buffers_bind_as_descriptors() {
        assert_eq!(
            BufferUsage::Uniform.descriptor_type(),
            Some(vk::DescriptorType::UNIFORM_BUFFER)
        );
        assert_eq!(
            BufferUsage::Storage.descriptor_type(),
            Some(vk::DescriptorType::STORAGE_BUFFER)
        );
        assert_eq!(BufferUsage::Vertex.descriptor_type(), None);
    }
}

/// Which window-space winding is front-facing when back faces are culled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrontFace {
    CounterClockwise,
    Clockwise,
}

impl FrontFace {
    pub(crate) fn raw(self) -> vk::FrontFace {
        match self {
            FrontFace::CounterClockwise => vk::FrontFace::COUNTER_CLOCKWISE,
            FrontFace::Clockwise => vk::FrontFace::CLOCKWISE,
        }
    }
}
