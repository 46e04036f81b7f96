//! Rail-vehicle description for railsim: rigid bodies, wheelsets and force elements.
//!
//! Place in the data flow: a vehicle file (TOML, `docs/formats/vehicle.md`) is read into a
//! [`VehicleSpec`] (one to one with the file, file units, spans kept), then
//! [`VehicleModel::compile`] resolves names to typed ids ([`BodyId`], [`WheelsetId`],
//! [`ForceElementId`]), converts to SI and checks ranges and references, reporting every
//! problem as `file:line:col: message`. The compiled [`VehicleModel`] is immutable; the
//! simulation builds its state from [`VehicleModel::dofs`] and
//! [`VehicleModel::internal_states`]. [`VehicleModel::static_equilibrium`] gives the static
//! wheel loads and suspension forces on level track. The crate knows nothing of contact or
//! track geometry; the models are described in `docs/models/vehicle.md`.
//!
//! Conventions (`docs/conventions.md`): SI inside; the vehicle frame has x forward, y left,
//! z up, origin at track level at the vehicle centre; force-element deflections are body 2
//! relative to body 1, forces are on body 2.
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod error;
pub mod linalg;
pub mod model;
pub mod spec;
pub mod statics;
pub mod suspension;

pub use error::{Problem, SourceMap, VehicleError};
pub use model::{
    Axis, BOGIE_FRAME_MIN_OFFSET, Body, BodyId, Bogie, Dof, DofKind, Endpoint, ForceElement,
    ForceElementId, ForceLaw, ForceTable, InternalState, InternalStateKind, Member, NormalLoad,
    NormalRule, Sign, VehicleModel, WheelDefect, WheelProfile, Wheelset, WheelsetId,
    radius_deviation, rim_support, series_force, series_state_rate,
};
pub use spec::{
    BodySpec, ForceSpec, NumberOrTriple, OutOfRoundnessSpec, VehicleSpec, WheelProfileSpec,
    WheelsetSpec,
};
pub use statics::StaticEquilibrium;
pub use suspension::{DamperTable, damper_series_law, friction_law};
