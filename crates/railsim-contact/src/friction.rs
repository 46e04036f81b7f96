//! The Coulomb friction coefficient of a wheel/rail pair: one value, or a value that varies
//! across the rail head with the contact angle (a lubricated gauge face, a friction modifier on
//! the top of the rail).
//!
//! The variation is a piecewise-linear function of the contact angle δ (railsim's convention:
//! the rotation from the track's z axis to the contact normal, positive when the normal leans
//! toward the flange, for both wheels; docs/conventions.md), constant beyond the table's ends.
//! This is CONTACT's friction variation across the rail profile ("VARFRC": coefficients given
//! at a few surface inclinations α and interpolated linearly between them; Vollebregt, CONTACT
//! user guide, and its example `mbench_a22_varfric`); for the right rail CONTACT's α is −δ.
//!
//! Where the coefficient is taken:
//! - the Hertz models (`linear`, `polach`, `fastsim`): at the contact angle of the patch's rigid
//!   contact pair, one value per patch;
//! - `stripes` with FaStrip or FASTSIM: at each strip's own normal, so a patch that spans the
//!   gauge corner has the coefficients of its parts; the flexibilities' creepage blend (CONTACT's,
//!   which depends on μ) takes the value at the patch's rigid pair;
//! - `halfspace` and the exact tangential solution: at each grid row's normal (the row's pair of
//!   the travelling), entering the traction bound μ·p of the row.
//!
//! With a constant coefficient every path computes exactly what it did with a plain number.

use crate::ContactError;

/// Friction that falls with the slip velocity `w` \[m/s\]: the coefficient is
/// `mu0 ((1 - A) exp(-B w) + A)`, `mu0` the pair's [`Friction`] where it is taken (Polach,
/// Wear 258, 2005, eq. 3; the exponential decrease of CONTACT's velocity-dependent friction
/// laws). The default, `A = 1`, `B = 0`, is Coulomb friction.
///
/// Which slip velocity each model takes (docs/models/contact.md §6):
/// - `polach`: its own, `V s_C`, the spin-corrected creepage of Polach's model;
/// - `fastsim` (Hertz): the same `V s_C` for the whole ellipse;
/// - `stripes` with FaStrip or FASTSIM: each strip's rigid slip velocity at its centre,
///   `V |(ξ_i, η_i)|`, with the strip's own creepages.
///
/// The local slip of a slip area is smaller than the rigid slip, most where the adhesion area
/// is large, so the friction falls a little early there; at full slip the two agree. The
/// linear model has no friction, and the half-space level and the exact tangential solution
/// (the reference levels) take Coulomb friction: they refuse any other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FallingFriction {
    /// \[-\] `A`: the friction at infinite slip velocity over `mu0`, in [0, 1]
    pub ratio: f64,
    /// \[s/m\] `B`: the rate at which the friction falls with the slip velocity, ≥ 0
    pub decay: f64,
}

impl Default for FallingFriction {
    fn default() -> Self {
        FallingFriction {
            ratio: 1.0,
            decay: 0.0,
        }
    }
}

impl FallingFriction {
    /// Whether this is Coulomb friction (`A = 1` or `B = 0`).
    pub fn is_coulomb(&self) -> bool {
        self.ratio == 1.0 || self.decay == 0.0
    }

    /// The factor `(1 - A) exp(-B w) + A` on `mu0` at slip velocity `w` \[m/s\] (exactly 1
    /// for Coulomb friction).
    #[inline]
    pub fn factor(&self, w: f64) -> f64 {
        if self.is_coulomb() {
            return 1.0;
        }
        (1.0 - self.ratio) * (-self.decay * w).exp() + self.ratio
    }

    /// The first parameter out of its range, as (key, value found, what is expected).
    pub fn problem(&self) -> Option<(&'static str, String, &'static str)> {
        if !(0.0..=1.0).contains(&self.ratio) {
            Some((
                "friction ratio at infinite slip A",
                self.ratio.to_string(),
                "a ratio in [0, 1]",
            ))
        } else if !(self.decay.is_finite() && self.decay >= 0.0) {
            Some((
                "friction decay B",
                self.decay.to_string(),
                "a finite rate >= 0 s/m",
            ))
        } else {
            None
        }
    }
}

/// The Coulomb friction coefficient of a wheel/rail pair.
#[derive(Clone, Debug, PartialEq)]
pub enum Friction {
    /// \[-\] one coefficient everywhere.
    Constant(f64),
    /// A coefficient that varies with the contact angle: `mu[i]` at `angle[i]` \[rad\]
    /// (strictly increasing), linear in between, constant beyond the ends.
    ByContactAngle {
        /// \[rad\] contact angles, strictly increasing, at least two.
        angle: Vec<f64>,
        /// \[-\] the coefficients at those angles, each in (0, 2).
        mu: Vec<f64>,
    },
}

impl Default for Friction {
    fn default() -> Self {
        Friction::Constant(0.3)
    }
}

/// The friction coefficients accepted: those of scene and track files (it was (0, 2) here, so
/// `railsim contact --mu 1.5` ran where a scene refused it).
pub use railsim_spec::FRICTION_RANGE as MU_RANGE;

impl Friction {
    /// \[-\] the coefficient at the contact angle `delta` \[rad\].
    #[inline]
    pub fn at(&self, delta: f64) -> f64 {
        match self {
            Friction::Constant(mu) => *mu,
            Friction::ByContactAngle { angle, mu } => {
                let n = angle.len();
                // (a NaN angle too: the first value rather than a NaN coefficient)
                if delta.is_nan() || delta <= angle[0] {
                    return mu[0];
                }
                if delta >= angle[n - 1] {
                    return mu[n - 1];
                }
                let k = angle.partition_point(|&a| a <= delta) - 1;
                let t = (delta - angle[k]) / (angle[k + 1] - angle[k]);
                mu[k] + t * (mu[k + 1] - mu[k])
            }
        }
    }

    /// \[-\] the coefficient where the contact normal is `n` (y, z in the side frame, from
    /// rail to wheel): at its contact angle ([`crate::patch::contact_angle_of`]).
    #[inline]
    pub fn at_normal(&self, n: [f64; 2]) -> f64 {
        match self {
            Friction::Constant(mu) => *mu,
            _ => self.at(crate::patch::contact_angle_of(n)),
        }
    }

    /// \[-\] the largest coefficient anywhere.
    pub fn max(&self) -> f64 {
        match self {
            Friction::Constant(mu) => *mu,
            Friction::ByContactAngle { mu, .. } => mu.iter().copied().fold(0.0, f64::max),
        }
    }

    /// Whether the coefficient is the same everywhere.
    pub fn is_constant(&self) -> bool {
        matches!(self, Friction::Constant(_))
    }

    /// Check the values: every coefficient finite and in [`MU_RANGE`]; a table with at least
    /// two points, as many coefficients as angles, angles finite, strictly increasing and
    /// within ±90°.
    pub fn check(&self) -> Result<(), ContactError> {
        let (lo, hi) = MU_RANGE;
        let bad_mu = |v: f64| ContactError::BadOption {
            key: "mu",
            value: railsim_profile::short_number(v),
            expected: format!("a friction coefficient from {lo} to {hi}"),
        };
        let ok = |v: f64| v.is_finite() && (lo..=hi).contains(&v);
        match self {
            Friction::Constant(mu) => {
                if !ok(*mu) {
                    return Err(bad_mu(*mu));
                }
            }
            Friction::ByContactAngle { angle, mu } => {
                if angle.len() < 2 || angle.len() != mu.len() {
                    return Err(ContactError::BadOption {
                        key: "friction",
                        value: format!("{} angles and {} coefficients", angle.len(), mu.len()),
                        expected: "as many coefficients as contact angles, at least two".into(),
                    });
                }
                if let Some(&v) = mu.iter().find(|&&v| !ok(v)) {
                    return Err(bad_mu(v));
                }
                let half_pi = std::f64::consts::FRAC_PI_2;
                let in_range = |a: f64| a.is_finite() && a.abs() <= half_pi;
                if let Some(&a) = angle.iter().find(|&&a| !in_range(a)) {
                    return Err(ContactError::BadOption {
                        key: "contact_angle",
                        value: format!("{} rad", railsim_profile::short_number(a)),
                        expected: "a contact angle within ±90°".into(),
                    });
                }
                if let Some(w) = angle.windows(2).find(|w| w[1] <= w[0]) {
                    return Err(ContactError::BadOption {
                        key: "contact_angle",
                        value: format!(
                            "{} rad after {} rad",
                            railsim_profile::short_number(w[1]),
                            railsim_profile::short_number(w[0])
                        ),
                        expected: "strictly increasing contact angles".into(),
                    });
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_linear_between_its_points_and_constant_beyond() {
        let d = |deg: f64| deg.to_radians();
        let f = Friction::ByContactAngle {
            angle: vec![d(10.0), d(20.0), d(60.0)],
            mu: vec![0.3, 0.2, 0.1],
        };
        f.check().unwrap();
        for (deg, want) in [
            (-5.0, 0.3),
            (10.0, 0.3),
            (15.0, 0.25),
            (19.26, 0.2074),
            (20.0, 0.2),
            (40.0, 0.15),
            (70.0, 0.1),
        ] {
            assert!(
                (f.at(d(deg)) - want).abs() < 1e-12,
                "{deg}°: {}",
                f.at(d(deg))
            );
        }
        assert_eq!(f.at(f64::NAN), 0.3);
        assert_eq!(f.max(), 0.3);
        assert!(!f.is_constant());
        assert_eq!(Friction::Constant(0.25).at(1.0), 0.25);
    }

    #[test]
    fn bad_tables_are_refused() {
        let table = |angle: Vec<f64>, mu: Vec<f64>| Friction::ByContactAngle { angle, mu };
        for (f, key) in [
            (Friction::Constant(0.0), "mu"),
            (Friction::Constant(f64::NAN), "mu"),
            (table(vec![0.1], vec![0.3]), "friction"),
            (table(vec![0.1, 0.2], vec![0.3]), "friction"),
            (table(vec![0.1, 0.2], vec![0.3, 2.5]), "mu"),
            (Friction::Constant(1.5), "mu"),
            (Friction::Constant(0.005), "mu"),
            (table(vec![0.2, 0.1], vec![0.3, 0.2]), "contact_angle"),
            (table(vec![0.1, 0.1], vec![0.3, 0.2]), "contact_angle"),
            (table(vec![0.1, 2.0], vec![0.3, 0.2]), "contact_angle"),
            (table(vec![f64::NAN, 0.2], vec![0.3, 0.2]), "contact_angle"),
        ] {
            match f.check() {
                Err(ContactError::BadOption { key: k, .. }) => assert_eq!(k, key, "{f:?}"),
                other => panic!("{f:?}: {other:?}"),
            }
        }
    }
}
