//! A run that starts inside a curve from its quasi-static state (`[initial] state =
//! "quasi-static"`, `railsim_sim::InitialState::QuasiStatic`): the steady state at the start,
//! found by Newton's method, from which the vehicle runs on steadily from the first sample. A
//! static start there is refused (the members placed on their own frames miss each other by
//! the curve's versines), so without it a run in a curve must begin on the tangent before it.

use crate::common;

use railsim_contact::{ContactModelKind, TravelOptions};
use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic, quasi_static_curving};
use railsim_sim::{InitialState, Sample, Scene, Simulation};

/// The Manchester vehicle (carbody x frozen, DOPRI5 at its default tolerances) with contact
/// model `model` on `track` at `kmh`, starting at `start_m`, with the `[initial]` keys `initial`.
fn manchester(
    track: &str,
    model: &str,
    kmh: f64,
    start_m: f64,
    seconds: f64,
    initial: &str,
) -> Scene {
    common::scene(&format!(
        r#"
        vehicle = "vehicles/manchester_vehicle1.toml"
        track = "{track}"
        freeze = ["carbody.x"]
        speed_kmh = {kmh}
        start_m = {start_m}
        duration_s = {seconds}
        [contact]
        model = "{model}"
        [initial]
        {initial}
        "#
    ))
}

/// [`manchester`] from the quasi-static state.
fn quasi_static(track: &str, model: &str, kmh: f64, start_m: f64, seconds: f64) -> Scene {
    manchester(
        track,
        model,
        kmh,
        start_m,
        seconds,
        "state = \"quasi-static\"",
    )
}

/// The largest change of any wheelset's lateral displacement \[m\] and of any wheel's Y or Q
/// \[N\] from the first sample.
fn drift(samples: &[Sample]) -> (f64, f64) {
    let first = &samples[0];
    let (mut lateral, mut force) = (0.0f64, 0.0f64);
    for s in samples {
        for (a, b) in s.lateral.iter().zip(&first.lateral) {
            lateral = lateral.max((a - b).abs());
        }
        for (a, b) in s.wheelsets.iter().zip(&first.wheelsets) {
            for d in [
                a.y_left_n - b.y_left_n,
                a.y_right_n - b.y_right_n,
                a.q_left_n - b.q_left_n,
                a.q_right_n - b.q_right_n,
            ] {
                force = force.max(d.abs());
            }
        }
    }
    (lateral, force)
}

/// R = 300 m, 150 mm cant, 80 km/h (`tracks/curve_r300.toml`, a right curve; 0.7 m/s² cant
/// deficiency), `polach`: the run's first sample is the quasi-static curving solution of the
/// same curve (`railsim curving --method quasi-static`: the same equations solved on the
/// curving study's own track), and the vehicle stays there: over 1.5 s no wheelset moves
/// laterally by more than 1 µm and no wheel force changes by more than 150 N (measured 0.1 µm
/// and 62 N: DOPRI5's stability-limited ripple at atol 1e-8, docs/models/ode.md).
#[test]
fn a_run_started_in_a_curve_from_its_quasi_static_state_runs_on_steadily() {
    let scene = quasi_static("tracks/curve_r300.toml", "polach", 80.0, 420.0, 1.5);
    assert_eq!(scene.initial_state, InitialState::QuasiStatic);
    let (sim, samples, _) = common::run(&scene);
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    println!("{iterations} Newton iterations, residual {residual:.3}");
    assert!(iterations > 0 && residual <= 1.0);
    let reference = quasi_static_curving(
        &scene,
        &CurveCase {
            radius: 300.0,
            cant: 0.15,
            left: false,
            speed: 80.0 / 3.6,
        },
        &CurvingRun::default(),
        &QuasiStatic::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let first = &samples[0];
    for (n, (w, m)) in first.wheelsets.iter().zip(&reference.wheelsets).enumerate() {
        println!(
            "ws{n}: Y {:.1} {:.1} against {:.1} {:.1} N, Q {:.1} {:.1} against {:.1} {:.1} N, lateral {:.4} against {:.4} mm",
            w.y_left_n,
            w.y_right_n,
            m.wheels[0].y,
            m.wheels[1].y,
            w.q_left_n,
            w.q_right_n,
            m.wheels[0].q,
            m.wheels[1].q,
            first.lateral[n] * 1e3,
            m.lateral * 1e3
        );
        // (Newton's force tolerance: 1e-3 of the mean static wheel load, 55 N)
        for (got, want) in [
            (w.y_left_n, m.wheels[0].y),
            (w.y_right_n, m.wheels[1].y),
            (w.q_left_n, m.wheels[0].q),
            (w.q_right_n, m.wheels[1].q),
        ] {
            assert!((got - want).abs() < 55.0, "ws{n}: {got} against {want} N");
        }
        assert!((first.lateral[n] - m.lateral).abs() < 1e-6);
    }
    // the leading wheelset runs out toward the outer (left) rail by several millimetres
    assert!(first.lateral[0] > 5e-3, "{}", first.lateral[0]);
    let (lateral, force) = drift(&samples);
    println!("drift over 1.5 s: {:.4} mm, {force:.1} N", lateral * 1e3);
    assert!(lateral < 1e-6 && force < 150.0, "{lateral} m, {force} N");
}

/// R = 300 m with 100 mm cant at 40 km/h (0.24 m/s² cant excess), `polach`: Newton from the
/// static start does not reach the steady state (its line search stalls after 5 iterations), so
/// the start comes from the curving case's continuation in curvature and cant, and the run is
/// steady from it. The same start with `stripes`, whose forces Newton reaches directly here.
#[test]
fn a_quasi_static_start_that_needs_the_continuation_is_steady_too() {
    let track = "crates/railsim-sim/tests/tracks/r300_cant100.toml";
    for model in ["polach", "stripes"] {
        let scene = quasi_static(track, model, 40.0, 100.0, 1.0);
        let (sim, samples, _) = common::run(&scene);
        let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
        let (lateral, force) = drift(&samples);
        println!(
            "{model}: {iterations} Newton iterations, residual {residual:.3}; drift over 1 s {:.4} mm, {force:.1} N",
            lateral * 1e3
        );
        assert!(residual <= 1.0);
        assert!(lateral < 1e-6 && force < 150.0, "{lateral} m, {force} N");
        // a left curve: the leading wheelset toward the outer (right) rail, the trailing one of
        // the bogie toward the inner one (cant excess)
        assert!(samples[0].lateral[0] < -5e-3 && samples[0].lateral[1] > 2e-3);
    }
}

/// R = 150 m, 40 km/h, `stripes`: Newton from the static start stalls (STRIPES' forces are not
/// smooth enough for it from afar), from `polach`'s quasi-static state it converges in a few
/// iterations. On these rigid rails that steady state is unstable (the flange contact's
/// flutter, docs/models/contact.md §8), so the run stays near it only briefly: within 2 µm and
/// 500 N over the first 0.05 s (measured 0.7 µm and 95 N; later the oscillation grows to kN).
#[test]
fn stripes_start_from_the_polach_state() {
    let scene = quasi_static("tracks/curve_r150.toml", "stripes", 40.0, 150.0, 0.05);
    let (sim, samples, _) = common::run(&scene);
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    let polach = quasi_static("tracks/curve_r150.toml", "polach", 40.0, 150.0, 0.05);
    let psim = Simulation::new(&polach).unwrap();
    let (p_iterations, _) = psim.quasi_static_start().unwrap();
    let (lateral, force) = drift(&samples);
    println!(
        "stripes: {iterations} Newton iterations in all (polach {p_iterations}), residual {residual:.3}; drift {:.4} mm, {force:.1} N",
        lateral * 1e3
    );
    assert!(residual <= 1.0 && iterations > p_iterations);
    assert!(lateral < 2e-6 && force < 500.0, "{lateral} m, {force} N");
}

/// The shipped scene `scenes/manchester_in_curve_r300.toml` (R = 300 m, 150 mm cant, 80 km/h)
/// starts with `stripes` at the default 1 mm contact step. Until the start got the curving
/// case's continuation with the scene's own model as its last fallback it did not: Newton
/// stalled from the static state (largest scaled residual 32.4) and from `polach`'s (29.8), and
/// the scene set `step_mm = 0.5` as a workaround. Now the continuation reaches the steady state
/// (25 iterations in all, residual below 0.1) and the leading wheelsets lie where the 0.5 mm
/// start puts them (criterion 0.05 mm, as the curving test's between `stripes` and `polach`).
#[test]
fn the_in_curve_scene_starts_with_stripes_at_the_default_step() {
    let path = common::root().join("scenes/manchester_in_curve_r300.toml");
    let mut scene = Scene::from_file(&path).unwrap();
    assert_eq!(scene.contact.model, ContactModelKind::Stripes);
    let default_step = TravelOptions::default().step;
    assert_eq!(scene.contact.travel.step, default_step);
    let sim = Simulation::new(&scene).unwrap_or_else(|e| panic!("{e}"));
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    scene.contact.travel.step = 0.5e-3;
    let fine = Simulation::new(&scene).unwrap();
    let (fine_iterations, fine_residual) = fine.quasi_static_start().unwrap();
    println!(
        "1 mm: {iterations} iterations, residual {residual:.3}; 0.5 mm: {fine_iterations}, {fine_residual:.3}"
    );
    assert!(residual <= 1.0 && iterations <= 40);
    for ws in ["ws1", "ws3"] {
        let i = common::state_index(&sim, &format!("{ws}.y"));
        let (a, b) = (sim.initial_state()[i], fine.initial_state()[i]);
        println!(
            "{ws}: {:.4} mm at 1 mm, {:.4} mm at 0.5 mm",
            a * 1e3,
            b * 1e3
        );
        assert!(a.abs() > 5e-3 && (a - b).abs() < 0.05e-3, "{ws}: {a} / {b}");
    }
}

/// The in-curve scene with out-of-round wheels (a fifth-order polygon on ws1, a flat on ws3):
/// its quasi-static start goes through the curving case's study, which has round wheels and so
/// no rolled-angle lags (`MemberModel::rolled_angle`); the scene's own Newton then takes that
/// state with the lags at zero and holds them there (a lag grows while a wheel rolls on a
/// radius other than r0: no steady state keeps it). It starts (until stop 35's rolled angles
/// were given to the study's state, the lags' index was out of its bounds: a panic), with every
/// lag at zero and the same wheelset positions as the round-wheeled scene's start to 0.05 mm.
#[test]
fn an_out_of_round_vehicle_starts_in_the_curve_from_its_quasi_static_state() {
    let dir = std::env::temp_dir().join(format!("railsim-qs-oor-{}", std::process::id()));
    let vehicle = common::out_of_round_manchester(&dir, 0.0);
    let path = common::root().join("scenes/manchester_in_curve_r300.toml");
    let scene_text = std::fs::read_to_string(&path).unwrap().replace(
        "vehicle = \"../vehicles/manchester_vehicle1.toml\"",
        &format!("vehicle = \"{}\"", vehicle.display()),
    );
    let scene = Scene::from_toml_str(&scene_text, "in_curve.toml", path.parent().unwrap())
        .unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_dir_all(&dir).ok();
    let sim = Simulation::new(&scene).unwrap_or_else(|e| panic!("{e}"));
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    let round = Simulation::new(&Scene::from_file(&path).unwrap()).unwrap();
    println!("out of round: {iterations} iterations, residual {residual:.3}");
    assert!(residual <= 1.0);
    for ws in ["ws1", "ws3"] {
        let lag = common::state_index(&sim, &format!("{ws} rolled angle lag"));
        assert_eq!(sim.initial_state()[lag], 0.0);
        let i = common::state_index(&sim, &format!("{ws}.y"));
        let j = common::state_index(&round, &format!("{ws}.y"));
        let (a, b) = (sim.initial_state()[i], round.initial_state()[j]);
        println!("{ws}: {:.4} mm against {:.4} mm round", a * 1e3, b * 1e3);
        assert!((a - b).abs() < 0.05e-3, "{ws}: {a} / {b}");
    }
}

/// R = 150 m, 100 mm cant at 120 km/h (6.7 m/s² uncompensated; the curving study finds no
/// steady state there either): the start is an error that says so and what to do instead.
#[test]
fn a_curve_without_a_steady_state_is_an_error() {
    let scene = quasi_static("tracks/curve_r150.toml", "polach", 120.0, 150.0, 0.3);
    let e = Simulation::new(&scene)
        .err()
        .expect("no steady state")
        .to_string();
    println!("{e}");
    assert!(
        e.contains("quasi-static start of scene")
            && e.contains("at s = 150.00 m: no steady state found")
            && e.contains("state = \"static\""),
        "{e}"
    );
}

/// Irregular rails under the vehicle at the start (`tracks/straight_irregular_into_r1200.toml`,
/// ERRI B176 low, 160 km/h, `polach`): the wheelsets start with the lateral, vertical and roll
/// rates of the rails moving under them (`run::follow_rails`), so neither start hits the rails.
/// Every wheel load over the first 0.05 s, at the quasi-static start in the R = 1200 m curve
/// (where Newton finds the state whose other rates vanish on the rails as they are there) and at
/// a static start at s = 300 m on the tangent: 38.5–70.0 and 47.8–59.5 kN (criterion 30–80 kN);
/// with the wheelsets started at rest, 1.7–131.0 and 2.7–90.2 kN.
#[test]
fn the_wheelsets_start_with_the_rails_moving_under_them() {
    let track = "tracks/straight_irregular_into_r1200.toml";
    let in_curve = quasi_static(track, "polach", 160.0, 1000.0, 0.05);
    let on_tangent = manchester(track, "polach", 160.0, 300.0, 0.05, "");
    for (name, scene) in [("quasi-static", in_curve), ("static", on_tangent)] {
        let (sim, samples, _) = common::run(&scene);
        if let Some((iterations, residual)) = sim.quasi_static_start() {
            println!("{name}: {iterations} Newton iterations, residual {residual:.3}");
            assert!(residual <= 1.0);
        }
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for w in samples.iter().flat_map(|s| &s.wheelsets) {
            for q in [w.q_left_n, w.q_right_n] {
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
        println!(
            "{name}: wheel loads {:.1} .. {:.1} kN",
            lo * 1e-3,
            hi * 1e-3
        );
        assert!(lo > 30e3 && hi < 80e3, "{name}: {lo} .. {hi} N");
    }
}

/// The R = 150 m curve on the elastic rail support (`tracks/curve_r150_elastic.toml`, 40 km/h,
/// `polach`): Newton from the static start stalls, and the continuation in quarters of the
/// curvature and cant stalls at its second step (R = 300 m from the solution at 600 m). With that
/// step halved (R = 400 m) it goes on by quarters (R = 240, 171, 150 m; 29 Newton iterations in
/// all) to the steady state, and the run stays there (0.4 N over 0.5 s; criteria as above).
#[test]
fn the_continuation_halves_its_step_where_newton_fails() {
    let scene = quasi_static("tracks/curve_r150_elastic.toml", "polach", 40.0, 150.0, 0.5);
    let t = std::time::Instant::now();
    let (sim, samples, _) = common::run(&scene);
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    let (lateral, force) = drift(&samples);
    println!(
        "{iterations} Newton iterations, residual {residual:.3}; drift over 0.5 s {:.4} mm, {force:.1} N; {:.1} s",
        lateral * 1e3,
        t.elapsed().as_secs_f64()
    );
    assert!(residual <= 1.0);
    assert!(lateral < 1e-6 && force < 150.0, "{lateral} m, {force} N");
}

/// A disturbance with the quasi-static start (R = 1200 m, 120 mm cant, 118 km/h, `polach`; the
/// leading wheelset 5.2 mm out toward the outer rail on its tread): `lateral_offset_mm = 1`
/// moves it 1 mm back in from its steady position, and the rest of the vehicle is balanced about
/// it held there. Released, it returns to the undisturbed start's steady state (within 0.3 s;
/// after 1 s within 10 µm) without a flange impact (every wheel load 45–65 kN, measured
/// 49.7–59.2 kN). Near a flange contact such a kick ends in one: the same 0.5 mm kick at
/// R = 300 m, 80 km/h gives 160 kN on rigid rails (docs/models/dynamics.md). (The case was at
/// 120 km/h until stop 26: with the vehicle's loaded geometry Newton stalls there, 12.85 times
/// the tolerance on the vertical balance of the front bogie's trailing wheelset, while 115, 118,
/// 122 and 125 km/h converge in 8–9 iterations and the time integration settles at 120 km/h;
/// docs/validation.md §10.)
#[test]
fn a_disturbance_is_added_to_the_steady_state_and_decays() {
    let track = "tracks/curve_r1200.toml";
    let steady = quasi_static(track, "polach", 118.0, 600.0, 0.05);
    let (_, steady, _) = common::run(&steady);
    let kicked = manchester(
        track,
        "polach",
        118.0,
        600.0,
        1.0,
        "state = \"quasi-static\"\nlateral_offset_mm = 1",
    );
    let (sim, samples, _) = common::run(&kicked);
    let (iterations, residual) = sim.quasi_static_start().expect("a quasi-static start");
    let (y0, y_first) = (steady[0].lateral[0], samples[0].lateral[0]);
    let y_last = samples.last().unwrap().lateral[0];
    println!(
        "{iterations} Newton iterations, residual {residual:.3}; lead wheelset steady {:.4} mm, kicked {:.4} mm, after 1 s {:.4} mm",
        y0 * 1e3,
        y_first * 1e3,
        y_last * 1e3
    );
    assert!(residual <= 1.0);
    assert!(
        (y_first - (y0 + 1e-3)).abs() < 1e-6,
        "{y_first} against {y0}"
    );
    assert!((y_last - y0).abs() < 10e-6, "{y_last} against {y0}");
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for w in samples.iter().flat_map(|s| &s.wheelsets) {
        for q in [w.q_left_n, w.q_right_n] {
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    println!("wheel loads {:.1} .. {:.1} kN", lo * 1e-3, hi * 1e-3);
    assert!(lo > 45e3 && hi < 65e3, "{lo} .. {hi} N");
}
