//! A minimal SPIR-V module reader: the instruction stream of a module, enough to check the
//! uniform-block layout against its Rust twin and (later) to count arithmetic opcodes.
use crate::error::{Error, Result};

/// SPIR-V magic number (little-endian word 0).
pub const MAGIC: u32 = 0x0723_0203;
/// Opcodes used here (SPIR-V 1.6 spec, section 3.52).
pub const OP_DECORATE: u16 = 71;
pub const OP_MEMBER_DECORATE: u16 = 72;
/// Decorations (section 3.20).
pub const DECORATION_BLOCK: u32 = 2;
pub const DECORATION_OFFSET: u32 = 35;

/// One instruction: opcode and operand words (without the leading word).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instruction {
    pub opcode: u16,
    pub operands: Vec<u32>,
}

/// Splits a module into instructions. Errors on a bad magic number or a truncated instruction.
pub fn instructions(bytes: &[u8]) -> Result<Vec<Instruction>> {
    if bytes.len() % 4 != 0 || bytes.len() < 20 {
        return Err(Error::Shader(format!(
            "SPIR-V module of {} bytes is not a whole number of words",
            bytes.len()
        )));
    }
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if words[0] != MAGIC {
        return Err(Error::Shader(format!(
            "bad SPIR-V magic number {:#010x}",
            words[0]
        )));
    }
    let mut out = Vec::new();
    let mut i = 5;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        let opcode = (words[i] & 0xffff) as u16;
        if count == 0 || i + count > words.len() {
            return Err(Error::Shader(format!(
                "truncated SPIR-V instruction at word {i}"
            )));
        }
        out.push(Instruction {
            opcode,
            operands: words[i + 1..i + count].to_vec(),
        });
        i += count;
    }
    Ok(out)
}

/// Member offsets of the uniform block by member index: the `Block`-decorated struct whose
/// members carry `Offset` decorations (a vertex shader's `gl_PerVertex` is a Block too, but its
/// members are BuiltIns without offsets). Errors when there is no such struct.
pub fn block_member_offsets(bytes: &[u8]) -> Result<Vec<u32>> {
    let ins = instructions(bytes)?;
    let blocks = ins
        .iter()
        .filter(|i| i.opcode == OP_DECORATE && i.operands.get(1) == Some(&DECORATION_BLOCK))
        .map(|i| i.operands[0]);
    for block in blocks {
        let mut offsets: Vec<(u32, u32)> = ins
            .iter()
            .filter(|i| {
                i.opcode == OP_MEMBER_DECORATE
                    && i.operands.len() >= 4
                    && i.operands[0] == block
                    && i.operands[2] == DECORATION_OFFSET
            })
            .map(|i| (i.operands[1], i.operands[3]))
            .collect();
        if !offsets.is_empty() {
            offsets.sort();
            return Ok(offsets.into_iter().map(|(_, o)| o).collect());
        }
    }
    Err(Error::Shader(
        "no Block-decorated struct with member offsets in the module".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module(body: &[u32]) -> Vec<u8> {
        let mut w = vec![MAGIC, 0x0001_0600, 0, 100, 0];
        w.extend_from_slice(body);
        w.iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    #[test]
    fn reads_block_offsets_in_member_order() {
        // OpDecorate %7 Block; OpMemberDecorate %7 1 Offset 16; OpMemberDecorate %7 0 Offset 0
        // plus a gl_PerVertex-like Block %3 whose member is a BuiltIn (decoration 11), not an offset
        let m = module(&[
            (3 << 16) | 71,
            3,
            2,
            (5 << 16) | 72,
            3,
            0,
            11,
            0,
            (3 << 16) | 71,
            7,
            2,
            (5 << 16) | 72,
            7,
            1,
            35,
            16,
            (5 << 16) | 72,
            7,
            0,
            35,
            0,
        ]);
        assert_eq!(block_member_offsets(&m).unwrap(), vec![0, 16]);
        let no_offsets = module(&[(3 << 16) | 71, 3, 2]);
        assert!(block_member_offsets(&no_offsets).is_err());
    }

    #[test]
    fn rejects_bad_magic_and_truncation() {
        let mut m = module(&[]);
        m[0] = 0;
        assert!(instructions(&m).unwrap_err().to_string().contains("magic"));
        let m = module(&[(9 << 16) | 71, 7]);
        assert!(instructions(&m)
            .unwrap_err()
            .to_string()
            .contains("truncated"));
    }
}
