//! `shadelab prove`: for each covered method, a proven upper bound of its normal-space errors
//! over each declared input domain ([`domain`]: any triangle, and stress's edge geometry), by
//! interval branch-and-bound ([`bnb`]) on the method's own formula evaluated in outward-rounded
//! intervals ([`interval`]), beside the best value found at a real point of that domain (a
//! `stress` case, replayable with `stress --replay`) and the gap between the two. The colour
//! error is carried from the normal-space bounds through the lighting's derivatives;
//! `max_valid_angle` is proven per domain (the largest angle at which that colour bound stays
//! within the threshold), stress's grid's beside it (its cases are edges). The claims that are
//! bounds are judged in [`bounds`] (their parts in [`parts`]). Output: proof.json (docs/proof.schema.json), a table.
pub mod bnb;
pub mod bounds;
pub mod covered;
pub mod domain;
pub mod parts;
/// The interval types live with the number types of the formulas ([`crate::method::real`]);
/// `prove` is where they are used.
pub use crate::method::{dual, interval};
mod output;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod triangles;

use std::time::Instant;

use serde::Serialize;

use self::bnb::{Effort, Outcome};
use self::covered::Metric;
pub use self::domain::Domain;
use self::interval::Interval;
pub use self::output::{table, write};
use crate::cases::grid::{self as sweeps, Grid, Sweep};
use crate::cases::{errors, Case, CaseSpec, DIFFUSE, SPECULAR};
use crate::error::{Error, Result};
use crate::method::Method;
use crate::method::Scale;

/// Version of proof.json (docs/proof.schema.json).
pub const SCHEMA_VERSION: u32 = 3;

/// Options of a proof run.
#[derive(Debug, Clone)]
pub struct ProveOptions {
    pub max_angle_deg: f64,
    /// Relative gap at which a bound counts as tight: upper <= found (1 + tolerance).
    pub tolerance: f64,
    pub shininess: f64,
    /// Colour error within which a case is valid (1/255).
    pub threshold: f64,
    /// The effort of each branch-and-bound: the boxes and seconds it may spend.
    pub max_boxes: usize,
    pub max_seconds: f64,
    /// Progress lines on stderr.
    pub progress: bool,
}

impl Default for ProveOptions {
    fn default() -> Self {
        ProveOptions {
            max_angle_deg: 90.0,
            tolerance: 0.01,
            shininess: 50.0,
            threshold: 1.0 / 255.0,
            max_boxes: 400_000,
            max_seconds: 20.0,
            progress: false,
        }
    }
}

/// One metric of one method (fractions; angles in radians).
#[derive(Debug, Clone, Serialize)]
pub struct MetricProof {
    pub metric: &'static str,
    /// Null: nothing finite could be proven (an unbounded box remained).
    pub proven_upper: Option<f64>,
    /// Null: a real point gave a non-finite value (a failure, see `found_non_finite`).
    pub found: Option<f64>,
    pub found_non_finite: bool,
    /// The stress case of the found point (`stress --replay` runs it:
    /// cases/<method>_<domain>_<metric>.json).
    pub found_input: Option<CaseSpec>,
    pub gap: Option<f64>,
    pub relative_gap: Option<f64>,
    /// proven_upper <= found (1 + tolerance) + 1e-12.
    pub within_tolerance: bool,
    pub boxes: usize,
    pub seconds: f64,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl MetricProof {
    fn new(metric: Metric, o: &Outcome, domain: Domain, shininess: f64) -> MetricProof {
        MetricProof {
            metric: metric.as_str(),
            proven_upper: finite(o.proven_upper),
            found: finite(o.found),
            found_non_finite: o.found.is_nan(),
            found_input: o.found_at.map(|p| domain.spec_at(&p, shininess)),
            gap: finite(o.gap()),
            relative_gap: finite(o.relative_gap()),
            within_tolerance: o.converged && o.proven_upper.is_finite(),
            boxes: o.boxes,
            seconds: o.seconds,
        }
    }
}

/// The colour error over one domain: proven through the lighting, found at its real points.
#[derive(Debug, Clone, Serialize)]
pub struct ColourProof {
    pub shininess: f64,
    /// (k_d + k_s n (1 + e+)^(n-1)) (E + A): see `how`. Null: not provable (n < 1 or an
    /// unbounded normal-space bound).
    pub proven_upper: Option<f64>,
    pub how: &'static str,
    /// e+: the proven largest signed length error |N'| - 1 (to 1e-6), the slope's input.
    pub length_error_signed_upper: Option<f64>,
    /// Max abs colour error at the found points of the normal-space metrics (view and light
    /// along the exact normal there).
    pub found: Option<f64>,
    pub found_input: Option<CaseSpec>,
}

/// The largest valid angle proven over one domain.
#[derive(Debug, Clone, Serialize)]
pub struct ValidAngle {
    pub threshold: f64,
    /// Largest angle (bisection to max_angle/4096) at which the proven colour bound over the
    /// domain is within the threshold; null: not even at 0.
    pub proven_deg: Option<f64>,
}

/// Everything proven about one method over one domain.
#[derive(Debug, Clone, Serialize)]
pub struct DomainProof {
    pub domain: Domain,
    pub metrics: Vec<MetricProof>,
    pub colour: ColourProof,
    pub max_valid_angle: ValidAngle,
}

/// stress's angle sweep for one method (f64 twin, this shininess): its cases are edges, so
/// its figures stand beside the edge domain's.
#[derive(Debug, Clone, Serialize)]
pub struct StressGrid {
    /// The domain its cases lie in: always the edge.
    pub domain: Domain,
    /// Max f64 colour error over the facing cases with theta <= max_angle_deg.
    pub colour_found: Option<f64>,
    pub cases: usize,
    pub non_finite: usize,
    /// stress's rule: the largest grid angle up to which every facing case is within the
    /// threshold.
    pub max_valid_angle_deg: Option<f64>,
}

/// Everything proven about one method.
#[derive(Debug, Clone, Serialize)]
pub struct MethodProof {
    pub name: String,
    /// The reference: exact normalisation (a scale of N keeps its direction, so exact slerp
    /// does not apply).
    pub reference: &'static str,
    /// One per domain, in [`Domain::ALL`]'s order (triangle, edge).
    pub domains: Vec<DomainProof>,
    pub stress_grid: StressGrid,
    pub seconds: f64,
}

impl MethodProof {
    /// The proof over `d`.
    pub fn over(&self, d: Domain) -> Option<&DomainProof> {
        self.domains.iter().find(|p| p.domain == d)
    }
}

/// A method out of reach and why.
#[derive(Debug, Clone, Serialize)]
pub struct OutOfReach {
    pub name: String,
    pub reason: &'static str,
}

/// proof.json.
#[derive(Debug, Clone, Serialize)]
pub struct ProofReport {
    pub schema_version: u32,
    /// The largest angle between any two vertex normals (triangle domain), or between N0 and
    /// N1 (edge domain), degrees.
    pub max_angle_deg: f64,
    pub tolerance: f64,
    pub shininess: f64,
    pub threshold: f64,
    /// The domains each method's figures are for, described.
    pub domains: Vec<domain::DomainInfo>,
    pub methods: Vec<MethodProof>,
    pub out_of_reach: Vec<OutOfReach>,
    pub claims: Vec<bounds::ProofClaim>,
    /// Every metric of every covered method within the tolerance, over both domains.
    pub all_within_tolerance: bool,
    pub seconds: f64,
}

/// Branch-and-bound of one metric of `m` (interval factor `k`) over `domain` up to
/// `max_angle_deg`.
pub fn prove_metric(
    m: &Method,
    k: &Scale,
    metric: Metric,
    domain: Domain,
    max_angle_deg: f64,
    opts: &ProveOptions,
) -> Outcome {
    prove_metric_in(
        m,
        k,
        metric,
        domain,
        max_angle_deg,
        domain.z_range(max_angle_deg),
        opts,
    )
}

/// [`prove_metric`] over the proven range `z` of N.N: a covered method's metrics depend on the
/// inputs only through z, so the search is one-dimensional; each z probed is a real point of
/// the domain ([`Domain::point_for_z`]).
fn prove_metric_in(
    m: &Method,
    k: &Scale,
    metric: Metric,
    domain: Domain,
    max_angle_deg: f64,
    z: Interval,
    opts: &ProveOptions,
) -> Outcome {
    // The signed length error only enters the colour bound: 1e-6 is plenty there (its
    // maximum, 0, lies at z = 1, where the inputs' rounding alone leaves ~1e-7).
    let atol = if metric == Metric::LengthSigned {
        1e-6
    } else {
        bnb::ATOL
    };
    let effort = Effort {
        tolerance: opts.tolerance,
        atol,
        max_boxes: opts.max_boxes,
        max_seconds: opts.max_seconds,
    };
    let point = Interval::point(0.0);
    let mut o = bnb::maximise(
        [z, point, point],
        effort,
        |c| covered::upper(k, metric, c[0]),
        |p| {
            let q = domain.point_for_z(p[0], max_angle_deg);
            let case = Case::new(domain.spec_at(&q, opts.shininess));
            covered::measure(m, &case, metric).map(|v| v.0)
        },
    );
    o.found_at = o.found_at.map(|p| domain.point_for_z(p[0], max_angle_deg));
    o
}

/// The three normal-space metrics of `m` over `domain` up to `max`: length, signed length,
/// angle.
fn prove_metrics(
    m: &Method,
    k: &Scale,
    domain: Domain,
    max: f64,
    opts: &ProveOptions,
) -> [Outcome; 3] {
    let z = domain.z_range(max);
    [Metric::Length, Metric::LengthSigned, Metric::Angle]
        .map(|x| prove_metric_in(m, k, x, domain, max, z, opts))
}

/// The colour bound from the normal-space bounds E (largest |length error|), e+ (largest
/// signed length error, >= 0) and A (angle). Per channel the colour changes by k_d d(N.L) +
/// k_s d(max(0, N.H)^n). With A = 0 (the normal only scaled, N' = (1 + e) n): d(N.L) = e n.L,
/// and d(N.H)^n = ((1 + e)^n - 1)(n.H)^n, whose size the derivative n (1 + x)^(n-1) of
/// (1 + x)^n bounds by its ends: max((1 + e+)^n - 1, 1 - (1 - E)^n). Otherwise |N' - n| <=
/// E + A, max(0, x) is 1-Lipschitz, x^n's derivative is at most n (1 + e+)^(n-1) on
/// [0, 1 + e+], and both terms lie in [0, (1 + e+)^n]. None for n < 1 (x^n has no bounded
/// derivative at 0) or unbounded inputs.
pub fn colour_bound(metrics: &[Outcome; 3], shininess: f64) -> Option<f64> {
    let (kd, ks) = (f64::from(DIFFUSE as f32), f64::from(SPECULAR as f32));
    let (e, e_plus, a) = (
        metrics[0].proven_upper,
        metrics[1].proven_upper,
        metrics[2].proven_upper,
    );
    colour_slope(e, e_plus, a, shininess, kd, ks)
}

/// [`colour_bound`] for one white light of a material (`kd`, `ks`, exponent `shininess`) from
/// the normal-space bounds E (`e`), e+ (`e_plus`, taken as at least 0) and A (`a`).
pub fn colour_slope(e: f64, e_plus: f64, a: f64, shininess: f64, kd: f64, ks: f64) -> Option<f64> {
    let e_plus = e_plus.max(0.0);
    if shininess < 1.0 || !(e.is_finite() && e_plus.is_finite() && a.is_finite()) {
        return None;
    }
    let n = shininess;
    let top = (1.0 + e_plus).powf(n);
    let bound = if a == 0.0 {
        let spec = (top - 1.0).max(1.0 - (1.0 - e).max(0.0).powf(n));
        kd * e + ks * spec
    } else {
        let d = e + a;
        kd * d.min(1.0 + e_plus) + ks * (n * (1.0 + e_plus).powf(n - 1.0) * d).min(top)
    };
    // powf and the products are within a few ulps: 1e-12 relative covers them.
    finite(bound * (1.0 + 1e-12))
}

pub const COLOUR_HOW: &str = "k_d E + k_s max((1 + e+)^n - 1, 1 - (1 - E)^n) when the angle \
     bound A is 0 (the normal only scaled: the derivative of (1 + x)^n over [-E, e+]); \
     otherwise k_d min(E + A, 1 + e+) + k_s min(n (1 + e+)^(n-1) (E + A), (1 + e+)^n) \
     (max(0, x) 1-Lipschitz, x^n's derivative on [0, 1 + e+]); E, e+, A the proven largest \
     |length error|, signed length error and angle";

/// The proven largest valid angle over `domain`: the whole range if the bound holds there,
/// else bisection (every angle returned had its colour bound proven within the threshold, and
/// the domain at a smaller angle is a part of it).
fn proven_valid_angle(m: &Method, k: &Scale, domain: Domain, opts: &ProveOptions) -> Option<f64> {
    let quick = ProveOptions {
        max_boxes: opts.max_boxes / 8,
        max_seconds: opts.max_seconds / 8.0,
        ..opts.clone()
    };
    let valid = |theta: f64| {
        colour_bound(&prove_metrics(m, k, domain, theta, &quick), opts.shininess)
            .is_some_and(|c| c <= opts.threshold)
    };
    if valid(opts.max_angle_deg) {
        return Some(opts.max_angle_deg);
    }
    if !valid(0.0) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, opts.max_angle_deg);
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if valid(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

/// stress's angle sweep, facing cases with theta <= max, at `shininess` (f64 twin only).
pub fn stress_grid(max_angle_deg: f64, shininess: f64) -> Grid {
    let cases: Vec<Case> = Grid::specs()
        .into_iter()
        .filter(|(k, s)| {
            *k == Sweep::Angle && s.elevation_deg < 90.0 && s.theta_deg <= max_angle_deg
        })
        .map(|(_, s)| Case::new(CaseSpec { shininess, ..s }))
        .collect();
    let kinds = vec![Sweep::Angle; cases.len()];
    Grid {
        cases,
        gpu: Vec::new(),
        kinds,
    }
}

/// Proves everything about one covered method over one domain.
pub fn prove_domain(m: &Method, k: &Scale, domain: Domain, opts: &ProveOptions) -> DomainProof {
    let outcomes = prove_metrics(m, k, domain, opts.max_angle_deg, opts);
    let metrics: Vec<MetricProof> = [Metric::Length, Metric::LengthSigned, Metric::Angle]
        .iter()
        .zip(&outcomes)
        .filter(|(&x, _)| x != Metric::LengthSigned)
        .map(|(&x, o)| MetricProof::new(x, o, domain, opts.shininess))
        .collect();
    // The colour at the found points (view and light along the exact normal there).
    let mut found: Option<(f64, CaseSpec)> = None;
    for o in &outcomes {
        if let Some(p) = o.found_at {
            let spec = domain.spec_at(&p, opts.shininess);
            if let Some((_, c)) = covered::measure(m, &Case::new(spec), Metric::Length) {
                // a non-finite colour is kept (a failure, never replaced by a finite one)
                if found.is_none_or(|(f, _)| !f.is_nan() && (c.is_nan() || c > f)) {
                    found = Some((c, spec));
                }
            }
        }
    }
    DomainProof {
        domain,
        metrics,
        colour: ColourProof {
            shininess: opts.shininess,
            proven_upper: colour_bound(&outcomes, opts.shininess),
            how: COLOUR_HOW,
            length_error_signed_upper: finite(outcomes[1].proven_upper),
            found: found.and_then(|f| finite(f.0)),
            found_input: found.map(|f| f.1),
        },
        max_valid_angle: ValidAngle {
            threshold: opts.threshold,
            proven_deg: proven_valid_angle(m, k, domain, opts),
        },
    }
}

/// stress's angle sweep (`grid`, [`stress_grid`]) for `m`.
fn stress_grid_of(m: &Method, grid: &Grid, threshold: f64) -> StressGrid {
    let errs: Vec<_> = grid
        .cases
        .iter()
        .map(|c| {
            let s = m.eval_f64(&c.fragment, &c.lighting);
            errors(c, s.color, s.normal)
        })
        .collect();
    let mut worst = sweeps::Worst::default();
    for e in &errs {
        if let Some(v) = e.counted() {
            worst.add(v);
        }
    }
    StressGrid {
        domain: Domain::Edge,
        colour_found: worst.max,
        cases: worst.count,
        non_finite: worst.non_finite,
        max_valid_angle_deg: sweeps::max_valid_angle(grid, &errs, threshold),
    }
}

/// Proves everything about one covered method: over each domain, beside stress's grid.
pub fn prove_method(m: &Method, k: &Scale, grid: &Grid, opts: &ProveOptions) -> MethodProof {
    let start = Instant::now();
    let domains = Domain::ALL
        .iter()
        .map(|&d| prove_domain(m, k, d, opts))
        .collect();
    MethodProof {
        name: m.name.to_string(),
        reference: crate::method::PHONG_EXACT,
        domains,
        stress_grid: stress_grid_of(m, grid, opts.threshold),
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// Runs the proof for `methods`: the covered ones proven, the others listed with the reason.
pub fn run(methods: &[&'static Method], opts: &ProveOptions) -> Result<ProofReport> {
    if !(opts.max_angle_deg > 0.0 && opts.max_angle_deg <= 180.0) {
        return Err(Error::Usage(format!(
            "--max-angle {}: expected degrees in (0, 180]",
            opts.max_angle_deg
        )));
    }
    if !(opts.tolerance > 0.0 && opts.tolerance < 1.0) {
        return Err(Error::Usage(format!(
            "--tolerance {}: expected a fraction in (0, 1)",
            opts.tolerance
        )));
    }
    if !(opts.shininess.is_finite() && (0.0..=1e4).contains(&opts.shininess)) {
        return Err(Error::Usage(format!(
            "--shininess {}: expected 0..10000",
            opts.shininess
        )));
    }
    let start = Instant::now();
    let grid = stress_grid(opts.max_angle_deg, opts.shininess);
    let mut proofs = Vec::new();
    let mut out_of_reach = Vec::new();
    for m in methods {
        match covered::factor_of(m) {
            Some(k) => {
                if opts.progress {
                    log::info!("prove: {} ...", m.name);
                }
                let p = prove_method(m, k, &grid, opts);
                if opts.progress {
                    log::info!("prove: {} done in {:.2} s", m.name, p.seconds);
                }
                proofs.push(p);
            }
            None => out_of_reach.push(OutOfReach {
                name: m.name.to_string(),
                reason: covered::out_of_reach(m),
            }),
        }
    }
    let all = proofs.iter().all(|p| {
        p.domains
            .iter()
            .all(|d| d.metrics.iter().all(|x| x.within_tolerance))
    });
    let claims = bounds::proof_claims(methods);
    Ok(ProofReport {
        schema_version: SCHEMA_VERSION,
        max_angle_deg: opts.max_angle_deg,
        tolerance: opts.tolerance,
        shininess: opts.shininess,
        threshold: opts.threshold,
        domains: domain::described(),
        methods: proofs,
        out_of_reach,
        claims,
        all_within_tolerance: all,
        seconds: start.elapsed().as_secs_f64(),
    })
}
