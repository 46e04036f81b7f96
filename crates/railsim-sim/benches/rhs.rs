//! One right-hand-side evaluation of the simulator (frames, suspension, the online contact of
//! every wheel, equations of motion) for scenes of different size: what a scene does not use is
//! not evaluated; and the Manchester vehicle's on a thread of a two-thread pool (the wheels in
//! parallel). `cargo bench -p railsim-sim --bench rhs`.

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
        let mut d = Dynamics::new(model);
        let mut dx = vec![0.0; model.dim()];
        g.bench_function(name, |b| {
            b.iter(|| {
                d.rhs(black_box(0.0), black_box(&x), &mut dx).unwrap();
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
                        d.rhs(black_box(0.0), black_box(&x), &mut dx).unwrap();
                        black_box(dx[0])
                    })
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
