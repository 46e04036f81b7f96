//! Criterion benches: RK4 and Dormand–Prince on the harmonic oscillator, Radau5 on
//! Robertson's kinetics (to t = 4e10) and on Van der Pol (μ = 1000). The integrator is
//! built once outside the timed closure, as a simulation would reuse it.

use std::hint::black_box;
use std::ops::ControlFlow;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_ode::{Integrator, Method, OdeSystem, RhsError};

struct Oscillator;

impl OdeSystem for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        d[0] = x[1];
        d[1] = -4.0 * x[0];
        Ok(())
    }
}

struct Robertson;

impl OdeSystem for Robertson {
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
    fn abs_tol_scale(&self, i: usize) -> f64 {
        if i == 1 { 1e-4 } else { 1.0 }
    }
}

struct VanDerPol;

impl OdeSystem for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        d[0] = y[1];
        d[1] = 1000.0 * (1.0 - y[0] * y[0]) * y[1] - y[0];
        Ok(())
    }
}

fn run(integ: &mut Integrator, sys: &mut impl OdeSystem, x0: &[f64], t_end: f64) -> f64 {
    let mut x = [0.0; 3];
    let x = &mut x[..x0.len()];
    x.copy_from_slice(x0);
    let (r, _) = integ
        .integrate(sys, 0.0, x, t_end, &mut |_, _| ControlFlow::Continue(()))
        .expect("valid input");
    black_box(r);
    x[0]
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("oscillator_10_periods");
    let t_end = 10.0 * std::f64::consts::PI;
    let mut rk4 = Integrator::new(Method::Rk4 { h: 0.01 }, 2).unwrap();
    g.bench_function("rk4_h0.01", |b| {
        b.iter(|| run(&mut rk4, &mut Oscillator, &[1.0, 0.0], t_end))
    });
    let mut dp = Integrator::new(Method::dormand_prince(1e-8, 1e-8), 2).unwrap();
    g.bench_function("dopri5_tol1e-8", |b| {
        b.iter(|| run(&mut dp, &mut Oscillator, &[1.0, 0.0], t_end))
    });
    g.finish();

    let mut g = c.benchmark_group("stiff");
    let mut rob = Integrator::new(Method::radau5(1e-8, 1e-10), 3).unwrap();
    g.bench_function("radau5_robertson_4e10", |b| {
        b.iter(|| run(&mut rob, &mut Robertson, &[1.0, 0.0, 0.0], 4e10))
    });
    let mut vdp = Integrator::new(Method::radau5(1e-6, 1e-6), 2).unwrap();
    g.bench_function("radau5_vanderpol_mu1000_3000", |b| {
        b.iter(|| run(&mut vdp, &mut VanDerPol, &[2.0, 0.0], 3000.0))
    });
    g.finish();
}

criterion_group!(ode, benches);
criterion_main!(ode);
