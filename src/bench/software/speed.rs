//! The seeds' speed claims judged by `bench --engine software`: the claim list, the verdict
//! rule, the Vulkan column (from the same rounds with `--vulkan-paired`, or read from another
//! run's bench.json) and claims.md.
use std::path::Path;

use serde::Serialize;

use super::SoftwareBench;
use crate::analysis::stats::{paired_ratio, RatioEstimate};
use crate::cost::factor_verdict;
use crate::error::{Error, Result};
use crate::method::{Kind, Property, Verdict};
use crate::scene::Scene;

/// A ratio interval and the verdict it gives on one claim.
#[derive(Debug, Clone, Serialize)]
pub struct Judged {
    pub median: f64,
    pub ci95_low: f64,
    pub ci95_high: f64,
    /// Rounds with a finite ratio, and rounds without one (counted, never sorted in).
    pub rounds: usize,
    pub non_finite: usize,
    /// Whether the interval is of per-round ratios of the two programs; false when it is
    /// bounded from two separate ratios to phong_exact (a Vulkan bench.json's only choice
    /// for a claim that is not against phong_exact).
    pub paired: bool,
    pub verdict: Verdict,
}

/// One seed speed claim, judged in the software engine and, where a Vulkan bench.json is given,
/// in Vulkan.
#[derive(Debug, Clone, Serialize)]
pub struct SpeedClaim {
    pub claim: String,
    /// The ratio judged: `num / den` of frame times per round.
    pub num: String,
    pub den: String,
    /// The claim holds when `num / den` is at most this ([`judge`]).
    pub claimed_below: f64,
    /// `None` when a program of the ratio was not in the run.
    pub software: Option<Judged>,
    pub vulkan: Option<Judged>,
}

/// A claim before it is measured: `num / den` per round below `target`.
#[derive(Debug, Clone)]
pub(crate) struct ClaimSpec {
    pub claim: String,
    pub num: &'static str,
    pub den: &'static str,
    pub target: f64,
}

/// The speed claims of the rows ([`Kind::Speed`]: `factor` times faster than `than`, the same
/// claims the Vulkan bench judges), then the claim of [`Property::SqrtFree`] for each row with
/// it.
pub(crate) fn claim_specs() -> Vec<ClaimSpec> {
    let spec = |claim: &str, num, den, target| ClaimSpec {
        claim: claim.into(),
        num,
        den,
        target,
    };
    let mut out = Vec::new();
    for m in crate::method::METHODS {
        for c in m.claims {
            if let Kind::Speed { factor, than } = c.kind {
                out.push(spec(c.claim, m.name, than, 1.0 / factor));
            }
        }
    }
    for m in crate::method::with_property(Property::SqrtFree) {
        out.push(spec(
            "normalization without a square root is faster than exact normalization (docs/formulas.md#exact-phong)",
            m.name,
            crate::method::PHONG_EXACT,
            1.0,
        ));
    }
    out
}

/// The verdict of a claim "`num / den` is at most `target`" from the ratio's 95% interval, by
/// the rule of every engine ([`factor_verdict`]); inconclusive when no round gave a finite
/// ratio.
pub(crate) fn judge(r: &RatioEstimate, target: f64) -> Verdict {
    if r.rounds == 0 {
        Verdict::Inconclusive
    } else {
        factor_verdict(r.ci95_low, r.ci95_high, target)
    }
}

pub(crate) fn judged(r: RatioEstimate, target: f64, paired: bool) -> Judged {
    Judged {
        median: r.median,
        ci95_low: r.ci95_low,
        ci95_high: r.ci95_high,
        rounds: r.rounds,
        non_finite: r.non_finite,
        paired,
        verdict: judge(&r, target),
    }
}

/// A Vulkan run's ratios to phong_exact, read from its bench.json.
#[derive(Debug, Clone)]
pub(crate) struct VulkanRatios {
    pub path: String,
    pub scene: String,
    pub width: u64,
    pub height: u64,
    pub rounds: u64,
    /// (method, its paired ratio to phong_exact).
    pub ratios: Vec<(String, RatioEstimate)>,
    /// Timed in the same rounds as the software programs (`--vulkan-paired`): every program's
    /// per-round times, so any ratio of two of them is paired.
    pub same_rounds: Option<(Vec<String>, Vec<Vec<f64>>)>,
}

impl VulkanRatios {
    /// lavapipe's median frame time per method, when timed in the same rounds (else none).
    pub fn medians(&self) -> Vec<(String, f64)> {
        self.same_rounds
            .as_ref()
            .map(|(names, vk)| {
                names
                    .iter()
                    .zip(vk)
                    .map(|(n, v)| (n.clone(), crate::analysis::stats::median_ci(v).median))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Reads `path`; refuses a bench.json of another engine (`engine` other than `vulkan`; a
    /// bench.json without the field was written by the Vulkan bench).
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::Usage(format!(
                "--vulkan-bench {}: {e}: give the bench.json of a `shadelab bench` run",
                path.display()
            ))
        })?;
        let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
            Error::Usage(format!("--vulkan-bench {}: not JSON: {e}", path.display()))
        })?;
        Self::from_json(&v, &path.display().to_string())
    }

    pub fn from_json(v: &serde_json::Value, path: &str) -> Result<Self> {
        let engine = v.get("engine").and_then(|e| e.as_str()).unwrap_or("vulkan");
        if engine != "vulkan" {
            return Err(Error::Usage(format!(
                "--vulkan-bench {path}: its engine is {engine:?}, not \"vulkan\": give the \
                 bench.json of a `shadelab bench --engine vulkan` run"
            )));
        }
        let methods = v
            .get("methods")
            .and_then(|m| m.as_array())
            .ok_or_else(|| Error::Usage(format!("--vulkan-bench {path}: no `methods` array")))?;
        let f = |row: &serde_json::Value, k: &str| {
            row.get(k).and_then(|x| x.as_f64()).unwrap_or(f64::NAN)
        };
        let u = |row: &serde_json::Value, k: &str| {
            row.get(k).and_then(|x| x.as_u64()).unwrap_or(0) as usize
        };
        let ratios = methods
            .iter()
            .filter_map(|row| {
                let name = row.get("name")?.as_str()?.to_string();
                Some((
                    name,
                    RatioEstimate {
                        median: f(row, "ratio_median"),
                        ci95_low: f(row, "ratio_ci95_low"),
                        ci95_high: f(row, "ratio_ci95_high"),
                        rounds: u(row, "ratio_rounds"),
                        non_finite: u(row, "ratio_non_finite"),
                        confidence: f(row, "ratio_confidence"),
                    },
                ))
            })
            .collect();
        let n = |k: &str| v.get(k).and_then(|x| x.as_u64()).unwrap_or(0);
        Ok(VulkanRatios {
            path: path.into(),
            scene: v
                .get("scene")
                .and_then(|s| s.as_str())
                .unwrap_or("?")
                .into(),
            width: n("width"),
            height: n("height"),
            rounds: v
                .get("rounds")
                .and_then(|r| r.get("rounds"))
                .and_then(|r| r.as_u64())
                .unwrap_or(0),
            ratios,
            same_rounds: None,
        })
    }

    /// Ratios from lavapipe draws timed in the same rounds as the software ones (`values[i]`:
    /// program `names[i]`, one time per round).
    pub fn paired(names: Vec<String>, values: Vec<Vec<f64>>, scene: &Scene) -> Result<Self> {
        let phong = names
            .iter()
            .position(|n| n == crate::method::PHONG_EXACT)
            .ok_or_else(|| Error::Internal("phong_exact is not among the programs".into()))?;
        let ratios = names
            .iter()
            .zip(&values)
            .map(|(n, v)| (n.clone(), paired_ratio(v, &values[phong])))
            .collect();
        Ok(VulkanRatios {
            path: "the same rounds".into(),
            scene: scene.name.clone(),
            width: scene.width.into(),
            height: scene.height.into(),
            rounds: values.first().map_or(0, Vec::len) as u64,
            ratios,
            same_rounds: Some((names, values)),
        })
    }

    fn to_phong(&self, name: &str) -> Option<RatioEstimate> {
        if name == crate::method::PHONG_EXACT {
            return None;
        }
        self.ratios.iter().find(|(n, _)| n == name).map(|(_, r)| *r)
    }

    /// `num / den`: the paired ratio when `den` is phong_exact, otherwise the quotient of the
    /// two ratios to phong_exact with bounds from both intervals (not paired: widest ends).
    pub fn ratio(&self, num: &str, den: &str) -> Option<(RatioEstimate, bool)> {
        if let Some((names, values)) = &self.same_rounds {
            let at = |n: &str| names.iter().position(|x| x == n);
            let (i, j) = (at(num)?, at(den)?);
            return (i != j).then(|| (paired_ratio(&values[i], &values[j]), true));
        }
        let a = self.to_phong(num)?;
        if den == crate::method::PHONG_EXACT {
            return Some((a, true));
        }
        let b = self.to_phong(den)?;
        let high = if b.ci95_low > 0.0 {
            a.ci95_high / b.ci95_low
        } else {
            f64::NAN
        };
        Some((
            RatioEstimate {
                median: a.median / b.median,
                ci95_low: a.ci95_low / b.ci95_high,
                ci95_high: high,
                rounds: a.rounds.min(b.rounds),
                non_finite: a.non_finite.max(b.non_finite),
                confidence: a.confidence.min(b.confidence),
            },
            false,
        ))
    }
}

/// Every claim of [`claim_specs`] judged by `software` (per-round ratios of the programs
/// `names`, `values[i][r]` the time of program i in round r) and by `vulkan`.
pub(crate) fn judge_claims(
    names: &[String],
    values: &[Vec<f64>],
    vulkan: Option<&VulkanRatios>,
) -> Vec<SpeedClaim> {
    let at = |n: &str| names.iter().position(|x| x == n);
    claim_specs()
        .into_iter()
        .map(|c| {
            let software = match (at(c.num), at(c.den)) {
                (Some(i), Some(j)) => {
                    Some(judged(paired_ratio(&values[i], &values[j]), c.target, true))
                }
                _ => None,
            };
            let vulkan = vulkan
                .and_then(|v| v.ratio(c.num, c.den))
                .map(|(r, paired)| judged(r, c.target, paired));
            SpeedClaim {
                claim: c.claim,
                num: c.num.into(),
                den: c.den.into(),
                claimed_below: c.target,
                software,
                vulkan,
            }
        })
        .collect()
}

/// Whether the software engine is within 2x of lavapipe, from the paired interval: "yes" when
/// its upper end is at most 2, "no" when its lower end is above 2, else undecided.
pub fn within_2x(r: &RatioEstimate) -> &'static str {
    if r.rounds == 0 || !(r.ci95_low.is_finite() && r.ci95_high.is_finite()) {
        "within 2x: undecided (no finite ratio)"
    } else if r.ci95_high <= 2.0 {
        "within 2x: yes"
    } else if r.ci95_low > 2.0 {
        "within 2x: no"
    } else {
        "within 2x: undecided (the interval holds 2)"
    }
}

/// "median [low, high]" of a judged ratio, with its rounds and non-finite rounds.
pub(crate) fn cell(j: &Option<Judged>) -> (String, &'static str) {
    match j {
        None => ("not in the run".into(), "not checked"),
        Some(j) => (
            format!(
                "{:.4} [{:.4}, {:.4}], {} rounds{}{}",
                j.median,
                j.ci95_low,
                j.ci95_high,
                j.rounds,
                if j.non_finite > 0 {
                    format!(", {} non-finite", j.non_finite)
                } else {
                    String::new()
                },
                if j.paired { "" } else { ", not paired" }
            ),
            j.verdict.as_str(),
        ),
    }
}

/// claims.md: one table, software and Vulkan verdicts side by side.
pub(crate) fn claims_md(r: &SoftwareBench, vulkan: Option<&VulkanRatios>) -> String {
    let mut md = format!(
        "# The seeds' speed claims in the software engine\n\n\
         Scene {} at {}x{}, {} triangles; `software::render_into` on {} threads, {} interleaved \
         rounds ({}), clock: {}.\n\n",
        r.scene,
        r.width,
        r.height,
        r.triangles,
        r.threads,
        r.rounds.rounds,
        r.rounds.stopped.as_str(),
        r.clock
    );
    match vulkan {
        Some(v) if v.same_rounds.is_some() => {
            md += &format!(
                "Vulkan column: lavapipe drew the same methods in the same {} rounds \
                 (`--vulkan-paired`, wall clock: submit to fence), so every Vulkan ratio is \
                 paired per round, the dichotomy ratio too.\n",
                v.rounds
            );
            if let Some(a) = &r.software_to_lavapipe {
                md += &format!(
                    "Software / lavapipe phong_exact per round: {:.3} [{:.3}, {:.3}] ({}).\n",
                    a.median,
                    a.ci95_low,
                    a.ci95_high,
                    within_2x(a)
                );
            }
        }
        Some(v) => {
            md += &format!(
                "Vulkan column: the paired ratios of {} (scene {} at {}x{}, {} rounds): a \
                 separate run, so a software and a Vulkan figure are not paired with each \
                 other.\n",
                v.path, v.scene, v.width, v.height, v.rounds
            );
            if v.scene != r.scene || v.width != r.width as u64 || v.height != r.height as u64 {
                md += "**The Vulkan run drew another scene or size than this run.**\n";
            }
        }
        None => {
            md += "Vulkan column: not measured (pass `--vulkan-paired` to time lavapipe in the \
                   same rounds, or `--vulkan-bench DIR/bench.json` of a `shadelab bench` run of \
                   the same scene and size).\n"
        }
    }
    md += "\nEach claim is a ratio of frame times per round that should lie below the claimed \
           value: the verdict *agrees* when the whole 95% interval of the ratio lies below it, \
           *disagrees* when the whole interval lies above it, and is *inconclusive* when the \
           interval holds it or no round gave a finite ratio. Intervals are of per-round \
           ratios (sign test); a Vulkan ratio read from another run's bench.json and not \
           against phong_exact is bounded from two intervals (marked not paired).\n\n";
    md += "| claim | ratio per round | claimed below | software: median [95%] | software | Vulkan: median [95%] | Vulkan |\n";
    md += "|---|---|---|---|---|---|---|\n";
    for c in &r.claims {
        let (s, sv) = cell(&c.software);
        let (v, vv) = match (&c.vulkan, vulkan) {
            (None, None) => ("-".to_string(), "-"),
            (j, _) => cell(j),
        };
        md += &format!(
            "| {} | {} / {} | {:.4} | {s} | {sv} | {v} | {vv} |\n",
            c.claim.replace('|', "/"),
            c.num,
            c.den,
            c.claimed_below
        );
    }
    md
}
