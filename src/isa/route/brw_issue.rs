//! Intel's throughput model: the busy cycles of the EU's back-end units (the FPU and the
//! extended-math unit, EM) that one thread's GEN assembly occupies, per pixel, in FP32 FMAs.
//!
//! The cycles are brw's own: the back-end occupancy term (`db`) of `instruction_desc` in
//! src/intel/compiler/brw_ir_performance.cpp (Mesa 25.0.7, the same table in 22.3.6), which
//! brw sums per unit as `unit_busy` and which Intel's compiler developers fitted to
//! measured timings (the file's comment: "multivariate linear regression of a sample of
//! empirical timings measured using the tm0 register"). Each instruction costs
//! `db_1 + db_sx * sx` cycles on its unit, `sx` its execution size in 32-byte registers
//! (`DIV_ROUND_UP(exec_size * type_size(exec_type), REG_SIZE)`):
//!
//! | instructions | unit | `db_1` | `db_sx` |
//! |---|---|---|---|
//! | mov, add, mul, mad, sel, cmp, logic, shifts, dp*, bfe, csel, nop, sync, ... | FPU | 0 | 2 |
//! | the same with a 64-bit execution type before Gen11 | FPU | 0 | 4 |
//! | pln, lrp | FPU | 0 | 4 |
//! | math inv, rsq, sqrt, exp, log, sin, cos | EM | 0 | 4 |
//! | math pow | EM | 0 | 8 |
//! | math intdiv, intmod (quotient, remainder) | EM | 26 | 0 |
//! | if, else, endif, while, break, cont, halt | none | 0 | 0 |
//!
//! A 32x32-bit integer mul or mad counts as 64-bit ("half the usual ALU throughput", the
//! same file). brw itself turns these into a latency figure (`cycle_count`: the front end
//! stalls on every dependency, so a dependent chain costs its latency); the throughput model
//! keeps only the busy cycles, which other threads cannot hide. Messages (`send`: varyings on
//! Gen12+, render-target writes, loads) go to shared functions outside the EU and are counted
//! apart (`send_count`). A loop's body counts 10 times per nesting level, brw's own
//! `loop_weight` (the loops of the GEN assembly: a `while` whose JIP names a label before it);
//! brw's discard weight (a half after a `halt` on Gen12 below SIMD32) is not applied.
//!
//! One SIMD-W FP32 FMA (`mad`) is `2 * ceil(4 W / 32)` FPU cycles for W pixels, so a figure
//! in cycles over that is FP32 FMAs per pixel ([`fma_cycles`]): the unit of every family's
//! calibration.

/// An Intel chip's graphics architecture: what brw's rates ([`busy`]) and the EU's
/// threads depend on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Generation {
    Gen9,
    Gen11,
    XeLp,
    XeHpg,
    XeLpg,
    Xe2,
    Xe3,
}

/// Intel's GPU Occupancy Calculator, `Threads_Per_EU` of each device
/// (oneapi-src/oneAPI-samples, Tools/GPU-Occupancy-Calculator/index.html,
/// https://github.com/oneapi-src/oneAPI-samples).
pub const INTEL_OCCUPANCY: &str = "Intel GPU Occupancy Calculator, Threads_Per_EU \
(oneapi-src/oneAPI-samples Tools/GPU-Occupancy-Calculator/index.html, \
https://github.com/oneapi-src/oneAPI-samples)";

impl Generation {
    /// The architecture of a chip Intel's route knows ([`super::Vendor::known_chips`] of [`super::intel::Intel`]); `None` for another
    /// name.
    pub fn of(chip: &str) -> Option<Generation> {
        Some(match chip {
            "skl" | "bxt" | "kbl" | "aml" | "cml" | "glk" | "whl" | "cfl" => Generation::Gen9,
            "icl" | "ehl" | "jsl" => Generation::Gen11,
            "tgl" | "rkl" | "dg1" | "sg1" | "adl" | "rpl" => Generation::XeLp,
            "dg2" => Generation::XeHpg,
            "mtl" => Generation::XeLpg,
            "lnl" | "bmg" => Generation::Xe2,
            "ptl" => Generation::Xe3,
            _ => return None,
        })
    }

    /// The hardware threads per EU ([`INTEL_OCCUPANCY`]), each with its own 128 registers, so
    /// a program's registers do not change them: 7 on Gen9, Gen11 and Xe-LP, 8 on Xe-HPG,
    /// Xe-LPG and Xe2; `None` on Xe3, whose register allocation varies per program.
    pub fn threads_per_eu(self) -> Option<f64> {
        match self {
            Generation::Gen9 | Generation::Gen11 | Generation::XeLp => Some(7.0),
            Generation::XeHpg | Generation::XeLpg | Generation::Xe2 => Some(8.0),
            Generation::Xe3 => None,
        }
    }
}

/// The busy cycles of one thread's instructions on the FPU and the EM unit, and the messages.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Busy {
    pub fpu: f64,
    pub em: f64,
    pub sends: u32,
}

/// One SIMD-`width` FP32 FMA's FPU cycles: the unit of the per-pixel figures.
pub fn fma_cycles(width: u32) -> f64 {
    2.0 * f64::from((width * 4).div_ceil(32))
}

/// The bytes of a GEN register type suffix (`F`, `HF`, `DF`, `UD`, ...); `None` for another
/// word.
fn type_bytes(t: &str) -> Option<u32> {
    Some(match t {
        "B" | "UB" => 1,
        "W" | "UW" | "HF" | "BF" => 2,
        "F" | "D" | "UD" | "V" | "UV" | "VF" => 4,
        "DF" | "Q" | "UQ" => 8,
        _ => return None,
    })
}

/// The type of an operand as the disassembler prints it (`g4<8,8,1>F`, `-(abs)g10<0,1,0>F`,
/// `0x3f800000F`, `g12<1>UD`): (whether it is a float type, its bytes). `None` for a word
/// that is no typed operand, and for `null` (no source).
fn operand_type(op: &str) -> Option<(bool, u32)> {
    let op = op.trim_end_matches(',');
    let register = op
        .trim_start_matches(['-', '~'])
        .trim_start_matches("(abs)")
        .trim_start_matches('-');
    if register.starts_with("null") {
        return None;
    }
    let t = &op[op.trim_end_matches(|c: char| c.is_ascii_uppercase()).len()..];
    let bytes = type_bytes(t)?;
    Some((matches!(t, "F" | "HF" | "BF" | "DF" | "VF"), bytes))
}

/// One instruction of a disassembly line: (mnemonic words, execution size, operand words);
/// `None` for a line that is no instruction (a block label, a message descriptor's second
/// line, a comment).
fn instruction(line: &str) -> Option<(Vec<&str>, u32, Vec<&str>)> {
    let line = line.split('{').next()?;
    let mut words = line.split_whitespace().peekable();
    // A predicate: `(+f0.0)`, `(-f1.0.any4h)`.
    if words.peek().is_some_and(|w| w.starts_with('(')) {
        words.next();
    }
    let mut mnemonic = Vec::new();
    for _ in 0..2 {
        let w = words.next()?;
        if let Some((name, rest)) = w.split_once('(') {
            let size: u32 = rest.strip_suffix(')')?.parse().ok()?;
            if name.is_empty() || !name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'.') {
                return None;
            }
            mnemonic.push(name);
            let mut operands = Vec::new();
            let mut comment = false;
            for w in words {
                if w.starts_with("/*") {
                    comment = !w.ends_with("*/");
                    continue;
                }
                if comment {
                    comment = !w.ends_with("*/");
                    continue;
                }
                operands.push(w);
            }
            return Some((mnemonic, size, operands));
        }
        if !w.bytes().all(|b| b.is_ascii_lowercase() || b == b'.') {
            return None;
        }
        mnemonic.push(w);
    }
    None
}

/// The back-end unit and busy cycles brw's table gives one instruction.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cost {
    Fpu(f64),
    Em(f64),
    Send,
    None,
}

fn cost(mnemonic: &[&str], width: u32, operands: &[&str], gen9: bool) -> Cost {
    let opcode = mnemonic[0].split('.').next().unwrap_or("");
    let dest = operands.first().and_then(|o| operand_type(o));
    let sources: Vec<(bool, u32)> = operands
        .iter()
        .skip(1)
        .filter_map(|o| operand_type(o))
        .collect();
    // The execution type: the widest source's (the destination's where there is none).
    let (exec_float, mut exec_bytes) = sources
        .iter()
        .copied()
        .max_by_key(|t| t.1)
        .or(dest)
        .unwrap_or((true, 4));
    // 32x32-bit integer multiplication counts as 64-bit.
    if matches!(opcode, "mul" | "mad")
        && !exec_float
        && exec_bytes == 4
        && sources.first().map(|t| t.1) == sources.get(1).map(|t| t.1)
    {
        exec_bytes = 8;
    }
    let sx = f64::from((width * exec_bytes).div_ceil(32));
    match opcode {
        "send" | "sendc" | "sends" | "sendsc" => Cost::Send,
        "if" | "else" | "endif" | "while" | "break" | "cont" | "halt" | "jmpi" | "call"
        | "calla" | "ret" | "goto" | "join" | "brc" | "brd" | "wait" | "illegal" | "do" => {
            Cost::None
        }
        "math" => {
            let function = mnemonic.get(1).copied().unwrap_or("");
            match function.split('.').next().unwrap_or("") {
                "pow" => Cost::Em(8.0 * sx),
                "intdiv" | "intmod" | "intdivmod" => Cost::Em(26.0),
                _ => Cost::Em(4.0 * sx),
            }
        }
        "pln" | "lrp" => Cost::Fpu(4.0 * sx),
        _ if gen9 && exec_bytes > 4 => Cost::Fpu(4.0 * sx),
        _ => Cost::Fpu(2.0 * sx),
    }
}

/// brw's weight of a loop body per nesting level (`loop_weight` of `calculate_performance`,
/// brw_ir_performance.cpp).
pub const LOOP_WEIGHT: f64 = 10.0;

/// The busy cycles of a GEN assembly (one SIMD width's) on `chip`.
pub fn busy(asm: &str, chip: &str) -> Busy {
    // Before Gen11, 64-bit arithmetic runs at half rate in brw's table.
    let gen9 = Generation::of(chip) == Some(Generation::Gen9);
    let mut costs = Vec::new();
    let mut labels = std::collections::BTreeMap::new();
    let mut loops = Vec::new();
    for line in asm.lines() {
        if let Some(label) = line.trim().strip_suffix(':') {
            if label.starts_with("LABEL") {
                labels.insert(label.to_string(), costs.len());
            }
            continue;
        }
        let Some((mnemonic, width, operands)) = instruction(line) else {
            continue;
        };
        if mnemonic[0] == "while" {
            let target = operands
                .iter()
                .position(|w| *w == "JIP:")
                .and_then(|i| operands.get(i + 1));
            if let Some(&start) = target.and_then(|t| labels.get(*t)) {
                loops.push(start..=costs.len());
            }
        }
        costs.push(cost(&mnemonic, width, &operands, gen9));
    }
    let mut b = Busy::default();
    for (i, c) in costs.into_iter().enumerate() {
        let depth = loops.iter().filter(|l| l.contains(&i)).count();
        let weight = LOOP_WEIGHT.powi(depth as i32);
        match c {
            Cost::Fpu(c) => b.fpu += c * weight,
            Cost::Em(c) => b.em += c * weight,
            Cost::Send => b.sends += 1,
            Cost::None => {}
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_fma_at_the_dispatched_width_is_one_per_pixel() {
        for w in [8, 16, 32] {
            let asm = format!(
                "mad({w})         g12<1>F         g4<8,8,1>F      g2<0,1,0>F      g3<0,1,0>F {{ align1 1H }};"
            );
            let b = busy(&asm, "tgl");
            assert_eq!(b.fpu / fma_cycles(w), 1.0, "SIMD{w}");
            assert_eq!(b.em, 0.0);
        }
    }

    #[test]
    fn math_is_the_em_unit_at_brws_rates() {
        let asm = "\
   START B0 (202 cycles)
math inv(16)    g20<1>F         g18<8,8,1>F     null<8,8,1>F    { align1 1H compacted };
math rsq(16)    g22<1>F         g20<8,8,1>F     null<8,8,1>F    { align1 1H @1 $0 };
math pow(16)    g24<1>F         g22<8,8,1>F     g2<0,1,0>F      { align1 1H };
(+f0.0) sel(16) g5<1>F          g2<8,8,1>F      0x0F            /* 0F */ { align1 1H };
cmp.l.f0.0(16)  null<1>F        g2<8,8,1>F      0x3f800000F  /* 1F */ { align1 1H };
sendc(16)       null<1>UW       g120<0,1,0>F    0x90031000
                            render MsgDesc: RT write SIMD16 LastRT Surface = 0 mlen 8 rlen 0 { align1 1H EOT };
endif(16)       JIP:  LABEL1                                    { align1 1H };
";
        let b = busy(asm, "icl");
        // inv and rsq 4 cycles per register (2 registers each), pow 8.
        assert_eq!(b.em, 4.0 * 2.0 * 2.0 + 8.0 * 2.0);
        // sel and cmp at 2 per register.
        assert_eq!(b.fpu, 2.0 * 2.0 * 2.0);
        assert_eq!(b.sends, 1);
        // In FMAs per pixel: an inverse square root is two FMAs.
        assert_eq!(
            busy(&asm.lines().nth(2).unwrap(), "icl").em / fma_cycles(16),
            2.0
        );
    }

    #[test]
    fn sixty_four_bit_and_integer_multiplication_are_half_rate_where_brw_says() {
        let df = "add(8)          g4<1>DF         g6<4,4,1>DF     g8<4,4,1>DF     { align1 1Q };";
        // 8 x 8 bytes: 2 registers, at 4 cycles each before Gen11, 2 after.
        assert_eq!(busy(df, "skl").fpu, 8.0);
        assert_eq!(busy(df, "tgl").fpu, 4.0);
        let imul = "mul(8)          g4<1>D          g6<8,8,1>D      g8<8,8,1>D      { align1 1Q };";
        assert_eq!(busy(imul, "tgl").fpu, 4.0);
        // Teeth: a 16-bit by 32-bit multiplication is full rate, as is a float one.
        let mixed =
            "mul(8)          g4<1>D          g6<8,8,1>D      g8<16,8,2>W     { align1 1Q };";
        assert_eq!(busy(mixed, "tgl").fpu, 2.0);
        let fmul = "mul(8)          g4<1>F          g6<8,8,1>F      g8<8,8,1>F      { align1 1Q };";
        assert_eq!(busy(fmul, "skl").fpu, 2.0);
        assert_eq!(
            busy(
                "pln(16)  g6<1>F  g2<0,1,0>F  g2<8,8,1>F { align1 1H };",
                "skl"
            )
            .fpu,
            8.0
        );
    }

    #[test]
    fn lines_that_are_no_instruction_cost_nothing() {
        let asm = "   START B0 (50 cycles)\n   END B0 ->B1\n// SIMD16\n\
                   render MsgDesc: RT write SIMD16 LastRT Surface = 0 mlen 8 rlen 0\n\
                   LABEL1:\n";
        assert_eq!(busy(asm, "tgl"), Busy::default());
        assert!(instruction("mad(16) g1<1>F g2<8,8,1>F g3<8,8,1>F g4<8,8,1>F").is_some());
        // Teeth: a well-formed line is read, with its predicate.
        let (m, w, ops) = instruction("(+f0.0) sel.ge(8) g5<1>F g2<8,8,1>F 0x0F /* 0F */").unwrap();
        assert_eq!((m, w, ops.len()), (vec!["sel.ge"], 8, 3));
    }

    #[test]
    fn a_loop_body_counts_ten_times_per_nesting() {
        let asm = "\
mov(8)          g2<1>F          0x0F  /* 0F */                  { align1 1Q };
LABEL1:
add(8)          g2<1>F          g2<8,8,1>F      g3<8,8,1>F      { align1 1Q };
LABEL0:
mul(8)          g4<1>F          g2<8,8,1>F      g3<8,8,1>F      { align1 1Q };
while(8)        JIP:  LABEL0                                    { align1 1Q };
while(8)        JIP:  LABEL1                                    { align1 1Q };
mov(8)          g5<1>F          g4<8,8,1>F                      { align1 1Q };
";
        // mov 2, add 2 x 10, mul 2 x 100, mov 2.
        assert_eq!(busy(asm, "tgl").fpu, 2.0 + 20.0 + 200.0 + 2.0);
        // Teeth: a jump forward (an endif's JIP) is no loop.
        let forward = "endif(8)        JIP:  LABEL0      { align1 1Q };\nLABEL0:\n\
                       add(8)          g2<1>F          g2<8,8,1>F      g3<8,8,1>F      { align1 1Q };";
        assert_eq!(busy(forward, "tgl").fpu, 2.0);
    }
}
