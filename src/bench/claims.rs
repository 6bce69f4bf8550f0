//! The papers' claims in claims.json/md, each with a verdict computed by this run: paired
//! timings (never two separate intervals), SPIR-V operation counts, GPU errors, and the method
//! table's f64 checks.
use super::*;
use crate::cost::rule::{factor_verdict, FACTOR_RULE};

use crate::bench::isolated::Comparison;
use crate::gpu::spirv::OpCountsDelta;
use crate::method::{Property, Verdict};

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

/// The claimed factor (docs/formulas.md#gouraud-shading).
pub(crate) const GOURAUD_FACTOR: f64 = 50.0;

/// "Phong ... takes more than 50x longer than Gouraud": phong_exact / gouraud per round is the
/// reciprocal of gouraud's paired ratio, so its interval is [1 / high, 1 / low].
pub(crate) fn phong_50x_gouraud(
    phong: &MethodTiming,
    g: &MethodTiming,
    floor: &MethodTiming,
) -> ClaimCheck {
    let ratio = 1.0 / g.ratio_median;
    let low = 1.0 / g.ratio_ci95_high;
    let high = if g.ratio_ci95_low > 0.0 {
        1.0 / g.ratio_ci95_low
    } else {
        f64::INFINITY
    };
    let verdict = if g.ratio_rounds == 0 {
        Verdict::Inconclusive
    } else {
        factor_verdict(g.ratio_ci95_low, g.ratio_ci95_high, 1.0 / GOURAUD_FACTOR)
    };
    let phong_ms = phong.median_ms;
    let g_above = g.median_ms - floor.median_ms;
    let above = if g_above > 0.0 {
        format!(
            "{:.2}x above the constant-colour floor (medians)",
            (phong_ms - floor.median_ms) / g_above
        )
    } else {
        format!("Gouraud is at or below the constant-colour floor ({g_above:+.3} ms), so its cost above the floor is nil")
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: g.name.clone(),
        claim: "Phong shading of an average triangle takes more than 50x longer than Gouraud (docs/formulas.md#gouraud-shading)".into(),
        measured: format!(
            "phong_exact / gouraud per round: median {ratio:.3}x, 95% interval {low:.3}x to {high:.3}x over {} rounds; {above}",
            g.ratio_rounds
        ),
        verdict,
        how: format!(
            "{}; {FACTOR_RULE} ({GOURAUD_FACTOR}x)",
            timing_how(g)
        ),
        reason: "on a GPU-style pipeline both shade every covered pixel in the same fragment stage; Gouraud only moves the lighting to the vertices, and rasterization, interpolation and the framebuffer dominate".into(),
    }
}

/// docs/formulas.md#exact-phong: normalising costs 3 divisions, 3 multiplications, 2 additions and
/// 1 square root (and nothing else).
pub(crate) const NORMALIZATION_CLAIM: OpCountsDelta = OpCountsDelta {
    div: 3,
    sqrt: 1,
    inverse_sqrt: 0,
    mul: 3,
    add: 2,
    pow: 0,
    other_transcendental: 0,
};

/// The counted SPIR-V cost of exact normalisation against [`NORMALIZATION_CLAIM`], field by
/// field: all equal agrees; some of the claimed div/mul/add/sqrt counts equal partly; none
/// disagrees.
pub(crate) fn normalization_ops(d: &OpCountsDelta) -> ClaimCheck {
    let c = NORMALIZATION_CLAIM;
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
        method: crate::method::PHONG_EXACT.into(),
        claim: "normalisation costs 3 divisions + 3 multiplications + 2 additions + 1 square root (docs/formulas.md#exact-phong)".into(),
        measured: format!(
            "SPIR-V of phong_exact minus phong_unnormalized: {} div, {} sqrt, {} inverse sqrt, {} mul, {} add; {}",
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
        how: "static count of the compiled fragment shaders (src/gpu/spirv.rs count_ops, each \
              instruction once, weighted by components), phong_exact minus phong_unnormalized; \
              agrees when every count equals the claim, partly when some of the claimed \
              div/mul/add/sqrt counts do, disagrees when none does"
            .into(),
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

    /// (low, median, high) of a row's paired ratio to phong_exact by this measure.
    fn ratio(self, r: &MethodTiming) -> Option<(f64, f64, f64)> {
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
        .filter(|(lo, _, hi)| lo.is_finite() && hi.is_finite())
    }
}

/// A claim "`factor` times faster than phong_exact" (a range `factor..factor_hi`), judged by
/// `measure`: the method's paired ratio to phong_exact should be at most 1 / factor, by
/// [`factor_verdict`]; inconclusive when unmeasured.
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
        None => (
            Verdict::Inconclusive,
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

/// "2.5x faster normal interpolation with the approximated inverse root": dichotomy_poly1 over
/// dichotomy_exact, from their isolated-cost ratios to phong_exact (the quotient of the
/// medians; its interval is not paired, so the verdict needs the intervals to separate).
pub(crate) fn dichotomy_isolated(fast: &MethodTiming, exact: &MethodTiming) -> ClaimCheck {
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
                factor_verdict(rlo, rhi, 1.0 / 2.5),
                format!("dichotomy_exact / dichotomy_poly1 isolated cost: {mid:.2}x (bounds from the two intervals {lo:.2}x to {hi:.2}x)"),
            )
        }
        _ => (
            Verdict::Inconclusive,
            "isolated cost not measured".to_string(),
        ),
    };
    ClaimCheck {
        evidence: crate::method::Evidence::MEASURED,
        method: exact.name.clone(),
        claim: "2.5x faster normal interpolation with the approximated inverse root (docs/formulas.md#dichotomy)".into(),
        measured,
        verdict,
        how: format!("measure: isolated cost per evaluation; the speed-up of dichotomy_poly1 over dichotomy_exact bounded from their ratios to phong_exact; {FACTOR_RULE} (2.5x)"),
        reason: "both halve toward the pixel level by level; only the inverse root differs, and lavapipe's exact inverse root is one vector instruction".into(),
    }
}

/// The seeds' speed factors against exact Phong: (method, claim, factor).
pub(crate) const FACTOR_CLAIMS: [(&str, &str, f64); 6] = [
    (
        "spherical_angular",
        "doubles the speed of polygon shading (docs/formulas.md#spherical-angular-interpolation)",
        2.0,
    ),
    (
        "quadratic_scanline",
        "reduces the normal computation time about 2-3x (docs/formulas.md#quadratic-interpolation-along-the-span): at least 2x",
        2.0,
    ),
    (
        "segments_k2",
        "diffuse shading 1.3x faster at k = 2 (docs/formulas.md#digital-segments)",
        1.3,
    ),
    (
        "segments_k2_poly1",
        "diffuse shading 1.8x faster at k = 2 with the degree-1 polynomial (docs/formulas.md#digital-segments)",
        1.8,
    ),
    (
        "segments_k3",
        "diffuse shading 1.48x faster at k = 3 (docs/formulas.md#digital-segments)",
        1.48,
    ),
    (
        "segments_k3_poly1",
        "diffuse shading 2.09x faster at k = 3 with the degree-1 polynomial (docs/formulas.md#digital-segments)",
        2.09,
    ),
];

/// The seeds' claims about the methods of this run: timing claims from this run's timings,
/// the op-count claim from the SPIR-V, Mikami's error bound from this run's GPU images, and
/// the method table's claims from their f64 checks, run now. Claims of methods not yet
/// implemented are listed as not checked.
///
/// `len2_range`: the range of the interpolated normal's squared length |n|^2 over the scene's
/// triangles ([`interpolated_len2_range`]), said beside Mikami's GPU bound.
pub(crate) fn claims(
    rows: &[MethodTiming],
    floor: &MethodTiming,
    len2_range: Option<(f64, f64)>,
) -> Vec<ClaimCheck> {
    let mut out = Vec::new();
    let find = |n: &str| rows.iter().find(|r| r.name == n);
    let Some(phong) = find(crate::method::PHONG_EXACT) else {
        return out;
    };
    if let Some(g) = find("gouraud") {
        out.push(phong_50x_gouraud(phong, g, floor));
    }
    for n in crate::method::with_property(Property::SqrtFree).map(|m| m.name) {
        if let Some(r) = find(n) {
            out.push(faster_than_exact(r, phong));
            if r.isolated_ratio_to_phong_exact.is_some() {
                out.push(cheaper_isolated(r));
            }
        }
    }
    for (name, claim, factor) in FACTOR_CLAIMS {
        if let Some(r) = find(name) {
            out.push(factor_claim(r, claim, factor, Measure::FrameTime));
            out.push(factor_claim(r, claim, factor, Measure::IsolatedCost));
        }
    }
    if let (Some(exact), Some(g)) = (phong.isolated_ns_per_eval, find("gouraud")) {
        if let Some(i) = g.isolated_ratio_to_phong_exact {
            let (lo, hi) = (1.0 / i.ci95_high, 1.0 / i.ci95_low);
            out.push(ClaimCheck {
                evidence: crate::method::Evidence::MEASURED,
                method: g.name.clone(),
                claim: "Phong shading of an average triangle takes more than 50x longer than Gouraud (docs/formulas.md#gouraud-shading)".into(),
                measured: format!(
                    "phong_exact / gouraud isolated cost per round: median {:.2}x, 95% interval [{lo:.2}x, {hi:.2}x] (phong_exact {exact:.2} ns per evaluation)",
                    1.0 / i.median
                ),
                verdict: factor_verdict(i.ci95_low, i.ci95_high, 1.0 / GOURAUD_FACTOR),
                how: format!("measure: isolated cost per evaluation (phong_exact's over gouraud's, paired per round); {FACTOR_RULE} ({GOURAUD_FACTOR}x)"),
                reason: "gouraud's per-fragment code is a single interpolated colour, so its isolated cost is near the chain's own cost".into(),
            });
        }
    }
    if let (Some(fast), Some(exact)) = (find("dichotomy_poly1"), find("dichotomy_exact")) {
        out.push(dichotomy_isolated(fast, exact));
    }
    if let Some(d) = phong.static_ops_above_unnormalized {
        out.push(normalization_ops(&d));
    }
    for n in ["mikami_const", "mikami_linear", "mikami_quadratic"] {
        if let Some(e) = find(n)
            .and_then(|r| r.error.as_ref())
            .and_then(|e| e.max_normal_length_error)
        {
            out.push(ClaimCheck {
                evidence: crate::method::Evidence::found(e, crate::method::Quantity::RelativeError),
                method: n.into(),
                claim: "maximum normalised relative error <= 1.5 % (docs/formulas.md#mikami-square-root)".into(),
                measured: format!(
                    "max ||N'| - 1| on this scene's pixels: {:.3} %; {}",
                    e * 100.0,
                    len2_text(len2_range)
                ),
                verdict: if e <= 0.015 { Verdict::Agrees } else { Verdict::Disagrees },
                how: "the largest normal-length error over the covered pixels of this run's GPU image (compare metrics); agrees when <= 1.5 % over the |n|^2 range this scene reaches (stated in `measured`), not over the claim's whole range".into(),
                reason: "measured on the GPU in this run over the scene's |n|^2 range only; the f64 sweep over z = |n|^2 in [0.25, 1] is the row from the method table".into(),
            });
        }
    }
    // The method table's claims of the methods in this run, each checked now in f64; those
    // its checks leave to the bench (timing, op count) are the rows above.
    for m in crate::method::METHODS {
        if !rows.iter().any(|r| r.name == m.name) {
            continue;
        }
        for c in m.claims {
            let r = crate::prove::bounds::with_proof(m.name, c);
            if r.verdict == Verdict::NotChecked {
                continue;
            }
            out.push(ClaimCheck {
                evidence: r.evidence,
                method: m.name.into(),
                claim: c.claim.into(),
                measured: r.measured,
                verdict: r.verdict,
                how: r.how,
                reason: "a property of the formula, checked in f64 and, for a bound, by proof (the same check as `shadelab list --json`)".into(),
            });
        }
    }
    out
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

/// What [`claims`] says of the |n|^2 range it saw, against the claim's [0.25, 1].
fn len2_text(range: Option<(f64, f64)>) -> String {
    match range {
        Some((lo, hi)) => format!(
            "this scene's interpolated |n|^2 spans [{lo:.4}, {hi:.4}] (sampled at barycentric \
             steps of 1/8 on every triangle){}",
            if lo > 0.25 + 1e-9 {
                format!(
                    ": it never reaches the claim's lower end 0.25, so z in [0.25, {lo:.4}) is \
                     checked only by the f64 row"
                )
            } else {
                String::new()
            }
        ),
        None => "the scene's |n|^2 range was not computed".into(),
    }
}
