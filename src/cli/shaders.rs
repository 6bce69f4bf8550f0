//! `shadelab shaders`: compile glsl/ to spirv/, or check that spirv/ is fresh.
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::error::Result;
use crate::gpu::shaders;

// `shadelab shaders` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct ShadersArgs {
    #[arg(long)]
    check: bool,
    #[arg(long, default_value = "glsl")]
    glsl: PathBuf,
    #[arg(long, default_value = "spirv")]
    spirv: PathBuf,
}

pub(super) fn cmd_shaders(a: &ShadersArgs) -> Result<ExitCode> {
    let (check, glsl, spirv) = (a.check, a.glsl.as_path(), a.spirv.as_path());
    if check {
        shaders::check_fresh(glsl, spirv)?;
        println!("{} is fresh", spirv.display());
    } else {
        let n = shaders::write_spirv(glsl, spirv)?;
        println!("wrote {n} SPIR-V modules to {}", spirv.display());
    }
    Ok(ExitCode::SUCCESS)
}
