//! Charts of `bench`: the Pareto chart (run time against error, log scale, 95% intervals,
//! non-dominated methods, by the paired rule of `pareto_front_paired`, marked and labelled)
//! and the sweep charts (time against work), each written as SVG and PNG with plotters.
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::bench::{BenchReport, SweepResult};
use crate::error::{Error, Result};
use crate::output::chart::both;

/// Errors below this are drawn at this value on the log axis (exact zero has no logarithm).
pub const ERROR_FLOOR: f64 = 1e-9;

fn plot_err<E: std::fmt::Display>(e: E) -> Error {
    Error::output("a chart", e)
}

struct Point {
    name: String,
    t: f64,
    lo: f64,
    hi: f64,
    e: f64,
    front: bool,
    /// `auto`'s budget when this point is `auto` at some budget.
    budget: Option<f64>,
}

/// The methods with a finite error, as chart points. A method with non-finite pixels has an
/// infinite error (docs/summary.schema.json): it cannot sit on a log axis, and the chart names
/// it in its caption instead ([`unplottable`]).
fn pareto_points(r: &BenchReport, axis: Axis) -> Vec<Point> {
    r.methods
        .iter()
        .filter_map(|m| {
            let e = r.error_metric.of(m.error.as_ref()?)?;
            if !e.is_finite() {
                return None;
            }
            let (t, lo, hi, front) = match axis {
                Axis::FrameTime => (
                    m.median_ms,
                    m.ci95_low_ms,
                    m.ci95_high_ms,
                    r.pareto_front.contains(&m.name),
                ),
                Axis::IsolatedCost => (
                    m.isolated_ns_per_eval?,
                    m.isolated_ci95_low_ns?,
                    m.isolated_ci95_high_ns?,
                    r.pareto_front_isolated.contains(&m.name),
                ),
            };
            Some(Point {
                name: m.name.clone(),
                t,
                lo,
                hi,
                e: e.max(ERROR_FLOOR),
                front,
                budget: r.auto.iter().find(|a| a.name == m.name).map(|a| a.budget),
            })
        })
        .collect()
}

/// The x axis of a Pareto chart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Axis {
    /// Frame time of the whole draw.
    FrameTime,
    /// Isolated cost of one evaluation of the method's code.
    IsolatedCost,
}

/// The methods whose error is not finite (NaN/Inf pixels), left off the chart.
fn unplottable(r: &BenchReport) -> Vec<&str> {
    r.methods
        .iter()
        .filter(|m| {
            m.error
                .as_ref()
                .and_then(|e| r.error_metric.of(e))
                .is_some_and(|e| !e.is_finite())
        })
        .map(|m| m.name.as_str())
        .collect()
}

fn draw_pareto<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    r: &BenchReport,
    axis: Axis,
) -> Result<()> {
    area.fill(&WHITE).map_err(plot_err)?;
    let pts = pareto_points(r, axis);
    let ((x0, x1), (y0, y1)) = pareto_ranges(&pts);
    let mut chart = ChartBuilder::on(area)
        .caption(pareto_title(r, axis), ("sans-serif", 18))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(76)
        .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(match axis {
            Axis::FrameTime => "draw time per frame (ms)",
            Axis::IsolatedCost => "isolated cost of one evaluation (ns, compute kernel)",
        })
        .y_desc(format!("{} (log)", r.error_metric))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(plot_err)?;
    draw_pareto_series(&mut chart, &pts)
}

/// The axes' ranges: every interval and error, padded (a unit box when nothing is plotted).
fn pareto_ranges(pts: &[Point]) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in pts {
        x0 = x0.min(p.lo);
        x1 = x1.max(p.hi);
        y0 = y0.min(p.e);
        y1 = y1.max(p.e);
    }
    if pts.is_empty() {
        (x0, x1, y0, y1) = (0.0, 1.0, 1e-6, 1.0);
    }
    let pad = ((x1 - x0) * 0.08).max(0.05);
    (((x0 - pad).max(0.0), x1 + pad * 3.0), (y0 / 3.0, y1 * 3.0))
}

/// The chart's title: scene, size, clock, metric, the front's rule and what was left out.
fn pareto_title(r: &BenchReport, axis: Axis) -> String {
    let mut title = match axis {
        Axis::FrameTime => format!(
            "{} {}x{}: run time ({} clock, median, 95% CI) vs {}; front: dominated only beyond the paired interval",
            r.scene, r.width, r.height, r.clock.clock, r.error_metric
        ),
        Axis::IsolatedCost => format!(
            "{} {}x{}: isolated cost per evaluation (median, 95% CI) vs {}; front: dominated only when the intervals separate",
            r.scene, r.width, r.height, r.error_metric
        ),
    };
    let off = unplottable(r);
    if !off.is_empty() {
        title += &format!("; infinite error, not plotted: {}", off.join(", "));
    }
    title
}

/// Confidence bars, the front as a step line, auto's budget curve, the markers and their labels.
fn draw_pareto_series<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, LogCoord<f64>>,
    >,
    pts: &[Point],
) -> Result<()> {
    let blue = RGBColor(31, 119, 180);
    let grey = RGBColor(150, 150, 150);
    // confidence bars
    chart
        .draw_series(pts.iter().map(|p| {
            PathElement::new(
                vec![(p.lo, p.e), (p.hi, p.e)],
                if p.front {
                    blue.stroke_width(2)
                } else {
                    grey.stroke_width(1)
                },
            )
        }))
        .map_err(plot_err)?;
    // the front as a step line
    let mut front: Vec<&Point> = pts.iter().filter(|p| p.front).collect();
    front.sort_by(|a, b| a.t.total_cmp(&b.t));
    chart
        .draw_series(std::iter::once(PathElement::new(
            front.iter().map(|p| (p.t, p.e)).collect::<Vec<_>>(),
            blue.mix(0.5).stroke_width(1),
        )))
        .map_err(plot_err)?;
    // auto's budget curve, in budget order.
    let orange = RGBColor(230, 120, 20);
    let mut curve: Vec<&Point> = pts.iter().filter(|p| p.budget.is_some()).collect();
    curve.sort_by(|a, b| a.budget.unwrap_or(0.0).total_cmp(&b.budget.unwrap_or(0.0)));
    if curve.len() > 1 {
        chart
            .draw_series(std::iter::once(PathElement::new(
                curve.iter().map(|p| (p.t, p.e)).collect::<Vec<_>>(),
                orange.stroke_width(2),
            )))
            .map_err(plot_err)?;
    }
    chart
        .draw_series(
            curve
                .iter()
                .map(|p| Cross::new((p.t, p.e), 6, orange.stroke_width(2))),
        )
        .map_err(plot_err)?;
    chart
        .draw_series(pts.iter().map(|p| {
            let style = if p.front {
                blue.filled()
            } else {
                grey.stroke_width(1)
            };
            Circle::new((p.t, p.e), if p.front { 5 } else { 4 }, style)
        }))
        .map_err(plot_err)?;
    // Labels beside the markers: the front's in black, the others small and grey.
    chart
        .draw_series(pts.iter().map(|p| {
            let style = if p.front {
                ("sans-serif", 13).into_font().color(&BLACK)
            } else {
                ("sans-serif", 10).into_font().color(&grey)
            };
            EmptyElement::at((p.t, p.e))
                + Text::new(p.name.clone(), (7, if p.front { -16 } else { 3 }), style)
        }))
        .map_err(plot_err)?;
    Ok(())
}

/// DIR/pareto.svg and DIR/pareto.png; with isolated costs also DIR/pareto_isolated.svg/png.
pub fn pareto(out: &Path, r: &BenchReport) -> Result<()> {
    if r.methods.iter().any(|m| m.isolated_ns_per_eval.is_some()) {
        both(
            out,
            "pareto_isolated",
            &|a| draw_pareto(a, r, Axis::IsolatedCost),
            &|a| draw_pareto(a, r, Axis::IsolatedCost),
        )?;
    }
    both(
        out,
        "pareto",
        &|a| draw_pareto(a, r, Axis::FrameTime),
        &|a| draw_pareto(a, r, Axis::FrameTime),
    )
}

fn draw_sweep<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, s: &SweepResult) -> Result<()> {
    area.fill(&WHITE).map_err(plot_err)?;
    let xs = s.points.iter().map(|p| p.work.max(1.0));
    let (x0, x1) = xs
        .clone()
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    let (y0, y1) = s.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.ci95_low_ms.max(1e-3)), b.max(p.ci95_high_ms))
    });
    let slopes: Vec<String> = s
        .slopes
        .iter()
        .map(|(n, ms, ll)| format!("{n}: {ms:.3} ms/M, log-log {ll:.2}"))
        .collect();
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("time vs {} ({})", s.work, slopes.join("; ")),
            ("sans-serif", 14),
        )
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 1.5..y1 * 1.5).log_scale(),
        )
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(s.work.clone())
        .y_desc("median draw time (ms, wall clock)")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(plot_err)?;
    let colors = [
        RGBColor(120, 120, 120),
        RGBColor(214, 39, 40),
        RGBColor(31, 119, 180),
    ];
    for (k, (name, _, _)) in s.slopes.iter().enumerate() {
        let c = colors[k % colors.len()];
        let pts: Vec<_> = s.points.iter().filter(|p| &p.program == name).collect();
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (p.work.max(1.0), p.median_ms)),
                c.stroke_width(2),
            ))
            .map_err(plot_err)?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|p| {
                PathElement::new(
                    vec![
                        (p.work.max(1.0), p.ci95_low_ms),
                        (p.work.max(1.0), p.ci95_high_ms),
                    ],
                    c,
                )
            }))
            .map_err(plot_err)?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(plot_err)?;
    Ok(())
}

/// DIR/sweep_<size|triangles>.svg and .png.
pub fn sweep(out: &Path, s: &SweepResult) -> Result<()> {
    let stem = match s.sweep {
        crate::bench::Sweep::Size => "sweep_size",
        crate::bench::Sweep::Triangles => "sweep_triangles",
    };
    both(out, stem, &|a| draw_sweep(a, s), &|a| draw_sweep(a, s))
}
