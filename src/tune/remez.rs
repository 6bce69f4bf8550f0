//! Best uniform (minimax) polynomial approximations by the Remez exchange, with the optimum
//! certified by equioscillation.
//!
//! The problem: for `f` on `[lo, hi]` and a weight `w > 0`, find the polynomial `p` of degree
//! `d` that minimises `max |w(x) (p(x) - f(x))|` (w = 1: absolute error; w = 1/f: relative
//! error, e.g. `sqrt(z) p(z) - 1` for f = z^(-1/2), the length error of `N' = p(N.N) N`).
//! Weighted polynomials form a Haar system, so the optimum is the unique polynomial whose
//! error takes its largest magnitude with alternating signs at d + 2 points (Chebyshev's
//! alternation theorem), and for any polynomial whose error alternates in sign at d + 2 points
//! the smallest of those magnitudes is a lower bound of every polynomial's largest error (de la
//! Vallée Poussin). [`Fit::certificate`] states both ends: `lower <= optimum <= upper`, upper
//! the fit's own largest error on a dense grid refined at each extremum.
//!
//! The exchange: solve `p(x_i) - f(x_i) = (-1)^i h / w(x_i)` on d + 2 reference points (in the
//! variable t in [-1, 1] for conditioning), move the reference to the error's alternating
//! extrema (one per sign run of the error on a Chebyshev grid, each refined by golden-section
//! search, ends included, the largest kept), repeat until the largest error equals |h| to
//! 1e-9 relative.
use serde::Serialize;

/// What to approximate: `f` on `[lo, hi]`, weighted by `w`.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    pub f: fn(f64) -> f64,
    pub w: fn(f64) -> f64,
    pub lo: f64,
    pub hi: f64,
}

/// `z^(-1/2)` for relative error on `[lo, hi]`: the error is `sqrt(z) p(z) - 1`.
pub fn inv_sqrt_relative(lo: f64, hi: f64) -> Target {
    Target {
        f: |z| 1.0 / z.sqrt(),
        w: f64::sqrt,
        lo,
        hi,
    }
}

/// The weighted error of the polynomial `c` (lowest degree first) at `x`.
pub fn weighted_error(t: &Target, c: &[f64], x: f64) -> f64 {
    (t.w)(x) * (horner(c, x) - (t.f)(x))
}

/// `sum c_i x^i` by Horner's rule (lowest degree first).
pub fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |a, k| a * x + k)
}

/// The de la Vallée Poussin bracket of the optimum: every polynomial of the degree has a
/// largest weighted error of at least `lower`; this fit's is `upper`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Certificate {
    /// min |error| over d + 2 points where the fit's error alternates in sign.
    pub lower: f64,
    /// The fit's largest |error| (dense grid, refined at each extremum).
    pub upper: f64,
    /// The d + 2 signs alternate and `upper <= lower (1 + 1e-6) + 1e-15` (f64's own floor).
    pub equioscillates: bool,
}

/// A minimax fit.
#[derive(Debug, Clone, Serialize)]
pub struct Fit {
    /// Coefficients in x, lowest degree first.
    pub coeffs: Vec<f64>,
    /// The final reference (d + 2 points where the error alternates).
    pub reference: Vec<f64>,
    pub iterations: usize,
    pub certificate: Certificate,
}

/// Points of the dense grid (Chebyshev-spaced, denser at the ends where the extrema crowd).
const GRID: usize = 4000;

/// The minimax polynomial of degree `d` for `t`. Errors (a message) when the interval is empty
/// or the exchange cannot find d + 2 alternating extrema.
pub fn minimax(t: &Target, d: usize) -> Result<Fit, String> {
    if !(t.lo < t.hi && t.lo.is_finite() && t.hi.is_finite()) {
        return Err(format!("empty interval [{}, {}]", t.lo, t.hi));
    }
    let n = d + 2;
    let mut x: Vec<f64> = (0..n).map(|i| cheb(t, i, n - 1)).collect();
    let mut coeffs = vec![0.0; d + 1];
    let mut iterations = 0;
    for it in 0..60 {
        iterations = it + 1;
        let (c, h) = solve_reference(t, &x, d)?;
        coeffs = c;
        let ext = alternating_extrema(t, &coeffs, n);
        if ext.len() < n {
            break;
        }
        let top = ext.iter().map(|&(_, e)| e.abs()).fold(0.0, f64::max);
        x = ext.iter().map(|&(p, _)| p).collect();
        if top - h.abs() <= 1e-9 * h.abs() + 1e-16 {
            break;
        }
    }
    let certificate = certify(t, &coeffs, &x);
    Ok(Fit {
        coeffs,
        reference: x,
        iterations,
        certificate,
    })
}

/// The i-th of `m + 1` Chebyshev extrema mapped to [lo, hi], ascending.
fn cheb(t: &Target, i: usize, m: usize) -> f64 {
    let c = (std::f64::consts::PI * i as f64 / m as f64).cos();
    0.5 * (t.lo + t.hi) - 0.5 * (t.hi - t.lo) * c
}

/// Solves `sum a_j s_i^j + (-1)^i h / w(x_i) = f(x_i)` in s = (2x - lo - hi)/(hi - lo) and
/// returns the coefficients in x and h.
fn solve_reference(t: &Target, x: &[f64], d: usize) -> Result<(Vec<f64>, f64), String> {
    let (m, r) = (0.5 * (t.lo + t.hi), 0.5 * (t.hi - t.lo));
    let mut a: Vec<Vec<f64>> = x
        .iter()
        .enumerate()
        .map(|(i, &xi)| {
            let s = (xi - m) / r;
            let mut row: Vec<f64> = (0..=d).map(|j| s.powi(j as i32)).collect();
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            row.push(sign / (t.w)(xi));
            row.push((t.f)(xi));
            row
        })
        .collect();
    let sol = crate::method::linalg::gauss(&mut a).ok_or("singular reference system")?;
    // p(x) = sum a_j ((x - m)/r)^j: expand each power binomially.
    let mut c = vec![0.0; d + 1];
    for (j, aj) in sol[..=d].iter().enumerate() {
        let scale = aj / r.powi(j as i32);
        for (k, ck) in c.iter_mut().enumerate().take(j + 1) {
            *ck += scale * binomial(j, k) * (-m).powi((j - k) as i32);
        }
    }
    Ok((c, sol[d + 1]))
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |a, i| a * (n - i) as f64 / (i + 1) as f64)
}

/// Golden-section search for the largest |err| in [a, b] (err has one extremum there).
fn refine(err: &dyn Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    for _ in 0..80 {
        if err(c).abs() > err(d).abs() {
            b = d;
        } else {
            a = c;
        }
        c = b - g * (b - a);
        d = a + g * (b - a);
    }
    let mid = 0.5 * (a + b);
    [a, b, mid]
        .into_iter()
        .max_by(|p, q| err(*p).abs().total_cmp(&err(*q).abs()))
        .unwrap_or(mid)
}

/// The error's extrema, one per sign run (the largest of the run, refined), as (x, error);
/// trimmed to `n` from the ends (the smaller end first), which keeps the signs alternating and
/// the largest extremum.
fn alternating_extrema(t: &Target, c: &[f64], n: usize) -> Vec<(f64, f64)> {
    let err = |x: f64| weighted_error(t, c, x);
    let grid: Vec<f64> = (0..=GRID).map(|i| cheb(t, i, GRID)).collect();
    let mut runs: Vec<(usize, f64)> = Vec::new(); // (grid index of the run's largest, sign)
    for (i, &x) in grid.iter().enumerate() {
        let e = err(x);
        let s = if e >= 0.0 { 1.0 } else { -1.0 };
        match runs.last_mut() {
            Some((j, sj)) if *sj == s => {
                if e.abs() > err(grid[*j]).abs() {
                    *j = i;
                }
            }
            _ => runs.push((i, s)),
        }
    }
    let mut ext: Vec<(f64, f64)> = runs
        .iter()
        .map(|&(i, _)| {
            let (a, b) = (grid[i.saturating_sub(1)], grid[(i + 1).min(GRID)]);
            let x = refine(&err, a, b);
            (x, err(x))
        })
        .collect();
    while ext.len() > n {
        if ext[0].1.abs() < ext[ext.len() - 1].1.abs() {
            ext.remove(0);
        } else {
            ext.pop();
        }
    }
    ext
}

/// The bracket of the optimum for coefficients `c` and a reference `x` of d + 2 points.
pub fn certify(t: &Target, c: &[f64], x: &[f64]) -> Certificate {
    let err = |p: f64| weighted_error(t, c, p);
    let signs_alternate =
        x.windows(2).all(|w| err(w[0]) * err(w[1]) < 0.0) && x.len() == c.len() + 1;
    let lower = x
        .iter()
        .map(|&p| err(p).abs())
        .fold(f64::INFINITY, f64::min);
    let upper = largest_error(t, c);
    Certificate {
        lower,
        upper,
        equioscillates: signs_alternate && upper <= lower * (1.0 + 1e-6) + 1e-15,
    }
}

/// The largest |weighted error| of `c` on the dense grid, refined at each sign run's extremum.
pub fn largest_error(t: &Target, c: &[f64]) -> f64 {
    alternating_extrema(t, c, usize::MAX)
        .iter()
        .map(|&(_, e)| e.abs())
        .fold(0.0, f64::max)
}

/// The smallest and largest weighted error of `c` (signed), as [`largest_error`] finds them.
pub fn extremes(t: &Target, c: &[f64]) -> (f64, f64) {
    let ext = alternating_extrema(t, c, usize::MAX);
    let lo = ext.iter().map(|&(_, e)| e).fold(f64::INFINITY, f64::min);
    let hi = ext
        .iter()
        .map(|&(_, e)| e)
        .fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense f64 evaluation: the largest |error| over 10^6 evenly spaced points.
    fn dense(t: &Target, c: &[f64]) -> f64 {
        let n = 1_000_000;
        (0..=n)
            .map(|i| t.lo + (t.hi - t.lo) * i as f64 / n as f64)
            .map(|x| weighted_error(t, c, x).abs())
            .fold(0.0, f64::max)
    }

    /// The optimum against a dense evaluation, for 1/sqrt(z) (relative) and 1/sqrt(2 + z)
    /// (absolute) on several ranges and degrees: the largest dense error is the fit's
    /// certified one, and no perturbation of a coefficient lowers it (the optimum is unique).
    #[test]
    fn remez_matches_a_dense_evaluation_and_equioscillates() {
        let dichotomy = Target {
            f: |z| 1.0 / (2.0 + z).sqrt(),
            w: |_| 1.0,
            lo: 2f64.sqrt(),
            hi: 2.0,
        };
        let targets = [
            inv_sqrt_relative(0.5, 1.0),
            inv_sqrt_relative(0.25, 1.0),
            inv_sqrt_relative(0.9, 1.0),
            dichotomy,
        ];
        for t in &targets {
            for d in 0..=4 {
                let fit = minimax(t, d).unwrap();
                let c = fit.certificate;
                let dense_max = dense(t, &fit.coeffs);
                assert!(c.equioscillates, "{t:?} d {d}: {c:?}");
                assert!(
                    c.lower <= dense_max * (1.0 + 1e-9) + 1e-16,
                    "{c:?} {dense_max}"
                );
                assert!(
                    (dense_max - c.upper).abs() <= 1e-7 * c.upper + 1e-16,
                    "{t:?} d {d}: dense {dense_max} vs {c:?}"
                );
                for j in 0..=d {
                    for s in [-1.0, 1.0] {
                        let mut q = fit.coeffs.clone();
                        q[j] += s * 1e-4 * c.upper.max(1e-12);
                        assert!(dense(t, &q) > dense_max, "{t:?} d {d} coefficient {j}");
                    }
                }
            }
        }
        // the dichotomy's degree-2 optimum is the one docs/formulas.md#dichotomy cites
        let fit = minimax(&dichotomy, 2).unwrap();
        assert!((fit.certificate.upper - 2.016e-5).abs() < 1e-8, "{fit:?}");
    }

    /// Teeth: a polynomial that is not the optimum (the least-squares fit Romanyuk's rounds,
    /// or the optimum nudged) does not pass the certificate.
    #[test]
    fn a_fit_that_is_not_the_optimum_fails_the_certificate() {
        let t = inv_sqrt_relative(0.5, 1.0);
        let fit = minimax(&t, 2).unwrap();
        let romanyuk = [2.227, -2.046, 0.822];
        let c = certify(&t, &romanyuk, &fit.reference);
        assert!(!c.equioscillates, "{c:?}");
        let mut nudged = fit.coeffs.clone();
        nudged[1] += 1e-3;
        assert!(!certify(&t, &nudged, &fit.reference).equioscillates);
        let (rom, best) = (largest_error(&t, &romanyuk), fit.certificate.upper);
        assert!(rom > 1.05 * best, "{rom} vs {best}");
    }
}
