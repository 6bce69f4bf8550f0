//! The images a renderer returns: [`Frame`] (colour and shading normal) and [`IdFrame`]
//! (triangle id and interpolation weights per pixel), and [`SpareFrames`], frames handed back
//! for the next read-back. Plain data, no device.
use std::sync::Mutex;

/// A float image read back from the GPU, row-major from the top-left pixel.
#[derive(Debug, Clone)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// Linear colour; alpha 1 on covered pixels, 0 on the background.
    pub color: Vec<[f32; 4]>,
    /// Shading normal the method used; w 1 where the method has a per-pixel normal.
    pub normal: Vec<[f32; 4]>,
}

impl Frame {
    /// Number of covered (non-background) pixels.
    pub fn covered(&self) -> usize {
        self.color.iter().filter(|c| c[3] > 0.0).count()
    }

    /// The colour and normal vectors, for a renderer to read the next frame into
    /// (`gpu::Renderer::render_with_into`).
    pub fn into_pixels(self) -> (Vec<[f32; 4]>, Vec<[f32; 4]>) {
        (self.color, self.normal)
    }
}

/// The id pass: per pixel, the triangle index + 1 (0 = background) and the interpolation
/// weights the rasterizer used.
#[derive(Debug, Clone)]
pub struct IdFrame {
    pub width: u32,
    pub height: u32,
    pub prim: Vec<u32>,
    pub weights: Vec<[f32; 4]>,
}

impl IdFrame {
    /// Number of covered pixels (a triangle id other than 0).
    pub fn covered(&self) -> usize {
        self.prim.iter().filter(|&&p| p != 0).count()
    }
}

/// Frames their users are done with, kept for the renderer to read the next frame into
/// (`gpu::Renderer::render_with_into`): warm memory instead of fresh pages per frame. At most
/// `keep` are kept, the rest dropped, so the memory they hold stays bounded; shared between
/// threads (compare's workers give, its render thread takes).
pub struct SpareFrames {
    frames: Mutex<Vec<Frame>>,
    keep: usize,
}

impl SpareFrames {
    /// A pool that keeps at most `keep` frames.
    pub fn new(keep: usize) -> Self {
        SpareFrames {
            frames: Mutex::new(Vec::new()),
            keep,
        }
    }

    /// Hands a frame back: kept when there is room, dropped otherwise.
    pub fn give(&self, frame: Frame) {
        let mut frames = self.frames.lock().unwrap_or_else(|e| e.into_inner());
        if frames.len() < self.keep {
            frames.push(frame);
        }
    }

    /// A frame handed back, if any (its size and contents are whatever its last use left).
    pub fn take(&self) -> Option<Frame> {
        self.frames.lock().unwrap_or_else(|e| e.into_inner()).pop()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32) -> Frame {
        Frame {
            width,
            height: 1,
            color: vec![[0.0; 4]; width as usize],
            normal: Vec::new(),
        }
    }

    #[test]
    fn spare_frames_keep_at_most_their_bound() {
        let spare = SpareFrames::new(1);
        assert!(spare.take().is_none());
        spare.give(frame(2));
        spare.give(frame(3)); // no room: dropped
        assert_eq!(spare.take().map(|f| f.width), Some(2));
        assert!(spare.take().is_none());
        // Teeth: a pool with room for two keeps the second too.
        let two = SpareFrames::new(2);
        two.give(frame(2));
        two.give(frame(3));
        assert!(two.take().is_some() && two.take().is_some());
    }
}
