//! Kinematic oscillation of a free wheelset (issue 3, "Must show": a free wheelset with a pure
//! conical profile, λ = 0.2, has Klingel's wavelength within 2 %).
//!
//! This is a test harness, not the simulator: a single rigid wheelset on straight ideal track,
//! moving forward at a constant speed, free laterally, vertically, in roll, yaw and spin, held on
//! the rails only by the online contact forces of `railsim-contact` (STRIPES, both wheels, at every
//! right-hand-side evaluation) and integrated with `railsim-ode`'s Dormand–Prince 5(4). The
//! simulator of issue 3 must later pass the same check through its own `step`.
//!
//! Equations (track frame, small roll and yaw, spin Ω about the axle; Newton–Euler with the
//! gyroscopic terms of the spinning axle, e.g. Iwnicki (ed.), Handbook of Railway Vehicle
//! Dynamics, ch. 7): m ÿ = F_y, m z̈ = F_z − m g, I_x φ̈ = M_x + I_y Ω ψ̇, I_z ψ̈ = M_z − I_y Ω φ̇,
//! I_y Ω̇ = M_y, with forces and moments about the axle centre summed over all patches.
//! Klingel (1883): L = 2π sqrt(r0 e0 / λ), e0 half the distance between the contact points.

use std::ops::ControlFlow;

use railsim_contact::{
    ContactOptions, ContactWorkspace, PairSpec, Side, WheelRailContact, WheelRailPair,
    WheelsetPose, WheelsetVelocity,
};
use railsim_elastic::Material;
use railsim_ode::{Integrator, Method, OdeSystem, RhsError};
use railsim_profile::{Profile, ProfileKind, analytic};

use crate::common::tol_scale;

const M: f64 = 1500.0;
const IX: f64 = 800.0;
const IY: f64 = 100.0;
const IZ: f64 = 800.0;
const G: f64 = 9.81;
const R0: f64 = 0.46;

struct FreeWheelset {
    contact: WheelRailContact,
    ws: ContactWorkspace,
    v: f64,
}

impl FreeWheelset {
    /// Forces and moments on the wheelset about its axle centre, track frame.
    fn loads(
        &mut self,
        pose: &WheelsetPose,
        vel: &WheelsetVelocity,
    ) -> Result<([f64; 3], [f64; 3]), String> {
        let c = [0.0, pose.y, R0 + pose.z];
        let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
        for side in [Side::Left, Side::Right] {
            self.contact
                .evaluate(side, pose, vel, &mut self.ws)
                .map_err(|e| e.to_string())?;
            for p in &self.ws.patches {
                let r = [
                    p.point_track[0] - c[0],
                    p.point_track[1] - c[1],
                    p.point_track[2] - c[2],
                ];
                let q = p.force_track;
                for k in 0..3 {
                    f[k] += q[k];
                }
                m[0] += r[1] * q[2] - r[2] * q[1];
                m[1] += r[2] * q[0] - r[0] * q[2];
                m[2] += r[0] * q[1] - r[1] * q[0];
                for k in 0..3 {
                    m[k] += p.moment_track[k];
                }
            }
        }
        Ok((f, m))
    }
}

/// State: y, z, roll, yaw, their rates, spin.
impl OdeSystem for FreeWheelset {
    fn dim(&self) -> usize {
        9
    }
    fn rhs(&mut self, _t: f64, x: &[f64], d: &mut [f64]) -> Result<(), RhsError> {
        let pose = WheelsetPose {
            y: x[0],
            z: x[1],
            roll: x[2],
            yaw: x[3],
        };
        let vel = WheelsetVelocity {
            vx: self.v,
            vy: x[4],
            vz: x[5],
            roll_rate: x[6],
            yaw_rate: x[7],
            spin: x[8],
        };
        let (f, m) = self.loads(&pose, &vel).map_err(RhsError)?;
        d[0] = x[4];
        d[1] = x[5];
        d[2] = x[6];
        d[3] = x[7];
        d[4] = f[1] / M;
        d[5] = (f[2] - M * G) / M;
        d[6] = (m[0] + IY * x[8] * x[7]) / IX;
        d[7] = (m[2] - IY * x[8] * x[6]) / IZ;
        d[8] = m[1] / IY;
        Ok(())
    }
    fn abs_tol_scale(&self, i: usize) -> f64 {
        // metres and radians ~1e-3, rates ~1e-2, spin ~1
        [1.0, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 10.0, 1000.0][i]
    }
}

/// Wheel on the UIC60 rail inclined 1:40, gauge 1435 mm, flange-back distance 1360 mm.
fn pair_on_uic60(wheel: Profile) -> WheelRailPair {
    WheelRailPair::new(&PairSpec {
        wheel,
        rail: analytic::uic60(),
        r0: R0,
        flange_back_distance: 1.360,
        flange_back_y: -0.070,
        gauge: 1.435,
        gauge_depth: 0.014,
        inclination: (1.0f64 / 40.0).atan(),
        material: Material::new(82e9, 0.28).unwrap(),
        friction: railsim_contact::Friction::Constant(0.3),
        curve_ds: 5e-5,
        smoothing: 0.0,
    })
    .unwrap()
}

/// A pure cone: radius r0 - lambda * y over the whole running surface, no flange.
fn cone(lambda: f64) -> Profile {
    let points: Vec<[f64; 2]> = (0..=240)
        .map(|i| {
            let y = -0.06 + i as f64 * 0.0005;
            [y, lambda * y]
        })
        .collect();
    Profile::new("cone", ProfileKind::Wheel, points).unwrap()
}

/// The kinematic oscillation of a free wheelset started centred, at its static height, with a
/// small yaw angle (the motion then starts with y' = -yaw; a lateral offset without the matching
/// roll would start far from equilibrium on a steep cone).
struct Oscillation {
    /// \[m\] distance travelled between the first two up-crossings of y
    wavelength: f64,
    /// \[m\] largest |y|
    amplitude: f64,
    /// \[m\] rolling radius of the centred contact
    radius: f64,
    /// \[m\] half the distance between the centred contact points
    e0: f64,
}

fn oscillate(pair: WheelRailPair, v: f64, yaw0: f64, periods: f64, l_guess: f64) -> Oscillation {
    let contact = WheelRailContact::new(pair, ContactOptions::default()).unwrap();
    let mut sys = FreeWheelset {
        contact,
        ws: ContactWorkspace::new(),
        v,
    };
    let rolling = WheelsetVelocity {
        vx: v,
        spin: v / R0,
        ..Default::default()
    };
    // Static equilibrium height at y = 0: each wheel carries half the weight.
    let s = sys
        .contact
        .evaluate_with_load(
            Side::Left,
            &WheelsetPose::default(),
            &rolling,
            0.5 * M * G,
            1e-9,
            &mut sys.ws,
        )
        .unwrap();
    let centred = sys.ws.patches[0];
    let (radius, e0) = (centred.rolling_radius, centred.point_track[1].abs());
    let mut x = [0.0, s.z, 0.0, yaw0, 0.0, 0.0, 0.0, 0.0, v / radius];
    // A small first step and a step limit: a trial stage far from the contact equilibrium would
    // be rejected by the contact model as an absurd penetration.
    let method = Method::DormandPrince {
        rtol: 1e-6,
        atol: 1e-7,
        h0: Some(1e-5),
        h_max: 2e-3,
    };
    let mut ode = Integrator::new(method, 9).unwrap();
    let mut track: Vec<(f64, f64)> = Vec::new();
    let (reason, stats) = ode
        .integrate(&mut sys, 0.0, &mut x, periods * l_guess / v, &mut |t, x| {
            track.push((t, x[0]));
            ControlFlow::Continue(())
        })
        .unwrap();
    assert!(
        matches!(reason, railsim_ode::StopReason::Reached),
        "{reason:?}"
    );
    // Up-crossings of y (linear interpolation), distance travelled between them.
    let mut ups = Vec::new();
    for w in track.windows(2) {
        let ((t0, y0), (t1, y1)) = (w[0], w[1]);
        if y0 < 0.0 && y1 >= 0.0 {
            ups.push(t0 + (t1 - t0) * (-y0) / (y1 - y0));
        }
    }
    assert!(ups.len() >= 2, "fewer than two up-crossings");
    let amplitude = track.iter().map(|&(_, y)| y.abs()).fold(0.0, f64::max);
    eprintln!("{} steps, {} rhs evaluations", stats.steps, stats.rhs_evals);
    Oscillation {
        wavelength: v * (ups[1] - ups[0]),
        amplitude,
        radius,
        e0,
    }
}

#[test]
fn free_conical_wheelset_has_klingels_wavelength() {
    let lambda = 0.2;
    let o = oscillate(pair_on_uic60(cone(lambda)), 5.0, 5e-4, 3.2, 8.2);
    let l_klingel = 2.0 * std::f64::consts::PI * (o.radius * o.e0 / lambda).sqrt();
    eprintln!(
        "Klingel: L = {l_klingel:.3} m (e0 = {:.4} m, r = {:.4} m); simulated {:.3} m ({:+.2} %), max |y| {:.1} µm",
        o.e0,
        o.radius,
        o.wavelength,
        100.0 * (o.wavelength / l_klingel - 1.0),
        o.amplitude * 1e6
    );
    // A real oscillation of the expected size (yaw0 L / 2 pi ~ 0.65 mm), not noise.
    assert!(
        o.amplitude > 0.3e-3 && o.amplitude < 2e-3,
        "amplitude {}",
        o.amplitude
    );
    assert!((o.wavelength / l_klingel - 1.0).abs() < 0.02 * tol_scale());
}

#[test]
fn s1002_wheelset_wavelength_matches_klingel_at_its_equivalent_conicity() {
    // S1002 on UIC60 1:40, gauge 1435: the observed amplitude's equivalent conicity
    // (harmonic linearisation of the rigid Delta r) gives Klingel's wavelength within 5 %.
    use railsim_profile::conicity::{
        WheelsetTrackSetup, delta_r_interp, equivalent_conicity_harmonic, rolling_radius_difference,
    };
    let o = oscillate(pair_on_uic60(analytic::s1002()), 5.0, 2e-3, 2.6, 7.0);
    let (l_sim, amp) = (o.wavelength, o.amplitude);
    let setup = WheelsetTrackSetup::default();
    let ys: Vec<f64> = (-400..=400).map(|i| i as f64 * 25e-6).collect();
    let samples =
        rolling_radius_difference(&analytic::s1002(), &analytic::uic60(), &setup, &ys).unwrap();
    let lambda_e = equivalent_conicity_harmonic(|y| delta_r_interp(&samples, y), amp);
    let l_klingel = 2.0 * std::f64::consts::PI * (0.46 * 0.75 / lambda_e).sqrt();
    eprintln!(
        "S1002/UIC60: amplitude {:.2} mm, lambda_e {lambda_e:.3}, Klingel {l_klingel:.3} m, simulated {l_sim:.3} m ({:+.2} %)",
        amp * 1e3,
        100.0 * (l_sim / l_klingel - 1.0)
    );
    assert!(amp > 0.5e-3 && amp < 8e-3, "amplitude {amp}");
    assert!((l_sim / l_klingel - 1.0).abs() < 0.05 * tol_scale());
}
