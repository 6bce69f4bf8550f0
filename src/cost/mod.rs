//! Cost models: what a method costs, under one measurement, relative to phong_exact.
//!
//! One type family for every consumer: the answer table ([`crate::report::answer`]), the corpus
//! tables, `auto --cost-model`, the seeds' speed claims and the report's charts read
//! [`CostModel`] values and nothing else. A [`CostSource`] makes them: from what a run measured
//! ([`Evidence`], filled by the jobs that measure) or, for `auto`, by measuring now. Sources are
//! listed in a [`Registry`]; adding a cost model is one file implementing [`CostSource`] and one
//! line registering it (`crate::cli::costs::builtin`).
//!
//! Identity: a model's [`CostModelId`] is spelled the same in JSON, CSV, the command line and
//! HTML (`lavapipe_frame`, `lavapipe_isolated`, `software`, `isa:amd:navi21`, `isa:amd:navi21:f16`,
//! `bench:<machine>`). The verdict of each figure is the typed [`Verdict`] of the claim "cheaper
//! than phong_exact", by one rule per kind ([`rule`]).
pub mod rule;
pub mod source;

use serde::{Deserialize, Serialize};

pub use self::rule::{factor_verdict, Ratio};
pub use self::source::{CostSource, Evidence, Registry};
use crate::method::{Precision, Verdict};

/// A cost model's identifier: `[a-z0-9_.-]` words joined by `:` (`isa:navi21:f16`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct CostModelId(String);

/// lavapipe's frame time of the whole draw (bench's paired ratio, across runs).
pub const LAVAPIPE_FRAME: &str = "lavapipe_frame";
/// lavapipe's cost of one evaluation of the per-fragment code (isolated kernels).
pub const LAVAPIPE_ISOLATED: &str = "lavapipe_isolated";
/// The software scanline engine's frame time.
pub const SOFTWARE: &str = "software";

impl CostModelId {
    /// `s` when it is an identifier, else why not.
    /// Upper case is read as lower case (`isa:Navi21` is `isa:navi21`).
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim().to_ascii_lowercase();
        let s = s.as_str();
        let word = |w: &str| {
            !w.is_empty()
                && w.chars().all(|c| {
                    c.is_ascii_lowercase() || c.is_ascii_digit() || matches!(c, '_' | '-' | '.')
                })
        };
        if s.split(':').all(word) {
            Ok(CostModelId(s.to_string()))
        } else {
            Err(format!(
                "{s:?} is not a cost model id: lower-case words of [a-z0-9_.-] joined by ':' \
                 (e.g. lavapipe_isolated, isa:navi21)"
            ))
        }
    }

    /// `prefix:` and `text` made an id word: lower case, every run of other characters one `-`
    /// (`bench:llvmpipe-llvm-15-0-6-256-bits-...`).
    pub fn slug(prefix: &str, text: &str) -> Self {
        let mut w = String::new();
        for c in text.chars().map(|c| c.to_ascii_lowercase()) {
            if c.is_ascii_alphanumeric() || c == '.' || c == '_' {
                w.push(c);
            } else if !w.is_empty() && !w.ends_with('-') {
                w.push('-');
            }
        }
        CostModelId(format!("{prefix}:{}", w.trim_end_matches('-')))
    }

    /// A fixed id of this module ([`LAVAPIPE_FRAME`], ...).
    pub fn of(s: &'static str) -> Self {
        CostModelId(s.to_string())
    }

    /// The static model of GPU family `family` in `precision` (`isa:navi21`, `isa:navi21:f16`).
    pub fn isa(family: &str, precision: Precision) -> Self {
        CostModelId(match precision {
            Precision::F32 => format!("isa:{family}"),
            p => format!("isa:{family}:{}", p.as_str()),
        })
    }

    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl std::fmt::Display for CostModelId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl PartialEq<str> for CostModelId {
    fn eq(&self, other: &str) -> bool {
        self.0 == other
    }
}

impl std::str::FromStr for CostModelId {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::parse(s)
    }
}

/// How a cost model gives its figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CostKind {
    /// Measured: a ratio to phong_exact with an interval and the measurement's verdict.
    Interval,
    /// Counted: one deterministic figure per method, no interval.
    Static,
}

/// What a figure is: the statistic and its unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measure {
    /// "frame time of the whole draw", "ACO inverse throughput of the draw's fragment shader".
    pub statistic: String,
    /// "ms", "ns per evaluation", "busy cycles per wave".
    pub unit: String,
}

/// One method's figure under a cost model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostFigure {
    pub method: String,
    /// The figure itself in the model's unit (absent where only the ratio was kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// The ratio to phong_exact's figure (the median for an interval model); null: unmeasured.
    pub ratio: Option<f64>,
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    /// The verdict of "cheaper than phong_exact" by the model's rule ([`rule`]).
    pub verdict: Verdict,
    /// Where the figure comes from, relative to the output folder.
    pub evidence: String,
    /// Which measurement it is (e.g. the scene it was taken from).
    pub note: String,
}

impl CostFigure {
    /// Whether the model measured this method cheaper than phong_exact.
    pub fn cheaper(&self) -> bool {
        self.verdict == Verdict::Agrees
    }

    /// The verdict in the words of a cost ([`verdict_words`]).
    pub fn verdict_words(&self) -> &'static str {
        verdict_words(self.verdict)
    }
}

/// A verdict of "cheaper than phong_exact" in the words of a cost: cheaper, not cheaper,
/// inconclusive, unmeasured.
pub fn verdict_words(v: Verdict) -> &'static str {
    match v {
        Verdict::Agrees => "cheaper",
        Verdict::Disagrees => "not cheaper",
        Verdict::Inconclusive | Verdict::Partly => "inconclusive",
        Verdict::NotChecked => "unmeasured",
    }
}

/// A ratio the model measured directly between two methods (paired in the same rounds), where
/// it has one: the speed claims prefer it to a ratio bounded from two figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairFigure {
    pub num: String,
    pub den: String,
    pub median: Option<f64>,
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    pub note: String,
}

/// A cost model: what is measured, and one figure per method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostModel {
    /// The one spelling of the model ([`CostModelId`]).
    #[serde(rename = "name")]
    pub id: CostModelId,
    /// Column heading.
    pub title: String,
    pub kind: CostKind,
    pub measure: Measure,
    /// What is measured and how the figure per method is chosen.
    pub description: String,
    /// The precision of the programs it costs; a budget is checked on the errors of the same
    /// precision (compare in float16 for a float16 model).
    #[serde(default)]
    pub precision: Precision,
    pub figures: Vec<CostFigure>,
    /// Ratios measured directly between two methods (the software engine's claim pairs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<PairFigure>,
}

impl CostModel {
    /// The figure of `method`, if the model has one.
    pub fn figure(&self, method: &str) -> Option<&CostFigure> {
        self.figures.iter().find(|f| f.method == method)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_model_ids_have_one_spelling() {
        let id = |s: &str| CostModelId::parse(s).map(|i| i.to_string());
        assert_eq!(id("lavapipe_isolated").as_deref(), Ok("lavapipe_isolated"));
        assert_eq!(id(" isa:Navi21 ").as_deref(), Ok("isa:navi21"));
        assert_eq!(
            CostModelId::isa("navi21", crate::method::Precision::F16).to_string(),
            "isa:navi21:f16"
        );
        assert_eq!(
            CostModelId::slug("bench", "llvmpipe (LLVM 15) | Mesa 22.3.6").to_string(),
            "bench:llvmpipe-llvm-15-mesa-22.3.6"
        );
        for bad in ["", "isa:", ":x", "isa:a b", "isa:../x", "isa:x/y", "é"] {
            assert!(CostModelId::parse(bad).is_err(), "{bad:?} accepted");
        }
    }
}
