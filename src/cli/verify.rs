//! `shadelab verify`: every method against its f64 twin, within the float32 bound.
use std::process::ExitCode;

use super::*;
use crate::error::{Error, Result};
use crate::gpu::Shading;
use crate::method::{self};
use crate::truth;
pub(super) fn cmd_verify(
    scene_args: &SceneArgs,
    dev: &DeviceArgs,
    list: &str,
    against: Option<&str>,
) -> Result<ExitCode> {
    let methods = select_methods(list)?;
    let against = against.map(method::find).transpose()?;
    let scene = load_scene(scene_args)?;
    let r = renderer(dev)?;
    let exact = method::find("phong_exact")?;
    let mut all = methods.clone();
    all.push(exact);
    let prepared = r.prepare(&scene, &all)?;
    // The reference: f64 exact Phong at the rasterizer's weights on the scene's own triangles.
    let (_, base_ids) = r.render(prepared.base(), Shading::Method(exact), true)?;
    let base_ids = base_ids.ok_or_else(|| Error::Device("the id pass returned nothing".into()))?;
    let reference = truth::evaluate(&prepared.base().inputs, &base_ids, exact);
    println!(
        "scene {} at {}x{}: each method against its own f64 formula (error/bound <= 1 passes), and against f64 exact \
         Phong (ill-conditioned sliver pixels left out; NaN/ill = non-finite pixels, well-/ill-conditioned)",
        scene.name, scene.width, scene.height
    );
    println!(
        "{:<32} {:>7} {:>9} {:>9} {:>6} | {:>9} {:>9} {:>8} {:>8} {:>10} {:>8}",
        "method",
        "pixels",
        "dI/bound",
        "dN/bound",
        "ill",
        "max|dI|",
        "mean|dI|",
        "max deg",
        "mean deg",
        "max|len-1|",
        "NaN/ill"
    );
    let opt = |v: Option<f64>, prec: usize| {
        v.map(|x| format!("{x:.prec$}"))
            .unwrap_or_else(|| "-".into())
    };
    let mut failed = Vec::new();
    for m in methods {
        let gpu = prepared.for_method(m);
        let (frame, ids) = r.render(gpu, Shading::Method(m), true)?;
        let ids = ids.ok_or_else(|| Error::Device("the id pass returned nothing".into()))?;
        let a = truth::agreement(
            &frame,
            &truth::evaluate(&gpu.inputs, &ids, against.unwrap_or(m)),
        );
        let e = crate::analysis::pixel::error_stats(&frame, m.has_normal, &reference);
        if !a.within_bound() {
            failed.push(format!(
                "{} (ratio {:.3}, worst pixel {:?}, coverage mismatches {}, non-finite {})",
                m.name,
                a.max_color_ratio.max(a.max_normal_ratio),
                a.worst_pixel,
                a.coverage_mismatch,
                a.non_finite
            ));
        }
        println!(
            "{:<32} {:>7} {:>9.3} {:>9.3} {:>6} | {:>9.2e} {:>9.2e} {:>8} {:>8} {:>10} {:>8}",
            m.name,
            a.covered,
            a.max_color_ratio,
            a.max_normal_ratio,
            a.ill_conditioned,
            e.max_abs_error,
            e.mean_abs_error,
            opt(e.max_normal_angle_deg, 3),
            opt(e.mean_normal_angle_deg, 3),
            opt(e.max_normal_length_error, 5),
            format!("{}/{}", e.non_finite, e.non_finite_ill_conditioned),
        );
    }
    check_validation(r.context())?;
    if failed.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        let whose = against
            .map(|a| format!("{}'s", a.name))
            .unwrap_or_else(|| "their own".into());
        eprintln!(
            "outside the float32 bound of {whose} formula: {}",
            failed.join("; ")
        );
        Ok(ExitCode::from(EXIT_THRESHOLD))
    }
}
