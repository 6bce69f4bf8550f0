//! The files of `shadelab isa`: isa.json (docs/isa.schema.json), isa.csv (one line per row,
//! AMD's statistics and their ratios to phong_exact, then every vendor's ranking statistic,
//! its figure and ratio), the disassembly under asm/<family>/<method>.<stage>.s (`:` of a
//! family id as `_`) (isolated kernels: `.compute.repeat<K>.s`) and, with
//! compare results, a chart per family of error against inverse throughput with its Pareto
//! front ([`super::rank`]).
use std::io::Write;
use std::path::Path;

use super::report::IsaReport;
use super::table::REQUIRED;
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

fn csv(w: &mut dyn Write, r: &IsaReport) -> std::io::Result<()> {
    write!(w, "family,method,stage,kind,program")?;
    for k in REQUIRED {
        write!(w, ",{k}")?;
    }
    for k in REQUIRED {
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
        for k in REQUIRED {
            write!(w, ",{}", num(row.statistics.get(k)))?;
        }
        for k in REQUIRED {
            write!(w, ",{}", num(row.ratio_to_phong_exact.get(k)))?;
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
