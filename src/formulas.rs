//! Every formula in f64: the CPU reference used by the truth evaluator, the tests and (later)
//! the stress sweeps. Each function is a literal port of its GLSL twin in glsl/ (FORMULAS.md
//! appendix C), so the GPU-vs-f64 comparison proves the GLSL implements the formula.
use glam::DVec3;

/// Exact normalization `N / |N|` (FORMULAS.md 2.3). Returns the input unchanged when it has zero
/// length (the GPU's `normalize` gives NaN there; no sane mesh reaches it, see the hazard in 2.3).
pub fn normalize_exact(n: DVec3) -> DVec3 {
    let len = n.length();
    if len > 0.0 {
        n / len
    } else {
        n
    }
}

/// Lighting parameters as the GPU received them (f32 values widened to f64).
#[derive(Debug, Clone)]
pub struct Lighting {
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub shininess: f64,
    /// (direction towards the light L, colour I_L, half vector H), view space.
    pub lights: Vec<(DVec3, DVec3, DVec3)>,
}

impl Lighting {
    /// The seeds' lighting model (FORMULAS.md 1.2), twin of `shade()` in glsl/shading.glsl:
    /// `I = k_a I_a + sum I_L (k_d max(0, N.L) + k_s max(0, N.H)^n)`, with `0^n = 0`.
    pub fn shade(&self, n: DVec3) -> DVec3 {
        let mut c = self.ambient;
        for &(l, color, h) in &self.lights {
            let d = n.dot(l).max(0.0);
            let s = n.dot(h).max(0.0);
            let sp = if s > 0.0 { s.powf(self.shininess) } else { 0.0 };
            c += color * (self.diffuse * d + self.specular * sp);
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_exact_gives_unit_length_and_keeps_zero() {
        let n = normalize_exact(DVec3::new(3.0, 4.0, 12.0));
        assert!((n.length() - 1.0).abs() < 1e-15, "{n}");
        assert_eq!(normalize_exact(DVec3::ZERO), DVec3::ZERO);
    }

    #[test]
    fn shade_follows_the_blinn_model() {
        let lit = Lighting {
            ambient: DVec3::splat(0.1),
            diffuse: DVec3::splat(0.5),
            specular: DVec3::splat(0.25),
            shininess: 2.0,
            lights: vec![(DVec3::Z, DVec3::ONE, DVec3::Z)],
        };
        // N = Z: 0.1 + 0.5 * 1 + 0.25 * 1
        assert!((lit.shade(DVec3::Z).x - 0.85).abs() < 1e-15);
        // N at 60 degrees: 0.1 + 0.5 * 0.5 + 0.25 * 0.25
        let n = DVec3::new(0.75f64.sqrt(), 0.0, 0.5);
        assert!((lit.shade(n).x - 0.4125).abs() < 1e-15, "{}", lit.shade(n));
        // facing away: ambient only, and n = 0 gives no NaN
        let away = Lighting {
            shininess: 0.0,
            ..lit
        };
        assert_eq!(away.shade(-DVec3::Z), DVec3::splat(0.1));
    }
}
