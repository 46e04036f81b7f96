//! One generic explicit Runge–Kutta stepper driven by a [`ButcherTableau`].

use crate::integrator::{
    Integrator, Work, check_finite, clip_step, eval_rhs, initial_step, retry_shorter,
    step_too_small, wrms,
};
use crate::tableau::ButcherTableau;
use crate::{OdeSystem, StopReason};

/// PI step-size control constants of Hairer's DOPRI5 (*Solving ODEs I*, §II.4 and IV.2).
const SAFE: f64 = 0.9;
/// Smallest step-size ratio h_new / h.
const FAC_MIN: f64 = 0.2;
/// Largest step-size ratio h_new / h.
const FAC_MAX: f64 = 10.0;
/// Integral-part exponent of the PI controller (Gustafsson; Hairer uses 0.04 for DOPRI5).
const BETA: f64 = 0.04;

/// Stability-limited steps after which a run is reported stiff (Hairer's DOPRI5 code: 15) ...
const STIFF_RUN: usize = 15;
/// ... counted until this many consecutive steps are not limited (Hairer's code: 6; at the
/// stability boundary the controller switches between limited and not limited steps, which a
/// count of consecutive limited steps alone never reaches 15 over).
const NON_STIFF_RESET: usize = 6;

/// Whether the accepted step with stage derivatives `k` was limited by stability:
/// the last two stages are both at t + h, at the states x_{s−1} and x_s, so
/// h ‖k_s − k_{s−1}‖ / ‖x_s − x_{s−1}‖ estimates h·|λ| of the eigenvalue that dominates
/// their difference (Hairer & Wanner, *Solving ODEs II*, §IV.2). The state difference is
/// h Σ_j (a_{s,j} − a_{s−1,j}) k_j, so no stage state need be kept.
fn stability_limited(tab: &ButcherTableau, k: &[Vec<f64>], limit: f64) -> bool {
    let s = tab.stages();
    let (last, before) = (tab.a[s - 1], tab.a[s - 2]);
    let (mut num, mut den) = (0.0, 0.0);
    for m in 0..k[0].len() {
        let df = k[s - 1][m] - k[s - 2][m];
        let mut dx = 0.0;
        for (j, kj) in k.iter().enumerate().take(s - 1) {
            let aj = last[j] - before.get(j).copied().unwrap_or(0.0);
            dx += aj * kj[m];
        }
        num += df * df;
        den += dx * dx;
    }
    // h·|λ| ≈ h ‖Δf‖ / ‖h Δx'‖ = ‖Δf‖ / ‖Δx'‖ with Δx' = Σ_j (a_{s,j} − a_{s−1,j}) k_j
    den > 0.0 && num > limit * limit * den
}

pub(crate) struct ErkWork {
    tab: &'static ButcherTableau,
    dense_d: Option<&'static [f64; 7]>,
    /// Error control on (adaptive) or off (fixed step).
    adaptive: bool,
    /// Stage derivatives k_0 … k_{s−1}.
    k: Vec<Vec<f64>>,
    xs: Vec<f64>,
    x_new: Vec<f64>,
    err: Vec<f64>,
    /// h Σ d_i k_i of the last accepted step (Dormand–Prince dense output).
    dense5: Vec<f64>,
    /// Controller memory: error norm of the last accepted step.
    facold: f64,
    reject: bool,
    /// Accepted steps limited by stability since the last [`NON_STIFF_RESET`] consecutive
    /// steps that were not (see [`crate::Stats::stiff_from`]).
    stiff_run: usize,
    /// Consecutive accepted steps not limited by stability.
    non_stiff_run: usize,
}

impl ErkWork {
    pub(crate) fn new(tab: &'static ButcherTableau, adaptive: bool, n: usize) -> Self {
        let dense_d = if tab.fsal { tab.dense } else { None };
        Self {
            tab,
            dense_d,
            adaptive: adaptive && tab.e.is_some(),
            k: (0..tab.stages()).map(|_| vec![0.0; n]).collect(),
            xs: vec![0.0; n],
            x_new: vec![0.0; n],
            err: vec![0.0; n],
            dense5: vec![0.0; if dense_d.is_some() { n } else { 0 }],
            facold: 1e-4,
            reject: false,
            stiff_run: 0,
            non_stiff_run: 0,
        }
    }

    /// (address, capacity) of each buffer, for the no-reallocation test.
    #[cfg(test)]
    pub(crate) fn buffers(&self) -> Vec<(usize, usize)> {
        let mut v: Vec<(usize, usize)> = self
            .k
            .iter()
            .map(|b| (b.as_ptr() as usize, b.capacity()))
            .collect();
        for b in [&self.xs, &self.x_new, &self.err, &self.dense5] {
            v.push((b.as_ptr() as usize, b.capacity()));
        }
        v
    }

    pub(crate) fn reset(&mut self) {
        self.facold = 1e-4;
        self.reject = false;
        self.stiff_run = 0;
        self.non_stiff_run = 0;
    }

    pub(crate) fn dense(
        &self,
        theta: f64,
        h: f64,
        x0: &[f64],
        x1: &[f64],
        f0: &[f64],
        f1: &[f64],
        out: &mut [f64],
    ) {
        let th1 = 1.0 - theta;
        if self.dense_d.is_some() {
            for i in 0..out.len() {
                let d = x1[i] - x0[i];
                let b = h * f0[i] - d;
                let r4 = d - h * f1[i] - b;
                out[i] = x0[i] + theta * (d + th1 * (b + theta * (r4 + th1 * self.dense5[i])));
            }
        } else {
            // cubic Hermite interpolation
            for i in 0..out.len() {
                let d = x1[i] - x0[i];
                out[i] = x0[i]
                    + theta * d
                    + theta
                        * (theta - 1.0)
                        * ((1.0 - 2.0 * theta) * d + (theta - 1.0) * h * f0[i] + theta * h * f1[i]);
            }
        }
    }
}

impl Integrator {
    pub(crate) fn erk_step<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<(), StopReason> {
        // the end of this step's span: a breakpoint or the end of the run
        let (target, is_end) = self.span_end();
        let Work::Erk(w) = &mut self.work else {
            unreachable!("erk_step on a non-explicit method")
        };
        let tab = w.tab;
        let s = tab.stages();
        let n = self.n;
        if !self.f_valid {
            eval_rhs(sys, &mut self.stats, self.t, &self.x, &mut self.f, self.t)?;
            self.f_valid = true;
        }
        if self.h.is_nan() {
            let order = tab.embedded_order.max(1) + 1;
            self.h = initial_step(
                sys,
                &mut self.stats,
                self.t,
                &self.x,
                &self.f,
                &mut w.xs,
                &mut w.x_new,
                &self.atol_v,
                self.rtol,
                order,
                self.h_max,
                self.t_end - self.t,
            )?;
        }
        let t = self.t;
        // the last failed evaluation at a trial state of this step (adaptive only)
        let mut trial: Option<StopReason> = None;
        'attempt: loop {
            let (h, land) = clip_step(t, target, self.h_max, self.h);
            let last = land && is_end;
            if step_too_small(t, h) {
                return Err(trial.unwrap_or(StopReason::StepTooSmall { t, h }));
            }
            w.k[0].copy_from_slice(&self.f);
            // the stages and the new state; a failure at one of these trial states ends them
            let mut failed = None;
            for i in 1..s {
                let (done, rest) = w.k.split_at_mut(i);
                let a = tab.a[i];
                for m in 0..n {
                    let mut acc = 0.0;
                    for (j, aij) in a.iter().enumerate() {
                        acc += aij * done[j][m];
                    }
                    w.xs[m] = self.x[m] + h * acc;
                }
                let stage = eval_rhs(
                    sys,
                    &mut self.stats,
                    t + tab.c[i] * h,
                    &w.xs,
                    &mut rest[0],
                    t,
                );
                if let Err(e) = stage {
                    failed = Some(e);
                    break;
                }
            }
            if failed.is_none() {
                for m in 0..n {
                    let mut acc = 0.0;
                    for (j, bj) in tab.b.iter().enumerate() {
                        acc += bj * w.k[j][m];
                    }
                    w.x_new[m] = self.x[m] + h * acc;
                }
                failed = check_finite(&w.x_new, t).err();
            }
            if let Some(e) = failed {
                if !w.adaptive {
                    return Err(e);
                }
                // an overshoot of the trial step: reject it, retry shorter
                retry_shorter(
                    &mut self.stats,
                    &mut self.h,
                    h,
                    &mut w.reject,
                    &mut trial,
                    e,
                );
                continue 'attempt;
            }
            let mut h_next = self.h;
            if let (true, Some(e)) = (w.adaptive, tab.e) {
                for m in 0..n {
                    let mut acc = 0.0;
                    for (j, ej) in e.iter().enumerate() {
                        acc += ej * w.k[j][m];
                    }
                    w.err[m] = h * acc;
                }
                let err = wrms(&w.err, &self.x, &w.x_new, &self.atol_v, self.rtol);
                let expo = 1.0 / (tab.embedded_order as f64 + 1.0) - 0.75 * BETA;
                let fac11 = err.powf(expo);
                if err <= 1.0 {
                    let fac =
                        (fac11 / w.facold.powf(BETA) / SAFE).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
                    h_next = h / fac;
                    if w.reject {
                        h_next = h_next.min(h);
                    }
                    w.facold = err.max(1e-4);
                    w.reject = false;
                } else {
                    self.stats.rejected += 1;
                    w.reject = true;
                    self.h = h / (fac11 / SAFE).min(1.0 / FAC_MIN);
                    continue 'attempt;
                }
            }
            // accept
            if let Some(d) = w.dense_d {
                for m in 0..n {
                    let mut acc = 0.0;
                    for (j, dj) in d.iter().enumerate() {
                        acc += dj * w.k[j][m];
                    }
                    w.dense5[m] = h * acc;
                }
            }
            if let (true, Some(limit)) = (w.adaptive, tab.stiffness_limit) {
                if stability_limited(tab, &w.k, limit) {
                    self.stats.stability_limited += 1;
                    w.stiff_run += 1;
                    w.non_stiff_run = 0;
                    if w.stiff_run == STIFF_RUN && self.stats.stiff_from.is_none() {
                        self.stats.stiff_from = Some(t + h);
                    }
                } else {
                    w.non_stiff_run += 1;
                    if w.non_stiff_run == NON_STIFF_RESET {
                        w.stiff_run = 0;
                    }
                }
            }
            self.t_prev = t;
            self.x_prev.copy_from_slice(&self.x);
            self.f_prev.copy_from_slice(&self.f);
            self.x.copy_from_slice(&w.x_new);
            self.t = if land { target } else { t + h };
            self.stats.steps += 1;
            self.has_step = true;
            if !last {
                self.h = h_next;
            }
            self.finished = last;
            if tab.fsal {
                self.f.copy_from_slice(&w.k[s - 1]);
            } else {
                // f at the new point: next step's first stage and the Hermite end slope.
                let r = eval_rhs(sys, &mut self.stats, self.t, &self.x, &mut self.f, t);
                if r.is_err() {
                    self.f_valid = false;
                    return r;
                }
            }
            return Ok(());
        }
    }
}
