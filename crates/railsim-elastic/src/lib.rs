//! Elastic contact mechanics kernels for railsim.
//!
//! Place in the data flow: the geometry stage in `railsim-contact` locates contact patches and
//! produces, per patch, either relative curvatures (A, B) or a grid of undeformed gaps, plus
//! the creepages. This crate turns those into normal pressures and tangential tractions:
//!
//! - [`hertz`]: Hertz ellipses from curvatures (Carlson's elliptic integrals), with a fast
//!   tabulated variant for the time-stepping loop;
//! - [`kalker`]: Kalker's linear-theory creep coefficients C11, C22, C23, C33 and the linear
//!   creep forces;
//! - [`fastsim`]: Kalker's simplified theory (FASTSIM), per strip and on a Hertz ellipse;
//! - [`polach`](mod@polach): Polach's closed-form creep-force model;
//! - [`halfspace`]: a Boussinesq–Love boundary-element solver for the normal problem, used as
//!   the reference against which the fast models are measured;
//! - [`steady`]: Kalker's exact steady-rolling tangential problem on the same kind of grid, the
//!   reference for FASTSIM and FaStrip.
//!
//! It knows nothing of wheels and rails: everything is expressed in a contact frame with x the
//! rolling direction, y lateral and z the common normal. Units are SI throughout (m, N, Pa,
//! rad; spin creepage in 1/m). Forces follow Kalker's convention: they act on the upper body
//! and oppose the creepage (see [`Creepages`]).
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod error;
pub mod fastrip;
pub mod fastsim;
pub mod halfspace;
pub mod hertz;
pub mod kalker;
pub mod material;
pub mod polach;
pub mod steady;

pub use error::ElasticError;
pub use fastrip::{FastripPatch, StripMethod, fastrip_strip};
pub use fastsim::{
    Flexibilities, FlexibilityBlend, StripTraction, TractionBound, blended_flexibilities,
    fastsim_ellipse, fastsim_strip, flexibilities,
};
pub use halfspace::{Grid, HalfspaceSolver, NormalSolution, love_influence};
pub use hertz::{
    HertzCoeffs, HertzSolution, carlson_rd, carlson_rf, hertz_coeffs, hertz_coeffs_fast,
    hertz_from_approach, hertz_from_load, stripes_epsilon, try_carlson_rd, try_carlson_rf,
};
pub use kalker::{
    Creepages, KalkerCoeffs, KalkerTable, TangentialForces, kalker_coeffs, linear_kalker,
};
pub use material::Material;
pub use polach::{PolachParams, polach, spin_corrected_creepage};
pub use steady::{SteadyRollingSolver, SteadySolution, cerruti_influence};
