//! One right-hand-side evaluation of the simulator (frames, suspension, the online contact of
//! every wheel, equations of motion) for scenes of different size: what a scene does not use is
//! not evaluated; and the Manchester vehicle's on a thread of a two-thread pool (the wheels in
//! parallel). And the out-of-round wheel's support (`railsim_vehicle::rim_support`), which every
//! right-hand side evaluates per out-of-round wheel. `cargo bench -p railsim-sim --bench rhs`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_ode::OdeSystem;
use railsim_sim::dynamics::Dynamics;
use railsim_sim::{Scene, Simulation};

fn scene(text: &str) -> Scene {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    Scene::from_toml_str(text, "bench.toml", &root).unwrap()
}

fn bench(c: &mut Criterion) {
    let cases = [
        (
            "manchester_irregular",
            r#"vehicle = "vehicles/manchester_vehicle1.toml"
               track = "tracks/straight_irregular.toml"
               speed_kmh = 198
               duration_s = 1"#,
        ),
        (
            "manchester_ideal",
            r#"vehicle = "vehicles/manchester_vehicle1.toml"
               track = "tracks/straight.toml"
               speed_kmh = 198
               duration_s = 1"#,
        ),
        (
            "manchester_ideal_elastic_rails",
            r#"vehicle = "vehicles/manchester_vehicle1.toml"
               track = "tracks/straight_elastic.toml"
               speed_kmh = 198
               duration_s = 1"#,
        ),
        (
            "manchester_irregular_lateral_only",
            r#"vehicle = "vehicles/manchester_vehicle1.toml"
               track = "tracks/straight_irregular.toml"
               speed_kmh = 198
               duration_s = 1
               freeze = ["carbody.x", "carbody.pitch", "bogie_front.x", "bogie_front.pitch",
                         "bogie_rear.x", "bogie_rear.pitch"]"#,
        ),
        (
            "free_wheelset_ideal",
            r#"vehicle = "vehicles/wheelset_free.toml"
               track = "tracks/straight.toml"
               speed_kmh = 198
               duration_s = 1"#,
        ),
    ];
    let mut g = c.benchmark_group("rhs");
    g.sample_size(20);
    for (name, text) in cases {
        let s = scene(text);
        let sim = Simulation::new(&s).unwrap();
        let model = sim.model();
        let x = sim.initial_state().to_vec();
        // Three states 0.1 nm apart in every position, taken in turn: each contact slot reuses
        // the patches of its last two inputs when they repeat exactly (for the difference
        // Jacobian's column groups), which one state evaluated over and over would measure.
        let xs: Vec<Vec<f64>> = (0..3)
            .map(|k| {
                x.iter()
                    .enumerate()
                    .map(|(i, &v)| {
                        if i < model.n_pos {
                            v + 1e-10 * f64::from(k)
                        } else {
                            v
                        }
                    })
                    .collect()
            })
            .collect();
        let mut d = Dynamics::new(model);
        let mut dx = vec![0.0; model.dim()];
        let mut k = 0;
        g.bench_function(name, |b| {
            b.iter(|| {
                k = (k + 1) % 3;
                d.rhs(black_box(0.0), black_box(&xs[k]), &mut dx).unwrap();
                black_box(dx[0])
            })
        });
        if name == "manchester_irregular" {
            // the same on a thread of a two-thread rayon pool, as `railsim` runs it: the
            // wheels' contact evaluations shared between the two threads
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .unwrap();
            g.bench_function("manchester_irregular_two_threads", |b| {
                pool.install(|| {
                    b.iter(|| {
                        k = (k + 1) % 3;
                        d.rhs(black_box(0.0), black_box(&xs[k]), &mut dx).unwrap();
                        black_box(dx[0])
                    })
                })
            });
        }
    }
    g.finish();
    // The rim's support over 100 rolled angles across a 50 mm flat (and beyond its ends): a
    // shallow one (0.2 mm, the rim convex: Newton's method), a deep one (1 mm, the rim concave:
    // branch and bound), against the radius deviation at the bottom alone.
    use railsim_vehicle::{WheelDefect, radius_deviation, rim_support};
    let mut g = c.benchmark_group("rim_support_100_angles");
    let r0 = 0.46;
    let flat = |depth: f64| {
        [WheelDefect::Flat {
            length: 0.05,
            depth,
            position: 1.0,
        }]
    };
    let angles: Vec<f64> = (0..100).map(|k| 0.92 + 0.0016 * f64::from(k)).collect();
    for (name, d) in [("flat_0.2mm", flat(0.2e-3)), ("flat_1mm", flat(1e-3))] {
        g.bench_function(format!("{name}_support"), |b| {
            b.iter(|| {
                angles
                    .iter()
                    .map(|&t| rim_support(&d, black_box(t), r0).0)
                    .sum::<f64>()
            })
        });
        g.bench_function(format!("{name}_radius_at_bottom"), |b| {
            b.iter(|| {
                angles
                    .iter()
                    .map(|&t| radius_deviation(&d, black_box(t), r0).0)
                    .sum::<f64>()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
