//! The cost sources of this build, in the answer's column order: the one place where a cost
//! model is registered (its [`crate::cost::CostSource`] lives beside the job that measures it).
use crate::cost::Registry;

/// lavapipe's frame time and isolated cost, the software engine, every GPU family `isa`
/// compiled, and bench's frame time per machine over a corpus.
pub fn builtin() -> Registry {
    Registry::new()
        .with(crate::bench::cost::LavapipeFrame)
        .with(crate::bench::cost::LavapipeIsolated)
        .with(crate::bench::software::cost::SoftwareEngine)
        .with(crate::isa::cost::StaticCost)
        .with(crate::bench::per_machine::BenchPerMachine)
}

#[cfg(test)]
mod tests {
    use crate::cost::{CostModelId, Evidence};

    /// Only the registered sources measure on demand: anything else is a usage error naming
    /// the ids that are.
    #[test]
    fn an_unknown_model_is_refused_with_the_known_ones() {
        let id = CostModelId::parse("gpu:navi21").unwrap();
        let e = super::builtin()
            .measure(&id, &[], &Evidence::new())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("lavapipe_isolated") && e.contains("isa:FAMILY"),
            "{e}"
        );
    }
}
