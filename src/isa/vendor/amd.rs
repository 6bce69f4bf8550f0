//! AMD GCN and RDNA: Debian's RADV with `RADV_FORCE_FAMILY=<chip>` creates a null device whose
//! pipelines go through the production ACO compiler (../shared TOOLCHAIN "RADV null device",
//! docs/isa.md). No set-up beyond mesa-vulkan-drivers; another RADV build is chosen with
//! `--driver-files`. Its rows keep the bare chip name (`navi21`) as their family key.
use std::path::Path;

use super::{Api, Compiler, Ranking, Setup, Vendor};

/// The route through RADV and ACO.
pub struct Amd;

impl Vendor for Amd {
    fn prefix(&self) -> &'static str {
        "amd"
    }

    fn name(&self) -> &'static str {
        "AMD"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        &crate::isa::DEFAULT_FAMILIES
    }

    /// The names of Mesa's `ac_get_family_name` (src/amd/common/amd_family.c) that
    /// `RADV_FORCE_FAMILY` accepts: Mesa 22.3.6's (each tried with `shadelab isa`,
    /// 2026-11-28; navi24, rembrandt and gfx1036 die of SIGFPE there, reported per family), then
    /// Mesa 25.0.7's additions (../shared TOOLCHAIN "RADV null device"; 25 calls gfx1100
    /// navi31).
    fn known_chips(&self) -> Vec<&'static str> {
        vec![
            "tahiti",
            "pitcairn",
            "verde",
            "oland",
            "hainan",
            "bonaire",
            "kabini",
            "kaveri",
            "hawaii",
            "iceland",
            "tonga",
            "carrizo",
            "fiji",
            "stoney",
            "polaris10",
            "polaris11",
            "polaris12",
            "vegam",
            "vega10",
            "vega12",
            "vega20",
            "raven",
            "raven2",
            "renoir",
            "arcturus",
            "aldebaran",
            "navi10",
            "navi12",
            "navi14",
            "navi21",
            "navi22",
            "navi23",
            "vangogh",
            "navi24",
            "rembrandt",
            "gfx1036",
            "gfx1100",
            "gfx1101",
            "gfx1102",
            "gfx1103_r1",
            "gfx1103_r2",
            "navi31",
            "navi32",
            "navi33",
            "phoenix",
            "gfx1150",
            "gfx1151",
            "gfx1152",
            "gfx1153",
            "gfx1200",
            "gfx1201",
        ]
    }

    fn api(&self) -> Api {
        Api::Vulkan { device: "radv" }
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "RADV (ACO)".into(),
            api: "Vulkan".into(),
            mesa_version: None,
            production: true,
            note: "Mesa's RADV is AMD's production Vulkan driver on Linux (AMD's own AMDVLK \
                   is the other); ACO is its shader compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: "inverse_throughput".into(),
            stage: "fragment".into(),
            kind: "draw".into(),
            unit: "cycles per wave".into(),
            meaning: "ACO inverse throughput: estimated busy cycles to execute one wave \
                      (fragment shaders compile as wave64); a static model, not a timing"
                .into(),
        }
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &crate::isa::table::REQUIRED
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, driver_files: &Path) -> Result<Setup, String> {
        if driver_files.is_file() {
            Ok(Setup::default())
        } else {
            Err(format!(
                "{} is missing (Debian package mesa-vulkan-drivers, or another RADV build's ICD \
                 manifest with --driver-files)",
                driver_files.display()
            ))
        }
    }

    fn setup_command(&self) -> &'static str {
        "scripts/install-deps.sh run"
    }

    fn child_env(
        &self,
        chip: &str,
        _setup: &Setup,
        driver_files: &Path,
    ) -> Result<Vec<(String, String)>, String> {
        Ok(crate::isa::child_env(chip, driver_files))
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // "AMD RADV NAVI21": RADV names the null device after the forced family.
        if device_name.to_uppercase().contains(&chip.to_uppercase()) {
            Ok(())
        } else {
            Err(format!("RADV gave `{device_name}`, not {chip}"))
        }
    }
}
