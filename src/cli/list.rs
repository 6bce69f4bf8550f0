//! `shadelab list`: the method table as text or JSON.
use std::process::ExitCode;

use clap::Args;

use crate::error::{Error, Result};

// `shadelab list` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct ListArgs {
    #[arg(long)]
    pub(super) json: bool,
}

/// The table, then the user methods of `--method-file` (which have no software form, but for
/// the tuned files of `shadelab tune`).
pub(super) fn cmd_list(json: bool) -> Result<ExitCode> {
    if json {
        let text = serde_json::to_string_pretty(&serde_json::json!({
            "version": 1,
            "methods": crate::method::all()
                .into_iter()
                .map(judged)
                .collect::<Result<Vec<_>>>()?,
            // How each method runs under `--engine software` (src/software/): its scanline
            // form, or its per-pixel form where it has none (a tuned file's included).
            "software_forms": crate::method::all()
                .into_iter()
                .filter(|m| m.kernel.exists())
                .map(|m| (m.name, crate::software::form_of(m)))
                .collect::<std::collections::BTreeMap<_, _>>(),
        }))
        .map_err(|e| Error::output("the method list", e))?;
        println!("{text}");
    } else {
        for m in crate::method::all() {
            println!("{:<22} {}", m.name, m.description);
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Method `m` as JSON, its claims judged now by their checks (a bound the proof covers says
/// basis proven, with its proven upper bound beside the found value; see docs/proof.md).
fn judged(m: &'static crate::method::Method) -> Result<serde_json::Value> {
    Ok(crate::prove::bounds::json(m))
}
