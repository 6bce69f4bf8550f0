//! What a bench or report run decides, decided once: [`Schedule`], built from what the command
//! line gave ([`Given`]) and the table of defaults ([`Schedule::new`], tested in one place).
//! Every later step reads the schedule: bench's rounds, its fresh-process runs (the schedule
//! travels in their requests), the isolated cost, the control, the report's skips, software
//! bench and stress.
//!
//! The defaults, and why:
//!
//! | job | runs | rounds per run | warm-up | isolated rounds (warm-up) | stress refine |
//! |---|---|---|---|---|---|
//! | bench, 1 run | - | 40 | 3 | 21 (2) | - |
//! | bench, N runs (default 5) | N | 7 | 3 | 5 (1) | - |
//! | report, 1 run | - | 10 | 2 | 5 (2) | 2 |
//! | report, N runs (default 5) | N | 6 | 1 | 5 (1) | 2 |
//! | report --full, 1 run | - | 40 | 3 | 21 (2) | 8 |
//! | report --full, N runs | N | 7 | 3 | 5 (1) | 8 |
//!
//! With several runs the between-run spread dominates, so a run needs fewer rounds (7 keeps the
//! default bench near its 150 s target, about 1 s per round and run); a run's isolated kernels
//! were compiled (and their JIT done) when created, so one warm-up round is enough there. The
//! control (`phong_exact_control`) is timed when asked for and in every bench of several runs:
//! it is their noise floor. A report measures the isolated cost with its first scene only (it
//! does not depend on the scene: [`Schedule::later_scene`]).
use serde::{Deserialize, Serialize};

use super::rounds::RoundsSchedule;
use crate::error::{Error, Result};

/// The default number of fresh-process runs of `bench` and `report`.
pub const DEFAULT_RUNS: usize = 5;

/// Which command decides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Job {
    /// `shadelab bench` (the software engine: `software` true).
    Bench { software: bool },
    /// `shadelab report` (`--full`: bench's long setting).
    Report { full: bool },
}

/// What the command line gave; `None` (or false): the default.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Given {
    pub runs: Option<usize>,
    pub repeat: Option<usize>,
    pub warmup: Option<usize>,
    pub isolated_rounds: Option<usize>,
    pub control: bool,
    pub until_ci_pct: Option<f64>,
    pub max_time_s: Option<f64>,
}

/// Everything a bench or report run decides about its measurement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    /// Fresh-process measurement runs; 1: one run in this process.
    pub runs: usize,
    /// Each run's timed rounds (repeat, warm-up, `--until-ci` and its cap).
    pub rounds: RoundsSchedule,
    /// Isolated-cost rounds per run (0: not measured), after `isolated_warmup` discarded ones.
    pub isolated_rounds: usize,
    pub isolated_warmup: usize,
    /// Whether `phong_exact_control` is timed.
    pub control: bool,
    /// The report's stress: refinement rounds of the worst cases (0 outside a report).
    pub stress_refine: usize,
}

impl Schedule {
    /// The schedule of `job` with what the command line `given`, else the defaults of the table
    /// above; a usage error for a schedule that cannot run.
    pub fn new(job: Job, given: &Given) -> Result<Schedule> {
        let software = matches!(job, Job::Bench { software: true });
        let runs = given
            .runs
            .unwrap_or(if software { 1 } else { DEFAULT_RUNS });
        if runs == 0 {
            return Err(Error::Usage("--runs must be at least 1".into()));
        }
        if software && runs > 1 {
            return Err(Error::Usage(
                "--runs N > 1 is measured by the Vulkan bench only: use --runs 1 with --engine \
                 software"
                    .into(),
            ));
        }
        let many = runs > 1;
        if many && given.until_ci_pct.is_some() {
            return Err(Error::Usage(
                "--until-ci adds rounds within one run: use it with --runs 1".into(),
            ));
        }
        let (repeat, warmup, long) = match (job, many) {
            (Job::Bench { .. } | Job::Report { full: true }, false) => (40, 3, true),
            (Job::Bench { .. } | Job::Report { full: true }, true) => (7, 3, false),
            (Job::Report { full: false }, false) => (10, 2, false),
            (Job::Report { full: false }, true) => (6, 1, false),
        };
        let schedule = Schedule {
            runs,
            rounds: RoundsSchedule {
                repeat: given.repeat.unwrap_or(repeat),
                warmup: given.warmup.unwrap_or(warmup),
                until_ci_pct: given.until_ci_pct,
                max_time_s: given.max_time_s.unwrap_or(super::DEFAULT_MAX_TIME_S),
            },
            isolated_rounds: given
                .isolated_rounds
                .unwrap_or(if long && !many { 21 } else { 5 }),
            isolated_warmup: if many { 1 } else { 2 },
            control: given.control || many,
            stress_refine: match job {
                Job::Report { full: true } => 8,
                Job::Report { full: false } => 2,
                Job::Bench { .. } => 0,
            },
        };
        schedule.rounds.check()?;
        Ok(schedule)
    }

    /// Whether the timing comes from several fresh processes.
    pub fn many(&self) -> bool {
        self.runs > 1
    }

    /// The schedule of a report's scenes after the first: no isolated cost (it does not depend on
    /// the scene; the first scene measured it).
    pub fn later_scene(&self) -> Schedule {
        Schedule {
            isolated_rounds: 0,
            ..self.clone()
        }
    }

    /// The rounds of a report's skips (at least 6: its sign-test intervals need them).
    pub fn skips_rounds(&self) -> (usize, usize) {
        (self.rounds.repeat.max(6), self.rounds.warmup)
    }

    /// The rounds of a report's software bench (at least one warm-up: the first draw builds
    /// the engine's tables).
    pub fn software_rounds(&self) -> RoundsSchedule {
        RoundsSchedule {
            warmup: self.rounds.warmup.max(1),
            until_ci_pct: None,
            ..self.rounds.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(job: Job, runs: Option<usize>) -> (usize, usize, usize, usize, usize, bool, usize) {
        let p = Schedule::new(
            job,
            &Given {
                runs,
                ..Given::default()
            },
        )
        .unwrap();
        (
            p.runs,
            p.rounds.repeat,
            p.rounds.warmup,
            p.isolated_rounds,
            p.isolated_warmup,
            p.control,
            p.stress_refine,
        )
    }

    /// The table of defaults of the module's documentation, row by row.
    #[test]
    fn the_defaults_are_the_table() {
        let bench = Job::Bench { software: false };
        let short = Job::Report { full: false };
        let full = Job::Report { full: true };
        assert_eq!(row(bench, Some(1)), (1, 40, 3, 21, 2, false, 0));
        assert_eq!(row(bench, None), (5, 7, 3, 5, 1, true, 0));
        assert_eq!(row(short, Some(1)), (1, 10, 2, 5, 2, false, 2));
        assert_eq!(row(short, None), (5, 6, 1, 5, 1, true, 2));
        assert_eq!(row(full, Some(1)), (1, 40, 3, 21, 2, false, 8));
        assert_eq!(row(full, Some(3)), (3, 7, 3, 5, 1, true, 8));
        assert_eq!(row(Job::Bench { software: true }, None).0, 1);
    }

    /// What the command line gives wins; a schedule that cannot run is a usage error.
    #[test]
    fn given_values_win_and_bad_schedules_are_refused() {
        let g = Given {
            runs: Some(3),
            repeat: Some(12),
            warmup: Some(0),
            isolated_rounds: Some(0),
            ..Given::default()
        };
        let p = Schedule::new(Job::Bench { software: false }, &g).unwrap();
        assert_eq!(
            (p.rounds.repeat, p.rounds.warmup, p.isolated_rounds),
            (12, 0, 0)
        );
        assert_eq!(p.later_scene().isolated_rounds, 0);
        assert_eq!(p.skips_rounds(), (12, 0));
        assert_eq!(p.software_rounds().warmup, 1);
        let bad = |g: Given, job| Schedule::new(job, &g).unwrap_err().to_string();
        let bench = Job::Bench { software: false };
        let runs = |n| Given {
            runs: Some(n),
            ..Given::default()
        };
        assert!(bad(runs(0), bench).contains("--runs"));
        assert!(bad(runs(2), Job::Bench { software: true }).contains("--engine software"));
        let until = Given {
            until_ci_pct: Some(2.0),
            ..Given::default()
        };
        assert!(bad(until.clone(), bench).contains("--until-ci"));
        let one = Given {
            runs: Some(1),
            ..until
        };
        assert!(Schedule::new(bench, &one).is_ok());
        let zero = Given {
            runs: Some(1),
            repeat: Some(0),
            ..Given::default()
        };
        assert!(bad(zero, bench).contains("--repeat"));
    }
}
