//! The single-point search of the Hertz models (`railsim_contact::point`, bounding hierarchies
//! and Newton on the rigid contact pair) against the seed's travelling on the same models, over
//! poses spread across the whole wheel: tread, flange root and flange, both wheels, yaw to
//! ±25 mrad, roll to ±15 mrad, loads from 2 to 120 kN and poses lifted off the rail. Every patch
//! the travelling finds must be found, at the same place, with the same penetration and load.

use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, HertzSearch, PatchResult, Side,
    WheelRailContact, WheelsetPose,
};

use crate::common::{Lcg, mbench_pair, rolling_30_m_s, tol_scale};

fn contact(model: ContactModelKind, search: HertzSearch, step: f64) -> WheelRailContact {
    let mut opts = ContactOptions {
        model,
        hertz_search: search,
        ..Default::default()
    };
    opts.travel.step = step;
    WheelRailContact::new(mbench_pair(), opts).unwrap()
}

/// The patches that carry at least `frac` of the wheel's total normal load.
fn main_patches(p: &[PatchResult], frac: f64) -> Vec<PatchResult> {
    let total: f64 = p.iter().map(|q| q.forces.fn_).sum();
    p.iter()
        .filter(|q| q.forces.fn_ >= frac * total)
        .copied()
        .collect()
}

#[test]
fn the_point_search_finds_the_travelled_patches() {
    let s = tol_scale();
    for model in [ContactModelKind::Polach, ContactModelKind::Fastsim] {
        let tree = contact(model, HertzSearch::Point, 1e-3);
        let travel = contact(model, HertzSearch::Travel, 0.1e-3);
        let vel = rolling_30_m_s();
        let mut rng = Lcg(20261121);
        let (mut ws_a, mut ws_b) = (ContactWorkspace::new(), ContactWorkspace::new());
        let (mut worst_pen, mut worst_fn, mut worst_y) = (0.0f64, 0.0f64, 0.0f64);
        let (mut n_two, mut n_lifted, mut n_flange, mut n_flat, mut n_checked) = (0, 0, 0, 0, 0);
        let n = 400;
        for k in 0..n {
            let side = if k % 2 == 0 { Side::Left } else { Side::Right };
            let pose = WheelsetPose {
                y: rng.range(-10e-3, 10e-3),
                yaw: rng.range(-25e-3, 25e-3),
                roll: rng.range(-15e-3, 15e-3),
                ..Default::default()
            };
            let fz = rng.range(2e3, 120e3);
            // the height that carries the load, found with the travelling
            let Ok(loaded) = travel.evaluate_with_load(side, &pose, &vel, fz, 1e-6, &mut ws_b)
            else {
                continue;
            };
            let mut q = pose;
            // every tenth pose lifted 0.3 mm off the rail
            q.z = loaded.z + if k % 10 == 5 { 0.3e-3 } else { 0.0 };
            travel.evaluate(side, &q, &vel, &mut ws_b).unwrap();
            let sa = tree.evaluate(side, &q, &vel, &mut ws_a).unwrap();
            let (a, b) = (&ws_a.patches, &ws_b.patches);
            if b.is_empty() {
                n_lifted += 1;
                assert!(
                    a.is_empty(),
                    "pose {k}: patches where the travelling finds none: {a:?}"
                );
                continue;
            }
            // every patch with at least 2 % of the load, matched by the closest contact angle
            let (ma, mb) = (main_patches(a, 0.02), main_patches(b, 0.02));
            assert_eq!(
                ma.len(),
                mb.len(),
                "pose {k} ({side:?}, {q:?}): {} main patches against {} travelled\n{a:#?}\n{b:#?}",
                ma.len(),
                mb.len()
            );
            n_checked += 1;
            if mb.len() > 1 {
                n_two += 1;
            }
            for p in &mb {
                if p.contact_angle.abs() > 0.6 {
                    n_flange += 1;
                }
                let m = ma
                    .iter()
                    .min_by(|x, y| {
                        (x.contact_angle - p.contact_angle)
                            .abs()
                            .total_cmp(&(y.contact_angle - p.contact_angle).abs())
                    })
                    .unwrap();
                worst_pen = worst_pen.max((m.penetration / p.penetration - 1.0).abs());
                let dy = (m.rigid_pair_y_rail_profile - p.rigid_pair_y_rail_profile).abs();
                if dy > 0.2e-3 {
                    // Not the travelling's rigid pair: allowed only where the gap is flat (a
                    // conformal well), i.e. where the travelled gap at the point found is as
                    // deep as the travelling's deepest, to 1 % of the penetration.
                    let g = ws_b
                        .pairs
                        .iter()
                        .min_by(|x, y| {
                            let yx = travel.pair.rail_profile_y(x.b[0], x.b[1]);
                            let yy = travel.pair.rail_profile_y(y.b[0], y.b[1]);
                            (yx - m.rigid_pair_y_rail_profile)
                                .abs()
                                .total_cmp(&(yy - m.rigid_pair_y_rail_profile).abs())
                        })
                        .unwrap()
                        .gap;
                    let flat = (-g / p.penetration - 1.0).abs();
                    assert!(
                        flat < 0.01 * s,
                        "pose {k}: rigid pair {:.3} mm from the travelling's where the gap is \
                         {:.2} % shallower",
                        dy * 1e3,
                        flat * 100.0
                    );
                    n_flat += 1;
                } else {
                    worst_y = worst_y.max(dy);
                    worst_fn = worst_fn.max((m.forces.fn_ / p.forces.fn_ - 1.0).abs());
                }
            }
            assert!(!sa.travel.warm);
        }
        eprintln!(
            "{}: {n} poses, {n_checked} in contact compared, {n_lifted} lifted, {n_two} with two patches, {n_flange} flange patches, \
             {n_flat} on flat wells; worst penetration {worst_pen:.2e}, Fn {worst_fn:.2e}, rigid \
             pair {:.3} mm",
            model.name(),
            worst_y * 1e3
        );
        assert!(n_checked >= 300 && n_lifted >= 30 && n_two >= 3 && n_flange >= 50);
        assert!(worst_pen < 1e-3 * s, "penetration off by {worst_pen:.2e}");
        assert!(worst_fn < 2e-2 * s, "Fn off by {worst_fn:.2e}");
        assert!(worst_y < 0.2e-3 * s, "position off by {worst_y:.2e} m");
    }
}

/// A zone deeper than half the broad phase's depth (0.25 mm) is left to the travelling: the
/// results are those of the travelling, to the last bit; a shallower one is not. (1 mm lower
/// than the height that carries 10 kN: at least 0.3 mm along the normal of a 70° flange.)
#[test]
fn deep_zones_are_left_to_the_travelling() {
    let tree = contact(ContactModelKind::Polach, HertzSearch::Point, 1e-3);
    let travel = contact(ContactModelKind::Polach, HertzSearch::Travel, 1e-3);
    let vel = rolling_30_m_s();
    let (mut ws_a, mut ws_b) = (ContactWorkspace::new(), ContactWorkspace::new());
    for (y, side) in [(0.0, Side::Right), (-8e-3, Side::Right), (4e-3, Side::Left)] {
        let pose = WheelsetPose {
            y,
            yaw: 5e-3,
            ..Default::default()
        };
        let s = travel
            .evaluate_with_load(side, &pose, &vel, 10e3, 1e-6, &mut ws_b)
            .unwrap();
        for (extra, same) in [(1.0e-3, true), (0.05e-3, false)] {
            let q = WheelsetPose {
                z: s.z - extra,
                ..pose
            };
            let a = tree.evaluate(side, &q, &vel, &mut ws_a).unwrap();
            travel.evaluate(side, &q, &vel, &mut ws_b).unwrap();
            assert_eq!(a.travel.pairs > 20, same, "y {y}: {:?}", a.travel);
            if same {
                assert_eq!(ws_a.patches, ws_b.patches);
            }
        }
    }
}

/// The point search's warm start (`railsim_contact::broad::BroadMemory`: a broad-phase query
/// with a margin, reused while the wheel stays within it) against cold searches, along random walks of the pose like the poses of a time
/// integration: small steps (most searches warm), now and then a jump of a few mm or mrad (a new
/// query), over the tread and the flange, both wheels, yaw to ±25 mrad. Every evaluation must give
/// the cold search's patches bit for bit: the rules applied to the stored leaf pairs at the new
/// pose keep the leaf pairs a full query keeps (a full query could drop a pair at an ancestor
/// that the leaf rules keep; then the estimates, and possibly the Newton starts, could differ,
/// which this test would show).
#[test]
fn the_warm_point_search_gives_the_cold_result() {
    let c = contact(ContactModelKind::Polach, HertzSearch::Point, 1e-3);
    let vel = rolling_30_m_s();
    let mut rng = Lcg(11235813);
    let (mut ws_a, mut ws_b) = (ContactWorkspace::new(), ContactWorkspace::new());
    let (mut compared, mut two) = (0, 0);
    for side in [Side::Left, Side::Right] {
        let mut warm = railsim_contact::WarmStart::new();
        let mut pose = WheelsetPose::default();
        let (mut z0, mut dz) = (0.0, 0.0);
        for k in 0..1500 {
            if k % 150 == 0 {
                // a jump: a fresh pose anywhere on the wheel
                pose = WheelsetPose {
                    y: rng.range(-9e-3, 9e-3),
                    yaw: rng.range(-25e-3, 25e-3),
                    roll: rng.range(-5e-3, 5e-3),
                    ..Default::default()
                };
                let fz = rng.range(5e3, 100e3);
                let s = c
                    .evaluate_with_load(side, &pose, &vel, fz, 1e-6, &mut ws_a)
                    .unwrap();
                (z0, dz) = (s.z, 0.0);
            } else {
                // steps of up to 40 µm and 0.1 mrad; the height a random walk of 10 µm steps
                // within 0.15 mm below and 0.05 mm above the loaded height
                pose.y += rng.range(-40e-6, 40e-6);
                pose.yaw += rng.range(-1e-4, 1e-4);
                pose.roll += rng.range(-2e-5, 2e-5);
                dz = (dz + rng.range(-10e-6, 10e-6)).clamp(-0.15e-3, 0.05e-3);
            }
            pose.z = z0 + dz;
            let (Ok(a), Ok(b)) = (
                c.evaluate(side, &pose, &vel, &mut ws_a),
                c.evaluate_warm(side, &pose, &vel, &mut warm, &mut ws_b),
            ) else {
                panic!("pose {k} {side:?} {pose:?}: one search failed");
            };
            let (pa, pb) = (&ws_a.patches, &ws_b.patches);
            assert_eq!(pa, pb, "pose {k} {side:?} {pose:?}: {a:?} / {b:?}");
            compared += 1;
            two += usize::from(pa.len() == 2);
        }
        eprintln!(
            "{side:?}: {} warm of {} searches",
            warm.warm_count,
            warm.warm_count + warm.cold_count
        );
        assert!(
            warm.warm_count > 3 * warm.cold_count,
            "{side:?}: {} warm, {} cold",
            warm.warm_count,
            warm.cold_count
        );
    }
    eprintln!("{compared} poses compared, {two} with two patches");
    assert!(
        compared == 3000 && two > 20,
        "{compared} compared, {two} with two patches"
    );
}

/// Up to the largest yaw the wheel's contact locus supports (29.9 mrad for the benchmark's
/// S1002, `railsim_contact::pair::LocusLimits`), the point search and the travelling agree on
/// every pose: the same error, or the same patches carrying at least 2 % of the load with the
/// same penetrations, and the same vertical force, also far outside the running range (roll to ±30 mrad, the wheel pressed up to
/// 4 mm into the rail, flange climbing). Before the curvature bounds took the yawed locus into account, and without the
/// yaw limit, the broad phase missed deep flange contacts from 0.05 rad of yaw on (the travelling
/// found 9.8 MN where the point search found no contact).
#[test]
fn the_point_search_agrees_with_the_travelling_up_to_the_yaw_limit() {
    // (the same step: zones deeper than 0.25 mm are left to the travelling)
    let point = contact(ContactModelKind::Polach, HertzSearch::Point, 0.2e-3);
    let travel = contact(ContactModelKind::Polach, HertzSearch::Travel, 0.2e-3);
    let limit = point.pair.locus.tan_yaw_max.atan();
    let vel = rolling_30_m_s();
    let (mut ws_a, mut ws_b) = (ContactWorkspace::new(), ContactWorkspace::new());
    let mut rng = Lcg(20261122);
    let (mut both_ok, mut both_err, mut loaded, mut yawed) = (0, 0, 0, 0);
    let (mut minor, mut count_diff) = (0.0f64, 0);
    for k in 0..4000 {
        let side = if k % 2 == 0 { Side::Left } else { Side::Right };
        // a quarter of the poses within 5 % of the yaw limit
        let yaw = if k % 4 == 0 {
            rng.range(0.95, 1.0) * limit * if k % 8 == 0 { -1.0 } else { 1.0 }
        } else {
            rng.range(-limit, limit)
        };
        // two thirds near the running range, a third rolled far and pressed in up to 4 mm or
        // lifted
        let (z, roll) = if k % 3 == 0 {
            (rng.range(-4e-3, 1.5e-3), rng.range(-30e-3, 30e-3))
        } else {
            (rng.range(-1.2e-3, 0.3e-3), rng.range(-5e-3, 5e-3))
        };
        let pose = WheelsetPose {
            y: rng.range(-15e-3, 15e-3),
            z,
            roll,
            yaw,
        };
        let a = point
            .evaluate(side, &pose, &vel, &mut ws_a)
            .map(|s| s.force_track[2]);
        let b = travel
            .evaluate(side, &pose, &vel, &mut ws_b)
            .map(|s| s.force_track[2]);
        match (&a, &b) {
            (Ok(fa), Ok(fb)) => {
                // (wells of a wide zone carry shares of their Hertz solutions; a well less
                // prominent than the point search's estimates can resolve, with a share of a
                // few per cent, may be seen by the travelling only: the patches that carry at
                // least 2 % of the load are compared)
                let (pa, pb) = (
                    main_patches(&ws_a.patches, 0.02),
                    main_patches(&ws_b.patches, 0.02),
                );
                assert_eq!(pa.len(), pb.len(), "{side:?} {pose:?}: patches");
                let small = |all: &[PatchResult], main: &[PatchResult]| {
                    let t: f64 = all.iter().map(|q| q.forces.fn_).sum();
                    let m: f64 = main.iter().map(|q| q.forces.fn_).sum();
                    if t > 0.0 { (t - m) / t } else { 0.0 }
                };
                minor = minor
                    .max(small(&ws_a.patches, &pa))
                    .max(small(&ws_b.patches, &pb));
                if ws_a.patches.len() != ws_b.patches.len() {
                    count_diff += 1;
                }
                for (x, y) in pa.iter().zip(pb.iter()) {
                    let d = (x.penetration - y.penetration).abs();
                    assert!(
                        d <= 0.5e-6 + 5e-3 * y.penetration,
                        "{side:?} {pose:?}: penetration {} against {}",
                        x.penetration,
                        y.penetration
                    );
                }
                // the Hertz curvatures come from the rigid pair (point search) or from the
                // travelled pairs: up to 2.7 % apart in Fz near the yaw limit (1.7 % below a
                // fifth of it) where the penetrations agree to 0.25 µm
                assert!(
                    (fa - fb).abs() <= 0.03 * fb.abs() + 1.0,
                    "{side:?} {pose:?}: Fz {fa} against {fb}"
                );
                let na = pa.len();
                both_ok += 1;
                if na > 0 {
                    loaded += 1;
                    if yaw.abs() > 0.95 * limit {
                        yawed += 1;
                    }
                }
            }
            (Err(_), Err(_)) => both_err += 1,
            _ => panic!("{side:?} {pose:?}: point search {a:?}, travelling {b:?}"),
        }
    }
    // the sample covers contact, near-limit yaw and absurd presses
    println!(
        "{both_ok} poses evaluated by both ({loaded} in contact, {yawed} of them within 5 % of the \
         yaw limit), {both_err} errors from both; {count_diff} with different numbers of \
         patches, the patches below 2 % of the load carrying at most {:.2} % of it",
        minor * 100.0
    );
    assert!(loaded > 1500 && yawed > 300 && both_err > 300);
    // the wells one search sees and the other does not are small
    assert!(minor < 0.02, "{minor}");
}
