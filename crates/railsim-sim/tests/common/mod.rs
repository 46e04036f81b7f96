//! Helpers shared by the simulator's test binaries (each binary uses a part of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use railsim_contact::{Side, WheelsetPose, WheelsetVelocity};
use railsim_sim::{RunOptions, RunSummary, Sample, Scene, Simulation};

/// The repository root (scene paths in the tests are relative to it).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A scene from TOML text, paths relative to the repository root.
pub fn scene(text: &str) -> Scene {
    Scene::from_toml_str(text, "test.toml", &root()).unwrap_or_else(|e| panic!("{e}"))
}

/// The shipped free S1002 wheelset (`vehicles/wheelset_free.toml`) driven by 2 kN·m of
/// traction, held longitudinally (`ws.x` frozen) at 72 km/h on ideal straight track, with
/// `extra` TOML appended to the scene; the vehicle file is written to `dir`.
pub fn driven_wheelset(dir: &Path, extra: &str) -> Scene {
    driven_wheelset_on(dir, "tracks/straight.toml", 1.0, extra)
}

/// [`driven_wheelset`] on the track file `track` for `duration_s`.
#[allow(dead_code)]
pub fn driven_wheelset_on(dir: &Path, track: &str, duration_s: f64, extra: &str) -> Scene {
    std::fs::create_dir_all(dir).unwrap();
    let text = std::fs::read_to_string(root().join("vehicles/wheelset_free.toml")).unwrap();
    let vehicle = dir.join("driven.toml");
    std::fs::write(
        &vehicle,
        text.replace("wheel_profile = {", "torque_nm = 2000\nwheel_profile = {"),
    )
    .unwrap();
    scene(&format!(
        "vehicle = \"{}\"\ntrack = \"{track}\"\nspeed_kmh = 72\nduration_s = {duration_s}\n\
         freeze = [\"ws.x\"]\n{extra}",
        vehicle.display()
    ))
}

/// Writes to `dir` the Manchester vehicle 1 with out-of-round wheels: a fifth-order polygon of
/// 0.1 mm on both wheels of ws1 and a 40 × 0.1 mm flat on ws3's left wheel, its centre at the
/// bottom at the rolled angle `flat_position_deg`; returns the file's path.
#[allow(dead_code)]
pub fn out_of_round_manchester(dir: &Path, flat_position_deg: f64) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let mut text =
        std::fs::read_to_string(root().join("vehicles/manchester_vehicle1.toml")).unwrap();
    for (ws, defect) in [
        (
            "ws1",
            "type = \"harmonic\"\nside = \"both\"\norder = 5\namplitude_mm = 0.1".to_owned(),
        ),
        (
            "ws3",
            format!(
                "type = \"flat\"\nside = \"left\"\nlength_mm = 40\ndepth_mm = 0.1\n\
                 position_deg = {flat_position_deg}"
            ),
        ),
    ] {
        // the defect's table right after its wheelset's keys
        let at = text.find(&format!("name = \"{ws}\"\n")).unwrap();
        let end = text[at..].find("\n[").map_or(text.len(), |e| at + e + 1);
        text.insert_str(end, &format!("[[wheelset.out_of_roundness]]\n{defect}\n\n"));
    }
    let vehicle = dir.join("out_of_round.toml");
    std::fs::write(&vehicle, &text).unwrap();
    vehicle
}

/// The index of the state variable `name` (e.g. `"ws1.z"`) of a simulation.
#[allow(dead_code)]
pub fn state_index(sim: &Simulation, name: &str) -> usize {
    let names = &sim.model().state_names;
    names
        .iter()
        .position(|s| s == name)
        .unwrap_or_else(|| panic!("no state {name} in {names:?}"))
}

/// Run a scene without a log; return the simulation, the samples and the summary.
pub fn run(scene: &Scene) -> (Simulation, Vec<Sample>, RunSummary) {
    let mut sim = Simulation::new(scene).unwrap();
    let mut samples = Vec::new();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let summary = sim
        .run(scene, &opts, &mut |_, _| {}, &mut |s| {
            samples.push(s.clone())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    (sim, samples, summary)
}

/// The Manchester vehicle 1 with the Hertz/Polach contact (five times cheaper than `stripes`),
/// its carbody's x frozen, DOPRI5 at rtol 1e-4 / atol 1e-6, and the scene keys in `keys`
/// (track, speed, length; tables such as `[initial]` last).
pub fn manchester_polach(keys: &str) -> Scene {
    vehicle_polach("vehicles/manchester_vehicle1.toml", keys)
}

/// [`manchester_polach`] with another vehicle file (a changed copy of the Manchester vehicle).
pub fn vehicle_polach(vehicle: &str, keys: &str) -> Scene {
    scene(&format!(
        r#"
        vehicle = "{vehicle}"
        freeze = ["carbody.x"]
        {keys}
        [contact]
        model = "polach"
        [integrator]
        method = "dopri5"
        rtol = 1e-4
        atol = 1e-6
        "#
    ))
}

/// Rolling radius and half the distance between the contact points of the centred wheelset
/// under half its weight per wheel (the r0 and b of the linear formulas, measured on the actual
/// wheel/rail pair).
pub fn centred_contact(sim: &Simulation, load: f64, v: f64) -> (f64, f64) {
    let w = &sim.model().wheels[0];
    let mut ws = railsim_contact::ContactWorkspace::new();
    let vel = WheelsetVelocity {
        vx: v,
        spin: v / 0.46,
        ..Default::default()
    };
    w.contacts[0]
        .evaluate_with_load(
            Side::Left,
            &WheelsetPose::default(),
            &vel,
            load,
            1e-9,
            &mut ws,
        )
        .unwrap();
    let p = ws.patches[0];
    (p.rolling_radius, p.point_track[1].abs())
}

/// Effective conicity of a pure cone of slope `lambda` on UIC60 1:40 (gauge 1435 mm,
/// flange-back 1360 mm, r0 = 0.46 m): the slope of the rigid rolling-radius difference,
/// Δr = 2 λe y, computed by `railsim-profile`'s conicity module (independent of the dynamics).
/// The wheelset rolls by Δr / (2 e0) as it shifts, which moves both wheel contacts further by
/// r φ, so λe = λ / (1 − r λ / e0) for a cone on a rail whose contact point does not move.
pub fn cone_effective_conicity(lambda: f64) -> f64 {
    use railsim_profile::conicity::{WheelsetTrackSetup, rolling_radius_difference};
    use railsim_profile::{Profile, ProfileKind, analytic};
    let pts: Vec<[f64; 2]> = (0..=250)
        .map(|i| {
            let y = -0.065 + i as f64 * 0.0005;
            [y, lambda * y]
        })
        .collect();
    let cone = Profile::new("cone", ProfileKind::Wheel, pts).unwrap();
    let ys = [-1e-3, 1e-3];
    let d = rolling_radius_difference(
        &cone,
        &analytic::uic60(),
        &WheelsetTrackSetup::default(),
        &ys,
    )
    .unwrap();
    (d[1].delta_r - d[0].delta_r) / (2.0 * (ys[1] - ys[0]))
}

/// The Wickens reference of `vehicles/wheelset_springs.toml` (vehicle-reference.md §2.2) with
/// linear creep coefficient `f` \[N\], from the actual contact's r0 and b.
pub struct Wickens {
    /// \[m/s\] the formula as printed.
    pub plain: f64,
    /// \[m/s\] with the wheelset's roll on the rails folded in (below).
    pub with_roll: f64,
    /// \[m\] rolling radius and half contact distance of the centred wheelset.
    pub r0: f64,
    /// \[m\]
    pub b: f64,
    /// \[-\] the cone's effective conicity on UIC60 1:40.
    pub lambda_e: f64,
}

/// [`Wickens`] for the scene's wheelset: m = 1813 kg, I = 1120 kg m², λ = 0.15, k_y = 2 ×
/// 3.884 MN/m, k_ψ = 2 × 31.391 MN/m × (1 m)².
pub fn wickens_reference(f: f64) -> Wickens {
    let (m, i, lambda) = (1813.0, 1120.0, 0.15);
    let (ky, kpsi) = (2.0 * 3.884e6, 2.0 * 31.391e6);
    let probe = scene(
        r#"
        vehicle = "vehicles/wheelset_springs.toml"
        track = "tracks/straight.toml"
        speed_kmh = 100
        duration_s = 0.01
        "#,
    );
    let (r0, b) = centred_contact(&Simulation::new(&probe).unwrap(), 0.5 * m * 9.81, 28.0);
    let wickens = |m: f64, ky: f64| {
        let mb = m * b * b + i;
        let num = 4.0 * f * f * b * r0 * (kpsi + b * b * ky);
        let den = 4.0 * f * f * lambda * mb - b * r0 * (m * kpsi - i * ky).powi(2) / mb;
        (num / den).sqrt()
    };
    // The formula's two degrees of freedom (y, ψ) assume the contact point moves with the axle.
    // A wheelset that keeps both wheels on the rails rolls by φ = λe y / b as it shifts, and the
    // contact point moves by y_c = (1 + c) y, c = r0 λe / b, with λe / (1 + c) = λ for a cone. In
    // y_c the equations are exactly the formula's with m → m/(1+c)² + Ix λ²/b² and
    // k_y → k_y/(1+c)² (docs/validation.md §6). λe from the rigid geometry.
    let lambda_e = cone_effective_conicity(lambda);
    let c = r0 * lambda_e / b;
    Wickens {
        plain: wickens(m, ky),
        with_roll: wickens(
            m / (1.0 + c).powi(2) + i * (lambda / b).powi(2),
            ky / (1.0 + c).powi(2),
        ),
        r0,
        b,
        lambda_e,
    }
}

/// The Wickens wheelset's study scene (`vehicles/wheelset_springs.toml`, linear creep f = 1e8 N
/// without spin, DOPRI5 at rtol 1e-7, 2000 Hz samples); studies replace its speed and length.
pub fn wickens_scene() -> Scene {
    scene(
        r#"
        vehicle = "vehicles/wheelset_springs.toml"
        track = "tracks/straight.toml"
        speed_kmh = 1000
        duration_s = 1.4
        [contact]
        model = "linear"
        creep_coefficient_n = 1e8
        [integrator]
        method = "dopri5"
        rtol = 1e-7
        atol = 1e-10
        [log]
        rate_hz = 2000
        "#,
    )
}

/// The Wickens wheelset (`vehicles/wheelset_springs.toml`, [`wickens_scene`]) reduced to its
/// lateral displacement y, roll φ and yaw ψ, with the roll held by the contact's own normal
/// stiffness rather than slaved to y: the check on the eigenvalues of the simulator's full
/// model (docs/validation.md §11, "Wickens with the roll on the contact").
pub struct WickensThreeDof {
    /// \[m/s\] linear critical speed.
    pub critical_speed: f64,
    /// \[Hz\] frequency of the hunting mode there.
    pub frequency: f64,
    /// \[rad/m\] |φ| / |y| of the hunting mode there.
    pub roll_per_y: f64,
    /// \[rad/m\] |ψ| / |y| of the hunting mode there.
    pub yaw_per_y: f64,
    /// \[N/m\] the normal contact stiffness of each wheel used (`stiffness_scale` times the
    /// contact's own).
    pub normal_stiffness: f64,
}

/// Coefficients (ascending powers) of the product of two polynomials.
fn poly_mul(p: &[f64], q: &[f64]) -> Vec<f64> {
    let mut r = vec![0.0; p.len() + q.len() - 1];
    for (i, a) in p.iter().enumerate() {
        for (j, b) in q.iter().enumerate() {
            r[i + j] += a * b;
        }
    }
    r
}

/// `p + s q` (ascending powers).
fn poly_add(p: &[f64], q: &[f64], s: f64) -> Vec<f64> {
    (0..p.len().max(q.len()))
        .map(|i| p.get(i).unwrap_or(&0.0) + s * q.get(i).unwrap_or(&0.0))
        .collect()
}

/// Whether every root of the polynomial `a` (ascending powers, leading coefficient nonzero)
/// lies in the open left half-plane: Routh's array, whose first column must keep its sign.
fn routh_stable(a: &[f64]) -> bool {
    let c: Vec<f64> = a.iter().rev().copied().collect();
    let mut prev: Vec<f64> = c.iter().step_by(2).copied().collect();
    let mut row: Vec<f64> = c.iter().skip(1).step_by(2).copied().collect();
    for _ in 1..c.len() - 1 {
        if row[0] * prev[0] <= 0.0 {
            return false;
        }
        let next: Vec<f64> = (0..prev.len() - 1)
            .map(|k| prev[k + 1] - prev[0] / row[0] * row.get(k + 1).unwrap_or(&0.0))
            .collect();
        prev = std::mem::replace(&mut row, next);
    }
    row[0] * prev[0] > 0.0
}

/// [`WickensThreeDof`] with linear creep coefficient `f` \[N\] per wheel (f11 = f22, no spin)
/// and the contact's normal stiffness times `stiffness_scale` (a large scale approaches the
/// roll slaved to y, [`Wickens::with_roll`]'s premise).
///
/// Derived here (docs/validation.md §11) for a wheelset of pure cones, slope λ = tan δ, on
/// rails: the rigid contact keeps the normal velocity of each wheel's material point at its
/// contact zero, which ties the roll to the shift as φ = λk y / b, λk = λ / (1 − r0 λ / b).
/// On elastic contacts each wheel's interpenetration changes by ±g (λk y / b − φ), g = b cos δ
/// − r0 sin δ (the normal component of the wheel point's motion), against its normal
/// stiffness kn. A yawed cone's contact point leads the axle by (r0 tan δ − b) ψ, so the wheel
/// point's slip along the patch's lateral axis is cos δ ẏ + (r0 cos δ + b sin δ) φ̇ − V ψ /
/// cos δ; the creep force −f × slip / V along that axis gives the generalised forces by
/// virtual power. The rolling radius difference is 2 (λ cos²δ y + β φ): a shift at fixed roll
/// keeps the normals, so the deepest point stays put on the rail and moves along the cone by
/// y cos δ (the rest, y sin δ, is interpenetration); β = (λe − λ cos²δ) b / λk so that the rigid
/// contact's φ = λk y / b gives the rigid geometry's λe (railsim-profile's Δr,
/// [`cone_effective_conicity`]). kn is dN/dδ at the static load, the contact given its vertical
/// load (half the weight) and N = Fz / cos δ. The spinning axle (I_y, Ω = V / r0) adds −I_y Ω ψ̇ to the
/// roll equation and I_y Ω φ̇ to the yaw equation. Left out: gravity's stiffnesses (W λ / b
/// laterally, 2e-4 of the contact's; its yaw stiffness, 3e-5 of k_ψ), the spin and vertical
/// freedoms (uncoupled to first order). The critical speed is where Routh's criterion on
/// det(M s² + D s + K) first fails; the mode there is the null vector of that matrix at s = iω,
/// ω a common real root of the determinant's real and imaginary parts.
pub fn wickens_three_dof(f: f64, stiffness_scale: f64) -> WickensThreeDof {
    let (m, ix, iy, iz) = (1813.0, 1120.0, 112.0, 1120.0);
    let (ky, kpsi, lambda) = (2.0 * 3.884e6, 2.0 * 31.391e6, 0.15f64);
    let w = wickens_reference(f);
    let (r0, b) = (w.r0, w.b);
    // each wheel's normal stiffness dN/dδ at its static load, from the scene's own contact
    let delta = lambda.atan();
    let (cd, sd) = (delta.cos(), delta.sin());
    // the load the contact is given is vertical: half the weight, N = fz / cos δ
    let fz = 0.5 * m * 9.81;
    let sim = Simulation::new(&wickens_scene()).unwrap();
    let mut ws = railsim_contact::ContactWorkspace::new();
    let vel = WheelsetVelocity {
        vx: 28.0,
        spin: 28.0 / r0,
        ..Default::default()
    };
    let mut penetration = |load: f64| {
        sim.model().wheels[0].contacts[0]
            .evaluate_with_load(
                Side::Left,
                &WheelsetPose::default(),
                &vel,
                load,
                1e-12,
                &mut ws,
            )
            .unwrap();
        ws.patches[0].penetration
    };
    let kn_contact = 2e-3 * fz / cd / (penetration(1.001 * fz) - penetration(0.999 * fz));
    let kn = stiffness_scale * kn_contact;
    let lk = lambda / (1.0 - r0 * lambda / b);
    // the rolling radius: a shift at fixed roll keeps the normals, so the deepest point stays
    // put on the rail and moves along the cone by y cos δ (the rest, y sin δ, is
    // interpenetration): λ cos²δ per unit shift; the roll's part β makes up the rigid λe
    let lambda_y = lambda * cd * cd;
    let beta = (w.lambda_e - lambda_y) * b / lk;
    let g = b * cd - r0 * sd;
    let kc = 2.0 * kn * g * g;
    // the roll's lever of the lateral slip, and its share of the creep force's moment
    let h = r0 * cd + b * sd;
    // rows y, φ, ψ; each entry [k, d, m] of k + d s + m s²
    let entries = |v: f64| {
        let gyro = iy * (v / r0);
        [
            [
                [ky + kc * (lk / b).powi(2), 2.0 * f * cd * cd / v, m],
                [-kc * lk / b, 2.0 * f * cd * h / v, 0.0],
                [-2.0 * f, 0.0, 0.0],
            ],
            [
                [-kc * lk / b, 2.0 * f * h * cd / v, 0.0],
                [kc, 2.0 * f * h * h / v, ix],
                [-2.0 * f * h / cd, -gyro, 0.0],
            ],
            [
                [2.0 * f * b * lambda_y / r0, 0.0, 0.0],
                [2.0 * f * b * beta / r0, gyro, 0.0],
                [kpsi, 2.0 * f * b * b / v, iz],
            ],
        ]
    };
    let characteristic = |v: f64| {
        let e = entries(v);
        let minor = |i: usize, j: usize, k: usize, l: usize| {
            poly_add(
                &poly_mul(&e[i][k], &e[j][l]),
                &poly_mul(&e[i][l], &e[j][k]),
                -1.0,
            )
        };
        let d = poly_add(
            &poly_mul(&e[0][0], &minor(1, 2, 1, 2)),
            &poly_mul(&e[0][1], &minor(1, 2, 0, 2)),
            -1.0,
        );
        poly_add(&d, &poly_mul(&e[0][2], &minor(1, 2, 0, 1)), 1.0)
    };
    let (mut lo, mut hi) = (100.0, 600.0);
    assert!(routh_stable(&characteristic(lo)) && !routh_stable(&characteristic(hi)));
    while hi - lo > 1e-9 * hi {
        let mid = 0.5 * (lo + hi);
        if routh_stable(&characteristic(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let v = 0.5 * (lo + hi);
    let a = characteristic(v);
    // P(iω) = 0: the imaginary part a1 − a3 ω² + a5 ω⁴ = 0 gives ω², the real part picks the root
    let (qa, qb, qc) = (a[5], -a[3], a[1]);
    let disc = (qb * qb - 4.0 * qa * qc).sqrt();
    let real_part = |w2: f64| a[0] - a[2] * w2 + a[4] * w2 * w2 - a[6] * w2 * w2 * w2;
    let w2 = [(-qb - disc) / (2.0 * qa), (-qb + disc) / (2.0 * qa)]
        .into_iter()
        .filter(|w2| *w2 > 0.0)
        .min_by(|x, y| real_part(*x).abs().total_cmp(&real_part(*y).abs()))
        .unwrap();
    let omega = w2.sqrt();
    // E(iω) as complex entries (re, im), its null vector the cross product of two rows
    let e = entries(v);
    let c: Vec<Vec<(f64, f64)>> = e
        .iter()
        .map(|row| {
            row.iter()
                .map(|x| (x[0] - x[2] * w2, x[1] * omega))
                .collect()
        })
        .collect();
    let mul = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
    let cross = |i: usize, j: usize| {
        let (x, y) = (mul(c[1][i], c[2][j]), mul(c[1][j], c[2][i]));
        (x.0 - y.0, x.1 - y.1)
    };
    let null = [cross(1, 2), cross(2, 0), cross(0, 1)];
    let abs = |z: (f64, f64)| z.0.hypot(z.1);
    WickensThreeDof {
        critical_speed: v,
        frequency: omega / std::f64::consts::TAU,
        roll_per_y: abs(null[1]) / abs(null[0]),
        yaw_per_y: abs(null[2]) / abs(null[0]),
        normal_stiffness: kn,
    }
}
