//! NVIDIA Fermi to Turing: Debian 12's nouveau OpenGL driver (libgl1-mesa-dri) on
//! bookworm-backports' nouveau noop drm-shim (`NOUVEAU_CHIPSET=<hex>`), through EGL
//! surfaceless; the statistics are nouveau's shader-db line, delivered as a KHR_debug message
//! when a program is compiled ("type: 4, local: 0, shared: 0, gpr: 13, inst: 38, bytes: 304,
//! cached: 0"). The compiler is Mesa's own codegen for NVIDIA hardware, not NVIDIA's.
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::{Api, Compiler, Ranking, Setup, Vendor};
use crate::isa::throughput;

/// The route through nouveau's OpenGL driver.
pub struct Nouveau;

const SHIM: &str = "NOUVEAU_SHIM";

impl Vendor for Nouveau {
    fn prefix(&self) -> &'static str {
        "nvidia"
    }

    fn name(&self) -> &'static str {
        "NVIDIA"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        // Fermi GF100, Kepler GK104, Maxwell GM107, Pascal GP104, Turing TU102.
        &["nvc0", "nve4", "nv117", "nv134", "nv162"]
    }

    /// The chipsets Debian 12's nouveau (22.3.6) knows on the drm-shim (each tried with
    /// `shadelab isa`, 2026-11-28): NV50 to GT21x (known, but without OpenGL 4.3: reported per
    /// family), Fermi to Turing (compiled); Ampere's nv172, which Mesa 25's nouveau compiles
    /// (../shared TOOLCHAIN, Debian 13) and 22.3.6 hands to llvmpipe (refused per family).
    fn known_chips(&self) -> Vec<&'static str> {
        vec![
            "nv50", "nv84", "nv86", "nv92", "nv94", "nv96", "nv98", "nva0", "nva3", "nva5", "nva8",
            "nvaa", "nvac", "nvaf", "nvc0", "nvc1", "nvc3", "nvc4", "nvc8", "nvce", "nvcf", "nvd7",
            "nvd9", "nve4", "nve6", "nve7", "nvf0", "nvf1", "nv106", "nv108", "nv117", "nv118",
            "nv120", "nv124", "nv126", "nv12b", "nv130", "nv132", "nv134", "nv136", "nv137",
            "nv138", "nv13b", "nv140", "nv162", "nv164", "nv166", "nv167", "nv168", "nv172",
        ]
    }

    fn api(&self) -> Api {
        Api::OpenGl
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "nouveau (codegen)".into(),
            api: "OpenGL".into(),
            mesa_version: None,
            production: false,
            note: "Mesa's open-source compiler for NVIDIA hardware; NVIDIA's own driver, which \
                   players run, has another compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: throughput::MODEL_KEY.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "FMA issue slots".into(),
            meaning: "weighted issue count: nouveau's instruction count with each \
                      special-function operation (MUFU: rcp, rsq, exp2, log2, sin, cos) at the \
                      architecture's FP32:SFU throughput ratio of NVIDIA's CUDA guide (Fermi \
                      8 or 6, Kepler 6, Maxwell to Turing 4) instead of 1; the count of those \
                      operations is `sfu_ops`, read in the NIR Mesa hands nouveau (nouveau \
                      prints no disassembly)"
                .into(),
        }
    }

    /// The weighted issue count prices one FP32 FMA at one slot.
    fn counts_fmas(&self) -> bool {
        true
    }

    /// Registers and warps on every chipset this route compiles (Fermi to Turing).
    fn required_draw_statistics(&self) -> &'static [&'static str] {
        &[
            crate::isa::occupancy::REGISTERS_KEY,
            crate::isa::occupancy::WAVES_KEY,
        ]
    }

    fn occupancy(
        &self,
        chip: &str,
        stats: &BTreeMap<String, f64>,
    ) -> Option<crate::isa::occupancy::Occupancy> {
        let gpr = *stats.get("gpr")?;
        Some(crate::isa::occupancy::Occupancy {
            registers: gpr,
            waves: throughput::nvidia_weights(chip)
                .map(|w| crate::isa::occupancy::nvidia_warps(gpr, &w)),
        })
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &[
            "inst",
            "gpr",
            "bytes",
            "local",
            "shared",
            "sfu_ops",
            "model_cycles",
        ]
    }

    fn model(&self, chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        let w = throughput::nvidia_weights(chip)?;
        let cycles =
            throughput::weighted_issue(*stats.get("inst")?, *stats.get(throughput::SFU_KEY)?, &w);
        cycles.is_finite().then_some(throughput::Model {
            cycles,
            bound: throughput::Unit::Issue,
        })
    }

    fn counts_sfu_ops(&self) -> bool {
        true
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        Some(false)
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        super::gl_setup("nouveau", SHIM)
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
        let hex = chip
            .strip_prefix("nv")
            .filter(|h| !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()))
            .ok_or_else(|| format!("`{chip}`: nouveau chips are nv<hex>, e.g. nv162, nvc0"))?;
        let mut env = super::gl_env(setup, SHIM, "nouveau", ("NOUVEAU_CHIPSET", hex.to_string()))?;
        // The NIR handed to the compiler, on stdout: its special-function operations.
        env.push(("MESA_GLSL".into(), "dump".into()));
        Ok(env)
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // nouveau names its screen "NV%02X" after the chipset.
        if device_name.trim().eq_ignore_ascii_case(chip) {
            Ok(())
        } else {
            Err(format!(
                "the renderer is `{device_name}`, not {}",
                chip.to_uppercase()
            ))
        }
    }

    fn parse_debug_message(&self, message: &str) -> Option<(String, Vec<(String, f64)>)> {
        let pairs = super::shader_db_pairs(message);
        let ty = pairs.iter().find(|(k, _)| k == "type")?.1;
        // gallium's shader types are Mesa's stages in 22.3: 0 vertex, 4 fragment, 5 compute.
        let stage = match ty as i64 {
            0 => "vertex",
            4 => "fragment",
            5 => "compute",
            _ => return None,
        };
        let stats = pairs
            .into_iter()
            .filter(|(k, _)| k != "type" && k != "cached");
        Some((stage.into(), stats.collect()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_db_line_parses() {
        let (stage, stats) = Nouveau
            .parse_debug_message(
                "type: 4, local: 0, shared: 0, gpr: 13, inst: 38, bytes: 304, cached: 0",
            )
            .unwrap();
        assert_eq!(stage, "fragment");
        assert!(stats.contains(&("inst".into(), 38.0)));
        assert!(stats.contains(&("gpr".into(), 13.0)));
        assert!(!stats.iter().any(|(k, _)| k == "cached"));
        // Teeth: another message, and an unknown stage, give nothing.
        assert!(Nouveau
            .parse_debug_message("GLSL IR for shader 3")
            .is_none());
        assert!(Nouveau.parse_debug_message("type: 3, inst: 5").is_none());
    }

    #[test]
    fn the_renderer_must_be_the_chip() {
        assert!(Nouveau.check_device("nv162", "NV162").is_ok());
        assert!(Nouveau
            .check_device("nv172", "llvmpipe (LLVM 15.0.6, 256 bits)")
            .is_err());
        assert!(Nouveau.check_device("nv162", "NV134").is_err());
    }
}
