//! `shadelab plan`: prints [`crate::plan::plan`] as text or JSON.
use std::process::ExitCode;

use super::*;
use crate::error::Result;

// `shadelab plan` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct PlanArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    device: DeviceArgs,
    /// JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Also choose per triangle the cheapest method whose f64 error stays within this
    /// budget (the largest colour error, linear, max over the channels; a number or a
    /// fraction like 4/255), as `auto` would, and count them.
    #[arg(long, value_name = "E", value_parser = ErrorBudget::parse)]
    error_budget: Option<ErrorBudget>,
}

pub(super) fn cmd_plan(a: &PlanArgs) -> Result<ExitCode> {
    let (scene_args, dev, json, budget) = (&a.scene, &a.device, a.json, a.error_budget);
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
