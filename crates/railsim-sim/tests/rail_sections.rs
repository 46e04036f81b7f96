//! Rails that change along the track (`[[rail_section]]` in the track file): each wheel is
//! evaluated on the rails under it, so a vehicle crossing a change of rail inclination takes
//! it wheelset by wheelset, and runs on like a vehicle on the new rails throughout.
use crate::common;

use common::{manchester_polach, run, state_index};
use railsim_sim::Sample;

/// A straight ideal track of 300 m at the inclination `incl`, with `sections` appended,
/// written to a temporary file named after `tag`; its path.
fn track(tag: &str, incl: &str, sections: &str) -> String {
    track_with_gauge(tag, 1435.0, incl, sections)
}

/// As [`track`], with the gauge `gauge_mm`.
fn track_with_gauge(tag: &str, gauge_mm: f64, incl: &str, sections: &str) -> String {
    let dir = std::env::temp_dir().join(format!("railsim-rail-sections-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{tag}.toml"));
    std::fs::write(
        &path,
        format!(
            "gauge_mm = {gauge_mm}\nrail_inclination = \"{incl}\"\n\
             rail_profile = {{ left = \"uic60\", right = \"uic60\" }}\n\
             [[segment]]\ntype = \"tangent\"\nlength_m = 300\n{sections}"
        ),
    )
    .unwrap();
    path.display().to_string()
}

/// \[m\] where the rails change in the sectioned track
const CHANGE: f64 = 100.0;
/// \[m/s\]
const SPEED: f64 = 20.0;
/// \[m\] track position of the vehicle reference at t = 0
const START: f64 = 80.0;
/// \[m\] the wheelsets' x in the vehicle (front first)
const WHEELSETS: [f64; 4] = [10.78, 8.22, -8.22, -10.78];

/// The samples of the Manchester vehicle (`polach`) running 85 m at 20 m/s from s = 80 m on
/// `track_file`.
fn samples(track_file: &str) -> Vec<Sample> {
    let s = manchester_polach(&format!(
        "track = \"{track_file}\"\nspeed_kmh = {}\nstart_m = {START}\ndistance_m = 85\n\
         [log]\nrate_hz = 1000",
        SPEED * 3.6
    ));
    run(&s).1
}

/// State `index` (a wheelset's height) at every sample.
fn heights(samples: &[Sample], index: usize) -> Vec<f64> {
    samples.iter().map(|s| s.x[index]).collect()
}

/// The mean of `z` over its last 2000 samples (2 s at 1 kHz): on 1:20 the height keeps a small
/// oscillation (±4 µm with `polach`: DOPRI5 at atol 1e-6 on the edge of its stability region,
/// docs/models/track.md and `tests/stiffness.rs`).
fn late(z: &[f64]) -> f64 {
    let k = z.len() - 2000;
    z[k..].iter().sum::<f64>() / (z.len() - k) as f64
}

#[test]
fn each_wheelset_takes_the_new_rails_where_it_reaches_them() {
    let at_40 = track("at_1_40", "1:40", "");
    let at_20 = track("at_1_20", "1:20", "");
    let changed = track(
        "changed",
        "1:40",
        &format!("[[rail_section]]\nstart_m = {CHANGE}\nrail_inclination = \"1:20\"\n"),
    );
    let (a, b, c) = (samples(&at_40), samples(&at_20), samples(&changed));
    assert_eq!(a.len(), c.len());
    let sim = railsim_sim::Simulation::new(&manchester_polach(&format!(
        "track = \"{changed}\"\nspeed_kmh = 72\nstart_m = {START}\ndistance_m = 45"
    )))
    .unwrap();
    assert_eq!(sim.model().track.rail_sections().len(), 2);
    for (n, x) in WHEELSETS.iter().enumerate() {
        let iz = state_index(&sim, &format!("ws{}.z", n + 1));
        let (za, zb, zc) = (heights(&a, iz), heights(&b, iz), heights(&c, iz));
        // the time this wheelset reaches the change, the first sample where it differs from
        // the run on the old rails at all, and where by more than 30 µm (its own jump is about
        // 90 µm, what the others pass on through the bogie and the carbody a few µm)
        let t_cross = (CHANGE - START - x) / SPEED;
        let differs = |by: f64| {
            let k = zc.iter().zip(&za).position(|(c, a)| (c - a).abs() > by);
            c[k.unwrap()].t
        };
        let (t_first, t_jump) = (differs(1e-9), differs(30e-6));
        // the heights on the two inclinations and on the changed track, means over the last 2 s
        let (z40, z20, end) = (late(&za), late(&zb), late(&zc));
        eprintln!(
            "ws{}: reaches the change at {t_cross:.4} s, first differs at {t_first:.4} s, by 30 µm at {t_jump:.4} s; \
             height {:.4} mm on 1:40, {:.4} mm on 1:20, {:.4} mm on the changed track (means \
             over the last 2 s)",
            n + 1,
            z40 * 1e3,
            z20 * 1e3,
            end * 1e3
        );
        // nothing changes before the front wheelset reaches the change; each wheelset's height
        // jumps as it reaches it (within 4 ms: 8 cm)
        let t_front = (CHANGE - START - WHEELSETS[0]) / SPEED;
        assert!(t_first >= t_front - 1e-3, "{t_first} vs {t_front}");
        assert!(
            (0.0..4e-3).contains(&(t_jump - t_cross)),
            "{t_jump} vs {t_cross}"
        );
        // the inclination moves the contact and with it the wheelset's height
        assert!((z40 - z20).abs() > 1e-5, "{z40} {z20}");
        // at the end (all wheelsets 12 m or more past the change, as the last 2 s begin) the
        // run is the one on 1:20
        assert!(
            (end - z20).abs() < 0.02 * (z40 - z20).abs(),
            "{end} vs {z20} (1:40: {z40})"
        );
    }
}

/// A section that widens the gauge (1435 to 1450 mm, as in a tight curve) moves each rail
/// 7.5 mm outward under the wheels that reach it: their contact moves toward the field side and
/// the wheelsets run on as on a track of 1450 mm throughout.
#[test]
fn a_section_widens_the_gauge_under_the_wheelsets_that_reach_it() {
    let narrow = track("gauge_1435", "1:40", "");
    let wide = track_with_gauge("gauge_1450", 1450.0, "1:40", "");
    let widened = track(
        "widened",
        "1:40",
        &format!("[[rail_section]]\nstart_m = {CHANGE}\ngauge_mm = 1450\n"),
    );
    let (a, b, c) = (samples(&narrow), samples(&wide), samples(&widened));
    assert_eq!(a.len(), c.len());
    let sim = railsim_sim::Simulation::new(&manchester_polach(&format!(
        "track = \"{widened}\"\nspeed_kmh = 72\nstart_m = {START}\ndistance_m = 45"
    )))
    .unwrap();
    for n in 0..WHEELSETS.len() {
        let iz = state_index(&sim, &format!("ws{}.z", n + 1));
        let (za, zb, zc) = (heights(&a, iz), heights(&b, iz), heights(&c, iz));
        let (z35, z50, end) = (late(&za), late(&zb), late(&zc));
        eprintln!(
            "ws{}: height {:.4} mm at 1435 mm, {:.4} mm at 1450 mm, {:.4} mm widened at {CHANGE} m \
             (means over the last 2 s)",
            n + 1,
            z35 * 1e3,
            z50 * 1e3,
            end * 1e3
        );
        // the wider gauge lowers the wheelsets (a smaller rolling radius on the field side) ...
        assert!(z50 < z35 - 1e-5, "{z35} {z50}");
        // ... and past the change the run is the one on the wide gauge
        assert!(
            (end - z50).abs() < 0.02 * (z35 - z50),
            "{end} vs {z50} (1435 mm: {z35})"
        );
        // before the leading wheelset reaches it, nothing changes
        let t_front = (CHANGE - START - WHEELSETS[0]) / SPEED;
        let k = a.iter().position(|s| s.t >= t_front - 1e-3).unwrap();
        assert!(
            za[..k]
                .iter()
                .zip(&zc[..k])
                .all(|(x, y)| (x - y).abs() < 1e-9),
            "ws{} changed before {t_front} s",
            n + 1
        );
    }
}

/// The largest change of any wheel's vertical force Q from its value at the start.
fn q_swing(samples: &[Sample]) -> f64 {
    let q = |s: &Sample| -> Vec<f64> {
        s.wheelsets
            .iter()
            .flat_map(|w| [w.q_left_n, w.q_right_n])
            .collect()
    };
    let q0 = q(&samples[0]);
    samples
        .iter()
        .flat_map(|s| q(s).into_iter().zip(q0.clone()).map(|(a, b)| (a - b).abs()))
        .fold(0.0, f64::max)
}

/// Over a transition (`transition_m`) the wheel's forces pass linearly from the old rails' to
/// the new ones': the front wheelset's height moves between the two rails' heights while it
/// crosses, and the step the wheels take at an abrupt change (an impact) is gone.
#[test]
fn a_transition_spreads_the_change_of_rails() {
    let length = 5.0;
    let abrupt = track(
        "abrupt",
        "1:40",
        &format!("[[rail_section]]\nstart_m = {CHANGE}\nrail_inclination = \"1:20\"\n"),
    );
    let spread = track(
        "spread",
        "1:40",
        &format!(
            "[[rail_section]]\nstart_m = {CHANGE}\nrail_inclination = \"1:20\"\n\
             transition_m = {length}\n"
        ),
    );
    let (a, c) = (samples(&abrupt), samples(&spread));
    let sim = railsim_sim::Simulation::new(&manchester_polach(&format!(
        "track = \"{spread}\"\nspeed_kmh = 72\nstart_m = {START}\ndistance_m = 45"
    )))
    .unwrap();
    assert_eq!(sim.model().track.rail_sections()[1].transition, length);
    let iz = state_index(&sim, "ws1.z");
    let z_at = |run: &[Sample], t: f64| {
        run.iter()
            .min_by(|p, q| (p.t - t).abs().total_cmp(&(q.t - t).abs()))
            .unwrap()
            .x[iz]
    };
    let t_in = (CHANGE - START - WHEELSETS[0]) / SPEED;
    let t_out = t_in + length / SPEED;
    // before the transition and after it, the two runs agree (1:40; then 1:20, means over the
    // last 2 s as in the test above)
    let (z40, z20) = (z_at(&a, t_in - 0.01), late(&heights(&a, iz)));
    assert!((z_at(&c, t_in - 0.01) - z40).abs() < 1e-9);
    assert!((late(&heights(&c, iz)) - z20).abs() < 0.02 * (z40 - z20).abs());
    // inside, the height is between the two and passes them in order
    let quarter = |f: f64| z_at(&c, t_in + f * (t_out - t_in));
    let (q1, q2, q3) = (quarter(0.25), quarter(0.5), quarter(0.75));
    eprintln!(
        "ws1 height: 1:40 {:.4} mm; in the transition {:.4} / {:.4} / {:.4} mm; 1:20 {:.4} mm",
        z40 * 1e3,
        q1 * 1e3,
        q2 * 1e3,
        q3 * 1e3,
        z20 * 1e3
    );
    let (lo, hi) = (z40.min(z20), z40.max(z20));
    for q in [q1, q2, q3] {
        assert!(q > lo && q < hi, "{q} outside {lo} .. {hi}");
    }
    assert!((q1 - z40).abs() < (q2 - z40).abs() && (q2 - z40).abs() < (q3 - z40).abs());
    // the wheels' vertical forces: an abrupt change is a step in the rails, a transition
    // spreads it over 5 m
    let (swing_a, swing_c) = (q_swing(&a), q_swing(&c));
    eprintln!(
        "largest change of a wheel's Q: {:.1} kN abrupt, {:.1} kN over {length} m",
        swing_a * 1e-3,
        swing_c * 1e-3
    );
    assert!(swing_c < 0.2 * swing_a, "{swing_c} vs {swing_a}");
}

/// A start with a wheelset over a rail transition is refused (the static equilibrium at the
/// start is on one section's rails), naming the key, the vehicle's extent and the transition;
/// a start over an abrupt change is fine (each wheelset settles on its own rails).
#[test]
fn a_start_over_a_rail_transition_is_refused() {
    let spread = track(
        "start_over",
        "1:40",
        "[[rail_section]]\nstart_m = 100\nrail_inclination = \"1:20\"\ntransition_m = 5\n",
    );
    let text = |start: f64| {
        format!(
            "vehicle = \"vehicles/manchester_vehicle1.toml\"\ntrack = \"{spread}\"\n\
             speed_kmh = 72\nstart_m = {start}\ndistance_m = 10\n"
        )
    };
    let err = match railsim_sim::Scene::from_toml_str(&text(95.0), "over.toml", &common::root()) {
        Ok(_) => panic!("a start over the transition is an error"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("over.toml:4:")
            && err.contains("start_m = 95 m")
            && err.contains("over the rail transition at s = 100.00 .. 105.00 m"),
        "{err}"
    );
    // the whole vehicle before it, or over an abrupt change: accepted
    assert!(railsim_sim::Scene::from_toml_str(&text(80.0), "before.toml", &common::root()).is_ok());
    let abrupt = track(
        "start_abrupt",
        "1:40",
        "[[rail_section]]\nstart_m = 100\nrail_inclination = \"1:20\"\n",
    );
    let text = format!(
        "vehicle = \"vehicles/manchester_vehicle1.toml\"\ntrack = \"{abrupt}\"\n\
         speed_kmh = 72\nstart_m = 95\ndistance_m = 10\n"
    );
    assert!(railsim_sim::Scene::from_toml_str(&text, "abrupt.toml", &common::root()).is_ok());
}

/// A lubricated stretch inside the R = 150 m curve (`friction` by contact angle in a rail
/// section from s = 160 m: 0.3 up to 15°, 0.1 from 25° on): nothing changes until the leading
/// wheelset reaches it; then its outer wheel, in flange contact, dissipates far less.
#[test]
fn a_lubricated_section_relieves_the_flanging_wheel_from_its_start() {
    let curve = std::fs::read_to_string(common::root().join("tracks/curve_r150.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("railsim-rail-sections-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |tag: &str, extra: &str| {
        let path = dir.join(format!("{tag}.toml"));
        std::fs::write(&path, format!("{curve}\n{extra}")).unwrap();
        path.display().to_string()
    };
    let dry = write("r150_dry", "");
    let lubricated = write(
        "r150_lubricated",
        "[[rail_section]]\nstart_m = 160\n\
         friction = { contact_angle_deg = [15, 25], coefficient = [0.3, 0.1] }\n",
    );
    let (start, speed) = (39.0, 40.0 / 3.6);
    let run_on = |track: &str| {
        run(&manchester_polach(&format!(
            "track = \"{track}\"\nspeed_kmh = 40\nstart_m = {start}\nduration_s = 12\n\
             [log]\nrate_hz = 100"
        )))
        .1
    };
    let (a, b) = (run_on(&dry), run_on(&lubricated));
    assert_eq!(a.len(), b.len());
    // a left curve: the leading wheelset's outer wheel is its right one
    let wear = |s: &Sample| s.wheelsets[0].wear_number_right_n;
    let mean = |run: &[Sample], t0: f64, t1: f64| {
        let w: Vec<f64> = run
            .iter()
            .filter(|s| s.t >= t0 && s.t < t1)
            .map(wear)
            .collect();
        w.iter().sum::<f64>() / w.len() as f64
    };
    let t_reach = (160.0 - start - WHEELSETS[0]) / speed;
    let first = a
        .iter()
        .zip(&b)
        .position(|(p, q)| (p.x[0] - q.x[0]).abs() > 0.0 || wear(p) != wear(q))
        .map(|k| a[k].t);
    let (before, dry_after, after) = (
        mean(&a, t_reach - 1.5, t_reach - 0.5),
        mean(&a, t_reach + 1.0, 12.0),
        mean(&b, t_reach + 1.0, 12.0),
    );
    eprintln!(
        "leading wheelset reaches the section at {t_reach:.2} s, the runs first differ at {first:?} s; \
         outer wheel's Tγ {before:.1} N before, {dry_after:.1} N dry and {after:.1} N lubricated after"
    );
    assert!(first.is_some_and(|t| t >= t_reach - 0.01), "{first:?}");
    assert!(after < 0.4 * dry_after, "{after} vs {dry_after}");
    assert!(
        (dry_after / before - 1.0).abs() < 0.1,
        "{before} {dry_after}"
    );
}

/// The integrator ends a step wherever the right-hand side has a kink or a jump in time: here
/// where each wheelset meets a rail section's transition and leaves it (`SimModel::breakpoints`).
/// Without them Radau5 at rtol 1e-4, atol 1e-6 stepped over the start of the measured rail's
/// transition with an error its estimate did not see, and the leading wheelset rang for a
/// second with Q up to 81.9 kN in the samples (docs/performance.md, "Choosing the integrator");
/// the reference solution (DOPRI5 at rtol 1e-6, atol 1e-8) has no wheel's Q above 58.0 kN.
#[test]
fn steps_end_where_a_wheelset_meets_a_rail_transition() {
    let path = common::root().join("scenes/manchester_rail_sections.toml");
    let mut scene = railsim_sim::Scene::from_file(&path).unwrap();
    scene.integrator = railsim_ode::Method::radau5(1e-4, 1e-6);
    let sim = railsim_sim::Simulation::new(&scene).unwrap();
    let model = sim.model();
    let v = 120.0 / 3.6;
    let bps = model.breakpoints(0.0, 10.8);
    let sections = model.track.rail_sections();
    let mut expected = Vec::new();
    for m in model
        .members
        .iter()
        .filter(|m| matches!(m.kind, railsim_sim::model::MemberKind::Wheelset { .. }))
    {
        for r in &sections[1..] {
            for edge in [r.start, r.start + r.transition] {
                expected.push((edge - 120.0 - m.p0[0]) / v);
            }
        }
    }
    assert_eq!(expected.len(), 16);
    for t in &expected {
        assert!(
            bps.iter().any(|b| (b - t).abs() < 1e-9),
            "no breakpoint at {t} s in {bps:?}"
        );
    }
    assert_eq!(bps.len(), expected.len(), "{bps:?}");
    let (_, samples, _) = run(&scene);
    let q_max = samples
        .iter()
        .flat_map(|s| s.wheelsets.iter().flat_map(|w| [w.q_left_n, w.q_right_n]))
        .fold(0.0, f64::max);
    eprintln!(
        "largest Q with Radau5 at 1e-4 / 1e-6: {:.1} kN",
        q_max * 1e-3
    );
    assert!(q_max < 60e3, "largest Q {q_max} N");
}
