//! `auto` in one place: its error budget ([`ErrorBudget`], parsed and validated once) and the
//! error the budget bounds ([`colour_error`]), its candidates and their order by cost, the run's
//! specs ([`AutoSpec`], the budget curve's names), the per-triangle choice and its cache
//! ([`choice`]), whether grouping pays ([`grouping`]: one program when the extra programs cost
//! more than they save; [`frame`]: and only when the grouped frame measured cheaper than one
//! program's), and what was chosen ([`AutoSummary`], [`choose_summarised`]).
//! A cost model of [`crate::cost`] ranks the candidates ([`order_by_model`]: lavapipe's isolated
//! cost, a GPU family's static cost, any source of the registry that measures on demand).
mod choice;
pub mod frame;
mod grouping;
#[cfg(test)]
mod tests;

pub use choice::*;
pub use grouping::*;

use std::time::Instant;

use crate::error::{Error, Result};
use crate::method::{self, Method};
use crate::scene::SceneInputs;

/// An error budget: the largest [`colour_error`] (linear) a method may make. Finite and > 0;
/// written as a number (`0.0039`) or a fraction (`4/255`). Every command parses it with
/// [`ErrorBudget::parse`] (one message); the library takes it as this type.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "f64", into = "f64")]
pub struct ErrorBudget(f64);

impl TryFrom<f64> for ErrorBudget {
    type Error = String;
    fn try_from(v: f64) -> std::result::Result<Self, String> {
        Self::new(v)
    }
}

impl From<ErrorBudget> for f64 {
    fn from(b: ErrorBudget) -> f64 {
        b.0
    }
}

impl ErrorBudget {
    /// 1/255, the default of every command.
    pub const DEFAULT: ErrorBudget = ErrorBudget(1.0 / 255.0);

    /// `v` as a budget: finite and > 0.
    pub fn new(v: f64) -> std::result::Result<Self, String> {
        if v.is_finite() && v > 0.0 {
            Ok(ErrorBudget(v))
        } else {
            Err(Self::refusal(&v.to_string()))
        }
    }

    /// A number or a fraction `a/b` (`4/255`), finite and > 0.
    pub fn parse(s: &str) -> std::result::Result<Self, String> {
        let num = |x: &str| x.trim().parse::<f64>().map_err(|_| Self::refusal(s));
        let v = match s.trim().split_once('/') {
            Some((a, b)) => num(a)? / num(b)?,
            None => num(s)?,
        };
        Self::new(v).map_err(|_| Self::refusal(s))
    }

    /// The one message for a value that is not a budget.
    fn refusal(s: &str) -> String {
        format!(
            "{s:?} is not an error budget: expected a colour error > 0 (linear), a number or a \
             fraction like 4/255 (1/255 = 0.0039)"
        )
    }

    /// The budget, linear colour.
    pub fn get(self) -> f64 {
        self.0
    }

    /// Budgets separated by commas, or `none` (bench's `--auto-curve`).
    pub fn parse_list(s: &str) -> std::result::Result<Vec<Self>, String> {
        if s.trim() == "none" {
            return Ok(Vec::new());
        }
        s.split(',').map(Self::parse).collect()
    }
}

impl std::str::FromStr for ErrorBudget {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Self::parse(s)
    }
}

/// The error a budget bounds: the largest absolute error over the three colour channels
/// (linear), infinite when any channel's is not finite. `auto` applies it to each sample of
/// its choice, before drawing; bench applies it to the drawn image (compare's per-channel
/// `max_abs_error`) to say whether `auto` kept its budget. Colour, not luminance: a budget must
/// hold for every channel a method writes, and the choice sees the channels, not a weighted sum.
pub fn colour_error(abs_error_per_channel: [f64; 3]) -> f64 {
    if abs_error_per_channel.iter().any(|e| !e.is_finite()) {
        return f64::INFINITY;
    }
    abs_error_per_channel.into_iter().fold(0.0, f64::max)
}

/// The methods `auto` chooses from: the rows with [`method::Property::AutoCandidate`] (gouraud
/// and flat included, and the tuned rows of `--method-file`, each only where its proof holds:
/// [`choice`]), ordered at run time by their measured cost ([`order_by_cost`]); phong_exact is
/// the fallback.
pub fn candidates() -> Result<Vec<&'static Method>> {
    Ok(method::all()
        .into_iter()
        .filter(|m| m.has(method::Property::AutoCandidate))
        .collect())
}

/// The candidates with their cost (`cost` returns one per candidate, in order; a non-finite
/// cost sorts last), cheapest first; phong_exact stays last as the fallback whatever it costs.
pub fn order_by_cost(
    cost: impl FnOnce(&[&'static Method]) -> Result<Vec<f64>>,
) -> Result<Vec<(&'static Method, f64)>> {
    let ms = candidates()?;
    let costs = cost(&ms)?;
    if costs.len() != ms.len() {
        return Err(Error::Internal(format!(
            "auto: {} costs for {} candidates",
            costs.len(),
            ms.len()
        )));
    }
    let fallback = method::phong_exact();
    let mut order: Vec<(&'static Method, f64)> = ms
        .into_iter()
        .zip(costs)
        .map(|(m, c)| (m, if c.is_nan() { f64::INFINITY } else { c }))
        .collect();
    order.sort_by(|a, b| {
        std::ptr::eq(a.0, fallback)
            .cmp(&std::ptr::eq(b.0, fallback))
            .then(a.1.total_cmp(&b.1))
    });
    Ok(order)
}

/// The candidates ordered by cost model `id` of `costs`, measured now (with what `ev` holds:
/// the device's context), and the model measured. A candidate's cost is its figure in the
/// model's unit, or its ratio to phong_exact where the model kept no figure.
pub fn order_by_model(
    costs: &crate::cost::Registry,
    id: &crate::cost::CostModelId,
    ev: &crate::cost::Evidence,
) -> Result<(Vec<(&'static Method, f64)>, crate::cost::CostModel)> {
    let mut measured = None;
    let order = order_by_cost(|ms| {
        let model = costs.measure(id, ms, ev)?;
        let costs = ms
            .iter()
            .map(|m| {
                model
                    .figure(m.name)
                    .and_then(|f| f.value.or(f.ratio))
                    .unwrap_or(f64::NAN)
            })
            .collect();
        measured = Some(model);
        Ok(costs)
    })?;
    let model = measured
        .ok_or_else(|| Error::Internal(format!("auto: cost model {id} measured nothing")))?;
    Ok((order, model))
}

/// One line telling the candidates' order and costs (in the cost model's unit).
pub fn order_line(order: &[(&'static Method, f64)]) -> String {
    order
        .iter()
        .map(|(m, c)| format!("{} {c:.2}", m.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `list` (comma-separated method identifiers) without `auto`, and whether `auto` was in it.
pub fn split_methods(list: &str) -> (String, bool) {
    let parts: Vec<&str> = list.split(',').map(str::trim).collect();
    let with = parts.contains(&"auto");
    let rest: Vec<&str> = parts.into_iter().filter(|p| *p != "auto").collect();
    (rest.join(","), with)
}

/// What `auto` needs: the candidates cheapest first (the last is the fallback) and the budget.
/// In JSON (a bench run's request) the candidates are their names.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct AutoSpec {
    /// `auto` for the run's budget; `auto_<k>_255` and the like for a point of the budget curve
    /// ([`curve_name`]).
    pub name: String,
    #[serde(with = "method_names")]
    pub order: Vec<&'static Method>,
    pub budget: ErrorBudget,
    /// The cost of each candidate of `order` in `cost_model` (what [`grouping`] compares).
    pub costs: Vec<f64>,
    /// The costs' model.
    pub cost_model: crate::cost::CostModelId,
}

impl AutoSpec {
    /// `auto` at `budget` over candidates in `order` ([`order_by_cost`]).
    pub fn new(budget: ErrorBudget, order: &[(&'static Method, f64)]) -> Self {
        AutoSpec {
            name: "auto".into(),
            order: order.iter().map(|(m, _)| *m).collect(),
            budget,
            costs: order.iter().map(|(_, c)| *c).collect(),
            cost_model: crate::cost::CostModelId::of(crate::cost::LAVAPIPE_ISOLATED),
        }
    }

    /// This spec and a spec per budget of `curve` other than its own (each named by
    /// [`curve_name`]), once each: bench's budget curve.
    pub fn with_curve(self, curve: &[ErrorBudget]) -> Vec<AutoSpec> {
        let b0 = self.budget.get();
        let mut specs = vec![self];
        for &b in curve {
            let v = b.get();
            if (v - b0).abs() > 1e-12 * b0 && !specs.iter().any(|s| s.budget == b) {
                specs.push(AutoSpec {
                    name: curve_name(v),
                    budget: b,
                    ..specs[0].clone()
                });
            }
        }
        specs
    }
}

/// Methods as their names in JSON, found again in the method table when read.
mod method_names {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(
        ms: &[&'static crate::method::Method],
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        s.collect_seq(ms.iter().map(|m| m.name))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<Vec<&'static crate::method::Method>, D::Error> {
        Vec::<String>::deserialize(d)?
            .iter()
            .map(|n| crate::method::find(n).map_err(serde::de::Error::custom))
            .collect()
    }
}

/// The budgets of `auto`'s curve on bench's Pareto chart (issue 12): 1/1024, 1/255, 4/255,
/// 16/255.
pub const CURVE_BUDGETS: [f64; 4] = [1.0 / 1024.0, 1.0 / 255.0, 4.0 / 255.0, 16.0 / 255.0];

/// The name of `auto` at `budget` on the curve, an identifier like a method's:
/// `auto_<k>_255` or `auto_1_<k>` when the budget is k/255 or 1/k (to 1e-9), else
/// `auto_<budget in millionths>e_6`.
pub fn curve_name(budget: f64) -> String {
    let near = |a: f64| (a - a.round()).abs() < 1e-9 * a.abs().max(1.0);
    let k = budget * 255.0;
    if near(k) && k.round() >= 1.0 {
        return format!("auto_{}_255", k.round() as u64);
    }
    let inv = 1.0 / budget;
    if near(inv) && inv.round() >= 1.0 {
        return format!("auto_1_{}", inv.round() as u64);
    }
    format!("auto_{}e_6", (budget * 1e6).round() as u64)
}

/// What `auto` chose for a scene, for the outputs.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AutoSummary {
    /// `auto`, or [`curve_name`] for a point of bench's budget curve.
    #[serde(default = "auto_name")]
    pub name: String,
    pub budget: f64,
    pub margin: f64,
    pub samples_per_triangle: usize,
    /// (method, triangles), cheapest first.
    pub triangles: Vec<(String, usize)>,
    /// Time to choose (or to find the cached choice), ms.
    pub choice_ms: f64,
    /// Where the choice came from: computed, or cached in this process or on disk.
    #[serde(default = "computed")]
    pub source: ChoiceSource,
    /// Whether grouping paid ([`grouping`]); `triangles` counts what is drawn after it.
    #[serde(default)]
    pub grouping: Option<Grouping>,
}

fn computed() -> ChoiceSource {
    ChoiceSource::Computed
}

fn auto_name() -> String {
    "auto".into()
}

impl AutoSummary {
    /// The summary of `pick` (indices into `spec.order`).
    pub fn new(spec: &AutoSpec, pick: &[usize], choice_ms: f64, source: ChoiceSource) -> Self {
        AutoSummary {
            name: spec.name.clone(),
            budget: spec.budget.get(),
            margin: AUTO_MARGIN,
            samples_per_triangle: (AUTO_GRID + 1) * (AUTO_GRID + 2) / 2,
            triangles: spec
                .order
                .iter()
                .enumerate()
                .map(|(i, m)| (m.name.to_string(), pick.iter().filter(|&&k| k == i).count()))
                .collect(),
            choice_ms,
            source,
            grouping: None,
        }
    }

    /// One line for stderr: name, budget, where the choice came from and the triangles per
    /// method used.
    pub fn line(&self) -> String {
        format!(
            "{} (budget {:.3e}, {} in {:.0} ms): {}",
            self.name,
            self.budget,
            match self.source {
                ChoiceSource::Computed => "chosen",
                ChoiceSource::Memory => "found in this run's cache",
                ChoiceSource::Disk => "found in the disk cache",
            },
            self.choice_ms,
            self.triangles
                .iter()
                .filter(|(_, k)| *k > 0)
                .map(|(m, k)| format!("{m} {k}"))
                .collect::<Vec<_>>()
                .join(", ")
        ) + &self
            .grouping
            .as_ref()
            .map_or_else(String::new, |g| format!("; {}", g.line()))
    }
}

/// Whether a choice may come from the cache ([`choose_cached`]) or is computed now ([`choose`],
/// to time it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cache {
    Use,
    Bypass,
}

/// `spec`'s per-triangle choice on `inputs` (indices into `spec.order`), after [`settle_on`]
/// merged the groups that do not pay, and its summary, timed.
pub fn choose_summarised(
    inputs: &SceneInputs,
    spec: &AutoSpec,
    cache: Cache,
) -> (Vec<usize>, AutoSummary) {
    let t = Instant::now();
    let budget = spec.budget.get();
    let choice = match cache {
        Cache::Use => choose_cached(inputs, &spec.order, budget),
        Cache::Bypass => Choice {
            pick: choose(inputs, &spec.order, budget),
            source: ChoiceSource::Computed,
        },
    };
    let mut pick = choice.pick;
    let grouping = settle_on(inputs, spec, &mut pick);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let mut summary = AutoSummary::new(spec, &pick, ms, choice.source);
    summary.grouping = Some(grouping);
    (pick, summary)
}
