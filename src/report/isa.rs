//! The report's ISA section: what each method costs on every GPU family `shadelab isa`
//! compiled (each vendor's compiler and its ranking statistic), as a table of the fragment
//! shader's ranking figure over phong_exact's per method and family, and per family a chart of error (the
//! scenes' compare p99 and max) against that cost with its Pareto front. [`compile_all`]
//! compiles the report's methods in `isa`'s children before the answer (a few seconds per
//! precision): float32 into DIR/isa/ (isa.json, isa.csv, charts/*.svg; asm/ and the charts as
//! PNG only with `--full`), float16 into
//! DIR/isa-f16/; each supported family becomes a static cost model of the answer
//! ([`compiled`], read by [`crate::isa::cost::StaticCost`]). A failure is a paragraph saying why, never fatal to the report.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::html::esc;
use super::SceneResult;
use crate::isa::{IsaOptions, IsaReport};
use crate::method::{Method, Precision};

/// The section's folder under the report's DIR (float32), and the float16 programs' folder.
pub const DIR: &str = "isa";
pub const DIR_F16: &str = "isa-f16";

/// What `isa` gave the report: per precision the report and its charts, or why not.
#[derive(Debug, Clone)]
pub struct IsaRun {
    pub f32: std::result::Result<(IsaReport, Vec<String>), String>,
    pub f16: std::result::Result<IsaReport, String>,
}

impl IsaRun {
    /// A run that compiled nothing (`why`).
    pub fn none(why: &str) -> IsaRun {
        IsaRun {
            f32: Err(why.into()),
            f16: Err(why.into()),
        }
    }
}

/// Compiles the report's methods in float32 (with charts) and float16; the disassembly
/// (DIR/isa/asm/, tens of MB over every family) and the charts as PNG (which the page does
/// not show: it shows the SVG) are written only when `full` (`--full`).
pub fn compile_all(
    out: &Path,
    methods: &[&'static Method],
    scenes: &[SceneResult],
    full: bool,
) -> IsaRun {
    IsaRun {
        f32: compile(out, methods, scenes, full),
        f16: compile_f16(out, methods, full),
    }
}

/// Writes `r`'s files into `dir`: without the disassembly unless `full` (the report keeps the
/// disassembly in memory: the op-count claim was read from it).
fn write_files(dir: &Path, r: &IsaReport, full: bool) -> std::result::Result<(), String> {
    let lean;
    let r = if full {
        r
    } else {
        lean = IsaReport {
            disassembly: Vec::new(),
            asm: Vec::new(),
            ..r.clone()
        };
        &lean
    };
    crate::isa::files::write(dir, r).map_err(|e| e.to_string())
}

/// The reports `isa` gave, as the cost sources read them: float32 (DIR/isa/isa.json), then
/// float16 (DIR/isa-f16/isa.json).
pub fn compiled(run: &IsaRun) -> Vec<crate::isa::cost::Compiled> {
    let f32 = run.f32.as_ref().ok().map(|(r, _)| (r, DIR));
    let f16 = run.f16.as_ref().ok().map(|r| (r, DIR_F16));
    f32.into_iter()
        .chain(f16)
        .map(|(r, dir)| crate::isa::cost::Compiled {
            report: r.clone(),
            evidence: format!("{dir}/isa.json"),
        })
        .collect()
}

/// The ISA section of the report for `methods` from `run`.
pub fn section(run: &IsaRun, methods: &[&'static Method]) -> String {
    let mut h = String::from(
        "<section id=\"isa\"><h2>Static cost on GPU families</h2><p>Each vendor's compiler \
         (<code>shadelab isa</code>: RADV's ACO on AMD, Mesa's drivers behind drm-shims \
         elsewhere) on the timed draw's fragment shader, its own ranking statistic (ACO's \
         inverse throughput, Intel's busier back-end unit, a weighted issue count, ...: \
         isa.json names each family's) over phong_exact's on the same family; bold: cheaper \
         than exact normalisation; \"fewer waves\": the program keeps fewer waves resident than \
         phong_exact's. Deterministic figures, not timings: they rank programs \
         within a family, and families only by their ratios.</p>",
    );
    match &run.f32 {
        Ok((r, charts)) => {
            h += &table(r, methods);
            for c in charts.iter().filter(|c| c.ends_with(".svg")) {
                let _ = write!(
                    h,
                    "<figure><img src=\"{}/{}\" alt=\"error against static cost, {}\" \
                     loading=\"lazy\"><figcaption>{}</figcaption></figure>",
                    DIR,
                    esc(c),
                    esc(c),
                    esc(c)
                );
            }
            let _ = write!(
                h,
                "<p>Files: <a href=\"{DIR}/isa.json\">isa.json</a>, \
                 <a href=\"{DIR}/isa.csv\">isa.csv</a>. {}</p>",
                provenance(r)
            );
        }
        Err(why) => {
            let _ = write!(h, "<p>Not compiled: {}.</p>", esc(why));
        }
    }
    match &run.f16 {
        Ok(r) => {
            h += "<h3>Float16 programs</h3><p>The same, for the float16 programs (over \
                  phong_exact's float16 program); families without float16 arithmetic are \
                  named below the table.</p>";
            h += &table(r, methods);
            let _ = write!(
                h,
                "<p>Files: <a href=\"{DIR_F16}/isa.json\">isa.json</a>, \
                 <a href=\"{DIR_F16}/isa.csv\">isa.csv</a>. {}</p>",
                provenance(r)
            );
        }
        Err(why) => {
            let _ = write!(h, "<p>Float16 programs not compiled: {}.</p>", esc(why));
        }
    }
    h + "</section>"
}

/// How many families were compiled in this run and how many read from the compile store
/// (isa.json names each one's compiler identity and source).
fn provenance(r: &IsaReport) -> String {
    use crate::isa::store::Source;
    let count = |s| r.families.iter().filter(|f| f.source == Some(s)).count();
    format!(
        "Compiled in this run: {} families; read from the compile store (the same compiler \
         identity, request and files; isa.json's <code>compiler_id</code> and \
         <code>source</code> per family): {}.",
        count(Source::Compiled),
        count(Source::FromStore)
    )
}

/// The options of `isa` on the report's methods (phong_exact included) in `precision`.
fn options(
    methods: &[&'static Method],
    precision: Precision,
) -> std::result::Result<IsaOptions, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find shadelab: {e}"))?;
    // The children re-run this binary as `shadelab child`: only shadelab understands that.
    if exe.file_stem().and_then(|s| s.to_str()) != Some("shadelab") {
        return Err(format!("{} is not the shadelab binary", exe.display()));
    }
    Ok(IsaOptions::every_family(methods, precision, exe))
}

/// Runs isa on the float16 programs and writes DIR/isa-f16/ (no charts).
fn compile_f16(
    out: &Path,
    methods: &[&'static Method],
    full: bool,
) -> std::result::Result<IsaReport, String> {
    let opts = options(methods, Precision::F16)?;
    let r = crate::isa::run(&opts, &|_| {}).map_err(|e| e.to_string())?;
    write_files(&out.join(DIR_F16), &r, full)?;
    Ok(r)
}

/// Runs isa (default families, the report's methods), draws the charts, writes DIR/isa/.
fn compile(
    out: &Path,
    methods: &[&'static Method],
    scenes: &[SceneResult],
    full: bool,
) -> std::result::Result<(IsaReport, Vec<String>), String> {
    let opts = options(methods, Precision::F32)?;
    let mut r = crate::isa::run(&opts, &|_| {}).map_err(|e| e.to_string())?;
    let dir = out.join(DIR);
    let dirs: Vec<PathBuf> = scenes.iter().map(|s| out.join(&s.compare_dir)).collect();
    let charts = match crate::isa::chart::errors(&dirs) {
        Ok(err) => crate::isa::chart::write(&dir, &r, &err, full).map_err(|e| e.to_string())?,
        Err(e) => {
            r.charts_note = Some(e.to_string());
            Vec::new()
        }
    };
    r.charts = charts.clone();
    write_files(&dir, &r, full)?;
    Ok((r, charts))
}

/// Per method (rows, the report's order) and family (columns): the fragment shader's ranking
/// statistic over phong_exact's, with the bound unit where the family's model has several
/// pipes and "fewer waves" where the program keeps fewer waves resident than phong_exact's
/// ([`crate::isa::occupancy`]); refused families named in a line below.
fn table(r: &IsaReport, methods: &[&'static Method]) -> String {
    let fams = r.supported();
    let mut h = String::from("<table class=\"isa\"><thead><tr><th>method</th>");
    for f in &fams {
        let _ = write!(h, "<th>{}</th>", esc(f));
    }
    h += "</tr></thead><tbody>";
    for m in methods {
        let _ = write!(h, "<tr><th>{}</th>", esc(m.name));
        for f in &fams {
            let ratio = r.ranking_ratio(f, m.name).filter(|v| v.is_finite());
            let row = crate::isa::table::find_row(
                &r.results,
                f,
                m.name,
                "fragment",
                crate::isa::request::RowKind::Draw,
            );
            // The unit that bounds the program, where the model has more than one.
            let mut bound = row
                .and_then(|row| row.bound_unit)
                .filter(|u| *u != crate::isa::throughput::Unit::Issue)
                .map_or(String::new(), |u| format!(" <small>{}</small>", u.name()));
            // Fewer waves resident than phong_exact's: its latency is hidden less well.
            if row.and_then(|row| crate::isa::occupancy::fewer_waves(&row.ratio_to_phong_exact))
                == Some(true)
            {
                bound += " <small class=\"occupancy\">fewer waves</small>";
            }
            let _ = match ratio {
                Some(v) if v < 1.0 => write!(h, "<td><b>{v:.2}</b>{bound}</td>"),
                Some(v) => write!(h, "<td>{v:.2}{bound}</td>"),
                None => write!(h, "<td>-</td>"),
            };
        }
        h += "</tr>";
    }
    h += "</tbody></table>";
    let refused: Vec<String> = r
        .families
        .iter()
        .filter(|f| !f.supported)
        .map(|f| format!("{}: {}", f.family, f.status))
        .collect();
    if !refused.is_empty() {
        let _ = write!(h, "<p>{}</p>", esc(&refused.join("; ")));
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report of one family whose fragment draws have `stat` as their only statistic.
    fn report(family: &str, stat: &str, costs: &[(&str, f64)]) -> IsaReport {
        let rows: Vec<_> = costs
            .iter()
            .map(|(m, v)| {
                serde_json::json!({"family": family, "method": m, "stage": "fragment",
                    "kind": "draw", "program": m, "statistics": {stat: v},
                    "ratio_to_phong_exact": {}, "hash": []})
            })
            .collect();
        let mut r: IsaReport = serde_json::from_value(serde_json::json!({"version": 1,
            "precision": "f32", "scene": "s", "kernel_counts": [2, 3], "model": "m",
            "families": [{"family": family, "supported": true, "status": "compiled",
                "device_name": null, "driver_name": null, "driver_info": null,
                "elapsed_ms": null, "statistics": []}],
            "results": rows, "elapsed_s": 0.0}))
        .unwrap();
        crate::isa::table::fill_ratios(&mut r.results);
        r
    }

    #[test]
    fn the_table_reads_each_familys_own_ranking_statistic() {
        let (exact, floor) = (
            crate::method::phong_exact(),
            crate::method::phong_unnormalized(),
        );
        let methods: Vec<&'static Method> = vec![exact, floor];
        let costs = [(exact.name, 332.0), (floor.name, 249.0)];
        let intel = table(&report("intel:tgl", "model_cycles", &costs), &methods);
        assert!(intel.contains("<td><b>0.75</b></td>"), "{intel}");
        // A per-pipe model's bound unit is named beside the ratio; a single-pipe one is not.
        let mut mali = report("intel:tgl", "model_cycles", &costs);
        mali.results[1].bound_unit = Some(crate::isa::throughput::Unit::LoadStore);
        let mali = table(&mali, &methods);
        assert!(
            mali.contains("<b>0.75</b> <small>load_store</small>"),
            "{mali}"
        );
        assert!(!intel.contains("<small>"), "{intel}");
        // A program that keeps fewer waves resident than phong_exact's says so; the same
        // waves say nothing.
        let mut waves = report("intel:tgl", "model_cycles", &costs);
        for (row, w) in waves.results.iter_mut().zip([8.0, 4.0]) {
            row.statistics
                .insert(crate::isa::occupancy::WAVES_KEY.into(), w);
        }
        crate::isa::table::fill_ratios(&mut waves.results);
        let fewer = table(&waves, &methods);
        assert_eq!(fewer.matches("fewer waves").count(), 1, "{fewer}");
        waves.results[1]
            .statistics
            .insert(crate::isa::occupancy::WAVES_KEY.into(), 8.0);
        crate::isa::table::fill_ratios(&mut waves.results);
        assert!(!table(&waves, &methods).contains("fewer waves"));
        // Teeth: a statistic that is not the family's ranking one is no figure.
        let other = table(&report("intel:tgl", "cycle_count", &costs), &methods);
        assert!(
            !other.contains("0.75") && other.contains("<td>-</td>"),
            "{other}"
        );
    }
}
