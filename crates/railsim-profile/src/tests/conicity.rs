//! Rigid wheelset geometry: S1002 on UIC60 1:40, gauge 1435, fb 1360 (contact-theory §6.2).

use crate::analytic::{s1002, uic60};
use crate::conicity::*;

#[test]
fn s1002_uic60_1to40_conicity() {
    let t0 = std::time::Instant::now();
    let g = WheelsetTrack::new(&s1002(), &uic60(), &WheelsetTrackSetup::default()).unwrap();
    // Centred: contact at S = +3.25 mm, r = 459.906 mm, 1.39 deg (§5.3).
    let c0 = g.contact(0.0).unwrap();
    eprintln!(
        "y=0: S = {:.3} mm, r = {:.4} mm, angle {:.3} deg, roll {:.2e}",
        c0.y_contact_wheel_left * 1e3,
        c0.r_left * 1e3,
        c0.contact_angle_left.to_degrees(),
        c0.roll
    );
    assert!((c0.y_contact_wheel_left * 1e3 - 3.25).abs() < 0.1);
    assert!((c0.r_left * 1e3 - 459.906).abs() < 0.002);
    assert!((c0.contact_angle_left.to_degrees() - 1.39).abs() < 0.05);
    assert!(c0.delta_r.abs() < 1e-9);
    // Antisymmetry.
    let p = g.contact(0.002).unwrap();
    let m = g.contact(-0.002).unwrap();
    assert!(
        (p.delta_r + m.delta_r).abs() < 1e-8,
        "{} {}",
        p.delta_r,
        m.delta_r
    );
    // Table on [0, 6.5] mm every 0.02 mm, mirrored.
    let n = 325;
    let half: Vec<DeltaRSample> = (0..=n)
        .map(|i| g.contact(i as f64 * 0.02e-3).unwrap())
        .collect();
    let mut table: Vec<DeltaRSample> = half[1..]
        .iter()
        .rev()
        .map(|s| DeltaRSample {
            y_ws: -s.y_ws,
            delta_r: -s.delta_r,
            ..*s
        })
        .collect();
    table.extend(half.iter().copied());
    eprintln!("{} contact solutions in {:.2?}", n + 2, t0.elapsed());
    // Δr at 1..4 mm within 3% of §6.2; contact positions.
    let reference = [
        (1, 0.637, -9.36, 6.54),
        (2, 0.805, -11.15, 8.73),
        (3, 0.994, -13.11, 10.45),
        (4, 1.235, -15.37, 11.89),
    ];
    for (y, dr, sl, sr) in reference {
        let s = &half[y * 50];
        eprintln!(
            "y = {y} mm: dr = {:.4} mm (ref {dr}), S_L = {:.2} (ref {sl}), S_R = {:.2} (ref {sr})",
            s.delta_r * 1e3,
            s.y_contact_wheel_left * 1e3,
            s.y_contact_wheel_right * 1e3
        );
        assert!((s.delta_r * 1e3 / dr - 1.0).abs() < 0.03);
        assert!((s.y_contact_wheel_left * 1e3 - sl).abs() < 0.3);
        assert!((s.y_contact_wheel_right * 1e3 - sr).abs() < 0.3);
    }
    // Contact jumps: largest change of the left contact position per step.
    let jump = |lo: f64, hi: f64| {
        half.windows(2)
            .filter(|w| w[0].y_ws >= lo && w[1].y_ws <= hi)
            .map(|w| {
                (
                    w[1].y_contact_wheel_left - w[0].y_contact_wheel_left,
                    w[1].y_ws,
                )
            })
            .fold(
                (0.0f64, 0.0f64),
                |a, b| if b.0.abs() > a.0.abs() { b } else { a },
            )
    };
    let (j1, y1) = jump(0.0, 1e-3);
    let (j2, y2) = jump(5e-3, 6.5e-3);
    eprintln!(
        "tread jump {:.2} mm at y = {:.2} mm; flange jump {:.2} mm at y = {:.2} mm",
        j1 * 1e3,
        y1 * 1e3,
        j2 * 1e3,
        y2 * 1e3
    );
    assert!(j1 < -5e-3 && y1 > 0.2e-3 && y1 <= 0.26e-3);
    assert!(j2 < -2e-3 && y2 > 6.1e-3 && y2 <= 6.4e-3);
    let s7 = g.contact(7e-3).unwrap();
    eprintln!(
        "y = 7 mm: S_L = {:.2} mm, r_L = {:.2} mm, angle {:.1} deg",
        s7.y_contact_wheel_left * 1e3,
        s7.r_left * 1e3,
        s7.contact_angle_left.to_degrees()
    );
    // Equivalent conicity.
    let f = |y: f64| delta_r_interp(&table, y);
    for (a, h_ref, k_ref) in [
        (1.0, 0.375, 0.370),
        (2.0, 0.232, 0.229),
        (3.0, 0.185, 0.184),
        (4.0, 0.166, 0.165),
    ] {
        let lh = equivalent_conicity_harmonic(f, a * 1e-3);
        let (lk, l) = equivalent_conicity_kinematic(f, a * 1e-3, 0.75, 0.46).unwrap();
        eprintln!(
            "lambda_e({a} mm): harmonic {lh:.4} (ref {h_ref}), kinematic {lk:.4} (ref {k_ref}), L = {l:.2} m"
        );
        assert!((lh - h_ref).abs() < 0.01);
        assert!((lk - k_ref).abs() < 0.01);
    }
    let l3 = equivalent_conicity_harmonic(f, 3e-3);
    assert!((l3 - 0.185).abs() < 0.01);
}

#[test]
fn conicity_of_a_linear_cone() {
    // Δr = 2 λ y gives λ_e = λ for both definitions, and Klingel's wavelength.
    let f = |y: f64| 2.0 * 0.2 * y;
    assert!((equivalent_conicity_harmonic(f, 3e-3) - 0.2).abs() < 1e-9);
    let (lk, l) = equivalent_conicity_kinematic(f, 3e-3, 0.75, 0.46).unwrap();
    assert!((lk - 0.2).abs() < 1e-5, "{lk}");
    let klingel = 2.0 * std::f64::consts::PI * (0.75f64 * 0.46 / 0.2).sqrt();
    assert!((l - klingel).abs() < 1e-3);
}

/// S1002 on UIC60 1:20 at 6 mm: the flange-root jump lies just below the amplitude (about
/// 5.97 mm), where the harmonic weight of a jump changes fastest. Linear interpolation over a
/// 25 µm grid moves it to the middle of its interval, which gave λe 0.062 (contact-theory §6.2:
/// 0.051); with the jumps located ([`rolling_radius_difference_with_jumps`]) the value no longer
/// depends on the grid and lies near the step model's 0.054.
#[test]
fn located_contact_jumps_make_the_conicity_independent_of_the_grid() {
    let setup = WheelsetTrackSetup {
        inclination_rad: (1.0f64 / 20.0).atan(),
        ..Default::default()
    };
    let (wheel, rail) = (s1002(), uic60());
    let grid = |step: f64| -> Vec<f64> {
        let n = (10e-3 / step).round() as i64;
        (-n..=n).map(|i| i as f64 * step).collect()
    };
    let lambda = |samples: &[DeltaRSample]| {
        equivalent_conicity_harmonic(|y| delta_r_interp(samples, y), 6e-3)
    };
    let plain = lambda(&rolling_radius_difference(&wheel, &rail, &setup, &grid(25e-6)).unwrap());
    let located: Vec<f64> = [25e-6, 40e-6, 100e-6]
        .iter()
        .map(|&h| {
            lambda(
                &rolling_radius_difference_with_jumps(&wheel, &rail, &setup, &grid(h), 1e-3)
                    .unwrap(),
            )
        })
        .collect();
    eprintln!("λe(6 mm), 1:20: {plain:.4} on 25 µm, located {located:.4?} on 25, 40, 100 µm");
    for l in &located {
        assert!((l / located[0] - 1.0).abs() < 0.01, "{located:?}");
    }
    assert!((0.050..0.057).contains(&located[0]), "{}", located[0]);
    assert!(plain > 1.1 * located[0], "{plain} against {}", located[0]);
}

#[test]
fn s1002s_flange_angle_is_its_70_degree_flank() {
    // EN 13715's S1002: section E, the flange flank, is a straight line of slope 2.7475 =
    // tan 70.0° over -39.764 <= S < -38.427 mm (contact-theory note §5.1)
    let f = flange_angle(&s1002()).unwrap().unwrap();
    assert!(
        (f.angle.to_degrees() - 70.0).abs() < 0.02,
        "{}°",
        f.angle.to_degrees()
    );
    assert!((-39.8e-3..=-38.4e-3).contains(&f.y), "at {} mm", f.y * 1e3);
    // a wheel z(y) sampled every 2.5 mm over -60 ... 40 mm
    let wheel = |name: &str, z: &dyn Fn(f64) -> f64| {
        let points = (0..=40)
            .map(|i| -0.06 + i as f64 * 2.5e-3)
            .map(|y| [y, z(y)]);
        crate::Profile::new(name, crate::ProfileKind::Wheel, points.collect()).unwrap()
    };
    // a cone (1:20, the radius growing toward negative y) has no flange
    let cone = wheel("cone", &|y| 0.05 * y);
    assert_eq!(flange_angle(&cone).unwrap(), None);
    // a cone with a chamfer rising at its back (its lowest point inside the profile): its
    // steepest rise, 1:20, is no flange either
    let chamfer = |y: f64| if y < -0.05 { 0.3 * (-0.05 - y) } else { 0.0 };
    let chamfered = wheel("chamfered cone", &|y| 0.05 * y + chamfer(y));
    assert_eq!(flange_angle(&chamfered).unwrap(), None);
    // S1002 cut at its flange tip (S = -49.7 mm): the flank is still found
    let p = s1002();
    let cut: Vec<[f64; 2]> = p
        .points
        .iter()
        .copied()
        .filter(|q| q[0] >= -0.0497)
        .collect();
    let cut = crate::Profile::new("cut", crate::ProfileKind::Wheel, cut).unwrap();
    let f = flange_angle(&cut).unwrap().unwrap();
    assert!(
        (f.angle.to_degrees() - 70.0).abs() < 0.02,
        "{}°",
        f.angle.to_degrees()
    );
}

#[test]
fn s1002s_flange_dimensions_are_28_32_5_and_10_79_mm() {
    // contact-theory note §5.1, derived from the section formulas: the tip at S = -55 mm,
    // 28.000 mm high; the flange face 10 mm from the taping line at S = -37.500 (R13 root),
    // 32.50 mm from the flange back at S = -70; 2 mm from the tip at S = -48.294 (R20 corner),
    // qR 10.79 mm
    let d = flange_dimensions(&s1002(), -0.070).unwrap().unwrap();
    eprintln!("S1002: {d:?}");
    assert!((d.height - 0.028).abs() < 1e-6, "Sh {}", d.height);
    assert!((d.tip[0] + 0.055).abs() < 0.1e-3, "tip at {:?}", d.tip);
    assert!((d.thickness - 0.0325).abs() < 5e-6, "Sd {}", d.thickness);
    assert!((d.thickness_point[0] + 0.0375).abs() < 5e-6);
    assert!((d.thickness_point[1] + 0.010).abs() < 1e-9);
    assert!((d.qr - 0.010794).abs() < 5e-6, "qR {}", d.qr);
    assert!((d.qr_point[1] + 0.026).abs() < 1e-9);
    // Sd is measured from the flange back where it is given
    let d2 = flange_dimensions(&s1002(), -0.071).unwrap().unwrap();
    assert!((d2.thickness - d.thickness - 1e-3).abs() < 1e-12);
    // A flange built of straight lines and a flat top, sampled every 0.02 mm: tread level
    // (z = 0) from y = y_f, a 70° flank up to the tip 30 mm high, a flat tip to -55 mm and a
    // vertical back. Its dimensions by hand: Sh 30, Sd = y_f - 10/tan 70° + 70 mm, qR =
    // 18/tan 70° mm. A flange worn 3 mm thinner (the flank at y_f = -33 mm against -30): Sd
    // 3 mm less, Sh and qR the same.
    let t70 = 70f64.to_radians().tan();
    for y_f in [-0.030, -0.033] {
        let z = |y: f64| {
            if y >= y_f {
                0.0
            } else {
                (-(y_f - y) * t70).max(-0.030)
            }
        };
        let n = ((0.040 + 0.0549) / 2e-5) as usize;
        let points: Vec<[f64; 2]> = (0..=n)
            .map(|i| -0.0549 + i as f64 * 2e-5)
            .map(|y| [y, z(y)])
            .collect();
        let wheel =
            crate::Profile::new("trapezoid flange", crate::ProfileKind::Wheel, points).unwrap();
        let d = flange_dimensions(&wheel, -0.070).unwrap().unwrap();
        let sd = y_f - 0.010 / t70 + 0.070;
        let qr = 0.018 / t70;
        eprintln!("y_f {y_f}: {d:?}; Sd {sd}, qR {qr} by hand");
        assert!((d.height - 0.030).abs() < 10e-6, "Sh {}", d.height);
        assert!(
            (d.thickness - sd).abs() < 2e-6,
            "Sd {} against {sd}",
            d.thickness
        );
        assert!((d.qr - qr).abs() < 2e-6, "qR {} against {qr}", d.qr);
    }
    // no flange: a cone (its lowest point at its end), and S1002 cut short of its tip, on the
    // face (-38, -45 mm) or just before the tip (-54 mm): the cut end is no tip
    let cone: Vec<[f64; 2]> = (0..=40)
        .map(|i| -0.06 + i as f64 * 2.5e-3)
        .map(|y| [y, 0.05 * y])
        .collect();
    let cone = crate::Profile::new("cone", crate::ProfileKind::Wheel, cone).unwrap();
    assert_eq!(flange_dimensions(&cone, -0.070).unwrap(), None);
    let p = s1002();
    for cut_at in [-0.038, -0.045, -0.054] {
        let cut: Vec<[f64; 2]> = p
            .points
            .iter()
            .copied()
            .filter(|q| q[0] >= cut_at)
            .collect();
        let cut = crate::Profile::new("cut", crate::ProfileKind::Wheel, cut).unwrap();
        assert_eq!(
            flange_dimensions(&cut, -0.070).unwrap(),
            None,
            "cut at {cut_at}"
        );
    }
    // heights from the taping line's own level: the profile 5 mm higher measures the same
    let raised: Vec<[f64; 2]> = p.points.iter().map(|q| [q[0], q[1] + 0.005]).collect();
    let raised = crate::Profile::new("raised", crate::ProfileKind::Wheel, raised).unwrap();
    let r = flange_dimensions(&raised, -0.070).unwrap().unwrap();
    assert!((r.height - d.height).abs() < 1e-9 && (r.thickness - d.thickness).abs() < 1e-9);
    assert!((r.qr - d.qr).abs() < 1e-9);
    // a lip on the face (a dip of z to 11 mm below the taping line, 2.5 mm outside the face's
    // 10 mm point): Sd is taken at the outermost material at the 10 mm level, in the lip, the
    // point a gauge's finger coming from the tread touches; the lip's crossing by dense sampling
    let y_f = -0.030;
    let y_lip = y_f - 0.010 / t70 + 0.0025;
    let lip = |y: f64| {
        let base = if y >= y_f {
            0.0
        } else {
            (-(y_f - y) * t70).max(-0.030)
        };
        base - 0.011 * (-((y - y_lip) / 0.4e-3).powi(2)).exp()
    };
    let n = ((0.040 + 0.0549) / 2e-5) as usize;
    let points: Vec<[f64; 2]> = (0..=n)
        .map(|i| -0.0549 + i as f64 * 2e-5)
        .map(|y| [y, lip(y)])
        .collect();
    let lipped = crate::Profile::new("lip", crate::ProfileKind::Wheel, points).unwrap();
    let l = flange_dimensions(&lipped, -0.070).unwrap().unwrap();
    let outermost = (0..=600_000)
        .map(|i| -i as f64 * 1e-7)
        .find(|&y| lip(y) <= -0.010)
        .unwrap();
    eprintln!(
        "lip: Sd point {:?}, outermost {outermost}",
        l.thickness_point
    );
    assert!(outermost > y_f - 0.010 / t70 + 1e-3);
    assert!((l.thickness_point[0] - outermost).abs() < 5e-6);
}

#[test]
fn nadals_limit_has_its_tabulated_values() {
    // vehicle reference §6.2, computed there: 70°/0.36 -> 1.20, 70°/0.5 -> 0.95,
    // 60°/0.36 -> 0.85, 65°/0.36 -> 1.01
    for (deg, mu, want) in [
        (70.0f64, 0.36, 1.20),
        (70.0, 0.5, 0.95),
        (60.0, 0.36, 0.85),
        (65.0, 0.36, 1.01),
    ] {
        let got = nadal_limit(deg.to_radians(), mu);
        assert!((got - want).abs() < 0.006, "{deg}°, {mu}: {got}");
    }
    // frictionless: the flank's own slope
    assert!((nadal_limit(70f64.to_radians(), 0.0) - 70f64.to_radians().tan()).abs() < 1e-12);
}
