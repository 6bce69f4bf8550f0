//! The calibration's micro-kernels ([`Kernel`]: dependent chains of one operation, as
//! colour-only methods of glsl/methods' vocabulary) and the cost ratios to one FMA read out of
//! them ([`Ratio`]); `shadelab isa --calibrate` ([`super::calibrate`]) compiles them, and a
//! route names the ratios its compiler fuses ([`super::route::Vendor::fused_steps`]).
use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// A micro-kernel: one operation repeated in a dependent chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kernel {
    /// `x = x * y + z`: the reference.
    Fma,
    /// `x = inversesqrt(x)`.
    Rsqrt,
    /// `x = 1.0 / x + y`: a reciprocal and an addition (a chain of reciprocals alone folds,
    /// 1/(1/x) = x, in NIR's inexact algebra).
    Rcp,
    /// `v = vec3(dot(v, n), dot(v, n.yzx), dot(v, n.zxy))`: three dot products of the whole
    /// running vector (a dot with one running component would leave two products invariant,
    /// hoisted out of the chain).
    Dot,
    /// `v = normalize(v)` on a vec3.
    Normalize,
}

/// Every kernel, the reference first.
pub const KERNELS: [Kernel; 5] = [
    Kernel::Fma,
    Kernel::Rsqrt,
    Kernel::Rcp,
    Kernel::Dot,
    Kernel::Normalize,
];

impl Kernel {
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Fma => "fma",
            Kernel::Rsqrt => "rsqrt",
            Kernel::Rcp => "rcp",
            Kernel::Dot => "dot",
            Kernel::Normalize => "normalize",
        }
    }

    /// One step of the chain, in float32 (plain `float`: the kernels have no float16
    /// programs, which halves what each child compiles).
    pub fn step(self) -> &'static str {
        match self {
            Kernel::Fma => "x = x * y + z;",
            Kernel::Rsqrt => "x = inversesqrt(x);",
            Kernel::Rcp => "x = 1.0 / x + y;",
            Kernel::Dot => "v = vec3(dot(v, n), dot(v, n.yzx), dot(v, n.zxy));",
            Kernel::Normalize => "v = normalize(v);",
        }
    }

    /// The method id of the kernel at chain length `n`.
    pub fn method(self, n: u32) -> String {
        format!("calibration_{}_{n}", self.name())
    }

    /// The method file of the kernel at chain length `n` (a colour-only method of
    /// docs/your-method.md).
    pub fn glsl(self, n: u32) -> String {
        let steps: String = (0..n).map(|_| format!("    {}\n", self.step())).collect();
        let ret = match self {
            Kernel::Normalize | Kernel::Dot => "v",
            _ => "vec3(x, y, z)",
        };
        format!(
            "// isa --calibrate: {n} dependent steps of `{}`.\n\
             // shadelab-inputs: interpolated_normal\n\
             #define METHOD_COLOR\n\
             real3 methodColor() {{\n\
             \x20   vec3 n = vec3(vNormal);\n\
             \x20   vec3 v = n;\n\
             \x20   float x = n.x;\n\
             \x20   float y = n.y;\n\
             \x20   float z = n.z;\n\
             {steps}\
             \x20   return {ret};\n\
             }}\n",
            self.step()
        )
    }
}

/// A cost ratio to one FMA.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Ratio {
    Rsqrt,
    Rcp,
    Dot,
    Normalize,
}

pub const RATIOS: [Ratio; 4] = [Ratio::Rsqrt, Ratio::Rcp, Ratio::Dot, Ratio::Normalize];

impl Ratio {
    /// The kernel whose step gives the ratio.
    pub fn kernel(self) -> Kernel {
        match self {
            Ratio::Rsqrt => Kernel::Rsqrt,
            Ratio::Rcp => Kernel::Rcp,
            Ratio::Dot => Kernel::Dot,
            Ratio::Normalize => Kernel::Normalize,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Ratio::Rsqrt => "rsqrt",
            Ratio::Rcp => "rcp",
            Ratio::Dot => "dot",
            Ratio::Normalize => "normalize",
        }
    }

    /// The ratio out of each kernel's cost of one step (`step`): the kernel's step over the
    /// FMA's, per operation (the dot kernel's step is three dot products); the reciprocal's
    /// step carries an addition, priced as one FMA (every architecture here adds and
    /// multiply-adds at one rate) and taken off. `None` when a figure is missing, the FMA step
    /// costs nothing in the model, or the result is not finite.
    pub fn of(self, step: &BTreeMap<Kernel, f64>) -> Option<f64> {
        let fma = *step.get(&Kernel::Fma)?;
        let (per_step, extra) = match self {
            Ratio::Rsqrt | Ratio::Normalize => (1.0, 0.0),
            Ratio::Rcp => (1.0, 1.0),
            Ratio::Dot => (3.0, 0.0),
        };
        let r = step.get(&self.kernel())? / fma / per_step - extra;
        (fma > 0.0 && r.is_finite()).then_some(r)
    }
}
