//! MCAP logs for railsim.
//!
//! Place in the data flow: the simulator (`railsim-sim`) calls a [`LogWriter`] once per logged
//! step; `railsim replay` and the tests read logs back with a [`LogReader`] and turn them into CSV
//! or summary statistics with the [`export`] helpers. This crate knows the message types
//! ([`BodyState`], [`PatchMessage`], [`WheelsetMessage`], Foxglove's [`FrameTransform`]) but
//! nothing of how they are computed; any other `serde` type can be logged through
//! [`LogMessage`].
//!
//! File layout (see `docs/formats/log.md`): MCAP with a header, then the scene as a Metadata
//! record named `scene` (and optionally the scene TOML as an attachment `scene.toml`), then zstd
//! chunks holding the schemas, channels and JSON messages, then the summary. Log time = publish
//! time = simulation time in integer nanoseconds.
//!
//! Crash behaviour: the writer never seeks. Chunks are written whole, and [`LogWriter::flush`]
//! (called every `flush_every` messages and on demand) closes the current chunk and flushes the
//! file, so a process killed at any moment leaves a file that [`LogReader`] reads up to its last
//! complete chunk.
//!
//! ```
//! use railsim_log::{BodyState, LogHeader, LogReader, LogWriter, Quaternion, WriterOptions};
//! # fn main() -> Result<(), railsim_log::LogError> {
//! let path = std::env::temp_dir().join(format!("railsim_log_doc_{}.mcap", std::process::id()));
//! let header = LogHeader::new().scene_entry("speed_m_s", "55");
//! let mut log = LogWriter::create(&path, &header, WriterOptions::default())?;
//! let body = log.channel::<BodyState>("/bodies/wheelset_1")?;
//! for step in 0..10u64 {
//!     let t_ns = railsim_log::step_time_ns(step, 1_000_000)?; // dt = 1 ms
//!     let state = BodyState {
//!         t_s: railsim_log::ns_to_s(t_ns),
//!         name: "wheelset_1".into(),
//!         position: [0.0, 1e-3, 0.0],
//!         orientation: Quaternion::IDENTITY,
//!         velocity: [55.0, 0.0, 0.0],
//!         angular_velocity: [0.0; 3],
//!     };
//!     log.write(&body, t_ns, &state)?;
//! }
//! let stats = log.finish()?;
//! assert_eq!(stats.messages, 10);
//!
//! let reader = LogReader::open(&path)?;
//! assert!(reader.is_complete());
//! assert_eq!(reader.scene().unwrap()["speed_m_s"], "55");
//! let states = reader.read_topic::<BodyState>("/bodies/wheelset_1", None)?;
//! assert_eq!(states.len(), 10);
//! # std::fs::remove_file(&path).ok();
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod error;
pub mod export;
pub mod messages;
mod reader;
mod time;
mod writer;

pub use error::{LogError, Result};
pub use messages::{
    BodyState, BogieFrameMessage, CarbodyMessage, Creepages, ElementMessage, FoxgloveTime,
    FrameTransform, LogMessage, PatchMessage, Quaternion, Side, Vector3, WheelsetMessage, topics,
    wear_number,
};
pub use reader::{ChannelInfo, LogMessageRef, LogReader, Query};
pub use time::{NS_PER_S, ns_to_s, s_to_ns, step_time_ns};
pub use writer::{
    Channel, FORMAT_METADATA, FORMAT_VERSION, LogHeader, LogStats, LogWriter, SCENE_ATTACHMENT,
    SCENE_METADATA, WriterOptions,
};
