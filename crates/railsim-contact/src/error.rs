//! The contact crate's error type.

use thiserror::Error;

/// `v` with `decimals` decimals when moderate, with an exponent when huge (a message about an
/// absurd input stays short).
fn fixed(v: f64, decimals: usize) -> String {
    if v.abs() < 1e9 {
        format!("{v:.decimals$}")
    } else {
        railsim_profile::short_number(v)
    }
}

/// Everything that can go wrong in a contact evaluation. Every variant names what was found and
/// what was expected.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ContactError {
    /// An input (pose, velocity, load, option) is NaN or infinite.
    #[error("{what} must be finite, found {value}")]
    NonFinite {
        /// Name of the quantity.
        what: &'static str,
        /// Value found.
        value: f64,
    },
    /// An input is outside its physically meaningful range.
    #[error("{what} = {} is out of range: expected {expected}", railsim_profile::short_number(*.value))]
    OutOfRange {
        /// Name of the quantity.
        what: &'static str,
        /// Value found.
        value: f64,
        /// What was expected, in words.
        expected: &'static str,
    },
    /// The wheelset is yawed beyond the angle up to which the wheel's contact locus is a
    /// regular curve (`railsim_contact::pair::LocusLimits`).
    #[error(
        "wheelset yaw [rad] = {yaw} is out of range for this wheel profile: expected |yaw| <= {limit:.4} rad (beyond it the yawed wheel's contact locus folds near the flange root, docs/models/contact.md §2)"
    )]
    YawBeyondLocus {
        /// \[rad\] the yaw found
        yaw: f64,
        /// \[rad\] the largest accepted |yaw| for the pair's wheel profile
        limit: f64,
    },
    /// The wheel penetrates the rail by more than the plausibility limit.
    #[error(
        "absurd penetration on the {side} wheel: {} mm of interpenetration, expected at most {limit_mm:.1} mm",
        fixed(*.found_mm, 3)
    )]
    AbsurdPenetration {
        /// Which wheel.
        side: &'static str,
        /// \[mm\] interpenetration found.
        found_mm: f64,
        /// \[mm\] the limit.
        limit_mm: f64,
    },
    /// The prescribed vertical load could not be reached.
    #[error("could not reach the vertical load {} N on the {side} wheel: {reason}", fixed(*.target_n, 1))]
    LoadNotReached {
        /// Which wheel.
        side: &'static str,
        /// \[N\] the target.
        target_n: f64,
        /// Why.
        reason: String,
    },
    /// The travelling along the profiles found no overlap of wheel and rail.
    #[error(
        "the {side} wheel and rail profiles do not face each other at y = {y_mm:.2} mm: across \
         the track the wheel's profile (flange tip to field side) spans {:.1} to {:.1} mm and \
         the rail's {:.1} to {:.1} mm (from the track centre, outward); {}",
        wheel_mm[0], wheel_mm[1], rail_mm[0], rail_mm[1], no_overlap_hint(wheel_mm, rail_mm)
    )]
    NoOverlap {
        /// Which wheel.
        side: &'static str,
        /// \[mm\] the lateral wheelset displacement.
        y_mm: f64,
        /// \[mm\] the wheel profile's lateral span in the side frame (flange tip, field end).
        wheel_mm: [f64; 2],
        /// \[mm\] the rail profile's lateral span in the side frame.
        rail_mm: [f64; 2],
    },
    /// An option has an unusable value.
    #[error("option {key} = {value}: expected {expected}")]
    BadOption {
        /// The option's name.
        key: &'static str,
        /// Its value as text.
        value: String,
        /// What was expected.
        expected: String,
    },
    /// A profile could not be used.
    #[error(transparent)]
    Profile(#[from] railsim_profile::ProfileError),
    /// An elastic kernel failed.
    #[error(transparent)]
    Elastic(#[from] railsim_elastic::ElasticError),
}

/// Check that a value is finite, naming it in the error.
pub(crate) fn finite(what: &'static str, value: f64) -> Result<f64, ContactError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ContactError::NonFinite { what, value })
    }
}

/// What to check when the travelling found no facing pairs: the placement when the lateral spans
/// miss each other, the profiles themselves when they overlap (a point far off the outline, a
/// profile that folds back).
fn no_overlap_hint(wheel_mm: &[f64; 2], rail_mm: &[f64; 2]) -> &'static str {
    let (w0, w1) = (wheel_mm[0].min(wheel_mm[1]), wheel_mm[0].max(wheel_mm[1]));
    if w1 < rail_mm[0] || w0 > rail_mm[1] {
        "check the gauge, the flange-back distance and position, and the profiles' lateral origins"
    } else {
        "the spans overlap, so check the profiles' points for one far off the outline (a spike) \
         or a stretch that folds back, then the gauge and the flange-back distance and position"
    }
}
