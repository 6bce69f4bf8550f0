//! Shader modules, descriptor sets, graphics pipelines for dynamic rendering (no render-pass
//! objects) and compute pipelines. A pipeline is built from a plain [`PipelineDesc`]; everything a method does not
//! need (vertex streams, targets) is simply absent from its description.
use std::sync::Arc;

use ash::vk;

use super::conv::VkContext;
use super::{Buffer, Context, Format, FrontFace};
use crate::error::{Error, Result};

/// A SPIR-V module.
pub struct ShaderModule {
    ctx: Arc<Context>,
    pub(crate) raw: vk::ShaderModule,
}

impl ShaderModule {
    /// Creates a module from SPIR-V bytes (any alignment; length must be a multiple of 4).
    pub fn new(ctx: &Arc<Context>, name: &str, bytes: &[u8]) -> Result<Self> {
        let words = ash::util::read_spv(&mut std::io::Cursor::new(bytes))
            .map_err(|e| Error::Shader(format!("{name}: not a SPIR-V module: {e}")))?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: words is a complete SPIR-V module (magic checked by read_spv).
        let raw =
            unsafe { ctx.device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        Ok(ShaderModule {
            ctx: ctx.clone(),
            raw,
        })
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: modules are only referenced during pipeline creation.
        unsafe { self.ctx.device.destroy_shader_module(self.raw, None) };
    }
}

/// One descriptor set with its own layout and pool; bindings are visible to the vertex, fragment
/// and compute stages.
pub struct DescriptorSet {
    ctx: Arc<Context>,
    pub(crate) layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub(crate) raw: vk::DescriptorSet,
}

impl DescriptorSet {
    /// `bindings`: (binding number, buffer bound whole). The descriptor type follows the
    /// buffer's usage (uniform or storage); any other usage is an error.
    pub fn new(ctx: &Arc<Context>, bindings: &[(u32, &Buffer)]) -> Result<Self> {
        let bindings = bindings
            .iter()
            .map(|&(b, buf)| {
                let ty = buf.usage().descriptor_type().ok_or_else(|| {
                    Error::Device(format!(
                        "binding {b}: a {:?} buffer cannot be bound as a descriptor",
                        buf.usage()
                    ))
                })?;
                Ok((b, ty, buf))
            })
            .collect::<Result<Vec<_>>>()?;
        let d = &ctx.device;
        let stages = vk::ShaderStageFlags::VERTEX
            | vk::ShaderStageFlags::FRAGMENT
            | vk::ShaderStageFlags::COMPUTE;
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|&(b, ty, _)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: valid create info.
        let layout = unsafe { d.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let mut this = DescriptorSet {
            ctx: ctx.clone(),
            layout,
            pool: vk::DescriptorPool::null(),
            raw: vk::DescriptorSet::null(),
        };
        let sizes: Vec<_> = bindings
            .iter()
            .map(|&(_, ty, _)| vk::DescriptorPoolSize {
                ty,
                descriptor_count: 1,
            })
            .collect();
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid create info.
        this.pool =
            unsafe { d.create_descriptor_pool(&pool_info, None) }.vk("vkCreateDescriptorPool")?;
        let layouts = [layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(this.pool)
            .set_layouts(&layouts);
        // SAFETY: pool sized for exactly this set.
        this.raw = unsafe { d.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
            .iter()
            .map(|&(_, _, buf)| {
                [vk::DescriptorBufferInfo {
                    buffer: buf.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]
            })
            .collect();
        let writes: Vec<_> = bindings
            .iter()
            .zip(&infos)
            .map(|(&(b, ty, _), info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(this.raw)
                    .dst_binding(b)
                    .descriptor_type(ty)
                    .buffer_info(info)
            })
            .collect();
        // A capture context's buffers have no memory (RADV's null device has none), and its
        // sets are never bound to work: only their layouts matter, so they stay unwritten.
        if !ctx.captures_executables() {
            // SAFETY: writes reference live buffers and the set allocated above.
            unsafe { d.update_descriptor_sets(&writes, &[]) };
        }
        Ok(this)
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // SAFETY: no work in flight; destroying the pool frees the set.
        unsafe {
            if self.pool != vk::DescriptorPool::null() {
                self.ctx.device.destroy_descriptor_pool(self.pool, None);
            }
            self.ctx
                .device
                .destroy_descriptor_set_layout(self.layout, None);
        }
    }
}

/// One vertex stream: a tightly packed buffer bound at `location` (binding = location).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VertexStream {
    pub location: u32,
    pub format: Format,
    pub stride: u32,
}

/// Everything that defines a graphics pipeline.
pub struct PipelineDesc<'a> {
    pub vertex: &'a ShaderModule,
    pub fragment: &'a ShaderModule,
    pub streams: &'a [VertexStream],
    pub color_formats: &'a [Format],
    pub depth_format: Option<Format>,
    pub descriptors: Option<&'a DescriptorSet>,
    /// Fragment-stage specialization constants: (constant id, u32 value).
    pub specialization: &'a [(u32, u32)],
    /// Cull back faces, this winding being front; None: no culling.
    pub cull_front: Option<FrontFace>,
    /// How the depth attachment (when there is one) is tested and written.
    pub depth: DepthMode,
    /// Write the colour attachments (false: a depth-only pass with the same attachments).
    pub color_write: bool,
}

/// The depth test of a pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DepthMode {
    /// LESS, writing depth: the one-pass default.
    Less,
    /// LESS_OR_EQUAL without writing: the shading pass after a depth pre-pass drawn with the
    /// same vertex positions, so that only the visible fragment of each pixel passes.
    EqualAfterPrepass,
}

/// A graphics pipeline with its layout (triangle list, back faces culled or not, depth test
/// LESS).
pub struct GraphicsPipeline {
    pub(super) ctx: Arc<Context>,
    pub(crate) raw: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
}

impl GraphicsPipeline {
    pub fn new(ctx: &Arc<Context>, desc: &PipelineDesc) -> Result<Self> {
        let d = &ctx.device;
        let set_layouts: Vec<_> = desc.descriptors.iter().map(|s| s.layout).collect();
        let layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        // SAFETY: valid create info.
        let layout =
            unsafe { d.create_pipeline_layout(&layout_info, None) }.vk("vkCreatePipelineLayout")?;
        let mut this = GraphicsPipeline {
            ctx: ctx.clone(),
            raw: vk::Pipeline::null(),
            layout,
        };

        let (spec_entries, spec_data) = specialization(desc.specialization);
        let spec = vk::SpecializationInfo::default()
            .map_entries(&spec_entries)
            .data(bytemuck::cast_slice(&spec_data));
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(desc.vertex.raw)
                .name(c"main")
                .specialization_info(&spec),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(desc.fragment.raw)
                .name(c"main")
                .specialization_info(&spec),
        ];
        let (bindings, attributes) = vertex_streams(desc);
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes);
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = raster_state(desc);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = depth_state(desc);
        let blend_attachments: Vec<_> = desc
            .color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default().color_write_mask(
                    if desc.color_write {
                        vk::ColorComponentFlags::RGBA
                    } else {
                        vk::ColorComponentFlags::empty()
                    },
                )
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats: Vec<vk::Format> = desc.color_formats.iter().map(|f| f.raw()).collect();
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(desc.depth_format.map_or(vk::Format::UNDEFINED, Format::raw));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .flags(ctx.pipeline_flags())
            .push_next(&mut rendering);
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let pipelines =
            unsafe { d.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, r)| Error::Vulkan {
                    call: "vkCreateGraphicsPipelines",
                    result: format!("{r:?}"),
                })?;
        this.raw = pipelines[0];
        Ok(this)
    }
}

/// Vertex input of [`GraphicsPipeline::new`]: one binding per stream, at its location.
fn vertex_streams(
    desc: &PipelineDesc,
) -> (
    Vec<vk::VertexInputBindingDescription>,
    Vec<vk::VertexInputAttributeDescription>,
) {
    let bindings: Vec<_> = desc
        .streams
        .iter()
        .map(|s| vk::VertexInputBindingDescription {
            binding: s.location,
            stride: s.stride,
            input_rate: vk::VertexInputRate::VERTEX,
        })
        .collect();
    let attributes: Vec<_> = desc
        .streams
        .iter()
        .map(|s| vk::VertexInputAttributeDescription {
            location: s.location,
            binding: s.location,
            format: s.format.raw(),
            offset: 0,
        })
        .collect();
    (bindings, attributes)
}

/// Rasterisation state of [`GraphicsPipeline::new`]: filled, back faces culled when
/// `cull_front` names the front face.
fn raster_state(desc: &PipelineDesc) -> vk::PipelineRasterizationStateCreateInfo<'static> {
    vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(if desc.cull_front.is_some() {
            vk::CullModeFlags::BACK
        } else {
            vk::CullModeFlags::NONE
        })
        .front_face(
            desc.cull_front
                .map_or(vk::FrontFace::COUNTER_CLOCKWISE, FrontFace::raw),
        )
        .line_width(1.0)
}

/// Depth state of [`GraphicsPipeline::new`]: tested when there is a depth attachment, written
/// unless equal-after-prepass.
fn depth_state(desc: &PipelineDesc) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    let (compare, write) = match desc.depth {
        DepthMode::Less => (vk::CompareOp::LESS, true),
        DepthMode::EqualAfterPrepass => (vk::CompareOp::LESS_OR_EQUAL, false),
    };
    vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(desc.depth_format.is_some())
        .depth_write_enable(desc.depth_format.is_some() && write)
        .depth_compare_op(compare)
}

/// The map entries and data of specialization constants (constant id, u32 value).
fn specialization(constants: &[(u32, u32)]) -> (Vec<vk::SpecializationMapEntry>, Vec<u32>) {
    let entries = constants
        .iter()
        .enumerate()
        .map(|(i, &(id, _))| vk::SpecializationMapEntry {
            constant_id: id,
            offset: 4 * i as u32,
            size: 4,
        })
        .collect();
    (entries, constants.iter().map(|&(_, v)| v).collect())
}

/// A compute pipeline with its layout (one descriptor set).
pub struct ComputePipeline {
    pub(super) ctx: Arc<Context>,
    pub(crate) raw: vk::Pipeline,
    pub(crate) layout: vk::PipelineLayout,
}

impl ComputePipeline {
    /// `specialization`: (constant id, u32 value).
    pub fn new(
        ctx: &Arc<Context>,
        module: &ShaderModule,
        descriptors: &DescriptorSet,
        specialization: &[(u32, u32)],
    ) -> Result<Self> {
        let d = &ctx.device;
        let set_layouts = [descriptors.layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        // SAFETY: valid create info.
        let layout =
            unsafe { d.create_pipeline_layout(&layout_info, None) }.vk("vkCreatePipelineLayout")?;
        let mut this = ComputePipeline {
            ctx: ctx.clone(),
            raw: vk::Pipeline::null(),
            layout,
        };
        let (spec_entries, spec_data) = self::specialization(specialization);
        let spec = vk::SpecializationInfo::default()
            .map_entries(&spec_entries)
            .data(bytemuck::cast_slice(&spec_data));
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw)
            .name(c"main")
            .specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout)
            .flags(ctx.pipeline_flags());
        // SAFETY: every pointer in `info` refers to locals alive for the call.
        let pipelines =
            unsafe { d.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, r)| Error::Vulkan {
                    call: "vkCreateComputePipelines",
                    result: format!("{r:?}"),
                })?;
        this.raw = pipelines[0];
        Ok(this)
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: no work in flight; handles owned by self.
        unsafe {
            if self.raw != vk::Pipeline::null() {
                self.ctx.device.destroy_pipeline(self.raw, None);
            }
            self.ctx.device.destroy_pipeline_layout(self.layout, None);
        }
    }
}

impl Drop for GraphicsPipeline {
    fn drop(&mut self) {
        // SAFETY: no work in flight; handles owned by self.
        unsafe {
            if self.raw != vk::Pipeline::null() {
                self.ctx.device.destroy_pipeline(self.raw, None);
            }
            self.ctx.device.destroy_pipeline_layout(self.layout, None);
        }
    }
}
