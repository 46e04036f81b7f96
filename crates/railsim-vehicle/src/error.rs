//! The crate's error type, located problems, and the source map that turns byte spans into
//! `line:col`.

use std::fmt;
use std::ops::Range;

/// One located problem in a vehicle file: prints as `file:line:col: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// File the problem is in (the `source_name` given to the reader).
    pub file: String,
    /// \[-\] 1-based line.
    pub line: usize,
    /// \[-\] 1-based column (characters).
    pub col: usize,
    /// The offending key (`mass_kg`, `body2`, ...), as written in the file.
    pub key: String,
    /// What is wrong and what was expected; names the element and the key.
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {}",
            self.file, self.line, self.col, self.message
        )
    }
}

/// Every error of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VehicleError {
    /// The vehicle file has problems: syntax, unknown keys, wrong types, missing keys, values
    /// out of range, unknown or duplicate names. All of them, in file order.
    #[error("{}", list(.problems))]
    Invalid {
        /// The problems, sorted by line and column.
        problems: Vec<Problem>,
    },
    /// A file could not be read.
    #[error("{file}: {message}")]
    Io {
        /// The file that could not be read.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The static equilibrium could not be computed (a body is not supported).
    #[error("static equilibrium of vehicle '{vehicle}': {message}")]
    Statics {
        /// Name of the vehicle.
        vehicle: String,
        /// What is wrong: names the body and the degree of freedom left free.
        message: String,
    },
}

fn list(problems: &[Problem]) -> String {
    problems
        .iter()
        .map(|p| p.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

impl VehicleError {
    /// The located problems (empty for [`VehicleError::Io`] and [`VehicleError::Statics`]).
    pub fn problems(&self) -> &[Problem] {
        match self {
            VehicleError::Invalid { problems } => problems,
            _ => &[],
        }
    }
}

pub use railsim_spec::SourceMap;

/// Collects the problems of one file.
#[derive(Debug)]
pub(crate) struct Sink<'a> {
    pub file: &'a str,
    pub map: &'a SourceMap,
    pub problems: Vec<Problem>,
}

impl<'a> Sink<'a> {
    pub fn new(file: &'a str, map: &'a SourceMap) -> Self {
        Sink {
            file,
            map,
            problems: Vec::new(),
        }
    }

    /// Record a problem at the start of `span` (1:1 when there is no span).
    pub fn at(&mut self, span: Option<&Range<usize>>, key: &str, message: String) {
        let (line, col) = span.map_or((1, 1), |s| self.map.line_col(s.start));
        self.problems.push(Problem {
            file: self.file.to_owned(),
            line,
            col,
            key: key.to_owned(),
            message,
        });
    }
}

pub(crate) use railsim_spec::did_you_mean;
