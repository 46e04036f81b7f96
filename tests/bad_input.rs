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

/// The numbers a patch reports: forces, spin moment, peak pressure, size, penetration, angle.
fn patch_numbers(p: &railsim_contact::PatchResult) -> [f64; 9] {
    let f = &p.forces;
    [
        f.fn_,
        f.fx,
        f.fs,
        f.mz,
        f.p_max,
        f.length,
        f.width,
        p.penetration,
        p.contact_angle,
    ]
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
                        for v in patch_numbers(p) {
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
fn a_case_table_may_start_with_a_byte_order_mark() {
    let text = "\u{feff}side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\nleft,1,0,0,-4.3,1e4\n";
    let cases = parse_cases_csv(text, "bom.csv").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cases.len(), 1);
    assert!((cases[0].1.y_ws_mm - 1.0).abs() < 1e-15);
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

/// Every bad line of a case table is reported in one pass (each with its first problem), up to
/// `MAX_CASE_ERRORS`, then a count; it stopped at the first.
#[test]
fn every_bad_line_of_a_case_table_is_reported() {
    use railsim_contact::contact_format::MAX_CASE_ERRORS;
    let head = "side,y_ws_mm,yaw_ws_rad,roll_ws_rad,vpitch_rad_s,fz_target_N\n";
    let text = format!(
        "{head}left,1,0,0,-4.3,1e4\nright,abc,0,0,-4.3,1e4\nleft,2,0,0,-4.3,1e4\n\
         middle,1,0,0,-4.3,1e4\nleft,1,0,0,NaN,1e4\n"
    );
    let e = parse_cases_csv(&text, "cases.csv").unwrap_err();
    let msg = e.to_string();
    let lines: Vec<&str> = msg.lines().collect();
    assert_eq!(lines.len(), 3, "{msg}");
    assert!(
        lines[0].starts_with("cases.csv:3: column 'y_ws_mm'"),
        "{msg}"
    );
    assert!(lines[1].starts_with("cases.csv:5: column 'side'"), "{msg}");
    assert!(
        lines[2].starts_with("cases.csv:6: column 'vpitch_rad_s'"),
        "{msg}"
    );
    assert_eq!((e.line, e.more.len(), e.unreported), (3, 2, 0));
    // many bad lines: the first MAX_CASE_ERRORS, then how many more
    let many = format!(
        "{head}{}",
        "left,x,0,0,-4.3,1e4\n".repeat(MAX_CASE_ERRORS + 7)
    );
    let e = parse_cases_csv(&many, "m.csv").unwrap_err();
    assert_eq!((e.more.len() + 1, e.unreported), (MAX_CASE_ERRORS, 7));
    let msg = e.to_string();
    assert_eq!(msg.lines().count(), MAX_CASE_ERRORS + 1, "{msg}");
    assert!(msg.ends_with("m.csv: 7 more bad lines not shown"), "{msg}");
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

#[test]
fn yaw_beyond_the_locus_limit_is_an_error() {
    let c = mbench_contact(ContactModelKind::Polach, 1e-3);
    let limit = c.pair.locus.tan_yaw_max.atan();
    let mut ws = ContactWorkspace::new();
    let pose = |yaw| WheelsetPose {
        yaw,
        z: -0.3e-3,
        ..Default::default()
    };
    for yaw in [0.999 * limit, -0.999 * limit] {
        c.evaluate(Side::Right, &pose(yaw), &rolling(), &mut ws)
            .unwrap();
        assert!(!ws.patches.is_empty());
    }
    for yaw in [1.001 * limit, -0.1] {
        let e = c
            .evaluate(Side::Left, &pose(yaw), &rolling(), &mut ws)
            .unwrap_err();
        assert!(matches!(e, ContactError::YawBeyondLocus { .. }), "{e}");
        let msg = e.to_string();
        assert!(
            msg.contains("wheelset yaw") && msg.contains(&format!("{:.4} rad", limit)),
            "{msg}"
        );
    }
}

/// Found by random inputs: at these flange-climbing poses the neighbours of the deepest
/// travelled pair lay on the same side of it along the tangent, and the parabola through them
/// (the refinement of the rigid contact pair) panicked.
#[test]
fn a_deepest_pair_not_between_its_neighbours_is_not_refined() {
    let cases = [
        (
            ContactModelKind::Fastsim,
            0.2e-3,
            Side::Left,
            [
                0.01972142211278417,
                -0.0007074573300948641,
                -0.003902267627530022,
                0.025346054359885708,
            ],
        ),
        (
            ContactModelKind::Polach,
            0.5e-3,
            Side::Right,
            [
                -0.018661396198917803,
                -0.003740829183209676,
                0.0004009908702425555,
                -0.026812776029887114,
            ],
        ),
    ];
    for (model, step, side, [y, z, roll, yaw]) in cases {
        let mut opts = railsim_contact::ContactOptions {
            model,
            hertz_search: railsim_contact::HertzSearch::Travel,
            ..Default::default()
        };
        opts.travel.step = step;
        let c = railsim_contact::WheelRailContact::new(crate::common::mbench_pair(), opts).unwrap();
        let pose = WheelsetPose { y, z, roll, yaw };
        let vel = WheelsetVelocity {
            vx: 30.0,
            spin: 30.0 / 0.46,
            ..Default::default()
        };
        let mut ws = ContactWorkspace::new();
        // (no panic: a result or the absurd-penetration error of these 12 mm presses)
        match c.evaluate(side, &pose, &vel, &mut ws) {
            Ok(s) => assert!(s.force_track.iter().all(|f| f.is_finite())),
            Err(e) => assert!(matches!(e, ContactError::AbsurdPenetration { .. }), "{e}"),
        }
    }
}

/// Random poses and velocities far outside the running range (lateral ±20 mm, the wheel pressed
/// up to 4 mm in or lifted 2.4 mm, roll ±50 mrad, yaw up to the locus limit, any spin and
/// slip), every model and search, cold, warm-started and load-driven: each evaluation gives an
/// error or finite results, never a panic.
#[test]
fn random_inputs_give_errors_or_finite_results() {
    use railsim_contact::{ContactOptions, HertzSearch, Tangential, WarmStart, WheelRailContact};
    let cases = [
        (
            ContactModelKind::Polach,
            HertzSearch::Point,
            Tangential::Fastrip,
            1e-3,
            3000,
        ),
        (
            ContactModelKind::Polach,
            HertzSearch::Travel,
            Tangential::Fastrip,
            0.5e-3,
            1500,
        ),
        (
            ContactModelKind::Fastsim,
            HertzSearch::Point,
            Tangential::Fastrip,
            1e-3,
            1500,
        ),
        (
            ContactModelKind::Linear,
            HertzSearch::Point,
            Tangential::Fastrip,
            1e-3,
            1500,
        ),
        (
            ContactModelKind::Stripes,
            HertzSearch::Point,
            Tangential::Fastrip,
            1e-3,
            1500,
        ),
        (
            ContactModelKind::Stripes,
            HertzSearch::Point,
            Tangential::Fastsim,
            2e-3,
            500,
        ),
        (
            ContactModelKind::Stripes,
            HertzSearch::Point,
            Tangential::Exact,
            1e-3,
            20,
        ),
        (
            ContactModelKind::Halfspace,
            HertzSearch::Point,
            Tangential::Fastsim,
            1e-3,
            20,
        ),
    ];
    let mut rng = crate::common::Lcg(7);
    for (model, search, tangential, step, n) in cases {
        let mut opts = ContactOptions {
            model,
            hertz_search: search,
            tangential,
            ..Default::default()
        };
        opts.travel.step = step;
        let c = WheelRailContact::new(crate::common::mbench_pair(), opts).unwrap();
        let limit = c.pair.locus.tan_yaw_max.atan();
        let (mut ws, mut warm) = (ContactWorkspace::new(), WarmStart::new());
        let mut ok = 0;
        for k in 0..n {
            let pose = WheelsetPose {
                y: rng.range(-20e-3, 20e-3),
                z: rng.range(-4e-3, 2.4e-3),
                roll: rng.range(-50e-3, 50e-3),
                yaw: rng.range(-limit, limit),
            };
            let vel = WheelsetVelocity {
                vx: rng.range(1e-3, 100.0),
                vy: rng.range(-5.0, 5.0),
                vz: rng.range(-1.0, 1.0),
                roll_rate: rng.range(-2.5, 2.5),
                yaw_rate: rng.range(-2.5, 2.5),
                spin: rng.range(-120.0, 280.0),
            };
            let side = if k % 2 == 0 { Side::Left } else { Side::Right };
            let r = match k % 5 {
                0 => c.evaluate_with_load(side, &pose, &vel, rng.range(0.0, 200e3), 1e-6, &mut ws),
                1 | 2 => c.evaluate_warm(side, &pose, &vel, &mut warm, &mut ws),
                _ => c.evaluate(side, &pose, &vel, &mut ws),
            };
            let Ok(s) = r else { continue };
            ok += 1;
            let what = format!("{model:?} {search:?} {tangential:?} {side:?} {pose:?} {vel:?}");
            assert!(s.force_track.iter().all(|f| f.is_finite()), "{what}");
            for p in &ws.patches {
                let f = &p.forces;
                for v in patch_numbers(p) {
                    assert!(v.is_finite(), "{what}: {p:?}");
                }
                // Kalker's linear theory is not bounded by friction: at these creepages its
                // creep forces reach thousands of times the normal force, and their part along
                // the reported (reference-point) normal can outweigh it.
                if model != ContactModelKind::Linear {
                    assert!(f.fn_ > 0.0, "{what}: {p:?}");
                }
            }
        }
        // a good share of the poses are in contact within the limits
        assert!(
            ok * 4 > n,
            "{model:?} {search:?}: only {ok} of {n} evaluated"
        );
    }
}

/// One to three random edits of a profile file's lines: a line deleted, doubled, swapped with
/// another, cut short, a number replaced by NaN, ±inf, ±1e300, 0, a word or nothing, shifted by up
/// to 1 mm or scaled by up to 5e-4, the file cut off, or a line of control characters inserted.
fn mutate(text: &str, rng: &mut crate::common::Lcg) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let pick =
        |rng: &mut crate::common::Lcg, n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    for _ in 0..1 + pick(rng, 3) {
        if lines.is_empty() {
            break;
        }
        let i = pick(rng, lines.len());
        let mut tokens: Vec<String> = lines[i].split_whitespace().map(str::to_string).collect();
        let k = if tokens.is_empty() {
            None
        } else {
            Some(pick(rng, tokens.len()))
        };
        let number = k.and_then(|k| tokens[k].parse::<f64>().ok());
        match pick(rng, 9) {
            0 => {
                lines.remove(i);
            }
            1 => lines.insert(i, lines[i].clone()),
            2 => {
                let j = pick(rng, lines.len());
                lines.swap(i, j);
            }
            3 => {
                if let Some(k) = k {
                    let bad = ["NaN", "inf", "-inf", "1e300", "-1e300", "0", "x", ""];
                    tokens[k] = bad[pick(rng, bad.len())].to_string();
                    lines[i] = tokens.join(" ");
                }
            }
            4 => {
                let cut = pick(rng, lines[i].len() + 1);
                let cut = (0..=cut)
                    .rev()
                    .find(|&c| lines[i].is_char_boundary(c))
                    .unwrap_or(0);
                lines[i].truncate(cut);
            }
            5 | 6 => {
                if let (Some(k), Some(v)) = (k, number) {
                    tokens[k] = if pick(rng, 2) == 0 {
                        format!("{}", v + rng.range(-1.0, 1.0))
                    } else {
                        format!("{}", v * (1.0 + rng.range(-5e-4, 5e-4)))
                    };
                    lines[i] = tokens.join(" ");
                }
            }
            7 => lines.truncate(i),
            _ => lines.insert(i, "\u{0}\u{7f}é,,;;".to_string()),
        }
    }
    lines.join("\n")
}

/// Randomly damaged wheel and rail files (600 of each): every one is read, or rejected with an
/// error that names the file; every one read becomes a contact pair or an error naming the file;
/// every pair evaluates four poses with `stripes` and `polach` to finite forces or an error.
/// Before, a coordinate of 1e300 mm passed the reader and failed in the spline fit with a message
/// that named no file.
#[test]
fn damaged_profile_files_are_located_errors_or_work() {
    use railsim_contact::contact_format::manchester_benchmark_spec;
    use railsim_contact::{ContactOptions, WheelRailContact, WheelRailPair};
    use railsim_profile::{ProfileKind, parse_simpack};
    let read = |rel: &str| std::fs::read_to_string(crate::common::repo(rel)).unwrap();
    let wheel = read("vehicles/profiles/MBench_S1002_v3.prw");
    let rail = read("tracks/profiles/MBench_UIC60_v3.prr");
    let mut rng = crate::common::Lcg(11);
    let (mut read_ok, mut built, mut evaluated) = (0, 0, 0);
    for k in 0..1200 {
        let (w, r) = if k % 2 == 0 {
            (mutate(&wheel, &mut rng), rail.clone())
        } else {
            (wheel.clone(), mutate(&rail, &mut rng))
        };
        let name = if k % 2 == 0 { "w.prw" } else { "r.prr" };
        let profiles = parse_simpack(&w, "w.prw", ProfileKind::Wheel)
            .and_then(|wp| Ok((wp, parse_simpack(&r, "r.prr", ProfileKind::Rail)?)));
        let (wp, rp) = match profiles {
            Ok(p) => p,
            Err(e) => {
                assert!(e.to_string().starts_with(name), "{e}");
                continue;
            }
        };
        read_ok += 1;
        let pair = match WheelRailPair::new(&manchester_benchmark_spec(wp, rp)) {
            Ok(p) => p,
            Err(e) => {
                assert!(e.to_string().contains(name), "{e}");
                continue;
            }
        };
        built += 1;
        let mut ws = ContactWorkspace::new();
        for model in [ContactModelKind::Stripes, ContactModelKind::Polach] {
            let opts = ContactOptions {
                model,
                ..Default::default()
            };
            let c = WheelRailContact::new(pair.clone(), opts).unwrap();
            for (y, yaw) in [(0.0, 0.0), (5e-3, 0.005), (-5e-3, -0.005), (9e-3, 0.01)] {
                let pose = WheelsetPose {
                    y,
                    yaw,
                    ..Default::default()
                };
                let vel = crate::common::rolling_30_m_s();
                if let Ok(s) = c.evaluate_with_load(Side::Right, &pose, &vel, 50e3, 1e-6, &mut ws) {
                    assert!(s.force_track.iter().all(|f| f.is_finite()), "{k}: {pose:?}");
                    evaluated += 1;
                }
            }
        }
    }
    println!("{read_ok} of 1200 damaged files read, {built} pairs built, {evaluated} evaluations");
    assert!(read_ok > 150 && built > 150 && evaluated > 8 * 140);
}

#[test]
fn absurd_values_are_printed_short() {
    let c = mbench_contact(ContactModelKind::Polach, 1e-3);
    let mut ws = ContactWorkspace::new();
    let pose = WheelsetPose {
        roll: 1e300,
        ..Default::default()
    };
    let e = c
        .evaluate(Side::Left, &pose, &rolling(), &mut ws)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "wheelset roll [rad] = 1e300 is out of range: expected |roll| <= 0.2 rad"
    );
}

/// The pair's numbers are checked against plausible ranges: an infinite flange-back coordinate
/// used to pass and made `halfspace` allocate gigabytes before failing.
#[test]
fn implausible_pair_options_are_rejected() {
    use railsim_contact::contact_format::manchester_benchmark_spec;
    use railsim_contact::{PairSpec, WheelRailPair};
    use railsim_profile::{ProfileKind, read_simpack};
    let wheel = read_simpack(
        &crate::common::repo("vehicles/profiles/MBench_S1002_v3.prw"),
        ProfileKind::Wheel,
    )
    .unwrap();
    let rail = read_simpack(
        &crate::common::repo("tracks/profiles/MBench_UIC60_v3.prr"),
        ProfileKind::Rail,
    )
    .unwrap();
    let base = manchester_benchmark_spec(wheel, rail);
    assert!(WheelRailPair::new(&base).is_ok());
    type Spoil = fn(&mut PairSpec);
    let cases: [(&str, Spoil); 7] = [
        ("flange_back_y", |s| s.flange_back_y = f64::INFINITY),
        ("gauge", |s| s.gauge = 1e300),
        ("r0", |s| s.r0 = 46.0),
        ("flange_back_distance", |s| s.flange_back_distance = 0.0),
        ("gauge_depth", |s| s.gauge_depth = 0.2),
        ("inclination", |s| s.inclination = 0.5),
        ("curve_ds", |s| s.curve_ds = 1e-9),
    ];
    for (key, spoil) in cases {
        let mut spec = base.clone();
        spoil(&mut spec);
        let e = WheelRailPair::new(&spec).unwrap_err();
        assert!(
            matches!(&e, ContactError::BadOption { key: k, .. } if *k == key),
            "{key}: {e}"
        );
        assert!(e.to_string().len() < 200, "{e}");
    }
}

/// Polach's reduction factors and the falling friction out of their ranges are refused when
/// the contact is built, each by name (k_A in (0, 1], k_S in (0, k_A], A in [0, 1], B finite
/// and ≥ 0), never at an evaluation; so is a falling friction with the models that take
/// Coulomb friction or none (`linear`, `halfspace`, the exact tangential solution).
#[test]
fn polachs_parameters_out_of_range_are_refused() {
    use railsim_contact::{
        ContactOptions, FallingFriction, PolachAdhesion, Tangential, WheelRailContact,
    };
    let ok = PolachAdhesion::default();
    let coulomb = FallingFriction::default();
    let falling = FallingFriction {
        ratio: 0.4,
        decay: 0.2,
    };
    let polach = |polach, falling_friction| ContactOptions {
        model: ContactModelKind::Polach,
        polach,
        falling_friction,
        ..Default::default()
    };
    for (opts, key) in [
        (
            polach(PolachAdhesion { k_a: 0.0, ..ok }, coulomb),
            "polach k_a",
        ),
        (
            polach(PolachAdhesion { k_a: 1.5, ..ok }, coulomb),
            "polach k_a",
        ),
        (
            polach(PolachAdhesion { k_a: 0.3, k_s: 0.4 }, coulomb),
            "polach k_s",
        ),
        (
            polach(
                PolachAdhesion {
                    k_s: f64::NAN,
                    ..ok
                },
                coulomb,
            ),
            "polach k_s",
        ),
        (
            polach(
                ok,
                FallingFriction {
                    ratio: -0.1,
                    ..falling
                },
            ),
            "friction ratio at infinite slip A",
        ),
        (
            polach(
                ok,
                FallingFriction {
                    decay: f64::INFINITY,
                    ..falling
                },
            ),
            "friction decay B",
        ),
        (
            ContactOptions {
                model: ContactModelKind::Linear,
                falling_friction: falling,
                ..Default::default()
            },
            "falling friction",
        ),
        (
            ContactOptions {
                model: ContactModelKind::Halfspace,
                falling_friction: falling,
                ..Default::default()
            },
            "falling friction",
        ),
        (
            ContactOptions {
                tangential: Tangential::Exact,
                falling_friction: falling,
                ..Default::default()
            },
            "falling friction",
        ),
    ] {
        let what = format!(
            "{:?} {:?} {:?}",
            opts.model, opts.polach, opts.falling_friction
        );
        match WheelRailContact::new(crate::common::mbench_pair(), opts) {
            Err(ContactError::BadOption { key: k, .. }) => assert_eq!(k, key, "{what}"),
            other => panic!("{what}: {:?}", other.map(|_| ())),
        }
    }
    let good = polach(PolachAdhesion { k_a: 0.3, k_s: 0.1 }, falling);
    assert!(WheelRailContact::new(crate::common::mbench_pair(), good).is_ok());
    for model in [ContactModelKind::Fastsim, ContactModelKind::Stripes] {
        let opts = ContactOptions {
            model,
            falling_friction: falling,
            ..Default::default()
        };
        assert!(WheelRailContact::new(crate::common::mbench_pair(), opts).is_ok());
    }
}
