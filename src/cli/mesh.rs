//! `shadelab mesh`: write a generated mesh, or regenerate the shipped ones.
use std::path::PathBuf;
use std::process::ExitCode;

use crate::error::{Error, Result};
use crate::geometry;
pub(super) fn cmd_mesh(
    generator: Option<String>,
    params: &[String],
    out: Option<PathBuf>,
    shipped: Option<PathBuf>,
) -> Result<ExitCode> {
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
    let g = geometry::parse_generator_args(&name, params)?;
    let m = g.build()?;
    geometry::write_obj(&m, &out)?;
    log::info!("wrote {} ({} triangles)", out.display(), m.triangle_count());
    Ok(ExitCode::SUCCESS)
}
