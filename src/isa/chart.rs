//! A chart per family of error against static cost: x the fragment shader's ranking statistic
//! (AMD: ACO's inverse throughput; FamilyStatus::ranking), y compare's p99 and max absolute error (the worst over the
//! compare folders given with `--compare`), with the Pareto front on p99 (no cheaper method
//! has a lower p99). Deterministic: the figures have no intervals. Without compare results
//! there is no error axis, and no chart (isa.json's `charts_note` says so).
use std::collections::BTreeMap;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use std::fmt::Write as _;

use super::report::IsaReport;
use super::throughput::Unit;
use crate::compare::Metric;
use crate::error::{Error, Result};
use crate::output::chart::{both, plot_err, svg};

/// The error axis: from 1e-9 (exact methods, with 0, sit on this floor) to 1, as the report's
/// own charts ([`crate::output::chart::ERROR_CEILING_DECADE`]); an error above 1 is drawn on the
/// top edge as a triangle, its value in the legend.
const ERROR_FLOOR: f64 = 1e-9;
const ERROR_CEILING: f64 = 1.0;

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

/// A method on one family's chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub method: String,
    /// The family's ranking statistic of the timed draw's fragment program.
    pub cost: f64,
    /// The worst p99 and max absolute error over the compare folders.
    pub p99: f64,
    pub max: f64,
    /// No cheaper method has a lower p99.
    pub front: bool,
    /// The unit that bounds the program in the family's throughput model, where it names one.
    pub bound: Option<Unit>,
}

impl Point {
    /// An error as drawn: within [floor, ceiling]; whether it lies above the ceiling.
    fn shown(e: f64) -> (f64, bool) {
        (e.clamp(ERROR_FLOOR, ERROR_CEILING), e > ERROR_CEILING)
    }

    /// The legend's line: its number, name, cost and bound unit, and any error off the axis.
    fn legend(&self, n: usize, unit: &str) -> String {
        let mut l = format!("{n:>2} {} {} {unit}", self.method, fmt_cost(self.cost));
        if let Some(b) = self.bound {
            let _ = write!(l, ", {} bound", b.name());
        }
        for (what, e) in [("p99", self.p99), ("max", self.max)] {
            if Point::shown(e).1 {
                let _ = write!(l, "; {what} {e:.1e} above 1");
            }
        }
        l
    }
}

fn fmt_cost(c: f64) -> String {
    if c.fract() == 0.0 && c.abs() < 1e9 {
        format!("{c:.0}")
    } else {
        format!("{c:.3}")
    }
}

/// The points of one family, sorted by cost, with the Pareto front on p99 marked.
pub fn points(report: &IsaReport, family: &str, err: &BTreeMap<String, (f64, f64)>) -> Vec<Point> {
    let ranking = report.family(family).and_then(|f| f.ranking());
    let mut pts: Vec<Point> = err
        .iter()
        .filter_map(|(m, &(p99, max))| {
            let cost = report.ranking_value(family, m)?;
            let bound = ranking
                .as_ref()
                .and_then(|r| report.row(family, m, &r.stage, r.kind))
                .and_then(|row| row.bound_unit);
            Some(Point {
                method: m.clone(),
                cost,
                p99,
                max,
                front: false,
                bound,
            })
        })
        .collect();
    mark_front(&mut pts);
    pts
}

/// Sorts by cost (then p99, then name) and marks the Pareto front on p99: a point is on it
/// when every cheaper point has a higher p99.
fn mark_front(pts: &mut [Point]) {
    pts.sort_by(|a, b| {
        a.cost
            .total_cmp(&b.cost)
            .then(a.p99.total_cmp(&b.p99))
            .then(a.method.cmp(&b.method))
    });
    let mut best = f64::INFINITY;
    for p in pts.iter_mut() {
        p.front = p.p99 < best;
        best = best.min(p.p99);
    }
}

/// The chart's width share of the drawing; the legend takes the rest.
const PLOT_SHARE: f64 = 0.62;

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    family: &str,
    axis: (&str, &str),
    pts: &[Point],
) -> Result<()> {
    area.fill(&WHITE).map_err(plot_err)?;
    let (w, _) = area.dim_in_pixel();
    let (plot, legend) = area.split_horizontally((f64::from(w) * PLOT_SHARE) as u32);
    // room on the right for the last point's number (no text clipped)
    let x1 = pts.iter().map(|p| p.cost).fold(1.0, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(&plot)
        .caption(
            format!("{family}: error vs static cost (not a timing)"),
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(
            0.0..x1,
            (ERROR_FLOOR / 2.0..ERROR_CEILING * 1.5).log_scale(),
        )
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(format!("{} ({})", axis.0, axis.1))
        .y_desc("abs error: p99 circle, max cross (1e-9 = exact)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(plot_err)?;
    let front: Vec<(f64, f64)> = pts
        .iter()
        .filter(|p| p.front)
        .map(|p| (p.cost, Point::shown(p.p99).0))
        .collect();
    chart
        .draw_series(LineSeries::new(front, RED.stroke_width(1)))
        .map_err(plot_err)?;
    for (i, p) in pts.iter().enumerate() {
        let ((p99, p99_off), (max, max_off)) = (Point::shown(p.p99), Point::shown(p.max));
        let colour = if p.front { RED } else { BLUE };
        let style = if p.front {
            colour.filled()
        } else {
            colour.stroke_width(1)
        };
        if p99_off {
            chart
                .draw_series([TriangleMarker::new((p.cost, p99), 6, colour.filled())])
                .map_err(plot_err)?;
        } else {
            chart
                .draw_series([Circle::new((p.cost, p99), 4, style)])
                .map_err(plot_err)?;
        }
        if max_off {
            chart
                .draw_series([TriangleMarker::new(
                    (p.cost, max),
                    6,
                    BLACK.mix(0.5).filled(),
                )])
                .map_err(plot_err)?;
        } else {
            chart
                .draw_series([Cross::new((p.cost, max), 4, BLACK.mix(0.5))])
                .map_err(plot_err)?;
        }
        chart
            .draw_series([EmptyElement::at((p.cost, p99))
                + Text::new(
                    format!("{}", i + 1),
                    (5, -11),
                    ("sans-serif", 10).into_font(),
                )])
            .map_err(plot_err)?;
    }
    // The legend: every point by number, cheapest first; the front in red.
    let font = ("sans-serif", 11).into_font();
    let line = ((f64::from(area.dim_in_pixel().1) - 60.0) / pts.len().max(1) as f64).min(15.0);
    legend
        .draw(&Text::new(
            "cost, bound unit; red: Pareto front; triangle: above 1".to_string(),
            (4, 14),
            font.clone(),
        ))
        .map_err(plot_err)?;
    for (i, p) in pts.iter().enumerate() {
        let colour = if p.front { RED } else { BLACK };
        legend
            .draw(&Text::new(
                p.legend(i + 1, axis.1),
                (4, 36 + (i as f64 * line) as i32),
                font.clone().color(&colour),
            ))
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
        let (key, unit) = report
            .family(f)
            .and_then(|s| s.ranking())
            .map_or((String::from("static cost"), String::new()), |r| {
                (format!("{} of the fragment shader", r.key), r.unit)
            });
        let axis = (key.as_str(), unit.as_str());
        let draw_svg = |a: &DrawingArea<SVGBackend, Shift>| draw(a, f, axis, &pts);
        written.push(format!("charts/{file}.svg"));
        if png {
            both(&dir, &file, &draw_svg, &|a| draw(a, f, axis, &pts))?;
            written.push(format!("charts/{file}.png"));
        } else {
            svg(&dir, &file, &draw_svg)?;
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(method: &str, cost: f64, p99: f64, max: f64) -> Point {
        Point {
            method: method.into(),
            cost,
            p99,
            max,
            front: false,
            bound: None,
        }
    }

    #[test]
    fn the_front_keeps_only_what_no_cheaper_method_beats() {
        // b is dearer and worse than a, c is dearer and better.
        let mut pts = vec![
            pt("c", 30.0, 1e-4, 1e-4),
            pt("b", 20.0, 5e-2, 5e-2),
            pt("a", 10.0, 1e-2, 1e-2),
        ];
        mark_front(&mut pts);
        let front: Vec<&str> = pts
            .iter()
            .filter(|p| p.front)
            .map(|p| p.method.as_str())
            .collect();
        assert_eq!(front, ["a", "c"]);
    }

    /// The chart of `pts` as SVG text.
    fn svg_of(pts: &[Point]) -> String {
        crate::output::heatmap::register_font().unwrap();
        let mut svg = String::new();
        {
            let root =
                SVGBackend::with_string(&mut svg, crate::output::chart::SIZE).into_drawing_area();
            draw(&root, "amd:navi21", ("inverse_throughput", "cycles"), pts).unwrap();
            root.present().unwrap();
        }
        svg
    }

    #[test]
    fn every_point_is_named_and_an_error_above_one_is_marked_on_the_edge() {
        let mut pts = vec![
            pt("phong_exact", 40.0, 0.0, 0.0),
            pt("lyon_taylor", 30.0, 3e-3, 2e-2),
            pt("runaway", 20.0, 2e9, 3e9),
        ];
        pts[1].bound = Some(Unit::LoadStore);
        mark_front(&mut pts);
        let svg = svg_of(&pts);
        for name in ["phong_exact", "lyon_taylor", "runaway"] {
            assert!(svg.contains(name), "{name} not named");
        }
        assert!(
            svg.contains("load_store bound"),
            "the bound unit is not shown"
        );
        assert!(
            svg.contains("p99 2.0e9 above 1"),
            "the off-scale p99 is not in the legend"
        );
        // The axis stops at 1: no tick label of 1e9.
        assert!(!svg.contains("\n1e1\n"), "the axis runs past 1");
        assert!(svg.contains("\n1e0\n"), "the axis does not reach 1");
        // Teeth: without the runaway method nothing is above 1.
        // (The legend's heading says what a triangle means: one "above 1" more.)
        assert_eq!(svg.matches("above 1").count(), 3);
        let tame: Vec<Point> = pts
            .iter()
            .filter(|p| p.method != "runaway")
            .cloned()
            .collect();
        assert_eq!(svg_of(&tame).matches("above 1").count(), 1);
    }
}
