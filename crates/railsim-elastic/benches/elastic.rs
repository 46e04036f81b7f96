//! Criterion benches of the elastic kernels: tabulated Hertz coefficients, FASTSIM on a
//! 25 x 25 ellipse, Polach, a half-space solve on a 40 x 40 grid, and Kalker's exact
//! steady-rolling tangential solution on a 32 x 32 grid.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use railsim_elastic::{
    Creepages, Grid, HalfspaceSolver, Material, PolachParams, SteadyRollingSolver, TractionBound,
    blended_flexibilities, fastsim_ellipse, hertz_coeffs_fast, polach,
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
    // Exact steady rolling on a Hertz circle, 32 x 32 cells, partial slip with spin (the kind of
    // patch the `exact` tangential level solves), cold start, tolerance 1e-7.
    let (a, b) = (4e-3, 4e-3);
    let grid = Grid::covering(32, 32, -1.04 * a, 1.04 * a, -1.04 * b, 1.04 * b).unwrap();
    let p0 = 1.5 * 5e4 / (std::f64::consts::PI * a * b);
    let (mut pn, mut wx, mut wy) = (
        vec![0.0; grid.len()],
        vec![0.0; grid.len()],
        vec![0.0; grid.len()],
    );
    for i in 0..grid.len() {
        let (x, y) = (grid.x(i % grid.nx), grid.y(i / grid.nx));
        let q = 1.0 - (x / a).powi(2) - (y / b).powi(2);
        pn[i] = if q > 0.0 { p0 * q.sqrt() } else { 0.0 };
        wx[i] = 1e-3 - 0.2 * y;
        wy[i] = 1e-3 + 0.2 * x;
    }
    let mut steady = SteadyRollingSolver::new(grid, &mat).unwrap();
    c.bench_function("steady_rolling_32x32_cold", |b| {
        b.iter(|| {
            steady
                .solve(&pn, &wx, &wy, black_box(0.3), 1e-7, 1000, false)
                .unwrap()
        })
    });
}

criterion_group!(elastic, benches);
criterion_main!(elastic);
