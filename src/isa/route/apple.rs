//! Apple GPUs (AGX): the G13 of the M1 through Honeykrisp, Mesa's asahi Vulkan driver, and its
//! AGX compiler, built by `make compilers` in a configuration of its own (asahi compiles an
//! OpenCL C library of its own with LLVM at build time, which the other drivers do not need),
//! on the asahi noop drm-shim. The shim is a G13G (`gpu_generation = 13`, `gpu_variant = 'G'` in
//! src/asahi/drm-shim/asahi_noop.c, no variable to choose another), so the device is "Apple M1
//! (G13G A0)" and any other chip is refused. The compiler has no other target to offer: its
//! device key differs between G13G and G13X only in atomics' cluster coherency
//! (src/asahi/compiler/agx_compile.h, `agx_device_key`), G14 and G15 only in the command
//! stream, and its cycle model is "for G13G" (src/asahi/compiler/agx_performance.c).
//!
//! Vulkan rather than OpenGL ES: Mesa 25.0.7's gallium loader has no entry for asahi alone (it
//! reaches it only through kmsro, as the render half of a display device, and kmsro's list of
//! render drivers lacks asahi: src/gallium/auxiliary/pipe-loader/pipe_loader_drm.c), so EGL
//! fails ("DRI2: failed to create screen"); Honeykrisp opens the shim's render node. Its
//! pipeline statistics are a code size and a register count; the compiler's shader-db line
//! (`AGX_MESA_DEBUG=shaderdb`, printed on stderr: [`crate::isa::stderr`]) adds the
//! instructions, the cycle model's estimated cycles of the F/SCIB unit (`fscib`: float, select,
//! compare, integer add) and of the IC unit (`ic`: integer multiply, conversions and the
//! transcendentals: rcp, rsqrt, exp2, log2), `alu` the larger of the two (the units run in
//! parallel across warps), code bytes, registers, threads, spills. The bound unit is named in
//! the row as `bound_fscib` or `bound_ic` (both on a tie), with `alu`'s figure. float16
//! programs compile with 16-bit arithmetic (AGX has it; Honeykrisp offers shaderFloat16).
//!
//! Mesa's compiler is the production driver of Linux on Apple silicon (Asahi Linux); macOS
//! and iOS ship Apple's own compiler.
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::{mesa_build, Api, Compiler, Ranking, Setup, Vendor};
use crate::isa::throughput;

/// The route through asahi.
pub struct Apple;

/// The keys of `compilers.env` this route reads: Honeykrisp's ICD manifest and the shim.
const KEYS: [&str; 2] = ["ASAHI_ICD", "ASAHI_SHIM"];

/// The chips the shim can be, with the variant code the driver puts in its device name
/// ("Apple M1 (G13G A0)"): the shim is a G13G and nothing else.
const CHIPS: [(&str, &str); 1] = [("g13", "G13G")];

/// The cycle model's units (agx_performance.c): whichever estimate is larger bounds `alu`.
const UNITS: [&str; 2] = ["fscib", "ic"];

impl Vendor for Apple {
    fn prefix(&self) -> &'static str {
        "apple"
    }

    fn name(&self) -> &'static str {
        "Apple"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        &["g13"]
    }

    fn known_chips(&self) -> Vec<&'static str> {
        CHIPS.iter().map(|(c, _)| *c).collect()
    }

    fn api(&self) -> Api {
        Api::Vulkan { device: "apple" }
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "Honeykrisp (asahi's AGX compiler)".into(),
            api: "Vulkan".into(),
            mesa_version: None,
            production: false,
            note: "Mesa's open-source compiler for Apple GPUs, the driver of Asahi Linux; \
                   macOS and iOS ship Apple's own compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: "alu".into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "cycles".into(),
            meaning: "the AGX compiler's cycle model for G13G: the estimated cycles of the \
                      bound unit, the larger of F/SCIB (float and integer ALU) and IC \
                      (transcendentals at 4-8 cycles, conversions) (`alu`; the unit named in \
                      `bound_fscib` or `bound_ic`), the instruction count `inst` beside it"
                .into(),
        }
    }

    /// The larger of the F/SCIB (arithmetic) and IC (transcendentals, conversions) units.
    fn model(&self, _chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        use throughput::Unit;
        throughput::bound(&[
            (Unit::Arithmetic, *stats.get("fscib")?),
            (Unit::Sfu, *stats.get("ic")?),
        ])
    }

    /// agx states the threads per core its registers allow.
    fn occupancy_statistics(&self) -> Option<(&'static str, Option<&'static str>)> {
        Some(("number_of_gprs", Some("threads")))
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &[
            "inst", "alu", "fscib", "ic", "bytes", "regs", "threads", "spills", "fills",
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
        _chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        // Every chip runs on the G13G shim; check_device refuses any other.
        mesa_build::vulkan_env(
            setup,
            "ASAHI_ICD",
            "ASAHI_SHIM",
            &[("AGX_MESA_DEBUG", "shaderdb".into())],
        )
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        let known: Vec<&str> = CHIPS.iter().map(|(c, _)| *c).collect();
        let Some((_, code)) = CHIPS.iter().find(|(c, _)| *c == chip) else {
            return Err(format!(
                "`{chip}`: the asahi shim is a G13G (M1) only; known chips: {}",
                known.join(", ")
            ));
        };
        // "Apple M1 (G13G A0)": the code between the parenthesis and the revision.
        let inner = device_name
            .split_once('(')
            .and_then(|(_, rest)| rest.split_whitespace().next());
        if device_name.starts_with("Apple ") && inner == Some(code) {
            Ok(())
        } else {
            Err(format!(
                "the renderer is `{device_name}`, not an Apple {code}"
            ))
        }
    }

    /// A shader-db line, as the compiler prints it ("SHADER-DB: <label> - MESA_SHADER_FRAGMENT
    /// shader: 60 inst, 48 alu, ...") or bare.
    fn parse_debug_message(&self, message: &str) -> Option<(String, Vec<(String, f64)>)> {
        let line = &message[message.find("MESA_SHADER_")?..];
        let (stage, mut stats) = mesa_build::parse_shader_db(line)?;
        let get = |k: &str| stats.iter().find(|(n, _)| n == k).map(|(_, v)| *v);
        if let Some(alu) = get("alu") {
            let bound: Vec<(String, f64)> = UNITS
                .iter()
                .filter(|u| get(u) == Some(alu))
                .map(|u| (format!("bound_{u}"), alu))
                .collect();
            stats.extend(bound);
        }
        Some((stage, stats))
    }

    fn statistics_on_stderr(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bound(message: &str) -> Vec<String> {
        let (_, stats) = Apple.parse_debug_message(message).unwrap();
        stats
            .into_iter()
            .filter(|(k, _)| k.starts_with("bound_"))
            .map(|(k, _)| k)
            .collect()
    }

    #[test]
    fn the_bound_unit_is_named() {
        let line = |fscib: u32, ic: u32| {
            format!(
                "MESA_SHADER_FRAGMENT shader: 60 inst, {} alu, {fscib} fscib, {ic} ic, 496 \
                 bytes, 31 regs, 2 uniforms, 0 scratch, 1024 threads, 0 loops, 0:0 spills:fills",
                fscib.max(ic)
            )
        };
        let (stage, stats) = Apple.parse_debug_message(&line(48, 24)).unwrap();
        assert_eq!(stage, "fragment");
        for (k, v) in [("inst", 60.0), ("alu", 48.0), ("ic", 24.0), ("fills", 0.0)] {
            assert!(stats.contains(&(k.into(), v)), "{k}: {stats:?}");
        }
        assert_eq!(bound(&line(48, 24)), ["bound_fscib"]);
        assert_eq!(bound(&line(20, 32)), ["bound_ic"]);
        // A tie: both units bound the program.
        assert_eq!(bound(&line(32, 32)), ["bound_fscib", "bound_ic"]);
        // Teeth: a line without the cycle model names no unit; another message gives nothing.
        assert!(bound("MESA_SHADER_FRAGMENT shader: 60 inst, 1024 threads").is_empty());
        assert!(Apple.parse_debug_message("GLSL IR for shader 3").is_none());
    }

    #[test]
    fn only_the_shims_chip_is_measured() {
        assert!(Apple.check_device("g13", "Apple M1 (G13G A0)").is_ok());
        // Teeth: a chip the shim is not, a renderer of another variant, a software fallback.
        assert!(Apple.check_device("g14", "Apple M1 (G13G A0)").is_err());
        assert!(Apple.check_device("g13", "Apple M1 Max (G13C A0)").is_err());
        assert!(Apple.check_device("g13", "Apple M2 (G14G A0)").is_err());
        assert!(Apple
            .check_device("g13", "llvmpipe (LLVM 15.0.6, 256 bits)")
            .is_err());
    }

    #[test]
    fn the_compiler_s_stderr_line_parses() {
        let (stage, stats) = Apple
            .parse_debug_message(
                "SHADER-DB:  - MESA_SHADER_FRAGMENT shader: 60 inst, 48 alu, 48 fscib, 24 ic, \
                 496 bytes, 31 regs, 2 uniforms, 0 scratch, 1024 threads, 0 loops, 0:0 \
                 spills:fills",
            )
            .unwrap();
        assert_eq!(stage, "fragment");
        assert!(stats.contains(&("bound_fscib".into(), 48.0)), "{stats:?}");
        // Teeth: a line of something else.
        assert!(Apple
            .parse_debug_message("SHADER-DB: nothing here")
            .is_none());
    }
}
