//! `shadelab prove`: runs [`crate::prove::run`], prints its table and writes proof.json.
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::Result;
use crate::prove::{self, ProveOptions};

/// The arguments of `shadelab prove`.
#[derive(Debug, Args)]
pub struct ProveArgs {
    /// Comma-separated method identifiers, or `all` (methods out of reach are listed).
    #[arg(long, default_value = "all", value_parser = super::checks::method_list)]
    methods: String,
    /// Largest angle between any two vertex normals, degrees (0, 180]. Each figure is for
    /// one of two domains: `triangle`, any triangle (three free unit normals pairwise at most
    /// DEG apart, any weights); `edge`, stress's cases (N0, N1 at most DEG apart, N2 their
    /// bisector), a part of it.
    #[arg(long, value_name = "DEG")]
    max_angle: f64,
    /// Relative gap at which a bound counts as tight.
    #[arg(long, default_value_t = 0.01)]
    tolerance: f64,
    /// Phong exponent of the colour bound (default: the scenes' material).
    #[arg(long)]
    shininess: Option<f64>,
    /// Output directory (proof.json, cases/<method>_<domain>_<metric>.json).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

impl ProveArgs {
    /// What prove writes ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("proof.json"),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_prove(a: &ProveArgs) -> Result<ExitCode> {
    let methods = select_methods(&a.methods)?;
    for m in &methods {
        m.require_twin("prove")?;
    }
    let out: &Path = &a.out;
    let opts = ProveOptions {
        max_angle_deg: a.max_angle,
        tolerance: a.tolerance,
        shininess: a.shininess.unwrap_or(scene::Material::default().shininess),
        progress: true,
        ..ProveOptions::default()
    };
    let report = prove::run(&methods, &opts)?;
    prove::write(out, &report)?;
    print!("{}", prove::table(&report));
    println!("wrote {}", out.join("proof.json").display());
    Ok(ExitCode::SUCCESS)
}
