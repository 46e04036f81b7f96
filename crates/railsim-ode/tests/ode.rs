//! Integration tests of railsim-ode on problems with known solutions: harmonic
//! oscillator, observed orders of convergence, stiff Van der Pol, Robertson kinetics,
//! failure reporting and bad input. The numbers quoted in docs/models/ode.md are
//! printed by these tests (`cargo test -p railsim-ode -- --nocapture`).

use std::f64::consts::PI;
use std::ops::ControlFlow;

use railsim_ode::linear::jacobian;
use railsim_ode::tableau::{BS3, DOPRI5, RK4};
use railsim_ode::{
    Integrator, JacobianPattern, Method, OdeError, OdeSystem, RhsError, Stats, StepOutcome,
    StopReason,
};

fn go(_: f64, _: &[f64]) -> ControlFlow<()> {
    ControlFlow::Continue(())
}

/// x'' = −ω² x, x(0) = 1, x'(0) = 0: x = cos ωt.
struct Oscillator {
    w: f64,
}

impl OdeSystem for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError> {
        dxdt[0] = x[1];
        dxdt[1] = -self.w * self.w * x[0];
        Ok(())
    }
}

impl Oscillator {
    fn exact(&self, t: f64) -> [f64; 2] {
        [(self.w * t).cos(), -self.w * (self.w * t).sin()]
    }
    fn energy(&self, x: &[f64]) -> f64 {
        0.5 * x[1] * x[1] + 0.5 * self.w * self.w * x[0] * x[0]
    }
}

/// Van der Pol in its classical form x'' − μ (1 − x²) x' + x = 0:
/// y1' = y2, y2' = μ (1 − y1²) y2 − y1. Relaxation oscillation of period
/// ≈ (3 − 2 ln 2) μ for large μ.
struct VanDerPol {
    mu: f64,
}

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        d[0] = y[1];
        d[1] = self.mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
        Ok(())
    }
}

/// Robertson's chemical kinetics (Hairer & Wanner II, §IV.1).
struct Robertson;

impl OdeSystem for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        d[0] = -r1 + r2;
        d[1] = r1 - r2 - r3;
        d[2] = r3;
        Ok(())
    }
    /// y2 stays below 4e-5: its absolute tolerance is 1e-4 of the others.
    fn abs_tol_scale(&self, i: usize) -> f64 {
        if i == 1 { 1e-4 } else { 1.0 }
    }
}

/// A list of numbers in scientific notation.
fn fmt_e(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", s.join(", "))
}

/// Least-squares slope of log(err) against log(h).
fn slope(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let lx: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

fn run(
    method: Method,
    sys: &mut impl OdeSystem,
    t0: f64,
    x0: &[f64],
    t_end: f64,
) -> (Vec<f64>, StopReason, Stats) {
    let mut integ = Integrator::new(method, sys.dim()).unwrap();
    let mut x = x0.to_vec();
    let (r, s) = integ.integrate(sys, t0, &mut x, t_end, &mut go).unwrap();
    (x, r, s)
}

fn osc_error(method: Method, t_end: f64) -> (f64, Stats) {
    let mut sys = Oscillator { w: 2.0 };
    let (x, r, s) = run(method, &mut sys, 0.0, &[1.0, 0.0], t_end);
    assert_eq!(r, StopReason::Reached);
    let ex = sys.exact(t_end);
    ((x[0] - ex[0]).abs().max((x[1] - ex[1]).abs() / sys.w), s)
}

// ---------------------------------------------------------------- oscillator

#[test]
fn oscillator_rk4_error_energy_and_counters() {
    let sys = Oscillator { w: 2.0 };
    let t_end = 10.0 * PI; // ten periods
    let (err, stats) = osc_error(Method::Rk4 { h: 0.01 }, t_end);
    eprintln!("RK4 h=0.01 over 10 periods: error {err:.3e}, {stats:?}");
    assert!(err < 1e-6, "error {err}");
    assert_eq!(stats.steps, (t_end / 0.01).round() as usize);
    assert_eq!(stats.rhs_evals, 4 * stats.steps + 1);
    assert_eq!(stats.rejected, 0);
    // energy drift: RK4 is dissipative, drift ~ (ωh)^4 t ω/ 72 per unit energy
    let mut integ = Integrator::new(Method::Rk4 { h: 0.01 }, 2).unwrap();
    let mut x = [1.0, 0.0];
    let e0 = sys.energy(&x);
    let mut max_drift: f64 = 0.0;
    let mut s2 = Oscillator { w: 2.0 };
    integ
        .integrate(&mut s2, 0.0, &mut x, t_end, &mut |_, x| {
            max_drift = max_drift.max((sys.energy(x) - e0).abs() / e0);
            ControlFlow::Continue(())
        })
        .unwrap();
    eprintln!("RK4 h=0.01 relative energy drift over 10 periods: {max_drift:.3e}");
    assert!(max_drift < 1e-6 && max_drift > 0.0);
}

#[test]
fn oscillator_dopri_error_and_energy() {
    let t_end = 10.0 * PI;
    for (rtol, bound) in [(1e-6, 1e-4), (1e-9, 1e-7), (1e-12, 1e-10)] {
        let (err, stats) = osc_error(Method::dormand_prince(rtol, rtol), t_end);
        eprintln!("DOPRI5 rtol=atol={rtol:e}: error {err:.3e}, {stats:?}");
        assert!(err < bound, "rtol {rtol}: error {err}");
        // FSAL bookkeeping: 1 (f0) + 1 (initial step) + 6 per attempt
        assert_eq!(stats.rhs_evals, 2 + 6 * (stats.steps + stats.rejected));
    }
    let sys = Oscillator { w: 2.0 };
    let mut s2 = Oscillator { w: 2.0 };
    let mut integ = Integrator::new(Method::dormand_prince(1e-10, 1e-10), 2).unwrap();
    let mut x = [1.0, 0.0];
    let e0 = sys.energy(&x);
    let mut max_drift: f64 = 0.0;
    integ
        .integrate(&mut s2, 0.0, &mut x, t_end, &mut |_, x| {
            max_drift = max_drift.max((sys.energy(x) - e0).abs() / e0);
            ControlFlow::Continue(())
        })
        .unwrap();
    eprintln!("DOPRI5 tol 1e-10 relative energy drift over 10 periods: {max_drift:.3e}");
    assert!(max_drift < 1e-8);
}

#[test]
fn dopri_error_tracks_tolerance() {
    // Global error ∝ tol^k with k ≈ 1 for DOPRI5 (local extrapolation: h ∝ tol^(1/5),
    // error of the 5th-order solution ∝ h^5).
    let tols = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    let errs: Vec<f64> = tols
        .iter()
        .map(|&t| osc_error(Method::dormand_prince(t, t), 10.0).0)
        .collect();
    let k = slope(&tols, &errs);
    eprintln!(
        "DOPRI5 error vs tolerance: {}, exponent {k:.3}",
        fmt_e(&errs)
    );
    assert!((0.8..1.2).contains(&k), "exponent {k}");
}

// ---------------------------------------------------------------- orders

#[test]
fn observed_order_rk4() {
    let hs = [0.1, 0.05, 0.025, 0.0125];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| osc_error(Method::Rk4 { h }, 4.0).0)
        .collect();
    let p = slope(&hs, &errs);
    eprintln!("RK4 errors {}, observed order {p:.3}", fmt_e(&errs));
    assert!((p - 4.0).abs() < 0.2, "order {p}");
}

#[test]
fn observed_order_dopri5_fixed_step() {
    let hs = [0.2, 0.1, 0.05, 0.025];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| {
            osc_error(
                Method::ExplicitFixed {
                    tableau: &DOPRI5,
                    h,
                },
                4.0,
            )
            .0
        })
        .collect();
    let p = slope(&hs, &errs);
    eprintln!(
        "DOPRI5 fixed-step errors {}, observed order {p:.3}",
        fmt_e(&errs)
    );
    assert!((p - 5.0).abs() < 0.2, "order {p}");
    // the generic fixed-step driver reproduces Method::Rk4 exactly
    let a = osc_error(
        Method::ExplicitFixed {
            tableau: &RK4,
            h: 0.05,
        },
        4.0,
    )
    .0;
    let b = osc_error(Method::Rk4 { h: 0.05 }, 4.0).0;
    assert_eq!(a, b);
}

#[test]
fn observed_order_radau5_fixed_step() {
    let hs = [0.4, 0.2, 0.1, 0.05];
    let mut errs = vec![];
    for &h in &hs {
        let (e, s) = osc_error(
            Method::Radau5Fixed {
                h,
                rtol: 1e-12,
                atol: 1e-12,
            },
            4.0,
        );
        assert!(s.jacobians <= 2, "{s:?}");
        errs.push(e);
    }
    let p = slope(&hs, &errs);
    eprintln!(
        "Radau5 fixed-step errors {}, observed order {p:.3}",
        fmt_e(&errs)
    );
    assert!((p - 5.0).abs() < 0.3, "order {p}");
}

/// Dense-output error at the midpoints of fixed steps, against the exact solution.
fn dense_error(method: Method, h: f64) -> f64 {
    let sys = Oscillator { w: 2.0 };
    let mut s2 = Oscillator { w: 2.0 };
    let t_end = 4.0;
    let times: Vec<f64> = (0..(t_end / h).round() as usize)
        .map(|k| (k as f64 + 0.5) * h)
        .collect();
    let mut integ = Integrator::new(method, 2).unwrap();
    let mut x = [1.0, 0.0];
    let mut worst: f64 = 0.0;
    let mut count = 0;
    let (r, _) = integ
        .integrate_at(&mut s2, 0.0, &mut x, &times, &mut |t, x| {
            worst = worst.max((x[0] - sys.exact(t)[0]).abs());
            count += 1;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(r, StopReason::Reached);
    assert_eq!(count, times.len());
    worst
}

#[test]
fn observed_order_dopri5_dense_output() {
    // DOPRI5 with h0 = h_max = h and a huge tolerance takes fixed steps; at mid-step
    // the interpolant's own error O(h^5) adds to the global error O(h^5) of the steps.
    let hs = [0.2, 0.1, 0.05, 0.025];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| {
            dense_error(
                Method::DormandPrince {
                    rtol: 1e3,
                    atol: 1e3,
                    h0: Some(h),
                    h_max: h,
                },
                h,
            )
        })
        .collect();
    let p = slope(&hs, &errs);
    eprintln!(
        "DOPRI5 dense output at mid-step: errors {}, observed order {p:.3}",
        fmt_e(&errs)
    );
    assert!(
        (p - 5.0).abs() < 0.3,
        "dense output order {p} (local error exponent)"
    );
    // One step of the nonlinear x' = 1 + x², x = tan t, isolates the interpolant: its
    // local error is O(h^5) (continuous extension of order 4), against O(h^6) at the
    // step end. (On the linear oscillator the interpolant happens to be O(h^6).)
    struct Tan;
    impl OdeSystem for Tan {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            d[0] = 1.0 + x[0] * x[0];
            Ok(())
        }
    }
    let hs1 = [0.4, 0.2, 0.1, 0.05];
    let (mut mid, mut end) = (vec![], vec![]);
    for &h in &hs1 {
        let m = Method::DormandPrince {
            rtol: 1e3,
            atol: 1e3,
            h0: Some(h),
            h_max: h,
        };
        let mut integ = Integrator::new(m, 1).unwrap();
        integ.start(&Tan, 0.0, &[0.0], h).unwrap();
        assert!(matches!(integ.step(&mut Tan), StepOutcome::Accepted { .. }));
        let mut out = [0.0];
        integ.dense(0.5 * h, &mut out).unwrap();
        mid.push((out[0] - (0.5 * h).tan()).abs());
        end.push((integ.x()[0] - h.tan()).abs());
    }
    let (pm, pe) = (slope(&hs1, &mid), slope(&hs1, &end));
    eprintln!(
        "DOPRI5 one step of x' = 1 + x^2: dense error at h/2 {}, exponent {pm:.3}; step-end error {}, exponent {pe:.3}",
        fmt_e(&mid),
        fmt_e(&end)
    );
    assert!((pm - 5.0).abs() < 0.3, "dense local exponent {pm}");
    assert!(pe > 5.7, "step local exponent {pe}");
    // RK4's cubic Hermite output: local error O(h^4)
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| dense_error(Method::Rk4 { h }, h))
        .collect();
    let p = slope(&hs, &errs);
    eprintln!(
        "RK4 Hermite dense output: errors {}, observed order {p:.3}",
        fmt_e(&errs)
    );
    assert!((p - 4.0).abs() < 0.3, "Hermite order {p}");
}

#[test]
fn dense_output_is_exact_at_the_step_ends_and_refuses_outside() {
    let mut sys = Oscillator { w: 2.0 };
    let mut integ = Integrator::new(Method::dormand_prince(1e-8, 1e-8), 2).unwrap();
    integ.start(&sys, 0.0, &[1.0, 0.0], 1.0).unwrap();
    let StepOutcome::Accepted { t } = integ.step(&mut sys) else {
        panic!("no step")
    };
    let mut out = [0.0; 2];
    integ.dense(t, &mut out).unwrap();
    assert_eq!(out, [integ.x()[0], integ.x()[1]]);
    integ.dense(0.0, &mut out).unwrap();
    assert_eq!(out, [1.0, 0.0]);
    assert!(matches!(
        integ.dense(t * 1.5, &mut out),
        Err(OdeError::DenseOutOfRange { .. })
    ));
    assert!(matches!(
        integ.dense(-0.1, &mut out),
        Err(OdeError::DenseOutOfRange { .. })
    ));
}

// ---------------------------------------------------------------- stiff problems

/// Times at which y1 crosses zero downwards, by linear interpolation between steps.
fn vdp_run(method: Method, mu: f64, t_end: f64) -> (Vec<f64>, Vec<f64>, StopReason, Stats) {
    let mut sys = VanDerPol { mu };
    let mut integ = Integrator::new(method, 2).unwrap();
    let mut x = [2.0, 0.0];
    let mut crossings = vec![];
    let mut last = (0.0, 2.0);
    let (r, s) = integ
        .integrate(&mut sys, 0.0, &mut x, t_end, &mut |t, y| {
            if last.1 > 0.0 && y[0] <= 0.0 {
                crossings.push(last.0 + (t - last.0) * last.1 / (last.1 - y[0]));
            }
            last = (t, y[0]);
            ControlFlow::Continue(())
        })
        .unwrap();
    (x.to_vec(), crossings, r, s)
}

#[test]
fn stiff_van_der_pol_radau5() {
    let mu = 1000.0;
    let (x_ref, _, r, s_ref) = vdp_run(Method::radau5(1e-11, 1e-11), mu, 3000.0);
    assert_eq!(r, StopReason::Reached);
    let (x, cross, r, s) = vdp_run(Method::radau5(1e-6, 1e-6), mu, 3000.0);
    assert_eq!(r, StopReason::Reached);
    let err = (x[0] - x_ref[0]).abs();
    eprintln!(
        "VdP mu=1000 y(3000): reference {x_ref:?} ({s_ref:?}); tol 1e-6 {x:?}, |dy1| {err:.2e}, {s:?}"
    );
    assert!(
        err < 1e-4 * x_ref[0].abs().max(1.0),
        "y1 {} vs {}",
        x[0],
        x_ref[0]
    );
    assert!(s.steps < 1500, "{s:?}");
    assert!(s.jacobians < s.steps, "{s:?}");
    // limit-cycle period from successive downward zero crossings
    assert!(cross.len() >= 2, "crossings {cross:?}");
    let period = cross[1] - cross[0];
    let asymptotic = (3.0 - 2.0 * 2f64.ln()) * mu;
    eprintln!(
        "VdP period {period:.2} (asymptotic (3 - 2 ln 2) mu = {asymptotic:.2}; crossings {cross:?})"
    );
    assert!(
        (period - asymptotic).abs() < 0.01 * asymptotic,
        "period {period}"
    );
}

#[test]
fn stiff_van_der_pol_needs_far_more_explicit_steps() {
    let mu = 1000.0;
    let t_end = 300.0;
    let (xr, _, r, sr) = vdp_run(Method::radau5(1e-6, 1e-6), mu, t_end);
    assert_eq!(r, StopReason::Reached);
    let (xd, _, r, sd) = vdp_run(Method::dormand_prince(1e-6, 1e-6), mu, t_end);
    assert_eq!(r, StopReason::Reached);
    eprintln!("VdP mu=1000 on [0, 300]: Radau5 {sr:?}; DOPRI5 {sd:?}");
    assert!((xr[0] - xd[0]).abs() < 1e-3, "{xr:?} vs {xd:?}");
    assert!(
        sd.steps > 50 * sr.steps,
        "DOPRI {} vs Radau {}",
        sd.steps,
        sr.steps
    );
    // and DOPRI5 says why: its steps are held by stability, from the first fraction of a second
    assert!(sd.stiff_from.is_some_and(|t| t < 1.0), "{sd:?}");
    assert!(sd.stability_limited > sd.steps * 99 / 100, "{sd:?}");
}

#[test]
fn robertson_radau5() {
    let mut sys = Robertson;
    let mut integ = Integrator::new(Method::radau5(1e-8, 1e-10), 3).unwrap();
    let mut x = [1.0, 0.0, 0.0];
    let mut times = vec![40.0];
    let mut t = 1e2;
    while t <= 4e10 {
        times.push(t);
        t *= 10.0;
    }
    times.push(4e10);
    let mut at40 = [0.0; 3];
    let mut worst_mass: f64 = 0.0;
    let (r, s) = integ
        .integrate_at(&mut sys, 0.0, &mut x, &times, &mut |t, y| {
            if t == 40.0 {
                at40.copy_from_slice(y);
            }
            worst_mass = worst_mass.max((y[0] + y[1] + y[2] - 1.0).abs());
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(r, StopReason::Reached);
    eprintln!(
        "Robertson to 4e10: y(40) = {at40:?}, y(4e10) = {x:?}, mass error {worst_mass:.2e}, {s:?}"
    );
    // published reference values at t = 40 (Hairer & Wanner)
    let published = [0.715_827_1, 9.185_535e-6, 0.284_163_7];
    for i in 0..3 {
        let rel = (at40[i] - published[i]).abs() / published[i];
        assert!(
            rel < 1e-4,
            "y{} = {} vs {}: rel {rel:.2e}",
            i + 1,
            at40[i],
            published[i]
        );
    }
    assert!(worst_mass < 1e-6, "mass error {worst_mass}");
    // late: y1 → 0, y3 → 1
    assert!(x[0] < 1e-6 && x[2] > 0.999_99, "{x:?}");
    // Jacobian and LU reuse
    assert!(s.jacobians * 3 < s.steps, "{s:?}");
    assert!(
        s.lu_factorizations < s.steps + s.rejected + s.newton_failures + 1,
        "{s:?}"
    );
    assert!(s.steps < 400, "{s:?}");
    // A slowly converging Newton iteration gets a fresh Jacobian with its shorter step (RADAU5):
    // one Newton failure here; 16 when the stale Jacobian was kept.
    assert!(s.newton_failures <= 3, "{s:?}");
}

// ---------------------------------------------------------------- failures

struct Failing {
    fail_after: f64,
    nan: bool,
}

impl OdeSystem for Failing {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        if t > self.fail_after {
            if self.nan {
                d[0] = x[1];
                d[1] = f64::NAN;
                return Ok(());
            }
            return Err(RhsError(format!("derailed at t = {t}")));
        }
        d[0] = x[1];
        d[1] = -x[0];
        Ok(())
    }
}

fn all_methods() -> [Method; 5] {
    [
        Method::Rk4 { h: 0.01 },
        Method::ExplicitFixed {
            tableau: &DOPRI5,
            h: 0.01,
        },
        Method::dormand_prince(1e-6, 1e-8),
        Method::radau5(1e-6, 1e-8),
        Method::Radau5Fixed {
            h: 0.01,
            rtol: 1e-6,
            atol: 1e-8,
        },
    ]
}

#[test]
fn rhs_error_stops_with_time_and_keeps_last_state() {
    for m in all_methods() {
        let mut sys = Failing {
            fail_after: 1.0,
            nan: false,
        };
        let mut integ = Integrator::new(m, 2).unwrap();
        let mut x = [1.0, 0.0];
        let mut last_t = 0.0;
        let (r, _) = integ
            .integrate(&mut sys, 0.0, &mut x, 5.0, &mut |t, _| {
                last_t = t;
                ControlFlow::Continue(())
            })
            .unwrap();
        match r {
            StopReason::RhsFailed { t, msg } => {
                assert!(t > 1.0 && t < 1.5, "{m:?}: t {t}");
                assert!(msg.starts_with("derailed"), "{msg}");
            }
            other => panic!("{m:?}: {other:?}"),
        }
        // x is the last accepted state, close to the exact solution there
        assert!(last_t <= 1.0 + 0.5 && last_t > 0.5, "{m:?}: {last_t}");
        assert!(
            (x[0] - last_t.cos()).abs() < 1e-4,
            "{m:?}: {x:?} at {last_t}"
        );
        // repeated stepping repeats the failure
        assert!(matches!(
            integ.step(&mut sys),
            StepOutcome::Stop(StopReason::RhsFailed { .. })
        ));
    }
}

#[test]
fn nan_in_rhs_is_non_finite_with_index() {
    for m in all_methods() {
        let mut sys = Failing {
            fail_after: 2.0,
            nan: true,
        };
        let (x, r, _) = run(m, &mut sys, 0.0, &[1.0, 0.0], 5.0);
        match r {
            StopReason::NonFinite { t, index } => {
                assert_eq!(index, 1, "{m:?}");
                assert!((1.0..=2.0).contains(&t), "{m:?}: t {t}");
            }
            other => panic!("{m:?}: {other:?}"),
        }
        assert!(x.iter().all(|v| v.is_finite()), "{m:?}: {x:?}");
    }
}

#[test]
fn observer_break_interrupts() {
    let mut sys = Oscillator { w: 1.0 };
    let mut integ = Integrator::new(Method::Rk4 { h: 0.1 }, 2).unwrap();
    let mut x = [1.0, 0.0];
    let (r, s) = integ
        .integrate(&mut sys, 0.0, &mut x, 10.0, &mut |t, _| {
            if t >= 0.5 - 1e-12 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
    assert!(
        matches!(r, StopReason::Interrupted { t } if (t - 0.5).abs() < 1e-12),
        "{r:?}"
    );
    assert_eq!(s.steps, 5);
    assert!((x[0] - 0.5f64.cos()).abs() < 1e-6);
}

#[test]
fn max_steps_and_step_too_small() {
    let mut sys = VanDerPol { mu: 1000.0 };
    let mut integ = Integrator::new(Method::dormand_prince(1e-6, 1e-6), 2).unwrap();
    integ.set_max_steps(100);
    let mut x = [2.0, 0.0];
    let (r, s) = integ
        .integrate(&mut sys, 0.0, &mut x, 3000.0, &mut go)
        .unwrap();
    assert!(matches!(r, StopReason::MaxSteps { .. }), "{r:?}");
    assert_eq!(s.steps, 100);

    // a finite-time blow-up x' = x², x(0) = 1 (singular at t = 1)
    struct Blowup;
    impl OdeSystem for Blowup {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            d[0] = x[0] * x[0];
            Ok(())
        }
    }
    let (x, r, _) = run(
        Method::dormand_prince(1e-8, 1e-8),
        &mut Blowup,
        0.0,
        &[1.0],
        2.0,
    );
    assert!(
        matches!(r, StopReason::StepTooSmall { t, .. } | StopReason::NonFinite { t, .. } if t < 1.001 && t > 0.99),
        "{r:?}"
    );
    assert!(x[0].is_finite());
}

// ---------------------------------------------------------------- bad input

#[test]
fn bad_settings_are_construction_errors() {
    let bad = [
        Method::Rk4 { h: 0.0 },
        Method::Rk4 { h: f64::NAN },
        Method::Rk4 { h: -1.0 },
        Method::ExplicitFixed {
            tableau: &RK4,
            h: f64::INFINITY,
        },
        Method::dormand_prince(-1e-6, 1e-6),
        Method::dormand_prince(1e-6, 0.0),
        Method::dormand_prince(f64::NAN, 1e-6),
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-6,
            h0: Some(0.0),
            h_max: 1.0,
        },
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-6,
            h0: None,
            h_max: 0.0,
        },
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-6,
            h0: None,
            h_max: f64::NAN,
        },
        Method::radau5(0.0, 1e-6),
        Method::radau5(1e-15, 1e-6),
        Method::radau5(1e-6, -1.0),
        Method::Radau5 {
            rtol: 1e-6,
            atol: 1e-6,
            h0: None,
            h_max: 1.0,
            jacobian_reuse: f64::NAN,
        },
        Method::Radau5Fixed {
            h: 0.0,
            rtol: 1e-6,
            atol: 1e-6,
        },
    ];
    for m in bad {
        let e = Integrator::new(m, 2).err();
        assert!(
            matches!(e, Some(OdeError::InvalidParameter { .. })),
            "{m:?}: {e:?}"
        );
        // messages name the parameter
        assert!(e.unwrap().to_string().starts_with("invalid "));
    }
    assert_eq!(
        Integrator::new(Method::Rk4 { h: 0.1 }, 0).err(),
        Some(OdeError::ZeroDimension)
    );
}

#[test]
fn bad_run_input_is_rejected_before_integrating() {
    let mut integ = Integrator::new(Method::dormand_prince(1e-6, 1e-6), 2).unwrap();
    let mut sys = Oscillator { w: 1.0 };
    let e = integ
        .integrate(&mut sys, 0.0, &mut [1.0, 0.0, 0.0], 1.0, &mut go)
        .err();
    assert!(
        matches!(e, Some(OdeError::DimensionMismatch { .. })),
        "{e:?}"
    );
    let e = integ
        .integrate(&mut sys, 1.0, &mut [1.0, 0.0], 0.0, &mut go)
        .err();
    assert!(matches!(e, Some(OdeError::InvalidTimeSpan { .. })), "{e:?}");
    let e = integ
        .integrate(&mut sys, 0.0, &mut [1.0, f64::NAN], 1.0, &mut go)
        .err();
    assert!(matches!(
        e,
        Some(OdeError::NonFiniteInitialState { index: 1, .. })
    ));
    let e = integ
        .integrate_at(&mut sys, 0.0, &mut [1.0, 0.0], &[0.5, 0.2], &mut go)
        .err();
    assert!(
        matches!(e, Some(OdeError::InvalidOutputTime { .. })),
        "{e:?}"
    );
    struct BadScale;
    impl OdeSystem for BadScale {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, _x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            d.fill(0.0);
            Ok(())
        }
        fn abs_tol_scale(&self, i: usize) -> f64 {
            if i == 1 { 0.0 } else { 1.0 }
        }
    }
    let e = integ
        .integrate(&mut BadScale, 0.0, &mut [1.0, 0.0], 1.0, &mut go)
        .err();
    assert_eq!(
        e,
        Some(OdeError::InvalidScale {
            index: 1,
            value: 0.0
        })
    );
    // t_end == t0 is fine and does nothing
    let (r, s) = integ
        .integrate(&mut sys, 1.0, &mut [1.0, 0.0], 1.0, &mut go)
        .unwrap();
    assert_eq!(r, StopReason::Reached);
    assert_eq!(s, Stats::default());
}

#[test]
fn step_interface_matches_integrate() {
    let mut sys = Robertson;
    let m = Method::radau5(1e-6, 1e-8);
    let (x_a, _, s_a) = run(m, &mut Robertson, 0.0, &[1.0, 0.0, 0.0], 100.0);
    let mut integ = Integrator::new(m, 3).unwrap();
    integ.start(&sys, 0.0, &[1.0, 0.0, 0.0], 100.0).unwrap();
    let mut n = 0;
    while let StepOutcome::Accepted { .. } = integ.step(&mut sys) {
        n += 1;
    }
    assert!(integ.is_finished());
    assert_eq!(integ.t(), 100.0);
    assert_eq!(integ.x(), &x_a[..]);
    assert_eq!(n, s_a.steps);
    assert_eq!(integ.stats(), s_a);
}

#[test]
fn bogacki_shampine_has_order_three_and_controls_its_error() {
    // Fixed step: observed order 3.
    let hs = [0.1, 0.05, 0.025, 0.0125];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| osc_error(Method::ExplicitFixed { tableau: &BS3, h }, 4.0).0)
        .collect();
    let p = slope(&hs, &errs);
    eprintln!(
        "BS3 fixed-step errors {}, observed order {p:.3}",
        fmt_e(&errs)
    );
    assert!((p - 3.0).abs() < 0.2, "order {p}");
    // Adaptive: the error follows the tolerance, three evaluations per step (FSAL).
    let adaptive = |tol: f64| {
        osc_error(
            Method::AdaptiveExplicit {
                tableau: &BS3,
                rtol: tol,
                atol: tol,
                h0: None,
                h_max: f64::INFINITY,
            },
            4.0,
        )
    };
    let (e1, s1) = adaptive(1e-5);
    let (e2, s2) = adaptive(1e-8);
    eprintln!("BS3 adaptive: tol 1e-5 error {e1:.2e} ({s1:?}); tol 1e-8 error {e2:.2e}");
    assert!(e1 < 1e-3 && e2 < 1e-6 && e2 < e1 / 100.0);
    assert!(s2.steps > s1.steps);
    let attempts = s1.steps + s1.rejected;
    assert!(s1.rhs_evals <= 3 * attempts + 3, "{s1:?}");
    // A tableau without an error estimate is refused.
    assert!(
        Integrator::new(
            Method::AdaptiveExplicit {
                tableau: &RK4,
                rtol: 1e-6,
                atol: 1e-6,
                h0: None,
                h_max: f64::INFINITY,
            },
            2
        )
        .is_err()
    );
}

/// x' = λ (1 − x), x(0) = 0, λ = 200: x = 1 − e^(−λt) approaches 1 from below and never reaches
/// it. The system cannot be evaluated above `limit` (like a contact model asked for an absurd
/// penetration); a step too long for the fast mode overshoots there at a trial state.
struct Overshoot {
    limit: f64,
}

impl OdeSystem for Overshoot {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError> {
        if x[0] > self.limit {
            return Err(RhsError(format!("x = {} beyond {}", x[0], self.limit)));
        }
        dxdt[0] = 200.0 * (1.0 - x[0]);
        Ok(())
    }
}

/// A failure at a trial state (a stage, a Newton iterate, the initial-step probe) rejects the
/// step of an adaptive method instead of stopping the run; where the solution itself reaches
/// the failing region the run still stops with the system's error, at that time.
#[test]
fn a_failure_at_a_trial_state_rejects_the_step() {
    let adaptive = [
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-9,
            h0: Some(0.05),
            h_max: f64::INFINITY,
        },
        Method::dormand_prince(1e-6, 1e-9),
        Method::Radau5 {
            rtol: 1e-6,
            atol: 1e-9,
            h0: Some(0.05),
            h_max: f64::INFINITY,
            jacobian_reuse: 0.001,
        },
    ];
    for (k, m) in adaptive.into_iter().enumerate() {
        // The solution stays below 1; the first trial steps overshoot past 1.001 (with the
        // automatic initial step, from x0 = 0.999, its explicit Euler probe does).
        let x0 = if k == 1 { 0.999 } else { 0.0 };
        let mut sys = Overshoot { limit: 1.001 };
        let mut integ = Integrator::new(m, 1).unwrap();
        let mut x = [x0];
        let (r, stats) = integ
            .integrate(&mut sys, 0.0, &mut x, 0.2, &mut go)
            .unwrap();
        assert_eq!(r, StopReason::Reached, "{m:?}: {stats:?}");
        assert!(
            stats.trial_failures > 0,
            "{m:?}: no failed trial: {stats:?}"
        );
        let exact = 1.0 - (1.0 - x0) * (-200.0f64 * 0.2).exp();
        assert!((x[0] - exact).abs() < 1e-5, "{m:?}: {} vs {exact}", x[0]);
        eprintln!(
            "{m:?}: {} failed trials, {} steps",
            stats.trial_failures, stats.steps
        );

        // The solution crosses 0.5 at t* = ln 2 / 200: the run stops there with the error.
        let mut sys = Overshoot { limit: 0.5 };
        let mut integ = Integrator::new(m, 1).unwrap();
        let mut x = [0.0];
        let mut last = 0.0;
        let (r, _) = integ
            .integrate(&mut sys, 0.0, &mut x, 0.2, &mut |t, _| {
                last = t;
                ControlFlow::Continue(())
            })
            .unwrap();
        let t_star = 2f64.ln() / 200.0;
        match r {
            StopReason::RhsFailed { t, msg } => {
                assert!(
                    (t - t_star).abs() < 1e-6,
                    "{m:?}: stopped at {t}, crossing {t_star}"
                );
                assert!(msg.contains("beyond 0.5"), "{msg}");
            }
            other => panic!("{m:?}: {other:?}"),
        }
        assert!(
            (last - t_star).abs() < 1e-6 && x[0] <= 0.5,
            "{m:?}: {last} {x:?}"
        );
    }
    // Fixed-step methods cannot shorten the step: they stop at the first failure.
    for m in [
        Method::Rk4 { h: 0.05 },
        Method::Radau5Fixed {
            h: 0.05,
            rtol: 1e-6,
            atol: 1e-9,
        },
    ] {
        let mut sys = Overshoot { limit: 1.001 };
        let mut integ = Integrator::new(m, 1).unwrap();
        let mut x = [0.0];
        let (r, _) = integ
            .integrate(&mut sys, 0.0, &mut x, 0.2, &mut go)
            .unwrap();
        assert!(matches!(r, StopReason::RhsFailed { .. }), "{m:?}: {r:?}");
    }
}

// ---------------------------------------------------------------- stiffness detection

/// y' = λ (y − cos t) − sin t, y(0) = 1: y = cos t for every λ; with λ ≪ 0 an explicit
/// method's step is held by stability at h ≈ 3.3 / |λ| (DOPRI5) although the solution is smooth.
struct StiffCosine {
    lambda: f64,
}

impl OdeSystem for StiffCosine {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, y: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        d[0] = self.lambda * (y[0] - t.cos()) - t.sin();
        Ok(())
    }
}

/// The run's statistics and its accepted step sizes (from the observer's times).
fn steps_of(method: Method, sys: &mut impl OdeSystem, x0: &[f64], t_end: f64) -> (Stats, Vec<f64>) {
    let mut integ = Integrator::new(method, sys.dim()).unwrap();
    let mut x = x0.to_vec();
    let mut times = vec![];
    let (r, s) = integ
        .integrate(sys, 0.0, &mut x, t_end, &mut |t, _| {
            times.push(t);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(r, StopReason::Reached);
    (s, times.windows(2).map(|w| w[1] - w[0]).collect())
}

#[test]
fn dopri5_counts_exactly_the_steps_beyond_its_stability_limit() {
    // On a linear scalar problem the two last stages differ by λ times their states' difference,
    // so the estimate h|λ| is exact: the stability-limited steps are those with h > 3.25/|λ|.
    let lambda = -1000.0;
    let (s, h) = steps_of(
        Method::dormand_prince(1e-4, 1e-6),
        &mut StiffCosine { lambda },
        &[1.0],
        2.0,
    );
    let beyond = h.iter().filter(|&&h| h * lambda.abs() > 3.25).count();
    let mut sorted = h.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    eprintln!(
        "stiff cosine, DOPRI5: {s:?}; median h|λ| {:.3}; {beyond} steps beyond 3.25",
        median * lambda.abs()
    );
    assert_eq!(s.stability_limited, beyond);
    // the step hovers at the stability boundary (about 3.3 on the negative real axis; Hairer &
    // Wanner, Solving ODEs II, §IV.2) ...
    assert!(
        (3.2..3.4).contains(&(median * lambda.abs())),
        "median h {median}"
    );
    // ... from early on, which the run reports as stiff
    let from = s.stiff_from.expect("reported stiff");
    assert!(from < 0.1, "stiff from {from}");
    assert!(s.stability_limited > s.steps / 4, "{s:?}");
}

/// x'' + 2ζω x' + ω² x = sin t with ω = 2000 rad/s: a weakly damped stiff mode, as a wheel on
/// its contact stiffness. DOPRI5 at tight tolerances sits on its stability boundary, where the
/// controller switches between limited and not limited steps (the longest run of limited
/// steps was 2 to 5): Hairer's counters, which forget the limited steps only after 6
/// consecutive others, report it stiff within 0.1 s; the count of consecutive limited steps
/// before stop 39 never did.
#[test]
fn a_weakly_damped_stiff_mode_is_reported_stiff() {
    struct Oscillator {
        omega: f64,
        zeta: f64,
    }
    impl OdeSystem for Oscillator {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            d[0] = x[1];
            d[1] = -self.omega * self.omega * x[0] - 2.0 * self.zeta * self.omega * x[1] + t.sin();
            Ok(())
        }
    }
    for (zeta, tol) in [(0.05, 1e-8), (0.3, 1e-6), (0.01, 1e-4)] {
        let (s, _) = steps_of(
            Method::dormand_prince(tol, tol),
            &mut Oscillator {
                omega: 2000.0,
                zeta,
            },
            &[0.0, 0.0],
            1.0,
        );
        eprintln!("ζ {zeta}, tol {tol:e}: {s:?}");
        let from = s
            .stiff_from
            .unwrap_or_else(|| panic!("not reported stiff: {s:?}"));
        assert!(from < 0.1, "stiff from {from}");
    }
}

#[test]
fn non_stiff_runs_and_other_methods_report_no_stability_limit() {
    // the oscillator's steps are set by accuracy: h|λ| = 2h stays far below 3.25
    let (_, s) = osc_error(Method::dormand_prince(1e-6, 1e-9), 20.0);
    assert_eq!((s.stability_limited, s.stiff_from), (0, None), "{s:?}");
    // methods without the test report nothing, even on a stiff problem
    for method in [
        Method::AdaptiveExplicit {
            tableau: &BS3,
            rtol: 1e-6,
            atol: 1e-9,
            h0: None,
            h_max: f64::INFINITY,
        },
        Method::radau5(1e-6, 1e-9),
        Method::Rk4 { h: 1e-3 },
    ] {
        let (s, _) = steps_of(method, &mut StiffCosine { lambda: -1000.0 }, &[1.0], 0.5);
        assert_eq!((s.stability_limited, s.stiff_from), (0, None), "{method:?}");
    }
}

// ---------------------------------------------------------------- breakpoints

/// x' = −λ (x − g(t)) with g = c·max(0, t − 1): a stiff relaxation to an input whose slope
/// jumps at t = 1. For t ≥ 1, x = c (t − 1) − (c/λ)(1 − e^{−λ (t − 1)}) (x = 0 before).
struct KinkedInput {
    lambda: f64,
    c: f64,
}

impl OdeSystem for KinkedInput {
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        let g = self.c * (t - 1.0).max(0.0);
        d[0] = -self.lambda * (x[0] - g);
        Ok(())
    }
}

/// The run of `method` on [`KinkedInput`] over [0, 2], with a breakpoint at t = 1 or none:
/// the error at t = 2, the statistics and whether a step ended exactly at t = 1.
fn kinked_run(method: Method, breakpoint: bool) -> (f64, Stats, bool) {
    let mut sys = KinkedInput {
        lambda: 1e4,
        c: 1.0,
    };
    let mut integ = Integrator::new(method, 1).unwrap();
    if breakpoint {
        integ.set_breakpoints(&[1.0, -5.0, 7.0]).unwrap();
    }
    let mut x = vec![0.0];
    let mut hit = false;
    let (r, s) = integ
        .integrate(&mut sys, 0.0, &mut x, 2.0, &mut |t, _| {
            hit |= t == 1.0;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(r, StopReason::Reached);
    let exact = 1.0 - (1.0 - (-1e4f64).exp()) / 1e4;
    ((x[0] - exact).abs(), s, hit)
}

/// With the slope jump of the input declared as a breakpoint, a step of DOPRI5 and of Radau5
/// ends on it (the others, outside the run, are ignored), fewer steps are rejected and the
/// error at the end is within the tolerance; without it both step over the kink.
#[test]
fn breakpoints_end_a_step_where_the_input_has_a_kink() {
    for method in [
        Method::DormandPrince {
            rtol: 1e-6,
            atol: 1e-9,
            h0: None,
            h_max: f64::INFINITY,
        },
        Method::radau5(1e-6, 1e-9),
    ] {
        let (e_with, s_with, hit_with) = kinked_run(method, true);
        let (e_without, s_without, hit_without) = kinked_run(method, false);
        eprintln!(
            "{method:?}: with the breakpoint error {e_with:.2e}, {s_with:?}; \
             without {e_without:.2e}, {s_without:?}"
        );
        assert!(hit_with && !hit_without, "{method:?}");
        assert!(e_with < 1e-6, "{method:?}: error {e_with:e}");
        assert!(
            s_with.rejected < s_without.rejected,
            "{method:?}: {} rejected with the breakpoint, {} without",
            s_with.rejected,
            s_without.rejected
        );
    }
}

/// Fixed-step methods keep their grid: breakpoints change nothing.
#[test]
fn fixed_step_methods_ignore_breakpoints() {
    let mut sys = KinkedInput {
        lambda: 10.0,
        c: 1.0,
    };
    let mut times = Vec::new();
    let mut integ = Integrator::new(Method::Rk4 { h: 0.3 }, 1).unwrap();
    integ.set_breakpoints(&[1.0]).unwrap();
    let mut x = vec![0.0];
    integ
        .integrate(&mut sys, 0.0, &mut x, 2.0, &mut |t, _| {
            times.push(t);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert!(!times.contains(&1.0), "{times:?}");
    assert!((times[4] - 1.2).abs() < 1e-12, "{times:?}");
}

#[test]
fn a_non_finite_breakpoint_is_refused() {
    let mut integ = Integrator::new(Method::Rk4 { h: 0.1 }, 1).unwrap();
    let e = integ.set_breakpoints(&[0.5, f64::NAN]).unwrap_err();
    assert!(
        matches!(
            e,
            OdeError::InvalidParameter {
                name: "breakpoint",
                ..
            }
        ),
        "{e:?}"
    );
}

// ---------------------------------------------------------------- Jacobian patterns

/// The Brusselator with diffusion on N grid points of (0, 1) (Hairer & Wanner, *Solving ODEs
/// II*, §IV.1, "BRUSS"): u_i' = 1 + u_i² v_i − 4 u_i + c (u_{i−1} − 2 u_i + u_{i+1}),
/// v_i' = 3 u_i − u_i² v_i + c (v_{i−1} − 2 v_i + v_{i+1}), c = α (N + 1)², α = 1/50,
/// u = 1 and v = 3 at both ends; stiff for large N. State interleaved (u_1, v_1, u_2, …), so
/// each derivative depends on at most five neighbouring variables.
struct Bruss {
    n: usize,
    /// Declare the pattern (else dense).
    sparse: bool,
}

impl Bruss {
    fn start(&self) -> Vec<f64> {
        (0..self.n)
            .flat_map(|i| {
                let x = (i + 1) as f64 / (self.n + 1) as f64;
                [1.0 + (2.0 * PI * x).sin(), 3.0]
            })
            .collect()
    }
}

impl OdeSystem for Bruss {
    fn dim(&self) -> usize {
        2 * self.n
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        let n = self.n;
        let c = (n + 1) as f64 * (n + 1) as f64 / 50.0;
        for i in 0..n {
            let (u, v) = (x[2 * i], x[2 * i + 1]);
            let (ul, vl) = if i == 0 {
                (1.0, 3.0)
            } else {
                (x[2 * i - 2], x[2 * i - 1])
            };
            let (ur, vr) = if i + 1 == n {
                (1.0, 3.0)
            } else {
                (x[2 * i + 2], x[2 * i + 3])
            };
            d[2 * i] = 1.0 + u * u * v - 4.0 * u + c * (ul - 2.0 * u + ur);
            d[2 * i + 1] = 3.0 * u - u * u * v + c * (vl - 2.0 * v + vr);
        }
        Ok(())
    }
    fn jacobian_pattern(&self) -> Option<JacobianPattern> {
        if !self.sparse {
            return None;
        }
        let m = 2 * self.n;
        let mut p = JacobianPattern::new(m);
        for i in 0..self.n {
            for (row, col) in [(0, 1), (1, 0)] {
                p.insert(2 * i + row, 2 * i + col).unwrap();
            }
            for k in 0..2 {
                for j in [i.wrapping_sub(1), i, i + 1] {
                    if j < self.n {
                        p.insert(2 * i + k, 2 * j + k).unwrap();
                    }
                }
            }
        }
        Some(p)
    }
}

/// Radau5 with the Brusselator's pattern: a handful of right-hand sides per Jacobian instead of
/// one per variable, and the same solution (within the tolerance) as with the dense difference.
#[test]
fn radau5_estimates_a_banded_jacobian_by_column_groups() {
    let n = 40;
    let run = |sparse: bool| {
        let mut sys = Bruss { n, sparse };
        let mut x = sys.start();
        let mut integ = Integrator::new(Method::radau5(1e-6, 1e-8), 2 * n).unwrap();
        let (r, s) = integ
            .integrate(&mut sys, 0.0, &mut x, 10.0, &mut go)
            .unwrap();
        assert_eq!(r, StopReason::Reached);
        (x, s)
    };
    let (xd, sd) = run(false);
    let (xs, ss) = run(true);
    eprintln!("BRUSS N = {n}: dense {sd:?}\n  grouped {ss:?}");
    let worst = xd
        .iter()
        .zip(&xs)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "solutions differ by {worst:.2e}");
    assert_eq!(sd.jacobian_rhs_evals, sd.jacobians * 2 * n, "{sd:?}");
    // at most five variables per column's rows: the greedy colouring needs four groups here
    let groups = Bruss { n, sparse: true }
        .jacobian_pattern()
        .unwrap()
        .column_groups()
        .len();
    assert_eq!(groups, 4);
    assert_eq!(ss.jacobian_rhs_evals, ss.jacobians * groups, "{ss:?}");
    // the same Jacobians to rounding: the same steps and Newton iterations
    let other = |s: &Stats| (s.rhs_evals - s.jacobian_rhs_evals) as f64;
    assert!(
        (other(&ss) / other(&sd) - 1.0).abs() < 0.05,
        "{ss:?} against {sd:?}"
    );
    assert!(ss.rhs_evals < sd.rhs_evals * 2 / 3, "{ss:?} against {sd:?}");
}

/// The linearisation with the pattern equals the column-by-column one to rounding, at a
/// fraction of the right-hand sides.
#[test]
fn the_linearisation_with_a_pattern_equals_the_dense_one() {
    struct Counted(Bruss, usize);
    impl OdeSystem for Counted {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            self.1 += 1;
            self.0.rhs(t, x, d)
        }
        fn jacobian_pattern(&self) -> Option<JacobianPattern> {
            self.0.jacobian_pattern()
        }
    }
    let n = 30;
    let x = Bruss { n, sparse: false }.start();
    let steps = vec![1e-5; 2 * n];
    let mut dense = Counted(Bruss { n, sparse: false }, 0);
    let mut grouped = Counted(Bruss { n, sparse: true }, 0);
    let jd = jacobian(&mut dense, 0.0, &x, &steps).unwrap();
    let jg = jacobian(&mut grouped, 0.0, &x, &steps).unwrap();
    assert_eq!((dense.1, grouped.1), (4 * n, 8));
    let scale = (0..2 * n)
        .flat_map(|j| (0..2 * n).map(move |i| (i, j)))
        .map(|(i, j)| jd[(i, j)].abs())
        .fold(0.0, f64::max);
    for j in 0..2 * n {
        for i in 0..2 * n {
            let d = (jd[(i, j)] - jg[(i, j)]).abs();
            assert!(
                d <= 1e-9 * scale,
                "({i}, {j}): {} against {}",
                jg[(i, j)],
                jd[(i, j)]
            );
        }
    }
    // the pattern is not vacuous: the diffusion couples neighbours
    assert!(jd[(0, 2)].abs() > 1.0 && jg[(0, 2)] == jd[(0, 2)]);
}

/// A pattern of the wrong dimension is refused before integrating.
#[test]
fn a_pattern_of_the_wrong_dimension_is_refused() {
    struct Wrong;
    impl OdeSystem for Wrong {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
            d[0] = -x[0];
            d[1] = -x[1];
            Ok(())
        }
        fn jacobian_pattern(&self) -> Option<JacobianPattern> {
            Some(JacobianPattern::new(3))
        }
    }
    let mut integ = Integrator::new(Method::radau5(1e-6, 1e-8), 2).unwrap();
    let mut x = [1.0, 1.0];
    let e = integ
        .integrate(&mut Wrong, 0.0, &mut x, 1.0, &mut go)
        .unwrap_err();
    assert_eq!(
        e,
        OdeError::DimensionMismatch {
            what: "Jacobian pattern",
            expected: 2,
            found: 3
        }
    );
    assert!(jacobian(&mut Wrong, 0.0, &x, &[1e-6; 2]).is_err());
}

/// `Integrator::jump` replaces the state where the step loop stands and the method goes on from
/// there: the oscillator x = cos t stepped to a breakpoint t1, its velocity reversed there, then
/// stepped to t = π, ends where the reversed motion's closed form puts it, x = cos(2 t1 − t).
/// DOPRI5 and Radau IIA; the statistics are kept across the jump.
#[test]
fn a_jump_of_the_state_restarts_the_method_where_it_stands() {
    for method in [
        Method::DormandPrince {
            rtol: 1e-10,
            atol: 1e-12,
            h0: None,
            h_max: 1.0,
        },
        Method::Radau5 {
            rtol: 1e-10,
            atol: 1e-12,
            h0: None,
            h_max: 1.0,
            jacobian_reuse: 0.001,
        },
    ] {
        let mut sys = Oscillator { w: 1.0 };
        let mut integ = Integrator::new(method, 2).unwrap();
        let t1 = 0.5 * PI - 0.3;
        integ.set_breakpoints(&[t1]).unwrap();
        integ.start(&sys, 0.0, &[1.0, 0.0], PI).unwrap();
        while integ.t() < t1 {
            assert!(matches!(integ.step(&mut sys), StepOutcome::Accepted { .. }));
        }
        assert_eq!(integ.t(), t1);
        let steps = integ.stats().steps;
        let mut x = integ.x().to_vec();
        x[1] = -x[1];
        assert!(integ.jump(&[f64::NAN, 0.0]).is_err());
        assert!(integ.jump(&[1.0]).is_err());
        integ.jump(&x).unwrap();
        assert_eq!(integ.x(), x.as_slice());
        while !integ.is_finished() {
            assert!(matches!(integ.step(&mut sys), StepOutcome::Accepted { .. }));
        }
        let exact = (2.0 * t1 - PI).cos();
        let err = (integ.x()[0] - exact).abs();
        println!("{method:?}: x(π) {:.12} against {exact:.12}", integ.x()[0]);
        assert!(err < 1e-8, "{err}");
        assert!(integ.stats().steps > steps);
    }
}
