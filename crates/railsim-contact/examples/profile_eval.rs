//! Repeated evaluations of one benchmark case, for profiling with perf or callgrind:
//! `cargo run --release -p railsim-contact --example profile_eval -- [model] [step_mm] [n]`;
//! with `SEQ=1`, warm-started evaluations along the pose sequence of the `pose_sequence_55kN`
//! benchmark instead.
use std::path::PathBuf;

use railsim_contact::contact_format::{manchester_benchmark_pair, parse_cases_csv, solve_case};
use railsim_contact::{ContactModelKind, ContactOptions, ContactWorkspace, WheelRailContact};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model =
        ContactModelKind::from_name(args.get(1).map(String::as_str).unwrap_or("stripes")).unwrap();
    let step: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.2);
    let n: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(20000);
    let repo = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let pair = manchester_benchmark_pair(&repo).unwrap();
    let mut opts = ContactOptions {
        model,
        ..Default::default()
    };
    opts.travel.step = step * 1e-3;
    let c = WheelRailContact::new(pair, opts).unwrap();
    let text =
        std::fs::read_to_string(repo.join("tests/reference/mbench_a22/reference.csv")).unwrap();
    let cases = parse_cases_csv(&text, "reference.csv").unwrap();
    let mut ws = ContactWorkspace::new();
    let mut rows = Vec::new();
    let mut poses = Vec::new();
    for (_, case) in &cases {
        let z = solve_case(&c, case, &mut ws, &mut rows).unwrap().z_mm;
        let (mut p, v) = case.to_railsim();
        p.z = -z * 1e-3;
        poses.push((case.side, p, v));
    }
    if std::env::var("PAIRS").is_ok() {
        for k in [4usize, 25] {
            let (side, p, v) = &poses[k];
            c.evaluate(*side, p, v, &mut ws).unwrap();
            let mut prev = 0.0;
            for q in &ws.pairs {
                println!(
                    "case {k} s_r {:7.3} ds {:6.3} gap {:9.4} mm",
                    q.s_r * 1e3,
                    (q.s_r - prev) * 1e3,
                    q.gap * 1e3
                );
                prev = q.s_r;
            }
        }
    }
    if std::env::var("SEQ").is_ok() {
        pose_sequence(&c, n);
        return;
    }
    let t0 = std::time::Instant::now();
    let mut pairs = 0u64;
    let mut corr = 0u64;
    let mut reseeds = 0u64;
    for k in 0..n {
        let (side, p, v) = &poses[k % poses.len()];
        let s = c.evaluate(*side, p, v, &mut ws).unwrap();
        pairs += s.travel.pairs as u64;
        corr += s.travel.corrections as u64;
        reseeds += s.travel.reseeds as u64;
    }
    let dt = t0.elapsed().as_secs_f64() / n as f64;
    // Per-case times: each case evaluated n/42 times, the median over the cases.
    let reps = (n / poses.len()).max(10);
    let mut per_case: Vec<f64> = poses
        .iter()
        .map(|(side, p, v)| {
            let t = std::time::Instant::now();
            for _ in 0..reps {
                c.evaluate(*side, p, v, &mut ws).unwrap();
            }
            t.elapsed().as_secs_f64() / reps as f64
        })
        .collect();
    per_case.sort_by(f64::total_cmp);
    println!(
        "per case: median {:.2} µs, min {:.2}, max {:.2}",
        per_case[per_case.len() / 2] * 1e6,
        per_case[0] * 1e6,
        per_case[per_case.len() - 1] * 1e6
    );
    println!(
        "{} step {step} mm: {:.2} µs per evaluation, {:.1} pairs, {:.1} corrections, {:.2} reseeds",
        model.name(),
        dt * 1e6,
        pairs as f64 / n as f64,
        corr as f64 / n as f64,
        reseeds as f64 / n as f64
    );
}

/// `SEQ=1`: warm-started evaluations of the right wheel at 55 kN along the pose sequence of the
/// `pose_sequence_55kN` benchmark (400 poses over one period of a 3 mm, 1 mrad oscillation).
fn pose_sequence(c: &WheelRailContact, n: usize) {
    use railsim_contact::{Side, WarmStart, WheelsetPose, WheelsetVelocity};
    let vel = WheelsetVelocity {
        vx: 55.0,
        spin: 55.0 / 0.46, // forward rolling (+V/r0; it was reversed, a full slide)
        ..Default::default()
    };
    let mut ws = ContactWorkspace::new();
    let m = 400;
    let poses: Vec<WheelsetPose> = (0..m)
        .map(|k| {
            let phase = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
            let mut pose = WheelsetPose {
                y: 3e-3 * phase.sin(),
                z: 0.0,
                roll: 0.0,
                yaw: 1e-3 * phase.cos(),
            };
            pose.z = c
                .evaluate_with_load(Side::Right, &pose, &vel, 55e3, 1e-8, &mut ws)
                .unwrap()
                .z;
            pose
        })
        .collect();
    let mut warm = WarmStart::new();
    let t0 = std::time::Instant::now();
    for k in 0..n {
        c.evaluate_warm(Side::Right, &poses[k % m], &vel, &mut warm, &mut ws)
            .unwrap();
    }
    let dt = t0.elapsed().as_secs_f64() / n as f64;
    println!(
        "pose sequence: {:.2} µs per warm-started evaluation, {} warm, {} cold",
        dt * 1e6,
        warm.warm_count,
        warm.cold_count
    );
}
