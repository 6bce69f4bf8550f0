//! The sweeps of the cases: which cases each holds ([`Grid`]), which methods each applies to,
//! and the largest valid angle of the angle sweep; [`Worst`] folds their errors. Built once and
//! shared by `stress`, `bench`'s isolated cost and `plan`.
use serde::Serialize;

use super::{Case, CaseSpec, Errors, Shape};
use crate::error::Result;
use crate::gpu::evaluate::GpuCase;
use crate::method::{Input, Method};

/// The sweep a case belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    /// Angle between the vertex normals x elevation x frame x light (the validity map).
    Angle,
    /// Angle x shininess, the light on the specular peak and 10 degrees off it.
    Shininess,
    /// Span length (1 to 4096 pixels) x angle, every pixel of short spans.
    Span,
    /// Vertex normals scaled by 0 .. 1e38 (methods that take the interpolated normal).
    Length,
    /// Slivers and a sub-pixel triangle.
    Shape,
}

/// Angles between the vertex normals, degrees: dense near 0 and near 180.
pub const ANGLES: [f64; 31] = [
    0.0, 0.01, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0, 15.0, 22.5, 30.0, 40.0, 45.0, 50.0, 60.0, 75.0, 90.0,
    100.0, 105.0, 120.0, 135.0, 150.0, 160.0, 170.0, 175.0, 178.0, 179.0, 179.5, 179.9, 179.99,
    180.0,
];
/// Angle of the pair's bisector from the viewer, degrees (90: edge-on, 180: facing away).
pub const ELEVATIONS: [f64; 19] = [
    0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 90.0, 91.0, 95.0, 105.0, 120.0, 135.0, 150.0,
    165.0, 175.0, 179.0, 180.0,
];
/// (pair azimuth, roll) in degrees: the pair's plane holding or crossing the view axis, and the
/// whole configuration turned about the view axis.
pub const FRAMES: [(f64, f64); 4] = [(0.0, 0.0), (90.0, 0.0), (0.0, 90.0), (90.0, 45.0)];
/// (angle of L from the bisector, out of the pair's plane): along the normal, 45 degrees,
/// grazing in and across the plane, below the horizon.
pub const LIGHTS: [(f64, bool); 5] = [
    (0.0, false),
    (45.0, false),
    (89.9, false),
    (89.9, true),
    (100.0, false),
];
pub const SHININESS: [f64; 16] = [
    1.0, 2.0, 5.0, 10.0, 20.0, 30.0, 50.0, 67.0, 68.0, 80.0, 100.0, 150.0, 200.0, 300.0, 500.0,
    1000.0,
];
pub const SHININESS_ANGLES: [f64; 9] = [1.0, 2.0, 4.0, 8.0, 15.0, 30.0, 45.0, 60.0, 90.0];
pub const SPANS: [u32; 16] = [
    1, 2, 3, 4, 5, 7, 8, 16, 33, 64, 128, 256, 512, 1024, 2048, 4096,
];
pub const LENGTHS: [f64; 16] = [
    0.0, 1e-45, 1e-40, 1e-38, 1e-30, 1e-20, 1e-10, 1e-3, 0.5, 1.0, 2.0, 1e3, 1e10, 1e20, 1e30, 1e38,
];
/// The lengths a float16 run adds to [`LENGTHS`] (issue 23), around float16's limits: |n|^2
/// is a float16 subnormal below |n| = 2^-7 (smallest normal 2^-14) and rounds to zero below
/// about 1.7e-4 (2^-25); |n|^2 itself overflows 65504 above |n| = 255.9, and a method's own
/// intermediate sooner (lyon_taylor's (|n|^2 - 1)^2 above |n| ~ 16, Mikami's s0^2 above ~ 20).
pub const F16_LENGTHS: [f64; 12] = [
    1e-5, 1e-4, 2.4e-4, 3e-3, 6.1e-3, 0.01, 16.0, 20.0, 100.0, 181.0, 256.0, 300.0,
];
/// Angles of the span, length and shape sweeps.
pub const FEW_ANGLES: [f64; 3] = [4.0, 30.0, 90.0];
/// The strip's span in the angle and shininess sweeps, and its sampled pixels.
pub const SPAN: u32 = 64;
const SHAPES: [Shape; 3] = [Shape::SliverRow, Shape::SliverColumn, Shape::SubPixel];

/// `n` pixels spread over a span of `span` (all of them when it is no longer).
fn pixels(span: u32, n: u32) -> Vec<u32> {
    if span <= n {
        return (0..span).collect();
    }
    let mut v: Vec<u32> = (0..n)
        .map(|k| {
            ((u64::from(k) * u64::from(span - 1) + u64::from(n / 2)) / u64::from(n - 1)) as u32
        })
        .map(|p| p.min(span - 1))
        .collect();
    v.dedup();
    v
}

/// What a sweep holds, for stress.json.
#[derive(Debug, Clone, Serialize)]
pub struct SweepInfo {
    pub sweep: Sweep,
    pub cases: usize,
    pub varies: &'static str,
}

/// Every case of every sweep, built once and shared by all methods.
pub struct Grid {
    pub cases: Vec<Case>,
    pub gpu: Vec<GpuCase>,
    pub kinds: Vec<Sweep>,
}

impl Grid {
    /// The specs of every sweep, in a fixed order.
    pub fn specs() -> Vec<(Sweep, CaseSpec)> {
        let base = CaseSpec::default();
        let mut out = Vec::new();
        for &theta in &ANGLES {
            for &elevation in &ELEVATIONS {
                for &(az, roll) in &FRAMES {
                    for &(light, out_of_plane) in &LIGHTS {
                        for pixel in pixels(SPAN, 17) {
                            out.push((
                                Sweep::Angle,
                                CaseSpec {
                                    theta_deg: theta,
                                    elevation_deg: elevation,
                                    pair_azimuth_deg: az,
                                    roll_deg: roll,
                                    light_deg: light,
                                    light_out_of_plane: out_of_plane,
                                    span_px: SPAN,
                                    pixel,
                                    ..base
                                },
                            ));
                        }
                    }
                }
            }
        }
        for &theta in &SHININESS_ANGLES {
            // At 4 degrees every integer n up to 100 (the digital-segment paper's claim), then the
            // coarse list.
            let dense: Vec<f64> = if theta == 4.0 {
                (1..=100)
                    .map(f64::from)
                    .chain([150.0, 200.0, 300.0, 500.0, 1000.0])
                    .collect()
            } else {
                SHININESS.to_vec()
            };
            for &n in &dense {
                for elevation in [0.0, 30.0, 60.0] {
                    // light_deg = elevation in the pair's plane puts H on the bisector.
                    for off in [0.0, 10.0] {
                        for pixel in pixels(SPAN, 17) {
                            out.push((
                                Sweep::Shininess,
                                CaseSpec {
                                    theta_deg: theta,
                                    elevation_deg: elevation,
                                    light_deg: elevation + off,
                                    shininess: n,
                                    span_px: SPAN,
                                    pixel,
                                    ..base
                                },
                            ));
                        }
                    }
                }
            }
        }
        for &span in &SPANS {
            for &theta in &FEW_ANGLES {
                for pixel in pixels(span, 65) {
                    out.push((
                        Sweep::Span,
                        CaseSpec {
                            theta_deg: theta,
                            span_px: span,
                            pixel,
                            ..base
                        },
                    ));
                }
            }
        }
        for &length in &LENGTHS {
            for &theta in &FEW_ANGLES {
                for pixel in pixels(SPAN, 17) {
                    out.push((
                        Sweep::Length,
                        CaseSpec {
                            theta_deg: theta,
                            length,
                            pixel,
                            ..base
                        },
                    ));
                }
            }
        }
        for &shape in &SHAPES {
            for &theta in &FEW_ANGLES {
                let along = if shape == Shape::SubPixel {
                    vec![0]
                } else {
                    pixels(3413, 33)
                };
                for pixel in along {
                    out.push((
                        Sweep::Shape,
                        CaseSpec {
                            theta_deg: theta,
                            shape,
                            pixel,
                            ..base
                        },
                    ));
                }
            }
        }
        out
    }

    /// Builds every case (f64 references and the device's f32 inputs).
    pub fn new() -> Result<Grid> {
        Grid::from_specs(Grid::specs())
    }

    /// The grid of a stress run in `precision`: [`Grid::new`] for float32; float16 adds
    /// [`F16_LENGTHS`] to the sweep of lengths.
    pub fn for_precision(precision: crate::method::Precision) -> Result<Grid> {
        let mut specs = Grid::specs();
        if precision == crate::method::Precision::F16 {
            let base = CaseSpec::default();
            for &length in &F16_LENGTHS {
                for &theta in &FEW_ANGLES {
                    for pixel in pixels(SPAN, 17) {
                        let spec = CaseSpec {
                            theta_deg: theta,
                            length,
                            pixel,
                            ..base
                        };
                        specs.push((Sweep::Length, spec));
                    }
                }
            }
        }
        Grid::from_specs(specs)
    }

    fn from_specs(specs: Vec<(Sweep, CaseSpec)>) -> Result<Grid> {
        let mut cases = Vec::with_capacity(specs.len());
        let mut gpu = Vec::with_capacity(specs.len());
        let mut kinds = Vec::with_capacity(specs.len());
        for (kind, spec) in specs {
            let case = Case::new(spec);
            gpu.push(GpuCase::new(&case.fragment, &case.lighting)?);
            cases.push(case);
            kinds.push(kind);
        }
        Ok(Grid { cases, gpu, kinds })
    }

    /// Cases per sweep.
    pub fn info(&self) -> Vec<SweepInfo> {
        [
            (Sweep::Angle, "angle between the vertex normals x elevation x frame x light x pixel"),
            (Sweep::Shininess, "angle x shininess 1..1000 x elevation x light on / 10 degrees off the peak x pixel"),
            (Sweep::Span, "span of 1..4096 pixels x angle x pixel"),
            (Sweep::Length, "vertex normals' length 0, 1e-45 (subnormal) .. 1e38 x angle x pixel"),
            (Sweep::Shape, "slivers along a row and a column (4096 x 0.1 px), a sub-pixel triangle x angle"),
        ]
        .into_iter()
        .map(|(sweep, varies)| SweepInfo {
            sweep,
            cases: self.kinds.iter().filter(|&&k| k == sweep).count(),
            varies,
        })
        .collect()
    }
}

/// Whether a sweep applies to a method: the sweep of lengths only to methods that take the
/// interpolated normal (the others read unit corner normals).
pub fn applies(m: &Method, sweep: Sweep) -> bool {
    match sweep {
        Sweep::Length => m.inputs.contains(&Input::InterpolatedNormal),
        _ => true,
    }
}

/// The largest angle of [`ANGLES`] up to which every facing case of the angle sweep is finite
/// and within `threshold` (None: not even the first).
pub fn max_valid_angle(grid: &Grid, errs: &[Errors], threshold: f64) -> Option<f64> {
    let mut per_angle = vec![Worst::default(); ANGLES.len()];
    for (i, c) in grid.cases.iter().enumerate() {
        if grid.kinds[i] == Sweep::Angle && c.spec.elevation_deg < 90.0 {
            if let (Some(a), Some(e)) = (
                ANGLES.iter().position(|&a| a == c.spec.theta_deg),
                errs[i].counted(),
            ) {
                per_angle[a].add(e);
            }
        }
    }
    let valid = per_angle.iter().take_while(|w| w.valid(threshold)).count();
    valid.checked_sub(1).map(|k| ANGLES[k])
}

/// Max of finite values and how many were not finite.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Worst {
    /// Largest finite value (null when there was none).
    pub max: Option<f64>,
    pub non_finite: usize,
    pub count: usize,
}

impl Worst {
    /// Counts `v`: the largest finite value so far, or one more non-finite.
    pub fn add(&mut self, v: f64) {
        self.count += 1;
        if v.is_finite() {
            self.max = Some(self.max.map_or(v, |m| m.max(v)));
        } else {
            self.non_finite += 1;
        }
    }

    /// Within `threshold` on every case (no non-finite case, at least one case).
    pub fn valid(&self, threshold: f64) -> bool {
        self.count > 0 && self.non_finite == 0 && self.max.is_some_and(|m| m <= threshold)
    }
}
