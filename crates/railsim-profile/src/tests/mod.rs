//! Unit tests of the crate.
mod conicity;
mod errors;
mod geometry;
