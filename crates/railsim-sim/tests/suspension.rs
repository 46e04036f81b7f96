//! The nonlinear dissipative suspension elements in a simulation: the Coulomb-damped
//! oscillator (dry friction with a stick stiffness, constant or load-dependent sliding force)
//! against its closed-form decrements, and a damper's table against the bushing's viscous
//! damping.
use crate::common;

use common::{root, scene};
use railsim_sim::{RunOptions, SimError, Simulation};

/// A scene with the test vehicle `tests/vehicles/friction_mass.toml`, its friction element
/// completed by `keys` (written to a temporary vehicle file named after `tag`), run for
/// `duration` s with Radau IIA.
fn friction_scene(tag: &str, keys: &str, duration: f64) -> railsim_sim::Scene {
    friction_scene_logging(tag, keys, duration, "")
}

/// [`friction_scene`] with more `[log]` keys.
fn friction_scene_logging(
    tag: &str,
    keys: &str,
    duration: f64,
    log_keys: &str,
) -> railsim_sim::Scene {
    let base = root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml");
    let text = std::fs::read_to_string(&base).unwrap() + keys;
    vehicle_scene(tag, &text, duration, &format!("rate_hz = 2000\n{log_keys}"))
}

/// A scene for the vehicle `text` (written to a temporary file named after `tag`): straight
/// ideal track at 36 km/h for `duration` s, `polach`, Radau IIA at rtol 1e-8, and the `[log]`
/// keys `log_keys`.
fn vehicle_scene(tag: &str, text: &str, duration: f64, log_keys: &str) -> railsim_sim::Scene {
    let dir = std::env::temp_dir().join(format!("railsim-suspension-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{tag}.toml"));
    std::fs::write(&path, text).unwrap();
    scene(&format!(
        r#"
        vehicle = "{}"
        track = "tracks/straight.toml"
        speed_kmh = 36
        duration_s = {duration}
        [contact]
        model = "polach"
        [integrator]
        method = "radau5"
        rtol = 1e-8
        atol = 1e-11
        [log]
        {log_keys}
        "#,
        path.display()
    ))
}

/// Run `s` from its static equilibrium with the mass lifted by `lift` \[m\] (the friction
/// relaxed there); the mass's vertical displacement from equilibrium at every sample.
fn released(s: &railsim_sim::Scene, lift: f64) -> (Vec<f64>, Vec<f64>) {
    let mut sim = Simulation::new(s).unwrap();
    let (iz, z0) = lift_mass(&mut sim, lift);
    let (mut t, mut z) = (Vec::new(), Vec::new());
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    sim.run(s, &opts, &mut |_, _| {}, &mut |smp| {
        t.push(smp.t);
        z.push(smp.x[iz] - z0);
    })
    .unwrap();
    (t, z)
}

/// Restart `sim` from its initial state with the mass `lift` \[m\] above its equilibrium on the
/// spring, the internal states (friction slider, damper) relaxed there; the mass's state index
/// and equilibrium. (The spring carries the weight as its preload, so the equilibrium is the
/// nominal position; the initial state also moves bodies by the wheelsets' contact sink,
/// 0.19 mm here, which a body hung from the track does not share.)
fn lift_mass(sim: &mut Simulation, lift: f64) -> (usize, f64) {
    let names = &sim.model().state_names;
    let iz = names.iter().position(|n| n == "mass.z").unwrap();
    let mut x = sim.initial_state().to_vec();
    let z0 = 0.0;
    for (i, n) in names.iter().enumerate() {
        // (a planar friction's z component moves with the mass, its other one does not)
        if n.ends_with("friction slip")
            || n.ends_with("friction slip z")
            || n.ends_with("damper elongation")
        {
            x[i] += z0 + lift - x[iz];
        }
    }
    x[iz] = z0 + lift;
    sim.start_from(0.0, &x).unwrap();
    (iz, z0)
}

/// The turning points of `z` (samples where the motion reverses) whose excursion exceeds
/// `floor`, refined by a parabola through the neighbouring samples.
fn turning_points(z: &[f64], floor: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..z.len() - 1 {
        let (a, b, c) = (z[i - 1], z[i], z[i + 1]);
        let peak = (b > a && b >= c) || (b < a && b <= c);
        if peak && b.abs() > floor {
            let den = a - 2.0 * b + c;
            let ext = if den != 0.0 {
                b - (c - a) * (c - a) / (8.0 * den)
            } else {
                b
            };
            out.push(ext);
        }
    }
    out
}

/// The index of the force element `name` of `sim`'s vehicle.
fn element(sim: &Simulation, name: &str) -> usize {
    sim.model()
        .elements
        .iter()
        .position(|e| e.name == name)
        .unwrap()
}

const K_SPRING: f64 = 1e6;
const K_STICK: f64 = 1e7;
const MASS: f64 = 1000.0;
/// \[m/s²\] the vehicle files' default gravity
const G: f64 = 9.81;

/// Constant sliding force F0: each half cycle loses 2 F0 / k of amplitude (Den Hartog 1931),
/// less the elastic stretch of the stick stiffness at the reversal (energy balance of the
/// elastoplastic element: z1 − |z2| = (2 F0/k)(1 − 2 F0 / (k_f (z1 + |z2|)))), and the mass
/// comes to rest inside the band |z| < F0 / k.
#[test]
fn a_constant_friction_force_damps_the_oscillation_by_coulombs_decrement() {
    let f0 = 500.0;
    let s = friction_scene("constant", "friction_force_n = 500\n", 2.5);
    let (t, z) = released(&s, 10e-3);
    let tp = turning_points(&z, 0.3 * f0 / K_SPRING);
    assert!(tp.len() >= 8, "{tp:?}");
    let step = 2.0 * f0 / K_SPRING;
    let mut worst = 0.0f64;
    for w in tp.windows(2) {
        let (z1, z2) = (w[0].abs(), w[1].abs());
        let want = step * (1.0 - 2.0 * f0 / (K_STICK * (z1 + z2)));
        eprintln!(
            "{:+.5} mm -> {:+.5} mm: lost {:.5} mm, closed form {:.5} mm",
            w[0] * 1e3,
            w[1] * 1e3,
            (z1 - z2) * 1e3,
            want * 1e3
        );
        let rel = (z1 - z2) / want - 1.0;
        worst = worst.max(rel.abs());
        assert!(w[0] * w[1] < 0.0, "turning points alternate: {tp:?}");
    }
    eprintln!(
        "{} turning points from {:.4} mm, worst decrement error {worst:.2e}",
        tp.len(),
        tp[0] * 1e3
    );
    assert!(worst < 1e-3, "{worst}");
    // At rest inside the band, after the last reversal: held by the friction (the residual
    // oscillation on the stick stiffness is undamped but tiny).
    let late: Vec<f64> = t
        .iter()
        .zip(&z)
        .filter(|(ti, _)| **ti > 2.0)
        .map(|(_, zi)| *zi)
        .collect();
    let (lo, hi) = late
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    assert!(
        hi.abs() < f0 / K_SPRING && lo.abs() < f0 / K_SPRING,
        "{lo} {hi}"
    );
    // what is left oscillates on the stick stiffness about the held position: the mass is
    // at most (F0 + k z_last) / (k + k_f) from it (the tension's swing from sliding to held)
    let last = tp[tp.len() - 1].abs();
    let swing = (f0 + K_SPRING * last) / (K_SPRING + K_STICK);
    assert!(
        hi - lo <= 2.0 * swing,
        "still moving: {lo} .. {hi} (swing {swing})"
    );
}

/// Sliding force μ N with N the spring's force (the weight plus the spring's change): the
/// friction is larger below the equilibrium. Without the stick stiffness the energy balance over
/// a half cycle gives z1 + z2 = 2 μ m g / (k (1 + μ)) moving down and −2 μ m g / (k (1 − μ))
/// moving up; with it ([`elastoplastic_half_cycle`]) the stick stretch at each reversal, up to
/// 0.19 mm here, is taken up before the slider moves.
#[test]
fn a_load_dependent_friction_follows_its_normal_force() {
    let mu = 0.05;
    let s = friction_scene(
        "normal",
        "friction_coefficient = 0.05\nnormal_element = \"spring\"\nnormal_direction = \"z\"\n",
        1.2,
    );
    let (_, z) = released(&s, 10e-3);
    let tp = turning_points(&z, 1e-3);
    assert!(tp.len() >= 6, "{tp:?}");
    let mg = MASS * G;
    let sliding = |z: f64| mu * (mg - K_SPRING * z);
    let mut worst = 0.0f64;
    for w in tp.windows(2) {
        let (z1, z2) = (w[0], w[1]);
        let down = z1 > 0.0;
        let rigid = if down {
            2.0 * mu * mg / (K_SPRING * (1.0 + mu))
        } else {
            -2.0 * mu * mg / (K_SPRING * (1.0 - mu))
        };
        let want = z1 + elastoplastic_half_cycle(z1, &sliding);
        let rel = (z1 + z2 - want) / want;
        eprintln!(
            "{} from {:+.4} mm to {:+.4} mm: z1 + z2 = {:+.5} mm, elastoplastic {:+.5} mm ({rel:+.2e}), rigid slider {:+.5} mm",
            if down { "down" } else { "up  " },
            z1 * 1e3,
            z2 * 1e3,
            (z1 + z2) * 1e3,
            want * 1e3,
            rigid * 1e3,
        );
        worst = worst.max(rel.abs());
    }
    assert!(worst < 1e-3, "{worst}");
}

/// The next turning point of the mass on its spring after a reversal at `z1`, with an
/// elastoplastic friction element of stick stiffness `K_STICK` whose sliding force is
/// `sliding(z)`: the tension swings from `sliding(z1)` to the opposite sliding force while the
/// slider sticks (the mass moves by the stretch), then the slider dissipates `∫ sliding dz`;
/// the spring's and the stick stiffness's energies balance that (solved by bisection).
fn elastoplastic_half_cycle(z1: f64, sliding: &dyn Fn(f64) -> f64) -> f64 {
    let dir = -z1.signum();
    let mut stretch = 0.0;
    for _ in 0..20 {
        stretch = (sliding(z1) + sliding(z1 + dir * stretch)) / K_STICK;
    }
    let zs = z1 + dir * stretch;
    // ∫ sliding dz from zs to z, by Simpson's rule (the integrand is linear here: exact)
    let dissipated =
        |z: f64| (z - zs).abs() / 6.0 * (sliding(zs) + 4.0 * sliding(0.5 * (zs + z)) + sliding(z));
    // The slider's work: the tension follows the sliding force, so the slider moves by
    // dz − de/k_f and dissipates ∫ F dz − [F²/(2 k_f)]; with the stick stiffness's energy
    // F²/(2 k_f) at both turning points the balance keeps F(z1)² − F(zs)².
    let balance = |z: f64| {
        0.5 * K_SPRING * (z1 * z1 - z * z)
            + (sliding(z1).powi(2) - sliding(zs).powi(2)) / (2.0 * K_STICK)
            - dissipated(z)
    };
    // from the start of sliding (energy to spare) to the mirror point (none left)
    let (mut a, mut b) = (zs, -z1);
    assert!(balance(a) > 0.0 && balance(b) < 0.0);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if balance(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// A damper whose table is linear (force = c v) and a bushing with the same viscous
/// coefficient give the same motion; with a series stiffness the damper follows the series
/// spring-damper.
#[test]
fn a_linear_damper_table_moves_like_the_viscous_bushing() {
    let c = 20e3;
    let body = |damping: &str| {
        format!(
            r#"
name = "damped mass (test)"
[[body]]
name = "mass"
mass_kg = 1000
inertia_kgm2 = [100, 100, 100]
position_m = [0.0, 0.0, 1.0]
frozen = ["x", "y", "roll", "pitch", "yaw"]
[[wheelset]]
name = "ws"
mass_kg = 1813
inertia_kgm2 = [1120, 112, 1120]
position_m = [0.0, 0.0, 0.46]
nominal_radius_m = 0.46
back_to_back_mm = 1360
wheel_profile = {{ left = "s1002", right = "s1002" }}
frozen = ["x", "y", "yaw", "spin"]
[[force]]
name = "spring"
type = "bushing"
body1 = "track"
body2 = "mass"
point_m = [0.0, 0.0, 1.0]
stiffness_n_per_m = [0, 0, 1e6]
{damping}
"#
        )
    };
    let run = |tag: &str, damping: &str| {
        let dir = std::env::temp_dir().join(format!("railsim-suspension-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{tag}.toml"));
        std::fs::write(&path, body(damping)).unwrap();
        let s = scene(&format!(
            r#"
            vehicle = "{}"
            track = "tracks/straight.toml"
            speed_kmh = 36
            duration_s = 0.6
            [contact]
            model = "polach"
            [integrator]
            method = "radau5"
            rtol = 1e-9
            atol = 1e-12
            [log]
            rate_hz = 1000
            "#,
            path.display()
        ));
        let mut sim = Simulation::new(&s).unwrap();
        let (iz, z0) = lift_mass(&mut sim, 5e-3);
        let mut z = Vec::new();
        let opts = RunOptions {
            no_log: true,
            ..Default::default()
        };
        sim.run(&s, &opts, &mut |_, _| {}, &mut |smp| z.push(smp.x[iz] - z0))
            .unwrap();
        z
    };
    let common_keys = "body1 = \"track\"\nbody2 = \"mass\"\npoint_m = [0.0, 0.0, 1.0]\n";
    let viscous = run(
        "viscous",
        &format!(
            "[[force]]\nname = \"d\"\ntype = \"bushing\"\n{common_keys}damping_ns_per_m = [0, 0, {c}]\n"
        ),
    );
    let table = run(
        "table",
        &format!(
            "[[force]]\nname = \"d\"\ntype = \"damper\"\n{common_keys}direction = \"z\"\nvelocity_m_per_s = [0.0, 1.0]\nforce_n = [0.0, {c}]\nsymmetric = true\n"
        ),
    );
    let series_table = run(
        "series_table",
        &format!(
            "[[force]]\nname = \"d\"\ntype = \"damper\"\n{common_keys}direction = \"z\"\nstiffness_n_per_m = 4e6\nvelocity_m_per_s = [-1.0, 1.0]\nforce_n = [-{c}, {c}]\n"
        ),
    );
    let series = run(
        "series",
        &format!(
            "[[force]]\nname = \"d\"\ntype = \"series_spring_damper\"\n{common_keys}direction = \"z\"\nstiffness_n_per_m = 4e6\ndamping_ns_per_m = {c}\n"
        ),
    );
    let diff = |a: &[f64], b: &[f64]| {
        assert_eq!(a.len(), b.len());
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    };
    let (d1, d2) = (diff(&viscous, &table), diff(&series, &series_table));
    eprintln!(
        "largest difference: table vs bushing {d1:.2e} m, series table vs series element {d2:.2e} m"
    );
    // the oscillation decays (ζ = c / (2 sqrt(k m)) = 0.32), and the two agree to the
    // integrator's tolerance
    assert!(viscous[viscous.len() - 1].abs() < 0.01 * 5e-3);
    assert!(d1 < 1e-8, "{d1}");
    assert!(d2 < 1e-8, "{d2}");
    // the series stiffness changes the motion (it is not ignored)
    assert!(diff(&viscous, &series) > 1e-5);
}

/// The `/elements/<name>` topic: each element's deflections, forces, state and (friction) sliding
/// force, read back as sampled; the friction never exceeds its sliding force, which is the
/// coefficient times the spring's force, and the spring's force is its stiffness times its
/// deflection.
#[test]
fn element_forces_are_logged_as_sampled() {
    let dir = std::env::temp_dir().join(format!("railsim-elements-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let log = dir.join("elements.mcap");
    // The friction element listed before its normal element: the right-hand side must still
    // evaluate the spring first (`SimModel::element_order`), or the sliding force below would be
    // the spring's force of the previous evaluation.
    let base = root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml");
    let text = std::fs::read_to_string(&base).unwrap();
    let (head, forces) = text.split_at(text.find("[[force]]").unwrap());
    let (spring, rubbing) = forces.split_at(forces.rfind("[[force]]").unwrap());
    let text = format!(
        "{head}{rubbing}friction_coefficient = 0.05\nnormal_element = \"spring\"\nnormal_direction = \"z\"\n\n{spring}"
    );
    let s = vehicle_scene(
        "logged",
        &text,
        0.3,
        "rate_hz = 2000\ntopics = [\"bodies\", \"elements\"]",
    );
    let mut sim = Simulation::new(&s).unwrap();
    const RUBBING: usize = 0;
    const SPRING: usize = 1;
    assert_eq!(sim.model().elements[RUBBING].name, "rubbing");
    // lifted 15 mm: above 9.81 mm the spring (1 MN/m under 9.81 kN) pulls the mass down, and
    // the rubbing surfaces it presses part
    lift_mass(&mut sim, 15e-3);
    let mut samples = Vec::new();
    let opts = RunOptions {
        log_path: Some(log.clone()),
        ..Default::default()
    };
    sim.run(&s, &opts, &mut |_, _| {}, &mut |smp| {
        samples.push(smp.clone())
    })
    .unwrap();
    let reader = railsim_log::LogReader::open(&log).unwrap();
    let spring: Vec<(u64, railsim_log::ElementMessage)> = reader
        .read_topic(&railsim_log::topics::element("spring"), None)
        .unwrap();
    let rubbing: Vec<(u64, railsim_log::ElementMessage)> = reader
        .read_topic(&railsim_log::topics::element("rubbing"), None)
        .unwrap();
    assert_eq!(spring.len(), samples.len());
    assert_eq!(rubbing.len(), samples.len());
    let (mut slid, mut parted) = (0, 0);
    for (((_, sp), (_, ru)), smp) in spring.iter().zip(&rubbing).zip(&samples) {
        assert_eq!(
            (sp.element.as_str(), sp.kind.as_str()),
            ("spring", "bushing")
        );
        assert_eq!(
            (ru.element.as_str(), ru.kind.as_str()),
            ("rubbing", "friction")
        );
        assert_eq!(sp.t_s, smp.t);
        // read back as sampled
        assert_eq!(sp.force_n, smp.elements[SPRING].force);
        assert_eq!(ru.deflection_m, smp.elements[RUBBING].deflection);
        assert_eq!(
            ru.state_m.as_deref(),
            Some(&smp.elements[RUBBING].state[..1])
        );
        assert_eq!(sp.state_m, None);
        assert_eq!(sp.sliding_force_n, None);
        // the spring: F = m g - k z along its local z (its preload carries the weight)
        assert!((sp.force_n[2] - MASS * G + K_SPRING * sp.deflection_m[2]).abs() < 1e-6);
        // the friction's sliding force is 0.05 times the spring's force while the spring
        // pushes the mass up (normal_direction = "z"), none while it pulls, and its own force
        // stays within it (up to the transition's overshoot while the load falls, and the
        // law's floor of 10 N)
        let f0 = ru.sliding_force_n.unwrap();
        assert_eq!(f0, 0.05 * sp.force_n[2].max(0.0), "{f0}");
        // (at the floor, the transition's overshoot reaches 2^(1/20) = 1.035 of it)
        let (f0, overshoot) = if f0 < K_STICK * 1e-6 {
            (K_STICK * 1e-6, 1.04)
        } else {
            (f0, 1.001)
        };
        if sp.force_n[2] < -100.0 {
            // parted: at most the law's floor, the stick stiffness times 1 µm (10 N)
            parted += 1;
            assert!(
                ru.force_n[2].abs() <= 1.04 * K_STICK * 1e-6,
                "{:?}",
                ru.force_n
            );
        }
        assert!(
            ru.force_n[2].abs() <= overshoot * f0,
            "{} > {f0}",
            ru.force_n[2]
        );
        assert_eq!(
            ru.force_n[2],
            -K_STICK * (ru.deflection_m[2] - ru.state_m.as_ref().unwrap()[0])
        );
        if ru.force_n[2].abs() > 0.99 * f0 {
            slid += 1;
        }
    }
    assert!(slid > samples.len() / 2, "slides most of the time: {slid}");
    assert!(parted > 20, "the spring in tension at {parted} samples");
    std::fs::remove_dir_all(&dir).ok();
}

/// Linearised at rest, a friction element is stuck: the mass bounces on its spring and the stick
/// stiffness in parallel, undamped (docs/models/vehicle.md).
#[test]
fn a_friction_element_at_rest_linearises_as_stuck() {
    use railsim_sim::modal::{ModalOptions, modes_at};
    let s = friction_scene("modes", "friction_force_n = 500\n", 1.0);
    let a = modes_at(&s, 10.0, &ModalOptions::default()).unwrap();
    let bounce = a
        .modes
        .iter()
        .find(|m| m.is_oscillatory() && m.shape.first().is_some_and(|(n, _)| n == "mass.z"))
        .expect("the mass's bounce");
    let f = ((K_SPRING + K_STICK) / MASS).sqrt() / (2.0 * std::f64::consts::PI);
    eprintln!(
        "bounce: {:.4} Hz (stuck: {f:.4} Hz), Re λ {:.2e} 1/s",
        bounce.frequency, bounce.re
    );
    assert!(
        (bounce.frequency / f - 1.0).abs() < 1e-3,
        "{}",
        bounce.frequency
    );
    assert!(bounce.re.abs() < 1e-3, "{}", bounce.re);
}

/// Rotational friction (side bearers, centre pivot): a body turning about z on a torsional
/// spring with a friction moment loses Coulomb's decrement per half cycle, as the translational
/// element does: (2 M0/k_r)(1 − 2 M0/(k_f (ψ1 + |ψ2|))).
#[test]
fn a_friction_moment_damps_a_yaw_oscillation_by_coulombs_decrement() {
    let (k_r, k_f, m0, izz) = (2e6, 2e7, 2e3, 2e3);
    let vehicle = format!(
        r#"
name = "yaw friction (test)"
[[body]]
name = "frame"
mass_kg = 2000
inertia_kgm2 = [1000, 1000, {izz}]
position_m = [0.0, 0.0, 0.6]
frozen = ["x", "y", "z", "roll", "pitch"]
[[wheelset]]
name = "ws"
mass_kg = 1813
inertia_kgm2 = [1120, 112, 1120]
position_m = [0.0, 0.0, 0.46]
nominal_radius_m = 0.46
back_to_back_mm = 1360
wheel_profile = {{ left = "s1002", right = "s1002" }}
frozen = ["x", "y", "yaw", "spin"]
[[force]]
name = "torsion"
type = "bushing"
body1 = "track"
body2 = "frame"
point_m = [0.0, 0.0, 0.6]
rotational_stiffness_nm_per_rad = [0, 0, {k_r}]
[[force]]
name = "side_bearers"
type = "rotational_friction"
body1 = "track"
body2 = "frame"
point_m = [0.0, 0.0, 0.6]
about = "z"
rotational_stiffness_nm_per_rad = {k_f}
friction_moment_nm = {m0}
"#
    );
    let s = vehicle_scene("yaw", &vehicle, 1.5, "rate_hz = 4000");
    let mut sim = Simulation::new(&s).unwrap();
    let names = sim.model().state_names.clone();
    let iy = names.iter().position(|n| n == "frame.yaw").unwrap();
    let is = names
        .iter()
        .position(|n| n == "side_bearers friction slip")
        .unwrap();
    // 20 mrad of yaw, the friction relaxed there
    let mut x = sim.initial_state().to_vec();
    let psi0 = x[iy];
    x[iy] += 0.02;
    x[is] += 0.02;
    sim.start_from(0.0, &x).unwrap();
    let mut psi = Vec::new();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let ir = names.iter().position(|n| n == "d/dt frame.yaw").unwrap();
    let (ib, it) = (element(&sim, "side_bearers"), element(&sim, "torsion"));
    // the oscillation's energy (the torsion spring on its own measure of the rotation, the
    // frame's yaw, the stick stiffness)
    let energy = |smp: &railsim_sim::Sample| {
        let (p, r, m) = (
            smp.elements[it].rotation[2],
            smp.x[ir],
            smp.elements[ib].moment[2],
        );
        0.5 * k_r * p * p + 0.5 * izz * r * r + m * m / (2.0 * k_f)
    };
    let mut ends = [None; 2];
    let summary = sim
        .run(&s, &opts, &mut |_, _| {}, &mut |smp| {
            psi.push(smp.x[iy] - psi0);
            ends[usize::from(ends[0].is_some())] = Some(energy(smp));
        })
        .unwrap();
    // the friction moment dissipates what the oscillation lost (the moment's branch of the
    // dissipation, −M·ṡ), to the order of the rotational elements' small-angle measure of the
    // rotation: its rate is the relative angular velocity, the measure itself sin ψ, which
    // differ by 1 − cos ψ = 2e-4 at 20 mrad
    let lost = ends[0].unwrap() - ends[1].unwrap();
    let dissipated = summary.elements[ib].dissipated;
    eprintln!("the oscillation lost {lost:.6} J, the side bearers dissipated {dissipated:.6} J");
    assert!(lost > 300.0, "{lost}");
    assert!(
        (dissipated / lost - 1.0).abs() < 1e-4,
        "{dissipated} vs {lost}"
    );
    let tp = turning_points(&psi, 0.3 * m0 / k_r);
    assert!(tp.len() >= 6, "{tp:?}");
    let mut worst = 0.0f64;
    for w in tp.windows(2) {
        let (a, b) = (w[0].abs(), w[1].abs());
        let want = 2.0 * m0 / k_r * (1.0 - 2.0 * m0 / (k_f * (a + b)));
        worst = worst.max(((a - b) / want - 1.0).abs());
        assert!(w[0] * w[1] < 0.0, "{tp:?}");
    }
    eprintln!(
        "{} yaw reversals from {:.3} mrad, worst decrement error {worst:.2e}",
        tp.len(),
        tp[0] * 1e3
    );
    assert!(worst < 1e-3, "{worst}");
}

/// A planar friction in the plane z–x of a mass that moves only along z behaves as the one-axis
/// element: the same motion to the integrator's tolerance (the planar law along one axis is the
/// one-axis law; its second state stays at rest).
#[test]
fn a_planar_friction_moving_along_one_axis_is_the_one_axis_element() {
    let one = released(
        &friction_scene("axis", "friction_force_n = 500\n", 1.0),
        10e-3,
    )
    .1;
    // the base vehicle's friction keys with `direction` replaced by `plane`
    let base = root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml");
    let text = std::fs::read_to_string(&base)
        .unwrap()
        .replace("type = \"friction\"", "type = \"planar_friction\"")
        .replace("direction = \"z\"", "plane = \"zx\"")
        + "friction_force_n = 500\n";
    let s = vehicle_scene("planar", &text, 1.0, "rate_hz = 2000");
    let names = Simulation::new(&s).unwrap().model().state_names.clone();
    assert!(
        names.iter().any(|n| n == "rubbing friction slip z"),
        "{names:?}"
    );
    assert!(
        names.iter().any(|n| n == "rubbing friction slip x"),
        "{names:?}"
    );
    let planar = released(&s, 10e-3).1;
    assert_eq!(one.len(), planar.len());
    let diff = one
        .iter()
        .zip(&planar)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!("planar against one-axis friction: largest difference {diff:.2e} m");
    assert!(diff < 1e-7, "{diff}");
}

/// The work the elements absorb and the energy they dissipate (`RunSummary::elements`, the
/// trapezoidal rule on each element's power and dissipation over the samples) balance the
/// mass's mechanical energy: the spring's work is the change of its stored energy,
/// ½ k (z_end² − z_0²) − m g (z_end − z_0) (its preload m g carries the weight at the loaded
/// geometry, z = 0), and it dissipates nothing; the friction dissipates what the oscillation
/// lost, E_0 − E_end, with E = ½ k z² + ½ m v² + F_f² / (2 k_f) (the weight and the preload
/// cancel; the spring and the friction's stick stiffness both stored), and absorbs that plus
/// the change of its stick
/// energy. The log's cumulative values at the last sample are the summary's.
#[test]
fn the_elements_work_balances_the_mechanical_energy() {
    let s = friction_scene("energy", "friction_force_n = 500\n", 1.0);
    let lift = 10e-3;
    let mut sim = Simulation::new(&s).unwrap();
    let (iz, z0) = lift_mass(&mut sim, lift);
    let names = sim.model().state_names.clone();
    let iv = names.iter().position(|n| n == "d/dt mass.z").unwrap();
    let (spring, rubbing) = (element(&sim, "spring"), element(&sim, "rubbing"));
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let mut first = None;
    let mut last = None;
    let mut min_dissipation = f64::INFINITY;
    let summary = sim
        .run(&s, &opts, &mut |_, _| {}, &mut |smp| {
            let here = (
                smp.x[iz],
                smp.x[iv],
                smp.elements[rubbing].force[2],
                smp.element_work.clone(),
            );
            min_dissipation = min_dissipation.min(smp.elements[rubbing].dissipation);
            if first.is_none() {
                first = Some(here.clone());
            }
            last = Some(here);
        })
        .unwrap();
    let ((za, va, fa, wa), (zb, vb, fb, wb)) = (first.unwrap(), last.unwrap());
    assert!(
        wa.iter().flatten().all(|w| *w == 0.0),
        "nothing before the first sample"
    );
    // the spring's deflection is the mass's height from nominal, its force m g − k d (the
    // preload balances the weight: their potentials cancel)
    let energy = |z: f64, v: f64, ff: f64| {
        0.5 * K_SPRING * z * z + 0.5 * MASS * v * v + ff * ff / (2.0 * K_STICK)
    };
    let lost = energy(za, va, fa) - energy(zb, vb, fb);
    let by_name = |n: &str| summary.elements.iter().find(|e| e.name == n).unwrap();
    let (ws, wf) = (by_name("spring"), by_name("rubbing"));
    // (its work: the elastic energy's change less the preload's work, m g (zb − za))
    let stored = 0.5 * K_SPRING * (zb * zb - za * za) - MASS * G * (zb - za);
    let stick = (fb * fb - fa * fa) / (2.0 * K_STICK);
    eprintln!(
        "from {:.4} mm above equilibrium to {:.4} mm: the friction dissipated {:.6} J and \
         absorbed {:.6} J, the oscillation lost {lost:.6} J, the stick energy changed \
         {stick:.6} J; the spring absorbed {:.6} J, its stored energy changed {stored:.6} J",
        (za - z0) * 1e3,
        (zb - z0) * 1e3,
        wf.dissipated,
        wf.work,
        ws.work
    );
    assert!(lost > 30.0, "the oscillation lost most of its 50 J: {lost}");
    assert!(
        (wf.dissipated / lost - 1.0).abs() < 1e-4,
        "{} vs {lost}",
        wf.dissipated
    );
    assert!((wf.work - wf.dissipated - stick).abs() < 1e-4 * lost);
    assert!(
        (ws.work - stored).abs() < 1e-3 * lost,
        "{} vs {stored}",
        ws.work
    );
    assert_eq!(ws.dissipated, 0.0);
    assert!(wf.dissipates && !ws.dissipates);
    assert!(min_dissipation >= 0.0, "{min_dissipation}");
    assert!(wf.peak_dissipation > 0.0);
    assert!((wf.mean_dissipation - wf.dissipated / 1.0).abs() < 1e-9 * wf.dissipated);
    // the cumulative values of the last sample are the summary's
    assert_eq!(wb[rubbing], [wf.work, wf.dissipated]);
    assert_eq!(wb[spring], [ws.work, ws.dissipated]);
}

/// A wheelset's elements act on its axle boxes, which sit on bearings: an element attached off
/// the axle line makes no torque about the axle (docs/models/vehicle.md). The Wickens wheelset
/// (`vehicles/wheelset_springs.toml`, two bushings to the track with the Manchester primary
/// k_x, k_y) moved 1 mm forward, with its bushings on the axle line and raised 0.1 m above it:
/// the same spin acceleration, where the lever of the raised bushings' 62.8 kN would have turned
/// the spin at 0.1 m × 62.8 kN / 112 kg·m² = 56 rad/s². Their moment about the other axes still
/// acts: the raised bushings' lateral forces roll the wheelset once it is moved sideways.
#[test]
fn elements_on_a_wheelset_make_no_torque_about_its_axle() {
    use railsim_ode::OdeSystem;
    use railsim_sim::dynamics::Dynamics;
    let text = std::fs::read_to_string(root().join("vehicles/wheelset_springs.toml")).unwrap();
    let raised = text.replace("1.0, 0.46]", "1.0, 0.56]");
    assert_eq!(raised.matches("0.56]").count(), 2);
    let rates = |tag: &str, text: &str, shift: (f64, f64)| {
        let s = vehicle_scene(tag, text, 0.01, "rate_hz = 1000");
        let sim = Simulation::new(&s).unwrap();
        let names = &sim.model().state_names;
        let at = |n: &str| names.iter().position(|x| x == n).unwrap();
        let mut x = sim.initial_state().to_vec();
        x[at("ws.x")] += shift.0;
        x[at("ws.y")] += shift.1;
        let mut dx = vec![0.0; x.len()];
        Dynamics::new(sim.model()).rhs(0.0, &x, &mut dx).unwrap();
        (dx[at("d/dt ws.spin")], dx[at("d/dt ws.roll")])
    };
    let (spin_on, _) = rates("axle-line", &text, (1e-3, 0.0));
    let (spin_raised, _) = rates("raised", &raised, (1e-3, 0.0));
    println!(
        "spin acceleration: bushings on the axle line {spin_on:.6e}, raised {spin_raised:.6e} rad/s²"
    );
    assert!(
        (spin_raised - spin_on).abs() < 1e-6 * (1.0 + spin_on.abs()),
        "{spin_raised} against {spin_on}"
    );
    // moved 1 mm sideways, the raised bushings' lateral force (2 × 3.884 kN) rolls the
    // wheelset about x by 0.1 m × 7.768 kN / 1120 kg·m² = 0.694 rad/s² more
    let (_, roll_on) = rates("axle-line-y", &text, (0.0, 1e-3));
    let (_, roll_raised) = rates("raised-y", &raised, (0.0, 1e-3));
    println!("roll acceleration: on the axle line {roll_on:.4}, raised {roll_raised:.4} rad/s²");
    let lever = 0.1 * 2.0 * 3.884e6 * 1e-3 / 1120.0;
    assert!(
        ((roll_raised - roll_on).abs() - lever).abs() < 0.02 * lever,
        "{roll_raised} against {roll_on}"
    );
}

/// An element along the line between its points (`direction = "line"`) turns with that line:
/// a mass hung from the track by a stiff vertical spring 0.5 m long swings laterally as a
/// pendulum, period 2π √(L/g) = 1.4186 s (the spring's preload, the weight, times the line's
/// turning, y / L, is the restoring force), and the work the hanger absorbs balances the mass's
/// energy; the same spring along the fixed local z has no lateral stiffness: the static solve
/// finds the mass without lateral support.
#[test]
fn an_element_along_its_line_hangs_a_pendulum() {
    let base = root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml");
    let text = std::fs::read_to_string(&base).unwrap();
    let head = &text[..text.find("[[force]]").unwrap()];
    let head = head.replace(
        "frozen = [\"x\", \"y\", \"roll\", \"pitch\", \"yaw\"]",
        "frozen = [\"x\", \"roll\", \"pitch\", \"yaw\"]",
    );
    let (len, k) = (0.5, 1e7);
    let swing = |direction: &str| {
        let vehicle = format!(
            "{head}[[force]]\nname = \"hanger\"\ntype = \"table\"\nbody1 = \"track\"\n\
             body2 = \"mass\"\npoint_m = [0.0, 0.0, {top}]\npoint2_m = [0.0, 0.0, 1.0]\n\
             direction = \"{direction}\"\ndeflection_mm = [-100, 100]\n\
             force_n = [{lo}, {hi}]\n",
            top = 1.0 + len,
            lo = -k * 0.1,
            hi = k * 0.1,
        );
        let s = vehicle_scene(
            &format!("hanger-{direction}"),
            &vehicle,
            4.5,
            "rate_hz = 200",
        );
        let mut sim = match Simulation::new(&s) {
            Ok(sim) => sim,
            Err(e) => return Err(e.to_string()),
        };
        let names = &sim.model().state_names;
        let at = |n: &str| names.iter().position(|m| m == n).unwrap();
        let (iy, iz, ivy, ivz) = (
            at("mass.y"),
            at("mass.z"),
            at("d/dt mass.y"),
            at("d/dt mass.z"),
        );
        let mut x = sim.initial_state().to_vec();
        let y0 = x[iy];
        x[iy] += 20e-3;
        sim.start_from(0.0, &x).unwrap();
        let (mut t, mut y, mut ends) = (Vec::new(), Vec::new(), Vec::new());
        let opts = RunOptions {
            no_log: true,
            ..Default::default()
        };
        let summary = sim
            .run(&s, &opts, &mut |_, _| {}, &mut |smp| {
                t.push(smp.t);
                y.push(smp.x[iy] - y0);
                // the mass's kinetic and potential energy
                let (vy, vz) = (smp.x[ivy], smp.x[ivz]);
                let e = 0.5 * MASS * (vy * vy + vz * vz) + MASS * G * smp.x[iz];
                ends.push(e);
            })
            .unwrap();
        let hanger = summary
            .elements
            .iter()
            .find(|e| e.name == "hanger")
            .unwrap();
        // What the hanger absorbed is what the mass lost: the mass starts displaced sideways
        // at its nominal height, so the hanger starts stretched by √(L² + y²) − L = 0.4 mm
        // and gives up some 11 J; the balance leaves room for the hanger's own stored energy
        // at the end (its 16 Hz axial oscillation).
        let lost = ends[0] - ends[ends.len() - 1];
        eprintln!(
            "{direction}: hanger absorbed {:.6} J, the mass lost {lost:.6} J",
            hanger.work
        );
        assert!(
            (hanger.work - lost).abs() < 5e-3 * lost.abs() + 1e-3,
            "{} J vs {lost} J",
            hanger.work
        );
        Ok((t, y))
    };
    // along the line: the upward zero crossings, interpolated, a period apart
    let (t, y) = swing("line").unwrap();
    let mut up = Vec::new();
    for i in 1..y.len() {
        if y[i - 1] < 0.0 && y[i] >= 0.0 {
            up.push(t[i - 1] + (t[i] - t[i - 1]) * y[i - 1] / (y[i - 1] - y[i]));
        }
    }
    assert!(up.len() >= 3, "{up:?}");
    let period = (up[up.len() - 1] - up[0]) / (up.len() - 1) as f64;
    let expected = 2.0 * std::f64::consts::PI * (len / G).sqrt();
    eprintln!(
        "period {period:.5} s, pendulum {expected:.5} s ({} crossings)",
        up.len()
    );
    assert!(
        (period / expected - 1.0).abs() < 2e-3,
        "period {period} s, pendulum {expected} s"
    );
    // swinging, not decaying or growing: the amplitude stays 20 mm
    let amp = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    eprintln!("amplitude {:.4} mm", amp * 1e3);
    assert!((amp - 20e-3).abs() < 0.2e-3, "{amp}");
    // along the fixed z: no lateral stiffness at all
    let e = swing("z").unwrap_err();
    assert!(e.contains("body 'mass' has no support in y"), "{e}");
}

/// An element along its line whose points meet has no direction: the run stops there, naming
/// the element and the distance, with the samples before it kept. A 2 cm hanger, soft beyond its
/// preload (1 kN/m, so 1 rad/s with the 1 t mass), and the mass thrown up at 0.1 m/s: it comes
/// within 1 mm of the top point, where the run stops, at asin((0.019 − z0) / 0.1) = 0.193 s.
#[test]
fn a_line_element_whose_points_meet_stops_the_run_naming_it() {
    let base = root().join("crates/railsim-sim/tests/vehicles/friction_mass.toml");
    let text = std::fs::read_to_string(&base).unwrap();
    let head = &text[..text.find("[[force]]").unwrap()];
    let vehicle = format!(
        "{head}[[force]]\nname = \"hanger\"\ntype = \"table\"\nbody1 = \"track\"\n\
         body2 = \"mass\"\npoint_m = [0.0, 0.0, 1.02]\npoint2_m = [0.0, 0.0, 1.0]\n\
         direction = \"line\"\ndeflection_mm = [-100, 100]\nforce_n = [-100, 100]\n"
    );
    let s = vehicle_scene("hanger-collapse", &vehicle, 1.0, "rate_hz = 1000");
    let mut sim = Simulation::new(&s).unwrap();
    let names = &sim.model().state_names;
    let ivz = names.iter().position(|m| m == "d/dt mass.z").unwrap();
    let iz = names.iter().position(|m| m == "mass.z").unwrap();
    let mut x = sim.initial_state().to_vec();
    // (the initial state's height, a fraction of a millimetre from the nominal one)
    let z0 = x[iz];
    x[ivz] = 0.1;
    sim.start_from(0.0, &x).unwrap();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let mut last = 0.0;
    let e = sim
        .run(&s, &opts, &mut |_, _| {}, &mut |smp| last = smp.t)
        .unwrap_err();
    let SimError::Stopped {
        t, body, quantity, ..
    } = &e
    else {
        panic!("{e}")
    };
    eprintln!("{e}");
    assert_eq!(body, "element 'hanger'", "{e}");
    assert!(
        quantity.contains("mm apart (nominal 0.020 m)"),
        "{quantity}"
    );
    // (the rejected steps close in on the crossing: the stop's time is the last failed
    // evaluation's; the samples, every 1 ms, end before it)
    let expected = ((0.019 - z0) / 0.1).asin();
    eprintln!("expected {expected:.6} s, last sample {last:.6} s");
    assert!(
        (t - expected).abs() < 1e-3,
        "stopped at {t} s, expected {expected} s"
    );
    assert!(last > t - 1.001e-3 && last <= *t, "last sample at {last} s");
}
