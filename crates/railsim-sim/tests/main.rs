//! railsim-sim's integration tests, built as one test binary: one compile and link instead of one
//! per file, and the long simulations of one file share the cores with the short tests of the
//! others (docs/performance.md, "Tests and CI"). Run one file's tests with a filter on its module,
//! e.g. `cargo test -p railsim-sim --test sim stability::`.

mod common;

mod assessment;
mod curving;
mod dynamics;
mod jacobian_pattern;
mod modal;
mod quasi_static_start;
mod rail_sections;
mod rail_support;
mod robustness;
mod scene;
mod stability;
mod stiffness;
mod suspension;
