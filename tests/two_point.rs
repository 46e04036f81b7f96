//! Two-point contact of STRIPES: a flange-root and a flange patch on the same wheel.
//!
//! In a tight curve the leading outer wheel runs in two-point contact at the R13 flange root and
//! on the 70° flank, whose normals differ by half a radian. Until the wells of a run became
//! STRIPES patches (docs/models/contact.md §4.1) the two were one zone or two depending on a
//! threshold on the hump between them, the zone's deepest pair set the virtual penetration of
//! both, and the strips' spin slip was counted from the patch's reference point: along a lateral
//! sweep the lateral force jumped by −38 % where the zone split and the longitudinal force by
//! +85 % where the deepest pair changed wells, and the Manchester vehicle bounced its leading
//! wheels off the rail through a 150 m curve at 40 km/h (Q up to 374 kN; docs/validation.md §6).

use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, Side, Tangential, WheelRailContact,
    WheelRailPair, WheelsetPose, WheelsetVelocity,
};

use crate::common::{
    mbench_contact, mbench_contact_with, rolling_30_m_s, standard_spec, tol_scale,
};

/// S1002 on UIC60 1:40, gauge 1435 mm, flange-back 1360 mm (`railsim contact`'s defaults).
fn standard_contact(model: ContactModelKind, step: f64) -> WheelRailContact {
    let mut opts = ContactOptions {
        model,
        ..Default::default()
    };
    opts.travel.step = step;
    WheelRailContact::new(WheelRailPair::new(&standard_spec()).unwrap(), opts).unwrap()
}

/// The right wheel at 14.7 mrad angle of attack (the leading wheelset of the Manchester vehicle
/// in the 150 m curve), swept 0.16 mm into flange contact at fixed height in 2 µm steps: the
/// flange patch appears beside the flange-root patch and both grow to 100–170 kN. Flange contact
/// is stiff (the force grows by up to 8 % of itself per step), so a jump is told from a steep
/// rise by its neighbours: no step of a force component may exceed three times the larger of the
/// two steps beside it (plus 0.2 % of |F|). The jumps this catches were −9 kN in Fy against
/// neighbouring steps of about +1 kN (the split threshold) and +20 kN in Fx (the deepest pair
/// changing wells).
#[test]
fn two_point_flange_contact_is_continuous_in_the_lateral_position() {
    assert_continuous_sweep(ContactModelKind::Stripes);
}

/// The same sweep with the half-space model, whose zones are cut into wells as STRIPES' are
/// (docs/models/contact.md §4.1): before, it solved the flange-root/flank run in one plane at its
/// deepest pair, and its lateral force jumped from 41.5 to 144 kN between y = −6.612 and −6.620 mm
/// where the deepest pair changed wells.
#[test]
fn half_space_two_point_contact_is_continuous_in_the_lateral_position() {
    assert_continuous_sweep(ContactModelKind::Halfspace);
}

fn assert_continuous_sweep(model: ContactModelKind) {
    let contact = standard_contact(model, 1e-3);
    let vel = WheelsetVelocity {
        vx: 11.11,
        spin: 11.11 / 0.46,
        ..Default::default()
    };
    let mut ws = ContactWorkspace::new();
    let mut forces = Vec::new();
    let mut two = 0;
    for k in 0..=80 {
        let pose = WheelsetPose {
            y: -6.50e-3 - k as f64 * 2e-6,
            z: 0.70e-3,
            roll: 0.0,
            yaw: -14.7e-3,
        };
        let s = contact.evaluate(Side::Right, &pose, &vel, &mut ws).unwrap();
        two += usize::from(ws.patches.len() == 2);
        forces.push(s.force_track);
    }
    let (mut worst, mut at) = (0.0f64, 0);
    for k in 1..forces.len() - 1 {
        let scale = forces[k].iter().map(|v| v * v).sum::<f64>().sqrt();
        for c in 0..3 {
            let step = |j: usize| (forces[j + 1][c] - forces[j][c]).abs();
            let beside = if k + 1 < forces.len() - 1 {
                step(k - 1).max(step(k + 1))
            } else {
                step(k - 1)
            };
            let r = step(k) / (3.0 * beside + 2e-3 * scale);
            if r > worst {
                (worst, at) = (r, k);
            }
        }
    }
    eprintln!(
        "{}: largest step against three times its neighbours: {worst:.2} at y = {:.3} mm; {two} of \
         81 poses with two patches",
        model.name(),
        -6.50 - at as f64 * 2e-3
    );
    assert!(two > 40, "two-point contact expected, {two} poses");
    assert!(
        worst < 1.0 * tol_scale(),
        "a force component jumps at y = {:.3} mm ({worst:.2} times the bound)",
        -6.50 - at as f64 * 2e-3
    );
}

/// A flange contact at 50 kN (the left wheel of the benchmark profiles 6.4 mm toward its flange):
/// the zone is 12–20 pairs wide at the default 1 mm step but its contact, where the
/// interpenetration exceeds (1 − ε) δ0, only a third of that. When narrow zones were refined by
/// their pair count, the 1 mm step carried 63–67 kN here where 0.1 mm gives 46–50 kN (+35 %), and
/// the load jumped by 24 % where the zone fell below 12 pairs (the load iteration of
/// `warm_start_gives_the_cold_patches` then failed to converge). Refined by the pairs in contact,
/// the 1 mm step is within 7 % of 0.1 mm and continuous.
#[test]
fn a_flange_patch_is_resolved_by_the_pairs_in_its_contact() {
    let vel = rolling_30_m_s();
    let loads = |step: f64| -> Vec<f64> {
        let contact = mbench_contact(ContactModelKind::Stripes, step);
        let mut ws = ContactWorkspace::new();
        (0..12)
            .map(|i| {
                let pose = WheelsetPose {
                    y: 6.422_539_801_528_917e-3,
                    z: 0.385e-3 + i as f64 * 1.5e-6,
                    roll: 0.777_071_747_526_823_9e-3,
                    yaw: 2.212_031_161_239_859e-3,
                };
                contact
                    .evaluate(Side::Left, &pose, &vel, &mut ws)
                    .unwrap()
                    .force_track[2]
            })
            .collect()
    };
    let (coarse, fine) = (loads(1e-3), loads(0.1e-3));
    eprintln!("Fz at 1 mm {coarse:.0?}\nFz at 0.1 mm {fine:.0?}");
    for (i, (c, f)) in coarse.iter().zip(&fine).enumerate() {
        assert!(
            (c / f - 1.0).abs() < 0.10 * tol_scale(),
            "pose {i}: {c:.0} N at 1 mm against {f:.0} N at 0.1 mm"
        );
    }
    for w in coarse.windows(2) {
        assert!(
            (w[1] / w[0] - 1.0).abs() < 0.02 * tol_scale(),
            "Fz jumps from {:.0} to {:.0} N in 1.5 µm",
            w[0],
            w[1]
        );
    }
}

/// The half-space model's FASTSIM and FaStrip rows against Kalker's exact solution on the same
/// pressure, in the yawed two-point contact of the sweep above (14.7 mrad): each row's
/// creepages are taken at its own locus point, which a yawed flange contact puts ahead of the
/// reference point, so the row must be solved about that point. Solved about the reference
/// point (before stop 24) the spin slip φ·x counted that lead twice: on the flank patch Fx was
/// 11 % above the exact solution and Fs 8 % below; now both are within 2 % of it (FASTSIM
/// 0.6 % and 1.0 %, FaStrip 0.4 % and 0.6 % of the patch's creep force since stop 37).
#[test]
fn half_space_rows_count_the_yawed_lead_once() {
    let pose = WheelsetPose {
        y: -6.55e-3,
        z: 0.70e-3,
        roll: 0.0,
        yaw: -14.7e-3,
    };
    let vel = WheelsetVelocity {
        vx: 11.11,
        spin: 11.11 / 0.46,
        ..Default::default()
    };
    let solve = |tangential: Tangential| {
        let mut opts = ContactOptions {
            model: ContactModelKind::Halfspace,
            tangential,
            ..Default::default()
        };
        opts.travel.step = 1e-3;
        let c = WheelRailContact::new(WheelRailPair::new(&standard_spec()).unwrap(), opts).unwrap();
        let mut ws = ContactWorkspace::new();
        c.evaluate(Side::Right, &pose, &vel, &mut ws).unwrap();
        ws.patches
            .iter()
            .map(|p| (p.contact_angle, p.forces.fx, p.forces.fs))
            .collect::<Vec<_>>()
    };
    let exact = solve(Tangential::Exact);
    for tangential in [Tangential::Fastsim, Tangential::Fastrip] {
        let rows = solve(tangential);
        eprintln!("{tangential:?} rows {rows:.3?}\nexact {exact:.3?}");
        assert_eq!(rows.len(), exact.len());
        let flank = rows.iter().filter(|p| p.0 > 1.0).count();
        assert_eq!(flank, 1, "one flank patch expected: {rows:?}");
        for (r, e) in rows.iter().zip(&exact) {
            let scale = e.1.hypot(e.2);
            for (what, got, want) in [("Fx", r.1, e.1), ("Fs", r.2, e.2)] {
                assert!(
                    (got - want).abs() < 0.02 * scale * tol_scale(),
                    "{tangential:?}, patch at {:.3} rad: {what} {got:.0} N against the exact {want:.0} N",
                    r.0
                );
            }
        }
    }
}

/// The right wheel pushed 6.3 to 7.2 mm toward its flange at 2 mrad of yaw and 55 kN, in
/// 5 µm steps (`railsim contact`'s defaults, `stripes` at its 1 mm step): every position
/// carries its load. Where the flange zone appears beside the flange-root zone, its strips
/// cross the junction of the profiles' arcs, where the line-load coefficient K changes by up to
/// 30 times within a tenth of a millimetre; interpolated between pairs 1/3 mm apart, K and the
/// virtual interpenetration made the vertical force jump across the load at 3 of these 181
/// positions (residuals 274–1525 N). Integrated at sub-points with the profiles' own curvatures
/// (`stripes::junction_segment`, docs/models/contact.md §5) the force is continuous there.
#[test]
fn every_flange_position_carries_its_load_at_the_default_step() {
    let contact = standard_contact(ContactModelKind::Stripes, 1.0e-3);
    let vel = WheelsetVelocity {
        vx: 20.0,
        spin: -4.3481181,
        ..Default::default()
    };
    let mut ws = ContactWorkspace::new();
    let load = 55e3;
    let mut missed = Vec::new();
    for i in 0..=180 {
        let pose = WheelsetPose {
            y: -(6.3 + 0.005 * i as f64) * 1e-3,
            z: 0.0,
            roll: 0.0,
            yaw: 2e-3,
        };
        let s = contact
            .evaluate_with_load(Side::Right, &pose, &vel, load, 1e-9, &mut ws)
            .unwrap();
        if s.load_residual > railsim_contact::LOAD_RESIDUAL_NOTICE * load * tol_scale() {
            missed.push((-pose.y * 1e3, s.load_residual));
        }
    }
    assert!(
        missed.is_empty(),
        "no height carries 55 kN at (y mm, residual N): {missed:?}"
    );
}

/// The two-point pose of the leading outer wheel in the elastic-rail R = 150 m curve (benchmark
/// profiles, right wheel 6.287 mm toward its flange, 15.17 mrad of yaw, at a fixed height): the
/// wheel's forces at the default 1 mm step with its refinement to 12 pairs in contact, and at the
/// next level (14), against a 0.02 mm step. The flange zone's strips cross the junction of the
/// wheel's flange-root and flange arcs, where K changes 27 times within 0.3 mm; interpolated
/// between the pairs, the default was 2.0 % off in Fy and 1.1 % in Fz, and the two levels
/// differed by 211 N in Fy: the step the refinement made when it changed level, which rang the
/// elastic rail (docs/models/contact.md §3). With the junction segments: 0.23 % and 0.10 %,
/// and 58 N between the levels.
#[test]
fn the_two_point_flange_contact_converges_at_the_default_step() {
    let vel = rolling_30_m_s();
    let pose = WheelsetPose {
        y: -6.287e-3,
        z: 333.8e-6,
        roll: -0.54e-3,
        yaw: -15.17e-3,
    };
    let forces = |step: f64, pairs: usize| {
        let contact = mbench_contact_with(ContactModelKind::Stripes, step, pairs);
        let mut ws = ContactWorkspace::new();
        let s = contact.evaluate(Side::Right, &pose, &vel, &mut ws).unwrap();
        assert_eq!(ws.zones.len(), 2, "a flange-root and a flange patch");
        [s.force_track[1], s.force_track[2]]
    };
    let fine = forces(0.02e-3, 12);
    let default = forces(1.0e-3, 12);
    let next = forces(1.0e-3, 14);
    for (k, (name, bound)) in [("Fy", 5e-3), ("Fz", 3e-3)].into_iter().enumerate() {
        for (level, f) in [("12 pairs", default), ("14 pairs", next)] {
            let err = (f[k] - fine[k]).abs() / fine[k].abs();
            assert!(
                err <= bound * tol_scale(),
                "{name} at {level}: {:.1} N against {:.1} N at 0.02 mm ({:.2} %)",
                f[k],
                fine[k],
                100.0 * err
            );
        }
        let step = (default[k] - next[k]).abs() / fine[k].abs();
        assert!(
            step <= 2e-3 * tol_scale(),
            "{name} steps by {:.1} N between the levels",
            default[k] - next[k]
        );
    }
}
