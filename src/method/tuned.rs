//! Tuned methods: the forms `shadelab tune` fits (src/tune/), as method rows with their f64
//! twin. A tuned form is a polynomial seed in z = N.N, Horner's order, followed by `steps`
//! Newton steps `y <- y (1.5 - 0.5 z y y)`: [`k`] is that one generic formula, which tune's
//! candidates evaluate (f64, its rounding-aware type) and the row's kernel instantiates five
//! times ([`TunedFactor`], a [`Factor`]), so the proof, the twin and the software engine
//! read the same operations in the same order as the GLSL ([`Tuned::code`]).
//!
//! A tuned method file carries one machine-readable line, [`TUNED_MARKER`] then JSON
//! ([`Tuned`]: form, steps, float32 coefficients, the proven domain of z). `--method-file`
//! reads it ([`crate::method::user::prepare`]): the file's code must be the code the line
//! generates ([`Tuned::matches`]), else the file is refused; the row is then
//! [`super::Family::Tuned`], kernel `Scaled(times(k))`, an `auto` candidate that `auto` draws
//! only on triangles whose z lies inside the proven domain (src/auto/choice.rs).
use half::f16;
use serde::{Deserialize, Serialize};

use super::dual::Dual;
use super::interval::Interval;
use super::kernel::{Factor, Kernel, Scale};
use super::real::Real;
use super::{Family, Geometry, Input, Method, Property, Reference};

/// The marker of a tuned file's line: `// shadelab-tuned: {json}`.
pub const TUNED_MARKER: &str = "// shadelab-tuned:";

/// The form of a tuned method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TunedForm {
    /// `k(z) = p(z)`: a minimax polynomial (no steps).
    Minimax,
    /// A seed `p(z)` followed by `steps` >= 1 Newton steps.
    Newton,
}

/// What a tuned file's line says.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tuned {
    pub form: TunedForm,
    /// Newton steps after the seed (0 for minimax).
    pub steps: u32,
    /// The seed's coefficients in z, lowest degree first: float32 values, written as strings
    /// (the shortest decimal that reads back to the same float32, read by Rust's correctly
    /// rounded parser: JSON numbers pass through a parser that need not round correctly).
    #[serde(with = "exact_f32")]
    pub coeffs: Vec<f64>,
    /// The domain of z = N.N over which `tune` proved the form: [lo, hi], strings as the
    /// coefficients (the shortest decimal of each double).
    #[serde(with = "exact_f64")]
    pub domain: [f64; 2],
    /// The proven largest `| |N'| - 1 |` of the float32 program over the domain, as `tune`
    /// proved it when it wrote the file (a string as the others): the claim a loader re-proves
    /// (src/tune/check.rs). Absent in a file of an older shadelab, which is then refused.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "exact_opt")]
    pub length_error: Option<f64>,
}

/// A float32 value of the line read from its decimal string: a number beyond float32's range
/// (`1e300`) is refused with its text and the limit, not read as `inf`.
fn f32_of(t: &str) -> Result<f64, String> {
    match t.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(f64::from(x)),
        Ok(_)
            if t.trim_start_matches(['+', '-'])
                .parse::<f64>()
                .is_ok_and(f64::is_finite) =>
        {
            Err(format!(
                "{t:?} is beyond float32's range (its largest finite value is {:e})",
                f32::MAX
            ))
        }
        _ => Err(format!("{t:?} is not a finite float32")),
    }
}

/// An optional double as an exact decimal string.
mod exact_opt {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(x) => s.serialize_str(&format!("{x:?}")),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        let t = String::deserialize(d)?;
        t.parse::<f64>()
            .map(Some)
            .map_err(|_| serde::de::Error::custom(format!("{t:?} is not a number")))
    }
}

/// Float32 values as exact decimal strings.
mod exact_f32 {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|&x| (x as f32).to_string()))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Vec::<String>::deserialize(d)?
            .iter()
            .map(|t| super::f32_of(t).map_err(serde::de::Error::custom))
            .collect()
    }
}

/// Doubles as exact decimal strings.
mod exact_f64 {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &[f64; 2], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|x| format!("{x:?}")))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
        let v = <[String; 2]>::deserialize(d)?;
        let p = |t: &String| {
            t.parse::<f64>()
                .map_err(|_| serde::de::Error::custom(format!("{t:?} is not a number")))
        };
        Ok([p(&v[0])?, p(&v[1])?])
    }
}

/// `sum c_i z^i` in Horner's order: `k = c_d; k = k z + c_(d-1); ...`.
pub fn horner<T: Real>(c: &[f64], z: T) -> T {
    let mut it = c.iter().rev();
    let mut k = T::c(it.next().copied().unwrap_or(0.0));
    for &ci in it {
        k = k * z + T::c(ci);
    }
    k
}

/// One Newton step for `1/sqrt(z)`: `y (3/2 - (z/2) y y)`, in the GLSL's order.
pub fn newton_step<T: Real>(z: T, y: T) -> T {
    y * (T::c(1.5) - T::c(0.5) * z * y * y)
}

/// The tuned formula: the seed `coeffs` in Horner's order, then `steps` Newton steps.
pub fn k<T: Real>(coeffs: &[f64], steps: u32, z: T) -> T {
    let mut y = horner(coeffs, z);
    for _ in 0..steps {
        y = newton_step(z, y);
    }
    y
}

/// The GLSL literal of a float32 coefficient (`R(0.5)`): exact, as Rust writes the double.
fn lit(c: f64) -> String {
    format!("R({c:?})")
}

impl Tuned {
    /// The scale factor `k(z)`, `N' = k(z) N`.
    pub fn k<T: Real>(&self, z: T) -> T {
        k(&self.coeffs, self.steps, z)
    }

    /// The line (`// shadelab-tuned: {...}`).
    pub fn line(&self) -> String {
        let json = serde_json::to_string(self).unwrap_or_default();
        format!("{TUNED_MARKER} {json}")
    }

    /// Why the line is not a tuned form, if it is not one: at least one coefficient, each
    /// finite and a float32 value; minimax without steps, newton with 1..=4; a domain
    /// 0 <= lo <= hi, finite.
    pub fn check(&self) -> Result<(), String> {
        if self.coeffs.is_empty() || self.coeffs.len() > 16 {
            return Err("coeffs: 1 to 16 coefficients".into());
        }
        if let Some(c) = self
            .coeffs
            .iter()
            .find(|c| !c.is_finite() || f64::from(**c as f32) != **c)
        {
            return Err(format!("coefficient {c:?} is not a finite float32 value"));
        }
        match (self.form, self.steps) {
            (TunedForm::Minimax, 0) | (TunedForm::Newton, 1..=4) => {}
            (f, s) => return Err(format!("{f:?} with {s} steps (minimax: 0, newton: 1 to 4)")),
        }
        let [lo, hi] = self.domain;
        if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi) {
            return Err(format!(
                "domain [{lo}, {hi}]: expected 0 <= lo <= hi, finite"
            ));
        }
        if let Some(e) = self.length_error.filter(|e| !(e.is_finite() && *e >= 0.0)) {
            return Err(format!("length_error {e}: expected a finite bound >= 0"));
        }
        Ok(())
    }

    /// The method file's code (below its comment lines): the input declaration and
    /// `methodNormal()`, the operations of [`k`] in its order.
    pub fn code(&self) -> String {
        let mut s = String::from("// shadelab-inputs: interpolated_normal\n");
        s += "real3 methodNormal() {\n    real3 n = R3(vNormal);\n";
        let mut it = self.coeffs.iter().rev();
        let top = it.next().copied().unwrap_or(0.0);
        if self.coeffs.len() == 1 && self.steps == 0 {
            s += &format!("    return n * {};\n}}\n", lit(top));
            return s;
        }
        s += "    real z = dot(n, n);\n";
        s += &format!("    real k = {};\n", lit(top));
        for &c in it {
            s += &format!("    k = k * z + {};\n", lit(c));
        }
        for _ in 0..self.steps {
            s += "    k = k * (R(1.5) - R(0.5) * z * k * k);\n";
        }
        s += "    return n * k;\n}\n";
        s
    }

    /// The line of `text`, if it has one: `Err` when the line does not parse or check.
    pub fn of_text(text: &str) -> Option<Result<Tuned, String>> {
        let json = text
            .lines()
            .find_map(|l| l.trim().strip_prefix(TUNED_MARKER))?;
        Some(
            serde_json::from_str::<Tuned>(json.trim())
                .map_err(|e| format!("its {TUNED_MARKER} line does not parse: {e}"))
                .and_then(|t| t.check().map(|()| t)),
        )
    }

    /// Whether `text`'s code is [`Tuned::code`]: the same lines once comments (other than the
    /// input declaration), blank lines and the lines' outer spaces are dropped.
    pub fn matches(&self, text: &str) -> bool {
        code_lines(text) == code_lines(&self.code())
    }

    /// The row of the tuned file `name` at `path` (leaked, as user rows are; registered by
    /// [`crate::method::user::prepare`]).
    pub fn row(self, name: &'static str, path: &'static str) -> &'static Method {
        let [lo, hi] = self.domain;
        let factor: &'static TunedFactor = Box::leak(Box::new(TunedFactor { name, tuned: self }));
        Box::leak(Box::new(Method {
            name,
            description: leak(format!(
                "tuned by shadelab tune ({}), from {path}",
                factor.tuned.words()
            )),
            citation: path,
            inputs: &[Input::InterpolatedNormal],
            family: Family::Tuned,
            properties: &[Property::AutoCandidate],
            geometry: Geometry::Mesh,
            has_normal: true,
            reference: Reference::Phong,
            validity: leak(format!(
                "proven by shadelab tune on z = N.N in [{lo:.9}, {hi:.9}]; auto draws it only \
                 on triangles whose z lies there"
            )),
            claims: &[],
            glsl: path,
            kernel: Kernel::Scaled(Scale::times(factor)),
        }))
    }

    /// The form in words: `minimax d2`, `newton k1 seed d0`.
    pub fn words(&self) -> String {
        let d = self.coeffs.len().saturating_sub(1);
        match self.form {
            TunedForm::Minimax => format!("minimax d{d}"),
            TunedForm::Newton => format!("newton k{} seed d{d}", self.steps),
        }
    }
}

fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// The code lines of a GLSL text: comments stripped (the input declaration kept), trimmed,
/// blank lines dropped.
fn code_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| {
            let t = l.trim();
            if t.starts_with(super::user::INPUTS_MARKER) {
                return Some(t.split_whitespace().collect::<Vec<_>>().join(" "));
            }
            let code = t.split_once("//").map_or(t, |(a, _)| a).trim();
            (!code.is_empty()).then(|| code.to_string())
        })
        .collect()
}

/// A tuned form as a [`Factor`]: [`k`] in every number type, proven on its domain.
pub struct TunedFactor {
    pub name: &'static str,
    pub tuned: Tuned,
}

impl Factor for TunedFactor {
    fn name(&self) -> &str {
        self.name
    }
    fn f64(&self, z: f64) -> f64 {
        self.tuned.k(z)
    }
    fn f32(&self, z: f32) -> f32 {
        self.tuned.k(z)
    }
    fn f16(&self, z: f16) -> f16 {
        self.tuned.k(z)
    }
    fn interval(&self, z: Interval) -> Interval {
        self.tuned.k(z)
    }
    fn dual(&self, z: Dual) -> Dual {
        self.tuned.k(z)
    }
    fn proven_domain(&self) -> Option<[f64; 2]> {
        Some(self.tuned.domain)
    }
}

/// The proven domain of z of a tuned row ([`Factor::proven_domain`]); None for every other
/// row.
pub fn proven_domain(m: &Method) -> Option<[f64; 2]> {
    match m.kernel {
        Kernel::Scaled(s) => s.factor.proven_domain(),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t() -> Tuned {
        Tuned {
            form: TunedForm::Newton,
            steps: 1,
            coeffs: vec![f64::from(1.8f32), f64::from(-0.8f32)],
            domain: [0.5, 1.0000005],
            length_error: Some(1.25e-3),
        }
    }

    /// The line round-trips exactly; the code it generates matches, an edited one does not.
    #[test]
    fn the_line_round_trips_and_pins_the_code() {
        let t = t();
        let text = format!("// a comment\n{}\n{}", t.line(), t.code());
        let back = Tuned::of_text(&text).unwrap().unwrap();
        assert_eq!(back, t);
        assert!(back.matches(&text));
        let edited = text.replace("R(1.5)", "R(1.25)");
        assert!(!back.matches(&edited));
        let other_input = text.replace("interpolated_normal", "interpolated_normal, flat_normal");
        assert!(!back.matches(&other_input));
        assert!(Tuned::of_text("no line").is_none());
        let bad = text.replace("\"1.8\"", "1.8");
        assert!(
            Tuned::of_text(&bad).unwrap().is_err(),
            "a number, not a string"
        );
        // a coefficient beyond float32's range names its text and the limit, not "inf"
        let huge = text.replace("\"1.8\"", "\"1e300\"");
        let why = Tuned::of_text(&huge).unwrap().unwrap_err();
        assert!(
            why.contains("\"1e300\" is beyond float32's range") && why.contains("3.4028235e38"),
            "{why}"
        );
        assert!(!why.contains("inf"), "{why}");
        // each coefficient reads back to the same float32, bit for bit
        for x in [
            1.0423665046691895f64,
            -0.5665342211723328,
            1.5651870965957642,
        ] {
            let t = Tuned {
                coeffs: vec![x],
                ..t.clone()
            };
            assert_eq!(Tuned::of_text(&t.line()).unwrap().unwrap().coeffs, vec![x]);
        }
    }

    /// The factor is the formula: one step of a seed at z.
    #[test]
    fn the_factor_is_the_formula() {
        let t = t();
        let z = 0.7f64;
        let y = t.coeffs[0] + t.coeffs[1] * z;
        let want = y * (1.5 - 0.5 * z * y * y);
        assert_eq!(t.k(z), want);
        let f = TunedFactor {
            name: "x",
            tuned: t,
        };
        assert_eq!(f.f64(z), want);
        assert!(f.interval(Interval::point(z)).contains(want));
    }
}
