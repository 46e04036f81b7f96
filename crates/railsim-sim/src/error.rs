//! The crate's error type: located problems, from the scene file and from the vehicle and track
//! files it refers to, all reported together.

use std::fmt;
use std::ops::Range;

/// One located problem: prints as `file:line:col: message`.
///
/// `file` is the scene file for problems of the scene itself, and the vehicle or track file
/// (with its own line and column) for problems found while compiling those.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// File the problem is in.
    pub file: String,
    /// \[-\] 1-based line.
    pub line: usize,
    /// \[-\] 1-based column (characters).
    pub col: usize,
    /// The offending key (`speed_kmh`, `contact.model`, ...), as written in the file; empty for
    /// a syntax error.
    pub key: String,
    /// What is wrong and what was expected; names the key.
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
pub enum SceneError {
    /// The scene, or a file it refers to, has problems. All of them: the scene file's first
    /// (in file order), then the vehicle file's, then the track file's.
    #[error("{}", list(.problems))]
    Invalid {
        /// The problems.
        problems: Vec<Problem>,
    },
    /// The scene file could not be read.
    #[error("{file}: {message}")]
    Io {
        /// The file that could not be read.
        file: String,
        /// The operating system's message.
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

impl SceneError {
    /// The located problems (empty for [`SceneError::Io`]).
    pub fn problems(&self) -> &[Problem] {
        match self {
            SceneError::Invalid { problems } => problems,
            SceneError::Io { .. } => &[],
        }
    }
}

pub use railsim_spec::SourceMap;

/// Collects the problems of the scene file.
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

    /// Record a problem at the start of `span`.
    pub fn at(&mut self, span: &Range<usize>, key: &str, message: String) {
        let (line, col) = self.map.line_col(span.start);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_for_scene_names() {
        assert_eq!(
            did_you_mean("dopri", ["rk4", "dopri5", "radau5"]),
            " (did you mean 'dopri5'?)"
        );
        assert_eq!(did_you_mean("zzzzzz", ["rk4", "dopri5"]), "");
    }
}
