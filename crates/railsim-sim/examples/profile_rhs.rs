//! Repeated right-hand-side evaluations of the default scene's vehicle for profiling:
//! `cargo run --release -p railsim-sim --example profile_rhs -- 2000`
//! (e.g. under `perf record -g`).

use std::path::Path;

use railsim_ode::OdeSystem;
use railsim_sim::dynamics::Dynamics;
use railsim_sim::{Scene, Simulation};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    // RAILSIM_STEP_MM: the contact's travelling step (default: the contact's default)
    let step = std::env::var("RAILSIM_STEP_MM")
        .map(|s| format!("\n[contact]\nstep_mm = {s}"))
        .unwrap_or_default();
    let text = format!(
        r#"vehicle = "vehicles/manchester_vehicle1.toml"
           track = "tracks/straight_irregular.toml"
           speed_kmh = 198
           duration_s = 1{step}"#
    );
    let scene = Scene::from_toml_str(&text, "profile.toml", &root).expect("scene");
    let sim = Simulation::new(&scene).expect("simulation");
    let model = sim.model();
    let x = sim.initial_state().to_vec();
    let mut d = Dynamics::new(model);
    let mut dx = vec![0.0; model.dim()];
    let t0 = std::time::Instant::now();
    for _ in 0..n {
        d.rhs(0.0, &x, &mut dx).expect("rhs");
    }
    let dt = t0.elapsed().as_secs_f64() / n as f64;
    println!("{n} evaluations, {:.1} µs each", dt * 1e6);
}
