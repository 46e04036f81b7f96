//! The elastic rail support (`docs/models/track.md`, "Elastic rail support"): its static
//! deflection in the initial state, and the damping it brings to two-point flange contact.

use railsim_sim::{Sample, Scene, Simulation};
use railsim_track::RailSupport;

use crate::common;
use common::{run, scene};

fn manchester_on(track: &str, duration_s: f64, extra: &str) -> Scene {
    scene(&format!(
        r#"
        vehicle = "vehicles/manchester_vehicle1.toml"
        track = "{track}"
        speed_kmh = 40
        duration_s = {duration_s}
        freeze = ["carbody.x"]
        {extra}
        [integrator]
        method = "dopri5"
        rtol = 1e-4
        atol = 1e-6
        [log]
        rate_hz = 100
        "#
    ))
}

/// \[m\] How far a wheelset's rails lie from their static balance k d = −(force on the wheel)
/// (Y toward the field side): the largest of the four components.
fn imbalance(w: &railsim_log::messages::WheelsetMessage, sup: &RailSupport) -> f64 {
    let d = w.rail_displacement_m.expect("rail displacements logged");
    let expected = [
        w.y_left_n / sup.lateral_stiffness,
        -w.q_left_n / sup.vertical_stiffness,
        -w.y_right_n / sup.lateral_stiffness,
        -w.q_right_n / sup.vertical_stiffness,
    ];
    (0..4)
        .map(|k| (d[k] - expected[k]).abs())
        .fold(0.0, f64::max)
}

#[test]
fn an_elastic_rail_support_starts_in_static_equilibrium() {
    let rigid = Simulation::new(&manchester_on("tracks/straight.toml", 1.0, "")).unwrap();
    let s = manchester_on("tracks/straight_elastic.toml", 2.0, "");
    let (sim, samples, summary) = run(&s);
    // Model only what the scene requires: four rail states per wheel, none on rigid rails.
    let m = sim.model();
    assert_eq!(m.dim(), rigid.model().dim() + 4 * m.wheels.len());
    assert_eq!(rigid.model().n_rail, 0);
    let sup = m.rail_support.expect("rail support");
    let (mut worst_rail, mut worst_q, mut worst_drift) = (0.0f64, 0.0f64, 0.0f64);
    let q0: Vec<[f64; 2]> = samples[0]
        .wheelsets
        .iter()
        .map(|w| [w.q_left_n, w.q_right_n])
        .collect();
    for smp in &samples {
        for (w, q0) in smp.wheelsets.iter().zip(&q0) {
            worst_rail = worst_rail.max(imbalance(w, &sup));
            for (q, q0) in [w.q_left_n, w.q_right_n].into_iter().zip(q0) {
                worst_q = worst_q.max((q / 54.5e3 - 1.0).abs());
                worst_drift = worst_drift.max((q / q0 - 1.0).abs());
            }
        }
    }
    let d = samples[0].wheelsets[0].rail_displacement_m.unwrap();
    eprintln!(
        "rail deflection {:.4} mm down, {:.4} mm lateral; worst rail balance {:.2e} m, wheel load {:.3} %, drift {:.2e}",
        -d[1] * 1e3,
        d[0] * 1e3,
        worst_rail,
        worst_q * 100.0,
        worst_drift
    );
    // 54.5 kN on 100 MN/m: 0.545 mm.
    assert!((-d[1] - 54.5e3 / sup.vertical_stiffness).abs() < 0.01 * 0.545e-3);
    // 0.2 µm: 0.04 % of the static deflection (the loads settle to 1e-10 of the load, the run
    // follows them to the integrator tolerance).
    assert!(
        worst_rail < 2e-7,
        "rail off its static balance by {worst_rail} m"
    );
    assert!(worst_q < 0.01, "wheel load off by {:.2} %", worst_q * 100.0);
    assert!(worst_drift < 1e-3, "wheel loads drift by {worst_drift:.2e}");
    // The run summary's largest rail displacements are those of its samples: the log's and,
    // since stop 33, the assessment's between them (1 kHz on this 100 Hz log), so at least the
    // log samples' largest and, the rails being at rest, within their balance of it.
    let [lat, vert] = summary.max_rail.expect("rail maxima in the summary");
    let max_of = |k: [usize; 2]| {
        samples
            .iter()
            .flat_map(|s| &s.wheelsets)
            .flat_map(|w| {
                let d = w.rail_displacement_m.unwrap();
                [d[k[0]].abs(), d[k[1]].abs()]
            })
            .fold(0.0, f64::max)
    };
    for (summary_max, k) in [(lat.0, [0, 2]), (vert.0, [1, 3])] {
        let logged = max_of(k);
        assert!(
            summary_max >= logged && summary_max - logged < 2e-7,
            "{summary_max} against {logged} m"
        );
    }
    assert!((vert.0 - 54.5e3 / sup.vertical_stiffness).abs() < 0.01 * 0.545e-3);
}

/// Manchester vehicle 1 at 40 km/h and friction 0.4 for 5 s on the test track
/// `r150_short_entry_<support>.toml`: the range of the leading wheelset's outer (right) Q from
/// `t0` to the end, and its maximum over the run.
fn outer_q(support: &str, t0: f64) -> (f64, f64) {
    let track = format!("crates/railsim-sim/tests/tracks/r150_short_entry_{support}.toml");
    let (_, samples, _) = run(&manchester_on(&track, 5.0, "[contact]\nfriction = 0.4"));
    let q = |s: &Sample| s.wheelsets[0].q_right_n;
    let window: Vec<f64> = samples.iter().filter(|s| s.t >= t0).map(q).collect();
    let lo = window.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = window.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let max_q = samples.iter().map(q).fold(0.0, f64::max);
    eprintln!(
        "{support}: outer Q range {:.1} kN from {t0} s, max {:.1} kN",
        (hi - lo) * 1e-3,
        max_q * 1e-3
    );
    (hi - lo, max_q)
}

#[test]
fn a_damped_rail_support_steadies_two_point_flange_contact() {
    // Manchester vehicle 1 at 40 km/h into R = 150 m, friction 0.4: the leading wheelset runs
    // in two-point contact (flange root and flange) on the outer rail. On a damped elastic
    // support it settles (the next test: without damping it does not).
    let (range, max_q) = outer_q("elastic", 4.0);
    assert!(
        range < 10e3,
        "outer Q still swings by {:.1} kN",
        range * 1e-3
    );
    assert!(max_q < 100e3, "outer Q reached {:.1} kN", max_q * 1e-3);
}

#[test]
fn an_undamped_rail_support_lets_two_point_flange_contact_bounce() {
    // The case of the test above on the same support without damping: the creep forces drive
    // the wheel into bouncing on the rail (as on rigid rails, docs/validation.md §6). A test of
    // its own, so that the two 5 s runs share the cores.
    let (range, _) = outer_q("undamped", 3.0);
    assert!(
        range > 50e3,
        "undamped: outer Q swings by only {:.1} kN",
        range * 1e-3
    );
}

/// A soft lateral support (1 MN/m, the format's lower bound) still starts in static balance. The
/// fixed-point iteration of the deflections (rail at −F/k, wheelset settled again) diverged
/// here: the lateral force of a wheel changes with its rail's lateral position faster than the
/// support's stiffness (a fuzzing run found "did not settle within 20 iterations"); Newton's
/// method on the deflections converges.
#[test]
fn a_soft_lateral_rail_support_settles_in_static_balance() {
    let dir = std::env::temp_dir().join(format!("railsim-soft-support-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(common::root().join("tracks/straight_elastic.toml"))
        .unwrap()
        .replace("lateral_stiffness_mn_m = 40", "lateral_stiffness_mn_m = 1");
    let track = dir.join("soft.toml");
    std::fs::write(&track, text).unwrap();
    let s = manchester_on(
        track.to_str().unwrap(),
        0.05,
        "[initial]\nlateral_offset_mm = 1.0",
    );
    let (sim, samples, _) = run(&s);
    std::fs::remove_dir_all(&dir).ok();
    let sup = sim.model().rail_support.expect("rail support");
    assert!((sup.lateral_stiffness - 1e6).abs() < 1e-6);
    let mut worst = 0.0f64;
    let mut lateral = 0.0f64;
    for w in &samples[0].wheelsets {
        let d = w.rail_displacement_m.unwrap();
        worst = worst.max(imbalance(w, &sup));
        lateral = lateral.max(d[0].abs()).max(d[2].abs());
    }
    eprintln!(
        "soft support: lateral rail deflection {:.3} mm, balance {worst:.2e} m",
        lateral * 1e3
    );
    // The deflections balance the static contact forces; the first sample's forces add the
    // rolling wheels' creep forces (a few newtons, as on the stiff support of the test above).
    assert!(
        worst * sup.lateral_stiffness < 10.0,
        "rail off its static balance by {worst} m"
    );
}
