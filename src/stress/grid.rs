//! What `stress` makes of the sweeps of [`crate::cases::grid`]: the per-case errors folded into
//! curves and the validity map, the local search's neighbours, the digital-segment paper's
//! specular bound and the claims.
use std::collections::HashMap;

use serde::Serialize;

use super::{CurvePoint, MethodStress, StressClaim, ValidityMap};
use crate::cases::grid::{Grid, Sweep, Worst, ANGLES, ELEVATIONS};
use crate::cases::{CaseSpec, Errors, Shape};
use crate::method::checks::VISIBLE_LENGTH_ERROR_PCT;
use crate::method::{Criteria, Kind, Verdict};

/// Folds cases into points keyed by `key` (insertion order kept), each case's error chosen by
/// `select` (None: left out).
#[allow(clippy::too_many_arguments)]
fn fold(
    grid: &Grid,
    sweep: Sweep,
    applies: &[bool],
    primary: &[Errors],
    twin: &[Errors],
    select: fn(&Errors) -> Option<f64>,
    key: impl Fn(&CaseSpec) -> Option<Vec<f64>>,
    label: impl Fn(&CaseSpec) -> Option<String>,
) -> Vec<CurvePoint> {
    let mut points: Vec<CurvePoint> = Vec::new();
    let mut index: HashMap<Vec<u64>, usize> = HashMap::new();
    for (i, c) in grid.cases.iter().enumerate() {
        if grid.kinds[i] != sweep || !applies[i] {
            continue;
        }
        let Some(k) = key(&c.spec) else { continue };
        let (dev, f64) = (select(&primary[i]), select(&twin[i]));
        let bits: Vec<u64> = k.iter().map(|x| x.to_bits()).collect();
        let j = *index.entry(bits).or_insert_with(|| {
            points.push(CurvePoint {
                key: k.clone(),
                label: label(&c.spec),
                device: Worst::default(),
                f64: Worst::default(),
            });
            points.len() - 1
        });
        if let Some(e) = dev {
            points[j].device.add(e);
        }
        if let Some(e) = f64 {
            points[j].f64.add(e);
        }
    }
    points
}

/// The curves of one method.
pub struct Curves {
    pub angle: Vec<CurvePoint>,
    /// The normal's length error ||N| - 1| per angle (facing the viewer); empty for a method
    /// without a normal.
    pub length_vs_angle: Vec<CurvePoint>,
    pub shininess: Vec<CurvePoint>,
    pub span: Vec<CurvePoint>,
    pub length: Vec<CurvePoint>,
    pub shape: Vec<CurvePoint>,
}

/// Worst error per angle (facing the viewer), per (angle, shininess), per (angle, span), per
/// length, per (shape, angle).
pub fn curves(grid: &Grid, applies: &[bool], primary: &[Errors], twin: &[Errors]) -> Curves {
    let none = |_: &CaseSpec| None;
    let colour: fn(&Errors) -> Option<f64> = Errors::counted;
    let facing = |s: &CaseSpec| (s.elevation_deg < 90.0).then(|| vec![s.theta_deg]);
    let curve = |sweep, select, key: &dyn Fn(&CaseSpec) -> Option<Vec<f64>>| {
        fold(grid, sweep, applies, primary, twin, select, key, none)
    };
    Curves {
        angle: curve(Sweep::Angle, colour, &facing),
        // a method without a normal has no point on it
        length_vs_angle: curve(Sweep::Angle, Errors::counted_length, &facing)
            .into_iter()
            .filter(|p| p.device.count + p.f64.count > 0)
            .collect(),
        shininess: curve(Sweep::Shininess, colour, &|s| {
            Some(vec![s.theta_deg, s.shininess])
        }),
        span: curve(Sweep::Span, colour, &|s| {
            Some(vec![s.theta_deg, f64::from(s.span_px)])
        }),
        length: curve(Sweep::Length, colour, &|s| Some(vec![s.length])),
        shape: fold(
            grid,
            Sweep::Shape,
            applies,
            primary,
            twin,
            colour,
            |s| Some(vec![s.theta_deg]),
            |s| Some(format!("{:?}", s.shape).to_lowercase()),
        ),
    }
}

/// Worst error per (elevation, angle) cell of the angle sweep.
pub fn validity_map(grid: &Grid, errs: &[Errors]) -> ValidityMap {
    let mut cells = vec![vec![Worst::default(); ANGLES.len()]; ELEVATIONS.len()];
    for (i, c) in grid.cases.iter().enumerate() {
        if grid.kinds[i] != Sweep::Angle {
            continue;
        }
        let a = ANGLES.iter().position(|&a| a == c.spec.theta_deg);
        let e = ELEVATIONS.iter().position(|&e| e == c.spec.elevation_deg);
        if let (Some(a), Some(e), Some(v)) = (a, e, errs[i].counted()) {
            cells[e][a].add(v);
        }
    }
    ValidityMap {
        angles_deg: ANGLES.to_vec(),
        elevations_deg: ELEVATIONS.to_vec(),
        cells,
    }
}

/// A neighbour of `s` for the local search: angles, elevation, frame and light moved by up to
/// `step` degrees, the pixel by up to `step / 2` pixels, clamped to their domains.
pub fn perturb(s: &CaseSpec, step: f64, rng: &mut fastrand::Rng) -> CaseSpec {
    let mut d = |x: f64, lo: f64, hi: f64| (x + step * (2.0 * rng.f64() - 1.0)).clamp(lo, hi);
    let mut out = CaseSpec {
        theta_deg: d(s.theta_deg, 0.0, 180.0),
        elevation_deg: d(s.elevation_deg, 0.0, 180.0),
        pair_azimuth_deg: d(s.pair_azimuth_deg, 0.0, 180.0),
        roll_deg: d(s.roll_deg, -180.0, 180.0),
        light_deg: d(s.light_deg, 0.0, 180.0),
        ..*s
    };
    let span = match s.shape {
        Shape::Strip => s.span_px.max(1),
        Shape::SubPixel => 1,
        _ => 3413,
    };
    let jump = (step / 2.0).ceil() as i64;
    let p = i64::from(s.pixel) + rng.i64(-jump..=jump);
    out.pixel = p.clamp(0, i64::from(span) - 1) as u32;
    out
}

/// The digital-segment paper's specular bound at 4 degrees: one digital segment of `2^k` pixels
/// whose end normals are 4 degrees apart, H on their bisector (the segment's middle pixel, t = 1/2), specular
/// term alone; the relative error there for n = 1..=100.
#[derive(Debug, Clone, Serialize)]
pub struct SpecularBound {
    pub method: String,
    pub shininess: Vec<f64>,
    /// (exact - method) / exact at the middle pixel, on the device (f64 twin without one).
    pub relative_error: Vec<f64>,
    /// The seed's bound 1 - cos^n(theta/2).
    pub bound: Vec<f64>,
}

/// The specs of [`SpecularBound`] for a segment of `2^k` pixels.
pub fn specular_bound_specs(k: u32) -> Vec<CaseSpec> {
    (1..=100)
        .map(|n| CaseSpec {
            theta_deg: 4.0,
            elevation_deg: 0.0,
            light_deg: 0.0,
            shininess: f64::from(n),
            span_px: 1 << k,
            pixel: 1 << (k - 1),
            specular_only: true,
            ..CaseSpec::default()
        })
        .collect()
}

/// The validity claims of the stressed methods' rows ([`Kind::Validity`]), each with its row's
/// name: those judged by a criterion of the sweep up to the claimed angle first, then those
/// that claim a collapse beyond it ([`Criteria::CollapsesBeyond`]), in the run's order.
fn validity_claims(
    methods: &[MethodStress],
    collapse: bool,
) -> Vec<(&MethodStress, &'static str, f64, Criteria)> {
    let mut out = Vec::new();
    for m in methods {
        let Ok(row) = crate::method::find(&m.name) else {
            continue;
        };
        for c in row.claims {
            if let Kind::Validity {
                up_to_deg,
                criteria,
            } = c.kind
            {
                if (criteria == Criteria::CollapsesBeyond) == collapse {
                    out.push((m, c.claim, up_to_deg, criteria));
                }
            }
        }
    }
    out
}

/// Where a collapse claim's "before" starts, and how far its "beyond" reaches, degrees.
const COLLAPSE_FROM_DEG: f64 = 60.0;
const COLLAPSE_SPAN_DEG: f64 = 30.0;

fn fmt(x: Option<f64>) -> String {
    x.map_or("none".into(), |v| format!("{v}"))
}

/// The worst device error at angles in `(lo, hi]` of a method's angle curve.
fn worst_between(m: &MethodStress, lo: f64, hi: f64) -> Worst {
    worst_of(&m.error_vs_angle, lo, hi)
}

/// The worst device value at angles in `(lo, hi]` of an angle curve.
fn worst_of(curve: &[CurvePoint], lo: f64, hi: f64) -> Worst {
    let mut w = Worst::default();
    for p in curve.iter().filter(|p| p.key[0] > lo && p.key[0] <= hi) {
        w.count += p.device.count;
        w.non_finite += p.device.non_finite;
        if let Some(v) = p.device.max {
            w.max = Some(w.max.map_or(v, |x: f64| x.max(v)));
        }
    }
    w
}

/// "Accuracy collapses beyond 90 degrees", from the worst errors at 60-90 (`upto`) and 90-120
/// degrees (`beyond`) against the stress threshold (the criterion of every validity claim
/// here): collapses = within it before 90 and above it after. Agrees when so; disagrees when
/// still within it after 90; partly when above it on both sides (the loss starts before 90);
/// inconclusive when any case is non-finite (it has no error: neither a collapse nor its
/// absence) or nothing was measured.
pub(crate) fn collapse_verdict(upto: &Worst, beyond: &Worst, threshold: f64) -> Verdict {
    let within =
        |w: &Worst| w.count > 0 && w.non_finite == 0 && w.max.is_some_and(|m| m <= threshold);
    let above = |w: &Worst| w.non_finite == 0 && w.max.is_some_and(|m| m > threshold);
    if upto.non_finite + beyond.non_finite > 0 {
        Verdict::Inconclusive
    } else if within(upto) && above(beyond) {
        Verdict::Agrees
    } else if within(beyond) {
        Verdict::Disagrees
    } else if above(upto) && above(beyond) {
        Verdict::Partly
    } else {
        Verdict::Inconclusive
    }
}

/// Verdicts of the validity claims and the digital-segment paper's specular bound, from the sweeps.
pub fn claims(
    methods: &[MethodStress],
    specular: &[SpecularBound],
    threshold: f64,
) -> Vec<StressClaim> {
    let mut out = Vec::new();
    usable_up_to_claims(methods, threshold, &mut out);
    collapse_claims(methods, threshold, &mut out);
    specular_claims(specular, &mut out);
    out
}

/// The rows' validity claims: valid up to the claimed angle on the device, by each claim's
/// [`Criteria`], every criterion named in `measured` and `how`.
fn usable_up_to_claims(methods: &[MethodStress], threshold: f64, out: &mut Vec<StressClaim>) {
    let word = |ok: bool| if ok { "holds" } else { "fails" };
    for (m, claim, range, criteria) in validity_claims(methods, false) {
        let v = m.max_valid_angle_deg;
        let colour = v.is_some_and(|v| v >= range);
        let at = worst_between(m, 0.0, range);
        let colour_text = format!(
            "colour criterion (within {threshold:.6} = 1/255 on the device): valid up to {} \
             degrees on the device ({} in f64); worst error up to {range} degrees {} ({} \
             non-finite)",
            fmt(v),
            fmt(m.max_valid_angle_deg_f64),
            fmt(at.max),
            at.non_finite
        );
        let how_colour = format!(
            "max_valid_angle_deg: the largest angle of the sweep up to which every case facing \
             the viewer (elevation < 90, 4 frames, 5 lights, shininess 20, 17 pixels) is finite \
             and within {threshold:.6} on the device"
        );
        let (measured, verdict, how) = match criteria {
            Criteria::Colour | Criteria::CollapsesBeyond => (
                colour_text,
                if colour {
                    Verdict::Agrees
                } else {
                    Verdict::Disagrees
                },
                format!("{how_colour}; agrees when it reaches the claimed angle"),
            ),
            Criteria::LengthAndColour => {
                let len = worst_of(&m.length_error_vs_angle, f64::NEG_INFINITY, range);
                let length = len.valid(VISIBLE_LENGTH_ERROR_PCT / 100.0);
                (
                    format!(
                        "length criterion (worst ||N| - 1| up to {range} degrees on the device \
                         within {VISIBLE_LENGTH_ERROR_PCT} %): {} % ({} non-finite): {}; \
                         {colour_text}: {}",
                        fmt(len.max.map(|x| 100.0 * x)),
                        len.non_finite,
                        word(length),
                        word(colour)
                    ),
                    match (length, colour) {
                        (true, true) => Verdict::Agrees,
                        (false, false) => Verdict::Disagrees,
                        _ => Verdict::Partly,
                    },
                    format!(
                        "two criteria, as `shadelab list` judges this claim: the length \
                         criterion, the worst ||N| - 1| of the device's normal over the same \
                         facing cases up to the claimed angle, holds when within \
                         {VISIBLE_LENGTH_ERROR_PCT} % (the project's visible-length threshold); \
                         the colour criterion, {how_colour}, holds when it reaches the claimed \
                         angle; agrees when both hold, partly when one does, disagrees when \
                         neither"
                    ),
                )
            }
        };
        out.push(StressClaim {
            method: m.name.clone(),
            claim: claim.into(),
            measured,
            verdict,
            how,
        });
    }
}

/// The rows' collapse claims ([`Criteria::CollapsesBeyond`] at angle a): within the threshold
/// from 60 degrees to a, above it from a to a + 30.
fn collapse_claims(methods: &[MethodStress], threshold: f64, out: &mut Vec<StressClaim>) {
    for (m, claim, a, _) in validity_claims(methods, true) {
        let upto = worst_between(m, COLLAPSE_FROM_DEG, a);
        let beyond = worst_between(m, a, a + COLLAPSE_SPAN_DEG);
        let verdict = collapse_verdict(&upto, &beyond, threshold);
        let (lo, hi) = (COLLAPSE_FROM_DEG, a + COLLAPSE_SPAN_DEG);
        out.push(StressClaim {
            method: m.name.clone(),
            claim: claim.into(),
            measured: format!(
                "worst error at {lo}-{a} degrees {} ({} non-finite), at {a}-{hi} degrees {} ({} \
                 non-finite); threshold {threshold:.6}",
                fmt(upto.max),
                upto.non_finite,
                fmt(beyond.max),
                beyond.non_finite,
            ),
            verdict,
            how: format!(
                "worst device error over the facing cases of the angle sweep, against the \
                 stress threshold {threshold:.6} (1/255, the criterion of every validity claim \
                 here): collapses = within it at {lo}-{a} degrees and above it at {a}-{hi}; \
                 agrees when so, disagrees when still within it at {a}-{hi}, partly when above \
                 it at both (the loss starts before {a}), inconclusive when any case is \
                 non-finite (no error to judge) or nothing was measured"
            ),
        });
    }
}

/// Whether a relative error fails the digital-segment paper's 4 % (its magnitude above it, or
/// NaN): the claim is a bound on the error's size, whichever its sign.
fn above_4_percent(e: f64) -> bool {
    e.is_nan() || e.abs() > 0.04
}

/// The digital-segment paper's claim: within 4 % specular error for n <= 100 at 4 degrees between
/// end normals.
fn specular_claims(specular: &[SpecularBound], out: &mut Vec<StressClaim>) {
    for s in specular {
        let failing: Vec<f64> = s
            .shininess
            .iter()
            .zip(&s.relative_error)
            .filter(|(_, &e)| above_4_percent(e))
            .map(|(&n, _)| n)
            .collect();
        let bound_failing = s
            .shininess
            .iter()
            .zip(&s.bound)
            .filter(|(_, &b)| b > 0.04)
            .map(|(&n, _)| n)
            .collect::<Vec<_>>();
        let range = |v: &[f64]| match (v.first(), v.last()) {
            (Some(a), Some(b)) => format!("n = {a}..{b} ({} values)", v.len()),
            _ => "no n".into(),
        };
        let at100 = s.relative_error.last().copied().unwrap_or(f64::NAN);
        let first = s
            .shininess
            .iter()
            .zip(&s.relative_error)
            .find(|(_, &e)| above_4_percent(e))
            .map_or(String::new(), |(n, e)| {
                format!(" (first: n = {n}, {:.4} %)", 100.0 * e)
            });
        out.push(StressClaim {
            method: s.method.clone(),
            claim: "for n <= 100 the specular error stays within 4 % at 4 degrees between \
                    segment-end normals (docs/formulas.md#digital-segments-error-bounds)"
                .into(),
            measured: format!(
                "relative specular error at the segment's middle above 4 % for {}{first}; {:.2} % at n = 100; \
                 the seed's bound 1 - cos^n(2 deg) exceeds 4 % for {}",
                range(&failing),
                100.0 * at100,
                range(&bound_failing)
            ),
            verdict: if failing.is_empty() {
                Verdict::Agrees
            } else {
                Verdict::Disagrees
            },
            how: "one segment of 2^k pixels, end normals 4 degrees apart, H on their bisector, \
                  specular term alone (k_s = 1), n = 1..100, evaluated on the device at the \
                  middle pixel; disagrees when any n <= 100 exceeds 4 %"
                .into(),
        });
    }
}
