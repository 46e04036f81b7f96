//! The warm-started travelling (`railsim_contact::warm`) against the cold one along pose
//! sequences like those of a time integration: a lateral sweep from the tread to the flange and
//! back with roll, yaw and a fast vertical oscillation, a jump, and a lift-off. Every patch must
//! come out as in a cold evaluation, and most evaluations must be warm.

use railsim_contact::{
    ContactModelKind, ContactWorkspace, PatchResult, Side, WarmStart, WheelsetPose,
};

use crate::common::{Lcg, mbench_contact, rolling_30_m_s, tol_scale};

fn sorted(p: &[PatchResult]) -> Vec<PatchResult> {
    let mut p = p.to_vec();
    p.sort_by(|a, b| a.y_rail_profile.total_cmp(&b.y_rail_profile));
    p
}

/// Largest differences between two patch lists of the same length: forces relative to the
/// wheel's largest normal force, positions in metres.
fn diff(a: &[PatchResult], b: &[PatchResult]) -> (f64, f64) {
    let fmax = a.iter().map(|p| p.forces.fn_).fold(1.0, f64::max);
    let (mut df, mut dy) = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        for (x, y) in [
            (p.forces.fn_, q.forces.fn_),
            (p.forces.fx, q.forces.fx),
            (p.forces.fs, q.forces.fs),
        ] {
            df = df.max((x - y).abs() / fmax);
        }
        dy = dy.max((p.y_rail_profile - q.y_rail_profile).abs());
        dy = dy.max((p.penetration - q.penetration).abs());
    }
    (df, dy)
}

#[test]
fn warm_start_gives_the_cold_patches() {
    let contact = mbench_contact(ContactModelKind::Stripes, 1.0e-3);
    let vel = rolling_30_m_s();
    let n = 600;
    // yaw up to 3 mrad (straight track) and up to 12 mrad (angles of attack in curves, as in the
    // contact benchmark)
    for (side, yaw_amp) in [
        (Side::Right, 3e-3),
        (Side::Left, 3e-3),
        (Side::Right, 12e-3),
        (Side::Left, 12e-3),
    ] {
        let (mut ws_cold, mut ws_warm, mut ws_load) = (
            ContactWorkspace::new(),
            ContactWorkspace::new(),
            ContactWorkspace::new(),
        );
        let mut warm = WarmStart::new();
        let (mut worst_f, mut worst_y) = (0.0f64, 0.0f64);
        let (mut two_patch, mut lifted) = (0, 0);
        for k in 0..n {
            let t = k as f64 / n as f64;
            // a sweep to 8 mm toward each flange (flange contact on the right wheel at
            // y < -6.5 mm, on the left at y > 6.5 mm), with a jump of 1.5 mm at k = 300
            let jump = if k >= 300 { 1.5e-3 } else { 0.0 };
            let mut pose = WheelsetPose {
                y: 8.0e-3 * (2.0 * std::f64::consts::PI * t).sin() + jump,
                z: 0.0,
                roll: 1e-3 * (6.0 * t).sin(),
                yaw: yaw_amp * (5.0 * t).cos(),
            };
            // the height that carries 50 kN (cold, its own workspace), plus a 150 Hz-like
            // vertical oscillation of 15 µm; lifted by 0.5 mm for 20 poses (no contact)
            let s = contact
                .evaluate_with_load(side, &pose, &vel, 50e3, 1e-8, &mut ws_load)
                .unwrap_or_else(|e| panic!("{side:?} pose {k} {pose:?}: {e}"));
            pose.z = s.z + 15e-6 * (k as f64 * 0.9).sin();
            if (450..470).contains(&k) {
                pose.z += 0.5e-3;
            }
            contact.evaluate(side, &pose, &vel, &mut ws_cold).unwrap();
            let s = contact
                .evaluate_warm(side, &pose, &vel, &mut warm, &mut ws_warm)
                .unwrap();
            // the first evaluation and the 1.5 mm jump (over the 1 mm limit) are travelled cold
            if k == 0 || k == 300 {
                assert!(
                    !s.travel.warm,
                    "{side:?} pose {k}: a cold travelling expected"
                );
            }
            let (a, b) = (sorted(&ws_cold.patches), sorted(&ws_warm.patches));
            assert_eq!(
                a.len(),
                b.len(),
                "{side:?} pose {k} (y = {:.3} mm): {} cold patches, {} warm",
                pose.y * 1e3,
                a.len(),
                b.len()
            );
            two_patch += usize::from(a.len() >= 2);
            lifted += usize::from(a.is_empty());
            let (df, dy) = diff(&a, &b);
            worst_f = worst_f.max(df);
            worst_y = worst_y.max(dy);
        }
        eprintln!(
            "{side:?}, yaw up to {:.0} mrad: warm {} cold {}, worst force difference {worst_f:.2e} of Fn, position \
             {worst_y:.2e} m, {two_patch} poses with two patches, {lifted} lifted",
            yaw_amp * 1e3,
            warm.warm_count,
            warm.cold_count
        );
        assert!(two_patch > 10, "the sweep must reach two-patch contact");
        assert!(lifted >= 20, "the lift-off must leave no patch");
        assert!(
            worst_f < 1e-6 * tol_scale(),
            "forces differ by {worst_f:.3e} of Fn"
        );
        assert!(
            worst_y < 1e-9 * tol_scale(),
            "positions differ by {worst_y:.3e} m"
        );
        // the jump and the first evaluation are cold; the rest mostly warm
        assert!(
            warm.warm_count as f64 > 0.8 * n as f64,
            "only {} of {n} warm",
            warm.warm_count
        );
    }
}

/// The cold travelling restricted to windows around the broad phase's candidates (what
/// `evaluate` does without a warm start, `railsim_contact::point::travel_windows`) against the
/// travelling of the whole profile (what a warm start's first, cold evaluation does) on random
/// poses over tread, flange root and flange, both wheels, yaw to ±25 mrad, roll to ±15 mrad,
/// 2–120 kN, every tenth pose pressed 1 mm deeper (zones past the broad phase's depth: the
/// whole profile is travelled), every tenth 0.4 mm deeper, and every tenth lifted off. Both must give the same patches up
/// to where the pairs' Newton iterations started (as the warm start: the same anchored rail
/// nodes and subdivision, §3.1).
#[test]
fn windowed_cold_travelling_gives_the_full_travellings_patches() {
    let contact = mbench_contact(ContactModelKind::Stripes, 1.0e-3);
    let vel = rolling_30_m_s();
    let mut rng = Lcg(4242);
    let mut rnd = |a: f64, b: f64| rng.range(a, b);
    let (mut ws_a, mut ws_b) = (ContactWorkspace::new(), ContactWorkspace::new());
    let (mut worst_f, mut worst_y) = (0.0f64, 0.0f64);
    let (mut windowed, mut full, mut compared, mut two) = (0, 0, 0, 0);
    for k in 0..400 {
        let side = if k % 2 == 0 { Side::Left } else { Side::Right };
        let mut pose = WheelsetPose {
            y: rnd(-10e-3, 10e-3),
            yaw: rnd(-25e-3, 25e-3),
            roll: rnd(-15e-3, 15e-3),
            ..Default::default()
        };
        let fz = rnd(2e3, 120e3);
        let Ok(s) = contact.evaluate_with_load(side, &pose, &vel, fz, 1e-6, &mut ws_a) else {
            continue;
        };
        pose.z = s.z
            + match k % 10 {
                5 => 0.3e-3,
                0 => -1.0e-3,
                2 => -0.4e-3,
                _ => 0.0,
            };
        let (Ok(a), Ok(b)) = (
            contact.evaluate(side, &pose, &vel, &mut ws_a),
            contact.evaluate_warm(side, &pose, &vel, &mut WarmStart::new(), &mut ws_b),
        ) else {
            panic!("pose {k} {side:?} {pose:?}: one evaluation failed");
        };
        if a.travel.pairs < b.travel.pairs {
            windowed += 1;
        } else {
            full += 1;
        }
        let (pa, pb) = (sorted(&ws_a.patches), sorted(&ws_b.patches));
        assert_eq!(
            pa.len(),
            pb.len(),
            "pose {k} {side:?} {pose:?}: {a:?} / {b:?}"
        );
        let (df, dy) = diff(&pa, &pb);
        assert!(
            df < 1e-8 && dy < 1e-9,
            "pose {k} {side:?} {pose:?}: forces {df:e} of Fn, positions {dy:e} m apart"
        );
        (worst_f, worst_y) = (worst_f.max(df), worst_y.max(dy));
        compared += 1;
        two += usize::from(pa.len() > 1);
    }
    eprintln!(
        "{compared} poses ({windowed} windowed, {full} travelled whole, {two} with two or more \
         patches): forces within {worst_f:.1e} of Fn, positions within {worst_y:.1e} m"
    );
    assert!(compared > 350 && windowed > 250 && full > 30 && two >= 3);
}
