//! `shadelab stress`: runs [`crate::stress::run`] and writes its outputs, or replays one case.
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::stress::{self, StressOptions};

// `shadelab stress` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct StressArgs {
    #[command(flatten)]
    device: DeviceArgs,
    /// Comma-separated method identifiers, or `all`.
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Output directory (stress.json, charts, validity/<method>.png, cases/<method>.json).
    #[arg(long, value_name = "DIR", required_unless_present = "replay")]
    out: Option<PathBuf>,
    /// Evaluate one case again (a cases/<method>.json, or a worst_case of stress.json).
    #[arg(long, value_name = "CASE.json", conflicts_with = "out")]
    replay: Option<PathBuf>,
    /// Max abs colour error (linear) within which a case is valid.
    #[arg(long, default_value_t = 1.0 / 255.0, value_parser = parse_threshold)]
    threshold: f64,
    /// Local-search rounds around each method's worst case (0: grid only; at most 1000).
    #[arg(long, default_value_t = 8, value_parser = count::<0, 1000>)]
    refine: usize,
    /// (`--replay` takes the precision recorded in the case file.)
    #[command(flatten)]
    precision: PrecisionArgs,
}

impl StressArgs {
    /// What stress reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            marker: Some("stress.json"),
            dir: self.out.as_deref().map(|o| ("--out", o)),
            inputs: self.replay.iter().map(PathBuf::as_path).collect(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_stress(a: &StressArgs) -> Result<ExitCode> {
    let opts = &StressOptions {
        threshold: a.threshold,
        refine_rounds: a.refine,
        progress: true,
        precision: a.precision.precision,
    };
    let (dev, list) = (&a.device, a.methods.as_str());
    let (out, replay) = (a.out.as_deref(), a.replay.as_deref());
    a.precision.check_engine(dev)?;
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
