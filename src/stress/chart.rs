//! Charts of `stress`: error against the angle between the vertex normals and against the
//! shininess (log y, one line per method, non-finite points drawn as crosses on the top edge),
//! and one validity map per method (angle x elevation, worst error per cell, with a colorbar).
//! Each case is evaluated once (the device is deterministic), so there is no repetition and no
//! interval band to draw.
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{CurvePoint, MethodStress, StressReport};
use crate::error::Result;
use crate::output::chart::{both, plot_err};
use crate::output::heatmap::{self, Figure};

/// Errors below this are drawn at it (log axis).
const FLOOR: f64 = 1e-9;
/// Where a non-finite point is drawn.
const TOP: f64 = 10.0;

/// The axes of an error chart (a macro: the x coordinate type differs between linear and log).
macro_rules! label {
    ($chart:ident, $x_desc:expr) => {
        $chart
            .configure_mesh()
            .x_desc($x_desc)
            .y_desc("worst |colour error| (linear)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(plot_err)?
    };
}

fn palette(i: usize) -> RGBColor {
    let c = colorous::TABLEAU10[i % 10];
    RGBColor(c.r, c.g, c.b)
}

/// One method's points as (x, worst error or `None` when non-finite).
type Curve = Vec<(f64, Option<f64>)>;
/// Plotted points (x, y).
type Series = Vec<(f64, f64)>;

/// One line per method through `points(m)` as (x, worst error or non-finite).
fn draw_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    r: &StressReport,
    caption: &str,
    x_desc: &str,
    x_log: bool,
    points: &dyn Fn(&MethodStress) -> Curve,
) -> Result<()> {
    area.fill(&WHITE).map_err(plot_err)?;
    let all: Vec<(f64, Option<f64>)> = r.methods.iter().flat_map(points).collect();
    let (x0, x1) = all
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    if !x0.is_finite() {
        return Ok(());
    }
    let (plot, legend) = area.split_horizontally(700);
    let mut builder = ChartBuilder::on(&plot);
    builder
        .caption(caption, ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(64);
    let y = (FLOOR..TOP * 2.0).log_scale();
    let lines = |draw: &mut dyn FnMut(usize, Series, Series) -> Result<()>| {
        for (i, m) in r.methods.iter().enumerate() {
            let pts = points(m);
            let finite = pts
                .iter()
                .map(|&(x, e)| (x, e.unwrap_or(TOP).max(FLOOR)))
                .collect();
            let crosses = pts
                .iter()
                .filter(|p| p.1.is_none())
                .map(|&(x, _)| (x, TOP))
                .collect();
            draw(i, finite, crosses)?;
        }
        Ok(())
    };
    // Both branches draw the same series; only the x coordinate's type differs.
    macro_rules! series {
        ($chart:ident) => {
            label!($chart, x_desc);
            lines(&mut |i, finite, crosses| {
                $chart
                    .draw_series(LineSeries::new(finite, palette(i).stroke_width(1)))
                    .map_err(plot_err)?;
                $chart
                    .draw_series(crosses.into_iter().map(|p| Cross::new(p, 4, palette(i))))
                    .map_err(plot_err)?;
                Ok(())
            })?;
        };
    }
    if x_log {
        let mut chart = builder
            .build_cartesian_2d((x0.max(1e-3)..x1 * 1.2).log_scale(), y)
            .map_err(plot_err)?;
        series!(chart);
    } else {
        let mut chart = builder.build_cartesian_2d(x0..x1, y).map_err(plot_err)?;
        series!(chart);
    }
    // The legend: one short line and the name per method, with the line's dash colour.
    for (i, m) in r.methods.iter().enumerate() {
        let yy = 14 + 16 * i as i32;
        legend
            .draw(&PathElement::new(
                vec![(4, yy), (22, yy)],
                palette(i).stroke_width(2),
            ))
            .map_err(plot_err)?;
        legend
            .draw(&Text::new(m.name.clone(), (26, yy - 6), ("sans-serif", 11)))
            .map_err(plot_err)?;
    }
    Ok(())
}

fn angle_points(m: &MethodStress) -> Vec<(f64, Option<f64>)> {
    m.error_vs_angle.iter().map(point).collect()
}

fn point(p: &CurvePoint) -> (f64, Option<f64>) {
    let v = if p.device.non_finite > 0 {
        None
    } else {
        p.device.max
    };
    (*p.key.last().unwrap_or(&0.0), v)
}

/// The angle at which error_vs_shininess is drawn.
pub const SHININESS_CHART_ANGLE: f64 = 15.0;

/// DIR/error_vs_angle.svg and .png.
pub fn error_vs_angle(out: &Path, r: &StressReport) -> Result<()> {
    let caption = "worst error vs angle between the vertex normals (facing the viewer)";
    let x = "angle between the vertex normals (degrees)";
    both(
        out,
        "error_vs_angle",
        &|a| draw_lines(a, r, caption, x, false, &angle_points),
        &|a| draw_lines(a, r, caption, x, false, &angle_points),
    )
}

fn shininess_points(m: &MethodStress) -> Vec<(f64, Option<f64>)> {
    m.error_vs_shininess
        .iter()
        .filter(|p| p.key[0] == SHININESS_CHART_ANGLE)
        .map(point)
        .collect()
}

/// DIR/error_vs_shininess.svg and .png (at [`SHININESS_CHART_ANGLE`]).
pub fn error_vs_shininess(out: &Path, r: &StressReport) -> Result<()> {
    let caption =
        format!("worst error vs shininess, vertex normals {SHININESS_CHART_ANGLE} degrees apart");
    let x = "shininess n";
    both(
        out,
        "error_vs_shininess",
        &|a| draw_lines(a, r, &caption, x, true, &shininess_points),
        &|a| draw_lines(a, r, &caption, x, true, &shininess_points),
    )
}

/// Cell size of the validity map, pixels.
const CELL: u32 = 18;

/// DIR/validity/<method>.png: the worst device error per (angle, elevation) cell (angle to the
/// right in the sweep's order, elevation down), magma on a log scale with the threshold
/// marked on the colorbar's scale; grey cells are non-finite.
pub fn validity_map(path: &Path, m: &MethodStress, threshold: f64) -> Result<()> {
    let v = &m.validity_map;
    let (cols, rows) = (v.angles_deg.len() as u32, v.elevations_deg.len() as u32);
    let (w, h) = (cols * CELL, rows * CELL);
    let desc = heatmap::HeatmapDesc {
        label: "worst |colour error| per cell",
        gradient: heatmap::Colormap::Magma,
        scale: heatmap::Scale::Log {
            lo: (threshold / 100.0).max(1e-9),
            hi: 1.0,
        },
    };
    let value = |i: usize| {
        let (x, y) = (i as u32 % w / CELL, i as u32 / w / CELL);
        let c = &v.cells[y as usize][x as usize];
        if c.non_finite > 0 {
            None
        } else {
            c.max
        }
    };
    let field = heatmap::render(&value, w, h, &desc)?;
    // Margins for the axis labels around the field.
    let (left, top, bottom) = (64u32, 30u32, 46u32);
    let fw = field.width + left;
    let fh = field.height.max(h + top + bottom) + top;
    let mut rgb = vec![255u8; (fw * fh * 3) as usize];
    for y in 0..field.height {
        for x in 0..field.width {
            let s = ((y * field.width + x) * 3) as usize;
            let d = (((y + top) * fw + x + left) * 3) as usize;
            rgb[d..d + 3].copy_from_slice(&field.rgb[s..s + 3]);
        }
    }
    {
        crate::output::heatmap::register_font()?;
        let root = BitMapBackend::with_buffer(&mut rgb, (fw, fh)).into_drawing_area();
        let font = ("sans-serif", 11).into_font();
        root.draw(&Text::new(
            format!(
                "{}: worst error, angle (x) by elevation (y); grey = NaN/Inf",
                m.name
            ),
            (4, 6),
            ("sans-serif", 13),
        ))
        .map_err(plot_err)?;
        for (k, a) in v.angles_deg.iter().enumerate() {
            if [0.0, 15.0, 45.0, 90.0, 135.0, 179.0, 180.0].contains(a) {
                let x = (left + k as u32 * CELL) as i32;
                root.draw(&Text::new(
                    format!("{a}"),
                    (x, (top + h + 4) as i32),
                    font.clone(),
                ))
                .map_err(plot_err)?;
            }
        }
        root.draw(&Text::new(
            "angle between the vertex normals (degrees)",
            (left as i32, (top + h + 22) as i32),
            font.clone(),
        ))
        .map_err(plot_err)?;
        for (k, e) in v.elevations_deg.iter().enumerate() {
            if k % 3 == 0 || *e == 90.0 || *e == 180.0 {
                let y = (top + k as u32 * CELL + 3) as i32;
                root.draw(&Text::new(format!("{e}"), (8, y), font.clone()))
                    .map_err(plot_err)?;
            }
        }
        root.draw(&Text::new("elev.", (8, (top - 14) as i32), font.clone()))
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }
    heatmap::write_png(
        path,
        &Figure {
            width: fw,
            height: fh,
            rgb,
            bar: (0, 0, 0, 0),
        },
        heatmap::Rows::Charts,
    )
}
