//! The papers' claims in claims.json/md, each with a verdict computed by this run: paired
//! timings (never two separate intervals), SPIR-V operation counts, GPU errors, and the method
//! table's f64 checks.
use super::*;
use crate::cost::rule::{factor_verdict, FACTOR_RULE};

use crate::bench::isolated::Comparison;
use crate::gpu::spirv::OpCountsDelta;
use crate::method::{Bound, Kind, Ops, Property, Verdict};

fn ratio_text(r: &MethodTiming, phong: &MethodTiming) -> String {
    format!(
        "{} / phong_exact per round: median {:.4}, 95% interval [{:.4}, {:.4}] over {} rounds{} ({}); medians {:.3} ms vs {:.3} ms",
        r.name,
        r.ratio_median,
        r.ratio_ci95_low,
        r.ratio_ci95_high,
        r.ratio_rounds,
        if r.ratio_non_finite > 0 {
            format!(", {} rounds without a finite ratio", r.ratio_non_finite)
        } else {
            String::new()
        },
        r.speed_vs_phong_exact.as_str(),
        r.median_ms,
        phong.median_ms
    )
}

/// How the timing verdicts are measured (bench.json has the samples and the clock).
fn timing_how(r: &MethodTiming) -> String {
    format!(
        "paired: in each of {} interleaved rounds ({} clock) the ratio of this program's draw to \
         phong_exact's in the same round; the median of those ratios with the sign-test 95% \
         interval (order statistics); faster when the interval lies below 1, slower when above, \
         inconclusive when it contains 1",
        r.samples, r.clock
    )
}

/// "normalization without a square root is faster than exact normalization", judged by the
/// paired ratio to phong_exact: faster agrees, slower disagrees, inconclusive is inconclusive.
pub(crate) fn faster_than_exact(r: &MethodTiming, phong: &MethodTiming) -> ClaimCheck {
    let speed = Speed::from_ratio(&super::row_ratio(r));
    let (verdict, reason) = match speed {
        Speed::Faster => (Verdict::Agrees, "faster: the paired 95% interval lies below 1"),
        Speed::Slower => (
            Verdict::Disagrees,
            "slower: the paired 95% interval lies above 1; lavapipe's inverse square root is a single vector instruction, the approximation costs more arithmetic",
        ),
        Speed::Inconclusive => (
            Verdict::Inconclusive,
            "the paired 95% interval contains 1: no measurable difference at this number of rounds; lavapipe computes inversesqrt with one vector instruction, so there is little to save",
        ),
        Speed::Unmeasured => (
            Verdict::Inconclusive,
            "no round gave a finite ratio (see ratio_non_finite): nothing to judge",
        ),
        Speed::TooNoisy => (
            Verdict::Inconclusive,
            "the machine is too noisy: phong_exact_control came out faster or slower than phong_exact across runs, so no speed verdict is given",
        ),
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: r.name.clone(),
        claim: "normalization without a square root is faster than exact normalization (docs/formulas.md#exact-phong)".into(),
        measured: ratio_text(r, phong),
        verdict,
        how: format!(
            "{}; the claim agrees when faster, disagrees when slower, else inconclusive",
            timing_how(r)
        ),
        reason: reason.into(),
    }
}

/// The operation counts a row's [`Kind::OperationCount`] claims, as the SPIR-V counter's delta.
pub(crate) fn claimed_ops(o: Ops) -> OpCountsDelta {
    OpCountsDelta {
        div: o.div.into(),
        sqrt: o.sqrt.into(),
        inverse_sqrt: 0,
        mul: o.mul.into(),
        add: o.add.into(),
        pow: 0,
        other_transcendental: 0,
    }
}

/// The counted SPIR-V cost of `method` above the unnormalised baseline against the claimed
/// counts `c` (claim `claim`), field by field: all equal agrees; some of the claimed
/// div/mul/add/sqrt counts equal partly; none disagrees.
pub(crate) fn op_counts(
    method: &str,
    claim: &str,
    c: OpCountsDelta,
    d: &OpCountsDelta,
) -> ClaimCheck {
    let fields = [
        ("div", d.div, c.div),
        ("mul", d.mul, c.mul),
        ("add", d.add, c.add),
        ("sqrt", d.sqrt, c.sqrt),
        ("inverse_sqrt", d.inverse_sqrt, c.inverse_sqrt),
        ("pow", d.pow, c.pow),
        (
            "other_transcendental",
            d.other_transcendental,
            c.other_transcendental,
        ),
    ];
    let differ: Vec<String> = fields
        .iter()
        .filter(|(_, got, want)| got != want)
        .map(|(name, got, want)| format!("{name} {got} (claimed {want})"))
        .collect();
    let claimed_equal = fields[..4]
        .iter()
        .filter(|(_, got, want)| got == want)
        .count();
    let verdict = if differ.is_empty() {
        Verdict::Agrees
    } else if claimed_equal > 0 {
        Verdict::Partly
    } else {
        Verdict::Disagrees
    };
    let same: Vec<&str> = fields[..4]
        .iter()
        .filter(|(_, got, want)| got == want)
        .map(|(name, _, _)| *name)
        .collect();
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: method.into(),
        claim: claim.into(),
        measured: format!(
            "SPIR-V of {method} minus phong_unnormalized: {} div, {} sqrt, {} inverse sqrt, {} mul, {} add; {}",
            d.div,
            d.sqrt,
            d.inverse_sqrt,
            d.mul,
            d.add,
            if differ.is_empty() {
                "as claimed".to_string()
            } else {
                format!("differs in {}", differ.join(", "))
            }
        ),
        verdict,
        how: format!(
            "static count of the compiled fragment shaders (src/gpu/spirv.rs count_ops, each \
             instruction once, weighted by components), {method} minus phong_unnormalized; \
             agrees when every count equals the claim, partly when some of the claimed \
             div/mul/add/sqrt counts do, disagrees when none does"
        ),
        reason: if same.is_empty() {
            "none of the claimed counts is what the compiler emits".into()
        } else {
            format!(
                "equal: {}; the compiler emits one GLSL.std.450 Normalize, which the counter prices by its definition as 1 inverse square root + n mul + (n-1) add (the dot) + n mul (src/gpu/spirv.rs), not as what a driver compiles it to",
                same.join(", ")
            )
        },
    }
}

/// Which measure a speed verdict comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Measure {
    /// The paired ratio of frame times (the whole draw).
    FrameTime,
    /// The paired ratio of isolated costs per evaluation ([`crate::bench::isolated`]).
    IsolatedCost,
}

impl Measure {
    fn name(self) -> &'static str {
        match self {
            Measure::FrameTime => "paired frame time",
            Measure::IsolatedCost => "isolated cost per evaluation",
        }
    }

    /// (low, median, high) of a row's paired ratio to phong_exact by this measure, when
    /// finite.
    fn ratio(self, r: &MethodTiming) -> Option<(f64, f64, f64)> {
        self.raw(r)
            .filter(|(lo, _, hi)| lo.is_finite() && hi.is_finite())
    }

    /// The ratio as measured, finite or not; None when this run did not measure it.
    fn raw(self, r: &MethodTiming) -> Option<(f64, f64, f64)> {
        match self {
            Measure::FrameTime => (r.ratio_rounds > 0).then_some((
                r.ratio_ci95_low,
                r.ratio_median,
                r.ratio_ci95_high,
            )),
            Measure::IsolatedCost => r
                .isolated_ratio_to_phong_exact
                .map(|i| (i.ci95_low, i.median, i.ci95_high)),
        }
    }
}

/// A claim "`factor` times faster than phong_exact" (a range `factor..factor_hi`), judged by
/// `measure`: the method's paired ratio to phong_exact should be at most 1 / factor, by
/// [`factor_verdict`]; inconclusive when the measured ratio is not finite; `not_checked` when
/// this run did not measure it (a report measures the isolated cost on its first scene only):
/// no measurement, no verdict.
pub(crate) fn factor_claim(
    r: &MethodTiming,
    claim: &str,
    factor: f64,
    measure: Measure,
) -> ClaimCheck {
    let target = 1.0 / factor;
    let (verdict, measured) = match measure.ratio(r) {
        Some((lo, mid, hi)) => (
            factor_verdict(lo, hi, target),
            format!(
                "{} / phong_exact by {}: median {mid:.4} (speed-up {:.2}x), 95% interval [{lo:.4}, {hi:.4}] (speed-up {:.2}x to {:.2}x); the claim needs <= {target:.4}",
                r.name,
                measure.name(),
                1.0 / mid,
                1.0 / hi,
                1.0 / lo
            ),
        ),
        // measured, but not finite: a failure of the measurement, never "no verdict"
        None if measure.raw(r).is_some() => (
            Verdict::Inconclusive,
            format!(
                "{}: {} / phong_exact is not finite (a failed measurement)",
                r.name,
                measure.name()
            ),
        ),
        None => (
            Verdict::NotChecked,
            format!("{}: not measured by {}", r.name, measure.name()),
        ),
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: r.name.clone(),
        claim: claim.into(),
        measured,
        verdict,
        how: format!(
            "measure: {}; paired per round against phong_exact, median and sign-test 95% interval; \
             {FACTOR_RULE} ({factor}x)",
            measure.name()
        ),
        reason: match measure {
            Measure::FrameTime => "the whole draw: rasterization, interpolation and the framebuffer are shared by every method and dominate a lavapipe frame",
            Measure::IsolatedCost => "the method's per-fragment code alone, evaluated independently per pixel as a fragment shader must; the seeds' speed-ups come from incremental evaluation along a scanline, which a fragment shader cannot do",
        }
        .into(),
    }
}

/// "Normalization without a square root is faster", judged by the isolated cost.
pub(crate) fn cheaper_isolated(r: &MethodTiming) -> ClaimCheck {
    let (verdict, measured) = match (r.isolated_vs_phong_exact, r.isolated_ratio_to_phong_exact) {
        (Some(c), Some(i)) => (
            match c {
                Comparison::Cheaper => Verdict::Agrees,
                Comparison::Dearer => Verdict::Disagrees,
                Comparison::Indistinguishable | Comparison::TooNoisy => Verdict::Inconclusive,
            },
            format!(
                "{} / phong_exact isolated cost per round: median {:.4}, 95% interval [{:.4}, {:.4}] ({c:?})",
                r.name, i.median, i.ci95_low, i.ci95_high
            ),
        ),
        _ => (
            Verdict::Inconclusive,
            format!("{}: isolated cost not measured", r.name),
        ),
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: r.name.clone(),
        claim: "normalization without a square root is faster than exact normalization (docs/formulas.md#exact-phong)".into(),
        measured,
        verdict,
        how: "measure: isolated cost per evaluation; agrees when the paired ratio's 95% interval lies below 1, disagrees above, inconclusive when it holds 1".into(),
        reason: "the formula alone, without rasterization; the shared lighting (a pow per light) is part of every evaluation".into(),
    }
}

/// "`fast` is `factor` times faster than `exact`" (a speed claim against a method other than
/// phong_exact, e.g. dichotomy_poly1's 2.5x over dichotomy_exact), from their isolated-cost
/// ratios to phong_exact (the quotient of the medians; its interval is not paired, so the
/// verdict needs the intervals to separate).
pub(crate) fn isolated_between(
    fast: &MethodTiming,
    exact: &MethodTiming,
    claim: &str,
    factor: f64,
) -> ClaimCheck {
    let (verdict, measured) = match (
        fast.isolated_ratio_to_phong_exact,
        exact.isolated_ratio_to_phong_exact,
    ) {
        (Some(f), Some(e)) => {
            // speed-up = exact / fast; its widest bounds from the two intervals
            let (lo, mid, hi) = (
                e.ci95_low / f.ci95_high,
                e.median / f.median,
                e.ci95_high / f.ci95_low,
            );
            // the ratio fast / exact, bounded the same way (a denominator end at or below 0
            // leaves it unbounded: inconclusive)
            let (rlo, rhi) = if e.ci95_low > 0.0 && e.ci95_high > 0.0 {
                (f.ci95_low / e.ci95_high, f.ci95_high / e.ci95_low)
            } else {
                (f64::NAN, f64::NAN)
            };
            (
                factor_verdict(rlo, rhi, 1.0 / factor),
                format!(
                    "{} / {} isolated cost: {mid:.2}x (bounds from the two intervals {lo:.2}x to {hi:.2}x)",
                    exact.name, fast.name
                ),
            )
        }
        _ => (
            Verdict::Inconclusive,
            "isolated cost not measured".to_string(),
        ),
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: fast.name.clone(),
        claim: claim.into(),
        measured,
        verdict,
        how: format!(
            "measure: isolated cost per evaluation; the speed-up of {} over {} bounded from their ratios to phong_exact; {FACTOR_RULE} ({factor}x)",
            fast.name, exact.name
        ),
        reason: "the two programs are timed in separate rounds against phong_exact, so the ratio between them is bounded from two intervals, not paired".into(),
    }
}

/// The claims of the rows of this run, each with a verdict computed now: a speed claim
/// ([`Kind::Speed`]) from this run's paired frame times and isolated costs, an operation count
/// from the SPIR-V, a length bound ([`Bound::Length`]) from this run's GPU images (beside its
/// check's f64 sweep and proof), every row's check that measures something, and the claim of
/// [`Property::SqrtFree`] ("faster than exact normalisation") for each row that has it.
///
/// `len2_range`: the range of the interpolated normal's squared length |n|^2 over the scene's
/// triangles ([`interpolated_len2_range`]), said beside a length bound judged on the GPU.
pub(crate) fn claims(rows: &[MethodTiming], len2_range: Option<(f64, f64)>) -> Vec<ClaimCheck> {
    let mut out = Vec::new();
    let find = |n: &str| rows.iter().find(|r| r.name == n);
    let Some(phong) = find(crate::method::PHONG_EXACT) else {
        return out;
    };
    for m in crate::method::METHODS {
        let Some(r) = find(m.name) else { continue };
        if m.has(Property::SqrtFree) {
            out.push(faster_than_exact(r, phong));
            if r.isolated_ratio_to_phong_exact.is_some() {
                out.push(cheaper_isolated(r));
            }
        }
        for c in m.claims {
            match c.kind {
                Kind::Speed { factor, than } if than == crate::method::PHONG_EXACT => {
                    out.push(factor_claim(r, c.claim, factor, Measure::FrameTime));
                    out.push(factor_claim(r, c.claim, factor, Measure::IsolatedCost));
                }
                Kind::Speed { factor, than } => {
                    if let Some(slow) = find(than) {
                        out.push(isolated_between(r, slow, c.claim, factor));
                    }
                }
                Kind::OperationCount(Some(ops)) => {
                    if let Some(d) = &r.static_ops_above_unnormalized {
                        out.push(op_counts(m.name, c.claim, claimed_ops(ops), d));
                    }
                }
                Kind::ErrorBound(Bound::Length { at_most, z }) => {
                    if let Some(e) = r.error.as_ref().and_then(|e| e.max_normal_length_error) {
                        out.push(gpu_length_bound(m.name, c.claim, at_most, z, e, len2_range));
                    }
                }
                _ => {}
            }
            // the row's own check (f64 sweep, proof); those it leaves to the bench (timing,
            // op count) are the rows above
            let j = crate::prove::bounds::judge(m, c);
            if j.verdict != Verdict::NotChecked {
                out.push(ClaimCheck {
                    evidence: j.evidence,
                    method: m.name.into(),
                    claim: c.claim.into(),
                    measured: j.measured,
                    verdict: j.verdict,
                    how: j.how,
                    reason: "a property of the formula, checked in f64 and, for a bound, by proof (the same check as `shadelab list --json`)".into(),
                });
            }
        }
    }
    out
}

/// A length bound ([`Bound::Length`], at most `at_most` for z in `z`) against the largest
/// normal-length error `e` of this run's GPU image.
fn gpu_length_bound(
    method: &str,
    claim: &str,
    at_most: f64,
    z: (f64, f64),
    e: f64,
    len2_range: Option<(f64, f64)>,
) -> ClaimCheck {
    let pct = 100.0 * at_most;
    ClaimCheck {
        evidence: crate::method::Evidence::found(e, crate::method::Quantity::RelativeError),
        method: method.into(),
        claim: claim.into(),
        measured: format!(
            "max ||N'| - 1| on this scene's pixels: {:.3} %; {}",
            e * 100.0,
            len2_text(len2_range, z.0)
        ),
        verdict: if e <= at_most {
            Verdict::Agrees
        } else {
            Verdict::Disagrees
        },
        how: format!(
            "the largest normal-length error over the covered pixels of this run's GPU image \
             (compare metrics); agrees when <= {pct} % over the |n|^2 range this scene reaches \
             (stated in `measured`), not over the claim's whole range"
        ),
        reason: format!(
            "measured on the GPU in this run over the scene's |n|^2 range only; the f64 sweep \
             over z = |n|^2 in [{}, {}] is the row from the method table",
            z.0, z.1
        ),
    }
}

/// The range of |n|^2 of the linearly interpolated vertex normals (`normals`, three unit
/// normals per triangle) over every triangle, sampled at the barycentric points (i, j, k) / 8:
/// the z that Mikami's approximations see on this scene. `None` without a triangle or with a
/// non-finite normal.
pub(crate) fn interpolated_len2_range(normals: &[[f32; 3]]) -> Option<(f64, f64)> {
    const STEPS: usize = 8;
    let mut range: Option<(f64, f64)> = None;
    for t in normals.chunks_exact(3) {
        for i in 0..=STEPS {
            for j in 0..=STEPS - i {
                let w = [i, j, STEPS - i - j].map(|x| x as f64 / STEPS as f64);
                let mut n = [0.0f64; 3];
                for (c, wc) in t.iter().zip(w) {
                    for (a, b) in n.iter_mut().zip(c) {
                        *a += wc * f64::from(*b);
                    }
                }
                let z = n.iter().map(|x| x * x).sum::<f64>();
                if !z.is_finite() {
                    return None;
                }
                range = Some(range.map_or((z, z), |(lo, hi)| (lo.min(z), hi.max(z))));
            }
        }
    }
    range
}

/// What [`claims`] says of the |n|^2 range it saw, against the claim's range from `lower`.
fn len2_text(range: Option<(f64, f64)>, lower: f64) -> String {
    match range {
        Some((lo, hi)) => format!(
            "this scene's interpolated |n|^2 spans [{lo:.4}, {hi:.4}] (sampled at barycentric \
             steps of 1/8 on every triangle){}",
            if lo > lower + 1e-9 {
                format!(
                    ": it never reaches the claim's lower end {lower}, so z in [{lower}, {lo:.4}) \
                     is checked only by the f64 row"
                )
            } else {
                String::new()
            }
        ),
        None => "the scene's |n|^2 range was not computed".into(),
    }
}
