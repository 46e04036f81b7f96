//! Kalker's linear theory of rolling contact: creep coefficients and linear creep forces.
//!
//! Conventions (Kalker 1967, 1990; contact-theory note §3.1): rolling in +x; creepages
//! `xi` (longitudinal), `eta` (lateral), `phi` (spin, [1/m]); rigid slip per unit rolling
//! distance `w_x = xi - phi y`, `w_y = eta + phi x`; forces act on the upper body and oppose
//! the creepage.

use crate::error::{ElasticError, finite, in_range, positive};
use crate::material::Material;
use std::f64::consts::PI;

/// Kalker's creep coefficients of linear theory (Kalker 1967; table E.3 of Kalker 1990).
#[derive(Clone, Copy, Debug)]
pub struct KalkerCoeffs {
    /// [-] longitudinal creep coefficient
    pub c11: f64,
    /// [-] lateral creep coefficient
    pub c22: f64,
    /// [-] lateral/spin coupling coefficient
    pub c23: f64,
    /// [-] spin coefficient
    pub c33: f64,
}

/// Kalker (1990), *Three-dimensional elastic bodies in rolling contact*, table E.3.
/// C11, C22, C23 as in CONTACT's `linrol` data; C33 as recalled in the contact-theory note
/// §3.1 (checked there against CONTACT runs). Rows 0..=9: a/b = 0.1..1.0 (a < b);
/// rows 10..=18: b/a = 0.9..0.1 (a > b). Columns: for each of C11, C22, C23, C33 the values at
/// nu = 0, 0.25, 0.5.
#[rustfmt::skip]
#[allow(clippy::approx_constant)] // 3.14 is a table entry (C22), not pi
const TABLE_E3: [[f64; 12]; 19] = [
    [2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731, 6.42, 8.28, 11.7],
    [2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809, 3.46, 4.27, 5.66],
    [2.68, 3.44, 4.8, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889, 2.49, 2.96, 3.72],
    [2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.72, 0.823, 0.977, 2.02, 2.32, 2.77],
    [2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07, 1.74, 1.93, 2.22],
    [2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.93, 1.03, 1.18, 1.56, 1.68, 1.86],
    [3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29, 1.43, 1.5, 1.6],
    [3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.4, 1.34, 1.37, 1.42],
    [3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51, 1.27, 1.27, 1.27],
    [3.4, 4.12, 5.2, 3.4, 3.67, 3.98, 1.33, 1.47, 1.63, 1.21, 1.19, 1.16],
    [3.51, 4.22, 5.3, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77, 1.16, 1.11, 1.06],
    [3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94, 1.1, 1.04, 0.954],
    [3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18, 1.05, 0.965, 0.852],
    [4.06, 4.78, 5.8, 4.06, 4.5, 5.04, 2.01, 2.23, 2.5, 1.01, 0.892, 0.751],
    [4.37, 5.1, 6.11, 4.37, 4.9, 5.56, 2.35, 2.62, 2.96, 0.958, 0.819, 0.65],
    [4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.7, 0.912, 0.747, 0.549],
    [5.57, 6.34, 7.34, 5.57, 6.4, 7.51, 3.79, 4.32, 5.01, 0.868, 0.674, 0.446],
    [6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89, 0.828, 0.601, 0.341],
    [10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0, 0.795, 0.526, 0.228],
];

/// Table row of shape index `j` (1..=10, g = j/10) in the given branch.
fn row(a_lt_b: bool, j: usize) -> usize {
    if a_lt_b { j - 1 } else { 19 - j }
}

/// Coefficients of one table row at Poisson ratio `nu`: quadratic Lagrange interpolation of
/// 1/C through nu = 0, 0.25, 0.5 (CONTACT `linrol`; contact-theory note §3.1).
fn row_at_nu(r: usize, nu: f64) -> [f64; 4] {
    let w0 = 8.0 * (nu - 0.25) * (nu - 0.5);
    let w1 = -16.0 * nu * (nu - 0.5);
    let w2 = 8.0 * nu * (nu - 0.25);
    let t = &TABLE_E3[r];
    let mut out = [0.0; 4];
    for (k, o) in out.iter_mut().enumerate() {
        let inv = w0 / t[3 * k] + w1 / t[3 * k + 1] + w2 / t[3 * k + 2];
        *o = 1.0 / inv;
    }
    out
}

/// Kalker's creep coefficients for an ellipse with semi-axes `a` (rolling direction x) and `b`
/// (lateral) \[m\] and Poisson ratio `nu` in [0, 0.5].
///
/// For `g = min(a/b, b/a) >= 0.1`: Kalker (1990) table E.3, quadratic in nu on 1/C, then
/// linear in g between the rows of the same branch (a < b or a > b), as CONTACT's `linrol`.
///
/// For `g < 0.1` (contact-theory note §3.1, CONTACT `linrol`; Kalker 1967 asymptotes):
/// - a << b: `C11 = pi^2/(4(1-nu))`, `C22 = pi^2/4`,
///   `C23 = pi sqrt(g)/(3(1-nu)) (1 + nu(ln(16/g) - 5))`;
/// - a >> b, with `L = ln(16/g^2)`: `C11 = 2pi/((L-2nu) g) (1 + (3-ln4)/(L-2nu))`,
///   `C22 = 2pi/g (1 + (1-nu)(3-ln4)/((1-nu)L+2nu)) / ((1-nu)L+2nu)`,
///   `C23 = 2pi/(3 g^{3/2} ((1-nu)L - 2 + 4nu))`.
///
/// No asymptote for C33 is given in those sources. Here C33 is continued from the g = 0.1
/// row: as `C33(0.1) * 0.1/g` for a << b (the 1/g growth of strip theory, where each strip
/// carries a 2-D Carter/Johnson 1985 §8.3 linear traction, giving `C33 ~ pi^2/(16(1-nu) g)`),
/// and held constant for a >> b. These C33 values are a modelling choice, not Kalker's.
pub fn kalker_coeffs(a: f64, b: f64, nu: f64) -> Result<KalkerCoeffs, ElasticError> {
    positive("a [m]", a)?;
    positive("b [m]", b)?;
    in_range("nu [-]", nu, 0.0, 0.5, "a Poisson ratio in [0, 0.5]")?;
    Ok(coeffs_from_rows(a, b, nu, |r| row_at_nu(r, nu)))
}

/// Kalker's table at one Poisson ratio, its rows interpolated in ν once, for the many lookups of
/// a contact model (each strip of a STRIPES patch takes the coefficients of its own ellipse).
/// [`KalkerTable::coeffs`] gives the same values as [`kalker_coeffs`].
#[derive(Clone, Debug)]
pub struct KalkerTable {
    nu: f64,
    rows: [[f64; 4]; 19],
}

impl KalkerTable {
    /// The table at Poisson ratio `nu` in [0, 0.5].
    pub fn new(nu: f64) -> Result<Self, ElasticError> {
        in_range("nu [-]", nu, 0.0, 0.5, "a Poisson ratio in [0, 0.5]")?;
        let mut rows = [[0.0; 4]; 19];
        for (r, row) in rows.iter_mut().enumerate() {
            *row = row_at_nu(r, nu);
        }
        Ok(KalkerTable { nu, rows })
    }

    /// \[-\] the table's Poisson ratio.
    pub fn nu(&self) -> f64 {
        self.nu
    }

    /// Kalker's coefficients for the ellipse with semi-axes `a` (rolling direction) and `b`
    /// \[m\], as [`kalker_coeffs`] at the table's ν.
    pub fn coeffs(&self, a: f64, b: f64) -> Result<KalkerCoeffs, ElasticError> {
        positive("a [m]", a)?;
        positive("b [m]", b)?;
        Ok(coeffs_from_rows(a, b, self.nu, |r| self.rows[r]))
    }
}

/// [`kalker_coeffs`] for checked `a`, `b` > 0 with the table's rows at ν given by `row_nu` (row
/// index → C11, C22, C23, C33).
#[inline]
fn coeffs_from_rows(a: f64, b: f64, nu: f64, row_nu: impl Fn(usize) -> [f64; 4]) -> KalkerCoeffs {
    let a_lt_b = a <= b;
    let g = if a_lt_b { a / b } else { b / a };
    if g >= 0.1 {
        let p = (g * 10.0).min(10.0);
        let j0 = (p.floor() as usize).clamp(1, 9);
        let w = p - j0 as f64;
        let lo = row_nu(row(a_lt_b, j0));
        let hi = row_nu(row(a_lt_b, j0 + 1));
        let c = |k: usize| (1.0 - w) * lo[k] + w * hi[k];
        return KalkerCoeffs {
            c11: c(0),
            c22: c(1),
            c23: c(2),
            c33: c(3),
        };
    }
    let edge = row_nu(row(a_lt_b, 1));
    if a_lt_b {
        KalkerCoeffs {
            c11: PI * PI / (4.0 * (1.0 - nu)),
            c22: PI * PI / 4.0,
            c23: PI * g.sqrt() / (3.0 * (1.0 - nu)) * (1.0 + nu * ((16.0 / g).ln() - 5.0)),
            c33: edge[3] * 0.1 / g,
        }
    } else {
        let lam = (16.0 / (g * g)).ln();
        let ln4 = 4f64.ln();
        let d1 = lam - 2.0 * nu;
        let d2 = (1.0 - nu) * lam + 2.0 * nu;
        KalkerCoeffs {
            c11: 2.0 * PI / (d1 * g) * (1.0 + (3.0 - ln4) / d1),
            c22: 2.0 * PI / g * (1.0 + (1.0 - nu) * (3.0 - ln4) / d2) / d2,
            c23: 2.0 * PI / (3.0 * g.powf(1.5) * ((1.0 - nu) * lam - 2.0 + 4.0 * nu)),
            c33: edge[3],
        }
    }
}

/// Creepages in Kalker's convention (contact-theory note §3.1): rigid slip per unit rolling
/// distance `w_x = xi - phi y`, `w_y = eta + phi x`, rolling in +x.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Creepages {
    /// [-] longitudinal creepage
    pub xi: f64,
    /// [-] lateral creepage
    pub eta: f64,
    /// [1/m] spin creepage
    pub phi: f64,
}

impl Creepages {
    pub(crate) fn check(&self) -> Result<(), ElasticError> {
        finite("xi [-]", self.xi)?;
        finite("eta [-]", self.eta)?;
        finite("phi [1/m]", self.phi)?;
        Ok(())
    }
}

/// Tangential contact forces on the upper body (wheel), Kalker's convention: they oppose the
/// creepage.
#[derive(Clone, Copy, Debug, Default)]
pub struct TangentialForces {
    /// \[N\] longitudinal force
    pub fx: f64,
    /// \[N\] lateral force
    pub fy: f64,
    /// [N m] moment about the contact normal through the patch origin
    pub mz: f64,
    /// [-] fraction of loaded area (or cells) in adhesion
    pub adhesion_fraction: f64,
}

/// Kalker's linear (no-slip) theory (Kalker 1967; contact-theory note §3.1), with `c^2 = ab`:
/// `Fx = -G ab C11 xi`, `Fy = -G ab C22 eta - G (ab)^{3/2} C23 phi`,
/// `Mz = G (ab)^{3/2} C23 eta - G (ab)^2 C33 phi`.
///
/// The sign of the eta–Mz coupling is that of the traction field of the simplified theory
/// (FASTSIM): lateral creepage loads the trailing half more, giving `Mz > 0` for `eta > 0`.
/// The full adhesion result is returned (`adhesion_fraction = 1`).
pub fn linear_kalker(
    a: f64,
    b: f64,
    creep: &Creepages,
    mat: &Material,
) -> Result<TangentialForces, ElasticError> {
    creep.check()?;
    let c = kalker_coeffs(a, b, mat.nu)?;
    let ab = a * b;
    let g = mat.g;
    let ab32 = ab * ab.sqrt();
    Ok(TangentialForces {
        fx: -g * ab * c.c11 * creep.xi,
        fy: -g * ab * c.c22 * creep.eta - g * ab32 * c.c23 * creep.phi,
        mz: g * ab32 * c.c23 * creep.eta - g * ab * ab * c.c33 * creep.phi,
        adhesion_fraction: 1.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table interpolated in ν once gives the coefficients of `kalker_coeffs` exactly, on
    /// both branches, between and beyond the table's rows.
    #[test]
    fn the_table_at_one_poisson_ratio_gives_kalker_coeffs() {
        for nu in [0.0, 0.25, 0.28, 0.5] {
            let t = KalkerTable::new(nu).unwrap();
            assert_eq!(t.nu(), nu);
            for g in [0.02, 0.1, 0.137, 0.5, 0.95, 1.0] {
                for (a, b) in [(g * 4e-3, 4e-3), (4e-3, g * 4e-3)] {
                    let want = kalker_coeffs(a, b, nu).unwrap();
                    let got = t.coeffs(a, b).unwrap();
                    assert_eq!(
                        [got.c11, got.c22, got.c23, got.c33],
                        [want.c11, want.c22, want.c23, want.c33]
                    );
                }
            }
        }
        assert!(KalkerTable::new(0.6).is_err());
        assert!(KalkerTable::new(0.3).unwrap().coeffs(0.0, 1e-3).is_err());
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn table_values_at_circle() {
        let c = kalker_coeffs(1.0, 1.0, 0.25).unwrap();
        assert!(rel(c.c11, 4.12) < 1e-12);
        assert!(rel(c.c22, 3.67) < 1e-12);
        assert!(rel(c.c23, 1.47) < 1e-12);
        assert!(rel(c.c33, 1.19) < 1e-12);
        // Scale invariance: only the ratio matters.
        let d = kalker_coeffs(3e-3, 3e-3, 0.25).unwrap();
        assert_eq!(c.c11, d.c11);
    }

    #[test]
    fn nu_028_column_of_note() {
        // (a, b, C11, C22, C23, C33) at nu = 0.28, contact-theory note §3.1 second table.
        let rows = [
            (0.1, 1.0, 3.441, 2.521, 0.496, 8.580),
            (0.5, 1.0, 3.734, 3.026, 0.943, 1.958),
            (0.8, 1.0, 4.019, 3.438, 1.266, 1.375),
            (1.0, 1.0, 4.226, 3.705, 1.488, 1.187),
            (1.0, 0.7, 4.644, 4.261, 1.975, 0.952),
            (1.0, 0.5, 5.204, 4.971, 2.657, 0.799),
            (1.0, 0.2, 7.892, 8.308, 6.759, 0.564),
            (1.0, 0.1, 11.832, 13.112, 14.945, 0.476),
        ];
        for (a, b, c11, c22, c23, c33) in rows {
            let c = kalker_coeffs(a, b, 0.28).unwrap();
            // 1e-3 relative, or half a unit of the third decimal printed.
            let ok = |x: f64, e: f64| rel(x, e) < 1e-3 || (x - e).abs() <= 5.01e-4;
            assert!(ok(c.c11, c11), "a/b={}: C11 {} vs {c11}", a / b, c.c11);
            assert!(ok(c.c22, c22), "a/b={}: C22 {} vs {c22}", a / b, c.c22);
            assert!(ok(c.c23, c23), "a/b={}: C23 {} vs {c23}", a / b, c.c23);
            assert!(ok(c.c33, c33), "a/b={}: C33 {} vs {c33}", a / b, c.c33);
        }
        // nu = 0.30 at b/a = 0.5
        let c = kalker_coeffs(2.0, 1.0, 0.30).unwrap();
        assert!(rel(c.c11, 5.275) < 1e-3 && rel(c.c22, 5.020) < 1e-3 && rel(c.c23, 2.682) < 1e-3);
    }

    #[test]
    fn linear_in_g_between_rows() {
        let lo = kalker_coeffs(0.3, 1.0, 0.25).unwrap();
        let hi = kalker_coeffs(0.4, 1.0, 0.25).unwrap();
        let mid = kalker_coeffs(0.35, 1.0, 0.25).unwrap();
        assert!(rel(mid.c22, 0.5 * (lo.c22 + hi.c22)) < 1e-12);
        assert!(rel(lo.c22, 2.75) < 1e-12 && rel(hi.c22, 2.88) < 1e-12);
        // Continuous across the circle between branches.
        let l = kalker_coeffs(1.0 - 1e-9, 1.0, 0.28).unwrap();
        let r = kalker_coeffs(1.0, 1.0 - 1e-9, 0.28).unwrap();
        assert!(rel(l.c11, r.c11) < 1e-7 && rel(l.c33, r.c33) < 1e-7);
    }

    #[test]
    fn asymptotes_join_table_at_g_0_1() {
        let mut worst: f64 = 0.0;
        for &nu in &[0.0, 0.25, 0.28, 0.5] {
            for &(a, b) in &[(1.0, 10.0), (10.0, 1.0)] {
                let t = kalker_coeffs(a, b, nu).unwrap();
                let s = if a < b {
                    kalker_coeffs(a * (1.0 - 1e-9), b, nu).unwrap()
                } else {
                    kalker_coeffs(a, b * (1.0 - 1e-9), nu).unwrap()
                };
                for (x, y) in [
                    (t.c11, s.c11),
                    (t.c22, s.c22),
                    (t.c23, s.c23),
                    (t.c33, s.c33),
                ] {
                    worst = worst.max(rel(y, x));
                }
            }
        }
        eprintln!("kalker: largest jump table/asymptote at g = 0.1: {worst:.4}");
        assert!(worst < 0.07, "jump {worst}");
        // C11 of a << b tends to the 2-D Carter value pi^2/(4(1-nu)).
        let c = kalker_coeffs(1e-4, 1.0, 0.3).unwrap();
        assert!(rel(c.c11, std::f64::consts::PI.powi(2) / 2.8) < 1e-12);
    }

    #[test]
    fn linear_forces_and_signs() {
        let mat = Material::new(82e9, 0.28).unwrap();
        let (a, b) = (8e-3, 4e-3);
        let c = kalker_coeffs(a, b, 0.28).unwrap();
        let f = linear_kalker(
            a,
            b,
            &Creepages {
                xi: 1e-4,
                eta: 0.0,
                phi: 0.0,
            },
            &mat,
        )
        .unwrap();
        assert!(rel(f.fx, -82e9 * a * b * c.c11 * 1e-4) < 1e-14);
        assert_eq!(f.fy, 0.0);
        let f = linear_kalker(
            a,
            b,
            &Creepages {
                xi: 0.0,
                eta: 1e-4,
                phi: 0.0,
            },
            &mat,
        )
        .unwrap();
        assert!(f.fy < 0.0 && f.mz > 0.0);
        let f = linear_kalker(
            a,
            b,
            &Creepages {
                xi: 0.0,
                eta: 0.0,
                phi: 0.1,
            },
            &mat,
        )
        .unwrap();
        assert!(f.fy < 0.0 && f.mz < 0.0);
        assert!(rel(f.mz, -82e9 * (a * b).powi(2) * c.c33 * 0.1) < 1e-14);
        let bad = Creepages {
            xi: f64::NAN,
            ..Default::default()
        };
        assert!(linear_kalker(a, b, &bad, &mat).is_err());
        assert!(kalker_coeffs(0.0, 1.0, 0.3).is_err());
        assert!(kalker_coeffs(1.0, 1.0, 0.51).is_err());
    }
}
