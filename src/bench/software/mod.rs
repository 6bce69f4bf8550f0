//! `shadelab bench --engine software`: the frame time of [`software::render_into`] for every
//! selected method and phong_exact, in the interleaved rounds of [`super::rounds`] (a balanced
//! order), each method's paired per-round ratio to phong_exact with the sign-test 95%
//! interval ([`paired_ratio`]), and the seeds' speed claims judged by those intervals
//! (claims.md / claims.json), beside the verdict of a Vulkan bench.json when one is given
//! (`--vulkan-bench`).
//!
//! Clock: the wall time of one `software::render_into` call, from set-up to finished images,
//! into one kept set of colour and depth images (cleared by each draw, band by band; no normal
//! target, as in the Vulkan bench's timed draws). The software engine has no constant-colour floor program, no
//! isolated-cost kernel, no control, no baseline, no sweeps and one run: those stay with the
//! Vulkan bench, and [`SoftwareOptions`] cannot ask for them.
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use super::rounds::{ratios, round_values, run_rounds, widest, Draws};
use super::{RoundsReport, RoundsSchedule, RATIO_INTERVAL};
use crate::analysis::stats::{median_ci, paired_ratio, RatioEstimate};
use crate::engine::Engine;
use crate::error::{Error, Result};
use crate::gpu::{Clock, Sample};
use crate::method::{self, Method};
use crate::output;
use crate::output::provenance::{cpu_model, Provenance};
use crate::scene::{Scene, SceneInputs};
use crate::software;

pub mod cost;
pub mod speed;
pub use speed::*;

/// Version of the software bench.json layout.
pub const SCHEMA_VERSION: u32 = 1;
/// The clock, as bench.json states it.
pub const CLOCK: &str = "wall: one software::render_into call, set-up to finished images \
     (kept colour and depth images, cleared inside it; no normal target)";

/// Options of the software bench (typed: what the Vulkan bench alone measures, sweeps,
/// baselines, the control, the floors, cannot be asked for).
#[derive(Debug, Clone)]
pub struct SoftwareOptions {
    /// The rounds, as the Vulkan bench runs them.
    pub rounds: RoundsSchedule,
    /// Threads of the software engine (at least 1).
    pub threads: usize,
    /// A Vulkan run's bench.json whose paired ratios are judged beside this run's.
    pub vulkan_bench: Option<PathBuf>,
    /// The command line, recorded in bench.json.
    pub command_line: Vec<String>,
}

/// The programs of a run: each method drawn by the software engine on its own geometry.
struct Renders<'a> {
    programs: Vec<(&'static Method, &'a SceneInputs)>,
    threads: usize,
    /// One set of images for every draw (all programs share the image size): colour and depth,
    /// no normal target (nobody reads it when timing, as in the Vulkan bench).
    targets: std::cell::RefCell<software::Targets>,
}

impl Draws for Renders<'_> {
    fn len(&self) -> usize {
        self.programs.len()
    }

    fn run(&self, i: usize) -> Result<Sample> {
        let (m, inputs) = self.programs[i];
        let mut targets = self.targets.borrow_mut();
        let t = Instant::now();
        software::render_into(inputs, m, self.threads, &mut targets)?;
        let wall_ms = t.elapsed().as_secs_f64() * 1e3;
        Ok(Sample {
            wall_ms,
            timestamp_ms: None,
        })
    }
}

/// The software renders, then (with `--vulkan-paired`) the same methods drawn by lavapipe:
/// programs `0..n` software, `n..2n` lavapipe, all in the same rounds.
struct Both<'a> {
    software: Renders<'a>,
    vulkan: Option<crate::gpu::TimedDraws>,
}

impl Draws for Both<'_> {
    fn len(&self) -> usize {
        self.software.len() + self.vulkan.as_ref().map_or(0, |v| v.len())
    }

    fn run(&self, i: usize) -> Result<Sample> {
        let n = self.software.len();
        match &self.vulkan {
            Some(v) if i >= n => v.run(i - n),
            _ => self.software.run(i),
        }
    }
}

/// One method's frame time and its paired ratio to phong_exact (the ratio fields are named as
/// in the Vulkan bench.json, so one reader serves both).
#[derive(Debug, Clone, Serialize)]
pub struct SoftwareTiming {
    pub name: String,
    /// Whether the method ran in its scanline (incremental) form ([`software::form`]).
    pub scanline_form: bool,
    pub form: &'static str,
    pub median_ms: f64,
    pub ci95_low_ms: f64,
    pub ci95_high_ms: f64,
    pub samples: usize,
    pub ratio_median: f64,
    pub ratio_ci95_low: f64,
    pub ratio_ci95_high: f64,
    pub ratio_rounds: usize,
    pub ratio_non_finite: usize,
    pub ratio_confidence: f64,
    /// The frame time of every round, in round order (pairs with every other program's).
    pub round_ms: Vec<f64>,
}

/// DIR/bench.json of `bench --engine software`.
#[derive(Debug, Clone, Serialize)]
pub struct SoftwareBench {
    pub schema_version: u32,
    pub engine: &'static str,
    pub provenance: Provenance,
    pub cpu_model: String,
    pub cpu_count: usize,
    pub threads: usize,
    pub command_line: Vec<String>,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub repeat: usize,
    pub warmup: usize,
    pub rounds: RoundsReport,
    pub ratio_interval: String,
    pub clock: &'static str,
    pub methods: Vec<SoftwareTiming>,
    /// The bench.json the Vulkan verdicts come from, if any.
    pub vulkan_bench: Option<String>,
    /// Whether lavapipe drew the same methods in the same rounds (`--vulkan-paired`): the
    /// Vulkan verdicts are then paired per round, the dichotomy ratio too.
    pub vulkan_paired: bool,
    /// With `vulkan_paired`: lavapipe's median frame time per method (wall clock).
    pub vulkan_median_ms: Vec<(String, f64)>,
    /// With `vulkan_paired`: software phong_exact over lavapipe phong_exact per round (the
    /// anchor of issue 13: within 2x when the interval's upper end is <= 2).
    pub software_to_lavapipe: Option<RatioEstimate>,
    pub claims: Vec<SpeedClaim>,
    pub total_s: f64,
}

/// Refused: a Vulkan column both timed in the same rounds and read from another run.
const BOTH_VULKAN_COLUMNS: &str = "--vulkan-paired times lavapipe in the same rounds; \
     --vulkan-bench reads another run: give one of them";

/// Runs the software bench and writes DIR/bench.json, claims.md and claims.json.
pub fn bench(
    scene: &Scene,
    methods_: &[&'static Method],
    out: &Path,
    sw: &SoftwareOptions,
    paired_vulkan: Option<&crate::gpu::Renderer>,
) -> Result<SoftwareBench> {
    let start = Instant::now();
    let schedule = &sw.rounds;
    schedule.check()?;
    if paired_vulkan.is_some() && sw.vulkan_bench.is_some() {
        return Err(Error::Usage(BOTH_VULKAN_COLUMNS.into()));
    }
    // Read the Vulkan figures first: a bad path must not cost a whole run.
    let file_vulkan = sw
        .vulkan_bench
        .as_deref()
        .map(VulkanRatios::load)
        .transpose()?;
    let threads = sw.threads.max(1);
    let exact = method::phong_exact();
    let mut all = methods_.to_vec();
    if !all.iter().any(|m| m.name == exact.name) {
        all.push(exact);
    }
    let inputs = inputs_of(scene, &all);
    let programs: Vec<(&'static Method, &SceneInputs)> = all
        .iter()
        .map(|&m| {
            let i = inputs.iter().find(|i| i.geometry == m.geometry);
            (m, i.unwrap_or(&inputs[0]))
        })
        .collect();
    let names: Vec<String> = all.iter().map(|m| m.name.to_string()).collect();
    let phong = names
        .iter()
        .position(|n| n == crate::method::PHONG_EXACT)
        .ok_or_else(|| Error::Internal("phong_exact is not among the programs".into()))?;
    let software = Renders {
        programs,
        threads,
        targets: std::cell::RefCell::new(software::Targets::new(
            scene.width,
            scene.height,
            false,
            false,
        )),
    };
    // lavapipe's draws of the same methods (colour and depth, as timed by `bench`).
    let (prepared, vulkan_draws) = match paired_vulkan {
        Some(r) => lavapipe_draws(r, scene, &all).map(|(p, d)| (Some(p), Some(d)))?,
        None => (None, None),
    };
    let n = names.len();
    let draws = Both {
        software,
        vulkan: vulkan_draws,
    };
    let (samples, rounds) = time(&draws, schedule, &names, phong, threads)?;
    let values = values_all(&samples[..n]);
    let vulkan = match &draws.vulkan {
        Some(_) => Some(VulkanRatios::paired(
            names.clone(),
            values_all(&samples[n..]),
            scene,
        )?),
        None => file_vulkan,
    };
    drop(prepared);
    // The anchor: software phong_exact over lavapipe's, per round.
    let software_to_lavapipe = vulkan
        .as_ref()
        .and_then(|v| v.same_rounds.as_ref())
        .map(|(_, vk)| paired_ratio(&values[phong], &vk[phong]));
    let to_phong: Vec<RatioEstimate> = values
        .iter()
        .map(|v| paired_ratio(v, &values[phong]))
        .collect();
    let methods = timings(&names, &values, &to_phong);
    let claims = judge_claims(&names, &values, vulkan.as_ref());
    let mut report = SoftwareBench {
        schema_version: SCHEMA_VERSION,
        engine: "software",
        provenance: Engine::Software { threads }.provenance(),
        cpu_model: cpu_model(),
        cpu_count: software::default_threads(),
        threads,
        command_line: sw.command_line.clone(),
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        triangles: inputs[0].triangle_count(),
        repeat: schedule.repeat,
        warmup: schedule.warmup,
        rounds,
        ratio_interval: RATIO_INTERVAL.into(),
        clock: CLOCK,
        methods,
        vulkan_bench: vulkan
            .as_ref()
            .filter(|v| v.same_rounds.is_none())
            .map(|v| v.path.clone()),
        vulkan_paired: software_to_lavapipe.is_some(),
        vulkan_median_ms: vulkan
            .as_ref()
            .map(VulkanRatios::medians)
            .unwrap_or_default(),
        software_to_lavapipe,
        claims,
        total_s: 0.0,
    };
    report.total_s = start.elapsed().as_secs_f64();
    write_files(out, &report, vulkan.as_ref())?;
    Ok(report)
}

/// The software renders (and lavapipe's, after them) in the same interleaved rounds; the
/// widest interval is of the software programs' ratios.
fn time(
    draws: &Both,
    schedule: &RoundsSchedule,
    names: &[String],
    phong: usize,
    threads: usize,
) -> Result<(Vec<Vec<Sample>>, RoundsReport)> {
    let n = names.len();
    log::info!(
        "bench --engine software: {} programs on {threads} threads in the same interleaved \
         rounds: {}",
        draws.len(),
        schedule.describe()
    );
    // Every program is its own "floor": the floor ratios are 1 and never the widest.
    let own: Vec<usize> = (0..n).collect();
    run_rounds(draws, schedule, "bench --engine software", |samples| {
        let (p, f) = ratios(&values_all(&samples[..n]), phong, &own);
        widest(names, &p, &f)
    })
}

/// Every program's per-round wall times.
fn values_all(samples: &[Vec<Sample>]) -> Vec<Vec<f64>> {
    samples
        .iter()
        .map(|s| round_values(s, Clock::Wall))
        .collect()
}

/// The scene's inputs, one per geometry of `all`.
fn inputs_of(scene: &Scene, all: &[&'static Method]) -> Vec<SceneInputs> {
    let mut inputs: Vec<SceneInputs> = Vec::new();
    for m in all {
        if !inputs.iter().any(|i| i.geometry == m.geometry) {
            inputs.push(SceneInputs::new(scene, m.geometry));
        }
    }
    inputs
}

/// lavapipe's timed draws of `all` (`--vulkan-paired`), with the prepared scene they draw.
fn lavapipe_draws(
    r: &crate::gpu::Renderer,
    scene: &Scene,
    all: &[&'static Method],
) -> Result<(crate::gpu::Prepared, crate::gpu::TimedDraws)> {
    let prepared = r.prepare(scene, all)?;
    let list: Vec<(&crate::gpu::GpuScene, crate::gpu::Shading)> = all
        .iter()
        .map(|&m| (prepared.for_method(m), crate::gpu::Shading::Method(m)))
        .collect();
    let draws = r.timed_draws(&list)?;
    Ok((prepared, draws))
}

/// Every method's row: its frame times and its paired ratio to phong_exact.
fn timings(
    names: &[String],
    values: &[Vec<f64>],
    to_phong: &[RatioEstimate],
) -> Vec<SoftwareTiming> {
    names
        .iter()
        .zip(values)
        .zip(to_phong)
        .map(|((name, v), r)| {
            let e = median_ci(v);
            let form = software::form(name);
            SoftwareTiming {
                name: name.clone(),
                scanline_form: form.scanline,
                form: form.form,
                median_ms: e.median,
                ci95_low_ms: e.ci95_low,
                ci95_high_ms: e.ci95_high,
                samples: e.samples,
                ratio_median: r.median,
                ratio_ci95_low: r.ci95_low,
                ratio_ci95_high: r.ci95_high,
                ratio_rounds: r.rounds,
                ratio_non_finite: r.non_finite,
                ratio_confidence: r.confidence,
                round_ms: v.clone(),
            }
        })
        .collect()
}

/// DIR/claims.json, claims.md and, last (the run's completion marker), bench.json.
fn write_files(out: &Path, report: &SoftwareBench, vulkan: Option<&VulkanRatios>) -> Result<()> {
    let json = serde_json::to_string_pretty(&report.claims)
        .map_err(|e| Error::output("claims.json", e))?
        + "\n";
    output::write_bytes_atomic(&out.join("claims.json"), json.as_bytes())?;
    let md = claims_md(report, vulkan);
    output::write_bytes_atomic(&out.join("claims.md"), md.as_bytes())?;
    let json =
        serde_json::to_string_pretty(report).map_err(|e| Error::output("bench.json", e))? + "\n";
    output::write_bytes_atomic(&out.join("bench.json"), json.as_bytes())
}

/// The text table of a run: every program's frame time and paired ratio to phong_exact.
pub fn table(r: &SoftwareBench) -> String {
    let mut t = format!(
        "scene {} at {}x{}, {} triangles; software engine on {} threads; clock: wall; {} rounds ({}); widest paired ratio interval +-{:.2} % ({})\n",
        r.scene,
        r.width,
        r.height,
        r.triangles,
        r.threads,
        r.rounds.rounds,
        r.rounds.stopped.as_str(),
        r.rounds.widest_half_width_pct,
        r.rounds.widest
    );
    t += &format!(
        "{:<32} {:>9} {:>19} {:>30} {:>9}\n",
        "method", "median ms", "95% CI ms", "/ phong_exact (paired)", "form"
    );
    let mut rows: Vec<&SoftwareTiming> = r.methods.iter().collect();
    rows.sort_by(|a, b| a.median_ms.total_cmp(&b.median_ms));
    for m in rows {
        t += &format!(
            "{:<32} {:>9.3} {:>19} {:>30} {:>9}\n",
            m.name,
            m.median_ms,
            format!("[{:.3}, {:.3}]", m.ci95_low_ms, m.ci95_high_ms),
            format!(
                "{:.4} [{:.4}, {:.4}]{}",
                m.ratio_median,
                m.ratio_ci95_low,
                m.ratio_ci95_high,
                if m.ratio_non_finite > 0 {
                    format!(" ({} non-finite)", m.ratio_non_finite)
                } else {
                    String::new()
                }
            ),
            if m.scanline_form {
                "scanline"
            } else {
                "per-pixel"
            }
        );
    }
    for c in &r.claims {
        let (s, sv) = cell(&c.software);
        let vk = c
            .vulkan
            .as_ref()
            .map(|v| format!("; Vulkan: {}", v.verdict.as_str()))
            .unwrap_or_default();
        t += &format!(
            "claim {} / {} < {:.4}: {s}: {sv}{vk}\n",
            c.num, c.den, c.claimed_below
        );
    }
    if let Some(a) = &r.software_to_lavapipe {
        let vk = r
            .vulkan_median_ms
            .iter()
            .find(|(n, _)| n == crate::method::PHONG_EXACT)
            .map_or(f64::NAN, |(_, ms)| *ms);
        t += &format!(
            "software / lavapipe phong_exact per round (same rounds; lavapipe median {vk:.3} ms): \
             {:.3} [{:.3}, {:.3}]; {}\n",
            a.median,
            a.ci95_low,
            a.ci95_high,
            within_2x(a)
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Verdict;

    fn est(lo: f64, mid: f64, hi: f64) -> RatioEstimate {
        RatioEstimate {
            median: mid,
            ci95_low: lo,
            ci95_high: hi,
            rounds: 21,
            non_finite: 0,
            confidence: 0.97,
        }
    }

    #[test]
    fn a_verdict_follows_the_interval_and_flips_with_it() {
        // spherical_angular "doubles the speed": ratio below 0.5
        assert_eq!(judge(&est(0.30, 0.35, 0.40), 0.5), Verdict::Agrees);
        // a tampered (too slow) ratio flips it
        assert_eq!(judge(&est(0.60, 0.65, 0.70), 0.5), Verdict::Disagrees);
        // an interval holding the claimed value decides nothing
        assert_eq!(judge(&est(0.45, 0.50, 0.55), 0.5), Verdict::Inconclusive);
        // no finite round, or a non-finite end, is never an agreement
        let mut none = est(0.1, 0.1, 0.1);
        none.rounds = 0;
        assert_eq!(judge(&none, 0.5), Verdict::Inconclusive);
        assert_eq!(judge(&est(f64::NAN, 0.3, 0.4), 0.5), Verdict::Inconclusive);
    }

    #[test]
    fn claims_are_judged_from_per_round_values_and_count_non_finite_rounds() {
        let names: Vec<String> = [crate::method::PHONG_EXACT, "gouraud", "spherical_angular"]
            .map(String::from)
            .to_vec();
        let phong = vec![10.0; 21];
        let fast = vec![4.0; 21]; // 0.4 of phong_exact: doubles the speed
        let mut slow = vec![9.0; 21]; // 0.9: does not
        slow[3] = f64::NAN;
        let of = |c: &[SpeedClaim], num: &str| {
            c.iter()
                .find(|c| c.num == num)
                .and_then(|c| c.software.clone())
                .unwrap()
        };
        let good = judge_claims(&names, &[phong.clone(), slow.clone(), fast.clone()], None);
        assert_eq!(of(&good, "spherical_angular").verdict, Verdict::Agrees);
        // gouraud at 0.9 of Phong is far from 1/50
        let g = of(&good, "gouraud");
        assert_eq!(g.verdict, Verdict::Disagrees);
        assert_eq!((g.rounds, g.non_finite), (20, 1));
        // swapped inputs: the verdict flips
        let bad = judge_claims(&names, &[phong, fast, slow], None);
        assert_eq!(of(&bad, "spherical_angular").verdict, Verdict::Disagrees);
        // a claim whose programs were not run is not judged
        assert!(good
            .iter()
            .any(|c| c.num == "dichotomy_poly1" && c.software.is_none()));
    }

    fn bench_json(engine: Option<&str>) -> serde_json::Value {
        let row = |name: &str, lo: f64, mid: f64, hi: f64| {
            serde_json::json!({"name": name, "ratio_median": mid, "ratio_ci95_low": lo,
                "ratio_ci95_high": hi, "ratio_rounds": 40, "ratio_non_finite": 0,
                "ratio_confidence": 0.96})
        };
        let mut v = serde_json::json!({
            "scene": "sphere_fine", "width": 512, "height": 512, "rounds": {"rounds": 40},
            "methods": [row(crate::method::PHONG_EXACT, 1.0, 1.0, 1.0), row("dichotomy_exact", 2.0, 2.2, 2.4),
                        row("dichotomy_poly1", 0.9, 1.0, 1.1), row("newton_raphson", 1.01, 1.02, 1.03)]
        });
        if let Some(e) = engine {
            v["engine"] = serde_json::json!(e);
        }
        v
    }

    #[test]
    fn the_vulkan_column_reads_a_vulkan_bench_and_refuses_another_engine() {
        let v = VulkanRatios::from_json(&bench_json(None), "old/bench.json").unwrap();
        let (r, paired) = v
            .ratio("newton_raphson", crate::method::PHONG_EXACT)
            .unwrap();
        assert!(paired);
        assert_eq!(judge(&r, 1.0), Verdict::Disagrees);
        // dichotomy: poly1 / exact bounded from both intervals: [0.9/2.4, 1.1/2.0]
        let (d, paired) = v.ratio("dichotomy_poly1", "dichotomy_exact").unwrap();
        assert!(!paired);
        assert!((d.ci95_low - 0.9 / 2.4).abs() < 1e-12 && (d.ci95_high - 0.55).abs() < 1e-12);
        assert_eq!(judge(&d, 0.4), Verdict::Inconclusive);
        assert!(v.ratio("gouraud", crate::method::PHONG_EXACT).is_none());
        assert!(VulkanRatios::from_json(&bench_json(Some("vulkan")), "x").is_ok());
        let err = VulkanRatios::from_json(&bench_json(Some("software")), "sw/bench.json")
            .unwrap_err()
            .to_string();
        assert!(err.contains("not \"vulkan\""), "{err}");
    }
}
