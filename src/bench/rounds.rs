//! Interleaved rounds of timed draws and the paired statistics they allow.
//!
//! Round r submits every program once, in an order balanced over rounds for position and for
//! the program just before ([`round_order`]), so the drift of a shared machine and the
//! carry-over of one draw into the next hit every program alike and the samples of one round are paired: the ratio of a
//! program's time to phong_exact's (or to its floor's) in the same round cancels what the
//! machine did during that round. Each ratio is reported as the median of the per-round
//! ratios with the sign-test 95% interval ([`paired_ratio`]).
use serde::Serialize;

use crate::analysis::stats::{paired_ratio, RatioEstimate};
use crate::error::{Error, Result};
use crate::gpu::{Clock, Sample, TimedDraws};

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

    /// Runs `count` more rounds, each visiting every draw once in the order of
    /// [`round_order`].
    pub fn run(&mut self, count: usize) -> Result<()> {
        let n = self.draws.len();
        for _ in 0..count {
            for i in round_order(n, self.len()) {
                self.samples[i].push(self.draws.run(i)?);
            }
        }
        Ok(())
    }
}

/// The order in which round `round` visits `n` programs: a Williams design, balanced for
/// position and for the program just before. Round r is the sequence 0, 1, n-1, 2, n-2, ...
/// shifted by r (mod n); for odd n, rounds n..2n-1 are those sequences reversed. Over every n
/// rounds (2n for odd n) each program is in every position equally often and follows every
/// other program equally often, so a carry-over (a draw running faster or slower after a
/// heavy one) falls on every program alike. A plain rotation keeps each program behind the
/// same neighbour in every round: on lavapipe that biased a paired ratio by ~5 % between two
/// draws of identical work (`shadelab skips` on the cube, front-to-back order).
pub fn round_order(n: usize, round: usize) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let first = (0..n).map(|k| {
        if k % 2 == 1 {
            k.div_ceil(2)
        } else {
            (n - k / 2) % n
        }
    });
    let shift = round % n;
    let mut order: Vec<usize> = first.map(|x| (x + shift) % n).collect();
    if n % 2 == 1 && (round / n) % 2 == 1 {
        order.reverse();
    }
    order
}

/// The per-round times of one program on `clock` (`timestamp` or `wall`); a round without a
/// timestamp on the timestamp clock is NaN, so that the ratios count it as non-finite instead
/// of mixing clocks.
pub(crate) fn round_values(samples: &[Sample], clock: Clock) -> Vec<f64> {
    samples.iter().map(|s| clock.of(s)).collect()
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
    for (k, list) in [
        (crate::method::PHONG_EXACT, to_phong),
        ("its floor", to_floor),
    ] {
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

/// How many rounds a run times, the part of a bench's options every engine shares: `warmup`
/// discarded submissions of each program, `repeat` rounds, then with `until_ci_pct` one round
/// at a time until every paired ratio interval is within +-PCT % or `max_time_s` of rounds has
/// passed.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RoundsSchedule {
    pub repeat: usize,
    pub warmup: usize,
    pub until_ci_pct: Option<f64>,
    pub max_time_s: f64,
}

impl RoundsSchedule {
    /// Refuses a schedule that cannot run: no round, a target or a cap that is not a positive
    /// number.
    pub fn check(&self) -> Result<()> {
        if self.repeat == 0 {
            return Err(Error::Usage("--repeat must be at least 1".into()));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if let Some(p) = self.until_ci_pct.filter(|p| !positive(*p)) {
            return Err(Error::Usage(format!(
                "--until-ci must be a percentage > 0, got {p}"
            )));
        }
        if !positive(self.max_time_s) {
            return Err(Error::Usage(format!(
                "--max-time must be a number of seconds > 0, got {}",
                self.max_time_s
            )));
        }
        Ok(())
    }

    /// "W warm-up submissions each, then R rounds[ and more until ...]".
    pub(crate) fn describe(&self) -> String {
        format!(
            "{} warm-up submissions each, then {} rounds{}",
            self.warmup,
            self.repeat,
            self.until_ci_pct.map_or(String::new(), |p| format!(
                " and more until every paired ratio interval is within +-{p} % (cap {} s)",
                self.max_time_s
            ))
        )
    }
}

/// The warm-up and rounds of `draws` by `schedule` (see [`RoundsSchedule`]); `widest_of` gives the
/// widest paired ratio interval (+- percent, and whose) of the rounds so far. Says on stderr,
/// after `who`, how the rounds went and why they stopped. Shared by every engine's bench.
pub(crate) fn run_rounds<D: Draws + ?Sized>(
    draws: &D,
    schedule: &RoundsSchedule,
    who: &str,
    widest_of: impl Fn(&[Vec<Sample>]) -> (f64, String),
) -> Result<(Vec<Vec<Sample>>, RoundsReport)> {
    let mut rounds = Rounds::new(draws, schedule.warmup)?;
    let t0 = std::time::Instant::now();
    rounds.run(schedule.repeat)?;
    let (stopped, (w, which)) = loop {
        let w = widest_of(&rounds.samples);
        let Some(target) = schedule.until_ci_pct else {
            break (Stop::FixedRepeat, w);
        };
        if let Some(stop) =
            until_ci_stop(w.0, target, t0.elapsed().as_secs_f64(), schedule.max_time_s)
        {
            break (stop, w);
        }
        if rounds.len() % 10 == 0 {
            log::info!(
                "{who}: {} rounds, widest paired ratio interval +-{:.2} % ({})",
                rounds.len(),
                w.0,
                w.1
            );
        }
        rounds.run(1)?;
    };
    let timing_s = t0.elapsed().as_secs_f64();
    let n = rounds.len();
    let target = schedule.until_ci_pct.unwrap_or(f64::NAN);
    match stopped {
        Stop::FixedRepeat => log::info!(
            "{who}: {n} rounds in {timing_s:.1} s; widest paired ratio interval +-{w:.2} % ({which})"
        ),
        Stop::TargetReached => log::info!(
            "{who}: stopped: target reached: every paired ratio interval within +-{target} % after {n} rounds ({timing_s:.1} s); widest +-{w:.2} % ({which})"
        ),
        Stop::TimeCap => log::info!(
            "{who}: stopped: time cap of {} s reached after {n} rounds; target +-{target} % NOT reached: widest paired ratio interval +-{w:.2} % ({which})",
            schedule.max_time_s
        ),
    }
    let report = RoundsReport::new(schedule, n, stopped, timing_s, (w, which));
    Ok((rounds.samples, report))
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

impl RoundsReport {
    /// The report of `rounds` rounds run by `opts`, stopped for `stopped` after `timing_s`
    /// seconds with `widest` (half-width in percent, and whose) the widest interval.
    pub(crate) fn new(
        opts: &RoundsSchedule,
        rounds: usize,
        stopped: Stop,
        timing_s: f64,
        widest: (f64, String),
    ) -> Self {
        RoundsReport {
            repeat: opts.repeat,
            rounds,
            until_ci_pct: opts.until_ci_pct,
            max_time_s: opts.until_ci_pct.map(|_| opts.max_time_s),
            stopped,
            timing_s,
            widest_half_width_pct: widest.0,
            widest: widest.1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::round_order;

    /// Every round is a permutation; over a full cycle every program takes every position
    /// equally often and follows every other program equally often.
    #[test]
    fn round_orders_balance_position_and_predecessor() {
        for n in 1..=9 {
            let cycle = if n % 2 == 0 { n } else { 2 * n };
            let mut position = vec![vec![0usize; n]; n];
            let mut after = vec![vec![0usize; n]; n];
            for r in 0..cycle {
                let o = round_order(n, r);
                let mut sorted = o.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "n {n} round {r}: {o:?}");
                for (k, &i) in o.iter().enumerate() {
                    position[i][k] += 1;
                }
                for w in o.windows(2) {
                    after[w[1]][w[0]] += 1;
                }
            }
            let per_position = cycle / n;
            assert!(
                position.iter().flatten().all(|&c| c == per_position),
                "n {n}: {position:?}"
            );
            let per_pair = if n > 1 {
                cycle * (n - 1) / (n * (n - 1))
            } else {
                0
            };
            for (b, row) in after.iter().enumerate() {
                for (a, &c) in row.iter().enumerate() {
                    let want = if a == b { 0 } else { per_pair };
                    assert_eq!(c, want, "n {n}: {a} before {b} {c} times");
                }
            }
        }
    }

    /// Teeth: a plain rotation is balanced for position but not for the predecessor.
    #[test]
    fn a_plain_rotation_is_not_balanced_for_the_predecessor() {
        let n = 4;
        let mut after = vec![vec![0usize; n]; n];
        for r in 0..n {
            let o: Vec<usize> = (0..n).map(|k| (k + r) % n).collect();
            for w in o.windows(2) {
                after[w[1]][w[0]] += 1;
            }
        }
        assert_eq!(after[1][0], 3, "1 follows 0 in three rounds of four");
        assert_eq!(after[0][1], 0, "0 never follows 1");
    }
}
