//! `shadelab shaders`: compile glsl/ to spirv/, or check that spirv/ is fresh.
use std::path::Path;
use std::process::ExitCode;

use crate::error::Result;
use crate::gpu::shaders;
pub(super) fn cmd_shaders(check: bool, glsl: &Path, spirv: &Path) -> Result<ExitCode> {
    if check {
        shaders::check_fresh(glsl, spirv)?;
        println!("{} is fresh", spirv.display());
    } else {
        let n = shaders::write_spirv(glsl, spirv)?;
        println!("wrote {n} SPIR-V modules to {}", spirv.display());
    }
    Ok(ExitCode::SUCCESS)
}
