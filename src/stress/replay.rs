//! `shadelab stress --replay CASE.json`: one case (a `worst_case` or `non_finite_example` of
//! stress.json, or DIR/cases/<method>.json) evaluated again on the device and in f64. The case
//! is rebuilt from its spec, so the device reads the same f32 inputs; the colour is compared
//! bit for bit with the recorded one.
use std::path::Path;
use std::sync::Arc;

use super::{case_report, measure, CaseReport, Output};
use crate::cases::{Case, CaseSpec, Shape};
use crate::error::{Error, Result};
use crate::gpu::evaluate::Kernel;
use crate::gpu::shaders::has_evaluate_program;
use crate::gpu::vk::Context;
use crate::method;

/// Largest input size accepted (a case file is a few kB).
const MAX_BYTES: usize = 1 << 20;

fn check_spec(path: &Path, s: &CaseSpec) -> Result<()> {
    let bad = |m: String| Error::input(path, None, m);
    let angles = [
        ("theta_deg", s.theta_deg),
        ("elevation_deg", s.elevation_deg),
        ("pair_azimuth_deg", s.pair_azimuth_deg),
        ("roll_deg", s.roll_deg),
        ("light_deg", s.light_deg),
        ("apex_deg", s.apex_deg),
    ];
    for (name, v) in angles {
        if !v.is_finite() || v.abs() > 360.0 {
            return Err(bad(format!(
                "spec.{name} = {v}: expected a finite angle in degrees within [-360, 360]"
            )));
        }
    }
    if !(s.shininess.is_finite() && (0.0..=1e4).contains(&s.shininess)) {
        return Err(bad(format!(
            "spec.shininess = {}: expected 0..10000",
            s.shininess
        )));
    }
    if !(s.length.is_finite() && (0.0..=1e38).contains(&s.length)) {
        return Err(bad(format!(
            "spec.length = {}: expected 0..1e38 (the vertex normals' length, within float32)",
            s.length
        )));
    }
    if s.shape == Shape::Strip && !(1..=1 << 20).contains(&s.span_px) {
        return Err(bad(format!(
            "spec.span_px = {}: expected 1..1048576",
            s.span_px
        )));
    }
    let rows = crate::cases::STRIP_APEX_Y as u32;
    if s.row != 0 && !(s.shape == Shape::Strip && s.row < rows) {
        return Err(bad(format!(
            "spec.row = {}: a row is a strip's (shape \"strip\"), 0..{}",
            s.row,
            rows - 1
        )));
    }
    Ok(())
}

/// Parses a case file (JSON of a [`CaseReport`]) read from `path`; every error names what is
/// wrong.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<CaseReport> {
    let bad = |m: String| Error::input(path, None, m);
    if bytes.len() > MAX_BYTES {
        return Err(bad(format!(
            "a case file is at most {MAX_BYTES} bytes; this one has {}",
            bytes.len()
        )));
    }
    let r: CaseReport = serde_json::from_slice(bytes)
        .map_err(|e| bad(format!("not a stress case (JSON of a worst_case): {e}")))?;
    method::find(&r.method).map_err(|e| bad(e.to_string()))?;
    check_spec(path, &r.spec)?;
    Ok(r)
}

/// Reads and parses a case file.
pub fn load(path: &Path) -> Result<CaseReport> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse(path, &bytes)
}

/// The case evaluated again, and whether the device's colour is bit-identical to the recorded.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Replayed {
    pub now: CaseReport,
    /// None when the file recorded no device colour (or the method has no device program).
    pub bit_identical: Option<bool>,
}

/// Evaluates `recorded` again.
pub fn replay(ctx: &Arc<Context>, recorded: &CaseReport) -> Result<Replayed> {
    let m = method::find(&recorded.method)?;
    let case = Case::new(recorded.spec);
    let mut kernel = if has_evaluate_program(m) {
        Some(Kernel::with_precision(ctx, m, 1, recorded.precision)?)
    } else {
        None
    };
    let measured = measure(&mut kernel.as_mut(), m, std::slice::from_ref(&case))?;
    let dev: Option<Output> = measured.into_iter().next().and_then(|(_, o)| o);
    let now = case_report(m, &case, dev.as_ref(), recorded.precision)?;
    // The recorded bits, or the recorded colour's where a hand-made file has no bits.
    let recorded_bits = recorded.device_color_bits.or_else(|| {
        recorded
            .device_color
            .map(|c| c.map(|x| (x as f32).to_bits()))
    });
    let bit_identical = match (recorded_bits, now.device_color_bits) {
        (Some(a), Some(b)) => Some(a == b),
        _ => None,
    };
    Ok(Replayed { now, bit_identical })
}
