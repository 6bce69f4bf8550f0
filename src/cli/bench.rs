//! `shadelab bench`: timed draws, clock check, sweeps, claims.
use std::path::Path;
use std::process::ExitCode;

use super::*;
use crate::error::Result;
pub(super) fn cmd_bench(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    out: &Path,
    opts: &crate::bench::BenchOptions,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let report = crate::bench::bench(&r, &scene, &methods, out, opts)?;
    println!(
        "scene {} at {}x{}, {} triangles; clock: {}; LP_NUM_THREADS={}; {} repetitions",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        report.clock.clock,
        report.lp_num_threads.as_deref().unwrap_or("unset"),
        report.repeat
    );
    println!(
        "{:<32} {:>9} {:>19} {:>8} {:>9} {:>8} {:>12}",
        "program", "median ms", "95% CI ms", "ns/px", "x phong", "floor+ms", report.error_metric
    );
    let mut rows: Vec<&crate::bench::MethodTiming> = std::iter::once(&report.floor)
        .chain(&report.methods)
        .collect();
    rows[1..].sort_by(|a, b| a.median_ms.total_cmp(&b.median_ms));
    for m in rows {
        let err = m
            .error
            .as_ref()
            .and_then(|e| e.metric(&report.error_metric));
        println!(
            "{:<32} {:>9.3} {:>19} {:>8.2} {:>9.3} {:>8.3} {:>12}{}",
            m.name,
            m.median_ms,
            format!("[{:.3}, {:.3}]", m.ci95_low_ms, m.ci95_high_ms),
            m.ns_per_pixel,
            m.ratio_to_phong_exact,
            m.above_floor_ms,
            err.map(|e| format!("{e:.3e}"))
                .unwrap_or_else(|| "-".into()),
            if report.pareto_front.contains(&m.name) {
                "  pareto"
            } else {
                ""
            }
        );
    }
    for s in &report.sweeps {
        for (name, per_m, loglog) in &s.slopes {
            println!(
                "sweep {:?}: {name}: {per_m:.4} ms per million {}, log-log slope {loglog:.3}",
                s.sweep, s.work
            );
        }
    }
    eprintln!(
        "wrote {} ({:.1} s)",
        out.join("bench.json").display(),
        report.total_s
    );
    check_validation(r.context())?;
    Ok(ExitCode::SUCCESS)
}
