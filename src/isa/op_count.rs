//! Judging a speed claim on the compiled code. The op-count claim ("exact normalisation costs
//! 3 divisions + 3 multiplications + 2 additions + 1 square root") is checked per family on
//! the real instructions: what phong_exact's fragment shader has that phong_unnormalized's
//! (the same shader without the normalisation) has not, counted per operation class in the
//! disassembly, and what it adds to ACO's inverse throughput. [`super::report`] judges it on
//! every family it compiled; bench's speed claims (src/bench/speed_claims.rs) read the verdicts.
use crate::isa::request::RowKind;
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::table::{asm_dir, find_row, Row};
use crate::method::Verdict;

/// The claim's operations: (class, count), 9 in all.
pub const CLAIMED: [(&str, u32); 4] = [
    ("division", 3),
    ("multiplication", 3),
    ("addition", 2),
    ("square_root", 1),
];

/// The class of a GCN/RDNA vector ALU mnemonic, for the classes of [`CLAIMED`] plus
/// `fused_multiply_add` (one instruction doing a multiplication and an addition).
pub fn class(mnemonic: &str) -> Option<&'static str> {
    let m = mnemonic;
    if !m.starts_with("v_") || !(m.contains("_f32") || m.contains("_f16") || m.contains("_f64")) {
        return None;
    }
    let op = &m[2..];
    if op.starts_with("rcp") || op.starts_with("div") {
        Some("division")
    } else if op.starts_with("sqrt") || op.starts_with("rsq") {
        Some("square_root")
    } else if op.starts_with("fma") || op.starts_with("mac") || op.starts_with("mad") {
        Some("fused_multiply_add")
    } else if op.starts_with("mul") {
        Some("multiplication")
    } else if op.starts_with("add") || op.starts_with("sub") {
        Some("addition")
    } else {
        None
    }
}

/// Counts of each class in a disassembly (one instruction per line, mnemonic first).
pub fn class_counts(asm: &str) -> BTreeMap<String, i64> {
    let mut out = BTreeMap::new();
    for line in asm.lines() {
        let Some(mnemonic) = line.split_whitespace().next() else {
            continue;
        };
        if let Some(c) = class(mnemonic) {
            *out.entry(c.to_string()).or_insert(0) += 1;
        }
    }
    out
}

/// The op-count claim judged on one family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OpCountVerdict {
    pub family: String,
    pub claimed_operations: u32,
    /// Vector ALU instructions of phong_exact's fragment shader minus phong_unnormalized's.
    pub extra_instructions: f64,
    /// Per class (division, multiplication, fused_multiply_add, addition, square_root), the
    /// instructions phong_exact has beyond phong_unnormalized.
    pub extra_by_class: BTreeMap<String, i64>,
    /// ACO's inverse throughput of phong_exact's fragment shader over phong_unnormalized's.
    pub inverse_throughput_ratio: f64,
    pub verdict: OpCount,
}

/// What the compiled instructions say of the op-count claim, written as its words ("holds",
/// "overstated", "other mix") in isa.json and bench.json.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum OpCount {
    /// At least as many instructions as operations claimed, every claimed class present.
    #[serde(rename = "holds")]
    Holds,
    /// Fewer instructions than operations claimed.
    #[serde(rename = "overstated")]
    Overstated,
    /// As many, in other classes.
    #[serde(rename = "other mix")]
    OtherMix,
}

impl OpCount {
    /// The words, as in the JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            OpCount::Holds => "holds",
            OpCount::Overstated => "overstated",
            OpCount::OtherMix => "other mix",
        }
    }

    /// As a claims verdict: the claim's 9 operations of its classes are there (agrees), fewer
    /// (disagrees: overstated), or as many of other classes (partly).
    pub fn verdict(self) -> Verdict {
        match self {
            OpCount::Holds => Verdict::Agrees,
            OpCount::Overstated => Verdict::Disagrees,
            OpCount::OtherMix => Verdict::Partly,
        }
    }
}

impl std::fmt::Display for OpCount {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The op-count claim on each of `families` (the compiled ones, keys of `rows`), from their
/// rows and `disassembly` ((path, text) of each); families without both shaders' disassembly
/// are left out.
pub fn op_count(
    rows: &[Row],
    disassembly: &[(String, String)],
    families: &[&str],
) -> Vec<OpCountVerdict> {
    let asm = |f: &str, m: &str| {
        let path = format!("asm/{}/{m}.fragment.s", asm_dir(f));
        disassembly
            .iter()
            .find(|(p, _)| *p == path)
            .map(|(_, t)| t.as_str())
    };
    let claimed: u32 = CLAIMED.iter().map(|(_, n)| n).sum();
    let unnormalized = crate::method::phong_unnormalized().name;
    let mut out = Vec::new();
    for &f in families {
        let (Some(exact), Some(unnorm)) =
            (asm(f, crate::method::PHONG_EXACT), asm(f, unnormalized))
        else {
            continue;
        };
        let it = |m| {
            find_row(rows, f, m, "fragment", RowKind::Draw)
                .and_then(|r| r.statistics.get("inverse_throughput").copied())
        };
        let (Some(a), Some(b)) = (it(crate::method::PHONG_EXACT), it(unnormalized)) else {
            continue;
        };
        let (ce, cu) = (class_counts(exact), class_counts(unnorm));
        let mut extra = BTreeMap::new();
        for k in ce.keys().chain(cu.keys()) {
            let d = ce.get(k).copied().unwrap_or(0) - cu.get(k).copied().unwrap_or(0);
            extra.insert(k.clone(), d);
        }
        let total: i64 = extra.values().sum();
        let verdict = if total < i64::from(claimed) {
            OpCount::Overstated
        } else if CLAIMED
            .iter()
            .all(|(c, _)| extra.get(*c).copied().unwrap_or(0) > 0)
        {
            OpCount::Holds
        } else {
            OpCount::OtherMix
        };
        out.push(OpCountVerdict {
            family: f.to_string(),
            claimed_operations: claimed,
            extra_instructions: total as f64,
            extra_by_class: extra,
            inverse_throughput_ratio: a / b,
            verdict,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_of_mnemonics() {
        assert_eq!(class("v_rsq_f32_e32"), Some("square_root"));
        assert_eq!(class("v_sqrt_f32"), Some("square_root"));
        assert_eq!(class("v_rcp_f32_e32"), Some("division"));
        assert_eq!(class("v_div_scale_f32"), Some("division"));
        assert_eq!(class("v_fmac_f32_e32"), Some("fused_multiply_add"));
        assert_eq!(class("v_mac_f32_e32"), Some("fused_multiply_add"));
        assert_eq!(class("v_mul_f32_e32"), Some("multiplication"));
        assert_eq!(class("v_sub_f32_e32"), Some("addition"));
        // Integer and scalar instructions are not the formula's arithmetic.
        assert_eq!(class("v_add_u32_e32"), None);
        assert_eq!(class("s_mul_i32"), None);
        assert_eq!(class("v_mov_b32_e32"), None);
    }

    #[test]
    fn counts_by_class() {
        let asm =
            "\tv_mul_f32_e32 v1, v2, v3\n\tv_rsq_f32_e32 v4, v1\n\tv_mul_f32_e32 v5, v4, v1\n\
                   BB0:\n\ts_endpgm\n\tv_add_f32_e32 v1, v1, v2 ; comment\n";
        let c = class_counts(asm);
        assert_eq!(c["multiplication"], 2);
        assert_eq!(c["square_root"], 1);
        assert_eq!(c["addition"], 1);
        assert!(!c.contains_key("division"));
    }
}
