//! A minimal SPIR-V module reader: the instruction stream of a module, enough to check the
//! uniform-block layout against its Rust twin and to count a shader's arithmetic statically
//! ([`count_ops`]). Opcode and GLSL.std.450 numbers are the spec's, quoted next to each constant.
use std::collections::HashMap;

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

/// Opcodes read by [`count_ops`] (SPIR-V 1.6 spec, section 3.52).
const OP_EXT_INST_IMPORT: u16 = 11;
const OP_EXT_INST: u16 = 12;
const OP_TYPE_FLOAT: u16 = 22;
const OP_TYPE_VECTOR: u16 = 23;
const OP_TYPE_MATRIX: u16 = 24;
const OP_FADD: u16 = 129;
const OP_FSUB: u16 = 131;
const OP_FMUL: u16 = 133;
const OP_FDIV: u16 = 136;
const OP_VECTOR_TIMES_SCALAR: u16 = 142;
const OP_MATRIX_TIMES_SCALAR: u16 = 143;
const OP_VECTOR_TIMES_MATRIX: u16 = 144;
const OP_MATRIX_TIMES_VECTOR: u16 = 145;
const OP_MATRIX_TIMES_MATRIX: u16 = 146;
const OP_OUTER_PRODUCT: u16 = 147;
const OP_DOT: u16 = 148;

/// Name of the extended instruction set whose instructions [`count_ops`] weighs.
const GLSL_STD_450: &str = "GLSL.std.450";
/// GLSL.std.450 instruction numbers (GLSL.std.450 spec, section 2 / `GLSL.std.450.h`).
const GLSL_SIN: u32 = 13;
const GLSL_ATAN2: u32 = 25;
const GLSL_POW: u32 = 26;
const GLSL_EXP: u32 = 27;
const GLSL_LOG2: u32 = 30;
const GLSL_SQRT: u32 = 31;
const GLSL_INVERSE_SQRT: u32 = 32;
const GLSL_FMIX: u32 = 46;
const GLSL_FMA: u32 = 50;
const GLSL_LENGTH: u32 = 66;
const GLSL_DISTANCE: u32 = 67;
const GLSL_NORMALIZE: u32 = 69;

/// Scalar arithmetic operations in a module, counted statically (each instruction once, a loop
/// body once) and per component (a vec3 multiply is 3 multiplications).
///
/// Built by [`count_ops`]; see there for what each instruction counts as.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct OpCounts {
    pub div: u32,
    pub sqrt: u32,
    pub inverse_sqrt: u32,
    pub mul: u32,
    pub add: u32,
    pub pow: u32,
    pub other_transcendental: u32,
}

/// The difference of two [`OpCounts`] (field by field, may be negative): the cost of a method
/// above a baseline.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct OpCountsDelta {
    pub div: i64,
    pub sqrt: i64,
    pub inverse_sqrt: i64,
    pub mul: i64,
    pub add: i64,
    pub pow: i64,
    pub other_transcendental: i64,
}

impl OpCounts {
    /// `self - base`, field by field: what this module costs above `base`.
    pub fn minus(&self, base: &OpCounts) -> OpCountsDelta {
        let d = |a: u32, b: u32| i64::from(a) - i64::from(b);
        OpCountsDelta {
            div: d(self.div, base.div),
            sqrt: d(self.sqrt, base.sqrt),
            inverse_sqrt: d(self.inverse_sqrt, base.inverse_sqrt),
            mul: d(self.mul, base.mul),
            add: d(self.add, base.add),
            pow: d(self.pow, base.pow),
            other_transcendental: d(self.other_transcendental, base.other_transcendental),
        }
    }
}

/// Shape of a float scalar (1 x 1), vector (n x 1) or matrix (rows x columns) type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Shape {
    rows: u32,
    cols: u32,
}

impl Shape {
    fn new(rows: u32, cols: u32) -> Self {
        Shape { rows, cols }
    }

    fn components(self) -> u32 {
        self.rows * self.cols
    }
}

/// Counts the scalar arithmetic of a module statically: every instruction once wherever it
/// sits (a loop body once, a function once however often it is called, both sides of a branch),
/// weighted by the component count of its float type. Opcode numbers are from the SPIR-V 1.6
/// spec, section 3.52; extended instructions from the GLSL.std.450 spec.
///
/// Core instructions (n = components of the result type):
/// - `OpFAdd` (129), `OpFSub` (131): n add. `OpFMul` (133): n mul. `OpFDiv` (136): n div.
/// - `OpVectorTimesScalar` (142), `OpMatrixTimesScalar` (143): n mul.
/// - `OpMatrixTimesVector` (145), an r x c matrix times a c-vector: r*c mul + r*(c-1) add;
///   `OpVectorTimesMatrix` (144), an r-vector times an r x c matrix: r*c mul + (r-1)*c add.
/// - `OpMatrixTimesMatrix` (146), (r x k) times (k x c): r*c*k mul + r*c*(k-1) add;
///   `OpOuterProduct` (147): n mul.
/// - `OpDot` (148) on n-vectors (n from the operand, the result is a scalar): n mul + (n-1) add.
///
/// `OpExtInst` (12) only on the set imported as `"GLSL.std.450"` (`OpExtInstImport`, 11);
/// other sets (e.g. `NonSemantic.*` debug info) are ignored:
/// - `Sqrt` (31): n sqrt. `InverseSqrt` (32): n inverse_sqrt. `Pow` (26): n pow.
/// - `Sin`..`Atan2` (13..=25, trigonometric and hyperbolic), `Exp`, `Log`, `Exp2`, `Log2`
///   (27..=30): n other_transcendental.
/// - `Normalize` (69) on an n-vector: n mul + (n-1) add (the dot) + 1 inverse_sqrt + n mul.
/// - `Length` (66) on an n-vector: n mul + (n-1) add + 1 sqrt.
/// - `Distance` (67) on n-vectors: n add (the difference) + n mul + (n-1) add + 1 sqrt.
/// - `FMix` (46): per component 1 mul + 2 add (x + (y - x) * a). `Fma` (50): per component
///   1 mul + 1 add.
///
/// Not counted: `OpFNegate` (a sign flip, usually free as a source modifier), `OpFRem`/`OpFMod`
/// (rare; their cost depends on the driver's lowering), `OpSpecConstantOp` (folded when the
/// pipeline is created), integer arithmetic, conversions, comparisons, and every other
/// GLSL.std.450 instruction (FMin, FMax, FClamp, FAbs, Floor, Round, Fract, Step, SmoothStep,
/// Cross, Reflect, Determinant, ...). All float widths count alike.
///
/// Errors when the module does not parse or an instruction above names a value whose float type
/// is not declared (a malformed module: the count would silently be wrong).
pub fn count_ops(bytes: &[u8]) -> Result<OpCounts> {
    let ins = instructions(bytes)?;
    let mut types: HashMap<u32, Shape> = HashMap::new();
    let mut values: HashMap<u32, Shape> = HashMap::new();
    let mut glsl_set = None;
    for i in &ins {
        let o = &i.operands;
        match i.opcode {
            OP_EXT_INST_IMPORT if o.len() >= 2 && literal_string(&o[1..]) == GLSL_STD_450 => {
                glsl_set = Some(o[0]);
            }
            OP_TYPE_FLOAT if !o.is_empty() => {
                types.insert(o[0], Shape::new(1, 1));
            }
            // Vectors of a float scalar, and matrices of such columns; integer vectors are left
            // out, so their values never enter `values`.
            OP_TYPE_VECTOR if o.len() >= 3 && types.get(&o[1]) == Some(&Shape::new(1, 1)) => {
                types.insert(o[0], Shape::new(o[2], 1));
            }
            OP_TYPE_MATRIX if o.len() >= 3 && types.contains_key(&o[1]) => {
                types.insert(o[0], Shape::new(types[&o[1]].rows, o[2]));
            }
            // The logical layout (spec section 2.4) puts names and decorations before the type
            // declarations, so an instruction whose first operand is an already declared float
            // type has it as its result type and the next word is its result id.
            _ if o.len() >= 2 && types.contains_key(&o[0]) => {
                values.insert(o[1], types[&o[0]]);
            }
            _ => {}
        }
    }
    let shape_of = |map: &HashMap<u32, Shape>, id: u32, what: &str| {
        map.get(&id).copied().ok_or_else(|| {
            Error::Shader(format!(
                "SPIR-V {what} %{id} has no float scalar, vector or matrix type: malformed module"
            ))
        })
    };
    let result = |o: &[u32]| shape_of(&types, o[0], "result type");
    let operand = |o: &[u32], k: usize| shape_of(&values, o[k], "operand");
    let mut c = OpCounts::default();
    for i in &ins {
        let o = &i.operands[..];
        match i.opcode {
            OP_FADD | OP_FSUB if o.len() >= 4 => c.add += result(o)?.components(),
            OP_FMUL | OP_VECTOR_TIMES_SCALAR | OP_MATRIX_TIMES_SCALAR | OP_OUTER_PRODUCT
                if o.len() >= 4 =>
            {
                c.mul += result(o)?.components()
            }
            OP_FDIV if o.len() >= 4 => c.div += result(o)?.components(),
            OP_MATRIX_TIMES_VECTOR if o.len() >= 4 => {
                let m = operand(o, 2)?;
                c.mul += m.rows * m.cols;
                c.add += m.rows * m.cols.saturating_sub(1);
            }
            OP_VECTOR_TIMES_MATRIX if o.len() >= 4 => {
                let m = operand(o, 3)?;
                c.mul += m.rows * m.cols;
                c.add += m.rows.saturating_sub(1) * m.cols;
            }
            OP_MATRIX_TIMES_MATRIX if o.len() >= 4 => {
                let (out, k) = (result(o)?, operand(o, 2)?.cols);
                c.mul += out.components() * k;
                c.add += out.components() * k.saturating_sub(1);
            }
            OP_DOT if o.len() >= 4 => dot(&mut c, operand(o, 2)?.components()),
            OP_EXT_INST if o.len() >= 4 && Some(o[2]) == glsl_set => match o[3] {
                GLSL_SQRT => c.sqrt += result(o)?.components(),
                GLSL_INVERSE_SQRT => c.inverse_sqrt += result(o)?.components(),
                GLSL_POW => c.pow += result(o)?.components(),
                GLSL_SIN..=GLSL_ATAN2 | GLSL_EXP..=GLSL_LOG2 => {
                    c.other_transcendental += result(o)?.components()
                }
                GLSL_NORMALIZE => {
                    let n = result(o)?.components();
                    dot(&mut c, n);
                    c.inverse_sqrt += 1;
                    c.mul += n;
                }
                GLSL_LENGTH if o.len() >= 5 => {
                    dot(&mut c, operand(o, 4)?.components());
                    c.sqrt += 1;
                }
                GLSL_DISTANCE if o.len() >= 5 => {
                    let n = operand(o, 4)?.components();
                    c.add += n;
                    dot(&mut c, n);
                    c.sqrt += 1;
                }
                GLSL_FMIX => {
                    let n = result(o)?.components();
                    c.mul += n;
                    c.add += 2 * n;
                }
                GLSL_FMA => {
                    let n = result(o)?.components();
                    c.mul += n;
                    c.add += n;
                }
                _ => {}
            },
            _ => {}
        }
    }
    Ok(c)
}

/// Adds a dot product of two n-vectors: n mul + (n-1) add.
fn dot(c: &mut OpCounts, n: u32) {
    c.mul += n;
    c.add += n.saturating_sub(1);
}

/// A SPIR-V literal string (spec section 2.2.1): UTF-8 bytes in little-endian words, ended by a
/// NUL inside the last word.
fn literal_string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn module(body: &[u32]) -> Vec<u8> {
        let mut w = vec![MAGIC, 0x0001_0600, 0, 100, 0];
        w.extend_from_slice(body);
        w.iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    /// One instruction: word count and opcode, then the operands.
    fn op(opcode: u16, operands: &[u32]) -> Vec<u32> {
        let mut w = vec![((operands.len() as u32 + 1) << 16) | u32::from(opcode)];
        w.extend_from_slice(operands);
        w
    }

    /// A literal string as NUL-terminated, NUL-padded words.
    fn string(s: &str) -> Vec<u32> {
        let mut b = s.as_bytes().to_vec();
        b.resize(s.len() / 4 * 4 + 4, 0);
        b.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    // Ids of the prelude shared by the counting tests.
    const GLSL: u32 = 1;
    const FLOAT: u32 = 2;
    const VEC3: u32 = 3;
    const VEC4: u32 = 4;
    const MAT4: u32 = 5;
    /// Four columns of vec3: 3 rows x 4 columns (GLSL `mat4x3`).
    const MAT3X4: u32 = 6;
    const OTHER_SET: u32 = 7;
    const F: u32 = 10;
    const V3: u32 = 11;
    const V4: u32 = 12;
    const M4: u32 = 13;
    const M3X4: u32 = 14;
    const OP_UNDEF: u16 = 1;

    /// Counts `body` after a prelude of imports, types and one undefined value of each type.
    fn count(body: &[Vec<u32>]) -> Result<OpCounts> {
        let mut w = op(
            OP_EXT_INST_IMPORT,
            &[&[GLSL][..], &string("GLSL.std.450")].concat(),
        );
        w.extend(op(
            OP_EXT_INST_IMPORT,
            &[&[OTHER_SET][..], &string("NonSemantic.Other")].concat(),
        ));
        w.extend(op(OP_TYPE_FLOAT, &[FLOAT, 32]));
        w.extend(op(OP_TYPE_VECTOR, &[VEC3, FLOAT, 3]));
        w.extend(op(OP_TYPE_VECTOR, &[VEC4, FLOAT, 4]));
        w.extend(op(OP_TYPE_MATRIX, &[MAT4, VEC4, 4]));
        w.extend(op(OP_TYPE_MATRIX, &[MAT3X4, VEC3, 4]));
        for (ty, id) in [
            (FLOAT, F),
            (VEC3, V3),
            (VEC4, V4),
            (MAT4, M4),
            (MAT3X4, M3X4),
        ] {
            w.extend(op(OP_UNDEF, &[ty, id]));
        }
        w.extend(body.iter().flatten());
        count_ops(&module(&w))
    }

    /// A GLSL.std.450 (or other set's) instruction `inst` with result `ty` on `args`.
    fn ext(set: u32, ty: u32, inst: u32, args: &[u32]) -> Vec<u32> {
        op(OP_EXT_INST, &[&[ty, 100, set, inst][..], args].concat())
    }

    fn only(f: impl FnOnce(&mut OpCounts)) -> OpCounts {
        let mut c = OpCounts::default();
        f(&mut c);
        c
    }

    #[test]
    fn core_arithmetic_is_weighted_by_result_components() {
        let c = |body: Vec<u32>| count(&[body]).unwrap();
        assert_eq!(c(op(OP_FMUL, &[VEC3, 100, V3, V3])), only(|c| c.mul = 3));
        assert_eq!(c(op(OP_FADD, &[VEC4, 100, V4, V4])), only(|c| c.add = 4));
        assert_eq!(c(op(OP_FSUB, &[FLOAT, 100, F, F])), only(|c| c.add = 1));
        assert_eq!(c(op(OP_FDIV, &[FLOAT, 100, F, F])), only(|c| c.div = 1));
        assert_eq!(c(op(OP_FDIV, &[VEC3, 100, V3, V3])), only(|c| c.div = 3));
        let vts = op(OP_VECTOR_TIMES_SCALAR, &[VEC3, 100, V3, F]);
        assert_eq!(c(vts), only(|c| c.mul = 3));
        let mts = op(OP_MATRIX_TIMES_SCALAR, &[MAT4, 100, M4, F]);
        assert_eq!(c(mts), only(|c| c.mul = 16));
    }

    #[test]
    fn dot_is_weighted_by_operand_components() {
        let c = count(&[op(OP_DOT, &[FLOAT, 100, V3, V3])]).unwrap();
        assert_eq!(c, only(|c| (c.mul, c.add) = (3, 2)));
    }

    #[test]
    fn matrix_products_count_rows_and_columns() {
        let c = |body: Vec<u32>| count(&[body]).unwrap();
        // mat4 * vec4: 4 rows of a 4-term dot product.
        let mv = op(OP_MATRIX_TIMES_VECTOR, &[VEC4, 100, M4, V4]);
        assert_eq!(c(mv), only(|c| (c.mul, c.add) = (16, 12)));
        // (3 rows x 4 cols) * vec4 -> vec3: 3 dots of 4 terms; swapping rows and cols gives 12 add.
        let mv = op(OP_MATRIX_TIMES_VECTOR, &[VEC3, 100, M3X4, V4]);
        assert_eq!(c(mv), only(|c| (c.mul, c.add) = (12, 9)));
        // vec3 * (3 rows x 4 cols) -> vec4: 4 dots of 3 terms.
        let vm = op(OP_VECTOR_TIMES_MATRIX, &[VEC4, 100, V3, M3X4]);
        assert_eq!(c(vm), only(|c| (c.mul, c.add) = (12, 8)));
        // (3 x 4) * (4 x 4) -> 3 x 4: 12 dots of 4 terms.
        let mm = op(OP_MATRIX_TIMES_MATRIX, &[MAT3X4, 100, M3X4, M4]);
        assert_eq!(c(mm), only(|c| (c.mul, c.add) = (48, 36)));
        let outer = op(OP_OUTER_PRODUCT, &[MAT3X4, 100, V3, V4]);
        assert_eq!(c(outer), only(|c| c.mul = 12));
    }

    #[test]
    fn glsl_std_450_instructions_have_their_documented_cost() {
        let c = |inst: u32, ty: u32, args: &[u32]| count(&[ext(GLSL, ty, inst, args)]).unwrap();
        let normalize = c(GLSL_NORMALIZE, VEC3, &[V3]);
        assert_eq!(
            normalize,
            only(|c| (c.mul, c.add, c.inverse_sqrt) = (6, 2, 1))
        );
        let length = c(GLSL_LENGTH, FLOAT, &[V3]);
        assert_eq!(length, only(|c| (c.mul, c.add, c.sqrt) = (3, 2, 1)));
        let distance = c(GLSL_DISTANCE, FLOAT, &[V4, V4]);
        assert_eq!(distance, only(|c| (c.mul, c.add, c.sqrt) = (4, 4 + 3, 1)));
        let mix = c(GLSL_FMIX, VEC3, &[V3, V3, V3]);
        assert_eq!(mix, only(|c| (c.mul, c.add) = (3, 6)));
        let fma = c(GLSL_FMA, VEC4, &[V4, V4, V4]);
        assert_eq!(fma, only(|c| (c.mul, c.add) = (4, 4)));
        assert_eq!(c(GLSL_SQRT, VEC3, &[V3]), only(|c| c.sqrt = 3));
        assert_eq!(
            c(GLSL_INVERSE_SQRT, FLOAT, &[F]),
            only(|c| c.inverse_sqrt = 1)
        );
        assert_eq!(c(GLSL_POW, VEC3, &[V3, V3]), only(|c| c.pow = 3));
        // Sin 13, Atan2 25 (the ends of the trigonometric range), Exp 27, Exp2 29, Log2 30.
        for (inst, ty, arg, n) in [
            (13, FLOAT, F, 1),
            (25, VEC3, V3, 3),
            (27, FLOAT, F, 1),
            (29, VEC4, V4, 4),
            (30, VEC3, V3, 3),
        ] {
            let got = c(inst, ty, &[arg, arg]);
            assert_eq!(
                got,
                only(|c| c.other_transcendental = n),
                "GLSL.std.450 {inst}"
            );
        }
        // Documented as free: Floor 8, Fract 10, FMin 37, FMax 40, FClamp 43, Cross 68.
        for inst in [8, 10, 37, 40, 43, 68] {
            assert_eq!(c(inst, VEC3, &[V3, V3, V3]), OpCounts::default(), "{inst}");
        }
        // OpFNegate 127 and OpFMod 141 are not counted either.
        let free = count(&[op(127, &[VEC3, 100, V3]), op(141, &[VEC3, 101, V3, V3])]);
        assert_eq!(free.unwrap(), OpCounts::default());
    }

    #[test]
    fn ext_inst_of_another_set_is_ignored() {
        let other = count(&[ext(OTHER_SET, VEC3, GLSL_NORMALIZE, &[V3])]).unwrap();
        assert_eq!(other, OpCounts::default());
        // The same instruction on the GLSL.std.450 set does count.
        let glsl = count(&[ext(GLSL, VEC3, GLSL_NORMALIZE, &[V3])]).unwrap();
        assert_ne!(glsl, OpCounts::default());
    }

    #[test]
    fn instructions_add_up_and_untyped_operands_are_errors() {
        let body = [
            op(OP_FMUL, &[VEC3, 100, V3, V3]),
            op(OP_DOT, &[FLOAT, 101, V3, V3]),
            op(OP_FDIV, &[FLOAT, 102, F, F]),
        ];
        let c = count(&body).unwrap();
        assert_eq!(c, only(|c| (c.mul, c.add, c.div) = (6, 2, 1)));
        let err = count(&[op(OP_DOT, &[FLOAT, 100, 99, V3])]).unwrap_err();
        assert!(err.to_string().contains("%99"), "{err}");
    }

    #[test]
    fn minus_subtracts_field_by_field() {
        let a = OpCounts {
            mul: 5,
            add: 2,
            inverse_sqrt: 1,
            ..Default::default()
        };
        let b = OpCounts {
            mul: 2,
            add: 4,
            div: 1,
            ..Default::default()
        };
        let d = a.minus(&b);
        let want = OpCountsDelta {
            mul: 3,
            add: -2,
            inverse_sqrt: 1,
            div: -1,
            ..Default::default()
        };
        assert_eq!(d, want);
        assert_eq!(a.minus(&a), OpCountsDelta::default());
    }

    /// Counts a fragment shader that writes `vec4(expr, 1.0)` for a vec3 input `v`, compiled by
    /// shaderc with the options of src/gpu/shaders.rs (Vulkan 1.3, optimised for performance).
    /// Returns the module too, to check which instructions the compiler kept.
    fn compiled(expr: &str) -> (OpCounts, Vec<Instruction>) {
        let src = format!(
            "#version 450\nlayout(location = 0) in vec3 v;\nlayout(location = 0) out vec4 o;\n\
             void main() {{ o = vec4({expr}, 1.0); }}\n"
        );
        let compiler = shaderc::Compiler::new().expect("shaderc compiler");
        let mut opts = shaderc::CompileOptions::new().expect("shaderc options");
        opts.set_target_env(
            shaderc::TargetEnv::Vulkan,
            shaderc::EnvVersion::Vulkan1_3 as u32,
        );
        opts.set_optimization_level(shaderc::OptimizationLevel::Performance);
        let spv = compiler
            .compile_into_spirv(
                &src,
                shaderc::ShaderKind::Fragment,
                "t.frag",
                "main",
                Some(&opts),
            )
            .unwrap_or_else(|e| panic!("{expr}: {e}"));
        let bytes = spv.as_binary_u8();
        (count_ops(bytes).unwrap(), instructions(bytes).unwrap())
    }

    fn has_glsl_inst(ins: &[Instruction], inst: u32) -> bool {
        ins.iter()
            .any(|i| i.opcode == OP_EXT_INST && i.operands.get(3) == Some(&inst))
    }

    #[test]
    fn compiled_glsl_counts_the_operations_its_source_spells_out() {
        // Sources whose arithmetic is known by reading them; the compiler, not this file,
        // writes the SPIR-V.
        assert_eq!(compiled("v").0, OpCounts::default());
        assert_eq!(compiled("v * v").0, only(|c| c.mul = 3));
        assert_eq!(compiled("v + v.x").0, only(|c| c.add = 3));
        // The shading survey's normalisation (docs/formulas.md#exact-phong): dot (3 mul, 2 add),
        // 1 sqrt, 3 divisions.
        let s004 = compiled("v / sqrt(dot(v, v))").0;
        assert_eq!(s004, only(|c| (c.div, c.mul, c.add, c.sqrt) = (3, 3, 2, 1)));
        // The inverse-square-root form: dot, 1 inversesqrt, 3 multiplications.
        let rsqrt = compiled("v * inversesqrt(dot(v, v))").0;
        assert_eq!(rsqrt, only(|c| (c.mul, c.add, c.inverse_sqrt) = (6, 2, 1)));
    }

    #[test]
    fn normalize_and_length_cost_what_their_expansions_cost() {
        // The counter prices GLSL.std.450 Normalize and Length by their definitions (the
        // counter's price, not a driver's compiled count); the compiler keeps them as single
        // instructions. Each price is checked against the figure read off the definition, so a
        // wrong price fails even where the counter's dot would be wrong the same way on both
        // sides of a comparison with the written-out expansion (which follows).
        let (normalize, ins) = compiled("normalize(v)");
        assert!(
            has_glsl_inst(&ins, GLSL_NORMALIZE),
            "Normalize was expanded"
        );
        // vec3: the dot (3 mul, 2 add), 1 inversesqrt, 3 mul
        assert_eq!(
            normalize,
            only(|c| (c.mul, c.add, c.inverse_sqrt) = (6, 2, 1))
        );
        assert_eq!(normalize, compiled("v * inversesqrt(dot(v, v))").0);
        let (length, ins) = compiled("v * length(v)");
        assert!(has_glsl_inst(&ins, GLSL_LENGTH), "Length was expanded");
        // the dot (3 mul, 2 add), 1 sqrt, and v * scalar (3 mul)
        assert_eq!(length, only(|c| (c.mul, c.add, c.sqrt) = (6, 2, 1)));
        assert_eq!(length, compiled("v * sqrt(dot(v, v))").0);
    }

    #[test]
    fn exact_phong_costs_one_normalize_over_unnormalized() {
        let read = |name: &str| {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("spirv")
                .join(name);
            let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            count_ops(&bytes).unwrap()
        };
        let exact = read("phong_exact.screen_linear.frag.spv");
        let unnormalized = read("phong_unnormalized.screen_linear.frag.spv");
        let d = exact.minus(&unnormalized);
        println!("phong_exact:        {exact:?}");
        println!("phong_unnormalized: {unnormalized:?}");
        println!("difference:         {d:?}");
        // The two shaders differ by `normalize(vNormal)` (glsl/methods/phong_exact.glsl): the
        // difference must be what one compiled vec3 normalize costs over none.
        let one = compiled("normalize(v)").0.minus(&compiled("v").0);
        assert_eq!(d, one);
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
