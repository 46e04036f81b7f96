//! The crate's error type and the source map that turns byte spans into `line:col`.

use std::fmt;
use std::ops::Range;

/// One problem found while reading or compiling a track, with its location.
///
/// Every variant prints as `file:line:col: message` (or `file: message` when no position is
/// known), and the message names the key and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// TOML syntax error, or a serde error (unknown key, missing key, wrong type).
    #[error("{file}:{line}:{col}: {message}")]
    Parse {
        /// File the problem is in.
        file: String,
        /// \[-\] 1-based line.
        line: usize,
        /// \[-\] 1-based column (characters).
        col: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    /// A value that parsed but is out of range, inconsistent or refers to something missing.
    #[error("{file}:{line}:{col}: {message}")]
    Invalid {
        /// File the problem is in.
        file: String,
        /// \[-\] 1-based line.
        line: usize,
        /// \[-\] 1-based column (characters).
        col: usize,
        /// The offending key (`radius_m`, `segment`, ...).
        key: String,
        /// What is wrong and what was expected; contains `key`.
        message: String,
    },
    /// A file could not be read.
    #[error("{file}: {message}")]
    Io {
        /// The file that could not be read.
        file: String,
        /// The operating system's message.
        message: String,
    },
}

/// Every problem found in one track (never just the first).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct TrackErrors {
    /// The problems, in the order of the file.
    pub errors: Vec<TrackError>,
}

impl fmt::Display for TrackErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.errors.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{e}")?;
        }
        Ok(())
    }
}

impl From<TrackError> for TrackErrors {
    fn from(e: TrackError) -> Self {
        TrackErrors { errors: vec![e] }
    }
}

pub use railsim_spec::SourceMap;

/// Collects problems for one file.
#[derive(Debug)]
pub(crate) struct Sink<'a> {
    pub file: &'a str,
    pub map: &'a SourceMap,
    pub errors: Vec<TrackError>,
}

impl<'a> Sink<'a> {
    pub fn new(file: &'a str, map: &'a SourceMap) -> Self {
        Sink {
            file,
            map,
            errors: Vec::new(),
        }
    }

    /// Record an out-of-range or inconsistent value at `span`.
    pub fn invalid(&mut self, span: &Range<usize>, key: &str, message: String) {
        let (line, col) = self.map.at(span);
        self.errors.push(TrackError::Invalid {
            file: self.file.to_owned(),
            line,
            col,
            key: key.to_owned(),
            message,
        });
    }

    /// Record a parse problem at `span`.
    pub fn parse(&mut self, span: Option<Range<usize>>, message: String) {
        let (line, col) = span.map_or((1, 1), |s| self.map.at(&s));
        self.errors.push(TrackError::Parse {
            file: self.file.to_owned(),
            line,
            col,
            message,
        });
    }

    pub fn finish(self) -> Result<(), TrackErrors> {
        if self.errors.is_empty() {
            Ok(())
        } else {
            Err(TrackErrors {
                errors: self.errors,
            })
        }
    }
}
