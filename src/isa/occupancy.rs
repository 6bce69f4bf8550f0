//! Occupancy beside cost: the registers a program holds and the waves (threads, warps) its
//! family can keep resident with them, the latency-hiding a throughput model assumes. Written
//! into a draw row's statistics as [`REGISTERS_KEY`] and [`WAVES_KEY`] by each vendor's
//! [`super::route::Vendor::occupancy`], so that isa.json's `ratio_to_phong_exact` says
//! whether a method keeps fewer waves resident than phong_exact ([`fewer_waves`]).
//!
//! Where the compiler states the waves its registers allow (RADV's `subgroups_per_simd`,
//! Turnip's `max_waves_per_core`, agx's `threads`, vc4's and v3d's `threads`), that figure is
//! used as it stands. NVIDIA's warps come from the CUDA guide's register file and resident
//! warp limits ([`nvidia_warps`]); Intel's EU threads are fixed by the hardware, each with its
//! own register file, so a program's registers do not change them ([`intel_threads`]).
use std::collections::BTreeMap;

/// The statistic of the registers a program holds, in its compiler's unit.
pub const REGISTERS_KEY: &str = "occupancy_registers";
/// The statistic of the waves (threads, warps) resident per SIMD, EU, core or SM.
pub const WAVES_KEY: &str = "occupancy_waves";

/// A program's registers and the waves they allow; `waves` is absent where no published
/// register file size gives them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Occupancy {
    pub registers: f64,
    pub waves: Option<f64>,
}

impl Occupancy {
    /// Writes the figures into a row's statistics.
    pub fn write(self, stats: &mut BTreeMap<String, f64>) {
        stats.insert(REGISTERS_KEY.into(), self.registers);
        if let Some(w) = self.waves {
            stats.insert(WAVES_KEY.into(), w);
        }
    }
}

/// The occupancy stated by the compiler: registers and, where it states them, waves from its
/// statistics.
pub fn stated(
    stats: &BTreeMap<String, f64>,
    registers: &str,
    waves: Option<&str>,
) -> Option<Occupancy> {
    let r = *stats.get(registers)?;
    let w = waves.and_then(|w| stats.get(w)).copied();
    (r.is_finite() && w.is_none_or(f64::is_finite)).then_some(Occupancy {
        registers: r,
        waves: w,
    })
}

/// Whether a row keeps fewer waves resident than phong_exact's on its family (its
/// `ratio_to_phong_exact` of [`WAVES_KEY`] below 1); `None` without the figure.
pub fn fewer_waves(ratio_to_phong_exact: &BTreeMap<String, f64>) -> Option<bool> {
    ratio_to_phong_exact.get(WAVES_KEY).map(|r| *r < 1.0)
}

/// An NVIDIA architecture's register file and resident-warp limit per multiprocessor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarpLimits {
    pub registers_per_sm: f64,
    pub max_warps: f64,
}

/// CUDA C++ Programming Guide, "Technical Specifications per Compute Capability", rows
/// "Number of 32-bit registers per multiprocessor" and "Maximum number of resident warps per
/// multiprocessor" (https://docs.nvidia.com/cuda/cuda-c-programming-guide/index.html#features-and-technical-specifications-technical-specifications-per-compute-capability).
pub const CUDA_SPECIFICATIONS: &str = "NVIDIA CUDA C++ Programming Guide, Technical \
Specifications per Compute Capability (https://docs.nvidia.com/cuda/cuda-c-programming-guide/\
index.html#features-and-technical-specifications-technical-specifications-per-compute-capability)";

/// The limits of an NVIDIA chipset (nouveau's `nv<hex>`) by compute capability
/// ([`CUDA_SPECIFICATIONS`]): Fermi 32 K registers and 48 warps, Kepler to Volta 64 K and 64,
/// Turing 64 K and 32, Ampere GA10x 64 K and 48; `None` for Tesla.
pub fn nvidia_limits(chip: &str) -> Option<WarpLimits> {
    let id = u32::from_str_radix(chip.strip_prefix("nv")?, 16).ok()?;
    let (registers_per_sm, max_warps) = match id {
        0xc0..=0xcf | 0xd7 | 0xd9 => (32768.0, 48.0),
        0xe0..=0xff | 0x106 | 0x108 | 0x110..=0x12f | 0x130..=0x13f | 0x140 => (65536.0, 64.0),
        0x160..=0x16f => (65536.0, 32.0),
        0x172..=0x177 => (65536.0, 48.0),
        _ => return None,
    };
    Some(WarpLimits {
        registers_per_sm,
        max_warps,
    })
}

/// The warps resident per multiprocessor with `gpr` registers a thread: the register file over
/// a warp's registers (32 threads), at most the architecture's limit. The allocation
/// granularity (whole register blocks per warp) is not modelled.
pub fn nvidia_warps(gpr: f64, limits: WarpLimits) -> f64 {
    let per_warp = gpr.max(1.0) * 32.0;
    (limits.registers_per_sm / per_warp)
        .floor()
        .min(limits.max_warps)
}

/// Intel's GPU Occupancy Calculator, `Threads_Per_EU` of each device
/// (oneapi-src/oneAPI-samples, Tools/GPU-Occupancy-Calculator/index.html,
/// https://github.com/oneapi-src/oneAPI-samples): each hardware thread has its own 128
/// registers, so the threads per EU do not depend on the program's registers.
pub const INTEL_OCCUPANCY: &str = "Intel GPU Occupancy Calculator, Threads_Per_EU \
(oneapi-src/oneAPI-samples Tools/GPU-Occupancy-Calculator/index.html, \
https://github.com/oneapi-src/oneAPI-samples)";

/// The hardware threads per EU of an Intel chip ([`INTEL_OCCUPANCY`]): 7 on Gen9, Gen11 and
/// Xe-LP, 8 on Xe-HPG, Xe-LPG and Xe2; `None` for Xe3 (Panther Lake), whose register
/// allocation varies per program, and any other name.
pub fn intel_threads(chip: &str) -> Option<f64> {
    match chip {
        "skl" | "bxt" | "kbl" | "aml" | "cml" | "glk" | "whl" | "cfl" | "icl" | "ehl" | "jsl"
        | "tgl" | "rkl" | "dg1" | "sg1" | "adl" | "rpl" => Some(7.0),
        "dg2" | "mtl" | "lnl" | "bmg" => Some(8.0),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nvidia_warps_fall_with_registers_to_the_file_size() {
        let turing = nvidia_limits("nv162").unwrap();
        // 6 registers: the resident limit; 64 registers: 65536 / 2048 = 32; 128: 16.
        assert_eq!(nvidia_warps(6.0, turing), 32.0);
        assert_eq!(nvidia_warps(128.0, turing), 16.0);
        let fermi = nvidia_limits("nvc0").unwrap();
        assert_eq!(nvidia_warps(6.0, fermi), 48.0);
        assert_eq!(nvidia_warps(32.0, fermi), 32.0);
        // Teeth: Tesla and non-chipsets have no limits.
        assert!(nvidia_limits("nv50").is_none() && nvidia_limits("g57").is_none());
    }

    #[test]
    fn fewer_waves_is_a_ratio_below_one_and_stated_figures_are_read() {
        let mut stats = BTreeMap::from([("vgprs".to_string(), 24.0), ("w".to_string(), 10.0)]);
        let o = stated(&stats, "vgprs", Some("w")).unwrap();
        assert_eq!((o.registers, o.waves), (24.0, Some(10.0)));
        o.write(&mut stats);
        assert_eq!(stats[WAVES_KEY], 10.0);
        assert_eq!(
            fewer_waves(&BTreeMap::from([(WAVES_KEY.to_string(), 0.5)])),
            Some(true)
        );
        assert_eq!(
            fewer_waves(&BTreeMap::from([(WAVES_KEY.to_string(), 1.0)])),
            Some(false)
        );
        // Teeth: no registers, no occupancy; a non-finite figure, none either.
        assert!(stated(&stats, "sgprs", Some("w")).is_none());
        stats.insert("w".into(), f64::NAN);
        assert!(stated(&stats, "vgprs", Some("w")).is_none());
        assert_eq!(fewer_waves(&BTreeMap::new()), None);
        assert_eq!(intel_threads("tgl"), Some(7.0));
        assert_eq!(intel_threads("ptl"), None);
    }
}
