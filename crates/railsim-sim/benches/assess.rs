//! The post-processing of a run's samples (`railsim_sim::assess`: EN 14363 track-shift force,
//! per-wheel (Y/Q)2m, Q and quasi-static forces, the bogie frames' simplified stability
//! criterion, Sperling, carbody accelerations, EN 12299 N_MV) on synthetic series the size of
//! the default scene's run (23.6 s at 200 Hz, four axles, eight wheels, a curve over the second
//! half, two bogie frames measured at four points, three carbody points) and of ten minutes at
//! 200 Hz; and the default run's size without the wheels and bogie frames (the assessment before
//! they were added), for the ratio. `cargo bench -p railsim-sim --bench assess`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_contact::Side;
use railsim_sim::assess::{
    AssessOptions, BogieSeries, ComfortSeries, CurveSection, Series, WheelSeries, assess,
};

/// A deterministic broadband series of `seconds` at 200 Hz and 55 m/s.
fn series(seconds: f64) -> Series {
    let fs = 200.0;
    let n = (seconds * fs) as usize;
    let mut state = 7u64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let signal = |amp: f64, f: f64, noise: &mut dyn FnMut() -> f64| -> Vec<f64> {
        (0..n)
            .map(|i| amp * (2.0 * std::f64::consts::PI * f * i as f64 / fs).sin() + noise() * amp)
            .collect()
    };
    let distance: Vec<f64> = (0..n).map(|i| 55.0 * i as f64 / fs).collect();
    let length = distance[n - 1];
    Series {
        rate_hz: fs,
        wheels: (0..8)
            .map(|k| WheelSeries {
                wheelset: k / 2,
                side: if k % 2 == 0 { Side::Left } else { Side::Right },
                static_load: 54.5e3,
                y: signal(10e3, 4.9, &mut noise),
                q: signal(5e3, 4.9, &mut noise)
                    .iter()
                    .map(|v| v + 54.5e3)
                    .collect(),
            })
            .collect(),
        wheelset_position: (0..4)
            .map(|k| distance.iter().map(|d| d + 9.0 - 2.5 * k as f64).collect())
            .collect(),
        curves: vec![CurveSection {
            s: [0.5 * length, 2.0 * length],
            radius: 1200.0,
            cant: -0.12,
        }],
        bogies: (0..2)
            .map(|k| BogieSeries {
                name: format!("frame {k}"),
                mass: 6240.0,
                points: (0..2)
                    .map(|j| (format!("frame {k} point {j}"), signal(1.0, 4.9, &mut noise)))
                    .collect(),
            })
            .collect(),
        distance,
        sum_y: (0..4).map(|_| signal(5e3, 4.9, &mut noise)).collect(),
        comfort: (0..3)
            .map(|k| ComfortSeries {
                name: format!("point {k}"),
                longitudinal: signal(0.05, 1.0, &mut noise),
                lateral: signal(0.3, 1.2, &mut noise),
                vertical: signal(0.2, 1.5, &mut noise)
                    .iter()
                    .map(|v| v + 9.81)
                    .collect(),
                position: Vec::new(),
            })
            .collect(),
    }
}

fn bench(c: &mut Criterion) {
    let loads = [109.1e3; 4];
    let opts = AssessOptions::default();
    let mut g = c.benchmark_group("assess");
    g.sample_size(10);
    for (name, seconds) in [("default_run_23.6s", 23.6), ("ten_minutes", 600.0)] {
        let s = series(seconds);
        g.bench_function(name, |b| {
            b.iter(|| black_box(assess(black_box(&s), &loads, &opts)))
        });
    }
    let axles_only = Series {
        wheels: Vec::new(),
        bogies: Vec::new(),
        ..series(23.6)
    };
    g.bench_function("default_run_23.6s_axles_and_carbody_only", |b| {
        b.iter(|| black_box(assess(black_box(&axles_only), &loads, &opts)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
