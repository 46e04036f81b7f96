//! Steady-state curving (`railsim_sim::curving`) against the physics of a bogie vehicle in a
//! curve: the track-shift forces carry the uncompensated acceleration, the leading wheelset of
//! each bogie runs out toward the outer rail with a positive angle of attack and the flange
//! force, the trailing one nearer the centre; a right curve mirrors a left one.

use crate::common;

use railsim_sim::RunOptions;
use railsim_sim::curving::{
    CurveCase, CurvingRun, CurvingSolution, QuasiStatic, SteadyCurving, quasi_static_curving,
    steady_curving,
};

fn polach_scene() -> railsim_sim::Scene {
    common::manchester_polach("track = \"tracks/straight.toml\"\nspeed_kmh = 80\nduration_s = 1")
}

fn case(left: bool) -> SteadyCurving {
    let c = CurveCase {
        radius: 300.0,
        cant: 0.1,
        left,
        speed: 80.0 / 3.6,
    };
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    steady_curving(
        &polach_scene(),
        &c,
        &CurvingRun::default(),
        &opts,
        &mut |_, _| {},
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn print(r: &SteadyCurving) {
    println!(
        "R {} m, cant {} mm, {:.0} km/h: a_q {:.3} m/s², deficiency {:.1} mm, {} samples, carbody {:?}",
        r.case.radius,
        r.case.cant * 1e3,
        r.case.speed * 3.6,
        r.uncompensated,
        r.cant_deficiency * 1e3,
        r.samples,
        r.carbody_lateral
    );
    for (n, w) in r.wheelsets.iter().enumerate() {
        println!(
            "  ws{n}: y {:7.3} mm (swing {:.3}) aoa {:7.3} mrad ΣY {:8.2} kN | L: Y {:7.2} Q {:7.2} Y/Q {:6.3} Tγ {:6.1} | R: Y {:7.2} Q {:7.2} Y/Q {:6.3} Tγ {:6.1}",
            w.lateral * 1e3,
            w.lateral_swing * 1e3,
            w.angle_of_attack * 1e3,
            w.sum_y * 1e-3,
            w.wheels[0].y * 1e-3,
            w.wheels[0].q * 1e-3,
            w.wheels[0].y_over_q,
            w.wheels[0].wear,
            w.wheels[1].y * 1e-3,
            w.wheels[1].q * 1e-3,
            w.wheels[1].y_over_q,
            w.wheels[1].wear
        );
    }
}

/// R = 300 m, 100 mm cant, 80 km/h (0.99 m/s² uncompensated, 151 mm cant deficiency),
/// `polach`. Values at stop 26, left curve: leading wheelsets 6.28 / 6.24 mm outward, angle of
/// attack 7.8 / 7.0 mrad toward the outside, outer Y/Q 0.39 / 0.30 (outer Q 74.4 / 71.6 kN);
/// trailing wheelsets 0.8 / 1.1 mm inward. (When written, outer Y/Q 0.42 / 0.32: the vehicle
/// then rested 0.22 m low on its springs, and the higher carbody of its loaded geometry moves
/// more load onto the outer wheels.)
/// \[kg\] the vehicle's mass from the run's static axle loads.
fn vehicle_mass(r: &SteadyCurving) -> f64 {
    let CurvingSolution::Run(summary) = &r.solution else {
        panic!("not a run");
    };
    summary
        .assessment
        .axles
        .iter()
        .map(|a| a.axle_load)
        .sum::<f64>()
        / 9.81
}

#[test]
fn a_bogie_vehicle_curves_with_its_leading_wheelsets_in_flange_contact() {
    let left = case(true);
    print(&left);
    let g = 9.81;
    let mass = vehicle_mass(&left);
    // toward the outside: -y in a left curve
    let sum_y: f64 = left.wheelsets.iter().map(|w| w.sum_y).sum();
    let expect = -mass * left.uncompensated;
    assert!(
        (sum_y / expect - 1.0).abs() < 0.01,
        "ΣY {sum_y} against {expect}"
    );
    assert!((left.cant_deficiency - left.uncompensated * 1.5 / g).abs() < 1e-12);
    let w = &left.wheelsets;
    for lead in [0, 2] {
        let (l, t) = (&w[lead], &w[lead + 1]);
        // out toward the outer (right) rail, nose toward the outside, flange force there
        assert!(l.lateral < -5e-3, "ws{lead}: {l:?}");
        assert!(l.angle_of_attack < -3e-3, "ws{lead}: {l:?}");
        assert!(l.wheels[1].y_over_q > 0.25, "ws{lead}: {l:?}");
        assert!(l.wheels[1].y_over_q > t.wheels[1].y_over_q + 0.1);
        // the trailing wheelset near the centre
        assert!(t.lateral.abs() < 2e-3, "ws{}: {t:?}", lead + 1);
        assert!(t.angle_of_attack.abs() < 2e-3, "ws{}: {t:?}", lead + 1);
    }
    for (n, ws) in w.iter().enumerate() {
        // the outer wheels carry more (cant deficiency), the vehicle runs steadily
        assert!(ws.wheels[1].q > ws.wheels[0].q + 10e3, "ws{n}: {ws:?}");
        assert!(ws.lateral_swing < 0.1e-3, "ws{n}: {ws:?}");
    }
    // the carbody leans out: its accelerometer reads more than the track plane's acceleration,
    // toward the curve's centre
    let cb = left.carbody_lateral.unwrap();
    assert!(cb > left.uncompensated, "{cb}");
    // the right curve mirrors it: left and right wheels swapped, lateral quantities negated
    let right = case(false);
    print(&right);
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
    for (a, b) in left.wheelsets.iter().zip(&right.wheelsets) {
        assert!(close(a.lateral, -b.lateral, 1e-6), "{a:?}\n{b:?}");
        assert!(close(a.angle_of_attack, -b.angle_of_attack, 1e-6));
        assert!(close(a.sum_y, -b.sum_y, 50.0));
        for k in 0..2 {
            assert!(close(a.wheels[k].y, b.wheels[1 - k].y, 50.0));
            assert!(close(a.wheels[k].q, b.wheels[1 - k].q, 50.0));
            assert!(close(a.wheels[k].wear, b.wheels[1 - k].wear, 0.5));
        }
    }
    assert!(close(cb, -right.carbody_lateral.unwrap(), 1e-3));
}

#[test]
fn bad_curving_cases_are_reported() {
    let s = polach_scene();
    let good = CurveCase {
        radius: 300.0,
        cant: 0.1,
        left: true,
        speed: 20.0,
    };
    let run = CurvingRun::default();
    let with = |f: &dyn Fn(&mut CurveCase)| {
        let mut c = good;
        f(&mut c);
        railsim_sim::curving::curving_scene(&s, &c, &run)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    assert!(with(&|c| c.radius = 30.0).contains("the radius must be at least"));
    assert!(with(&|c| c.radius = f64::NAN).contains("found NaN m"));
    assert!(with(&|c| c.cant = 0.25).contains("the cant must lie in [0, 200] mm, found 250 mm"));
    assert!(with(&|c| c.speed = 0.0).contains("the speed must be positive"));
    let short = CurvingRun {
        average: 0.0,
        ..run
    };
    let e = railsim_sim::curving::curving_scene(&s, &good, &short)
        .unwrap_err()
        .to_string();
    assert!(e.contains("averaging length (0 m)"), "{e}");
    // a good case: the track's curve starts after the vehicle and the transition
    let (scene, curve_start) = railsim_sim::curving::curving_scene(&s, &good, &run).unwrap();
    let f = scene.track.frame_at(curve_start + 1.0);
    assert!((f.curvature - 1.0 / 300.0).abs() < 1e-12);
    assert!(
        scene
            .track
            .frame_at(curve_start - run.transition - 0.5)
            .curvature
            == 0.0
    );
    assert!(scene.track.irregularities().is_none());
    // the study's means come from the log's samples: it is assessed at its log rate and does
    // not evaluate the run between them (the scene itself, without the key, at 1 kHz)
    assert_eq!(s.assessment.rate_hz, None);
    assert!(s.assessment_rate() >= 1000.0);
    assert_eq!(scene.assessment_samples_per_log(), 1);
}

/// The quasi-static solution of the R = 300 m case against the time integration's means (the
/// same equations, the same contact): every wheelset's displacement and angle of attack, every
/// wheel's Y, Q, Y/Q and wear number, the carbody's reading; and ΣY = M·a again.
#[test]
fn the_quasi_static_solution_is_the_steady_state_of_the_time_integration() {
    let run = case(true);
    let c = run.case;
    let qs = quasi_static_curving(
        &polach_scene(),
        &c,
        &CurvingRun::default(),
        &QuasiStatic::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    print(&qs);
    let CurvingSolution::QuasiStatic {
        iterations,
        residual,
        wall,
    } = qs.solution
    else {
        panic!("not quasi-static")
    };
    println!("quasi-static: {iterations} iterations, residual {residual:.3}, {wall:.2} s");
    assert!(residual <= 1.0 && iterations > 0);
    assert_eq!(qs.samples, 1);
    for (n, (a, b)) in run.wheelsets.iter().zip(&qs.wheelsets).enumerate() {
        println!(
            "ws{n}: dy {:.4} mm, daoa {:.4} mrad, dΣY {:.1} N",
            (a.lateral - b.lateral) * 1e3,
            (a.angle_of_attack - b.angle_of_attack) * 1e3,
            a.sum_y - b.sum_y
        );
        assert!(
            (a.lateral - b.lateral).abs() < 0.02e-3,
            "ws{n}: {a:?}\n{b:?}"
        );
        assert!((a.angle_of_attack - b.angle_of_attack).abs() < 0.05e-3);
        assert!((a.sum_y - b.sum_y).abs() < 200.0);
        assert_eq!(b.lateral_swing, 0.0);
        for k in 0..2 {
            let (p, q) = (&a.wheels[k], &b.wheels[k]);
            assert!((p.y - q.y).abs() < 200.0, "ws{n} wheel {k}: {p:?} {q:?}");
            assert!((p.q - q.q).abs() < 200.0, "ws{n} wheel {k}: {p:?} {q:?}");
            assert!((p.y_over_q - q.y_over_q).abs() < 0.005);
            assert!((p.wear - q.wear).abs() < 0.02 * p.wear.max(10.0));
        }
    }
    let (a, b) = (run.carbody_lateral.unwrap(), qs.carbody_lateral.unwrap());
    assert!((a - b).abs() < 0.005, "{a} vs {b}");
    let sum_y: f64 = qs.wheelsets.iter().map(|w| w.sum_y).sum();
    let expect = -vehicle_mass(&run) * qs.uncompensated;
    assert!(
        (sum_y / expect - 1.0).abs() < 0.01,
        "ΣY {sum_y} against {expect}"
    );
}

/// A curve with cant excess (R = 300 m at 40 km/h, −0.24 m/s²) that Newton from the centred
/// start does not reach: the continuation in curvature and cant finds the run's steady state.
/// At 120 km/h (3.0 m/s²) the continuation needs a halved step, and finds a steady state that
/// is linearly stable (every mode about it decays: `modes_in_curve`). That case was reported
/// without a steady state before the halving, because the time integration still swings by
/// 0.64 mm after the default 100 m of settling; after 600 m it has settled (0.025 mm) to the
/// quasi-static solution (`railsim curving --model polach --radius-m 300 --speed-kmh 120
/// --settle-m 600`: leading wheelset 6.31 mm and 5.40 mrad out, as here). A case without a
/// steady state (R = 150 m at 120 km/h, 6.7 m/s²) is an error that points to the time
/// integration.
#[test]
fn the_quasi_static_solution_continues_in_curvature_and_reports_curves_without_a_steady_state() {
    let c = CurveCase {
        radius: 300.0,
        cant: 0.1,
        left: true,
        speed: 40.0 / 3.6,
    };
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let (scene, run) = (polach_scene(), CurvingRun::default());
    let ti = steady_curving(&scene, &c, &run, &opts, &mut |_, _| {}).unwrap();
    let qs = quasi_static_curving(&scene, &c, &run, &QuasiStatic::default()).unwrap();
    print(&ti);
    print(&qs);
    for (a, b) in ti.wheelsets.iter().zip(&qs.wheelsets) {
        assert!(a.lateral_swing < 0.1e-3);
        assert!((a.lateral - b.lateral).abs() < 0.02e-3, "{a:?}\n{b:?}");
        assert!((a.angle_of_attack - b.angle_of_attack).abs() < 0.05e-3);
        for k in 0..2 {
            assert!((a.wheels[k].y - b.wheels[k].y).abs() < 200.0);
            assert!((a.wheels[k].q - b.wheels[k].q).abs() < 200.0);
        }
    }
    let fast = CurveCase {
        speed: 120.0 / 3.6,
        ..c
    };
    let qs = QuasiStatic::default();
    let solved = quasi_static_curving(&scene, &fast, &run, &qs).unwrap_or_else(|e| panic!("{e}"));
    print(&solved);
    let lead = &solved.wheelsets[0];
    assert!((lead.lateral.abs() - 6.31e-3).abs() < 0.01e-3, "{lead:?}");
    let modes = railsim_sim::modal::modes_in_curve(
        &scene,
        &fast,
        &run,
        &qs,
        &railsim_sim::modal::ModalOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let least = &modes.modes[0];
    println!("least stable mode: {least:?}");
    assert!(least.re < 0.0, "{least:?}");
    let tight = CurveCase {
        radius: 150.0,
        ..fast
    };
    let e = quasi_static_curving(&scene, &tight, &run, &qs)
        .expect_err("no steady state")
        .to_string();
    assert!(
        e.contains("R = 150 m at 120.0 km/h") && e.contains("time integration"),
        "{e}"
    );
}

/// A lubricated gauge face (`friction` by contact angle: 0.3 up to 15°, 0.1 from 25° on) in the
/// R = 150 m curve at 40 km/h (`polach`, quasi-static): the leading outer wheel, in flange
/// contact, dissipates far less (its wear number Tγ falls with the flange's μ), while the
/// leading inner wheel, on its tread below 15°, is unchanged and the wheel loads still carry
/// the vehicle's weight. Lubricating the outer rail alone (`friction = { left, right }`) relieves
/// the flanging wheel nearly as much and leaves the inner rail's wheels as on dry rails.
#[test]
fn a_lubricated_gauge_face_relieves_the_flanging_wheel() {
    let solve = |friction: &str| {
        let s = common::scene(&format!(
            "vehicle = \"vehicles/manchester_vehicle1.toml\"\nfreeze = [\"carbody.x\"]\n\
             track = \"tracks/straight.toml\"\nspeed_kmh = 40\nduration_s = 1\n\
             [contact]\nmodel = \"polach\"\nfriction = {friction}\n"
        ));
        let c = CurveCase {
            radius: 150.0,
            cant: 0.1,
            left: true,
            speed: 40.0 / 3.6,
        };
        let r = quasi_static_curving(&s, &c, &CurvingRun::default(), &QuasiStatic::default())
            .unwrap_or_else(|e| panic!("{e}"));
        print(&r);
        r
    };
    let dry = solve("0.3");
    let lub = solve("{ contact_angle_deg = [15, 25], coefficient = [0.3, 0.1] }");
    // a left curve: the leading wheelset runs out to the right (outer) rail
    let (d, l) = (&dry.wheelsets[0], &lub.wheelsets[0]);
    assert!(d.lateral < -5e-3 && l.lateral < -5e-3, "{d:?} {l:?}");
    let (outer_d, outer_l) = (d.wheels[1].wear, l.wheels[1].wear);
    let (inner_d, inner_l) = (d.wheels[0].wear, l.wheels[0].wear);
    println!(
        "leading wheelset Tγ: outer {outer_d:.1} → {outer_l:.1} N, inner {inner_d:.1} → {inner_l:.1} N"
    );
    assert!(outer_l < 0.4 * outer_d, "{outer_d} → {outer_l}");
    assert!(
        (inner_l / inner_d - 1.0).abs() < 0.05,
        "{inner_d} → {inner_l}"
    );
    // only the outer (right, high) rail lubricated: its flanging wheel gains nearly as much
    // (Tγ 97.3 N against 84.7 N with both rails: the dry inner rail steers the wheelsets a
    // little differently), while the inner rail's wheels run as on dry rails (the trailing
    // wheelset's inner wheel, toward its inner flange, changed Y/Q by 30 % with both lubricated)
    let high =
        solve("{ left = 0.3, right = { contact_angle_deg = [15, 25], coefficient = [0.3, 0.1] } }");
    let h = &high.wheelsets[0];
    println!(
        "outer rail only: leading outer Tγ {:.1} N; trailing inner Y/Q {:.3} (dry {:.3}, both {:.3})",
        h.wheels[1].wear,
        high.wheelsets[1].wheels[0].y_over_q,
        dry.wheelsets[1].wheels[0].y_over_q,
        lub.wheelsets[1].wheels[0].y_over_q
    );
    assert!(
        h.wheels[1].wear < 0.4 * outer_d,
        "{} vs {outer_d}",
        h.wheels[1].wear
    );
    let inner = |r: &SteadyCurving| r.wheelsets[1].wheels[0].y_over_q;
    assert!((inner(&high) - inner(&dry)).abs() < 0.2 * (inner(&lub) - inner(&dry)).abs());
    let q = |r: &SteadyCurving| -> f64 {
        r.wheelsets
            .iter()
            .flat_map(|w| w.wheels.iter().map(|k| k.q))
            .sum()
    };
    assert!(
        (q(&lub) / q(&dry) - 1.0).abs() < 1e-3,
        "{} {}",
        q(&dry),
        q(&lub)
    );
}

/// `stripes` at R = 600 m, 100 mm cant, 80 km/h: Newton from the centred start stalls on the
/// strips' kinks, and from `polach`'s steady state of the case it converges (before that fallback
/// this case was an error). Its residual certifies the steady state of STRIPES' equations (it
/// equals the means of the built-in study's time integration, docs/validation.md §10, to the
/// table's digits: 6.05 / 5.91 mm, 3.76 / 3.52 mrad); against `polach`'s the leading wheelsets
/// differ by the models' difference, 0.10 / 0.14 mm and 0.14 / 0.19 mrad (criteria 0.2 mm and
/// 0.3 mrad).
#[test]
fn the_quasi_static_solution_with_stripes_starts_from_polach() {
    let c = CurveCase {
        radius: 600.0,
        cant: 0.1,
        left: true,
        speed: 80.0 / 3.6,
    };
    let (run, qs) = (CurvingRun::default(), QuasiStatic::default());
    let polach = quasi_static_curving(&polach_scene(), &c, &run, &qs).unwrap();
    let mut stripes_scene = polach_scene();
    stripes_scene.contact.model = railsim_contact::ContactModelKind::Stripes;
    let stripes =
        quasi_static_curving(&stripes_scene, &c, &run, &qs).unwrap_or_else(|e| panic!("{e}"));
    print(&polach);
    print(&stripes);
    let CurvingSolution::QuasiStatic { residual, .. } = stripes.solution else {
        panic!("not quasi-static")
    };
    assert!(residual <= 1.0);
    for k in [0, 2] {
        let (a, b) = (&polach.wheelsets[k], &stripes.wheelsets[k]);
        assert!((a.lateral - b.lateral).abs() < 0.2e-3, "{a:?}\n{b:?}");
        assert!((a.angle_of_attack - b.angle_of_attack).abs() < 0.3e-3);
    }
}

/// `stripes` at R = 300 m, 100 mm cant, 80 km/h, in flange contact, quasi-static at the default
/// contact step of 1 mm and at 0.5 mm: both converge, within 0.05 mm and 0.3 mrad of `polach`'s
/// leading wheelsets (the time integration's means of the two models differ by 0.02 mm and
/// 0.16 mrad there, §10). Measured: 32 and 30 iterations, within 0.016 mm and 0.15 mrad. Until
/// stop 26 (the vehicle's loaded geometry, docs/models/dynamics.md) the strips left some 250 N at
/// 1 mm that no state removed and Newton stalled there; the error's hint to refine the step
/// (`SMOOTH_STRIPES_STEP`) stays for cases that do.
#[test]
fn stripes_converges_in_flange_contact_at_the_default_and_a_finer_step() {
    let c = CurveCase {
        radius: 300.0,
        cant: 0.1,
        left: true,
        speed: 80.0 / 3.6,
    };
    let (run, qs) = (CurvingRun::default(), QuasiStatic::default());
    let mut scene = polach_scene();
    scene.contact.model = railsim_contact::ContactModelKind::Stripes;
    let coarse = quasi_static_curving(&scene, &c, &run, &qs).unwrap_or_else(|e| panic!("{e}"));
    scene.contact.travel.step = 0.5e-3;
    let fine = quasi_static_curving(&scene, &c, &run, &qs).unwrap_or_else(|e| panic!("{e}"));
    let polach = quasi_static_curving(&polach_scene(), &c, &run, &qs).unwrap();
    print(&fine);
    for (r, step) in [(&coarse, "1 mm"), (&fine, "0.5 mm")] {
        let CurvingSolution::QuasiStatic {
            iterations,
            residual,
            ..
        } = r.solution
        else {
            panic!("not quasi-static")
        };
        eprintln!("{step}: {iterations} iterations, residual {residual:.3}");
        assert!(residual <= 1.0);
        for k in [0, 2] {
            let (a, b) = (&polach.wheelsets[k], &r.wheelsets[k]);
            assert!(
                (a.lateral - b.lateral).abs() < 0.05e-3,
                "{step}: {a:?}\n{b:?}"
            );
            assert!(
                (a.angle_of_attack - b.angle_of_attack).abs() < 0.3e-3,
                "{step}"
            );
        }
    }
}

/// The steady state is solved at least 1 m into the circular curve: with no settling distance
/// the rearmost wheelset's frame stood exactly on the transition's end (where the curvature's
/// rate jumps) and its forces moved by some 50 N; now `settle` 0 and 2 m solve the same point
/// (`curving::steady_at`) and agree, on tracks whose curves differ in length by 2 m.
#[test]
fn the_steady_state_is_solved_inside_the_curve_whatever_the_settling_distance() {
    let c = CurveCase {
        radius: 600.0,
        cant: 0.1,
        left: true,
        speed: 80.0 / 3.6,
    };
    let scene = polach_scene();
    let solve = |settle: f64| {
        let run = CurvingRun {
            settle,
            ..CurvingRun::default()
        };
        quasi_static_curving(&scene, &c, &run, &QuasiStatic::default())
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let (a, b) = (solve(0.0), solve(2.0));
    for (x, y) in a.wheelsets.iter().zip(&b.wheelsets) {
        eprintln!(
            "ΣY {:.2} / {:.2} N, y {:.4} / {:.4} mm",
            x.sum_y,
            y.sum_y,
            x.lateral * 1e3,
            y.lateral * 1e3
        );
        assert!((x.sum_y - y.sum_y).abs() < 1.0, "{x:?}\n{y:?}");
        assert!((x.lateral - y.lateral).abs() < 1e-7);
    }
}
