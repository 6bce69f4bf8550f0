//! Intel Gen9 to Xe-HPG: the system's ANV (mesa-vulkan-drivers; its ICD manifest found by its
//! library, [`LIBRARY`]) on Mesa's Intel noop drm-shim (`LD_PRELOAD`,
//! `INTEL_STUB_GPU_PLATFORM=<chip>`), the shim built from the release's own Mesa source by
//! `scripts/setup-vendors.sh intel` into the user's cache. Meteor Lake, Lunar Lake,
//! Battlemage and Panther Lake ([`XE_CHIPS`]) go through the system's ANV where it is Mesa 25
//! (Debian 13), else (Debian 12's ANV 22.3.6 does not know them) through bookworm-backports'
//! ANV 25.0.7 on the shim built from Mesa 25.0.7 by `make compilers`; both with
//! `INTEL_FORCE_PROBE='*'` (25.0 still marks Xe3 experimental); their rows carry that Mesa
//! version. ANV is Intel's production Linux Vulkan driver; its back-end (brw)
//! compiles every fragment shader at SIMD8 (before Xe2) and, where it can, SIMD16 and SIMD32,
//! each an executable with its own statistics.
//!
//! Which width runs: brw_compile_fs (src/intel/compiler/brw_fs.cpp, Mesa 22.3.6) always keeps
//! SIMD8, keeps SIMD16 when it compiles without spilling, and keeps SIMD32 only when its
//! estimated throughput beats the narrower ones' ("SIMD32 shader inefficient" otherwise); ANV
//! enables every kept width in 3DSTATE_PS (genX_pipeline.c, `brw_fs_get_dispatch_enables` of
//! brw_compiler.h), and the hardware dispatches the widest enabled width when it has pixels
//! enough (the "Variable Pixel Dispatch" table of the PRM cited there). So a draw's pixels run
//! at the widest kept width: its figures are the row's unprefixed statistics, with
//! `dispatch_width`; every width's are kept as `simd<W>_<statistic>`.
use crate::isa::request::RowKind;
use std::collections::BTreeMap;
use std::path::Path;

use super::brw_issue::{self, Generation};
use super::{Api, Compiler, Ranking, Setup, Vendor};
use crate::gpu::vk::{Executable, Representation, StatValue, Statistic};
use crate::isa::throughput;

/// The route through ANV and brw.
pub struct Intel;

/// ANV's driver library, whose ICD manifest is found by the loader's rules
/// ([`crate::gpu::icd`]).
pub const LIBRARY: &str = "libvulkan_intel.so";

/// The chips compiled by ANV 25.0.7 of `make compilers`: Meteor Lake (Xe-LPG), Lunar Lake
/// and Battlemage (Xe2), Panther Lake (Xe3).
pub const XE_CHIPS: [&str; 4] = ["mtl", "lnl", "bmg", "ptl"];

impl Vendor for Intel {
    fn prefix(&self) -> &'static str {
        "intel"
    }

    fn name(&self) -> &'static str {
        "Intel"
    }

    fn default_chips(&self) -> &'static [&'static str] {
        // Gen9 Skylake, Gen11 Ice Lake, Gen12 Tiger Lake and Alder Lake, Xe-HPG DG2 (Arc);
        // through ANV 25.0.7: Meteor Lake, Lunar Lake, Battlemage, Panther Lake.
        &[
            "skl", "icl", "tgl", "adl", "dg2", "mtl", "lnl", "bmg", "ptl",
        ]
    }

    /// The platforms of `INTEL_STUB_GPU_PLATFORM` ANV 22.3.6 creates a device on (each tried
    /// with `shadelab isa`, 2026-11-28: Gen7/8 names are hasvk's, refused by ANV), then
    /// [`XE_CHIPS`] of ANV 25.0.7.
    fn known_chips(&self) -> Vec<&'static str> {
        let mut v = vec![
            "skl", "bxt", "kbl", "aml", "cml", "glk", "whl", "cfl", "icl", "ehl", "jsl", "tgl",
            "rkl", "dg1", "adl", "sg1", "rpl", "dg2",
        ];
        v.extend(XE_CHIPS);
        v
    }

    fn api(&self) -> Api {
        Api::Vulkan { device: "intel" }
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            driver: "ANV (brw)".into(),
            api: "Vulkan".into(),
            mesa_version: None,
            production: true,
            note: "Mesa's ANV is Intel's own production Vulkan driver on Linux; the Windows \
                   driver has another compiler"
                .into(),
        }
    }

    fn ranking(&self) -> Ranking {
        Ranking {
            key: throughput::MODEL_KEY.into(),
            stage: "fragment".into(),
            kind: RowKind::Draw,
            unit: "FP32 FMAs per pixel".into(),
            meaning: "busy cycles of the EU's busier back-end unit (FPU `fpu_fmas` or extended \
                      math `em_fmas`) at the SIMD width the driver dispatches (the widest it \
                      kept: `dispatch_width`), each instruction at brw's own per-instruction \
                      rate (brw_ir_performance.cpp), per pixel in FP32 FMAs; brw's latency \
                      estimate of one thread alone is the statistic `cycle_count`; a static \
                      model, not a timing"
                .into(),
        }
    }

    /// One SIMD-width FP32 FMA is one per pixel.
    fn counts_fmas(&self) -> bool {
        true
    }

    /// The busier of the FPU and the EM unit ([`brw_issue`]).
    fn model(&self, _chip: &str, stats: &BTreeMap<String, f64>) -> Option<throughput::Model> {
        throughput::bound(&[
            (throughput::Unit::Arithmetic, *stats.get("fpu_fmas")?),
            (throughput::Unit::Sfu, *stats.get("em_fmas")?),
        ])
    }

    /// Registers on every chip; the threads per EU are not known on Xe3.
    fn required_draw_statistics(&self) -> &'static [&'static str] {
        &[crate::isa::occupancy::REGISTERS_KEY]
    }

    fn occupancy(
        &self,
        chip: &str,
        stats: &BTreeMap<String, f64>,
    ) -> Option<crate::isa::occupancy::Occupancy> {
        // Threads per EU are fixed: each has its own register file.
        Some(crate::isa::occupancy::Occupancy {
            registers: *stats.get("grf_registers")?,
            waves: Generation::of(chip).and_then(Generation::threads_per_eu),
        })
    }

    fn required_statistics(&self) -> &'static [&'static str] {
        &[
            "instruction_count",
            "cycle_count",
            "fpu_fmas",
            "em_fmas",
            "model_cycles",
            "send_count",
            "spill_count",
            "fill_count",
            "grf_registers",
            "dispatch_width",
        ]
    }

    fn float16(&self, _chip: &str) -> Option<bool> {
        None
    }

    fn setup(&self, _driver_files: Option<&Path>) -> Result<Setup, String> {
        let manifest = crate::gpu::icd::find_driver(LIBRARY, "mesa-vulkan-drivers")?;
        let mut setup = super::read_env("intel")?;
        setup.get("SHIM")?;
        setup
            .values
            .insert("ICD".into(), manifest.path.display().to_string());
        Ok(setup)
    }

    fn setup_command(&self) -> &'static str {
        "scripts/setup-vendors.sh intel"
    }

    fn setup_for(&self, chip: &str, driver_files: Option<&Path>) -> Result<Setup, String> {
        if !XE_CHIPS.contains(&chip) {
            return self.setup(driver_files);
        }
        // The system's ANV and shim where both are Mesa 25 (Debian 13); else those of `make
        // compilers`.
        match self.setup(driver_files) {
            Ok(s) if system_knows_xe(&s) => Ok(s),
            _ => super::mesa_build::setup(&["ANV_ICD", "INTEL_SHIM"]),
        }
    }

    fn setup_command_for(&self, chip: &str) -> &'static str {
        if XE_CHIPS.contains(&chip) && !self.setup(None).is_ok_and(|s| system_knows_xe(&s)) {
            super::mesa_build::SETUP_COMMAND
        } else {
            self.setup_command()
        }
    }

    fn child_env(
        &self,
        chip: &str,
        setup: &Setup,
        _driver_files: Option<&Path>,
    ) -> Result<Vec<(String, String)>, String> {
        if XE_CHIPS.contains(&chip) && !system_knows_xe(setup) {
            return super::mesa_build::vulkan_env(
                setup,
                "ANV_ICD",
                "INTEL_SHIM",
                &[
                    ("INTEL_STUB_GPU_PLATFORM", chip.into()),
                    ("INTEL_FORCE_PROBE", "*".into()),
                ],
            );
        }
        let icd = setup.get("ICD")?;
        let mut env = vec![
            ("LD_PRELOAD".into(), setup.get("SHIM")?.into()),
            ("INTEL_STUB_GPU_PLATFORM".into(), chip.into()),
            ("VK_DRIVER_FILES".into(), icd.into()),
            ("VK_ICD_FILENAMES".into(), icd.into()),
            ("NODEVICE_SELECT".into(), "1".into()),
            ("MESA_SHADER_CACHE_DISABLE".into(), "true".into()),
        ];
        if XE_CHIPS.contains(&chip) {
            // Mesa 25.0 still marks Xe3 experimental.
            env.push(("INTEL_FORCE_PROBE".into(), "*".into()));
        }
        Ok(env)
    }

    fn check_device(&self, chip: &str, device_name: &str) -> Result<(), String> {
        super::refuse_software(device_name)?;
        if device_name.to_lowercase().contains("intel") {
            Ok(())
        } else {
            Err(format!("ANV gave `{device_name}`, not an Intel {chip}"))
        }
    }

    fn merge_executables(&self, chip: &str, exes: Vec<Executable>) -> Vec<Executable> {
        merge_simd(chip, exes)
    }
}

/// Whether the system's ANV and the shim of `scripts/setup-vendors.sh intel` (built from the
/// system's Mesa source, `MESA_VERSION` of intel.env) are Mesa 25 or later, which know Meteor
/// Lake to Panther Lake: then those chips need no `make compilers` (Debian 13's Mesa 25.0.7).
pub fn system_knows_xe(setup: &Setup) -> bool {
    setup
        .get("MESA_VERSION")
        .ok()
        .and_then(|v| v.split('.').next()?.parse::<u32>().ok())
        .is_some_and(|major| major >= 25)
}

/// The SIMD width of an executable: ANV names fragment executables "SIMD16 fragment" and
/// describes every one as "SIMD8 vertex shader"; the subgroup size is the same width.
fn width(e: &Executable) -> u32 {
    let text = format!("{} {}", e.name, e.description);
    text.split_whitespace()
        .find_map(|w| w.strip_prefix("SIMD")?.parse().ok())
        .unwrap_or(e.subgroup_size)
}

/// The distinct general registers (`g<N>`) an assembly names: a proxy of the registers the
/// program holds (ANV 22.3.6 reports no register statistic; a SIMD16 operand spans two
/// registers and is named once; the render-target write's payload sits in the top ones).
pub fn grf_registers(asm: &str) -> Option<u32> {
    let mut seen = std::collections::BTreeSet::new();
    for token in asm.split(|c: char| !(c.is_ascii_alphanumeric())) {
        if let Some(n) = token.strip_prefix('g').and_then(|d| d.parse::<u32>().ok()) {
            seen.insert(n);
        }
    }
    (!seen.is_empty()).then_some(seen.len() as u32)
}

fn stat(name: String, value: f64) -> Statistic {
    Statistic {
        description: String::new(),
        name,
        value: StatValue::Float(value),
    }
}

/// One executable per stage: every width's statistics as "SIMD<W> <name>" (with
/// "GRF registers", "FPU FMAs" and "EM FMAs" from its assembly on `chip`: [`brw_issue`]), the
/// dispatched (widest) width's also under their own names with "Dispatch Width", and the
/// widths' assemblies one after the other.
pub fn merge_simd(chip: &str, exes: Vec<Executable>) -> Vec<Executable> {
    let mut by_stage: BTreeMap<String, Vec<Executable>> = BTreeMap::new();
    let mut order = Vec::new();
    for e in exes {
        if !order.contains(&e.stage) {
            order.push(e.stage.clone());
        }
        by_stage.entry(e.stage.clone()).or_default().push(e);
    }
    let mut out = Vec::new();
    for stage in order {
        let mut list = by_stage.remove(&stage).unwrap_or_default();
        list.sort_by_key(width);
        let Some(widest) = list.last() else { continue };
        let w_max = width(widest);
        let mut merged = Executable {
            name: stage.clone(),
            description: format!("{stage} shader, dispatched at SIMD{w_max}"),
            stage: stage.clone(),
            subgroup_size: w_max,
            statistics: Vec::new(),
            representations: Vec::new(),
        };
        let mut text = String::new();
        for e in &list {
            let w = width(e);
            // "GEN Assembly" only (ANV also gives "Final NIR").
            let asm: String = e
                .representations
                .iter()
                .filter(|r| r.name.to_lowercase().contains("assembl"))
                .map(|r| r.text.as_str())
                .collect();
            let mut stats = e.statistics.clone();
            if let Some(g) = grf_registers(&asm) {
                stats.push(Statistic {
                    name: "GRF registers".into(),
                    description: "distinct general registers the assembly names".into(),
                    value: StatValue::Uint(u64::from(g)),
                });
            }
            if !asm.is_empty() {
                let busy = brw_issue::busy(&asm, chip);
                let per_pixel = brw_issue::fma_cycles(w);
                stats.push(stat("FPU FMAs".into(), busy.fpu / per_pixel));
                stats.push(stat("EM FMAs".into(), busy.em / per_pixel));
            }
            for s in &stats {
                let mut p = s.clone();
                p.name = format!("SIMD{w} {}", s.name);
                merged.statistics.push(p);
            }
            if w == w_max {
                merged.statistics.extend(stats);
                merged
                    .statistics
                    .push(stat("Dispatch Width".into(), f64::from(w)));
            }
            if !asm.is_empty() {
                text += &format!("// SIMD{w}\n{asm}\n");
            }
        }
        if !text.is_empty() {
            merged.representations.push(Representation {
                name: "GEN Assembly".into(),
                description: "every SIMD width, narrowest first".into(),
                text,
            });
        }
        out.push(merged);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exe(name: &str, cycles: u64, asm: &str) -> Executable {
        Executable {
            name: name.into(),
            description: format!("{name} shader"),
            stage: "fragment".into(),
            subgroup_size: 0,
            statistics: vec![Statistic {
                name: "Cycle Count".into(),
                description: String::new(),
                value: StatValue::Uint(cycles),
            }],
            representations: vec![Representation {
                name: "GEN Assembly".into(),
                description: String::new(),
                text: asm.into(),
            }],
        }
    }

    #[test]
    fn widths_merge_into_one_row_with_the_widest_unprefixed() {
        let merged = merge_simd(
            "tgl",
            vec![
                exe(
                    "SIMD16 fragment",
                    300,
                    "mad(16) g12<1>F g4<8,8,1>F g2<0,1,0>F",
                ),
                exe("SIMD8 fragment", 200, "mov(8) g3<1>F g7<8,8,1>F"),
            ],
        );
        assert_eq!(merged.len(), 1);
        let get = |n: &str| {
            merged[0]
                .statistics
                .iter()
                .find(|s| s.name == n)
                .map(|s| s.value.as_f64())
        };
        assert_eq!(get("SIMD8 Cycle Count"), Some(200.0));
        assert_eq!(get("SIMD16 Cycle Count"), Some(300.0));
        assert_eq!(get("Cycle Count"), Some(300.0));
        assert_eq!(get("Dispatch Width"), Some(16.0));
        assert_eq!(get("SIMD8 GRF registers"), Some(2.0));
        assert_eq!(get("GRF registers"), Some(3.0));
        // One SIMD16 mad is one FMA per pixel; the SIMD8 mov one too, at its own width.
        assert_eq!(get("FPU FMAs"), Some(1.0));
        assert_eq!(get("SIMD8 FPU FMAs"), Some(1.0));
        assert_eq!(get("EM FMAs"), Some(0.0));
        // Teeth: with SIMD8 alone, SIMD8 is what runs.
        let merged = merge_simd("tgl", vec![exe("SIMD8 fragment", 200, "mov(8) g3<1>F g7")]);
        let c = merged[0]
            .statistics
            .iter()
            .find(|s| s.name == "Cycle Count");
        assert_eq!(c.map(|s| s.value.as_f64()), Some(200.0));
    }

    #[test]
    fn every_known_chip_has_its_generation() {
        for chip in Intel.known_chips() {
            assert!(Generation::of(chip).is_some(), "{chip}");
        }
        assert_eq!(
            Generation::of("tgl").and_then(Generation::threads_per_eu),
            Some(7.0)
        );
        assert_eq!(
            Generation::of("dg2").and_then(Generation::threads_per_eu),
            Some(8.0)
        );
        // Teeth: Xe3's threads are not known, nor is a name that is no chip's.
        assert_eq!(
            Generation::of("ptl").and_then(Generation::threads_per_eu),
            None
        );
        assert!(Generation::of("g57").is_none());
    }

    #[test]
    fn registers_are_the_distinct_ones_named() {
        assert_eq!(
            grf_registers("add(8) g10<1>F g2<8,8,1>F -g10<0,1,0>F"),
            Some(2)
        );
        assert_eq!(grf_registers("nop"), None);
    }
}
