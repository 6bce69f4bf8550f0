//! A tuned method file is a claim, not a proof: its `// shadelab-tuned:` line states the form,
//! its coefficients, the domain of z and the float32 program's proven length error there
//! ([`crate::method::tuned::Tuned`]), and every command that loads the file proves the line
//! again ([`check_files`], before anything is compiled), in milliseconds, by `tune`'s own
//! interval branch-and-bound ([`super::proof::length_bound`], with a box budget and no time
//! limit, so that the bound is the same number wherever it is computed). A line whose domain or
//! coefficients were edited then proves a larger bound than it states (or none below 1, where
//! N' may turn round or overflow) and the file is refused (exit 2): `auto` draws a tuned row
//! only on triangles inside its domain, so an unproven domain would let it draw the form
//! where it was never proven (a domain widened to [0, 100] drew non-finite pixels).
use std::path::{Path, PathBuf};

use super::candidate::{Candidate, Family};
use super::proof::length_bound;
use crate::error::{Error, Result};
use crate::method::rounded::F32;
use crate::method::tuned::{Tuned, TunedForm};
use crate::prove::interval::Interval;

/// The box budget of a line's proof. The forms tune writes converge in at most a few thousand
/// boxes (tune.json's `boxes`: 1,664 for a quartic on sphere_coarse's domain), each a few
/// microseconds; the cap keeps a pathological line under about 0.1 s.
pub const LINE_BOXES: usize = 20_000;

/// The candidate of a line (its form, steps and coefficients).
fn candidate(t: &Tuned) -> Candidate {
    Candidate {
        id: "tuned".into(),
        family: match t.form {
            TunedForm::Minimax => Family::Minimax,
            TunedForm::Newton => Family::Newton,
        },
        degree: Some(t.coeffs.len().saturating_sub(1)),
        steps: t.steps,
        coeffs: t.coeffs.clone(),
        ..Candidate::reference()
    }
}

/// The float32 program's proven length error over the line's domain (infinite when nothing
/// finite is proven): what `tune` writes into the line, what a loader checks.
pub fn line_bound(t: &Tuned) -> f64 {
    let [lo, hi] = t.domain;
    length_bound::<F32>(&candidate(t), Interval::new(lo, hi), LINE_BOXES)
}

/// Proves `t`'s line again: its bound over its domain must be below 1 (N' keeps its
/// direction, nothing overflows) and at most the bound the line states. `Err` says what
/// differs and what to do.
pub fn verify(t: &Tuned) -> std::result::Result<f64, String> {
    let [lo, hi] = t.domain;
    let again = "its domain or coefficients are not the ones shadelab tune proved: run \
                 `shadelab tune` again, or delete the line to use the file as your own method";
    let Some(stated) = t.length_error else {
        return Err(format!(
            "its {} line states no proven length error (a file of an older shadelab): run \
             `shadelab tune` again",
            crate::method::tuned::TUNED_MARKER
        ));
    };
    let proven = line_bound(t);
    // a NaN bound is no proof either
    if proven.is_nan() || proven >= 1.0 {
        return Err(format!(
            "the form is not proven on its domain of z [{lo}, {hi}]: its length error there is \
             bounded by {proven:e} only (the limit is 1; beyond it N' may turn round or \
             overflow): {again}"
        ));
    }
    if proven > stated {
        return Err(format!(
            "its line claims a length error of at most {stated:e} on z in [{lo}, {hi}]; proven \
             again, the bound there is {proven:e}: {again}"
        ));
    }
    Ok(proven)
}

/// Checks every tuned file among `paths` (folders expanded as `--method-file` expands them):
/// the first whose line does not prove again is an error (exit 2) naming the file. Files
/// without a line are the user's own methods, not checked here.
pub fn check_files(paths: &[PathBuf]) -> Result<()> {
    for p in crate::method::user::expand(paths)? {
        check_file(&p)?;
    }
    Ok(())
}

fn check_file(path: &Path) -> Result<()> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    match Tuned::of_text(&text) {
        // a line that does not parse is refused by the loader with its own message
        None | Some(Err(_)) => Ok(()),
        Some(Ok(t)) => verify(&t)
            .map(|_| ())
            .map_err(|why| Error::Usage(format!("{}: {why}", path.display()))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// tune's newton k1 seed d1 for sphere_coarse (its file's line, 2026-11-28).
    fn line() -> Tuned {
        let mut t = Tuned {
            form: TunedForm::Newton,
            steps: 1,
            coeffs: vec![f64::from(1.5775199f32), f64::from(-0.57940733f32)],
            domain: [0.8181351227401077, 1.0000005513794614],
            length_error: None,
        };
        t.length_error = Some(line_bound(&t));
        t
    }

    /// The line as written proves again, in well under a second, with the bound it states.
    #[test]
    fn the_line_tune_writes_proves_again() {
        let t = line();
        let start = std::time::Instant::now();
        let b = verify(&t).unwrap();
        assert!(start.elapsed().as_secs_f64() < 0.5, "{:?}", start.elapsed());
        assert_eq!(Some(b), t.length_error);
        // the bound holds the formula at real points of the domain
        for i in 0..=1000 {
            let z = t.domain[0] + (t.domain[1] - t.domain[0]) * i as f64 / 1000.0;
            assert!((t.k(z) * z.sqrt() - 1.0).abs() <= b, "z {z}");
        }
        // a narrower domain is a weaker claim, proven too
        let narrow = Tuned {
            domain: [0.9, 1.0],
            ..t.clone()
        };
        assert!(verify(&narrow).is_ok());
    }

    /// Teeth: an edited domain or coefficient, a lowered bound or none at all are refused, each
    /// saying why.
    #[test]
    fn an_edited_line_is_refused() {
        let t = line();
        let refuse = |edited: Tuned, needle: &str| {
            let why = verify(&edited).unwrap_err();
            assert!(why.contains(needle), "{needle}: {why}");
        };
        refuse(
            Tuned {
                domain: [0.0, 100.0],
                ..t.clone()
            },
            "not proven on its domain",
        );
        refuse(
            Tuned {
                domain: [0.5, 1.0000005513794614],
                ..t.clone()
            },
            "proven again, the bound there is",
        );
        let mut coeffs = t.coeffs.clone();
        coeffs[1] = f64::from(-0.57f32);
        refuse(
            Tuned {
                coeffs,
                ..t.clone()
            },
            "proven again",
        );
        refuse(
            Tuned {
                length_error: t.length_error.map(|e| e / 2.0),
                ..t.clone()
            },
            "claims a length error of at most",
        );
        refuse(
            Tuned {
                length_error: None,
                ..t
            },
            "states no proven length error",
        );
    }
}
