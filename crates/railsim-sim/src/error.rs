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
        for (i, b) in text.bytes().enumerate() {
            if b == b'\n' {
                line_starts.push(i + 1);
            }
        }
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
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let col = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count());
        (line + 1, col + 1)
    }
}

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

/// Levenshtein distance between two strings (characters).
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let up = row[j + 1];
            row[j + 1] = (diag + usize::from(ca != *cb)).min(up + 1).min(row[j] + 1);
            diag = up;
        }
    }
    row[b.len()]
}

/// `" (did you mean 'x'?)"` for the closest candidate within a small edit distance, else `""`.
pub(crate) fn did_you_mean<'c>(
    word: &str,
    candidates: impl IntoIterator<Item = &'c str>,
) -> String {
    let limit = (word.chars().count() / 3).max(2);
    let word = word.to_lowercase();
    let candidates: Vec<&str> = candidates.into_iter().collect();
    // A word that is the start of a candidate ("rate" for "rate_hz") is a truncation.
    if word.len() >= 3
        && let Some(c) = candidates
            .iter()
            .find(|c| c.to_lowercase().starts_with(&word))
    {
        return format!(" (did you mean '{c}'?)");
    }
    let best = candidates
        .into_iter()
        .map(|c| (edit_distance(&word, &c.to_lowercase()), c))
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
        assert_eq!(edit_distance("stripse", "stripes"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(
            did_you_mean("dopri", ["rk4", "dopri5", "radau5"]),
            " (did you mean 'dopri5'?)"
        );
        assert_eq!(did_you_mean("zzzzzz", ["rk4", "dopri5"]), "");
    }

    #[test]
    fn line_col_counts_characters() {
        let m = SourceMap::new("a = 1\nbé = 2\n");
        assert_eq!(m.line_col(0), (1, 1));
        assert_eq!(m.line_col(6), (2, 1));
        assert_eq!(m.line_col(9), (2, 3));
    }
}
