//! Radau IIA of order 5 (three-stage collocation at the right Radau points), after
//! E. Hairer & G. Wanner, *Solving ODEs II: Stiff and Differential-Algebraic Problems*,
//! 2nd ed., Springer 1996, §IV.8, and the structure of their Fortran code RADAU5.
//!
//! Simplified Newton: the 3n×3n iteration matrix is block-diagonalised with the
//! eigenvectors of A⁻¹ (matrices `T`, `TI`), leaving one real n×n system
//! `(γ/h I − J)` and one complex n×n system `((α + iβ)/h I − J)`, both factorised with
//! faer's in-place LU. The Jacobian `J` is a finite difference, kept across steps while
//! Newton converges fast, and the LU is kept while `h` does not change.

use faer::{Mat, c64};

use crate::integrator::{
    Integrator, Work, check_finite, clip_step, eval_rhs, initial_step, retry_shorter,
    step_too_small,
};
use crate::linalg::DenseLu;
use crate::{JacobianPattern, OdeSystem, StopReason};

/// √6
const SQ6: f64 = 2.449_489_742_783_178;
/// Collocation nodes c₁, c₂ (c₃ = 1).
pub(crate) const C1: f64 = (4.0 - SQ6) / 10.0;
pub(crate) const C2: f64 = (4.0 + SQ6) / 10.0;
/// Error-estimate weights (RADAU5's DD1..DD3): err = (γ/h I − J)⁻¹ (f₀ + Σ dd_i z_i / h).
pub(crate) const DD: [f64; 3] = [
    -(13.0 + 7.0 * SQ6) / 3.0,
    (-13.0 + 7.0 * SQ6) / 3.0,
    -1.0 / 3.0,
];
// RADAU5's published digits are kept as printed.
#[allow(clippy::excessive_precision)]
/// Eigenvector matrix T of A⁻¹ (T⁻¹ A⁻¹ T = [[γ,0,0],[0,α,−β],[0,β,α]]), RADAU5's values.
pub(crate) const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294_279_2e-2,
        -0.141_255_295_020_954_208_43,
        -3.002_919_410_514_742_449_2e-2,
    ],
    [
        0.241_717_932_707_107_018_96,
        0.204_129_352_293_799_931_99,
        0.382_942_112_757_261_937_79,
    ],
    [0.966_048_182_615_092_936_19, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
/// T⁻¹, RADAU5's values.
pub(crate) const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155_351_0,
        0.339_199_251_815_809_869_54,
        0.541_770_539_935_874_871_19,
    ],
    [
        -4.178_718_591_551_904_727_3,
        -0.327_682_820_761_062_387_08,
        0.476_623_554_500_550_451_96,
    ],
    [
        -0.502_872_634_945_786_875_95,
        2.571_926_949_855_605_429_2,
        -0.596_039_204_828_224_924_97,
    ],
];

/// Eigenvalues of A⁻¹: the real one γ and the complex pair α ± iβ.
pub(crate) fn eigenvalues() -> (f64, f64, f64) {
    let c81 = 81f64.cbrt();
    let c9 = 9f64.cbrt();
    let u1 = (6.0 + c81 - c9) / 30.0;
    let alph = (12.0 - c81 + c9) / 60.0;
    let beta = (c81 + c9) * 3f64.sqrt() / 60.0;
    let cno = alph * alph + beta * beta;
    (1.0 / u1, alph / cno, beta / cno)
}

/// Maximum Newton iterations per step (RADAU5's NIT).
const NIT: usize = 7;
/// Safety factor of the step-size controller.
const SAFE: f64 = 0.9;
/// Bounds of h / h_new: h_new ∈ [h/5, 8h].
const FACL: f64 = 5.0;
const FACR: f64 = 1.0 / 8.0;
/// Keep h (and the LU) when the proposed ratio h_new/h is in [QUOT1, QUOT2].
const QUOT1: f64 = 1.0;
const QUOT2: f64 = 1.2;
/// Consecutive singular iteration matrices tolerated before giving up.
const MAX_SINGULAR: usize = 5;

pub(crate) struct RadauWork {
    gamma: f64,
    alpha: f64,
    beta: f64,
    /// Jacobian reuse threshold on the Newton contraction rate.
    thet: f64,
    /// Fixed step, no error test.
    fixed: bool,
    jac: Mat<f64>,
    e1: DenseLu<f64>,
    e2: DenseLu<c64>,
    /// Stage increments Z_i = Y_i − x.
    z: [Vec<f64>; 3],
    /// Transformed increments W = T⁻¹ Z.
    w: [Vec<f64>; 3],
    /// Stage derivatives f(t + c_i h, x + Z_i).
    g: [Vec<f64>; 3],
    dw1: Vec<f64>,
    dw23: Vec<c64>,
    xs: Vec<f64>,
    scal: Vec<f64>,
    err: Vec<f64>,
    err_f: Vec<f64>,
    /// Z of the last accepted step: the collocation polynomial for dense output and
    /// Newton starting values.
    cont: [Vec<f64>; 3],
    has_cont: bool,
    need_jac: bool,
    jac_fresh: bool,
    h_lu: f64,
    first: bool,
    reject: bool,
    theta: f64,
    faccon: f64,
    hold: f64,
    hacc: f64,
    erracc: f64,
    nsing: usize,
    fnewt: f64,
    /// The system's Jacobian pattern (dense if it declares none) and its column groups, set by
    /// `start`.
    pattern: JacobianPattern,
    groups: Vec<Vec<usize>>,
    /// Each column's difference step, as represented in floating point.
    delta: Vec<f64>,
}

/// Lagrange basis at nodes {0, c₁, c₂, 1}, without the node 0 (where Z = 0).
fn lagrange(theta: f64) -> [f64; 3] {
    let nodes = [0.0, C1, C2, 1.0];
    let mut l = [0.0; 3];
    for (k, lk) in l.iter_mut().enumerate() {
        let tk = nodes[k + 1];
        let mut p = 1.0;
        for (m, &tm) in nodes.iter().enumerate() {
            if m != k + 1 {
                p *= (theta - tm) / (tk - tm);
            }
        }
        *lk = p;
    }
    l
}

impl RadauWork {
    pub(crate) fn new(n: usize, thet: f64, fixed: bool) -> Self {
        let (gamma, alpha, beta) = eigenvalues();
        let v = || [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        Self {
            gamma,
            alpha,
            beta,
            thet,
            fixed,
            jac: Mat::zeros(n, n),
            e1: DenseLu::new(n),
            e2: DenseLu::new(n),
            z: v(),
            w: v(),
            g: v(),
            dw1: vec![0.0; n],
            dw23: vec![c64::new(0.0, 0.0); n],
            xs: vec![0.0; n],
            scal: vec![0.0; n],
            err: vec![0.0; n],
            err_f: vec![0.0; n],
            cont: v(),
            has_cont: false,
            need_jac: true,
            jac_fresh: false,
            h_lu: f64::NAN,
            first: true,
            reject: false,
            theta: 0.0,
            faccon: 1.0,
            hold: f64::NAN,
            hacc: f64::NAN,
            erracc: 1e-2,
            nsing: 0,
            fnewt: 0.03,
            pattern: JacobianPattern::new(0),
            groups: Vec::new(),
            delta: vec![0.0; n],
        }
    }

    /// Takes the system's Jacobian pattern for this run (`None`: dense, one column per group)
    /// and zeroes the Jacobian, whose entries outside the pattern are never written.
    pub(crate) fn set_pattern(&mut self, pattern: Option<JacobianPattern>) {
        let n = self.jac.nrows();
        self.pattern = pattern.unwrap_or_else(|| JacobianPattern::dense(n));
        self.groups = self.pattern.column_groups();
        for j in 0..n {
            for i in 0..n {
                self.jac[(i, j)] = 0.0;
            }
        }
    }

    /// (address, capacity) of each buffer, for the no-reallocation test.
    #[cfg(test)]
    pub(crate) fn buffers(&self) -> Vec<(usize, usize)> {
        let p = |b: &Vec<f64>| (b.as_ptr() as usize, b.capacity());
        let mut v: Vec<(usize, usize)> = vec![];
        for arr in [&self.z, &self.w, &self.g, &self.cont] {
            v.extend(arr.iter().map(p));
        }
        for b in [
            &self.dw1,
            &self.xs,
            &self.scal,
            &self.err,
            &self.err_f,
            &self.delta,
        ] {
            v.push(p(b));
        }
        v.push((self.dw23.as_ptr() as usize, self.dw23.capacity()));
        v.push((self.jac.as_ptr() as usize, self.jac.nrows()));
        v.push((self.e1.a.as_ptr() as usize, self.e1.a.nrows()));
        v.push((self.e2.a.as_ptr() as usize, self.e2.a.nrows()));
        v
    }

    /// Resets the run state; `rtol` is the transformed relative tolerance.
    pub(crate) fn reset(&mut self, rtol: f64) {
        self.has_cont = false;
        self.need_jac = true;
        self.jac_fresh = false;
        self.h_lu = f64::NAN;
        self.first = true;
        self.reject = false;
        self.theta = self.thet.abs();
        self.faccon = 1.0;
        self.hold = f64::NAN;
        self.hacc = f64::NAN;
        self.erracc = 1e-2;
        self.nsing = 0;
        self.fnewt = (10.0 * f64::EPSILON / rtol).max(0.03f64.min(rtol.sqrt()));
    }

    pub(crate) fn dense(&self, theta: f64, x0: &[f64], out: &mut [f64]) {
        let l = lagrange(theta);
        for i in 0..out.len() {
            out[i] =
                x0[i] + l[0] * self.cont[0][i] + l[1] * self.cont[1][i] + l[2] * self.cont[2][i];
        }
    }

    /// Builds and factorises both iteration matrices for step `h`. False if singular.
    fn factor(&mut self, h: f64) -> bool {
        let n = self.jac.nrows();
        let fac1 = self.gamma / h;
        let (alphn, betan) = (self.alpha / h, self.beta / h);
        for j in 0..n {
            for i in 0..n {
                let jij = self.jac[(i, j)];
                let d = if i == j { 1.0 } else { 0.0 };
                self.e1.a[(i, j)] = d * fac1 - jij;
                self.e2.a[(i, j)] = c64::new(d * alphn - jij, d * betan);
            }
        }
        self.e1.factor() && self.e2.factor()
    }
}

enum Newton {
    Converged(usize),
    /// Converging, but too slowly for the step: retry with h multiplied by this.
    Slow(f64),
    Diverged,
    /// The right-hand side failed (or was not finite) at an iterate: retry with a shorter step.
    TrialFailed(StopReason),
}

impl Integrator {
    pub(crate) fn radau_step<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
    ) -> Result<(), StopReason> {
        // the end of this step's span: a breakpoint or the end of the run
        let (target, is_end) = self.span_end();
        let Work::Radau(w) = &mut self.work else {
            unreachable!("radau_step on another method")
        };
        let w = &mut **w;
        let n = self.n;
        let t = self.t;
        let rtol = self.rtol;
        if !self.f_valid {
            eval_rhs(sys, &mut self.stats, t, &self.x, &mut self.f, t)?;
            self.f_valid = true;
        }
        if self.h.is_nan() {
            self.h = initial_step(
                sys,
                &mut self.stats,
                t,
                &self.x,
                &self.f,
                &mut w.xs,
                &mut w.err,
                &self.atol_v,
                rtol,
                5,
                self.h_max,
                self.t_end - t,
            )?;
        }
        for i in 0..n {
            w.scal[i] = self.atol_v[i] + rtol * self.x[i].abs();
        }
        // the last failed evaluation at a trial state of this step
        let mut trial: Option<StopReason> = None;
        loop {
            let (h, land) = clip_step(t, target, self.h_max, self.h);
            let last = land && is_end;
            self.h = h;
            if step_too_small(t, h) {
                return Err(trial.unwrap_or(StopReason::StepTooSmall { t, h }));
            }
            if w.need_jac {
                self.stats.jacobians += 1;
                // Forward differences with the step sqrt(eps)·max(|x_j|, atol_j/rtol): the
                // component's own scale where it is at 0 (RADAU5 takes sqrt(eps·max(1e-5,
                // |x_j|)) instead, an absolute floor of 4.7e-11 that, tried here in stop 39,
                // took Robertson's problem, whose y2 is 1e-13 late, from 1 to 83 Newton
                // failures). At a tolerance ratio atol/rtol far below the component's scale
                // (1e-13 gives a step of 1.5e-21) the differences are round-off and the
                // Newton iteration slows; the converged solution does not depend on the
                // Jacobian. The columns of a group share no row and are perturbed together
                // (Curtis, Powell & Reid 1974; crate::sparsity; without a pattern, one column
                // per group).
                for cols in &w.groups {
                    w.xs.copy_from_slice(&self.x);
                    for &j in cols {
                        let xj = self.x[j];
                        let typical = self.atol_v[j] / rtol;
                        w.xs[j] = xj + f64::EPSILON.sqrt() * xj.abs().max(typical);
                        w.delta[j] = w.xs[j] - xj;
                    }
                    eval_rhs(sys, &mut self.stats, t, &w.xs, &mut w.err, t)?;
                    self.stats.jacobian_rhs_evals += 1;
                    for &j in cols {
                        for &i in w.pattern.rows(j) {
                            w.jac[(i, j)] = (w.err[i] - self.f[i]) / w.delta[j];
                        }
                    }
                }
                w.need_jac = false;
                w.jac_fresh = true;
                w.h_lu = f64::NAN;
            }
            if w.h_lu != h {
                self.stats.lu_factorizations += 1;
                if !w.factor(h) {
                    w.h_lu = f64::NAN;
                    w.nsing += 1;
                    if w.nsing >= MAX_SINGULAR {
                        return Err(StopReason::SingularMatrix { t });
                    }
                    // RADAU5 (label 78): halve the step, and take a new Jacobian unless it is
                    // fresh (a stale one may be what made the matrix singular)
                    self.h *= 0.5;
                    w.reject = true;
                    if !w.jac_fresh {
                        w.need_jac = true;
                    }
                    continue;
                }
                w.h_lu = h;
                w.nsing = 0;
            }

            // Starting values: extrapolated collocation polynomial of the last step.
            if w.first || !w.has_cont {
                for k in 0..3 {
                    w.z[k].fill(0.0);
                    w.w[k].fill(0.0);
                }
            } else {
                let r = h / w.hold;
                let ls = [
                    lagrange(1.0 + C1 * r),
                    lagrange(1.0 + C2 * r),
                    lagrange(1.0 + r),
                ];
                for i in 0..n {
                    let c = [w.cont[0][i], w.cont[1][i], w.cont[2][i]];
                    let mut zi = [0.0; 3];
                    for k in 0..3 {
                        zi[k] = ls[k][0] * c[0] + ls[k][1] * c[1] + ls[k][2] * c[2] - c[2];
                        w.z[k][i] = zi[k];
                    }
                    for k in 0..3 {
                        w.w[k][i] = TI[k][0] * zi[0] + TI[k][1] * zi[1] + TI[k][2] * zi[2];
                    }
                }
            }

            // Simplified Newton iteration.
            w.faccon = w.faccon.max(f64::EPSILON).powf(0.8);
            w.theta = w.thet.abs();
            let fac1 = w.gamma / h;
            let (alphn, betan) = (w.alpha / h, w.beta / h);
            let c = [C1, C2, 1.0];
            let mut dynold = 0.0;
            let mut thqold = 0.0;
            let mut newt = 0;
            let outcome = 'newton: loop {
                if newt >= NIT {
                    break Newton::Diverged;
                }
                for k in 0..3 {
                    for i in 0..n {
                        w.xs[i] = self.x[i] + w.z[k][i];
                    }
                    // a Newton iterate the system cannot evaluate: retry shorter
                    if let Err(e) =
                        eval_rhs(sys, &mut self.stats, t + c[k] * h, &w.xs, &mut w.g[k], t)
                    {
                        break 'newton Newton::TrialFailed(e);
                    }
                }
                for i in 0..n {
                    let g = [w.g[0][i], w.g[1][i], w.g[2][i]];
                    let tg = |k: usize| TI[k][0] * g[0] + TI[k][1] * g[1] + TI[k][2] * g[2];
                    let (w1, w2, w3) = (w.w[0][i], w.w[1][i], w.w[2][i]);
                    w.dw1[i] = tg(0) - fac1 * w1;
                    w.dw23[i] = c64::new(
                        tg(1) - alphn * w2 + betan * w3,
                        tg(2) - betan * w2 - alphn * w3,
                    );
                }
                w.e1.solve(&mut w.dw1);
                w.e2.solve(&mut w.dw23);
                newt += 1;
                self.stats.newton_iterations += 1;
                let mut s = 0.0;
                for i in 0..n {
                    let sc = w.scal[i];
                    s += (w.dw1[i] / sc).powi(2)
                        + (w.dw23[i].re / sc).powi(2)
                        + (w.dw23[i].im / sc).powi(2);
                }
                let dyno = (s / (3 * n) as f64).sqrt();
                if !dyno.is_finite() {
                    break Newton::Diverged;
                }
                if newt > 1 && newt < NIT {
                    let thq = dyno / dynold;
                    w.theta = if newt == 2 {
                        thq
                    } else {
                        (thq * thqold).sqrt()
                    };
                    thqold = thq;
                    if w.theta < 0.99 {
                        w.faccon = w.theta / (1.0 - w.theta);
                        let dyth =
                            w.faccon * dyno * w.theta.powi((NIT - 1 - newt) as i32) / w.fnewt;
                        if dyth >= 1.0 && !w.fixed {
                            let qnewt = dyth.clamp(1e-4, 20.0);
                            let hhfac = 0.8 * qnewt.powf(-1.0 / (4.0 + (NIT - 1 - newt) as f64));
                            break Newton::Slow(hhfac);
                        }
                    } else {
                        break Newton::Diverged;
                    }
                }
                dynold = dyno.max(f64::EPSILON);
                for i in 0..n {
                    w.w[0][i] += w.dw1[i];
                    w.w[1][i] += w.dw23[i].re;
                    w.w[2][i] += w.dw23[i].im;
                    let ww = [w.w[0][i], w.w[1][i], w.w[2][i]];
                    for k in 0..3 {
                        w.z[k][i] = T[k][0] * ww[0] + T[k][1] * ww[1] + T[k][2] * ww[2];
                    }
                }
                if w.faccon * dyno <= w.fnewt {
                    break Newton::Converged(newt);
                }
            };
            let newt = match outcome {
                Newton::Converged(k) => k,
                Newton::TrialFailed(e) => {
                    if w.fixed {
                        return Err(e);
                    }
                    retry_shorter(
                        &mut self.stats,
                        &mut self.h,
                        h,
                        &mut w.reject,
                        &mut trial,
                        e,
                    );
                    continue;
                }
                Newton::Slow(hhfac) => {
                    // Hairer & Wanner's RADAU5: a shorter step, with a new Jacobian unless the
                    // one in use is fresh (only the iteration matrices are then refactored).
                    self.stats.newton_failures += 1;
                    w.reject = true;
                    self.h *= hhfac;
                    if !w.jac_fresh {
                        w.need_jac = true;
                    }
                    continue;
                }
                Newton::Diverged => {
                    self.stats.newton_failures += 1;
                    if w.fixed {
                        if w.jac_fresh {
                            return Err(StopReason::NewtonFailed { t, h });
                        }
                        w.need_jac = true;
                        continue;
                    }
                    w.reject = true;
                    self.h *= 0.5;
                    if !w.jac_fresh {
                        w.need_jac = true;
                    }
                    continue;
                }
            };

            // Error estimate (Hairer & Wanner §IV.8, eq. (8.19)–(8.20)).
            let (err, mut hnew, mut quot) = if w.fixed {
                (0.0, h, 1.0)
            } else {
                let hee = [DD[0] / h, DD[1] / h, DD[2] / h];
                for i in 0..n {
                    w.err_f[i] = hee[0] * w.z[0][i] + hee[1] * w.z[1][i] + hee[2] * w.z[2][i];
                    w.err[i] = self.f[i] + w.err_f[i];
                    // error scale: atol + rtol max(|x|, |x_new|)
                    w.xs[i] = self.x[i] + w.z[2][i];
                }
                w.e1.solve(&mut w.err);
                let mut err = crate::integrator::wrms(&w.err, &self.x, &w.xs, &self.atol_v, rtol);
                if err >= 1.0 && (w.first || w.reject) {
                    // Filtered estimate for stiff components (one more f and solve).
                    for i in 0..n {
                        w.xs[i] = self.x[i] + w.err[i];
                    }
                    if let Err(e) = eval_rhs(sys, &mut self.stats, t, &w.xs, &mut w.g[0], t) {
                        retry_shorter(
                            &mut self.stats,
                            &mut self.h,
                            h,
                            &mut w.reject,
                            &mut trial,
                            e,
                        );
                        continue;
                    }
                    for i in 0..n {
                        w.err[i] = w.g[0][i] + w.err_f[i];
                        w.xs[i] = self.x[i] + w.z[2][i];
                    }
                    w.e1.solve(&mut w.err);
                    err = crate::integrator::wrms(&w.err, &self.x, &w.xs, &self.atol_v, rtol);
                }
                // A non-finite estimate comes from a trial state the model cannot evaluate: an
                // overshoot, retried shorter like the other trial failures. (A finite estimate
                // whose norm overflows is an ordinary rejection, by the largest factor.)
                if let Err(e) = check_finite(&w.err, t) {
                    retry_shorter(
                        &mut self.stats,
                        &mut self.h,
                        h,
                        &mut w.reject,
                        &mut trial,
                        e,
                    );
                    continue;
                }
                let err = err.max(1e-10);
                let fac =
                    SAFE.min(SAFE * (1.0 + 2.0 * NIT as f64) / (newt as f64 + 2.0 * NIT as f64));
                let quot = (err.powf(0.25) / fac).clamp(FACR, FACL);
                let hnew = h / quot;
                (err, hnew, quot)
            };
            if err < 1.0 {
                // Accepted. Gustafsson's predictive controller.
                if !w.fixed && !w.first && w.hacc.is_finite() {
                    let facgus =
                        ((w.hacc / h) * (err * err / w.erracc).powf(0.25) / SAFE).clamp(FACR, FACL);
                    quot = quot.max(facgus);
                    hnew = h / quot;
                }
                w.hacc = h;
                w.erracc = err.max(1e-2);
                for i in 0..n {
                    w.xs[i] = self.x[i] + w.z[2][i];
                }
                match check_finite(&w.xs, t) {
                    Ok(()) => {}
                    Err(e) if !w.fixed => {
                        retry_shorter(
                            &mut self.stats,
                            &mut self.h,
                            h,
                            &mut w.reject,
                            &mut trial,
                            e,
                        );
                        continue;
                    }
                    Err(e) => return Err(e),
                }
                w.first = false;
                self.t_prev = t;
                self.x_prev.copy_from_slice(&self.x);
                self.f_prev.copy_from_slice(&self.f);
                self.x.copy_from_slice(&w.xs);
                for k in 0..3 {
                    w.cont[k].copy_from_slice(&w.z[k]);
                }
                w.has_cont = true;
                w.hold = h;
                self.t = if land { target } else { t + h };
                self.stats.steps += 1;
                self.has_step = true;
                self.finished = last;
                w.jac_fresh = false;
                hnew = hnew.min(self.h_max);
                if w.reject {
                    hnew = hnew.min(h);
                }
                w.reject = false;
                let qt = hnew / h;
                if w.fixed {
                    // keep h and J; J is refreshed only when Newton fails
                } else if !(w.theta <= w.thet && (QUOT1..=QUOT2).contains(&qt)) {
                    self.h = hnew;
                    if w.theta > w.thet {
                        w.need_jac = true;
                    }
                }
                let r = eval_rhs(sys, &mut self.stats, self.t, &self.x, &mut self.f, t);
                if r.is_err() {
                    self.f_valid = false;
                    return r;
                }
                return Ok(());
            }
            // Rejected by the error test.
            self.stats.rejected += 1;
            w.reject = true;
            self.h = if w.first { 0.1 * h } else { hnew };
            if !w.jac_fresh {
                w.need_jac = true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Butcher matrix of Radau IIA, order 5 (Hairer & Wanner II, Table IV.5.6).
    fn radau_a() -> [[f64; 3]; 3] {
        [
            [
                (88.0 - 7.0 * SQ6) / 360.0,
                (296.0 - 169.0 * SQ6) / 1800.0,
                (-2.0 + 3.0 * SQ6) / 225.0,
            ],
            [
                (296.0 + 169.0 * SQ6) / 1800.0,
                (88.0 + 7.0 * SQ6) / 360.0,
                (-2.0 - 3.0 * SQ6) / 225.0,
            ],
            [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0],
        ]
    }

    fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    }

    #[test]
    fn sqrt6_constant() {
        assert!((SQ6 - 6f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn transformation_diagonalises_a_inverse() {
        let ti_t = mul(&TI, &T);
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (ti_t[i][j] - e).abs() < 1e-14,
                    "TI T [{i}][{j}] = {}",
                    ti_t[i][j]
                );
            }
        }
        // TI A⁻¹ T = Λ  ⇔  A T Λ = T
        let (g, a, b) = eigenvalues();
        let lam = [[g, 0.0, 0.0], [0.0, a, -b], [0.0, b, a]];
        let at_l = mul(&mul(&radau_a(), &T), &lam);
        for i in 0..3 {
            for j in 0..3 {
                assert!(
                    (at_l[i][j] - T[i][j]).abs() < 1e-13,
                    "A T Λ [{i}][{j}]: {} vs {}",
                    at_l[i][j],
                    T[i][j]
                );
            }
        }
    }

    #[test]
    fn collocation_rows_sum_to_nodes_and_error_weights_are_consistent() {
        let a = radau_a();
        for (i, c) in [C1, C2, 1.0].iter().enumerate() {
            assert!((a[i].iter().sum::<f64>() - c).abs() < 1e-15);
        }
        // The estimate γ₀ h f₀ + γ₀ Σ dd_i z_i vanishes for x' = 1, 2t, 3t².
        let cs = [C1, C2, 1.0];
        let m = |k: i32| (0..3).map(|i| DD[i] * cs[i].powi(k)).sum::<f64>();
        assert!((m(1) + 1.0).abs() < 1e-14);
        assert!(m(2).abs() < 1e-13);
        assert!(m(3).abs() < 1e-13);
        assert!(m(4).abs() > 1e-3, "estimate must see the t^4 term");
    }

    #[test]
    fn lagrange_basis_interpolates() {
        let l = lagrange(C1);
        assert!((l[0] - 1.0).abs() < 1e-14 && l[1].abs() < 1e-14 && l[2].abs() < 1e-14);
        let l = lagrange(1.0);
        assert!(l[0].abs() < 1e-14 && l[1].abs() < 1e-14 && (l[2] - 1.0).abs() < 1e-14);
        assert!(lagrange(0.0).iter().all(|v| v.abs() < 1e-15));
    }
}
