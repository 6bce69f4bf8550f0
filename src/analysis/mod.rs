//! Analysis of results: statistics ([`stats`]), the per-pixel error against the truth ([`pixel`],
//! walked over a reference's columns by [`scan`]) and the FLIP perceptual difference ([`flip`]).
pub mod flip;
pub mod pixel;
pub mod scan;
pub mod stats;
