//! AMD GCN and RDNA: Debian's RADV with `RADV_FORCE_FAMILY=<chip>` creates a null device whose
//! pipelines go through the production ACO compiler (../shared TOOLCHAIN "RADV null device",
//! docs/isa.md). No set-up beyond mesa-vulkan-drivers, whose RADV is found by its library
//! (`libvulkan_radeon.so`) among the loader's ICD manifests; another RADV build is chosen with
//! `--driver-files`. Its rows keep the bare chip name (`navi21`) as their family key, and the
//! name the user wrote where RADV renamed a chip ([`RENAMED`]).
use crate::isa::request::RowKind;
use std::path::Path;

use super::{Api, Compiler, Ranking, Setup, Vendor};

/// The route through RADV and ACO.
pub struct Amd;

/// RADV's driver library, whose ICD manifest is found by the loader's rules
/// ([`crate::gpu::icd`]).
pub const LIBRARY: &str = "libvulkan_radeon.so";

/// The statistics every RADV row carries (docs/isa.schema.json requires them).
pub const STATISTICS: [&str; 8] = [
    "instructions",
    "code_size",
    "vgprs",
    "sgprs",
    "spilled_vgprs",
    "spilled_sgprs",
    "latency",
    "inverse_throughput",
];

/// The chips compiled by default: a spread Mesa 22.3.6 accepts, oldest first (GCN1, GCN4,
/// GCN5, RDNA1, RDNA2, RDNA3).
pub const DEFAULT_CHIPS: [&str; 6] = [
    "tahiti",
    "polaris10",
    "vega10",
    "navi10",
    "navi21",
    "gfx1100",
];

/// Chips RADV knows under another name in newer Mesa releases: (the name of Mesa 22.3, the
/// name of Mesa 25). A family id keeps the name the user wrote; the driver is given its own
/// (../shared/TOOLCHAIN.md "RADV null device": 25.0.7 rejects gfx1100, use navi31).
pub const RENAMED: [(&str, &str); 5] = [
    ("gfx1100", "navi31"),
    ("gfx1101", "navi32"),
    ("gfx1102", "navi33"),
    ("gfx1103_r1", "phoenix"),
    ("gfx1103_r2", "phoenix2"),
];

/// The environment of a child compiling for `chip` with the ICD `driver_files`: set before
/// the child's Vulkan loader starts, never in this process (tests run as threads, and the
/// others use lavapipe).
fn child_env(chip: &str, driver_files: &Path) -> Vec<(String, String)> {
    vec![
        ("RADV_FORCE_FAMILY".into(), chip.into()),
        ("VK_DRIVER_FILES".into(), driver_files.display().to_string()),
        // The loader's older name for the same setting (loaders before 1.3.207).
        (
            "VK_ICD_FILENAMES".into(),
            driver_files.display().to_string(),
        ),
        ("NODEVICE_SELECT".into(), "1".into()),
        ("MESA_SHADER_CACHE_DISABLE".into(), "true".into()),
    ]
}

/// Whether a dotted version ("1.4.305") is at least `(major, minor)`.
pub fn version_at_least(version: &str, want: (u32, u32)) -> bool {
    let mut parts = version
        .split('.')
        .map(|p| p.trim().parse::<u32>().unwrap_or(0));
    let major = parts.next().unwrap_or(0);
    let minor = parts.next().unwrap_or(0);
    (major, minor) >= want
}

impl Vendor for Amd {
    fn prefix(&self) -> &'static str {
        "amd"
    }

    fn name(&self) -> &'static str {
        "AMD"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        &DEFAULT_CHIPS
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
            kind: RowKind::Draw,
            unit: "cycles per wave".into(),
            meaning: "ACO inverse throughput: estimated busy cycles to execute one wave \
                      (fragment shaders compile as wave64); a static model, not a timing"
                .into(),
        }
    }

    /// RADV computes the waves per SIMD from VGPRs, SGPRs and LDS.
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        Some(("vgprs", Some("subgroups_per_simd")))
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &STATISTICS
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, driver_files: Option<&Path>) -> Result<Setup, String> {
        let manifest = match driver_files {
            Some(p) => crate::gpu::icd::Manifest::read(p).ok_or_else(|| {
                format!(
                    "{} is not a Vulkan ICD manifest (--driver-files: a RADV build's \
                     radeon_icd json)",
                    p.display()
                )
            })?,
            None => crate::gpu::icd::find_driver(LIBRARY, "mesa-vulkan-drivers")?,
        };
        let mut setup = Setup::default();
        setup
            .values
            .insert("ICD".into(), manifest.path.display().to_string());
        setup
            .values
            .insert("API_VERSION".into(), manifest.api_version);
        Ok(setup)
    }

    fn setup_command(&self) -> &'static str {
        "scripts/install-deps.sh run"
    }

    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        Ok(child_env(chip, Path::new(setup.get("ICD")?)))
    }

    fn driver_chips(&self, chip: &str, setup: &Setup) -> Vec<String> {
        let Some(&(old, new)) = RENAMED.iter().find(|(o, n)| *o == chip || *n == chip) else {
            return vec![chip.to_string()];
        };
        // The name of the driver's release first, told by its manifest's Vulkan version
        // (Mesa 22.3.6's says 1.3.230 and knows `gfx1100`, 25.0.7's says 1.4.305 and knows
        // `navi31`); the other is tried when the driver says it does not know the first.
        let newer = setup
            .get("API_VERSION")
            .map(|v| version_at_least(v, (1, 4)))
            .unwrap_or(false);
        if newer {
            vec![new.to_string(), old.to_string()]
        } else {
            vec![old.to_string(), new.to_string()]
        }
    }

    fn unknown_chip(&self, why: &str) -> bool {
        // radv_physical_device.c: "Unknown family: %s" before it aborts.
        why.contains("Unknown family")
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // "AMD RADV NAVI21": RADV names the null device after the forced family, under the
        // name of its release (`gfx1100` on Mesa 22.3, `navi31` on Mesa 25).
        let upper = device_name.to_uppercase();
        let names = RENAMED
            .iter()
            .filter(|(o, n)| *o == chip || *n == chip)
            .flat_map(|(o, n)| [*o, *n])
            .chain([chip]);
        if names.into_iter().any(|n| upper.contains(&n.to_uppercase())) {
            Ok(())
        } else {
            Err(format!("RADV gave `{device_name}`, not {chip}"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(api: &str) -> Setup {
        let mut s = Setup::default();
        s.values.insert("API_VERSION".into(), api.into());
        s
    }

    #[test]
    fn a_renamed_chip_is_given_to_the_driver_under_its_releases_name() {
        assert_eq!(
            Amd.driver_chips("gfx1100", &setup("1.3.230")),
            ["gfx1100", "navi31"]
        );
        assert_eq!(
            Amd.driver_chips("gfx1100", &setup("1.4.305")),
            ["navi31", "gfx1100"]
        );
        assert_eq!(Amd.driver_chips("navi21", &setup("1.4.305")), ["navi21"]);
        // The device RADV names after either name is the chip asked for.
        assert!(Amd.check_device("gfx1100", "AMD RADV NAVI31").is_ok());
        assert!(Amd.check_device("gfx1100", "AMD RADV GFX1100").is_ok());
        // Teeth: another chip's device is refused, and so is a software renderer.
        assert!(Amd.check_device("gfx1100", "AMD RADV NAVI21").is_err());
        assert!(Amd
            .check_device("navi21", "llvmpipe (LLVM 19.1.7, 256 bits)")
            .is_err());
        assert!(Amd.unknown_chip("radv: Unknown family: gfx1100"));
        assert!(!Amd.unknown_chip("killed by signal 8"));
        assert!(version_at_least("1.4.305", (1, 4)));
        assert!(!version_at_least("1.3.230", (1, 4)));
    }
}
