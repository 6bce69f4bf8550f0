//! The files of `shadelab isa`: isa.json (docs/isa.schema.json), isa.csv (one line per row:
//! the statistics each vendor of the report requires, in the routes' order, and their ratios
//! to phong_exact, then the row's ranking statistic, its figure and ratio, and the bound unit), the disassembly under asm/<family>/<method>.<stage>.s (`:` of a
//! family id as `_`) (isolated kernels: `.compute.repeat<K>.s`) and, with
//! compare results, a chart per family of error against inverse throughput with its Pareto
//! front ([`super::rank`]).
use std::io::Write;
use std::path::Path;

use super::report::IsaReport;
use crate::error::{Error, Result};
use crate::output::{
    sync_filesystem, write_atomic, write_atomic_as, write_bytes_atomic, Durability,
};

/// Reads an isa.json of `shadelab isa`.
pub fn read(path: &Path) -> Result<IsaReport> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text)
        .map_err(|e| Error::input(path, None, format!("not an isa.json: {e}")))
}

/// Writes the disassembly, isa.csv and, last (the run's completion marker), isa.json into
/// `out`.
pub fn write(out: &Path, report: &IsaReport) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    // Atomic like every output (a full disk left 0-byte .s files of plain writes), without an
    // fsync each: hundreds to thousands of small files, synced once below.
    for (rel, text) in &report.disassembly {
        write_atomic_as(&out.join(rel), Durability::Batched, |w| {
            w.write_all(text.as_bytes())
        })?;
    }
    if !report.disassembly.is_empty() {
        sync_filesystem(out)?;
    }
    write_atomic(&out.join("isa.csv"), |w| csv(w, report))?;
    // Compact (one line): 3.3 MB against 4.7 MB indented for the report's 37 methods on 37
    // families; `jq .` indents it for reading.
    let json = serde_json::to_vec(report).map_err(|e| Error::output("isa.json", e))?;
    write_bytes_atomic(&out.join("isa.json"), &json)
}

/// The statistic columns of isa.csv: every statistic a vendor of `r`'s families requires
/// ([`super::Vendor::required_statistics`]), vendors in the routes' order, each key once. A
/// report of AMD's families alone has RADV's eight.
fn columns(r: &IsaReport) -> Vec<&'static str> {
    let present: Vec<&str> = r
        .families
        .iter()
        .filter_map(|f| Some(f.resolve()?.0.prefix()))
        .collect();
    let mut out: Vec<&'static str> = Vec::new();
    for v in super::route::VENDORS {
        if present.contains(&v.prefix()) {
            for k in v.required_statistics() {
                if !out.contains(k) {
                    out.push(k);
                }
            }
        }
    }
    out
}

fn csv(w: &mut dyn Write, r: &IsaReport) -> std::io::Result<()> {
    let columns = columns(r);
    write!(w, "family,method,stage,kind,program")?;
    for k in &columns {
        write!(w, ",{k}")?;
    }
    for k in &columns {
        write!(w, ",ratio_{k}")?;
    }
    // Every vendor: its ranking statistic, the row's figure and its ratio to phong_exact's.
    // and the unit that bounds the program in the family's throughput model.
    write!(w, ",ranking,ranking_value,ratio_ranking,bound_unit")?;
    writeln!(w)?;
    let num = |v: Option<&f64>| v.map_or(String::new(), |v| format!("{v}"));
    for row in &r.results {
        write!(
            w,
            "{},{},{},{},{}",
            row.family, row.method, row.stage, row.kind, row.program
        )?;
        for k in &columns {
            write!(w, ",{}", num(row.statistics.get(*k)))?;
        }
        for k in &columns {
            write!(w, ",{}", num(row.ratio_to_phong_exact.get(*k)))?;
        }
        let key = r
            .family(&row.family)
            .and_then(|f| f.ranking())
            .map_or(String::new(), |k| k.key);
        write!(
            w,
            ",{key},{},{},{}",
            num(row.statistics.get(&key)),
            num(row.ratio_to_phong_exact.get(&key)),
            row.bound_unit.map_or("", |u| u.name())
        )?;
        writeln!(w)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report of `families` with one fragment draw of phong_exact each, carrying `stats`.
    fn report(families: &[&str], stats: &[(&str, f64)]) -> IsaReport {
        let stats: serde_json::Map<String, serde_json::Value> = stats
            .iter()
            .map(|(k, v)| (k.to_string(), (*v).into()))
            .collect();
        let rows: Vec<_> = families
            .iter()
            .map(|f| {
                serde_json::json!({"family": f, "method": "phong_exact", "stage": "fragment",
                    "kind": "draw", "program": "phong_exact", "statistics": stats,
                    "ratio_to_phong_exact": {}, "hash": []})
            })
            .collect();
        let fams: Vec<_> = families
            .iter()
            .map(|f| {
                serde_json::json!({"family": f, "id": f, "supported": true, "status": "compiled",
                    "device_name": null, "driver_name": null, "driver_info": null,
                    "elapsed_ms": null, "statistics": []})
            })
            .collect();
        serde_json::from_value(serde_json::json!({"version": 1, "precision": "f32",
            "scene": "s", "kernel_counts": [2, 3], "model": "m", "families": fams,
            "results": rows, "elapsed_s": 0.0}))
        .unwrap()
    }

    fn header(r: &IsaReport) -> String {
        let mut out = Vec::new();
        csv(&mut out, r).unwrap();
        String::from_utf8(out)
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .to_string()
    }

    #[test]
    fn the_csv_columns_are_the_statistics_of_the_reports_vendors() {
        let amd = super::super::route::amd::STATISTICS;
        let r = report(&["amd:navi21"], &[("inverse_throughput", 40.0)]);
        assert_eq!(columns(&r), amd);
        let h = header(&r);
        assert!(
            h.starts_with("family,method,stage,kind,program,instructions,"),
            "{h}"
        );
        assert!(
            h.ends_with(",ranking,ranking_value,ratio_ranking,bound_unit"),
            "{h}"
        );
        // A second vendor adds its own columns after AMD's, each key once.
        let r = report(&["nvidia:nv162", "amd:navi21"], &[("inst", 38.0)]);
        let cols = columns(&r);
        assert_eq!(&cols[..amd.len()], amd);
        assert!(
            cols.contains(&"sfu_ops") && cols.contains(&"model_cycles"),
            "{cols:?}"
        );
        let h = header(&r);
        assert!(h.contains(",inst,") && h.contains(",ratio_sfu_ops,"), "{h}");
        // Teeth: without an NVIDIA family, no NVIDIA column.
        let r = report(&["intel:tgl"], &[("model_cycles", 30.0)]);
        assert!(!columns(&r).contains(&"sfu_ops"));
        assert!(!columns(&r).contains(&"inverse_throughput"));
    }
}
