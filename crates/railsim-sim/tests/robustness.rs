//! Randomly damaged vehicle files: every one is a located error, fails to find its initial state
//! with a message, or runs (to the end or to a stop that names time, body and quantity), never a
//! panic or a non-finite state.

use std::path::PathBuf;

use crate::common;

use railsim_sim::{RunOptions, Scene, SimError, Simulation};

/// Knuth's 64-bit LCG, uniform in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn pick(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}

/// Byte ranges (line, start, end) of the numbers outside comments.
fn numbers(text: &str) -> Vec<(usize, usize, usize)> {
    let mut out = vec![];
    for (ln, line) in text.lines().enumerate() {
        let b = line.split('#').next().unwrap_or("").as_bytes();
        let mut i = 0;
        while i < b.len() {
            let starts = b[i].is_ascii_digit()
                || (b[i] == b'-' && b.get(i + 1).is_some_and(|c| c.is_ascii_digit()));
            let glued = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
            if !starts {
                i += 1;
                continue;
            }
            let s = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"._+-".contains(&b[i])) {
                i += 1;
            }
            if !glued {
                out.push((ln, s, i));
            }
        }
    }
    out
}

/// One or two numbers of `text` replaced: by 0, its negative, 1e30, nan, 1e-30, or 100, 0.01 or
/// 3 times itself.
fn mutate(text: &str, spans: &[(usize, usize, usize)], rng: &mut Lcg) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..1 + rng.pick(2) {
        let (ln, s, e) = spans[rng.pick(spans.len())];
        let v: f64 = lines[ln][s..e].parse().unwrap_or(1.0);
        let new = match rng.pick(8) {
            0 => "0".to_string(),
            1 => format!("{}", -v),
            2 => "1e30".to_string(),
            3 => "nan".to_string(),
            4 => format!("{}", v * 100.0),
            5 => format!("{}", v * 0.01),
            6 => "1e-30".to_string(),
            _ => format!("{}", v * 3.0),
        };
        lines[ln] = format!("{}{}{}", &lines[ln][..s], new, &lines[ln][e..]);
    }
    lines.join("\n")
}

#[test]
fn damaged_vehicle_files_give_located_errors_or_run() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let vehicle = std::fs::read_to_string(root.join("vehicles/manchester_vehicle1.toml")).unwrap();
    let spans = numbers(&vehicle);
    assert!(spans.len() > 100);
    let dir = std::env::temp_dir().join(format!("railsim-robustness-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let track = root.join("tracks/straight.toml");
    let scene_text = format!(
        "vehicle = \"v.toml\"\ntrack = \"{}\"\nspeed_kmh = 198\nduration_s = 0.05\n",
        track.display()
    );
    let mut rng = Lcg(3);
    let (mut located, mut initial, mut stopped, mut ran) = (0, 0, 0, 0);
    for k in 0..60 {
        let text = mutate(&vehicle, &spans, &mut rng);
        std::fs::write(dir.join("v.toml"), &text).unwrap();
        let scene = match Scene::from_toml_str(&scene_text, "s.toml", &dir) {
            Ok(s) => s,
            Err(e) => {
                // the problem is in the vehicle file, with line and column
                assert!(e.to_string().contains("v.toml:"), "{k}: {e}");
                located += 1;
                continue;
            }
        };
        let result = Simulation::new(&scene).and_then(|mut sim| {
            let opts = RunOptions {
                no_log: true,
                ..Default::default()
            };
            sim.run(&scene, &opts, &mut |_, _| {}, &mut |s| {
                assert!(s.t.is_finite());
            })
        });
        match result {
            Ok(_) => ran += 1,
            Err(SimError::Initial { .. }) => initial += 1,
            Err(SimError::Stopped { body, quantity, .. }) => {
                assert!(!body.is_empty() && !quantity.is_empty());
                stopped += 1;
            }
            Err(e) => panic!("{k}: unexpected error {e}\n{text}"),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "{located} located errors, {initial} without an initial state, {stopped} stopped, {ran} ran"
    );
    assert!(located > 10 && ran > 10);
}

/// At walking pace the creep forces act as very stiff dampers (creepages are slip velocities over
/// the rolling speed, 0.01 m/s here): a trial stage of Dormand–Prince overshoots to a negative
/// rolling speed, which the contact model cannot evaluate. That rejects the step (it stopped the
/// run at t = 0.1 ms before trial failures were retried); the run goes on with shorter steps.
#[test]
fn a_contact_failure_at_a_trial_stage_shortens_the_step() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene_text = format!(
        "vehicle = \"{}\"\ntrack = \"{}\"\nspeed_kmh = 0.036\nduration_s = 0.0003\n\
         freeze = [\"carbody.x\"]\n[integrator]\nmethod = \"dopri5\"\nrtol = 1e-4\natol = 1e-6\n",
        root.join("vehicles/manchester_vehicle1.toml").display(),
        root.join("tracks/straight.toml").display()
    );
    let scene = Scene::from_toml_str(&scene_text, "s.toml", &root).unwrap();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let summary = Simulation::new(&scene)
        .and_then(|mut sim| sim.run(&scene, &opts, &mut |_, _| {}, &mut |_| {}))
        .unwrap();
    assert!(
        summary.stats.trial_failures > 0,
        "no trial stage failed: {:?}",
        summary.stats
    );
    // less than one 2 m window: no sliding mean of Y/Q
    let wheels = &summary.assessment.wheels;
    assert!(!wheels.is_empty() && wheels.iter().all(|w| w.y_over_q.is_empty()));
    assert!(summary.max_y_over_q.is_some());
}

/// The 2 m sliding mean of Y/Q is taken once the run has covered 2 m, whatever the spacing of
/// the samples: at 250 km/h and 200 Hz they are 0.347 m apart, and the mean was never taken
/// before (the oldest kept sample had to lie 1.9 m back, and 5 × 0.347 m is 1.74 m).
#[test]
fn the_2_m_mean_of_y_over_q_is_taken_at_any_sample_spacing() {
    let scene = common::scene(
        r#"
        vehicle = "vehicles/wheelset_free.toml"
        track = "tracks/straight.toml"
        speed_kmh = 250
        duration_s = 0.06
        [log]
        rate_hz = 200
        "#,
    );
    let (_, _, summary) = common::run(&scene);
    // 4.2 m run, 13 samples: windows ending at 2, 2.5, 3, 3.5 and 4 m
    assert_eq!(summary.samples, 13);
    for w in &summary.assessment.wheels {
        assert_eq!(w.y_over_q.len(), 1, "{w:?}");
        let z = &w.y_over_q[0];
        assert_eq!(z.windows, 5);
        assert!(z.percentile.is_finite() && z.percentile <= z.largest.value + 1e-12);
    }
}

/// A run whose solution reaches a contact limit stops there naming the wheel: a free S1002
/// wheelset (no suspension) started off centre and yawed at 200–300 km/h hunts violently into
/// flange contact, and its yaw may pass the profile's locus limit (29.4 mrad). Its motion is
/// chaotic (which start reaches the limit changes with any change of the contact forces), so
/// several starts are run: every stop must name the wheelset, at least one must be the yaw
/// limit naming the wheel.
#[test]
fn a_contact_limit_reached_by_the_solution_stops_the_run_naming_the_wheel() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut yaw_stops = 0;
    for (speed, offset, yaw) in [(200, 3, 20), (250, 3, 10), (250, 5, 10), (300, 3, 10)] {
        let scene_text = format!(
            "vehicle = \"{}\"\ntrack = \"{}\"\nspeed_kmh = {speed}\nduration_s = 1\n\
             [initial]\nlateral_offset_mm = {offset}\nyaw_mrad = {yaw}\n",
            root.join("vehicles/wheelset_free.toml").display(),
            root.join("tracks/straight.toml").display()
        );
        let scene = Scene::from_toml_str(&scene_text, "s.toml", &root).unwrap();
        let opts = RunOptions {
            no_log: true,
            ..Default::default()
        };
        let result = Simulation::new(&scene)
            .and_then(|mut sim| sim.run(&scene, &opts, &mut |_, _| {}, &mut |_| {}));
        match result {
            Ok(_) => {}
            Err(SimError::Stopped {
                t, body, quantity, ..
            }) => {
                eprintln!(
                    "{speed} km/h, {offset} mm, {yaw} mrad: stopped at {t:.3} s: {body}: {quantity}"
                );
                assert!(
                    body.starts_with("ws") || body.starts_with("wheelset 'ws'"),
                    "{body}"
                );
                if quantity.starts_with("contact: wheelset yaw [rad]") {
                    assert!(body.starts_with("wheelset 'ws', "), "{body}: {quantity}");
                    assert!(t > 0.0 && t < 1.0, "{t}");
                    yaw_stops += 1;
                }
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(yaw_stops > 0, "no start reached the yaw limit");
}

/// The wheels' contact evaluations run in parallel on a thread of a rayon pool (as `railsim`
/// runs its commands) and one after the other elsewhere: the runs are identical, bit for bit,
/// with `stripes` on irregular track, where every wheel's contact differs.
#[test]
fn the_wheels_in_parallel_give_the_same_run_bit_for_bit() {
    let scene = common::scene(
        r#"
        vehicle = "vehicles/manchester_vehicle1.toml"
        track = "tracks/straight_irregular.toml"
        speed_kmh = 198
        duration_s = 0.5
        [log]
        rate_hz = 200
        "#,
    );
    let (_, _, alone) = common::run(&scene);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let (_, _, shared) = pool.install(|| common::run(&scene));
    assert_eq!(alone.digest, shared.digest);
    assert_eq!(alone.stats.rhs_evals, shared.stats.rhs_evals);
    assert!(alone.samples > 100, "{}", alone.samples);
}

/// A restart (`Simulation::start_from`) checks its state and time, and a run restarted from its
/// own start state at t = 0 is the run itself.
#[test]
fn a_restart_checks_its_state_and_time_and_a_restart_at_the_start_is_the_run() {
    let scene = common::scene(
        r#"
        vehicle = "vehicles/wheelset_free.toml"
        track = "tracks/straight.toml"
        speed_kmh = 100
        duration_s = 0.2
        [initial]
        lateral_offset_mm = 1
        "#,
    );
    let mut sim = Simulation::new(&scene).unwrap();
    let x = sim.initial_state().to_vec();
    let err = |r: Result<(), railsim_sim::SimError>| r.unwrap_err().to_string();
    assert!(err(sim.start_from(0.0, &x[1..])).contains("restart state of"));
    let mut bad = x.clone();
    bad[2] = f64::NAN;
    assert!(err(sim.start_from(0.0, &bad)).contains("is NaN"));
    assert!(err(sim.start_from(0.2, &x)).contains("outside the run's [0, 0.2) s"));
    assert!(err(sim.start_from(-1.0, &x)).contains("outside"));
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let (_, _, whole) = common::run(&scene);
    sim.start_from(0.0, &x).unwrap();
    let again = sim.run(&scene, &opts, &mut |_, _| {}, &mut |_| {}).unwrap();
    assert_eq!(whole.digest, again.digest);
    // restarted half way: the samples from there on, on the log's grid
    sim.start_from(0.1, &x).unwrap();
    let mut times = Vec::new();
    let half = sim
        .run(&scene, &opts, &mut |_, _| {}, &mut |s| times.push(s.t))
        .unwrap();
    assert_eq!(half.samples as usize, times.len());
    assert!((times[0] - 0.1).abs() < 1e-9 && (times[times.len() - 1] - 0.2).abs() < 1e-9);
    let early = RunOptions {
        t_end: Some(0.05),
        ..opts
    };
    let e = sim
        .run(&scene, &early, &mut |_, _| {}, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("not after its start at 0.1 s"), "{e}");
}

/// A static equilibrium beyond a limit is not an instability: on a rail support of 2 MN/m per
/// wheel the rails of the Manchester vehicle rest 27 mm down under their 54.5 kN, beyond the
/// 10 mm limit of the rail's displacement, before any step. The stop names the rail and says
/// that the initial state is beyond the limit and which keys to check (it said "unstable").
#[test]
fn a_static_state_beyond_a_limit_is_not_called_unstable() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let track = std::fs::read_to_string(root.join("tracks/straight_elastic.toml")).unwrap();
    let soft = track.replace(
        "vertical_stiffness_mn_m = 100",
        "vertical_stiffness_mn_m = 2",
    );
    assert_ne!(soft, track);
    let dir = std::env::temp_dir().join(format!("railsim-soft-rail-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("t.toml"), soft).unwrap();
    let scene_text = format!(
        "vehicle = \"{}\"\ntrack = \"t.toml\"\nspeed_kmh = 198\nduration_s = 0.05\n",
        root.join("vehicles/manchester_vehicle1.toml").display()
    );
    let scene = Scene::from_toml_str(&scene_text, "s.toml", &dir).unwrap();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let result = Simulation::new(&scene)
        .and_then(|mut sim| sim.run(&scene, &opts, &mut |_, _| {}, &mut |_| {}));
    let _ = std::fs::remove_dir_all(&dir);
    match result {
        Err(SimError::Stopped {
            t, body, quantity, ..
        }) => {
            assert_eq!(t, 0.0);
            assert!(body.starts_with("rail under wheelset"), "{body}");
            assert!(
                quantity.starts_with("vertical displacement -27")
                    && quantity.contains("in the initial state, before any step")
                    && quantity.contains("the rail support")
                    && !quantity.contains("unstable"),
                "{quantity}"
            );
        }
        other => panic!("{other:?}"),
    }
}
