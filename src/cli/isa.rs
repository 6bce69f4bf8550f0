//! `shadelab isa`: the methods compiled for GPU generations of several vendors without their
//! GPUs (AMD through RADV's null device, Intel, NVIDIA and AMD TeraScale through Mesa's
//! drm-shims); see [`crate::isa`] and its vendor seam [`crate::isa::route`]. The hidden `--child REQUEST` runs one
//! family inside the process the parent started with the driver selected in its environment.
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;

use crate::error::{Error, Result};
use crate::isa::{self, IsaOptions};

#[derive(Args, Debug)]
pub(super) struct IsaArgs {
    /// Comma-separated method identifiers, or `all` (phong_exact is always compiled: the ratios'
    /// base).
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Comma-separated family ids, `<vendor>:<chip>` (amd:navi21, intel:tgl, nvidia:nv162,
    /// terascale:cayman; a bare chip name is AMD's), or `all`: every default family of every
    /// vendor (docs/isa.md); a vendor whose route is not set up is reported as such.
    #[arg(long, default_value = "all")]
    families: String,
    /// The RADV Vulkan ICD manifest to load (VK_DRIVER_FILES), e.g. a Mesa 25 build (docs/isa.md);
    /// by default the system's RADV, found among the loader's ICD manifests by its library.
    #[arg(long, value_name = "JSON")]
    driver_files: Option<PathBuf>,
    /// Scene whose timed draw is compiled (specialization constants, streams, culling);
    /// default: the shipped generated torus.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// A bench.json of `shadelab bench` (with isolated costs): per family, Spearman's rank
    /// correlation between the static cost and lavapipe's isolated cost.
    #[arg(long, value_name = "FILE.json")]
    bench: Option<PathBuf>,
    /// A `shadelab compare` output folder (its summary.json); repeatable, the worst error of
    /// each method is taken. With it, a chart per family of error against inverse throughput.
    #[arg(long, value_name = "DIR")]
    compare: Vec<PathBuf>,
    #[command(flatten)]
    precision: super::PrecisionArgs,
    /// Also compile this compute SPIR-V as is (one storage buffer at binding 0); repeatable.
    #[arg(long, value_name = "FILE.spv", hide = true)]
    probe: Vec<PathBuf>,
    /// Instead of the methods: compile micro-kernels (chains of FMA, rsqrt, rcp, dot,
    /// normalize) on the families and write DIR/calibration.json, each family's model ratios
    /// (rsqrt : FMA, ...) beside published measurements of real GPUs of its architecture
    /// (docs/calibration.md).
    #[arg(long, conflicts_with_all = ["methods", "bench", "compare", "probe", "scene", "driver_files"])]
    calibrate: bool,
    /// Output directory (isa.json, isa.csv, asm/; calibration.json with --calibrate).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    #[command(flatten)]
    pub(super) store: super::StoreArgs,
}

impl IsaArgs {
    /// What isa reads and writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("isa.json"),
            inputs: self
                .scene
                .iter()
                .chain(&self.bench)
                .chain(&self.probe)
                .map(PathBuf::as_path)
                .collect(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_isa(args: IsaArgs) -> Result<ExitCode> {
    if args.calibrate {
        return calibrate(args);
    }
    let out = args.out;
    let mut methods = super::select_methods(&args.methods)?;
    let exact = crate::method::phong_exact();
    if !methods.iter().any(|m| m.name == exact.name) {
        methods.insert(0, exact);
    }
    let families =
        super::checks::family_list(&args.families).unwrap_or_else(isa::route::default_family_ids);
    let exe = std::env::current_exe()
        .map_err(|e| Error::Device(format!("cannot find shadelab's own binary: {e}")))?;
    let opts = IsaOptions {
        methods,
        families,
        driver_files: args.driver_files,
        scene: args.scene,
        exe,
        precision: args.precision.precision,
        probes: args.probe,
        store: isa::store::default_store(),
    };
    let bench = match &args.bench {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| Error::io(p, e))?;
            Some(
                serde_json::from_str::<serde_json::Value>(&text)
                    .map_err(|e| Error::input(p, None, format!("not JSON: {e}")))?,
            )
        }
        None => None,
    };
    let start = Instant::now();
    let mut report = isa::run(&opts, &|line| log::info!("{line}"))?;
    if report.supported().is_empty() {
        // Nothing measured is a failed run, never "0 compiled" at exit 0 with an isa.json.
        let why: Vec<String> = report
            .families
            .iter()
            .map(|f| format!("{}: {}", f.family, f.status))
            .collect();
        return Err(Error::Device(format!(
            "isa: none of the {} families compiled ({}); set their routes up (docs/isa.md) or \
             name families that are",
            report.families.len(),
            why.join("; ")
        )));
    }
    if let Some(b) = &bench {
        report.spearman = report.against_bench(b)?;
    }
    if args.compare.is_empty() {
        report.charts_note = Some(
            "no --compare folder: the error axis comes from `shadelab compare` summary.json \
             files (docs/isa.md), so no chart was drawn"
                .into(),
        );
    } else {
        let err = isa::chart::errors(&args.compare)?;
        report.charts = isa::chart::write(&out, &report, &err, true)?;
    }
    isa::files::write(&out, &report)?;
    print!("{}", report.text_table());
    println!(
        "{} families ({} compiled), {} rows in {:.2} s; {}",
        report.families.len(),
        report.supported().len(),
        report.results.len(),
        start.elapsed().as_secs_f64(),
        out.join("isa.json").display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `isa --calibrate`: the kernels on the families, calibration.json, a line per check.
fn calibrate(args: IsaArgs) -> Result<ExitCode> {
    let families = super::checks::family_list(&args.families).unwrap_or_default();
    let exe = std::env::current_exe()
        .map_err(|e| Error::Device(format!("cannot find shadelab's own binary: {e}")))?;
    let cal = isa::calibrate::run(exe, families, &args.out, &|line| log::info!("{line}"))?;
    if !cal.families.iter().any(|f| f.supported) {
        return Err(Error::Device(
            "isa --calibrate: no family compiled; set their routes up (docs/isa.md)".into(),
        ));
    }
    println!(
        "{:<20} {:>8} {:>8} {:>8} {:>9}  checks",
        "family", "rsqrt", "rcp", "dot", "normalize"
    );
    for f in cal.families.iter().filter(|f| f.supported) {
        let r = |k| match f.model.get(&k) {
            _ if f.fused.contains(&k) => "fused".to_string(),
            Some(v) => format!("{v:.2}"),
            None => "-".to_string(),
        };
        use isa::calibrate::Ratio;
        let checks: Vec<String> = f
            .checks
            .iter()
            .map(|c| {
                format!(
                    "{} {:.2} vs {} {}{}",
                    c.ratio.name(),
                    c.model,
                    if c.measured_low == c.measured_high {
                        format!("{}", c.measured_low)
                    } else {
                        format!("{}-{}", c.measured_low, c.measured_high)
                    },
                    c.gpu,
                    if c.disagrees { " (disagrees)" } else { "" }
                )
            })
            .collect();
        println!(
            "{:<20} {:>8} {:>8} {:>8} {:>9}  {}",
            f.family,
            r(Ratio::Rsqrt),
            r(Ratio::Rcp),
            r(Ratio::Dot),
            r(Ratio::Normalize),
            checks.join("; ")
        );
    }
    for line in cal.families.iter().flat_map(isa::calibrate::not_positive) {
        log::warn!("isa --calibrate: {line}: this model cannot rank programs");
    }
    println!(
        "{} families ({} compiled) in {:.1} s; {}",
        cal.families.len(),
        cal.families.iter().filter(|f| f.supported).count(),
        cal.elapsed_s,
        args.out.join("calibration.json").display()
    );
    Ok(ExitCode::SUCCESS)
}
