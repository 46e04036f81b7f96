//! Reference tests of railsim against analytic solutions and independent codes. One test binary
//! (ripgrep's layout); each module is one reference case or family. Tolerances live in
//! `tests/reference/<case>/tolerances.toml` and are multiplied by `RAILSIM_TOL_SCALE`.

mod bad_input;
mod common;
mod conformal_jump;
mod hertz_reference;
mod klingel;
mod mbench;
mod point_search;
mod stripes_curved;
mod stripes_hertz;
mod travel;
mod two_point;
mod varfric;
mod warm_start;
