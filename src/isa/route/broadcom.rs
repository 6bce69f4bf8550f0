//! Broadcom VideoCore: V3D 4.2 (Raspberry Pi 4) through Mesa's v3d OpenGL ES driver and VC4
//! (Raspberry Pi 0-3) through vc4, both built by `make compilers`, each on its noop drm-shim
//! (v3d's emulates a V3D 4.2 and vc4's a VideoCore IV; neither takes another chip). OpenGL ES
//! rather than v3dv: v3dv uploads buffers through the kernel at pipeline creation, which the
//! shim does not execute (it crashes), and offers Vulkan 1.2 without dynamic rendering. The
//! statistics are the shader-db line, a KHR_debug message (`V3D_DEBUG=shaderdb`,
//! `VC4_DEBUG=shaderdb`; v3d also needs `precompile`, or it compiles nothing before a
//! draw): instructions, threads, uniforms, temporaries, and on V3D stalls and
//! NOPs, on VC4 estimated cycles. Neither chip computes float16: their `mediump` is float32.
//! These are Broadcom's production Linux drivers (Raspberry Pi OS ships them).
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::{mesa_build, Api, Compiler, Ranking, Setup, Vendor};
use crate::isa::throughput;

/// The route through v3d and vc4.
pub struct Broadcom;

impl Vendor for Broadcom {
    fn prefix(&self) -> &'static str {
        "broadcom"
    }

    fn name(&self) -> &'static str {
        "Broadcom"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        &["vc4", "v3d42"]
    }

    /// The two chips the shims emulate, and the Raspberry Pi 5's V3D 7.1, which Mesa's v3d
    /// knows and the V3D 4.2 shim cannot be (refused per family).
    fn known_chips(&self) -> Vec<&'static str> {
        vec!["vc4", "v3d42", "v3d71"]
    }

    fn api(&self) -> Api {
        Api::OpenGlEs
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "v3d / vc4".into(),
            api: "OpenGL ES".into(),
            mesa_version: None,
            production: true,
            note: "Mesa's v3d and vc4 are the drivers the Raspberry Pi ships".into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: throughput::MODEL_KEY.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "cycles".into(),
            meaning: "the compiler's cycles of one QPU thread (one instruction issued a \
                      cycle): VC4's scheduler estimate (`estimated_cycles`, a special function \
                      read 3 instructions after it is written), V3D's instructions and stalls \
                      (`inst_and_stalls`); the instruction count `inst` beside it"
                .into(),
        }
    }

    /// vc4 and v3d choose the threads per QPU from the registers the program needs.
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        Some(("max_temps", Some("threads")))
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &["inst", "threads", "uniforms", "max_temps", "model_cycles"]
    }

    /// VC4: its estimated cycles; V3D: its instructions and stalls (single-pipe).
    fn model(&self, chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        let key = if chip == "vc4" {
            "estimated_cycles"
        } else {
            "inst_and_stalls"
        };
        throughput::issue(stats, key)
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        mesa_build::setup(&["GLES_LIB", "V3D_SHIM", "VC4_SHIM"])
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
        // Any other chip runs on v3d's shim and is refused by its renderer (V3D 4.2).
        if chip == "vc4" {
            mesa_build::gles_env(
                setup,
                "VC4_SHIM",
                "vc4",
                &[("VC4_DEBUG", "shaderdb".into())],
            )
        } else {
            mesa_build::gles_env(
                setup,
                "V3D_SHIM",
                "v3d",
                // v3d compiles at the first draw unless told to precompile (at link time, with
                // the draw's default key), and we never draw.
                &[("V3D_DEBUG", "shaderdb,precompile".into())],
            )
        }
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        // v3d: "V3D 4.2" (sometimes with a revision); vc4: "VC4 V3D 2.1".
        let want = match chip {
            "vc4" => "VC4 ",
            "v3d42" => "V3D 4.2",
            _ => "",
        };
        if !want.is_empty() && device_name.starts_with(want) {
            Ok(())
        } else {
            Err(format!(
                "the renderer is `{device_name}`, not {chip} (the shims emulate V3D 4.2 and \
                 VC4 only)"
            ))
        }
    }

    fn parse_debug_message(&self, message: &str) -> Option<(String, Vec<(String, f64)>)> {
        mesa_build::parse_shader_db(message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renderers_must_be_the_chip() {
        assert!(Broadcom.check_device("v3d42", "V3D 4.2.14.0").is_ok());
        assert!(Broadcom.check_device("vc4", "VC4 V3D 2.1").is_ok());
        // Teeth: a chip the shims do not emulate is refused whatever the renderer says.
        assert!(Broadcom.check_device("v3d71", "V3D 4.2.14.0").is_err());
        assert!(Broadcom.check_device("vc4", "V3D 4.2").is_err());
    }
}
