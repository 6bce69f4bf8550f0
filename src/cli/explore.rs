//! `shadelab explore`: serves the page of [`crate::explore`] until Ctrl-C or SIGTERM.
use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::error::{Error, Result};

// `shadelab explore` (its help is the variant's doc comment).
#[derive(Args, Debug)]
pub(super) struct ExploreArgs {
    /// The scene files (*.toml) the page offers.
    #[arg(long, value_name = "DIR", default_value = "scenes")]
    scenes: PathBuf,
    /// Mesh files (OBJ, glTF, PLY) the page offers beside the scenes.
    #[arg(long, value_name = "DIR")]
    models: Option<PathBuf>,
    /// The port to listen on (default: a free one).
    #[arg(long, value_name = "P", default_value_t = 0)]
    port: u16,
    /// The address to listen on: loopback unless you say otherwise (the page runs compilers
    /// and a Vulkan driver on what it is sent; the token still guards it).
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1")]
    bind: IpAddr,
    /// A report's folder (`shadelab report --out DIR`): the page shows each method's valid
    /// angle from its stress.json. Default: out/report when it has one.
    #[arg(long, value_name = "DIR")]
    report: Option<PathBuf>,
    /// The longest a render or one family's compile may take, seconds (its worker is stopped
    /// past it; the suite shortens it).
    #[arg(long, value_name = "SECONDS", default_value_t = 60, hide = true)]
    deadline: u64,
    /// Serve the page's files (index.html, explore.js, explore.css) from this folder instead of
    /// the copies built into the binary (the suite's broken page).
    #[arg(long, value_name = "DIR", hide = true)]
    assets: Option<PathBuf>,
}

pub(super) fn cmd_explore(a: &ExploreArgs) -> Result<ExitCode> {
    let exe = std::env::current_exe()
        .map_err(|e| Error::Internal(format!("explore: where is this binary? {e}")))?;
    if !a.bind.is_loopback() {
        log::warn!(
            "explore: listening on {}, not loopback: anyone who can reach it and has the token \
             runs compilers here",
            a.bind
        );
    }
    crate::workers::configure(crate::workers::Limits {
        deadline: std::time::Duration::from_secs(a.deadline),
        ..crate::workers::Limits::default()
    });
    let opts = crate::explore::ExploreOptions {
        scenes: a.scenes.clone(),
        models: a.models.clone(),
        bind: a.bind,
        port: a.port,
        deadline: std::time::Duration::from_secs(a.deadline),
        assets: a.assets.clone(),
        report: a.report.clone().or_else(|| {
            let default = PathBuf::from("out/report");
            default
                .join("stress/stress.json")
                .is_file()
                .then_some(default)
        }),
        exe,
    };
    crate::explore::serve(&opts, &|url| {
        use std::io::Write;
        println!("{url}");
        let _ = std::io::stdout().flush();
        log::info!("shadelab explore: open {url} (Ctrl-C stops it)");
    })?;
    Ok(ExitCode::SUCCESS)
}
