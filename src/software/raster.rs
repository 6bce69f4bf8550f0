//! The scanline rasterizer: triangle set-up, coverage, the depth test and the threads. It has
//! the conventions of the Vulkan pipeline (src/gpu/vk/pipeline.rs): window coordinates with the
//! origin top-left and pixel centres at +0.5, corners snapped to 1/256 pixel (lavapipe's 8
//! subpixel bits) and covered by exact integer edge functions with the top-left fill rule, no
//! culling, depth `z/w` interpolated linearly on screen and tested LESS against a buffer cleared
//! to 1. Attributes are interpolated linearly on screen from the f32 window corners.
//!
//! Work is split into bands of [`BAND`] rows; each thread takes the next band (a shared queue)
//! and owns that band's rows of every image, so no two threads write the same pixel. Within a
//! band triangles are drawn in submission order, so the depth test resolves exactly as a
//! sequential draw would. A [`Shader`] shades one span of one row; nothing in the per-row or
//! per-pixel path allocates (the per-thread scratch is allocated once per draw).
use std::sync::Mutex;

use glam::{Vec2, Vec3};

use crate::error::{Error, Result};
use crate::frame::{Frame, IdFrame};
use crate::scene::{SceneInputs, Winding};

/// Rows per band of work.
pub const BAND: u32 = 16;
/// Subpixel steps per pixel (8 bits, lavapipe's `FIXED_ORDER`).
const SUBPIXEL: f64 = 256.0;
/// Largest |window coordinate| in pixels the integer edge functions take (products of two
/// fixed-point differences stay below 2^63).
const MAX_COORD: f64 = (1u64 << 26) as f64;

/// One triangle, set up: integer edge functions for coverage, f32 planes for attributes.
#[derive(Debug, Clone)]
pub struct Tri {
    /// Index in the scene's triangle list.
    pub index: u32,
    /// First and last row that may be covered.
    pub rows: (u32, u32),
    /// Per edge: (A, B, C, m): covered where `A i + B j + C >= m` at pixel (i, j).
    edges: [[i64; 4]; 3],
    /// Window corners (f32, as uploaded).
    pub s: [Vec2; 3],
    /// Unit view-space vertex normals.
    pub n: [Vec3; 3],
    pub flat: Vec3,
    pub pn: [Vec3; 3],
    /// Gradients (d/dx, d/dy) of the weights of corners 1 and 2.
    pub dw1: Vec2,
    pub dw2: Vec2,
    /// Depth at corner 0 and its gradient.
    z0: f32,
    dz: Vec2,
}

impl Tri {
    /// Weights (w0, w1, w2) at window position `p`, from the plane equations.
    #[inline(always)]
    pub fn weights(&self, p: Vec2) -> Vec3 {
        let d = p - self.s[0];
        let w1 = self.dw1.x * d.x + self.dw1.y * d.y;
        let w2 = self.dw2.x * d.x + self.dw2.y * d.y;
        Vec3::new(1.0 - w1 - w2, w1, w2)
    }

    /// A per-corner attribute at `p` (`a0 + w1 (a1 - a0) + w2 (a2 - a0)`) and its x step.
    #[inline(always)]
    pub fn attribute(&self, a: &[Vec3; 3], p: Vec2) -> (Vec3, Vec3) {
        let w = self.weights(p);
        let (d1, d2) = (a[1] - a[0], a[2] - a[0]);
        (
            a[0] + d1 * w.y + d2 * w.z,
            d1 * self.dw1.x + d2 * self.dw2.x,
        )
    }

    /// The covered pixels of row `j` as an inclusive range, clipped to `0..width`.
    #[inline]
    fn cover(&self, j: u32, width: u32) -> Option<(u32, u32)> {
        let (mut lo, mut hi) = (0i64, width as i64 - 1);
        for &[a, b, c, m] in &self.edges {
            let cj = b * j as i64 + c;
            // a i + cj >= m
            if a > 0 {
                lo = lo.max(-((cj - m).div_euclid(a)));
            } else if a < 0 {
                hi = hi.min((cj - m).div_euclid(-a));
            } else if cj < m {
                return None;
            }
        }
        (lo <= hi).then_some((lo as u32, hi as u32))
    }
}

/// Sets up every triangle of `inputs` that can cover a pixel. Errors on a scene the engine does
/// not clip (a corner in front of the near plane, or window coordinates beyond [`MAX_COORD`]).
pub fn setup(inputs: &SceneInputs) -> Result<Vec<Tri>> {
    if let Some(t) = inputs.near_clipped() {
        return Err(Error::Usage(format!(
            "triangle {t} crosses the near plane (or lies behind the eye); the software engine \
             does not clip: move the camera back or the near plane closer, or use --engine vulkan"
        )));
    }
    let depth: Vec<f32> = inputs.clip_corners().map(|c| (c.z / c.w) as f32).collect();
    let (w, h) = (inputs.width as i64, inputs.height as i64);
    let mut tris = Vec::with_capacity(inputs.triangle_count());
    for t in 0..inputs.triangle_count() {
        let s: [Vec2; 3] = [0, 1, 2].map(|k| Vec2::from(inputs.window[3 * t + k]));
        if s.iter().any(|p| {
            // Beyond MAX_COORD, or NaN.
            let m = p.abs().max_element() as f64;
            m.is_nan() || m >= MAX_COORD
        }) {
            return Err(Error::Usage(format!(
                "triangle {t} has a window coordinate beyond {MAX_COORD} pixels (or not finite); \
                 the software engine does not clip: use --engine vulkan"
            )));
        }
        // Corners snapped to the subpixel grid, round to nearest.
        let q: [[i64; 2]; 3] = s.map(|p| {
            [
                (p.x as f64 * SUBPIXEL).round() as i64,
                (p.y as f64 * SUBPIXEL).round() as i64,
            ]
        });
        let area =
            (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
        if area == 0 {
            continue;
        }
        // Back-face culling as the Vulkan pipeline does it (SceneInputs::cull_front): Vulkan's
        // signed area -1/2 sum(x_i y_(i+1) - x_(i+1) y_i) is positive for counter-clockwise,
        // and `area` above is minus twice it.
        if let Some(front) = inputs.cull_front {
            let front_facing = match front {
                Winding::CounterClockwise => area < 0,
                Winding::Clockwise => area > 0,
            };
            if !front_facing {
                continue;
            }
        }
        // Inside is where every edge function is positive: wind the edges by the area's sign.
        let order = if area > 0 { [0, 1, 2] } else { [0, 2, 1] };
        let half = SUBPIXEL as i64 / 2;
        let edges = [0, 1, 2].map(|e| {
            let (p, r) = (q[order[e]], q[order[(e + 1) % 3]]);
            let (dx, dy) = (r[0] - p[0], r[1] - p[1]);
            let top_left = dy < 0 || (dy == 0 && dx > 0);
            // E = dx (Py - py) - dy (Px - px), P = (256 i + 128, 256 j + 128)
            [
                -dy * SUBPIXEL as i64,
                dx * SUBPIXEL as i64,
                dx * (half - p[1]) - dy * (half - p[0]),
                if top_left { 0 } else { 1 },
            ]
        });
        let ymin = q.iter().map(|p| p[1]).min().unwrap_or(0);
        let ymax = q.iter().map(|p| p[1]).max().unwrap_or(0);
        // Rows whose centre (256 j + 128) lies in [ymin, ymax].
        let j0 = -((half - ymin).div_euclid(SUBPIXEL as i64));
        let j1 = (ymax - half).div_euclid(SUBPIXEL as i64);
        let (j0, j1) = (j0.max(0), j1.min(h - 1));
        let xmin = q.iter().map(|p| p[0]).min().unwrap_or(0);
        let xmax = q.iter().map(|p| p[0]).max().unwrap_or(0);
        if j0 > j1 || xmax < 0 || xmin >= w * SUBPIXEL as i64 {
            continue;
        }
        let (e1, e2) = (s[1] - s[0], s[2] - s[0]);
        let det = e1.x * e2.y - e1.y * e2.x;
        let dw1 = Vec2::new(e2.y, -e2.x) / det;
        let dw2 = Vec2::new(-e1.y, e1.x) / det;
        let z = [depth[3 * t], depth[3 * t + 1], depth[3 * t + 2]];
        let dz = dw1 * (z[1] - z[0]) + dw2 * (z[2] - z[0]);
        let v3 = |a: [f32; 3]| Vec3::from(a);
        tris.push(Tri {
            index: t as u32,
            rows: (j0 as u32, j1 as u32),
            edges,
            s,
            n: [0, 1, 2].map(|k| v3(inputs.view_normals[3 * t + k])),
            flat: v3(inputs.flat_normals[t]),
            pn: inputs.pn_mids[t].map(v3),
            dw1,
            dw2,
            z0: z[0],
            dz,
        });
    }
    Ok(tris)
}

/// One row of a band: the images' pixels of that row.
pub struct RowOut<'a> {
    pub color: &'a mut [[f32; 4]],
    /// The normal target, when the draw has one.
    pub normal: Option<&'a mut [[f32; 4]]>,
    pub depth: &'a mut [f32],
    /// Triangle ids and weights, when the draw records them.
    pub ids: Option<(&'a mut [u32], &'a mut [[f32; 4]])>,
}

impl RowOut<'_> {
    /// Depth test at pixel `i`: LESS; on a pass writes the depth (and the ids) and returns true.
    #[inline(always)]
    pub fn test(&mut self, tri: &Tri, i: usize, z: f32, p: Vec2) -> bool {
        if z < self.depth[i] {
            self.depth[i] = z;
            if let Some((prim, weights)) = &mut self.ids {
                prim[i] = tri.index + 1;
                let w = tri.weights(p);
                weights[i] = [w.x, w.y, w.z, 0.0];
            }
            true
        } else {
            false
        }
    }

    /// Writes a shaded pixel (alpha 1 = covered; normal w 1 where the method has one).
    #[inline(always)]
    pub fn put(&mut self, i: usize, c: Vec3, n: [f32; 4]) {
        self.color[i] = [c.x, c.y, c.z, 1.0];
        if let Some(normal) = &mut self.normal {
            normal[i] = n;
        }
    }
}

/// The span of one row to shade: row `y`, pixels `i0..=i1`, depth `z` at `i0` and its step.
#[derive(Debug, Clone, Copy)]
pub struct RowSpan {
    pub y: u32,
    pub i0: usize,
    pub i1: usize,
    pub z: f32,
    pub dz: f32,
}

impl RowSpan {
    /// Centre of pixel `i` of the row.
    #[inline(always)]
    pub fn centre(&self, i: usize) -> Vec2 {
        Vec2::new(i as f32 + 0.5, self.y as f32 + 0.5)
    }
}

/// A method in its span form: per-triangle set-up, then one covered span of a row at a time.
pub trait Shader: Sync {
    /// What the method computes once per triangle.
    type Setup: Send + Sync;
    fn setup(&self, tri: &Tri) -> Self::Setup;
    /// Shades pixels `span.i0..=span.i1` of row `span.y` (each passing `out.test` is written).
    /// `scratch` is per thread, reused across rows.
    fn row(
        &self,
        tri: &Tri,
        setup: &Self::Setup,
        span: RowSpan,
        out: &mut RowOut,
        scratch: &mut Vec<Vec3>,
    );
}

/// A band of rows and its part of the images.
struct Band<'a> {
    first: u32,
    color: &'a mut [[f32; 4]],
    normal: Option<&'a mut [[f32; 4]]>,
    depth: &'a mut [f32],
    prim: Option<&'a mut [u32]>,
    weights: Option<&'a mut [[f32; 4]]>,
}

/// The images of a software draw, reusable: a draw clears each band of rows just before it
/// draws that band (on the thread that draws it), so a timed draw into kept targets touches no
/// fresh memory (a fresh 1024x1024 frame is 36 MB of page faults).
pub struct Targets {
    pub width: u32,
    pub height: u32,
    color: Vec<[f32; 4]>,
    /// None: no normal target (nobody reads it).
    normal: Option<Vec<[f32; 4]>>,
    depth: Vec<f32>,
    /// Triangle ids and weights (the id frame), when asked for.
    ids: Option<(Vec<u32>, Vec<[f32; 4]>)>,
}

impl Targets {
    /// Colour and depth, and the normal target and the id frame when asked for.
    pub fn new(width: u32, height: u32, normal: bool, ids: bool) -> Self {
        let n = width as usize * height as usize;
        Targets {
            width,
            height,
            color: vec![[0.0; 4]; n],
            normal: normal.then(|| vec![[0.0; 4]; n]),
            depth: vec![1.0; n],
            ids: ids.then(|| (vec![0; n], vec![[0.0; 4]; n])),
        }
    }

    /// The images as the Vulkan renderer returns them (`normal` empty without a normal target).
    pub fn into_frames(self) -> (Frame, Option<IdFrame>) {
        let (width, height) = (self.width, self.height);
        let frame = Frame {
            width,
            height,
            color: self.color,
            normal: self.normal.unwrap_or_default(),
        };
        let ids = self.ids.map(|(prim, weights)| IdFrame {
            width,
            height,
            prim,
            weights,
        });
        (frame, ids)
    }
}

/// Draws the set-up triangles with `shader` on `threads` threads (at least 1) into new
/// targets (with a normal target).
pub fn draw<S: Shader>(
    width: u32,
    height: u32,
    tris: &[Tri],
    shader: &S,
    threads: usize,
    with_ids: bool,
) -> (Frame, Option<IdFrame>) {
    let mut targets = Targets::new(width, height, true, with_ids);
    draw_into(&mut targets, tris, shader, threads);
    targets.into_frames()
}

/// Draws the set-up triangles with `shader` on `threads` threads (at least 1) into `targets`,
/// clearing them first (colour and normal 0, depth 1, ids 0).
pub fn draw_into<S: Shader>(targets: &mut Targets, tris: &[Tri], shader: &S, threads: usize) {
    let (width, height) = (targets.width, targets.height);
    let w = width as usize;
    let setups: Vec<S::Setup> = tris.iter().map(|t| shader.setup(t)).collect();
    let bands = (height as usize).div_ceil(BAND as usize);
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (k, t) in tris.iter().enumerate() {
        for b in (t.rows.0 / BAND)..=(t.rows.1 / BAND) {
            bins[b as usize].push(k as u32);
        }
    }
    let rows = BAND as usize * w;
    let Targets {
        color,
        normal,
        depth,
        ids,
        ..
    } = targets;
    let mut normal_chunks = normal.as_mut().map(|n| n.chunks_mut(rows));
    let (mut prim_chunks, mut weight_chunks) = match ids {
        Some((p, wt)) => (Some(p.chunks_mut(rows)), Some(wt.chunks_mut(rows))),
        None => (None, None),
    };
    let jobs: Vec<Band> = color
        .chunks_mut(rows)
        .zip(depth.chunks_mut(rows))
        .enumerate()
        .map(|(b, (color, depth))| Band {
            first: b as u32 * BAND,
            color,
            normal: normal_chunks.as_mut().and_then(Iterator::next),
            depth,
            prim: prim_chunks.as_mut().and_then(Iterator::next),
            weights: weight_chunks.as_mut().and_then(Iterator::next),
        })
        .collect();
    let queue = Mutex::new(jobs.into_iter());
    let work = || {
        let mut scratch = Vec::with_capacity(1 << 13);
        loop {
            let job = queue.lock().map(|mut q| q.next()).unwrap_or(None);
            let Some(band) = job else { break };
            draw_band(band, width, tris, &setups, &bins, shader, &mut scratch);
        }
    };
    let threads = threads.clamp(1, bands.max(1));
    std::thread::scope(|s| {
        for _ in 1..threads {
            s.spawn(work);
        }
        work();
    });
}

fn draw_band<S: Shader>(
    band: Band,
    width: u32,
    tris: &[Tri],
    setups: &[S::Setup],
    bins: &[Vec<u32>],
    shader: &S,
    scratch: &mut Vec<Vec3>,
) {
    let w = width as usize;
    let rows = (band.color.len() / w) as u32;
    let last = band.first + rows - 1;
    let Band {
        first,
        color,
        mut normal,
        depth,
        mut prim,
        mut weights,
    } = band;
    // Clear this band where it is drawn (the thread's own cache, no other thread's rows).
    color.fill([0.0; 4]);
    depth.fill(1.0);
    if let Some(n) = &mut normal {
        n.fill([0.0; 4]);
    }
    if let (Some(p), Some(wt)) = (&mut prim, &mut weights) {
        p.fill(0);
        wt.fill([0.0; 4]);
    }
    for &k in &bins[(first / BAND) as usize] {
        let tri = &tris[k as usize];
        for y in tri.rows.0.max(first)..=tri.rows.1.min(last) {
            let Some((i0, i1)) = tri.cover(y, width) else {
                continue;
            };
            let r = (y - first) as usize * w;
            let ids = match (&mut prim, &mut weights) {
                (Some(p), Some(wt)) => Some((&mut p[r..r + w], &mut wt[r..r + w])),
                _ => None,
            };
            let mut out = RowOut {
                color: &mut color[r..r + w],
                normal: normal.as_mut().map(|n| &mut n[r..r + w]),
                depth: &mut depth[r..r + w],
                ids,
            };
            let p = Vec2::new(i0 as f32 + 0.5, y as f32 + 0.5) - tri.s[0];
            let span = RowSpan {
                y,
                i0: i0 as usize,
                i1: i1 as usize,
                z: tri.z0 + tri.dz.x * p.x + tri.dz.y * p.y,
                dz: tri.dz.x,
            };
            shader.row(tri, &setups[k as usize], span, &mut out, scratch);
        }
    }
}
