//! A fitted candidate as a method file: its `// shadelab-tuned:` line, proven on its domain as
//! every loader proves it again ([`super::check`]), then the code the line generates.
use super::candidate::{Candidate, Family};
use crate::method::tuned::{Tuned, TunedForm};

/// The tuned form of a fitted candidate, proven on `domain` (None for a paper or the
/// reference): what its method file's `// shadelab-tuned:` line says, its float32 length
/// error over `domain` included.
pub fn tuned(c: &Candidate, domain: [f64; 2]) -> Option<Tuned> {
    let form = match c.family {
        Family::Minimax => TunedForm::Minimax,
        Family::Newton => TunedForm::Newton,
        Family::Paper | Family::Reference => return None,
    };
    let mut t = Tuned {
        form,
        steps: c.steps,
        coeffs: c.coeffs.clone(),
        domain,
        length_error: None,
    };
    // the claim the line states, proven as a loader proves it again (src/tune/check.rs)
    let bound = super::check::line_bound(&t);
    t.length_error = bound.is_finite().then_some(bound);
    Some(t)
}

/// The method file (None for a paper: its file is the table's), its form proven on
/// `domain`: the header, the `// shadelab-tuned:` line, then the code that line generates
/// ([`Tuned::code`]). `header` lines are written as comments after the formula.
pub fn glsl(c: &Candidate, header: &[String], domain: [f64; 2]) -> Option<String> {
    let tuned = tuned(c, domain)?;
    let mut s = format!("// {}: {} (shadelab tune)\n", c.id, c.label());
    s += &format!("// {}; N' = k(N.N) N\n", c.formula());
    for h in header {
        s += &format!("// {h}\n");
    }
    s += &tuned.line();
    s.push('\n');
    s += &tuned.code();
    Some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper candidate of the table's row `name`.
    fn paper(name: &str) -> Candidate {
        Candidate::paper(crate::method::find(name).unwrap()).unwrap()
    }

    /// The method file computes the formula's operations in its order, with the float32
    /// coefficients written exactly.
    #[test]
    fn the_glsl_spells_the_formula() {
        let c = Candidate::newton("m_newton1_seed1".into(), 1, 1, 0.5, 1.0).unwrap();
        let g = glsl(&c, &["a header".into()], [0.5, 1.0]).unwrap();
        for x in &c.coeffs {
            assert!(g.contains(&format!("R({x:?})")), "{g}");
            assert_eq!(f64::from(format!("{x:?}").parse::<f32>().unwrap()), *x);
        }
        assert!(g.contains("k = k * (R(1.5) - R(0.5) * z * k * k);"), "{g}");
        assert!(g.contains("// a header\n// shadelab-tuned: {"), "{g}");
        assert!(
            g.contains("}\n// shadelab-inputs: interpolated_normal\n"),
            "{g}"
        );
        let t = Tuned::of_text(&g).unwrap().unwrap();
        assert!(t.matches(&g) && t.coeffs == c.coeffs && t.steps == 1);
        assert_eq!(t.domain, [0.5, 1.0]);
        let p = crate::method::user::parse(std::path::Path::new("/x/m_newton1_seed1.glsl"), &g);
        assert!(p.unwrap().has_normal);
        let zero = Candidate::minimax("m_minimax0".into(), 0, 0.5, 1.0).unwrap();
        assert!(glsl(&zero, &[], [0.5, 1.0])
            .unwrap()
            .contains("return n * R("));
        assert!(glsl(&paper("romanyuk_poly"), &[], [0.5, 1.0]).is_none());
    }
}
