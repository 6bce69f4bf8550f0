//! What `prove` prints and writes: the terminal table (every figure beside the domain it is
//! for) and DIR/proof.json with one replayable stress case per found input.
use std::path::Path;

use super::ProofReport;
use crate::cases::Case;
use crate::error::{Error, Result};

fn num(x: Option<f64>) -> String {
    x.map_or("null".into(), |v| format!("{v:.4e}"))
}

fn deg(x: Option<f64>) -> String {
    x.map_or("none".into(), |a| format!("{a:.2}"))
}

/// The terminal table: per method and domain the metrics, the colour and the valid angle;
/// then stress's grid (edges), the claims and the methods out of reach.
pub fn table(r: &ProofReport) -> String {
    let mut s = String::new();
    for d in &r.domains {
        s += &format!("domain {}: {}\n", d.name.as_str(), d.description);
    }
    s += &format!(
        "{:<20} {:<9} {:<16} {:>11} {:>11} {:>9} {:>8} {:>7}\n",
        "method", "domain", "metric", "proven", "found", "rel.gap", "boxes", "s"
    );
    for m in &r.methods {
        for d in &m.domains {
            let domain = d.domain.as_str();
            for x in &d.metrics {
                s += &format!(
                    "{:<20} {:<9} {:<16} {:>11} {:>11} {:>9} {:>8} {:>7.2}{}\n",
                    m.name,
                    domain,
                    x.metric,
                    num(x.proven_upper),
                    num(x.found),
                    x.relative_gap.map_or("null".into(), |g| format!("{g:.2e}")),
                    x.boxes,
                    x.seconds,
                    if x.within_tolerance {
                        ""
                    } else {
                        "  NOT WITHIN TOLERANCE"
                    }
                );
            }
            s += &format!(
                "{:<20} {:<9} {:<16} {:>11} {:>11}   max valid angle proven {} deg ({domain})\n",
                m.name,
                domain,
                "colour_error",
                num(d.colour.proven_upper),
                num(d.colour.found),
                deg(d.max_valid_angle.proven_deg),
            );
        }
        let g = &m.stress_grid;
        s += &format!(
            "{:<20} stress grid ({} cases, {}): colour {}, max valid angle {} deg\n",
            m.name,
            g.cases,
            g.domain.as_str(),
            num(g.colour_found),
            g.max_valid_angle_deg
                .map_or("none".into(), |a| format!("{a}")),
        );
    }
    for c in &r.claims {
        s += &format!(
            "claim {} [{}, {}]: {}\n",
            c.method,
            c.verdict,
            c.basis.as_str(),
            c.measured
        );
    }
    for o in &r.out_of_reach {
        s += &format!("out of reach: {}: {}\n", o.name, o.reason);
    }
    s += &format!(
        "all within tolerance {}: {} ({:.1} s)\n",
        r.tolerance, r.all_within_tolerance, r.seconds
    );
    s
}

/// Writes DIR/cases/<method>_<domain>_<metric>.json (each found input as a stress case file,
/// for `stress --replay`) and, last (the run's completion marker), DIR/proof.json.
pub fn write(out: &Path, r: &ProofReport) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let cases = out.join("cases");
    std::fs::create_dir_all(&cases).map_err(|e| Error::io(&cases, e))?;
    for m in &r.methods {
        let method = crate::method::find(&m.name)?;
        for d in &m.domains {
            let inputs = d
                .metrics
                .iter()
                .map(|x| (x.metric, x.found_input))
                .chain([("colour_error", d.colour.found_input)]);
            for (name, spec) in inputs {
                let Some(spec) = spec else { continue };
                let case = crate::stress::case_report(
                    method,
                    &Case::new(spec),
                    None,
                    crate::method::Precision::F32,
                )?;
                let json = serde_json::to_string_pretty(&case)
                    .map_err(|e| Error::output("a case file", e))?;
                let file = format!("{}_{}_{name}.json", m.name, d.domain.as_str());
                crate::output::write_bytes_atomic(&cases.join(file), (json + "\n").as_bytes())?;
            }
        }
    }
    let json = serde_json::to_string_pretty(r).map_err(|e| Error::output("proof.json", e))?;
    crate::output::write_bytes_atomic(&out.join("proof.json"), (json + "\n").as_bytes())
}
