//! Linearisation of an [`OdeSystem`] about a state, and the eigenvalues and eigenvectors of
//! the result: the linear stability of an equilibrium and its modes.
//!
//! The Jacobian `J = ∂f/∂x` at `(t, x)` is a central difference per column,
//! `J e_j = (f(x + h_j e_j) − f(x − h_j e_j)) / (2 h_j)`, second-order accurate in the steps
//! `h_j` that the caller gives (a right-hand side computed by inner iterations, such as a
//! contact search, needs steps well above its own tolerance, which only the caller knows).
//! With the system's [`OdeSystem::jacobian_pattern`] the columns of a group share no row and
//! are differenced together (`crate::JacobianPattern::column_groups`): `2 g` right-hand sides
//! for `g` groups instead of `2 n`, each entry from its own row as in the column-by-column
//! difference (to rounding).
//! Near an equilibrium `x*` (`f(t, x*) = 0`) the motion `x = x* + Σ c_k v_k e^{λ_k t}` is
//! governed by the eigenpairs `(λ_k, v_k)` of `J`: the equilibrium is asymptotically stable
//! when every `Re λ_k < 0` (Lyapunov's indirect method). The eigenpairs come from faer's
//! real Schur decomposition (Francis' double-shift QR; Golub & Van Loan, *Matrix
//! Computations*, 4th ed., §7.5).

use faer::Mat;

use crate::{JacobianPattern, OdeSystem, RhsError};

/// The Jacobian of `sys` at `(t, x)` by central differences with steps `steps` (one per
/// component, each finite and non-zero), column-major in an n×n matrix. Costs `2 n`
/// right-hand sides, or two per column group of the system's Jacobian pattern (its other
/// entries zero). A failed right-hand side is returned as it is; a non-finite entry is
/// reported as an error naming its row and column.
pub fn jacobian<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t: f64,
    x: &[f64],
    steps: &[f64],
) -> Result<Mat<f64>, RhsError> {
    let n = sys.dim();
    if x.len() != n || steps.len() != n {
        return Err(RhsError(format!(
            "linearisation: the state has {} and the steps {} components, the system {n}",
            x.len(),
            steps.len()
        )));
    }
    if let Some((j, h)) = steps
        .iter()
        .enumerate()
        .find(|(_, h)| !(h.is_finite() && **h != 0.0))
    {
        return Err(RhsError(format!(
            "linearisation: the step of component {j} must be finite and non-zero, found {h}"
        )));
    }
    let mut jac = Mat::<f64>::zeros(n, n);
    let pattern = sys
        .jacobian_pattern()
        .unwrap_or_else(|| JacobianPattern::dense(n));
    if pattern.dim() != n {
        return Err(RhsError(format!(
            "linearisation: the Jacobian pattern has dimension {}, the system {n}",
            pattern.dim()
        )));
    }
    let (mut xs, mut fp, mut fm) = (x.to_vec(), vec![0.0; n], vec![0.0; n]);
    let (mut hp, mut hm) = (vec![0.0; n], vec![0.0; n]);
    for cols in pattern.column_groups() {
        for &j in &cols {
            xs[j] = x[j] + steps[j];
            hp[j] = xs[j] - x[j];
        }
        sys.rhs(t, &xs, &mut fp)?;
        for &j in &cols {
            xs[j] = x[j] - steps[j];
            hm[j] = x[j] - xs[j];
        }
        sys.rhs(t, &xs, &mut fm)?;
        for &j in &cols {
            xs[j] = x[j];
            for &i in pattern.rows(j) {
                let d = (fp[i] - fm[i]) / (hp[j] + hm[j]);
                if !d.is_finite() {
                    return Err(RhsError(format!(
                        "linearisation: the derivative of component {i} with respect to component {j} is not finite ({d})"
                    )));
                }
                jac[(i, j)] = d;
            }
        }
    }
    Ok(jac)
}

/// One eigenpair of a real matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Eigenpair {
    /// Real part of the eigenvalue \[1/s for a Jacobian in time\].
    pub re: f64,
    /// Imaginary part of the eigenvalue.
    pub im: f64,
    /// The eigenvector, `(re, im)` per component, scaled so that its largest component is
    /// `1 + 0i`.
    pub vector: Vec<[f64; 2]>,
}

impl Eigenpair {
    /// \[Hz\] the damped natural frequency `|Im λ| / 2π`.
    pub fn frequency(&self) -> f64 {
        self.im.abs() / std::f64::consts::TAU
    }

    /// \[-\] the damping ratio `−Re λ / |λ|` (1 for a decaying real eigenvalue, negative for
    /// a growing one; 0 for λ = 0).
    pub fn damping_ratio(&self) -> f64 {
        let m = self.re.hypot(self.im);
        if m > 0.0 { -self.re / m } else { 0.0 }
    }
}

/// The eigenvalues and eigenvectors of the square matrix `a`, one entry per eigenvalue
/// (complex ones in conjugate pairs), sorted by decreasing real part (the least stable
/// first). Errors when the QR iteration does not converge or `a` is not square or not finite.
pub fn eigenpairs(a: &Mat<f64>) -> Result<Vec<Eigenpair>, String> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(format!("eigenpairs: the matrix is {n}x{}", a.ncols()));
    }
    for j in 0..n {
        for i in 0..n {
            if !a[(i, j)].is_finite() {
                return Err(format!("eigenpairs: entry ({i}, {j}) is not finite"));
            }
        }
    }
    let evd = a
        .eigen()
        .map_err(|e| format!("eigenpairs: the QR iteration did not converge ({e:?})"))?;
    let (u, s) = (evd.U(), evd.S());
    let mut out: Vec<Eigenpair> = (0..n)
        .map(|k| {
            let l = s[k];
            let col: Vec<[f64; 2]> = (0..n).map(|i| [u[(i, k)].re, u[(i, k)].im]).collect();
            // normalise by the largest component (phase and size)
            let big = col
                .iter()
                .copied()
                .max_by(|p, q| p[0].hypot(p[1]).total_cmp(&q[0].hypot(q[1])))
                .unwrap_or([1.0, 0.0]);
            let m2 = big[0] * big[0] + big[1] * big[1];
            let vector = if m2 > 0.0 {
                col.iter()
                    .map(|c| {
                        [
                            (c[0] * big[0] + c[1] * big[1]) / m2,
                            (c[1] * big[0] - c[0] * big[1]) / m2,
                        ]
                    })
                    .collect()
            } else {
                col
            };
            Eigenpair {
                re: l.re,
                im: l.im,
                vector,
            }
        })
        .collect();
    out.sort_by(|p, q| q.re.total_cmp(&p.re).then(q.im.total_cmp(&p.im)));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two masses on springs and dampers in a chain, with a gyroscopic coupling:
    /// `M q'' + (C + G) q' + K q = 0` as a first-order system.
    struct Chain {
        m: [f64; 2],
        k: [f64; 2],
        c: [f64; 2],
        g: f64,
    }

    impl Chain {
        fn matrix(&self) -> [[f64; 4]; 4] {
            let (m, k, c, g) = (self.m, self.k, self.c, self.g);
            // K = [[k0 + k1, -k1], [-k1, k1]], C likewise, G = [[0, g], [-g, 0]]
            let kk = [[k[0] + k[1], -k[1]], [-k[1], k[1]]];
            let cc = [[c[0] + c[1], -c[1]], [-c[1], c[1]]];
            let gg = [[0.0, g], [-g, 0.0]];
            let mut a = [[0.0; 4]; 4];
            a[0][2] = 1.0;
            a[1][3] = 1.0;
            for i in 0..2 {
                for j in 0..2 {
                    a[2 + i][j] = -kk[i][j] / m[i];
                    a[2 + i][2 + j] = -(cc[i][j] + gg[i][j]) / m[i];
                }
            }
            a
        }
    }

    impl OdeSystem for Chain {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), RhsError> {
            let a = self.matrix();
            for i in 0..4 {
                dxdt[i] = (0..4).map(|j| a[i][j] * x[j]).sum();
            }
            Ok(())
        }
    }

    #[test]
    fn the_jacobian_of_a_linear_system_is_its_matrix() {
        let mut sys = Chain {
            m: [2.0, 0.5],
            k: [800.0, 300.0],
            c: [3.0, 1.0],
            g: 4.0,
        };
        let a = sys.matrix();
        let x = [0.01, -0.02, 0.3, 0.1];
        let j = jacobian(&mut sys, 0.0, &x, &[1e-4, 1e-4, 1e-3, 1e-3]).unwrap();
        for r in 0..4 {
            for c in 0..4 {
                assert!(
                    (j[(r, c)] - a[r][c]).abs() < 1e-9 * (1.0 + a[r][c].abs()),
                    "({r}, {c}): {} vs {}",
                    j[(r, c)],
                    a[r][c]
                );
            }
        }
    }

    #[test]
    fn eigenpairs_of_a_damped_oscillator_are_the_roots_of_its_characteristic_equation() {
        // one mass (the second decoupled and stiff), m x'' + c x' + k x = 0:
        // λ = −c/2m ± i sqrt(k/m − (c/2m)²)
        let (m, k, c) = (2.0, 800.0, 3.0);
        let mut sys = Chain {
            m: [m, 1.0],
            k: [k, 0.0],
            c: [c, 0.0],
            g: 0.0,
        };
        let j = jacobian(&mut sys, 0.0, &[0.0; 4], &[1e-6; 4]).unwrap();
        let e = eigenpairs(&j).unwrap();
        let sigma = -c / (2.0 * m);
        let wd = (k / m - sigma * sigma).sqrt();
        let osc: Vec<_> = e.iter().filter(|p| p.im.abs() > 1.0).collect();
        assert_eq!(osc.len(), 2, "{e:?}");
        for p in osc {
            assert!((p.re - sigma).abs() < 1e-9, "{p:?}");
            assert!((p.im.abs() - wd).abs() < 1e-9, "{p:?}");
            assert!((p.damping_ratio() - c / (2.0 * (k * m).sqrt())).abs() < 1e-12);
            assert!((p.frequency() - wd / std::f64::consts::TAU).abs() < 1e-12);
            // the mode moves the first mass only, velocity = λ · position
            assert!(p.vector[1][0].hypot(p.vector[1][1]) < 1e-9);
            let (pr, pi) = (p.vector[0][0], p.vector[0][1]);
            let (vr, vi) = (p.re * pr - p.im * pi, p.re * pi + p.im * pr);
            assert!(
                (p.vector[2][0] - vr).abs() < 1e-6 * wd && (p.vector[2][1] - vi).abs() < 1e-6 * wd
            );
        }
        // sorted by decreasing real part, eigenvector normalised to a largest component of 1
        assert!(e.windows(2).all(|w| w[0].re >= w[1].re));
        for p in &e {
            let big = p
                .vector
                .iter()
                .map(|c| c[0].hypot(c[1]))
                .fold(0.0, f64::max);
            assert!((big - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_negative_damping_gives_a_growing_mode_and_a_gyroscopic_term_shifts_the_frequencies() {
        // negative damping on the first mass: one pair with Re λ > 0
        let mut sys = Chain {
            m: [1.0, 1.0],
            k: [100.0, 50.0],
            c: [-0.5, 0.2],
            g: 0.0,
        };
        let j = jacobian(&mut sys, 0.0, &[0.0; 4], &[1e-6; 4]).unwrap();
        let e = eigenpairs(&j).unwrap();
        assert!(e[0].re > 0.0 && e[0].damping_ratio() < 0.0, "{e:?}");
        // the eigenvalues solve det(λ² M + λ (C + G) + K) = 0: check the residual for each
        let check = |sys: &Chain, e: &[Eigenpair]| {
            for p in e {
                let l = faer::c64::new(p.re, p.im);
                let a = sys.matrix();
                // the characteristic matrix (A − λ I) v = 0 with the returned eigenvector
                for r in 0..4 {
                    let mut s = faer::c64::new(0.0, 0.0);
                    for c in 0..4 {
                        s += faer::c64::new(a[r][c], 0.0)
                            * faer::c64::new(p.vector[c][0], p.vector[c][1]);
                    }
                    s -= l * faer::c64::new(p.vector[r][0], p.vector[r][1]);
                    assert!(s.norm() < 1e-8 * (1.0 + l.norm()), "row {r}: {s:?}");
                }
            }
        };
        check(&sys, &e);
        sys.c = [0.5, 0.2];
        sys.g = 6.0;
        let e = eigenpairs(&jacobian(&mut sys, 0.0, &[0.0; 4], &[1e-6; 4]).unwrap()).unwrap();
        assert!(e.iter().all(|p| p.re < 0.0));
        check(&sys, &e);
    }

    #[test]
    fn bad_steps_and_failing_right_hand_sides_are_errors() {
        let mut sys = Chain {
            m: [1.0, 1.0],
            k: [1.0, 1.0],
            c: [0.0, 0.0],
            g: 0.0,
        };
        let e = jacobian(&mut sys, 0.0, &[0.0; 4], &[1e-6, 0.0, 1e-6, 1e-6]).unwrap_err();
        assert!(e.0.contains("component 1"), "{e}");
        let e = jacobian(&mut sys, 0.0, &[0.0; 3], &[1e-6; 3]).unwrap_err();
        assert!(e.0.contains("3 components"), "{e}");
        struct Fails;
        impl OdeSystem for Fails {
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, _t: f64, x: &[f64], _d: &mut [f64]) -> Result<(), RhsError> {
                Err(RhsError(format!("derailed at {}", x[0])))
            }
        }
        assert!(jacobian(&mut Fails, 0.0, &[0.0], &[1e-6]).is_err());
        let mut m = Mat::<f64>::zeros(2, 2);
        m[(0, 1)] = f64::NAN;
        assert!(eigenpairs(&m).unwrap_err().contains("(0, 1)"));
    }
}
