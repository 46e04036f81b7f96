//! The crate's single error type.

use std::path::PathBuf;

/// Everything that can go wrong while writing, reading or exporting a log.
///
/// Every variant names the file it concerns.
#[derive(Debug, thiserror::Error)]
pub enum LogError {
    /// An operating-system I/O error on the log file or an export file.
    #[error("{}: {action}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What was being done, e.g. "creating the log".
        action: &'static str,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The MCAP library reported an error while writing.
    #[error("{}: writing MCAP: {source}", path.display())]
    Write {
        /// The log file.
        path: PathBuf,
        /// The underlying error.
        source: mcap::McapError,
    },
    /// The file is not a well-formed MCAP log.
    #[error("{}: {what}: expected {expected}", path.display())]
    Corrupt {
        /// The log file.
        path: PathBuf,
        /// What was found, with its byte offset where known.
        what: String,
        /// What was expected instead.
        expected: String,
    },
    /// A message's JSON does not match the requested type.
    #[error(
        "{}: message on '{topic}' at t = {t_ns} ns does not decode as {schema}: {source}",
        path.display()
    )]
    Decode {
        /// The log file.
        path: PathBuf,
        /// The message's topic.
        topic: String,
        /// \[ns\] the message's log time
        t_ns: u64,
        /// The schema name of the requested type.
        schema: &'static str,
        /// The underlying error.
        source: serde_json::Error,
    },
    /// A topic was asked for that the log does not contain, or with the wrong type.
    #[error("{}: {message}", path.display())]
    Topic {
        /// The log file.
        path: PathBuf,
        /// What is wrong, naming the topic.
        message: String,
    },
    /// A message was logged at an earlier time than the previous one on the same log.
    #[error(
        "{}: message on '{topic}' at t = {t_ns} ns is earlier than the previous message at {previous_ns} ns",
        path.display()
    )]
    TimeWentBackwards {
        /// The log file.
        path: PathBuf,
        /// The message's topic.
        topic: String,
        /// \[ns\] the rejected time
        t_ns: u64,
        /// \[ns\] the time of the previous message
        previous_ns: u64,
    },
    /// `step * dt_ns` does not fit in 64 bits.
    #[error("step {step} x dt {dt_ns} ns overflows the 64-bit nanosecond clock")]
    TimeOverflow {
        /// The step counter.
        step: u64,
        /// \[ns\] the step length
        dt_ns: u64,
    },
    /// Messages to export or summarise do not have the same flattened fields.
    #[error("{}: {message}", path.display())]
    Export {
        /// The log file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Shorthand for results of this crate.
pub type Result<T, E = LogError> = std::result::Result<T, E>;
