//! Explicit Runge–Kutta methods as data: Butcher tableaus with their sources.
//!
//! A tableau is read by one generic stepper (`explicit.rs`); adding a method means
//! adding a constant here, not writing a new integrator.

/// An explicit Runge–Kutta method written as its Butcher tableau.
///
/// Stage i (0-based) is `k_i = f(t + c_i h, x + h Σ_{j<i} a_i[j] k_j)`, the solution is
/// `x + h Σ b_i k_i` and, when present, the local error estimate is `h Σ e_i k_i`
/// with `e = b − b̂` (the difference to the embedded method).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ButcherTableau {
    /// Short name used in messages and docs.
    pub name: &'static str,
    /// \[-\] order of the solution `b`.
    pub order: u32,
    /// \[-\] order of the embedded solution b̂; the step-size controller uses
    /// `1 / (embedded_order + 1)` as its exponent. Zero when there is no estimate.
    pub embedded_order: u32,
    /// \[-\] nodes c_i (fractions of the step).
    pub c: &'static [f64],
    /// \[-\] strictly lower-triangular coefficients; row i has i entries.
    pub a: &'static [&'static [f64]],
    /// \[-\] weights of the solution.
    pub b: &'static [f64],
    /// \[-\] error weights e = b − b̂, or `None` for a fixed-step method.
    pub e: Option<&'static [f64]>,
    /// \[-\] coefficients d_i of a fourth-order continuous extension in the form of
    /// [`DOPRI5_DENSE`] (needs `fsal`), or `None`.
    pub dense: Option<&'static [f64; 7]>,
    /// "First same as last": the last stage is evaluated at (t + h, x_new), so it is
    /// f at the start of the next step.
    pub fsal: bool,
    /// \[-\] for methods whose last two stages are both evaluated at t + h (DOPRI5): the
    /// value of the estimate h·|λ| = h ‖k_s − k_{s−1}‖ / ‖x_s − x_{s−1}‖ of the dominant
    /// eigenvalue beyond which a step counts as limited by stability rather than by accuracy
    /// (about where the stability region ends on the negative real axis); `None`: no test.
    /// Hairer & Wanner, *Solving ODEs II*, §IV.2 ("Stiffness detection"), and the stiffness
    /// test of their DOPRI5 code (3.25).
    pub stiffness_limit: Option<f64>,
}

impl ButcherTableau {
    /// Number of stages.
    pub const fn stages(&self) -> usize {
        self.c.len()
    }
}

/// The classical fourth-order Runge–Kutta method.
///
/// W. Kutta, "Beitrag zur näherungsweisen Integration totaler Differentialgleichungen",
/// Z. Math. Phys. 46 (1901) 435–453; Hairer, Nørsett & Wanner, *Solving ODEs I*,
/// Table II.1.2 (left).
pub const RK4: ButcherTableau = ButcherTableau {
    name: "RK4",
    order: 4,
    embedded_order: 0,
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    e: None,
    dense: None,
    fsal: false,
    stiffness_limit: None,
};

/// Bogacki–Shampine 3(2), four stages with FSAL (three evaluations per step), third-order
/// solution with a second-order embedded estimate. Cheap per step for right-hand sides whose
/// cost dominates and whose accuracy needs are modest; its stability region reaches about
/// ±1.7i on the imaginary axis and −2.5 on the real axis.
///
/// P. Bogacki and L. F. Shampine, "A 3(2) pair of Runge–Kutta formulas", Appl. Math. Lett.
/// 2(4) (1989) 321–325 (the method of MATLAB's `ode23`).
pub const BS3: ButcherTableau = ButcherTableau {
    name: "BS3",
    order: 3,
    embedded_order: 2,
    c: &[0.0, 0.5, 0.75, 1.0],
    a: &[
        &[],
        &[0.5],
        &[0.0, 0.75],
        &[2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0],
    ],
    b: &[2.0 / 9.0, 1.0 / 3.0, 4.0 / 9.0, 0.0],
    // b − b̂ with b̂ = (7/24, 1/4, 1/3, 1/8).
    e: Some(&[
        2.0 / 9.0 - 7.0 / 24.0,
        1.0 / 3.0 - 1.0 / 4.0,
        4.0 / 9.0 - 1.0 / 3.0,
        -1.0 / 8.0,
    ]),
    dense: None,
    fsal: true,
    stiffness_limit: None,
};

/// Dormand–Prince 5(4), seven stages with FSAL, fifth-order solution (local extrapolation).
///
/// J. R. Dormand & P. J. Prince, "A family of embedded Runge–Kutta formulae",
/// J. Comput. Appl. Math. 6 (1980) 19–26; Hairer, Nørsett & Wanner, *Solving ODEs I*,
/// Table II.5.2. The error weights are b − b̂ of that table.
pub const DOPRI5: ButcherTableau = ButcherTableau {
    name: "DOPRI5",
    order: 5,
    embedded_order: 4,
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    e: Some(&[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ]),
    dense: Some(&DOPRI5_DENSE),
    fsal: true,
    stiffness_limit: Some(3.25),
};

/// \[-\] Coefficients d of the fourth-order continuous extension of [`DOPRI5`]
/// (index = stage, 0-based; stage 2 has none).
///
/// With θ = (t − t_n)/h, Δ = x_{n+1} − x_n, B = h k_1 − Δ:
/// `x(θ) = x_n + θ (Δ + (1−θ) (B + θ (Δ − h k_7 − B + (1−θ) h Σ d_i k_i)))`.
/// L. F. Shampine, "Some practical Runge–Kutta formulas", Math. Comp. 46 (1986) 135–150;
/// Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.6, as used in their code DOPRI5.
pub const DOPRI5_DENSE: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Order conditions up to order 5, every rooted tree (1, 1, 2, 4 and 9 of orders 1–5;
    /// Hairer, Nørsett & Wanner, Table II.2.2).
    fn check_order(t: &ButcherTableau, b: &[f64], p: u32, tol: f64) {
        let s = t.stages();
        let a = |i: usize, j: usize| if j < i { t.a[i][j] } else { 0.0 };
        // row sums
        for i in 0..s {
            let r: f64 = t.a[i].iter().sum();
            assert!(
                (r - t.c[i]).abs() < 1e-14,
                "{}: row {i} sums to {r}",
                t.name
            );
        }
        let sum = |f: &dyn Fn(usize) -> f64| (0..s).map(|i| b[i] * f(i)).sum::<f64>();
        let ac = |i: usize, k: i32| (0..s).map(|j| a(i, j) * t.c[j].powi(k)).sum::<f64>();
        let mut conds: Vec<(f64, f64)> = vec![(sum(&|_| 1.0), 1.0)];
        if p >= 2 {
            conds.push((sum(&|i| t.c[i]), 0.5));
        }
        if p >= 3 {
            conds.push((sum(&|i| t.c[i] * t.c[i]), 1.0 / 3.0));
            conds.push((sum(&|i| ac(i, 1)), 1.0 / 6.0));
        }
        if p >= 4 {
            conds.push((sum(&|i| t.c[i].powi(3)), 0.25));
            conds.push((sum(&|i| t.c[i] * ac(i, 1)), 1.0 / 8.0));
            conds.push((sum(&|i| ac(i, 2)), 1.0 / 12.0));
            let aac = |i: usize| (0..s).map(|j| a(i, j) * ac(j, 1)).sum::<f64>();
            conds.push((sum(&aac), 1.0 / 24.0));
        }
        if p >= 5 {
            conds.push((sum(&|i| t.c[i].powi(4)), 0.2));
            conds.push((sum(&|i| ac(i, 3)), 1.0 / 20.0));
            conds.push((sum(&|i| t.c[i].powi(2) * ac(i, 1)), 1.0 / 10.0));
            conds.push((sum(&|i| ac(i, 1).powi(2)), 1.0 / 20.0));
            let aac = |i: usize| (0..s).map(|j| a(i, j) * ac(j, 1)).sum::<f64>();
            conds.push((
                sum(&|i| (0..s).map(|j| a(i, j) * aac(j)).sum::<f64>()),
                1.0 / 120.0,
            ));
            // the other four of the nine trees of order 5
            conds.push((sum(&|i| t.c[i] * ac(i, 2)), 1.0 / 15.0));
            conds.push((sum(&|i| t.c[i] * aac(i)), 1.0 / 30.0));
            conds.push((
                sum(&|i| (0..s).map(|j| a(i, j) * t.c[j] * ac(j, 1)).sum::<f64>()),
                1.0 / 40.0,
            ));
            conds.push((
                sum(&|i| (0..s).map(|j| a(i, j) * ac(j, 2)).sum::<f64>()),
                1.0 / 60.0,
            ));
        }
        for (k, (lhs, rhs)) in conds.iter().enumerate() {
            assert!(
                (lhs - rhs).abs() < tol,
                "{}: condition {k}: {lhs} != {rhs}",
                t.name
            );
        }
    }

    #[test]
    fn rk4_has_order_4() {
        check_order(&RK4, RK4.b, 4, 1e-15);
    }

    #[test]
    fn dopri5_has_order_5_and_embedded_order_4() {
        check_order(&DOPRI5, DOPRI5.b, 5, 1e-14);
        let e = DOPRI5.e.unwrap();
        let bhat: Vec<f64> = DOPRI5.b.iter().zip(e).map(|(b, e)| b - e).collect();
        check_order(&DOPRI5, &bhat, 4, 1e-14);
        // the embedded method is genuinely different (not of order 5)
        let c4: f64 = (0..7).map(|i| bhat[i] * DOPRI5.c[i].powi(4)).sum();
        assert!((c4 - 0.2).abs() > 1e-6);
        // FSAL: the last row of a equals b
        for j in 0..6 {
            assert_eq!(DOPRI5.a[6][j], DOPRI5.b[j]);
        }
    }
}
