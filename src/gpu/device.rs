//! Which Vulkan device draws, as data: the CLI's `--device`, `--validate` and `--precision`
//! parsed once; a child process is given the same value in its request and opens the same
//! device ([`DeviceSpec::renderer`]).
use serde::{Deserialize, Serialize};

use super::vk::{Context, ContextDesc};
use super::Renderer;
use crate::error::Result;
use crate::method::Precision;

/// A device and the precision of its method programs.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct DeviceSpec {
    /// Case-insensitive substring of the device name; `None`: lavapipe.
    pub device: Option<String>,
    /// Under the Khronos validation layer.
    pub validate: bool,
    pub precision: Precision,
}

impl DeviceSpec {
    /// The renderer on this device in this precision (an error when the device lacks float16
    /// arithmetic for a float16 spec).
    pub fn renderer(&self) -> Result<Renderer> {
        let ctx = Context::new(&ContextDesc {
            device: self.device.clone(),
            validate: self.validate,
        })?;
        Renderer::new(ctx).with_precision(self.precision)
    }
}
