//! The checks behind the method table's claims. Each runs an f64 sweep of the formula in
//! [`formulas`](super::formulas) when claims are written (`shadelab list --json`, and
//! `shadelab bench`'s claims.json/md) and derives its verdict from the number it measured, by
//! a rule stated in its `how`. No verdict is written by hand.
//!
//! Each check reads its row: the kernel's formula and the claim's kind (figure, criterion).
//! The checks here are sampled (basis found or measured); the bounds on a scaled method's
//! length error, which the proof judges, are in src/prove/bounds.rs; a claim no f64 formula
//! measures says which command judges it ([`judged_elsewhere`]).
//!
//! Each check's core takes the formula as a parameter, so a test can feed it a deliberately
//! wrong formula and see the verdict flip (the tests at the end). The sweep helpers here are
//! shared with the formulas tests, which pin the same figures against docs/formulas.md#methods.
use glam::DVec3;

use super::formulas as f;
#[cfg(test)]
pub(crate) use super::worst::worst;
pub(crate) use super::worst::Worst;
use super::{Claim, Evidence, Form, Kind, Measurement, Method, Quantity, Scale, Verdict};

/// A scalar factor `k(z) ~ 1/sqrt(z)`, `z = N.N`.
pub(crate) type Factor = fn(f64) -> f64;

/// Points per edge of a sweep: `t = i / STEPS`, i = 0..=STEPS.
pub(crate) const STEPS: usize = 100_000;

/// `t = i / STEPS`, i = 0..=STEPS, along an edge.
pub(crate) fn ts() -> impl Iterator<Item = f64> {
    (0..=STEPS).map(|i| i as f64 / STEPS as f64)
}

/// Two unit normals `theta` degrees apart, symmetric about +Z in the xz plane.
pub(crate) fn pair(theta_deg: f64) -> (DVec3, DVec3) {
    let h = (0.5 * theta_deg).to_radians();
    (
        DVec3::new(-h.sin(), 0.0, h.cos()),
        DVec3::new(h.sin(), 0.0, h.cos()),
    )
}

/// Angle between two vectors in degrees (atan2 form: accurate for tiny angles).
pub(crate) fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Signed relative length error `k(z)|N| - 1` in percent at the worst point of an edge whose
/// unit end normals are `theta` apart (docs/formulas.md#error-measures). The edge covers z in
/// [cos^2(theta/2), 1], so this is also the worst case over all angles up to `theta`.
#[cfg(test)]
pub(crate) fn scalar_error_pct(k: Factor, theta_deg: f64) -> f64 {
    scalar_error(k, theta_deg).value()
}

/// [`scalar_error_pct`]'s sweep, reduced by [`Worst`].
#[cfg(test)]
pub(crate) fn scalar_error(k: Factor, theta_deg: f64) -> Worst {
    edge_error(&|z| k(z) * z.sqrt() - 1.0, theta_deg)
}

/// A relative length error `err(z)` (a fraction) in percent at the worst point of an edge whose
/// unit end normals are `theta` apart, reduced by [`Worst`].
pub(crate) fn edge_error(err: &dyn Fn(f64) -> f64, theta_deg: f64) -> Worst {
    let (a, b) = pair(theta_deg);
    Worst::of(ts().map(|t| {
        let n = a.lerp(b, t);
        100.0 * err(n.dot(n))
    }))
}

/// The same length error over a triangle's interior: z from `z_lo` to 1. Three unit normals
/// `theta` apart pairwise have their centroid at |n|^2 = (1 + 2 cos theta)/3, below any point
/// of the edges (cos^2(theta/2)), so the interior reaches smaller z than an edge.
pub(crate) fn interior_error_of(err: &dyn Fn(f64) -> f64, theta_deg: f64) -> Worst {
    let z_lo = (1.0 + 2.0 * theta_deg.to_radians().cos()) / 3.0;
    Worst::of(ts().map(|t| 100.0 * err(z_lo + (1.0 - z_lo) * t)))
}

/// [`interior_error_of`] for the factor `k`.
#[cfg(test)]
pub(crate) fn interior_error(k: Factor, theta_deg: f64) -> Worst {
    interior_error_of(&|z| k(z) * z.sqrt() - 1.0, theta_deg)
}

/// The relative length error of a scaled kernel's normal at `z = N.N` (a fraction), with the
/// twin's operations: `k(z) sqrt(z) - 1`, or `sqrt(z)/s(z) - 1` for a divided one.
pub fn length_error_at(s: &Scale, z: f64) -> f64 {
    match s.form {
        Form::Over => z.sqrt() / s.factor.f64(z) - 1.0,
        Form::Times | Form::Exact => s.factor.f64(z) * z.sqrt() - 1.0,
    }
}

/// Mikami's normalised relative error `sqrt(z)/s1 - 1` in percent
/// (docs/formulas.md#mikami-square-root).
#[cfg(test)]
pub(crate) fn mikami_error_pct(z: f64, beta: Factor) -> f64 {
    100.0 * (z.sqrt() / f::mikami_sqrt(z, beta(z)) - 1.0)
}

/// Worst Mikami error on z in [lo, 1] (fine grid; docs/formulas.md#mikami-square-root sweeps
/// [0.25, 1]).
#[cfg(test)]
pub(crate) fn mikami_worst_pct(lo: f64, beta: Factor) -> f64 {
    Worst::of(ts().map(|t| mikami_error_pct(lo + (1.0 - lo) * t, beta))).value()
}

/// Worst angle (degrees) between `method(N)` and normalize(N) along the edge of a pair (NaN
/// when any point is not finite).
#[cfg(test)]
pub(crate) fn worst_edge_angle(theta_deg: f64, method: impl Fn(DVec3) -> DVec3) -> f64 {
    edge_angle(theta_deg, method).value()
}

/// [`worst_edge_angle`]'s sweep, reduced by [`Worst`].
#[cfg(test)]
pub(crate) fn edge_angle(theta_deg: f64, method: impl Fn(DVec3) -> DVec3) -> Worst {
    let (a, b) = pair(theta_deg);
    Worst::of(ts().map(|t| {
        let n = a.lerp(b, t);
        angle_deg(method(n), n)
    }))
}

/// A length error above this many percent counts as a visible error: the diffuse term scales
/// with the length, so 1 % is 2.6 of 255 levels at full intensity (our threshold; the seeds
/// state none).
pub const VISIBLE_LENGTH_ERROR_PCT: f64 = 1.0;

/// A length within this of 1 counts as exactly unit (f64 rounding of a few operations).
const UNIT_TOLERANCE: f64 = 1e-12;

pub(crate) fn sweep_how(formula: &str) -> String {
    format!(
        "f64 sweep of {formula} (src/method/formulas.rs) at {} points along an edge between two \
         unit vertex normals, run when this was written (src/method/checks.rs)",
        STEPS + 1
    )
}

// ---- claims that are not measured in f64 -----------------------------------------------------

/// A claim no f64 formula measures, by its kind: `not_checked` here, with the command that
/// judges it (a speed factor: `shadelab bench` in both engines; an operation count: bench's
/// SPIR-V count or isolated cost; a validity range of a method without a scale: `shadelab
/// stress` on the device).
pub fn judged_elsewhere(_: &Method, c: &Claim) -> Measurement {
    let how = match c.kind {
        Kind::Speed { factor, than } => format!(
            "a speed claim ({factor}x against {than}): no f64 formula measures it; `shadelab \
             bench` times it on this machine (paired rounds, both engines) and writes the \
             verdict to claims.json"
        ),
        Kind::OperationCount(Some(_)) => "an operation count: no f64 formula measures it; \
             `shadelab bench` counts the SPIR-V of phong_exact minus phong_unnormalized and \
             writes the verdict to claims.json (GLSL.std.450 Normalize at the counter's price, \
             its definition: 1 inverse square root + 6 mul + 2 add for a vec3; not a driver's \
             compiled count)"
            .into(),
        Kind::OperationCount(None) => "a cost statement: no f64 formula measures it; \
             `shadelab bench` measures each formula's isolated cost per fragment (bench.json \
             `isolated`) on this machine"
            .into(),
        Kind::Validity { up_to_deg, .. } => format!(
            "a validity range (up to {up_to_deg} degrees between the vertex normals) judged by \
             the rendered colour: `shadelab stress` judges it on the device (stress.json \
             `claims`)"
        ),
        Kind::ErrorBound(_) | Kind::Property => {
            "not measurable by an f64 formula of this row".into()
        }
    };
    Measurement {
        evidence: Evidence::MEASURED,
        measured: "-".into(),
        verdict: Verdict::NotChecked,
        how,
    }
}

// ---- newton_raphson ---------------------------------------------------------------------------

/// The colour criterion of "usable": one 8-bit level of a full-intensity diffuse term, in
/// percent of the length (the diffuse term scales with the length). `shadelab stress` judges
/// the same claim by the same 1/255 on the rendered colour.
pub const COLOUR_LEVEL_PCT: f64 = 100.0 / 255.0;

/// The NVIDIA formula exactly as the shading survey prints it: `N (3 - N.N) / 3`
/// (docs/formulas.md#newton-raphson-step).
fn k_newton_as_printed_in_s004(z: f64) -> f64 {
    (3.0 - z) / 3.0
}

/// "the shading survey prints N (3 - N.N)/3": is the printed formula a normalisation?
pub fn newton_as_printed_in_s004(_: &Method, _: &Claim) -> Measurement {
    printed_vs_corrected(k_newton_as_printed_in_s004, f::k_newton)
}

/// A normalisation must leave a unit vector unit: `k(1) = 1`. Disagrees when the printed
/// factor fails that and the corrected one (`/2`) passes; inconclusive when both fail.
pub(crate) fn printed_vs_corrected(printed: Factor, corrected: Factor) -> Measurement {
    let (p, c) = (printed(1.0), corrected(1.0));
    let unit = |k: f64| (k - 1.0).abs() <= UNIT_TOLERANCE;
    Measurement {
        evidence: Evidence::MEASURED,
        measured: format!("k(1) = {p:.6} as printed (/3); k(1) = {c:.6} with /2"),
        verdict: match (unit(p), unit(c)) {
            (true, _) => Verdict::Agrees,
            (false, true) => Verdict::Disagrees,
            (false, false) => Verdict::Inconclusive,
        },
        how: "evaluates the printed factor (3 - z)/3 and formulas::k_newton (3 - z)/2 at z = 1 \
              (a unit normal at a vertex); disagrees when the printed k(1) is not 1 and /2's is \
              (a seed typo)"
            .into(),
    }
}

// ---- lyon_taylor ------------------------------------------------------------------------------

/// "the approximation error is large" (docs/formulas.md#lyon-taylor-form) of a scaled
/// method: its row's formula swept.
pub fn error_is_large(m: &Method, c: &Claim) -> Measurement {
    match m.kernel {
        super::Kernel::Scaled(s) => error_is_large_of(&|z| length_error_at(&s, z), s.factor.name()),
        _ => judged_elsewhere(m, c),
    }
}

/// "Large" means above [`VISIBLE_LENGTH_ERROR_PCT`]; measured at 40 and 90 degrees: large at
/// both agrees, at neither disagrees, at one of them partly.
pub(crate) fn error_is_large_of(err: &dyn Fn(f64) -> f64, name: &str) -> Measurement {
    let (e40, e90) = (edge_error(err, 40.0), edge_error(err, 90.0));
    let large = |e: &Worst| e.finite.abs() > VISIBLE_LENGTH_ERROR_PCT;
    Measurement {
        evidence: Evidence::found(e90.value().abs() / 100.0, Quantity::RelativeError),
        measured: format!(
            "worst length error {:+.4} % at 40 deg{}, {:+.2} % at 90 deg{}",
            e40.finite,
            e40.note(),
            e90.finite,
            e90.note()
        ),
        verdict: match (large(&e40), large(&e90)) {
            _ if e40.non_finite + e90.non_finite > 0 => Verdict::Disagrees,
            (true, true) => Verdict::Agrees,
            (false, false) => Verdict::Disagrees,
            _ => Verdict::Partly,
        },
        how: format!(
            "{}; large = |length error| > {VISIBLE_LENGTH_ERROR_PCT} %: agrees if large at both \
             40 and 90 deg, partly if at one; any non-finite point disagrees",
            sweep_how(&format!("k(z)|N| - 1 with {name}"))
        ),
    }
}

// ---- hast_half_vector, quaternion: unit length without a square root ---------------------------

/// Angles between the vertex normals swept by the unit-length checks.
const UNIT_ANGLES: [f64; 4] = [40.0, 60.0, 90.0, 120.0];

/// "normalization without a square root" (docs/formulas.md#hast-barrera-bengtsson-half-vector) for
/// Hast-Barrera-Bengtsson.
pub fn hbb_is_unit(_: &Method, _: &Claim) -> Measurement {
    flat_based_is_unit(f::hbb)
}

/// Where the flat normal is put for [`flat_based_is_unit`]: the point at `s` along the arc
/// from the first vertex normal (0) to the second (1), turned `off_deg` degrees towards the
/// direction `dir_deg` (0: the pair plane's normal, 90: along the arc, onward). A real
/// triangle's flat normal need not lie on the arc between two of its vertex normals, so the
/// sweep leaves it: over every `s` and direction these are the flat normals within `off_deg`
/// of the arc (beyond its ends too).
pub(crate) fn flat_off_arc((a, b): (DVec3, DVec3), s: f64, off_deg: f64, dir_deg: f64) -> DVec3 {
    let on = super::scanline::slerp(a, b, s);
    let across = a.cross(b).normalize();
    let along = across.cross(on);
    let (sd, cd) = dir_deg.to_radians().sin_cos();
    let (so, co) = off_deg.to_radians().sin_cos();
    on * co + (across * cd + along * sd) * so
}

/// Distances of the flat normal from the arc between the vertex normals, degrees.
pub(crate) const FLAT_OFFSETS: [f64; 3] = [0.0, 10.0, 20.0];

/// Positions of the flat normal along the arc: `s = i / FLAT_STEPS`.
const FLAT_STEPS: u32 = 10;

/// The flat normals of [`flat_based_is_unit`] `off` degrees from the arc of the pair `p`: 11
/// positions along it, each turned towards 12 directions (30-degree steps; one, on the arc,
/// for `off` = 0).
fn flats(p: (DVec3, DVec3), off: f64) -> impl Iterator<Item = DVec3> {
    let dirs = if off == 0.0 { 1 } else { 12 };
    (0..=FLAT_STEPS).flat_map(move |i| {
        (0..dirs).map(move |d| {
            flat_off_arc(
                p,
                f64::from(i) / f64::from(FLAT_STEPS),
                off,
                30.0 * f64::from(d),
            )
        })
    })
}

/// The length of `method(lerp, flat)` along edges 40..120 degrees wide, the flat normal on the
/// arc between the vertex normals (11 positions, vertex normals and bisector included) and up
/// to [`FLAT_OFFSETS`] off it ([`flats`]): agrees when it is 1 to 1e-12 everywhere (the result
/// needs no normalisation, so no square root). Also prints the angle error against
/// normalize(lerp) at 90 degrees, for each distance the least and the largest over the flat
/// normals at that distance, each with the domain it was measured on.
pub(crate) fn flat_based_is_unit(method: fn(DVec3, DVec3) -> DVec3) -> Measurement {
    let mut dev = Worst::default();
    for theta in UNIT_ANGLES {
        let (a, b) = pair(theta);
        for off in FLAT_OFFSETS {
            for flat in flats((a, b), off) {
                for t in ts().step_by(100) {
                    dev.push((method(a.lerp(b, t), flat).length() - 1.0).abs());
                }
            }
        }
    }
    let (a, b) = pair(90.0);
    let angles: Vec<String> = FLAT_OFFSETS
        .iter()
        .map(|&off| {
            // on the arc every point of the edge (the 3.17 of docs/formulas.md#hast-barrera-bengtsson-half-vector sits at 3.165004),
            // off it every hundredth
            let step = if off == 0.0 { 1 } else { 100 };
            let (least, most) = flats((a, b), off)
                .map(|flat| {
                    Worst::of(ts().step_by(step).map(|t| {
                        let n = a.lerp(b, t);
                        angle_deg(method(n, flat), n)
                    }))
                    .value()
                })
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
                    if e.is_nan() || lo.is_nan() {
                        (f64::NAN, f64::NAN)
                    } else {
                        (lo.min(e), hi.max(e))
                    }
                });
            let domain = if off == 0.0 {
                "the flat normal on the arc between the vertex normals".to_string()
            } else {
                format!(
                    "the flat normal {off} deg off that arc (any direction, beyond its ends too)"
                )
            };
            format!("{least:.2} to {most:.1} deg with {domain}")
        })
        .collect();
    unit_measurement(
        dev,
        format!(
            ", angle error vs normalize(lerp) at 90 deg (least to largest over where the flat \
             normal is): {}",
            angles.join("; ")
        ),
        &format!(
            "formulas::hbb, flat normal at {} positions along the arc between the vertex \
             normals and {FLAT_OFFSETS:?} deg off it in 12 directions; the angle error along the \
             edge at {} points with the flat normal on the arc, {} off it",
            FLAT_STEPS + 1,
            STEPS + 1,
            STEPS / 100 + 1
        ),
        STEPS / 100 + 1,
    )
}

/// "no square root needed" (docs/formulas.md#quaternion-interpolation) for Hast's quaternion
/// interpolation.
pub fn quaternion_is_unit(_: &Method, _: &Claim) -> Measurement {
    quaternion_recovery_is_unit(f::normal_from_quat)
}

/// The length of `recover(lerp(q_a, q_b))` along edges 40..120 degrees wide: agrees when it is
/// 1 to 1e-12 everywhere. Also prints the angle error against normalize(lerp) at 90 degrees,
/// worst over the frames of the method's whole validity ([`quaternion_angle_over_frames`]),
/// and over those whose vertex normals both face the viewer.
pub(crate) fn quaternion_recovery_is_unit(recover: fn(DVec3) -> DVec3) -> Measurement {
    let mut dev = Worst::default();
    for theta in UNIT_ANGLES {
        let (a, b) = pair(theta);
        let (qa, qb) = (f::quat_from_normal(a), f::quat_from_normal(b));
        for t in ts() {
            dev.push((recover(qa.lerp(qb, t)).length() - 1.0).abs());
        }
    }
    let symmetric = quaternion_angle(recover, pair(90.0), 10);
    let frames = quaternion_angle_over_frames(recover, 90.0);
    let at = |f: &QuatFrame| {
        format!(
            "{:.2} deg{} (bisector tilted {} deg from +Z, pair spread {} deg from the tilt \
             plane, lowest n_z {:.3})",
            f.worst.finite,
            f.worst.note(),
            f.tilt_deg,
            f.spread_deg,
            f.lowest_nz
        )
    };
    unit_measurement(
        dev,
        format!(
            ", angle error vs normalize(lerp) at 90 deg: {:.2} deg with the pair symmetric \
             about +Z; worst over frames with both vertex normals facing the viewer (n_z >= 0) \
             {}; over the whole validity (n_z > -1) {}: an edge passing near -Z is \
             interpolated the long way round",
            symmetric.value(),
            at(&frames.facing),
            at(&frames.all),
        ),
        &format!(
            "formulas::normal_from_quat of the lerped formulas::quat_from_normal; the angle \
             error over frames: the pair's bisector tilted 0..180 deg from +Z in 1-degree steps, \
             its spread 0..150 deg from the tilt plane in 30-degree steps, frames with a vertex \
             normal within {QUAT_NZ_MARGIN:e} of n_z = -1 left out, {} points per edge",
            STEPS / 100 + 1
        ),
        STEPS + 1,
    )
}

/// The angle between `recover(lerp(q_a, q_b))` and `lerp(a, b)` along the edge `a`-`b`, at
/// every `step`-th point of [`ts`].
fn quaternion_angle(recover: fn(DVec3) -> DVec3, (a, b): (DVec3, DVec3), step: usize) -> Worst {
    let (qa, qb) = (f::quat_from_normal(a), f::quat_from_normal(b));
    Worst::of(
        ts().step_by(step)
            .map(|t| angle_deg(recover(qa.lerp(qb, t)), a.lerp(b, t))),
    )
}

/// The worst angle error over a set of frames and the frame that gave it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct QuatFrame {
    pub worst: Worst,
    pub tilt_deg: u32,
    pub spread_deg: u32,
    /// The smaller n_z of the frame's two vertex normals.
    pub lowest_nz: f64,
}

impl QuatFrame {
    /// Folds in one frame: the counts add up, the worst finite value is the larger, and the
    /// frame named is the worst one (the first with a non-finite point, once there is one).
    fn add(&mut self, f: QuatFrame) {
        let (non_finite, points) = (
            self.worst.non_finite + f.worst.non_finite,
            self.worst.points + f.worst.points,
        );
        let finite = self.worst.finite.max(f.worst.finite);
        if self.worst.non_finite == 0
            && (f.worst.non_finite > 0 || f.worst.finite > self.worst.finite)
        {
            *self = f;
        }
        self.worst = Worst {
            finite,
            non_finite,
            points,
        };
    }
}

/// [`quaternion_angle_over_frames`]: the whole validity, and the frames facing the viewer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct QuatFrames {
    pub all: QuatFrame,
    pub facing: QuatFrame,
}

/// How close to -Z a vertex normal of a swept frame may come: the quaternion's 1/sqrt(1 + n_z)
/// is singular at n_z = -1, which the validity (n_z > -1) leaves out; 1e-6 is 0.08 degrees.
const QUAT_NZ_MARGIN: f64 = 1e-6;

/// The quaternion of a normal is taken in a fixed frame (+Z), so its angle error depends on
/// where the pair sits. Turning the pair about +Z turns the quaternions with it, so every pair
/// `theta` apart is, up to that turn, a pair whose bisector is tilted 0..=180 degrees from +Z
/// (1-degree steps) and whose spread makes 0..180 degrees with the tilt plane (30-degree
/// steps): that is the method's whole validity (both n_z > -1; frames with a normal within
/// [`QUAT_NZ_MARGIN`] of -Z are left out), swept at 1,001 points per edge. Returns the worst
/// over all of them and over those whose vertex normals both face the viewer (n_z >= 0).
pub(crate) fn quaternion_angle_over_frames(recover: fn(DVec3) -> DVec3, theta: f64) -> QuatFrames {
    let mut all = QuatFrame::default();
    let mut facing = QuatFrame::default();
    for tilt in 0..=180u32 {
        let r = glam::DQuat::from_rotation_y(f64::from(tilt).to_radians());
        for spread in (0..180u32).step_by(30) {
            let spin = glam::DQuat::from_rotation_z(f64::from(spread).to_radians());
            let (a, b) = pair(theta);
            let (a, b) = (r * (spin * a), r * (spin * b));
            let lowest_nz = a.z.min(b.z);
            if lowest_nz <= -1.0 + QUAT_NZ_MARGIN {
                continue;
            }
            let w = quaternion_angle(recover, (a, b), 100);
            let frame = QuatFrame {
                worst: w,
                tilt_deg: tilt,
                spread_deg: spread,
                lowest_nz,
            };
            all.add(frame);
            if lowest_nz >= 0.0 {
                facing.add(frame);
            }
        }
    }
    QuatFrames { all, facing }
}

/// The unit-length verdict of a sweep of `points` points per edge (`what`: the formula and
/// where the sweep goes).
fn unit_measurement(dev: Worst, extra: String, what: &str, points: usize) -> Measurement {
    Measurement {
        evidence: Evidence::found(dev.value(), Quantity::RelativeError),
        measured: format!("max ||N'| - 1| = {:.1e}{}{extra}", dev.finite, dev.note()),
        verdict: if dev.within(UNIT_TOLERANCE) {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "f64 sweep of |N'| (src/method/formulas.rs) at {points} points along an edge between \
             two unit vertex normals, run when this was written (src/method/checks.rs) ({what}; \
             edges {UNIT_ANGLES:?} deg); agrees when |N'| = 1 to {UNIT_TOLERANCE:e} everywhere, \
             i.e. the result needs no square root to be unit"
        ),
    }
}

// ---- trueform ---------------------------------------------------------------------------------

/// The PN tessellator's signature (`formulas::pn_tessellate`).
pub(crate) type Tessellator = fn([DVec3; 3], [DVec3; 3], u32) -> Vec<([DVec3; 3], [DVec3; 3])>;

/// "9 sub-triangles per triangle: 2 extra vertices per edge + 1 centre"
/// (docs/formulas.md#pn-triangles-and-trueform).
pub fn trueform_level_3_counts(_: &Method, _: &Claim) -> Measurement {
    tessellation_counts(f::pn_tessellate)
}

/// Not checked: the count is a property of the tessellation pattern the seed describes, and
/// the only tessellator here (`formulas::pn_tessellate`) was written from that same
/// description, so counting its output would confirm the description by itself. The count it
/// gives is printed, as what this project draws, not as a verdict.
pub(crate) fn tessellation_counts(tessellate: Tessellator) -> Measurement {
    let n = [
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(0.3, 0.0, 1.0),
        DVec3::new(0.0, 0.3, 1.0),
    ]
    .map(|v| v.normalize());
    let tris = tessellate(n, n, 3);
    let mut distinct: Vec<[u64; 3]> = tris
        .iter()
        .flat_map(|(ps, _)| ps.iter().map(|v| v.to_array().map(f64::to_bits)))
        .collect();
    distinct.sort_unstable();
    distinct.dedup();
    let (t, v) = (tris.len(), distinct.len());
    Measurement {
        evidence: Evidence::MEASURED,
        measured: format!(
            "this project's level-3 tessellation (formulas::pn_tessellate): {t} triangles, {v} \
             distinct vertices"
        ),
        verdict: Verdict::NotChecked,
        how: "not checked: the claim describes the pattern of ATI's tessellator, which is not \
              available here; formulas::pn_tessellate was written from the same description, so \
              its count (printed) cannot test the claim"
            .into(),
    }
}

// ---- specular_lut -----------------------------------------------------------------------------

/// "tables for n = 1..255 need more than 4 MB" (docs/formulas.md#specular-table).
pub fn specular_lut_over_4_mb(_: &Method, _: &Claim) -> Measurement {
    lut_bytes(f::specular_lut)
}

/// Not checked: the size of a cos^n table is rows x samples x bytes per entry, and the seed
/// gives neither the sample count nor the entry size, so any size can be reached by choosing
/// them (this project's 4096 f32 samples were chosen to match the figure). The size of the
/// table this project builds is printed, as a figure, not as a verdict.
pub(crate) fn lut_bytes(build: fn(usize, usize) -> Vec<f32>) -> Measurement {
    let table = build(f::LUT_ROWS, f::LUT_SAMPLES);
    let bytes = std::mem::size_of_val(table.as_slice());
    Measurement {
        evidence: Evidence::MEASURED,
        measured: format!(
            "this project's table: {} exponents x {} cosines x 32 bit = {bytes} bytes ({:.2} MB)",
            f::LUT_ROWS,
            f::LUT_SAMPLES,
            bytes as f64 / 1e6
        ),
        verdict: Verdict::NotChecked,
        how: "not checked: the seed states neither the samples per row nor the bytes per entry, \
              so the size is not measurable from the claim (it follows from those two choices; \
              LUT_SAMPLES = 4096 was chosen to give the seed's figure)"
            .into(),
    }
}

#[cfg(test)]
mod tests {
    //! Teeth: every check's core fed a deliberately wrong formula must change its verdict.
    use super::*;

    /// The verdict of claim `i` of row `name`, judged by its check.
    fn judged(name: &str, i: usize) -> Measurement {
        let m = crate::method::find(name).unwrap();
        m.claims[i]
            .judge_without_proof(m)
            .expect("a claim this layer checks")
    }

    #[test]
    fn the_table_checks_give_the_verdicts_of_formulas_md_section_3() {
        let v = |name, i| judged(name, i).verdict;
        assert_eq!(v("newton_raphson", 1), Verdict::Disagrees);
        assert_eq!(v("lyon_taylor", 0), Verdict::Partly);
        assert_eq!(v("hast_half_vector", 0), Verdict::Agrees);
        assert_eq!(v("quaternion", 0), Verdict::Agrees);
        assert_eq!(v("trueform", 0), Verdict::NotChecked);
        assert_eq!(v("specular_lut", 0), Verdict::NotChecked);
        assert_eq!(v("gouraud", 0), Verdict::NotChecked);
    }

    #[test]
    fn a_claim_judged_elsewhere_says_where_by_its_kind() {
        let how = |name, i| judged(name, i).how;
        assert!(how("gouraud", 0).contains("`shadelab bench` times it"));
        assert!(how(crate::method::PHONG_EXACT, 0).contains("counts the SPIR-V"));
        assert!(how("slerp", 0).contains("isolated cost"));
        assert!(how("dichotomy_poly1", 1).contains("`shadelab stress` judges it"));
        assert!(how("dichotomy_poly1", 2).contains("2.5x against dichotomy_exact"));
    }

    #[test]
    fn worst_counts_non_finite_points_and_fails_them() {
        let w = Worst::of([0.5, -2.0, 1.0].into_iter());
        assert_eq!((w.finite, w.non_finite, w.points), (-2.0, 0, 3));
        assert!(w.within(2.0) && !w.within(1.9));
        assert_eq!(w.note(), "");
        let w = Worst::of([0.5, f64::NAN, f64::INFINITY, -0.1].into_iter());
        assert_eq!((w.finite, w.non_finite, w.points), (0.5, 2, 4));
        assert!(!w.within(f64::INFINITY), "a NaN point passed");
        assert!(w.value().is_nan());
        assert_eq!(w.note(), " (2 of 4 points non-finite)");
        // the old fold(0.0, f64::max) read an all-NaN sweep as 0
        assert!(worst([f64::NAN].into_iter()).is_nan());
        assert!(worst_edge_angle(90.0, |_| DVec3::NAN).is_nan());
    }

    #[test]
    fn every_f64_check_fails_on_a_nan_with_its_count() {
        let nan = |_: f64| f64::NAN;
        // NaN at z = 1 only (the two ends of an edge sweep), finite elsewhere
        let nan_at_1 = |z: f64| if z == 1.0 { f64::NAN } else { 0.0 };
        for m in [
            error_is_large_of(&nan, "NaN"),
            error_is_large_of(&nan_at_1, "NaN at 1"),
            flat_based_is_unit(|_, _| DVec3::NAN),
            quaternion_recovery_is_unit(|_| DVec3::NAN),
        ] {
            assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
            assert!(m.measured.contains("points non-finite)"), "{m:?}");
        }
        let m = error_is_large_of(&nan_at_1, "NaN at 1");
        assert!(
            m.measured.contains("(2 of 100001 points non-finite)"),
            "{m:?}"
        );
    }

    #[test]
    fn the_interior_reaches_below_the_edge() {
        // (1 + 2 cos 90)/3 = 1/3 < cos^2(45) = 1/2
        let (edge, inside) = (
            scalar_error(f::k_lyon2, 90.0),
            interior_error(f::k_lyon2, 90.0),
        );
        assert!(
            inside.finite.abs() > edge.finite.abs(),
            "{inside:?} {edge:?}"
        );
    }

    #[test]
    fn the_quaternion_angle_error_is_the_worst_over_frames() {
        let frames = quaternion_angle_over_frames(f::normal_from_quat, 90.0);
        let symmetric = quaternion_angle(f::normal_from_quat, pair(90.0), 10).value();
        assert!((symmetric - 3.17).abs() < 0.01, "{symmetric}");
        // facing the viewer: 19.47 deg, the pair across a 90-degree tilt
        let facing = frames.facing;
        assert!(
            (facing.worst.finite - 19.47).abs() < 0.01 && facing.worst.non_finite == 0,
            "{facing:?}"
        );
        assert!(
            facing.lowest_nz >= 0.0 && facing.tilt_deg == 90,
            "{facing:?}"
        );
        // the whole validity (n_z > -1) reaches past a 90-degree tilt, where an edge whose arc
        // passes through -Z turns the normal the long way round, to the opposite direction
        // (the old sweep stopped at 90 degrees)
        let all = frames.all;
        assert!(all.tilt_deg > 90 && all.lowest_nz < 0.0, "{all:?}");
        assert!(
            all.worst.finite > 179.99 && all.worst.non_finite == 0,
            "{all:?}"
        );
        assert!(all.worst.points > 180 * 6 * 1000, "{all:?}");
        let m = judged("quaternion", 0);
        assert!(
            m.measured
                .contains("over the whole validity (n_z > -1) 180.00 deg")
                && m.measured
                    .contains("facing the viewer (n_z >= 0) 19.47 deg"),
            "{m:?}"
        );
    }

    /// Hast-Barrera-Bengtsson's "3.17 to 10.3 deg" holds for flat normals on the arc between
    /// the vertex normals; each figure names its domain, and the sweep leaves the arc (12.4
    /// and 14.8 deg at 10 and 20 deg off it, beyond a vertex normal; the old figure named the
    /// bisector and a vertex normal only).
    #[test]
    fn the_hbb_angle_figures_name_where_the_flat_normal_is() {
        let m = judged("hast_half_vector", 0);
        assert_eq!(m.verdict, Verdict::Agrees, "{m:?}");
        for part in [
            "3.17 to 10.3 deg with the flat normal on the arc between the vertex normals",
            "to 12.4 deg with the flat normal 10 deg off that arc",
            "to 14.8 deg with the flat normal 20 deg off that arc",
        ] {
            assert!(m.measured.contains(part), "{part}: {m:?}");
        }
        // the flat normals lie `off` degrees from their point on the arc, unit, in the pair's
        // plane beyond the second vertex normal for the direction 90 at s = 1
        let p = pair(90.0);
        for (s, off, dir) in [(0.5, 10.0, 0.0), (0.3, 20.0, 210.0), (1.0, 10.0, 90.0)] {
            let f = flat_off_arc(p, s, off, dir);
            let on = crate::method::scanline::slerp(p.0, p.1, s);
            assert!((f.length() - 1.0).abs() < 1e-12);
            assert!((angle_deg(f, on) - off).abs() < 1e-9, "{s} {off} {dir}");
        }
        let beyond = flat_off_arc(p, 1.0, 10.0, 90.0);
        assert!(beyond.y.abs() < 1e-12 && (angle_deg(beyond, p.0) - 100.0).abs() < 1e-9);
        // teeth: the figures follow the method: exact normalisation has no angle error
        let exact = flat_based_is_unit(|n, _| n.normalize());
        assert!(
            exact
                .measured
                .contains("0.00 to 0.0 deg with the flat normal 20"),
            "{exact:?}"
        );
    }

    #[test]
    fn printed_formula_check_flips_when_the_printed_factor_is_right() {
        assert_eq!(
            printed_vs_corrected(f::k_newton, f::k_newton).verdict,
            Verdict::Agrees
        );
        let m = printed_vs_corrected(k_newton_as_printed_in_s004, k_newton_as_printed_in_s004);
        assert_eq!(m.verdict, Verdict::Inconclusive, "{m:?}");
    }

    #[test]
    fn unit_length_checks_flip_for_a_method_that_does_not_normalise() {
        let m = flat_based_is_unit(|n, _| n);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
        let m = quaternion_recovery_is_unit(|q| q);
        assert_eq!(m.verdict, Verdict::Disagrees, "{m:?}");
    }

    #[test]
    fn error_is_large_flips_for_other_factors() {
        // k = 1 (no normalisation) is large at both angles (-6.0 %, -29 %).
        let one = error_is_large_of(&|z: f64| z.sqrt() - 1.0, "k = 1");
        assert_eq!(one.verdict, Verdict::Agrees);
        // Exact 1/sqrt(z) has no error: never large.
        let exact = error_is_large_of(&|z: f64| 1.0 / z.sqrt() * z.sqrt() - 1.0, "exact");
        assert_eq!(exact.verdict, Verdict::Disagrees, "{exact:?}");
    }

    #[test]
    fn tessellation_and_lut_are_not_checked_and_print_what_they_measured() {
        // Not verdicts: whatever the builder, not_checked; the figures follow the builder.
        let m = tessellation_counts(f::pn_tessellate);
        assert!(m.measured.contains("9 triangles, 10 distinct"), "{m:?}");
        let m = tessellation_counts(|p, n, _| f::pn_tessellate(p, n, 2));
        assert_eq!(m.verdict, Verdict::NotChecked, "{m:?}");
        assert!(!m.measured.contains("9 triangles"), "{m:?}");
        let m = lut_bytes(|rows, samples| f::specular_lut(rows, samples / 2));
        assert_eq!(m.verdict, Verdict::NotChecked, "{m:?}");
        assert!(m.measured.contains("2088960 bytes"), "{m:?}");
        assert!(m.how.contains("not measurable"), "{m:?}");
    }
}
