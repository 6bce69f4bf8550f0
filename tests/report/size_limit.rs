//! The default report of the shipped scenes (`make demo`'s) stays under its size limit
//! (docs/report.md), checked on the files a run writes, not on a timing.
use std::path::Path;

use shadelab::report::{tree_size, SIZE_LIMIT_BYTES};

use crate::support::*;

/// What the default's five bench runs per scene add over the one run of the test (per-run
/// figures in bench.json): 55 KB per shipped scene measured (2026-11-27), allowed 1 MB in all.
const FIVE_RUNS_MORE: u64 = 1_000_000;

/// Why the report in `dir` would break the size limit once the default's five runs are added, or
/// `None` when it fits: its size per top-level entry, largest first.
fn over_limit(dir: &Path) -> Option<String> {
    let (total, files) = tree_size(dir).unwrap();
    if total + FIVE_RUNS_MORE <= SIZE_LIMIT_BYTES {
        return None;
    }
    let mut parts: Vec<(u64, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let bytes = if e.path().is_dir() {
                tree_size(&e.path()).unwrap().0
            } else {
                e.metadata().unwrap().len()
            };
            (bytes, e.file_name().to_string_lossy().into_owned())
        })
        .collect();
    parts.sort_by(|a, b| b.cmp(a));
    let parts: Vec<String> = parts
        .iter()
        .map(|(b, n)| format!("{n} {:.1} MB", *b as f64 / 1e6))
        .collect();
    Some(format!(
        "{:.1} MB in {files} files (+{:.1} MB for five runs) is over the {:.0} MB size limit: {}",
        total as f64 / 1e6,
        FIVE_RUNS_MORE as f64 / 1e6,
        SIZE_LIMIT_BYTES as f64 / 1e6,
        parts.join(", ")
    ))
}

/// The report of every shipped scene at the default size with every method, as `make demo`
/// writes it but for one bench run per scene (the default's five take minutes): under the
/// size limit, without the CLI's warning, and with the isa charts as SVG only (PNG with --full).
#[test]
fn default_report_of_the_shipped_scenes_fits_its_size_limit() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-size-limit");
    let _ = std::fs::remove_dir_all(&out);
    let scenes = root().join("scenes");
    let (code, _, stderr) = run(&[
        "report",
        "--scenes",
        scenes.to_str().unwrap(),
        "--runs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "report failed:\n{stderr}");
    if let Some(why) = over_limit(&out) {
        panic!("{why}");
    }
    // The CLI's own check agrees (its warning: "... is over the 50 MB size limit of a report").
    assert!(!stderr.contains("size limit of a report"), "{stderr}");
    if let Ok(charts) = std::fs::read_dir(out.join("isa/charts")) {
        let png: Vec<_> = charts
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".png"))
            .collect();
        assert!(png.is_empty(), "isa charts as PNG without --full: {png:?}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Teeth: a folder of one file just over the size limit (less the five runs' allowance) is over,
/// one just under is not; the message names the file.
#[test]
fn over_limit_counts_every_byte_under_the_folder() {
    let t = tempfile::tempdir().unwrap();
    let f = std::fs::File::create(t.path().join("big.bin")).unwrap();
    f.set_len(SIZE_LIMIT_BYTES - FIVE_RUNS_MORE).unwrap();
    assert_eq!(over_limit(t.path()), None);
    std::fs::create_dir(t.path().join("sub")).unwrap();
    std::fs::write(t.path().join("sub/one.txt"), "x").unwrap();
    let why = over_limit(t.path()).expect("one byte over");
    assert!(
        why.contains("big.bin 49.0 MB") && why.contains("sub 0.0 MB"),
        "{why}"
    );
}
