//! The seed's travelling: its error (Fig. 10) and step-size convergence (Tables 1–2), on the
//! benchmark wheel at the right wheel's y = 5 mm position of case A-2.2 (tread and flange-root
//! patches at once) and y = 6.5 mm (flange).

use railsim_contact::contact_format::ContactCase;
use railsim_contact::{ContactModelKind, ContactWorkspace, PatchResult, Side};

use crate::common::{mbench_contact_with, tol_scale};

/// Right wheel of the benchmark at y = 5 mm (yaw 12 mrad) at CONTACT's converged height.
fn case(y_mm: f64, yaw: f64, roll: f64, z_mm: f64, vpitch: f64) -> ContactCase {
    ContactCase {
        side: Side::Right,
        y_ws_mm: y_mm,
        yaw_ws_rad: yaw,
        roll_ws_rad: roll,
        vpitch_rad_s: vpitch,
        z_ws_mm: Some(z_mm),
        fz_target_n: None,
        speed_mm_s: 2000.0,
    }
}

fn y5() -> ContactCase {
    case(5.0, 0.012, -0.0003554, 0.001519237626, -4.3353637)
}

fn y65() -> ContactCase {
    case(6.5, 0.0156, -0.004376, -3.046792175, -4.3293718)
}

/// The seed's scheme: a fixed step inside the zones (no narrow-zone refinement).
fn solve(c: &ContactCase, step: f64, ws: &mut ContactWorkspace) -> Vec<PatchResult> {
    let contact = mbench_contact_with(ContactModelKind::Stripes, step, 0);
    let (pose, vel) = c.to_railsim();
    contact.evaluate(c.side, &pose, &vel, ws).unwrap();
    let mut p = ws.patches.clone();
    p.sort_by(|a, b| a.y_rail_profile.total_cmp(&b.y_rail_profile));
    p
}

#[test]
fn travelling_error_below_seed_bounds_at_0_1_mm() {
    let mut ws = ContactWorkspace::new();
    // y = 5: flange root (steep, concave-convex) and tread patches.
    let patches = solve(&y5(), 0.1e-3, &mut ws);
    assert_eq!(patches.len(), 2, "tread and flange-root patches expected");
    let (flange, tread) = (&patches[0], &patches[1]);
    eprintln!(
        "travel error at 0.1 mm: tread {:.2e} rad, flange root {:.2e} rad",
        tread.travel_error, flange.travel_error
    );
    assert!(
        tread.travel_error < 1e-5 * tol_scale(),
        "tread {:.3e}",
        tread.travel_error
    );
    assert!(
        flange.travel_error < 1e-3 * tol_scale(),
        "flange root {:.3e}",
        flange.travel_error
    );
    // y = 6.5: the flange flank.
    let patches = solve(&y65(), 0.1e-3, &mut ws);
    let flank = patches
        .iter()
        .max_by(|a, b| a.forces.fn_.total_cmp(&b.forces.fn_))
        .unwrap();
    eprintln!(
        "travel error at 0.1 mm: flange flank {:.2e} rad",
        flank.travel_error
    );
    assert!(flank.travel_error < 1e-3 * tol_scale());
    // The seed's Fig. 10 also shows the 0.5 mm step. Our correction is a Newton step with the
    // curvature terms, so at 0.5 mm the error is already far below the seed's bounds (reported,
    // and held to the same bounds).
    let coarse = solve(&y5(), 0.5e-3, &mut ws);
    eprintln!(
        "travel error at 0.5 mm: tread {:.2e}, flange root {:.2e}",
        coarse[1].travel_error, coarse[0].travel_error
    );
    assert!(
        coarse[1].travel_error < 1e-5 * tol_scale() && coarse[0].travel_error < 1e-3 * tol_scale()
    );
}

#[test]
fn step_refinement_converges_like_seed_tables_1_2() {
    let mut ws = ContactWorkspace::new();
    let fine = solve(&y5(), 0.01e-3, &mut ws);
    assert_eq!(fine.len(), 2);
    let mut prev: Option<[[f64; 3]; 2]> = None;
    let mut first: Option<[[f64; 3]; 2]> = None;
    eprintln!("step mm | patch | position err mm | angle err rad | Fn err %");
    for step_mm in [0.5, 0.2, 0.1] {
        let p = solve(&y5(), step_mm * 1e-3, &mut ws);
        assert_eq!(p.len(), 2, "two patches at step {step_mm}");
        let mut errs = [[0.0; 3]; 2];
        for k in 0..2 {
            errs[k] = [
                (p[k].y_rail_profile - fine[k].y_rail_profile).abs() * 1e3,
                (p[k].contact_angle - fine[k].contact_angle).abs(),
                (p[k].forces.fn_ / fine[k].forces.fn_ - 1.0).abs() * 100.0,
            ];
            eprintln!(
                "{step_mm:7} | {} | {:15.3e} | {:13.2e} | {:8.4} | delta0 {:.6} vs {:.6} um",
                if k == 0 { "flange root" } else { "tread      " },
                errs[k][0],
                errs[k][1],
                errs[k][2],
                p[k].penetration * 1e6,
                fine[k].penetration * 1e6
            );
        }
        if let Some(pe) = prev {
            // Position and angle errors fall at every refinement (allow round-off noise). The
            // Fn error is compared between 0.5 and 0.1 mm below (the statement): at a
            // coarse step it depends on where the first pair falls in the narrow flange-root
            // zone, so it need not fall monotonically through 0.2 mm.
            // Noise floors: 10 nm in position and 1e-7 rad in angle, the level at which the
            // 0.01 mm reference solution itself is no longer converged (the tread's errors at
            // 0.2 and 0.1 mm are 1.8 and 5.4 nm, 4e-8 and 6e-8 rad).
            let floor = [1e-5, 1e-7];
            for k in 0..2 {
                for q in 0..2 {
                    assert!(
                        errs[k][q] <= pe[k][q] * 1.05 + floor[q],
                        "error {q} of patch {k} grew from {} to {} at step {step_mm}",
                        pe[k][q],
                        errs[k][q]
                    );
                }
            }
        }
        if step_mm == 0.5 {
            first = Some(errs);
        }
        if step_mm == 0.1 {
            let f = first.expect("0.5 mm ran first");
            for k in 0..2 {
                for q in 0..3 {
                    assert!(
                        errs[k][q] < f[k][q],
                        "error {q} of patch {k}: {} at 0.1 mm, not below {} at 0.5 mm",
                        errs[k][q],
                        f[k][q]
                    );
                }
            }
        }
        prev = Some(errs);
    }
    // At 0.1 mm the tread patch is within 0.1 % of the 0.01 mm solution (position relative to
    // the patch width, angle relative to itself, Fn relative).
    let p = solve(&y5(), 0.1e-3, &mut ws);
    let t = (&p[1], &fine[1]);
    let pos_rel = (t.0.y_rail_profile - t.1.y_rail_profile).abs() / t.1.forces.width;
    let ang_rel = (t.0.contact_angle / t.1.contact_angle - 1.0).abs();
    let fn_rel = (t.0.forces.fn_ / t.1.forces.fn_ - 1.0).abs();
    eprintln!(
        "tread at 0.1 mm: position {pos_rel:.2e}, angle {ang_rel:.2e}, Fn {fn_rel:.2e} (relative)"
    );
    let tol = 1e-3 * tol_scale();
    assert!(pos_rel < tol && ang_rel < tol && fn_rel < tol);
}

/// The travelling tries longer steps than the safe step and keeps them only under the curvature
/// certificate (docs/models/contact.md §3). Against a brute-force travelling (0.05 mm everywhere,
/// no longer tries possible: the base step is the largest step), no patch carrying more than 1 %
/// of the wheel load may be missed, over a sweep of lateral positions and yaw angles at 55 kN
/// (wide patches, flange contact) on both wheels.
#[test]
fn longer_tried_steps_skip_no_patch() {
    use railsim_contact::{WheelsetPose, WheelsetVelocity};
    let fast = crate::common::mbench_contact(ContactModelKind::Stripes, 0.5e-3);
    let mut brute = crate::common::mbench_contact(ContactModelKind::Stripes, 0.05e-3);
    brute.opts.travel.max_step = 0.05e-3;
    let mut ws = ContactWorkspace::new();
    let vel = WheelsetVelocity {
        vx: 30.0,
        spin: 30.0 / 0.46,
        ..Default::default()
    };
    let mut checked = 0;
    let mut patches = 0;
    for side in [Side::Left, Side::Right] {
        for yaw in [0.0, 0.01] {
            for k in 0..=28 {
                let y = -5e-3 + k as f64 * 0.5e-3;
                let pose = WheelsetPose {
                    y,
                    yaw,
                    ..Default::default()
                };
                let s = brute
                    .evaluate_with_load(side, &pose, &vel, 55e3, 1e-4, &mut ws)
                    .unwrap();
                let reference: Vec<(f64, f64)> = ws
                    .patches
                    .iter()
                    .map(|p| (p.y_rail_profile, p.forces.fn_))
                    .collect();
                let total: f64 = reference.iter().map(|r| r.1).sum();
                let at = WheelsetPose { z: s.z, ..pose };
                fast.evaluate(side, &at, &vel, &mut ws).unwrap();
                for &(yr, fn_) in &reference {
                    if fn_ < 0.01 * total {
                        continue;
                    }
                    patches += 1;
                    let found = ws
                        .patches
                        .iter()
                        .any(|p| (p.y_rail_profile - yr).abs() < 1.5e-3);
                    assert!(
                        found,
                        "{side:?} y {:.1} mm yaw {yaw}: patch at {:.2} mm on the rail with {:.0} N \
                         (of {:.0} N) missed by the default travelling",
                        y * 1e3,
                        yr * 1e3,
                        fn_,
                        total
                    );
                }
                checked += 1;
            }
        }
    }
    eprintln!("{checked} poses, {patches} patches above 1 % of the load, none missed");
    assert_eq!(checked, 116);
}

/// Regression (found in a 60 s run of issue 3's case): a tread run split into two zones that are
/// both refined to at least 12 pairs met at one rail node, which was then recorded twice; the
/// zero-width segment gave an infinite STRIPES load. The pairs must be strictly ordered on the
/// rail and the patch loads must agree with a finer step.
#[test]
fn adjacent_refined_zones_share_no_pair() {
    use railsim_contact::{
        ContactOptions, WheelRailContact, WheelRailPair, WheelsetPose, WheelsetVelocity,
    };
    let spec = crate::common::standard_spec();
    let pose = WheelsetPose {
        y: 4.952_128_143_583_95e-3,
        z: -0.041_263_927_736_956_42e-3,
        roll: 0.361_842_082_064_898_8e-3,
        yaw: 0.460_273_341_853_849_95e-3,
    };
    let vel = WheelsetVelocity {
        vx: 55.0,
        spin: 55.0 / 0.46,
        ..Default::default()
    };
    let fn_at = |step: f64| {
        let mut opts = ContactOptions::default();
        opts.travel.step = step;
        let c = WheelRailContact::new(WheelRailPair::new(&spec).unwrap(), opts).unwrap();
        let mut ws = ContactWorkspace::new();
        c.evaluate(Side::Left, &pose, &vel, &mut ws).unwrap();
        for w in ws.pairs.windows(2) {
            assert!(
                w[1].s_r > w[0].s_r,
                "pairs out of order at s_r = {} mm",
                w[1].s_r * 1e3
            );
        }
        let mut f: Vec<f64> = ws.patches.iter().map(|p| p.forces.fn_).collect();
        f.sort_by(f64::total_cmp);
        f
    };
    // Both zones are refined (at 1 mm to a grid that puts 12 pairs across each patch's contact),
    // and the loads must agree with a fine step: before the fix the shared node made one patch
    // 74 kN instead of 26 kN. Measured: 28.3 and 32.5 kN at 1 mm, 28.5 and 32.7 kN at 0.05 mm
    // (before the contact-based refinement and the wells, the flange-root patch converged
    // slowly: 30.4 kN at 1 mm, 27.3 kN at 0.05 mm).
    let (coarse, fine) = (fn_at(1.0e-3), fn_at(0.05e-3));
    eprintln!(
        "patch loads: 1 mm {coarse:.0?}, 0.5 mm {:.0?}, 0.1 mm {:.0?}, 0.05 mm {fine:.0?}",
        fn_at(0.5e-3),
        fn_at(0.1e-3),
    );
    assert_eq!(coarse.len(), 2, "{coarse:?}");
    assert_eq!(fine.len(), 2, "{fine:?}");
    for (c, f) in coarse.iter().zip(&fine) {
        assert!(
            c.is_finite() && (c / f - 1.0).abs() < 0.02,
            "patch load {c:.0} N at 1 mm vs {f:.0} N at 0.05 mm"
        );
    }
}
