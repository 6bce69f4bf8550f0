//! The candidates `tune` proves and costs: each a family with a degree and float32
//! coefficients, one generic formula `k(z)` ([`Candidate::k`], over f64, prove's intervals and
//! their derivatives, and the rounding-aware [`super::rounded::Rounded`]) and its GLSL method
//! file in glsl/methods/' vocabulary ([`Candidate::glsl`]), the same operations in the same
//! order.
//!
//! - [`Family::Minimax`]: `p_d(z) ~ z^(-1/2)`, the minimax polynomial for relative error on the
//!   domain ([`super::remez`]), d = 0..4, Horner in z.
//! - [`Family::Newton`]: a seed `p_d(z)` followed by k Newton steps `y <- y (3/2 - z y^2 / 2)`
//!   (Mikami's idea: fit the seed for the error after the steps): the seed is the minimax of
//!   relative error, scaled so that the error after the steps is equal at its two ends (one
//!   step turns a seed error e into `-(3/2) e^2 - e^3/2 <= 0`, larger for e > 0 than for -e).
//! - [`Family::Paper`]: the rows of the method table that say they are a baseline of tune
//!   ([`crate::method::Property::TuneBaseline`]: the papers' fixed formulas), each its row's
//!   scale ([`papers`]).
//! - [`Family::Reference`]: phong_exact itself, `1/sqrt(z)`: the yardstick of every cost, and
//!   its own proven bound (the rounding of its program) beside the candidates'.
use serde::Serialize;

use super::remez::{self, Certificate, Target};
use crate::method::kernel::{Evaluate, Form};
use crate::method::real::Real;
pub use crate::method::tuned::{horner, newton_step};
use crate::method::{Method, Property, Scale};

/// A candidate's family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    Minimax,
    Newton,
    Paper,
    Reference,
}

impl Family {
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Minimax => "minimax",
            Family::Newton => "newton",
            Family::Paper => "paper",
            Family::Reference => "reference",
        }
    }
}

/// The papers' methods `tune` takes as baselines: every row of the method table (its own
/// rows, and rows registered at run time) with [`Property::TuneBaseline`] whose kernel is a
/// scale of N.N ([`Candidate::paper`]), the factors `N' = k(z) N` before the divisors
/// `N' = N / s(z)` (Mikami's), each group in table order: the order tune has always listed
/// them in.
pub fn papers() -> Vec<Candidate> {
    let mut rows: Vec<(&'static Method, Scale)> = crate::method::all()
        .into_iter()
        .filter(|m| m.has(Property::TuneBaseline))
        .filter_map(|m| Some((m, *m.kernel.provable()?)))
        .collect();
    rows.sort_by_key(|(_, s)| s.form == Form::Over);
    rows.into_iter()
        .filter_map(|(m, _)| Candidate::paper(m))
        .collect()
}

/// One candidate.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The method id: the file stem of its method file, or the table's name for a paper.
    pub id: String,
    pub family: Family,
    /// The polynomial's degree (the seed's for Newton; null for a paper).
    pub degree: Option<usize>,
    /// Newton steps after the seed (0 otherwise).
    pub steps: u32,
    /// The coefficients in z, lowest degree first, as float32 values (empty for a paper).
    pub coeffs: Vec<f64>,
    /// The range of z the coefficients were fitted on.
    pub fitted_on: Option<[f64; 2]>,
    /// The Remez certificate of the polynomial (the seed's) before rounding to float32.
    pub remez: Option<Certificate>,
    /// The seed's scale (Newton): the minimax seed times this.
    pub seed_scale: Option<f64>,
    /// A paper's formula: its row's scale (None for the other families).
    #[serde(skip)]
    pub scale: Option<Scale>,
}

impl Candidate {
    /// The scale factor `k(z)`, `N' = k(N.N) N`: the one formula of the candidate.
    pub fn k<T: Real + Evaluate>(&self, z: T) -> T {
        match self.family {
            // the row's own factor (`1 / s(z)` for a divisor), NaN for a paper without one
            Family::Paper => self.scale.map_or_else(|| T::c(f64::NAN), |s| s.k(z)),
            // normalize(n): as n (1 / sqrt(n.n)), whose two roundings bound Vulkan's
            Family::Reference => T::c(1.0) / z.sqrt(),
            // the tuned rows' formula (src/method/tuned.rs), the one copy
            Family::Minimax | Family::Newton => {
                crate::method::tuned::k(&self.coeffs, self.steps, z)
            }
        }
    }

    /// The paper method of row `m`: its kernel's scale, when it is a scale of N.N that is not
    /// exact normalisation ([`crate::method::Kernel::provable`]); None otherwise.
    pub fn paper(m: &'static Method) -> Option<Candidate> {
        let scale = *m.kernel.provable()?;
        Some(Candidate {
            id: m.name.to_string(),
            family: Family::Paper,
            scale: Some(scale),
            ..Candidate::reference()
        })
    }

    /// phong_exact, the reference.
    pub fn reference() -> Candidate {
        Candidate {
            id: crate::method::PHONG_EXACT.to_string(),
            family: Family::Reference,
            degree: None,
            steps: 0,
            coeffs: Vec::new(),
            fitted_on: None,
            remez: None,
            seed_scale: None,
            scale: None,
        }
    }

    /// The minimax polynomial of degree `d` for relative error on [lo, hi], coefficients
    /// rounded to float32; `id` its method id.
    pub fn minimax(id: String, d: usize, lo: f64, hi: f64) -> Result<Candidate, String> {
        let fit = remez::minimax(&remez::inv_sqrt_relative(lo, hi), d)?;
        Ok(Candidate {
            id,
            family: Family::Minimax,
            degree: Some(d),
            steps: 0,
            coeffs: to_f32(&fit.coeffs),
            fitted_on: Some([lo, hi]),
            remez: Some(fit.certificate),
            seed_scale: None,
            scale: None,
        })
    }

    /// A seed of degree `d` and `steps` Newton steps, fitted on [lo, hi] for the error after
    /// the steps.
    pub fn newton(id: String, d: usize, steps: u32, lo: f64, hi: f64) -> Result<Candidate, String> {
        let t = remez::inv_sqrt_relative(lo, hi);
        let fit = remez::minimax(&t, d)?;
        let s = balanced_scale(&t, &fit.coeffs, steps);
        let seed: Vec<f64> = fit.coeffs.iter().map(|c| c * s).collect();
        Ok(Candidate {
            id,
            family: Family::Newton,
            degree: Some(d),
            steps,
            coeffs: to_f32(&seed),
            fitted_on: Some([lo, hi]),
            remez: Some(fit.certificate),
            seed_scale: Some(s),
            scale: None,
        })
    }

    /// How the candidate reads in a table: `minimax d3`, `newton k1 seed d2`, or its name.
    pub fn label(&self) -> String {
        match (self.family, self.degree) {
            (Family::Minimax, Some(d)) => format!("minimax d{d}"),
            (Family::Newton, Some(d)) => format!("newton k{} seed d{d}", self.steps),
            _ => self.id.clone(),
        }
    }

    /// The formula in words, with its coefficients (what the method file's header says).
    pub fn formula(&self) -> String {
        let p = self
            .coeffs
            .iter()
            .enumerate()
            .map(|(i, c)| match i {
                0 => format!("{c:e}"),
                1 => format!("{c:e} z"),
                _ => format!("{c:e} z^{i}"),
            })
            .collect::<Vec<_>>()
            .join(" + ");
        match self.family {
            Family::Minimax => format!("k(z) = {p}"),
            Family::Newton => format!(
                "y0 = {p}; {} x y <- y (1.5 - 0.5 z y y); k(z) = y",
                self.steps
            ),
            Family::Paper | Family::Reference => format!("the table's {}", self.id),
        }
    }
}

/// Each value rounded to float32 (to nearest), as f64.
fn to_f32(c: &[f64]) -> Vec<f64> {
    c.iter().map(|&x| f64::from(x as f32)).collect()
}

/// The relative error after `steps` Newton steps of a seed with relative error `e`.
pub fn after_steps(e: f64, steps: u32) -> f64 {
    (0..steps).fold(e, |e, _| {
        (1.0 + e) * (1.5 - 0.5 * (1.0 + e) * (1.0 + e)) - 1.0
    })
}

/// The scale s of the seed `c` that makes the error after `steps` equal at the seed error's two
/// ends (s (1 + e_lo) - 1 and s (1 + e_hi) - 1): by bisection on s, below which the upper
/// end's error is the smaller. 1 when there are no steps.
pub fn balanced_scale(t: &Target, c: &[f64], steps: u32) -> f64 {
    if steps == 0 {
        return 1.0;
    }
    let (lo, hi) = remez::extremes(t, c);
    let gap = |s: f64| {
        after_steps(s * (1.0 + hi) - 1.0, steps).abs()
            - after_steps(s * (1.0 + lo) - 1.0, steps).abs()
    };
    let (mut a, mut b) = (1.0 / (1.0 + hi), 1.0 / (1.0 + lo));
    if !(gap(a) <= 0.0 && gap(b) >= 0.0) {
        return 1.0;
    }
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if gap(m) > 0.0 {
            b = m;
        } else {
            a = m;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One step turns e into -(3/2) e^2 - e^3/2; the balanced seed's error after the steps is
    /// the same at both ends, and smaller than the unscaled seed's.
    #[test]
    fn the_seed_is_balanced_for_the_error_after_the_steps() {
        for e in [-0.1, 0.01, 0.2] {
            let want = -1.5 * e * e - 0.5 * e * e * e;
            assert!((after_steps(e, 1) - want).abs() < 1e-15);
        }
        for steps in [1, 2] {
            for d in 0..=2 {
                let (lo, hi) = (0.4, 1.0);
                let t = remez::inv_sqrt_relative(lo, hi);
                let c = Candidate::newton("x".into(), d, steps, lo, hi).unwrap();
                let plain = remez::minimax(&t, d).unwrap();
                let worst = |cs: &[f64]| {
                    (0..=20_000)
                        .map(|i| lo + (hi - lo) * f64::from(i) / 20_000.0)
                        .map(|z| {
                            let mut y = horner(cs, z);
                            for _ in 0..steps {
                                y = newton_step(z, y);
                            }
                            (z.sqrt() * y - 1.0).abs()
                        })
                        .fold(0.0, f64::max)
                };
                let (tuned, unscaled) = (worst(&c.coeffs), worst(&plain.coeffs));
                assert!(tuned < unscaled, "k{steps} d{d}: {tuned} vs {unscaled}");
                let (elo, ehi) = remez::extremes(&t, &plain.coeffs);
                let s = c.seed_scale.unwrap();
                let (a, b) = (
                    after_steps(s * (1.0 + elo) - 1.0, steps).abs(),
                    after_steps(s * (1.0 + ehi) - 1.0, steps).abs(),
                );
                // equal to the f64 rounding of after_steps' cancellation
                assert!((a - b).abs() <= 1e-6 * a.max(b) + 1e-18, "{a} {b}");
            }
        }
    }

    /// The paper candidate of the table's row `name`.
    pub(crate) fn paper(name: &str) -> Candidate {
        Candidate::paper(crate::method::find(name).unwrap()).unwrap()
    }

    /// The papers' formulas are the table's: romanyuk at z = 0.75 (docs/formulas.md golden
    /// values: 1.154875), newton_raphson's (3 - z)/2, Mikami's 1 / s(z), the same in every
    /// number type (a float32 program's rounding enclosed around the f64 value).
    #[test]
    fn paper_formulas_are_the_tables() {
        assert!((paper("romanyuk_poly").k(0.75f64) - 1.154875).abs() < 1e-12);
        assert_eq!(paper("newton_raphson").k(0.5), 1.25);
        assert_eq!(paper(crate::method::phong_unnormalized().name).k(0.3), 1.0);
        let s = crate::method::formulas::s_mikami_linear(0.8f64);
        assert_eq!(paper("mikami_linear").k(0.8f64), 1.0 / s);
        use crate::method::interval::Interval;
        use crate::method::rounded::{Rounded, F32};
        let r = paper("romanyuk_poly").k(Rounded::<F32>::input(
            Interval::point(0.75),
            Interval::point(0.0),
        ));
        let v = paper("romanyuk_poly").k(0.75f64);
        assert!(r.computed().lo <= v && v <= r.computed().hi, "{r:?}");
        assert!(r.e.hi - r.e.lo < 1e-6, "the rounding is known: {r:?}");
    }

    /// The baselines are the rows that say so, in the order tune has always listed them (the
    /// factors, then Mikami's divisors); a row that is not a scale of N.N is no baseline.
    #[test]
    fn the_baselines_are_the_rows_that_say_so() {
        let names: Vec<String> = papers().into_iter().map(|c| c.id).collect();
        assert_eq!(
            names,
            [
                crate::method::phong_unnormalized().name,
                "newton_raphson",
                "lyon_taylor",
                "lyon_shift",
                "romanyuk_poly",
                "mikami_const",
                "mikami_linear",
                "mikami_quadratic",
            ]
        );
        // Teeth: exact normalisation and a span method have no scale to take.
        assert!(Candidate::paper(crate::method::phong_exact()).is_none());
        assert!(Candidate::paper(crate::method::find("slerp").unwrap()).is_none());
    }
}
