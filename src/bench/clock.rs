//! The clock check: GPU timestamps against the submit-to-fence wall clock.
use serde::Serialize;

use super::*;
use crate::analysis::stats::median_ci;
use crate::error::Result;
use crate::gpu::{Renderer, Shading};
use crate::method::{self};
use crate::scene::Scene;

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
    pub clock: Clock,
    pub reason: String,
    pub points: Vec<ClockPoint>,
}
/// Checks the timestamp placement against the wall clock at every size of [`SIZES`].
pub fn check_clock(renderer: &Renderer, scene: &Scene) -> Result<ClockCheck> {
    let exact = method::phong_exact();
    let max = renderer.context().info().max_image_dimension_2d;
    let mut points = Vec::new();
    for &size in SIZES.iter().filter(|&&s| s <= max) {
        let mut s = scene.clone();
        s.width = size;
        s.height = size;
        let prepared = renderer.prepare(&s, &[exact])?;
        let draws = renderer.timed_draws(&[(prepared.base(), Shading::Method(exact))])?;
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
            clock: Clock::Timestamp,
            reason: format!(
                "the timestamp interval tracks the submit-to-fence wall clock at every size (within {:.0} % or {CLOCK_SLACK_MS} ms)",
                CLOCK_TOLERANCE * 100.0
            ),
            points,
        }
    } else {
        ClockCheck {
            clock: Clock::Wall,
            reason: format!("timestamps do not track the wall clock on this driver ({}); timing with the wall clock", bad.join("; ")),
            points,
        }
    })
}

/// The clock check `known` (made before on this device: the report's, with its first scene),
/// else one made now; `job` names who says so on stderr.
pub fn known_or_checked(
    renderer: &Renderer,
    scene: &Scene,
    known: Option<&ClockCheck>,
    job: &str,
) -> Result<ClockCheck> {
    if let Some(known) = known {
        log::info!(
            "{job}: clock = {} (checked before: {})",
            known.clock,
            known.reason
        );
        return Ok(known.clone());
    }
    log::info!("{job}: checking the clock at sizes {SIZES:?}");
    let clock = check_clock(renderer, scene)?;
    log::info!("{job}: clock = {} ({})", clock.clock, clock.reason);
    Ok(clock)
}
