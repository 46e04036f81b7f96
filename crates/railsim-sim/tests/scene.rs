//! Integration tests of railsim-sim: every shipped scene compiles, the format doc's example
//! compiles, and each kind of bad scene is reported with `file:line:col` and its key, several at
//! once.

use std::path::{Path, PathBuf};

use railsim_contact::{ContactModelKind, HertzSearch, Tangential};
use railsim_ode::Method;
use railsim_sim::assess::{SectionOptions, VerticalWeighting};
use railsim_sim::{
    RunLength, Scene, SceneError, Topic, longest_rigid_wheelbase, required_curve_radius,
};
use railsim_vehicle::{Dof, DofKind, Member};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scenes_dir() -> PathBuf {
    root().join("scenes")
}

/// Compile text as if it were `scenes/x.toml`.
fn compile(text: &str) -> Result<Scene, SceneError> {
    Scene::from_toml_str(text, "scenes/x.toml", &scenes_dir())
}

fn problems(text: &str) -> Vec<String> {
    match compile(text) {
        Ok(_) => panic!("expected problems for:\n{text}"),
        Err(e) => {
            assert!(!e.problems().is_empty(), "not a located error: {e}");
            e.problems().iter().map(|p| p.to_string()).collect()
        }
    }
}

/// The one problem in `file` at `line` containing all `needles`.
fn expect_in(problems: &[String], file: &str, line: usize, needles: &[&str]) {
    let prefix = format!("{file}:{line}:");
    let hit = problems
        .iter()
        .find(|p| p.starts_with(&prefix) && needles.iter().all(|n| p.contains(n)));
    let Some(hit) = hit else {
        panic!(
            "no problem at {file}:{line} containing {needles:?} in:\n{}",
            problems.join("\n")
        );
    };
    let col: usize = hit[prefix.len()..]
        .split(':')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(col >= 1);
}

fn expect(problems: &[String], line: usize, needles: &[&str]) {
    expect_in(problems, "scenes/x.toml", line, needles);
}

const GOOD: &str = r#"vehicle = "../vehicles/bogie_two_axle.toml"
track = "../tracks/curve_r1200.toml"
speed_kmh = 100
duration_s = 1
"#;

/// The shipped scene files (at least three).
fn scene_files() -> Vec<std::path::PathBuf> {
    let files: Vec<_> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .collect();
    assert!(
        files.len() >= 3,
        "expected at least three scenes, found {files:?}"
    );
    files
}

#[test]
fn every_scene_file_compiles() {
    for path in scene_files() {
        let scene = Scene::from_file(&path).unwrap_or_else(|e| panic!("{}:\n{e}", path.display()));
        assert!(scene.duration() > 0.0 && scene.distance() > 0.0);
        assert!(!scene.dofs().is_empty());
    }
}

/// Every shipped scene also starts: its simulation builds, with its initial state (a
/// quasi-static start in a curve included). `scenes/manchester_in_curve_r300.toml` compiled but
/// did not start from stop 26 until stop 27 (STRIPES at the 1 mm step, Newton stalled).
#[test]
fn every_scene_file_starts() {
    for path in scene_files() {
        let scene = Scene::from_file(&path).unwrap();
        let sim = railsim_sim::Simulation::new(&scene)
            .unwrap_or_else(|e| panic!("{}:\n{e}", path.display()));
        assert!(sim.initial_state().iter().all(|v| v.is_finite()));
    }
}

#[test]
fn default_scene_is_the_issue_default() {
    let s = Scene::from_file(scenes_dir().join("default.toml")).unwrap();
    assert_eq!(s.vehicle.wheelsets().len(), 4);
    assert!((s.speed.speed_at(0.0) - 55.0).abs() < 1e-12);
    assert!(s.speed.is_constant());
    assert!(s.track.irregularities().is_some());
    let r_min = s
        .track
        .segments()
        .iter()
        .map(|g| g.curvature_start.abs().max(g.curvature_end.abs()))
        .fold(0.0, f64::max);
    assert!((1.0 / r_min - 1200.0).abs() < 1e-6);
    assert_eq!(s.contact.model, ContactModelKind::Stripes);
    assert!(matches!(s.integrator, Method::DormandPrince { .. }));
    assert_eq!(s.log.topics, Topic::DEFAULT.to_vec());
    // Rear wheelset at s = 0, and the whole run stays on the track.
    assert!((s.start - 10.78).abs() < 1e-12);
    assert!(s.start + s.distance() + 10.78 <= s.track.length());
    // Messages name files the way a user would.
    assert!(
        s.vehicle_file
            .ends_with("vehicles/manchester_vehicle1.toml")
    );
    assert!(!s.vehicle_file.to_string_lossy().contains(".."));
}

#[test]
fn other_scenes_carry_their_choices() {
    let w = Scene::from_file(scenes_dir().join("wheelset_springs_critical.toml")).unwrap();
    assert!((w.speed.speed_at(0.0) - 1096.1 / 3.6).abs() < 1e-9);
    assert_eq!(w.contact.model, ContactModelKind::Linear);
    assert_eq!(w.contact.linear_creep, Some(1e8));
    assert_eq!(w.dofs().len(), 6);
    assert!((w.initial.lateral_offset - 0.02e-3).abs() < 1e-15);

    // The default scene holds the carbody's longitudinal position to the frame.
    let d = Scene::from_file(scenes_dir().join("default.toml")).unwrap();
    let x = Dof {
        member: Member::Body(d.vehicle.body_id("carbody").unwrap()),
        kind: DofKind::X,
    };
    assert!(d.is_frozen(x));
    assert!(!d.dofs().contains(&x));
    assert_eq!(d.dofs().len(), d.vehicle.dofs().len() - 1);

    let k = Scene::from_file(scenes_dir().join("free_wheelset_klingel.toml")).unwrap();
    assert!((k.speed.speed_at(0.0) - 5.0).abs() < 1e-12);
    assert_eq!(k.length, RunLength::Distance(100.0));
    assert!((k.duration() - 20.0).abs() < 1e-12);
    assert!((k.initial.lateral_offset - 1e-3).abs() < 1e-15);
}

#[test]
fn units_are_converted_and_defaults_applied() {
    let s = compile(&format!(
        "{GOOD}[contact]\nmodel = \"fastsim\"\nstep_mm = 0.25\n[integrator]\nmethod = \"radau5\"\nrtol = 1e-5\nmax_step_s = 1e-3\n[initial]\nyaw_mrad = 2\n"
    ))
    .unwrap();
    assert_eq!(s.contact.model, ContactModelKind::Fastsim);
    assert!((s.contact.travel.step - 0.25e-3).abs() < 1e-15);
    match s.integrator {
        Method::Radau5 {
            rtol, atol, h_max, ..
        } => {
            assert_eq!((rtol, atol, h_max), (1e-5, 1e-8, 1e-3));
        }
        m => panic!("{m:?}"),
    }
    assert!((s.initial.yaw - 2e-3).abs() < 1e-15);
    assert_eq!(s.vehicle.wheelset(s.initial.wheelset).name, "ws_front");
    assert_eq!(s.log.rate_hz, 200.0);
    let rk = compile(&format!(
        "{GOOD}[integrator]\nmethod = \"rk4\"\nstep_s = 2e-5\n"
    ))
    .unwrap();
    assert_eq!(rk.integrator, Method::Rk4 { h: 2e-5 });
    let p = compile(
        "vehicle = \"../vehicles/wheelset_free.toml\"\ntrack = \"../tracks/straight.toml\"\ndistance_m = 300\n[speed_profile]\ndistance_m = [0, 100, 200]\nspeed_kmh = [36, 72, 72]\n",
    )
    .unwrap();
    assert!((p.speed.speed_at(50.0) - 15.0).abs() < 1e-12);
    assert!((p.duration() - (2f64.ln() / 0.1 + 10.0)).abs() < 1e-9);
}

#[test]
fn curve_criterion_uses_the_longest_rigid_wheelbase() {
    let bogie =
        railsim_vehicle::VehicleModel::from_file(root().join("vehicles/bogie_two_axle.toml"))
            .unwrap();
    let wb = longest_rigid_wheelbase(&bogie).unwrap();
    assert!((wb.length - 2.56).abs() < 1e-12);
    assert!((required_curve_radius(&bogie) - 51.2).abs() < 1e-9);
    let manchester =
        railsim_vehicle::VehicleModel::from_file(root().join("vehicles/manchester_vehicle1.toml"))
            .unwrap();
    // The bogie wheelbase, not the 19 m bogie-centre distance: the carbody holds bogies, not
    // wheelsets.
    assert!((longest_rigid_wheelbase(&manchester).unwrap().length - 2.56).abs() < 1e-12);
    let free = railsim_vehicle::VehicleModel::from_file(root().join("vehicles/wheelset_free.toml"))
        .unwrap();
    assert!(longest_rigid_wheelbase(&free).is_none());
    assert_eq!(required_curve_radius(&free), 0.0);
}

/// A two-axle wagon with a 9 m rigid wheelbase (wheelsets sprung straight to the body) written
/// next to a track with an R = 150 m curve: 150 < 20 × 9 = 180 m is rejected; R = 300 m passes.
#[test]
fn a_curve_too_tight_for_the_wheelbase_is_rejected() {
    let dir = std::env::temp_dir().join(format!("railsim-sim-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ws = |name: &str, x: f64| {
        format!(
            "[[wheelset]]\nname = \"{name}\"\nmass_kg = 1200\ninertia_kgm2 = [700, 100, 700]\nposition_m = [{x}, 0, 0.46]\nnominal_radius_m = 0.46\nback_to_back_mm = 1360\nwheel_profile = {{ left = \"s1002\", right = \"s1002\" }}\n"
        )
    };
    let spring = |name: &str, ws: &str, x: f64, y: f64| {
        format!(
            "[[force]]\nname = \"{name}\"\ntype = \"bushing\"\nbody1 = \"body\"\nbody2 = \"{ws}\"\npoint_m = [{x}, {y}, 0.46]\nstiffness_n_per_m = [1e7, 1e6, 1e6]\n"
        )
    };
    let mut wagon = String::from(
        "name = \"two-axle wagon\"\n[[body]]\nname = \"body\"\nmass_kg = 10000\ninertia_kgm2 = [1e4, 1e5, 1e5]\nposition_m = [0, 0, 1.5]\n",
    );
    wagon += &ws("ws1", 4.5);
    wagon += &ws("ws2", -4.5);
    for (n, w, x) in [("a", "ws1", 4.5), ("b", "ws2", -4.5)] {
        wagon += &spring(&format!("{n}_l"), w, x, 1.0);
        wagon += &spring(&format!("{n}_r"), w, x, -1.0);
    }
    std::fs::write(dir.join("wagon.toml"), wagon).unwrap();
    let track = |r: f64| {
        format!(
            "gauge_mm = 1435\nrail_inclination = \"1:40\"\nrail_profile = {{ left = \"uic60\", right = \"uic60\" }}\n[[segment]]\ntype = \"tangent\"\nlength_m = 100\n[[segment]]\ntype = \"curve\"\nradius_m = {r}\ndirection = \"right\"\nlength_m = 200\n"
        )
    };
    std::fs::write(dir.join("r150.toml"), track(150.0)).unwrap();
    std::fs::write(dir.join("r300.toml"), track(300.0)).unwrap();
    let scene = |t: &str| {
        format!("vehicle = \"wagon.toml\"\ntrack = \"{t}\"\nspeed_kmh = 40\ndistance_m = 200\n")
    };
    let ok = Scene::from_toml_str(&scene("r300.toml"), "scenes/x.toml", &dir);
    assert!(ok.is_ok(), "{}", ok.unwrap_err());
    let err = Scene::from_toml_str(&scene("r150.toml"), "scenes/x.toml", &dir).unwrap_err();
    let p: Vec<String> = err.problems().iter().map(|p| p.to_string()).collect();
    expect(
        &p,
        2,
        &[
            "track",
            "radius 150.0 m",
            "r150.toml:9:12",
            "9.00 m",
            "'ws1' and 'ws2'",
            "180.0 m",
        ],
    );
    assert_eq!(err.problems()[0].key, "track");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unknown_key_is_reported_with_a_suggestion() {
    let p = problems(&format!("{GOOD}sped_kmh = 3\n[log]\nrate = 10\n"));
    expect(
        &p,
        5,
        &["unknown key 'sped_kmh'", "did you mean 'speed_kmh'"],
    );
    expect(
        &p,
        7,
        &["[log] unknown key 'rate'", "did you mean 'rate_hz'"],
    );
}

#[test]
fn missing_vehicle_file_is_reported_at_the_key() {
    let p = problems(&GOOD.replace("bogie_two_axle", "no_such_vehicle"));
    expect(
        &p,
        1,
        &[
            "vehicle: cannot read vehicle file",
            "vehicles/no_such_vehicle.toml",
        ],
    );
}

#[test]
fn missing_keys_are_reported() {
    let p = problems("name = \"empty\"\n");
    for key in [
        "'vehicle'",
        "'track'",
        "missing speed",
        "missing run length",
    ] {
        assert!(
            p.iter()
                .any(|x| x.starts_with("scenes/x.toml:1:1:") && x.contains(key)),
            "{key}: {p:?}"
        );
    }
}

#[test]
fn both_duration_and_distance_are_rejected() {
    let p = problems(&format!("{GOOD}distance_m = 100\n"));
    expect(&p, 5, &["distance_m", "either duration_s or distance_m"]);
}

#[test]
fn negative_speed_is_rejected() {
    let p = problems(&GOOD.replace("speed_kmh = 100", "speed_kmh = -100"));
    expect(
        &p,
        3,
        &["speed_kmh must be a speed from 0.01 to 1500 km/h", "-100"],
    );
    // a vehicle (almost) at rest has no creepages: refused at the key, not in the contact
    let p = problems(&GOOD.replace("speed_kmh = 100", "speed_kmh = 1e-9"));
    expect(
        &p,
        3,
        &["speed_kmh must be a speed from 0.01 to 1500 km/h, found 1e-9"],
    );
    let p = problems(
        "vehicle = \"../vehicles/wheelset_free.toml\"\ntrack = \"../tracks/straight.toml\"\nduration_s = 1\n[speed_profile]\ndistance_m = [0, 10]\nspeed_kmh = [10, -5]\n",
    );
    expect(&p, 6, &["[speed_profile] speed_kmh", "-5"]);
}

#[test]
fn bad_contact_model_lists_the_valid_names() {
    let p = problems(&format!("{GOOD}[contact]\nmodel = \"stripse\"\n"));
    expect(
        &p,
        6,
        &[
            "unknown contact model 'stripse'",
            "did you mean 'stripes'",
            "linear, polach, fastsim, stripes, halfspace",
        ],
    );
}

#[test]
fn hertz_search_is_read_and_checked() {
    let s = compile(&format!(
        "{GOOD}[contact]\nmodel = \"polach\"\nhertz_search = \"travel\"\n"
    ))
    .unwrap();
    assert_eq!(s.contact.hertz_search, HertzSearch::Travel);
    let s = compile(&format!("{GOOD}[contact]\nmodel = \"polach\"\n")).unwrap();
    assert_eq!(s.contact.hertz_search, HertzSearch::Point);
    let p = problems(&format!(
        "{GOOD}[contact]\nmodel = \"polach\"\nhertz_search = \"pointt\"\n"
    ));
    expect(
        &p,
        7,
        &[
            "unknown search 'pointt'",
            "did you mean 'point'",
            "point, travel",
        ],
    );
}

#[test]
fn the_tangential_solution_is_read_and_checked() {
    let s = compile(&format!("{GOOD}[contact]\ntangential = \"fastsim\"\n")).unwrap();
    assert_eq!(s.contact.tangential, Tangential::Fastsim);
    let s = compile(&format!("{GOOD}[contact]\nmodel = \"halfspace\"\n")).unwrap();
    assert_eq!(s.contact.tangential, Tangential::Fastrip);
    for (text, want) in [
        (
            "tangential = \"fastsin\"",
            vec!["unknown solution 'fastsin'", "did you mean 'fastsim'"],
        ),
        (
            "tangential = \"exact\"",
            vec!["reference level", "not for dynamics", "fastrip, fastsim"],
        ),
        (
            "model = \"polach\"\ntangential = \"fastsim\"",
            vec![
                "applies only to model = \"stripes\" or \"halfspace\"",
                "polach",
            ],
        ),
    ] {
        let p = problems(&format!("{GOOD}[contact]\n{text}\n"));
        let line = 6 + text.lines().count() - 1;
        expect(&p, line, &want);
    }
}

/// `[contact] polach`: Polach's reduction factors, and `[contact] falling_friction`, read into
/// the contact options, with the 1999 model's and Coulomb friction's values for the keys left
/// out; `falling_friction` with `polach`, `fastsim` and `stripes`; each key's range, k_S <= k_A,
/// an unknown key, `polach` with another model and `falling_friction` with `linear` or
/// `halfspace` reported at the key's line.
#[test]
fn polachs_extended_model_is_read_and_checked() {
    use railsim_contact::{FallingFriction, PolachAdhesion};
    let s = compile(&format!(
        "{GOOD}[contact]\nmodel = \"polach\"\npolach = {{ k_a = 0.8, k_s = 0.4 }}\n\
         falling_friction = {{ ratio_at_infinite_slip = 0.4, decay_s_per_m = 0.6 }}\n"
    ))
    .unwrap();
    assert_eq!(s.contact.polach, PolachAdhesion { k_a: 0.8, k_s: 0.4 });
    assert_eq!(
        s.contact.falling_friction,
        FallingFriction {
            ratio: 0.4,
            decay: 0.6
        }
    );
    let s = compile(&format!(
        "{GOOD}[contact]\nmodel = \"polach\"\npolach = {{ k_s = 0.5 }}\n"
    ))
    .unwrap();
    assert_eq!(s.contact.polach, PolachAdhesion { k_a: 1.0, k_s: 0.5 });
    assert_eq!(s.contact.falling_friction, FallingFriction::default());
    let s = compile(&format!("{GOOD}[contact]\nmodel = \"polach\"\n")).unwrap();
    assert_eq!(s.contact.polach, PolachAdhesion::default());
    for model in ["fastsim", "stripes"] {
        let s = compile(&format!(
            "{GOOD}[contact]\nmodel = \"{model}\"\nfalling_friction = {{ decay_s_per_m = 2 }}\n"
        ))
        .unwrap();
        assert_eq!(
            s.contact.falling_friction,
            FallingFriction {
                ratio: 1.0,
                decay: 2.0
            },
            "{model}"
        );
    }
    for (text, want) in [
        (
            "model = \"polach\"\npolach = { k_a = 1.2 }",
            vec!["polach.k_a must lie in (0e0, 1e0], found 1.2"],
        ),
        (
            "model = \"polach\"\npolach = { k_a = 0.5, k_s = 0.8 }",
            vec![
                "polach.k_s must not exceed polach.k_a",
                "k_s = 0.8 and k_a = 0.5",
            ],
        ),
        (
            "model = \"polach\"\nfalling_friction = { ratio_at_infinite_slip = 1.5 }",
            vec!["falling_friction.ratio_at_infinite_slip must lie in [0e0, 1e0], found 1.5"],
        ),
        (
            "model = \"stripes\"\nfalling_friction = { decay_s_per_m = -0.6 }",
            vec!["falling_friction.decay_s_per_m must lie in [0e0, 1e2] s/m, found -0.6"],
        ),
        (
            "model = \"polach\"\npolach = { friction_ratio_at_infinite_slip = 0.4 }",
            vec!["unknown field `friction_ratio_at_infinite_slip`", "k_a"],
        ),
        (
            "model = \"polach\"\npolach = { k_b = 0.5 }",
            vec!["unknown field `k_b`", "k_a"],
        ),
        (
            "model = \"fastsim\"\npolach = { k_a = 0.5 }",
            vec!["applies only to model = \"polach\"", "fastsim"],
        ),
        (
            "model = \"linear\"\nfalling_friction = { decay_s_per_m = 1 }",
            vec![
                "falling_friction applies to model",
                "\"linear\"",
                "no friction",
            ],
        ),
        (
            "model = \"halfspace\"\nfalling_friction = { decay_s_per_m = 1 }",
            vec![
                "falling_friction applies to model",
                "\"halfspace\"",
                "reference level",
            ],
        ),
    ] {
        let p = problems(&format!("{GOOD}[contact]\n{text}\n"));
        let line = 6 + text.lines().count() - 1;
        expect(&p, line, &want);
    }
}

#[test]
fn bad_integrator_and_tolerances_are_rejected() {
    let p = problems(&format!("{GOOD}[integrator]\nmethod = \"dopri45\"\n"));
    expect(
        &p,
        6,
        &["unknown integrator 'dopri45'", "dopri5, bs3, rk4, radau5"],
    );
    let p = problems(&format!(
        "{GOOD}[integrator]\nmethod = \"dopri5\"\nrtol = 0.5\natol = -1\nstep_s = 1e-4\n"
    ));
    expect(&p, 7, &["rtol must lie in"]);
    expect(&p, 8, &["atol must lie in"]);
    expect(&p, 9, &["'step_s' does not apply to method 'dopri5'"]);
    let p = problems(&format!(
        "{GOOD}[integrator]\nmethod = \"rk4\"\nrtol = 1e-6\n"
    ));
    expect(&p, 6, &["method 'rk4' needs step_s"]);
    expect(&p, 7, &["'rtol' does not apply to method 'rk4'"]);
    // a largest step so small that time hardly advances (a fuzzing run: 1e-300 s ran forever)
    let p = problems(&format!(
        "{GOOD}[integrator]\nmethod = \"dopri5\"\nmax_step_s = 1e-300\n"
    ));
    expect(&p, 7, &["max_step_s must lie in"]);
}

/// Freezing everything the vehicle leaves free gave the integrator's "state dimension must be
/// positive" with no file or key.
#[test]
fn freezing_every_degree_of_freedom_is_located() {
    let text = "vehicle = \"../vehicles/wheelset_free.toml\"\ntrack = \"../tracks/straight.toml\"\n\
                speed_kmh = 100\nduration_s = 1\n\
                freeze = [\"ws.x\", \"ws.y\", \"ws.z\", \"ws.roll\", \"ws.spin\", \"ws.yaw\"]\n";
    let p = problems(text);
    expect(
        &p,
        5,
        &["freeze: every degree of freedom", "nothing would move"],
    );
}

#[test]
fn unknown_dof_in_freeze_gets_a_suggestion() {
    let p = problems(&format!(
        "{GOOD}freeze = [\"ws_front.spn\", \"bogy.x\", \"ws_rear.pitch\", \"ws_front\"]\n"
    ));
    expect(
        &p,
        5,
        &[
            "'spn' is not a degree of freedom of wheelset 'ws_front'",
            "did you mean 'spin'",
        ],
    );
    expect(
        &p,
        5,
        &["no body or wheelset 'bogy'", "did you mean 'bogie'"],
    );
    expect(
        &p,
        5,
        &[
            "'pitch' is not a degree of freedom of wheelset 'ws_rear'",
            "x, y, z, roll, spin, yaw",
        ],
    );
    expect(
        &p,
        5,
        &["'ws_front' is not a degree of freedom", "body.dof"],
    );
    assert_eq!(p.len(), 4, "{p:?}");
}

#[test]
fn run_past_the_end_of_the_track_is_rejected() {
    // curve_r1200.toml is 1540 m long.
    let p = problems(&GOOD.replace("duration_s = 1", "duration_s = 100"));
    expect(
        &p,
        4,
        &["duration_s", "beyond the end of track", "curve_r1200.toml"],
    );
}

/// The initial state is the static equilibrium on straight level track: a start inside a curve
/// (here R = 1200 m with 120 mm cant, from s = 320 m) placed the bodies off each other's
/// attachment points by the curve's versines, and the Manchester vehicle started in a 150 m curve
/// "derailed" at t = 0.03 s. Such a start is rejected at `start_m`, with the largest start that
/// keeps the vehicle on the tangent before the curve.
#[test]
fn a_start_on_curved_or_canted_track_is_rejected() {
    let p = problems(&GOOD.replace("duration_s = 1", "duration_s = 1\nstart_m = 400"));
    expect(
        &p,
        5,
        &[
            "start_m = 400 m",
            "on curved or canted track",
            "static equilibrium on straight level track",
            "expected start_m at most",
        ],
    );
    // at the end of the tangent (200 m) the same vehicle is accepted
    let tangent = compile(&GOOD.replace("duration_s = 1", "duration_s = 1\nstart_m = 150"));
    assert!(tangent.is_ok(), "{:?}", tangent.err());
}

/// `[initial] state = "quasi-static"` starts inside a circular curve (R = 1200 m from s = 320
/// to 1120 m), also with a disturbance; a start where curvature or cant change under the vehicle
/// (the clothoid before it) and an unknown state are rejected at their keys.
#[test]
fn a_quasi_static_start_lies_where_the_track_is_constant() {
    let start = |s: f64, initial: &str| {
        GOOD.replace(
            "duration_s = 1",
            &format!("duration_s = 1\nstart_m = {s}\n[initial]\n{initial}"),
        )
    };
    let inside = compile(&start(600.0, "state = \"quasi-static\""));
    let inside = inside.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(inside.initial_state, railsim_sim::InitialState::QuasiStatic);
    let p = problems(&start(300.0, "state = \"quasi-static\""));
    expect(
        &p,
        5,
        &[
            "start_m = 300 m",
            "where the track changes",
            "needs curvature and cant constant under the vehicle",
            "expected a start with every wheelset on one tangent or in one circular curve",
        ],
    );
    // a disturbance is added to the steady state (crates/railsim-sim/tests/quasi_static_start.rs)
    let kicked = compile(&start(
        600.0,
        "state = \"quasi-static\"\nlateral_offset_mm = 2",
    ));
    let kicked = kicked.unwrap_or_else(|e| panic!("{e}"));
    assert!((kicked.initial.lateral_offset - 2e-3).abs() < 1e-15);
    let p = problems(&start(150.0, "state = \"quasistatic\""));
    expect(
        &p,
        7,
        &[
            "unknown initial state 'quasistatic'",
            "expected one of: static, quasi-static",
        ],
    );
    // the static start's rejection names the quasi-static one
    let p = problems(&start(600.0, "state = \"static\""));
    expect(
        &p,
        5,
        &["on curved or canted track", "state = \"quasi-static\""],
    );
}

#[test]
fn disturbance_of_a_frozen_dof_and_bad_log_are_rejected() {
    let p = problems(&format!(
        "{GOOD}freeze = [\"ws_front.y\"]\n[initial]\nlateral_offset_mm = 2\nyaw_mrad = 500\n[log]\npath = \"out/run.txt\"\nrate_hz = 0\ntopics = [\"bodies\", \"contacts\", \"bodies\"]\n"
    ));
    expect(
        &p,
        7,
        &["lateral_offset_mm", "'ws_front' has 'y' frozen (by freeze)"],
    );
    expect(&p, 8, &["yaw_mrad must lie in [-20, 20] mrad"]);
    expect(&p, 10, &["ending in '.mcap'"]);
    expect(&p, 11, &["rate_hz must lie in"]);
    expect(
        &p,
        12,
        &["unknown topic 'contacts'", "did you mean 'contact'"],
    );
    expect(&p, 12, &["'bodies' is listed twice"]);
}

#[test]
fn wrong_types_are_reported_and_the_rest_still_checked() {
    let p = problems(
        "vehicle = 3\ntrack = \"../tracks/straight.toml\"\nspeed_kmh = \"fast\"\nduration_s = -1\n[contact]\nmodel = \"hertz\"\n",
    );
    expect(&p, 1, &["vehicle"]);
    expect(&p, 3, &["speed_kmh"]);
    expect(&p, 4, &["duration_s must be a positive time"]);
    expect(&p, 6, &["unknown contact model 'hertz'"]);
    // Dropped keys are not reported again as missing.
    assert!(
        !p.iter()
            .any(|x| x.contains("missing key 'vehicle'") || x.contains("missing speed")),
        "{p:?}"
    );
}

#[test]
fn several_problems_in_several_files_are_all_reported() {
    // Scene problems (bad speed, bad model, bad integrator, both lengths) and the vehicle
    // file's own problems, with the vehicle file's own line and column, in one error.
    let dir = std::env::temp_dir().join(format!("railsim-sim-many-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("bad_vehicle.toml"),
        "[[wheelset]]\nname = \"ws\"\nmass_kg = -5\ninertia_kgm2 = [1120, 112, 1120]\nposition_m = [0, 0, 0.46]\nnominal_radius_m = 0.46\nback_to_back_mm = 1360\nwheel_profile = { left = \"s1002\", right = \"s1002\" }\ncolour = \"red\"\n",
    )
    .unwrap();
    let text = format!(
        "vehicle = \"bad_vehicle.toml\"\ntrack = \"{}\"\nspeed_kmh = 0\nduration_s = 1\ndistance_m = 5\n[contact]\nmodel = \"kalker\"\n[integrator]\nmethod = \"euler\"\n",
        root().join("tracks/straight.toml").display()
    );
    let err = Scene::from_toml_str(&text, "scenes/x.toml", &dir).unwrap_err();
    let p: Vec<String> = err.problems().iter().map(|p| p.to_string()).collect();
    expect(&p, 1, &["vehicle file", "has 2 problem(s)"]);
    expect(&p, 3, &["speed_kmh must be a speed from 0.01 to 1500 km/h"]);
    expect(&p, 5, &["either duration_s or distance_m"]);
    expect(&p, 7, &["unknown contact model 'kalker'"]);
    expect(&p, 9, &["unknown integrator 'euler'"]);
    let vfile = dir.join("bad_vehicle.toml").display().to_string();
    expect_in(&p, &vfile, 3, &["mass_kg"]);
    expect_in(&p, &vfile, 9, &["unknown key 'colour'"]);
    // The scene's own problems come first, in file order.
    let lines: Vec<usize> = err
        .problems()
        .iter()
        .take_while(|q| q.file == "scenes/x.toml")
        .map(|q| q.line)
        .collect();
    assert_eq!(lines, vec![1, 3, 5, 7, 9]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn syntax_error_is_located() {
    let p = problems("vehicle = \"a.toml\nspeed_kmh = 3\n");
    assert!(
        p[0].starts_with("scenes/x.toml:1:") && p[0].contains("TOML syntax"),
        "{p:?}"
    );
}

#[test]
fn format_doc_example_compiles() {
    let doc = std::fs::read_to_string(root().join("docs/formats/scene.md")).unwrap();
    let start = doc.find("```toml\n").expect("a toml example") + "```toml\n".len();
    let end = start + doc[start..].find("```").unwrap();
    let scene = Scene::from_toml_str(&doc[start..end], "docs/formats/scene.md", &scenes_dir())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.vehicle.wheelsets().len(), 4);
    assert!(!scene.frozen.is_empty());
    let _ = Path::new(".");
}

#[test]
fn assessment_settings_are_read_and_checked() {
    let s = compile(&format!(
        "{GOOD}[assessment]\nalpha = 0.85\ninstability_frequency_hz = 5.5\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.assessment.alpha, 0.85);
    assert_eq!(s.assessment.instability_frequency, Some(5.5));
    let s = compile(GOOD).unwrap();
    assert_eq!(s.assessment, railsim_sim::assess::AssessOptions::default());
    // out of range, a band the log rate cannot carry, an unknown key
    let p = problems(&format!(
        "{GOOD}[assessment]\nalpha = 1.2\ninstability_frequency_hz = 0\nbogus = 1\n"
    ));
    expect(&p, 6, &["alpha must lie in (0e0, 1e0]", "found 1.2"]);
    expect(
        &p,
        7,
        &["instability_frequency_hz must lie in", "Hz, found 0"],
    );
    expect(&p, 8, &["bogus"]);
    // the band is checked against the assessment's rate: at a 15 Hz log it is 1005 Hz by
    // default, which carries the band; set to the log rate, it cannot
    let low_log =
        format!("{GOOD}[log]\nrate_hz = 15\n[assessment]\ninstability_frequency_hz = 6\n");
    let s = compile(&low_log).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.assessment_rate(), 1005.0);
    let p = problems(&format!("{low_log}rate_hz = 15\n"));
    expect(
        &p,
        8,
        &[
            "instability_frequency_hz = 6 Hz",
            "reaches 8 Hz",
            "assessment rate above 16 Hz",
            "samples at 15 Hz",
        ],
    );
}

#[test]
fn assessment_limits_are_read_in_file_units_and_checked() {
    let s = compile(&format!(
        "{GOOD}[assessment]\ny_over_q_limit = 0.9\ny_over_q_limit_small_radius = 1.1\n\
         small_radius_m = 300\nq_limit_kn = 180\ny_qst_limit_kn = 50\nq_qst_limit_kn = 140\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    let l = s.assessment.limits;
    assert_eq!(
        (l.y_over_q, l.y_over_q_small_radius, l.small_radius),
        (0.9, 1.1, 300.0)
    );
    assert_eq!((l.q, l.y_qst, l.q_qst), (Some(180e3), 50e3, 140e3));
    // the defaults
    let d = compile(GOOD).unwrap().assessment.limits;
    assert_eq!((d.y_over_q, d.y_over_q_small_radius), (0.8, 1.2));
    assert_eq!((d.q, d.y_qst, d.q_qst), (None, 60e3, 145e3));
    let p = problems(&format!(
        "{GOOD}[assessment]\ny_qst_limit_kn = -5\ny_over_q_limit = 0\nq_limit_kn = nan\n"
    ));
    expect(
        &p,
        6,
        &["y_qst_limit_kn must lie in (0e0, 1e4] kN", "found -5"],
    );
    expect(&p, 7, &["y_over_q_limit must lie in (0e0, 1e1]", "found 0"]);
    expect(&p, 8, &["q_limit_kn must lie in", "found NaN"]);
}

#[test]
fn the_vertical_comfort_weighting_is_read_and_checked() {
    let s = compile(&format!(
        "{GOOD}[assessment]\nvertical_weighting = \"iso2631-4\"\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        s.assessment.vertical_weighting,
        VerticalWeighting::Iso2631_4
    );
    let d = compile(GOOD).unwrap().assessment.vertical_weighting;
    assert_eq!(d, VerticalWeighting::En12299);
    let p = problems(&format!(
        "{GOOD}[assessment]\nvertical_weighting = \"iso2631\"\n"
    ));
    expect(
        &p,
        6,
        &[
            "vertical_weighting: unknown weighting 'iso2631'",
            "did you mean 'iso2631-4'",
            "en12299, iso2631-4",
        ],
    );
}

#[test]
fn the_per_section_statistics_are_read_and_checked() {
    let s = compile(&format!(
        "{GOOD}[assessment]\nsection_length_m = 250\nsection_k = 3\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        s.assessment.sections,
        Some(SectionOptions {
            length: 250.0,
            k: Some(3.0)
        })
    );
    let s = compile(&format!("{GOOD}[assessment]\nsection_length_m = 500\n")).unwrap();
    assert_eq!(
        s.assessment.sections.map(|o| (o.length, o.k)),
        Some((500.0, None))
    );
    assert_eq!(compile(GOOD).unwrap().assessment.sections, None);
    let p = problems(&format!(
        "{GOOD}[assessment]\nsection_length_m = 5\nsection_k = 0\n"
    ));
    expect(
        &p,
        6,
        &["section_length_m must lie in [1e1, 1e5] m, found 5"],
    );
    expect(&p, 7, &["section_k must lie in (0e0, 1e1], found 0"]);
    let p = problems(&format!("{GOOD}[assessment]\nsection_k = 3\n"));
    expect(
        &p,
        6,
        &[
            "section_k: expected section_length_m beside it",
            "found none",
        ],
    );
}

#[test]
fn comfort_points_are_read_and_checked() {
    let s = compile(&format!(
        "{GOOD}[assessment]\ncomfort_points = [{{ name = \"floor front\", x_m = 1.2, z_m = -0.8 }}, {{ name = \"floor centre\", z_m = -0.8 }}]\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    let p = &s.assessment.comfort_points;
    assert_eq!(p.len(), 2);
    assert_eq!(
        (p[0].name.as_str(), p[0].offset),
        ("floor front", [1.2, 0.0, -0.8])
    );
    assert_eq!(
        (p[1].name.as_str(), p[1].offset),
        ("floor centre", [0.0, 0.0, -0.8])
    );
    let p = problems(&format!(
        "{GOOD}[assessment]\ncomfort_points = [{{ name = \"a\", x_m = 99 }}, {{ name = \"a\" }}, {{ name = \" \" }}]\n"
    ));
    expect(&p, 6, &["x_m must lie in [-5e1, 5e1] m, found 99"]);
    expect(
        &p,
        6,
        &["comfort point name 'a': expected a non-empty name used once"],
    );
    expect(
        &p,
        6,
        &["comfort point name '': expected a non-empty name used once"],
    );
    let p = problems(&format!(
        "{GOOD}[assessment]\ncomfort_points = [{{ name = \"a\", q_m = 1 }}]\n"
    ));
    assert!(p.iter().any(|x| x.contains("q_m")), "{p:?}");
    // a vehicle without a rigid body has no carbody to carry them
    let p = problems(
        "vehicle = \"../vehicles/wheelset_free.toml\"\ntrack = \"../tracks/straight.toml\"\nspeed_kmh = 10\nduration_s = 1\n[assessment]\ncomfort_points = [{ name = \"a\" }]\n",
    );
    expect(
        &p,
        6,
        &["the vehicle has no rigid body (carbody) to carry them"],
    );
}

/// `[contact] friction` is a number or a table of coefficients at contact angles (a lubricated
/// gauge face); bad tables are located at the key.
#[test]
fn friction_is_a_number_or_a_table_by_contact_angle() {
    use railsim_contact::Friction;
    let s = compile(&format!("{GOOD}[contact]\nfriction = 0.4\n")).unwrap();
    assert_eq!(
        s.friction,
        [Friction::Constant(0.4), Friction::Constant(0.4)]
    );
    let s = compile(&format!(
        "{GOOD}[contact]\nfriction = {{ contact_angle_deg = [10, 20], coefficient = [0.3, 0.15] }}\n"
    ))
    .unwrap();
    for f in &s.friction {
        match f {
            Friction::ByContactAngle { angle, mu } => {
                assert_eq!(mu, &[0.3, 0.15]);
                assert!((angle[1] - 20f64.to_radians()).abs() < 1e-15);
            }
            f => panic!("{f:?}"),
        }
    }
    // per rail: only the right (high) rail's gauge face lubricated
    let s = compile(&format!(
        "{GOOD}[contact]\nfriction = {{ left = 0.35, right = {{ contact_angle_deg = [15, 25], \
         coefficient = [0.35, 0.1] }} }}\n"
    ))
    .unwrap();
    assert_eq!(s.friction[0], Friction::Constant(0.35));
    assert!(matches!(&s.friction[1], Friction::ByContactAngle { mu, .. } if mu == &[0.35, 0.1]));
    // GOOD has four lines: the friction is on line 6
    for (value, needles) in [
        ("1.5", &["friction must lie in"][..]),
        ("\"dry\"", &["friction must be a number, a table"][..]),
        (
            "{ contact_angle_deg = [10], coefficient = [0.3] }",
            &["1 contact angles and 1 coefficients", "at least two"][..],
        ),
        (
            "{ contact_angle_deg = [10, 20], coefficient = [0.3, 0] }",
            &["friction.coefficient must lie in", "found 0"][..],
        ),
        (
            "{ contact_angle_deg = [20, 10], coefficient = [0.3, 0.2] }",
            &["must increase strictly, found 10 after 20"][..],
        ),
        (
            "{ contact_angle_deg = [10, 95], coefficient = [0.3, 0.2] }",
            &["contact_angle_deg must lie in [-90, 90] deg, found 95"][..],
        ),
        (
            "{ angle = [10, 20], coefficient = [0.3, 0.2] }",
            &["friction must be a number, a table"][..],
        ),
        (
            "{ contact_angle_deg = [10, 20], coefficient = [0.3, 0.2], left = 0.3 }",
            &["friction must be a number, a table"][..],
        ),
        (
            "{ left = 0.3, right = 2 }",
            &["friction.right must lie in", "found 2"][..],
        ),
        (
            "{ left = { left = 0.3, right = 0.3 }, right = 0.3 }",
            &["friction.left must be a number or a table by contact angle"][..],
        ),
    ] {
        let p = problems(&format!("{GOOD}[contact]\nfriction = {value}\n"));
        expect(&p, 6, needles);
    }
}

/// A run's log stores its integrator in the scene file's terms (`railsim replay` lists it), not
/// as Rust's debug form of the method (before stop 23 a `bs3` run stored its whole tableau).
#[test]
fn the_integrator_is_written_in_scene_file_terms() {
    use railsim_sim::scene::integrator_text;
    let cases = [
        (
            Method::dormand_prince(1e-4, 1e-6),
            "dopri5, rtol 1e-4, atol 1e-6, max_step_s unlimited",
        ),
        (
            Method::AdaptiveExplicit {
                tableau: &railsim_ode::tableau::BS3,
                rtol: 2.5e-5,
                atol: 1e-8,
                h0: None,
                h_max: 0.001,
            },
            "bs3, rtol 2.5e-5, atol 1e-8, max_step_s 0.001",
        ),
        (Method::Rk4 { h: 5e-4 }, "rk4, step_s 5e-4"),
        (
            Method::Radau5Fixed {
                h: 1e-3,
                rtol: 1e-6,
                atol: 1e-8,
            },
            "radau5 with a fixed step, step_s 0.001, rtol 1e-6, atol 1e-8",
        ),
    ];
    for (m, text) in cases {
        assert_eq!(integrator_text(&m), text, "{m:?}");
    }
    // every method the scene format offers
    for (method, keys) in [
        ("dopri5", "rtol = 1e-5\nmax_step_s = 0.01"),
        ("bs3", "rtol = 1e-5"),
        ("radau5", "rtol = 1e-5"),
        ("rk4", "step_s = 1e-3"),
    ] {
        let s = compile(&format!(
            "{GOOD}[integrator]\nmethod = \"{method}\"\n{keys}\n"
        ))
        .unwrap_or_else(|e| panic!("{e}"));
        let text = integrator_text(&s.integrator);
        assert!(text.starts_with(&format!("{method}, ")), "{text}");
        assert!(!text.contains('{'), "{text}");
    }
}

/// A bad profile file is read when the simulation is built: its error names the file and the
/// wheelset, side and key that point to it.
#[test]
fn a_bad_profile_file_is_named_with_the_key_that_points_to_it() {
    let dir = std::env::temp_dir().join(format!("railsim-sim-profile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // a profile in metres: far too narrow
    std::fs::write(
        dir.join("narrow.txt"),
        "0 0\n0.01 0.001\n0.02 0\n0.03 0.001\n",
    )
    .unwrap();
    let vehicle = std::fs::read_to_string(root().join("vehicles/wheelset_free.toml"))
        .unwrap()
        .lines()
        .map(|l| {
            if l.starts_with("wheel_profile") {
                "wheel_profile = { left = \"narrow.txt\", right = \"s1002\" }".to_owned()
            } else {
                l.to_owned()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(dir.join("v.toml"), vehicle).unwrap();
    let track = root().join("tracks/straight.toml");
    let text = format!(
        "vehicle = \"v.toml\"\ntrack = {:?}\nspeed_kmh = 100\nduration_s = 0.1\n",
        track.display().to_string()
    );
    let scene = Scene::from_toml_str(&text, "x.toml", &dir).unwrap_or_else(|e| panic!("{e}"));
    let e = match railsim_sim::Simulation::new(&scene) {
        Ok(_) => panic!("a 0.03 mm wide profile was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("wheelset 'ws', left wheel_profile (vehicle file): ")
            && e.contains("narrow.txt: the profile spans only 0.03 mm"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
