//! The [`Integrator`]: settings, run state, buffers, the step loop and dense output.

use std::ops::ControlFlow;

use crate::explicit::ErkWork;
use crate::radau::RadauWork;
use crate::tableau::{self, ButcherTableau};
use crate::{Method, OdeError, OdeSystem, Stats, StopReason};

/// What one call of [`Integrator::step`] did.
#[derive(Debug, Clone, PartialEq)]
pub enum StepOutcome {
    /// A step was accepted; the state is now at `t`. [`Integrator::is_finished`] tells
    /// whether `t_end` has been reached.
    Accepted {
        /// \[s\] time at the end of the accepted step.
        t: f64,
    },
    /// No step was taken because the run is over. [`StopReason::Reached`] after the last
    /// step; otherwise the failure, repeated by later calls.
    Stop(StopReason),
}

pub(crate) enum Work {
    Erk(ErkWork),
    Radau(Box<RadauWork>),
}

/// Check the settings of an adaptive explicit method and allocate its work space.
fn adaptive_explicit(
    tableau: &'static ButcherTableau,
    rtol: f64,
    atol: f64,
    h0: Option<f64>,
    h_max: f64,
    dim: usize,
) -> Result<(Work, f64), OdeError> {
    if !(rtol.is_finite() && rtol >= 0.0) {
        return Err(OdeError::InvalidParameter {
            name: "rtol",
            value: rtol,
            expected: "a finite number >= 0",
        });
    }
    check_pos("atol", atol)?;
    if let Some(h0) = h0 {
        check_pos("h0", h0)?;
    }
    check_h_max(h_max)?;
    if tableau.e.is_none() || !tableau.fsal || tableau.embedded_order == 0 {
        return Err(OdeError::InvalidParameter {
            name: "tableau",
            value: f64::NAN,
            expected: "an FSAL tableau with an embedded error estimate",
        });
    }
    Ok((Work::Erk(ErkWork::new(tableau, true, dim)), h_max))
}

/// A reusable integrator holding the method, the run state and every buffer.
///
/// All memory is allocated in [`Integrator::new`]; [`Integrator::start`],
/// [`Integrator::step`], [`Integrator::integrate`], [`Integrator::integrate_at`] and
/// [`Integrator::dense`] allocate nothing (the FD Jacobian and faer's LU work in
/// preallocated storage).
pub struct Integrator {
    pub(crate) method: Method,
    pub(crate) n: usize,
    pub(crate) max_steps: usize,
    pub(crate) started: bool,
    pub(crate) finished: bool,
    pub(crate) stopped: Option<StopReason>,
    /// \[s\] current time.
    pub(crate) t: f64,
    pub(crate) t_end: f64,
    /// \[s\] next step size to try; NaN until chosen.
    pub(crate) h: f64,
    pub(crate) h_max: f64,
    pub(crate) x: Vec<f64>,
    /// f(t, x) when `f_valid`.
    pub(crate) f: Vec<f64>,
    pub(crate) f_valid: bool,
    /// Start of the last accepted step, for dense output.
    pub(crate) t_prev: f64,
    pub(crate) x_prev: Vec<f64>,
    pub(crate) f_prev: Vec<f64>,
    pub(crate) has_step: bool,
    /// atol · scale_i (transformed for Radau5).
    pub(crate) atol_v: Vec<f64>,
    /// Relative tolerance in use (transformed for Radau5).
    pub(crate) rtol: f64,
    pub(crate) stats: Stats,
    out: Vec<f64>,
    pub(crate) work: Work,
    /// \[s\] times where the right-hand side is not smooth, sorted ([`Integrator::set_breakpoints`])
    breaks: Vec<f64>,
}

fn check_pos(name: &'static str, v: f64) -> Result<(), OdeError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(OdeError::InvalidParameter {
            name,
            value: v,
            expected: "a finite positive number",
        })
    }
}

fn check_h_max(v: f64) -> Result<(), OdeError> {
    if v > 0.0 {
        Ok(())
    } else {
        Err(OdeError::InvalidParameter {
            name: "h_max",
            value: v,
            expected: "a positive number or infinity",
        })
    }
}

/// Smallest relative tolerance accepted by Radau5 (its transformed value is then 1e-9).
const RADAU_MIN_RTOL: f64 = 1e-12;

impl Integrator {
    /// Validates the method's settings and allocates every buffer for states of
    /// dimension `dim`.
    pub fn new(method: Method, dim: usize) -> Result<Self, OdeError> {
        if dim == 0 {
            return Err(OdeError::ZeroDimension);
        }
        let (work, h_max) = match method {
            Method::Rk4 { h } => {
                check_pos("h", h)?;
                (
                    Work::Erk(ErkWork::new(&tableau::RK4, false, dim)),
                    f64::INFINITY,
                )
            }
            Method::ExplicitFixed { tableau, h } => {
                check_pos("h", h)?;
                (Work::Erk(ErkWork::new(tableau, false, dim)), f64::INFINITY)
            }
            Method::DormandPrince {
                rtol,
                atol,
                h0,
                h_max,
            } => adaptive_explicit(&tableau::DOPRI5, rtol, atol, h0, h_max, dim)?,
            Method::AdaptiveExplicit {
                tableau,
                rtol,
                atol,
                h0,
                h_max,
            } => adaptive_explicit(tableau, rtol, atol, h0, h_max, dim)?,
            Method::Radau5 {
                rtol,
                atol,
                h0,
                h_max,
                jacobian_reuse,
            } => {
                if !(rtol.is_finite() && rtol >= RADAU_MIN_RTOL) {
                    return Err(OdeError::InvalidParameter {
                        name: "rtol",
                        value: rtol,
                        expected: "a finite number >= 1e-12",
                    });
                }
                check_pos("atol", atol)?;
                if let Some(h0) = h0 {
                    check_pos("h0", h0)?;
                }
                check_h_max(h_max)?;
                if !jacobian_reuse.is_finite() {
                    return Err(OdeError::InvalidParameter {
                        name: "jacobian_reuse",
                        value: jacobian_reuse,
                        expected: "a finite number",
                    });
                }
                (
                    Work::Radau(Box::new(RadauWork::new(dim, jacobian_reuse, false))),
                    h_max,
                )
            }
            Method::Radau5Fixed { h, rtol, atol } => {
                check_pos("h", h)?;
                if !(rtol.is_finite() && rtol >= RADAU_MIN_RTOL) {
                    return Err(OdeError::InvalidParameter {
                        name: "rtol",
                        value: rtol,
                        expected: "a finite number >= 1e-12",
                    });
                }
                check_pos("atol", atol)?;
                (
                    Work::Radau(Box::new(RadauWork::new(dim, 0.1, true))),
                    f64::INFINITY,
                )
            }
        };
        Ok(Self {
            method,
            n: dim,
            max_steps: 10_000_000,
            started: false,
            finished: true,
            stopped: None,
            t: 0.0,
            t_end: 0.0,
            h: f64::NAN,
            h_max,
            x: vec![0.0; dim],
            f: vec![0.0; dim],
            f_valid: false,
            t_prev: 0.0,
            x_prev: vec![0.0; dim],
            f_prev: vec![0.0; dim],
            has_step: false,
            atol_v: vec![0.0; dim],
            rtol: 0.0,
            stats: Stats::default(),
            out: vec![0.0; dim],
            breaks: Vec::new(),
            work,
        })
    }

    /// The method this integrator was built with.
    pub fn method(&self) -> &Method {
        &self.method
    }

    /// State dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Limits the number of accepted steps per run (default 10 000 000); the run then
    /// stops with [`StopReason::MaxSteps`].
    pub fn set_max_steps(&mut self, max_steps: usize) {
        self.max_steps = max_steps;
    }

    /// The limit of accepted steps per run ([`Integrator::set_max_steps`]).
    pub fn max_steps(&self) -> usize {
        self.max_steps
    }

    /// \[s\] current time (end of the last accepted step).
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Current state (at [`Integrator::t`]).
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// \[s\] step size the next step will try (NaN before the first step of an
    /// adaptive method).
    pub fn next_step_size(&self) -> f64 {
        self.h
    }

    /// Counters of the current run.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// True once `t_end` has been reached, or before [`Integrator::start`].
    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// Replaces the state at the current time by `x`: a jump of the state at an event (e.g.
    /// where the system's coordinates are redefined). The method goes on from there as from a
    /// start, keeping its next step size and its statistics; the dense output of the steps
    /// before is no longer available (take what is needed of it first). An error for a state
    /// of the wrong length or with a non-finite value, which leaves the integrator as it was.
    pub fn jump(&mut self, x: &[f64]) -> Result<(), OdeError> {
        if x.len() != self.n {
            return Err(OdeError::DimensionMismatch {
                what: "state",
                expected: self.n,
                found: x.len(),
            });
        }
        if let Some(index) = x.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFiniteInitialState {
                index,
                value: x[index],
            });
        }
        self.x.copy_from_slice(x);
        self.t_prev = self.t;
        self.f_valid = false;
        self.has_step = false;
        match &mut self.work {
            Work::Erk(w) => w.reset(),
            Work::Radau(w) => w.reset(self.rtol),
        }
        Ok(())
    }

    /// Declares the times at which the right-hand side is not smooth in time (a kink or a
    /// jump of `f`, e.g. where a prescribed input changes its slope): from then on no step
    /// spans one; each ends a step, as `t_end` does (stretching a step by up to 1 % to land
    /// on it). Replaces earlier breakpoints; kept by [`Integrator::start`]; times outside a
    /// run are ignored, and so are all by the fixed-step methods, which keep their grid. An
    /// error-controlled step across such a point has a local error of the
    /// order of the jump in `f` (or in its slope) times the step, which an error estimate
    /// can miss; landing on it avoids that (Hairer, Nørsett & Wanner, *Solving ODEs I*,
    /// §II.6, discontinuities). Allocates (once, outside the step loop).
    pub fn set_breakpoints(&mut self, times: &[f64]) -> Result<(), OdeError> {
        if let Some(&t) = times.iter().find(|t| !t.is_finite()) {
            return Err(OdeError::InvalidParameter {
                name: "breakpoint",
                value: t,
                expected: "a finite time",
            });
        }
        self.breaks.clear();
        self.breaks.extend_from_slice(times);
        self.breaks.sort_by(f64::total_cmp);
        self.breaks.dedup();
        Ok(())
    }

    /// The end of the span the next step may cover: the first breakpoint after `t` that a
    /// step can reach, or `t_end`; and whether it is `t_end`.
    pub(crate) fn span_end(&self) -> (f64, bool) {
        let fixed = matches!(
            self.method,
            Method::Rk4 { .. } | Method::ExplicitFixed { .. } | Method::Radau5Fixed { .. }
        );
        if fixed {
            return (self.t_end, true);
        }
        let t = self.t;
        let i = self.breaks.partition_point(|&b| b <= t);
        match self.breaks[i..]
            .iter()
            .find(|&&b| !step_too_small(t, b - t))
        {
            Some(&b) if b < self.t_end => (b, false),
            _ => (self.t_end, true),
        }
    }

    /// Prepares a run from `(t0, x0)` to `t_end` for step-wise use with
    /// [`Integrator::step`]. Resets the statistics. Evaluates nothing.
    pub fn start<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &S,
        t0: f64,
        x0: &[f64],
        t_end: f64,
    ) -> Result<(), OdeError> {
        if sys.dim() != self.n {
            return Err(OdeError::DimensionMismatch {
                what: "system",
                expected: self.n,
                found: sys.dim(),
            });
        }
        if x0.len() != self.n {
            return Err(OdeError::DimensionMismatch {
                what: "initial state",
                expected: self.n,
                found: x0.len(),
            });
        }
        if !(t0.is_finite() && t_end.is_finite() && t_end >= t0) {
            return Err(OdeError::InvalidTimeSpan { t0, t_end });
        }
        if let Some(index) = x0.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFiniteInitialState {
                index,
                value: x0[index],
            });
        }
        let (rtol, atol, h0) = match self.method {
            Method::Rk4 { h } | Method::ExplicitFixed { h, .. } => (0.0, 1.0, Some(h)),
            Method::DormandPrince { rtol, atol, h0, .. }
            | Method::AdaptiveExplicit { rtol, atol, h0, .. } => (rtol, atol, h0),
            Method::Radau5 { rtol, atol, h0, .. } => {
                // Hairer & Wanner's RADAU5 tolerance mapping.
                let r = 0.1 * rtol.powf(2.0 / 3.0);
                (r, atol * r / rtol, h0)
            }
            Method::Radau5Fixed { h, rtol, atol } => {
                let r = 0.1 * rtol.powf(2.0 / 3.0);
                (r, atol * r / rtol, Some(h))
            }
        };
        for i in 0..self.n {
            let s = sys.abs_tol_scale(i);
            if !(s.is_finite() && s > 0.0) {
                return Err(OdeError::InvalidScale { index: i, value: s });
            }
            self.atol_v[i] = atol * s;
        }
        self.rtol = rtol;
        self.t = t0;
        self.t_end = t_end;
        self.t_prev = t0;
        self.x.copy_from_slice(x0);
        self.h = h0.map_or(f64::NAN, |h| h.min(self.h_max));
        self.f_valid = false;
        self.has_step = false;
        self.started = true;
        self.finished = t_end == t0;
        self.stopped = None;
        self.stats = Stats::default();
        match &mut self.work {
            Work::Erk(w) => w.reset(),
            Work::Radau(w) => {
                let pattern = sys.jacobian_pattern();
                if let Some(p) = &pattern
                    && p.dim() != self.n
                {
                    return Err(OdeError::DimensionMismatch {
                        what: "Jacobian pattern",
                        expected: self.n,
                        found: p.dim(),
                    });
                }
                w.reset(rtol);
                w.set_pattern(pattern);
            }
        }
        Ok(())
    }

    /// Advances by one accepted step (rejected attempts are retried inside), or reports
    /// why it cannot. Call [`Integrator::start`] first.
    pub fn step<S: OdeSystem + ?Sized>(&mut self, sys: &mut S) -> StepOutcome {
        if let Some(r) = &self.stopped {
            return StepOutcome::Stop(r.clone());
        }
        if self.finished {
            return StepOutcome::Stop(StopReason::Reached);
        }
        if self.stats.steps >= self.max_steps {
            return self.fail(StopReason::MaxSteps { t: self.t });
        }
        let r = match self.work {
            Work::Erk(_) => self.erk_step(sys),
            Work::Radau(_) => self.radau_step(sys),
        };
        match r {
            Ok(()) => StepOutcome::Accepted { t: self.t },
            Err(reason) => self.fail(reason),
        }
    }

    fn fail(&mut self, reason: StopReason) -> StepOutcome {
        self.stopped = Some(reason.clone());
        StepOutcome::Stop(reason)
    }

    /// Integrates from `(t0, x)` to `t_end`, calling `observer(t, x)` at `t0` and after
    /// every accepted step; `ControlFlow::Break` stops the run with
    /// [`StopReason::Interrupted`]. On return `x` holds the state at the last accepted
    /// step (at `t_end` when the reason is [`StopReason::Reached`]).
    pub fn integrate<S, F>(
        &mut self,
        sys: &mut S,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut F,
    ) -> Result<(StopReason, Stats), OdeError>
    where
        S: OdeSystem + ?Sized,
        F: FnMut(f64, &[f64]) -> ControlFlow<()>,
    {
        self.start(sys, t0, x, t_end)?;
        let mut reason = if observer(t0, &self.x).is_break() {
            Some(StopReason::Interrupted { t: t0 })
        } else {
            None
        };
        while reason.is_none() {
            match self.step(sys) {
                StepOutcome::Accepted { t } => {
                    if observer(t, &self.x).is_break() {
                        reason = Some(StopReason::Interrupted { t });
                    }
                }
                StepOutcome::Stop(r) => reason = Some(r),
            }
        }
        x.copy_from_slice(&self.x);
        Ok((reason.unwrap_or(StopReason::Reached), self.stats))
    }

    /// Integrates from `(t0, x)` to the last of `times` and calls `observer(t, x(t))` at
    /// each of `times` (non-decreasing, all ≥ `t0`), using dense output: the steps are
    /// chosen by the method, not by the output grid. On return `x` holds the state at
    /// the last accepted step.
    pub fn integrate_at<S, F>(
        &mut self,
        sys: &mut S,
        t0: f64,
        x: &mut [f64],
        times: &[f64],
        observer: &mut F,
    ) -> Result<(StopReason, Stats), OdeError>
    where
        S: OdeSystem + ?Sized,
        F: FnMut(f64, &[f64]) -> ControlFlow<()>,
    {
        let t_end = times.last().copied().unwrap_or(t0);
        let mut prev = t0;
        for &t in times {
            if !(t >= prev && t <= t_end) {
                return Err(OdeError::InvalidOutputTime { t, t0, t_end });
            }
            prev = t;
        }
        self.start(sys, t0, x, t_end)?;
        let mut k = 0;
        let mut reason = None;
        while k < times.len() && times[k] <= t0 {
            if observer(times[k], &self.x).is_break() {
                reason = Some(StopReason::Interrupted { t: t0 });
                break;
            }
            k += 1;
        }
        let mut out = std::mem::take(&mut self.out);
        while reason.is_none() {
            match self.step(sys) {
                StepOutcome::Accepted { t } => {
                    while k < times.len() && (times[k] <= t || self.finished) {
                        // inside the step by construction
                        let tk = times[k].min(t);
                        if self.dense(tk, &mut out).is_err() {
                            out.copy_from_slice(&self.x);
                        }
                        k += 1;
                        if observer(tk, &out).is_break() {
                            reason = Some(StopReason::Interrupted { t });
                            break;
                        }
                    }
                }
                StepOutcome::Stop(r) => reason = Some(r),
            }
        }
        self.out = out;
        x.copy_from_slice(&self.x);
        Ok((reason.unwrap_or(StopReason::Reached), self.stats))
    }

    /// Writes the continuous extension at `t` into `out`; `t` must lie in the last
    /// accepted step `[t_prev, t]`. Order 4 for Dormand–Prince (Shampine's
    /// interpolant), 3 for RK4 (cubic Hermite) and Radau5 (collocation polynomial).
    pub fn dense(&self, t: f64, out: &mut [f64]) -> Result<(), OdeError> {
        if out.len() != self.n {
            return Err(OdeError::DimensionMismatch {
                what: "dense output buffer",
                expected: self.n,
                found: out.len(),
            });
        }
        let slack = 8.0 * f64::EPSILON * self.t.abs().max(self.t_prev.abs());
        let inside = (self.t_prev - slack..=self.t + slack).contains(&t);
        if !self.has_step || !inside {
            return Err(OdeError::DenseOutOfRange {
                t,
                t_prev: self.t_prev,
                t_last: self.t,
            });
        }
        let h = self.t - self.t_prev;
        let theta = if h > 0.0 {
            ((t - self.t_prev) / h).clamp(0.0, 1.0)
        } else {
            1.0
        };
        match &self.work {
            Work::Erk(w) => w.dense(theta, h, &self.x_prev, &self.x, &self.f_prev, &self.f, out),
            Work::Radau(w) => w.dense(theta, &self.x_prev, out),
        }
        Ok(())
    }
}

/// Limits the trial step to `h_max` and the remaining span; returns the step and whether
/// it is the last one (DOPRI5/RADAU5 rule: stretch up to 1 % to land on `t_end`).
pub(crate) fn clip_step(t: f64, t_end: f64, h_max: f64, h: f64) -> (f64, bool) {
    let h = h.min(h_max);
    if t + 1.01 * h >= t_end {
        (t_end - t, true)
    } else {
        (h, false)
    }
}

/// True when `h` cannot advance the floating-point time `t` meaningfully.
pub(crate) fn step_too_small(t: f64, h: f64) -> bool {
    // also true for NaN
    h.is_nan() || h <= 10.0 * f64::EPSILON * t.abs() || h < 1e-300
}

/// \[-\] step-size factor after a failed evaluation at a trial state.
pub(crate) const TRIAL_FAILURE_SHRINK: f64 = 0.25;

/// After a failed evaluation `e` at a trial state of a step of length `h`: count it, mark the
/// step rejected, make the next attempt a quarter as long (`h_next`) and keep `e` as the stop
/// reason should the step become too small.
pub(crate) fn retry_shorter(
    stats: &mut Stats,
    h_next: &mut f64,
    h: f64,
    reject: &mut bool,
    trial: &mut Option<StopReason>,
    e: StopReason,
) {
    stats.trial_failures += 1;
    *reject = true;
    *h_next = h * TRIAL_FAILURE_SHRINK;
    *trial = Some(e);
}

/// Evaluates the right-hand side, counting it and checking the output. Its errors
/// (`RhsFailed`, `NonFinite`) are what the adaptive methods treat as an overshoot at a trial
/// state (`OdeSystem::rhs`).
/// `t_step` is the start of the step, reported for non-finite values.
pub(crate) fn eval_rhs<S: OdeSystem + ?Sized>(
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    x: &[f64],
    out: &mut [f64],
    t_step: f64,
) -> Result<(), StopReason> {
    stats.rhs_evals += 1;
    sys.rhs(t, x, out)
        .map_err(|e| StopReason::RhsFailed { t, msg: e.0 })?;
    match out.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(StopReason::NonFinite { t: t_step, index }),
        None => Ok(()),
    }
}

/// Returns the first non-finite component of `x`, as a stop reason.
pub(crate) fn check_finite(x: &[f64], t_step: f64) -> Result<(), StopReason> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(StopReason::NonFinite { t: t_step, index }),
        None => Ok(()),
    }
}

/// Weighted RMS norm: sqrt(mean((e_i / sc_i)²)), sc_i = atol_i + rtol·max(|x0_i|, |x1_i|).
pub(crate) fn wrms(e: &[f64], x0: &[f64], x1: &[f64], atol: &[f64], rtol: f64) -> f64 {
    let mut s = 0.0;
    for i in 0..e.len() {
        let sc = atol[i] + rtol * x0[i].abs().max(x1[i].abs());
        let r = e[i] / sc;
        s += r * r;
    }
    (s / e.len() as f64).sqrt()
}

/// Initial step (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4, code HINIT).
/// `f0` = f(t, x); uses `x1`, `f1` as scratch.
pub(crate) fn initial_step<S: OdeSystem + ?Sized>(
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    x: &[f64],
    f0: &[f64],
    x1: &mut [f64],
    f1: &mut [f64],
    atol: &[f64],
    rtol: f64,
    order: u32,
    h_max: f64,
    span: f64,
) -> Result<f64, StopReason> {
    let n = x.len();
    let (mut dnf, mut dny) = (0.0, 0.0);
    for i in 0..n {
        let sk = atol[i] + rtol * x[i].abs();
        dnf += (f0[i] / sk).powi(2);
        dny += (x[i] / sk).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max).min(span);
    // The explicit Euler probe may overshoot into a region the system cannot evaluate:
    // shorter probes until one succeeds (or the step cannot be reduced).
    loop {
        for i in 0..n {
            x1[i] = x[i] + h * f0[i];
        }
        match eval_rhs(sys, stats, t + h, x1, f1, t) {
            Ok(()) => break,
            Err(_) if !step_too_small(t, h * TRIAL_FAILURE_SHRINK) => {
                stats.trial_failures += 1;
                h *= TRIAL_FAILURE_SHRINK;
            }
            Err(e) => return Err(e),
        }
    }
    let mut der2 = 0.0;
    for i in 0..n {
        let sk = atol[i] + rtol * x[i].abs();
        der2 += ((f1[i] - f0[i]) / sk).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / order as f64)
    };
    Ok((100.0 * h).min(h1).min(h_max).min(span))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RhsError;

    struct Rober;
    impl OdeSystem for Rober {
        fn dim(&self) -> usize {
            3
        }
        fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            let (r1, r2, r3) = (0.04 * y[0], 1e4 * y[1] * y[2], 3e7 * y[1] * y[1]);
            d[0] = -r1 + r2;
            d[1] = r1 - r2 - r3;
            d[2] = r3;
            Ok(())
        }
    }

    /// (address, capacity) of every buffer the integrator owns.
    fn fingerprint(i: &Integrator) -> Vec<(usize, usize)> {
        let v = |b: &Vec<f64>| (b.as_ptr() as usize, b.capacity());
        let mut f = vec![
            v(&i.x),
            v(&i.f),
            v(&i.x_prev),
            v(&i.f_prev),
            v(&i.atol_v),
            v(&i.out),
        ];
        match &i.work {
            Work::Erk(w) => f.extend(w.buffers()),
            Work::Radau(w) => f.extend(w.buffers()),
        }
        f
    }

    /// All buffers are allocated in `new`: runs neither move nor grow any of them.
    #[test]
    fn runs_do_not_reallocate_buffers() {
        for m in [
            Method::Rk4 { h: 0.5 },
            Method::dormand_prince(1e-6, 1e-8),
            Method::radau5(1e-6, 1e-10),
        ] {
            let mut integ = Integrator::new(m, 3).unwrap();
            let before = fingerprint(&integ);
            let mut x = [1.0, 0.0, 0.0];
            let times = [1.0, 10.0, 100.0];
            let mut go = |_: f64, _: &[f64]| ControlFlow::Continue(());
            let (r, s) = integ
                .integrate_at(&mut Rober, 0.0, &mut x, &times, &mut go)
                .unwrap();
            assert!(s.steps > 0, "{m:?}: {r:?}");
            integ
                .integrate(&mut Rober, 0.0, &mut x, 1.0, &mut go)
                .unwrap();
            assert_eq!(before, fingerprint(&integ), "{m:?}");
        }
    }
}
