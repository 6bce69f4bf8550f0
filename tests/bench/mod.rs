//! `shadelab bench` and `shadelab skips`: structure only (no speed assertions), by topic.
mod auto;
mod files;
mod options;
mod runs;
mod skips;
