//! The warm-started travelling (`railsim_contact::warm`) against the cold one along pose
//! sequences like those of a time integration: a lateral sweep from the tread to the flange and
//! back with roll, yaw and a fast vertical oscillation, a jump, and a lift-off. Every patch must
//! come out as in a cold evaluation, and most evaluations must be warm.

use railsim_contact::{
    ContactModelKind, ContactWorkspace, PatchResult, Side, WarmStart, WheelsetPose,
};

use crate::common::{mbench_contact, rolling_30_m_s, tol_scale};

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
