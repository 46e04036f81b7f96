//! Integration tests of railsim-vehicle: every shipped vehicle file, the Manchester vehicle's
//! mass and static wheel loads, degrees of freedom and internal states, and bad input.

use std::path::{Path, PathBuf};

use railsim_vehicle::{
    Axis, DofKind, ForceLaw, InternalStateKind, Member, NormalRule, Sign, VehicleError,
    VehicleModel, WheelProfile, series_force, series_state_rate,
};

fn vehicles_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../vehicles")
}

fn compile(text: &str) -> Result<VehicleModel, VehicleError> {
    VehicleModel::from_toml_str(text, "vehicles/x.toml", &vehicles_dir())
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

/// The one problem containing all `needles`, at `line` (column > 0).
fn expect(problems: &[String], line: usize, needles: &[&str]) {
    let prefix = format!("vehicles/x.toml:{line}:");
    let hit = problems
        .iter()
        .find(|p| p.starts_with(&prefix) && needles.iter().all(|n| p.contains(n)));
    assert!(
        hit.is_some(),
        "no problem at line {line} containing {needles:?} in:\n{}",
        problems.join("\n")
    );
    let rest = &hit.unwrap()[prefix.len()..];
    let col: usize = rest.split(':').next().unwrap().parse().unwrap();
    assert!(col >= 1);
}

const WS: &str = r#"
[[wheelset]]
name = "ws"
mass_kg = 1813
inertia_kgm2 = [1120, 112, 1120]
position_m = [0, 0, 0.46]
nominal_radius_m = 0.46
back_to_back_mm = 1360
wheel_profile = { left = "s1002", right = "s1002" }
"#;

#[test]
fn wheelset_products_of_inertia_are_refused() {
    let text = format!("{}\nproducts_kgm2 = [0, 5, 0]\n", WS.trim_end());
    let p = problems(&text);
    expect(
        &p,
        10,
        &[
            "wheelset 'ws'",
            "products_kgm2",
            "axisymmetric rotor",
            "[0.0, 5.0, 0.0]",
        ],
    );
    let text = format!("{}\nproducts_kgm2 = [0, 0, 0]\n", WS.trim_end());
    compile(&text).unwrap();
}

#[test]
fn every_vehicle_file_compiles_and_stands() {
    let mut n = 0;
    for entry in std::fs::read_dir(vehicles_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let v = VehicleModel::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(!v.wheelsets().is_empty());
            let eq = v
                .static_equilibrium()
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let weight = v.total_mass() * v.gravity();
            // Only elements to the track could carry weight; none of the shipped files has a
            // vertical one, so the wheels carry all of it.
            let rel = (eq.total_wheel_load() - weight).abs() / weight;
            assert!(
                rel < 1e-9,
                "{}: wheels carry {} of {weight} N",
                path.display(),
                eq.total_wheel_load()
            );
            n += 1;
        }
    }
    assert!(n >= 4, "found only {n} vehicle files");
}

#[test]
fn manchester_vehicle1_mass_and_static_wheel_loads() {
    let v = VehicleModel::from_file(vehicles_dir().join("manchester_vehicle1.toml")).unwrap();
    assert_eq!(v.bodies().len(), 3);
    assert_eq!(v.wheelsets().len(), 4);
    // vehicle-reference.md §1.2 [D]: total mass 44 482 kg.
    assert!(
        (v.total_mass() - 44_482.0).abs() < 1e-9,
        "{}",
        v.total_mass()
    );
    let eq = v.static_equilibrium().unwrap();
    // §1.2 [D]: Q0 = 54.5 kN per wheel; issue 3 asks for 54.5 kN ± 1 %.
    let q0 = 44_482.0 * 9.81 / 8.0;
    eprintln!(
        "Manchester vehicle 1 static wheel loads [N]: {:?}",
        eq.wheel_loads
    );
    for (i, q) in eq.wheel_loads.iter().enumerate() {
        for side in q {
            assert!(
                (side - q0).abs() / q0 < 1e-6,
                "wheelset {i}: {side} N vs {q0} N"
            );
            assert!(
                (side - 54_500.0).abs() / 54_500.0 < 0.01,
                "wheelset {i}: {side} N"
            );
        }
    }
    // §1.2 [D]: axle load P0 = 109.1 kN.
    let p0 = eq.wheel_loads[0][0] + eq.wheel_loads[0][1];
    assert!((p0 / 1e3 - 109.1).abs() < 0.05, "{p0}");
    // Primary spring preload = (carbody/4 + bogie) / 2... per axlebox: (32000/2 + 2615)/4 · g.
    let id = v.force_id("primary_ws1_l").unwrap();
    let fz = eq.element_force[id.index()][2];
    let expected = (32_000.0 / 2.0 + 2615.0) / 4.0 * 9.81;
    assert!(
        (-fz - expected).abs() / expected < 1e-6,
        "{fz} vs {expected}"
    );
    // Carbody sinks by the series deflection of secondary and primary springs.
    let dz = eq.body_displacement[v.body_id("carbody").unwrap().index()][2];
    let sec = 32_000.0 * 9.81 / (4.0 * 430e3);
    let prim = (32_000.0 + 2.0 * 2615.0) * 9.81 / (8.0 * 1.22e6);
    assert!((-dz - sec - prim).abs() < 2e-4, "{dz} vs {}", sec + prim);
}

#[test]
fn the_bogies_are_the_frames_with_their_nearest_wheelsets() {
    let v = VehicleModel::from_file(vehicles_dir().join("manchester_vehicle1.toml")).unwrap();
    assert_eq!(v.carbody(), v.body_id("carbody"));
    let ids =
        |names: &[&str]| -> Vec<_> { names.iter().map(|n| v.wheelset_id(n).unwrap()).collect() };
    let bogies = v.bogies();
    assert_eq!(bogies.len(), 2);
    assert_eq!(Some(bogies[0].frame), v.body_id("bogie_front"));
    assert_eq!(bogies[0].wheelsets, ids(&["ws1", "ws2"]));
    assert_eq!(Some(bogies[1].frame), v.body_id("bogie_rear"));
    assert_eq!(bogies[1].wheelsets, ids(&["ws3", "ws4"]));
    // a lone wheelset has neither carbody nor bogies; a two-axle bogie alone is a carbody
    let w = VehicleModel::from_file(vehicles_dir().join("wheelset_springs.toml")).unwrap();
    assert_eq!((w.carbody(), w.bogies()), (None, Vec::new()));
    let b = VehicleModel::from_file(vehicles_dir().join("bogie_two_axle.toml")).unwrap();
    assert!(b.carbody().is_some() && b.bogies().is_empty());
}

#[test]
fn manchester_vehicle1_elements() {
    let v = VehicleModel::from_file(vehicles_dir().join("manchester_vehicle1.toml")).unwrap();
    let bump = v.force(v.force_id("lateral_bump_stop_bogie_front").unwrap());
    let ForceLaw::Table { table, .. } = &bump.law else {
        panic!("not a table")
    };
    assert_eq!(table.force(0.020), 0.0);
    assert!((table.force(0.0325) - (600.0 + 1760.0) / 2.0).abs() < 1e-9);
    assert!((table.force(-0.0325) + (600.0 + 1760.0) / 2.0).abs() < 1e-9);
    assert!(matches!(
        v.force(v.force_id("anti_roll_bar_bogie_rear").unwrap()).law,
        ForceLaw::AntiRollBar { stiffness } if stiffness == 940e3
    ));
    assert_eq!(v.wheelsets()[0].profiles[0], WheelProfile::S1002);
    assert!((v.wheelsets()[0].contact_half_distance() - 0.75).abs() < 1e-12);
    assert_eq!(v.dofs().len(), 7 * 6);
    assert!(v.internal_states().is_empty(), "§1.2 lists no yaw damper");
}

#[test]
fn frozen_dofs_are_excluded() {
    let text = format!("{}\nfrozen = [\"x\", \"spin\"]\n", WS.trim_end());
    let v = compile(&text).unwrap_or_else(|e| panic!("{e}"));
    let dofs = v.dofs();
    assert_eq!(dofs.len(), 4);
    assert!(
        dofs.iter()
            .all(|d| d.kind != DofKind::X && d.kind != DofKind::Pitch)
    );
    assert!(dofs.iter().all(|d| matches!(d.member, Member::Wheelset(_))));
    assert_eq!(v.dof_name(dofs[0]), "ws.y");
    // A frozen body is held: a body frozen in z needs no vertical support.
    let text = format!(
        "{WS}\n[[body]]\nname = \"mass\"\nmass_kg = 100\ninertia_kgm2 = [1, 1, 1]\nposition_m = [0, 0, 1]\nfrozen = [\"x\", \"y\", \"z\", \"roll\", \"pitch\", \"yaw\"]\n"
    );
    let v = compile(&text).unwrap();
    assert_eq!(v.dofs().len(), 6);
    let eq = v.static_equilibrium().unwrap();
    assert!((eq.total_wheel_load() - 1813.0 * 9.81).abs() < 1e-6);
}

/// A vehicle file whose `frozen` lists leave nothing free is refused at its (last) `frozen`
/// key; before stop 39 the simulation reported the integrator's "state dimension must be
/// positive", naming neither file nor key.
#[test]
fn a_vehicle_with_nothing_free_is_refused_at_its_frozen_list() {
    let text = format!(
        "{}\nfrozen = [\"x\", \"y\", \"z\", \"roll\", \"yaw\", \"spin\"]\n",
        WS.trim_end()
    );
    let p = problems(&text);
    let line = text.lines().count();
    expect(
        &p,
        line,
        &["frozen", "every degree of freedom", "nothing would move"],
    );
}

#[test]
fn unsupported_body_is_reported_by_statics() {
    let text = format!(
        "{WS}\n[[body]]\nname = \"floating\"\nmass_kg = 100\ninertia_kgm2 = [1, 1, 1]\nposition_m = [0, 0, 1]\n"
    );
    let v = compile(&text).unwrap();
    let e = v.static_equilibrium().unwrap_err().to_string();
    assert!(e.contains("body 'floating' has no support"), "{e}");
}

#[test]
fn series_spring_damper_declares_one_internal_state() {
    let v = VehicleModel::from_file(vehicles_dir().join("bogie_two_axle.toml")).unwrap();
    let states = v.internal_states();
    assert_eq!(states.len(), 2, "two yaw dampers");
    let f = v.force(states[0].element);
    assert_eq!(f.name, "yaw_damper_l");
    assert_eq!(f.law.internal_states(), 1);
    assert_eq!(states[0].kind, InternalStateKind::DamperElongation);
    let ForceLaw::SeriesSpringDamper {
        stiffness, damping, ..
    } = f.law
    else {
        panic!()
    };
    // Spring force equals damper force c·ṡ; at rest (s = Δ) there is no force.
    let (delta, s) = (0.01, 0.004);
    let rate = series_state_rate(stiffness, damping, delta, s);
    assert!((damping * rate + series_force(stiffness, delta, s)).abs() < 1e-9);
    assert_eq!(series_force(stiffness, delta, delta), 0.0);
    // Static solve: a series element carries no static force.
    let eq = v.static_equilibrium().unwrap();
    assert!(
        eq.element_force[states[0].element.index()]
            .iter()
            .all(|x| *x == 0.0)
    );
}

#[test]
fn wheelset_springs_match_the_wickens_case() {
    let v = VehicleModel::from_file(vehicles_dir().join("wheelset_springs.toml")).unwrap();
    let w = &v.wheelsets()[0];
    assert_eq!(w.profiles[0], WheelProfile::Cone { conicity: 0.15 });
    let (mut ky, mut kpsi) = (0.0, 0.0);
    for f in v.forces() {
        let ForceLaw::Bushing { stiffness, .. } = f.law else {
            panic!()
        };
        ky += stiffness[1];
        kpsi += stiffness[0] * f.point1[1].powi(2);
    }
    assert!((ky - 7.768e6).abs() < 1.0);
    assert!((kpsi - 62.782e6).abs() < 1.0);
}

#[test]
fn each_kind_of_bad_input_is_located_and_named() {
    let text = r#"name = "bad"
[[body]]
name = "bogie"
mass_kg = -5
inertia_kgm2 = [10, 10, 30]
position_m = [0, 0, 0.6]

[[body]]
name = "bogie"
mass_kg = 100
inertia_kgm2 = [10, 10, 10]
products_kgm2 = [20, 0, 0]
position_m = [0, 0, 0.6]

[[wheelset]]
name = "ws"
mass_kg = "heavy"
inertia_kgm2 = [1120, 112, 1120]
position_m = [0, 0, 0.46]
nominal_radius_m = 0
back_to_back_mm = 1360
wheel_profile = { left = "s1002", right = "s1020" }
colour = "red"

[[force]]
name = "yaw_damper_l"
type = "bushing"
body1 = "bogy"
body2 = "ws"
point_m = [0, 1, 0.5]
stiffness_n_per_m = [1e6, 1e6, 1e6]

[[force]]
name = "stop"
type = "table"
body1 = "bogie"
body2 = "ws"
point_m = [0, 0, 0.5]
direction = "y"
deflection_mm = [0, 25, 20]
force_n = [0, 0, 100]

[[force]]
name = "stop"
type = "anti_roll_bar"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.5]
rotational_stiffness_nm_per_rad = 1e5
"#;
    let p = problems(text);
    // negative mass
    expect(&p, 4, &["body 'bogie'", "mass_kg", "positive", "-5"]);
    // principal moments violate the triangle inequality
    expect(&p, 5, &["inertia_kgm2", "triangle"]);
    // duplicate name
    expect(&p, 9, &["duplicate name 'bogie'", "line 3"]);
    // products make the tensor indefinite
    expect(&p, 12, &["products_kgm2", "not positive definite"]);
    // wrong type
    expect(&p, 17, &["wheelset 'ws'", "mass_kg", "string"]);
    // zero wheel radius
    expect(&p, 20, &["nominal_radius_m", "positive", "found 0"]);
    // unknown built-in profile with suggestion
    expect(
        &p,
        22,
        &["wheel_profile.right", "s1020", "did you mean 's1002'"],
    );
    // unknown key with suggestion-free list
    expect(&p, 23, &["unknown key 'colour'", "expected one of"]);
    // unknown body with suggestion
    expect(
        &p,
        28,
        &[
            "force 'yaw_damper_l'",
            "body1",
            "unknown body 'bogy'",
            "did you mean 'bogie'?",
        ],
    );
    // decreasing table
    expect(
        &p,
        40,
        &["force 'stop'", "deflection_mm", "strictly increasing"],
    );
    // duplicate force name
    expect(&p, 44, &["duplicate name 'stop'"]);
    assert!(p.len() >= 11, "{}", p.join("\n"));
    // sorted by position
    let lines: Vec<usize> = p
        .iter()
        .map(|s| s.split(':').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "{lines:?}");
}

#[test]
fn unknown_keys_all_reported_with_suggestions() {
    let text = format!("{}\nmas_kg = 3\nradius_m = 1\n", WS.trim_end());
    let p = problems(&text);
    expect(&p, 10, &["unknown key 'mas_kg'", "did you mean 'mass_kg'"]);
    expect(&p, 11, &["unknown key 'radius_m'"]);
    let p = problems(&format!("masss = 1\n{WS}"));
    expect(&p, 1, &["vehicle: unknown key 'masss'"]);
}

#[test]
fn several_wrong_types_in_one_table_are_all_reported() {
    let text = WS
        .replace("mass_kg = 1813", "mass_kg = \"a\"")
        .replace("back_to_back_mm = 1360", "back_to_back_mm = [1360]");
    let p = problems(&text);
    expect(&p, 4, &["mass_kg", "string"]);
    expect(&p, 8, &["back_to_back_mm"]);
    // dropped keys are not reported again as missing
    assert!(
        !p.iter().any(|s| s.contains("missing key 'mass_kg'")),
        "{p:?}"
    );
}

#[test]
fn missing_keys_and_wheelsets_are_reported() {
    let p = problems("[[body]]\nname = \"b\"\n");
    expect(&p, 1, &["body 'b'", "missing key 'mass_kg'"]);
    expect(&p, 1, &["missing key 'inertia_kgm2'"]);
    expect(&p, 1, &["at least one [[wheelset]]"]);
}

#[test]
fn force_element_checks() {
    let text = format!(
        r#"{WS}
[[force]]
name = "far"
type = "series_spring_damper"
body1 = "track"
body2 = "ws"
point_m = [5, 0, 0.5]
direction = "w"
stiffness_n_per_m = -1
damping_ns_per_m = [1, 2, 3]
deflection_mm = [0, 1]

[[force]]
name = "self"
type = "bushin"
body1 = "ws"
body2 = "ws"
point_m = [0, 0, 0.5]
"#
    );
    let p = problems(&text);
    expect(
        &p,
        16,
        &["force 'far'", "point_m", "from the centre of gravity"],
    );
    expect(&p, 17, &["direction 'w'"]);
    expect(&p, 18, &["stiffness_n_per_m", "positive", "-1"]);
    expect(&p, 19, &["damping_ns_per_m", "one number"]);
    expect(
        &p,
        20,
        &[
            "deflection_mm",
            "does not apply to type 'series_spring_damper'",
        ],
    );
    expect(&p, 24, &["unknown type 'bushin'", "did you mean 'bushing'"]);
    expect(&p, 26, &["body1 and body2 are the same"]);
}

#[test]
fn syntax_error_is_located() {
    let p = problems("name = \"x\"\n[[body]\n");
    assert!(p[0].starts_with("vehicles/x.toml:2:"), "{p:?}");
}

#[test]
fn missing_file_is_an_io_error() {
    let e = VehicleModel::from_file(Path::new("no/such/vehicle.toml")).unwrap_err();
    assert!(matches!(e, VehicleError::Io { .. }));
}

#[test]
fn the_format_documentation_example_compiles() {
    let doc = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/formats/vehicle.md"),
    )
    .unwrap();
    let start = doc.find("```toml\n").expect("example block") + "```toml\n".len();
    let end = start + doc[start..].find("```").unwrap();
    let v = VehicleModel::from_toml_str(&doc[start..end], "format-doc", &vehicles_dir())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.internal_states().len(), 1);
    assert_eq!(v.dofs().len(), 5 + 6);
    assert!(matches!(
        v.wheelsets()[0].profiles[1],
        WheelProfile::File(ref p) if p.ends_with("profiles/MBench_S1002_v3.prw")
    ));
    v.static_equilibrium().unwrap();
}

#[test]
fn implausible_masses_and_inertias_are_located() {
    // (found by random edits of the Manchester vehicle: a 1e30 kg bogie compiled and failed only
    // in the wheel-load search of the initial state)
    let text = r#"name = "absurd"
[[body]]
name = "bogie"
mass_kg = 1e30
inertia_kgm2 = [1722, 1476, 3067]
position_m = [0, 0, 0.6]

[[body]]
name = "frame"
mass_kg = 1e-30
inertia_kgm2 = [1e30, 1e30, 1e30]
position_m = [0, 0, 0.6]
"#;
    let p = problems(text);
    expect(
        &p,
        4,
        &[
            "body 'bogie'",
            "mass_kg = 1e30 kg",
            "implausible",
            "1 to 1e6 kg",
        ],
    );
    expect(&p, 10, &["body 'frame'", "mass_kg", "implausible"]);
    expect(
        &p,
        11,
        &[
            "body 'frame'",
            "inertia_kgm2",
            "implausible",
            "at most 1e8 kg·m²",
        ],
    );
}

/// The friction and damper elements: compiled with their states, the normal element resolved.
#[test]
fn friction_and_damper_elements_compile_with_their_states() {
    let text = format!(
        r#"{WS}
[[force]]
name = "spring"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
stiffness_n_per_m = [0, 1e6, 0]

[[force]]
name = "rub"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_force_n = 100
friction_coefficient = 0.1
normal_element = "spring"
normal_direction = "y"

[[force]]
name = "blow_off"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
velocity_m_per_s = [0.1, 0.5]
force_n = [10e3, 14e3]
symmetric = true
stiffness_n_per_m = 6e6

[[force]]
name = "plain"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
velocity_m_per_s = [-1, 1]
force_n = [-5e3, 5e3]
"#
    );
    let v = compile(&text).unwrap_or_else(|e| panic!("{e}"));
    let states = v.internal_states();
    assert_eq!(
        states.len(),
        2,
        "friction and the damper with a series stiffness"
    );
    assert_eq!(states[0].kind, InternalStateKind::FrictionSlip);
    assert_eq!(states[1].kind, InternalStateKind::DamperElongation);
    let ForceLaw::Friction {
        stiffness,
        force,
        coefficient,
        normal,
        ..
    } = v.forces()[1].law
    else {
        panic!("{:?}", v.forces()[1].law);
    };
    assert_eq!((stiffness, force, coefficient), (5e6, 100.0, 0.1));
    let normal = normal.unwrap();
    assert_eq!(Some(normal.element), v.force_id("spring"));
    assert_eq!(
        normal.rule,
        NormalRule::Along {
            axis: Axis::Y,
            sign: Sign::Plus
        }
    );
    // the spring presses while its force on body2 points along +y, and not at all the other way
    assert_eq!(normal.load([5.0, 300.0, -7.0]), 300.0);
    assert_eq!(normal.load([5.0, -300.0, -7.0]), 0.0);
    let ForceLaw::Damper {
        ref table,
        stiffness,
        ..
    } = v.forces()[2].law
    else {
        panic!();
    };
    assert_eq!(stiffness, Some(6e6));
    // the mirrored table through the origin
    assert_eq!(table.velocity, [0.0, 0.1, 0.5]);
    assert!((table.force(-0.3) + 12e3).abs() < 1e-9);
    assert_eq!(v.forces()[3].law.internal_states(), 0);
    // dissipative elements carry no static load
    v.static_equilibrium().unwrap();
}

#[test]
fn bad_friction_and_damper_elements_are_located() {
    let text = format!(
        r#"{WS}
[[force]]
name = "rub"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = -0.1
normal_element = "sprung"

[[force]]
name = "spring"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
stiffness_n_per_m = [0, 1e6, 0]

[[force]]
name = "rub2"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = 0.1
normal_element = "rub3"

[[force]]
name = "rub3"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
velocity_m_per_s = [0, 1]

[[force]]
name = "d1"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
velocity_m_per_s = [-1, 0, 1]
force_n = [-5e3, 5e3, 4e3]

[[force]]
name = "d2"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
velocity_m_per_s = [-1, 1]
force_n = [-4e3, 6e3]
friction_force_n = 10
"#
    );
    let p = problems(&text);
    // line numbers in the text above (WS takes lines 1-10)
    expect(
        &p,
        19,
        &[
            "force 'rub'",
            "friction_coefficient",
            "non-negative number, found -0.1",
        ],
    );
    expect(
        &p,
        20,
        &[
            "normal_element refers to unknown force element 'sprung'",
            "did you mean 'spring'",
        ],
    );
    expect(&p, 39, &["force 'rub2'", "'rub3' is a friction element"]);
    expect(&p, 41, &["force 'rub3'", "needs friction_force_n"]);
    expect(
        &p,
        49,
        &["velocity_m_per_s", "does not apply to type 'friction'"],
    );
    expect(
        &p,
        59,
        &[
            "force 'd1'",
            "force_n must be strictly increasing",
            "4000 follows 5000",
        ],
    );
    expect(
        &p,
        69,
        &["force 'd2'", "gives 1000 N at zero velocity", "expected 0"],
    );
    expect(
        &p,
        70,
        &["friction_force_n", "does not apply to type 'damper'"],
    );
}

/// A friction element's normal load needs the direction in which its normal element presses:
/// missing, not an axis, another axis than a one-axis element's own, an anti-roll bar (no
/// force) and a direction without a normal element are located.
#[test]
fn the_normal_direction_of_a_friction_element_is_checked() {
    let text = format!(
        r#"{WS}
[[force]]
name = "spring"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
stiffness_n_per_m = [0, 1e6, 1e6]

[[force]]
name = "rub1"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = 0.1
normal_element = "spring"

[[force]]
name = "rub2"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = 0.1
normal_element = "spring"
normal_direction = "up"

[[force]]
name = "table"
type = "table"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "z"
deflection_mm = [-10, 10]
force_n = [-1e4, 1e4]

[[force]]
name = "rub3"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = 0.1
normal_element = "table"
normal_direction = "-y"

[[force]]
name = "bar"
type = "anti_roll_bar"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
rotational_stiffness_nm_per_rad = 1e6

[[force]]
name = "rub4"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_coefficient = 0.1
normal_element = "bar"
normal_direction = "z"

[[force]]
name = "rub5"
type = "friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "y"
stiffness_n_per_m = 5e6
friction_force_n = 100
normal_direction = "z"
"#
    );
    let p = problems(&text);
    expect(
        &p,
        28,
        &[
            "force 'rub1'",
            "missing key 'normal_direction'",
            "\"-z\"",
            "\"any\"",
        ],
    );
    expect(
        &p,
        40,
        &[
            "force 'rub2'",
            "normal_direction 'up' is not a signed local axis",
        ],
    );
    expect(
        &p,
        62,
        &["force 'rub3'", "'table' acts along its local z only"],
    );
    expect(&p, 81, &["force 'rub4'", "'bar' is an anti-roll bar"]);
    expect(
        &p,
        93,
        &["force 'rub5'", "normal_direction needs normal_element"],
    );
    assert_eq!(p.len(), 5, "{p:#?}");
}

#[test]
fn rotational_friction_compiles_and_its_keys_are_checked() {
    let good = format!(
        r#"{WS}
[[force]]
name = "spring"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
stiffness_n_per_m = [0, 0, 1e6]

[[force]]
name = "pivot"
type = "rotational_friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
about = "z"
rotational_stiffness_nm_per_rad = 2e7
friction_moment_nm = 500
friction_coefficient = 0.1
normal_element = "spring"
normal_direction = "any"
friction_radius_m = 0.8
"#
    );
    let v = compile(&good).unwrap_or_else(|e| panic!("{e}"));
    let f = &v.forces()[1];
    assert_eq!(f.law.type_name(), "rotational_friction");
    let ForceLaw::Friction {
        rotational,
        stiffness,
        force,
        coefficient,
        normal,
        ..
    } = f.law
    else {
        panic!("{:?}", f.law);
    };
    assert!(rotational);
    assert_eq!((stiffness, force), (2e7, 500.0));
    assert!((coefficient - 0.08).abs() < 1e-15, "μ times the radius");
    let normal = normal.unwrap();
    assert_eq!(Some(normal.element), v.force_id("spring"));
    assert_eq!(normal.rule, NormalRule::Magnitude);
    assert_eq!(normal.load([3.0, 0.0, -4.0]), 5.0);
    assert_eq!(v.internal_states()[0].kind, InternalStateKind::FrictionSlip);
    let bad = format!(
        r#"{WS}
[[force]]
name = "pivot"
type = "rotational_friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "z"
rotational_stiffness_nm_per_rad = [1, 2, 3]
friction_force_n = 5
friction_coefficient = 0.1
normal_element = "pivot"
"#
    );
    let p = problems(&bad);
    expect(&p, 11, &["force 'pivot'", "missing key 'about'"]);
    expect(
        &p,
        11,
        &["missing key 'friction_radius_m'", "× normal force × radius"],
    );
    expect(
        &p,
        17,
        &["direction", "does not apply to type 'rotational_friction'"],
    );
    expect(&p, 18, &["rotational_stiffness_nm_per_rad", "one number"]);
    expect(&p, 19, &["friction_force_n", "does not apply"]);
    expect(&p, 21, &["normal_element names the element itself"]);
}

#[test]
fn planar_friction_compiles_with_two_states_and_its_plane_is_checked() {
    let text = |plane: &str| {
        format!(
            r#"{WS}
[[force]]
name = "plate"
type = "planar_friction"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
plane = "{plane}"
stiffness_n_per_m = 5e6
friction_force_n = 2000
"#
        )
    };
    let v = compile(&text("yx")).unwrap_or_else(|e| panic!("{e}"));
    let law = &v.forces()[0].law;
    assert_eq!(law.type_name(), "planar_friction");
    assert_eq!(law.internal_states(), 2);
    assert!(matches!(
        law,
        ForceLaw::PlanarFriction { axes: [railsim_vehicle::Axis::Y, railsim_vehicle::Axis::X], force, .. } if *force == 2000.0
    ));
    let states = v.internal_states();
    assert_eq!(states.len(), 2);
    assert!(
        states
            .iter()
            .all(|s| s.kind == InternalStateKind::FrictionSlip)
    );
    for bad in ["xx", "x", "xyz", "ab"] {
        let p = problems(&text(bad));
        expect(
            &p,
            17,
            &[
                "force 'plate'",
                &format!("plane '{bad}'"),
                "two different local axes",
            ],
        );
    }
    let p = problems(&text("xy").replace("stiffness_n_per_m = 5e6", "direction = \"x\""));
    expect(
        &p,
        18,
        &["direction", "does not apply to type 'planar_friction'"],
    );
    expect(&p, 11, &["missing key 'stiffness_n_per_m'"]);
}

#[test]
fn a_torque_reaction_names_a_body() {
    let head = r#"name = "driven"
[[body]]
name = "frame"
mass_kg = 2000
inertia_kgm2 = [1000, 1000, 2000]
position_m = [0, 0, 0.6]
"#;
    let ws =
        |reaction: &str| format!("{head}{WS}torque_nm = 3000\ntorque_reaction = \"{reaction}\"\n");
    let v = compile(&ws("frame")).unwrap_or_else(|e| panic!("{e}"));
    let w = &v.wheelsets()[0];
    assert_eq!(w.torque, 3000.0);
    assert_eq!(w.torque_reaction, v.body_id("frame"));
    assert!(w.torque_reaction.is_some());
    // the reaction key is on line 17 (the body ends on line 6; the wheelset, after a blank
    // line, on 8 to 17)
    for (name, needle) in [("ws", "must name a body"), ("fram", "did you mean 'frame'")] {
        let p = problems(&ws(name));
        expect(
            &p,
            17,
            &[
                "wheelset 'ws'",
                &format!("torque_reaction = \"{name}\""),
                needle,
            ],
        );
    }
    // without the key the reaction acts on nothing modelled
    let v = compile(&format!("{head}{WS}")).unwrap();
    assert_eq!(v.wheelsets()[0].torque_reaction, None);
}

/// The 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no line with {needle:?}"))
}

/// A body, the wheelset and a bushing between them: every `[x, y, z]` key once, each line
/// unique.
fn every_triple_key() -> String {
    format!(
        r#"name = "triples"
[[body]]
name = "frame"
mass_kg = 2000
inertia_kgm2 = [1000, 1000, 2000]
products_kgm2 = [0, 0, 0]
position_m = [0, 0, 0.6]
{WS}
[[force]]
name = "spring"
type = "bushing"
body1 = "frame"
body2 = "ws"
point_m = [0, 1, 0.5]
point2_m = [0, 1, 0.46]
orientation_deg = [0, 0, 0]
stiffness_n_per_m = [1e6, 1e6, 1e6]
"#
    )
}

/// (found by fuzzing: `inertia_kgm2 = [56800, 1970000, 1970000, 1]` compiled, the fourth
/// number silently dropped) Every `[x, y, z]` key refuses any length but 3, located at the
/// array, naming the key and the length found; so does a bushing's triple.
#[test]
fn arrays_of_three_numbers_refuse_any_other_length() {
    let good = every_triple_key();
    compile(&good).unwrap_or_else(|e| panic!("{e}"));
    let keys = [
        ("inertia_kgm2 = [1000, 1000, 2000]", "body 'frame'"),
        ("products_kgm2 = [0, 0, 0]", "body 'frame'"),
        ("position_m = [0, 0, 0.6]", "body 'frame'"),
        ("inertia_kgm2 = [1120, 112, 1120]", "wheelset 'ws'"),
        ("position_m = [0, 0, 0.46]", "wheelset 'ws'"),
        ("point_m = [0, 1, 0.5]", "force 'spring'"),
        ("point2_m = [0, 1, 0.46]", "force 'spring'"),
        ("orientation_deg = [0, 0, 0]", "force 'spring'"),
        ("stiffness_n_per_m = [1e6, 1e6, 1e6]", "force 'spring'"),
    ];
    for (line, label) in keys {
        let key = line.split(' ').next().unwrap();
        let n = line_of(&good, line);
        for (array, found) in [
            ("[1, 2, 3, 4]", "found an array of 4 numbers"),
            ("[1, 2]", "found an array of 2 numbers"),
            ("[]", "found an array of 0 numbers"),
        ] {
            let text = good.replace(line, &format!("{key} = {array}"));
            let p = problems(&text);
            expect(&p, n, &[label, key, "an array of 3 numbers", found]);
            // reported once, as a wrong value, not again as a missing key
            assert!(
                !p.iter()
                    .any(|s| s.contains(&format!("missing key '{key}'"))),
                "{p:?}"
            );
        }
    }
    // a bushing's key that takes one number or three names both
    let text = good.replace(
        "stiffness_n_per_m = [1e6, 1e6, 1e6]",
        "stiffness_n_per_m = \"stiff\"",
    );
    let p = problems(&text);
    expect(
        &p,
        line_of(&good, "stiffness_n_per_m"),
        &[
            "stiffness_n_per_m",
            "expected a number or an array of 3 numbers",
        ],
    );
}

/// A vehicle of the wheelset and one `[[force]]` to the track made of `keys`.
fn with_force(keys: &str) -> String {
    format!(
        "{WS}\n[[force]]\nname = \"e\"\nbody1 = \"track\"\nbody2 = \"ws\"\npoint_m = [0, 0, 0.46]\n{keys}\n"
    )
}

/// (found by fuzzing: a series spring-damper of 1e15 N/m and 1e-9 N·s/m hung a run at t = 0,
/// 1e-300 N·s/m gave NaN) The relaxation time c/k of a damper in series with a spring is at
/// least 1e-5 s, for a series spring-damper and for a damper table on a mount stiffness.
#[test]
fn series_dampers_relax_no_faster_than_the_bound() {
    let series = |k: &str, c: &str| {
        with_force(&format!(
            "type = \"series_spring_damper\"\ndirection = \"x\"\nstiffness_n_per_m = {k}\ndamping_ns_per_m = {c}"
        ))
    };
    let text = series("1e7", "1");
    let p = problems(&text);
    expect(
        &p,
        line_of(&text, "damping_ns_per_m"),
        &[
            "force 'e'",
            "relaxation time damping_ns_per_m / stiffness_n_per_m = 1 N·s/m / 1e7 N/m = 1e-7 s",
            "below 1e-5 s",
            "at least 100 N·s/m",
            "model the damper alone",
        ],
    );
    let text = series("6e6", "1e-300");
    expect(
        &problems(&text),
        line_of(&text, "damping_ns_per_m"),
        &["relaxation time", "below 1e-5 s"],
    );
    // the fuzzed case: the stiffness is refused first
    let text = series("1e15", "1e-9");
    expect(
        &problems(&text),
        line_of(&text, "stiffness_n_per_m"),
        &[
            "stiffness_n_per_m 1e15 N/m is implausible",
            "at most 1e10 N/m",
        ],
    );
    // at the bound it compiles
    let v = compile(&series("1e7", "100")).unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(
        v.forces()[0].law,
        ForceLaw::SeriesSpringDamper { damping, .. } if damping == 100.0
    ));

    // a damper table of 100 N·s/m on a 2e7 N/m mount: τ = 5 µs
    let damper = |k: &str| {
        with_force(&format!(
            "type = \"damper\"\ndirection = \"x\"\nvelocity_m_per_s = [-1, 0, 0.5, 1]\nforce_n = [-50e3, 0, 50, 60e3]\nstiffness_n_per_m = {k}"
        ))
    };
    let text = damper("2e7");
    expect(
        &problems(&text),
        line_of(&text, "stiffness_n_per_m"),
        &[
            "force 'e'",
            "relaxation time",
            "= 100 N·s/m / 2e7 N/m = 5e-6 s (between 0 and 0.5 m/s)",
            "drop stiffness_n_per_m",
            "at most 1e7 N/m",
        ],
    );
    let v = compile(&damper("1e7")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.internal_states().len(), 1);
    // without the mount the same table has no state and no bound on its slope's time scale
    let v = compile(&damper("1e7").replace("stiffness_n_per_m = 1e7", ""))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(v.internal_states().is_empty());
}

/// (found by fuzzing: a damper table of ±1e300 N at ±1e-300 m/s gave NaN at t = 0) Table values
/// and slopes are bounded: forces within ±1e8 N, velocities within ±100 m/s, deflections within
/// ±1000 mm, damper slopes at most 1e9 N·s/m and force-table slopes at most 1e10 N/m.
#[test]
fn absurd_table_values_and_slopes_are_located() {
    let damper = |v: &str, f: &str| {
        with_force(&format!(
            "type = \"damper\"\ndirection = \"y\"\nvelocity_m_per_s = {v}\nforce_n = {f}"
        ))
    };
    let text = damper("[-1e-300, 1e-300]", "[-1e300, 1e300]");
    let p = problems(&text);
    expect(
        &p,
        line_of(&text, "force_n"),
        &[
            "force 'e'",
            "force_n value -1e300 N is implausible",
            "within ±1e8 N",
        ],
    );
    let text = damper("[-1e-12, 1e-12]", "[-1e3, 1e3]");
    expect(
        &problems(&text),
        line_of(&text, "force_n"),
        &[
            "force_n: the slope between -1e-12 and 1e-12 m/s (velocity_m_per_s) is 1e15 N·s/m",
            "at most 1e9 N·s/m",
        ],
    );
    let text = damper("[-1000, 1000]", "[-1e3, 1e3]");
    expect(
        &problems(&text),
        line_of(&text, "velocity_m_per_s"),
        &[
            "velocity_m_per_s value -1000 m/s is implausible",
            "±100 m/s",
        ],
    );
    // a steep but plausible table compiles
    compile(&damper("[-0.001, 0.001]", "[-1e5, 1e5]")).unwrap_or_else(|e| panic!("{e}"));

    let stop = |d: &str, f: &str| {
        with_force(&format!(
            "type = \"table\"\ndirection = \"y\"\nsymmetric = true\ndeflection_mm = {d}\nforce_n = {f}"
        ))
    };
    let text = stop("[0, 1e-300]", "[0, 1e300]");
    expect(
        &problems(&text),
        line_of(&text, "force_n"),
        &["force_n value 1e300 N is implausible"],
    );
    let text = stop("[0, 1e-300]", "[0, 1000]");
    expect(
        &problems(&text),
        line_of(&text, "force_n"),
        &[
            "force_n: the slope between 0 and 1e-300 mm (deflection_mm) is 1e306 N/m",
            "implausibly steep",
            "at most 1e10 N/m",
        ],
    );
    // the mirrored table's added origin (0, 0) is checked too: 1e5 N over 1 µm is 1e11 N/m
    let text = stop("[1e-3, 2]", "[1e5, 2e5]");
    expect(
        &problems(&text),
        line_of(&text, "force_n"),
        &["force_n: the slope between 0 and 0.001 mm", "1e11 N/m"],
    );
    let text = stop("[0, 2000]", "[0, 1e3]");
    expect(
        &problems(&text),
        line_of(&text, "deflection_mm"),
        &["deflection_mm value 2000 mm is implausible", "±1000 mm"],
    );
}

/// (found by fuzzing: 1e20 N/m primary springs were reported as "body 'bogie_front' has no
/// support in roll" by the static solve) Stiffness and damping above their plausible bounds are
/// refused at the key; the shipped vehicle still compiles and stands with every primary
/// stiffness at the bound.
#[test]
fn implausible_stiffness_and_damping_are_located() {
    let manchester =
        std::fs::read_to_string(vehicles_dir().join("manchester_vehicle1.toml")).unwrap();
    let primary = "stiffness_n_per_m = [31.391e6, 3.884e6, 1.22e6]";
    let text = manchester.replacen(primary, "stiffness_n_per_m = [1e20, 1e20, 1e20]", 1);
    let p = problems(&text);
    expect(
        &p,
        line_of(&manchester, primary),
        &[
            "force 'primary_",
            "stiffness_n_per_m [1e20, 1e20, 1e20]: 1e20 N/m is implausible",
            "at most 1e10 N/m",
            "freeze it",
        ],
    );
    let text = manchester.replace(primary, "stiffness_n_per_m = [1e10, 1e10, 1e10]");
    let v = compile(&text).unwrap_or_else(|e| panic!("{e}"));
    let eq = v.static_equilibrium().unwrap_or_else(|e| panic!("{e}"));
    let weight = v.total_mass() * v.gravity();
    assert!((eq.total_wheel_load() - weight).abs() < 1e-6 * weight);

    for (keys, key, needle) in [
        (
            "type = \"bushing\"\ndamping_ns_per_m = [0, 2e9, 0]",
            "damping_ns_per_m",
            "2e9 N·s/m is implausible (expected at most 1e9 N·s/m",
        ),
        (
            "type = \"bushing\"\nrotational_stiffness_nm_per_rad = [0, 0, 1e11]",
            "rotational_stiffness_nm_per_rad",
            "1e11 N·m/rad is implausible (expected at most 1e10 N·m/rad",
        ),
        (
            "type = \"bushing\"\nrotational_damping_nms_per_rad = [5e9, 0, 0]",
            "rotational_damping_nms_per_rad",
            "5e9 N·m·s/rad is implausible (expected at most 1e9 N·m·s/rad",
        ),
        (
            "type = \"anti_roll_bar\"\nrotational_stiffness_nm_per_rad = 1e12",
            "rotational_stiffness_nm_per_rad",
            "1e12 N·m/rad is implausible",
        ),
        (
            "type = \"friction\"\ndirection = \"y\"\nstiffness_n_per_m = 2e10\nfriction_force_n = 100",
            "stiffness_n_per_m",
            "2e10 N/m is implausible",
        ),
        (
            "type = \"planar_friction\"\nplane = \"xy\"\nstiffness_n_per_m = 2e10\nfriction_force_n = 100",
            "stiffness_n_per_m",
            "2e10 N/m is implausible",
        ),
        (
            "type = \"rotational_friction\"\nabout = \"z\"\nrotational_stiffness_nm_per_rad = 2e10\nfriction_moment_nm = 100",
            "rotational_stiffness_nm_per_rad",
            "2e10 N·m/rad is implausible",
        ),
        (
            "type = \"damper\"\ndirection = \"y\"\nvelocity_m_per_s = [-1, 1]\nforce_n = [-1e3, 1e3]\nstiffness_n_per_m = 2e10",
            "stiffness_n_per_m",
            "2e10 N/m is implausible",
        ),
        (
            "type = \"series_spring_damper\"\ndirection = \"y\"\nstiffness_n_per_m = 1e6\ndamping_ns_per_m = 2e9",
            "damping_ns_per_m",
            "2e9 N·s/m is implausible",
        ),
    ] {
        let text = with_force(keys);
        expect(
            &problems(&text),
            line_of(&text, key),
            &["force 'e'", key, needle],
        );
    }
}

#[test]
fn two_wheelsets_in_one_place_are_refused() {
    // a copied [[wheelset]] table whose name was changed but not its position
    let second = WS.replace("name = \"ws\"", "name = \"ws_copy\"");
    let p = problems(&format!("name = \"two\"\n{WS}{second}"));
    expect(
        &p,
        16,
        &[
            "wheelset 'ws_copy': position_m x = 0 m is 0 m from wheelset 'ws'",
            "at least their wheels' radii apart (0.92 m)",
        ],
    );
    // a bogie's wheelbase is fine
    let apart = second.replace("position_m = [0, 0, 0.46]", "position_m = [2.5, 0, 0.46]");
    assert!(compile(&format!("name = \"two\"\n{WS}{apart}")).is_ok());
}

/// Values a robustness sweep found accepted although no vehicle has them: a symmetric table
/// with a force at zero deflection (mirrored, a step through zero), moments of inertia in the
/// wrong unit (the run could not advance), an axle torque of 1e12 N·m; and an implausible
/// attachment point was reported twice.
#[test]
fn implausible_tables_inertias_and_torques_are_located() {
    let text = r#"
[[wheelset]]
name = "ws"
mass_kg = 1813
inertia_kgm2 = [1e-6, 112, 1120]
position_m = [0, 0, 0.46]
nominal_radius_m = 0.46
back_to_back_mm = 1360
wheel_profile = { left = "s1002", right = "s1002" }
torque_nm = 1e12

[[force]]
name = "stop"
type = "table"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.5]
direction = "y"
symmetric = true
deflection_mm = [0, 25, 30]
force_n = [1e5, 1e5, 2e5]

[[force]]
name = "wide"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 3, 0.5]
stiffness_n_per_m = [1e6, 1e6, 1e6]
"#;
    let p = problems(text);
    // an implausible point_m is reported once, though it is both bodies' attachment point
    let wide: Vec<&String> = p.iter().filter(|m| m.contains("force 'wide'")).collect();
    assert!(
        wide.len() == 1 && wide[0].contains("point_m [0.0, 3.0, 0.5] is implausible"),
        "{wide:#?}"
    );
    expect(
        &p,
        5,
        &[
            "inertia_kgm2",
            "1e-6 kg·m² is implausible",
            "at least 0.001",
        ],
    );
    expect(&p, 10, &["torque_nm = 1e12 is implausible", "±1e6 N·m"]);
    expect(
        &p,
        21,
        &[
            "symmetric table",
            "force_n at deflection_mm = 0 must be 0",
            "found 100000",
        ],
    );
}

/// A table gives the force beyond the static preload, from the vehicle file's loaded geometry:
/// a one-sided table with a force at zero deflection (interpolated, or extrapolated from its
/// first interval) is located on `force_n`; one through 0 N at 0 mm compiles. The static solve
/// used only the table's slope there, so the vehicle started out of equilibrium.
#[test]
fn a_one_sided_table_with_a_force_at_zero_is_located() {
    let base = r#"
[[wheelset]]
name = "ws"
mass_kg = 1813
inertia_kgm2 = [1120, 112, 1120]
position_m = [0, 0, 0.46]
nominal_radius_m = 0.46
back_to_back_mm = 1360
wheel_profile = { left = "s1002", right = "s1002" }

[[force]]
name = "stop"
type = "table"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.5]
direction = "y"
"#;
    let p = problems(&format!(
        "{base}deflection_mm = [-10, 10]\nforce_n = [-500, 1500]\n"
    ));
    expect(
        &p,
        19,
        &["force at deflection_mm = 0", "is 500 N, expected 0"],
    );
    let p = problems(&format!(
        "{base}deflection_mm = [10, 20]\nforce_n = [0, 5000]\n"
    ));
    expect(&p, 19, &["is -5000 N (extrapolated from its end)"]);
    compile(&format!(
        "{base}deflection_mm = [-10, 0, 10, 20]\nforce_n = [-500, 0, 0, 5000]\n"
    ))
    .unwrap_or_else(|e| panic!("{e}"));
}

/// The Manchester vehicle with one body's centre of gravity moved along x from `x0` by `dx`
/// (its `position_m` line edited in a copy of the file; the force elements stay where they
/// are), and its static equilibrium.
fn manchester_with_cg_moved(
    body: &str,
    x0: f64,
    dx: f64,
) -> (VehicleModel, railsim_vehicle::StaticEquilibrium) {
    let text = std::fs::read_to_string(vehicles_dir().join("manchester_vehicle1.toml")).unwrap();
    let start = text.find(&format!("name = \"{body}\"")).unwrap();
    let key = "position_m = [";
    let line_start = start + text[start..].find(key).unwrap();
    let comma = line_start + text[line_start..].find(',').unwrap();
    let x_old: f64 = text[line_start + key.len()..comma].trim().parse().unwrap();
    assert_eq!(x_old, x0, "{body}");
    let moved = format!("{}{key}{}{}", &text[..line_start], x0 + dx, &text[comma..]);
    let v = VehicleModel::from_toml_str(&moved, "vehicles/moved.toml", &vehicles_dir())
        .unwrap_or_else(|e| panic!("{e}"));
    let b = v.body(v.body_id(body).unwrap());
    assert_eq!(
        b.position,
        [x0 + dx, 0.0, if body == "carbody" { 1.8 } else { 0.6 }]
    );
    let eq = v.static_equilibrium().unwrap();
    let weight = v.total_mass() * v.gravity();
    let rel = (eq.total_wheel_load() - weight).abs() / weight;
    assert!(
        rel < 1e-9,
        "wheels carry {} of {weight} N",
        eq.total_wheel_load()
    );
    (v, eq)
}

/// The stiffness of a bushing and its attachment point.
fn bushing(v: &VehicleModel, name: &str) -> ([f64; 6], [f64; 3]) {
    let f = v.force(v.force_id(name).unwrap());
    match f.law {
        ForceLaw::Bushing { stiffness, .. } => (stiffness, f.point2),
        _ => panic!("{name} is not a bushing"),
    }
}

/// Sum of a wheelset's two static wheel loads.
fn axle_load(v: &VehicleModel, eq: &railsim_vehicle::StaticEquilibrium, ws: &str) -> f64 {
    let q = eq.wheel_loads[v.wheelset_id(ws).unwrap().index()];
    q[0] + q[1]
}

/// The carbody's centre of gravity 1 m toward the front bogie: the bogies' loads follow the
/// lever rule of the rigid carbody on two supports 2a = 19 m apart (pitch-moment balance about
/// the centre of gravity): `Q_front − Q_rear = m_c·g·2·dx / 2a`, the total the vehicle's
/// weight. The linear static solve is statically indeterminate: the secondary springs' bending
/// stiffness `k_b` about y (4 × 10.5 kN·m/rad) carries part of the pitch moment `m_c·g·dx`
/// as a moment, in parallel with the vertical springs' pitch stiffness
/// `k_p = 2·a²·k_v` (`k_v` the secondary's two springs in series with the four axleboxes per
/// bogie; the carbody's longitudinal forces all act at the secondary height and sum to zero,
/// so they add no moment): the difference falls short of the lever rule by `k_b/(k_p + k_b)`
/// = 0.032 %. Tolerance 0.1 %. The front secondary springs carry the front bogie's load less
/// its bogie frame and wheelsets (vertical equilibrium of the bogie, to rounding).
#[test]
fn an_off_centre_carbody_loads_its_bogies_by_the_lever_rule() {
    let dx = 1.0;
    let (v, eq) = manchester_with_cg_moved("carbody", 0.0, dx);
    let (front, rear) = (
        axle_load(&v, &eq, "ws1") + axle_load(&v, &eq, "ws2"),
        axle_load(&v, &eq, "ws3") + axle_load(&v, &eq, "ws4"),
    );
    let g = v.gravity();
    let m_c = v.body(v.body_id("carbody").unwrap()).mass;
    let (k2, p2) = bushing(&v, "secondary_bogie_front_l");
    let (k1, _) = bushing(&v, "primary_ws1_l");
    let a = p2[0];
    let lever = m_c * g * 2.0 * dx / (2.0 * a);
    let k_v = 1.0 / (1.0 / (2.0 * k2[2]) + 1.0 / (4.0 * k1[2]));
    let (k_p, k_b) = (2.0 * a * a * k_v, 4.0 * k2[4]);
    let rel = (front - rear) / lever - 1.0;
    eprintln!(
        "bogie loads {front:.1} / {rear:.1} N: difference {:.2} N, lever rule {lever:.2} N \
         ({:+.4} %; the bending stiffness's share -{:.4} %)",
        front - rear,
        rel * 100.0,
        k_b / (k_p + k_b) * 100.0
    );
    assert!(rel.abs() < 1e-3, "{rel}");
    assert!(lever > 3e4, "{lever}");
    // the front secondary springs' vertical forces on the carbody
    let secondary: f64 = ["secondary_bogie_front_l", "secondary_bogie_front_r"]
        .iter()
        .map(|n| eq.element_force[v.force_id(n).unwrap().index()][2])
        .sum();
    let m_b = v.body(v.body_id("bogie_front").unwrap()).mass;
    let m_w = v.wheelset(v.wheelset_id("ws1").unwrap()).mass;
    let below = (m_b + 2.0 * m_w) * g;
    assert!(
        (secondary + below - front).abs() < 1e-9 * front,
        "secondary {secondary} N + {below} N vs {front} N"
    );
}

/// The front bogie frame's centre of gravity 0.3 m toward its leading wheelset: its wheelsets'
/// loads follow the lever rule of the frame on two axles 2l = 2.56 m apart,
/// `Q_ws1 − Q_ws2 = m_b·g·2·dx / 2l`, and the carbody's share of each bogie stays equal. Here
/// the secondary suspension carries a part of the frame's pitch moment that the solve must
/// give it: the bending stiffness (2 × 10.5 kN·m/rad) and the secondary's longitudinal
/// stiffness at h = 0.3675 m above the axleboxes (which hold the frame at axle height; the
/// carbody, held equally by the rear bogie, takes half the deflection: 2·kx/2·h²), in parallel
/// with the axleboxes' pitch stiffness `4·kz·l²`, so the difference is the lever rule less
/// that share, 0.53 %. Tolerance: 0.05 % of the lever rule about the corrected value (the
/// neglected couplings: the axleboxes' finite longitudinal stiffness, 0.25 % of the 0.27 %
/// longitudinal share; the carbody's pitch, 10⁻⁴ of the bending share). The bogies' totals
/// differ only by the bending moment passed to the carbody, 2 N.
#[test]
fn an_off_centre_bogie_frame_loads_its_wheelsets_by_the_lever_rule() {
    let dx = 0.3;
    let (v, eq) = manchester_with_cg_moved("bogie_front", 9.5, dx);
    let g = v.gravity();
    let m_b = v.body(v.body_id("bogie_front").unwrap()).mass;
    let (k1, p1) = bushing(&v, "primary_ws1_l");
    let (k2, p2) = bushing(&v, "secondary_bogie_front_l");
    let l = p1[0] - p2[0];
    let h = p2[2] - p1[2];
    let lever = m_b * g * 2.0 * dx / (2.0 * l);
    let k_p = 4.0 * k1[2] * l * l;
    let k_s = 2.0 * k2[4] + k2[0] * h * h;
    let share = k_s / (k_p + k_s);
    let diff = axle_load(&v, &eq, "ws1") - axle_load(&v, &eq, "ws2");
    let rel = diff / lever - 1.0;
    eprintln!(
        "front wheelsets' difference {diff:.2} N, lever rule {lever:.2} N ({:+.4} %; the \
         secondary's share -{:.4} %)",
        rel * 100.0,
        share * 100.0
    );
    assert!((rel + share).abs() < 5e-4, "{rel} vs -{share}");
    assert!(share < 0.01, "{share}");
    // The carbody rests on both bogies as before but for the bending moment the front
    // secondary passes to it (its longitudinal forces act at one height on the carbody), which
    // the carbody puts on its bogies as a couple at ±a.
    let (front, rear) = (
        axle_load(&v, &eq, "ws1") + axle_load(&v, &eq, "ws2"),
        axle_load(&v, &eq, "ws3") + axle_load(&v, &eq, "ws4"),
    );
    let a = p2[0];
    let bending = 2.0 * k2[4] / (k_p + k_s) * m_b * g * dx;
    assert!(
        (front - rear - bending / a).abs() < 1e-4 * lever,
        "{front} vs {rear}: {bending} N m at {a} m"
    );
}

/// `[[wheelset.out_of_roundness]]`: harmonics and flats per side read into the wheelset (in
/// SI), and each kind of bad entry reported at its line with the entry's number.
#[test]
fn out_of_roundness_is_read_and_checked() {
    use railsim_vehicle::WheelDefect;
    let text = format!(
        "{WS}\n[[wheelset.out_of_roundness]]\ntype = \"harmonic\"\nside = \"both\"\norder = 8\n\
         amplitude_mm = 0.03\nphase_deg = 90\n\n[[wheelset.out_of_roundness]]\ntype = \"flat\"\n\
         side = \"right\"\nlength_mm = 40\ndepth_mm = 0.1\n"
    );
    let v = compile(&text).unwrap_or_else(|e| panic!("{e}"));
    let w = &v.wheelsets()[0];
    let harmonic = WheelDefect::Harmonic {
        order: 8,
        amplitude: 0.03e-3,
        phase: 90f64.to_radians(),
    };
    let flat = WheelDefect::Flat {
        length: 0.04,
        depth: 0.1e-3,
        position: 0.0,
    };
    assert_eq!(w.out_of_roundness[0], vec![harmonic]);
    assert_eq!(w.out_of_roundness[1], vec![harmonic, flat]);
    // a round wheel has none
    assert!(
        compile(WS).unwrap().wheelsets()[0]
            .out_of_roundness
            .iter()
            .all(Vec::is_empty)
    );
    // (the entry's keys start at line 12 of the text: WS's 10 lines, a blank, the header)
    for (entry, line, want) in [
        (
            "type = \"polygon\"\nside = \"left\"",
            12,
            vec![
                "out_of_roundness 1: type = \"polygon\"",
                "\"harmonic\" or \"flat\"",
            ],
        ),
        (
            "type = \"flat\"\nside = \"up\"\nlength_mm = 40\ndepth_mm = 0.1",
            13,
            vec!["side = \"up\"", "\"both\""],
        ),
        (
            "type = \"harmonic\"\nside = \"left\"\norder = 2.5\namplitude_mm = 0.1",
            11,
            vec!["order = 2.5", "whole number"],
        ),
        (
            "type = \"harmonic\"\nside = \"left\"\norder = 4\namplitude_mm = 7",
            15,
            vec!["amplitude_mm = 7", "(0, 5] mm"],
        ),
        (
            "type = \"flat\"\nside = \"left\"\nlength_mm = 40",
            11,
            vec!["missing key 'depth_mm'"],
        ),
        (
            "type = \"flat\"\nside = \"left\"\nlength_mm = 40\ndepth_mm = 0.1\norder = 3",
            11,
            vec!["order does not apply to type = \"flat\""],
        ),
        (
            "type = \"flat\"\nside = \"left\"\nlength_mm = 40\ndepth_mm = 0.1\nposition_deg = 400",
            16,
            vec!["position_deg = 400", "±360 deg"],
        ),
        ("side = \"left\"\norder = 3", 11, vec!["missing key 'type'"]),
    ] {
        let p = problems(&format!("{WS}\n[[wheelset.out_of_roundness]]\n{entry}\n"));
        expect(&p, line, &want);
    }
}

/// The radius deviation of the defects (`radius_deviation`): a harmonic's value and phase, a
/// rounded flat's depth at its centre, zero beyond its ends and continuous at them, the flat
/// found again one turn later, and the rate against a centred difference everywhere.
#[test]
fn the_radius_deviation_of_harmonics_and_flats() {
    use railsim_vehicle::{WheelDefect, radius_deviation};
    let r0 = 0.46;
    let h = [WheelDefect::Harmonic {
        order: 3,
        amplitude: 1e-4,
        phase: 0.5,
    }];
    let (dr, _) = radius_deviation(&h, 0.2, r0);
    assert!((dr - 1e-4 * (3.0 * 0.2 + 0.5f64).cos()).abs() < 1e-18);
    let f = [WheelDefect::Flat {
        length: 0.05,
        depth: 0.2e-3,
        position: 1.0,
    }];
    let half = 0.5 * 0.05 / r0;
    for turn in [0.0, std::f64::consts::TAU, -std::f64::consts::TAU] {
        assert!((radius_deviation(&f, 1.0 + turn, r0).0 + 0.2e-3).abs() < 1e-15);
        assert_eq!(
            radius_deviation(&f, 1.0 + turn + 1.01 * half, r0),
            (0.0, 0.0)
        );
        assert!(
            radius_deviation(&f, 1.0 + turn + 0.999_999 * half, r0)
                .0
                .abs()
                < 1e-14
        );
    }
    let both: Vec<WheelDefect> = h.iter().chain(&f).copied().collect();
    let e = 1e-7;
    for k in 0..2000 {
        let th = -7.0 + 14.0 * f64::from(k) / 2000.0;
        let (_, rate) = radius_deviation(&both, th, r0);
        let fd = (radius_deviation(&both, th + e, r0).0 - radius_deviation(&both, th - e, r0).0)
            / (2.0 * e);
        assert!((rate - fd).abs() < 1e-9, "theta {th}: {rate} against {fd}");
    }
}

/// The out-of-round wheel's support on a flat rail (`rim_support`): the height of the wheel
/// centre less r0 is the largest `(r0 + δr(θ + u)) cos u` over the rim, found here by brute
/// force on 200 001 points of |u| ≤ 0.1 rad (error below 6e-13 m by the bound on the second
/// derivative): within 2e-12 m on 80 rolled angles across each of six wheels, three of them
/// with concave parts of the rim (a 1 mm deep flat, a 20th-order polygon of 1.5 mm, a 1.5 mm
/// deep flat with a polygon), which the branch and bound handles, the other three by Newton's
/// method; its rate `de/dθ` within 1e-7 m/rad of a centred
/// difference wherever the support point does not jump. At the centre of the shallow flat the
/// centre's path is curved as the support function says, `e″ = R δr″/(R − δr″)` (3.7 times
/// δr″), and the round wheel has no support offset.
#[test]
fn an_out_of_round_wheel_rests_on_the_lowest_point_of_its_rim() {
    use railsim_vehicle::{WheelDefect, radius_deviation, rim_support};
    let r0 = 0.46;
    let flat = |length: f64, depth: f64| WheelDefect::Flat {
        length,
        depth,
        position: 1.0,
    };
    let poly = |order: u32, amplitude: f64| WheelDefect::Harmonic {
        order,
        amplitude,
        phase: 0.3,
    };
    let wheels: Vec<(&str, Vec<WheelDefect>)> = vec![
        ("shallow flat", vec![flat(0.05, 0.2e-3)]),
        ("deep flat", vec![flat(0.05, 1.0e-3)]),
        ("polygon 3", vec![poly(3, 0.05e-3)]),
        ("polygon 20", vec![poly(20, 1.5e-3)]),
        (
            "flat and polygon",
            vec![flat(0.08, 0.5e-3), poly(8, 0.1e-3)],
        ),
        (
            "deep flat and polygon",
            vec![flat(0.04, 1.5e-3), poly(20, 0.3e-3)],
        ),
    ];
    assert_eq!(rim_support(&[], 0.7, r0), (0.0, 0.0));
    let brute = |d: &[WheelDefect], th: f64| -> (f64, f64) {
        let n = 200_000;
        (0..=n)
            .map(|i| {
                let u = -0.1 + 0.2 * f64::from(i) / f64::from(n);
                ((r0 + radius_deviation(d, th + u, r0).0) * u.cos() - r0, u)
            })
            .fold(
                (f64::NEG_INFINITY, 0.0),
                |a, b| if b.0 > a.0 { b } else { a },
            )
    };
    for (name, d) in &wheels {
        let mut worst: f64 = 0.0;
        for k in 0..80 {
            // across the flat (centred at 1 rad, 0.04 to 0.08 m long) and beyond its ends
            let th = 1.0 - 0.12 + 0.24 * f64::from(k) / 79.0 + 1e-4;
            let (e, rate) = rim_support(d, th, r0);
            let (e_bf, u_bf) = brute(d, th);
            worst = worst.max((e - e_bf).abs());
            assert!(
                (e - e_bf).abs() < 2e-12,
                "{name}, theta {th}: {e} against {e_bf} (u {u_bf})"
            );
            let eps = 1e-7;
            let (ep, em) = (
                rim_support(d, th + eps, r0).0,
                rim_support(d, th - eps, r0).0,
            );
            let (up, um) = (brute(d, th + eps).1, brute(d, th - eps).1);
            if (up - um).abs() < 1e-3 {
                let fd = (ep - em) / (2.0 * eps);
                assert!(
                    (rate - fd).abs() < 1e-7,
                    "{name}, theta {th}: rate {rate} against {fd}"
                );
            }
        }
        eprintln!("{name}: largest difference from brute force {worst:.2e} m");
    }
    // the shallow flat's centre: the support function's curvature
    let d = &wheels[0].1;
    let k = 2e-4;
    let e2 = (rim_support(d, 1.0 + k, r0).0 - 2.0 * rim_support(d, 1.0, r0).0
        + rim_support(d, 1.0 - k, r0).0)
        / (k * k);
    let tau = std::f64::consts::TAU;
    let dr2 = 0.5 * 0.2e-3 * (tau * r0 / 0.05).powi(2);
    let rad = r0 - 0.2e-3;
    let want = rad * dr2 / (rad - dr2);
    eprintln!("shallow flat: e'' {e2:.4} against {want:.4} (d2r {dr2:.4})");
    assert!((e2 / want - 1.0).abs() < 1e-3, "{e2} against {want}");
    assert!(want / dr2 > 3.6);
}

/// An element along the line between its points (`direction = "line"`): its local x is that
/// line, and in the static solve a hanger in tension holds its body laterally by its pendulum
/// stiffness (weight / length), which the same element along a fixed axis does not.
#[test]
fn a_hanger_along_its_line_holds_its_body_laterally() {
    let hanger = |direction: &str| {
        format!(
            r#"{WS}
[[body]]
name = "mass"
mass_kg = 1000
inertia_kgm2 = [100, 100, 100]
position_m = [0.0, 0.0, 1.0]
frozen = ["x", "roll", "pitch", "yaw"]

[[force]]
name = "hanger"
type = "table"
body1 = "track"
body2 = "mass"
point_m = [0.0, 0.0, 1.5]
point2_m = [0.0, 0.0, 1.0]
direction = "{direction}"
deflection_mm = [-100, 100]
force_n = [-1e6, 1e6]
"#
        )
    };
    let v = compile(&hanger("line")).unwrap_or_else(|e| panic!("{e}"));
    let f = &v.forces()[0];
    assert!(f.line);
    // local x down the line, from point_m to point2_m
    assert_eq!([f.axes[0][0], f.axes[1][0], f.axes[2][0]], [0.0, 0.0, -1.0]);
    let eq = v.static_equilibrium().unwrap_or_else(|e| panic!("{e}"));
    // the hanger carries the weight in tension: on body 2 (the mass), up the line (-x)
    let fx = eq.element_force[0][0];
    assert!((fx + 1000.0 * 9.81).abs() < 1e-6 * 9810.0, "{fx}");
    let e = compile(&hanger("z"))
        .unwrap()
        .static_equilibrium()
        .unwrap_err();
    assert!(
        e.to_string().contains("body 'mass' has no support in y"),
        "{e}"
    );
}

/// A 10 t mass on a bushing (3 MN/m laterally, 1 MN/m vertically) and an inclined hanger (0.2 m
/// across, 0.4 m down, 100 MN/m): the hanger's force and the mass's displacement make a static
/// equilibrium with the hanger's geometric stiffness at that force, on the branch that starts
/// unloaded. On softer lateral support the single inclined hanger pulls the mass sideways: at
/// 100 kN/m it turns by 0.25 rad, beyond the linearisation (an error); at 10 kN/m the repeated
/// solve does not settle (an error); a strut from below with the weight far above its buckling
/// load (about ky·L) leaves the mass without lateral support, and the message says why.
#[test]
fn an_inclined_hanger_finds_its_equilibrium_or_says_why_not() {
    let kb = 1e8;
    let vehicle = |ky: f64, top: [f64; 3]| {
        format!(
            r#"{WS}
[[body]]
name = "mass"
mass_kg = 10000
inertia_kgm2 = [100, 100, 100]
position_m = [0.0, 0.0, 1.0]
frozen = ["x", "roll", "pitch", "yaw"]

[[force]]
name = "bushing"
type = "bushing"
body1 = "track"
body2 = "mass"
point_m = [0.0, 0.0, 1.0]
stiffness_n_per_m = [{ky}, {ky}, 1e6]

[[force]]
name = "hanger"
type = "table"
body1 = "track"
body2 = "mass"
point_m = [{}, {}, {}]
point2_m = [0.0, 0.0, 1.0]
direction = "line"
deflection_mm = [-100, 100]
force_n = [{}, {}]
"#,
            top[0],
            top[1],
            top[2],
            -kb * 0.1,
            kb * 0.1
        )
    };
    let (ky, kz) = (3e6, 1e6);
    let v = compile(&vehicle(ky, [0.0, -0.2, 1.4])).unwrap_or_else(|e| panic!("{e}"));
    let w = 10000.0 * v.gravity();
    let eq = v.static_equilibrium().unwrap_or_else(|e| panic!("{e}"));
    // the line from the top point to the mass, in the y-z plane
    let len = (0.2f64 * 0.2 + 0.4 * 0.4).sqrt();
    let u = [0.2 / len, -0.4 / len];
    // the line's force G(F) of the 2 × 2 solve at load `lam` with the geometric stiffness of F
    let solve = |f: f64, lam: f64| {
        let kt = -f / len;
        let k = |i: usize, j: usize| {
            let d = if i == j { 1.0 } else { 0.0 };
            [ky, kz][i] * d + kb * u[i] * u[j] + kt * (d - u[i] * u[j])
        };
        let det = k(0, 0) * k(1, 1) - k(0, 1) * k(1, 0);
        let g = [0.0, -lam * w];
        let d = [
            (k(1, 1) * g[0] - k(0, 1) * g[1]) / det,
            (k(0, 0) * g[1] - k(1, 0) * g[0]) / det,
        ];
        (-kb * (u[0] * d[0] + u[1] * d[1]), d)
    };
    let f = eq.element_force[1][0];
    let d = &eq.body_displacement[0];
    let (g, dd) = solve(f, 1.0);
    eprintln!(
        "hanger {f:.3} N, G(F) {g:.3} N; displacement y {:.4} mm, z {:.4} mm",
        d[1] * 1e3,
        d[2] * 1e3
    );
    // a fixed point, and the reported displacement its solution
    assert!((g - f).abs() < 1e-6 * w, "{g} against {f}");
    assert!(
        (dd[0] - d[1]).abs() < 1e-9 && (dd[1] - d[2]).abs() < 1e-9,
        "{dd:?} against {d:?}"
    );
    // on the branch that starts unloaded: its root followed from no load in 1000 increments
    let mut root = 0.0;
    for i in 1..=1000 {
        let lam = f64::from(i) / 1000.0;
        for _ in 0..50 {
            let (r0, _) = solve(root, lam);
            let h = 1e-6 * (1.0 + root.abs());
            let (r1, _) = solve(root + h, lam);
            let step = (r0 - root) / ((r1 - r0) / h - 1.0);
            root -= step;
            if step.abs() < 1e-12 * (1.0 + root.abs()) {
                break;
            }
        }
    }
    eprintln!("followed from no load: {root:.3} N");
    assert!((root - f).abs() < 1e-6 * w, "{root} against {f}");
    assert!(
        f < -0.5 * w,
        "the hanger carries most of the weight in tension: {f}"
    );
    let error = |ky: f64, top: [f64; 3]| {
        let e = compile(&vehicle(ky, top))
            .unwrap()
            .static_equilibrium()
            .unwrap_err()
            .to_string();
        eprintln!("{e}");
        e
    };
    let e = error(1e5, [0.0, -0.2, 1.4]);
    assert!(
        e.contains("element 'hanger' along its line turns by 0.25"),
        "{e}"
    );
    let e = error(1e4, [0.0, -0.2, 1.4]);
    assert!(
        e.contains("did not settle in 20 passes") && e.contains("element 'hanger'"),
        "{e}"
    );
    let e = error(1e5, [0.0, -0.07, 0.6]);
    assert!(
        e.contains("body 'mass' has no support in")
            && e.contains("element 'hanger' along its line is in compression"),
        "{e}"
    );
}

/// Wheel unloading on a twisted track (`static_equilibrium_on`): a rigid 20 t body on four
/// springs (k_z = 1 MN/m at x = ±a, y = ±b_s, at axle height) over two wheelsets. (Their
/// horizontal stiffness is kept small, 10 kN/m: a wheelset rolls about its contact points, so
/// its axle moves sideways by r0 φ_i, in opposite directions front and rear, and with 1 MN/m
/// horizontally the springs' shear added 6 % to ΔQ.) Each wheelset rolls with its
/// rails, φ_i = c_i/(2 b_w); the body, rigid, cannot follow the warp b_s(φ1 − φ2)/2 of the spring
/// seats, so each spring takes ±k times it, and each wheel ΔQ = k b_s² (c1 − c2)/(4 b_w²): with a
/// twist g over the wheelbase 2a, c1 − c2 = 2ag. Rails raised evenly lift the vehicle and leave
/// the loads; a wrong count of rail heights, or a non-finite one, is refused.
#[test]
fn a_twisted_track_unloads_the_wheels_as_a_rigid_body_on_four_springs() {
    let (a, bs, k) = (1.5, 1.0, 1e6);
    let mut text = String::from("name = \"two-axle\"\n");
    for (name, x) in [("ws1", a), ("ws2", -a)] {
        text += &format!(
            "[[wheelset]]\nname = \"{name}\"\nmass_kg = 1500\ninertia_kgm2 = [800, 100, 800]\n\
             position_m = [{x}, 0, 0.46]\nnominal_radius_m = 0.46\nback_to_back_mm = 1360\n\
             wheel_profile = {{ left = \"s1002\", right = \"s1002\" }}\n"
        );
    }
    text += "[[body]]\nname = \"body\"\nmass_kg = 20000\ninertia_kgm2 = [20000, 40000, 40000]\n\
             position_m = [0, 0, 1.5]\n";
    for (ws, x) in [("ws1", a), ("ws2", -a)] {
        for (side, y) in [("l", bs), ("r", -bs)] {
            text += &format!(
                "[[force]]\nname = \"spring_{ws}_{side}\"\ntype = \"bushing\"\nbody1 = \"{ws}\"\n\
                 body2 = \"body\"\npoint_m = [{x}, {y}, 0.46]\n\
                 stiffness_n_per_m = [1e4, 1e4, {k}]\n"
            );
        }
    }
    let v = compile(&text).unwrap_or_else(|e| panic!("{e}"));
    let bw = v.wheelsets()[0].contact_half_distance();
    let level = v.static_equilibrium().unwrap();
    // rails raised by 5 mm everywhere: the vehicle rises with them, the loads stay
    let raised = v.static_equilibrium_on(&[[5e-3; 2]; 2]).unwrap();
    for (r, l) in raised
        .wheel_loads
        .iter()
        .flatten()
        .zip(level.wheel_loads.iter().flatten())
    {
        assert!((r - l).abs() < 1e-6 * l, "{r} against {l}");
    }
    assert!((raised.body_displacement[0][2] - level.body_displacement[0][2] - 5e-3).abs() < 1e-9);
    let q0 = level.wheel_loads[0][0];
    let g = 3e-3;
    // cross-level g (x − x̄): the left rail up by half of it, the right one down
    let c = [g * a, -g * a];
    let eq = v
        .static_equilibrium_on(&[[c[0] / 2.0, -c[0] / 2.0], [c[1] / 2.0, -c[1] / 2.0]])
        .unwrap();
    let dq = k * bs * bs * (c[0] - c[1]) / (4.0 * bw * bw);
    eprintln!(
        "Q0 {q0:.1} N, b_w {bw:.4} m; twisted {:?} N; ΔQ expected {dq:.1} N ({:.3} of Q0)",
        eq.wheel_loads,
        dq / q0
    );
    // the raised left rail at the front and the lowered one at the rear load those wheels
    let want = [[q0 + dq, q0 - dq], [q0 - dq, q0 + dq]];
    for (got, want) in eq.wheel_loads.iter().zip(want) {
        for (q, w) in got.iter().zip(want) {
            assert!((q - w).abs() < 2e-3 * dq, "{q} against {w}");
        }
    }
    // the total load is the weight still
    let total: f64 = eq.wheel_loads.iter().flatten().sum();
    assert!((total - level.total_wheel_load()).abs() < 1e-6 * total);
    let e = v
        .static_equilibrium_on(&[[0.0; 2]])
        .unwrap_err()
        .to_string();
    assert!(e.contains("of the 2 wheelsets, found 1 pairs"), "{e}");
    let e = v
        .static_equilibrium_on(&[[0.0, f64::NAN], [0.0; 2]])
        .unwrap_err()
        .to_string();
    assert!(e.contains("finite rail height"), "{e}");
}

/// `direction = "line"` needs body 2's own point at least 1 cm away and no orientation, and
/// applies to the one-axis types only.
#[test]
fn a_line_element_without_its_second_point_is_located() {
    let text = format!(
        r#"{WS}
[[force]]
name = "a"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
direction = "line"
velocity_m_per_s = [-1, 1]
force_n = [-5e3, 5e3]

[[force]]
name = "b"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
point2_m = [0, 0.005, 0.46]
direction = "line"
velocity_m_per_s = [-1, 1]
force_n = [-5e3, 5e3]

[[force]]
name = "c"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
point2_m = [0, 0.5, 0.46]
direction = "line"
orientation_deg = [0, 0, 90]
velocity_m_per_s = [-1, 1]
force_n = [-5e3, 5e3]

[[force]]
name = "d"
type = "bushing"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
point2_m = [0, 0.5, 0.46]
direction = "line"
stiffness_n_per_m = [1e6, 1e6, 1e6]

[[force]]
name = "e"
type = "damper"
body1 = "track"
body2 = "ws"
point_m = [0, 0, 0.46]
point2_m = [0, 0.5, 0.46]
direction = "lien"
velocity_m_per_s = [-1, 1]
force_n = [-5e3, 5e3]
"#
    );
    let p = problems(&text);
    expect(
        &p,
        17,
        &[
            "force 'a'",
            "missing key 'point2_m'",
            "line from point_m to point2_m",
        ],
    );
    expect(
        &p,
        27,
        &[
            "force 'b'",
            "point2_m lies 0.0050 m from point_m",
            "at least 0.01 m",
        ],
    );
    expect(
        &p,
        40,
        &[
            "force 'c'",
            "orientation_deg does not apply",
            "direction = \"line\"",
        ],
    );
    expect(&p, 51, &["direction", "does not apply to type 'bushing'"]);
    expect(
        &p,
        61,
        &[
            "force 'e'",
            "direction 'lien' is not a local axis",
            "\"line\"",
        ],
    );
    assert_eq!(p.len(), 5, "{p:#?}");
}
