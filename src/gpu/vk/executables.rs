//! What the driver compiled a pipeline into (VK_KHR_pipeline_executable_properties): per
//! executable (one per shader stage on RADV), the compiler's statistics with their own names,
//! descriptions and typed values, and its internal representations (NIR, ACO IR, disassembly)
//! as text. Only pipelines of a [`Context::for_executables`] context capture them; the calls
//! query the pipeline, they never submit work (RADV's null device cannot execute).
use std::ffi::{c_char, c_void, CStr};
use std::sync::Arc;

use ash::vk;

use super::conv::VkContext;
use super::{ComputePipeline, Context, GraphicsPipeline};
use crate::error::{Error, Result};

/// A statistic's value, typed as the driver reports it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum StatValue {
    Bool(bool),
    Int(i64),
    Uint(u64),
    Float(f64),
}

impl StatValue {
    /// The value as a number (booleans 0 or 1).
    pub fn as_f64(self) -> f64 {
        match self {
            StatValue::Bool(b) => f64::from(u8::from(b)),
            StatValue::Int(i) => i as f64,
            StatValue::Uint(u) => u as f64,
            StatValue::Float(f) => f,
        }
    }
}

/// One compiler statistic, with the driver's own name and description.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Statistic {
    pub name: String,
    pub description: String,
    pub value: StatValue,
}

/// One internal representation (e.g. "Assembly"), as text.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Representation {
    pub name: String,
    pub description: String,
    pub text: String,
}

/// One executable of a pipeline: a compiled shader stage.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Executable {
    /// The driver's name ("Fragment Shader" on Mesa 22.3, "fragment" on Mesa 25).
    pub name: String,
    pub description: String,
    /// "vertex", "fragment" or "compute" (from the stage flags), or the flags' debug form.
    pub stage: String,
    pub subgroup_size: u32,
    pub statistics: Vec<Statistic>,
    pub representations: Vec<Representation>,
}

impl GraphicsPipeline {
    /// The executables the driver made of this pipeline, with statistics and representations.
    /// An error when its context does not capture them ([`Context::for_executables`]).
    pub fn executables(&self) -> Result<Vec<Executable>> {
        executables(&self.ctx, self.raw)
    }
}

impl ComputePipeline {
    /// [`GraphicsPipeline::executables`] of a compute pipeline.
    pub fn executables(&self) -> Result<Vec<Executable>> {
        executables(&self.ctx, self.raw)
    }
}

fn text(chars: &[c_char]) -> String {
    // SAFETY: c_char and u8 have the same size and alignment; the slice stays borrowed.
    let bytes: &[u8] = unsafe { std::slice::from_raw_parts(chars.as_ptr().cast(), chars.len()) };
    CStr::from_bytes_until_nul(bytes)
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_else(|_| String::from_utf8_lossy(bytes).into_owned())
}

fn stage_name(flags: vk::ShaderStageFlags) -> String {
    match flags {
        vk::ShaderStageFlags::VERTEX => "vertex".into(),
        vk::ShaderStageFlags::FRAGMENT => "fragment".into(),
        vk::ShaderStageFlags::COMPUTE => "compute".into(),
        f => format!("{f:?}").to_lowercase(),
    }
}

fn executables(ctx: &Arc<Context>, pipeline: vk::Pipeline) -> Result<Vec<Executable>> {
    let ext = ctx.executables.as_ref().ok_or_else(|| {
        Error::Internal(
            "pipeline executables asked of a context made without capture \
             (use Context::for_executables)"
                .into(),
        )
    })?;
    let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
    // SAFETY: the pipeline is alive (borrowed through its wrapper) and was created with the
    // capture flags on this device.
    let props = unsafe { ext.get_pipeline_executable_properties(&info) }
        .vk("vkGetPipelineExecutablePropertiesKHR")?;
    let mut out = Vec::with_capacity(props.len());
    for (i, p) in props.iter().enumerate() {
        let exe = vk::PipelineExecutableInfoKHR::default()
            .pipeline(pipeline)
            .executable_index(i as u32);
        // SAFETY: as above; index i < the executable count the driver returned.
        let stats = unsafe { ext.get_pipeline_executable_statistics(&exe) }
            .vk("vkGetPipelineExecutableStatisticsKHR")?;
        let statistics = stats
            .iter()
            .map(|s| Statistic {
                name: text(&s.name),
                description: text(&s.description),
                // SAFETY: `format` names the union member the driver wrote.
                value: unsafe {
                    match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => {
                            StatValue::Bool(s.value.b32 != vk::FALSE)
                        }
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => {
                            StatValue::Int(s.value.i64)
                        }
                        vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => {
                            StatValue::Float(s.value.f64)
                        }
                        _ => StatValue::Uint(s.value.u64),
                    }
                },
            })
            .collect();
        out.push(Executable {
            name: text(&p.name),
            description: text(&p.description),
            stage: stage_name(p.stages),
            subgroup_size: p.subgroup_size,
            statistics,
            representations: representations(ext, &exe)?,
        });
    }
    Ok(out)
}

/// The internal representations of one executable: a first call for their sizes, a second
/// with buffers of those sizes. Binary representations are kept as lossy text.
fn representations(
    ext: &ash::khr::pipeline_executable_properties::Device,
    exe: &vk::PipelineExecutableInfoKHR,
) -> Result<Vec<Representation>> {
    // SAFETY: as in `executables`; this call fills counts and sizes only (p_data null).
    let sized = unsafe { ext.get_pipeline_executable_internal_representations(exe) }
        .vk("vkGetPipelineExecutableInternalRepresentationsKHR")?;
    let mut buffers: Vec<Vec<u8>> = sized.iter().map(|r| vec![0u8; r.data_size]).collect();
    let mut reprs: Vec<vk::PipelineExecutableInternalRepresentationKHR> = sized
        .iter()
        .zip(&mut buffers)
        .map(|(r, b)| vk::PipelineExecutableInternalRepresentationKHR {
            data_size: r.data_size,
            p_data: b.as_mut_ptr() as *mut c_void,
            ..Default::default()
        })
        .collect();
    let mut count = reprs.len() as u32;
    // SAFETY: `reprs` holds `count` structures whose p_data point at buffers of data_size
    // bytes, alive (in `buffers`) until the texts are copied out below.
    let r = unsafe {
        (ext.fp()
            .get_pipeline_executable_internal_representations_khr)(
            ext.device(),
            exe,
            &mut count,
            reprs.as_mut_ptr(),
        )
    };
    if r != vk::Result::SUCCESS && r != vk::Result::INCOMPLETE {
        return Err(Error::Vulkan {
            call: "vkGetPipelineExecutableInternalRepresentationsKHR",
            result: format!("{r:?}"),
        });
    }
    Ok(reprs
        .iter()
        .zip(&buffers)
        .take(count as usize)
        .map(|(r, b)| {
            let n = r.data_size.min(b.len());
            let bytes = &b[..n];
            let end = bytes.iter().position(|&c| c == 0).unwrap_or(n);
            Representation {
                name: text(&r.name),
                description: text(&r.description),
                text: String::from_utf8_lossy(&bytes[..end]).into_owned(),
            }
        })
        .collect())
}
