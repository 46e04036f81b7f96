//! Simulation time as integer nanoseconds.
//!
//! Log times are `u64` nanoseconds since the start of the simulation (so tools show dates in
//! 1970-01-01). They come from an integer step counter, `t_ns = step * dt_ns`, never from an
//! accumulated floating-point time, so that two runs of the same scene stamp identical times.

use crate::error::{LogError, Result};

/// \[ns\] Nanoseconds in one second.
pub const NS_PER_S: u64 = 1_000_000_000;

/// \[ns\] The time of step `step` of length `dt_ns`, checked for overflow.
pub fn step_time_ns(step: u64, dt_ns: u64) -> Result<u64> {
    step.checked_mul(dt_ns)
        .ok_or(LogError::TimeOverflow { step, dt_ns })
}

/// \[s\] Integer nanoseconds as seconds, for the `t_s` fields of messages.
pub fn ns_to_s(t_ns: u64) -> f64 {
    // Split so that times beyond 2^53 ns (104 days) keep nanosecond resolution in the fraction.
    (t_ns / NS_PER_S) as f64 + (t_ns % NS_PER_S) as f64 * 1e-9
}

/// \[ns\] Seconds as integer nanoseconds, rounded to the nearest nanosecond; `None` if `t_s` is
/// negative, not finite or beyond the 64-bit clock. Use it for user input (time ranges), not to
/// derive log times.
pub fn s_to_ns(t_s: f64) -> Option<u64> {
    if !t_s.is_finite() || t_s < 0.0 {
        return None;
    }
    let ns = (t_s * 1e9).round();
    if ns >= u64::MAX as f64 {
        return None;
    }
    Some(ns as u64)
}
