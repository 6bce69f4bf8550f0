//! Qualcomm Adreno a6xx and a7xx: Mesa's Turnip Vulkan driver (ir3 compiler) built by `make
//! compilers`, on Mesa's freedreno noop drm-shim (`FD_GPU_ID=<number>`). Turnip exposes
//! Vulkan 1.4 on these chips, so the timed draw's pipelines compile as on every Vulkan route,
//! with VK_KHR_pipeline_executable_properties' statistics (instruction count with ir3's
//! scheduling NOPs, registers, waves per core, sync stalls, per-category counts) and ir3's
//! disassembly. The compiler is Mesa's own for Adreno hardware; the phones ship Qualcomm's.
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::{mesa_build, Api, Compiler, Ranking, Setup, Vendor};
use crate::isa::throughput;

/// The route through Turnip and ir3.
pub struct Qualcomm;

const KEYS: [&str; 2] = ["TURNIP_ICD", "FREEDRENO_SHIM"];

/// The GPU id the freedreno shim takes for `chip` (`a630` -> 630).
fn gpu_id(chip: &str) -> Result<String, String> {
    chip.strip_prefix('a')
        .filter(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
        .map(str::to_string)
        .ok_or_else(|| format!("`{chip}`: Adreno chips are a<number>, e.g. a630, a740"))
}

impl Vendor for Qualcomm {
    fn prefix(&self) -> &'static str {
        "qualcomm"
    }

    fn name(&self) -> &'static str {
        "Qualcomm"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        // a6xx: Snapdragon 710 (618), 845 (630), 888 (660); a7xx: 7 Gen 1 (730), 8 Gen 2
        // (740), 8 Gen 3 (750).
        &["a618", "a630", "a660", "a730", "a740", "a750"]
    }

    /// The defaults named; any Adreno number of freedreno's a2xx to a7xx taken (the shim takes
    /// the number; Turnip compiles a6xx and a7xx and refuses the older ones, reported per
    /// family, as a chip it does not know).
    fn known_chips(&self) -> Vec<&'static str> {
        self.default_chips().to_vec()
    }

    fn knows(&self, chip: &str) -> bool {
        gpu_id(chip).is_ok_and(|id| id.len() == 3 && ('2'..='7').any(|d| id.starts_with(d)))
    }

    fn other_chips(&self) -> Option<&'static str> {
        Some("or any Adreno number a2NN to a7NN")
    }

    fn api(&self) -> Api {
        Api::Vulkan { device: "adreno" }
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "Turnip (ir3)".into(),
            api: "Vulkan".into(),
            mesa_version: None,
            production: false,
            note: "Mesa's open-source compiler for Adreno; Android phones ship Qualcomm's own \
                   driver and compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: throughput::MODEL_KEY.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "issued instructions".into(),
            meaning: "ir3's issued instructions: its instruction count less the NOPs its \
                      scheduler inserts to cover latency (ir3.c counts a NOP flag and a NOP \
                      instruction in both), each one issue slot; a thread waiting on a \
                      latency yields the ALU to other waves, so the NOPs and the estimated \
                      (ss)/(sy) stall cycles are statistics, not cost; no published \
                      special-function rate for Adreno is used"
                .into(),
        }
    }

    /// Instructions less NOPs: the issue slots the program itself takes.
    fn model(&self, _chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        let cycles = stats.get("instruction_count")? - stats.get("nops_count")?;
        (cycles.is_finite() && cycles >= 0.0).then_some(throughput::Model {
            cycles,
            bound: throughput::Unit::Issue,
        })
    }

    /// ir3 states the waves per core its register footprint allows.
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        Some(("registers_used", Some("max_waves_per_core")))
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &[
            "instruction_count",
            "nops_count",
            "registers_used",
            "half_registers_used",
            "max_waves_per_core",
            "model_cycles",
        ]
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        mesa_build::setup(&KEYS)
    }

    fn setup_command(&self) -> &'static str {
        mesa_build::SETUP_COMMAND
    }

    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        mesa_build::vulkan_env(
            setup,
            "TURNIP_ICD",
            "FREEDRENO_SHIM",
            &[("FD_GPU_ID", gpu_id(chip)?)],
        )
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // Turnip names its device "Turnip Adreno (TM) 630".
        let id = gpu_id(chip)?;
        let name = device_name.to_lowercase();
        if name.contains("adreno") && name.split_whitespace().any(|w| w == id) {
            Ok(())
        } else {
            Err(format!("Turnip gave `{device_name}`, not an Adreno {id}"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chips_are_adreno_numbers_and_the_device_must_match() {
        assert_eq!(gpu_id("a630").as_deref(), Ok("630"));
        assert!(gpu_id("630").is_err());
        assert!(gpu_id("a6x0").is_err());
        assert!(Qualcomm
            .check_device("a630", "Turnip Adreno (TM) 630")
            .is_ok());
        // Teeth: another Adreno, or a software fallback, is refused.
        assert!(Qualcomm
            .check_device("a630", "Turnip Adreno (TM) 640")
            .is_err());
        assert!(Qualcomm.check_device("a630", "llvmpipe (LLVM 15)").is_err());
    }

    #[test]
    fn the_model_is_issued_instructions_without_nops_or_stalls() {
        let stats: BTreeMap<String, f64> = [
            ("instruction_count".to_string(), 59.0),
            ("nops_count".to_string(), 16.0),
            ("estimated_cycles_stalled_on_ss".to_string(), 40.0),
        ]
        .into();
        let m = Qualcomm.model("a630", &stats).unwrap();
        assert_eq!((m.cycles, m.bound), (43.0, throughput::Unit::Issue));
        // Teeth: without the NOP count there is no model (never the count with its NOPs).
        let mut no_nops = stats.clone();
        no_nops.remove("nops_count");
        assert!(Qualcomm.model("a630", &no_nops).is_none());
    }
}
