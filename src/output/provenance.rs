//! Where a result came from: tool version, git revision, device, driver, CPU, command line.
use serde::{Deserialize, Serialize};

/// The tool, device and scene a summary was made with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub tool: String,
    pub version: String,
    pub git_revision: String,
    pub device: String,
    pub driver: String,
    pub driver_info: String,
    pub vulkan_api: String,
    pub mesa_version: Option<String>,
    pub llvm_version: Option<String>,
}

impl Provenance {
    pub fn new(info: &crate::gpu::vk::DeviceInfo) -> Self {
        let after = |key: &str| {
            info.driver_info.find(key).map(|i| {
                info.driver_info[i + key.len()..]
                    .split(|c: char| c.is_whitespace() || c == ')' || c == ',')
                    .next()
                    .unwrap_or("")
                    .to_string()
            })
        };
        Provenance {
            tool: "shadelab".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            git_revision: env!("SHADELAB_GIT_REVISION").into(),
            device: info.name.clone(),
            driver: info.driver_name.clone(),
            driver_info: info.driver_info.clone(),
            vulkan_api: info.api_version.clone(),
            mesa_version: after("Mesa "),
            llvm_version: after("LLVM "),
        }
    }
}
pub(crate) fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}
