//! The images a renderer returns: [`Frame`] (colour and shading normal) and [`IdFrame`]
//! (triangle id and interpolation weights per pixel). Plain data, no device.
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
