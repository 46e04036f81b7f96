//! Shared machinery of railsim's TOML file formats (tracks, vehicles, scenes): every format
//! crate parses its own serde spec, and reports problems as `file:line:col: message` naming the
//! key, with "did you mean" suggestions for misspelt names. This crate holds the pieces those
//! messages need, so that they are written once.
#![deny(rustdoc::broken_intra_doc_links)]

use std::fmt;
use std::ops::Range;

use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

/// One located problem in a file: prints as `file:line:col: message`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// File the problem is in.
    pub file: String,
    /// \[-\] 1-based line.
    pub line: usize,
    /// \[-\] 1-based column (characters).
    pub col: usize,
    /// The offending key, as written in the file; empty for a syntax error.
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

/// Collects the problems of one file.
#[derive(Debug)]
pub struct Sink<'a> {
    /// The file's name, as it appears in messages.
    pub file: &'a str,
    /// The file's source map.
    pub map: &'a SourceMap,
    /// The problems so far.
    pub problems: Vec<Problem>,
}

impl<'a> Sink<'a> {
    /// An empty sink for `file`.
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

/// Problems one per line, in order: the text of an error that carries several.
pub fn list_problems(problems: &[Problem]) -> String {
    problems
        .iter()
        .map(|p| p.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Deserialize one table: report every unknown key (with a suggestion, and the list of
/// `known` keys), then deserialize, dropping and reporting each wrongly typed value until the
/// rest reads, so that one run reports every problem of the table. `prefix` starts every message
/// (`"[contact] "`, `"body 'x': "`, or empty); `rewrite` turns serde's message into the one shown.
/// Dropped keys are pushed to `dropped` with the table's start offset.
pub fn read_table<T: DeserializeOwned>(
    mut table: DeTable<'_>,
    span: Range<usize>,
    known: &[&str],
    prefix: &str,
    sink: &mut Sink<'_>,
    dropped: &mut Vec<(usize, String)>,
    rewrite: fn(&str) -> String,
) -> Option<T> {
    let unknown: Vec<(String, Range<usize>)> = table
        .iter()
        .filter(|(k, _)| !known.contains(&k.get_ref().as_ref()))
        .map(|(k, _)| (k.get_ref().to_string(), k.span()))
        .collect();
    for (k, key_span) in unknown {
        sink.at(
            Some(&key_span),
            &k,
            format!(
                "{prefix}unknown key '{k}'{}; expected one of: {}",
                did_you_mean(&k, known.iter().copied()),
                known.join(", ")
            ),
        );
        table.remove(k.as_str());
    }
    loop {
        let copy = DeValue::Table(table.clone());
        let value = Spanned::new(span.clone(), DeValue::Table(table.clone()));
        match T::deserialize(ValueDeserializer::from(value)) {
            Ok(v) => return Some(v),
            Err(e) => {
                let key = e.span().and_then(|sp| key_at(&copy, sp.start));
                let message = rewrite(e.message().trim());
                let top = key
                    .as_deref()
                    .map(|k| k.split('.').next().unwrap_or(k).to_owned());
                let at = e.span().unwrap_or_else(|| span.clone());
                let k = key.unwrap_or_default();
                let text = if k.is_empty() {
                    format!("{prefix}{message}")
                } else {
                    format!("{prefix}{k}: {message}")
                };
                sink.at(Some(&at), &k, text);
                match top {
                    Some(top) if table.remove(top.as_str()).is_some() => {
                        dropped.push((span.start, top));
                    }
                    _ => return None,
                }
            }
        }
    }
}

/// serde's message as it is.
pub fn as_is(message: &str) -> String {
    message.to_owned()
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

    /// 1-based `(line, col)` of the start of `span`.
    pub fn at(&self, span: &std::ops::Range<usize>) -> (usize, usize) {
        self.line_col(span.start)
    }
}

/// The dotted key whose key or value span contains byte `offset` in a parsed TOML value
/// (deepest match), to name the key of a serde error that only has a span.
pub fn key_at(value: &DeValue<'_>, offset: usize) -> Option<String> {
    key_in_value(value, offset, "")
}

fn key_in_value(value: &DeValue<'_>, offset: usize, prefix: &str) -> Option<String> {
    let DeValue::Table(table) = value else {
        return None;
    };
    for (k, v) in table.iter() {
        let name = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        if v.span().contains(&offset) || k.span().contains(&offset) {
            return key_in_value(v.get_ref(), offset, &name).or(Some(name));
        }
    }
    None
}

/// A number for a message: as Rust prints it when moderate, with an exponent when huge or tiny
/// (`1e30`, not thirty-one digits).
pub fn short_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-3..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Levenshtein distance between two strings (characters).
pub fn edit_distance(a: &str, b: &str) -> usize {
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

/// `" (did you mean 'x'?)"` for the best candidate, else `""`: a candidate that starts with the
/// word (a truncation such as "rate" for "rate_hz", words of 3 characters or more), otherwise
/// the closest one within a small edit distance (a third of the word's length, at least 2);
/// case-insensitive.
pub fn did_you_mean<'c>(word: &str, candidates: impl IntoIterator<Item = &'c str>) -> String {
    let limit = (word.chars().count() / 3).max(2);
    let word = word.to_lowercase();
    let candidates: Vec<&str> = candidates.into_iter().collect();
    if word.chars().count() >= 3
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
        assert_eq!(edit_distance("bogy", "bogie"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(
            did_you_mean("bogy", ["carbody", "bogie", "ws1"]),
            " (did you mean 'bogie'?)"
        );
        assert_eq!(did_you_mean("zzzzzz", ["carbody", "bogie"]), "");
        assert_eq!(
            did_you_mean("rate", ["path", "rate_hz"]),
            " (did you mean 'rate_hz'?)"
        );
    }

    #[test]
    fn line_col_counts_characters() {
        let m = SourceMap::new("a = 1\nbé = 2\n");
        assert_eq!(m.line_col(0), (1, 1));
        assert_eq!(m.line_col(6), (2, 1));
        assert_eq!(m.line_col(9), (2, 3));
        assert_eq!(SourceMap::default().line_col(5), (1, 1));
    }

    #[test]
    fn key_at_finds_the_deepest_key() {
        // (Spans of inline tables cover their contents; the formats look keys up inside one
        // table or array item at a time.)
        let text = "a = 1\nb = { c = { d = \"x\" } }\n";
        let root = toml::de::DeTable::parse(text).unwrap();
        let v = DeValue::Table(root.into_inner());
        let off = text.find("\"x\"").unwrap();
        assert_eq!(key_at(&v, off).as_deref(), Some("b.c.d"));
        assert_eq!(key_at(&v, 0).as_deref(), Some("a"));
    }
}

/// A Coulomb friction coefficient as the scene (`[contact] friction`) and the track
/// (`[[rail_section]] friction`) give it: one number, coefficients at contact angles (railsim's
/// contact angle, positive toward the flange), linear in between and constant beyond the ends
/// (`railsim_contact::Friction`), or either of those per rail (`{ left = .., right = .. }`, e.g.
/// only the high rail's gauge face lubricated).
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(untagged)]
pub enum FrictionSpec {
    /// \[-\] the same everywhere.
    Constant(f64),
    /// Varying with the contact angle.
    ByContactAngle(FrictionTable),
    /// One of the other two forms per rail.
    PerRail(FrictionPerRail),
}

/// Friction coefficients at contact angles.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionTable {
    /// \[deg\] contact angles, strictly increasing.
    pub contact_angle_deg: Vec<f64>,
    /// \[-\] the coefficient at each angle.
    pub coefficient: Vec<f64>,
}

/// Friction per rail.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionPerRail {
    /// The left rail's: a number or a table by contact angle.
    pub left: Box<FrictionSpec>,
    /// The right rail's.
    pub right: Box<FrictionSpec>,
}

/// \[-\] the friction coefficients the files accept.
pub const FRICTION_RANGE: (f64, f64) = (0.01, 1.0);

/// What a `friction` value of neither form is told (serde's message for the untagged enum names
/// no form): see [`friction_message`].
pub const FRICTION_FORMS: &str = "friction must be a number, a table { contact_angle_deg = [..], \
     coefficient = [..] } or a table { left = .., right = .. } of those";

/// A deserialisation message with serde's words for a `friction` of neither form replaced by
/// [`FRICTION_FORMS`]; other messages as they are (a `rewrite` for [`read_table`]).
pub fn friction_message(message: &str) -> String {
    if message.contains("untagged enum FrictionSpec") {
        FRICTION_FORMS.to_owned()
    } else {
        message.to_owned()
    }
}

impl FrictionSpec {
    /// The friction of rail `k` (0 left, 1 right): a per-rail value's part, otherwise itself.
    pub fn rail(&self, k: usize) -> &FrictionSpec {
        match self {
            FrictionSpec::PerRail(p) => {
                if k == 0 {
                    &p.left
                } else {
                    &p.right
                }
            }
            other => other,
        }
    }

    /// What is wrong with the value, as a message about `key` (e.g. `friction`); `None` when
    /// every coefficient lies in [`FRICTION_RANGE`], a table has at least two points, as many
    /// coefficients as angles, and angles strictly increasing within ±90°, and a per-rail value
    /// holds no other per-rail value.
    pub fn problem(&self, key: &str) -> Option<String> {
        let (lo, hi) = FRICTION_RANGE;
        let ok = |x: f64| x.is_finite() && (lo..=hi).contains(&x);
        match self {
            FrictionSpec::Constant(x) => (!ok(*x))
                .then(|| format!("{key} must lie in [{lo}, {hi}], found {}", short_number(*x))),
            FrictionSpec::ByContactAngle(FrictionTable {
                contact_angle_deg: a,
                coefficient: c,
            }) => {
                if a.len() < 2 || a.len() != c.len() {
                    return Some(format!(
                        "{key}: {} contact angles and {} coefficients; expected as many \
                         coefficients as angles, at least two",
                        a.len(),
                        c.len()
                    ));
                }
                if let Some(x) = c.iter().find(|x| !ok(**x)) {
                    return Some(format!(
                        "{key}.coefficient must lie in [{lo}, {hi}], found {}",
                        short_number(*x)
                    ));
                }
                if let Some(x) = a.iter().find(|x| !(x.is_finite() && x.abs() <= 90.0)) {
                    return Some(format!(
                        "{key}.contact_angle_deg must lie in [-90, 90] deg, found {x}"
                    ));
                }
                a.windows(2).find(|w| w[1] <= w[0]).map(|w| {
                    format!(
                        "{key}.contact_angle_deg must increase strictly, found {} after {}",
                        w[1], w[0]
                    )
                })
            }
            FrictionSpec::PerRail(p) => [("left", &p.left), ("right", &p.right)]
                .into_iter()
                .find_map(|(side, f)| {
                    let key = format!("{key}.{side}");
                    match **f {
                        FrictionSpec::PerRail(_) => Some(format!(
                            "{key} must be a number or a table by contact angle, found another \
                             {{ left, right }} table"
                        )),
                        _ => f.problem(&key),
                    }
                }),
        }
    }
}
