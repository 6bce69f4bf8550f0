//! `shadelab plan`: prints [`crate::plan::plan`] as text or JSON.
use std::process::ExitCode;

use super::*;
use crate::error::Result;

pub(super) fn cmd_plan(scene_args: &SceneArgs, json: bool) -> Result<ExitCode> {
    let scene = load_scene(scene_args)?;
    let p = crate::plan::plan(&scene);
    if json {
        let text = serde_json::to_string_pretty(&p).map_err(|e| Error::output("plan JSON", e))?;
        println!("{text}");
    } else {
        print!("{}", p.text());
    }
    Ok(ExitCode::SUCCESS)
}
