//! The answer's error budgets ([`Budget`]): a limit on one of compare's luminance metrics, the
//! limit an [`ErrorBudget`] (the budget type of `auto` and every `--error-budget`) given as a
//! fraction. A budget is named by its id (`max_4_255`: the metric's statistic and the
//! fraction) in answer.json's checks, cells and summary, and written in full (id, metric,
//! limit, label) in its `budgets`; both read back into the same budget.
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::auto::ErrorBudget;
use crate::compare::Metric;

/// The fractions every budget list of the answer and of the corpus tables takes, tightest
/// first: 1/1024, 1/255 (one 8-bit step of a linear channel), 4/255.
pub const FRACTIONS: [(u32, u32); 3] = [(1, 1024), (1, 255), (4, 255)];

/// The metrics a budget of the answer limits: the largest and the 99th percentile of |dI|, the
/// luminance error (the answer's and the corpus tables' metrics).
pub const METRICS: [Metric; 2] = [Metric::MaxAbsError, Metric::P99AbsError];

/// [`METRICS`], each with the word of its id and how a person reads it.
const STATISTICS: [(Metric, &str, &str); 2] = [
    (METRICS[0], "max", "max |dI|"),
    (METRICS[1], "p99", "p99 |dI|"),
];

/// One error budget: compare's `metric` (of the linear luminance) at most `limit`, the limit
/// given as the fraction `num/den`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    pub metric: Metric,
    pub limit: ErrorBudget,
    num: u32,
    den: u32,
}

/// The six budgets of the answer: largest and p99 |dI| at each of [`FRACTIONS`].
pub fn budgets() -> Vec<Budget> {
    STATISTICS
        .iter()
        .flat_map(|&(metric, ..)| {
            FRACTIONS
                .iter()
                .map(move |&(num, den)| Budget::new(metric, num, den).expect("a valid budget"))
        })
        .collect()
}

/// `num/den` as text (`4/255`), as the corpus tables key their shares.
pub fn fraction_text((num, den): (u32, u32)) -> String {
    format!("{num}/{den}")
}

/// The colour-error limit of a fraction of [`FRACTIONS`].
pub fn limit_of((num, den): (u32, u32)) -> ErrorBudget {
    ErrorBudget::new(f64::from(num) / f64::from(den)).expect("FRACTIONS are positive")
}

impl Budget {
    /// `metric` at most `num/den`: a metric of [`STATISTICS`] and a positive fraction.
    pub fn new(metric: Metric, num: u32, den: u32) -> Result<Budget, String> {
        if !STATISTICS.iter().any(|(m, ..)| *m == metric) {
            return Err(format!(
                "{metric} is not a metric an answer budget limits (max_abs_error, p99_abs_error)"
            ));
        }
        if num == 0 || den == 0 {
            return Err(format!("{num}/{den} is not a budget: a fraction > 0"));
        }
        let limit = ErrorBudget::new(f64::from(num) / f64::from(den))?;
        Ok(Budget {
            metric,
            limit,
            num,
            den,
        })
    }

    fn statistic(&self) -> (&'static str, &'static str) {
        let (_, word, shown) = STATISTICS
            .iter()
            .find(|(m, ..)| *m == self.metric)
            .expect("Budget::new admits only these metrics");
        (word, shown)
    }

    /// `max_1_1024`, `p99_4_255`: the statistic's word and the fraction.
    pub fn id(&self) -> String {
        format!("{}_{}_{}", self.statistic().0, self.num, self.den)
    }

    /// As a person reads it: `max |dI| <= 1/255`.
    pub fn label(&self) -> String {
        format!("{} <= {}/{}", self.statistic().1, self.num, self.den)
    }

    /// The budget whose [`Budget::id`] is `id`.
    pub fn parse_id(id: &str) -> Result<Budget, String> {
        let refuse = || {
            format!("{id:?} is not a budget id: STAT_NUM_DEN with STAT max or p99 (e.g. max_4_255)")
        };
        let mut parts = id.rsplitn(3, '_');
        let (Some(den), Some(num), Some(word)) = (parts.next(), parts.next(), parts.next()) else {
            return Err(refuse());
        };
        let metric = STATISTICS
            .iter()
            .find(|(_, w, _)| *w == word)
            .map(|(m, ..)| *m)
            .ok_or_else(refuse)?;
        let num = num.parse().map_err(|_| refuse())?;
        let den = den.parse().map_err(|_| refuse())?;
        Budget::new(metric, num, den)
    }
}

impl std::fmt::Display for Budget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.id())
    }
}

/// A budget as answer.json's `budgets` write it.
#[derive(Serialize, Deserialize)]
struct Written {
    id: String,
    metric: Metric,
    limit: ErrorBudget,
    label: String,
}

impl Serialize for Budget {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Written {
            id: self.id(),
            metric: self.metric,
            limit: self.limit,
            label: self.label(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Budget {
    /// The budget of its id, refused when the metric, limit or label written beside it say
    /// otherwise.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let w = Written::deserialize(d)?;
        let b = Budget::parse_id(&w.id).map_err(serde::de::Error::custom)?;
        if b.metric != w.metric || b.limit != w.limit || b.label() != w.label {
            return Err(serde::de::Error::custom(format!(
                "budget {}: metric {}, limit {} and label {:?} do not match the id",
                w.id,
                w.metric,
                w.limit.get(),
                w.label
            )));
        }
        Ok(b)
    }
}

/// A field holding a budget by its id (`#[serde(with = "as_id")]`): a cell's, a check's.
pub mod as_id {
    use super::Budget;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(b: &Budget, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&b.id())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Budget, D::Error> {
        Budget::parse_id(&String::deserialize(d)?).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The six budgets are written as before (id, metric, limit, label), and read back into
    /// the same budgets; a budget whose written fields contradict its id is refused.
    #[test]
    fn budgets_are_written_as_before_and_read_back() {
        let b = budgets();
        let ids: Vec<String> = b.iter().map(Budget::id).collect();
        assert_eq!(
            ids,
            [
                "max_1_1024",
                "max_1_255",
                "max_4_255",
                "p99_1_1024",
                "p99_1_255",
                "p99_4_255"
            ]
        );
        let json = serde_json::to_value(b[5]).unwrap();
        assert_eq!(
            json,
            serde_json::json!({"id": "p99_4_255", "metric": "p99_abs_error",
                "limit": 4.0 / 255.0, "label": "p99 |dI| <= 4/255"})
        );
        let back: Vec<Budget> = serde_json::from_value(serde_json::to_value(&b).unwrap()).unwrap();
        assert_eq!(back, b);
        assert_eq!(Budget::parse_id("max_1_255").unwrap(), b[1]);
        // Teeth: a contradicting metric or limit, an unknown statistic, a zero fraction.
        let mut wrong = json.clone();
        wrong["metric"] = "max_abs_error".into();
        assert!(serde_json::from_value::<Budget>(wrong).is_err());
        let mut wrong = json;
        wrong["limit"] = (1.0 / 255.0).into();
        assert!(serde_json::from_value::<Budget>(wrong).is_err());
        for bad in ["mean_1_255", "max_0_255", "max_1", "max_a_255", ""] {
            assert!(Budget::parse_id(bad).is_err(), "{bad}");
        }
        assert!(Budget::new(Metric::Rmse, 1, 255).is_err());
    }
}
