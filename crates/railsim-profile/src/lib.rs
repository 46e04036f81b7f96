//! Wheel and rail cross-section profiles: file readers, analytic S1002/UIC60, smoothing
//! splines, arc-length curves, rail placement and equivalent conicity.
//!
//! # Place in the data flow
//! Profiles are read once when a model is compiled ([`read_simpack`], [`read_table_mm`] or
//! [`analytic`]), smoothed and resampled into an [`ArcCurve`] (arc length s, tangent,
//! curvature, O(1) evaluation) that the contact crate uses for its contact search; rails are
//! placed on the track with [`place_rail`]. [`conicity`] is a side product: rigid 2-D wheelset
//! geometry (rolling-radius difference, equivalent conicity). Everything here is pure geometry.
//!
//! # Conventions
//! * SI inside: metres, radians.
//! * A [`Profile`] is a 2-D cross-section in its own profile frame: **y lateral, positive toward
//!   the field side** (the outside of the track), **z positive up**, points strictly increasing
//!   in y.
//! * Wheel profile: y = S of EN 13715 (origin on the measuring circle, flange at negative y,
//!   flange back at y = -70 mm for S1002), z = -F(S) (the flange tip is at z = -28 mm); the
//!   wheel radius at y is r0 - z.
//! * Rail profile: y toward the field side, z up, origin as the file gives it (benchmark
//!   `.prr`: the highest point of the already-canted head) or, for the analytic UIC60, the crown
//!   top on the rail's symmetry axis (uncanted).
//! * SIMPACK files, after their processing steps, are in CONTACT's canonical form (y toward the
//!   field, z down, mm); they are converted with y = y_c/1000, z = -z_c/1000.
//! * Rotations are counter-clockwise positive in the (y, z) plane (y toward z). A rail inclined
//!   toward the track centre by 1:40 is rotated by +atan(1/40).
//! * Side frame ([`place_rail`]): y = lateral distance from the track centre line, positive
//!   toward this rail's field side, z up, z = 0 at the highest point of the placed rail.
//! * Curvature ([`CurvePoint::kappa`]) is dθ/ds with θ the tangent angle, counter-clockwise
//!   positive, s increasing with y.
//!
//! # Sources
//! EN 13715 / UIC 510-2 S1002 with the DLR coefficient set (H. Netter); a UIC60 head
//! reconstructed from the Manchester benchmark file; the SIMPACK profile format and its
//! processing order as implemented by Vollebregt's CONTACT; Reinsch (1967) smoothing splines
//! (as used for profiles by Jalili & Salehi 2011, §3.1); EN 15302-style equivalent conicity.
//! See `docs/models/profiles.md`.
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod analytic;
pub mod conicity;
mod curve;
mod error;
mod io;
mod profile;
mod rail;
mod spline;

pub use curve::{ArcCurve, CurvePoint, DEFAULT_DS};
pub use error::{ProfileError, short_number};
pub use io::{parse_simpack, parse_table_mm, read_simpack, read_table_mm};
pub use profile::{Profile, ProfileKind};
pub use rail::{RailPlacement, place_rail};
pub use spline::SmoothingSpline;

#[cfg(test)]
mod tests;
