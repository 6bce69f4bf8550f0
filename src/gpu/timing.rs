//! Timed draws: recorded once, submitted repeatedly, each bracketed by timestamps; one
//! [`Sample`] per submission.
use super::*;
use crate::error::Result;
use crate::gpu::vk::queries::timestamp_delta_ns;
use crate::gpu::vk::{GraphicsPipeline, OneShot, QueryPool, Recorded};

/// One timed submission: the submit-to-fence wall time and the timestamp interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub wall_ms: f64,
    /// `None` when the queue has no timestamps.
    pub timestamp_ms: Option<f64>,
    /// Fragment-shader invocations reported by a pipeline-statistics query (`None` when the
    /// device has none). Not necessarily the covered pixels: Mesa 22.3 counts whole blocks.
    pub fragment_invocations: Option<u64>,
}

/// Draws recorded by [`Renderer::timed_draws`], ready to be submitted in any order.
pub struct TimedDraws {
    draws: Vec<(Recorded, QueryPool, Option<QueryPool>, GraphicsPipeline)>,
    _targets: Targets,
    valid_bits: u32,
    period_ns: f32,
}

impl TimedDraws {
    /// Submits draw `i` once and waits for it.
    pub fn run(&self, i: usize) -> Result<Sample> {
        let (cmd, pool, stats, _) = &self.draws[i];
        let wall = cmd.submit()?;
        let t = pool.results()?;
        let fragment_invocations = match stats {
            Some(q) => q.results()?.first().copied(),
            None => None,
        };
        Ok(Sample {
            wall_ms: wall.as_secs_f64() * 1e3,
            timestamp_ms: timestamp_delta_ns(t[0], t[2], self.valid_bits, self.period_ns)
                .map(|ns| ns / 1e6),
            fragment_invocations,
        })
    }

    /// Number of recorded draws.
    pub fn len(&self) -> usize {
        self.draws.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.draws.is_empty()
    }
}

impl Renderer {
    /// Records, once, the draw of every shading into shared targets (clear + draw into the
    /// colour and normal targets, no readback), each bracketed by timestamps, for repeated
    /// submission by a benchmark. All shadings must draw the same geometry as `gpu`.
    ///
    /// Timestamp placement (measured in ../shared/TOOLCHAIN.md on Mesa 22.3): a
    /// TOP_OF_PIPE/BOTTOM_OF_PIPE pair around the draw reports ~0.2 ms for ~20 ms of work,
    /// because a timestamp's value is latched when the *next* flush runs. Two BOTTOM_OF_PIPE
    /// writes before the rendering and two after it, reading the first of each pair, track the
    /// submit-to-fence wall clock; `bench` re-checks that on every run.
    pub fn timed_draws(&self, gpu: &GpuScene, shadings: &[Shading]) -> Result<TimedDraws> {
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let targets = Targets::new(&self.ctx, w, h)?;
        let mut draws = Vec::new();
        for s in shadings {
            let (streams, buffers) = gpu.buffers(*s)?;
            let pipeline = self.pipeline(gpu, &self.program(gpu, *s), &streams, &[COLOR, COLOR])?;
            let pool = QueryPool::timestamps(&self.ctx, 4)?;
            let stats = QueryPool::fragment_invocations(&self.ctx)?;
            let mut cmd = OneShot::begin(&self.ctx)?;
            cmd.reset_queries(&pool);
            if let Some(q) = &stats {
                cmd.reset_queries(q);
            }
            cmd.timestamp(&pool, 0);
            cmd.timestamp(&pool, 1);
            targets.begin(&mut cmd);
            if let Some(q) = &stats {
                cmd.begin_query(q);
            }
            cmd.draw(
                &pipeline,
                Some(&gpu.set),
                &buffers,
                gpu.inputs.positions.len() as u32,
            );
            if let Some(q) = &stats {
                cmd.end_query(q);
            }
            cmd.end_rendering();
            cmd.timestamp(&pool, 2);
            cmd.timestamp(&pool, 3);
            draws.push((cmd.finish()?, pool, stats, pipeline));
        }
        let info = self.ctx.info();
        Ok(TimedDraws {
            draws,
            _targets: targets,
            valid_bits: info.timestamp_valid_bits,
            period_ns: info.timestamp_period_ns,
        })
    }
}
