//! Speed claims of the papers, each with a verdict computed from this run's timings.
use super::*;

fn ratio_text(r: &MethodTiming, phong: &MethodTiming) -> String {
    format!(
        "{:.3} ms [{:.3}, {:.3}] vs phong_exact {:.3} ms [{:.3}, {:.3}] (ratio {:.3})",
        r.median_ms,
        r.ci95_low_ms,
        r.ci95_high_ms,
        phong.median_ms,
        phong.ci95_low_ms,
        phong.ci95_high_ms,
        r.ratio_to_phong_exact
    )
}

/// The seeds' claims that this milestone's methods can test, measured in this run where they
/// are timing or GPU-error claims, and as the method table records otherwise.
pub(crate) fn claims(rows: &[MethodTiming], floor: &MethodTiming) -> Vec<ClaimCheck> {
    let mut out = Vec::new();
    let find = |n: &str| rows.iter().find(|r| r.name == n);
    let Some(phong) = find("phong_exact") else {
        return out;
    };
    if let Some(g) = find("gouraud") {
        let ratio = phong.median_ms / g.median_ms;
        let g_above = g.median_ms - floor.median_ms;
        let above = if g_above > 0.0 {
            format!(
                "{:.2}x above the constant-colour floor",
                (phong.median_ms - floor.median_ms) / g_above
            )
        } else {
            format!("Gouraud is at or below the constant-colour floor ({g_above:+.3} ms), so its cost above the floor is nil")
        };
        out.push(ClaimCheck {
            method: "gouraud".into(),
            claim: "Phong shading of an average triangle takes more than 50x longer than Gouraud (S002 l.151-153)".into(),
            measured: format!("phong_exact / gouraud = {ratio:.2}x per frame; {above}"),
            verdict: if ratio > 50.0 { "agrees" } else { "disagrees" }.into(),
            reason: "on a GPU-style pipeline both shade every covered pixel in the same fragment stage; Gouraud only moves the lighting to the vertices, and rasterization, interpolation and the framebuffer dominate".into(),
        });
    }
    for n in [
        "newton_raphson",
        "lyon_taylor",
        "lyon_shift",
        "hast_half_vector",
        "mikami_const",
        "mikami_linear",
        "mikami_quadratic",
        "romanyuk_poly",
        "quaternion",
        "quaternion_local",
    ] {
        let Some(r) = find(n) else { continue };
        let faster = r.ci95_high_ms < phong.ci95_low_ms;
        let slower = r.ci95_low_ms > phong.ci95_high_ms;
        out.push(ClaimCheck {
            method: n.into(),
            claim: "normalization without a square root is faster than exact normalization (S000, S004 l.159-172)".into(),
            measured: ratio_text(r, phong),
            verdict: if faster { "agrees" } else { "disagrees" }.into(),
            reason: if faster {
                "faster beyond both 95% intervals".into()
            } else if slower {
                "slower beyond both 95% intervals: lavapipe's inverse square root is a single vector instruction, the approximation costs more arithmetic".into()
            } else {
                "the 95% intervals overlap: no measurable difference; lavapipe computes inversesqrt with one vector instruction, so there is little to save".into()
            },
        });
    }
    if let (Some(d), Some(ops)) = (phong.static_ops_above_unnormalized, phong.static_ops) {
        let _ = ops;
        out.push(ClaimCheck {
            method: "phong_exact".into(),
            claim: "normalisation costs 3 divisions + 3 multiplications + 2 additions + 1 square root (S004 l.159-163)".into(),
            measured: format!(
                "SPIR-V of phong_exact minus phong_unnormalized: {} div, {} sqrt, {} inverse sqrt, {} mul, {} add",
                d.div, d.sqrt, d.inverse_sqrt, d.mul, d.add
            ),
            verdict: "partly".into(),
            reason: "the same dot product (3 mul + 2 add), but the compiler normalizes with one inverse square root and multiplications instead of a square root and three divisions".into(),
        });
    }
    for n in ["mikami_const", "mikami_linear", "mikami_quadratic"] {
        if let Some(e) = find(n)
            .and_then(|r| r.error.as_ref())
            .and_then(|e| e.max_normal_length_error)
        {
            out.push(ClaimCheck {
                method: n.into(),
                claim: "maximum normalised relative error <= 1.5 % (S000 l.74)".into(),
                measured: format!("max ||N'| - 1| on this scene's pixels: {:.3} %", e * 100.0),
                verdict: if e <= 0.015 { "agrees" } else { "disagrees" }.into(),
                reason: "measured on the GPU in this run (the f64 sweep over z in [0.25, 1] is in the method table)".into(),
            });
        }
    }
    // The method table's claims (measured by the formulas tests), for completeness.
    for m in crate::method::METHODS {
        for c in m.claims {
            if c.verdict == "not_checked" {
                continue;
            }
            out.push(ClaimCheck {
                method: m.name.into(),
                claim: c.claim.into(),
                measured: c.measured.into(),
                verdict: c.verdict.into(),
                reason: "f64 check of the formula (src/formulas.rs tests)".into(),
            });
        }
    }
    for (claim, who) in [
        (
            "spherical-angular interpolation doubles polygon shading speed (S000 l.102-104)",
            "spherical_angular",
        ),
        (
            "quadratic interpolation reduces normal computation time 2-3x (S000 l.151-152)",
            "quadratic_scanline",
        ),
        (
            "dichotomy with the approximated inverse root: 2.5x faster (S000 l.181)",
            "dichotomy",
        ),
        (
            "digital segments k = 2: 1.3x / 1.8x; k = 3: 1.48x / 2.09x (S002 l.674-682)",
            "digital_segments",
        ),
        (
            "Bishop-Weimer: 5 additions and 1 memory access per pixel (S004 l.124-128)",
            "bishop_weimer",
        ),
    ] {
        out.push(ClaimCheck {
            method: who.into(),
            claim: claim.into(),
            measured: "-".into(),
            verdict: "not_checked".into(),
            reason: "the scanline family is not implemented yet (roadmap step 5)".into(),
        });
    }
    out
}
