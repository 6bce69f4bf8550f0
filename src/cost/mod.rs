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

/// A cost model's identifier: `[a-z0-9_.-]` words joined by `:` (`isa:amd:navi21:f16`), with
/// what it names ([`IdKind`]: a GPU family's vendor, chip and precision) read from its words
/// once, when it is made or read from JSON. Written as its text everywhere.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct CostModelId {
    text: String,
    kind: IdKind,
}

/// What a [`CostModelId`] names.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum IdKind {
    /// lavapipe's timings ([`LAVAPIPE_FRAME`], [`LAVAPIPE_ISOLATED`]): measured on this machine's
    /// CPU, where nothing else may run beside them.
    Lavapipe,
    /// A GPU family's static cost: `isa:VENDOR:CHIP`, `isa:VENDOR:CHIP:f16`; `isa:CHIP` and
    /// `isa:CHIP:f16` leave the vendor to `isa` (a bare chip is AMD's).
    Isa {
        vendor: Option<String>,
        chip: String,
        precision: Precision,
    },
    /// Any other source's model ([`SOFTWARE`], `bench:<machine>`, a registered source's own).
    Other,
}

/// lavapipe's frame time of the whole draw (bench's paired ratio, across runs).
pub const LAVAPIPE_FRAME: &str = "lavapipe_frame";
/// lavapipe's cost of one evaluation of the per-fragment code (isolated kernels).
pub const LAVAPIPE_ISOLATED: &str = "lavapipe_isolated";
/// The software scanline engine's frame time.
pub const SOFTWARE: &str = "software";

impl IdKind {
    /// The kind of the (valid) id `text`.
    fn of(text: &str) -> IdKind {
        if text == LAVAPIPE_FRAME || text == LAVAPIPE_ISOLATED {
            return IdKind::Lavapipe;
        }
        let words: Vec<&str> = text.split(':').collect();
        let precision = |w: &str| Precision::ALL.into_iter().find(|p| p.as_str() == w);
        let isa = |vendor: Option<&str>, chip: &str, precision| IdKind::Isa {
            vendor: vendor.map(str::to_string),
            chip: chip.to_string(),
            precision,
        };
        match words[..] {
            ["isa", chip] => isa(None, chip, Precision::F32),
            ["isa", chip, p] if precision(p).is_some() => isa(None, chip, precision(p).unwrap()),
            ["isa", vendor, chip] => isa(Some(vendor), chip, Precision::F32),
            ["isa", vendor, chip, p] if precision(p).is_some() => {
                isa(Some(vendor), chip, precision(p).unwrap())
            }
            _ => IdKind::Other,
        }
    }
}

impl CostModelId {
    /// `s` when it is an identifier, else why not.
    /// Upper case is read as lower case (`isa:Navi21` is `isa:navi21`).
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim().to_ascii_lowercase();
        let word = |w: &str| {
            !w.is_empty()
                && w.chars().all(|c| {
                    c.is_ascii_lowercase() || c.is_ascii_digit() || matches!(c, '_' | '-' | '.')
                })
        };
        if s.split(':').all(word) {
            Ok(CostModelId::made(s))
        } else {
            Err(format!(
                "{s:?} is not a cost model id: lower-case words of [a-z0-9_.-] joined by ':' \
                 (e.g. lavapipe_isolated, isa:navi21)"
            ))
        }
    }

    /// The id of a valid `text`.
    fn made(text: String) -> Self {
        CostModelId {
            kind: IdKind::of(&text),
            text,
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
        CostModelId::made(format!("{prefix}:{}", w.trim_end_matches('-')))
    }

    /// A fixed id of this module ([`LAVAPIPE_FRAME`], ...).
    pub fn of(s: &'static str) -> Self {
        CostModelId::made(s.to_string())
    }

    /// The static model of GPU family `family` (`vendor:chip`, or a bare chip) in `precision`
    /// (`isa:amd:navi21`, `isa:amd:navi21:f16`).
    pub fn isa(family: &str, precision: Precision) -> Self {
        CostModelId::made(match precision {
            Precision::F32 => format!("isa:{family}"),
            p => format!("isa:{family}:{}", p.as_str()),
        })
    }

    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// What the id names.
    pub fn kind(&self) -> &IdKind {
        &self.kind
    }

    /// The vendor of a GPU family's model (`isa:intel:tgl` -> `intel`); `None` for other
    /// models and for a bare chip (`isa:navi21`), whose vendor `isa` decides.
    pub fn vendor(&self) -> Option<&str> {
        match &self.kind {
            IdKind::Isa { vendor, .. } => vendor.as_deref(),
            _ => None,
        }
    }

    /// The chip of a GPU family's model (`isa:intel:tgl:f16` -> `tgl`).
    pub fn chip(&self) -> Option<&str> {
        match &self.kind {
            IdKind::Isa { chip, .. } => Some(chip),
            _ => None,
        }
    }

    /// The GPU family of a static model's id, as `isa` names families (`isa:intel:tgl:f16` ->
    /// `intel:tgl`, `isa:navi21` -> `navi21`).
    pub fn gpu_family(&self) -> Option<String> {
        match &self.kind {
            IdKind::Isa {
                vendor: Some(v),
                chip,
                ..
            } => Some(format!("{v}:{chip}")),
            IdKind::Isa { chip, .. } => Some(chip.clone()),
            _ => None,
        }
    }

    /// The precision the id names: a GPU family's (`:f16`), float32 for every other id (a
    /// model's own precision is [`CostModel::precision`]).
    pub fn precision(&self) -> Precision {
        match &self.kind {
            IdKind::Isa { precision, .. } => *precision,
            _ => Precision::F32,
        }
    }
}

impl TryFrom<String> for CostModelId {
    type Error = String;
    fn try_from(s: String) -> std::result::Result<Self, String> {
        Self::parse(&s)
    }
}

impl From<CostModelId> for String {
    fn from(id: CostModelId) -> String {
        id.text
    }
}

impl std::fmt::Display for CostModelId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl PartialEq<str> for CostModelId {
    fn eq(&self, other: &str) -> bool {
        self.text == other
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

/// Writes a verdict of "cheaper than phong_exact" as its words ([`verdict_words`]), as
/// tune.json does (`#[serde(serialize_with = "crate::cost::as_words")]`).
pub fn as_words<S: serde::Serializer>(v: &Verdict, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(verdict_words(*v))
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

    /// The vendor, chip and precision are read from the id's words once: a precision word is
    /// not a chip (`isa:navi21:f16` has no vendor), a vendor word is not a precision.
    #[test]
    fn an_id_knows_its_gpu_family() {
        let id = |s: &str| CostModelId::parse(s).unwrap();
        let gpu = |s: &str| {
            let i = id(s);
            (
                i.vendor().map(str::to_string),
                i.chip().map(str::to_string),
                i.precision(),
            )
        };
        let p16 = Precision::F16;
        let s = |x: &str| Some(x.to_string());
        assert_eq!(gpu("isa:intel:tgl"), (s("intel"), s("tgl"), Precision::F32));
        assert_eq!(gpu("isa:amd:navi21:f16"), (s("amd"), s("navi21"), p16));
        assert_eq!(gpu("isa:navi21:f16"), (None, s("navi21"), p16));
        assert_eq!(gpu("isa:navi21"), (None, s("navi21"), Precision::F32));
        // Teeth: other ids have no family; an unknown last word is not a precision.
        assert_eq!(gpu("lavapipe_frame"), (None, None, Precision::F32));
        assert_eq!(gpu("bench:isa-x"), (None, None, Precision::F32));
        assert_eq!(id("isa:a:b:f64").kind(), &IdKind::Other);
        assert_eq!(id(LAVAPIPE_ISOLATED).kind(), &IdKind::Lavapipe);
        assert_eq!(id(SOFTWARE).kind(), &IdKind::Other);
        // JSON reads into the same id, written as its text.
        let json = serde_json::to_string(&id("isa:arm:g610:f16")).unwrap();
        assert_eq!(json, "\"isa:arm:g610:f16\"");
        let back: CostModelId = serde_json::from_str(&json).unwrap();
        assert_eq!(back.vendor(), Some("arm"));
        assert!(serde_json::from_str::<CostModelId>("\"isa:a b\"").is_err());
    }
}
