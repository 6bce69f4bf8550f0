//! Throughput models: what ranks a family's programs when its compiler only counts, and the
//! unit that bounds each program ([`Unit`], after the pipes Arm's offline compiler names).
//!
//! Where the compiler has a cycle model of its own (ACO's inverse throughput, panfrost's
//! per-pipe cycles on Bifrost and Valhall, agx's F/SCIB and IC units, vc4's estimated cycles,
//! v3d's instructions and stalls) the model is that figure; where it prices a thread's latency
//! instead (brw's cycle estimate, ir3's scheduling NOPs and sync stalls) the model keeps the
//! busy cycles alone (Intel's [`super::route::brw_issue`], Adreno's issued instructions); a
//! vendor's [`super::route::Vendor::model`] reads it out of a row's statistics. Where the compiler only counts (nouveau), the model is a
//! weighted issue count: every instruction one issue slot at the FMA rate, each
//! special-function operation ([`SFU_OPS`]) at the architecture's FMA:SFU throughput ratio of
//! a [`WeightTable`] (one per architecture, each citing its source).
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// The unit that bounds a program in its family's model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Unit {
    /// Floating-point and integer arithmetic (FMA, CVT, F/SCIB pipes).
    Arithmetic,
    /// Special functions: reciprocal, reciprocal square root, exp2, log2, sin, cos.
    Sfu,
    /// Memory messages: uniform and storage loads and stores.
    LoadStore,
    /// Varying interpolation.
    Varying,
    /// Texture sampling.
    Texture,
    /// A single-pipe model (one figure of issue cycles): nothing else to name.
    Issue,
}

impl Unit {
    pub fn name(self) -> &'static str {
        match self {
            Unit::Arithmetic => "arithmetic",
            Unit::Sfu => "sfu",
            Unit::LoadStore => "load_store",
            Unit::Varying => "varying",
            Unit::Texture => "texture",
            Unit::Issue => "issue",
        }
    }
}

/// A family's model figure of one row: its value (the ranking statistic) and the bound unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    pub cycles: f64,
    pub bound: Unit,
}

/// The statistic a derived model is written under in a row (the ranking key of the vendors
/// whose figure is not one of their compiler's statistics as it stands).
pub const MODEL_KEY: &str = "model_cycles";
/// The count of special-function operations of a program (the weighted models' input).
pub const SFU_KEY: &str = "sfu_ops";

/// The issue cost of each instruction class on one architecture, relative to an FP32 FMA
/// (1.0): `sfu` is the FMA rate over the special-function rate. Classes without a published
/// rate cost one slot, as an FMA.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeightTable {
    /// The architecture, as its vendor names it ("Turing").
    pub architecture: &'static str,
    /// One reciprocal, reciprocal square root, exp2, log2, sin or cos, in FMA issue slots.
    pub sfu: f64,
    /// 32-bit registers per multiprocessor and the most warps resident on one
    /// ([`CUDA_SPECIFICATIONS`]): the occupancy a program's registers allow
    /// ([`super::occupancy::nvidia_warps`]).
    pub registers_per_sm: f64,
    pub max_warps: f64,
    /// Where `sfu` comes from: document, table, columns, URL.
    pub source: &'static str,
}

/// NVIDIA's table: CUDA C++ Programming Guide, section "Arithmetic Instructions", table
/// "Throughput of Native Arithmetic Instructions (Number of Results per Clock Cycle per
/// Multiprocessor)", rows "32-bit floating-point add, multiply, multiply-add" and "32-bit
/// floating-point reciprocal, reciprocal square root, base-2 logarithm (__log2f), base 2
/// exponential (exp2f), sine (__sinf), cosine (__cosf)",
/// https://docs.nvidia.com/cuda/cuda-c-programming-guide/index.html#arithmetic-instructions
/// (also the CUDA 9.1 guide, p. 85,
/// https://docs.nvidia.com/cuda/archive/9.1/pdf/CUDA_C_Programming_Guide.pdf).
const CUDA_GUIDE: &str = "NVIDIA CUDA C++ Programming Guide, Arithmetic Instructions, table \
\"Throughput of Native Arithmetic Instructions\" (https://docs.nvidia.com/cuda/\
cuda-c-programming-guide/index.html#arithmetic-instructions)";

/// CUDA C++ Programming Guide, "Technical Specifications per Compute Capability", rows
/// "Number of 32-bit registers per multiprocessor" and "Maximum number of resident warps per
/// multiprocessor": Fermi 32 K and 48, Kepler to Volta 64 K and 64, Turing 64 K and 32, Ampere
/// GA10x 64 K and 48.
pub const CUDA_SPECIFICATIONS: &str = "NVIDIA CUDA C++ Programming Guide, Technical \
Specifications per Compute Capability (https://docs.nvidia.com/cuda/cuda-c-programming-guide/\
index.html#features-and-technical-specifications-technical-specifications-per-compute-capability)";

/// Fermi GF100/GF110, compute capability 2.0: 32 FP32 results and 4 SFU results per clock
/// per multiprocessor ([`CUDA_GUIDE`]).
pub const FERMI_CC20: WeightTable = WeightTable {
    architecture: "Fermi (compute capability 2.0)",
    sfu: 32.0 / 4.0,
    registers_per_sm: 32768.0,
    max_warps: 48.0,
    source: CUDA_GUIDE,
};
/// Fermi GF104 and later, compute capability 2.1: 48 FP32, 8 SFU ([`CUDA_GUIDE`]).
pub const FERMI_CC21: WeightTable = WeightTable {
    architecture: "Fermi (compute capability 2.1)",
    sfu: 48.0 / 8.0,
    registers_per_sm: 32768.0,
    max_warps: 48.0,
    source: CUDA_GUIDE,
};
/// Kepler, compute capability 3.x: 192 FP32, 32 SFU ([`CUDA_GUIDE`]).
pub const KEPLER: WeightTable = WeightTable {
    architecture: "Kepler (compute capability 3.x)",
    sfu: 192.0 / 32.0,
    registers_per_sm: 65536.0,
    max_warps: 64.0,
    source: CUDA_GUIDE,
};
/// Maxwell, compute capability 5.x: 128 FP32, 32 SFU ([`CUDA_GUIDE`]).
pub const MAXWELL: WeightTable = WeightTable {
    architecture: "Maxwell (compute capability 5.x)",
    sfu: 128.0 / 32.0,
    registers_per_sm: 65536.0,
    max_warps: 64.0,
    source: CUDA_GUIDE,
};
/// Pascal GP100, compute capability 6.0: 64 FP32, 16 SFU ([`CUDA_GUIDE`]).
pub const PASCAL_CC60: WeightTable = WeightTable {
    architecture: "Pascal (compute capability 6.0)",
    sfu: 64.0 / 16.0,
    registers_per_sm: 65536.0,
    max_warps: 64.0,
    source: CUDA_GUIDE,
};
/// Pascal GP102-GP108, compute capability 6.1: 128 FP32, 32 SFU ([`CUDA_GUIDE`]).
pub const PASCAL_CC61: WeightTable = WeightTable {
    architecture: "Pascal (compute capability 6.1)",
    sfu: 128.0 / 32.0,
    registers_per_sm: 65536.0,
    max_warps: 64.0,
    source: CUDA_GUIDE,
};
/// Volta, compute capability 7.0: 64 FP32, 16 SFU ([`CUDA_GUIDE`]).
pub const VOLTA: WeightTable = WeightTable {
    architecture: "Volta (compute capability 7.0)",
    sfu: 64.0 / 16.0,
    registers_per_sm: 65536.0,
    max_warps: 64.0,
    source: CUDA_GUIDE,
};
/// Turing, compute capability 7.5: 64 FP32, 16 SFU ([`CUDA_GUIDE`]).
pub const TURING: WeightTable = WeightTable {
    architecture: "Turing (compute capability 7.5)",
    sfu: 64.0 / 16.0,
    registers_per_sm: 65536.0,
    max_warps: 32.0,
    source: CUDA_GUIDE,
};
/// Ampere GA10x, compute capability 8.6: 128 FP32, 16 SFU ([`CUDA_GUIDE`]).
pub const AMPERE_CC86: WeightTable = WeightTable {
    architecture: "Ampere (compute capability 8.6)",
    sfu: 128.0 / 16.0,
    registers_per_sm: 65536.0,
    max_warps: 48.0,
    source: CUDA_GUIDE,
};

/// The weights of an NVIDIA chipset (nouveau's `nv<hex>`), by its architecture; `None` for
/// Tesla (nv50 to nvaf), which the sources of this module do not cover.
pub fn nvidia_weights(chip: &str) -> Option<WeightTable> {
    let id = u32::from_str_radix(chip.strip_prefix("nv")?, 16).ok()?;
    Some(match id {
        0xc0 | 0xc8 => FERMI_CC20,
        0xc1..=0xcf | 0xd7 | 0xd9 => FERMI_CC21,
        0xe0..=0xff | 0x106 | 0x108 => KEPLER,
        0x110..=0x12f => MAXWELL,
        0x130 => PASCAL_CC60,
        0x131..=0x13f => PASCAL_CC61,
        0x140 => VOLTA,
        0x160..=0x16f => TURING,
        0x172..=0x177 => AMPERE_CC86,
        _ => return None,
    })
}

/// NIR's special-function ALU operations (what Mesa hands a back-end: the program the
/// compiler schedules, printed by `MESA_GLSL=dump`), each with its SFU operations per
/// component: `fpow` is a log2 and an exp2.
pub const SFU_OPS: [(&str, f64); 8] = [
    ("frsq", 1.0),
    ("frcp", 1.0),
    ("fsqrt", 1.0),
    ("fexp2", 1.0),
    ("flog2", 1.0),
    ("fsin", 1.0),
    ("fcos", 1.0),
    ("fpow", 2.0),
];

/// The special-function operations of each stage of a NIR dump (`shader: MESA_SHADER_<STAGE>`
/// sections), by stage name in lower case ("fragment"), each counted once per component.
/// A definition is read in both of the forms Mesa's `nir_print.c` has printed: `vecN BITS
/// [con|div] ssa_M = op ...` (Mesa 23 and before) and `[con |div ]BITS[xN] %M = op ...` (Mesa
/// 24 on). A stage none of whose lines reads as a definition is left out, so that a print form
/// this reader does not know makes the statistic missing (and the weighted model refused)
/// rather than zero. A stage printed twice keeps its last section.
pub fn sfu_ops_per_stage(dump: &str) -> BTreeMap<String, f64> {
    // (stage, special-function operations, definitions read)
    let mut out = BTreeMap::new();
    let mut current: Option<(String, f64, usize)> = None;
    let mut close = |c: Option<(String, f64, usize)>| {
        if let Some((stage, n, defs)) = c {
            if defs > 0 {
                out.insert(stage, n);
            } else {
                out.remove(&stage);
            }
        }
    };
    for line in dump.lines() {
        if let Some(stage) = line.strip_prefix("shader: MESA_SHADER_") {
            close(current.take());
            current = Some((stage.trim().to_lowercase(), 0.0, 0));
            continue;
        }
        let Some((_, n, defs)) = current.as_mut() else {
            continue;
        };
        let Some((width, op)) = nir_definition(line) else {
            continue;
        };
        *defs += 1;
        if let Some((_, per)) = SFU_OPS.iter().find(|(o, _)| *o == op) {
            *n += per * width;
        }
    }
    close(current);
    out
}

/// The component count and the operation of a NIR definition line, in either print form of
/// [`sfu_ops_per_stage`]; `None` for any other line.
fn nir_definition(line: &str) -> Option<(f64, &str)> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let eq = words.iter().position(|w| *w == "=")?;
    let (dest, op) = (*words.get(eq.checked_sub(1)?)?, *words.get(eq + 1)?);
    let index = dest
        .strip_prefix("ssa_")
        .or_else(|| dest.strip_prefix('%'))?;
    if index.is_empty() || !index.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let mut width = None;
    for w in &words[..eq - 1] {
        let size = if let Some(n) = w.strip_prefix("vec") {
            n.parse::<u32>().ok()
        } else if let Some((bits, n)) = w.split_once('x') {
            bits.parse::<u32>().ok().and(n.parse::<u32>().ok())
        } else if matches!(*w, "con" | "div") {
            continue;
        } else {
            w.parse::<u32>().ok().map(|_| 1)
        };
        // `vecN BITS`: the width is the first size word.
        width = width.or(Some(size?));
    }
    Some((f64::from(width?), op))
}

/// The weighted issue count of a program of `instructions` of which `sfu` are
/// special-function operations: `instructions - sfu + sfu * weights.sfu`, in FMA issue slots.
pub fn weighted_issue(instructions: f64, sfu: f64, weights: &WeightTable) -> f64 {
    instructions - sfu + sfu * weights.sfu
}

/// The bound unit among `pipes` ((unit, cycles)): the largest figure's; ties go to the first.
pub fn bound(pipes: &[(Unit, f64)]) -> Option<Model> {
    let mut best: Option<Model> = None;
    for &(unit, cycles) in pipes {
        if !cycles.is_finite() {
            return None;
        }
        if best.is_none_or(|b| cycles > b.cycles) {
            best = Some(Model {
                cycles,
                bound: unit,
            });
        }
    }
    best
}

/// The figure of `key` in `stats` as a single-pipe model.
pub fn issue(stats: &BTreeMap<String, f64>, key: &str) -> Option<Model> {
    let cycles = *stats.get(key)?;
    cycles.is_finite().then_some(Model {
        cycles,
        bound: Unit::Issue,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nvidia_chips_have_their_architecture_s_weights() {
        assert_eq!(nvidia_weights("nvc0").unwrap().sfu, 8.0);
        assert_eq!(nvidia_weights("nve4").unwrap().sfu, 6.0);
        assert_eq!(nvidia_weights("nv117").unwrap().sfu, 4.0);
        assert_eq!(nvidia_weights("nv134").unwrap().sfu, 4.0);
        assert_eq!(nvidia_weights("nv162").unwrap().sfu, 4.0);
        assert_eq!(nvidia_weights("nv172").unwrap().sfu, 8.0);
        // Teeth: Tesla and a name that is not a chipset have none.
        assert!(nvidia_weights("nv50").is_none());
        assert!(nvidia_weights("g57").is_none());
        for w in [FERMI_CC20, KEPLER, MAXWELL, TURING] {
            assert!(w.source.contains("https://docs.nvidia.com/cuda/"), "{w:?}");
        }
    }

    #[test]
    fn sfu_operations_are_counted_per_stage_and_component() {
        let dump = "shader: MESA_SHADER_VERTEX\n\tvec1 32 ssa_1 = frsq ssa_0\n\
                    shader: MESA_SHADER_FRAGMENT\n\tvec1 32 ssa_4 = fdot3 ssa_3, ssa_3\n\
                    \tvec1 32 ssa_5 = frsq ssa_4\n\tvec3 32 ssa_6 = fmul ssa_3, ssa_5.xxx\n\
                    \t\tvec1 32 ssa_18 = fpow ssa_14, ssa_82.w\n\tvec2 32 ssa_9 = frcp ssa_8\n\
                    (expression float rsq (var_ref x))\n";
        let n = sfu_ops_per_stage(dump);
        assert_eq!(n["vertex"], 1.0);
        // frsq 1, fpow 2, vec2 frcp 2; the GLSL IR line and fmul do not count.
        assert_eq!(n["fragment"], 5.0);
        // Teeth: an op that is not a special function is not counted, nor a line before any
        // section.
        let n = sfu_ops_per_stage("\tvec1 32 ssa_5 = frsq ssa_4\nshader: MESA_SHADER_COMPUTE\n\tvec1 32 ssa_5 = ffma ssa_4, ssa_4, ssa_4\n");
        assert_eq!(n["compute"], 0.0);
        assert_eq!(n.len(), 1);
    }

    #[test]
    fn mesa_24_and_later_print_forms_are_counted_too() {
        // nir_print.c since Mesa 24: "[con |div ]BITS[xN] %M = op", padded.
        let dump = "shader: MESA_SHADER_FRAGMENT\n\
                    \t32x3   %3 = @load_interpolated_input (%2, %1) (base=1)\n\
                    \t32     %4 = fdot3 %3, %3\n\
                    \tcon 32     %5 = frsq %4\n\
                    \tdiv 32x2   %9 = frcp %8\n\
                    \t32     %10 = fpow %6, %7\n\
                    \tstore_output (%11, %0) (base=0)\n";
        // frsq 1, frcp of two components 2, fpow 2.
        assert_eq!(sfu_ops_per_stage(dump)["fragment"], 5.0);
        // The old form with the divergence word after the bit size.
        assert_eq!(
            sfu_ops_per_stage("shader: MESA_SHADER_FRAGMENT\n\tvec1 32 con ssa_5 = frsq ssa_4\n")
                ["fragment"],
            1.0
        );
    }

    #[test]
    fn a_stage_whose_lines_are_not_definitions_is_left_out_not_zero() {
        // A print form the reader does not know: the statistic goes missing, so the weighted
        // model is refused instead of pricing every rsqrt as an FMA.
        let dump = "shader: MESA_SHADER_FRAGMENT\n\tr5 <- frsq r4\n\tr6 <- ffma r5, r5, r5\n";
        assert!(sfu_ops_per_stage(dump).is_empty());
        // Teeth: one readable definition is enough for a count, zero included.
        let dump = "shader: MESA_SHADER_FRAGMENT\n\t32 %6 = ffma %5, %5, %5\n";
        assert_eq!(sfu_ops_per_stage(dump)["fragment"], 0.0);
        assert_eq!(
            nir_definition("\tcon 32x4 %12 = fmul %3, %4"),
            Some((4.0, "fmul"))
        );
        assert_eq!(
            nir_definition("\tvec4 32 ssa_12 = fmul ssa_3, ssa_4"),
            Some((4.0, "fmul"))
        );
        assert_eq!(
            nir_definition("\tdecl_var shader_in INTERP_MODE_SMOOTH vec3 n = 1"),
            None
        );
    }

    #[test]
    fn a_weighted_count_prices_an_sfu_operation_at_its_weight() {
        // 38 instructions, one of them an rsqrt, on Turing: 37 + 4.
        assert_eq!(weighted_issue(38.0, 1.0, &TURING), 41.0);
        // Teeth: the weight matters (Fermi GF100: 37 + 8).
        assert_eq!(weighted_issue(38.0, 1.0, &FERMI_CC20), 45.0);
        assert_eq!(weighted_issue(38.0, 0.0, &FERMI_CC20), 38.0);
    }

    #[test]
    fn the_bound_unit_is_the_largest_pipe() {
        let m = bound(&[
            (Unit::Arithmetic, 1.5),
            (Unit::Sfu, 0.5),
            (Unit::LoadStore, 7.0),
        ])
        .unwrap();
        assert_eq!((m.bound, m.cycles), (Unit::LoadStore, 7.0));
        // Teeth: a non-finite pipe gives no model, nor does none.
        assert!(bound(&[(Unit::Arithmetic, f64::NAN)]).is_none());
        assert!(bound(&[]).is_none());
        assert_eq!(Unit::LoadStore.name(), "load_store");
        assert_eq!(
            serde_json::to_string(&Unit::LoadStore).unwrap(),
            "\"load_store\""
        );
    }
}
