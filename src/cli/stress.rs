//! `shadelab stress`: runs [`crate::stress::run`] and writes its outputs, or replays one case.
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::stress::{self, StressOptions};

pub(super) fn cmd_stress(
    dev: &DeviceArgs,
    list: &str,
    out: Option<&Path>,
    replay: Option<&Path>,
    opts: &StressOptions,
) -> Result<ExitCode> {
    PrecisionArgs {
        precision: opts.precision,
    }
    .check_engine(dev)?;
    let ctx = renderer(dev)?.context().clone();
    if let Some(path) = replay {
        let recorded = stress::replay::load(path)?;
        let r = stress::replay::replay(&ctx, &recorded)?;
        let show = |c: Option<[f64; 3]>| {
            c.map_or("none".to_string(), |c| {
                let bits = c.map(|x| format!("{:08x}", (x as f32).to_bits()));
                format!(
                    "({:.9}, {:.9}, {:.9}) bits {}",
                    c[0],
                    c[1],
                    c[2],
                    bits.join(" ")
                )
            })
        };
        println!("method   {}", r.now.method);
        println!("exact    {}", show(r.now.exact_phong));
        println!("device   {}", show(r.now.device_color));
        println!("recorded {}", show(recorded.device_color));
        let twin = crate::method::find(&r.now.method)?.twin().is_some();
        let no_twin = crate::stress::NO_TWIN;
        match twin {
            true => println!("f64      {}", show(r.now.f64_color)),
            false => println!("f64      {no_twin} (a user method: judged against exact Phong)"),
        }
        let err = |e: Option<f64>| e.map_or("non-finite".into(), |e| format!("{e:.3e}"));
        let f64_err = if twin {
            err(r.now.f64_abs_error)
        } else {
            no_twin.into()
        };
        println!(
            "error    device {}, f64 {f64_err}",
            err(r.now.device_abs_error),
        );
        check_validation(&ctx)?;
        return Ok(match r.bit_identical {
            Some(true) => {
                println!("reproduced: the device colour is bit-identical to the recorded one");
                ExitCode::SUCCESS
            }
            Some(false) => {
                println!("NOT reproduced: the device colour differs from the recorded one");
                ExitCode::from(EXIT_THRESHOLD)
            }
            None => {
                println!("no recorded device colour to compare with");
                ExitCode::SUCCESS
            }
        });
    }
    let out = out.ok_or_else(|| Error::Usage("give --out DIR (or --replay CASE.json)".into()))?;
    let methods = select_methods(list)?;
    let report = stress::run(&ctx, &methods, opts)?;
    stress::write(out, &report)?;
    print!("{}", stress::table(&report));
    check_validation(&ctx)?;
    log::info!(
        "stress: {} methods x {} cases in {:.1} s; wrote {}",
        report.methods.len(),
        report.cases_per_method,
        report.seconds,
        out.join("stress.json").display()
    );
    Ok(ExitCode::SUCCESS)
}
