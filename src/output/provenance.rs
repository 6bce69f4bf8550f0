//! Where a result came from: tool version, git revision, device, driver, CPU, command line.
use serde::{Deserialize, Serialize};

/// `shadelab --version`: the version, the git revision and how the shader compiler was linked
/// (build.rs's choice: which archives or library, from which folder).
pub const LONG_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("SHADELAB_GIT_REVISION"),
    ")\nshader compiler: ",
    env!("SHADELAB_SHADERC_LINK")
);

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
    /// The user methods' files (`--method-file`): id, path, SHA-256; absent without one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub method_files: Vec<MethodFile>,
}

/// Which file a run measured: a user method's id, path and SHA-256 (`--method-file`, issue 28;
/// src/method/user.rs records each one it registers here).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodFile {
    pub name: String,
    pub path: String,
    pub sha256: String,
}

static METHOD_FILES: std::sync::RwLock<Vec<MethodFile>> = std::sync::RwLock::new(Vec::new());

/// Records a registered method file: every provenance made from now on names it.
pub fn record_method_file(f: MethodFile) {
    if let Ok(mut v) = METHOD_FILES.write() {
        v.push(f);
    }
}

/// The method files recorded so far, in registration order.
pub fn method_files() -> Vec<MethodFile> {
    METHOD_FILES.read().map(|v| v.clone()).unwrap_or_default()
}

impl Provenance {
    /// The provenance of a result computed on a device named `device`, whose driver is
    /// `driver` (`driver_info`: the driver's version string, where Mesa and LLVM versions are
    /// found) and whose Vulkan API version is `vulkan_api`.
    pub fn new(device: &str, driver: &str, driver_info: &str, vulkan_api: &str) -> Self {
        let after = |key: &str| {
            driver_info.find(key).map(|i| {
                driver_info[i + key.len()..]
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
            device: device.into(),
            driver: driver.into(),
            driver_info: driver_info.into(),
            vulkan_api: vulkan_api.into(),
            mesa_version: after("Mesa "),
            llvm_version: after("LLVM "),
            method_files: method_files(),
        }
    }
}

/// The CPU's model name from /proc/cpuinfo (`unknown` where there is none).
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
