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

/// Line starts of a text, to turn byte offsets into 1-based `line:col`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SourceMap {
    text: String,
    line_starts: Vec<usize>,
}

impl SourceMap {
    /// Index `text`.
    pub fn new(text: &str) -> Self {
        let mut line_starts = vec![0];
        line_starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        SourceMap {
            text: text.to_owned(),
            line_starts,
        }
    }

    /// 1-based `(line, col)` of byte `offset` (col counts characters). An empty map gives (1, 1).
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        if self.line_starts.is_empty() {
            return (1, 1);
        }
        let offset = offset.min(self.text.len());
        let line = match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i.saturating_sub(1),
        };
        let start = self.line_starts[line];
        let col = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count())
            + 1;
        (line + 1, col)
    }
}

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

/// Levenshtein distance between two strings (characters).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// `" (did you mean 'x'?)"` for the closest candidate within a small edit distance, else `""`.
pub(crate) fn did_you_mean<'c>(
    word: &str,
    candidates: impl IntoIterator<Item = &'c str>,
) -> String {
    let limit = (word.chars().count() / 3).max(2);
    let best = candidates
        .into_iter()
        .map(|c| (edit_distance(&word.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d);
    match best {
        Some((_, c)) => format!(" (did you mean '{c}'?)"),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_and_suggestion() {
        assert_eq!(edit_distance("bogy", "bogie"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(
            did_you_mean("bogy", ["carbody", "bogie", "ws1"]),
            " (did you mean 'bogie'?)"
        );
        assert_eq!(did_you_mean("zzzzzz", ["carbody", "bogie"]), "");
    }

    #[test]
    fn line_col_counts_characters() {
        let m = SourceMap::new("a = 1\nbé = 2\n");
        assert_eq!(m.line_col(0), (1, 1));
        assert_eq!(m.line_col(6), (2, 1));
        assert_eq!(m.line_col(9), (2, 3));
    }
}
