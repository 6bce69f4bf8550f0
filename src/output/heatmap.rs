//! Heatmaps with colorbars: a per-pixel scalar field -> an RGB figure whose right-hand panel is
//! a colorbar with numbered ticks and the quantity's units. Colormaps are matplotlib's magma and
//! ColorBrewer's RdBu, `colorous`'s colours computed by [`Colormap`] (exactly, faster); ticks
//! and labels are drawn by `plotters` with the DejaVu Sans font embedded in the binary (no
//! system fonts needed).
use std::sync::Once;

use plotters::prelude::*;

pub use crate::output::colormap::Colormap;

use crate::output::colormap::Changes;
use crate::output::steps::ONE;

use crate::error::{Error, Result};

/// How values map to the colormap.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Scale {
    /// `lo..hi` linearly.
    Linear { lo: f64, hi: f64 },
    /// `lo..hi` on a log10 axis (values below `lo` take the bottom colour).
    Log { lo: f64, hi: f64 },
}

impl Scale {
    /// Position of `v` on the colormap, clamped to [0, 1].
    pub fn t(&self, v: f64) -> f64 {
        let t = match *self {
            Scale::Linear { lo, hi } => (v - lo) / (hi - lo),
            Scale::Log { lo, hi } => (v.max(lo).log10() - lo.log10()) / (hi.log10() - lo.log10()),
        };
        if t.is_nan() {
            0.0
        } else {
            t.clamp(0.0, 1.0)
        }
    }

    /// [`Scale::t`] with the scale's own logarithms taken once, for a field of values.
    fn mapping(&self) -> Mapping {
        match *self {
            Scale::Linear { lo, hi } => Mapping::Linear { lo, span: hi - lo },
            Scale::Log { lo, hi } => Mapping::Log {
                lo,
                log_lo: lo.log10(),
                span: hi.log10() - lo.log10(),
                floor: self.t(lo),
            },
        }
    }

    /// The value at colormap position `t`.
    pub fn value(&self, t: f64) -> f64 {
        match *self {
            Scale::Linear { lo, hi } => lo + t * (hi - lo),
            Scale::Log { lo, hi } => 10f64.powf(lo.log10() + t * (hi.log10() - lo.log10())),
        }
    }

    /// The (lo, hi) range.
    pub fn range(&self) -> (f64, f64) {
        match *self {
            Scale::Linear { lo, hi } | Scale::Log { lo, hi } => (lo, hi),
        }
    }
}

/// [`Scale::t`] per pixel: the same operations on the same values, with the parts that depend
/// only on the scale (`hi - lo`, the logarithms of `lo` and `hi`) computed once.
#[derive(Debug, Clone, Copy)]
enum Mapping {
    Linear {
        lo: f64,
        span: f64,
    },
    /// `floor` is `t(lo)`: every finite `v <= lo` has `v.max(lo)` equal to `lo` in value (the
    /// only equal values with other bits are +-0, whose log10 are both -inf), so `t(v) = t(lo)`
    /// without its logarithm.
    Log {
        lo: f64,
        log_lo: f64,
        span: f64,
        floor: f64,
    },
}

impl Mapping {
    /// [`Scale::t`] of a finite `v`.
    #[inline]
    fn t(&self, v: f64) -> f64 {
        let t = match *self {
            Mapping::Linear { lo, span } => (v - lo) / span,
            Mapping::Log { lo, floor, .. } if v <= lo => return floor,
            Mapping::Log {
                lo, log_lo, span, ..
            } => (v.max(lo).log10() - log_lo) / span,
        };
        if t.is_nan() {
            0.0
        } else {
            t.clamp(0.0, 1.0)
        }
    }
}

/// Everything that describes one heatmap.
#[derive(Debug, Clone, Copy)]
pub struct HeatmapDesc<'a> {
    /// Colorbar label with units, e.g. "|dI| (linear intensity)".
    pub label: &'a str,
    pub gradient: Colormap,
    pub scale: Scale,
}

/// A rendered figure: RGB8 pixels, and where the colorbar's gradient was drawn.
pub struct Figure {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    /// Pixel rectangle (x0, y0, x1, y1), exclusive ends, of the colorbar gradient: bottom = `lo`.
    pub bar: (u32, u32, u32, u32),
}

/// Colour of pixels outside the field (background, or covered by only one of two images).
pub const NO_DATA: [u8; 3] = [128, 128, 128];
/// Width of the colorbar panel in pixels.
const PANEL: u32 = 130;

/// The colour `gradient` gives at `t` in [0, 1] (clamped): colorous's
/// `eval_continuous(t.clamp(0.0, 1.0))`, which evaluates the f32 nearest `t`.
pub fn color_at(gradient: &Colormap, t: f64) -> [u8; 3] {
    gradient.rgb(t.clamp(0.0, 1.0) as f32)
}

/// A field of values to draw, row-major, `None` = no data.
#[derive(Clone, Copy)]
pub enum Field<'a> {
    /// `value(i)` at pixel `i`: a function, so a caller maps its own storage without a copy.
    Fn(&'a dyn Fn(usize) -> Option<f64>),
    /// `values[i]` where `mask[i]` (its absolute value when `abs`), no data elsewhere: a field
    /// the figure reads without a call per pixel. Both slices cover the field.
    Masked {
        values: &'a [f64],
        mask: &'a [bool],
        abs: bool,
    },
}

/// The position of a pixel without data in a row of positions: no f32 in [0, 1] (nor -0.0,
/// the other position [`Mapping::t`] can give) has these bits.
const NO_POSITION: u32 = u32::MAX;

impl Mapping {
    /// The colormap positions of a row, as f32 bits: `t(v) as f32` of each finite value, and
    /// [`NO_POSITION`] for no data or a value that is not finite. Runs of one value take the
    /// position once (the log scale's `log10` is a libm call).
    fn positions(&self, out: &mut [u32], values: impl Iterator<Item = Option<f64>>) {
        let mut last = (f64::NAN.to_bits(), NO_POSITION);
        for (p, v) in out.iter_mut().zip(values) {
            *p = match v {
                Some(v) if v.is_finite() => {
                    if last.0 != v.to_bits() {
                        last = (v.to_bits(), (self.t(v) as f32).to_bits());
                    }
                    last.1
                }
                _ => NO_POSITION,
            };
        }
    }

    /// [`Mapping::positions`] of `values[i]` (`|values[i]|` when `ABS`) where `mask[i]`: on a
    /// linear scale, every pixel's `(v - lo) / span`, clamped, as one loop without a branch on
    /// the data (the divisions overlap instead of waiting on each other), the value then
    /// dropped where there is no data; the same operations on the same values. (On a log
    /// scale, the `log10` per value in a loop of its own and then the divisions in this one
    /// measured no faster: perf, busy, 616 -> 670 samples.)
    fn masked_positions<const ABS: bool>(&self, out: &mut [u32], values: &[f64], mask: &[bool]) {
        let Mapping::Linear { lo, span } = *self else {
            let value = |(&v, &m): (&f64, &bool)| m.then_some(if ABS { v.abs() } else { v });
            return self.positions(out, values.iter().zip(mask).map(value));
        };
        for ((p, &v), &m) in out.iter_mut().zip(values).zip(mask) {
            let v = if ABS { v.abs() } else { v };
            let t = (v - lo) / span;
            let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
            let bits = (t as f32).to_bits();
            *p = if m && v.is_finite() {
                bits
            } else {
                NO_POSITION
            };
        }
    }
}

/// The colours of a row's colormap positions: positions inside the last coloured region of
/// the colormap, or equal to the previous one (every error below a log scale's floor is at
/// t = 0), reuse its colour, the colour being a function of the position.
struct Painter {
    table: &'static Changes,
    /// The coloured region ([`Changes::region`]) of the last position looked up: its first bit
    /// pattern, its length in patterns (0 at first: no pattern is inside) and its colour.
    region: (u32, u32, [u8; 3]),
    /// The last colormap position's bits and colour (a NaN's at first: `t` is never NaN).
    last_t: (u32, [u8; 3]),
}

impl Painter {
    fn new(table: &'static Changes) -> Painter {
        Painter {
            table,
            region: (0, 0, NO_DATA),
            last_t: (f32::NAN.to_bits(), NO_DATA),
        }
    }

    /// [`Changes::rgb`] of the position `b` (bits of an f32 `t`), from the last coloured region
    /// when `b` lies in it (neighbouring pixels mostly do: no bucket index or region start to
    /// load), else from the last position, else looked up (keeping its region when it has a
    /// colour).
    #[inline]
    fn color_at(&mut self, b: u32) -> [u8; 3] {
        // `b - start` wraps past the length for patterns below the start
        if b.wrapping_sub(self.region.0) < self.region.1 {
            return self.region.2;
        }
        if self.last_t.0 == b {
            return self.last_t.1;
        }
        let c = match (b <= ONE).then(|| self.table.region(b)) {
            Some((start, end, Some(c))) => {
                self.region = (start, end - start, c);
                c
            }
            // a region the spline colours, or -0.0 (its bit pattern is past ONE)
            _ => self.table.spline_rgb(f32::from_bits(b)),
        };
        self.last_t = (b, c);
        c
    }

    /// Colours `row` (3 bytes per pixel) from its `positions`, NO_DATA where there is none.
    #[inline]
    fn row(&mut self, row: &mut [u8], positions: &[u32]) {
        for (px, &b) in row.chunks_exact_mut(3).zip(positions) {
            let c = if b == NO_POSITION {
                NO_DATA
            } else {
                self.color_at(b)
            };
            px.copy_from_slice(&c);
        }
    }
}

/// The figure's pixels, row-major, `fig_w` x `fig_h`: the field `values` (`width` x `height`)
/// in the top-left corner, white elsewhere. `rgb` is a buffer to reuse (its content is
/// dropped; one of another size is replaced by zeroed pages): every byte is written once, by
/// index. Per row, the colormap positions of its values, then their colours.
fn field_pixels(
    values: Field,
    (width, height): (u32, u32),
    (fig_w, fig_h): (u32, u32),
    desc: &HeatmapDesc,
    mut rgb: Vec<u8>,
) -> Vec<u8> {
    let (mapping, mut painter) = (desc.scale.mapping(), Painter::new(desc.gradient.changes()));
    let (w, stride) = (width as usize, fig_w as usize * 3);
    if rgb.len() != stride * fig_h as usize {
        drop(rgb);
        rgb = vec![0u8; stride * fig_h as usize];
    }
    let mut positions = vec![NO_POSITION; w];
    for (y, row) in rgb.chunks_exact_mut(stride).enumerate() {
        if y >= height as usize {
            row.fill(255);
            continue;
        }
        let (out, margin) = row.split_at_mut(w * 3);
        margin.fill(255);
        let span = y * w..(y + 1) * w;
        match values {
            Field::Fn(f) => mapping.positions(&mut positions, span.map(f)),
            Field::Masked { values, mask, abs } => {
                let (values, mask) = (&values[span.clone()], &mask[span]);
                if abs {
                    mapping.masked_positions::<true>(&mut positions, values, mask)
                } else {
                    mapping.masked_positions::<false>(&mut positions, values, mask)
                }
            }
        }
        painter.row(out, &positions);
    }
    rgb
}

pub(crate) fn register_font() -> Result<()> {
    static ONCE: Once = Once::new();
    let mut result = Ok(());
    ONCE.call_once(|| {
        result = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        )
        .map_err(|_| {
            Error::output(
                "figures",
                "the embedded DejaVu Sans font could not be registered",
            )
        });
    });
    result
}

fn plot_err<E: std::fmt::Display>(e: E) -> Error {
    Error::output("a heatmap", e)
}

/// Draws the field `values(i)` (i row-major, `None` = no data; a function, so a caller maps its
/// own storage without a copy) as a heatmap of `width` x `height` with a colorbar panel on the right.
pub fn render(
    values: &dyn Fn(usize) -> Option<f64>,
    width: u32,
    height: u32,
    desc: &HeatmapDesc,
) -> Result<Figure> {
    render_reusing(Field::Fn(values), width, height, desc, Vec::new())
}

/// [`render`] of any [`Field`] into `buffer` (e.g. the `rgb` of a figure already written): one
/// allocation, and its pages touched once, for a series of figures of one size.
pub fn render_reusing(
    values: Field,
    width: u32,
    height: u32,
    desc: &HeatmapDesc,
    buffer: Vec<u8>,
) -> Result<Figure> {
    register_font()?;
    let fig_w = width + PANEL;
    let fig_h = height.max(200);
    let mut rgb = field_pixels(values, (width, height), (fig_w, fig_h), desc, buffer);
    let bar;
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (fig_w, fig_h)).into_drawing_area();
        let (_, panel) = root.split_horizontally(width);
        let (lo, hi) = desc.scale.range();
        let font = ("sans-serif", 12).into_font();
        let mut builder = ChartBuilder::on(&panel);
        builder
            .margin_top(14)
            .margin_bottom(14)
            .margin_right(8)
            .y_label_area_size(62);
        let steps = 256;
        // The bar is drawn in colormap space (t from 0 at the bottom to 1 at the top, linear),
        // as `steps` bands; tick labels show the scale's value at t. With the fixed log scale
        // (five decades) the ticks at t = 0, 0.2, ... 1 fall on whole decades.
        let mut chart = builder
            .build_cartesian_2d(0f64..1f64, 0f64..1f64)
            .map_err(plot_err)?;
        chart
            .draw_series((0..steps).map(|i| {
                let (t0, t1) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
                let c = color_at(&desc.gradient, (t0 + t1) / 2.0);
                Rectangle::new([(0.0, t0), (1.0, t1)], RGBColor(c[0], c[1], c[2]).filled())
            }))
            .map_err(plot_err)?;
        let label = |t: &f64| {
            let v = desc.scale.value(*t);
            match desc.scale {
                // whole decades as 1e-3, anything else with one more digit (2.5e-4)
                Scale::Log { .. } if (v.log10() - v.log10().round()).abs() < 1e-9 => {
                    format!("{v:.0e}")
                }
                Scale::Log { .. } => format!("{v:.1e}"),
                Scale::Linear { .. } => format_tick(v, hi - lo),
            }
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(6)
            .y_label_style(font.clone())
            .y_label_formatter(&label)
            .y_desc(desc.label)
            .axis_desc_style(font)
            .draw()
            .map_err(plot_err)?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        bar = (
            xr.start as u32,
            yr.start as u32,
            xr.end as u32,
            yr.end as u32,
        );
        root.present().map_err(plot_err)?;
    }
    // plotters reports the plotting area in the root's (figure) coordinates.
    Ok(Figure {
        width: fig_w,
        height: fig_h,
        rgb,
        bar,
    })
}

/// A tick label with as many decimals as the span needs.
fn format_tick(v: f64, span: f64) -> String {
    if span.abs() >= 10.0 {
        format!("{v:.0}")
    } else if span.abs() >= 1.0 {
        format!("{v:.1}")
    } else if span.abs() >= 0.01 {
        format!("{v:.3}")
    } else {
        format!("{v:.1e}")
    }
}

/// How a figure is compressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rows {
    /// Lines and text on white (charts, validity maps): zlib's default level (6), each row's
    /// best predictor (PNG's adaptive filter).
    Charts,
    /// A per-pixel field in colormap colours, written by the hundred (compare's heatmaps),
    /// whose neighbours seldom predict each other: zlib level 4, rows unfiltered.
    Field,
}

/// Writes a figure as PNG. Measured on the report of the shipped scenes (`png` crate, levels
/// 1-9 and every filter): compare's 624 heatmaps take 16.9 MB as [`Rows::Field`] against
/// 24.7 MB at the fast level, about 2 ms each (busy; the default level saves 0.7 MB more for
/// twice the time); the charts and validity maps 2.4 MB as [`Rows::Charts`] against 5.4 MB.
pub fn write_png(path: &std::path::Path, fig: &Figure, rows: Rows) -> Result<()> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder;
    let (level, filter) = match rows {
        Rows::Charts => (CompressionType::Default, FilterType::Adaptive),
        Rows::Field => (CompressionType::Level(4), FilterType::NoFilter),
    };
    let (w, h) = (fig.width, fig.height);
    crate::output::write_atomic(path, |out| {
        let png = PngEncoder::new_with_quality(out, level, filter);
        let written = png.write_image(&fig.rgb, w, h, image::ExtendedColorType::Rgb8);
        written.map_err(std::io::Error::other)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colormap_endpoints_are_magma_and_rdbu_ends() {
        // matplotlib's magma starts near black and ends pale yellow; RdBu runs red -> blue.
        let m0 = color_at(&Colormap::Magma, 0.0);
        let m1 = color_at(&Colormap::Magma, 1.0);
        assert!(m0.iter().all(|&c| c < 10), "{m0:?}");
        assert!(m1[0] > 240 && m1[1] > 240 && m1[2] > 150, "{m1:?}");
        let r0 = color_at(&Colormap::RedBlue, 0.0);
        let r1 = color_at(&Colormap::RedBlue, 1.0);
        assert!(r0[0] > r0[2] && r1[2] > r1[0], "{r0:?} {r1:?}");
        // clamped outside [0, 1]
        assert_eq!(color_at(&Colormap::Magma, -3.0), m0);
        assert_eq!(color_at(&Colormap::Magma, 7.0), m1);
    }

    #[test]
    fn scales_map_ends_and_clamp() {
        let lin = Scale::Linear { lo: -0.1, hi: 0.1 };
        assert_eq!(lin.t(0.0), 0.5);
        assert_eq!(lin.t(-1.0), 0.0);
        assert_eq!(lin.t(1.0), 1.0);
        let log = Scale::Log { lo: 1e-5, hi: 1.0 };
        assert!((log.t(1e-3) - 0.4).abs() < 1e-12);
        assert_eq!(log.t(0.0), 0.0);
        assert!((log.value(0.4) - 1e-3).abs() < 1e-15);
        assert_eq!(lin.t(f64::NAN), 0.0);
    }

    /// The field as it was drawn before [`field_pixels`]: a white figure, then per pixel
    /// colorous's colour at `Scale::t` (or NO_DATA).
    fn field_by_definition(
        values: &[Option<f64>],
        (w, h): (u32, u32),
        fig_w: u32,
        fig_h: u32,
        gradient: colorous::Gradient,
        scale: Scale,
    ) -> Vec<u8> {
        let mut rgb = vec![255u8; (fig_w * fig_h * 3) as usize];
        for y in 0..h {
            for x in 0..w {
                let c = match values[(y * w + x) as usize] {
                    Some(v) if v.is_finite() => {
                        let c = gradient.eval_continuous(scale.t(v).clamp(0.0, 1.0));
                        [c.r, c.g, c.b]
                    }
                    _ => NO_DATA,
                };
                let o = ((y * fig_w + x) * 3) as usize;
                rgb[o..o + 3].copy_from_slice(&c);
            }
        }
        rgb
    }

    /// Values that exercise every path: runs of one value, +-0, values below, at and above a
    /// log scale's floor, NaN/Inf and no data, negative values, a smooth ramp.
    fn awkward_values(n: usize) -> Vec<Option<f64>> {
        (0..n)
            .map(|i| match i % 23 {
                0 => None,
                1 => Some(f64::NAN),
                2 => Some(f64::INFINITY),
                3..=5 => Some(0.0),
                6 => Some(-0.0),
                7 => Some(1e-5),
                8 => Some(-3e-3 * (i % 7) as f64),
                9 | 10 => Some(2.5e-6),
                _ => Some((i as f64 * 0.618_033_988_7).fract().powi(3) * 1.3 - 0.05),
            })
            .collect()
    }

    #[test]
    fn mapping_equals_scale_t() {
        let scales = [
            Scale::Linear { lo: -0.1, hi: 0.1 },
            Scale::Linear { lo: 0.0, hi: 7.3 },
            Scale::Log { lo: 1e-5, hi: 1.0 },
            Scale::Log {
                lo: 3.7e-9,
                hi: 3.7e-5,
            },
            Scale::Log { lo: 0.0, hi: 1.0 },
            Scale::Log { lo: 1.0, hi: 1.0 },
        ];
        let values: Vec<f64> = awkward_values(5000).into_iter().flatten().collect();
        for scale in scales {
            let m = scale.mapping();
            for &v in values.iter().filter(|v| v.is_finite()) {
                assert_eq!(m.t(v).to_bits(), scale.t(v).to_bits(), "{scale:?} at {v:e}");
            }
        }
        // teeth: the check sees a mapping of another scale
        let (a, b) = (
            Scale::Log { lo: 1e-5, hi: 1.0 },
            Scale::Log { lo: 1e-4, hi: 1.0 },
        );
        assert!(values
            .iter()
            .any(|&v| b.mapping().t(v).to_bits() != a.t(v).to_bits()));
    }

    /// The figure's field and white margins equal the per-pixel definition, byte for byte.
    #[test]
    fn field_pixels_equal_the_per_pixel_definition() {
        let (w, h) = (97u32, 61u32);
        let values = awkward_values((w * h) as usize);
        let cases = [
            (Colormap::Magma, Scale::Log { lo: 1e-5, hi: 1.0 }),
            (Colormap::Magma, Scale::Linear { lo: 0.0, hi: 1.2 }),
            (Colormap::RedBlue, Scale::Linear { lo: -1.0, hi: 1.0 }),
            (Colormap::RedBlue, Scale::Log { lo: 1e-3, hi: 1e-2 }),
        ];
        for (map, scale) in cases {
            let desc = HeatmapDesc {
                label: "",
                gradient: map,
                scale,
            };
            let sizes = [(w + PANEL, 200), (w, h), (w + 3, h + 1)];
            // dirty buffers to reuse: of another size, and of the figure's own size
            let buffers = |fig_w: u32, fig_h: u32| {
                [5, 3].map(|bytes| vec![7u8; bytes * (fig_w * fig_h) as usize])
            };
            for ((fig_w, fig_h), used) in sizes
                .into_iter()
                .flat_map(|s| buffers(s.0, s.1).map(|b| (s, b)))
            {
                let got = field_pixels(
                    Field::Fn(&|i| values[i]),
                    (w, h),
                    (fig_w, fig_h),
                    &desc,
                    used,
                );
                let want =
                    field_by_definition(&values, (w, h), fig_w, fig_h, map.colorous(), scale);
                assert!(got == want, "{map:?} {scale:?} {fig_w}x{fig_h}");
                // teeth: the other colormap's figure is not this one's
                let other = match map {
                    Colormap::Magma => colorous::RED_BLUE,
                    Colormap::RedBlue => colorous::MAGMA,
                };
                assert!(got != field_by_definition(&values, (w, h), fig_w, fig_h, other, scale));
            }
        }
    }

    /// Positions that cross every region of both colormaps in order (each start, its
    /// neighbours and the middle of the region), as neighbouring pixels of a smooth field do,
    /// then back down and around again at random: the painter's colours (reusing the last
    /// coloured region) are colorous's at each position. Teeth: a painter whose regions reach
    /// one pattern too far gives other colours.
    #[test]
    fn painter_rows_equal_colorous_across_every_region() {
        for map in [Colormap::Magma, Colormap::RedBlue] {
            let table = map.changes();
            let mut positions = Vec::new();
            let mut b = 0;
            while b <= ONE {
                let (start, end, _) = table.region(b);
                let mid = start + (end - start) / 2;
                positions.extend([start.saturating_sub(1), start, start + 1, mid, end - 1]);
                b = end;
            }
            let down: Vec<u32> = positions.iter().rev().copied().collect();
            let mut rng = fastrand::Rng::with_seed(28);
            positions.extend(down);
            positions.extend((0..20_000).map(|_| rng.u32(0..=ONE)));
            positions.extend([NO_POSITION, (-0.0f32).to_bits(), ONE, 0, NO_POSITION]);
            let colorous = map.colorous();
            let want: Vec<u8> = positions
                .iter()
                .flat_map(|&b| match b {
                    NO_POSITION => NO_DATA,
                    _ => {
                        let c = colorous.eval_continuous(f32::from_bits(b) as f64);
                        [c.r, c.g, c.b]
                    }
                })
                .collect();
            let mut got = vec![0u8; positions.len() * 3];
            Painter::new(table).row(&mut got, &positions);
            assert!(got == want, "{map:?}");
            // teeth: after every colour, the kept region one pattern longer
            let mut wrong = Painter::new(table);
            let wrong_rgb: Vec<u8> = positions
                .iter()
                .flat_map(|&b| {
                    let mut px = [0u8; 3];
                    wrong.row(&mut px, &[b]);
                    wrong.region.1 = wrong.region.1.saturating_add(1);
                    px
                })
                .collect();
            assert!(wrong_rgb != want, "{map:?}");
        }
    }

    /// A masked field of slices draws the figure of the same field as a function (what
    /// compare drew with before: `mask[i].then(|| values[i])`, `abs` mapped on it), byte for
    /// byte, and the per-pixel definition's; teeth: the other `abs`, or one pixel's mask
    /// flipped, gives another figure.
    #[test]
    fn masked_fields_equal_the_same_field_as_a_function() {
        let (w, h) = (97u32, 61u32);
        let n = (w * h) as usize;
        let awkward = awkward_values(n);
        let values: Vec<f64> = awkward.iter().map(|v| v.unwrap_or(0.25)).collect();
        let mask: Vec<bool> = (0..n)
            .map(|i| awkward[i].is_some() && i % 31 != 4)
            .collect();
        let cases = [
            (Colormap::Magma, Scale::Log { lo: 1e-5, hi: 1.0 }, true),
            (
                Colormap::RedBlue,
                Scale::Linear { lo: -0.1, hi: 0.1 },
                false,
            ),
            (Colormap::Magma, Scale::Linear { lo: 0.0, hi: 10.0 }, false),
            (Colormap::Magma, Scale::Linear { lo: 0.0, hi: 0.3 }, true),
            (Colormap::RedBlue, Scale::Log { lo: 1e-3, hi: 1e-2 }, false),
        ];
        let draw = |field: Field, desc: &HeatmapDesc| {
            field_pixels(field, (w, h), (w + PANEL, 200), desc, vec![9u8; 17])
        };
        for (gradient, scale, abs) in cases {
            let desc = HeatmapDesc {
                label: "",
                gradient,
                scale,
            };
            let masked = |values: &[f64], mask: &[bool], abs| {
                draw(Field::Masked { values, mask, abs }, &desc)
            };
            let f = |i: usize| {
                mask[i]
                    .then(|| values[i])
                    .map(|v| if abs { v.abs() } else { v })
            };
            let want = draw(Field::Fn(&f), &desc);
            assert!(
                masked(&values, &mask, abs) == want,
                "{gradient:?} {scale:?} {abs}"
            );
            let defined: Vec<Option<f64>> = (0..n).map(f).collect();
            let by_definition =
                field_by_definition(&defined, (w, h), w + PANEL, 200, gradient.colorous(), scale);
            assert!(want == by_definition);
            // teeth
            assert!(
                masked(&values, &mask, !abs) != want,
                "{gradient:?} {scale:?} {abs}"
            );
            let mut other = mask.clone();
            let i = (0..n)
                .find(|&i| mask[i] && values[i].is_finite() && values[i] != 0.0)
                .unwrap();
            other[i] = false;
            assert!(masked(&values, &other, abs) != want);
        }
        // a log scale from 0 (every position is 0 or NaN, then 0) draws the same too
        let desc = HeatmapDesc {
            label: "",
            gradient: Colormap::Magma,
            scale: Scale::Log { lo: 0.0, hi: 1.0 },
        };
        let f = |i: usize| mask[i].then(|| values[i]);
        let masked = Field::Masked {
            values: &values,
            mask: &mask,
            abs: false,
        };
        assert!(draw(masked, &desc) == draw(Field::Fn(&f), &desc));
    }

    /// The colorbar is there: down its centre column the pixels follow the colormap from the
    /// top (hi) to the bottom (lo), and the field pixels use the same map.
    #[test]
    fn colorbar_pixels_match_the_colormap() {
        for scale in [
            Scale::Linear { lo: 0.0, hi: 10.0 },
            Scale::Log { lo: 1e-4, hi: 1.0 },
        ] {
            let (w, h) = (64u32, 220u32);
            let values: Vec<Option<f64>> = (0..w * h)
                .map(|i| {
                    if i % w < 32 {
                        Some(scale.value((i / w) as f64 / h as f64))
                    } else {
                        None
                    }
                })
                .collect();
            let desc = HeatmapDesc {
                label: "error (deg)",
                gradient: Colormap::Magma,
                scale,
            };
            let fig = render(&|i| values[i], w, h, &desc).unwrap();
            let (x0, y0, x1, y1) = fig.bar;
            assert!(
                x0 >= w && x1 <= fig.width && y1 > y0 + 100,
                "bar rectangle {:?}",
                fig.bar
            );
            let px = |x: u32, y: u32| {
                let o = ((y * fig.width + x) * 3) as usize;
                [fig.rgb[o], fig.rgb[o + 1], fig.rgb[o + 2]]
            };
            let xc = (x0 + x1) / 2;
            for k in 1..10 {
                let y = y0 + (y1 - y0) * k / 10;
                let t = 1.0 - (y - y0) as f64 / (y1 - y0) as f64;
                let want = color_at(&Colormap::Magma, t);
                let got = px(xc, y);
                let d = (0..3)
                    .map(|c| (got[c] as i32 - want[c] as i32).abs())
                    .max()
                    .unwrap();
                assert!(
                    d <= 12,
                    "{scale:?}: bar at t = {t:.2}: {got:?} vs magma {want:?}"
                );
            }
            // outside the bar (left of the axis labels' area) stays white: the panel is drawn
            assert_eq!(px(w + 2, y0 + 5), [255, 255, 255]);
            // field pixels: coloured where there is data, NO_DATA elsewhere
            assert_eq!(px(40, 10), NO_DATA);
            assert_eq!(px(0, 0), color_at(&Colormap::Magma, 0.0));
            // labels were drawn: some dark text pixels left of the bar
            let dark = (y0..y1)
                .flat_map(|y| (w..x0).map(move |x| (x, y)))
                .filter(|&(x, y)| px(x, y)[0] < 100)
                .count();
            assert!(dark > 50, "no tick labels drawn ({dark} dark pixels)");
        }
    }
}
