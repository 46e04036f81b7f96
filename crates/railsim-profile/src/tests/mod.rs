//! Unit tests of the crate.
mod errors;
mod geometry;
