//! The eigenvalue analysis of the Manchester vehicle 1 (`railsim_sim::modal::modes_at`, 78
//! states: Simulation::new, the spin settling, 156 right-hand sides of the central-difference
//! Jacobian and the eigen decomposition) at 200 km/h with `polach` and with `stripes` (the
//! shipped hunting scene), and the quasi-static solution of a curving case (R = 600 m, 100 mm
//! cant, 80 km/h, `polach`; `railsim_sim::curving::quasi_static_curving`).
//! `cargo bench -p railsim-sim --bench modal`.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_contact::ContactModelKind;
use railsim_sim::Scene;
use railsim_sim::curving::{CurveCase, CurvingRun, QuasiStatic, quasi_static_curving};
use railsim_sim::modal::{ModalOptions, modes_at};

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let base = Scene::from_file(root.join("scenes/manchester_hunting.toml")).unwrap();
    let opts = ModalOptions::default();
    let mut g = c.benchmark_group("modal");
    g.sample_size(10);
    for model in [ContactModelKind::Polach, ContactModelKind::Stripes] {
        let mut scene = base.clone();
        scene.contact.model = model;
        g.bench_function(format!("manchester_200kmh_{}", model.name()), |b| {
            b.iter(|| black_box(modes_at(black_box(&scene), 200.0 / 3.6, &opts).unwrap()))
        });
    }
    let mut curving = Scene::from_file(root.join("scenes/manchester_curving.toml")).unwrap();
    curving.contact.model = ContactModelKind::Polach;
    let case = CurveCase {
        radius: 600.0,
        cant: 0.1,
        left: true,
        speed: 80.0 / 3.6,
    };
    g.bench_function("curving_quasi_static_r600_polach", |b| {
        b.iter(|| {
            black_box(
                quasi_static_curving(
                    black_box(&curving),
                    &case,
                    &CurvingRun::default(),
                    &QuasiStatic::default(),
                )
                .unwrap(),
            )
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
