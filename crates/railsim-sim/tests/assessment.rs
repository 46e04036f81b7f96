//! The EN 14363 track-shift force of a run (`railsim_sim::assess`) against the physics it
//! measures: in a steady curve the axles' track-shift forces carry the vehicle's uncompensated
//! lateral acceleration; hunting exceeds Prud'homme's limit where stable running stays far
//! below it.

use crate::common;

use common::run;

/// The Manchester vehicle with the Hertz/Polach contact on `track` at `kmh` over `metres`.
fn manchester(track: &str, kmh: f64, metres: f64, initial: &str) -> railsim_sim::Scene {
    common::manchester_polach(&format!(
        "track = \"{track}\"\nspeed_kmh = {kmh}\ndistance_m = {metres}\n{initial}"
    ))
}

#[test]
fn in_a_steady_curve_the_track_shift_forces_carry_the_uncompensated_acceleration() {
    // R = 1200 m, 120 mm cant (tracks/curve_r1200.toml) at 160 km/h: 0.86 m/s² uncompensated
    // in the track plane. The rear wheelset reaches the curve at 320 m; from 450 m on the
    // vehicle runs steadily.
    let s = manchester("tracks/curve_r1200.toml", 160.0, 650.0, "");
    let (sim, samples, summary) = run(&s);
    let v = 160.0 / 3.6;
    let frame = s.track.frame_at(560.0);
    let (kappa, roll) = (frame.curvature, frame.roll);
    assert!((1.0 / kappa - 1200.0).abs() < 1e-6 && roll < 0.0);
    let g = 9.81;
    let axle_loads: Vec<f64> = sim.static_loads().iter().map(|q| q[0] + q[1]).collect();
    let mass = axle_loads.iter().sum::<f64>() / g;
    // Rails on the vehicle along the track plane's y: M (v² κ cos φ + g sin φ); the vehicle
    // on the rails the opposite.
    let expect = -mass * (v * v * kappa * roll.cos() + g * roll.sin());
    let steady: Vec<f64> = samples
        .iter()
        .filter(|smp| {
            let d = smp.t * v;
            (450.0..=650.0).contains(&d)
        })
        .map(|smp| {
            smp.wheelsets
                .iter()
                .map(|w| w.y_left_n - w.y_right_n)
                .sum::<f64>()
        })
        .collect();
    let mean = steady.iter().sum::<f64>() / steady.len() as f64;
    println!(
        "ΣY of the vehicle {:.3} kN against M a = {:.3} kN ({} samples)",
        mean * 1e-3,
        expect * 1e-3,
        steady.len()
    );
    assert!(steady.len() > 500);
    assert!(
        (mean / expect - 1.0).abs() < 0.01,
        "{mean} N against {expect} N"
    );
    // each axle's steady share, by wheelset number
    let mut share = [0.0; 4];
    let mut n_steady = 0;
    for smp in samples
        .iter()
        .filter(|smp| (450.0..=650.0).contains(&(smp.t * v)))
    {
        for w in &smp.wheelsets {
            share[w.wheelset as usize] += w.y_left_n - w.y_right_n;
        }
        n_steady += 1;
    }
    share.iter_mut().for_each(|x| *x /= n_steady as f64);
    println!("steady ΣY per axle [kN]: {:.3?}", share.map(|x| x * 1e-3));
    // The assessment: one axle per wheelset, Prud'homme's limit of its static axle load, and
    // the standard's statistic at least the steady share of its axle. The axles that carry a
    // large share (the bogies' trailing wheelsets, -16.8 and -18.3 kN) have their largest
    // (ΣY)2m toward the outside (-y); the leading ones (-2.2 and -0.8 kN) may reach theirs in
    // the transition, in either direction: the rear bogie's read -2.42 kN at the transition's
    // start from the 200 Hz samples before stop 33, an alias; assessed at 1, 2 (this test's
    // default with `polach`) and 5 kHz it is +2.18 kN within the transition.
    let a = &summary.assessment;
    assert_eq!(a.axles.len(), 4);
    assert!(a.lowpass && a.alpha == 1.0);
    let mut loads_by_number = [0.0; 4];
    for (pair, q) in sim.model().wheels.chunks(2).zip(&axle_loads) {
        loads_by_number[pair[0].wheelset_number as usize] = *q;
    }
    for ax in &a.axles {
        let q0 = loads_by_number[ax.wheelset as usize];
        assert!((ax.axle_load - q0).abs() < 1e-9);
        assert!((ax.sum_y_limit - (10e3 + q0 / 3.0)).abs() < 1e-6);
        let m = ax.sum_y_2m.unwrap();
        let steady = share[ax.wheelset as usize];
        if steady < -5e3 {
            assert!(m.value < 0.0, "wheelset {}: {m:?}", ax.wheelset);
        }
        // the standard's statistic lies between the steady share and the largest value
        let p = ax.sum_y_2m_percentile.unwrap();
        assert!(p <= m.value.abs() + 1e-9);
        assert!(
            p >= 0.98 * steady.abs(),
            "wheelset {}: statistic {p} N, steady share {steady} N",
            ax.wheelset
        );
    }
    // below the limits: a curve this mild is no test of the vehicle's safety
    for ax in &a.axles {
        assert!(ax.sum_y_2m.unwrap().value.abs() < ax.sum_y_limit);
        assert!(ax.sum_y_rms.unwrap().value < ax.rms_limit());
    }
    // What an accelerometer at the carbody's centre reads in the steady curve: the specific
    // force of the frame's motion, (0, v²κ cos φ + g sin φ, g cos φ − v²κ sin φ) in the track
    // plane's axes, turned into the carbody's by its roll ψ relative to the track plane (it
    // leans out of the curve: ψ > 0 in a left curve).
    let names: Vec<&str> = a.comfort.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "carbody centre",
            "carbody above bogie_front",
            "carbody above bogie_rear"
        ]
    );
    let m = &sim.model().members;
    let cb = m.iter().position(|mm| mm.name == "carbody").unwrap();
    let roll_ix = m[cb].pos[3].unwrap();
    let steady: Vec<&railsim_sim::Sample> = samples
        .iter()
        .filter(|smp| (450.0..=650.0).contains(&(smp.t * v)))
        .collect();
    let n = steady.len() as f64;
    let psi = steady.iter().map(|smp| smp.x[roll_ix]).sum::<f64>() / n;
    let f_t = [
        v * v * kappa * roll.cos() + g * roll.sin(),
        g * roll.cos() - v * v * kappa * roll.sin(),
    ];
    let expect = [
        psi.cos() * f_t[0] + psi.sin() * f_t[1],
        -psi.sin() * f_t[0] + psi.cos() * f_t[1],
    ];
    for (k, what) in ["lateral", "vertical"].iter().enumerate() {
        let mean = steady.iter().map(|smp| smp.carbody[0][k + 1]).sum::<f64>() / n;
        println!(
            "carbody centre, {what}: {mean:.4} m/s² against {:.4} (carbody roll {:.2} mrad)",
            expect[k],
            psi * 1e3
        );
        assert!(
            (mean - expect[k]).abs() < 0.002 * g,
            "{what}: {mean} against {}",
            expect[k]
        );
    }
    assert!(psi > 0.0, "the carbody leans out of the curve: {psi}");
    // Quasi-static wheel forces (the medians in the circular curve): their sums carry the
    // vehicle's weight and centrifugal force as the track plane sees them. Every wheel ran in
    // the curve; the right wheel is the outer one of this left curve.
    assert_eq!(a.wheels.len(), 8);
    let (mut sum_q, mut sum_y) = (0.0, 0.0);
    for w in &a.wheels {
        assert_eq!(w.quasi_static.len(), 1, "{w:?}");
        let q = &w.quasi_static[0];
        assert!((q.radius - 1200.0).abs() < 1e-6);
        assert_eq!(q.outer, w.side == railsim_contact::Side::Right);
        sum_q += q.q_qst;
        // Y on the rail toward its field side: +y on the left rail, -y on the right
        sum_y += match w.side {
            railsim_contact::Side::Left => q.y_qst,
            railsim_contact::Side::Right => -q.y_qst,
        };
        // (Y/Q)2m: one zone (1200 m is no small radius); its climbing tail at least the
        // steady quotient; Q's limit 90 kN + Q0 (160 km/h: no cap below 200 kN)
        assert_eq!(w.y_over_q.len(), 1);
        let z = &w.y_over_q[0];
        assert!(!z.small_radius && z.limit == 0.8);
        assert!(z.percentile >= q.y_qst / q.q_qst - 1e-3, "{z:?} {q:?}");
        assert!(z.percentile < 0.2 && w.q_percentile.unwrap() < w.q_limit);
        assert!(w.q_percentile.unwrap() >= q.q_qst);
        assert!((w.q_limit - (90e3 + w.static_load)).abs() < 1e-6);
        assert!(q.y_qst.abs() < a.limits.y_qst && q.q_qst < a.limits.q_qst);
    }
    let weight = mass * f_t[1];
    let lateral = -mass * f_t[0];
    println!(
        "sum of Q_qst {:.3} kN against M (g cos φ - v²κ sin φ) = {:.3} kN; sum of Y_qst toward \
         +y {:.3} kN against {:.3} kN",
        sum_q * 1e-3,
        weight * 1e-3,
        sum_y * 1e-3,
        lateral * 1e-3
    );
    assert!((sum_q / weight - 1.0).abs() < 0.002, "{sum_q} {weight}");
    assert!((sum_y / lateral - 1.0).abs() < 0.02, "{sum_y} {lateral}");
    // The bogie frames: two, each measured above its two wheelsets, m_b the frame and its
    // wheelsets; a steady curve gives no hunting
    let names: Vec<&str> = a
        .bogies
        .iter()
        .flat_map(|b| b.points.iter().map(|p| p.name.as_str()))
        .collect();
    assert_eq!(
        names,
        [
            "bogie_front above ws1",
            "bogie_front above ws2",
            "bogie_rear above ws3",
            "bogie_rear above ws4"
        ]
    );
    let mass_of = |n: &str| m.iter().find(|mm| mm.name == n).unwrap().mass;
    let m_b = mass_of("bogie_front") + mass_of("ws1") + mass_of("ws2");
    assert!((a.bogies[0].mass - m_b).abs() < 1e-9);
    assert!((a.bogies[0].peak_limit - (12.0 - m_b / 5e3)).abs() < 1e-12);
    for b in &a.bogies {
        for p in &b.points {
            assert!(p.rms.unwrap().value < 0.05 * b.rms_limit(), "{p:?}");
        }
    }
}

/// Flange-contact hunting against a decaying disturbance: the track-shift force's statistic
/// near its limit, its running-stability r.m.s. at it, the ride and the bogie frames'
/// criterion, against values far below. Until stop 32 the assessment sampled this 200 Hz run
/// at 200 Hz and gave (ΣY)2m 3.1 times its limit, an alias of the flange impacts; assessed at
/// the Hertz models' default 2 kHz it is 0.79 (0.80 at 1 kHz, 0.79 at 5 kHz; docs/validation.md
/// §9).
#[test]
fn flange_hunting_nears_the_track_shift_limit_where_stable_running_does_not() {
    // Ideal straight track, the leading wheelset 5 mm off centre. With `polach` the vehicle
    // hunts in flange contact at 300 km/h and settles at 160 km/h (docs/validation.md §8:
    // the ramp-down fold of `polach` is near 190 km/h).
    let initial = "[initial]\nlateral_offset_mm = 5.0";
    let hunting = manchester("tracks/straight.toml", 300.0, 600.0, initial);
    let (_, hunting_samples, h) = run(&hunting);
    let stable = manchester("tracks/straight.toml", 160.0, 600.0, initial);
    let (_, _, st) = run(&stable);
    let worst = |s: &railsim_sim::RunSummary| {
        s.assessment
            .axles
            .iter()
            .map(|a| a.sum_y_2m_percentile.unwrap() / a.sum_y_limit)
            .fold(0.0f64, f64::max)
    };
    let worst_rms = |s: &railsim_sim::RunSummary| {
        s.assessment
            .axles
            .iter()
            .map(|a| a.sum_y_rms.unwrap().value / a.rms_limit())
            .fold(0.0f64, f64::max)
    };
    println!(
        "(ΣY)2m / limit: hunting {:.2}, stable {:.2}; r.m.s. / limit: hunting {:.2}, stable {:.2}",
        worst(&h),
        worst(&st),
        worst_rms(&h),
        worst_rms(&st)
    );
    // (ΣY)2m: hunting 0.79 of the limit, stable 0.21 (assessed at 2 kHz)
    assert!(worst(&h) > 0.6, "{}", worst(&h));
    assert!(worst(&st) < 0.4, "{}", worst(&st));
    // the r.m.s. criterion: hunting at its limit (0.95 when written, 1.02 since stop 33), the
    // decaying disturbance far below (0.08)
    assert!(worst_rms(&h) > 0.7, "{}", worst_rms(&h));
    assert!(worst_rms(&st) < 0.2, "{}", worst_rms(&st));
    // the ride: hunting shakes the carbody over its bogies far more than the decaying
    // disturbance does (lateral Wz)
    let wz = |s: &railsim_sim::RunSummary| -> Vec<f64> {
        s.assessment
            .comfort
            .iter()
            .map(|c| c.wz[0].unwrap())
            .collect()
    };
    println!("lateral Wz: hunting {:?}, stable {:?}", wz(&h), wz(&st));
    for (a, b) in wz(&h).iter().zip(wz(&st)) {
        assert!(*a > b + 0.5, "{a} {b}");
    }
    // the simplified method sees the same: the bogie frames' band-passed lateral acceleration
    // of the hunting run against that of the decaying disturbance
    let bogie = |s: &railsim_sim::RunSummary| {
        s.assessment
            .bogies
            .iter()
            .flat_map(|b| {
                b.points
                    .iter()
                    .map(|p| p.rms.unwrap().value / b.rms_limit())
            })
            .fold(0.0f64, f64::max)
    };
    println!(
        "bogie frame r.m.s. / limit: hunting {:.2}, stable {:.3}",
        bogie(&h),
        bogie(&st)
    );
    // the criterion's verdict: exceeded by the flange hunting (1.15 when written), met by the
    // decaying disturbance (0.40, the flange impacts of the 5 mm start)
    assert!(bogie(&h) > 1.0, "{}", bogie(&h));
    assert!(bogie(&st) < 1.0, "{}", bogie(&st));
    // the instability frequency found in ΣY is the hunting frequency of the half waves
    let (f0, found) = h.assessment.instability_frequency.unwrap();
    assert!(found);
    let hunting_period = hunting_period(&hunting_samples);
    assert!(
        (f0 * hunting_period - 1.0).abs() < 0.05,
        "f0 {f0} Hz, half waves {} Hz",
        1.0 / hunting_period
    );
}

/// \[s\] the mean period of the leading wheelset's hunting over the second half of a run,
/// from its half waves.
fn hunting_period(samples: &[railsim_sim::Sample]) -> f64 {
    let t: Vec<f64> = samples.iter().map(|x| x.t).collect();
    let y: Vec<f64> = samples.iter().map(|x| x.lateral[0]).collect();
    let half = railsim_sim::stability::half_cycles(&t, &y, 0.0, 0.5e-3);
    let late: Vec<_> = half.iter().filter(|c| c.t > 0.5 * t[t.len() - 1]).collect();
    assert!(late.len() > 4, "{late:?}");
    2.0 * (late[late.len() - 1].t - late[0].t) / (late.len() - 1) as f64
}

#[test]
fn the_carbody_and_bogie_frame_accelerometers_are_logged_as_sampled() {
    let dir = std::env::temp_dir().join(format!("railsim-carbody-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let log = dir.join("carbody.mcap");
    let s = manchester("tracks/straight.toml", 100.0, 15.0, "");
    let mut sim = railsim_sim::Simulation::new(&s).unwrap();
    let mut samples = Vec::new();
    let opts = railsim_sim::RunOptions {
        log_path: Some(log.clone()),
        ..Default::default()
    };
    sim.run(&s, &opts, &mut |_, _| {}, &mut |smp| {
        samples.push(smp.clone())
    })
    .unwrap();
    let reader = railsim_log::LogReader::open(&log).unwrap();
    let names = [
        "carbody centre",
        "carbody above bogie_front",
        "carbody above bogie_rear",
    ];
    for (n, name) in names.iter().enumerate() {
        let msgs: Vec<(u64, railsim_log::CarbodyMessage)> = reader
            .read_topic(&railsim_log::topics::carbody(n), None)
            .unwrap();
        assert_eq!(msgs.len(), samples.len());
        for ((_, m), smp) in msgs.iter().zip(&samples) {
            assert_eq!(m.point, *name);
            assert_eq!(
                [m.longitudinal_m_s2, m.lateral_m_s2, m.vertical_m_s2],
                smp.carbody[n]
            );
            assert_eq!(m.t_s, smp.t);
        }
        // at 100 km/h on ideal straight track the carbody rests at (0, +g), but for the small
        // settling of the start (1.6 mm/s² above the front bogie at 0.54 s when written)
        let (_, last) = &msgs[msgs.len() - 1];
        assert!(last.longitudinal_m_s2.abs() < 1e-3, "{last:?}");
        assert!(last.lateral_m_s2.abs() < 1e-3, "{last:?}");
        assert!((last.vertical_m_s2 - 9.81).abs() < 0.01, "{last:?}");
    }
    // the bogie frames' accelerometers, one above each wheelset, likewise
    let names = [
        "bogie_front above ws1",
        "bogie_front above ws2",
        "bogie_rear above ws3",
        "bogie_rear above ws4",
    ];
    for (n, name) in names.iter().enumerate() {
        let msgs: Vec<(u64, railsim_log::BogieFrameMessage)> = reader
            .read_topic(&railsim_log::topics::bogie_frame(n), None)
            .unwrap();
        assert_eq!(msgs.len(), samples.len());
        for ((_, m), smp) in msgs.iter().zip(&samples) {
            assert_eq!(m.point, *name);
            assert_eq!(
                [m.longitudinal_m_s2, m.lateral_m_s2, m.vertical_m_s2],
                smp.bogie_frames[n]
            );
        }
        let (_, last) = &msgs[msgs.len() - 1];
        assert!(last.lateral_m_s2.abs() < 1e-2, "{last:?}");
        assert!((last.vertical_m_s2 - 9.81).abs() < 0.05, "{last:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_scene_places_its_own_measuring_points() {
    let base = manchester("tracks/straight.toml", 100.0, 15.0, "");
    let custom = manchester(
        "tracks/straight.toml",
        100.0,
        15.0,
        "[assessment]\ncomfort_points = [{ name = \"floor\", x_m = 9.5, z_m = -1.0 }, \
         { name = \"cog\" }]",
    );
    let (_, a, sa) = run(&base);
    let (_, b, sb) = run(&custom);
    let names: Vec<&str> = sb
        .assessment
        .comfort
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, ["floor", "cog"]);
    // the points do not change the motion: the centre of gravity reads as the default centre
    assert_eq!(sa.digest, sb.digest);
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.carbody[0], y.carbody[1]);
    }
    // and a point off the centre reads the rigid-body terms: different, but close at rest
    let last = &b[b.len() - 1].carbody;
    assert_ne!(last[0], last[1]);
    assert!((last[0][2] - last[1][2]).abs() < 0.05, "{last:?}");
}

/// Transition shapes as the carbody feels them: the Manchester vehicle at 100 km/h from a
/// tangent through a 50 m transition into R = 500 m with 100 mm cant (0.69 m/s² uncompensated
/// in the curve), once over a clothoid and once over a Bloss curve. Both reach the same steady
/// curve (the leading outer wheel's Y_qst agrees within 1 %). At the clothoid's ends the cant's
/// slope steps, so the frame's roll rate does (V φ′ = 0.037 rad/s here): since stop 38 the bodies
/// keep their absolute motion there (`run::frame_kinks`) and their suspensions make them follow,
/// and EN 14363's band-passed (0.4–10 Hz) lateral acceleration at the carbody's centre peaks at
/// 0.057 m/s² over the clothoid against 0.056 over the Bloss curve, whose smooth ends still ride
/// a little better (Sperling's Wz 1.19 against 1.11). Before, each body took the frame's new
/// rate at once, a kick no force gave, and the clothoid's peak was 0.222 m/s² (Wz 1.95): the
/// criterion (below 0.1 m/s²) fails without the kink handling.
#[test]
fn over_a_clothoid_the_carbody_takes_no_kick_at_the_kinks() {
    let dir = std::env::temp_dir().join(format!("railsim_transition_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut runs = Vec::new();
    for shape in ["clothoid", "bloss"] {
        let path = dir.join(format!("{shape}.toml"));
        std::fs::write(
            &path,
            format!(
                "gauge_mm = 1435\nrail_inclination = \"1:40\"\n\
                 rail_profile = {{ left = \"uic60\", right = \"uic60\" }}\n\
                 [[segment]]\ntype = \"tangent\"\nlength_m = 120\n\
                 [[segment]]\ntype = \"{shape}\"\nlength_m = 50\n\
                 [[segment]]\ntype = \"curve\"\nradius_m = 500\ncant_mm = 100\n\
                 direction = \"right\"\nlength_m = 200\n"
            ),
        )
        .unwrap();
        let s = manchester(path.to_str().unwrap(), 100.0, 300.0, "");
        let (_, _, summary) = run(&s);
        let a = &summary.assessment;
        let centre = &a.comfort[0];
        let (peak, _) = centre.band_passed[0].unwrap();
        // the leading wheelset's outer (left) wheel in the curve
        let y_qst = a
            .wheels
            .iter()
            .find(|w| w.wheelset == 0 && w.side == railsim_contact::Side::Left)
            .unwrap()
            .quasi_static[0]
            .y_qst;
        println!(
            "{shape}: {} band-passed lateral peak {peak:.3} m/s², Wz {:.2}; Y_qst {:.2} kN",
            centre.name,
            centre.wz[0].unwrap(),
            y_qst * 1e-3
        );
        runs.push((peak, y_qst, centre.wz[0].unwrap()));
    }
    std::fs::remove_dir_all(&dir).ok();
    let ((clothoid, y_c, wz_c), (bloss, y_b, wz_b)) = (runs[0], runs[1]);
    assert!((y_b / y_c - 1.0).abs() < 0.01, "{y_b} against {y_c}");
    assert!(y_c > 15e3, "the outer wheel carries the curve: {y_c}");
    assert!(clothoid < 0.1, "{clothoid} m/s²");
    assert!(bloss < 1.05 * clothoid, "{bloss} against {clothoid} m/s²");
    assert!(wz_b < wz_c, "Wz {wz_b} against {wz_c}");
}

/// `[assessment] rate_hz` (docs/models/dynamics.md, "Aliasing"): the assessment's samples
/// between the log's. A `polach` run logged at 200 Hz and assessed at 2 kHz is the run logged at
/// 2 kHz to the bit (the same evaluations: the same state digest and assessment), with a tenth of
/// the log's samples; without the key, a 200 Hz log is assessed at 2 kHz too (the Hertz models'
/// default; 1 kHz for STRIPES); assessed at 1 kHz or at its 200 Hz log rate, the same run differs.
#[test]
fn the_assessment_rate_samples_between_the_log_samples() {
    let scene = |log_hz: u32, extra: &str| {
        manchester(
            "tracks/straight_irregular.toml",
            198.0,
            30.0,
            &format!("[log]\nrate_hz = {log_hz}\n{extra}"),
        )
    };
    let (_, fast_log, fast) = run(&scene(2000, ""));
    let (_, slow_log, assessed) = run(&scene(200, "[assessment]\nrate_hz = 2000"));
    let (_, default_log, default) = run(&scene(200, ""));
    let (_, _, at_1k) = run(&scene(200, "[assessment]\nrate_hz = 1000"));
    let (_, _, aliased) = run(&scene(200, "[assessment]\nrate_hz = 200"));
    eprintln!(
        "log samples {} / {}; digests {:016x} {:016x} {:016x} {:016x} {:016x}",
        fast.samples,
        assessed.samples,
        fast.digest,
        assessed.digest,
        default.digest,
        at_1k.digest,
        aliased.digest
    );
    for other in [&assessed, &default] {
        assert_eq!(fast.digest, other.digest);
        assert_eq!(
            format!("{:?}", fast.assessment),
            format!("{:?}", other.assessment)
        );
        assert_eq!(
            (fast.max_q, fast.max_y_over_q),
            (other.max_q, other.max_y_over_q)
        );
    }
    assert_eq!(fast_log.len() as u64, fast.samples);
    assert_eq!(slow_log.len() as u64, assessed.samples);
    assert_eq!(default_log.len() as u64, default.samples);
    assert_eq!(default.samples, assessed.samples);
    assert_eq!(fast.samples, 10 * (assessed.samples - 1) + 1);
    assert_ne!(fast.digest, at_1k.digest);
    assert_ne!(fast.digest, aliased.digest);
    let rates = [&fast, &assessed, &default, &at_1k, &aliased].map(|s| s.assessment_rate_hz);
    assert_eq!(rates, [2000.0, 2000.0, 2000.0, 1000.0, 200.0]);
}
