//! `shadelab merge`: checks the shards of a corpus and writes the corpus tables (see
//! [`crate::corpus::merge`] and [`crate::corpus::tables`]).
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::corpus::{merge, tables};
use crate::error::Result;

#[derive(Args, Debug)]
pub(super) struct MergeArgs {
    /// The shards' output folders (each with its manifest.json).
    #[arg(value_name = "SHARD_DIR", required = true)]
    shards: Vec<PathBuf>,
    /// Output folder (corpus.json, corpus.csv, index.html, meshes/<id>/result.json).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
}

impl MergeArgs {
    /// What merge reads and writes: the output may not be a shard's folder (its
    /// meshes/<id>/result.json would replace the shard's) ([`super::checks::check_paths`]).
    pub(super) fn io(&self) -> super::checks::Io<'_> {
        super::checks::Io {
            dir: Some(("--out", &self.out)),
            marker: Some("corpus.json"),
            input_dirs: self.shards.iter().map(PathBuf::as_path).collect(),
            ..Default::default()
        }
    }
}

pub(super) fn cmd_merge(a: MergeArgs) -> Result<ExitCode> {
    let shards = merge::check(&a.shards)?;
    let meshes = merge::gather(&shards)?;
    let isa = shards
        .iter()
        .map(|s| s.dir.join("isa").join("isa.json"))
        .find(|p| p.is_file());
    let isa = match &isa {
        Some(p) => Some(crate::isa::cost::Compiled {
            report: crate::isa::files::read(p)?,
            evidence: p.display().to_string(),
        }),
        None => None,
    };
    let report = tables::report(&shards, &meshes, isa.as_ref(), &crate::costs::builtin());
    tables::write(&a.out, &report, &meshes)?;
    if report.mixed_machines {
        log::info!(
            "merge: the shards ran on {} machines: error merged, time kept per machine",
            report.machines.len()
        );
    }
    println!("{}", a.out.join("index.html").display());
    log::info!(
        "merge: {} shards, {} meshes, {} failed -> {}",
        shards.len(),
        report.meshes,
        report.failed.len(),
        a.out.join("corpus.json").display()
    );
    Ok(if report.failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(super::EXIT_THRESHOLD)
    })
}
