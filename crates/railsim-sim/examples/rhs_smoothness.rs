//! Smoothness of the right-hand side along a run (a diagnostic of the contact forces for the
//! integrators): `cargo run --release -p railsim-sim --example rhs_smoothness -- SCENE T SPAN N`
//! runs SCENE to T (s), then evaluates f(x + τ f(x)) at N points τ over ±SPAN (s) and prints the
//! twelve components with the largest second difference, scaled by the error weight
//! 1e-6 + 1e-4 |x| of an integrator at atol 1e-6, rtol 1e-4. A jump in f shows as one large
//! second difference that stays when N grows.
//! - `PRINT=name` also prints that component around its largest second difference and the
//!   patches of the evaluations on either side.
//! - `TRACE=i,t0` prints state component `i` at every sample from `t0` on.
//!
//! The run samples at 10 kHz (the state at T is a sample); the samples' right-hand sides update
//! the contact warm starts, so the trajectory differs from `railsim run`'s within the contact
//! search's tolerance.

use std::path::Path;

use railsim_ode::OdeSystem;
use railsim_sim::dynamics::Dynamics;
use railsim_sim::{RunOptions, Scene, Simulation};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 5 {
        eprintln!("usage: rhs_smoothness SCENE T_S SPAN_S N");
        std::process::exit(2);
    }
    let (t, span): (f64, f64) = (a[2].parse().unwrap(), a[3].parse().unwrap());
    let n: usize = a[4].parse::<usize>().unwrap().max(3);
    let mut scene = Scene::from_file(Path::new(&a[1])).expect("scene");
    scene.log.rate_hz = 10_000.0;
    let trace: Option<(usize, f64)> = std::env::var("TRACE").ok().map(|v| {
        let (i, t0) = v.split_once(',').expect("TRACE=i,t0");
        (i.parse().unwrap(), t0.parse().unwrap())
    });
    let mut sim = Simulation::new(&scene).expect("simulation");
    let opts = RunOptions {
        t_end: Some(t),
        no_log: true,
        ..Default::default()
    };
    let mut x = Vec::new();
    let summary = sim
        .run(&scene, &opts, &mut |_, _| {}, &mut |s| {
            if let Some((i, t0)) = trace
                && s.t >= t0
            {
                println!("{:.5} {:.6e}", s.t, s.x[i]);
            }
            x.clone_from(&s.x);
        })
        .expect("run");
    let st = summary.stats;
    println!(
        "run to {t} s: {} steps, {} rejected, {} Newton failures, {} right-hand sides",
        st.steps, st.rejected, st.newton_failures, st.rhs_evals
    );
    let model = sim.model();
    let dim = model.dim();
    let mut d = Dynamics::new(model);
    let mut f0 = vec![0.0; dim];
    d.rhs(t, &x, &mut f0).unwrap();
    let point = |k: usize, xt: &mut [f64]| {
        let tau = -span + 2.0 * span * k as f64 / (n - 1) as f64;
        for i in 0..dim {
            xt[i] = x[i] + tau * f0[i];
        }
        t + tau
    };
    let mut fs = vec![vec![0.0; dim]; n];
    let mut xt = vec![0.0; dim];
    for (k, f) in fs.iter_mut().enumerate() {
        let tk = point(k, &mut xt);
        d.rhs(tk, &xt, f).unwrap();
    }
    // (scaled largest second difference, component, where)
    let mut rows: Vec<(f64, usize, usize)> = (0..dim)
        .map(|i| {
            let (mut worst, mut at) = (0.0, 0);
            for k in 1..n - 1 {
                let d2 = (fs[k + 1][i] - 2.0 * fs[k][i] + fs[k - 1][i]).abs();
                if d2 > worst {
                    (worst, at) = (d2, k);
                }
            }
            (worst / (1e-6 + 1e-4 * x[i].abs()), i, at)
        })
        .collect();
    rows.sort_by(|p, q| q.0.total_cmp(&p.0));
    for (r, i, k) in rows.iter().take(12) {
        println!("{:34} {r:10.3e} at point {k}", model.state_names[*i]);
    }
    if let Ok(name) = std::env::var("PRINT") {
        let i = model
            .state_names
            .iter()
            .position(|s| *s == name)
            .expect("a state name");
        let k0 = rows.iter().find(|r| r.1 == i).unwrap().2;
        for (k, f) in fs
            .iter()
            .enumerate()
            .take((k0 + 5).min(n))
            .skip(k0.saturating_sub(4))
        {
            println!("{k:5} {:.12e}", f[i]);
        }
        d.ws.record = true;
        for k in k0.saturating_sub(1)..=(k0 + 1).min(n - 1) {
            let tk = point(k, &mut xt);
            d.rhs(tk, &xt, &mut f0.clone()).unwrap();
            println!("point {k}");
            for p in &d.ws.patches {
                let r = &p.result;
                println!(
                    "  wheel {} y_r {:9.4} mm angle {:8.5} pen {:.6e} Fn {:12.4} Fx {:10.4} Fs {:10.4}",
                    p.wheel,
                    r.y_rail_profile * 1e3,
                    r.contact_angle,
                    r.penetration,
                    r.forces.fn_,
                    r.forces.fx,
                    r.forces.fs,
                );
            }
        }
    }
}
