//! The floating-point precision a method's programs compute in: one type for every command's
//! `--precision` (render, compare, stress, bench, isa, verify; parsed in cli::PrecisionArgs, as
//! clap stays in cli/) and every output that records it.
//!
//! `F32` is the shipped programs as they are. `F16` is the same method source compiled with the
//! float16 vocabulary (issue 23): the method and the lighting computed in `float16_t`, inputs read
//! as float32 varyings and converted where the shader first reads them.
use serde::{Deserialize, Serialize};

/// A program's arithmetic precision.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    /// IEEE binary32 (GLSL `float`).
    #[default]
    F32,
    /// IEEE binary16 (GLSL `float16_t`, GL_EXT_shader_explicit_arithmetic_types_float16).
    F16,
}

impl Precision {
    /// Every precision, in the order outputs list them.
    pub const ALL: [Precision; 2] = [Precision::F32, Precision::F16];

    /// The name on the command line and in JSON (`f32`, `f16`).
    pub fn as_str(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F16 => "f16",
        }
    }

    /// The unit roundoff u = 2^-p of round-to-nearest (p = significand bits, hidden bit
    /// included): 2^-24 for binary32, 2^-11 for binary16. The error bounds of `verify` are
    /// derived in multiples of it.
    pub fn unit_roundoff(self) -> f64 {
        match self {
            Precision::F32 => (-24f64).exp2(),
            Precision::F16 => (-11f64).exp2(),
        }
    }
}

impl std::str::FromStr for Precision {
    type Err = String;

    /// The command-line name (`f32`, `f16`); the error lists the accepted ones.
    fn from_str(s: &str) -> Result<Self, String> {
        Precision::ALL
            .into_iter()
            .find(|p| p.as_str() == s)
            .ok_or_else(|| format!("unknown precision {s:?}: use f32 or f16"))
    }
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_roundoff_is_half_an_ulp_of_one() {
        // f32::EPSILON is the ulp of 1.0 (2^-23); u is half of it.
        assert_eq!(
            Precision::F32.unit_roundoff(),
            f64::from(f32::EPSILON) / 2.0
        );
        // binary16 has 10 stored significand bits: ulp(1) = 2^-10.
        assert_eq!(Precision::F16.unit_roundoff(), 2f64.powi(-10) / 2.0);
        assert_ne!(
            Precision::F16.unit_roundoff(),
            Precision::F32.unit_roundoff()
        );
    }

    #[test]
    fn names_round_trip_through_json() {
        for p in Precision::ALL {
            let text = serde_json::to_string(&p).unwrap();
            assert_eq!(text, format!("\"{}\"", p.as_str()));
            assert_eq!(serde_json::from_str::<Precision>(&text).unwrap(), p);
        }
        assert!(serde_json::from_str::<Precision>("\"f64\"").is_err());
        for p in Precision::ALL {
            assert_eq!(p.as_str().parse::<Precision>(), Ok(p));
        }
        assert!("f64".parse::<Precision>().is_err());
        assert!("F32".parse::<Precision>().is_err());
    }
}
