//! `shadelab mesh`: write a generated mesh, or regenerate the shipped ones.
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::error::{Error, Result};
use crate::geometry;

// `shadelab mesh` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct MeshArgs {
    /// Generator: uv_sphere, icosphere, torus or cube.
    #[arg(required_unless_present = "shipped")]
    generator: Option<String>,
    /// Generator parameters as key=value.
    params: Vec<String>,
    /// Output OBJ file.
    #[arg(long, value_name = "FILE.obj", required_unless_present = "shipped")]
    out: Option<PathBuf>,
    /// Write every shipped mesh into DIR instead.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["generator", "out"])]
    shipped: Option<PathBuf>,
}

impl MeshArgs {
    /// What mesh writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            files: self.out.iter().map(|o| ("--out", o.as_path())).collect(),
            dir: self.shipped.as_deref().map(|d| ("--shipped", d)),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_mesh(a: MeshArgs) -> Result<ExitCode> {
    let MeshArgs {
        generator,
        params,
        out,
        shipped,
    } = a;
    if let Some(dir) = shipped {
        for p in geometry::write_shipped(&dir)? {
            log::info!("wrote {}", p.display());
        }
        return Ok(ExitCode::SUCCESS);
    }
    let (Some(name), Some(out)) = (generator, out) else {
        return Err(Error::Usage(
            "give a generator and --out FILE.obj, or --shipped DIR".into(),
        ));
    };
    let g = geometry::parse_generator_args(&name, &params)?;
    let m = g.build()?;
    geometry::write_obj(&m, &out)?;
    log::info!("wrote {} ({} triangles)", out.display(), m.triangle_count());
    Ok(ExitCode::SUCCESS)
}
