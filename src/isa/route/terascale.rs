//! AMD TeraScale 2 and 3 (Evergreen, Northern Islands): Debian 12's r600 OpenGL driver
//! (libgl1-mesa-dri) on bookworm-backports' radeon noop drm-shim (`RADEON_GPU_ID=<CHIP>`),
//! through EGL surfaceless; the statistics are r600's shader-db line, delivered as a KHR_debug
//! message ("FS shader: 110 dw, 17 gprs, 17 alu_groups, 0 loops, 3 cf, 1 stack"). The
//! compiler is Mesa's r600 back-end, not AMD's (Catalyst, discontinued for these chips).
use crate::isa::request::RowKind;
use std::path::Path;

use super::{Api, Compiler, Ranking, Setup, Vendor};

/// The route through r600's OpenGL driver.
pub struct TeraScale;

const SHIM: &str = "RADEON_SHIM";

impl Vendor for TeraScale {
    fn prefix(&self) -> &'static str {
        "terascale"
    }

    fn name(&self) -> &'static str {
        "TeraScale"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        // Evergreen (HD 5870) and Northern Islands (HD 6970, VLIW4).
        &["cypress", "cayman"]
    }

    /// The chips Debian 12's r600 (22.3.6) knows by `RADEON_GPU_ID` (each tried with
    /// `shadelab isa`, 2026-11-28): R600 and R700 (known, but without OpenGL 4.3: reported per
    /// family), Evergreen and Northern Islands (compiled).
    fn known_chips(&self) -> Vec<&'static str> {
        vec![
            "r600", "rv610", "rv630", "rv670", "rv620", "rv635", "rs780", "rs880", "rv770",
            "rv730", "rv710", "rv740", "cedar", "redwood", "juniper", "cypress", "hemlock", "palm",
            "sumo", "sumo2", "barts", "turks", "caicos", "cayman", "aruba",
        ]
    }

    fn api(&self) -> Api {
        Api::OpenGl
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "r600".into(),
            api: "OpenGL".into(),
            mesa_version: None,
            production: false,
            note: "Mesa's r600 compiler; AMD's own driver for these chips (Catalyst) is \
                   discontinued"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: "alu_groups".into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "ALU issue cycles".into(),
            meaning: "r600's VLIW ALU instruction groups of the compiled program: one group \
                      issues a cycle, whatever it holds (up to 5 operations on Evergreen, a \
                      transcendental in its t slot; 4 on Cayman); no published \
                      special-function rate for TeraScale is used"
                .into(),
        }
    }

    /// Registers only: no published register file size of r600 is used.
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        Some(("gprs", None))
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &["dw", "gprs", "alu_groups", "cf"]
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        Some(false)
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        super::gl_setup("r600", SHIM)
    }

    fn setup_command(&self) -> &'static str {
        "scripts/setup-vendors.sh gl"
    }

    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        super::gl_env(setup, SHIM, "r600", ("RADEON_GPU_ID", chip.to_uppercase()))
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // r600 names its screen "AMD CAYMAN (DRM ...)".
        let first = device_name.split_whitespace().nth(1).unwrap_or("");
        if first.eq_ignore_ascii_case(chip) {
            Ok(())
        } else {
            Err(format!(
                "the renderer is `{device_name}`, not AMD {}",
                chip.to_uppercase()
            ))
        }
    }

    fn parse_debug_message(&self, message: &str) -> Option<(String, Vec<(String, f64)>)> {
        let (head, rest) = message.split_once(" shader:")?;
        let stage = match head.trim() {
            "VS" => "vertex",
            "FS" => "fragment",
            "CS" => "compute",
            _ => return None,
        };
        Some((stage.into(), super::shader_db_pairs(rest)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_db_line_parses() {
        let (stage, stats) = TeraScale
            .parse_debug_message(
                "FS shader: 110 dw, 17 gprs, 17 alu_groups, 0 loops, 3 cf, 1 stack",
            )
            .unwrap();
        assert_eq!(stage, "fragment");
        assert!(stats.contains(&("alu_groups".into(), 17.0)));
        assert!(stats.contains(&("dw".into(), 110.0)));
        assert!(TeraScale.parse_debug_message("GS shader: 1 dw").is_none());
        assert!(TeraScale
            .check_device("cayman", "AMD CAYMAN (DRM 2.50.0)")
            .is_ok());
        assert!(TeraScale
            .check_device("cayman", "AMD CYPRESS (DRM 2.50.0)")
            .is_err());
        assert!(TeraScale
            .check_device("barts", "llvmpipe (LLVM 15.0.6, 256 bits)")
            .is_err());
    }
}
