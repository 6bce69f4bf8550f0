//! tune.json and the text table (also written as tune.txt).
use std::path::Path;

use super::choose::num;
use super::TuneReport;
use crate::cost::CostModelId;
use crate::error::{Error, Result};
use crate::method::{Precision, Verdict};

/// Writes DIR/tune.txt and, last (the run's completion marker), DIR/tune.json (the method
/// files are written by the run, before).
pub fn write(out: &Path, r: &TuneReport) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    crate::output::write_bytes_atomic(&out.join("tune.txt"), table(r).as_bytes())?;
    let json = serde_json::to_string_pretty(r).map_err(|e| Error::output("tune.json", e))?;
    crate::output::write_bytes_atomic(&out.join("tune.json"), (json + "\n").as_bytes())
}

fn domain_lines(r: &TuneReport) -> String {
    let [lo, hi] = r.domain.z_range;
    let mut s = format!("tune: {} ({})\n", r.name, r.source.kind);
    match &r.domain.mesh {
        Some(m) => {
            s += &format!(
                "domain: z in [{lo:.6}, {hi:.7}] over {} triangles (the smallest {:.6} at \
                 triangle {}); pixels at {}x{}: {} covered, z min {:.6}, p0.1 {:.6}, p1 {:.6}, \
                 median {:.6}\n",
                m.triangles,
                m.z_min,
                m.z_min_triangle,
                r.source.width.unwrap_or(0),
                r.source.height.unwrap_or(0),
                m.pixels_z.count,
                m.pixels_z.min,
                m.pixels_z.p0_1,
                m.pixels_z.p1,
                m.pixels_z.p50
            );
            let d = &m.dichotomy;
            s += &format!(
                "dichotomy: c = cos(span ends) >= {:.4} ({:.1} deg{}), 1/sqrt(2 + 2c) in \
                 [{:.4}, {:.4}]; pixels: factor median {:.4}, max {:.4}\n",
                d.c_min,
                d.max_angle_deg,
                if d.exact {
                    ""
                } else {
                    ", beyond 90: a lower end"
                },
                d.factor_range[0],
                d.factor_range[1],
                d.pixels_factor.p50,
                d.pixels_factor.max
            );
        }
        None => s += &format!("domain: z in [{lo:.6}, {hi:.7}]: {}\n", r.domain.how),
    }
    s += &format!(
        "budget: colour error {:.4e} (linear); {} light(s), shininess {}; bounds proven with \
         the programs' rounding (f32, f16)\n",
        r.budget,
        r.lights.colours.len(),
        r.lights.shininess
    );
    s
}

/// The proofs and the costs of every candidate, the answer per cost model, the classes and
/// the papers re-fitted.
pub fn table(r: &TuneReport) -> String {
    let mut s = domain_lines(r);
    s += &format!(
        "{:<32} {:<20} {:>10} {:>10} {:>10} {:>10} {:>10}\n",
        "candidate", "form", "f32 length", "f32 colour", "f16 colour", "in budget", "sampled"
    );
    for row in &r.candidates {
        let b = |p: Precision| row.bound(p);
        let within: Vec<&str> = Precision::ALL
            .iter()
            .filter(|&&p| b(p).is_some_and(|x| x.within(r.budget)))
            .map(|p| p.as_str())
            .collect();
        s += &format!(
            "{:<32} {:<20} {:>10} {:>10} {:>10} {:>10} {:>10}\n",
            row.candidate.id,
            row.candidate.label(),
            num(b(Precision::F32).and_then(|x| x.length_error)),
            num(b(Precision::F32).and_then(|x| x.colour)),
            num(b(Precision::F16).and_then(|x| x.colour)),
            if within.is_empty() {
                "no".into()
            } else {
                within.join("+")
            },
            num(row.sampled_length_error)
        );
    }
    for row in &r.candidates {
        if let Some(why) = &row.not_costed {
            s += &format!("{}: {why}\n", row.candidate.id);
        }
    }
    s += &cost_table(r);
    if let Some(note) = &r.note {
        s += &format!("answer: {note}\n");
    }
    s += "per cost model (cheapest proven within the budget and cheaper than phong_exact):\n";
    for a in &r.cost_models {
        s += &format!("  {}: {}\n", a.model, a.statement);
    }
    s += &super::classes::table(&r.classes);
    s += &super::refit::table(&r.papers);
    if !r.skipped.is_empty() {
        s += &format!("not fitted: {}\n", r.skipped.join("; "));
    }
    let t = &r.timings;
    s += &format!(
        "time: {:.1} s (domain {:.1}, fit and prove {:.1}, files {:.1}, costs {:.1}, classes {:.1})\n",
        t.total_s, t.domain_s, t.candidates_s, t.files_s, t.costs_s, t.classes_s
    );
    s
}

/// Each candidate's ratio to phong_exact per cost model (`*`: measured cheaper).
fn cost_table(r: &TuneReport) -> String {
    let models: Vec<&CostModelId> = r
        .cost_models
        .iter()
        .filter(|a| a.error.is_none())
        .map(|a| &a.model)
        .collect();
    if models.is_empty() {
        return "costs: no cost model measured\n".into();
    }
    let mut s = String::from("cost / phong_exact's (* cheaper):\n");
    s += &format!("{:<32}", "candidate");
    for m in &models {
        // a GPU family's model by its family (`amd:navi21:f16`), any other by its id
        let head = match m.gpu_family() {
            Some(f) if m.precision() == Precision::F32 => f,
            Some(f) => format!("{f}:{}", m.precision()),
            None => m.to_string(),
        };
        s += &format!(" {head:>16}");
    }
    s.push('\n');
    for row in &r.candidates {
        s += &format!("{:<32}", row.candidate.id);
        for m in &models {
            let c = row.costs.iter().find(|c| c.model == **m);
            let cell = c.map_or("n/a".to_string(), |c| {
                format!(
                    "{}{}",
                    c.ratio.map_or("n/a".into(), |x| format!("{x:.3}")),
                    if c.verdict == Verdict::Agrees {
                        "*"
                    } else {
                        ""
                    }
                )
            });
            s += &format!(" {cell:>16}");
        }
        s.push('\n');
    }
    s
}
