//! Timestamp query pools and the arithmetic of their values (valid bits, wrap, period).
use std::sync::Arc;

use ash::vk;

use super::conv::VkContext;
use super::Context;
use crate::error::Result;

/// A pool of `count` timestamp queries.
pub struct QueryPool {
    ctx: Arc<Context>,
    pub(crate) raw: vk::QueryPool,
    pub(crate) count: u32,
}

impl QueryPool {
    pub fn timestamps(ctx: &Arc<Context>, count: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(count);
        Self::new(ctx, info)
    }

    /// One pipeline-statistics query counting fragment-shader invocations. `None` when the
    /// device does not support pipeline statistics.
    pub fn fragment_invocations(ctx: &Arc<Context>) -> Result<Option<Self>> {
        if !ctx.info().pipeline_statistics {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .pipeline_statistics(vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS)
            .query_count(1);
        Self::new(ctx, info).map(Some)
    }

    fn new(ctx: &Arc<Context>, info: vk::QueryPoolCreateInfo) -> Result<Self> {
        let count = info.query_count;
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        Ok(QueryPool {
            ctx: ctx.clone(),
            raw,
            count,
        })
    }

    /// The raw 64-bit values of every query (waits for them; call after the submit returned).
    pub fn results(&self) -> Result<Vec<u64>> {
        let mut out = vec![0u64; self.count as usize];
        // SAFETY: the submission that wrote the queries has completed (synchronous submits).
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.raw,
                0,
                &mut out,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(out)
    }
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: no work in flight.
        unsafe { self.ctx.device.destroy_query_pool(self.raw, None) };
    }
}

/// Nanoseconds between two timestamps of a queue with `valid_bits` valid bits and a period of
/// `period_ns` per tick: the difference is taken modulo 2^valid_bits, so a counter that wrapped
/// once between the two still gives the right interval. `None` when the queue has no
/// timestamps (`valid_bits == 0`).
pub fn timestamp_delta_ns(t0: u64, t1: u64, valid_bits: u32, period_ns: f32) -> Option<f64> {
    if valid_bits == 0 {
        return None;
    }
    let mask = if valid_bits >= 64 {
        u64::MAX
    } else {
        (1u64 << valid_bits) - 1
    };
    let ticks = t1.wrapping_sub(t0) & mask;
    Some(ticks as f64 * period_ns as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_uses_the_period() {
        assert_eq!(timestamp_delta_ns(100, 350, 64, 1.0), Some(250.0));
        assert_eq!(timestamp_delta_ns(100, 350, 64, 2.5), Some(625.0));
    }

    #[test]
    fn delta_wraps_at_the_valid_bits() {
        // a 36-bit counter that wrapped: 2^36 - 10 -> 5 is 15 ticks
        let top = (1u64 << 36) - 10;
        assert_eq!(timestamp_delta_ns(top, 5, 36, 1.0), Some(15.0));
        // bits above the valid ones are ignored
        assert_eq!(
            timestamp_delta_ns(
                0xABC0_0000_0000_0000,
                0xABC0_0000_0000_0010 | (1 << 40),
                36,
                1.0
            ),
            Some(16.0)
        );
        // a full 64-bit counter wraps at 2^64
        assert_eq!(timestamp_delta_ns(u64::MAX - 1, 3, 64, 1.0), Some(5.0));
    }

    #[test]
    fn no_valid_bits_means_no_timestamps() {
        assert_eq!(timestamp_delta_ns(1, 2, 0, 1.0), None);
    }
}
