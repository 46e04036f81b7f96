//! Linear stability analysis (`railsim_sim::modal`): the eigenvalues of the linearised vehicle
//! against closed-form results (Klingel, Wickens) and against the time integration of the same
//! model (growth rates and the critical speed of the nonlinear simulator).

use railsim_sim::modal::{ModalOptions, Mode, linear_critical_speed, modes_at};
use railsim_sim::stability::{growth_at, half_cycles};
use railsim_sim::{RunOptions, Simulation};

use crate::common;
use common::{
    centred_contact, manchester_polach, scene, wickens_reference, wickens_scene, wickens_three_dof,
};

/// The oscillatory mode whose largest component is `coord`, least damped first.
fn mode_of<'a>(modes: &'a [Mode], coord: &str) -> &'a Mode {
    modes
        .iter()
        .find(|m| m.is_oscillatory() && m.shape.first().is_some_and(|s| s.0 == coord))
        .unwrap_or_else(|| panic!("no oscillatory mode led by {coord}: {modes:#?}"))
}

#[test]
fn the_free_conical_wheelsets_kinematic_mode_has_klingels_frequency() {
    // λ = 0.2 cones; Klingel's wavelength L = 2π sqrt(r e0 / λ) with r, e0 of the centred
    // contact, so f = V / L, proportional to the speed (vehicle-reference.md §2.1). Hertz and
    // Polach: the rigid contact pair moves smoothly with the pose (STRIPES' strips make the
    // linearisation depend on the difference step, docs/validation.md §11).
    let s = scene(
        r#"
        vehicle = "scenes/vehicles/wheelset_free_cone.toml"
        track = "tracks/straight.toml"
        speed_kmh = 18
        duration_s = 1
        [contact]
        model = "polach"
        "#,
    );
    let (r, e0) = centred_contact(&Simulation::new(&s).unwrap(), 0.5 * 1813.0 * 9.81, 5.0);
    let l_k = std::f64::consts::TAU * (r * e0 / 0.2).sqrt();
    for v in [5.0, 10.0] {
        let a = modes_at(&s, v, &ModalOptions::default()).unwrap();
        let m = mode_of(&a.modes, "ws.y");
        eprintln!(
            "{v} m/s: kinematic mode {:.4} Hz (Klingel {:.4} Hz, {:+.2} %), damping ratio {:.4}, shape {:?}; residual {:?}",
            m.frequency,
            v / l_k,
            100.0 * (m.frequency * l_k / v - 1.0),
            m.damping_ratio,
            m.shape,
            a.residual
        );
        // the simulated wavelength's criterion (tests/dynamics.rs): Klingel's formula neglects the
        // gravitational stiffness and takes the creep coefficients as infinite
        assert!((m.frequency * l_k / v - 1.0).abs() < 0.02);
        // the wheelset yaws with its lateral motion (ψ = ±2π y0 / L at a quarter period)
        assert!(m.shape.iter().any(|(n, _)| n == "ws.yaw"), "{:?}", m.shape);
        // a kinematic oscillation is nearly undamped at low speed
        assert!(m.damping_ratio.abs() < 0.05, "{}", m.damping_ratio);
    }
}

#[test]
fn the_wickens_wheelset_loses_its_damping_where_the_simulation_starts_to_grow() {
    // vehicle-reference.md §2.2: the formula with the wheelset's roll on the rails folded in
    // (tests/dynamics.rs) gives the reference speed; the time simulation's growth-rate bisection
    // found +2.07 % (docs/validation.md §6).
    let base = wickens_scene();
    let vc_formula = wickens_reference(1e8).with_roll;
    let opts = ModalOptions::default();
    let res = linear_critical_speed(&base, &opts, (250.0, 350.0), 4, 1e-3, &mut |_| {}).unwrap();
    let vc = res.critical_speed;
    eprintln!(
        "Wickens: eigenvalues {vc:.2} m/s ({:+.2} % from the formula's {vc_formula:.2} m/s), mode {:.2} Hz {:?}",
        100.0 * (vc / vc_formula - 1.0),
        res.mode.frequency,
        res.mode.shape
    );
    assert!((vc / vc_formula - 1.0).abs() < 0.03);
    // linear creep without spin: the initial state is an exact equilibrium
    let a = modes_at(&base, vc, &opts).unwrap();
    assert!(a.residual.1 < 1e-6, "{:?}", a.residual);
    assert!(res.mode.shape[0].0 == "ws.y" || res.mode.shape[0].0 == "ws.yaw");
    // The same model integrated in time from a 2 µm offset (small enough to stay linear): the measured growth rate of the
    // lateral motion (second half of 1.4 s) is the real part of the eigenvalue, and its sign
    // changes at the linear critical speed.
    for k in [0.97, 1.03] {
        let v = k * vc;
        let a = modes_at(&base, v, &opts).unwrap();
        let lam = mode_of(&a.modes, &res.mode.shape[0].0);
        let g = growth_at(&base, v, 1.4, 0.002e-3).unwrap();
        let rate = g.late_rate.unwrap();
        eprintln!(
            "{:.2} m/s: Re λ = {:.3}/s at {:.3} Hz, simulated growth {rate:.3}/s",
            v, lam.re, lam.frequency
        );
        assert_eq!(lam.re > 0.0, k > 1.0);
        assert_eq!(rate > 0.0, k > 1.0);
        assert!(
            (rate - lam.re).abs() < 0.1 * lam.re.abs(),
            "simulated {rate} vs Re λ {}",
            lam.re
        );
    }
}

#[test]
fn the_wickens_wheelsets_eigenvalues_match_its_lateral_roll_and_yaw_model() {
    // A model derived independently of the simulator (common::wickens_three_dof: the cones'
    // contact kinematics, the roll held by the contact's normal stiffness, the spinning axle's
    // gyroscopic couples) against the eigenvalues of the full linearised wheelset: the critical
    // speed, the hunting frequency and the mode's roll and yaw per lateral displacement.
    let res = linear_critical_speed(
        &wickens_scene(),
        &ModalOptions::default(),
        (250.0, 350.0),
        4,
        1e-4,
        &mut |_| {},
    )
    .unwrap();
    let (vc, mode) = (res.critical_speed, &res.mode);
    let part = |name: &str| {
        mode.shape
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("{name} not in {:?}", mode.shape))
            .1
    };
    assert_eq!(mode.shape[0].0, "ws.y", "{:?}", mode.shape);
    let (roll, yaw) = (part("ws.roll"), part("ws.yaw"));
    let model = wickens_three_dof(1e8, 1.0);
    // the same model with the roll slaved to y (the contact a hundred times stiffer)
    let stiff = wickens_three_dof(1e8, 100.0);
    eprintln!(
        "eigenvalues: {vc:.3} m/s, {:.4} Hz, roll/y {roll:.5}, yaw/y {yaw:.5}; three-DOF model \
         (kn {:.4e} N/m): {:.3} m/s ({:+.3} %), {:.4} Hz, roll/y {:.5}, yaw/y {:.5}; roll slaved: \
         {:.3} m/s, {:.4} Hz, roll/y {:.4}, yaw/y {:.4}",
        mode.frequency,
        model.normal_stiffness,
        model.critical_speed,
        100.0 * (vc / model.critical_speed - 1.0),
        model.frequency,
        model.roll_per_y,
        model.yaw_per_y,
        stiff.critical_speed,
        stiff.frequency,
        stiff.roll_per_y,
        stiff.yaw_per_y
    );
    // (they agree to 3e-6 in speed, 1.3e-5 in frequency and 1.3e-4 in the ratios; the
    // critical speed's search stops at 1e-4)
    assert!((vc / model.critical_speed - 1.0).abs() < 5e-4);
    assert!((mode.frequency / model.frequency - 1.0).abs() < 5e-4);
    assert!((roll / model.roll_per_y - 1.0).abs() < 1e-3);
    assert!((yaw / model.yaw_per_y - 1.0).abs() < 1e-3);
    // the roll's give on the contact matters: slaved, the model is 1.1 % faster and rolls by
    // 43 % more, far outside the bounds above
    assert!((vc / stiff.critical_speed - 1.0).abs() > 0.005);
    assert!(stiff.roll_per_y / roll > 1.2);
}

#[test]
fn a_yawed_cones_contact_leads_the_axle_and_slips_laterally_by_the_yaw_over_cos_delta() {
    // The kinematics the lateral-roll-yaw model rests on (common::wickens_three_dof), read at
    // the contact of the Wickens scene's cones (λ = tan δ = 0.15) on UIC60 1:40: a wheelset
    // yawed by ψ and rolling freely (Ω = V / r0) has its contact lead the axle by
    // (r0 tan δ - b) ψ, and its wheel point slips along the patch's lateral axis by -V ψ / cos δ.
    use railsim_contact::{Side, WheelsetPose, WheelsetVelocity};
    let w = wickens_reference(1e8);
    let (r0, b) = (w.r0, w.b);
    let sim = Simulation::new(&wickens_scene()).unwrap();
    let mut ws = railsim_contact::ContactWorkspace::new();
    let (v, psi, delta) = (28.0, 1e-4, 0.15f64.atan());
    let vel = WheelsetVelocity {
        vx: v,
        spin: v / r0,
        ..Default::default()
    };
    let pose = WheelsetPose {
        yaw: psi,
        ..Default::default()
    };
    sim.model().wheels[0].contacts[0]
        .evaluate_with_load(Side::Left, &pose, &vel, 0.5 * 1813.0 * 9.81, 1e-12, &mut ws)
        .unwrap();
    let p = &ws.patches[0];
    let lead = (r0 * delta.tan() - b) * psi;
    eprintln!(
        "ψ = {psi}: lead {:.4e} m against {lead:.4e}; η = {:.6e} against {:.6e}; angle {:.5}",
        p.point_track[0],
        p.creepages.eta,
        -psi / delta.cos(),
        p.contact_angle
    );
    assert!((p.contact_angle - delta).abs() < 1e-4);
    assert!((p.point_track[0] / lead - 1.0).abs() < 1e-3);
    assert!((p.creepages.eta * delta.cos() / -psi - 1.0).abs() < 1e-3);
}

#[test]
fn the_manchester_vehicles_linear_critical_speed_is_a_bogie_hunting_mode_that_the_simulation_confirms()
 {
    // Polach's contact (smooth in the pose at the difference steps' scale): the critical speed
    // must not depend on the step, the unstable mode must be a bogie's lateral motion, and the
    // simulator itself must see a 10 µm disturbance decay 5 % below and grow 5 % above.
    let s = manchester_polach(
        r#"
        track = "tracks/straight.toml"
        speed_kmh = 200
        duration_s = 1
        "#,
    );
    let range = (150.0 / 3.6, 400.0 / 3.6);
    let fine = ModalOptions {
        position_step: 0.25e-6,
        rate_step: 0.25e-5,
    };
    let coarse = ModalOptions {
        position_step: 4e-6,
        rate_step: 4e-5,
    };
    let a =
        linear_critical_speed(&s, &ModalOptions::default(), range, 5, 2e-3, &mut |_| {}).unwrap();
    let vc = a.critical_speed;
    let (f, c) = (
        linear_critical_speed(&s, &fine, range, 5, 2e-3, &mut |_| {})
            .unwrap()
            .critical_speed,
        linear_critical_speed(&s, &coarse, range, 5, 2e-3, &mut |_| {})
            .unwrap()
            .critical_speed,
    );
    eprintln!(
        "Manchester, polach: linear critical speed {:.2} km/h (steps 0.25 µm {:.2}, 4 µm {:.2}), mode {:.2} Hz, ζ {:.4}, {:?}",
        vc * 3.6,
        f * 3.6,
        c * 3.6,
        a.mode.frequency,
        a.mode.damping_ratio,
        a.mode.shape
    );
    for other in [f, c] {
        assert!((other / vc - 1.0).abs() < 0.005);
    }
    assert!(a.mode.shape[0].0.starts_with("bogie_") && a.mode.shape[0].0.ends_with(".y"));
    assert!(a.mode.frequency > 4.0 && a.mode.frequency < 10.0);
    // the time integration of the same vehicle
    for (k, grows) in [(0.95, false), (1.05, true)] {
        let g = growth_at(&s, k * vc, 6.0, 0.01e-3).unwrap();
        eprintln!(
            "{:.1} km/h: simulated growth {:?}/s, last half wave {:.2} µm",
            k * vc * 3.6,
            g.late_rate,
            g.last_amplitude * 1e6
        );
        assert_eq!(g.late_rate.unwrap() > 0.0, grows);
    }
}

#[test]
fn the_half_cycles_of_a_run_at_the_linear_critical_speed_have_the_modes_frequency() {
    // the Wickens wheelset just above its critical speed: the simulated oscillation's period
    // (between centre-line crossings) against the eigenvalue's frequency
    let base = wickens_scene();
    let v = 305.0;
    let a = modes_at(&base, v, &ModalOptions::default()).unwrap();
    let lam = a.least_stable().unwrap().clone();
    let study = base
        .study(
            railsim_sim::SpeedProfile::constant(v),
            railsim_sim::RunLength::Duration(1.0),
            0.02e-3,
        )
        .unwrap();
    let mut sim = Simulation::new(&study).unwrap();
    let (mut t, mut y) = (Vec::new(), Vec::new());
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    sim.run(&study, &opts, &mut |_, _| {}, &mut |s| {
        t.push(s.t);
        y.push(s.lateral[0]);
    })
    .unwrap();
    let c = half_cycles(&t, &y, 0.0, 1e-9);
    let late: Vec<_> = c.iter().filter(|h| h.t > 0.3).collect();
    let f_sim = (late.len() - 1) as f64 / (2.0 * (late[late.len() - 1].t - late[0].t));
    eprintln!(
        "{v} m/s: simulated {f_sim:.3} Hz over {} half waves, eigenvalue {:.3} Hz",
        late.len(),
        lam.frequency
    );
    assert!((f_sim / lam.frequency - 1.0).abs() < 0.01);
}

#[test]
fn bad_modal_settings_are_reported() {
    let s = wickens_scene();
    let err = |r: Result<(), railsim_sim::SimError>| r.expect_err("an error").to_string();
    let e = err(modes_at(&s, -3.0, &ModalOptions::default()).map(|_| ()));
    assert!(
        e.contains("speed must be positive") && e.contains("-3"),
        "{e}"
    );
    let e = err(modes_at(
        &s,
        100.0,
        &ModalOptions {
            position_step: 0.0,
            rate_step: 1e-5,
        },
    )
    .map(|_| ()));
    assert!(e.contains("difference steps"), "{e}");
    let opts = ModalOptions::default();
    let e = err(linear_critical_speed(&s, &opts, (320.0, 350.0), 2, 1e-3, &mut |_| {}).map(|_| ()));
    assert!(
        e.contains("already unstable") && e.contains("start lower"),
        "{e}"
    );
    let e = err(linear_critical_speed(&s, &opts, (100.0, 200.0), 2, 1e-3, &mut |_| {}).map(|_| ()));
    assert!(
        e.contains("damped up to") && e.contains("search higher"),
        "{e}"
    );
    let e = err(linear_critical_speed(&s, &opts, (200.0, 100.0), 2, 1e-3, &mut |_| {}).map(|_| ()));
    assert!(e.contains("0 < lo < hi"), "{e}");
}

/// A mode's animation (`animate_mode`): the logged lateral position of the Wickens wheelset
/// swings about the equilibrium by the asked amplitude with the mode's period, 50 frames per
/// period; a real mode or a bad amplitude is an error.
#[test]
fn a_modes_animation_logs_its_shape_at_its_frequency() {
    let mut s = wickens_scene();
    s.log.topics = vec![railsim_sim::Topic::Bodies];
    let a = modes_at(&s, 305.0, &ModalOptions::default()).unwrap();
    let m = mode_of(&a.modes, "ws.y").clone();
    let dir = std::env::temp_dir().join(format!("railsim-modal-{}", std::process::id()));
    let log = dir.join("mode.mcap");
    let stats = railsim_sim::modal::animate_mode(&s, &a, &m, 2e-3, 3.0, &log)
        .unwrap_or_else(|e| panic!("{e}"));
    let reader = railsim_log::LogReader::open(&stats.path).unwrap();
    let msgs: Vec<(u64, railsim_log::BodyState)> = reader
        .read_topic(&railsim_log::topics::body("ws"), None)
        .unwrap();
    assert_eq!(msgs.len(), 151, "3 periods of 50 frames and the last");
    let (t, y): (Vec<f64>, Vec<f64>) = msgs.iter().map(|(_, b)| (b.t_s, b.position[1])).unzip();
    let y_max = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // ws.y leads the mode: its swing is the amplitude (the centred equilibrium at y = 0)
    assert!((y_max / 2e-3 - 1.0).abs() < 1e-3, "{y_max}");
    let c = half_cycles(&t, &y, 0.0, 1e-6);
    let period = 2.0 * (c[c.len() - 1].t - c[0].t) / (c.len() - 1) as f64;
    eprintln!(
        "animation: {} half waves, period {period:.5} s against 1/f = {:.5} s",
        c.len(),
        1.0 / m.frequency
    );
    assert!((period * m.frequency - 1.0).abs() < 0.01);
    let real = a.modes.iter().find(|m| !m.is_oscillatory()).unwrap();
    let e = railsim_sim::modal::animate_mode(&s, &a, real, 2e-3, 3.0, &log).unwrap_err();
    assert!(e.to_string().contains("not oscillatory"), "{e}");
    let e = railsim_sim::modal::animate_mode(&s, &a, &m, 0.2, 3.0, &log).unwrap_err();
    assert!(e.to_string().contains("amplitude must lie in"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Modes in steady curving (`modes_in_curve`): about the quasi-static curving state.
/// - In a curve so wide (R = 50 km, no cant) that the wheels stay within micrometres of the
///   centre, the modes are those of straight track: the least damped oscillatory ones agree.
/// - In R = 600 m with 100 mm cant at 80 km/h, where the time integration settles, every mode
///   decays; the least damped one differs from straight track's (the wheels run off centre on
///   other contact geometry).
#[test]
fn modes_in_a_curve_are_the_straight_tracks_in_a_wide_curve_and_stable_where_curving_settles() {
    use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic};
    use railsim_sim::modal::modes_in_curve;
    let s = manchester_polach(
        r#"
        track = "tracks/straight.toml"
        speed_kmh = 100
        duration_s = 1
        "#,
    );
    let opts = ModalOptions::default();
    let v = 100.0 / 3.6;
    let straight = modes_at(&s, v, &opts).unwrap();
    let wide = CurveCase {
        radius: 50e3,
        cant: 0.0,
        left: true,
        speed: v,
    };
    let curve = modes_in_curve(
        &s,
        &wide,
        &CurvingRun::default(),
        &QuasiStatic::default(),
        &opts,
    )
    .unwrap();
    let osc = |m: &[Mode]| -> Vec<(f64, f64)> {
        m.iter()
            .filter(|m| m.is_oscillatory())
            .take(6)
            .map(|m| (m.re, m.frequency))
            .collect()
    };
    let (a, b) = (osc(&straight.modes), osc(&curve.modes));
    eprintln!("straight {a:?}\ncurve R = 50 km {b:?}");
    for ((ra, fa), (rb, fb)) in a.iter().zip(&b) {
        assert!((fa - fb).abs() < 0.01 * fa, "{fa} Hz against {fb} Hz");
        assert!(
            (ra - rb).abs() < 0.02 * ra.abs() + 0.01,
            "{ra} against {rb}"
        );
    }
    let case = CurveCase {
        radius: 600.0,
        cant: 0.1,
        left: true,
        speed: 80.0 / 3.6,
    };
    let c = modes_in_curve(
        &s,
        &case,
        &CurvingRun::default(),
        &QuasiStatic::default(),
        &opts,
    )
    .unwrap();
    let least = c.least_stable().unwrap();
    let straight80 = modes_at(&s, 80.0 / 3.6, &opts).unwrap();
    eprintln!(
        "R = 600 m, 80 km/h: least damped {:.3} Hz, ζ {:.4}, {:?} (residual {:?}); straight: {:.3} Hz, ζ {:.4}",
        least.frequency,
        least.damping_ratio,
        least.shape,
        c.residual,
        straight80.least_stable().unwrap().frequency,
        straight80.least_stable().unwrap().damping_ratio
    );
    assert!(c.modes.iter().all(|m| m.re < 0.0), "{:?}", c.modes[0]);
    assert!(c.residual.1 < 1e-3, "{:?}", c.residual);
}

/// The linear critical speed about steady curving (`linear_critical_speed_about`) tends to
/// straight track's as the radius grows, and a wide curve already moves it: at R = 50 km the
/// wheelsets run 0.04–0.09 mm off centre at 240 km/h, on the conformal tread of S1002 whose
/// contact changes within tens of micrometres, and the critical speed is 4 % lower (239.6
/// against 249.7 km/h when written; the equilibrium's tolerance does not change it: 239.7 with
/// a thousand times tighter forces).
#[test]
fn the_linear_critical_speed_in_a_curve_tends_to_straight_tracks_as_the_radius_grows() {
    use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic};
    use railsim_sim::modal::{Linearisation, linear_critical_speed_about};
    let s = manchester_polach(
        r#"
        track = "tracks/straight.toml"
        speed_kmh = 200
        duration_s = 1
        "#,
    );
    let (opts, range) = (ModalOptions::default(), (200.0 / 3.6, 320.0 / 3.6));
    let straight = linear_critical_speed(&s, &opts, range, 8, 2e-3, &mut |_| {})
        .unwrap()
        .critical_speed;
    let in_curve = |radius: f64| {
        let about = Linearisation::Curve {
            case: CurveCase {
                radius,
                cant: 0.0,
                left: true,
                speed: 0.0,
            },
            run: CurvingRun::default(),
            qs: QuasiStatic::default(),
        };
        linear_critical_speed_about(&s, &about, &opts, range, 8, 2e-3, &mut |_| {})
            .unwrap()
            .critical_speed
    };
    let (far, wide) = (in_curve(1e6), in_curve(5e4));
    eprintln!(
        "linear critical speed: straight {:.2}, R = 1000 km {:.2}, R = 50 km {:.2} km/h",
        straight * 3.6,
        far * 3.6,
        wide * 3.6
    );
    assert!((far / straight - 1.0).abs() < 0.002, "{far} {straight}");
    assert!(wide < 0.99 * straight, "{wide} {straight}");
}

/// The linear critical speed about steady curving, checked by the time integration in the
/// curve: the run of the curving case restarted (`Simulation::start_from`) from the steady state
/// with the leading wheelset 10 µm further out; its late growth rate is negative 5 % below the
/// linear critical speed and positive 5 % above, as on straight track (R = 10 km, no cant, where
/// the critical speed is 24 % below straight track's).
#[test]
fn a_disturbance_of_steady_curving_decays_below_the_curves_linear_critical_speed_and_grows_above() {
    use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic, curving_scene};
    use railsim_sim::modal::{Linearisation, linear_critical_speed_about, modes_in_curve};
    use railsim_sim::stability::growth_rate;
    let s = manchester_polach(
        r#"
        track = "tracks/straight.toml"
        speed_kmh = 200
        duration_s = 1
        "#,
    );
    let opts = ModalOptions::default();
    let case = CurveCase {
        radius: 10e3,
        cant: 0.0,
        left: true,
        speed: 0.0,
    };
    // a curve long enough for 8 s after the restart
    let run = CurvingRun {
        average: 500.0,
        ..CurvingRun::default()
    };
    // the steady state solved tightly: the disturbance decays to below a micrometre, which
    // the default tolerance (1e-3 of the wheel load) would leave as an offset
    let qs = QuasiStatic {
        force_tol: 1e-7,
        rate_tol: 1e-10,
        ..QuasiStatic::default()
    };
    let about = Linearisation::Curve { case, run, qs };
    let vc = linear_critical_speed_about(
        &s,
        &about,
        &opts,
        (120.0 / 3.6, 250.0 / 3.6),
        6,
        2e-3,
        &mut |_| {},
    )
    .unwrap()
    .critical_speed;
    eprintln!("R = 10 km: linear critical speed {:.2} km/h", vc * 3.6);
    for (k, grows) in [(0.95, false), (1.05, true)] {
        let case = CurveCase {
            speed: k * vc,
            ..case
        };
        let a = modes_in_curve(&s, &case, &run, &qs, &opts).unwrap();
        let (study, _) = curving_scene(&s, &case, &run).unwrap();
        let mut sim = Simulation::new(&study).unwrap();
        let model = sim.model();
        // the leading wheelset (numbered 0) and its lateral coordinate
        let w0 = model
            .wheels
            .iter()
            .find(|w| w.wheelset_number == 0)
            .unwrap()
            .member
            .0;
        let iy = model.members[w0].pos[1].unwrap();
        // each wheelset oscillates about its steady lateral offset
        let centre = sim.sample_at(a.time, &a.equilibrium).unwrap().lateral;
        let mut x = a.equilibrium.clone();
        x[iy] += 10e-6;
        sim.start_from(a.time, &x).unwrap();
        let mut t = Vec::new();
        let mut y: Vec<Vec<f64>> = vec![Vec::new(); 4];
        let opts_run = RunOptions {
            no_log: true,
            ..Default::default()
        };
        sim.run(&study, &opts_run, &mut |_, _| {}, &mut |smp| {
            t.push(smp.t);
            for (n, v) in smp.lateral.iter().enumerate() {
                y[n].push(*v);
            }
        })
        .unwrap();
        let t_end = t[t.len() - 1];
        // after the first second, once the other wheelsets move with the leading one
        let late = a.time + 1.0;
        let rate = y
            .iter()
            .enumerate()
            .filter_map(|(n, yy)| growth_rate(&half_cycles(&t, yy, centre[n], 1e-9), late))
            .fold(f64::NEG_INFINITY, f64::max);
        eprintln!(
            "{:.1} km/h in R = 10 km: restarted at {:.2} s, run to {:.2} s, late growth {rate:.4}/s (least damped mode Re λ {:.4}/s)",
            k * vc * 3.6,
            a.time,
            t_end,
            a.least_stable().unwrap().re
        );
        assert!(rate.is_finite());
        assert_eq!(rate > 0.0, grows, "{rate}");
    }
}

/// The linearisation point's spin balances a traction torque (`run::settle_spins` with the
/// rolling-equilibrium target): a free wheelset driven by 2 kN·m at 72 km/h starts in free
/// rolling, its spin accelerating at T/I_y (no creep torque), and the modal analysis sets the
/// spin where the creep torque balances T, its spin acceleration below 1e-6 rad/s² (the
/// settling's tolerance). Fails if the analysis linearised about the free-rolling spin.
#[test]
fn the_modal_equilibrium_balances_a_traction_torque_by_creep() {
    use railsim_ode::OdeSystem;
    use railsim_sim::dynamics::Dynamics;
    use railsim_sim::modal::modal_scene;
    let dir = std::env::temp_dir().join(format!("railsim_modal_torque_{}", std::process::id()));
    let s = common::driven_wheelset(&dir, "");
    let speed = 20.0;
    let analysis = modes_at(&s, speed, &ModalOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let sim = Simulation::new(&modal_scene(&s, speed).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let m = sim.model();
    let spin = common::state_index(&sim, "d/dt ws.spin");
    let i_y = m.members[0].inertia[1][1];
    let mut d = Dynamics::new(m);
    let mut dx = vec![0.0; m.dim()];
    d.rhs(0.0, sim.initial_state(), &mut dx).unwrap();
    let free = dx[spin];
    d.rhs(0.0, &analysis.equilibrium, &mut dx).unwrap();
    let settled = dx[spin];
    eprintln!(
        "spin acceleration: free rolling {free:.4} rad/s² (T/I_y {:.4}), modal equilibrium {settled:.2e}; spin {:.6} -> {:.6} rad/s",
        2000.0 / i_y,
        sim.initial_state()[spin],
        analysis.equilibrium[spin]
    );
    assert!((free - 2000.0 / i_y).abs() < 1e-5);
    assert!(settled.abs() < 1e-6, "{settled}");
}

/// With a traction torque on every axle of the Manchester vehicle (5 kN·m, carbody x frozen) the
/// modal equilibrium is balanced as a whole, not only in the spins: Newton on the whole state
/// (`curving::newton_steady`) after the spins leaves every acceleration within its tolerance,
/// and each wheelset's two primary springs carry its creep force T/r0 longitudinally to the bogie
/// (before stop 42 they carried nothing: the state linearised about accelerated the wheelsets
/// at 6 m/s², and the CLI noted that it was no equilibrium). Without a torque the state is
/// already balanced (no Newton iteration).
#[test]
fn the_modal_equilibrium_carries_a_traction_torque_through_the_suspension() {
    let dir = std::env::temp_dir().join(format!("railsim_modal_traction_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(common::root().join("vehicles/manchester_vehicle1.toml"))
        .unwrap()
        .replace("[[wheelset]]\n", "[[wheelset]]\ntorque_nm = 5000\n");
    assert_eq!(text.matches("torque_nm = 5000").count(), 4);
    let vehicle = dir.join("driven.toml");
    std::fs::write(&vehicle, text).unwrap();
    let keys = "track = \"tracks/straight.toml\"\nspeed_kmh = 200\nduration_s = 1";
    let s = common::vehicle_polach(vehicle.to_str().unwrap(), keys);
    let speed = 200.0 / 3.6;
    let analysis = modes_at(&s, speed, &ModalOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    std::fs::remove_dir_all(&dir).ok();
    let iterations = analysis.balance.clone().unwrap_or_else(|e| panic!("{e}"));
    eprintln!(
        "Newton iterations {iterations}, residual {:.2e} ({})",
        analysis.residual.1, analysis.residual.0
    );
    assert!(iterations > 0);
    assert!(analysis.residual.1 < 1e-2, "{:?}", analysis.residual);
    // the primary springs' longitudinal forces on each wheelset at the equilibrium, in the
    // track frame: their local axes are the bogie's, pitched by θ under the traction (about
    // 2.4 mrad; the springs' 41 kN vertical force then has 98 N along the track)
    let mut sim = Simulation::new(&railsim_sim::modal::modal_scene(&s, speed).unwrap()).unwrap();
    let sample = sim.sample_at(analysis.time, &analysis.equilibrium).unwrap();
    let model = sim.model();
    let names: Vec<&str> = model.elements.iter().map(|e| e.name.as_str()).collect();
    let state = |n: &str| {
        let k = model.state_names.iter().position(|m| m == n).unwrap();
        analysis.equilibrium[k]
    };
    let carried = 5000.0 / 0.46;
    for ws in 1..=4 {
        let bogie = if ws <= 2 { "bogie_front" } else { "bogie_rear" };
        let (sin, cos) = state(&format!("{bogie}.pitch")).sin_cos();
        let fx: f64 = ["l", "r"]
            .iter()
            .map(|side| {
                let name = format!("primary_ws{ws}_{side}");
                let i = names.iter().position(|n| *n == name).unwrap();
                let f = sample.elements[i].force;
                cos * f[0] + sin * f[2]
            })
            .sum();
        eprintln!("ws{ws}: primary springs' Fx {fx:.1} N, T/r0 {carried:.1} N");
        // the creep force drives the wheelset forward; its springs hold it back
        assert!((-fx / carried - 1.0).abs() < 2e-3, "ws{ws}: {fx} N");
    }
    // without a torque: balanced already
    let plain = modes_at(
        &common::manchester_polach(keys),
        speed,
        &ModalOptions::default(),
    )
    .unwrap();
    assert_eq!(plain.balance, Ok(0));
}

/// The friction-induced instability of two-point flange contact on rigid rails
/// (docs/models/contact.md §8, docs/validation.md §6) in the linearisation about steady curving:
/// Manchester vehicle 1 in R = 150 m with 100 mm cant at 40 km/h. With `stripes` at friction 0.3
/// an oscillatory mode of the leading wheelset on its contact stiffness (z, roll, y; about
/// 135 Hz) grows, as its time integration oscillates; at friction 0.2, where the time
/// integration settles, and with `polach` at 0.3, which settles too, every oscillatory mode
/// decays. (The growth rate depends little on the difference step: +67.6, +73.0, +35.1, +5.6/s
/// at 0.25, 1, 4, 16 µm, `railsim modes --step-um`.)
#[test]
fn two_point_flange_contact_on_rigid_rails_linearises_unstable_where_its_time_integration_oscillates()
 {
    use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic};
    use railsim_sim::modal::modes_in_curve;
    let case = CurveCase {
        radius: 150.0,
        cant: 0.1,
        left: true,
        speed: 40.0 / 3.6,
    };
    for (model, friction, unstable) in [
        ("stripes", 0.3, true),
        ("stripes", 0.2, false),
        ("polach", 0.3, false),
    ] {
        let s = scene(&format!(
            "vehicle = \"vehicles/manchester_vehicle1.toml\"\ntrack = \"tracks/straight.toml\"\n\
             speed_kmh = 40\nduration_s = 1\nfreeze = [\"carbody.x\"]\n[contact]\n\
             model = \"{model}\"\nfriction = {friction}\n"
        ));
        let c = modes_in_curve(
            &s,
            &case,
            &CurvingRun::default(),
            &QuasiStatic::default(),
            &ModalOptions::default(),
        )
        .unwrap();
        let least = c.least_stable().unwrap();
        eprintln!(
            "{model}, friction {friction}: least damped {:.3} Hz, Re λ {:+.3}/s, {:?}",
            least.frequency, least.re, least.shape
        );
        if unstable {
            assert!(least.re > 10.0, "{least:?}");
            assert!(
                (100.0..170.0).contains(&least.frequency),
                "{}",
                least.frequency
            );
            assert!(
                least.shape[0].0.starts_with("ws1.") && least.shape[1].0.starts_with("ws1."),
                "{:?}",
                least.shape
            );
        } else {
            assert!(least.re < 0.0, "{least:?}");
        }
    }
}

/// The modal analysis linearises the vehicle with round wheels, as it removes the track's
/// irregularities: the Wickens wheelset with a polygon and a flat on its wheels has the same
/// eigenvalues, to the bit, as without them (a defect left in would shift the linearisation's
/// point with the wheel's radius at the study's track position, and couple x to z through the
/// defect's slope).
#[test]
fn the_modes_are_those_of_round_wheels() {
    let dir = std::env::temp_dir().join(format!("railsim-modal-oor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text =
        std::fs::read_to_string(common::root().join("vehicles/wheelset_springs.toml")).unwrap();
    let vehicle = dir.join("wheelset.toml");
    std::fs::write(
        &vehicle,
        format!(
            "{text}\n[[wheelset.out_of_roundness]]\ntype = \"harmonic\"\nside = \"both\"\norder = 5\n\
             amplitude_mm = 0.1\n\n[[wheelset.out_of_roundness]]\ntype = \"flat\"\nside = \"left\"\n\
             length_mm = 40\ndepth_mm = 0.1\n"
        ),
    )
    .unwrap();
    let round = common::wickens_scene();
    let scene_text = format!(
        "vehicle = \"{}\"\ntrack = \"tracks/straight.toml\"\nspeed_kmh = 1000\nduration_s = 1.4\n\
         [contact]\nmodel = \"linear\"\ncreep_coefficient_n = 1e8\n",
        vehicle.display()
    );
    let out_of_round = common::scene(&scene_text);
    assert!(
        out_of_round.vehicle.wheelsets()[0]
            .out_of_roundness
            .iter()
            .all(|d| !d.is_empty())
    );
    let study = railsim_sim::modal::modal_scene(&out_of_round, 50.0).unwrap();
    assert!(
        study.vehicle.wheelsets()[0]
            .out_of_roundness
            .iter()
            .all(Vec::is_empty)
    );
    let opts = ModalOptions::default();
    let (a, b) = (
        modes_at(&round, 50.0, &opts).unwrap(),
        modes_at(&out_of_round, 50.0, &opts).unwrap(),
    );
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(a.modes.len(), b.modes.len());
    for (p, q) in a.modes.iter().zip(&b.modes) {
        assert_eq!(
            (p.re.to_bits(), p.im.to_bits()),
            (q.re.to_bits(), q.im.to_bits())
        );
    }
}

/// A neutral mode does not decide the linear critical speed: the Wickens wheelset with a mass on
/// a spring and a dry-friction element to the track beside it (linearised as stuck: an undamped
/// 16.7 Hz mode whose real part is round-off of either sign) finds the wheelset's critical speed
/// as without the mass (to 0.1 %); before stop 38 the search stopped at its lower end, "already
/// unstable", or could have returned a spurious speed (`Mode::growth`, docs/models/dynamics.md).
#[test]
fn a_neutral_mode_does_not_decide_the_linear_critical_speed() {
    let dir = std::env::temp_dir().join(format!("railsim-neutral-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // the suspension tests' friction-damped mass (its body, spring and friction element, the
    // friction last) beside the Wickens wheelset
    let mass = std::fs::read_to_string(
        common::root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml"),
    )
    .unwrap();
    let tables: String = mass
        .split("\n[[")
        .skip(1)
        .filter(|t| !t.starts_with("wheelset]]"))
        .map(|t| format!("\n[[{t}"))
        .collect();
    assert!(tables.trim_end().ends_with("stiffness_n_per_m = 1e7"));
    let text = std::fs::read_to_string(common::root().join("vehicles/wheelset_springs.toml"))
        .unwrap()
        + &tables
        + "friction_force_n = 500\n";
    let vehicle = dir.join("wickens_friction.toml");
    std::fs::write(&vehicle, text).unwrap();
    let with_mass = scene(&format!(
        "vehicle = \"{}\"\ntrack = \"tracks/straight.toml\"\nspeed_kmh = 1000\nduration_s = 1\n\
         [contact]\nmodel = \"linear\"\ncreep_coefficient_n = 1e8\n",
        vehicle.display()
    ));
    let opts = ModalOptions::default();
    let a = modes_at(&with_mass, 250.0, &opts).unwrap();
    let neutral = a
        .modes
        .iter()
        .find(|m| m.is_oscillatory() && m.shape.first().is_some_and(|s| s.0 == "mass.z"))
        .expect("the stuck mass's mode");
    println!(
        "stuck mass: {:.2} Hz, Re λ {:.3e}/s, growth {}",
        neutral.frequency,
        neutral.re,
        neutral.growth()
    );
    assert_eq!(neutral.growth(), 0.0);
    let search = |s: &railsim_sim::Scene| {
        linear_critical_speed(s, &opts, (250.0, 350.0), 4, 1e-3, &mut |_| {})
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let (vc, vc_mass) = (
        search(&wickens_scene()).critical_speed,
        search(&with_mass).critical_speed,
    );
    println!("critical speed {vc:.2} m/s without the mass, {vc_mass:.2} with it");
    assert!((vc_mass / vc - 1.0).abs() < 1e-3, "{vc_mass} against {vc}");
    std::fs::remove_dir_all(&dir).ok();
}
