//! Combined elastic constants of two contacting bodies.

use crate::error::{ElasticError, in_range, positive};

/// Combined elastic constants of two bodies.
///
/// CONTACT's convention (Kalker 1990, §1.4; Vollebregt's CONTACT `combin_mater`):
/// `1/G = (1/G1 + 1/G2)/2` and `nu = G/2 (nu1/G1 + nu2/G2)`. The Hertz modulus is then
/// `E* = G/(1-nu)`, which for identical bodies equals `E/(2(1-nu^2))` (Johnson 1985, §4.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// \[Pa\] combined shear modulus
    pub g: f64,
    /// [-] combined Poisson ratio
    pub nu: f64,
}

impl Material {
    /// Combined constants given directly.
    ///
    /// `g` must be finite and positive, `nu` in `[0, 0.5]` (the range covered by Kalker's
    /// tables, see [`crate::kalker_coeffs`]).
    pub fn new(g: f64, nu: f64) -> Result<Self, ElasticError> {
        positive("g [Pa]", g)?;
        in_range("nu [-]", nu, 0.0, 0.5, "a Poisson ratio in [0, 0.5]")?;
        Ok(Self { g, nu })
    }

    /// Combine two bodies given by Young's moduli `e1`, `e2` \[Pa\] and Poisson ratios `nu1`, `nu2`.
    ///
    /// `G_i = E_i/(2(1+nu_i))`, then CONTACT's rule above.
    pub fn from_two(e1: f64, nu1: f64, e2: f64, nu2: f64) -> Result<Self, ElasticError> {
        positive("e1 [Pa]", e1)?;
        positive("e2 [Pa]", e2)?;
        in_range("nu1 [-]", nu1, 0.0, 0.5, "a Poisson ratio in [0, 0.5]")?;
        in_range("nu2 [-]", nu2, 0.0, 0.5, "a Poisson ratio in [0, 0.5]")?;
        let g1 = e1 / (2.0 * (1.0 + nu1));
        let g2 = e2 / (2.0 * (1.0 + nu2));
        let g = 2.0 / (1.0 / g1 + 1.0 / g2);
        let nu = 0.5 * g * (nu1 / g1 + nu2 / g2);
        Self::new(g, nu)
    }

    /// \[Pa\] Hertz modulus E* = G/(1-nu) (Johnson 1985, eq. 4.22 with CONTACT's combination).
    pub fn e_star(&self) -> f64 {
        self.g / (1.0 - self.nu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_steels_give_textbook_e_star() {
        let e = 210e9;
        let nu = 0.3;
        let m = Material::from_two(e, nu, e, nu).unwrap();
        assert!((m.g - e / 2.6).abs() < 1e-6 * m.g);
        assert!((m.nu - nu).abs() < 1e-14);
        let e_star = e / (2.0 * (1.0 - nu * nu));
        assert!((m.e_star() - e_star).abs() < 1e-12 * e_star);
    }

    #[test]
    fn harmonic_mean_of_shear_moduli() {
        let m = Material::from_two(210e9, 0.3, 105e9, 0.3).unwrap();
        let g1 = 210e9 / 2.6;
        let g2 = 105e9 / 2.6;
        assert!((1.0 / m.g - 0.5 * (1.0 / g1 + 1.0 / g2)).abs() * m.g < 1e-14);
        assert!((m.nu - 0.3).abs() < 1e-14);
    }

    #[test]
    fn rejects_bad_input() {
        assert!(Material::new(-1.0, 0.3).is_err());
        assert!(Material::new(f64::NAN, 0.3).is_err());
        assert!(Material::new(80e9, 0.6).is_err());
        assert!(Material::new(80e9, f64::NAN).is_err());
        assert!(Material::from_two(210e9, 0.3, f64::INFINITY, 0.3).is_err());
        let err = Material::new(80e9, 0.7).unwrap_err();
        assert!(err.to_string().contains("nu"));
    }
}
