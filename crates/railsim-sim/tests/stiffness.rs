//! The integrator's stiffness report on a vehicle: on ideal straight track nothing limits
//! DOPRI5's step but stability, and a weakly damped stiff mode on the edge of the stability
//! region then keeps an oscillation whose size is set by the tolerance, not by the physics
//! (docs/models/ode.md, "Stiffness detection"; validation §14).
use crate::common;

use common::{run, scene, state_index};
use railsim_sim::{RunSummary, Sample};

/// A straight ideal track of 300 m with UIC60 rails at 1:20, written to a temporary file; its
/// path.
fn track_1_20() -> String {
    let dir = std::env::temp_dir().join(format!("railsim-stiffness-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("straight_1_20.toml");
    std::fs::write(
        &path,
        "gauge_mm = 1435\nrail_inclination = \"1:20\"\n\
         rail_profile = { left = \"uic60\", right = \"uic60\" }\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 300\n",
    )
    .unwrap();
    path.display().to_string()
}

/// The Manchester vehicle (`polach`) 5 s at 72 km/h on `track`, logged at 1 kHz, with the
/// integrator table `integrator`: its summary and the leading wheelset's height at every sample.
/// (The oscillation grows 2.9 times every 0.25 s from the start's residual until the tolerance
/// holds it. The run was 3 s until the wheelsets started in free rolling: the start's spin
/// transient had begun it at ±1.3e-8 m, and both runs held it from 1.5 s on; from the free-rolling
/// start it begins at ±9e-11 m (atol 1e-6) and ±8e-13 m (atol 1e-7) and reaches its size at
/// about 3 and 3.5 s.)
fn heights(track: &str, integrator: &str) -> (RunSummary, Vec<f64>) {
    let s = scene(&format!(
        "vehicle = \"vehicles/manchester_vehicle1.toml\"\nfreeze = [\"carbody.x\"]\n\
         track = \"{track}\"\nspeed_kmh = 72\nstart_m = 80\nduration_s = 5\n\
         [log]\nrate_hz = 1000\n[contact]\nmodel = \"polach\"\n[integrator]\n{integrator}\n"
    ));
    let (sim, samples, summary) = run(&s);
    let iz = state_index(&sim, "ws1.z");
    (summary, samples.iter().map(|s: &Sample| s.x[iz]).collect())
}

/// Over the last second: the largest deviation from the mean and the number of upward crossings
/// of the mean (the frequency in Hz).
fn late_oscillation(z: &[f64]) -> (f64, usize) {
    let late = &z[z.len() - 1000..];
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    let amp = late.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
    let ups = late
        .windows(2)
        .filter(|w| w[0] < mean && w[1] >= mean)
        .count();
    (amp, ups)
}

#[test]
fn a_stability_limited_dopri5_keeps_a_tolerance_sized_oscillation_that_radau5_does_not() {
    let track = track_1_20();
    let (s6, z6) = heights(&track, "method = \"dopri5\"\nrtol = 1e-4\natol = 1e-6");
    let (s7, z7) = heights(&track, "method = \"dopri5\"\nrtol = 1e-5\natol = 1e-7");
    let (sr, zr) = heights(&track, "method = \"radau5\"\nrtol = 1e-4\natol = 1e-6");
    let ((a6, f6), (a7, f7), (ar, _)) = (
        late_oscillation(&z6),
        late_oscillation(&z7),
        late_oscillation(&zr),
    );
    eprintln!(
        "ws1.z over the last second: DOPRI5 atol 1e-6 ±{a6:.3e} m at {f6} Hz ({s6:?}); \
         atol 1e-7 ±{a7:.3e} m at {f7} Hz ({s7:?}); Radau5 ±{ar:.3e} m ({sr:?})",
        s6 = s6.stats,
        s7 = s7.stats,
        sr = sr.stats
    );
    // both DOPRI5 runs are reported stiff within their first tenth of a second
    for s in [&s6.stats, &s7.stats] {
        assert!(s.stiff_from.is_some_and(|t| t < 0.1), "{s:?}");
    }
    // the oscillation is the wheelset's vertical mode on its two contact stiffnesses,
    // √(2·1e9 N/m / 1813 kg) / 2π ≈ 167 Hz (docs/models/track.md) ...
    for f in [f6, f7] {
        assert!((155..=180).contains(&f), "{f} Hz");
    }
    // ... its size follows the tolerance (ratio 10.3 measured), not the physics ...
    assert!(a6 > 1e-6, "±{a6} m");
    assert!((5.0..20.0).contains(&(a6 / a7)), "{a6} / {a7}");
    // ... and an L-stable method at the same tolerance leaves none of it
    assert!(sr.stats.stiff_from.is_none());
    assert!(ar < 1e-3 * a6, "Radau5 ±{ar} m");
    // the mean height is the same in all three runs
    let mean = |z: &[f64]| z[z.len() - 1000..].iter().sum::<f64>() / 1000.0;
    for z in [&z7, &zr] {
        assert!(
            (mean(z) - mean(&z6)).abs() < 0.1e-6,
            "{} vs {}",
            mean(z),
            mean(&z6)
        );
    }
}
