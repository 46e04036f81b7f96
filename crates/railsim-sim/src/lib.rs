//! Scenes for railsim: what to simulate, read from a file and checked.
//!
//! Place in the data flow: a scene file (TOML, `docs/formats/scene.md`) is read into a
//! [`SceneSpec`] (one to one with the file, file units, spans kept), then [`Scene::compile`]
//! loads and compiles the vehicle (`railsim-vehicle`) and the track (`railsim-track`) it names,
//! converts everything to SI, and checks the values and their combinations: speed, run length,
//! contact model ([`railsim_contact::ContactModelKind`]), integrator ([`railsim_ode::Method`]),
//! logging, the initial disturbance, frozen degrees of freedom, that the run stays on the track
//! and that the track's curves suit the vehicle's rigid wheelbase ([`required_curve_radius`]).
//! Every problem is reported at once as `file:line:col: message`, those of the vehicle and
//! track files with their own file, line and column.
//!
//! The compiled [`Scene`] is immutable; the simulation (`step`, not written yet) will build its
//! model, state and workspace from it.
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod error;
pub mod scene;
pub mod spec;

pub use error::{Problem, SceneError, SourceMap};
pub use scene::{
    InitialDisturbance, LogOptions, RigidWheelbase, RunLength, Scene, SpeedProfile, Topic,
    longest_rigid_wheelbase, required_curve_radius,
};
pub use spec::{ContactSpec, InitialSpec, IntegratorSpec, LogSpec, SceneSpec, SpeedProfileSpec};
