//! STRIPES on a constant-curvature geometry gives back Hertz (issue 2: within 1 %), through the
//! whole pipeline: profiles → placement → isosceles travelling → patch → STRIPES.
//!
//! Geometry: a wheel whose profile is a circle of lateral radius `rw` (convex) on a rail head
//! that is a circle of radius `rr`, centred under the wheel profile's origin; zero yaw and roll.
//! Then A = 1/(2 r0) and B = (1/rw + 1/rr)/2 are constant over the patch.

use railsim_contact::stripes::StripesVariant;
use railsim_contact::{
    ContactModelKind, ContactOptions, ContactWorkspace, PairSpec, Side, WheelRailContact,
    WheelRailPair, WheelsetPose, WheelsetVelocity,
};
use railsim_elastic::{Material, hertz_from_approach, hertz_from_load};
use railsim_profile::{Profile, ProfileKind};

use crate::common::tol_scale;

const R0: f64 = 0.460;
const Y0: f64 = 0.750;

fn arc(r: f64, half: f64, sign: f64) -> Vec<[f64; 2]> {
    let n = 600;
    (0..=n)
        .map(|i| {
            let y = -half + 2.0 * half * i as f64 / n as f64;
            [y, sign * (r - (r * r - y * y).sqrt())]
        })
        .collect()
}

fn circle_pair(rw: f64, rr: f64) -> WheelRailPair {
    let wheel = Profile::new("circle wheel", ProfileKind::Wheel, arc(rw, 0.06, 1.0)).unwrap();
    let half_r = 0.06f64.min(0.95 * rr);
    let rail = Profile::new("circle rail", ProfileKind::Rail, arc(rr, half_r, -1.0)).unwrap();
    // Gauge point below the crown, on the gauge side, within the profile's depth.
    let depth = 0.8 * (rr - (rr * rr - half_r * half_r).sqrt());
    let yg = (rr * rr - (rr - depth) * (rr - depth)).sqrt();
    WheelRailPair::new(&PairSpec {
        wheel,
        rail,
        r0: R0,
        flange_back_distance: 2.0 * (Y0 - 0.07),
        flange_back_y: -0.07,
        gauge: 2.0 * (Y0 - yg),
        gauge_depth: depth,
        inclination: 0.0,
        material: Material::new(82e9, 0.28).unwrap(),
        friction: railsim_contact::Friction::Constant(0.3),
        curve_ds: 2e-5,
        smoothing: 0.0,
    })
    .unwrap()
}

fn contact(pair: WheelRailPair, variant: StripesVariant) -> WheelRailContact {
    let mut opts = ContactOptions {
        model: ContactModelKind::Stripes,
        stripes_variant: variant,
        ..Default::default()
    };
    opts.travel.step = 0.02e-3;
    WheelRailContact::new(pair, opts).unwrap()
}

fn rolling() -> WheelsetVelocity {
    WheelsetVelocity {
        vx: 10.0,
        spin: 10.0 / R0,
        ..Default::default()
    }
}

#[test]
fn stripes_recovers_hertz_for_constant_curvatures() {
    let tol = 0.01 * tol_scale();
    for (rw, rr) in [(0.3, 0.3), (1.0, 0.08), (0.2, 0.3)] {
        for variant in [StripesVariant::Seed, StripesVariant::LocalEpsilon] {
            let pair = circle_pair(rw, rr);
            let mat = pair.material;
            let c = contact(pair, variant);
            let mut ws = ContactWorkspace::new();
            // Prescribed position: 50 µm interpenetration.
            let pose = WheelsetPose {
                z: -50e-6,
                ..Default::default()
            };
            c.evaluate(Side::Left, &pose, &rolling(), &mut ws).unwrap();
            assert_eq!(
                ws.patches.len(),
                1,
                "one patch expected for rw={rw} rr={rr}"
            );
            let p = ws.patches[0];
            let a = 0.5 / p.rolling_radius;
            let b = 0.5 * (1.0 / rw + 1.0 / rr);
            let hz = hertz_from_approach(a, b, p.penetration, &mat).unwrap();
            let err_n = p.forces.fn_ / hz.n - 1.0;
            let err_p = p.forces.p_max / hz.p0 - 1.0;
            let err_w = p.forces.width / (2.0 * hz.b) - 1.0;
            let err_l = p.forces.length / (2.0 * hz.a) - 1.0;
            eprintln!(
                "rw={rw} rr={rr} {variant:?}: delta {:.2} µm, N {:.1} vs Hertz {:.1} ({:+.4} %), p0 {:+.3} %, 2b {:+.3} %, 2a {:+.3} %",
                p.penetration * 1e6,
                p.forces.fn_,
                hz.n,
                100.0 * err_n,
                100.0 * err_p,
                100.0 * err_w,
                100.0 * err_l
            );
            assert!(
                (p.penetration - 50e-6).abs() < 0.2e-6,
                "penetration {}",
                p.penetration
            );
            assert!(err_n.abs() < tol, "N off Hertz by {:.3} %", 100.0 * err_n);
            assert!(
                err_p.abs() < 2.0 * tol,
                "p0 off Hertz by {:.3} %",
                100.0 * err_p
            );
            assert!(
                err_w.abs() < 2.0 * tol,
                "width off Hertz by {:.3} %",
                100.0 * err_w
            );
            assert!(
                err_l.abs() < 2.0 * tol,
                "length off Hertz by {:.3} %",
                100.0 * err_l
            );
        }
    }
}

#[test]
fn stripes_load_control_gives_hertz_approach() {
    let pair = circle_pair(0.3, 0.3);
    let mat = pair.material;
    let c = contact(pair, StripesVariant::LocalEpsilon);
    let mut ws = ContactWorkspace::new();
    let s = c
        .evaluate_with_load(
            Side::Right,
            &WheelsetPose::default(),
            &rolling(),
            50e3,
            1e-8,
            &mut ws,
        )
        .unwrap();
    let p = ws.patches[0];
    let hz = hertz_from_load(
        0.5 / p.rolling_radius,
        0.5 * (2.0 / 0.3),
        p.forces.fn_,
        &mat,
    )
    .unwrap();
    let err = p.penetration / hz.delta - 1.0;
    eprintln!(
        "load control: delta {:.3} µm vs Hertz {:.3} µm ({:+.3} %), {} iterations",
        p.penetration * 1e6,
        hz.delta * 1e6,
        100.0 * err,
        s.load_iterations
    );
    assert!(
        (s.force_track[2] - 50e3).abs() < 1e-3,
        "vertical force {}",
        s.force_track[2]
    );
    assert!(err.abs() < 0.01 * tol_scale());
    // The iteration count is a machine-independent cost proxy.
    assert!(
        s.load_iterations <= 12,
        "{} load iterations",
        s.load_iterations
    );
}

#[test]
fn seed_equation_9_as_printed_does_not_recover_hertz() {
    // The seed's eq. (9) as printed, h_i = max(0, delta0 (1 - eps0) - z_i), gives the deepest
    // strip (1 - eps0) delta0 instead of eq. (7)'s eps0 delta0; with eps0 != 1/2 the load is off
    // Hertz by the factor (1 - eps0)/eps0 at the centre. This test documents the contradiction
    // numerically: for A/B = 0.1 (eps0 = 0.33) the two differ by a factor ~2.
    let (a, b) = (1.0, 10.0);
    let c = railsim_elastic::hertz_coeffs(a, b).unwrap();
    let eps0 = railsim_elastic::stripes_epsilon(&c, a, b);
    assert!((eps0 - 0.3306).abs() < 1e-3);
    assert!(((1.0 - eps0) / eps0 - 2.02).abs() < 0.01);
}

/// The half-space model through the whole pipeline at the default travelling step (1 mm) on the
/// constant-curvature geometry: normal force and peak pressure of Hertz at the same approach.
/// Its grid's gap was interpolated linearly between the pairs 1 mm apart, an inscribed roof
/// with a kink at every pair under which the pressure peaked: p0 13.5 % above Hertz at 2 µm
/// (54 % at 0.3 µm) on two 0.3 m circles. Now the mean of the neighbouring parabolas, as the
/// STRIPES strips: N within 0.03 % and p0 within 0.08 % of Hertz here. Criteria 0.5 % on N and
/// 1 % on p0 (the 48 × 48 grid's own resolution).
#[test]
fn halfspace_recovers_hertz_at_the_default_step() {
    let tol = tol_scale();
    let mut worst = (0.0f64, 0.0f64);
    for (rw, rr) in [(0.3, 0.3), (1.0, 0.08)] {
        for z in [-2e-6, -20e-6, -200e-6] {
            let pair = circle_pair(rw, rr);
            let mat = pair.material;
            let c = WheelRailContact::new(
                pair,
                ContactOptions {
                    model: ContactModelKind::Halfspace,
                    ..Default::default()
                },
            )
            .unwrap();
            let mut ws = ContactWorkspace::new();
            let pose = WheelsetPose {
                z,
                ..Default::default()
            };
            c.evaluate(Side::Left, &pose, &rolling(), &mut ws).unwrap();
            assert_eq!(ws.patches.len(), 1, "rw {rw} rr {rr} z {z}");
            let p = &ws.patches[0];
            let (a, b) = (0.5 / p.rolling_radius, 0.5 * (1.0 / rw + 1.0 / rr));
            let hz = hertz_from_approach(a, b, p.penetration, &mat).unwrap();
            let (dn, dp) = (p.forces.fn_ / hz.n - 1.0, p.forces.p_max / hz.p0 - 1.0);
            eprintln!(
                "rw {rw} rr {rr} approach {:.2} µm: N {:+.3} %, p0 {:+.3} %",
                p.penetration * 1e6,
                dn * 100.0,
                dp * 100.0
            );
            worst = (worst.0.max(dn.abs()), worst.1.max(dp.abs()));
        }
    }
    assert!(worst.0 < 0.005 * tol, "N off by {:.2} %", worst.0 * 100.0);
    assert!(worst.1 < 0.01 * tol, "p0 off by {:.2} %", worst.1 * 100.0);
}

/// Load control tries every lowering up to the largest interpenetration allowed (5 mm): a load
/// that needs 3.3 mm on two 0.3 m circles (15 MN, absurd but within the limit) is found. The
/// lowering doubled from 20 µm and stopped once the double passed 5 mm, so 2.56 mm was the
/// last tried and the error said "only 10 340 494.7 N at 5.120 mm", twice that. Beyond the limit
/// the error gives the lowering actually tried.
#[test]
fn load_control_reaches_the_interpenetration_limit() {
    let c = contact(circle_pair(0.3, 0.3), StripesVariant::LocalEpsilon);
    let mut ws = ContactWorkspace::new();
    let pose = WheelsetPose::default();
    let s = c
        .evaluate_with_load(Side::Left, &pose, &rolling(), 15e6, 1e-6, &mut ws)
        .unwrap_or_else(|e| panic!("{e}"));
    let pen = ws.patches[0].penetration;
    eprintln!(
        "15 MN: penetration {:.3} mm, Fz {:.0} N",
        pen * 1e3,
        s.force_track[2]
    );
    assert!(pen > 2.6e-3 && pen < 5e-3, "{pen}");
    assert!((s.force_track[2] / 15e6 - 1.0).abs() < 1e-5);
    let e = c
        .evaluate_with_load(Side::Left, &pose, &rolling(), 1e9, 1e-6, &mut ws)
        .unwrap_err()
        .to_string();
    assert!(e.contains("at 4.995 mm below first touch"), "{e}");
}
