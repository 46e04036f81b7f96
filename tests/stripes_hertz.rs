//! STRIPES on constant-curvature geometry gives back Hertz (placeholder, filled below).
