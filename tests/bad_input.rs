//! Bad input gives clear errors, never a panic or NaN; no contact is not an error.

use railsim_contact::contact_format::parse_cases_csv;
use railsim_contact::{
    ContactError, ContactModelKind, ContactWorkspace, Side, WheelsetPose, WheelsetVelocity,
};

use crate::common::mbench_contact;

fn rolling() -> WheelsetVelocity {
    WheelsetVelocity {
        vx: 2.0,
        spin: 2.0 / 0.46,
        ..Default::default()
    }
}

#[test]
fn lifted_wheel_has_no_patches() {
    let c = mbench_contact(ContactModelKind::Stripes, 0.2e-3);
    let mut ws = ContactWorkspace::new();
    let pose = WheelsetPose {
        z: 5e-3,
        ..Default::default()
    };
    for side in [Side::Left, Side::Right] {
        let s = c.evaluate(side, &pose, &rolling(), &mut ws).unwrap();
        assert_eq!(s.n_patches, 0);
        assert!(ws.patches.is_empty());
        assert_eq!(s.force_track, [0.0; 3]);
    }
}

#[test]
fn absurd_penetration_is_an_error() {
    let c = mbench_contact(ContactModelKind::Stripes, 0.2e-3);
    let mut ws = ContactWorkspace::new();
    let pose = WheelsetPose {
        z: -6e-3,
        ..Default::default()
    };
    match c.evaluate(Side::Left, &pose, &rolling(), &mut ws) {
        Err(ContactError::AbsurdPenetration {
            found_mm, limit_mm, ..
        }) => {
            assert!(found_mm > 5.0 && limit_mm == 5.0);
        }
        other => panic!("expected AbsurdPenetration, got {other:?}"),
    }
}

#[test]
fn non_finite_inputs_are_errors() {
    let c = mbench_contact(ContactModelKind::Stripes, 0.2e-3);
    let mut ws = ContactWorkspace::new();
    for bad in [f64::NAN, f64::INFINITY] {
        let pose = WheelsetPose {
            y: bad,
            ..Default::default()
        };
        let e = c
            .evaluate(Side::Left, &pose, &rolling(), &mut ws)
            .unwrap_err();
        assert!(matches!(e, ContactError::NonFinite { .. }), "{e}");
        let mut vel = rolling();
        vel.spin = bad;
        let e = c
            .evaluate(Side::Left, &WheelsetPose::default(), &vel, &mut ws)
            .unwrap_err();
        assert!(e.to_string().contains("spin"), "{e}");
        let e = c
            .evaluate_with_load(
                Side::Left,
                &WheelsetPose::default(),
                &rolling(),
                bad,
                1e-6,
                &mut ws,
            )
            .unwrap_err();
        assert!(e.to_string().contains("vertical load"), "{e}");
    }
    // Zero speed cannot give creepages.
    let vel = WheelsetVelocity::default();
    let e = c
        .evaluate(Side::Left, &WheelsetPose::default(), &vel, &mut ws)
        .unwrap_err();
    assert!(e.to_string().contains("forward speed"), "{e}");
}

#[test]
fn results_are_finite_over_a_sweep() {
    // A sweep over lateral position, yaw and roll, both wheels, all models but the reference:
    // every number finite, forces compressive.
    for model in [
        ContactModelKind::Polach,
        ContactModelKind::Fastsim,
        ContactModelKind::Stripes,
    ] {
        let c = mbench_contact(model, 0.2e-3);
        let mut ws = ContactWorkspace::new();
        for iy in -12..=12 {
            for yaw in [-0.02, 0.0, 0.02] {
                let pose = WheelsetPose {
                    y: iy as f64 * 0.8e-3,
                    yaw,
                    roll: 0.002 * yaw,
                    ..Default::default()
                };
                for side in [Side::Left, Side::Right] {
                    let s = c
                        .evaluate_with_load(side, &pose, &rolling(), 50e3, 1e-6, &mut ws)
                        .unwrap_or_else(|e| {
                            panic!("{model:?} y={} yaw={yaw} {side:?}: {e}", pose.y)
                        });
                    assert!(s.force_track.iter().all(|f| f.is_finite()));
                    for p in &ws.patches {
                        let f = &p.forces;
                        for v in [
                            f.fn_,
                            f.fx,
                            f.fs,
                            f.mz,
                            f.p_max,
                            f.length,
                            f.width,
                            p.penetration,
                            p.contact_angle,
                        ] {
                            assert!(v.is_finite(), "{model:?} y={} yaw={yaw}: {p:?}", pose.y);
                        }
                        assert!(f.fn_ > 0.0);
                    }
                }
            }
        }
    }
}

#[test]
fn case_table_errors_name_line_and_column() {
    let e = parse_cases_csv("side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\nleft,1,0,0,-4.3,1e4\nright,abc,0,0,-4.3,1e4\n", "cases.csv").unwrap_err();
    assert_eq!(e.line, 3);
    assert!(e.to_string().starts_with("cases.csv:3:"), "{e}");
    assert!(
        e.to_string().contains("y_ws_mm") && e.to_string().contains("abc"),
        "{e}"
    );
    let e = parse_cases_csv(
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s\nleft,1,0,0,-4.3\n",
        "c.csv",
    )
    .unwrap_err();
    assert!(e.to_string().contains("fz_target_N or z_ws_mm"), "{e}");
    let e = parse_cases_csv(
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,z_ws_mm\nmiddle,1,0,0,-4.3,0.1\n",
        "c.csv",
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("left or right") && e.line == 2,
        "{e}"
    );
    let e = parse_cases_csv(
        "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,z_ws_mm\nleft,1,0,0,NaN,0.1\n",
        "c.csv",
    )
    .unwrap_err();
    assert!(e.to_string().contains("finite"), "{e}");
}

#[test]
fn bad_options_are_rejected() {
    let e = ContactModelKind::from_name("exact").unwrap_err();
    assert!(
        e.to_string()
            .contains("linear, polach, fastsim, stripes, halfspace"),
        "{e}"
    );
    let mut opts = railsim_contact::ContactOptions::default();
    opts.travel.step = 0.0;
    let e = railsim_contact::WheelRailContact::new(crate::common::mbench_pair(), opts).unwrap_err();
    assert!(e.to_string().contains("step"), "{e}");
}

#[test]
fn extremes_of_load_and_step_stay_finite_and_monotone() {
    // Loads from 10 N to 300 kN and steps from 0.02 to 2 mm: every result finite, penetration
    // growing with the load, and the vertical force reached.
    for (model, step) in [
        (ContactModelKind::Stripes, 0.02e-3),
        (ContactModelKind::Stripes, 2.0e-3),
        (ContactModelKind::Fastsim, 2.0e-3),
        (ContactModelKind::Polach, 0.5e-3),
    ] {
        let c = mbench_contact(model, step);
        let mut ws = ContactWorkspace::new();
        for (y, yaw) in [(0.0, 0.0), (-3e-3, -0.007), (-7e-3, -0.017)] {
            let pose = WheelsetPose {
                y,
                yaw,
                ..Default::default()
            };
            let mut last_pen = 0.0;
            for load in [10.0, 1e3, 1e5, 3e5] {
                let s = c
                    .evaluate_with_load(Side::Left, &pose, &rolling(), load, 1e-6, &mut ws)
                    .unwrap_or_else(|e| panic!("{model:?} step {step} y {y} load {load}: {e}"));
                assert!(
                    (s.force_track[2] - load).abs() <= 1e-3 * load + s.load_residual.abs(),
                    "{model:?} load {load}: {}",
                    s.force_track[2]
                );
                let pen = ws.patches.iter().map(|p| p.penetration).fold(0.0, f64::max);
                assert!(
                    pen.is_finite() && pen > last_pen,
                    "{model:?} step {step} y {y}: pen {pen} after {last_pen}"
                );
                last_pen = pen;
                for p in &ws.patches {
                    let f = &p.forces;
                    assert!(
                        [f.fn_, f.fx, f.fs, f.mz, f.p_max, f.width, f.length]
                            .iter()
                            .all(|v| v.is_finite())
                    );
                }
            }
        }
    }
}
