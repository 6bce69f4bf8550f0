//! `shadelab bench`: run time against error. Timing on lavapipe with a validated clock,
//! interleaved repetitions, medians with distribution-free 95% confidence intervals, the error
//! metrics of `compare`, static operation counts of each fragment shader, a Pareto chart, the
//! papers' claims checked, and sweeps over image size and triangle count.
//!
//! Clock: Vulkan timestamps placed as TOOLCHAIN.md found to track the draw on Mesa 22.3 (see
//! `Renderer::timed_draws`). Every run re-checks the placement: at sizes 128..2048 the
//! timestamp interval must track the submit-to-fence wall clock ([`CLOCK_TOLERANCE`]); when it
//! does not, the run says so and times with the wall clock instead.
use std::path::Path;

use serde::Serialize;

use crate::compare::{self, CompareOptions, MethodReport, Provenance};
use crate::error::{Error, Result};
use crate::mesh::Generator;
use crate::methods::{self, Method};
use crate::output;
use crate::render::{Prepared, Renderer, Shading, TimedDraws};
use crate::scene::Scene;
use crate::spirv::{self, OpCounts, OpCountsDelta};

/// Version of the bench.json layout.
pub const SCHEMA_VERSION: u32 = 1;
/// Sizes of the clock check and of `--sweep size`.
pub const SIZES: [u32; 5] = [128, 256, 512, 1024, 2048];
/// The timestamp interval tracks the wall clock when, at every size, it is within this
/// fraction of the wall time or within [`CLOCK_SLACK_MS`] of it (submission overhead
/// dominates small draws).
pub const CLOCK_TOLERANCE: f64 = 0.25;
pub const CLOCK_SLACK_MS: f64 = 2.0;
/// (segments, rings) of the UV spheres of `--sweep triangles`: 2 * segments * (rings - 1)
/// triangles, about 100 to 1,000,000.
pub const SPHERES: [(u32, u32); 5] = [(10, 6), (32, 17), (100, 51), (316, 159), (1000, 501)];

/// What to sweep besides the main bench.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    Size,
    Triangles,
}

/// Options of a bench run.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    pub repeat: usize,
    pub warmup: usize,
    /// A compare metric (JSON name) for the Pareto chart's y axis.
    pub error_metric: String,
    /// Add `phong_exact_control`: phong_exact's program under a second name.
    pub control: bool,
    pub sweeps: Vec<Sweep>,
}

/// A median with its 95% confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    pub median: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    pub samples: usize,
}

/// P(X <= k) for X ~ Binomial(n, 1/2).
fn binomial_half_cdf(n: usize, k: usize) -> f64 {
    // log C(n, i) iteratively; exact enough for n up to millions.
    let mut log_c = 0.0f64;
    let mut sum = 0.0;
    let log_half_n = n as f64 * 0.5f64.ln();
    for i in 0..=k.min(n) {
        if i > 0 {
            log_c += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        sum += (log_c + log_half_n).exp();
    }
    sum.min(1.0)
}

/// Median and distribution-free 95% confidence interval from order statistics: the interval
/// [x(l), x(n+1-l)] (1-based, sorted) with l the largest rank such that P(Bin(n, 1/2) < l) <=
/// 2.5 %. With fewer than 6 samples no such rank exists and the interval is [min, max].
pub fn median_ci(samples: &[f64]) -> Estimate {
    let mut v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return Estimate {
            median: f64::NAN,
            ci95_low: f64::NAN,
            ci95_high: f64::NAN,
            samples: 0,
        };
    }
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    let mut l = 0usize; // 1-based rank; 0 = none
    for k in 1..=n / 2 {
        if binomial_half_cdf(n, k - 1) <= 0.025 {
            l = k;
        } else {
            break;
        }
    }
    let (lo, hi) = if l == 0 {
        (v[0], v[n - 1])
    } else {
        (v[l - 1], v[n - l])
    };
    Estimate {
        median,
        ci95_low: lo,
        ci95_high: hi,
        samples: n,
    }
}

/// Indices of the points not dominated by any other (smaller-or-equal in both coordinates and
/// smaller in one). Points with a non-finite coordinate are never on the front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (x, y) = points[i];
            x.is_finite()
                && y.is_finite()
                && !points.iter().enumerate().any(|(j, &(a, b))| {
                    j != i && a.is_finite() && b.is_finite() && a <= x && b <= y && (a < x || b < y)
                })
        })
        .collect()
}

/// The clock check at one size.
#[derive(Debug, Clone, Serialize)]
pub struct ClockPoint {
    pub width: u32,
    pub height: u32,
    pub wall_median_ms: f64,
    pub timestamp_median_ms: Option<f64>,
    pub tracks: bool,
}

/// Which clock the run uses, and why.
#[derive(Debug, Clone, Serialize)]
pub struct ClockCheck {
    /// `timestamp` or `wall`.
    pub clock: String,
    pub reason: String,
    pub points: Vec<ClockPoint>,
}

/// One method's (or the floor's) row of bench.json.
#[derive(Debug, Clone, Serialize)]
pub struct MethodTiming {
    pub name: String,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
    pub samples: usize,
    /// The clock the median comes from (`timestamp` or `wall`).
    pub clock: String,
    pub wall_median_ms: f64,
    pub timestamp_median_ms: Option<f64>,
    /// Covered pixels, counted in the method's own image.
    pub covered_pixels: usize,
    /// Fragment-shader invocations from a pipeline-statistics query, and whether they equal
    /// the covered pixels (only then are they an exact per-fragment count; Mesa 22.3 counts
    /// whole pixel blocks). `None` without pipeline statistics.
    pub fragment_invocations: Option<u64>,
    pub invocations_exact: Option<bool>,
    pub ns_per_pixel: f64,
    /// Median minus the constant-colour floor's median (same run).
    pub above_floor_ms: f64,
    pub ratio_to_phong_exact: f64,
    /// (median - floor) / (phong_exact - floor).
    pub ratio_above_floor_to_phong_exact: f64,
    /// Static scalar operation counts of the fragment shader, and their excess over
    /// `phong_unnormalized` (the cost of the normalization itself).
    pub static_ops: Option<OpCounts>,
    pub static_ops_above_unnormalized: Option<OpCountsDelta>,
    /// The error metrics of `compare` (null for the floor).
    pub error: Option<MethodReport>,
}

/// A claim of the seeds, measured.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimCheck {
    pub method: String,
    pub claim: String,
    pub measured: String,
    /// `agrees`, `disagrees`, `partly`, `not_applicable` or `not_checked`.
    pub verdict: String,
    pub reason: String,
}

/// One point of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    pub program: String,
    /// Pixels (size sweep) or triangles (triangle sweep).
    pub work: f64,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub covered_pixels: usize,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
}

/// A sweep and its fitted slopes.
#[derive(Debug, Clone, Serialize)]
pub struct SweepResult {
    pub sweep: Sweep,
    /// "covered pixels" or "triangles".
    pub work: String,
    pub points: Vec<SweepPoint>,
    /// Per program: least-squares slope of median_ms against work (ms per million units) and
    /// the log-log slope (1 = linear scaling).
    pub slopes: Vec<(String, f64, f64)>,
}

/// DIR/bench.json.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub schema_version: u32,
    pub provenance: Provenance,
    pub cpu_model: String,
    pub lp_num_threads: Option<String>,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub repeat: usize,
    pub warmup: usize,
    pub clock: ClockCheck,
    pub error_metric: String,
    pub floor: MethodTiming,
    pub methods: Vec<MethodTiming>,
    /// Names of the non-dominated methods (time, error).
    pub pareto_front: Vec<String>,
    pub claims: Vec<ClaimCheck>,
    pub sweeps: Vec<SweepResult>,
    pub total_s: f64,
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Times `draws` round-robin: `warmup` discarded submissions each, then `repeat` rounds, each
/// round visiting every draw once in an order rotated by one per round, so drift of a shared
/// machine hits every draw alike. Returns the samples per draw.
fn interleaved(
    draws: &TimedDraws,
    warmup: usize,
    repeat: usize,
) -> Result<Vec<Vec<crate::render::Sample>>> {
    let n = draws.len();
    for i in 0..n {
        for _ in 0..warmup {
            draws.run(i)?;
        }
    }
    let mut out = vec![Vec::with_capacity(repeat); n];
    for round in 0..repeat {
        for k in 0..n {
            let i = (k + round) % n;
            out[i].push(draws.run(i)?);
        }
    }
    Ok(out)
}

fn estimate(samples: &[crate::render::Sample], clock: &str) -> (Estimate, f64, Option<f64>) {
    let wall: Vec<f64> = samples.iter().map(|s| s.wall_ms).collect();
    let ts: Vec<f64> = samples.iter().filter_map(|s| s.timestamp_ms).collect();
    let w = median_ci(&wall);
    let t = (!ts.is_empty()).then(|| median_ci(&ts));
    let chosen = if clock == "timestamp" {
        t.unwrap_or(w)
    } else {
        w
    };
    (chosen, w.median, t.map(|t| t.median))
}

/// Checks the timestamp placement against the wall clock at every size of [`SIZES`].
pub fn check_clock(renderer: &Renderer, scene: &Scene) -> Result<ClockCheck> {
    let exact = methods::find("phong_exact")?;
    let max = renderer.context().info().max_image_dimension_2d;
    let mut points = Vec::new();
    for &size in SIZES.iter().filter(|&&s| s <= max) {
        let mut s = scene.clone();
        s.width = size;
        s.height = size;
        let prepared = renderer.prepare(&s, &[exact])?;
        let draws = renderer.timed_draws(prepared.base(), &[Shading::Method(exact)])?;
        let samples = interleaved(&draws, 2, 7)?;
        let wall = median_ci(&samples[0].iter().map(|s| s.wall_ms).collect::<Vec<_>>()).median;
        let ts: Vec<f64> = samples[0].iter().filter_map(|s| s.timestamp_ms).collect();
        let tsm = (!ts.is_empty()).then(|| median_ci(&ts).median);
        let tracks = tsm.is_some_and(|t| {
            (t - wall).abs() <= (CLOCK_TOLERANCE * wall).max(CLOCK_SLACK_MS) && t > 0.0
        });
        points.push(ClockPoint {
            width: size,
            height: size,
            wall_median_ms: wall,
            timestamp_median_ms: tsm,
            tracks,
        });
    }
    let bad: Vec<String> = points
        .iter()
        .filter(|p| !p.tracks)
        .map(|p| {
            format!(
                "{}x{}: timestamps {} vs wall {:.2} ms",
                p.width,
                p.height,
                p.timestamp_median_ms
                    .map(|t| format!("{t:.2} ms"))
                    .unwrap_or_else(|| "none".into()),
                p.wall_median_ms
            )
        })
        .collect();
    Ok(if bad.is_empty() {
        ClockCheck {
            clock: "timestamp".into(),
            reason: format!(
                "the timestamp interval tracks the submit-to-fence wall clock at every size (within {:.0} % or {CLOCK_SLACK_MS} ms)",
                CLOCK_TOLERANCE * 100.0
            ),
            points,
        }
    } else {
        ClockCheck {
            clock: "wall".into(),
            reason: format!("timestamps do not track the wall clock on this driver ({}); timing with the wall clock", bad.join("; ")),
            points,
        }
    })
}

fn static_ops(m: &Method, interp: crate::scene::Interpolation) -> Option<OpCounts> {
    let bytes =
        crate::shaders::embedded(&crate::shaders::program_name(m.name, interp), "frag").ok()?;
    spirv::count_ops(bytes).ok()
}

/// Runs the bench and writes DIR/bench.json, bench.csv, pareto.svg/png, claims.json/md (and
/// sweep files).
pub fn bench(
    renderer: &Renderer,
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    opts: &BenchOptions,
) -> Result<BenchReport> {
    let start = std::time::Instant::now();
    if !compare::METRICS.contains(&opts.error_metric.as_str()) {
        return Err(Error::Usage(format!(
            "--error-metric: unknown metric {:?}; valid metrics: {}",
            opts.error_metric,
            compare::METRICS.join(", ")
        )));
    }
    if opts.repeat == 0 {
        return Err(Error::Usage("--repeat must be at least 1".into()));
    }
    let exact = methods::find("phong_exact")?;
    let unnormalized = methods::find("phong_unnormalized")?;
    let mut all = methods_.to_vec();
    for m in [exact, unnormalized] {
        if !all.iter().any(|x| x.name == m.name) {
            all.push(m);
        }
    }
    eprintln!("bench: checking the clock at sizes {SIZES:?}");
    let clock = check_clock(renderer, scene)?;
    eprintln!("bench: clock = {} ({})", clock.clock, clock.reason);

    let prepared = renderer.prepare(scene, &all)?;
    // Shadings: the floor, the methods (and the control), each drawing its own geometry.
    let mut shadings: Vec<Shading> = vec![Shading::Constant];
    shadings.extend(all.iter().map(|m| Shading::Method(m)));
    if opts.control {
        shadings.push(Shading::Control(exact));
    }
    let samples = time_shadings(renderer, &prepared, &shadings, opts)?;

    eprintln!("bench: error metrics (compare, without images)");
    let copts = CompareOptions {
        images: false,
        ..CompareOptions::default()
    };
    let summary = compare::compare(renderer, scene, &all, out, &copts)?;

    // Coverage from each image itself.
    let mut rows = Vec::new();
    for (s, smp) in shadings.iter().zip(&samples) {
        let gpu = match s.method() {
            Some(m) => prepared.for_method(m),
            None => prepared.base(),
        };
        let (frame, _) = renderer.render(gpu, *s, false)?;
        let (e, wall, ts) = estimate(smp, &clock.clock);
        let covered = frame.covered();
        let invocations = smp.iter().filter_map(|x| x.fragment_invocations).max();
        let error = s
            .method()
            .and_then(|m| summary.methods.iter().find(|r| r.name == m.name).cloned());
        let ops = s
            .method()
            .and_then(|m| static_ops(m, scene.interpolation))
            .or_else(|| {
                crate::shaders::embedded(
                    &crate::shaders::program_name("constant", scene.interpolation),
                    "frag",
                )
                .ok()
                .and_then(|b| spirv::count_ops(b).ok())
            });
        rows.push(MethodTiming {
            name: s.name(),
            median_ms: e.median,
            ci95_low_ms: e.ci95_low,
            ci95_high_ms: e.ci95_high,
            samples: e.samples,
            clock: clock.clock.clone(),
            wall_median_ms: wall,
            timestamp_median_ms: ts,
            covered_pixels: covered,
            fragment_invocations: invocations,
            invocations_exact: invocations.map(|n| n as usize == covered),
            ns_per_pixel: e.median * 1e6 / covered.max(1) as f64,
            above_floor_ms: 0.0,
            ratio_to_phong_exact: 0.0,
            ratio_above_floor_to_phong_exact: 0.0,
            static_ops: ops,
            static_ops_above_unnormalized: None,
            error,
        });
    }
    let floor = rows.remove(0);
    let phong = rows
        .iter()
        .find(|r| r.name == "phong_exact")
        .map(|r| r.median_ms)
        .unwrap_or(f64::NAN);
    let base_ops = rows
        .iter()
        .find(|r| r.name == "phong_unnormalized")
        .and_then(|r| r.static_ops);
    for r in &mut rows {
        r.above_floor_ms = r.median_ms - floor.median_ms;
        r.ratio_to_phong_exact = r.median_ms / phong;
        r.ratio_above_floor_to_phong_exact =
            (r.median_ms - floor.median_ms) / (phong - floor.median_ms);
        r.static_ops_above_unnormalized = match (r.static_ops, base_ops) {
            (Some(a), Some(b)) => Some(a.minus(&b)),
            _ => None,
        };
    }
    // Only the methods the user asked for (phong_exact / unnormalized are always timed, as
    // the ratios' references, and kept).
    let metric = |r: &MethodTiming| r.error.as_ref().and_then(|e| e.metric(&opts.error_metric));
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.median_ms, metric(r).unwrap_or(f64::NAN)))
        .collect();
    let front: Vec<String> = pareto_front(&points)
        .into_iter()
        .map(|i| rows[i].name.clone())
        .collect();
    let claims = claims(&rows, &floor);

    let mut sweeps = Vec::new();
    for &sw in &opts.sweeps {
        eprintln!("bench: sweep {sw:?}");
        sweeps.push(sweep(renderer, scene, sw, opts)?);
    }
    let report = BenchReport {
        schema_version: SCHEMA_VERSION,
        provenance: Provenance::new(renderer.context().info()),
        cpu_model: cpu_model(),
        lp_num_threads: std::env::var("LP_NUM_THREADS").ok(),
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: prepared.base().inputs.triangle_count(),
        repeat: opts.repeat,
        warmup: opts.warmup,
        clock,
        error_metric: opts.error_metric.clone(),
        floor,
        methods: rows,
        pareto_front: front,
        claims,
        sweeps,
        total_s: start.elapsed().as_secs_f64(),
    };
    write(out, &report)?;
    Ok(report)
}

fn time_shadings(
    renderer: &Renderer,
    prepared: &Prepared,
    shadings: &[Shading],
    opts: &BenchOptions,
) -> Result<Vec<Vec<crate::render::Sample>>> {
    // Draws of different geometries need their own targets; group them, time each group.
    let mut out = vec![Vec::new(); shadings.len()];
    let mut groups: Vec<(crate::methods::Geometry, Vec<usize>)> = Vec::new();
    for (i, s) in shadings.iter().enumerate() {
        let g = s
            .method()
            .map(|m| m.geometry)
            .unwrap_or(crate::methods::Geometry::Mesh);
        match groups.iter_mut().find(|(k, _)| *k == g) {
            Some((_, v)) => v.push(i),
            None => groups.push((g, vec![i])),
        }
    }
    for (_, idx) in groups {
        let first = shadings[idx[0]];
        let gpu = match first.method() {
            Some(m) => prepared.for_method(m),
            None => prepared.base(),
        };
        let group: Vec<Shading> = idx.iter().map(|&i| shadings[i]).collect();
        eprintln!(
            "bench: timing {} programs x {} repetitions ({} warm-up)",
            group.len(),
            opts.repeat,
            opts.warmup
        );
        let draws = renderer.timed_draws(gpu, &group)?;
        for (k, s) in interleaved(&draws, opts.warmup, opts.repeat)?
            .into_iter()
            .enumerate()
        {
            out[idx[k]] = s;
        }
    }
    Ok(out)
}

fn ratio_text(r: &MethodTiming, phong: &MethodTiming) -> String {
    format!(
        "{:.3} ms [{:.3}, {:.3}] vs phong_exact {:.3} ms [{:.3}, {:.3}] (ratio {:.3})",
        r.median_ms,
        r.ci95_low_ms,
        r.ci95_high_ms,
        phong.median_ms,
        phong.ci95_low_ms,
        phong.ci95_high_ms,
        r.ratio_to_phong_exact
    )
}

/// The seeds' claims that this milestone's methods can test, measured in this run where they
/// are timing or GPU-error claims, and as the method table records otherwise.
fn claims(rows: &[MethodTiming], floor: &MethodTiming) -> Vec<ClaimCheck> {
    let mut out = Vec::new();
    let find = |n: &str| rows.iter().find(|r| r.name == n);
    let Some(phong) = find("phong_exact") else {
        return out;
    };
    if let Some(g) = find("gouraud") {
        let ratio = phong.median_ms / g.median_ms;
        let g_above = g.median_ms - floor.median_ms;
        let above = if g_above > 0.0 {
            format!(
                "{:.2}x above the constant-colour floor",
                (phong.median_ms - floor.median_ms) / g_above
            )
        } else {
            format!("Gouraud is at or below the constant-colour floor ({g_above:+.3} ms), so its cost above the floor is nil")
        };
        out.push(ClaimCheck {
            method: "gouraud".into(),
            claim: "Phong shading of an average triangle takes more than 50x longer than Gouraud (S002 l.151-153)".into(),
            measured: format!("phong_exact / gouraud = {ratio:.2}x per frame; {above}"),
            verdict: if ratio > 50.0 { "agrees" } else { "disagrees" }.into(),
            reason: "on a GPU-style pipeline both shade every covered pixel in the same fragment stage; Gouraud only moves the lighting to the vertices, and rasterization, interpolation and the framebuffer dominate".into(),
        });
    }
    for n in [
        "newton_raphson",
        "lyon_taylor",
        "lyon_shift",
        "hast_half_vector",
        "mikami_const",
        "mikami_linear",
        "mikami_quadratic",
        "romanyuk_poly",
        "quaternion",
        "quaternion_local",
    ] {
        let Some(r) = find(n) else { continue };
        let faster = r.ci95_high_ms < phong.ci95_low_ms;
        let slower = r.ci95_low_ms > phong.ci95_high_ms;
        out.push(ClaimCheck {
            method: n.into(),
            claim: "normalization without a square root is faster than exact normalization (S000, S004 l.159-172)".into(),
            measured: ratio_text(r, phong),
            verdict: if faster { "agrees" } else { "disagrees" }.into(),
            reason: if faster {
                "faster beyond both 95% intervals".into()
            } else if slower {
                "slower beyond both 95% intervals: lavapipe's inverse square root is a single vector instruction, the approximation costs more arithmetic".into()
            } else {
                "the 95% intervals overlap: no measurable difference; lavapipe computes inversesqrt with one vector instruction, so there is little to save".into()
            },
        });
    }
    if let (Some(d), Some(ops)) = (phong.static_ops_above_unnormalized, phong.static_ops) {
        let _ = ops;
        out.push(ClaimCheck {
            method: "phong_exact".into(),
            claim: "normalisation costs 3 divisions + 3 multiplications + 2 additions + 1 square root (S004 l.159-163)".into(),
            measured: format!(
                "SPIR-V of phong_exact minus phong_unnormalized: {} div, {} sqrt, {} inverse sqrt, {} mul, {} add",
                d.div, d.sqrt, d.inverse_sqrt, d.mul, d.add
            ),
            verdict: "partly".into(),
            reason: "the same dot product (3 mul + 2 add), but the compiler normalizes with one inverse square root and multiplications instead of a square root and three divisions".into(),
        });
    }
    for n in ["mikami_const", "mikami_linear", "mikami_quadratic"] {
        if let Some(e) = find(n)
            .and_then(|r| r.error.as_ref())
            .and_then(|e| e.max_normal_length_error)
        {
            out.push(ClaimCheck {
                method: n.into(),
                claim: "maximum normalised relative error <= 1.5 % (S000 l.74)".into(),
                measured: format!("max ||N'| - 1| on this scene's pixels: {:.3} %", e * 100.0),
                verdict: if e <= 0.015 { "agrees" } else { "disagrees" }.into(),
                reason: "measured on the GPU in this run (the f64 sweep over z in [0.25, 1] is in the method table)".into(),
            });
        }
    }
    // The method table's claims (measured by the formulas tests), for completeness.
    for m in crate::methods::METHODS {
        for c in m.claims {
            if c.verdict == "not_checked" {
                continue;
            }
            out.push(ClaimCheck {
                method: m.name.into(),
                claim: c.claim.into(),
                measured: c.measured.into(),
                verdict: c.verdict.into(),
                reason: "f64 check of the formula (src/formulas.rs tests)".into(),
            });
        }
    }
    for (claim, who) in [
        (
            "spherical-angular interpolation doubles polygon shading speed (S000 l.102-104)",
            "spherical_angular",
        ),
        (
            "quadratic interpolation reduces normal computation time 2-3x (S000 l.151-152)",
            "quadratic_scanline",
        ),
        (
            "dichotomy with the approximated inverse root: 2.5x faster (S000 l.181)",
            "dichotomy",
        ),
        (
            "digital segments k = 2: 1.3x / 1.8x; k = 3: 1.48x / 2.09x (S002 l.674-682)",
            "digital_segments",
        ),
        (
            "Bishop-Weimer: 5 additions and 1 memory access per pixel (S004 l.124-128)",
            "bishop_weimer",
        ),
    ] {
        out.push(ClaimCheck {
            method: who.into(),
            claim: claim.into(),
            measured: "-".into(),
            verdict: "not_checked".into(),
            reason: "the scanline family is not implemented yet (roadmap step 5)".into(),
        });
    }
    out
}

fn least_squares(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}

fn sweep(
    renderer: &Renderer,
    scene: &Scene,
    which: Sweep,
    opts: &BenchOptions,
) -> Result<SweepResult> {
    let exact = methods::find("phong_exact")?;
    let gouraud = methods::find("gouraud")?;
    let shadings = [
        Shading::Constant,
        Shading::Method(gouraud),
        Shading::Method(exact),
    ];
    let max = renderer.context().info().max_image_dimension_2d;
    let scenes: Vec<Scene> = match which {
        Sweep::Size => SIZES
            .iter()
            .filter(|&&s| s <= max)
            .map(|&s| {
                let mut c = scene.clone();
                c.width = s;
                c.height = s;
                c
            })
            .collect(),
        Sweep::Triangles => SPHERES
            .iter()
            .map(|&(segments, rings)| {
                let mut mesh = Generator::UvSphere { segments, rings }.build()?;
                crate::mesh::fit_unit(&mut mesh);
                let mut c = scene.clone();
                c.mesh = mesh;
                Ok(c)
            })
            .collect::<Result<_>>()?,
    };
    let mut points = Vec::new();
    let reps = opts.repeat.clamp(5, 15);
    for s in &scenes {
        let prepared = renderer.prepare(s, &[gouraud, exact])?;
        let draws = renderer.timed_draws(prepared.base(), &shadings)?;
        let samples = interleaved(&draws, opts.warmup.max(1), reps)?;
        for (sh, smp) in shadings.iter().zip(&samples) {
            let (frame, _) = renderer.render(prepared.base(), *sh, false)?;
            let wall: Vec<f64> = smp.iter().map(|x| x.wall_ms).collect();
            let e = median_ci(&wall);
            let tris = prepared.base().inputs.triangle_count();
            points.push(SweepPoint {
                program: sh.name(),
                work: match which {
                    Sweep::Size => frame.covered() as f64,
                    Sweep::Triangles => tris as f64,
                },
                width: s.width,
                height: s.height,
                triangles: tris,
                covered_pixels: frame.covered(),
                median_ms: e.median,
                ci95_low_ms: e.ci95_low,
                ci95_high_ms: e.ci95_high,
            });
        }
        eprintln!(
            "bench: sweep point {}x{}, {} triangles",
            s.width,
            s.height,
            prepared.base().inputs.triangle_count()
        );
    }
    let mut slopes = Vec::new();
    for sh in &shadings {
        let name = sh.name();
        let pts: Vec<&SweepPoint> = points.iter().filter(|p| p.program == name).collect();
        let xs: Vec<f64> = pts.iter().map(|p| p.work / 1e6).collect();
        let ys: Vec<f64> = pts.iter().map(|p| p.median_ms).collect();
        let lx: Vec<f64> = pts.iter().map(|p| p.work.max(1.0).ln()).collect();
        let ly: Vec<f64> = pts.iter().map(|p| p.median_ms.max(1e-9).ln()).collect();
        slopes.push((name, least_squares(&xs, &ys), least_squares(&lx, &ly)));
    }
    Ok(SweepResult {
        sweep: which,
        work: match which {
            Sweep::Size => "covered pixels".into(),
            Sweep::Triangles => "triangles".into(),
        },
        points,
        slopes,
    })
}

/// Writes every output of a bench run.
pub fn write(out: &Path, r: &BenchReport) -> Result<()> {
    let json = serde_json::to_string_pretty(r).map_err(|e| Error::Usage(e.to_string()))? + "\n";
    output::write_bytes_atomic(&out.join("bench.json"), json.as_bytes())?;
    output::write_atomic(&out.join("bench.csv"), |w| {
        let mut c = csv::Writer::from_writer(w);
        let mut header: Vec<String> = [
            "name",
            "median_ms",
            "ci95_low_ms",
            "ci95_high_ms",
            "samples",
            "clock",
            "wall_median_ms",
            "timestamp_median_ms",
            "covered_pixels",
            "ns_per_pixel",
            "above_floor_ms",
            "ratio_to_phong_exact",
            "ratio_above_floor_to_phong_exact",
            "ops_div",
            "ops_sqrt",
            "ops_inverse_sqrt",
            "ops_mul",
            "ops_add",
            "ops_pow",
        ]
        .map(String::from)
        .to_vec();
        header.extend(compare::METRICS.iter().map(|m| m.to_string()));
        c.write_record(&header).map_err(std::io::Error::other)?;
        for m in std::iter::once(&r.floor).chain(&r.methods) {
            let o = |v: Option<f64>| v.map(|x| format!("{x:e}")).unwrap_or_default();
            let ops = m.static_ops;
            let mut row = vec![
                m.name.clone(),
                format!("{:e}", m.median_ms),
                format!("{:e}", m.ci95_low_ms),
                format!("{:e}", m.ci95_high_ms),
                m.samples.to_string(),
                m.clock.clone(),
                format!("{:e}", m.wall_median_ms),
                o(m.timestamp_median_ms),
                m.covered_pixels.to_string(),
                format!("{:e}", m.ns_per_pixel),
                format!("{:e}", m.above_floor_ms),
                format!("{:e}", m.ratio_to_phong_exact),
                format!("{:e}", m.ratio_above_floor_to_phong_exact),
            ];
            for f in [
                |o: &OpCounts| o.div,
                |o: &OpCounts| o.sqrt,
                |o: &OpCounts| o.inverse_sqrt,
                |o: &OpCounts| o.mul,
                |o: &OpCounts| o.add,
                |o: &OpCounts| o.pow,
            ] {
                row.push(ops.map(|x| f(&x).to_string()).unwrap_or_default());
            }
            for k in compare::METRICS {
                row.push(o(m.error.as_ref().and_then(|e| e.metric(k))));
            }
            c.write_record(&row).map_err(std::io::Error::other)?;
        }
        c.flush()
    })?;
    let claims =
        serde_json::to_string_pretty(&r.claims).map_err(|e| Error::Usage(e.to_string()))? + "\n";
    output::write_bytes_atomic(&out.join("claims.json"), claims.as_bytes())?;
    let mut md = String::from("# The seeds' claims, measured\n\n");
    md += &format!(
        "{} at {}x{} on {} ({}), clock: {}. Written by `shadelab bench`.\n\n| method | claim | measured | verdict | why |\n|---|---|---|---|---|\n",
        r.scene, r.width, r.height, r.provenance.device, r.provenance.driver_info, r.clock.clock
    );
    for c in &r.claims {
        md += &format!(
            "| {} | {} | {} | {} | {} |\n",
            c.method, c.claim, c.measured, c.verdict, c.reason
        );
    }
    output::write_bytes_atomic(&out.join("claims.md"), md.as_bytes())?;
    crate::chart::pareto(out, r)?;
    for s in &r.sweeps {
        crate::chart::sweep(out, s)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_ci_matches_the_order_statistics_table() {
        // n = 100: the 95% interval of the median is [x(40), x(61)] (binomial table)
        let v: Vec<f64> = (1..=100).map(|x| x as f64).collect();
        let e = median_ci(&v);
        assert_eq!(
            (e.median, e.ci95_low, e.ci95_high, e.samples),
            (50.5, 40.0, 61.0, 100)
        );
        // n = 10: [x(2), x(9)]
        let v: Vec<f64> = (1..=10).map(|x| x as f64).collect();
        let e = median_ci(&v);
        assert_eq!((e.median, e.ci95_low, e.ci95_high), (5.5, 2.0, 9.0));
        // n = 5: no 95% rank exists -> [min, max]
        let e = median_ci(&[3.0, 1.0, 2.0, 5.0, 4.0]);
        assert_eq!((e.median, e.ci95_low, e.ci95_high), (3.0, 1.0, 5.0));
        // order does not matter, NaN ignored
        let e = median_ci(&[2.0, f64::NAN, 1.0, 3.0]);
        assert_eq!((e.median, e.samples), (2.0, 3));
    }

    #[test]
    fn binomial_cdf_is_exact_for_small_n() {
        assert!((binomial_half_cdf(4, 0) - 1.0 / 16.0).abs() < 1e-15);
        assert!((binomial_half_cdf(4, 1) - 5.0 / 16.0).abs() < 1e-15);
        assert!((binomial_half_cdf(4, 4) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn pareto_front_keeps_only_non_dominated_points() {
        let pts = [
            (1.0, 5.0),
            (2.0, 3.0),
            (3.0, 4.0),
            (4.0, 1.0),
            (2.0, 3.0),
            (0.5, f64::NAN),
        ];
        // (3, 4) is dominated by (2, 3); the two (2, 3) tie and both stay; NaN is never on it
        assert_eq!(pareto_front(&pts), vec![0, 1, 3, 4]);
        assert!(pareto_front(&[]).is_empty());
    }

    #[test]
    fn least_squares_slope() {
        assert!((least_squares(&[1.0, 2.0, 3.0], &[3.0, 5.0, 7.0]) - 2.0).abs() < 1e-12);
        assert!(least_squares(&[1.0, 1.0], &[1.0, 2.0]).is_nan());
    }
}
