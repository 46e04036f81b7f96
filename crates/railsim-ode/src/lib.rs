//! ODE integrators for railsim.
//!
//! This crate sits below the simulation crate in the data flow: `railsim-sim` turns a
//! vehicle on a track into a first-order system `x' = f(t, x)` (an [`OdeSystem`]) and
//! hands it to an [`Integrator`]. The crate knows nothing of railways; it only sees
//! a state vector, a right-hand side and per-component tolerance scales.
//!
//! Methods ([`Method`]):
//! - [`Method::Rk4`]: classical fixed-step Runge–Kutta (Kutta 1901);
//! - [`Method::DormandPrince`]: adaptive Dormand–Prince 5(4) with PI step control and a
//!   fourth-order continuous extension (dense output);
//! - [`Method::Radau5`]: Radau IIA of order 5 (Hairer & Wanner) for stiff systems, with a
//!   finite-difference Jacobian, faer's dense LU and Jacobian/LU reuse across steps.
//!
//! Explicit methods are Butcher tableaus defined as data ([`tableau`]). Errors are
//! measured in a weighted RMS norm whose absolute part is scaled per state variable
//! ([`OdeSystem::abs_tol_scale`]), so that metres, radians and m/s get tolerances in their
//! own units (as Drake does).
//!
//! Bad settings are construction errors ([`OdeError`]); what happens during a run is a
//! [`StopReason`]. Nothing panics on bad input and a non-finite state is never returned
//! silently. All buffers are allocated in [`Integrator::new`] (Radau5's Jacobian pattern and
//! column groups in [`Integrator::start`], once per run); a step allocates nothing.
//!
//! ```
//! use railsim_ode::{Integrator, Method, OdeSystem, RhsError, StopReason};
//! use std::ops::ControlFlow;
//!
//! /// x'' = -x as a first-order system.
//! struct Oscillator;
//! impl OdeSystem for Oscillator {
//!     fn dim(&self) -> usize { 2 }
//!     fn rhs(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError> {
//!         dxdt[0] = x[1];
//!         dxdt[1] = -x[0];
//!         Ok(())
//!     }
//! }
//!
//! let mut integ = Integrator::new(Method::dormand_prince(1e-8, 1e-10), 2)?;
//! let mut x = [1.0, 0.0];
//! let (stop, stats) = integ.integrate(&mut Oscillator, 0.0, &mut x, 1.0, &mut |_, _| {
//!     ControlFlow::Continue(())
//! })?;
//! assert_eq!(stop, StopReason::Reached);
//! assert!((x[0] - 1f64.cos()).abs() < 1e-7);
//! assert!(stats.steps > 0);
//! # Ok::<(), railsim_ode::OdeError>(())
//! ```

#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod explicit;
mod integrator;
mod linalg;
pub mod linear;
mod radau;
mod sparsity;
pub mod tableau;

pub use integrator::{Integrator, StepOutcome};
pub use sparsity::JacobianPattern;

/// A first-order system `x' = f(t, x)`.
///
/// Implementors own any scratch they need (through `&mut self`); the integrators call
/// [`OdeSystem::rhs`] with borrowed slices and expect no allocation per call.
pub trait OdeSystem {
    /// Number of state variables.
    fn dim(&self) -> usize;

    /// Writes `f(t, x)` into `dxdt` (both slices have length [`OdeSystem::dim`]).
    ///
    /// Return an [`RhsError`] when the model cannot be evaluated (a derailment, a
    /// failed inner solver, …). At an accepted state (the start of a run, the end of an
    /// accepted step) the integrator then stops with [`StopReason::RhsFailed`] naming the
    /// time. At a trial state inside a step (a stage, a Newton iterate, the initial-step
    /// probe) the adaptive methods treat it, like a non-finite result there, as an overshoot:
    /// they reject the step and retry with a quarter of it, and stop with that error only when
    /// the step can no longer be reduced (the solution itself reaches the failing region). The
    /// fixed-step methods stop at once.
    fn rhs(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError>;

    /// \[unit of x_i / unit of atol\] scale of the absolute tolerance for state variable `i`:
    /// the error weight is `atol * abs_tol_scale(i) + rtol * |x_i|`. Use it to give
    /// variables of different units comparable tolerances (e.g. 1 for metres, 1e-3 for
    /// radians if the absolute tolerance is meant as metres over a 1 km lever). Must be
    /// finite and positive. Read once per run, at the start.
    fn abs_tol_scale(&self, i: usize) -> f64 {
        let _ = i;
        1.0
    }

    /// The structure of ∂f/∂x ([`JacobianPattern`]): for each state variable, every
    /// derivative that may depend on it at any state. `None` (the default): dense.
    ///
    /// With a pattern, Radau5's finite-difference Jacobian and [`linear::jacobian`] perturb
    /// columns that share no row together, one right-hand side per group instead of per
    /// column. Entries outside the pattern are taken as zero, so a dependence left out makes
    /// the Jacobian wrong (for Radau5 a slower Newton iteration, for a linearisation wrong
    /// eigenvalues). Read once per run, at the start.
    fn jacobian_pattern(&self) -> Option<JacobianPattern> {
        None
    }
}

impl<S: OdeSystem + ?Sized> OdeSystem for &mut S {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn rhs(&mut self, t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError> {
        (**self).rhs(t, x, dxdt)
    }
    fn abs_tol_scale(&self, i: usize) -> f64 {
        (**self).abs_tol_scale(i)
    }
    fn jacobian_pattern(&self) -> Option<JacobianPattern> {
        (**self).jacobian_pattern()
    }
}

/// A failure reported by [`OdeSystem::rhs`], with a message for the user.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct RhsError(pub String);

/// The integration method and its settings.
///
/// Time is written in seconds below, but nothing depends on it: any unit of the
/// independent variable works as long as it is used consistently.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Classical Runge–Kutta of order 4 with a fixed step ([`tableau::RK4`]); the last
    /// step is shortened to land on `t_end`. Dense output is the cubic Hermite
    /// interpolant (order 3).
    Rk4 {
        /// \[s\] step size; finite and positive.
        h: f64,
    },
    /// Any explicit Runge–Kutta tableau with a fixed step (e.g. [`tableau::DOPRI5`] to
    /// measure its order); the embedded error estimate, if any, is not used. Dense output
    /// uses the tableau's continuous extension if it has one, else cubic Hermite.
    ExplicitFixed {
        /// The method.
        tableau: &'static tableau::ButcherTableau,
        /// \[s\] step size; finite and positive.
        h: f64,
    },
    /// Adaptive Dormand–Prince 5(4) ([`tableau::DOPRI5`]) with PI step-size control and a
    /// fourth-order continuous extension ([`tableau::DOPRI5_DENSE`]).
    DormandPrince {
        /// \[-\] relative tolerance; finite, ≥ 0.
        rtol: f64,
        /// \[units of x\] absolute tolerance, multiplied per component by
        /// [`OdeSystem::abs_tol_scale`]; finite and positive.
        atol: f64,
        /// \[s\] initial step; `None` picks one from the problem (Hairer's HINIT).
        h0: Option<f64>,
        /// \[s\] largest step allowed; finite and positive, or `f64::INFINITY`.
        h_max: f64,
    },
    /// Any explicit tableau with an embedded error estimate (e.g. [`tableau::BS3`]), adaptive
    /// with the same PI step-size control as `DormandPrince`; dense output by the tableau's
    /// continuous extension if it has one, else cubic Hermite (needs `fsal`).
    AdaptiveExplicit {
        /// The method; must have error weights `e` and be FSAL.
        tableau: &'static tableau::ButcherTableau,
        /// \[-\] relative tolerance; finite, ≥ 0.
        rtol: f64,
        /// \[units of x\] absolute tolerance, scaled per component as for `DormandPrince`.
        atol: f64,
        /// \[s\] initial step; `None` picks one from the problem.
        h0: Option<f64>,
        /// \[s\] largest step allowed; finite and positive, or `f64::INFINITY`.
        h_max: f64,
    },
    /// Radau IIA of order 5 (three-stage collocation, L-stable), the method of Hairer &
    /// Wanner's RADAU5, for stiff systems.
    ///
    /// The user tolerances are mapped as in RADAU5 (`rtol' = 0.1 rtol^(2/3)`,
    /// `atol' = atol · rtol'/rtol`) so that the achieved accuracy is of the order of
    /// `rtol`. Dense output is the collocation polynomial (order 3 uniformly).
    Radau5 {
        /// \[-\] relative tolerance; finite, > 0.
        rtol: f64,
        /// \[units of x\] absolute tolerance, multiplied per component by
        /// [`OdeSystem::abs_tol_scale`]; finite, > 0.
        atol: f64,
        /// \[s\] initial step; `None` picks one from the problem.
        h0: Option<f64>,
        /// \[s\] largest step allowed; finite and positive, or `f64::INFINITY`.
        h_max: f64,
        /// \[-\] Jacobian reuse threshold (RADAU5's `thet`): after an accepted step the
        /// Jacobian is kept when the Newton contraction rate was at most this. Larger
        /// values reuse more (0.1 suits costly right-hand sides, 0.001 small cheap
        /// ones); a negative value recomputes it after every accepted step.
        jacobian_reuse: f64,
    },
    /// Radau IIA of order 5 with a fixed step `h` (the last step is shortened to land on
    /// `t_end`) and no error control; Newton is converged to the tolerances. If Newton
    /// fails even with a fresh Jacobian the run stops with [`StopReason::NewtonFailed`].
    /// Meant for real-time-like runs and for measuring the order.
    Radau5Fixed {
        /// \[s\] step size; finite and positive.
        h: f64,
        /// \[-\] relative tolerance of the Newton iteration (mapped as for `Radau5`).
        rtol: f64,
        /// \[units of x\] absolute tolerance of the Newton iteration.
        atol: f64,
    },
}

impl Method {
    /// Dormand–Prince with the given tolerances, automatic initial step, no step limit.
    pub fn dormand_prince(rtol: f64, atol: f64) -> Self {
        Method::DormandPrince {
            rtol,
            atol,
            h0: None,
            h_max: f64::INFINITY,
        }
    }

    /// Radau IIA order 5 with the given tolerances, automatic initial step, no step
    /// limit and Jacobian reuse threshold 0.1.
    pub fn radau5(rtol: f64, atol: f64) -> Self {
        Method::Radau5 {
            rtol,
            atol,
            h0: None,
            h_max: f64::INFINITY,
            jacobian_reuse: 0.1,
        }
    }
}

/// Counters of one run (reset by [`Integrator::start`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// \[-\] accepted steps.
    pub steps: usize,
    /// \[-\] steps rejected by the error test.
    pub rejected: usize,
    /// \[-\] right-hand-side evaluations, including those for Jacobians.
    pub rhs_evals: usize,
    /// \[-\] finite-difference Jacobians.
    pub jacobians: usize,
    /// \[-\] right-hand-side evaluations for the Jacobians (included in `rhs_evals`): one per
    /// column, or one per column group with a [`JacobianPattern`].
    pub jacobian_rhs_evals: usize,
    /// \[-\] LU factorisations (Radau5 counts the real and the complex one as one).
    pub lu_factorizations: usize,
    /// \[-\] simplified-Newton iterations.
    pub newton_iterations: usize,
    /// \[-\] step attempts abandoned because Newton diverged or converged too slowly.
    pub newton_failures: usize,
    /// \[-\] step attempts abandoned because the right-hand side failed or was not finite at
    /// a trial state (adaptive methods; see [`OdeSystem::rhs`]).
    pub trial_failures: usize,
    /// \[-\] accepted steps of an adaptive explicit method that were limited by stability
    /// rather than accuracy: the estimate h·|λ| of the dominant eigenvalue exceeded the
    /// method's [`tableau::ButcherTableau::stiffness_limit`] (DOPRI5 only). Such steps keep a stiff
    /// component on the edge of the stability region, where a weakly damped mode can hold an
    /// oscillation of the order of the absolute tolerance.
    pub stability_limited: usize,
    /// \[s\] time at the end of the 15th stability-limited step without 6 consecutive steps
    /// that were not limited between them, the first time this happened in the run (Hairer's
    /// criterion for "the problem seems to be stiff", DOPRI5's IASTI/NONSTI counters); `None`
    /// if it never did.
    pub stiff_from: Option<f64>,
}

/// Why a run stopped. Every variant except [`StopReason::Reached`] leaves the state at
/// the last accepted step.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// `t_end` was reached.
    Reached,
    /// The observer returned `ControlFlow::Break` after the step ending at `t`.
    Interrupted {
        /// \[s\] time of the last accepted step.
        t: f64,
    },
    /// The right-hand side returned an error.
    RhsFailed {
        /// \[s\] time of the failed evaluation.
        t: f64,
        /// The system's message.
        msg: String,
    },
    /// The step size fell below what the floating-point time can resolve.
    StepTooSmall {
        /// \[s\] time of the last accepted step.
        t: f64,
        /// \[s\] the step size that was too small.
        h: f64,
    },
    /// The right-hand side or the new state had a NaN or an infinity in component `index`.
    NonFinite {
        /// \[s\] start of the step that produced it.
        t: f64,
        /// State component with the first non-finite value.
        index: usize,
    },
    /// Newton did not converge in a fixed-step run ([`Method::Radau5Fixed`]).
    NewtonFailed {
        /// \[s\] time of the last accepted step.
        t: f64,
        /// \[s\] the step size tried.
        h: f64,
    },
    /// The iteration matrix stayed singular after repeated step reductions (Radau5).
    SingularMatrix {
        /// \[s\] time of the last accepted step.
        t: f64,
    },
    /// The step limit ([`Integrator::set_max_steps`]) was hit before `t_end`.
    MaxSteps {
        /// \[s\] time of the last accepted step.
        t: f64,
    },
}

/// Invalid settings or input, found before any integration happens.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OdeError {
    /// The system has no state variables.
    #[error("the state dimension must be positive, found 0")]
    ZeroDimension,
    /// A method parameter is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidParameter {
        /// Parameter name as in [`Method`].
        name: &'static str,
        /// The value given.
        value: f64,
        /// What was expected.
        expected: &'static str,
    },
    /// The system, state or output buffer length differs from the integrator's dimension.
    #[error("{what} has dimension {found}, the integrator was built for {expected}")]
    DimensionMismatch {
        /// Which argument.
        what: &'static str,
        /// Integrator dimension.
        expected: usize,
        /// Dimension found.
        found: usize,
    },
    /// `t0` or `t_end` is not finite, or `t_end < t0` (only forward integration).
    #[error("invalid time span [{t0}, {t_end}]: both must be finite and t_end >= t0")]
    InvalidTimeSpan {
        /// \[s\] start.
        t0: f64,
        /// \[s\] end.
        t_end: f64,
    },
    /// The initial state has a NaN or infinity.
    #[error("initial state component {index} is not finite ({value})")]
    NonFiniteInitialState {
        /// Component index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// [`OdeSystem::abs_tol_scale`] returned a value that is not finite and positive.
    #[error("abs_tol_scale({index}) = {value}: expected finite and > 0")]
    InvalidScale {
        /// Component index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Output times must be non-decreasing and inside the time span.
    #[error("output time {t} is out of order or outside [{t0}, {t_end}]")]
    InvalidOutputTime {
        /// \[s\] the offending time.
        t: f64,
        /// \[s\] start.
        t0: f64,
        /// \[s\] end.
        t_end: f64,
    },
    /// Dense output was asked for outside the last accepted step, or before any step.
    #[error("dense output at t = {t} is outside the last step [{t_prev}, {t_last}]")]
    DenseOutOfRange {
        /// \[s\] requested time.
        t: f64,
        /// \[s\] start of the last step.
        t_prev: f64,
        /// \[s\] end of the last step.
        t_last: f64,
    },
    /// A [`JacobianPattern`] entry outside the system's dimension.
    #[error("Jacobian pattern entry (row {row}, column {col}) outside a system of dimension {dim}")]
    PatternOutOfRange {
        /// Row (derivative) index.
        row: usize,
        /// Column (state variable) index.
        col: usize,
        /// The pattern's dimension.
        dim: usize,
    },
}
