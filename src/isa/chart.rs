//! A chart per family of error against static cost: x the fragment shader's ranking statistic
//! (AMD: ACO's inverse throughput; FamilyStatus::ranking), y compare's p99 and max absolute error (the worst over the
//! compare folders given with `--compare`), with the Pareto front on p99 (no cheaper method
//! has a lower p99). Deterministic: the figures have no intervals. Without compare results
//! there is no error axis, and no chart (isa.json's `charts_note` says so).
use std::collections::BTreeMap;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::report::IsaReport;
use crate::compare::Metric;
use crate::error::{Error, Result};
use crate::output::chart::{both, plot_err, svg};

/// Errors below this sit on the floor of the log axis (exact methods have 0).
const ERROR_FLOOR: f64 = 1e-7;

/// Per method, the worst (p99, max) absolute error over the summary.json files of `dirs`;
/// methods with a non-finite error are left out (they cannot sit on a log axis).
pub fn errors(dirs: &[std::path::PathBuf]) -> Result<BTreeMap<String, (f64, f64)>> {
    let mut out: BTreeMap<String, (f64, f64)> = BTreeMap::new();
    for d in dirs {
        let path = d.join("summary.json");
        let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let v: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| Error::input(&path, None, format!("not JSON: {e}")))?;
        let methods = v["methods"].as_array().ok_or_else(|| {
            Error::input(&path, None, "no `methods` list: not a compare summary.json")
        })?;
        for m in methods {
            let (Some(name), Some(p99), Some(max)) = (
                m["name"].as_str(),
                m[Metric::P99AbsError.name()].as_f64(),
                m[Metric::MaxAbsError.name()].as_f64(),
            ) else {
                continue;
            };
            let e = out.entry(name.to_string()).or_insert((0.0, 0.0));
            *e = (e.0.max(p99), e.1.max(max));
        }
    }
    out.retain(|_, (a, b)| a.is_finite() && b.is_finite());
    if out.is_empty() {
        return Err(Error::Usage(format!(
            "--compare: no method with finite p99_abs_error and max_abs_error in {}",
            dirs.iter()
                .map(|d| d.join("summary.json").display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    Ok(out)
}

/// A chart point: (method, inverse throughput, p99, max, on the front).
type Point = (String, f64, f64, f64, bool);

/// The points of one family, with the Pareto front on p99 marked.
pub fn points(report: &IsaReport, family: &str, err: &BTreeMap<String, (f64, f64)>) -> Vec<Point> {
    let mut pts: Vec<Point> = err
        .iter()
        .filter_map(|(m, &(p99, max))| {
            let it = report.ranking_value(family, m)?;
            Some((m.clone(), it, p99, max, false))
        })
        .collect();
    mark_front(&mut pts);
    pts
}

/// Sorts by cost (then p99) and marks the Pareto front on p99: a point is on it when every
/// cheaper point has a higher p99.
fn mark_front(pts: &mut [Point]) {
    pts.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)));
    let mut best = f64::INFINITY;
    for p in pts.iter_mut() {
        p.4 = p.2 < best;
        best = best.min(p.2);
    }
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    family: &str,
    axis: &str,
    pts: &[Point],
) -> Result<()> {
    area.fill(&WHITE).map_err(plot_err)?;
    // room on the right for the last point's label (no text clipped)
    let x1 = pts.iter().map(|p| p.1).fold(1.0, f64::max) * 1.3;
    let y1 = pts
        .iter()
        .map(|p| p.3.max(ERROR_FLOOR))
        .fold(1e-3, f64::max)
        * 3.0;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{family}: error vs static cost (not a timing); filled: Pareto front"),
            ("sans-serif", 16),
        )
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x1, (ERROR_FLOOR / 2.0..y1).log_scale())
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(axis)
        .y_desc("abs error (p99 circle, max cross)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(plot_err)?;
    let front: Vec<(f64, f64)> = pts
        .iter()
        .filter(|p| p.4)
        .map(|p| (p.1, p.2.max(ERROR_FLOOR)))
        .collect();
    chart
        .draw_series(LineSeries::new(front, RED.stroke_width(1)))
        .map_err(plot_err)?;
    for p in pts {
        let (x, p99, max) = (p.1, p.2.max(ERROR_FLOOR), p.3.max(ERROR_FLOOR));
        let style = if p.4 {
            RED.filled()
        } else {
            BLUE.stroke_width(1)
        };
        chart
            .draw_series([Circle::new((x, p99), 4, style)])
            .map_err(plot_err)?;
        chart
            .draw_series([Cross::new((x, max), 4, BLACK.mix(0.5))])
            .map_err(plot_err)?;
        // Labels on the front and phong_exact only: 35 names on one panel overlap.
        if !(p.4 || p.0 == crate::method::PHONG_EXACT) {
            continue;
        }
        chart
            .draw_series([EmptyElement::at((x, p99))
                + Text::new(p.0.clone(), (6, -12), ("sans-serif", 11).into_font())])
            .map_err(plot_err)?;
    }
    Ok(())
}

/// Writes DIR/charts/<family>.svg for every compiled family, and beside it the same chart as
/// .png when `png` (`shadelab isa`, `report --full`: the report's page shows the SVG); returns
/// their paths relative to `out`.
pub fn write(
    out: &Path,
    report: &IsaReport,
    err: &BTreeMap<String, (f64, f64)>,
    png: bool,
) -> Result<Vec<String>> {
    let dir = out.join("charts");
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let mut written = Vec::new();
    for f in report.supported() {
        let pts = points(report, f, err);
        let file = super::table::asm_dir(f);
        let axis = report
            .family(f)
            .and_then(|s| s.ranking())
            .map_or(String::from("static cost"), |r| {
                format!("{} of the fragment shader ({})", r.key, r.unit)
            });
        let draw_svg = |a: &DrawingArea<SVGBackend, Shift>| draw(a, f, &axis, &pts);
        written.push(format!("charts/{file}.svg"));
        if png {
            both(&dir, &file, &draw_svg, &|a| draw(a, f, &axis, &pts))?;
            written.push(format!("charts/{file}.png"));
        } else {
            svg(&dir, &file, &draw_svg)?;
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_front_keeps_only_what_no_cheaper_method_beats() {
        // (name, cost, p99): b is dearer and worse than a, c is dearer and better.
        let mut pts = vec![
            ("c".to_string(), 30.0, 1e-4, 1e-4, false),
            ("b".to_string(), 20.0, 5e-2, 5e-2, true),
            ("a".to_string(), 10.0, 1e-2, 1e-2, false),
        ];
        super::mark_front(&mut pts);
        let front: Vec<&str> = pts.iter().filter(|p| p.4).map(|p| p.0.as_str()).collect();
        assert_eq!(front, ["a", "c"]);
    }
}
