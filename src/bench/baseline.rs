//! `bench --baseline OLD/bench.json [--fail-slower PCT]`: this run against an earlier one.
//!
//! The two runs were not interleaved, so the comparison is not paired: whatever the machine
//! did between them enters the difference. A program is called slower only when this run's
//! whole 95% interval of the median lies above the baseline's whole interval, and it fails
//! `--fail-slower PCT` only when even that gap (this run's low end over the baseline's high
//! end) exceeds PCT percent.
use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use crate::error::{Error, Result};

/// Where one program of this run lies against the baseline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Change {
    /// This run's interval lies entirely above the baseline's.
    Slower,
    /// Entirely below.
    Faster,
    /// The intervals overlap.
    Indistinguishable,
    /// A median or interval end is missing or not a finite positive number in either run.
    NotComparable,
}

/// One program in both runs.
#[derive(Debug, Clone, Serialize)]
pub struct BaselineRow {
    pub name: String,
    pub baseline_median_ms: Option<f64>,
    pub baseline_ci95_low_ms: Option<f64>,
    pub baseline_ci95_high_ms: Option<f64>,
    pub median_ms: Option<f64>,
    pub ci95_low_ms: Option<f64>,
    pub ci95_high_ms: Option<f64>,
    /// 100 (median / baseline median - 1).
    pub change_pct: Option<f64>,
    /// The slowdown both intervals agree on: 100 (ci95_low / baseline ci95_high - 1) when
    /// slower, else null.
    pub slower_by_at_least_pct: Option<f64>,
    pub change: Change,
    /// Whether this row fails `--fail-slower` (always false without it).
    pub fails: bool,
}

/// bench.json `baseline`.
#[derive(Debug, Clone, Serialize)]
pub struct BaselineComparison {
    pub path: String,
    /// Always false: the runs were not interleaved.
    pub paired: bool,
    pub note: String,
    pub fail_slower_pct: Option<f64>,
    /// Settings that differ between the runs (scene, size, clock, device, threads, ...).
    pub setup_differences: Vec<String>,
    pub programs: Vec<BaselineRow>,
    /// Programs slower beyond both intervals by more than `fail_slower_pct`.
    pub failing: Vec<String>,
    /// Programs of both runs that could not be compared (counted, never passed as equal).
    pub not_comparable: Vec<String>,
    pub only_in_baseline: Vec<String>,
    pub only_in_this_run: Vec<String>,
}

impl BaselineComparison {
    /// Whether `--fail-slower` is exceeded: a program slower by more than PCT beyond both
    /// intervals, or a program of both runs that cannot be compared (a gate must not pass
    /// what it cannot measure).
    pub fn exceeded(&self) -> bool {
        self.fail_slower_pct.is_some()
            && (!self.failing.is_empty() || !self.not_comparable.is_empty())
    }
}

pub const NOT_PAIRED: &str = "not paired: the baseline was measured in another run, so load \
     and drift between the runs enter the difference; a program is slower only when this run's \
     95% interval lies entirely above the baseline's";

/// Reads and checks a baseline bench.json (before the run, so that a bad path fails fast).
pub fn load(path: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let v: Value = serde_json::from_str(&text).map_err(|e| {
        Error::input(
            path,
            Some(e.line()),
            format!("--baseline: not valid JSON ({e}); give the bench.json of an earlier `shadelab bench` run"),
        )
    })?;
    if !v["methods"].is_array() || !v["floor"].is_object() {
        return Err(Error::input(
            path,
            None,
            "--baseline: no \"methods\" array and \"floor\" object: not a bench.json of `shadelab bench`",
        ));
    }
    Ok(v)
}

/// Every timed program of a bench.json: the floor, the other floors, the methods.
fn programs(v: &Value) -> Vec<&Value> {
    std::iter::once(&v["floor"])
        .chain(v["other_floors"].as_array().into_iter().flatten())
        .chain(v["methods"].as_array().into_iter().flatten())
        .filter(|p| p["name"].is_string())
        .collect()
}

/// A positive finite number at `key`, else None.
fn ms(p: &Value, key: &str) -> Option<f64> {
    p[key].as_f64().filter(|x| x.is_finite() && *x > 0.0)
}

/// Compares `new` (this run's bench.json as a value) with `old` by their separate 95%
/// intervals (see the module doc). `fail_slower_pct`: the slowdown beyond both intervals, in
/// percent, above which a program fails.
pub fn compare(
    old: &Value,
    new: &Value,
    path: &str,
    fail_slower_pct: Option<f64>,
) -> BaselineComparison {
    let (olds, news) = (programs(old), programs(new));
    let mut rows = Vec::new();
    for p in &news {
        let name = p["name"].as_str().unwrap_or_default();
        let Some(o) = olds.iter().copied().find(|o| o["name"] == name) else {
            continue;
        };
        let (ol, om, oh) = (
            ms(o, "ci95_low_ms"),
            ms(o, "median_ms"),
            ms(o, "ci95_high_ms"),
        );
        let (nl, nm, nh) = (
            ms(p, "ci95_low_ms"),
            ms(p, "median_ms"),
            ms(p, "ci95_high_ms"),
        );
        let (change, slower_by) = match (ol, om, oh, nl, nm, nh) {
            (Some(ol), Some(_), Some(oh), Some(nl), Some(_), Some(nh)) => {
                if nl > oh {
                    (Change::Slower, Some((nl / oh - 1.0) * 100.0))
                } else if nh < ol {
                    (Change::Faster, None)
                } else {
                    (Change::Indistinguishable, None)
                }
            }
            _ => (Change::NotComparable, None),
        };
        let fails = match (fail_slower_pct, slower_by) {
            (Some(limit), Some(by)) => by > limit,
            _ => false,
        };
        rows.push(BaselineRow {
            name: name.into(),
            baseline_median_ms: om,
            baseline_ci95_low_ms: ol,
            baseline_ci95_high_ms: oh,
            median_ms: nm,
            ci95_low_ms: nl,
            ci95_high_ms: nh,
            change_pct: om.zip(nm).map(|(o, n)| (n / o - 1.0) * 100.0),
            slower_by_at_least_pct: slower_by,
            change,
            fails,
        });
    }
    let names = |list: &[&Value]| -> Vec<String> {
        list.iter()
            .filter_map(|p| p["name"].as_str().map(String::from))
            .collect()
    };
    let (old_names, new_names) = (names(&olds), names(&news));
    let mut setup_differences = Vec::new();
    for key in [
        "/scene",
        "/width",
        "/height",
        "/triangles",
        "/clock/clock",
        "/lp_num_threads",
        "/cpu_model",
        "/provenance/device",
        "/provenance/driver_info",
    ] {
        let (a, b) = (old.pointer(key), new.pointer(key));
        if a != b {
            let show = |v: Option<&Value>| v.map_or("absent".to_string(), |v| v.to_string());
            setup_differences.push(format!(
                "{}: baseline {}, this run {}",
                &key[1..],
                show(a),
                show(b)
            ));
        }
    }
    BaselineComparison {
        path: path.into(),
        paired: false,
        note: NOT_PAIRED.into(),
        fail_slower_pct,
        setup_differences,
        failing: rows
            .iter()
            .filter(|r| r.fails)
            .map(|r| r.name.clone())
            .collect(),
        not_comparable: rows
            .iter()
            .filter(|r| r.change == Change::NotComparable)
            .map(|r| r.name.clone())
            .collect(),
        only_in_baseline: old_names
            .iter()
            .filter(|n| !new_names.contains(n))
            .cloned()
            .collect(),
        only_in_this_run: new_names
            .iter()
            .filter(|n| !old_names.contains(n))
            .cloned()
            .collect(),
        programs: rows,
    }
}
