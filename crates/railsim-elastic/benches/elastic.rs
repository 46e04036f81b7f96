//! Criterion benches of the elastic kernels: tabulated Hertz coefficients, FASTSIM on a
//! 25 x 25 ellipse, Polach, and a half-space solve on a 40 x 40 grid.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_elastic::{
    Creepages, Grid, HalfspaceSolver, Material, PolachParams, TractionBound, blended_flexibilities,
    fastsim_ellipse, hertz_coeffs_fast, polach,
};

fn benches(c: &mut Criterion) {
    let mat = Material::new(82e9, 0.28).unwrap();
    // Build the table outside the timing.
    black_box(hertz_coeffs_fast(0.5, 1.0));
    c.bench_function("hertz_coeffs_fast", |b| {
        let mut r = 0.37;
        b.iter(|| {
            r = if r > 900.0 { 0.37 } else { r * 1.7 };
            black_box(hertz_coeffs_fast(black_box(r), 1.0))
        })
    });

    let (a, bb, n, mu) = (8e-3, 4e-3, 82e3, 0.3);
    let creep = Creepages {
        xi: 1e-4,
        eta: -6.25e-4,
        phi: 0.625,
    };
    let flex = blended_flexibilities(a, bb, n, mu, &creep, &mat).unwrap();
    c.bench_function("fastsim_ellipse_25x25", |b| {
        b.iter(|| {
            fastsim_ellipse(
                a,
                bb,
                n,
                black_box(&creep),
                &flex,
                mu,
                TractionBound::Elliptic,
                25,
                25,
            )
            .unwrap()
        })
    });

    let params = PolachParams::coulomb(mu);
    c.bench_function("polach", |b| {
        b.iter(|| polach(a, bb, n, black_box(&creep), 30.0, &params, &mat).unwrap())
    });

    let (ac, bc) = (0.8464, 2.406);
    let grid = Grid::covering(40, 40, -8.8e-3, 8.8e-3, -4.4e-3, 4.4e-3).unwrap();
    let gap: Vec<f64> = (0..grid.len())
        .map(|i| {
            let (x, y) = (grid.x(i % grid.nx), grid.y(i / grid.nx));
            ac * x * x + bc * y * y
        })
        .collect();
    let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
    c.bench_function("halfspace_solve_force_40x40_cold", |b| {
        b.iter(|| {
            // Cold start each time: zero load resets the stored pressure.
            solver.solve_force(&gap, 0.0, 1e-8, 500).unwrap();
            solver.solve_force(&gap, black_box(n), 1e-8, 500).unwrap()
        })
    });
}

criterion_group!(elastic, benches);
criterion_main!(elastic);
