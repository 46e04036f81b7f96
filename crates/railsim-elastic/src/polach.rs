//! Polach's closed-form creep-force model (Polach 1999, VSD 33 suppl.; Polach 2005, Wear 258),
//! the fastest fidelity level.
//!
//! Polach writes forces with the sign of the creepage; this module returns them in Kalker's
//! convention (force on the upper body, opposing the creepage), i.e. with every component
//! negated (contact-theory note §3.4).

use crate::error::{ElasticError, in_range, non_negative, positive};
use crate::kalker::{Creepages, TangentialForces, kalker_coeffs};
use crate::material::Material;
use std::f64::consts::PI;

/// Parameters of Polach's model.
#[derive(Clone, Copy, Debug)]
pub struct PolachParams {
    /// [-] reduction factor of the initial slope in the adhesion area (k_A, Polach 2005)
    pub k_a: f64,
    /// [-] reduction factor in the slip area (k_S, Polach 2005)
    pub k_s: f64,
    /// [-] friction at zero slip velocity
    pub mu0: f64,
    /// [-] ratio A = mu_inf/mu0 of the friction at infinite slip velocity to mu0
    pub a_ratio: f64,
    /// [s/m] exponential decay rate B of the friction with slip velocity
    pub b_decay: f64,
}

impl PolachParams {
    /// Polach's 1999 model with constant (Coulomb) friction `mu`:
    /// `k_a = k_s = 1`, `A = 1`, `B = 0`.
    pub fn coulomb(mu: f64) -> Self {
        Self {
            k_a: 1.0,
            k_s: 1.0,
            mu0: mu,
            a_ratio: 1.0,
            b_decay: 0.0,
        }
    }

    fn check(&self) -> Result<(), ElasticError> {
        positive("k_a [-]", self.k_a)?;
        positive("k_s [-]", self.k_s)?;
        non_negative("mu0 [-]", self.mu0)?;
        in_range("a_ratio [-]", self.a_ratio, 0.0, 1.0, "a ratio in [0, 1]")?;
        non_negative("b_decay [s/m]", self.b_decay)?;
        Ok(())
    }

    /// Friction at slip velocity `w` [m/s]: `mu = mu0 ((1-A) exp(-B w) + A)` (Polach 2005, eq. 3).
    pub fn friction(&self, w: f64) -> f64 {
        self.mu0 * ((1.0 - self.a_ratio) * (-self.b_decay * w).exp() + self.a_ratio)
    }
}

/// Polach's total creepage `s_C = sqrt(s_x^2 + s_yC^2)` of an ellipse of semi-axis `a` \[m\]
/// along the rolling direction, with the spin-corrected lateral creepage `s_yC = s_y` if
/// `|s_y + phi a| <= |s_y|`, else `s_y + phi a` (Polach 1999; contact-theory note §3.4);
/// returns `(s_C, s_yC)`. `V s_C` is the slip velocity of his friction law.
pub fn spin_corrected_creepage(creep: &Creepages, a: f64) -> (f64, f64) {
    let (sx, sy, phi) = (creep.xi, creep.eta, creep.phi);
    let syc = if (sy + phi * a).abs() <= sy.abs() {
        sy
    } else {
        sy + phi * a
    };
    (sx.hypot(syc), syc)
}

/// Largest gradient used; beyond it the formulas have reached their limits to machine precision.
const EPS_MAX: f64 = 1e150;

/// Polach's creep forces for an ellipse with semi-axes `a` (rolling direction) and `b` \[m\],
/// normal load `n` \[N\], creepages `creep`, rolling speed `speed` [m/s] (for the slip velocity).
///
/// Formulas (Polach 1999; Polach 2005 eqs. 2-3; contact-theory note §3.4), Polach's sign:
/// - spin-corrected lateral creepage `s_yC = s_y` if `|s_y + phi a| <= |s_y|`, else
///   `s_y + phi a`; `s_C = sqrt(s_x^2 + s_yC^2)`; slip velocity `w = s_C V`;
/// - friction `mu = mu0 ((1-A) exp(-B w) + A)`;
/// - `c_jj = sqrt((C11 s_x/s)^2 + (C22 s_y/s)^2)` with `s = |(s_x, s_y)|`;
/// - gradient `eps = G pi a b c_jj s_C/(4 Q mu)`;
/// - `F = (2 Q mu/pi) (k_A eps/(1 + (k_A eps)^2) + atan(k_S eps))`,
///   `F_x = F s_x/s_C`, `F_y = F s_y/s_C`;
/// - spin: `K_s = 1 + 6.3 (1 - exp(-a/b))`, `eps_phi = 8 G b sqrt(ab) C23 |s_yC|/(3 K_s Q mu)`,
///   `delta = (eps_phi^2 - 1)/(eps_phi^2 + 1)`,
///   `K_M = eps_phi (delta^3/3 - delta^2/2 + 1/6) - sqrt((1-delta^2)^3)/3`,
///   `F_yS = -(9/16) a Q mu K_M K_s phi/s_C`, added to `F_y`.
///
/// In the small-creepage limit with `k_A = k_S = 1` this is Kalker's linear theory for
/// C11, C22 and (for `s_x = 0`) the C23 spin term. Returned in Kalker's sign convention (all
/// components negated). Polach's model has no spin moment: `mz = 0`. The adhesion fraction
/// is that of the model's reduced strip, `1/(1 + (k_A eps)^2)` (from the translational
/// gradient only).
pub fn polach(
    a: f64,
    b: f64,
    n: f64,
    creep: &Creepages,
    speed: f64,
    params: &PolachParams,
    mat: &Material,
) -> Result<TangentialForces, ElasticError> {
    positive("a [m]", a)?;
    positive("b [m]", b)?;
    non_negative("n [N]", n)?;
    non_negative("speed [m/s]", speed)?;
    creep.check()?;
    params.check()?;
    let c = kalker_coeffs(a, b, mat.nu)?;
    let (sx, sy, phi) = (creep.xi, creep.eta, creep.phi);
    let (sc, syc) = spin_corrected_creepage(creep, a);
    if sc == 0.0 {
        return Ok(TangentialForces {
            adhesion_fraction: 1.0,
            ..Default::default()
        });
    }
    let mu = params.friction(sc * speed);
    let q_mu = n * mu;
    if q_mu == 0.0 {
        return Ok(TangentialForces::default());
    }
    let s = sx.hypot(sy);
    let cjj = if s > 0.0 {
        (c.c11 * sx / s).hypot(c.c22 * sy / s)
    } else {
        0.0
    };
    let g = mat.g;
    let eps = (g * PI * a * b * cjj * sc / (4.0 * q_mu)).min(EPS_MAX);
    let ka = params.k_a * eps;
    let f = 2.0 * q_mu / PI * (ka / (1.0 + ka * ka) + (params.k_s * eps).atan());
    let fx = f * sx / sc;
    let mut fy = f * sy / sc;
    if phi != 0.0 {
        let k_s = 1.0 + 6.3 * (1.0 - (-a / b).exp());
        let e =
            (8.0 * g * b * (a * b).sqrt() * c.c23 * syc.abs() / (3.0 * k_s * q_mu)).min(EPS_MAX);
        // 1 - delta and 1 + delta without cancellation; delta^3/3 - delta^2/2 + 1/6
        // = (1-delta)^2 (1+2 delta)/6.
        let one_minus = 2.0 / (e * e + 1.0);
        let one_plus = 2.0 - one_minus;
        let delta = 1.0 - one_minus;
        let k_m = e * one_minus * one_minus * (1.0 + 2.0 * delta) / 6.0
            - (one_minus * one_plus).powf(1.5) / 3.0;
        fy += -(9.0 / 16.0) * a * q_mu * k_m * k_s * phi / sc;
    }
    Ok(TangentialForces {
        fx: -fx,
        fy: -fy,
        mz: 0.0,
        adhesion_fraction: 1.0 / (1.0 + ka * ka),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kalker::linear_kalker;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    fn mat() -> Material {
        Material::new(82e9, 0.28).unwrap()
    }

    #[test]
    fn linear_limit_is_kalker() {
        let mat = mat();
        let p = PolachParams::coulomb(0.3);
        let mut worst: f64 = 0.0;
        for &(a, b) in &[(4e-3, 8e-3), (6e-3, 6e-3), (8e-3, 4e-3)] {
            let cases = [
                Creepages {
                    xi: 1e-7,
                    eta: 0.0,
                    phi: 0.0,
                },
                Creepages {
                    xi: 0.0,
                    eta: -1e-7,
                    phi: 0.0,
                },
                Creepages {
                    xi: 0.0,
                    eta: 0.0,
                    phi: 2e-5,
                },
                Creepages {
                    xi: 0.0,
                    eta: 0.0,
                    phi: -2e-5,
                },
            ];
            for (i, cr) in cases.iter().enumerate() {
                let f = polach(a, b, 80e3, cr, 30.0, &p, &mat).unwrap();
                let k = linear_kalker(a, b, cr, &mat).unwrap();
                let (got, want) = if i == 0 { (f.fx, k.fx) } else { (f.fy, k.fy) };
                let e = rel(got, want);
                worst = worst.max(e);
                assert!(e < 0.01, "a={a} b={b} case {i}: {got} vs {want}");
                assert!(f.adhesion_fraction > 0.999);
            }
        }
        eprintln!("polach linear limit: worst relative error vs Kalker {worst:.2e}");
        // Reduced slopes: the initial slope scales with (k_A + k_S)/2.
        let pr = PolachParams {
            k_a: 0.8,
            k_s: 0.4,
            ..p
        };
        let cr = Creepages {
            xi: 1e-8,
            ..Default::default()
        };
        let f = polach(8e-3, 4e-3, 80e3, &cr, 30.0, &pr, &mat).unwrap();
        let k = linear_kalker(8e-3, 4e-3, &cr, &mat).unwrap();
        assert!(rel(f.fx, 0.6 * k.fx) < 1e-4);
    }

    #[test]
    fn saturates_at_mu_n() {
        let mat = mat();
        let p = PolachParams::coulomb(0.3);
        for cr in [
            Creepages {
                xi: 0.2,
                eta: 0.0,
                phi: 0.0,
            },
            Creepages {
                xi: -0.1,
                eta: 0.15,
                phi: 0.0,
            },
        ] {
            let f = polach(8e-3, 4e-3, 80e3, &cr, 30.0, &p, &mat).unwrap();
            let mag = f.fx.hypot(f.fy);
            assert!(rel(mag, 0.3 * 80e3) < 1e-3, "|F| = {mag}");
            assert!(f.fx * cr.xi < 0.0 && f.adhesion_fraction < 1e-3);
        }
        // monotone in creepage
        let mut last = 0.0;
        for k in 0..20 {
            let cr = Creepages {
                xi: 1e-6 * 1.8f64.powi(k),
                ..Default::default()
            };
            let f = polach(8e-3, 4e-3, 80e3, &cr, 30.0, &p, &mat).unwrap();
            assert!(-f.fx > last && -f.fx < 0.3 * 80e3);
            last = -f.fx;
        }
    }

    #[test]
    fn falling_friction_reduces_force() {
        let mat = mat();
        let constant = PolachParams::coulomb(0.55);
        let falling = PolachParams {
            k_a: 1.0,
            k_s: 1.0,
            mu0: 0.55,
            a_ratio: 0.4,
            b_decay: 0.6,
        };
        let cr = Creepages {
            xi: 0.1,
            ..Default::default()
        };
        let v = 30.0;
        let f0 = polach(8e-3, 4e-3, 80e3, &cr, v, &constant, &mat).unwrap();
        let f1 = polach(8e-3, 4e-3, 80e3, &cr, v, &falling, &mat).unwrap();
        let mu_w = falling.friction(0.1 * v);
        assert!(rel(mu_w, 0.55 * (0.6 * (-1.8f64).exp() + 0.4)) < 1e-14);
        assert!(f1.fx.abs() < 0.6 * f0.fx.abs());
        assert!(rel(f1.fx.abs(), mu_w * 80e3) < 0.01);
        // At zero speed the slip velocity is zero and mu = mu0.
        let f2 = polach(8e-3, 4e-3, 80e3, &cr, 0.0, &falling, &mat).unwrap();
        assert!(f2.fx.abs() > f1.fx.abs());
        // Polach's dry parameters (k_S = 0.4) lower it further, below mu(w) Q.
        let dry = PolachParams {
            k_s: 0.4,
            ..falling
        };
        let f3 = polach(8e-3, 4e-3, 80e3, &cr, v, &dry, &mat).unwrap();
        assert!(f3.fx.abs() < f1.fx.abs());
    }

    #[test]
    fn degenerate_and_bad_inputs() {
        let mat = mat();
        let p = PolachParams::coulomb(0.3);
        let zero = polach(8e-3, 4e-3, 80e3, &Creepages::default(), 30.0, &p, &mat).unwrap();
        assert_eq!((zero.fx, zero.fy, zero.adhesion_fraction), (0.0, 0.0, 1.0));
        let cr = Creepages {
            xi: 1e-3,
            eta: 2e-3,
            phi: 1.0,
        };
        let unloaded = polach(8e-3, 4e-3, 0.0, &cr, 30.0, &p, &mat).unwrap();
        assert_eq!((unloaded.fx, unloaded.fy), (0.0, 0.0));
        // Huge spin with tiny load stays finite.
        let tiny = polach(
            8e-3,
            4e-3,
            1e-200,
            &Creepages { phi: 1e6, ..cr },
            30.0,
            &p,
            &mat,
        )
        .unwrap();
        assert!(tiny.fx.is_finite() && tiny.fy.is_finite());
        assert!(polach(8e-3, 4e-3, -1.0, &cr, 30.0, &p, &mat).is_err());
        assert!(polach(8e-3, 4e-3, 1.0, &cr, f64::NAN, &p, &mat).is_err());
        let bad = PolachParams { a_ratio: 1.5, ..p };
        assert!(polach(8e-3, 4e-3, 1.0, &cr, 1.0, &bad, &mat).is_err());
    }
}
