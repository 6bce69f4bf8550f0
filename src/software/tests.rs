//! Unit tests of the software engine.
