//! Online wheel/rail contact for railsim: from the wheel and rail profiles and the wheelset's
//! pose and velocities to every contact patch and its forces, at every integration step, with no
//! pre-computed contact tables.
//!
//! Place in the data flow: `railsim-profile` gives the profiles as arc-length curves;
//! this crate places them ([`pair`]), finds every interpenetrated zone by the isosceles-pair
//! travelling of Jalili & Salehi (2011) ([`geometry`], warm-started by [`warm`]) or, for the
//! Hertz models, each zone's rigid contact pair by a single-point search ([`broad`] bounding
//! hierarchies, [`point`] Newton), turns each zone into a patch frame ([`patch`]) and solves it
//! with one of the models of the fidelity ladder ([`model`]), whose elastic kernels live in
//! `railsim-elastic`. The dynamics (a later crate) calls
//! [`WheelRailContact::evaluate`] once per wheel per right-hand-side evaluation with a reusable
//! [`ContactWorkspace`].
//!
//! Stages, in order: travel (pairs) → zones (patches), or for the Hertz models the point search
//! (one pair per zone) → rigid pair and frame → creepages →
//! normal problem → tangential problem → forces in patch, track and wheelset axes.
#![deny(rustdoc::broken_intra_doc_links)]

pub mod broad;
pub mod contact_format;
pub mod error;
pub mod friction;
pub mod geometry;
pub mod model;
pub mod pair;
pub mod patch;
pub mod point;
pub mod pose;
pub mod stripes;
pub mod warm;
pub mod wells;

pub use error::ContactError;
pub use friction::{FallingFriction, Friction};
pub use geometry::{IsoPair, TravelOptions, TravelStats};
pub use model::{
    ContactModelKind, ContactOptions, ContactWorkspace, HertzSearch, LOAD_RESIDUAL_NOTICE,
    PatchForces, PatchResult, PolachAdhesion, WheelRailContact, WheelSummary,
};
pub use pair::{PairSpec, WheelRailPair};
pub use pose::{Side, WheelsetPose, WheelsetVelocity};
pub use stripes::{StripesVariant, Tangential};
pub use warm::WarmStart;
