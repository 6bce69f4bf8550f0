//! Timed draws: recorded once, submitted repeatedly, each bracketed by timestamps; one
//! [`Sample`] per submission. The pipeline-statistics count of a draw is taken in a submission
//! of its own ([`Renderer::fragment_invocations`]), never inside a timed bracket.
use super::*;
use crate::error::{Error, Result};
use crate::gpu::vk::queries::timestamp_delta_ns;
use crate::gpu::vk::{DepthMode, GraphicsPipeline, OneShot, QueryPool, Recorded};

/// Which clock a time is read from; spelt `timestamp` or `wall` in every output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Clock {
    /// The timestamp queries around the draw on the device's queue.
    Timestamp,
    /// The host's submit-to-fence wall clock.
    Wall,
}

impl Clock {
    pub fn as_str(self) -> &'static str {
        match self {
            Clock::Timestamp => "timestamp",
            Clock::Wall => "wall",
        }
    }

    /// A sample's time on this clock: NaN for a timestamp the sample lacks (counted as
    /// non-finite, never mixed with the other clock).
    pub fn of(self, s: &Sample) -> f64 {
        match self {
            Clock::Timestamp => s.timestamp_ms.unwrap_or(f64::NAN),
            Clock::Wall => s.wall_ms,
        }
    }
}

impl std::fmt::Display for Clock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One timed submission: the submit-to-fence wall time and the timestamp interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub wall_ms: f64,
    /// `None` when the queue has no timestamps.
    pub timestamp_ms: Option<f64>,
}

/// Draws recorded by [`Renderer::timed_draws`], ready to be submitted in any order.
pub struct TimedDraws {
    draws: Vec<(Recorded, QueryPool, Vec<GraphicsPipeline>)>,
    _targets: [Option<Targets>; 2],
    valid_bits: u32,
    period_ns: f32,
}

impl TimedDraws {
    /// Submits draw `i` once and waits for it.
    pub fn run(&self, i: usize) -> Result<Sample> {
        let (cmd, pool, _) = &self.draws[i];
        let wall = cmd.submit()?;
        let t = pool.results()?;
        Ok(Sample {
            wall_ms: wall.as_secs_f64() * 1e3,
            timestamp_ms: timestamp_delta_ns(t[0], t[2], self.valid_bits, self.period_ns)
                .map(|ns| ns / 1e6),
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

/// Whether a timed draw renders the normal target by default. Nothing reads it when timing
/// (the shader's second output is discarded without an attachment); `shadelab skips` measures
/// what leaving it out saves.
pub const TIMING_NORMAL_TARGET: bool = false;
/// Whether a timed draw has a depth pre-pass by default (`shadelab skips` measures it).
pub const TIMING_PREPASS: bool = false;

/// What one timed program draws: ranges of one upload, each with its shading (one range for a
/// method or the floor; one per group for `auto`), all in one rendering.
#[derive(Clone)]
pub struct DrawList<'a> {
    pub gpu: &'a GpuScene,
    /// (shading, first vertex, vertex count).
    pub parts: Vec<(Shading<'a>, u32, u32)>,
    /// Draw every triangle depth-only first, then shade with LESS_OR_EQUAL and no depth write,
    /// so that no occluded fragment is shaded.
    pub prepass: bool,
    /// Render into a normal target too (false: nothing reads it; the shader's second output
    /// has no attachment and is discarded).
    pub normal: bool,
}

impl<'a> DrawList<'a> {
    /// Every vertex of `gpu` with one shading.
    pub fn whole(gpu: &'a GpuScene, shading: Shading<'a>) -> Self {
        DrawList {
            gpu,
            parts: vec![(shading, 0, gpu.inputs.positions.len() as u32)],
            prepass: TIMING_PREPASS,
            normal: TIMING_NORMAL_TARGET,
        }
    }

    /// The shadings' names joined with `+` (for messages).
    pub fn name(&self) -> String {
        let names: Vec<String> = self.parts.iter().map(|(s, ..)| s.name()).collect();
        names.join("+")
    }
}

/// One recorded draw of a [`DrawList`]: its pipeline, bindings and vertex range (first, count).
type RecordedDraw<'g> = (
    GraphicsPipeline,
    Vec<(u32, &'g crate::gpu::vk::Buffer)>,
    u32,
    u32,
);

impl Renderer {
    /// Records, once, the draw of every (upload, shading) pair into shared targets (clear +
    /// draw into the colour target, and the normal target when the list asks for it, no
    /// readback), each bracketed by timestamps,
    /// for repeated submission by a benchmark. The uploads may hold different geometries (the
    /// scene's triangles, a PN tessellation), so that every program of a run can be timed in the
    /// same interleaved rounds; they must share one image size. Nothing but the draw and its
    /// timestamps is inside a bracket (no pipeline-statistics query: see
    /// [`Renderer::fragment_invocations`]).
    ///
    /// Timestamp placement (measured in ../shared/TOOLCHAIN.md on Mesa 22.3): a
    /// TOP_OF_PIPE/BOTTOM_OF_PIPE pair around the draw reports ~0.2 ms for ~20 ms of work,
    /// because a timestamp's value is latched when the *next* flush runs. Two BOTTOM_OF_PIPE
    /// writes before the rendering and two after it, reading the first of each pair, track the
    /// submit-to-fence wall clock; `bench` re-checks that on every run.
    pub fn timed_draws(&self, programs: &[(&GpuScene, Shading)]) -> Result<TimedDraws> {
        let lists: Vec<DrawList> = programs
            .iter()
            .map(|(gpu, s)| DrawList::whole(gpu, *s))
            .collect();
        self.timed_draw_lists(&lists)
    }

    /// [`Renderer::timed_draws`] of draw lists: each program is one or more ranges of one
    /// upload, every range with its own pipeline, all in one rendering (`auto`'s groups).
    pub fn timed_draw_lists(&self, programs: &[DrawList]) -> Result<TimedDraws> {
        let Some(first) = programs.first() else {
            return Err(Error::Internal("timed_draws: no program to record".into()));
        };
        let (w, h) = (first.gpu.inputs.width, first.gpu.inputs.height);
        // Shared targets: with a normal target, and without one, made when a list asks.
        let mut targets: [Option<Targets>; 2] = [None, None];
        let mut draws = Vec::new();
        for list in programs {
            let gpu = list.gpu;
            if (gpu.inputs.width, gpu.inputs.height) != (w, h) {
                return Err(Error::Internal(format!(
                    "timed_draws: {} draws {}x{}, the shared targets are {w}x{h}",
                    list.name(),
                    gpu.inputs.width,
                    gpu.inputs.height
                )));
            }
            let slot = &mut targets[usize::from(list.normal)];
            if slot.is_none() {
                *slot = Some(Targets::with_normal(&self.ctx, w, h, list.normal)?);
            }
            let Some(t) = slot.as_ref() else {
                return Err(Error::Internal("timed_draws: targets missing".into()));
            };
            let recorded = self.record_list(list)?;
            let pool = QueryPool::timestamps(&self.ctx, 4)?;
            let mut cmd = OneShot::begin(&self.ctx)?;
            cmd.reset_queries(&pool);
            cmd.timestamp(&pool, 0);
            cmd.timestamp(&pool, 1);
            t.begin(&mut cmd);
            for (p, buffers, first, count) in &recorded {
                cmd.draw_range(p, Some(&gpu.set), buffers, *first, *count);
            }
            cmd.end_rendering();
            cmd.timestamp(&pool, 2);
            cmd.timestamp(&pool, 3);
            let cmd = cmd.finish()?;
            let pipelines = recorded.into_iter().map(|(p, ..)| p).collect();
            draws.push((cmd, pool, pipelines));
        }
        let info = self.ctx.info();
        Ok(TimedDraws {
            draws,
            _targets: targets,
            valid_bits: info.timestamp_valid_bits,
            period_ns: info.timestamp_period_ns,
        })
    }

    /// The pipeline, bindings and vertex range of every draw of `list`, in order: the depth
    /// pre-pass (the constant program, colour writes off, every vertex) when asked, then every
    /// part.
    pub(super) fn record_list<'g>(&self, list: &DrawList<'g>) -> Result<Vec<RecordedDraw<'g>>> {
        let gpu = list.gpu;
        let colors = color_formats(list.normal);
        let mut out = Vec::new();
        let depth = if list.prepass {
            let (streams, buffers) = gpu.buffers(Shading::Constant)?;
            let p = self.pipeline_with(
                gpu,
                &self.program(gpu, Shading::Constant),
                &streams,
                colors,
                DepthMode::Less,
                false,
            )?;
            out.push((p, buffers, 0, gpu.inputs.positions.len() as u32));
            DepthMode::EqualAfterPrepass
        } else {
            DepthMode::Less
        };
        for &(s, first, count) in &list.parts {
            let (streams, buffers) = gpu.buffers(s)?;
            let p =
                self.pipeline_with(gpu, &self.program(gpu, s), &streams, colors, depth, true)?;
            out.push((p, buffers, first, count));
        }
        Ok(out)
    }

    /// Fragment-shader invocations of one draw (clear + draw, as timed), counted by a
    /// pipeline-statistics query in a submission of its own, untimed, so that the query never
    /// sits inside a timed bracket. `None` when the device has no pipeline statistics. Not
    /// necessarily the covered pixels: Mesa 22.3 counts whole pixel blocks.
    pub fn fragment_invocations(&self, gpu: &GpuScene, shading: Shading) -> Result<Option<u64>> {
        self.fragment_invocations_list(&DrawList::whole(gpu, shading))
    }

    /// [`Renderer::fragment_invocations`] of a draw list (all its parts in one query).
    pub fn fragment_invocations_list(&self, list: &DrawList) -> Result<Option<u64>> {
        let Some(stats) = QueryPool::fragment_invocations(&self.ctx)? else {
            return Ok(None);
        };
        let gpu = list.gpu;
        let (w, h) = (gpu.inputs.width, gpu.inputs.height);
        let targets = Targets::with_normal(&self.ctx, w, h, list.normal)?;
        let recorded = self.record_list(list)?;
        let mut cmd = OneShot::begin(&self.ctx)?;
        cmd.reset_queries(&stats);
        targets.begin(&mut cmd);
        cmd.begin_query(&stats);
        for (p, buffers, first, count) in &recorded {
            cmd.draw_range(p, Some(&gpu.set), buffers, *first, *count);
        }
        cmd.end_query(&stats);
        cmd.end_rendering();
        cmd.submit()?;
        Ok(stats.results()?.first().copied())
    }
}
