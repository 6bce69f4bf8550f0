//! `shadelab plan`: prints [`crate::plan::plan`] as text or JSON.
use std::process::ExitCode;

use super::*;
use crate::error::Result;

pub(super) fn cmd_plan(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    json: bool,
    budget: Option<crate::auto::ErrorBudget>,
) -> Result<ExitCode> {
    let scene = load_scene(scene_args)?;
    let p = match budget {
        None => crate::plan::plan(&scene),
        Some(b) => {
            let r = renderer(dev)?;
            let start = std::time::Instant::now();
            let order = crate::plan::auto_order(r.context())?;
            let cost_ms = start.elapsed().as_secs_f64() * 1e3;
            crate::plan::plan_with_auto(&scene, &order, b, cost_ms)
        }
    };
    if json {
        let text = serde_json::to_string_pretty(&p).map_err(|e| Error::output("plan JSON", e))?;
        println!("{text}");
    } else {
        print!("{}", p.text());
    }
    Ok(ExitCode::SUCCESS)
}
