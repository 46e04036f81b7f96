//! Elastic contact kernels (stub, being written).
