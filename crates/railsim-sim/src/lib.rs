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
//! The compiled [`Scene`] is immutable; [`Simulation::new`] builds from it the simulation model
//! ([`SimModel`]: members, force elements, one online contact pair per wheel, the state layout),
//! the initial state (static equilibrium, wheelsets settled on the rails) and the workspace;
//! [`dynamics`] holds the right-hand side with its stages in order, and [`Simulation::run`]
//! steps the integrator, samples at the log rate, checks for derailment and instability, writes
//! the MCAP log and returns a [`RunSummary`].
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod assess;
pub mod curving;
pub mod dynamics;
pub mod error;
pub mod math;
pub mod modal;
pub mod model;
pub mod run;
pub mod scene;
pub mod signal;
pub mod spec;
pub mod stability;

pub use error::{Problem, SceneError, SimError, SourceMap};
pub use model::SimModel;
pub use run::{ElementEnergy, RunOptions, RunSummary, Sample, Simulation};
pub use scene::{
    InitialDisturbance, InitialState, LogOptions, RigidWheelbase, RunLength, Scene, SpeedProfile,
    Topic, longest_rigid_wheelbase, required_curve_radius,
};
pub use spec::{
    AssessmentSpec, ComfortPointSpec, ContactSpec, InitialSpec, IntegratorSpec, LogSpec, SceneSpec,
    SpeedProfileSpec,
};
