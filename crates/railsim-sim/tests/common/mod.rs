//! Helpers shared by the simulator's test binaries (each binary uses a part of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use railsim_contact::{Side, WheelsetPose, WheelsetVelocity};
use railsim_sim::{RunOptions, RunSummary, Sample, Scene, Simulation};

/// The repository root (scene paths in the tests are relative to it).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A scene from TOML text, paths relative to the repository root.
pub fn scene(text: &str) -> Scene {
    Scene::from_toml_str(text, "test.toml", &root()).unwrap_or_else(|e| panic!("{e}"))
}

/// Run a scene without a log; return the simulation, the samples and the summary.
pub fn run(scene: &Scene) -> (Simulation, Vec<Sample>, RunSummary) {
    let mut sim = Simulation::new(scene).unwrap();
    let mut samples = Vec::new();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let summary = sim
        .run(scene, &opts, &mut |_, _| {}, &mut |s| {
            samples.push(s.clone())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    (sim, samples, summary)
}

/// The Manchester vehicle 1 with the Hertz/Polach contact (five times cheaper than `stripes`),
/// its carbody's x frozen, DOPRI5 at rtol 1e-4 / atol 1e-6, and the scene keys in `keys`
/// (track, speed, length; tables such as `[initial]` last).
pub fn manchester_polach(keys: &str) -> Scene {
    scene(&format!(
        r#"
        vehicle = "vehicles/manchester_vehicle1.toml"
        freeze = ["carbody.x"]
        {keys}
        [contact]
        model = "polach"
        [integrator]
        method = "dopri5"
        rtol = 1e-4
        atol = 1e-6
        "#
    ))
}

/// Rolling radius and half the distance between the contact points of the centred wheelset
/// under half its weight per wheel (the r0 and b of the linear formulas, measured on the actual
/// wheel/rail pair).
pub fn centred_contact(sim: &Simulation, load: f64, v: f64) -> (f64, f64) {
    let w = &sim.model().wheels[0];
    let mut ws = railsim_contact::ContactWorkspace::new();
    let vel = WheelsetVelocity {
        vx: v,
        spin: v / 0.46,
        ..Default::default()
    };
    w.contact
        .evaluate_with_load(
            Side::Left,
            &WheelsetPose::default(),
            &vel,
            load,
            1e-9,
            &mut ws,
        )
        .unwrap();
    let p = ws.patches[0];
    (p.rolling_radius, p.point_track[1].abs())
}

/// Effective conicity of a pure cone of slope `lambda` on UIC60 1:40 (gauge 1435 mm,
/// flange-back 1360 mm, r0 = 0.46 m): the slope of the rigid rolling-radius difference,
/// Δr = 2 λe y, computed by `railsim-profile`'s conicity module (independent of the dynamics).
/// The wheelset rolls by Δr / (2 e0) as it shifts, which moves both wheel contacts further by
/// r φ, so λe = λ / (1 − r λ / e0) for a cone on a rail whose contact point does not move.
pub fn cone_effective_conicity(lambda: f64) -> f64 {
    use railsim_profile::conicity::{WheelsetTrackSetup, rolling_radius_difference};
    use railsim_profile::{Profile, ProfileKind, analytic};
    let pts: Vec<[f64; 2]> = (0..=250)
        .map(|i| {
            let y = -0.065 + i as f64 * 0.0005;
            [y, lambda * y]
        })
        .collect();
    let cone = Profile::new("cone", ProfileKind::Wheel, pts).unwrap();
    let ys = [-1e-3, 1e-3];
    let d = rolling_radius_difference(
        &cone,
        &analytic::uic60(),
        &WheelsetTrackSetup::default(),
        &ys,
    )
    .unwrap();
    (d[1].delta_r - d[0].delta_r) / (2.0 * (ys[1] - ys[0]))
}
