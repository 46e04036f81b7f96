//! Track geometry for railsim: from a track file to the track frame at any position s.
//!
//! Place in the data flow: a track file (TOML, `docs/formats/track.md`) is read into a
//! [`TrackSpec`] (one to one with the file, file units, spans kept), then
//! [`TrackModel::compile`] checks it, converts it to SI, chains the segments and generates or
//! reads the irregularities, reporting every problem as `file:line:col: message`. The
//! simulation then calls [`TrackModel::frame_at`] and [`TrackModel::irregularity_at`] at
//! every step: both are pure, allocation-free lookups (O(log n_segments)). The crate knows
//! nothing of vehicles or contact; the theory is in `docs/models/track.md`.
//!
//! Conventions (`docs/conventions.md`): SI inside; s is the distance along the track in plan;
//! the ground frame `G` has its origin at s = 0, x along the initial heading, y left, z up;
//! curvature is positive to the left; roll is right-handed about the track x-axis.
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod alignment;
pub mod error;
pub mod irregularity;
pub mod math;
pub mod model;
pub mod spec;

pub use alignment::{Segment, SegmentId, SegmentKind, ShapeValues, TrackFrame, TransitionShape};
pub use error::{SourceMap, TrackError, TrackErrors};
pub use irregularity::{Channel, Irregularity, IrregularitySeries, Spectrum};
pub use model::{
    CompileOptions, HARD_MIN_RADIUS_M, RailBlend, RailProfile, RailSection, RailSupport, TrackModel,
};
pub use spec::{
    IrregularitySpec, RailProfileSpec, RailSectionSpec, RailSupportSpec, SegmentSpec, TrackSpec,
};
