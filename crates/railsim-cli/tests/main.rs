//! The CLI's integration tests, built as one test binary (one compile and link instead of one per
//! file). Run one file's tests with a filter on its module, e.g.
//! `cargo test -p railsim-cli --test cli replay::`.

mod common;

mod cli;
mod replay;
mod run;
