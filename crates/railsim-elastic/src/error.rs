//! The crate's single error type.

use thiserror::Error;

/// Everything that can go wrong in an elastic kernel.
///
/// Every variant names the offending quantity, the value found and what was expected, so a
/// message can be traced back to its input without a debugger.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ElasticError {
    /// A scalar input is non-finite or out of its admissible range.
    #[error("{name} = {value:e} is invalid: expected {expected}")]
    InvalidInput {
        /// name of the argument or field, with its unit, e.g. `"a [m]"`
        name: &'static str,
        /// the value that was passed
        value: f64,
        /// the admissible range, in words
        expected: &'static str,
    },
    /// A count or slice length does not match what the kernel needs.
    #[error("{name} = {found} is invalid: expected {expected}")]
    InvalidSize {
        /// name of the argument, e.g. `"gap.len()"`
        name: &'static str,
        /// the size that was passed
        found: usize,
        /// what was expected, in words
        expected: String,
    },
    /// An iterative solver stopped at its iteration limit before reaching its tolerance.
    #[error(
        "{solver} did not converge in {iterations} iterations: residual {residual:e} > tolerance {tol:e}"
    )]
    NotConverged {
        /// which solver
        solver: &'static str,
        /// iterations performed
        iterations: usize,
        /// last value of the convergence measure
        residual: f64,
        /// the tolerance asked for
        tol: f64,
    },
    /// A conjugate-gradient iteration found no descent step: the step's denominator (the
    /// curvature `tᵀ A t` along the steepest-descent direction) was not positive, which for a
    /// positive definite influence matrix only round-off or overflow can cause.
    #[error(
        "{solver} found no descent step at iteration {iteration}: step denominator {denominator:e} <= 0"
    )]
    StepBreakdown {
        /// which solver
        solver: &'static str,
        /// the iteration
        iteration: usize,
        /// the denominator found
        denominator: f64,
    },
}

/// Returns `Ok(v)` if `v` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, v: f64) -> Result<f64, ElasticError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ElasticError::InvalidInput {
            name,
            value: v,
            expected: "a finite value > 0",
        })
    }
}

/// Returns `Ok(v)` if `v` is finite and non-negative.
pub(crate) fn non_negative(name: &'static str, v: f64) -> Result<f64, ElasticError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(ElasticError::InvalidInput {
            name,
            value: v,
            expected: "a finite value >= 0",
        })
    }
}

/// Returns `Ok(v)` if `v` is finite.
pub(crate) fn finite(name: &'static str, v: f64) -> Result<f64, ElasticError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ElasticError::InvalidInput {
            name,
            value: v,
            expected: "a finite value",
        })
    }
}

/// Returns `Ok(v)` if `lo <= v <= hi` (which also rejects NaN).
pub(crate) fn in_range(
    name: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<f64, ElasticError> {
    if v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(ElasticError::InvalidInput {
            name,
            value: v,
            expected,
        })
    }
}
