//! `shadelab stress`: every method swept over its input domain, in f64 (the method's own formula:
//! its approximation error) and in float32 on the device (glsl/evaluate.comp: the same GLSL as
//! the fragment shader, many cases per submission), both against f64 exact Phong (and exact
//! slerp along the span). Non-finite results are counted per method and rank above every finite
//! error. After the grid, a local search around the worst case looks for a worse one (a grid
//! misses maxima). Outputs: stress.json, charts, one validity map per method.
//!
//! `--precision f16` (issue 23) evaluates the float16 programs instead (same GLSL, float16_t
//! arithmetic), adds float16's own lengths to the sweep of lengths (|n|^2 overflowing 65504
//! from |n| ~ 181, and underflowing to float16 subnormals and zero), and reports each method's
//! `max_valid_angle_deg_f32` (the float32 program on the same grid) next to its float16 one.
pub mod chart;
pub mod grid;
pub mod replay;
#[cfg(test)]
mod tests;

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;
use serde::Serialize;

use crate::cases::grid::{self as sweeps, Grid};
use crate::cases::{errors, Case, CaseSpec, Errors};
use crate::error::{Error, Result};
use crate::gpu::evaluate::{Evaluated, GpuCase, Kernel};
use crate::gpu::shaders::has_evaluate_program;
use crate::gpu::vk::Context;
use crate::method::{Method, Precision, Reference};

use crate::cases::grid::Worst;

/// Version of stress.json (docs/stress.schema.json).
pub const SCHEMA_VERSION: u32 = 1;

/// Options of a stress run.
#[derive(Debug, Clone)]
pub struct StressOptions {
    /// Colour error (max abs, linear) within which a case counts as valid.
    pub threshold: f64,
    /// Local-search rounds after the grid (0: none).
    pub refine_rounds: usize,
    /// Show a progress bar on stderr (drawn only when stderr is a terminal).
    pub progress: bool,
    /// The precision of the device programs.
    pub precision: Precision,
}

impl Default for StressOptions {
    fn default() -> Self {
        StressOptions {
            threshold: 1.0 / 255.0,
            refine_rounds: 8,
            progress: false,
            precision: Precision::F32,
        }
    }
}

/// A result as numbers: colour and shading normal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Output {
    pub color: [f64; 3],
    pub normal: Option<[f64; 3]>,
}

impl Output {
    fn from_device(e: &Evaluated) -> Self {
        Output {
            color: e.color.map(f64::from),
            normal: e.normal.map(|n| n.map(f64::from)),
        }
    }

    fn color(&self) -> DVec3 {
        DVec3::from_array(self.color)
    }

    fn normal(&self) -> Option<DVec3> {
        self.normal.map(DVec3::from_array)
    }
}

/// One case with everything measured on it: replayable (`stress --replay FILE`).
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct CaseReport {
    pub method: String,
    /// The precision of the device program (absent in files written before issue 23: f32).
    #[serde(default)]
    pub precision: Precision,
    pub spec: CaseSpec,
    /// The f32 inputs the device read (glsl/evaluate.comp `struct Case`), for a reader.
    pub inputs: Option<GpuCaseJson>,
    /// Colours and normals: a NaN or infinite component is written as null (and read back
    /// as NaN).
    #[serde(default, deserialize_with = "nullable_rgb")]
    pub exact_phong: Option<[f64; 3]>,
    /// The device's colour (f32 widened).
    #[serde(default, deserialize_with = "nullable_rgb")]
    pub device_color: Option<[f64; 3]>,
    /// The device colour's f32 bit patterns, compared bit for bit by `--replay` (NaN too).
    #[serde(default)]
    pub device_color_bits: Option<[u32; 3]>,
    #[serde(default, deserialize_with = "nullable_rgb")]
    pub device_normal: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "nullable_rgb")]
    pub f64_color: Option<[f64; 3]>,
    /// Max abs colour error against exact Phong on the device (null: non-finite).
    pub device_abs_error: Option<f64>,
    pub f64_abs_error: Option<f64>,
}

/// The device inputs of a case, named.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct GpuCaseJson {
    pub weights: [f32; 3],
    pub pixel: [f32; 2],
    pub window: [[f32; 2]; 3],
    pub normals: [[f32; 3]; 3],
    pub flat_normal: [f32; 3],
    pub light_dir: [f32; 3],
    pub half_vec: [f32; 3],
    pub shininess: f32,
}

impl From<&GpuCase> for GpuCaseJson {
    fn from(g: &GpuCase) -> Self {
        let v3 = |v: [f32; 4]| [v[0], v[1], v[2]];
        GpuCaseJson {
            weights: v3(g.weights),
            pixel: [g.pixel[0], g.pixel[1]],
            window: g.window.map(|w| [w[0], w[1]]),
            normals: g.normals.map(v3),
            flat_normal: v3(g.flat_normal),
            light_dir: v3(g.light_dir),
            half_vec: v3(g.half_vec),
            shininess: g.specular[3],
        }
    }
}

/// Reads an RGB triple whose non-finite components were written as null.
fn nullable_rgb<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    let v: Option<[Option<f64>; 3]> = serde::Deserialize::deserialize(d)?;
    Ok(v.map(|c| c.map(|x| x.unwrap_or(f64::NAN))))
}

fn finite_or_none(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The f64 formula stress evaluates for `m`: its twin, or for a user method without one
/// (`--method-file`) exact Phong, whose figures are then reported as absent
/// ([`MethodStress::own_formula`] `no twin`): the device is judged against exact Phong either way.
fn f64_formula(m: &Method) -> &Method {
    // phong_exact is found by name: only when there is no twin.
    match m.twin() {
        Some(twin) => twin,
        None => crate::method::phong_exact(),
    }
}

/// What the "own formula" column says of a method without an f64 twin.
pub const NO_TWIN: &str = "no twin";

/// The report of one case evaluated both ways (the device in `precision`).
pub fn case_report(
    m: &Method,
    case: &Case,
    dev: Option<&Output>,
    precision: Precision,
) -> Result<CaseReport> {
    let f = f64_formula(m).eval_f64(&case.fragment, &case.lighting);
    let twin = m.twin().is_some();
    let ef = errors(case, f.color, f.normal);
    let ed = dev.map(|d| errors(case, d.color(), d.normal()));
    Ok(CaseReport {
        method: m.name.to_string(),
        precision,
        spec: case.spec,
        inputs: Some(GpuCaseJson::from(&GpuCase::new(
            &case.fragment,
            &case.lighting,
        )?)),
        exact_phong: Some(case.phong.to_array()),
        device_color: dev.map(|d| d.color),
        device_color_bits: dev.map(|d| d.color.map(|x| (x as f32).to_bits())),
        device_normal: dev.and_then(|d| d.normal),
        f64_color: twin.then(|| f.color.to_array()),
        device_abs_error: ed.and_then(|e| finite_or_none(e.abs)),
        f64_abs_error: finite_or_none(ef.abs).filter(|_| twin),
    })
}

/// One point of a curve: the worst error of the cases that share the key, both ways.
#[derive(Debug, Clone, Serialize)]
pub struct CurvePoint {
    /// The swept values (see the curve's name: angle; angle, shininess; angle, span; length;
    /// angle for a shape).
    pub key: Vec<f64>,
    /// The shape, for the shape sweep.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    pub device: Worst,
    pub f64: Worst,
}

/// The validity map: worst device error per (angle, elevation) cell of the angle sweep.
#[derive(Debug, Clone, Serialize)]
pub struct ValidityMap {
    pub angles_deg: Vec<f64>,
    pub elevations_deg: Vec<f64>,
    /// `cells[elevation][angle]`.
    pub cells: Vec<Vec<Worst>>,
}

/// Everything `stress` reports for one method (stress.json `methods[]`).
#[derive(Debug, Clone, Serialize)]
pub struct MethodStress {
    pub name: String,
    /// Evaluated on the device (false: a method that draws its own geometry, f64 only).
    pub device_evaluated: bool,
    pub cases: usize,
    /// Ill-conditioned cases with a finite result, left out of the errors (see
    /// [`crate::cases::Case::ill_conditioned`]; with a non-finite result they count as non-finite).
    pub ill_conditioned_cases: usize,
    /// Cases with a NaN or infinite colour or normal, on the device and in f64.
    pub non_finite_cases: usize,
    pub non_finite_cases_f64: usize,
    /// Worst colour error against exact Phong on the device, refined by the local search;
    /// null when any case was non-finite (then see `worst_finite_abs_error`).
    pub worst_abs_error: Option<f64>,
    pub worst_finite_abs_error: Option<f64>,
    /// The worst on the grid alone (before the local search).
    pub worst_grid_abs_error: Option<f64>,
    pub worst_abs_error_f64: Option<f64>,
    /// Against exact slerp along the span (angle-interpolating methods): the largest finite
    /// value; `non_finite_vs_slerp` counts the cases that had none.
    pub worst_abs_error_vs_slerp: Option<f64>,
    pub non_finite_vs_slerp: usize,
    pub worst_case: Option<CaseReport>,
    pub non_finite_example: Option<CaseReport>,
    /// Largest finite normal angle error; `non_finite_angle` counts the non-finite ones.
    pub worst_angle_deg: Option<f64>,
    pub non_finite_angle: usize,
    /// Largest finite normal length error; `non_finite_length` counts the non-finite ones.
    pub worst_length_error: Option<f64>,
    pub non_finite_length: usize,
    /// Largest vertex-normal angle up to which every case facing the viewer (elevation under
    /// 90 degrees) of the angle sweep is finite and within the threshold, on the device
    /// (null: not even at 0 degrees).
    pub max_valid_angle_deg: Option<f64>,
    pub max_valid_angle_deg_f64: Option<f64>,
    /// In a float16 run: the same angle for the float32 program on the same grid (absent in a
    /// float32 run, where it is `max_valid_angle_deg`; a method without a device program: its
    /// f64 figure, as `max_valid_angle_deg`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_valid_angle_deg_f32: Option<Option<f64>>,
    pub error_vs_angle: Vec<CurvePoint>,
    /// The normal's length error ||N| - 1| per angle, facing the viewer (the length criterion
    /// of a validity claim); empty for a method without a normal.
    pub length_error_vs_angle: Vec<CurvePoint>,
    pub error_vs_shininess: Vec<CurvePoint>,
    pub error_vs_span: Vec<CurvePoint>,
    pub error_vs_length: Vec<CurvePoint>,
    pub error_vs_shape: Vec<CurvePoint>,
    pub validity_map: ValidityMap,
    pub seconds: f64,
    /// [`NO_TWIN`] for a user method (`--method-file`): it has no f64 formula, so every `_f64`
    /// figure is null (its curves' `f64` empty) and the device is judged against exact Phong
    /// alone. Absent for the built-in methods.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub own_formula: Option<&'static str>,
}

/// Evaluates every case of `grid` for `m`: device results (None without a device program) and
/// f64 twin results, in grid order.
fn evaluate(
    kernel: Option<&mut Kernel>,
    m: &Method,
    cases: &[Case],
    gpu: &[GpuCase],
) -> Result<(Option<Vec<Output>>, Vec<Output>)> {
    let dev = match kernel {
        Some(k) => Some(k.run(gpu)?.iter().map(Output::from_device).collect()),
        None => None,
    };
    // Once per method, not per case (phong_exact is found by name).
    let formula = f64_formula(m);
    let twin = par_map(cases.len(), |i| {
        let c = &cases[i];
        let r = formula.eval_f64(&c.fragment, &c.lighting);
        Output {
            color: r.color.to_array(),
            normal: r.normal.map(|n| n.to_array()),
        }
    })?;
    Ok((dev, twin))
}

/// `f` of every index below `n`, in order, on every core (the f64 formulas and the errors of
/// stress's hundreds of thousands of cases).
fn par_map<U: Send>(n: usize, f: impl Fn(usize) -> U + Sync) -> Result<Vec<U>> {
    crate::parallel::map_indices(n, f)
        .map_err(|_| Error::Internal("a stress worker panicked".into()))
}

/// In a float16 run, the largest valid angle of the float32 program on the same grid (the
/// inner None: not even at 0 degrees; a method without a device program: filled in by the
/// caller with its f64 figure); None in a float32 run.
fn valid_angle_f32(
    ctx: &Arc<Context>,
    m: &Method,
    grid: &Grid,
    opts: &StressOptions,
) -> Result<Option<Option<f64>>> {
    if opts.precision == Precision::F32 {
        return Ok(None);
    }
    if !has_evaluate_program(m) {
        return Ok(Some(None));
    }
    let out = Kernel::new(ctx, m)?.run(&grid.gpu)?;
    let errs: Vec<Errors> = grid
        .cases
        .iter()
        .zip(&out)
        .map(|(c, e)| {
            let o = Output::from_device(e);
            errors(c, o.color(), o.normal())
        })
        .collect();
    Ok(Some(sweeps::max_valid_angle(grid, &errs, opts.threshold)))
}

/// A method's errors on the grid folded into its worst figures (the cases a sweep applies to).
struct GridWorst {
    /// The counted colour errors (device, or f64 without a device program), and the f64 twin's.
    all: Worst,
    all_f64: Worst,
    vs_slerp: Worst,
    angle: Worst,
    length: Worst,
    /// The worst finite counted case, and the first non-finite one.
    worst_i: Option<usize>,
    non_finite_i: Option<usize>,
    /// Finite results on ill-conditioned cases, left out.
    ill: usize,
}

/// Folds `primary` (and the twin's `f64_err`) over the cases `applies` selects.
fn fold_grid(m: &Method, applies: &[bool], primary: &[Errors], f64_err: &[Errors]) -> GridWorst {
    let mut g = GridWorst {
        all: Worst::default(),
        all_f64: Worst::default(),
        vs_slerp: Worst::default(),
        angle: Worst::default(),
        length: Worst::default(),
        worst_i: None,
        non_finite_i: None,
        ill: 0,
    };
    for i in (0..primary.len()).filter(|&i| applies[i]) {
        let e = &primary[i];
        if let Some(v) = f64_err[i].counted() {
            g.all_f64.add(v);
        }
        let Some(v) = e.counted() else {
            g.ill += 1;
            continue;
        };
        g.all.add(v);
        if m.reference == Reference::PhongAndSlerp {
            g.vs_slerp.add(e.abs_slerp);
        }
        if let Some(a) = e.angle_deg {
            g.angle.add(a);
        }
        if let Some(l) = e.length {
            g.length.add(l);
        }
        if e.non_finite {
            g.non_finite_i.get_or_insert(i);
        } else if g.worst_i.is_none_or(|w| e.abs > primary[w].abs) {
            g.worst_i = Some(i);
        }
    }
    g
}

/// Runs the sweeps for one method.
pub fn stress_method(
    ctx: &Arc<Context>,
    m: &'static Method,
    grid: &Grid,
    opts: &StressOptions,
) -> Result<MethodStress> {
    let start = Instant::now();
    let mut kernel = has_evaluate_program(m)
        .then(|| Kernel::with_precision(ctx, m, 1, opts.precision))
        .transpose()?;
    let (dev, twin) = evaluate(kernel.as_mut(), m, &grid.cases, &grid.gpu)?;
    let valid_f32 = valid_angle_f32(ctx, m, grid, opts)?;
    let applies: Vec<bool> = grid.kinds.iter().map(|&k| sweeps::applies(m, k)).collect();
    let errors_of = |out: &[Output]| {
        par_map(grid.cases.len(), |i| {
            errors(&grid.cases[i], out[i].color(), out[i].normal())
        })
    };
    let dev_err: Option<Vec<Errors>> = dev.as_deref().map(errors_of).transpose()?;
    let f64_err: Vec<Errors> = errors_of(&twin)?;
    // The measure of a case: the device's error, or the twin's without a device program.
    let primary = dev_err.as_ref().unwrap_or(&f64_err);

    let GridWorst {
        all,
        all_f64,
        vs_slerp,
        angle,
        length,
        worst_i,
        non_finite_i,
        ill,
    } = fold_grid(m, &applies, primary, &f64_err);
    let report =
        |i: usize, out: Option<&Output>| case_report(m, &grid.cases[i], out, opts.precision);
    let dev_out = |i: usize| dev.as_ref().map(|d| &d[i]);
    let mut worst_case = worst_i.map(|i| report(i, dev_out(i))).transpose()?;
    let non_finite_example = non_finite_i.map(|i| report(i, dev_out(i))).transpose()?;
    let worst_grid = all.max;
    let mut worst_finite = all.max;
    if let (Some(i), true) = (worst_i, opts.refine_rounds > 0) {
        let found = refine(kernel.as_mut(), m, grid.cases[i].spec, primary[i].abs, opts)?;
        if let Some((case, out, err)) = found {
            worst_finite = Some(err);
            worst_case = Some(case_report(m, &case, out.as_ref(), opts.precision)?);
        }
    }
    let curves = grid::curves(grid, &applies, primary, &f64_err);
    let max_valid = sweeps::max_valid_angle(grid, primary, opts.threshold);
    let max_valid_f64 = sweeps::max_valid_angle(grid, &f64_err, opts.threshold);
    let out = MethodStress {
        name: m.name.to_string(),
        device_evaluated: dev.is_some(),
        cases: all.count + ill,
        ill_conditioned_cases: ill,
        non_finite_cases: if dev.is_some() { all.non_finite } else { 0 },
        non_finite_cases_f64: all_f64.non_finite,
        worst_abs_error: if all.non_finite > 0 {
            None
        } else {
            worst_finite
        },
        worst_finite_abs_error: worst_finite,
        worst_grid_abs_error: worst_grid,
        worst_abs_error_f64: if all_f64.non_finite > 0 {
            None
        } else {
            all_f64.max
        },
        worst_abs_error_vs_slerp: vs_slerp.max,
        non_finite_vs_slerp: vs_slerp.non_finite,
        worst_case,
        non_finite_example,
        worst_angle_deg: angle.max,
        non_finite_angle: angle.non_finite,
        worst_length_error: length.max,
        non_finite_length: length.non_finite,
        max_valid_angle_deg: max_valid,
        max_valid_angle_deg_f64: max_valid_f64,
        // a method without a device program is its f64 twin in both precisions
        max_valid_angle_deg_f32: valid_f32.map(|v| if dev.is_some() { v } else { max_valid_f64 }),
        error_vs_angle: curves.angle,
        length_error_vs_angle: curves.length_vs_angle,
        error_vs_shininess: curves.shininess,
        error_vs_span: curves.span,
        error_vs_length: curves.length,
        error_vs_shape: curves.shape,
        validity_map: grid::validity_map(grid, primary),
        seconds: start.elapsed().as_secs_f64(),
        own_formula: None,
    };
    Ok(without_twin(m, out))
}

/// For a method without a twin: its f64 figures (exact Phong's) cleared, and `own_formula`
/// saying so. Other methods' reports are returned as they are.
fn without_twin(m: &Method, mut s: MethodStress) -> MethodStress {
    if m.twin().is_some() {
        return s;
    }
    s.own_formula = Some(NO_TWIN);
    s.non_finite_cases_f64 = 0;
    s.worst_abs_error_f64 = None;
    s.max_valid_angle_deg_f64 = None;
    for curve in [
        &mut s.error_vs_angle,
        &mut s.length_error_vs_angle,
        &mut s.error_vs_shininess,
        &mut s.error_vs_span,
        &mut s.error_vs_length,
        &mut s.error_vs_shape,
    ] {
        for p in curve.iter_mut() {
            p.f64 = Worst::default();
        }
    }
    s
}

/// The errors of `cases` (device, or f64 without a device program), with the device outputs.
fn measure(
    kernel: &mut Option<&mut Kernel>,
    m: &Method,
    cases: &[Case],
) -> Result<Vec<(Errors, Option<Output>)>> {
    match kernel {
        Some(k) => {
            let gpu = cases
                .iter()
                .map(|c| GpuCase::new(&c.fragment, &c.lighting))
                .collect::<Result<Vec<_>>>()?;
            let out = k.run(&gpu)?;
            Ok(cases
                .iter()
                .zip(out)
                .map(|(c, e)| {
                    let o = Output::from_device(&e);
                    (errors(c, o.color(), o.normal()), Some(o))
                })
                .collect())
        }
        None => Ok(cases
            .iter()
            .map(|c| {
                let r = f64_formula(m).eval_f64(&c.fragment, &c.lighting);
                (errors(c, r.color, r.normal), None)
            })
            .collect()),
    }
}

/// Local search around `start` (error `start_err`): each round perturbs the continuous
/// parameters of the best case so far (angles, light, pixel) by steps that shrink by half per
/// round, evaluates a batch and keeps the worst one the grid would count ([`Errors::counted`]:
/// finite, and not ill-conditioned, so a neighbour whose interpolated normal is shorter than
/// [`crate::cases::ILL_CONDITIONED`] never wins). Returns it when it beats the grid.
fn refine(
    mut kernel: Option<&mut Kernel>,
    m: &Method,
    start: CaseSpec,
    start_err: f64,
    opts: &StressOptions,
) -> Result<Option<(Case, Option<Output>, f64)>> {
    const BATCH: usize = 256;
    let mut rng = fastrand::Rng::with_seed(0x5eed ^ m.name.len() as u64);
    let (mut best, mut best_err) = (start, start_err);
    let mut found: Option<(Case, Option<Output>, f64)> = None;
    let mut step = 8.0;
    for _ in 0..opts.refine_rounds {
        let specs: Vec<CaseSpec> = (0..BATCH)
            .map(|_| grid::perturb(&best, step, &mut rng))
            .collect();
        let cases: Vec<Case> = specs.into_iter().map(Case::new).collect();
        let measured = measure(&mut kernel, m, &cases)?;
        for (case, (e, out)) in cases.into_iter().zip(measured) {
            let Some(err) = e.counted().filter(|v| v.is_finite()) else {
                continue;
            };
            if err > best_err {
                best_err = err;
                best = case.spec;
                found = Some((case, out, err));
            }
        }
        step *= 0.5;
    }
    Ok(found)
}

/// stress.json.
#[derive(Debug, Clone, Serialize)]
pub struct StressReport {
    pub schema_version: u32,
    /// The precision of the device programs (`f32`, `f16`).
    pub precision: Precision,
    pub threshold: f64,
    pub device: String,
    pub cases_per_method: usize,
    pub sweeps: Vec<sweeps::SweepInfo>,
    pub methods: Vec<MethodStress>,
    pub specular_bound: Vec<grid::SpecularBound>,
    pub claims: Vec<StressClaim>,
    pub seconds: f64,
    pub provenance: crate::output::provenance::Provenance,
}

/// A validity claim of the papers and its verdict, computed from the sweep.
#[derive(Debug, Clone, Serialize)]
pub struct StressClaim {
    pub method: String,
    pub claim: String,
    pub measured: String,
    pub verdict: crate::method::Verdict,
    pub how: String,
}

/// The text table: one row per method, worst first (non-finite above every finite error).
pub fn table(r: &StressReport) -> String {
    let mut rows: Vec<&MethodStress> = r.methods.iter().collect();
    let rank = |m: &MethodStress| {
        (
            m.non_finite_cases,
            m.worst_finite_abs_error.unwrap_or(f64::INFINITY),
        )
    };
    rows.sort_by(|a, b| {
        let (ra, rb) = (rank(a), rank(b));
        rb.0.cmp(&ra.0).then(rb.1.total_cmp(&ra.1))
    });
    let fmt = |x: Option<f64>, p: usize| x.map_or("-".to_string(), |v| format!("{v:.p$e}"));
    // a finite worst with the count of non-finite values beside it, never the worst alone
    let with_count = |x: Option<f64>, n: usize| match n {
        0 => fmt(x, 2),
        n => format!("{} +{n} NaN", fmt(x, 2)),
    };
    let mut s = format!(
        "{:<32} {:>8} {:>10} {:>10} {:>10} {:>16} {:>9}\n",
        "method", "cases", "non-finite", "worst", "worst f64", "max angle", "valid to"
    );
    for m in rows {
        s += &format!(
            "{:<32} {:>8} {:>10} {:>10} {:>10} {:>16} {:>9}\n",
            m.name,
            m.cases,
            if m.device_evaluated {
                m.non_finite_cases.to_string()
            } else {
                format!("{} (f64)", m.non_finite_cases_f64)
            },
            fmt(m.worst_finite_abs_error, 2),
            m.own_formula
                .map_or_else(|| fmt(m.worst_abs_error_f64, 2), str::to_string),
            with_count(m.worst_angle_deg, m.non_finite_angle),
            m.max_valid_angle_deg
                .map_or("none".to_string(), |a| format!("{a} deg")),
        );
    }
    for c in &r.claims {
        s += &format!(
            "claim {} [{}]: {} -> {}\n",
            c.method, c.verdict, c.claim, c.measured
        );
    }
    s
}

/// Writes the charts, the validity maps, the case files and, last (the run's completion
/// marker), DIR/stress.json.
pub fn write(out: &Path, report: &StressReport) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    chart::error_vs_angle(out, report)?;
    chart::error_vs_shininess(out, report)?;
    let maps = out.join("validity");
    std::fs::create_dir_all(&maps).map_err(|e| Error::io(&maps, e))?;
    let cases = out.join("cases");
    std::fs::create_dir_all(&cases).map_err(|e| Error::io(&cases, e))?;
    for m in &report.methods {
        chart::validity_map(&maps.join(format!("{}.png", m.name)), m, report.threshold)?;
        for (suffix, case) in [("", &m.worst_case), ("_non_finite", &m.non_finite_example)] {
            if let Some(c) = case {
                let json =
                    serde_json::to_string_pretty(c).map_err(|e| Error::output("a case file", e))?;
                let path = cases.join(format!("{}{suffix}.json", m.name));
                crate::output::write_bytes_atomic(&path, (json + "\n").as_bytes())?;
            }
        }
    }
    // Compact (one line): 3.2 MB against 7.4 MB indented for the report's 37 methods;
    // `python3 -m json.tool` or `jq .` indents it for reading.
    let json = serde_json::to_string(report).map_err(|e| Error::output("stress.json", e))?;
    crate::output::write_bytes_atomic(&out.join("stress.json"), (json + "\n").as_bytes())
}

/// The digital-segment paper's specular bound (see [`grid::SpecularBound`]) for the
/// colour-interpolating digital segments among `methods`.
fn specular_bounds(
    ctx: &Arc<Context>,
    methods: &[&'static Method],
    precision: Precision,
) -> Result<Vec<grid::SpecularBound>> {
    let mut out = Vec::new();
    for m in methods {
        let crate::method::Kernel::Span(crate::method::SpanKernel::Segments(k, None)) = m.kernel
        else {
            continue;
        };
        let name = m.name.to_string();
        let cases: Vec<Case> = grid::specular_bound_specs(k)
            .into_iter()
            .map(Case::new)
            .collect();
        let mut kernel = Some(Kernel::with_precision(ctx, m, 1, precision)?);
        let measured = measure(&mut kernel.as_mut(), m, &cases)?;
        let half = (2.0f64).to_radians();
        out.push(grid::SpecularBound {
            method: name,
            shininess: cases.iter().map(|c| c.spec.shininess).collect(),
            relative_error: cases
                .iter()
                .zip(&measured)
                .map(|(c, (_, o))| {
                    let got = o.as_ref().map_or(f64::NAN, |o| o.color[0]);
                    (c.phong.x - got) / c.phong.x
                })
                .collect(),
            bound: cases
                .iter()
                .map(|c| 1.0 - half.cos().powf(c.spec.shininess))
                .collect(),
        });
    }
    Ok(out)
}

/// Runs every sweep for `methods`, then the claims.
pub fn run(
    ctx: &Arc<Context>,
    methods: &[&'static Method],
    opts: &StressOptions,
) -> Result<StressReport> {
    let start = Instant::now();
    ctx.require_precision(opts.precision)?;
    let grid = Grid::for_precision(opts.precision)?;
    let bar = crate::output::progress_bar(opts.progress, methods.len() as u64);
    let mut out = Vec::with_capacity(methods.len());
    for m in methods {
        bar.set_message(m.name);
        out.push(stress_method(ctx, m, &grid, opts)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let specular = specular_bounds(ctx, methods, opts.precision)?;
    let claims = grid::claims(&out, &specular, opts.threshold);
    Ok(StressReport {
        schema_version: SCHEMA_VERSION,
        precision: opts.precision,
        threshold: opts.threshold,
        device: ctx.info().name.clone(),
        cases_per_method: grid.cases.len(),
        sweeps: grid.info(),
        methods: out,
        specular_bound: specular,
        claims,
        seconds: start.elapsed().as_secs_f64(),
        provenance: {
            let i = ctx.info();
            crate::output::provenance::Provenance::new(
                &i.name,
                &i.driver_name,
                &i.driver_info,
                &i.api_version,
            )
        },
    })
}
