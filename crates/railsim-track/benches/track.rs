//! Timing of the per-step lookups: `frame_at` on a curve with transitions and
//! `irregularity_at` on the straight track with synthetic irregularities.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_track::TrackModel;

fn tracks() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tracks")
}

fn bench(c: &mut Criterion) {
    let curve = TrackModel::from_file(tracks().join("curve_r300.toml")).expect("curve_r300");
    let irregular =
        TrackModel::from_file(tracks().join("straight_irregular.toml")).expect("irregular");
    let len = curve.length();
    // Positions spread over the whole track (tangents, clothoids, curve).
    let positions: Vec<f64> = (0..1024)
        .map(|i| (i as f64 + 0.37) * len / 1024.0)
        .collect();
    c.bench_function("frame_at (curve_r300, 1024 positions)", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &s in &positions {
                acc += curve.frame_at(black_box(s)).position_g[0];
            }
            acc
        })
    });
    let len = irregular.length();
    let positions: Vec<f64> = (0..1024)
        .map(|i| (i as f64 + 0.37) * len / 1024.0)
        .collect();
    c.bench_function(
        "irregularity_at (straight_irregular, 1024 positions)",
        |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for &s in &positions {
                    acc += irregular.irregularity_at(black_box(s)).lateral;
                }
                acc
            })
        },
    );
    c.bench_function("irregularity_at (ideal track)", |b| {
        b.iter(|| curve.irregularity_at(black_box(123.0)).lateral)
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
