//! Charts written as SVG and PNG of the same drawing (plotters; text through the embedded font).
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::output::heatmap::{self, Figure};

/// The largest error an axis shows: 1 (an error above it is wrong, not a degree of accuracy;
/// such a point is drawn on the top edge, marked, its value in the legend).
pub const ERROR_CEILING_DECADE: i32 = 0;
/// The smallest: 1e-9 (below, float32's rounding; drawn on the bottom edge, marked).
pub const ERROR_FLOOR_DECADE: i32 = -9;

/// The size of every chart, pixels.
pub const SIZE: (u32, u32) = (960, 640);

/// A plotting error, as the project's error.
pub fn plot_err<E: std::fmt::Display>(e: E) -> Error {
    Error::output("a chart", e)
}

/// Draws with `draw` into an SVG and a PNG of the same chart: DIR/<stem>.svg and .png.
pub fn both(
    out: &Path,
    stem: &str,
    draw: &dyn Fn(&DrawingArea<SVGBackend, Shift>) -> Result<()>,
    draw_png: &dyn Fn(&DrawingArea<BitMapBackend, Shift>) -> Result<()>,
) -> Result<()> {
    svg(out, stem, draw)?;
    let mut rgb = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw_png(&root)?;
        root.present().map_err(plot_err)?;
    }
    heatmap::write_png(
        &out.join(format!("{stem}.png")),
        &Figure {
            width: SIZE.0,
            height: SIZE.1,
            rgb,
            bar: (0, 0, 0, 0),
        },
        heatmap::Rows::Charts,
    )
}

/// Draws with `draw` into DIR/<stem>.svg only.
pub fn svg(
    out: &Path,
    stem: &str,
    draw: &dyn Fn(&DrawingArea<SVGBackend, Shift>) -> Result<()>,
) -> Result<()> {
    heatmap::register_font()?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(&root)?;
        root.present().map_err(plot_err)?;
    }
    crate::output::write_bytes_atomic(&out.join(format!("{stem}.svg")), svg.as_bytes())
}
