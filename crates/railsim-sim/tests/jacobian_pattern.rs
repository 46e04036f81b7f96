//! The simulator's Jacobian pattern (`SimModel::jacobian_pattern`) against the column-by-column
//! central difference of the full right-hand side: on scenes that use each of its couplings
//! (elastic rails in two-point flange contact, a traction torque's reaction, a friction element
//! loaded by an element between other members), every entry the pattern leaves out is zero in
//! the dense Jacobian, and the grouped Jacobian equals the dense one.
use crate::common;

use common::{root, scene};
use railsim_ode::linear::jacobian;
use railsim_ode::{JacobianPattern, OdeSystem, RhsError};
use railsim_sim::Simulation;
use railsim_sim::dynamics::Dynamics;

/// The model's right-hand side without its pattern: the dense difference.
struct Dense<'a>(Dynamics<'a>);

impl OdeSystem for Dense<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        self.0.rhs(t, x, d)
    }
}

/// Compares the grouped and the dense Jacobian of `sim` at `(t, x)`; returns the number of
/// column groups. Differences are measured per row against the row's largest entry: outside
/// the pattern the dense entries must vanish (below 1e-9 of it), inside both must agree to
/// 1e-6. The scenes run the contact without its warm start, whose memory of the last pose
/// moves forces by some 1e-10 between the two sequences of evaluations; without it both
/// differences are exactly zero (measured), and the couplings tested here, when left out of
/// the pattern, show as entries of 1e-5 to 1 of their rows.
fn check(sim: &Simulation, t: f64, x: &[f64], what: &str) -> usize {
    let model = sim.model();
    let n = x.len();
    // the linearisation's steps (railsim_sim::modal): 1 µm on positions, 1e-5 on rates
    let mut steps = vec![1e-6; n];
    for i in model.n_pos..model.n_pos + model.n_rate {
        steps[i] = 1e-5f64.max(1e-7 * x[i].abs());
    }
    for r in model.wheels.iter().filter_map(|w| w.rail) {
        steps[r + 2] = 1e-5;
        steps[r + 3] = 1e-5;
    }
    let pattern: JacobianPattern = model.jacobian_pattern();
    let groups = pattern.column_groups().len();
    let jd = jacobian(&mut Dense(Dynamics::new(model)), t, x, &steps).unwrap();
    let jg = jacobian(&mut Dynamics::new(model), t, x, &steps).unwrap();
    let mut inside = vec![vec![false; n]; n];
    for j in 0..n {
        for &i in pattern.rows(j) {
            inside[i][j] = true;
        }
    }
    let (mut worst_out, mut worst_in) = ((0.0f64, 0, 0), (0.0f64, 0, 0));
    for i in 0..n {
        let scale = (0..n).map(|j| jd[(i, j)].abs()).fold(0.0, f64::max);
        if scale == 0.0 {
            continue;
        }
        for j in 0..n {
            if inside[i][j] {
                let d = (jg[(i, j)] - jd[(i, j)]).abs() / scale;
                if d > worst_in.0 {
                    worst_in = (d, i, j);
                }
            } else {
                assert_eq!(jg[(i, j)], 0.0);
                let d = jd[(i, j)].abs() / scale;
                if d > worst_out.0 {
                    worst_out = (d, i, j);
                }
            }
        }
    }
    let name = |i: usize| model.state_names[i].as_str();
    eprintln!(
        "{what}: {n} states, {} structural non-zeros, {groups} groups; largest dense entry \
         outside the pattern {:.1e} of its row (d {} / d {}), largest grouped − dense inside \
         {:.1e} (d {} / d {})",
        pattern.nonzeros(),
        worst_out.0,
        name(worst_out.1),
        name(worst_out.2),
        worst_in.0,
        name(worst_in.1),
        name(worst_in.2),
    );
    assert!(
        worst_out.0 < 1e-9,
        "{what}: d {} / d {} = {:e} is outside the pattern",
        name(worst_out.1),
        name(worst_out.2),
        jd[(worst_out.1, worst_out.2)]
    );
    assert!(worst_in.0 < 1e-6, "{what}: {worst_in:?}");
    groups
}

/// The Manchester vehicle on the elastic rail support of the R = 150 m curve, started inside
/// the curve in its quasi-static state: the leading wheelsets in two-point flange contact, each
/// wheel's contact coupling its wheelset with the rail mass under it.
#[test]
fn the_pattern_holds_on_elastic_rails_in_flange_contact() {
    let s = scene(
        "vehicle = \"vehicles/manchester_vehicle1.toml\"\n\
         track = \"tracks/curve_r150_elastic.toml\"\nspeed_kmh = 40\nstart_m = 150\n\
         duration_s = 0.1\nfreeze = [\"carbody.x\"]\n[contact]\nwarm_start = false\n\
         [initial]\nstate = \"quasi-static\"\n",
    );
    let sim = Simulation::new(&s).unwrap();
    let m = sim.model();
    // the leading wheelset's outer (right) wheel in two-point flange contact
    let y = sim.initial_state()[common::state_index(&sim, "ws1.y")];
    assert!(y < -5e-3, "ws1.y = {y}");
    let groups = check(&sim, 0.0, sim.initial_state(), "elastic rails, R = 150 m");
    assert_eq!(m.dim(), 110);
    assert!(groups <= 48, "{groups} groups");
}

/// Traction torques whose reactions act on a bogie frame and on the carbody, and a friction
/// element between the carbody and the front bogie whose normal load is a primary spring's
/// force (between the bogie and a wheelset): the couplings that reach beyond an element's own ends. Evaluated in
/// the R = 300 m curve at the static state of the tangent (the Jacobian's state need not be an
/// equilibrium).
#[test]
fn the_pattern_holds_for_torque_reactions_and_friction_loaded_by_another_element() {
    let dir = std::env::temp_dir().join(format!("railsim-pattern-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut text =
        std::fs::read_to_string(root().join("vehicles/manchester_vehicle1.toml")).unwrap();
    // ws4's reaction on the carbody, which no element joins to it
    for (ws, mount) in [("ws1", "bogie_front"), ("ws4", "carbody")] {
        text = text.replace(
            &format!("name = \"{ws}\"\n"),
            &format!("name = \"{ws}\"\ntorque_nm = 3000\ntorque_reaction = \"{mount}\"\n"),
        );
    }
    text.push_str(
        "\n[[force]]\nname = \"rubbing\"\ntype = \"friction\"\nbody1 = \"carbody\"\n\
         body2 = \"bogie_front\"\npoint_m = [9.5, 0.0, 0.8]\ndirection = \"y\"\n\
         stiffness_n_per_m = 1e7\nfriction_coefficient = 0.1\nnormal_element = \"primary_ws1_l\"\n\
         normal_direction = \"-z\"\n",
    );
    let vehicle = dir.join("coupled.toml");
    std::fs::write(&vehicle, &text).unwrap();
    let s = scene(&format!(
        "vehicle = \"{}\"\ntrack = \"tracks/curve_r300.toml\"\nspeed_kmh = 72\n\
         duration_s = 0.1\nfreeze = [\"carbody.x\"]\n[contact]\nmodel = \"polach\"\n\
         warm_start = false\n",
        vehicle.display()
    ));
    let sim = Simulation::new(&s).unwrap();
    let model = sim.model();
    // the couplings are there: ws1's and ws4's states reach the carbody's rows (through the
    // friction element's normal load, through the torque's reaction)
    let p = model.jacobian_pattern();
    let ws1_y = common::state_index(&sim, "ws1.y");
    let ws4_x = common::state_index(&sim, "ws4.x");
    let carbody_rows: Vec<usize> = model
        .state_names
        .iter()
        .enumerate()
        .filter(|(_, s)| s.starts_with("d/dt carbody."))
        .map(|(i, _)| i)
        .collect();
    assert!(carbody_rows.iter().any(|i| p.rows(ws1_y).contains(i)));
    assert!(carbody_rows.iter().any(|i| p.rows(ws4_x).contains(i)));
    // the friction element sliding (its stick spring stretched 10 mm, 100 kN against a
    // sliding force of 0.1 times some 30 kN), where its force is the normal element's times the
    // coefficient
    let mut x = sim.initial_state().to_vec();
    x[common::state_index(&sim, "rubbing friction slip")] = 0.01;
    // in the circular curve (from 300 m), where the axle's direction, and with it the
    // torque's reaction on the bogie, turns with the wheelset's position along the track
    check(
        &sim,
        (400.0 - s.start) / 20.0,
        &x,
        "torque reactions, friction on a primary spring's load",
    );
}

/// Out-of-round wheels (a fifth-order polygon on both wheels of ws1, a flat on ws3's left
/// wheel): each such wheelset's rolled-angle lag is a state of its own, whose rate follows the
/// wheelset's spin and position rates and on which its wheels' contact forces depend through
/// the radius deviation; the pattern takes it into the wheelset's block. Evaluated 1 s into
/// the run's track (the polygon's slope is not zero there).
#[test]
fn the_pattern_holds_for_the_rolled_angles_of_out_of_round_wheels() {
    let dir = std::env::temp_dir().join(format!("railsim-pattern-oor-{}", std::process::id()));
    let vehicle = common::out_of_round_manchester(&dir, 10.0);
    let s = scene(&format!(
        "vehicle = \"{}\"\ntrack = \"tracks/straight.toml\"\nspeed_kmh = 72\n\
         duration_s = 0.1\nfreeze = [\"carbody.x\"]\n[contact]\nmodel = \"polach\"\n\
         warm_start = false\n",
        vehicle.display()
    ));
    std::fs::remove_dir_all(&dir).ok();
    let sim = Simulation::new(&s).unwrap();
    let lag = common::state_index(&sim, "ws1 rolled angle lag");
    common::state_index(&sim, "ws3 rolled angle lag");
    let mut x = sim.initial_state().to_vec();
    x[lag] = 0.3;
    check(&sim, 1.0, &x, "rolled angles of out-of-round wheels");
    // the coupling is there: the lag moves ws1's vertical acceleration (the polygon's radius)
    let mut d = Dynamics::new(sim.model());
    let z_rate = common::state_index(&sim, "d/dt ws1.z");
    let mut acc = [0.0; 2];
    for (k, l) in [0.3, 0.31].into_iter().enumerate() {
        x[lag] = l;
        let mut dx = vec![0.0; x.len()];
        d.rhs(1.0, &x, &mut dx).unwrap();
        acc[k] = dx[z_rate];
    }
    assert!((acc[1] - acc[0]).abs() > 1.0, "{acc:?}");
}

/// A grouped Jacobian re-evaluates only the wheels whose inputs a group moves: the other
/// wheels' evaluations at the base state are kept and reused (`dynamics::ContactSlot`). On the
/// Manchester vehicle (`stripes`, warm-started) the central difference then takes four
/// evaluations per wheelset column (two wheels, ±) and eight for the first group's unmoved
/// wheels at most, against 16 per group without the reuse; the Jacobian is the same as the
/// column-by-column one (the first test of this file).
#[test]
fn a_grouped_jacobian_evaluates_only_the_wheels_it_moves() {
    let s = scene(
        "vehicle = \"vehicles/manchester_vehicle1.toml\"\ntrack = \"tracks/straight.toml\"\n\
         speed_kmh = 72\nduration_s = 0.1\nfreeze = [\"carbody.x\"]\n",
    );
    let sim = Simulation::new(&s).unwrap();
    let model = sim.model();
    let x = sim.initial_state();
    let n = x.len();
    let wheelset_columns = model
        .members
        .iter()
        .filter(|m| m.is_wheelset())
        .map(|m| m.pos.iter().chain(m.rate.iter()).flatten().count())
        .sum::<usize>();
    let groups = model.jacobian_pattern().column_groups().len();
    let mut d = Dynamics::new(model);
    let count = |d: &Dynamics| {
        d.ws.warm_starts()
            .map(|w| w.warm_count + w.cold_count)
            .sum::<u64>() as usize
    };
    jacobian(&mut d, 0.0, x, &vec![1e-6; n]).unwrap();
    let evaluations = count(&d);
    eprintln!(
        "{n} states, {groups} groups, {wheelset_columns} wheelset columns: {evaluations} wheel \
         evaluations (without reuse {})",
        2 * groups * model.wheels.len()
    );
    assert!(evaluations >= 4 * wheelset_columns, "{evaluations}");
    assert!(evaluations <= 4 * wheelset_columns + 8, "{evaluations}");
    assert!(4 * wheelset_columns + 8 < 2 * groups * model.wheels.len());
}
