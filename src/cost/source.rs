//! Where cost models come from: the [`CostSource`] interface, the [`Evidence`] a run hands to
//! its sources, and the [`Registry`] of sources that every consumer reads through.
use std::any::Any;
use std::sync::Arc;

use super::{CostModel, CostModelId};
use crate::error::{Error, Result};
use crate::method::Method;

/// What a run measured, by type: each job puts in its own typed results (bench's timed scenes,
/// isa's reports, ...), each source takes the types it reads and ignores the rest. The judgement
/// layer thus never names a job's types.
#[derive(Default)]
pub struct Evidence {
    items: Vec<Box<dyn Any + Send + Sync>>,
}

impl Evidence {
    pub fn new() -> Self {
        Self::default()
    }

    /// `self` with `item` added.
    pub fn with<T: Any + Send + Sync>(mut self, item: T) -> Self {
        self.push(item);
        self
    }

    pub fn push<T: Any + Send + Sync>(&mut self, item: T) {
        self.items.push(Box::new(item));
    }

    /// Every item of type `T`, in the order they were added.
    pub fn all<T: Any>(&self) -> impl Iterator<Item = &T> {
        self.items.iter().filter_map(|b| b.downcast_ref::<T>())
    }

    /// The first item of type `T`.
    pub fn one<T: Any>(&self) -> Option<&T> {
        self.all::<T>().next()
    }
}

impl std::fmt::Debug for Evidence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Evidence({} items)", self.items.len())
    }
}

/// A source of cost figures: one implementation per kind of measurement (lavapipe's frame time,
/// its isolated cost, the software engine, a GPU compiler's static statistics, ...).
pub trait CostSource: Send + Sync {
    /// A short name for messages (`lavapipe_frame`, `isa`).
    fn name(&self) -> &'static str;

    /// The models this source makes of what `ev` holds, in column order (none when the run did
    /// not measure what the source reads).
    fn models(&self, ev: &Evidence) -> Vec<CostModel>;

    /// The ids this source measures on demand (`auto --cost-model`), as the help text says them
    /// (`lavapipe_isolated`, `isa:FAMILY`); `None`: it only reads what a run measured.
    fn on_demand(&self) -> Option<&'static str> {
        None
    }

    /// Every id this source can measure on demand here, for a caller that wants them all
    /// (`tune`): concrete ids, unlike [`CostSource::on_demand`]'s help text. None by default.
    fn on_demand_ids(&self) -> Vec<CostModelId> {
        Vec::new()
    }

    /// Whether [`CostSource::measure`] takes `id`.
    fn measures(&self, _id: &CostModelId) -> bool {
        false
    }

    /// Measures model `id` now on `methods`, with what the caller has in `ev` (the device's
    /// context, the binary to start children from).
    fn measure(
        &self,
        id: &CostModelId,
        _methods: &[&'static Method],
        _ev: &Evidence,
    ) -> Result<CostModel> {
        Err(Error::Usage(format!(
            "cost model {id}: {} does not measure on demand",
            self.name()
        )))
    }
}

/// The cost sources of a run, in column order.
#[derive(Clone, Default)]
pub struct Registry {
    sources: Vec<Arc<dyn CostSource>>,
}

impl std::fmt::Debug for Registry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.sources.iter().map(|s| s.name()))
            .finish()
    }
}

impl Registry {
    /// No source.
    pub fn new() -> Self {
        Self::default()
    }

    /// `self` with `source` after the others.
    pub fn with(mut self, source: impl CostSource + 'static) -> Self {
        self.sources.push(Arc::new(source));
        self
    }

    /// Every source's models of `ev`, sources in registration order.
    pub fn models(&self, ev: &Evidence) -> Vec<CostModel> {
        self.sources.iter().flat_map(|s| s.models(ev)).collect()
    }

    /// Model `id` measured now on `methods`; a usage error naming the ids that can be, when no
    /// source measures `id`.
    pub fn measure(
        &self,
        id: &CostModelId,
        methods: &[&'static Method],
        ev: &Evidence,
    ) -> Result<CostModel> {
        match self.sources.iter().find(|s| s.measures(id)) {
            Some(s) => s.measure(id, methods, ev),
            None => Err(Error::Usage(format!(
                "--cost-model {id}: no cost model of that id is measured on demand; expected \
                 one of: {}",
                self.on_demand().join(", ")
            ))),
        }
    }

    /// Whether some source measures `id` on demand.
    pub fn knows(&self, id: &CostModelId) -> bool {
        self.sources.iter().any(|s| s.measures(id))
    }

    /// Every concrete id the sources can measure on demand, sources in registration order.
    pub fn on_demand_ids(&self) -> Vec<CostModelId> {
        self.sources
            .iter()
            .flat_map(|s| s.on_demand_ids())
            .collect()
    }

    /// The on-demand ids of every source, as help text.
    pub fn on_demand(&self) -> Vec<&'static str> {
        self.sources.iter().filter_map(|s| s.on_demand()).collect()
    }
}
