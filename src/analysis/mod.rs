//! Analysis of results: statistics ([`stats`]), the per-pixel error against the truth ([`pixel`]) and
//! the FLIP perceptual difference ([`flip`]).
pub mod flip;
pub mod pixel;
pub mod stats;
