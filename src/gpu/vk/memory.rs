//! Buffers and the choice of memory type. Allocations are few and large (vertex streams, a
//! uniform block, readback buffers), so each buffer gets its own `vkAllocateMemory`; no
//! sub-allocator is needed. Every buffer is host-visible and coherent: lavapipe has exactly one
//! memory type that is device-local, host-visible, coherent and cached (TOOLCHAIN.md), and on a
//! discrete GPU host-visible vertex/readback buffers still work.
use std::sync::Arc;

use ash::vk;

use super::conv::VkContext;
use super::{BufferUsage, Context};
use crate::error::{Error, Result};

/// How to create a [`Buffer`].
#[derive(Debug, Clone, Copy)]
pub struct BufferDesc {
    pub size: u64,
    pub usage: BufferUsage,
}

/// A host-visible, persistently mapped buffer.
pub struct Buffer {
    ctx: Arc<Context>,
    pub(crate) raw: vk::Buffer,
    memory: vk::DeviceMemory,
    mapped: *mut u8,
    /// The host memory behind `mapped` on a capture context (empty otherwise).
    host: Vec<u8>,
    size: u64,
    usage: BufferUsage,
}

// SAFETY: the mapped pointer is only dereferenced through &self / &mut self methods; the
// buffer is never used by the GPU while the host touches it (synchronous submits).
unsafe impl Send for Buffer {}
// SAFETY: as above; shared access only reads.
unsafe impl Sync for Buffer {}

/// Finds a memory type allowed by `type_bits` with all of `flags`.
pub(crate) fn find_memory_type(
    ctx: &Context,
    type_bits: u32,
    flags: vk::MemoryPropertyFlags,
) -> Result<u32> {
    let props = &ctx.memory_properties;
    (0..props.memory_type_count)
        .find(|&i| {
            type_bits & (1 << i) != 0
                && props.memory_types[i as usize]
                    .property_flags
                    .contains(flags)
        })
        .ok_or_else(|| {
            Error::Device(format!(
                "no Vulkan memory type with {flags:?} on {}",
                ctx.info().name
            ))
        })
}

impl Buffer {
    /// Creates and maps a buffer of `desc.size` bytes (at least 1).
    pub fn new(ctx: &Arc<Context>, desc: BufferDesc) -> Result<Self> {
        let size = desc.size.max(4);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(desc.usage.raw())
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let d = &ctx.device;
        // SAFETY: valid device and create info.
        let raw = unsafe { d.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // From here the buffer must be destroyed if a later step fails.
        let mut this = Buffer {
            ctx: ctx.clone(),
            raw,
            memory: vk::DeviceMemory::null(),
            mapped: std::ptr::null_mut(),
            host: Vec::new(),
            size,
            usage: desc.usage,
        };
        // SAFETY: raw is a live buffer.
        let req = unsafe { d.get_buffer_memory_requirements(raw) };
        if ctx.captures_executables() {
            // A capture context (RADV's null device) has no memory type at all: the buffer
            // stays unbound, with host memory of its own behind bytes()/bytes_mut(). Nothing
            // ever reads it on the device (a capture context never submits).
            this.host = vec![0u8; size as usize];
            this.mapped = this.host.as_mut_ptr();
            return Ok(this);
        }
        let ty = find_memory_type(
            ctx,
            req.memory_type_bits,
            vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT,
        )?;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(ty);
        // SAFETY: valid allocate info.
        this.memory = unsafe { d.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
        // SAFETY: memory is fresh and large enough per the requirements.
        unsafe { d.bind_buffer_memory(raw, this.memory, 0) }.vk("vkBindBufferMemory")?;
        // SAFETY: host-visible memory, mapped once for the buffer's lifetime.
        this.mapped =
            unsafe { d.map_memory(this.memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }
                .vk("vkMapMemory")? as *mut u8;
        Ok(this)
    }

    /// Creates a buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &Arc<Context>,
        usage: BufferUsage,
        data: &[T],
    ) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut b = Buffer::new(
            ctx,
            BufferDesc {
                size: bytes.len() as u64,
                usage,
            },
        )?;
        b.bytes_mut()[..bytes.len()].copy_from_slice(bytes);
        Ok(b)
    }

    /// What the buffer was created for.
    pub fn usage(&self) -> BufferUsage {
        self.usage
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// The mapped contents (coherent: GPU writes are visible after the submit's fence).
    pub fn bytes(&self) -> &[u8] {
        // SAFETY: mapped covers `size` bytes for the buffer's lifetime; no GPU work in flight.
        unsafe { std::slice::from_raw_parts(self.mapped, self.size as usize) }
    }

    /// The mapped contents, writable.
    pub fn bytes_mut(&mut self) -> &mut [u8] {
        // SAFETY: as in `bytes`, and &mut self guarantees exclusive host access.
        unsafe { std::slice::from_raw_parts_mut(self.mapped, self.size as usize) }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: no GPU work in flight (synchronous submits); handles are owned by self.
        unsafe {
            if self.memory != vk::DeviceMemory::null() && !self.mapped.is_null() {
                self.ctx.device.unmap_memory(self.memory);
            }
            self.ctx.device.destroy_buffer(self.raw, None);
            if self.memory != vk::DeviceMemory::null() {
                self.ctx.device.free_memory(self.memory, None);
            }
        }
    }
}
