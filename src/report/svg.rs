//! The report's charts, drawn as inline SVG small multiples: one panel per method family (the
//! method table's `family`; a family of more than [`MAX_SERIES`] methods split into panels of
//! at most that many), shared axes across the panels of a chart, each point or line numbered
//! and named in the panel's legend (no label placed among the data, so none can collide), every
//! text inside the panel's view box (names shortened to [`NAME_CHARS`], the full name in a
//! `<title>`). The charts: cost against error (the answer's figures: lavapipe frame time across
//! runs against the worst max |dI| over the scenes, the budgets as dashed lines), the same per
//! scene (bench's Pareto data, in the scene's section), and stress's worst error against the
//! angle between the vertex normals and against the shininess (in the stress section). They
//! replace bench's and stress's PNG charts on the page (those stay files, linked).
use std::fmt::Write as _;

use super::html::esc;
use super::{ReportData, SceneResult};
use crate::method::Family;

/// The most series one panel draws.
pub const MAX_SERIES: usize = 8;
/// Longest name shown in a legend (longer ones end in an ellipsis).
pub const NAME_CHARS: usize = 26;
/// Panel size (the view box) and the plot area inside it.
const W: f64 = 510.0;
const H: f64 = 300.0;
const X0: f64 = 58.0;
const X1: f64 = 288.0;
const Y0: f64 = 30.0;
const Y1: f64 = 240.0;
/// The panels' text and line styles (inside each `<svg>`, so a panel reads the same alone).
const STYLE: &str = "<style>svg.panel text{font-family:sans-serif;fill:#222}\
svg.panel .title{font-size:13px;font-weight:bold}svg.panel .xt{font-size:10px;text-anchor:middle}\
svg.panel .yt{font-size:10px;text-anchor:end}svg.panel .note{font-size:10px}\
svg.panel .lg{font-size:11px}svg.panel .mk{font-size:9px;font-weight:bold;fill:#fff;\
text-anchor:middle}svg.panel .frame{fill:none;stroke:#999}svg.panel .grid{stroke:#eee}\
svg.panel .tick{stroke:#999}svg.panel .rule{stroke:#777;stroke-dasharray:4 3}</style>";
/// Eight colours a reader tells apart (Tableau 10, first eight).
const PALETTE: [&str; MAX_SERIES] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#9c755f",
];

/// One point of a series: x, y (`None`: non-finite) and x's interval when there is one.
pub type Point = (f64, Option<f64>, Option<(f64, f64)>);

/// One series of a panel: a method and its points (x, y; y `None`: non-finite).
pub struct Series {
    pub name: String,
    /// (x, y, x interval) per point.
    pub points: Vec<Point>,
}

/// A chart: its panels' titles and series, and the axes they share.
pub struct Chart {
    pub id: String,
    pub x_title: String,
    pub y_title: String,
    /// Lines: connect a series' points; otherwise each point is a numbered marker.
    pub lines: bool,
    pub x_range: (f64, f64),
    /// log10 of the y range.
    pub y_decades: (i32, i32),
    /// Dashed horizontal lines (y values) and a dashed vertical one (x value).
    pub h_rules: Vec<f64>,
    pub v_rule: Option<f64>,
    pub panels: Vec<(String, Vec<Series>)>,
}

/// Splits `(family, series)` into panels of at most [`MAX_SERIES`], titled by family.
pub fn panels(by_family: Vec<(Family, Vec<Series>)>) -> Vec<(String, Vec<Series>)> {
    let mut out = Vec::new();
    for (f, mut series) in by_family {
        if series.is_empty() {
            continue;
        }
        let parts = series.len().div_ceil(MAX_SERIES);
        let per = series.len().div_ceil(parts);
        let mut k = 1;
        while !series.is_empty() {
            let rest = series.split_off(per.min(series.len()));
            let title = if parts > 1 {
                format!("{} ({k} of {parts})", f.as_str())
            } else {
                f.as_str().to_string()
            };
            out.push((title, series));
            series = rest;
            k += 1;
        }
    }
    out
}

/// `name` in at most `n` characters (an ellipsis ends a cut one).
fn short_to(name: &str, n: usize) -> String {
    if name.chars().count() <= n {
        name.to_string()
    } else {
        name.chars().take(n.saturating_sub(1)).collect::<String>() + "\u{2026}"
    }
}

/// A value in a legend: `3e8`, `0.002`, `1.5`.
fn short_num(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e4).contains(&v.abs()) {
        format!("{v:.0e}")
    } else {
        format!("{}", (v * 1000.0).round() / 1000.0)
    }
}

/// Round tick values covering `(lo, hi)`, 3 to 7 of them.
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.0)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut v = Vec::new();
    while t <= hi + step * 1e-9 {
        v.push((t / step).round() * step);
        t += step;
    }
    v
}

impl Chart {
    fn px(&self, x: f64) -> f64 {
        let (a, b) = self.x_range;
        X0 + (x - a) / (b - a) * (X1 - X0)
    }

    fn py(&self, y: f64) -> f64 {
        let (a, b) = self.y_decades;
        let l = y.max(1e-300).log10().clamp(f64::from(a), f64::from(b));
        Y1 - (l - f64::from(a)) / f64::from(b - a) * (Y1 - Y0)
    }

    /// The largest value the y axis shows (values above are drawn on its top edge, marked).
    pub fn y_max(&self) -> f64 {
        10f64.powi(self.y_decades.1)
    }

    /// The smallest value the y axis shows (values below are drawn on its bottom edge,
    /// marked).
    pub fn y_min(&self) -> f64 {
        10f64.powi(self.y_decades.0)
    }

    /// Whether `y` lies beyond the y axis (or is not finite): drawn on an edge with a marker.
    fn off_scale(&self, y: Option<f64>) -> bool {
        y.is_none_or(|y| !(y.is_finite() && y <= self.y_max() && y >= self.y_min()))
    }

    /// x clamped to the axis (an interval reaching beyond it ends on the frame, with an arrow).
    fn px_clamped(&self, x: f64) -> (f64, bool) {
        let (a, b) = self.x_range;
        (self.px(x.clamp(a, b)), !(a..=b).contains(&x))
    }

    fn axes(&self, title: &str) -> String {
        let mut h = format!(
            "<text x=\"8\" y=\"18\" class=\"title\">{}</text><rect x=\"{X0}\" y=\"{Y0}\" \
             width=\"{}\" height=\"{}\" class=\"frame\"/>",
            esc(title),
            X1 - X0,
            Y1 - Y0
        );
        for t in ticks(self.x_range.0, self.x_range.1) {
            let x = self.px(t);
            let _ = write!(
                h,
                "<line x1=\"{x:.1}\" x2=\"{x:.1}\" y1=\"{Y1}\" y2=\"{:.1}\" class=\"tick\"/>\
                 <text x=\"{x:.1}\" y=\"{:.1}\" class=\"xt\">{}</text>",
                Y1 + 4.0,
                Y1 + 15.0,
                esc(&format!("{}", (t * 1000.0).round() / 1000.0))
            );
        }
        for d in self.y_decades.0..=self.y_decades.1 {
            let y = self.py(10f64.powi(d));
            let _ = write!(
                h,
                "<line x1=\"{X0}\" x2=\"{X1}\" y1=\"{y:.1}\" y2=\"{y:.1}\" class=\"grid\"/>\
                 <text x=\"{:.1}\" y=\"{:.1}\" class=\"yt\">1e{d}</text>",
                X0 - 4.0,
                y + 3.5
            );
        }
        for r in &self.h_rules {
            let y = self.py(*r);
            let _ = write!(
                h,
                "<line x1=\"{X0}\" x2=\"{X1}\" y1=\"{y:.1}\" y2=\"{y:.1}\" class=\"rule\"/>"
            );
        }
        if let Some(v) = self.v_rule {
            let x = self.px(v);
            let _ = write!(
                h,
                "<line x1=\"{x:.1}\" x2=\"{x:.1}\" y1=\"{Y0}\" y2=\"{Y1}\" class=\"rule\"/>"
            );
        }
        let _ = write!(
            h,
            "<text x=\"{:.1}\" y=\"{:.1}\" class=\"xt\">{}</text>\
             <text x=\"8\" y=\"{:.1}\" class=\"note\">{}</text>",
            (X0 + X1) / 2.0,
            Y1 + 32.0,
            esc(&self.x_title),
            H - 8.0,
            esc(&self.y_title)
        );
        h
    }

    /// One data point: a numbered marker (points) or a small dot (lines) where it lies on the
    /// axes; on the top or bottom edge, as a triangle pointing off the axis, where its value
    /// lies beyond them; a cross on the top edge where it is not finite. `data-y` holds the
    /// value (the browser test checks every point against the axes).
    fn point(&self, x: f64, y: Option<f64>, c: &str, n: usize) -> String {
        let px = self.px(x);
        let shown = y.map_or("nan".to_string(), |v| format!("{v:e}"));
        match y {
            None => format!(
                "<path class=\"pt off nonfinite\" data-y=\"nan\" d=\"M{:.1},{:.1}l6,6m0,-6l-6,6\" \
                 stroke=\"{c}\" stroke-width=\"2\"/>",
                px - 3.0,
                Y0 - 3.0
            ),
            Some(v) if self.off_scale(Some(v)) => {
                let (edge, dir) = if v.is_finite() && v < self.y_min() {
                    (Y1, 1.0)
                } else {
                    (Y0, -1.0)
                };
                format!(
                    "<path class=\"pt off\" data-y=\"{shown}\" data-edge=\"{edge}\" \
                     d=\"M{:.1},{edge:.1}l5,{:.1}l-10,0z\" fill=\"{c}\" stroke=\"#222\" \
                     stroke-width=\"0.8\"/>",
                    px,
                    -dir * 8.0
                )
            }
            Some(v) if self.lines => format!(
                "<circle class=\"pt\" data-y=\"{shown}\" cx=\"{px:.1}\" cy=\"{:.1}\" r=\"2\" \
                 fill=\"{c}\"/>",
                self.py(v)
            ),
            Some(v) => {
                let py = self.py(v);
                format!(
                    "<circle class=\"pt\" data-y=\"{shown}\" cx=\"{px:.1}\" cy=\"{py:.1}\" \
                     r=\"7\" fill=\"{c}\"/><text x=\"{px:.1}\" y=\"{:.1}\" class=\"mk\">{n}</text>",
                    py + 3.5
                )
            }
        }
    }

    /// A point's interval along x, clipped to the axis with an arrow where it reaches beyond.
    fn interval(&self, y: f64, (lo, hi): (f64, f64), c: &str) -> String {
        let py = self.py(y);
        let ((l, lo_off), (r, hi_off)) = (self.px_clamped(lo), self.px_clamped(hi));
        let mut h = format!(
            "<line x1=\"{l:.1}\" x2=\"{r:.1}\" y1=\"{py:.1}\" y2=\"{py:.1}\" stroke=\"{c}\" \
             stroke-width=\"2\"/>"
        );
        for (x, off, d) in [(l, lo_off, 1.0), (r, hi_off, -1.0)] {
            if off {
                let _ = write!(
                    h,
                    "<path class=\"clip\" d=\"M{x:.1},{py:.1}l{:.1},-4l0,8z\" fill=\"{c}\"/>",
                    d * 7.0
                );
            }
        }
        h
    }

    /// What the legend adds after a series' name: its off-scale values, largest first.
    fn legend_note(&self, s: &Series) -> String {
        let nonfinite = s.points.iter().any(|p| p.1.is_none_or(|y| !y.is_finite()));
        let above = (s.points.iter())
            .filter_map(|p| p.1)
            .filter(|y| y.is_finite() && *y > self.y_max())
            .fold(None, |m: Option<f64>, y| Some(m.map_or(y, |m| m.max(y))));
        let below = (s.points.iter())
            .filter_map(|p| p.1)
            .filter(|y| y.is_finite() && *y < self.y_min())
            .fold(None, |m: Option<f64>, y| Some(m.map_or(y, |m| m.min(y))));
        let mut parts = Vec::new();
        if let Some(v) = above {
            parts.push(format!("\u{25b2}{}", short_num(v)));
        }
        if let Some(v) = below {
            parts.push(format!("\u{25bc}{}", short_num(v)));
        }
        if nonfinite {
            parts.push("\u{d7}NaN".into());
        }
        if parts.is_empty() {
            String::new()
        } else {
            format!(" {}", parts.join(" "))
        }
    }

    fn series(&self, k: usize, s: &Series) -> String {
        let c = PALETTE[k % MAX_SERIES];
        let n = k + 1;
        let mut h = format!(
            "<g class=\"series\" data-method=\"{}\"><title>{}</title>",
            esc(&s.name),
            esc(&s.name)
        );
        // Lines run through every finite point, an off-scale one on its edge.
        let drawn: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter_map(|&(x, y, _)| {
                y.filter(|v| v.is_finite())
                    .map(|v| (self.px(x), self.py(v)))
            })
            .collect();
        if self.lines && drawn.len() > 1 {
            let pts: Vec<String> = drawn
                .iter()
                .map(|(x, y)| format!("{x:.1},{y:.1}"))
                .collect();
            let _ = write!(
                h,
                "<polyline points=\"{}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"1.6\"/>",
                pts.join(" ")
            );
        }
        for &(x, y, iv) in &s.points {
            if let (false, Some(v), Some(iv)) = (self.lines, y, iv) {
                if !self.off_scale(Some(v)) {
                    h += &self.interval(v, iv, c);
                }
            }
            h += &self.point(x, y, c, n);
        }
        if let (true, Some(&(x, y))) = (self.lines, drawn.last()) {
            let _ = write!(
                h,
                "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"7\" fill=\"{c}\"/>\
                 <text x=\"{x:.1}\" y=\"{:.1}\" class=\"mk\">{n}</text>",
                y + 3.5
            );
        }
        // Legend entry, right of the plot: the name, then any off-scale value.
        let ly = Y0 + 8.0 + 18.0 * k as f64;
        let note = self.legend_note(s);
        let room = NAME_CHARS.saturating_sub(note.chars().count()).max(8);
        let _ = write!(
            h,
            "<circle cx=\"{:.1}\" cy=\"{ly:.1}\" r=\"7\" fill=\"{c}\"/><text x=\"{:.1}\" \
             y=\"{:.1}\" class=\"mk\">{n}</text><text x=\"{:.1}\" y=\"{:.1}\" class=\"lg\">{}\
             <tspan class=\"offv\">{}</tspan></text></g>",
            X1 + 18.0,
            X1 + 18.0,
            ly + 3.5,
            X1 + 30.0,
            ly + 4.0,
            esc(&short_to(&s.name, room)),
            esc(&note)
        );
        h
    }

    /// The chart as a row of panels (one `<svg>` each, same view box and axes).
    pub fn html(&self, caption: &str) -> String {
        let mut h = format!(
            "<figure class=\"multiples\" id=\"{}\"><div class=\"panels\">",
            esc(&self.id)
        );
        for (title, series) in &self.panels {
            let _ = write!(
                h,
                "<svg class=\"panel\" viewBox=\"0 0 {W} {H}\" width=\"{W}\" height=\"{H}\" \
                 role=\"img\" aria-label=\"{}\" data-series=\"{}\" data-y-min=\"{:e}\" \
                 data-y-max=\"{:e}\" data-top=\"{Y0}\" data-bottom=\"{Y1}\" data-left=\"{X0}\" \
                 data-right=\"{X1}\">{STYLE}{}",
                esc(title),
                series.len(),
                self.y_min(),
                self.y_max(),
                self.axes(title)
            );
            for (k, s) in series.iter().enumerate() {
                h += &self.series(k, s);
            }
            h += "</svg>";
        }
        let _ = write!(
            h,
            "</div><figcaption>{}</figcaption></figure>",
            esc(caption)
        );
        h
    }
}

pub use crate::output::chart::{ERROR_CEILING_DECADE, ERROR_FLOOR_DECADE};

/// The decades of an error axis: those covering the finite positive values of `ys`, clamped
/// to [1e-9, 1] (at least one decade).
pub fn decades(ys: impl Iterator<Item = f64>) -> (i32, i32) {
    let (lo, hi) = ys
        .filter(|y| y.is_finite() && *y > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(y), b.max(y))
        });
    if !lo.is_finite() {
        return (-4, ERROR_CEILING_DECADE);
    }
    let top = ERROR_CEILING_DECADE;
    let a = (lo.log10().floor() as i32).clamp(ERROR_FLOOR_DECADE, top - 1);
    let b = (hi.log10().ceil() as i32).clamp(a + 1, top);
    (a, b)
}

fn family_of(name: &str) -> Family {
    crate::method::find(name).map_or(Family::Reference, |m| m.family)
}

fn group(series: Vec<Series>) -> Vec<(Family, Vec<Series>)> {
    let mut by: Vec<(Family, Vec<Series>)> = Family::ALL.iter().map(|f| (*f, Vec::new())).collect();
    for s in series {
        let f = family_of(&s.name);
        if let Some(slot) = by.iter_mut().find(|(g, _)| *g == f) {
            slot.1.push(s);
        }
    }
    by
}

/// A method's cost point: its name, cost, the cost's interval and its error (`None`:
/// non-finite).
type CostPoint = (String, f64, Option<(f64, f64)>, Option<f64>);

/// A cost chart from (method, ratio, interval, error) points.
fn cost_chart_of(id: String, x_title: &str, y_title: &str, points: Vec<CostPoint>) -> Chart {
    let series: Vec<Series> = points
        .into_iter()
        .map(|(name, x, iv, y)| Series {
            name,
            points: vec![(x, y, iv)],
        })
        .collect();
    // The medians set the x axis; an interval reaching beyond it ends on the frame, marked.
    let xs = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .filter(|x| x.is_finite())
        .chain([1.0]);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = (hi - lo).max(0.05) * 0.08;
    let ys = series
        .iter()
        .filter_map(|s| s.points[0].1)
        .chain([1.0 / 1024.0, 4.0 / 255.0]);
    Chart {
        id,
        x_title: x_title.into(),
        y_title: y_title.into(),
        lines: false,
        x_range: ((lo - pad).max(0.0), hi + pad),
        y_decades: decades(ys),
        h_rules: vec![1.0 / 1024.0, 1.0 / 255.0, 4.0 / 255.0],
        v_rule: Some(1.0),
        panels: panels(group(series)),
    }
}

/// Cost against error: the answer's lavapipe frame figure per method (the scene with the
/// largest ratio) against its worst max |dI| over the scenes (float32 programs).
pub fn cost_chart(d: &ReportData) -> Option<Chart> {
    let model = d
        .answer
        .cost_models
        .iter()
        .find(|m| m.id == *crate::cost::LAVAPIPE_FRAME)?;
    let budget = *d.answer.budgets.first()?;
    let mut points = Vec::new();
    for f in &model.figures {
        let Some(x) = f.ratio else { continue };
        let y = d
            .answer
            .checks
            .iter()
            .find(|c| c.method == f.method && c.budget == budget && c.precision == model.precision)
            .and_then(|c| c.worst);
        points.push((f.method.clone(), x, f.ci95_low.zip(f.ci95_high), y));
    }
    Some(cost_chart_of(
        "chart-cost".into(),
        "frame time / phong_exact (lavapipe)",
        "y: worst max |dI| over the scenes (log); \u{25b2} off the axis, value in the legend",
        points,
    ))
}

/// One scene's cost against error (bench's Pareto data): each method's frame time ratio to
/// phong_exact on this scene (with its interval) against its max |dI| on this scene.
pub fn scene_cost_chart(s: &SceneResult) -> Option<Chart> {
    let mut points = Vec::new();
    for r in &s.bench.methods {
        if r.floor_program == r.name || r.name.ends_with("_control") || !r.ratio_median.is_finite()
        {
            continue;
        }
        let Some(m) = s.summary.methods.iter().find(|m| m.name == r.name) else {
            continue;
        };
        let y = m
            .metric(crate::compare::Metric::MaxAbsError.name())
            .filter(|v| v.is_finite() && m.non_finite_pixels == 0);
        let iv = Some((r.ratio_ci95_low, r.ratio_ci95_high))
            .filter(|(l, h)| l.is_finite() && h.is_finite());
        points.push((r.name.clone(), r.ratio_median, iv, y));
    }
    (!points.is_empty()).then(|| {
        cost_chart_of(
            format!("scene-{}--chart-cost", s.id),
            "frame time / phong_exact (lavapipe, this scene)",
            "y: max |dI| on this scene (log); \u{25b2} off the axis, value in the legend",
            points,
        )
    })
}

/// Which stress sweep a chart draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Against the angle between the vertex normals.
    Angle,
    /// Against log2 of the shininess, at stress's chart angle.
    Shininess,
}

/// stress: worst device error against the angle between the vertex normals, or against the
/// shininess (log2) at [`crate::stress::chart::SHININESS_CHART_ANGLE`].
pub fn stress_chart(d: &ReportData, sweep: Sweep) -> Option<Chart> {
    let mut series = Vec::new();
    for m in &d.stress.methods {
        let curve: Vec<&crate::stress::CurvePoint> = match sweep {
            Sweep::Angle => m.error_vs_angle.iter().collect(),
            Sweep::Shininess => m
                .error_vs_shininess
                .iter()
                .filter(|p| p.key.first() == Some(&crate::stress::chart::SHININESS_CHART_ANGLE))
                .collect(),
        };
        let points: Vec<Point> = curve
            .iter()
            .map(|p| {
                let y = if p.device.non_finite > 0 {
                    None
                } else {
                    p.device.max
                };
                let x = *p.key.last().unwrap_or(&0.0);
                let x = match sweep {
                    Sweep::Angle => x,
                    Sweep::Shininess => x.max(1e-9).log2(),
                };
                (x, y, None)
            })
            .collect();
        if !points.is_empty() {
            series.push(Series {
                name: m.name.clone(),
                points,
            });
        }
    }
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if !lo.is_finite() {
        return None;
    }
    let ys = series
        .iter()
        .flat_map(|s| s.points.iter().filter_map(|p| p.1));
    let (id, x_title) = match sweep {
        Sweep::Angle => ("chart-stress", "angle between the vertex normals (degrees)"),
        Sweep::Shininess => ("chart-stress-shininess", "log2 of the shininess n"),
    };
    Some(Chart {
        id: id.into(),
        x_title: x_title.into(),
        y_title: "y: worst |colour error| (log); \u{25b2} off the axis (legend: its largest), \u{d7} not finite".into(),
        lines: true,
        x_range: (lo, hi.max(lo + 1.0)),
        y_decades: decades(ys.map(|y| y.max(1e-9))),
        h_rules: vec![d.stress.threshold],
        v_rule: None,
        panels: panels(group(series)),
    })
}

/// The charts section, after the answer.
pub fn charts_section(d: &ReportData) -> String {
    let mut h = String::from("<section id=\"charts\"><h2>Cost against error</h2>");
    if let Some(c) = cost_chart(d) {
        h += &c.html(
            "Each method's lavapipe frame time relative to phong_exact (the scene with the \
             largest ratio, with its interval across runs) against its worst max |dI| over the \
             scenes; dashed: the budgets 1/1024, 1/255, 4/255 and the ratio 1 (phong_exact). \
             One panel per method family, the same axes in every panel.",
        );
    }
    if let Some(c) = stress_chart(d, Sweep::Angle) {
        h += &c.html(
            "stress: worst error on the device against the angle between the vertex normals \
             (facing the viewer); dashed: the stress threshold. One panel per family, the same \
             axes in every panel; the numbered marker ends each line.",
        );
    }
    h + "</section>"
}
