//! Readers, analytic profiles, splines, arc curves and rail placement.

use crate::analytic::{s1002, s1002_f, uic60, uic60_head_zd};
use crate::*;

const PRW: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../vehicles/profiles/MBench_S1002_v3.prw"
);
const PRR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../tracks/profiles/MBench_UIC60_v3.prr"
);

fn wheel_file() -> Profile {
    read_simpack(std::path::Path::new(PRW), ProfileKind::Wheel).unwrap()
}
fn rail_file() -> Profile {
    read_simpack(std::path::Path::new(PRR), ProfileKind::Rail).unwrap()
}

#[test]
fn simpack_reader_wheel() {
    let w = wheel_file();
    // 399 point rows (the row at y = 70 is commented out).
    assert_eq!(w.points.len(), 399);
    let first = w.points[0];
    let last = w.points[w.points.len() - 1];
    // mirror.y + inversion: S ascending from the flange back to the field side, z = -F.
    assert!((first[0] + 69.612628e-3).abs() < 1e-12, "{first:?}");
    assert!((first[1] + 13.485642e-3).abs() < 1e-12);
    assert!((last[0] - 60e-3).abs() < 1e-12, "{last:?}");
    assert!((last[1] - 2.6356764e-3).abs() < 1e-12);
    assert!(w.points.windows(2).all(|p| p[1][0] > p[0][0]));
    // The flange tip is the lowest point, at z = -28 mm near y = -55 mm.
    let tip = w
        .points
        .iter()
        .fold([0.0, 1.0], |a, p| if p[1] < a[1] { *p } else { a });
    assert!(
        (tip[1] + 0.028).abs() < 1e-5 && (tip[0] + 0.055).abs() < 0.5e-3,
        "{tip:?}"
    );
}

#[test]
fn simpack_reader_rail() {
    let r = rail_file();
    assert_eq!(r.points.len(), 495);
    assert!((r.points[0][0] + 43.704898e-3).abs() < 1e-12);
    assert!((r.points[0][1] + 38.510726e-3).abs() < 1e-12);
    let last = r.points[r.points.len() - 1];
    assert!((last[0] - 30.595912e-3).abs() < 1e-12);
    assert!((last[1] + 36.653225e-3).abs() < 1e-12);
    // Origin at the highest point.
    let top = r.highest_point();
    assert!(top[0].abs() < 0.05e-3 && top[1].abs() < 1e-6, "{top:?}");
}

#[test]
fn analytic_s1002_check_values() {
    assert!((s1002_f(-55.0) - 28.0).abs() < 1e-6);
    assert!(s1002_f(0.0).abs() < 1e-12);
    assert!((s1002_f(60.0) + 2.6357).abs() < 1e-4);
    assert!((s1002_f(-70.0) - 9.5193).abs() < 1e-4);
    assert!(s1002_f(-70.1).is_nan() && s1002_f(60.1).is_nan());
    let p = s1002();
    assert!(Profile::new("s1002", ProfileKind::Wheel, p.points.clone()).is_ok());
}

#[test]
fn analytic_s1002_matches_benchmark() {
    let w = wheel_file();
    let mut max = 0.0f64;
    for q in &w.points {
        let z = -s1002_f(q[0] * 1e3);
        max = max.max((z - q[1] * 1e3).abs());
    }
    eprintln!("S1002 analytic vs MBench_S1002_v3.prw: max |dz| = {max:.3e} mm");
    assert!(max < 0.01, "{max}");
    assert!(max < 1e-5, "expected ~2e-6 mm, got {max}");
    // The blended, sampled profile too (linear interpolation of 0.05 mm samples adds ~1e-4
    // mm on the tight radii; compare within 0.01 mm).
    let a = s1002();
    let mut max2 = 0.0f64;
    for q in &w.points {
        max2 = max2.max((a.z_at(q[0]).unwrap() - q[1]).abs() * 1e3);
    }
    eprintln!("sampled S1002 (linear interp.) vs benchmark: max |dz| = {max2:.3e} mm");
    assert!(max2 < 0.01);
}

#[test]
fn analytic_uic60_matches_benchmark() {
    // Head width 72.00 mm at the R13/flank tangency.
    let (_, c13, _, tang) = crate::analytic::uic::derived();
    assert!((2.0 * tang[0] - 72.0).abs() < 1e-9);
    assert!((c13[0] - 23.0162).abs() < 1e-4 && (c13[1] - 14.9089).abs() < 1e-4);
    assert!((tang[1] - 14.2597).abs() < 1e-4);
    assert!(uic60_head_zd(0.0) == Some(0.0));
    assert!(uic60_head_zd(40.0).is_none());
    // Cant the analytic head by atan(1/40) toward the track centre about the crown point and
    // move the highest point to the origin; compare with the (already canted) file.
    let a = uic60();
    let canted = a.rotated((1.0f64 / 40.0).atan(), [0.0, 0.0]).unwrap();
    let top = canted.highest_point();
    let canted = canted.translated(-top[0], -top[1]);
    // Crown point on the axis: 7.49 mm gauge side, 0.094 mm below the highest point.
    assert!((top[0] * 1e3 - 7.4992).abs() < 2e-3, "{top:?}");
    assert!((top[1] * 1e3 - 0.0937).abs() < 1e-3, "{top:?}");
    let r = rail_file();
    let compare = |dy: f64| {
        let c = ArcCurve::from_profile(&canted.translated(dy, 0.0), 0.0, DEFAULT_DS).unwrap();
        let (mut max_z, mut max_n) = (0.0f64, 0.0f64);
        for q in &r.points {
            let s = c.s_at_y(q[0]).expect("analytic head covers the file");
            let cp = c.eval(s);
            let dz = cp.p[1] - q[1];
            max_z = max_z.max(dz.abs());
            max_n = max_n.max((dz * cp.t[0]).abs());
        }
        eprintln!(
            "UIC60 analytic (shift {:.4} mm) vs MBench_UIC60_v3.prr: max |dz| = {:.4} mm, \
             max normal = {:.2e} mm",
            dy * 1e3,
            max_z * 1e3,
            max_n * 1e3
        );
        (max_z * 1e3, max_n * 1e3)
    };
    // Highest point exactly at the file origin: the file's origin is 0.006 mm gauge-side of
    // the fitted crown top (R300 centre at (0.006, 300.000) in file coordinates, §5.2), so
    // the normal error is 0.006 mm (0.24 mm vertically on the near-vertical flanks).
    let (_, n0) = compare(0.0);
    assert!(n0 < 0.01);
    // With the fitted 0.006 mm offset the reconstruction matches to 0.3 µm normal.
    let (z1, n1) = compare(0.006e-3);
    assert!(z1 < 0.01, "{z1}");
    assert!(n1 < 1e-3, "{n1}");
}

fn circle(r: f64, h: f64, n: usize) -> Vec<[f64; 2]> {
    // Points every chord h on a circle of radius r, centre (0, -r) (crown-like, convex).
    let dphi = 2.0 * (h / (2.0 * r)).asin();
    (0..n)
        .map(|i| {
            let t = (i as f64 - (n as f64 - 1.0) / 2.0) * dphi;
            [r * t.sin(), r * t.cos() - r]
        })
        .collect()
}

#[test]
fn spline_interpolates_knots() {
    let pts = circle(0.013, 0.5e-3, 41);
    let sp = SmoothingSpline::fit(&pts, None, 0.0).unwrap();
    for (u, p) in sp.knots().iter().zip(&pts) {
        let (q, _, _) = sp.eval(*u);
        assert!((q[0] - p[0]).abs() < 1e-15 && (q[1] - p[1]).abs() < 1e-15);
    }
    let (u0, u1) = sp.param_range();
    assert_eq!(u0, 0.0);
    assert!(u1 > 0.0);
}

#[test]
fn spline_circle_curvature_and_arc_length() {
    let r = 0.05;
    let h = 0.5e-3;
    let n = 201;
    let pts = circle(r, h, n);
    let sp = SmoothingSpline::fit(&pts, None, 0.0).unwrap();
    let (u0, u1) = sp.param_range();
    let mut worst = 0.0f64;
    // Away from the natural ends (their influence decays by 0.27 per knot).
    let k = 400;
    for i in 0..=k {
        let u = u0 + 0.1 * (u1 - u0) + 0.8 * (u1 - u0) * i as f64 / k as f64;
        let (_, d1, d2) = sp.eval(u);
        let v = d1[0].hypot(d1[1]);
        let kappa = (d1[0] * d2[1] - d1[1] * d2[0]) / v.powi(3);
        worst = worst.max((kappa * r + 1.0).abs());
    }
    eprintln!("circle R50 at 0.5 mm: max relative curvature error {worst:.2e}");
    assert!(worst < 1e-4, "{worst}");
    // Arc length of a 300 mm radius arc sampled at 0.5 mm.
    let r = 0.3;
    let pts = circle(r, h, 101);
    let sp = SmoothingSpline::fit(&pts, None, 0.0).unwrap();
    let exact = 100.0 * 2.0 * r * (h / (2.0 * r)).asin();
    let rel = (sp.arc_length() - exact).abs() / exact;
    eprintln!("arc length R300: relative error {rel:.2e}");
    assert!(rel < 1e-9, "{rel}");
}

/// The parameters of ascending arc lengths, found by a walk over the segments, are those the
/// search gives one by one, to the bit: at every 0.05 mm of the S1002 wheel and at every knot's
/// arc length (where the segments change), the ends and beyond them.
#[test]
fn the_walked_parameters_are_the_searched_ones() {
    let p = wheel_file();
    let sp = SmoothingSpline::fit(&p.points, None, 0.0).unwrap();
    let total = sp.arc_length();
    let mut s: Vec<f64> = (0..=(total / 5e-5) as usize)
        .map(|k| k as f64 * 5e-5)
        .collect();
    s.extend(sp.knots().iter().map(|&u| sp.arc_length_at(u)));
    s.extend([-1.0, 0.0, total, total + 1.0]);
    s.sort_by(f64::total_cmp);
    let walked = sp.params_at_arc_lengths(s.iter().copied());
    assert_eq!(walked.len(), s.len());
    for (&si, &u) in s.iter().zip(&walked) {
        assert_eq!(
            u.to_bits(),
            sp.param_at_arc_length(si).to_bits(),
            "s = {si}"
        );
    }
}

#[test]
fn smoothing_reduces_roughness() {
    // Noisy straight-ish data: a gentle arc with deterministic pseudo-noise of 5 µm.
    let mut pts = circle(0.3, 0.5e-3, 101);
    let mut state = 12345u64;
    for p in pts.iter_mut() {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 10e-6;
        p[1] += noise;
    }
    let roughness = |sp: &SmoothingSpline| {
        let (u0, u1) = sp.param_range();
        (0..2000)
            .map(|i| {
                let (_, _, d2) = sp.eval(u0 + (u1 - u0) * (i as f64 + 0.5) / 2000.0);
                d2[1] * d2[1]
            })
            .sum::<f64>()
    };
    let interp = SmoothingSpline::fit(&pts, None, 0.0).unwrap();
    let smooth = SmoothingSpline::fit(&pts, None, 1e-9).unwrap();
    let (r0, r1) = (roughness(&interp), roughness(&smooth));
    eprintln!("roughness interpolating {r0:.3e}, smoothed {r1:.3e}");
    assert!(r1 < 0.01 * r0);
    // The smoothed curve stays close to the true arc.
    let (u0, u1) = smooth.param_range();
    let (p, _, _) = smooth.eval(0.5 * (u0 + u1));
    assert!(p[1].abs() < 5e-6, "{p:?}");
    // Weights: a heavy weight pins a point.
    let mut w = vec![1.0; pts.len()];
    w[50] = 1e9;
    let pinned = SmoothingSpline::fit(&pts, Some(&w), 1e-9).unwrap();
    let (q, _, _) = pinned.eval(pinned.knots()[50]);
    assert!((q[1] - pts[50][1]).abs() < 1e-9);
}

#[test]
fn arc_curve_uic60_curvature_and_position() {
    let a = uic60();
    let c = ArcCurve::from_profile(&a, 0.0, DEFAULT_DS).unwrap();
    assert!(c.ds() <= DEFAULT_DS && c.ds() > 0.99 * DEFAULT_DS);
    // R300 crown at the axis, R13 corner at u = -31 mm (gauge side); both convex (kappa < 0).
    let k_crown = c.eval(c.s_at_y(0.0).unwrap()).kappa;
    let k_corner = c.eval(c.s_at_y(-0.031).unwrap()).kappa;
    eprintln!(
        "UIC60 curvature radius crown {:.3} mm, corner {:.4} mm",
        -1e3 / k_crown,
        -1e3 / k_corner
    );
    assert!((k_crown * 0.3 + 1.0).abs() < 0.01);
    assert!((k_corner * 0.013 + 1.0).abs() < 0.01);
    // Tangent toward increasing y; position vs analytic (normal distance), sampled finely.
    let mut max_err = 0.0f64;
    let n = 20000;
    for i in 0..=n {
        let s = c.length() * i as f64 / n as f64;
        let cp = c.eval(s);
        assert!(cp.t[0] > 0.0 && (cp.t[0].hypot(cp.t[1]) - 1.0).abs() < 1e-12);
        if let Some(zd) = uic60_head_zd(cp.p[0] * 1e3) {
            let dz = cp.p[1] + zd * 1e-3;
            max_err = max_err.max((dz * cp.t[0]).abs());
        }
    }
    eprintln!("ArcCurve UIC60 position error (normal): {max_err:.2e} m");
    assert!(max_err < 1e-7, "{max_err}");
    // Clamping and y lookup.
    assert_eq!(c.eval(-1.0).p, c.eval(0.0).p);
    assert!(c.s_at_y(1.0).is_none());
    let (y0, y1) = c.y_range();
    assert!(y0 < 0.0 && y1 > 0.0);
    let s = c.s_at_y(0.02).unwrap();
    assert!((c.eval(s).p[0] - 0.02).abs() < 1e-13);
}

#[test]
fn arc_curve_wheel_flange() {
    // kappa is negative at the R13 flange root (the outline turns clockwise: concave wheel
    // material) and positive at the R12 flange tip (lowest point, convex wheel material).
    let c = ArcCurve::from_profile(&s1002(), 0.0, DEFAULT_DS).unwrap();
    let k_root = c.eval(c.s_at_y(-0.0365).unwrap()).kappa;
    let k_tip = c.eval(c.s_at_y(-0.055).unwrap()).kappa;
    assert!((k_root * 0.013 + 1.0).abs() < 0.02, "{}", 1.0 / k_root);
    assert!((k_tip * 0.012 - 1.0).abs() < 0.02, "{}", 1.0 / k_tip);
}

#[test]
fn place_rail_uic60() {
    let a = uic60();
    let (placed, pl) = place_rail(&a, (1.0f64 / 40.0).atan(), 1.435, 0.014).unwrap();
    eprintln!(
        "1:40 crown point at y = {:.4} mm, z = {:.4} mm",
        pl.y_origin * 1e3,
        pl.z_origin * 1e3
    );
    assert!((pl.y_origin * 1e3 - 753.040).abs() < 0.005);
    assert!((pl.z_origin * 1e3 + 0.0937).abs() < 2e-4);
    let top = placed.highest_point();
    assert!(top[1].abs() < 1e-12);
    let (_, pl20) = place_rail(&a, (1.0f64 / 20.0).atan(), 1.435, 0.014).unwrap();
    eprintln!(
        "1:20 crown point at y = {:.4} mm, z = {:.4} mm",
        pl20.y_origin * 1e3,
        pl20.z_origin * 1e3
    );
    assert!((pl20.y_origin * 1e3 - 752.520).abs() < 0.005);
    assert!((pl20.z_origin * 1e3 + 0.350).abs() < 1e-3);
    // Benchmark file, already canted.
    let r = rail_file();
    let (_, plf) = place_rail(&r, 0.0, 1.435, 0.014).unwrap();
    eprintln!("benchmark .prr origin at y = {:.4} mm", plf.y_origin * 1e3);
    assert!((plf.y_origin * 1e3 - 760.53).abs() < 0.02);
    // Axis crown point of the file at (-7.49, -0.094) mm maps to ~753.04.
    let crown = plf.apply([-7.4992e-3, -0.0937e-3]);
    assert!((crown[0] * 1e3 - 753.04).abs() < 0.02, "{crown:?}");
    assert!(place_rail(&a, 0.0, -1.0, 0.014).is_err());
    assert!(place_rail(&a, 0.0, 1.435, 0.5).is_err());
}

#[test]
fn profile_transforms() {
    let p = uic60();
    let m = p.mirrored();
    assert_eq!(m.points.len(), p.points.len());
    assert!(m.points.windows(2).all(|w| w[1][0] > w[0][0]));
    assert_eq!(m.points[0][0], -p.points[p.points.len() - 1][0]);
    let s = p.scaled(2.0).unwrap();
    assert_eq!(s.points[3][0], 2.0 * p.points[3][0]);
    assert!(p.scaled(0.0).is_err() && p.scaled(f64::NAN).is_err());
    let t = p.translated(1.0, 2.0);
    assert_eq!(t.points[5], [p.points[5][0] + 1.0, p.points[5][1] + 2.0]);
    // Rotating by 90 degrees makes y non-monotonic.
    assert!(matches!(
        p.rotated(std::f64::consts::FRAC_PI_2, [0.0, 0.0]),
        Err(ProfileError::NotMonotonic { .. })
    ));
    let r = p.rotated(0.02, [0.0, 0.0]).unwrap();
    let back = r.rotated(-0.02, [0.0, 0.0]).unwrap();
    assert!((back.points[7][1] - p.points[7][1]).abs() < 1e-15);
}

/// `ArcCurve::curvature` is `eval`'s curvature alone: the same value everywhere, including
/// between nodes and at the clamped ends (the STRIPES junction segments use it at sub-points).
#[test]
fn curvature_alone_equals_evals_curvature() {
    let c = ArcCurve::from_profile(&wheel_file(), 0.0, DEFAULT_DS).unwrap();
    let n = 20_000;
    let mut varied = 0.0f64;
    for i in 0..=n {
        let s = -1e-3 + (c.length() + 2e-3) * i as f64 / n as f64;
        let k = c.curvature(s);
        assert_eq!(k, c.eval(s).kappa, "at s = {s}");
        varied = varied.max(k.abs());
    }
    // the S1002 file has arcs down to a few millimetres: the test sees real curvature
    assert!(varied > 50.0, "{varied}");
}
