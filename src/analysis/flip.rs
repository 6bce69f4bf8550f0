//! FLIP (NVIDIA's perceptual image difference, through the nv-flip crate) over covered pixels.
use glam::DVec3;

use crate::analysis::stats::percentile;
use crate::output;

pub(crate) fn srgb_rgb8(color: impl Iterator<Item = DVec3>) -> Vec<u8> {
    color
        .flat_map(|c| [c.x, c.y, c.z].map(|v| output::srgb8(v as f32)))
        .collect()
}

/// FLIP between two RGB8 images, pooled (mean, p95) over `mask` pixels.
pub(crate) fn flip(
    reference: &[u8],
    test: &[u8],
    width: u32,
    height: u32,
    mask: &[bool],
) -> (f64, f64) {
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    let map = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let mut v: Vec<f64> = map
        .iter()
        .zip(mask)
        .filter(|(_, &m)| m)
        .map(|(&e, _)| e as f64)
        .collect();
    let mean = if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    };
    (mean, percentile(&mut v, 95.0))
}
