//! The rules of cost verdicts, written once: a static figure against phong_exact, a ratio
//! interval against a claimed factor, and the ratio of two methods under one model.
use super::{CostFigure, CostKind, CostModel};
use crate::method::Verdict;

/// A static (deterministic) ratio to phong_exact as the verdict of "cheaper than phong_exact":
/// agrees strictly below 1 (equal cost is not cheaper), disagrees at or above 1, not checked
/// without a finite figure.
pub fn static_cheaper(ratio: Option<f64>) -> Verdict {
    match ratio.filter(|q| q.is_finite()) {
        None => Verdict::NotChecked,
        Some(q) => factor_verdict(q, q, STRICTLY_BELOW_ONE),
    }
}

/// "Faster" (a claimed ratio of at most 1) needs a ratio strictly below 1.
const STRICTLY_BELOW_ONE: f64 = 1.0 - f64::EPSILON;

/// A claim "k times faster" judged by a ratio interval [lo, hi] of the method's cost over the
/// other's (`target` = 1 / k): the speed-up is the reciprocal of the ratio, so its interval is
/// [1 / hi, 1 / lo]:
/// - agrees when the whole speed-up interval reaches k: `0 < hi <= target`;
/// - disagrees when the whole speed-up interval lies below k: `lo > target`;
/// - inconclusive when the interval straddles k, when an end is not finite, or when the whole
///   ratio interval is at or below 0 (a cost the measurement cannot resolve).
///
/// A static figure is the degenerate interval [r, r].
pub fn factor_verdict(lo: f64, hi: f64, target: f64) -> Verdict {
    if !(lo.is_finite() && hi.is_finite() && target.is_finite()) || lo > hi {
        Verdict::Inconclusive
    } else if hi > 0.0 && hi <= target {
        Verdict::Agrees
    } else if lo > target {
        Verdict::Disagrees
    } else {
        Verdict::Inconclusive
    }
}

/// How [`factor_verdict`] reads, for the claims' `how`.
pub const FACTOR_RULE: &str = "agrees when the whole 95% interval of the speed-up \
     reaches the claimed factor, disagrees when the whole interval is below it, inconclusive \
     when it straddles the factor";

/// The ratio `num / den` under one model.
#[derive(Debug, Clone, PartialEq)]
pub struct Ratio {
    pub median: f64,
    /// The 95% interval; `None` for a static model (one deterministic figure).
    pub interval: Option<(f64, f64)>,
    /// How it was obtained (paired, bounded from two intervals, two static figures).
    pub note: String,
}

impl Ratio {
    /// The verdict of "num is at most `target` times den" by [`factor_verdict`]; a target of
    /// 1 ("faster") needs the ratio strictly below 1: equal cost is not faster.
    pub fn verdict(&self, target: f64) -> Verdict {
        let (lo, hi) = self.interval.unwrap_or((self.median, self.median));
        let target = if target == 1.0 {
            STRICTLY_BELOW_ONE
        } else {
            target
        };
        factor_verdict(lo, hi, target)
    }
}

fn finite(x: Option<f64>) -> Option<f64> {
    x.filter(|v| v.is_finite())
}

impl CostModel {
    /// `num / den` under this model: a pair the model measured directly, else from the two
    /// figures: `num`'s own interval when `den` is the reference (its ratio is already paired
    /// against it), an interval bounded from the two otherwise (not paired), or the quotient of
    /// two static figures. `None` when a figure is missing or not finite.
    pub fn ratio(&self, num: &str, den: &str, reference: &str) -> Option<Ratio> {
        if let Some(p) = self.pairs.iter().find(|p| p.num == num && p.den == den) {
            return Some(Ratio {
                median: finite(p.median)?,
                interval: finite(p.ci95_low).zip(finite(p.ci95_high)),
                note: p.note.clone(),
            });
        }
        let (a, b) = (self.figure(num)?, self.figure(den)?);
        let r = |f: &CostFigure| finite(f.ratio);
        match self.kind {
            CostKind::Static => {
                let (x, y) = (r(a)?, r(b)?);
                (y > 0.0).then(|| Ratio {
                    median: x / y,
                    interval: None,
                    note: format!("{} over {}", self.measure.statistic, self.measure.unit),
                })
            }
            CostKind::Interval => {
                let iv = |f: &CostFigure| Some((finite(f.ci95_low)?, r(f)?, finite(f.ci95_high)?));
                let (alo, amid, ahi) = iv(a)?;
                if den == reference {
                    return Some(Ratio {
                        median: amid,
                        interval: Some((alo, ahi)),
                        note: "paired per round".into(),
                    });
                }
                let (blo, bmid, bhi) = iv(b)?;
                (blo > 0.0).then(|| Ratio {
                    median: amid / bmid,
                    interval: Some((alo / bhi, ahi / blo)),
                    note: "bounded from two intervals, not paired".into(),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cost::{CostModelId, Measure};

    #[test]
    fn a_static_ratio_is_cheaper_only_strictly_below_one() {
        assert_eq!(static_cheaper(Some(0.93)), Verdict::Agrees);
        assert_eq!(static_cheaper(Some(1.0)), Verdict::Disagrees);
        assert_eq!(static_cheaper(Some(1.2)), Verdict::Disagrees);
        assert_eq!(static_cheaper(Some(f64::NAN)), Verdict::NotChecked);
        assert_eq!(static_cheaper(None), Verdict::NotChecked);
    }

    #[test]
    fn a_factor_verdict_needs_the_whole_interval() {
        assert_eq!(factor_verdict(0.3, 0.45, 0.5), Verdict::Agrees);
        assert_eq!(factor_verdict(0.45, 0.55, 0.5), Verdict::Inconclusive);
        assert_eq!(factor_verdict(0.55, 0.6, 0.5), Verdict::Disagrees);
        assert_eq!(factor_verdict(f64::NAN, 0.4, 0.5), Verdict::Inconclusive);
        assert_eq!(factor_verdict(-0.2, 0.0, 0.5), Verdict::Inconclusive);
        let r = |x: f64| Ratio {
            median: x,
            interval: None,
            note: String::new(),
        };
        assert_eq!(
            r(1.0).verdict(1.0),
            Verdict::Disagrees,
            "equal is not faster"
        );
        assert_eq!(r(0.999).verdict(1.0), Verdict::Agrees);
    }

    fn figure(method: &str, r: f64, lo: f64, hi: f64) -> CostFigure {
        CostFigure {
            method: method.into(),
            value: None,
            ratio: Some(r),
            ci95_low: Some(lo),
            ci95_high: Some(hi),
            verdict: Verdict::Inconclusive,
            evidence: String::new(),
            note: String::new(),
        }
    }

    fn model(kind: CostKind) -> CostModel {
        CostModel {
            id: CostModelId::of("test"),
            title: "test".into(),
            kind,
            measure: Measure {
                statistic: "s".into(),
                unit: "u".into(),
            },
            description: String::new(),
            precision: crate::method::Precision::F32,
            figures: vec![figure("a", 0.5, 0.4, 0.6), figure("b", 0.8, 0.7, 0.9)],
            pairs: Vec::new(),
        }
    }

    #[test]
    fn a_ratio_is_paired_against_the_reference_and_bounded_otherwise() {
        let m = model(CostKind::Interval);
        let paired = m.ratio("a", "ref", "ref");
        assert!(
            paired.is_none(),
            "no figure for the reference: nothing to pair"
        );
        let mut m = m;
        m.figures.push(figure("ref", 1.0, 1.0, 1.0));
        let p = m.ratio("a", "ref", "ref").unwrap();
        assert_eq!(p.interval, Some((0.4, 0.6)));
        let b = m.ratio("a", "b", "ref").unwrap();
        assert_eq!(b.interval, Some((0.4 / 0.9, 0.6 / 0.7)));
        assert!((b.median - 0.625).abs() < 1e-15);
        let s = model(CostKind::Static).ratio("a", "b", "ref").unwrap();
        assert_eq!(s.interval, None);
        assert!((s.median - 0.625).abs() < 1e-15);
    }
}
