//! Equivalent conicity (work in progress).
