//! Integration tests of railsim-track: every shipped track file, geometry (circle closure,
//! clothoid vs Fresnel, continuity, cant ramps, gradients), irregularities (PSD, determinism,
//! CSV) and bad input.

use std::f64::consts::PI;
use std::path::PathBuf;

use railsim_track::irregularity::{self, Channel, Spectrum, SyntheticParams};
use railsim_track::math::fresnel;
use railsim_track::{TrackError, TrackErrors, TrackModel, TrackSpec};

fn tracks_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tracks")
}

const HEAD: &str = r#"gauge_mm = 1435
rail_inclination = "1:40"
rail_profile = { left = "uic60", right = "uic60" }
"#;

fn compile(text: &str) -> Result<TrackModel, TrackErrors> {
    let spec = TrackSpec::from_toml_str(text, "mem.toml")?;
    TrackModel::compile(&spec, "mem.toml")
}

fn track(body: &str) -> TrackModel {
    compile(&format!("{HEAD}{body}")).unwrap_or_else(|e| panic!("{e}"))
}

fn errors(text: &str) -> Vec<String> {
    match compile(text) {
        Ok(_) => panic!("expected errors for:\n{text}"),
        Err(e) => e.errors.iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn every_track_file_compiles() {
    let mut n = 0;
    for entry in std::fs::read_dir(tracks_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let t = TrackModel::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(t.length() > 0.0);
            assert!((t.gauge() - 1.435).abs() < 1e-12);
            assert!((t.rail_inclination() - (1.0f64 / 40.0).atan()).abs() < 1e-15);
            n += 1;
        }
    }
    assert!(n >= 4, "found only {n} track files");
}

#[test]
fn shipped_curves_have_their_radius_and_cant() {
    let t = TrackModel::from_file(tracks_dir().join("curve_r1200.toml")).unwrap();
    let f = t.frame_at(200.0 + 120.0 + 400.0);
    assert!((f.curvature - 1.0 / 1200.0).abs() < 1e-15);
    assert!(
        (f.cant + 0.120).abs() < 1e-15,
        "left curve: right rail higher"
    );
    let t = TrackModel::from_file(tracks_dir().join("curve_r300.toml")).unwrap();
    let f = t.frame_at(150.0 + 150.0 + 200.0);
    assert!((f.curvature + 1.0 / 300.0).abs() < 1e-15);
    assert!(
        (f.cant - 0.150).abs() < 1e-15,
        "right curve: left rail higher"
    );
    assert!((f.roll - (0.150f64 / 1.5).asin()).abs() < 1e-15);
    // Ideal tracks evaluate no irregularities.
    assert!(t.irregularities().is_none());
    assert_eq!(t.irregularity_at(500.0), Default::default());
}

#[test]
fn full_circle_closes() {
    for r in [50.0, 300.0, 1200.0, 5000.0] {
        // One curve, and the same circle cut into 7 segments.
        let l = 2.0 * PI * r;
        let one = track(&format!(
            "[[segment]]\ntype = \"curve\"\nradius_m = {r}\ndirection = \"left\"\nlength_m = {l}\n"
        ));
        let mut body = String::new();
        for _ in 0..7 {
            body += &format!(
                "[[segment]]\ntype = \"curve\"\nradius_m = {r}\ndirection = \"left\"\nlength_m = {}\n",
                l / 7.0
            );
        }
        let seven = track(&body);
        for t in [&one, &seven] {
            let f = t.frame_at(l);
            let gap = f.position_g[0].hypot(f.position_g[1]);
            assert!(gap < 1e-9 * r, "R = {r}: gap {gap}");
            assert!((f.heading - 2.0 * PI).abs() < 1e-12);
            // Quarter circle at (R, R).
            let q = t.frame_at(l / 4.0);
            assert!((q.position_g[0] - r).abs() < 1e-9 * r);
            assert!((q.position_g[1] - r).abs() < 1e-9 * r);
        }
    }
}

#[test]
fn clothoid_end_heading_and_position_match_fresnel() {
    // Tangent 50 m, clothoid L into a right curve R: end heading -L/(2R); the spiral's
    // local coordinates are a√π (C(t), -S(t)), a² = R L, t = L / (a√π).
    for (l, r) in [(120.0, 1200.0), (150.0, 300.0), (80.0, 50.0)] {
        let t = track(&format!(
            "[[segment]]\ntype = \"tangent\"\nlength_m = 50\n\
             [[segment]]\ntype = \"clothoid\"\nlength_m = {l}\n\
             [[segment]]\ntype = \"curve\"\nradius_m = {r}\ndirection = \"right\"\nlength_m = 10\n"
        ));
        let f = t.frame_at(50.0 + l);
        assert!((f.heading + l / (2.0 * r)).abs() < 1e-14, "{}", f.heading);
        let scale = (r * l).sqrt() * PI.sqrt();
        let (c, s) = fresnel(l / scale).unwrap();
        let dx = f.position_g[0] - (50.0 + scale * c);
        let dy = f.position_g[1] + scale * s;
        assert!(
            dx.abs() < 1e-10 && dy.abs() < 1e-10,
            "L={l} R={r}: {dx:e} {dy:e}"
        );
        // Mid-clothoid: curvature half way, dκ/ds = -1/(R L).
        let m = t.frame_at(50.0 + l / 2.0);
        assert!((m.curvature + 0.5 / r).abs() < 1e-15);
        assert!((m.dcurvature_ds + 1.0 / (r * l)).abs() < 1e-18);
    }
}

#[test]
fn joins_are_continuous() {
    let t = TrackModel::from_file(tracks_dir().join("curve_r300.toml")).unwrap();
    let t2 = track(
        "vertical_curve_radius_m = 5000\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 100\ngradient_permille = 5\n\
         [[segment]]\ntype = \"clothoid\"\nlength_m = 90\ngradient_permille = -3\n\
         [[segment]]\ntype = \"curve\"\nradius_m = 500\ncant_mm = 110\ndirection = \"left\"\nlength_m = 200\n\
         [[segment]]\ntype = \"clothoid\"\nlength_m = 60\n\
         [[segment]]\ntype = \"curve\"\nradius_m = 700\ncant_mm = 80\ndirection = \"right\"\nlength_m = 200\n",
    );
    for t in [&t, &t2] {
        for seg in t.segments().iter().skip(1) {
            let s = seg.s_start;
            let (a, b) = (t.frame_at(s - 1e-9), t.frame_at(s + 1e-9));
            for k in 0..3 {
                assert!((a.position_g[k] - b.position_g[k]).abs() < 1e-8, "s={s}");
            }
            assert!((a.heading - b.heading).abs() < 1e-10, "s={s}");
            assert!((a.curvature - b.curvature).abs() < 1e-10, "s={s}");
            assert!((a.cant - b.cant).abs() < 1e-10, "s={s}");
            assert!((a.roll - b.roll).abs() < 1e-10, "s={s}");
            assert!((a.gradient - b.gradient).abs() < 1e-10, "s={s}");
        }
    }
}

#[test]
fn derivatives_match_finite_differences() {
    for shape in ["clothoid", "bloss", "cosine"] {
        let t = track(&format!(
            "vertical_curve_radius_m = 4000\n\
             [[segment]]\ntype = \"tangent\"\nlength_m = 60\n\
             [[segment]]\ntype = \"{shape}\"\nlength_m = 90\ngradient_permille = 8\n\
             [[segment]]\ntype = \"curve\"\nradius_m = 400\ncant_mm = 130\ndirection = \"left\"\nlength_m = 100\n",
        ));
        let h = 1e-4;
        for s in [10.0, 70.3, 101.0, 148.0, 170.0, 230.0] {
            let (a, f, b) = (t.frame_at(s - h), t.frame_at(s), t.frame_at(s + h));
            let d = |x: f64, y: f64| (y - x) / (2.0 * h);
            let at = format!("{shape}, s={s}");
            assert!((d(a.position_g[0], b.position_g[0]) - f.heading.cos()).abs() < 1e-7);
            assert!((d(a.position_g[1], b.position_g[1]) - f.heading.sin()).abs() < 1e-7);
            assert!((d(a.position_g[2], b.position_g[2]) - f.gradient).abs() < 1e-7);
            assert!((d(a.heading, b.heading) - f.curvature).abs() < 1e-9, "{at}");
            assert!(
                (d(a.curvature, b.curvature) - f.dcurvature_ds).abs() < 1e-9,
                "{at}"
            );
            assert!((d(a.cant, b.cant) - f.dcant_ds).abs() < 1e-9, "{at}");
            assert!((d(a.roll, b.roll) - f.droll_ds).abs() < 1e-9, "{at}");
            assert!(
                (d(a.droll_ds, b.droll_ds) - f.droll_ds2).abs() < 1e-9,
                "{at}"
            );
            assert!(
                (d(a.gradient, b.gradient) - f.vertical_curvature).abs() < 1e-7,
                "{at}"
            );
        }
    }
}

/// Bloss and cosine transitions against the clothoid: the same turn (every shape has ∫f = 1/2),
/// curvature and cant reach half their change at mid-length, zero curvature rate and cant slope
/// at both ends (the clothoid's jump there), and a smaller shift of the circle from the
/// tangent: p = y(L) − R (1 − cos ψ(L)) with y(L) = ∫₀ᴸ (L − v) κ(v) dv, to leading order
/// L²/(24 R) for the clothoid, L²/(40 R) for Bloss and (1/8 − 1/π²) L²/R = L²/(42.2 R) for the
/// cosine.
#[test]
fn bloss_and_cosine_transitions_turn_like_a_clothoid_with_less_shift() {
    let (l, r, cant) = (60.0, 1200.0, 0.1);
    // y(L) R / L² = ∫₀¹ (1 − t) f(t) dt: clothoid 1/6, Bloss 3/20, cosine 1/4 − 1/π²
    let lead = [
        ("clothoid", 1.0 / 6.0),
        ("bloss", 3.0 / 20.0),
        ("cosine", 0.25 - 1.0 / (PI * PI)),
    ];
    let mut shifts = Vec::new();
    for (shape, y_lead) in lead {
        let t = track(&format!(
            "[[segment]]\ntype = \"tangent\"\nlength_m = 50\n\
             [[segment]]\ntype = \"{shape}\"\nlength_m = {l}\n\
             [[segment]]\ntype = \"curve\"\nradius_m = {r}\ncant_mm = {}\ndirection = \"left\"\nlength_m = 100\n",
            cant * 1e3
        ));
        let end = t.frame_at(50.0 + l);
        // the turn of every shape: L / (2R)
        assert!((end.heading - l / (2.0 * r)).abs() < 1e-14, "{shape}");
        let mid = t.frame_at(50.0 + 0.5 * l);
        assert!((mid.curvature - 0.5 / r).abs() < 1e-15, "{shape}");
        assert!((mid.cant + 0.5 * cant).abs() < 1e-15, "{shape}");
        let start = t.frame_at(50.0);
        if shape == "clothoid" {
            assert!((start.dcurvature_ds - 1.0 / (r * l)).abs() < 1e-15);
        } else {
            for f in [&start, &end] {
                assert!(
                    f.dcurvature_ds.abs() < 1e-15 && f.dcant_ds.abs() < 1e-15,
                    "{shape}"
                );
                assert!(f.droll_ds.abs() < 1e-15, "{shape}");
            }
            // steeper in the middle: Bloss 3/2, cosine π/4 · 2 of the clothoid's slope
            let k = if shape == "bloss" { 1.5 } else { PI / 2.0 };
            assert!((mid.dcurvature_ds - k / (r * l)).abs() < 1e-15, "{shape}");
        }
        let y = end.position_g[1];
        // leading order, with the next term of relative size (L/R)² (0.25 %)
        assert!(
            (y * r / (l * l) / y_lead - 1.0).abs() < 3e-3,
            "{shape}: {y}"
        );
        shifts.push(y - r * (1.0 - end.heading.cos()));
    }
    let p = |k: f64| k * l * l / r;
    assert!((shifts[0] / p(1.0 / 24.0) - 1.0).abs() < 5e-3, "{shifts:?}");
    assert!((shifts[1] / p(1.0 / 40.0) - 1.0).abs() < 5e-3, "{shifts:?}");
    assert!(
        (shifts[2] / p(0.125 - 1.0 / (PI * PI)) - 1.0).abs() < 5e-3,
        "{shifts:?}"
    );
    assert!(shifts[1] < shifts[0] && shifts[2] < shifts[1]);
}

/// A Bloss transition from a tangent into R = 500 m over 200 m: its end point against Simpson's
/// rule on the closed-form heading ψ = (L/R)(t³ − t⁴/2) (20 000 intervals), and against the
/// figures a track-design program gives for it, (199.271, 11.965) m (quoted to 1 mm in a
/// discussion of the Bloss curve's series coordinates, pwayblog.com, 2017).
#[test]
fn bloss_end_point_matches_an_independent_integration() {
    let (r, l) = (500.0, 200.0);
    let t = track(&format!(
        "[[segment]]\ntype = \"bloss\"\nlength_m = {l}\n\
         [[segment]]\ntype = \"curve\"\nradius_m = {r}\ndirection = \"left\"\nlength_m = 10\n"
    ));
    let n = 20_000;
    let h = l / n as f64;
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..=n {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let u = i as f64 * h / l;
        let psi = l / r * u * u * u * (1.0 - 0.5 * u);
        x += w * psi.cos();
        y += w * psi.sin();
    }
    let (x, y) = (x * h / 3.0, y * h / 3.0);
    let end = t.frame_at(l);
    assert!(
        (end.position_g[0] - x).abs() < 1e-9,
        "{} {x}",
        end.position_g[0]
    );
    assert!(
        (end.position_g[1] - y).abs() < 1e-9,
        "{} {y}",
        end.position_g[1]
    );
    assert!((end.position_g[0] - 199.271).abs() < 5e-4);
    assert!((end.position_g[1] - 11.965).abs() < 5e-4);
}

#[test]
fn cant_ramps_linearly_on_transitions() {
    let t = TrackModel::from_file(tracks_dir().join("curve_r1200.toml")).unwrap();
    // Entry clothoid 200..320 m: cant 0 → -0.120 m (left curve), linear; exit mirrored.
    for i in 0..=12 {
        let u = 10.0 * i as f64;
        let f = t.frame_at(200.0 + u);
        assert!((f.cant + 0.120 * u / 120.0).abs() < 1e-15, "u={u}");
        if i < 12 {
            assert!((f.dcant_ds + 0.001).abs() < 1e-15, "{}", f.dcant_ds);
        }
        assert!((f.curvature - u / 120.0 / 1200.0).abs() < 1e-15);
        let g = t.frame_at(1120.0 + u);
        assert!((g.cant + 0.120 * (1.0 - u / 120.0)).abs() < 1e-15, "u={u}");
    }
}

#[test]
fn gradients_integrate_to_the_right_height() {
    let body = "[[segment]]\ntype = \"tangent\"\nlength_m = 300\ngradient_permille = 12.5\n\
                [[segment]]\ntype = \"curve\"\nradius_m = 800\ndirection = \"right\"\nlength_m = 250\ngradient_permille = -4\n\
                [[segment]]\ntype = \"tangent\"\nlength_m = 200\n";
    let expected = 300.0 * 0.0125 - 250.0 * 0.004;
    let sharp = track(body);
    let round = track(&format!("vertical_curve_radius_m = 6000\n{body}"));
    for t in [&sharp, &round] {
        assert!((t.frame_at(750.0).position_g[2] - expected).abs() < 1e-12);
    }
    // Rounding: gradient change 16.5 ‰ over 6000 m radius = 99 m, centred on s = 300.
    let f = round.frame_at(300.0);
    assert!((f.vertical_curvature + 1.0 / 6000.0).abs() < 1e-15);
    assert!((f.gradient - 0.5 * (0.0125 - 0.004)).abs() < 1e-15);
    assert_eq!(round.frame_at(240.0).vertical_curvature, 0.0);
    assert!(
        (round.frame_at(250.0).position_g[2] - sharp.frame_at(250.0).position_g[2]).abs() < 1e-15
    );
}

/// Welch periodogram (Hann window, 50 % overlap) of `x` at angular wavenumbers `omegas`,
/// one-sided in m²/(rad/m).
fn welch(x: &[f64], step: f64, seg: usize, omegas: &[f64]) -> Vec<f64> {
    let w: Vec<f64> = (0..seg)
        .map(|n| 0.5 - 0.5 * (2.0 * PI * n as f64 / seg as f64).cos())
        .collect();
    let w2: f64 = w.iter().map(|v| v * v).sum();
    let mut out = vec![0.0; omegas.len()];
    let mut count = 0;
    let mut start = 0;
    while start + seg <= x.len() {
        let chunk = &x[start..start + seg];
        let mean = chunk.iter().sum::<f64>() / seg as f64;
        for (o, &om) in out.iter_mut().zip(omegas) {
            let (mut re, mut im) = (0.0, 0.0);
            for n in 0..seg {
                let (s, c) = (om * n as f64 * step).sin_cos();
                let v = w[n] * (chunk[n] - mean);
                re += v * c;
                im -= v * s;
            }
            *o += 2.0 * step * (re * re + im * im) / (2.0 * PI * w2);
        }
        count += 1;
        start += seg / 2;
    }
    out.iter().map(|v| v / count as f64).collect()
}

#[test]
fn synthetic_psd_matches_erri_b176() {
    let p = SyntheticParams {
        spectrum: Spectrum::ErriB176Low,
        seed: 7,
        wavelength_min: 3.0,
        wavelength_max: 70.0,
        step: 0.375,
        components: irregularity::default_components(3.0, 70.0, 8000.0),
        taper: 0.0,
        start: 0.0,
        length: 8000.0,
    };
    let series = irregularity::synthesize(&p);
    let seg_len = 400.0;
    let seg = (seg_len / p.step) as usize;
    let d_om = 2.0 * PI / seg_len;
    // Bins from 0.13 rad/m (3 Hann bins above the band edge 0.0898) to 2.0 rad/m
    // (below the band edge 2.094), grouped into 5 logarithmic bands.
    let edges = [0.13, 0.22, 0.38, 0.65, 1.1, 2.0];
    let omegas: Vec<f64> = (1..)
        .map(|k| k as f64 * d_om)
        .skip_while(|&o| o < edges[0])
        .take_while(|&o| o < edges[5])
        .collect();
    for ch in Channel::ALL {
        let x = series.channel(ch);
        let est = welch(x, p.step, seg, &omegas);
        for b in 0..5 {
            let (mut e, mut t, mut n) = (0.0, 0.0, 0);
            for (i, &o) in omegas.iter().enumerate() {
                if o >= edges[b] && o < edges[b + 1] {
                    e += est[i];
                    t += p.spectrum.psd(ch, o);
                    n += 1;
                }
            }
            let ratio = e / t;
            println!("{ch:?} band {b} ({} bins): estimate/target = {ratio:.3}", n);
            assert!((ratio - 1.0).abs() < 0.25, "{ch:?} band {b}: ratio {ratio}");
        }
        // Variance vs the integral of the target over the band (midpoint rule, fine grid).
        let (w0, w1) = (2.0 * PI / 70.0, 2.0 * PI / 3.0);
        let m = 20000;
        let target: f64 = (0..m)
            .map(|i| {
                p.spectrum
                    .psd(ch, w0 + (i as f64 + 0.5) * (w1 - w0) / m as f64)
            })
            .sum::<f64>()
            * (w1 - w0)
            / m as f64;
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / x.len() as f64;
        println!(
            "{ch:?}: std {:.3} mm, target {:.3} mm",
            var.sqrt() * 1e3,
            target.sqrt() * 1e3
        );
        assert!(
            (var / target - 1.0).abs() < 0.10,
            "{ch:?}: {var} vs {target}"
        );
    }
}

#[test]
fn synthetic_is_deterministic() {
    let make = |seed: u64| {
        track(&format!(
            "[[segment]]\ntype = \"tangent\"\nlength_m = 600\n\
             [irregularities]\ntype = \"synthetic\"\nspectrum = \"erri_b176_high\"\nseed = {seed}\n\
             wavelength_min_m = 3\nwavelength_max_m = 70\ntaper_m = 20\n"
        ))
    };
    let (a, b, c) = (make(1), make(1), make(2));
    let (sa, sb, sc) = (
        a.irregularities().unwrap(),
        b.irregularities().unwrap(),
        c.irregularities().unwrap(),
    );
    for ch in Channel::ALL {
        assert_eq!(sa.channel(ch), sb.channel(ch), "same seed, same series");
        let diff = sa
            .channel(ch)
            .iter()
            .zip(sc.channel(ch))
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        let size = sa.channel(ch).iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(
            diff > 0.3 * size,
            "{ch:?}: different seed, different series"
        );
    }
    // The channels differ from each other, the taper starts from zero, lookups agree.
    assert_ne!(sa.channel(Channel::Lateral), sa.channel(Channel::Vertical));
    assert_eq!(a.irregularity_at(0.0).lateral, 0.0);
    assert_eq!(a.irregularity_at(300.0), b.irregularity_at(300.0));
}

#[test]
fn irregularity_interpolation_and_derivative() {
    let t = TrackModel::from_file(tracks_dir().join("straight_irregular.toml")).unwrap();
    let series = t.irregularities().unwrap();
    let s = series.positions();
    // Interpolation reproduces the samples.
    for i in [300, 1001, 7777] {
        let v = t.irregularity_at(s[i]);
        assert!((v.vertical - series.channel(Channel::Vertical)[i]).abs() < 1e-15);
    }
    // d/ds matches a finite difference of the interpolant.
    let h = 1e-5;
    for x in [123.4567, 2500.01, 4000.3] {
        let (a, f, b) = (
            t.irregularity_at(x - h),
            t.irregularity_at(x),
            t.irregularity_at(x + h),
        );
        assert!(((b.lateral - a.lateral) / (2.0 * h) - f.dlateral_ds).abs() < 1e-7);
        assert!(((b.gauge - a.gauge) / (2.0 * h) - f.dgauge_ds).abs() < 1e-7);
    }
    // Plausible size for good track: a few mm.
    let max = series
        .channel(Channel::Vertical)
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(max > 0.5e-3 && max < 20e-3, "max vertical {max}");
}

#[test]
fn measured_csv_is_read_and_errors_are_located() {
    let dir = std::env::temp_dir().join(format!("railsim-track-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = "# measured\ndistance_m,lateral_mm,vertical_mm,cross_level_mm,gauge_mm\n\
                0,0,0,0,0\n1,1.0,-2.0,0.5,0.2\n2,2.0,-4.0,1.0,0.4\n3,3.0,-6.0,1.5,0.6\n\
                4,0,0,0,0\n";
    std::fs::write(dir.join("good.csv"), good).unwrap();
    let toml_path = dir.join("m.toml");
    std::fs::write(
        &toml_path,
        format!(
            "{HEAD}[[segment]]\ntype = \"tangent\"\nlength_m = 10\n[irregularities]\ntype = \"measured\"\nfile = \"good.csv\"\n"
        ),
    )
    .unwrap();
    let t = TrackModel::from_file(&toml_path).unwrap_or_else(|e| panic!("{e}"));
    let v = t.irregularity_at(1.5);
    assert!((v.lateral - 1.5e-3).abs() < 1e-15);
    assert!((v.vertical + 3.0e-3).abs() < 1e-15);
    assert!((v.dcross_level_ds - 0.5e-3).abs() < 1e-15);
    assert_eq!(t.irregularity_at(4.5), Default::default());

    // Data that end away from zero would meet the vehicle as a step where the series ends: an
    // error naming the file, the column and the row, unless taper_m fades them out.
    let ramp = "distance_m,lateral_mm,vertical_mm,cross_level_mm,gauge_mm\n\
                0,0,0,0,0\n1,1.0,-2.0,0.5,0.2\n2,2.0,-4.0,1.0,0.4\n3,3.0,-6.0,1.5,0.6\n";
    std::fs::write(dir.join("ramp.csv"), ramp).unwrap();
    let with = |extra: &str| {
        std::fs::write(
            &toml_path,
            format!(
                "{HEAD}[[segment]]\ntype = \"tangent\"\nlength_m = 10\n[irregularities]\ntype = \"measured\"\nfile = \"ramp.csv\"\n{extra}"
            ),
        )
        .unwrap();
        TrackModel::from_file(&toml_path)
    };
    let e = with("").unwrap_err().to_string();
    assert!(
        e.contains("ramp.csv: lateral_mm = 3 at distance_m = 3 (its last row)")
            && e.contains("a 3 mm step")
            && e.contains("taper_m"),
        "{e}"
    );
    let t = with("taper_m = 1\n").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(t.irregularity_at(3.0).lateral, 0.0);
    assert!((t.irregularity_at(2.0).lateral - 2.0e-3).abs() < 1e-15);
    let e = with("taper_m = 2\n").unwrap_err().to_string();
    assert!(e.contains("taper_m = 2 must be between 0 and half"), "{e}");

    // a byte-order mark before the header is not part of it
    let bom = format!("\u{feff}{}", good.trim_start_matches("# measured\n"));
    assert_eq!(
        irregularity::parse_csv(&bom, "bom.csv")
            .unwrap()
            .positions()
            .len(),
        5
    );

    let bad = "distance_m,lateral_mm,vertical_mm,cross_level_mm,gauge_mm\n\
               0,0,0,0,0\n1, x1,0,0,0\n-0.5,0,0,0,0\n2,0,0\n";
    let e = irregularity::parse_csv(bad, "bad.csv").unwrap_err();
    let msgs: Vec<String> = e.errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(msgs.len(), 3, "{msgs:#?}");
    assert!(
        msgs[0].starts_with("bad.csv:3:4: lateral_mm: expected a finite number"),
        "{}",
        msgs[0]
    );
    assert!(
        msgs[1].starts_with("bad.csv:4:1: distance_m = -0.5 must be greater"),
        "{}",
        msgs[1]
    );
    assert!(
        msgs[2].starts_with("bad.csv:5:1: expected 5 fields"),
        "{}",
        msgs[2]
    );
    // Values a fuzzing run passed to the dynamics, where they failed naming no file: a metre
    // of irregularity (a unit error), a 10 mm step over 1e-300 m, rows 0.1 mm apart.
    let absurd = "distance_m,lateral_mm,vertical_mm,cross_level_mm,gauge_mm\n\
                  0,0,0,0,0\n1,1e9,0,0,0\n2,0,0,0,0\n3,0,0,0,0\n3.05,10,0,0,0\n\
                  4,0,0,0,30\n4.0005,0,0,0,30\n";
    let e = irregularity::parse_csv(absurd, "absurd.csv").unwrap_err();
    let msgs: Vec<String> = e.errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(msgs.len(), 3, "{msgs:#?}");
    assert!(
        msgs[0].starts_with(
            "absurd.csv:3:3: lateral_mm = 1e9: expected an irregularity within ±50 mm"
        ),
        "{}",
        msgs[0]
    );
    assert!(
        msgs[1].starts_with("absurd.csv:6:6: lateral_mm = 10: changes by 10.000 mm over 0.0500 m")
            && msgs[1].contains("steeper than 100 mm/m"),
        "{}",
        msgs[1]
    );
    assert!(
        msgs[2].starts_with("absurd.csv:8:1: distance_m = 4.0005: rows closer than 0.001 m"),
        "{}",
        msgs[2]
    );
    let e = irregularity::parse_csv("s,y\n", "h.csv").unwrap_err();
    assert!(
        e.errors[0]
            .to_string()
            .starts_with("h.csv:1:1: expected the header")
    );

    // A bad CSV referenced from a track: the CSV's location is reported.
    std::fs::write(dir.join("bad.csv"), bad).unwrap();
    std::fs::write(
        &toml_path,
        format!(
            "{HEAD}[[segment]]\ntype = \"tangent\"\nlength_m = 10\n[irregularities]\ntype = \"measured\"\nfile = \"bad.csv\"\n"
        ),
    )
    .unwrap();
    let e = TrackModel::from_file(&toml_path).unwrap_err();
    assert_eq!(e.errors.len(), 3);
    assert!(e.errors[0].to_string().contains("bad.csv:3:4:"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Assert a message with location `loc` naming `key` exists.
fn has(msgs: &[String], loc: &str, key: &str) {
    assert!(
        msgs.iter().any(|m| m.starts_with(loc) && m.contains(key)),
        "no message at {loc} naming {key}:\n{}",
        msgs.join("\n")
    );
}

#[test]
fn bad_values_are_all_reported_with_location_and_key() {
    let text = format!(
        "{HEAD}[[segment]]\n\
type = \"curve\"\n\
radius_m = -300\n\
cant_mm = 250\n\
direction = \"left\"\n\
length_m = 100\n\
[[segment]]\n\
type = \"tangent\"\n\
[[segment]]\n\
type = \"curve\"\n\
radius_m = 30\n\
direction = \"up\"\n\
length_m = 0\n"
    );
    let msgs = errors(&text);
    has(
        &msgs,
        "mem.toml:6:12:",
        "segment 1 (curve): radius_m = -300 must be positive",
    );
    has(
        &msgs,
        "mem.toml:7:11:",
        "segment 1 (curve): cant_mm = 250 must be between -200 and 200",
    );
    has(
        &msgs,
        "mem.toml:10:",
        "segment 2 (tangent): missing key length_m",
    );
    has(
        &msgs,
        "mem.toml:14:12:",
        "radius_m = 30 is tighter than the minimum radius 50 m",
    );
    has(
        &msgs,
        "mem.toml:15:13:",
        "direction = \"up\" must be \"left\" or \"right\"",
    );
    has(&msgs, "mem.toml:16:12:", "length_m = 0 must be positive");
    assert_eq!(msgs.len(), 6, "{msgs:#?}");
}

#[test]
fn structural_errors_in_several_tables_are_all_reported() {
    let text = "gauge_mm = \"wide\"\n\
rail_inclination = \"1:40\"\n\
rail_profile = { left = \"uic60\", right = \"uic60\" }\n\
[[segment]]\n\
type = \"tangent\"\n\
length = 100\n\
[[segment]]\n\
type = \"tangent\"\n\
length_m = \"100\"\n\
[irregularities]\n\
type = \"synthetic\"\n\
sead = 3\n";
    let msgs = errors(text);
    println!("{}", msgs.join("\n"));
    has(&msgs, "mem.toml:1:12:", "gauge_mm");
    has(&msgs, "mem.toml:6:1:", "segment 1: unknown field `length`");
    has(&msgs, "mem.toml:9:12:", "segment 2: length_m");
    has(
        &msgs,
        "mem.toml:12:1:",
        "irregularities: unknown field `sead`",
    );
    assert_eq!(msgs.len(), 4, "{msgs:#?}");
}

#[test]
fn missing_root_key_and_other_errors() {
    let msgs = errors(
        "rail_inclination = \"1:40\"\nrail_profile = { left = \"uic60\", right = \"uic60\" }\n",
    );
    has(&msgs, "mem.toml:1:1:", "missing field `gauge_mm`");

    let msgs = errors(
        "gauge_mm = 3000\nrail_inclination = \"40\"\nrail_profile = { left = \"uic61\", right = \"none.prr\" }\n\
         [[segment]]\ntype = \"spiral\"\nlength_m = 5\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 5\nradius_m = 100\n",
    );
    has(&msgs, "mem.toml:1:12:", "gauge_mm = 3000");
    has(&msgs, "mem.toml:2:20:", "rail_inclination");
    has(
        &msgs,
        "mem.toml:3:",
        "rail_profile.left = \"uic61\" is not a built-in profile",
    );
    has(
        &msgs,
        "mem.toml:3:",
        "rail_profile.right = \"none.prr\": file",
    );
    has(
        &msgs,
        "mem.toml:5:8:",
        "segment 1: type = \"spiral\" must be \"tangent\", \"curve\" or a transition (\"clothoid\", \"bloss\" or \"cosine\")",
    );
    has(
        &msgs,
        "mem.toml:10:12:",
        "segment 2 (tangent): key radius_m is not allowed",
    );

    // A transition with a cant of its own, a vertical curve that does not fit, an empty
    // synthetic table (two transitions in a row are a reverse curve's inflection, no error).
    let msgs = errors(&format!(
        "{HEAD}vertical_curve_radius_m = 20000\n\
         [[segment]]\ntype = \"clothoid\"\nlength_m = 50\n\
         [[segment]]\ntype = \"bloss\"\nlength_m = 50\ngradient_permille = 10\ncant_mm = 50\n\
         [irregularities]\ntype = \"synthetic\"\nwavelength_min_m = 3\nwavelength_max_m = 2\n"
    ));
    assert!(
        !msgs
            .iter()
            .any(|m| m.contains("transition") && !m.contains("a transition takes curvature")),
        "{msgs:#?}"
    );
    has(
        &msgs,
        "mem.toml:12:11:",
        "segment 2 (bloss): key cant_mm is not allowed (a transition takes curvature and cant",
    );
    has(
        &msgs,
        "mem.toml:11:21:",
        "segment 2: gradient_permille = 10: the vertical curve",
    );
    has(&msgs, "mem.toml:13:", "missing key spectrum");
    has(&msgs, "mem.toml:13:", "missing key seed");
    has(
        &msgs,
        "mem.toml:16:20:",
        "wavelength_max_m = 2 must be greater",
    );

    // A TOML syntax error has a location too.
    let msgs = errors("gauge_mm = = 3\n");
    assert!(msgs[0].starts_with("mem.toml:1:"), "{msgs:?}");
}

#[test]
fn min_radius_from_file_and_options() {
    let body =
        "[[segment]]\ntype = \"curve\"\nradius_m = 250\ndirection = \"left\"\nlength_m = 10\n";
    assert!(compile(&format!("{HEAD}{body}")).is_ok());
    let msgs = errors(&format!("{HEAD}min_radius_m = 300\n{body}"));
    has(
        &msgs,
        "mem.toml:7:12:",
        "radius_m = 250 is tighter than the minimum radius 300 m",
    );
    let spec = TrackSpec::from_toml_str(&format!("{HEAD}{body}"), "mem.toml").unwrap();
    let e = TrackModel::compile_with(
        &spec,
        "mem.toml",
        &railsim_track::CompileOptions { min_radius: 400.0 },
    )
    .unwrap_err();
    assert!(
        matches!(&e.errors[0], TrackError::Invalid { key, line: 6, col: 12, .. } if key == "radius_m")
    );
}

#[test]
fn rail_support_is_read_in_si_and_absent_means_rigid() {
    assert!(
        track("[[segment]]\ntype = \"tangent\"\nlength_m = 10\n")
            .rail_support()
            .is_none()
    );
    let t = track(
        "[rail_support]\nmass_kg = 150\nlateral_stiffness_mn_m = 40\nlateral_damping_kns_m = 200\n\
         vertical_stiffness_mn_m = 100\nvertical_damping_kns_m = 0\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 10\n",
    );
    let r = t.rail_support().expect("a rail support");
    assert_eq!(r.mass, 150.0);
    assert_eq!(r.lateral_stiffness, 40e6);
    assert_eq!(r.lateral_damping, 200e3);
    assert_eq!(r.vertical_stiffness, 100e6);
    assert_eq!(r.vertical_damping, 0.0);
}

#[test]
fn bad_rail_support_values_are_located() {
    let msgs = errors(&format!(
        "{HEAD}[rail_support]\nmass_kg = 0\nlateral_stiffness_mn_m = -40\nlateral_damping_kns_m = nan\n\
         vertical_stiffness_mn_m = 100\nvertical_damping_kns_m = 100\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 10\n"
    ));
    has(
        &msgs,
        "mem.toml:5:11:",
        "rail_support.mass_kg = 0 must be between 1 and 10000",
    );
    has(
        &msgs,
        "mem.toml:6:26:",
        "rail_support.lateral_stiffness_mn_m = -40",
    );
    has(
        &msgs,
        "mem.toml:7:25:",
        "rail_support.lateral_damping_kns_m = NaN",
    );
    assert_eq!(msgs.len(), 3, "{msgs:#?}");
    // A missing key and a misspelt one.
    let msgs = errors(&format!(
        "{HEAD}[rail_support]\nmass_kg = 150\nlateral_stiffnes_mn_m = 40\n\
         [[segment]]\ntype = \"tangent\"\nlength_m = 10\n"
    ));
    assert!(
        msgs.iter()
            .any(|m| m.starts_with("mem.toml:") && m.contains("lateral_stiffnes_mn_m")),
        "{msgs:#?}"
    );
}

#[test]
fn rail_sections_change_the_rails_from_their_start_and_inherit_the_rest() {
    use railsim_track::RailProfile;
    let t = track(
        "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n\
         [[rail_section]]\nstart_m = 100\nrail_inclination = \"1:20\"\n\
         [[rail_section]]\nstart_m = 200\n\
         rail_profile = { left = \"../../tracks/profiles/MBench_UIC60_v3.prr\", right = \"uic60\" }\n",
    );
    let r = t.rail_sections();
    assert_eq!(r.len(), 3);
    let (i40, i20) = ((1.0f64 / 40.0).atan(), (1.0f64 / 20.0).atan());
    assert_eq!((r[0].start, r[0].inclination), (0.0, i40));
    assert_eq!(r[0].profiles, [RailProfile::Uic60, RailProfile::Uic60]);
    // the second changes the inclination only, the third the left profile only
    assert_eq!((r[1].start, r[1].inclination), (100.0, i20));
    assert_eq!(r[1].profiles, r[0].profiles);
    assert_eq!((r[2].start, r[2].inclination), (200.0, i20));
    assert!(
        matches!(&r[2].profiles[0], RailProfile::File(p) if p.ends_with("MBench_UIC60_v3.prr"))
    );
    assert_eq!(r[2].profiles[1], RailProfile::Uic60);
    // the section under a point: the first before 100 m (and before the start), from a
    // section's start on that section
    for (s, want) in [
        (-5.0, 0),
        (0.0, 0),
        (99.999, 0),
        (100.0, 1),
        (199.9, 1),
        (200.0, 2),
        (400.0, 2),
    ] {
        assert_eq!(t.rail_section_at(s), want, "at {s} m");
    }
    // the whole-track accessors are the first section's
    assert_eq!(t.rail_inclination(), i40);
    // without sections: one, the top-level rails
    let plain = track("[[segment]]\ntype = \"tangent\"\nlength_m = 300\n");
    assert_eq!(plain.rail_sections().len(), 1);
    assert_eq!(plain.rail_section_at(150.0), 0);
}

#[test]
fn bad_rail_sections_are_located() {
    let seg = "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n";
    let msgs = errors(&format!(
        "{HEAD}{seg}\
         [[rail_section]]\nstart_m = 150\nrail_inclination = \"1:3\"\n\
         [[rail_section]]\nstart_m = 120\nrail_inclination = \"1:20\"\n\
         [[rail_section]]\nstart_m = 400\nrail_inclination = \"1:20\"\n\
         [[rail_section]]\nstart_m = 250\n\
         [[rail_section]]\nstart_m = 280\nrail_profile = {{ left = \"uic61\", right = \"uic60\" }}\n"
    ));
    // line 9: the first section's inclination; 11: a start before the previous one; 14: beyond
    // the end; 17: a section that changes nothing; 20: an unknown profile
    has(
        &msgs,
        "mem.toml:9:20:",
        "rail_section 1: rail_inclination = \"1:3\"",
    );
    has(
        &msgs,
        "mem.toml:11:11:",
        "rail_section 2: start_m = 120 must lie after",
    );
    has(
        &msgs,
        "mem.toml:14:11:",
        "rail_section 3: start_m = 400 must lie after",
    );
    has(&msgs, "mem.toml:17:11:", "rail_section 4: changes nothing");
    has(
        &msgs,
        "mem.toml:20:25:",
        "rail_section 5: rail_profile.left = \"uic61\"",
    );
    assert_eq!(msgs.len(), 5, "{msgs:#?}");
    // an unknown key
    let msgs = errors(&format!(
        "{HEAD}{seg}[[rail_section]]\nstart_m = 100\nrail_inclinaton = \"1:20\"\n"
    ));
    assert!(
        msgs.iter()
            .any(|m| m.starts_with("mem.toml:") && m.contains("rail_inclinaton")),
        "{msgs:#?}"
    );
}

/// A section may change the gauge (widening in a tight curve); like the other keys it is
/// inherited, and a value far from the track's gauge is refused as a slip.
#[test]
fn rail_sections_change_the_gauge() {
    let seg = "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n";
    let t = track(&format!(
        "{seg}[[rail_section]]\nstart_m = 100\ngauge_mm = 1450\ntransition_m = 10\n\
         [[rail_section]]\nstart_m = 200\nrail_inclination = \"1:20\"\n"
    ));
    let g: Vec<f64> = t.rail_sections().iter().map(|r| r.gauge).collect();
    assert_eq!(g, [1.435, 1.45, 1.45]);
    assert_eq!(t.gauge(), 1.435);
    assert_eq!(
        t.rail_sections()[1].inclination,
        t.rail_sections()[0].inclination
    );
    let msgs = errors(&format!(
        "{HEAD}{seg}\
         [[rail_section]]\nstart_m = 100\ngauge_mm = 1500\n\
         [[rail_section]]\nstart_m = 150\ngauge_mm = nan\n\
         [[rail_section]]\nstart_m = 200\ngauge_mm = 1.445\n"
    ));
    has(
        &msgs,
        "mem.toml:9:12:",
        "rail_section 1: gauge_mm = 1500 must lie within 50 mm of the track's gauge_mm = 1435",
    );
    has(
        &msgs,
        "mem.toml:12:12:",
        "rail_section 2: gauge_mm = NaN must be between 600 and 2000",
    );
    has(
        &msgs,
        "mem.toml:15:12:",
        "rail_section 3: gauge_mm = 1.445 must be between 600 and 2000",
    );
    assert_eq!(msgs.len(), 3, "{msgs:#?}");
}

/// A section may set the wheel/rail friction (a lubricated curve): a number or a table by
/// contact angle, inherited by the sections after it; bad values are located at the key.
#[test]
fn rail_sections_set_the_friction() {
    use railsim_spec::{FrictionSpec, FrictionTable};
    let seg = "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n";
    let t = track(&format!(
        "{seg}[[rail_section]]\nstart_m = 100\n\
         friction = {{ contact_angle_deg = [15, 25], coefficient = [0.3, 0.1] }}\n\
         [[rail_section]]\nstart_m = 200\nrail_inclination = \"1:20\"\n\
         [[rail_section]]\nstart_m = 250\nfriction = 0.25\n"
    ));
    let f: Vec<Option<FrictionSpec>> = t
        .rail_sections()
        .iter()
        .map(|r| r.friction.clone())
        .collect();
    let table = FrictionSpec::ByContactAngle(FrictionTable {
        contact_angle_deg: vec![15.0, 25.0],
        coefficient: vec![0.3, 0.1],
    });
    assert_eq!(
        f,
        [
            None,
            Some(table.clone()),
            Some(table),
            Some(FrictionSpec::Constant(0.25))
        ]
    );
    let msgs = errors(&format!(
        "{HEAD}{seg}\
         [[rail_section]]\nstart_m = 100\nfriction = 1.5\n\
         [[rail_section]]\nstart_m = 150\nfriction = {{ contact_angle_deg = [25, 15], coefficient = [0.3, 0.1] }}\n"
    ));
    has(
        &msgs,
        "mem.toml:9:12:",
        "rail_section 1: friction must lie in",
    );
    has(
        &msgs,
        "mem.toml:12:12:",
        "rail_section 2: friction.contact_angle_deg must increase strictly, found 15 after 25",
    );
    assert_eq!(msgs.len(), 2, "{msgs:#?}");
    let msgs = errors(&format!(
        "{HEAD}{seg}[[rail_section]]\nstart_m = 100\nfriction = \"wet\"\n"
    ));
    assert!(
        msgs.iter()
            .any(|m| m.starts_with("mem.toml:9:")
                && m.contains("friction must be a number, a table")),
        "{msgs:#?}"
    );
}

#[test]
fn rail_transitions_blend_linearly_and_bad_ones_are_located() {
    let seg = "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n";
    let t = track(&format!(
        "{seg}[[rail_section]]\nstart_m = 100\nrail_inclination = \"1:20\"\ntransition_m = 10\n\
         [[rail_section]]\nstart_m = 110\nrail_inclination = \"1:30\"\n"
    ));
    assert_eq!(t.rail_sections()[1].transition, 10.0);
    assert_eq!(t.rail_sections()[2].transition, 0.0);
    for (s, section, weight) in [
        (-5.0, 0, 1.0),
        (f64::NAN, 0, 1.0),
        (99.0, 0, 1.0),
        (100.0, 1, 0.0),
        (102.5, 1, 0.25),
        (109.0, 1, 0.9),
        (110.0, 2, 1.0),
        (250.0, 2, 1.0),
    ] {
        let b = t.rail_blend_at(s);
        assert_eq!(b.section, section, "at {s} m");
        assert!((b.weight - weight).abs() < 1e-12, "at {s} m: {}", b.weight);
    }
    let msgs = errors(&format!(
        "{HEAD}{seg}\
         [[rail_section]]\nstart_m = 100\nrail_inclination = \"1:20\"\ntransition_m = -1\n\
         [[rail_section]]\nstart_m = 150\nrail_inclination = \"1:30\"\ntransition_m = 20\n\
         [[rail_section]]\nstart_m = 160\nrail_inclination = \"1:40\"\n\
         [[rail_section]]\nstart_m = 290\nrail_inclination = \"1:20\"\ntransition_m = 20\n"
    ));
    has(
        &msgs,
        "mem.toml:10:16:",
        "rail_section 1: transition_m = -1 must be at least 0",
    );
    has(
        &msgs,
        "mem.toml:16:11:",
        "rail_section 3: start_m = 160 lies inside the transition of the section before (to 170 m)",
    );
    has(
        &msgs,
        "mem.toml:21:16:",
        "rail_section 4: transition_m = 20 must be at least 0 and end on the track",
    );
    assert_eq!(msgs.len(), 3, "{msgs:#?}");
}

/// A reverse curve without a tangent between: a curve to the left, a clothoid out of it and a
/// Bloss curve into a curve to the right. The two transitions meet at zero curvature and cant
/// (the inflection); heading, curvature and cant are continuous across every join, and each
/// transition turns by L/(2R), the first on to the left, the second back.
#[test]
fn adjacent_transitions_meet_at_a_reverse_curve_inflection() {
    let (r, l) = (500.0, 60.0);
    let t = track(&format!(
        "[[segment]]\ntype = \"curve\"\nradius_m = {r}\ncant_mm = 80\ndirection = \"left\"\nlength_m = 100\n\
         [[segment]]\ntype = \"clothoid\"\nlength_m = {l}\n\
         [[segment]]\ntype = \"bloss\"\nlength_m = {l}\n\
         [[segment]]\ntype = \"curve\"\nradius_m = {r}\ncant_mm = 80\ndirection = \"right\"\nlength_m = 100\n"
    ));
    let inflection = t.frame_at(100.0 + l);
    assert!(inflection.curvature.abs() < 1e-15 && inflection.cant.abs() < 1e-15);
    for s in [100.0, 100.0 + l, 100.0 + 2.0 * l] {
        let (a, b) = (t.frame_at(s - 1e-9), t.frame_at(s + 1e-9));
        assert!((a.heading - b.heading).abs() < 1e-10, "s={s}");
        assert!((a.curvature - b.curvature).abs() < 1e-10, "s={s}");
        assert!((a.cant - b.cant).abs() < 1e-10, "s={s}");
    }
    // 100/R to the left in the first curve, L/(2R) more to the left while the clothoid's
    // curvature falls to zero, and L/(2R) back in the Bloss curve: (100 + L/2)/R at the
    // inflection, 100/R where the second curve starts
    assert!((inflection.heading - (100.0 + 0.5 * l) / r).abs() < 1e-13);
    let second = t.frame_at(100.0 + 2.0 * l);
    assert!((second.heading - 100.0 / r).abs() < 1e-13);
    assert!((second.curvature + 1.0 / r).abs() < 1e-15 && second.cant > 0.0);
}

/// A measured series on an uneven grid: the slopes of the parabolas through three neighbouring
/// samples make the interpolant exact for a quadratic, value and slope (the centred difference
/// that ignores the spacing is not).
#[test]
fn measured_slopes_respect_uneven_spacing() {
    use railsim_track::irregularity::IrregularitySeries;
    let q = |x: f64| 1e-3 * (0.4 + 0.3 * x - 0.05 * x * x);
    let dq = |x: f64| 1e-3 * (0.3 - 0.1 * x);
    let s: Vec<f64> = (0..21)
        .scan(0.0, |x, i| {
            let at = *x;
            *x += if i % 2 == 0 { 0.25 } else { 0.5 };
            Some(at)
        })
        .collect();
    let v: Vec<f64> = s.iter().map(|&x| q(x)).collect();
    let series = IrregularitySeries::new(s.clone(), [v.clone(), v.clone(), v.clone(), v]);
    // the intervals away from the ends, whose slopes are one-sided
    for w in s[1..s.len() - 1].windows(2) {
        for f in [0.2, 0.5, 0.9] {
            let x = w[0] + f * (w[1] - w[0]);
            let r = series.at(x);
            assert!((r.vertical - q(x)).abs() < 1e-15, "value at {x}");
            assert!(
                (r.dvertical_ds - dq(x)).abs() < 1e-13,
                "slope at {x}: {} against {}",
                r.dvertical_ds,
                dq(x)
            );
        }
    }
}

/// A synthetic series carries the exact slopes of its cosine sum: at the coarsest step allowed
/// (λ_min/4) its derivative is within 4 % of the r.m.s. slope of the true one (the same cosines
/// on a 16 times finer grid; 1.8 % measured), where slopes from centred differences of the
/// samples are off by 26 %.
#[test]
fn synthetic_slopes_are_those_of_the_cosine_sum() {
    use railsim_track::irregularity::{IrregularitySeries, synthesize};
    let params = |step: f64| SyntheticParams {
        spectrum: Spectrum::ErriB176High,
        seed: 7,
        wavelength_min: 2.0,
        wavelength_max: 20.0,
        step,
        components: 400,
        taper: 10.0,
        start: 0.0,
        length: 200.0,
    };
    let coarse = synthesize(&params(0.5));
    let fine = synthesize(&params(0.5 / 16.0));
    let differenced = IrregularitySeries::new(
        coarse.positions().to_vec(),
        Channel::ALL.map(|c| coarse.channel(c).to_vec()),
    );
    let (mut e_exact, mut e_diff, mut rms) = (0.0f64, 0.0f64, 0.0f64);
    let n = 4000;
    for k in 0..n {
        let x = 200.0 * (k as f64 + 0.5) / n as f64;
        let t = fine.at(x).dvertical_ds;
        rms += t * t / n as f64;
        e_exact = e_exact.max((coarse.at(x).dvertical_ds - t).abs());
        e_diff = e_diff.max((differenced.at(x).dvertical_ds - t).abs());
    }
    let rms = rms.sqrt();
    assert!(
        e_exact < 0.04 * rms && e_exact < 0.2 * e_diff,
        "largest slope error {:.3} of the r.m.s. slope with the exact slopes, {:.3} with differences",
        e_exact / rms,
        e_diff / rms
    );
}

/// Without `taper_m` a synthetic series fades in and out over its longest wavelength (at most
/// half its length), so that it neither starts nor ends with a step.
#[test]
fn a_synthetic_series_fades_in_and_out_by_default() {
    let t = track(
        "[[segment]]\ntype = \"tangent\"\nlength_m = 300\n\
         [irregularities]\ntype = \"synthetic\"\nspectrum = \"erri_b176_high\"\nseed = 3\n\
         wavelength_min_m = 3\nwavelength_max_m = 70\n",
    );
    for s in [0.0, 300.0] {
        let v = t.irregularity_at(s);
        assert_eq!(
            [v.lateral, v.vertical, v.cross_level, v.gauge],
            [0.0; 4],
            "at s = {s} m"
        );
    }
    // full size from one longest wavelength in
    let series = t.irregularities().unwrap();
    let inside = |a: f64, b: f64| {
        series
            .positions()
            .iter()
            .zip(series.channel(Channel::CrossLevel))
            .filter(|(s, _)| **s > a && **s < b)
            .fold(0.0f64, |m, (_, v)| m.max(v.abs()))
    };
    assert!(inside(0.0, 5.0) < 0.2 * inside(70.0, 230.0));
}

/// A transition of 1e9 m took 35 s and 4.7 GB to build and 1e11 m hung: segment lengths are
/// bounded (10 km for a transition, 1000 km otherwise) and reported with the key.
#[test]
fn absurd_segment_lengths_are_located() {
    let e = errors(&format!(
        "{HEAD}[[segment]]\ntype = \"tangent\"\nlength_m = 100\n\
         [[segment]]\ntype = \"clothoid\"\nlength_m = 1e9\n\
         [[segment]]\ntype = \"curve\"\nradius_m = 1000\ndirection = \"left\"\ncant_mm = 0\nlength_m = 2e6\n"
    ));
    assert!(
        e.iter().any(|m| m.contains(":9:")
            && m.contains("length_m = 1e9 is longer than the 10000 m accepted")),
        "{e:#?}"
    );
    assert!(
        e.iter().any(|m| m.contains(":15:")
            && m.contains("length_m = 2e6 is longer than the 1e6 m accepted")),
        "{e:#?}"
    );
}

/// A cant that steps at a join (a canted curve right after a tangent, or two curves of different
/// cant) is refused at the second segment's `cant_mm`: the step would roll the track, and every
/// vehicle body as its frame passes, at once (docs/models/dynamics.md, "Kinks"). With a
/// transition between, or with the same cant on both sides, the track compiles.
#[test]
fn a_cant_step_at_a_join_is_refused() {
    let text = format!(
        "{HEAD}[[segment]]\n\
type = \"tangent\"\n\
length_m = 50\n\
[[segment]]\n\
type = \"curve\"\n\
radius_m = 600\n\
cant_mm = 100\n\
direction = \"left\"\n\
length_m = 100\n"
    );
    let msgs = errors(&text);
    has(
        &msgs,
        "mem.toml:10:11:",
        "segment 2: the cant steps by 100.0 mm where it starts",
    );
    assert_eq!(msgs.len(), 1, "{msgs:#?}");
    let eased = text.replace(
        "[[segment]]\ntype = \"curve\"",
        "[[segment]]\ntype = \"clothoid\"\nlength_m = 40\n[[segment]]\ntype = \"curve\"",
    );
    assert!(compile(&eased).is_ok());
    let same = text.replace("cant_mm = 100\n", "");
    assert!(compile(&same).is_ok());
}

/// The ERRI B176 level spectra against the second public form of the same set, SIMPACK's
/// b0 / (a0 + a2 Ω² + Ω⁴) as tabulated in docs/models/track.md (b0 = A Ω_c², a0 = Ω_r² Ω_c²,
/// a2 = Ω_r² + Ω_c², each given to seven digits): a wrong constant, Ω taken as a frequency in
/// cycles per metre, or a factor of 2 fails it. The cross level is the docs' reading (i): the
/// angle's spectrum (A_v / b²) Ω_c² Ω² / (…(Ω² + Ω_s²)) times (2b)², independent of b.
#[test]
fn the_erri_spectra_are_simpacks_tabulated_form() {
    let (a0, a2) = (0.000_288_55, 0.680_389_5);
    for (spectrum, b0_lateral, b0_vertical) in [
        (Spectrum::ErriB176Low, 1.440_846e-7, 2.741_619e-7),
        (Spectrum::ErriB176High, 4.164_787e-7, 7.343_623e-7),
    ] {
        for omega in [0.05f64, 0.2, 0.8246, 2.0] {
            let simpack = |b0: f64| b0 / (a0 + a2 * omega * omega + omega.powi(4));
            for (channel, b0) in [
                (Channel::Lateral, b0_lateral),
                (Channel::Vertical, b0_vertical),
            ] {
                let s = spectrum.psd(channel, omega);
                assert!(
                    (s / simpack(b0) - 1.0).abs() < 2e-6,
                    "{spectrum:?} {channel:?} at {omega} rad/m: {s} against {}",
                    simpack(b0)
                );
            }
            // cross level: 4 S_v Ω² / (Ω² + Ω_s²), Ω_s = 0.4380 rad/m
            let cross = spectrum.psd(Channel::CrossLevel, omega);
            let want =
                4.0 * simpack(b0_vertical) * omega * omega / (omega * omega + 0.438f64.powi(2));
            assert!((cross / want - 1.0).abs() < 2e-6, "{cross} against {want}");
        }
    }
}
