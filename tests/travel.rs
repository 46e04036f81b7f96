//! Travelling error and step convergence (placeholder, filled below).
