//! Occupancy beside cost: the registers a program holds and the waves (threads, warps) its
//! family can keep resident with them, the latency-hiding a throughput model assumes. Written
//! into a draw row's statistics as [`REGISTERS_KEY`] and [`WAVES_KEY`] by each vendor's
//! [`super::route::Vendor::occupancy`], so that isa.json's `ratio_to_phong_exact` says
//! whether a method keeps fewer waves resident than phong_exact ([`fewer_waves`]).
//!
//! Where the compiler states the waves its registers allow (RADV's `subgroups_per_simd`,
//! Turnip's `max_waves_per_core`, agx's `threads`, vc4's and v3d's `threads`), that figure is
//! used as it stands. NVIDIA's warps come from the CUDA guide's register file and resident
//! warp limits of each architecture's [`super::throughput::WeightTable`] ([`nvidia_warps`]);
//! Intel's EU threads are fixed by the hardware, each with its own register file, so a
//! program's registers do not change them ([`super::route::intel::Generation`]).
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

/// The warps resident per multiprocessor with `gpr` registers a thread: the register file over
/// a warp's registers (32 threads), at most the architecture's limit. The allocation
/// granularity (whole register blocks per warp) is not modelled.
pub fn nvidia_warps(gpr: f64, limits: &super::throughput::WeightTable) -> f64 {
    let per_warp = gpr.max(1.0) * 32.0;
    (limits.registers_per_sm / per_warp)
        .floor()
        .min(limits.max_warps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nvidia_warps_fall_with_registers_to_the_file_size() {
        use crate::isa::throughput::nvidia_weights;
        let turing = nvidia_weights("nv162").unwrap();
        // 6 registers: the resident limit; 64 registers: 65536 / 2048 = 32; 128: 16.
        assert_eq!(nvidia_warps(6.0, &turing), 32.0);
        assert_eq!(nvidia_warps(128.0, &turing), 16.0);
        let fermi = nvidia_weights("nvc0").unwrap();
        assert_eq!(nvidia_warps(6.0, &fermi), 48.0);
        assert_eq!(nvidia_warps(32.0, &fermi), 32.0);
        // Teeth: Tesla and non-chipsets have no limits.
        assert!(nvidia_weights("nv50").is_none() && nvidia_weights("g57").is_none());
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
    }
}
