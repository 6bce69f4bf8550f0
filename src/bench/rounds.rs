//! Interleaved rounds of timed draws and the paired statistics they allow.
//!
//! Round r submits every program once, starting at program r mod n, so the drift of a shared
//! machine hits every program alike and the samples of one round are paired: the ratio of a
//! program's time to phong_exact's (or to its floor's) in the same round cancels what the
//! machine did during that round. Each ratio is reported as the median of the per-round
//! ratios with the sign-test 95% interval ([`paired_ratio`]).
use serde::Serialize;

use crate::analysis::stats::{paired_ratio, RatioEstimate};
use crate::error::Result;
use crate::gpu::{Sample, TimedDraws};

/// Programs that can be timed one at a time, in any order: lavapipe's recorded draws, or the
/// software engine's renders ([`super::software`]).
pub(crate) trait Draws {
    fn len(&self) -> usize;
    /// Draws program `i` once and times it.
    fn run(&self, i: usize) -> Result<Sample>;
}

impl Draws for TimedDraws {
    fn len(&self) -> usize {
        TimedDraws::len(self)
    }
    fn run(&self, i: usize) -> Result<Sample> {
        TimedDraws::run(self, i)
    }
}

/// Rounds run so far over a set of draws.
pub(crate) struct Rounds<'d, D: Draws + ?Sized = TimedDraws> {
    draws: &'d D,
    /// `samples[i][r]`: program i in round r.
    pub samples: Vec<Vec<Sample>>,
}

impl<'d, D: Draws + ?Sized> Rounds<'d, D> {
    /// Runs `warmup` discarded submissions of each draw (the first includes lavapipe's JIT).
    pub fn new(draws: &'d D, warmup: usize) -> Result<Self> {
        for i in 0..draws.len() {
            for _ in 0..warmup {
                draws.run(i)?;
            }
        }
        Ok(Rounds {
            draws,
            samples: vec![Vec::new(); draws.len()],
        })
    }

    /// Rounds done.
    pub fn len(&self) -> usize {
        self.samples.first().map_or(0, Vec::len)
    }

    /// Runs `count` more rounds, each visiting every draw once in an order rotated by one per
    /// round.
    pub fn run(&mut self, count: usize) -> Result<()> {
        let n = self.draws.len();
        for _ in 0..count {
            let round = self.len();
            for k in 0..n {
                let i = (k + round) % n;
                self.samples[i].push(self.draws.run(i)?);
            }
        }
        Ok(())
    }
}

/// The per-round times of one program on `clock` (`timestamp` or `wall`); a round without a
/// timestamp on the timestamp clock is NaN, so that the ratios count it as non-finite instead
/// of mixing clocks.
pub(crate) fn round_values(samples: &[Sample], clock: &str) -> Vec<f64> {
    samples
        .iter()
        .map(|s| match clock {
            "timestamp" => s.timestamp_ms.unwrap_or(f64::NAN),
            _ => s.wall_ms,
        })
        .collect()
}

/// Every program's paired ratio to program `phong` and to its own floor (`floors[i]`).
pub(crate) fn ratios(
    values: &[Vec<f64>],
    phong: usize,
    floors: &[usize],
) -> (Vec<RatioEstimate>, Vec<RatioEstimate>) {
    let to_phong = values
        .iter()
        .map(|v| paired_ratio(v, &values[phong]))
        .collect();
    let to_floor = values
        .iter()
        .zip(floors)
        .map(|(v, &f)| paired_ratio(v, &values[f]))
        .collect();
    (to_phong, to_floor)
}

/// The widest ratio interval (largest "+-" in percent) among `to_phong` and `to_floor`, and
/// which it is. An interval without a finite ratio is infinitely wide: it is never "narrow".
pub(crate) fn widest(
    names: &[String],
    to_phong: &[RatioEstimate],
    to_floor: &[RatioEstimate],
) -> (f64, String) {
    let mut worst = (f64::NEG_INFINITY, String::new());
    for (k, list) in [("phong_exact", to_phong), ("its floor", to_floor)] {
        for (name, r) in names.iter().zip(list) {
            let w = r.half_width_pct();
            let w = if w.is_nan() { f64::INFINITY } else { w };
            if w > worst.0 {
                worst = (w, format!("{name} against {k}"));
            }
        }
    }
    worst
}

/// Why a run stopped adding rounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// No `--until-ci`: exactly `--repeat` rounds.
    FixedRepeat,
    /// Every ratio interval is within +-`--until-ci` percent.
    TargetReached,
    /// The time cap came first; the widest interval is recorded.
    TimeCap,
}

impl Stop {
    /// The snake_case name, as in the JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            Stop::FixedRepeat => "fixed_repeat",
            Stop::TargetReached => "target_reached",
            Stop::TimeCap => "time_cap",
        }
    }
}

/// The `--until-ci` rule: stop when the widest interval is within +-`target_pct` (a NaN or
/// infinite width never is), else when `elapsed_s` has reached `cap_s`, else go on (`None`).
pub(crate) fn until_ci_stop(
    widest_pct: f64,
    target_pct: f64,
    elapsed_s: f64,
    cap_s: f64,
) -> Option<Stop> {
    if widest_pct.is_finite() && widest_pct <= target_pct {
        Some(Stop::TargetReached)
    } else if elapsed_s >= cap_s {
        Some(Stop::TimeCap)
    } else {
        None
    }
}

/// How many rounds a run did and why it stopped (bench.json `rounds`).
#[derive(Debug, Clone, Serialize)]
pub struct RoundsReport {
    /// Rounds asked for with `--repeat` (the minimum with `--until-ci`).
    pub repeat: usize,
    /// Rounds done: the sample count of every program.
    pub rounds: usize,
    pub until_ci_pct: Option<f64>,
    /// The time cap of `--until-ci` (seconds of timed rounds), null without it.
    pub max_time_s: Option<f64>,
    pub stopped: Stop,
    /// Seconds spent in the timed rounds.
    pub timing_s: f64,
    /// The widest paired ratio interval when the rounds stopped, as +- percent of its median
    /// (null when some ratio had no finite round), and which one it was.
    pub widest_half_width_pct: f64,
    pub widest: String,
}
