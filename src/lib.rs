pub mod bench;
pub mod chart;
pub mod cli;
pub mod compare;
pub mod error;
pub mod formulas;
pub mod heatmap;
pub mod mesh;
pub mod methods;
pub mod output;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod spirv;
#[cfg(test)]
mod testutil;
pub mod truth;
pub mod vk;
pub use error::{Error, Result};
