//! The report's ISA section: what each method costs on AMD GPU generations (ACO's static
//! model on RADV's null device, `shadelab isa`), as a table of the fragment shader's inverse
//! throughput over phong_exact's per method and family, and per family a chart of error (the
//! scenes' compare p99 and max) against that cost with its Pareto front. It compiles the
//! report's methods now in `isa`'s children (a few seconds), writes DIR/isa/ (isa.json,
//! isa.csv, asm/, charts/) and returns the HTML; a failure is a paragraph saying why, never
//! fatal to the report.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::html::esc;
use super::SceneResult;
use crate::isa::{IsaOptions, IsaReport};
use crate::method::Method;

/// The section's folder under the report's DIR.
pub const DIR: &str = "isa";

/// The ISA section of the report in `out` for `methods`, with the error axis from the scenes'
/// compare folders.
pub fn section(out: &Path, methods: &[&'static Method], scenes: &[SceneResult]) -> String {
    let mut h = String::from(
        "<section id=\"isa\"><h2>Static cost on AMD GPU generations</h2><p>ACO's static model on \
         RADV's null device (<code>shadelab isa</code>): the inverse throughput of the timed \
         draw's fragment shader (estimated busy cycles per wave), over phong_exact's on the \
         same family; bold: cheaper than exact normalisation. Deterministic figures, not \
         timings: they rank programs.</p>",
    );
    match compile(out, methods, scenes) {
        Ok((r, charts)) => {
            h += &table(&r, methods);
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
                 <a href=\"{DIR}/isa.csv\">isa.csv</a>.</p>"
            );
        }
        Err(why) => {
            let _ = write!(h, "<p>Not compiled: {}.</p>", esc(&why));
        }
    }
    h + "</section>"
}

/// `page` with the [`section`] before its `</main>` (the report's hook).
pub fn splice(
    page: &str,
    out: &Path,
    methods: &[&'static Method],
    scenes: &[SceneResult],
) -> String {
    page.replacen("</main>", &(section(out, methods, scenes) + "</main>"), 1)
}

/// Runs isa (default families, the report's methods), draws the charts, writes DIR/isa/.
fn compile(
    out: &Path,
    methods: &[&'static Method],
    scenes: &[SceneResult],
) -> std::result::Result<(IsaReport, Vec<String>), String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find shadelab: {e}"))?;
    // The children re-run this binary as `isa --child`: only shadelab itself understands that.
    if exe.file_stem().and_then(|s| s.to_str()) != Some("shadelab") {
        return Err(format!("{} is not the shadelab binary", exe.display()));
    }
    if !Path::new(crate::isa::DEFAULT_DRIVER_FILES).is_file() {
        return Err(format!(
            "no RADV ICD at {}",
            crate::isa::DEFAULT_DRIVER_FILES
        ));
    }
    let mut ms = methods.to_vec();
    if !ms.iter().any(|m| m.name == crate::method::PHONG_EXACT) {
        ms.insert(0, crate::method::phong_exact());
    }
    let opts = IsaOptions {
        methods: ms,
        families: crate::isa::DEFAULT_FAMILIES.map(String::from).to_vec(),
        driver_files: PathBuf::from(crate::isa::DEFAULT_DRIVER_FILES),
        scene: None,
        exe,
        precision: crate::method::Precision::F32,
        probes: Vec::new(),
    };
    let mut r = crate::isa::run(&opts, &|_| {}).map_err(|e| e.to_string())?;
    let dir = out.join(DIR);
    let dirs: Vec<PathBuf> = scenes.iter().map(|s| out.join(&s.compare_dir)).collect();
    let charts = match crate::isa::chart::errors(&dirs) {
        Ok(err) => crate::isa::chart::write(&dir, &r, &err).map_err(|e| e.to_string())?,
        Err(e) => {
            r.charts_note = Some(e.to_string());
            Vec::new()
        }
    };
    r.charts = charts.clone();
    crate::isa::files::write(&dir, &r).map_err(|e| e.to_string())?;
    Ok((r, charts))
}

/// Per method (rows, the report's order) and family (columns): the fragment shader's inverse
/// throughput over phong_exact's; refused families named in a line below.
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
            let ratio = r
                .row(f, m.name, "fragment", "draw")
                .and_then(|row| row.ratio_to_phong_exact.get("inverse_throughput").copied())
                .filter(|v| v.is_finite());
            let _ = match ratio {
                Some(v) if v < 1.0 => write!(h, "<td><b>{v:.2}</b></td>"),
                Some(v) => write!(h, "<td>{v:.2}</td>"),
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
