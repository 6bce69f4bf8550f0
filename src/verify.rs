//! `verify`: every method's GPU image against its own formula in f64 (within the float32 bound
//! of the module doc of [`crate::truth`], or its float16 bound with `--precision f16`), and its
//! error against f64 exact Phong (the per-pixel error of [`crate::analysis::pixel`], the same
//! definition `compare` uses). In float16 the device's image is also judged against the
//! software engine's float16 twin ([`twin_agreement`]).
use crate::analysis::pixel::{error_stats, ErrorStats};
use crate::engine::{Engine, Ready};
use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::method::scanline;
use crate::method::{self, Method, Precision};
use crate::scene::{Scene, SceneInputs};
use crate::software;
use crate::truth::{agreement_at, evaluate, evaluate_at, Agreement, Truth};

/// One method's verdict.
#[derive(Debug, Clone, serde::Serialize)]
pub struct VerifyRow {
    pub method: &'static str,
    /// Against its own formula (or `against`'s): the float32-bound check.
    pub agreement: Agreement,
    /// Against f64 exact Phong.
    pub errors: ErrorStats,
    /// The Vulkan float16 image against the software engine's float16 image of the same
    /// method, within the sum of their two float16 bounds (None: not a float16 Vulkan run).
    pub twin: Option<Agreement>,
}

/// The result of [`verify`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct VerifyReport {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// The precision the programs computed in (the bound follows it).
    pub precision: Precision,
    /// The method whose formula judged every image, when not each method's own.
    pub against: Option<&'static str>,
    pub rows: Vec<VerifyRow>,
}

impl VerifyRow {
    /// Whether the image is within the bound of the formula it was judged by (and, in a
    /// float16 Vulkan run, within the bound of the software float16 twin).
    pub fn passed(&self) -> bool {
        self.agreement.within_bound() && self.twin.as_ref().is_none_or(Agreement::within_bound)
    }
}

impl VerifyReport {
    /// Whether every method passed.
    pub fn passed(&self) -> bool {
        self.rows.iter().all(VerifyRow::passed)
    }

    /// One line per method outside its bound, with the worst pixel and counts.
    pub fn failures(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter(|r| !r.passed())
            .map(|r| {
                let a = &r.agreement;
                let twin = r.twin.as_ref().map_or(String::new(), |w| {
                    format!(
                        "; against the float16 twin: ratio {:.3}, worst pixel {:?}, non-finite {}",
                        w.max_color_ratio.max(w.max_normal_ratio),
                        w.worst_pixel,
                        w.non_finite
                    )
                });
                format!(
                    "{} (ratio {:.3}, worst pixel {:?}, coverage mismatches {}, non-finite {}{twin})",
                    r.method,
                    a.max_color_ratio.max(a.max_normal_ratio),
                    a.worst_pixel,
                    a.coverage_mismatch,
                    a.non_finite
                )
            })
            .collect()
    }

    /// Whose formula judged the images, for messages: "their own" or "NAME's".
    pub fn judged_by(&self) -> String {
        self.against
            .map(|a| format!("{a}'s"))
            .unwrap_or_else(|| "their own".into())
    }

    /// The text table: a heading line, column names, one row per method.
    pub fn table(&self) -> String {
        let has_twin = self.rows.iter().any(|r| r.twin.is_some());
        let mut t = format!(
            "scene {} at {}x{} in {}: each method against {} f64 formula (error/bound <= 1 \
             passes), and against f64 exact Phong: |dI| = linear luminance error (ill-conditioned \
             sliver pixels left out; NaN/ill = non-finite pixels, well-/ill-conditioned; any \
             makes the errors inf){}\n",
            self.scene,
            self.width,
            self.height,
            self.precision,
            self.against
                .map(|a| format!("{a}'s"))
                .unwrap_or_else(|| "its own".into()),
            if has_twin {
                "; twin/bound = against the software engine's float16 twin, error over the sum \
                 of the two bounds (inf: a non-finite pixel)"
            } else {
                ""
            }
        );
        // The twin column only where a row has a twin (a float16 Vulkan run).
        let twin_cell = |r: &VerifyRow| match (&r.twin, has_twin) {
            (_, false) => String::new(),
            (None, true) => format!(" {:>10}", "-"),
            (Some(w), true) if w.non_finite > 0 => format!(" {:>10}", "inf"),
            (Some(w), true) => format!(" {:>10.3}", w.max_color_ratio.max(w.max_normal_ratio)),
        };
        t += &format!(
            "{:<32} {:>7} {:>9} {:>9}{} {:>6} | {:>9} {:>9} {:>8} {:>8} {:>10} {:>8}\n",
            "method",
            "pixels",
            "dI/bound",
            "dN/bound",
            if has_twin {
                format!(" {:>10}", "twin/bound")
            } else {
                String::new()
            },
            "ill",
            "max|dI|",
            "mean|dI|",
            "max deg",
            "mean deg",
            "max|len-1|",
            "NaN/ill"
        );
        let num = |v: f64, s: String| if v.is_finite() { s } else { "inf".into() };
        let opt = |v: Option<f64>, p: usize| match v {
            Some(x) => num(x, format!("{x:.p$}")),
            None => "-".into(),
        };
        for r in &self.rows {
            let (a, e) = (&r.agreement, &r.errors);
            let c = &e.counts;
            t += &format!(
                "{:<32} {:>7} {:>9.3} {:>9.3}{} {:>6} | {:>9} {:>9} {:>8} {:>8} {:>10} {:>8}\n",
                r.method,
                a.covered,
                a.max_color_ratio,
                a.max_normal_ratio,
                twin_cell(r),
                a.ill_conditioned,
                num(e.max_abs_error, format!("{:.2e}", e.max_abs_error)),
                num(e.mean_abs_error, format!("{:.2e}", e.mean_abs_error)),
                opt(e.max_normal_angle_deg, 3),
                opt(e.mean_normal_angle_deg, 3),
                opt(e.max_normal_length_error, 5),
                format!(
                    "{}/{}",
                    c.non_finite - c.non_finite_ill_conditioned,
                    c.non_finite_ill_conditioned
                ),
            );
        }
        t
    }
}

/// Renders every method of `methods` on `scene` with `engine` and judges its image by its own
/// f64 formula (or by `against`'s) within the float32 bound, evaluated at the engine's own
/// rasterizer weights (widened by the recurrence drift where the engine's form of the method
/// drifts: [`Engine::drifts`]), and against f64 exact Phong at those weights.
pub fn verify(
    engine: Engine,
    scene: &Scene,
    methods: &[&'static Method],
    against: Option<&'static Method>,
) -> Result<VerifyReport> {
    verify_at(engine, scene, methods, against, Precision::F32)
}

/// [`verify`] of the programs computing in `precision`: each image judged by the bound of that
/// precision ([`evaluate_at`]); in float16 on Vulkan, also against the software engine's
/// float16 twin ([`twin_agreement`]). The reference (f64 exact Phong) is the same.
pub fn verify_at(
    engine: Engine,
    scene: &Scene,
    methods: &[&'static Method],
    against: Option<&'static Method>,
    precision: Precision,
) -> Result<VerifyReport> {
    let exact = method::phong_exact();
    let mut all = methods.to_vec();
    all.push(exact);
    let ready = Ready::new(engine, scene, &all)?;
    let id_pass = || Error::Internal(format!("{}: no id frame came back", engine.name()));
    // The reference: f64 exact Phong at the engine's weights on the scene's own triangles.
    let (_, base_ids) = ready.render(exact, true)?;
    let reference = evaluate(ready.base(), &base_ids.ok_or_else(id_pass)?, exact);
    let mut rows = Vec::new();
    for &m in methods {
        let (frame, ids) = render_in(&ready, m, precision)?;
        let ids = ids.ok_or_else(id_pass)?;
        let inputs = ready.inputs(m)?;
        let mut truth = evaluate_at(inputs, &ids, against.unwrap_or(m), precision);
        if engine.drifts(m) {
            widen_for_drift(&mut truth, inputs, &ids, precision);
        }
        let twin = match (&ready, precision) {
            (Ready::Vulkan(..), Precision::F16) => {
                let (sw, _) =
                    software::render_at(inputs, m, software::default_threads(), false, precision)?;
                // The twin's own bound: the software engine's form of `m` may drift.
                let mut twin_truth = truth.clone();
                if software::form_of(m).drifts {
                    widen_for_drift(&mut twin_truth, inputs, &ids, precision);
                }
                Some(twin_agreement(&frame, &sw, &truth, &twin_truth))
            }
            _ => None,
        };
        rows.push(VerifyRow {
            method: m.name,
            agreement: agreement_at(&frame, &truth, precision),
            errors: error_stats(&frame, m.has_normal, &reference),
            twin,
        });
    }
    Ok(VerifyReport {
        scene: scene.name.clone(),
        width: scene.width,
        height: scene.height,
        precision,
        against: against.map(|a| a.name),
        rows,
    })
}

/// [`verify`] with the software engine (src/software/) on `threads` threads.
pub fn verify_software(
    scene: &Scene,
    methods: &[&'static Method],
    against: Option<&'static Method>,
    threads: usize,
) -> Result<VerifyReport> {
    verify(Engine::Software { threads }, scene, methods, against)
}

/// [`verify_at`] with the software engine on `threads` threads, computing in `precision`.
pub fn verify_software_at(
    scene: &Scene,
    methods: &[&'static Method],
    against: Option<&'static Method>,
    threads: usize,
    precision: Precision,
) -> Result<VerifyReport> {
    verify_at(
        Engine::Software { threads },
        scene,
        methods,
        against,
        precision,
    )
}

/// The frames of `m` computed in `precision`: the one place where a precision picks the
/// programs. Float32 is what `ready` renders; the software engine computes in any precision;
/// the Vulkan renderer draws the programs of the precision it was made with
/// (`Renderer::with_precision`); asking it for another precision is an internal error.
pub(crate) fn render_in(
    ready: &Ready,
    m: &Method,
    precision: Precision,
) -> Result<(Frame, Option<IdFrame>)> {
    match (ready, precision) {
        (Ready::Software { .. }, Precision::F32) => ready.render(m, true),
        (Ready::Software { threads, .. }, p) => {
            software::render_at(ready.inputs(m)?, m, *threads, true, p)
        }
        (Ready::Vulkan(r, _), p) if r.precision() == p => ready.render(m, true),
        (Ready::Vulkan(r, _), p) => Err(Error::Internal(format!(
            "verify {}: the renderer draws in {}, not {p} (Renderer::with_precision)",
            m.name,
            r.precision()
        ))),
    }
}

/// The device's float16 image against the software engine's float16 twin of the same method:
/// both are judged by the same f64 value, the device within `truth`'s float16 bound (at the
/// device's weights), the twin within `twin_truth`'s (the same, widened by the recurrence drift
/// where the software engine's form of the method drifts: [`software::drift_allowance_at`]),
/// so at every pixel they may differ by at most the sum of the two bounds; the software image
/// stands as the reference with that sum (the software engine's weights differ from the
/// device's by rasterizer rounding, inside the bound's interpolation term). Non-finite pixels
/// of either are failures, as everywhere.
pub fn twin_agreement(
    device: &Frame,
    twin: &Frame,
    truth: &Truth,
    twin_truth: &Truth,
) -> Agreement {
    let pixels = truth
        .pixels
        .iter()
        .zip(&twin_truth.pixels)
        .enumerate()
        .map(|(i, (t, w))| {
            let (t, w) = ((*t)?, (*w)?);
            let (c, n) = (twin.color[i], twin.normal[i]);
            let v = |a: [f32; 4]| glam::DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
            Some(crate::truth::TruthPixel {
                color: v(c),
                normal: t.normal.map(|_| v(n)),
                color_bound: t.color_bound + w.color_bound,
                normal_bound: t.normal_bound + w.normal_bound,
                ..t
            })
        })
        .collect();
    let reference = Truth {
        width: truth.width,
        height: truth.height,
        pixels,
    };
    agreement_at(device, &reference, Precision::F16)
}

/// Adds the recurrence drift of [`software::drift_allowance`] to each pixel's bound: `n` is the
/// pixel's distance from the first pixel centre of its triangle's span on that row (where the
/// recurrence starts), the normal allowance times `|N|`, the colour allowance that times the
/// largest slope of the lighting in a cosine (diffuse + shininess x specular, per light).
/// In float16 the allowance reaches the size of the normal itself on long spans, and a drifted
/// normal longer than 1 lights with N.H above 1: the specular slope `n s^(n-1)` is then taken
/// at the largest cosine the allowance permits, `1 + sqrt(3) d |N|` (mean value theorem: the
/// first-order slope at s <= 1 does not bound pow past 1). Float32 keeps the first-order slope
/// (its allowance stays far below 1/n on the shipped spans; its published figures stand).
fn widen_for_drift(truth: &mut Truth, inputs: &SceneInputs, ids: &IdFrame, precision: Precision) {
    let lit = inputs.lighting();
    let n_spec = lit.shininess.max(1.0);
    let slope = |reach: f64| -> f64 {
        lit.lights()
            .iter()
            .map(|&(_, c, _)| {
                (c * (lit.diffuse + lit.specular * n_spec * reach.powf(n_spec - 1.0))).max_element()
            })
            .sum()
    };
    for (i, px) in truth.pixels.iter_mut().enumerate() {
        let Some(p) = px else { continue };
        let t = ids.prim[i] as usize - 1;
        let (x, y) = (
            (i as u32 % ids.width) as f64 + 0.5,
            (i as u32 / ids.width) as f64 + 0.5,
        );
        let f = inputs.fragment(t, glam::DVec3::ZERO, glam::DVec2::new(x, y));
        let sp = scanline::span_at(y, scanline::corners(f.window), f.corner_normals);
        let n = (x - ((sp.xa - 0.5).ceil() + 0.5)).max(0.0) + 1.0;
        let d = software::drift_allowance_at(n, precision);
        let len = p.normal.map_or(1.0, |v| v.length().max(1.0));
        // (cosine's allowance, largest cosine): a component-wise d |N| moves N.v by up to
        // sqrt(3) d |N| for a unit v (float32 keeps its published first-order form).
        let (dcos, reach) = match precision {
            Precision::F32 => (d * len, 1.0),
            Precision::F16 => (3f64.sqrt() * d * len, 1.0 + 3f64.sqrt() * d * len),
        };
        p.normal_bound += d * len;
        p.color_bound += dcos * slope(reach);
    }
}
