//! Helpers shared by the simulator's test binaries (each binary uses a part of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

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
