//! Each candidate's length and colour error over a domain of z, proven by `prove`'s interval
//! branch-and-bound, for the program as it computes: in float32 or float16, with its
//! coefficients rounded to the format and every operation rounded ([`super::rounded`]).
//!
//! The program computes `n^ = n` converted to the format (float16: each component within one
//! ulp u_in; float32: the varying itself, u_in = 0), `z^ = dot(n^, n^)` (three products and two
//! sums of non-negative terms: within (1 + u)^3 - 1 relative), `k^ = k(z^)` in the format, and
//! `N' = n^ k^` (each component within one ulp u). So `|N'| = sqrt(z) k^ rho` with rho within
//! (1 -+ u_in)(1 -+ u), and `|N'| - 1 = [sqrt(z) k(z) - 1] + sqrt(z) (k^ - k(z)) rho +
//! sqrt(z) k(z) (rho - 1)`: the bracket (the real formula) is enclosed in the mean-value form
//! (tight near z = 1, where it cancels), the rest (the rounding, small) by [`Rounded`]. The
//! direction turns by at most asin(u_in) + asin(u) <= (u_in + u)(1 + 1e-6) while k^ > 0, which
//! the length bound proves where it is below 1.
//!
//! The colour error follows from these three bounds through the lighting's derivatives
//! ([`crate::prove::colour_slope`], per light and channel of the scene's material, summed over
//! the lights). The found value is the real formula's error at a real z of the domain (a lower
//! bound of the maximum); the branch-and-bound stops when the bound is within 1 % of it plus
//! the rounding's allowance over the whole domain.
use serde::Serialize;

use super::candidate::Candidate;
use crate::method::kernel::Evaluate;
use crate::method::real::Real;
use crate::method::rounded::{Format, Rounded, F16, F32};
use crate::method::Precision;
use crate::prove::bnb::{self, Effort};
use crate::prove::dual::{mean_value, Dual};
use crate::prove::interval::Interval;

/// The lighting a colour bound is for: per light, its colour; the material's diffuse and
/// specular (linear RGB, as uploaded in float32) and exponent.
#[derive(Debug, Clone, Serialize)]
pub struct Lights {
    pub colours: Vec<[f64; 3]>,
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
    pub shininess: f64,
}

impl Lights {
    /// The colour bound from the normal-space bounds: per channel, the sum over the lights of
    /// colour x (k_d, k_s slope bound); the largest channel. None when not provable.
    pub fn colour(&self, e: f64, e_plus: f64, a: f64) -> Option<f64> {
        let mut worst = 0.0f64;
        for ch in 0..3 {
            let per = crate::prove::colour_slope(
                e,
                e_plus,
                a,
                self.shininess,
                self.diffuse[ch],
                self.specular[ch],
            )?;
            let sum: f64 = self.colours.iter().map(|c| c[ch]).sum();
            worst = worst.max(sum * per);
        }
        // the products and the sum within a few ulps
        Some(worst * (1.0 + 1e-12))
    }
}

/// What was proven about one candidate in one precision.
#[derive(Debug, Clone, Serialize)]
pub struct Bound {
    pub precision: Precision,
    /// Proven largest `| |N'| - 1 |` of the program (null: nothing finite).
    pub length_error: Option<f64>,
    /// Proven largest `|N'| - 1`.
    pub length_error_signed: Option<f64>,
    /// Proven largest angle between N' and the exact normal, radians.
    pub angle_rad: f64,
    /// The colour bound (null: not provable).
    pub colour: Option<f64>,
    /// The real formula's largest length error found at a real z of the domain (null: none
    /// finite).
    pub found_length_error: Option<f64>,
    /// The rounding's share: the largest |program - real formula| over the domain, relative.
    pub rounding_allowance: f64,
    /// Both branch-and-bounds converged within the tolerance.
    pub converged: bool,
    pub boxes: usize,
    pub seconds: f64,
}

impl Bound {
    /// Proven within `budget` (a colour error).
    pub fn within(&self, budget: f64) -> bool {
        self.colour.is_some_and(|c| c <= budget)
    }
}

/// The effort of the branch-and-bounds: tolerance, boxes and seconds.
#[derive(Debug, Clone, Copy)]
pub struct ProofEffort {
    pub tolerance: f64,
    pub max_boxes: usize,
    pub max_seconds: f64,
}

impl Default for ProofEffort {
    fn default() -> Self {
        ProofEffort {
            tolerance: 0.01,
            max_boxes: 20_000,
            max_seconds: 2.0,
        }
    }
}

/// An enclosure of `|N'| - 1` of the program in format `F` over z in `z`, and of the rounding's
/// share in it.
pub fn length_error<F: Format>(c: &Candidate, z: Interval) -> (Interval, Interval)
where
    Rounded<F>: Evaluate,
{
    let one = Interval::point(1.0);
    let real = real_length_error(c, z);
    let (u, u_in) = (F::ULP, input_ulp::<F>());
    let up = |x: f64| x.next_up();
    let gamma = up(up(3.0 * u) + up(3.0 * u * u) + up(u * u * u));
    let (lo_in, hi_in) = (
        (1.0 - u_in) * (1.0 - u_in),
        up(up((1.0 + u_in) * (1.0 + u_in))),
    );
    let rel = Interval::new(
        (lo_in * (1.0 - gamma)).next_down() - 1.0,
        up(up(hi_in * (1.0 + gamma)) - 1.0),
    );
    let e_in = z * rel + Interval::new(-3.0 * F::TINY, 3.0 * F::TINY);
    let r = c.k(Rounded::<F>::input(z, e_in));
    let rho = Interval::new(
        ((1.0 - u_in) * (1.0 - u)).next_down(),
        up((1.0 + u_in) * (1.0 + u)),
    );
    let sz = z.sqrt();
    let rounding = sz * r.e * rho + sz * r.v * (rho - one);
    (real + rounding, rounding)
}

/// An enclosure of the real formula's `sqrt(z) k(z) - 1` over `z` (no rounding), in the
/// mean-value form.
pub fn real_length_error(c: &Candidate, z: Interval) -> Interval {
    mean_value(
        z,
        |z| c.k(z) * z.sqrt() - Interval::point(1.0),
        |z: Dual| c.k(z) * z.sqrt() - Dual::c(1.0),
    )
}

/// The relative error of the format's conversion of the float32 inputs (0 for float32).
fn input_ulp<F: Format>() -> f64 {
    match F::PRECISION {
        Precision::F32 => 0.0,
        Precision::F16 => F16::ULP,
    }
}

/// Proves `c` in format `F` over the domain `z` for the lighting `lights`.
pub fn prove_in<F: Format>(c: &Candidate, z: Interval, lights: &Lights, b: &ProofEffort) -> Bound
where
    Rounded<F>: Evaluate,
{
    let allowance = length_error::<F>(c, z).1.mag();
    let effort = Effort {
        tolerance: b.tolerance,
        atol: bnb::ATOL + allowance,
        max_boxes: b.max_boxes,
        max_seconds: b.max_seconds,
    };
    let point = Interval::point(0.0);
    let real = |p: &bnb::Point| {
        let v = c.k(p[0]) * p[0].sqrt() - 1.0;
        v.is_finite().then_some(v)
    };
    let abs = bnb::maximise(
        [z, point, point],
        effort,
        |cell| length_error::<F>(c, cell[0]).0.mag(),
        |p| real(p).map(f64::abs),
    );
    let signed = bnb::maximise(
        [z, point, point],
        effort,
        |cell| length_error::<F>(c, cell[0]).0.hi,
        real,
    );
    let finite = |x: f64| x.is_finite().then_some(x);
    // |N'| = 1 + L > 0 wherever |L| < 1, and |N'| = sqrt(z) k^ rho with sqrt(z), rho > 0: so
    // k^ > 0 and N' keeps the direction of n^.
    let angle = if abs.proven_upper < 1.0 {
        (input_ulp::<F>() + F::ULP) * (1.0 + 1e-6)
    } else {
        std::f64::consts::PI
    };
    let (e, e_plus) = (finite(abs.proven_upper), finite(signed.proven_upper));
    Bound {
        precision: F::PRECISION,
        length_error: e,
        length_error_signed: e_plus,
        angle_rad: angle,
        colour: e
            .zip(e_plus)
            .and_then(|(e, ep)| lights.colour(e, ep, angle)),
        found_length_error: finite(abs.found),
        rounding_allowance: allowance,
        converged: abs.converged && signed.converged,
        boxes: abs.boxes + signed.boxes,
        seconds: abs.seconds + signed.seconds,
    }
}

/// The proven largest `| |N'| - 1 |` of `c`'s program in format `F` over `z` (infinite where
/// nothing finite is proven), after at most `max_boxes` boxes and with no time limit: the same
/// number on every machine and every run, which a tuned file's line can state and a loader
/// re-prove ([`super::check`]).
pub fn length_bound<F: Format>(c: &Candidate, z: Interval, max_boxes: usize) -> f64
where
    Rounded<F>: Evaluate,
{
    let allowance = length_error::<F>(c, z).1.mag();
    let effort = Effort {
        tolerance: ProofEffort::default().tolerance,
        atol: bnb::ATOL + allowance,
        max_boxes,
        max_seconds: f64::INFINITY,
    };
    let point = Interval::point(0.0);
    let bound = bnb::maximise(
        [z, point, point],
        effort,
        |cell| length_error::<F>(c, cell[0]).0.mag(),
        |p| {
            let v = (c.k(p[0]) * p[0].sqrt() - 1.0).abs();
            v.is_finite().then_some(v)
        },
    )
    .proven_upper;
    if bound.is_nan() {
        f64::INFINITY
    } else {
        bound
    }
}

/// [`prove_in`] for `precision`.
pub fn prove(
    c: &Candidate,
    precision: Precision,
    z: Interval,
    lights: &Lights,
    b: &ProofEffort,
) -> Bound {
    match precision {
        Precision::F32 => prove_in::<F32>(c, z, lights, b),
        Precision::F16 => prove_in::<F16>(c, z, lights, b),
    }
}

/// The real formula's largest length error over sampled values of z (the covered pixels', as
/// compare would meet them): a sampled figure, never a verdict.
pub fn sampled_length_error(c: &Candidate, zs: impl Iterator<Item = f64>) -> f64 {
    zs.map(|z| (c.k(z) * z.sqrt() - 1.0).abs())
        .fold(
            0.0,
            |a: f64, e| if e.is_nan() { f64::INFINITY } else { a.max(e) },
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lights() -> Lights {
        Lights {
            colours: vec![[1.0; 3]],
            diffuse: [0.75, 0.55, 0.35],
            specular: [0.5; 3],
            shininess: 50.0,
        }
    }

    /// Float32 Horner of the candidate's seed and steps, as the device computes it (round to
    /// nearest, no fma), from a float32 normal.
    fn device_f32(c: &Candidate, n: [f32; 3]) -> f64 {
        let z = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        let mut it = c.coeffs.iter().rev().map(|&x| x as f32);
        let mut k = it.next().unwrap();
        for ci in it {
            k = k * z + ci;
        }
        for _ in 0..c.steps {
            k = k * (1.5 - 0.5 * z * k * k);
        }
        let out = n.map(|x| f64::from(x * k));
        (out[0] * out[0] + out[1] * out[1] + out[2] * out[2]).sqrt()
    }

    /// The proven bound holds what float32 computes on random normals of the domain, is within
    /// 1 % (plus the rounding) of the real formula's worst, and the paper's bound matches
    /// `prove`'s (the same real formula; the rounding adds < 1e-6).
    #[test]
    fn the_bound_holds_float32_programs_and_is_tight() {
        let (lo, hi) = (0.6, 1.0);
        let z = Interval::new(lo, hi);
        let mut rng = fastrand::Rng::with_seed(5);
        for (d, steps) in [(2, 0), (4, 0), (1, 1), (0, 2)] {
            let c = if steps == 0 {
                Candidate::minimax("m".into(), d, lo, hi).unwrap()
            } else {
                Candidate::newton("m".into(), d, steps, lo, hi).unwrap()
            };
            let b = prove(&c, Precision::F32, z, &lights(), &ProofEffort::default());
            let e = b.length_error.unwrap();
            let found = b.found_length_error.unwrap();
            assert!(b.converged && e <= found * 1.01 + b.rounding_allowance + 1e-12);
            assert!(b.rounding_allowance < 1e-5, "{b:?}");
            for _ in 0..20_000 {
                let len = (lo + (hi - lo) * rng.f64()).sqrt();
                let dir =
                    glam::DVec3::new(rng.f64() - 0.5, rng.f64() - 0.5, rng.f64() - 0.5).normalize();
                let n = (dir * len).to_array().map(|x| x as f32);
                let zf = n.iter().map(|&x| f64::from(x) * f64::from(x)).sum::<f64>();
                if !z.contains(zf) {
                    continue;
                }
                let got = device_f32(&c, n) - 1.0;
                assert!(got.abs() <= e, "d {d} k {steps}: {got} > {e}");
            }
        }
        let romanyuk = Candidate::paper(crate::method::find("romanyuk_poly").unwrap()).unwrap();
        let ours = prove(
            &romanyuk,
            Precision::F32,
            z,
            &lights(),
            &ProofEffort::default(),
        );
        let (e, found) = (ours.length_error.unwrap(), ours.found_length_error.unwrap());
        assert!(
            e >= found && e <= found * 1.01 + ours.rounding_allowance + 1e-12,
            "{ours:?}"
        );
        // docs/formulas.md: Romanyuk's largest |e| is 0.351 % on z in [0.5, 1]
        assert!((found - 3.51e-3).abs() < 1e-5, "{found}");
    }

    /// Teeth: float16 arithmetic and coefficients make the same polynomial's bound far larger
    /// (its real formula is the same), and a bound of the real formula alone is exceeded by
    /// what float32 computes (the quartic's real error on [0.95, 1] is ~1e-10, ~1e-7 with its
    /// coefficients rounded to float32; float32's arithmetic reaches three times that).
    #[test]
    fn rounding_is_in_the_bound() {
        let z = Interval::new(0.95, 1.0);
        let c = Candidate::minimax("m".into(), 4, 0.95, 1.0).unwrap();
        let f32b = prove(&c, Precision::F32, z, &lights(), &ProofEffort::default());
        let f16b = prove(&c, Precision::F16, z, &lights(), &ProofEffort::default());
        assert!(
            f16b.length_error.unwrap() > 100.0 * f32b.length_error.unwrap(),
            "{f16b:?}"
        );
        assert!(f16b.colour.unwrap() > f32b.colour.unwrap());
        let point = Interval::point(0.0);
        let effort = Effort {
            tolerance: 0.01,
            atol: 1e-15,
            max_boxes: 100_000,
            max_seconds: 5.0,
        };
        let real_only = bnb::maximise(
            [z, point, point],
            effort,
            |cell| real_length_error(&c, cell[0]).mag(),
            |p| Some((c.k(p[0]) * p[0].sqrt() - 1.0).abs()),
        )
        .proven_upper;
        let mut rng = fastrand::Rng::with_seed(11);
        let worst = (0..20_000)
            .map(|_| {
                let len = (0.95 + 0.05 * rng.f64()).sqrt() as f32;
                (device_f32(&c, [0.0, 0.0, len]) - 1.0).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst > 2.0 * real_only, "{worst} vs {real_only}");
        assert!(worst <= f32b.length_error.unwrap(), "{worst} vs {f32b:?}");
    }

    /// A factor that changes sign on the domain turns N' round: angle pi, no colour bound
    /// within any budget.
    #[test]
    fn a_factor_crossing_zero_is_not_within_anything() {
        let c = Candidate {
            coeffs: vec![1.0, -1.2],
            ..Candidate::minimax("m".into(), 1, 0.5, 1.0).unwrap()
        };
        let b = prove(
            &c,
            Precision::F32,
            Interval::new(0.5, 1.0),
            &lights(),
            &ProofEffort::default(),
        );
        assert_eq!(b.angle_rad, std::f64::consts::PI);
        assert!(!b.within(1.0 / 255.0));
    }
}
