//! Smoothness of the contact force against the pose: sweep the lateral position in small steps
//! at a fixed height and print the largest jumps (second differences) of Fz and Fy:
//! `cargo run --release -p railsim-contact --example smoothness -- [step_mm] [z_mm]`.
use std::path::PathBuf;

use railsim_contact::contact_format::manchester_benchmark_pair;
use railsim_contact::{
    ContactOptions, ContactWorkspace, Side, WheelRailContact, WheelsetPose, WheelsetVelocity,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let step: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(0.5);
    let z: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(-0.23);
    let repo = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let pair = manchester_benchmark_pair(&repo).unwrap();
    let mut opts = ContactOptions::default();
    opts.travel.step = step * 1e-3;
    let c = WheelRailContact::new(pair, opts).unwrap();
    let mut ws = ContactWorkspace::new();
    let vel = WheelsetVelocity {
        vx: 55.0,
        spin: 55.0 / 0.4601,
        ..Default::default()
    };
    let n: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2000);
    let dy = 1e-6;
    let mut f = Vec::new();
    for k in 0..n {
        let pose = WheelsetPose {
            y: k as f64 * dy,
            z: z * 1e-3,
            ..Default::default()
        };
        let s = c.evaluate(Side::Left, &pose, &vel, &mut ws).unwrap();
        f.push((s.force_track[2], s.force_track[1], s.travel.pairs));
    }
    let mut worst = (0.0f64, 0usize);
    let mut worst_y = (0.0f64, 0usize);
    let mut jumps = 0;
    for k in 1..n - 1 {
        let d2 = (f[k + 1].0 - 2.0 * f[k].0 + f[k - 1].0).abs() / f[k].0.abs();
        let d2y = (f[k + 1].1 - 2.0 * f[k].1 + f[k - 1].1).abs() / f[k].0.abs();
        if d2 > 1e-6 {
            jumps += 1;
        }
        if d2 > worst.0 {
            worst = (d2, k);
        }
        if d2y > worst_y.0 {
            worst_y = (d2y, k);
        }
    }
    let big: Vec<(usize, f64)> = (1..n - 1)
        .map(|k| {
            (
                k,
                (f[k + 1].0 - 2.0 * f[k].0 + f[k - 1].0).abs() / f[k].0.abs(),
            )
        })
        .filter(|(_, d)| *d > 1e-4)
        .collect();
    for (k, d) in big.iter().take(30) {
        println!(
            "  y {k} um: d2 Fz {d:.2e}, pairs {} -> {}",
            f[*k].2,
            f[k + 1].2
        );
    }
    println!("{} above 1e-4", big.len());
    println!(
        "step {step} mm, z {z} mm: Fz {:.1} N at y 0; second differences over 1 um steps (relative to Fz): Fz max {:.2e} at y {} um, Fy max {:.2e} at y {} um; {} of {} above 1e-6; pairs {}..{}",
        f[0].0,
        worst.0,
        worst.1,
        worst_y.0,
        worst_y.1,
        jumps,
        n - 2,
        f.iter().map(|x| x.2).min().unwrap(),
        f.iter().map(|x| x.2).max().unwrap()
    );
}
