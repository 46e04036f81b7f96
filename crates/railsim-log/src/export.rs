//! Export for replay: CSV tables and per-field summary statistics.
//!
//! Messages are flattened into columns in the order their JSON writes the fields (struct order
//! for railsim types): nested objects join their keys with `.` (`creepages.xi`), arrays append the
//! index (`position.0`). Units come from the channel's JSON Schema: a field whose `description`
//! starts with a unit in brackets (`[m] ...`, as every railsim numeric field does) gets a column
//! header `position.0 [m]`. Foxglove's `FrameTransform` schema carries no units, so they are
//! filled in from its documented meaning (translation in m, rotation dimensionless).

use std::collections::HashMap;
use std::fmt;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde::de::{DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::error::{LogError, Result};
use crate::reader::{ChannelInfo, LogReader, Query};

/// One scalar of a flattened message.
#[derive(Debug, Clone, PartialEq)]
pub enum Scalar {
    /// A JSON number.
    Number(f64),
    /// A JSON string.
    Text(String),
    /// A JSON boolean.
    Bool(bool),
    /// JSON `null` (serde_json writes non-finite floats as `null`).
    Null,
}

impl fmt::Display for Scalar {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            // `Display` of f64 is the shortest text that parses back to the same value.
            Scalar::Number(x) => write!(f, "{x}"),
            Scalar::Text(s) if s.contains([',', '"', '\n', '\r']) => {
                write!(f, "\"{}\"", s.replace('"', "\"\""))
            }
            Scalar::Text(s) => f.write_str(s),
            Scalar::Bool(b) => write!(f, "{b}"),
            Scalar::Null => Ok(()),
        }
    }
}

struct Flatten<'a> {
    prefix: String,
    out: &'a mut Vec<(String, Scalar)>,
}

impl Flatten<'_> {
    fn child(&mut self, key: &dyn fmt::Display) -> Flatten<'_> {
        let prefix = if self.prefix.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.prefix)
        };
        Flatten {
            prefix,
            out: self.out,
        }
    }
    fn push(self, value: Scalar) {
        self.out.push((self.prefix, value));
    }
}

impl<'de> DeserializeSeed<'de> for Flatten<'_> {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Flatten<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<(), E> {
        self.push(Scalar::Bool(v));
        Ok(())
    }
    fn visit_i64<E>(self, v: i64) -> Result<(), E> {
        self.push(Scalar::Number(v as f64));
        Ok(())
    }
    fn visit_u64<E>(self, v: u64) -> Result<(), E> {
        self.push(Scalar::Number(v as f64));
        Ok(())
    }
    fn visit_f64<E>(self, v: f64) -> Result<(), E> {
        self.push(Scalar::Number(v));
        Ok(())
    }
    fn visit_str<E>(self, v: &str) -> Result<(), E> {
        self.push(Scalar::Text(v.to_owned()));
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        self.push(Scalar::Null);
        Ok(())
    }
    fn visit_none<E>(self) -> Result<(), E> {
        self.push(Scalar::Null);
        Ok(())
    }
    fn visit_seq<A: SeqAccess<'de>>(mut self, mut seq: A) -> Result<(), A::Error> {
        let mut i = 0usize;
        while seq.next_element_seed(self.child(&i))?.is_some() {
            i += 1;
        }
        Ok(())
    }
    fn visit_map<A: MapAccess<'de>>(mut self, mut map: A) -> Result<(), A::Error> {
        while let Some(key) = map.next_key::<String>()? {
            map.next_value_seed(self.child(&key))?;
        }
        Ok(())
    }
}

/// Flattens one JSON message into `(column path, scalar)` pairs in document order.
pub fn flatten_json(json: &[u8]) -> Result<Vec<(String, Scalar)>, serde_json::Error> {
    let mut out = Vec::new();
    let mut de = serde_json::Deserializer::from_slice(json);
    Flatten {
        prefix: String::new(),
        out: &mut out,
    }
    .deserialize(&mut de)?;
    de.end()?;
    Ok(out)
}

/// The path without array indices: `position.0` → `position`, the key of [`units_of`].
fn unit_key(path: &str) -> String {
    path.split('.')
        .filter(|part| part.parse::<usize>().is_err())
        .collect::<Vec<_>>()
        .join(".")
}

/// Units by field path (array indices removed) as found in the channel's JSON Schema.
pub fn units_of(channel: &ChannelInfo) -> HashMap<String, String> {
    let mut units = HashMap::new();
    if channel.schema_name == "foxglove.FrameTransform" {
        for (k, u) in [
            ("timestamp.sec", "s"),
            ("timestamp.nsec", "ns"),
            ("translation.x", "m"),
            ("translation.y", "m"),
            ("translation.z", "m"),
            ("rotation.x", "1"),
            ("rotation.y", "1"),
            ("rotation.z", "1"),
            ("rotation.w", "1"),
        ] {
            units.insert(k.to_owned(), u.to_owned());
        }
        return units;
    }
    let Ok(root) = serde_json::from_slice::<serde_json::Value>(&channel.schema) else {
        return units;
    };
    walk_schema(&root, &root, "", &mut units, 0);
    units
}

fn walk_schema(
    node: &serde_json::Value,
    root: &serde_json::Value,
    prefix: &str,
    units: &mut HashMap<String, String>,
    depth: usize,
) {
    // Schemas are small trees; the depth limit only guards against a reference cycle.
    if depth > 16 {
        return;
    }
    if let Some(unit) = node
        .get("description")
        .and_then(|d| d.as_str())
        .and_then(|d| d.strip_prefix('['))
        .and_then(|d| d.split_once(']'))
        .map(|(unit, _)| unit.trim())
        && !prefix.is_empty()
    {
        units.insert(prefix.to_owned(), unit.to_owned());
    }
    if let Some(target) = node
        .get("$ref")
        .and_then(|r| r.as_str())
        .and_then(|r| r.strip_prefix("#/"))
    {
        let mut target_node = Some(root);
        for part in target.split('/') {
            target_node = target_node.and_then(|n| n.get(part));
        }
        if let Some(t) = target_node {
            walk_schema(t, root, prefix, units, depth + 1);
        }
    }
    for key in ["allOf", "anyOf", "oneOf"] {
        if let Some(list) = node.get(key).and_then(|l| l.as_array()) {
            for sub in list {
                walk_schema(sub, root, prefix, units, depth + 1);
            }
        }
    }
    if let Some(props) = node.get("properties").and_then(|p| p.as_object()) {
        for (name, sub) in props {
            let path = if prefix.is_empty() {
                name.clone()
            } else {
                format!("{prefix}.{name}")
            };
            walk_schema(sub, root, &path, units, depth + 1);
        }
    }
}

fn header_of(path: &str, units: &HashMap<String, String>) -> String {
    match units.get(&unit_key(path)) {
        Some(unit) => format!("{path} [{unit}]"),
        None => path.to_owned(),
    }
}

/// What [`export_csv`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CsvExport {
    /// The column headers, `log_time_ns` first, then `field [unit]`.
    pub columns: Vec<String>,
    /// Data rows written.
    pub rows: u64,
}

/// Writes the messages of `topic` (within the inclusive range `range_ns`, if given) as CSV to
/// `out`: a header line, then one row per message with its log time in ns and its flattened
/// fields. The columns are every field of any message, in the order they first appear; a
/// message without one (a patch's `weight` exists only in a rail transition) leaves its cell
/// empty. Two passes over the topic: the columns, then the rows.
pub fn export_csv(
    reader: &LogReader,
    topic: &str,
    range_ns: Option<(u64, u64)>,
    out: impl Write,
) -> Result<CsvExport> {
    let channel = reader.channel(topic).ok_or_else(|| LogError::Topic {
        path: reader.path().to_path_buf(),
        message: format!("the log has no topic '{topic}'"),
    })?;
    let units = units_of(channel);
    let mut out = BufWriter::new(out);
    let write_err = |e: std::io::Error| LogError::Export {
        path: reader.path().to_path_buf(),
        message: format!("writing the CSV of '{topic}': {e}"),
    };
    let mut query = Query::topics([topic]);
    if let Some((start, end)) = range_ns {
        query = query.between(start, end);
    }
    let not_json = |t_ns: u64, e: serde_json::Error| LogError::Export {
        path: reader.path().to_path_buf(),
        message: format!("message on '{topic}' at t = {t_ns} ns is not JSON: {e}"),
    };
    // first pass: the union of the fields, each new one after the field before it
    let mut paths: Vec<String> = Vec::new();
    reader.for_each(&query, |m| {
        let fields = flatten_json(m.data).map_err(|e| not_json(m.log_time_ns, e))?;
        let mut after: Option<usize> = None;
        for (p, _) in &fields {
            after = Some(match paths.iter().position(|q| q == p) {
                Some(k) => k,
                None => {
                    let k = after.map_or(0, |a| a + 1);
                    paths.insert(k, p.clone());
                    k
                }
            });
        }
        Ok(())
    })?;
    let mut columns = vec!["log_time_ns".to_owned()];
    columns.extend(paths.iter().map(|p| header_of(p, &units)));
    writeln!(out, "{}", columns.join(",")).map_err(write_err)?;
    // second pass: the rows
    let mut rows = 0u64;
    let mut cells: Vec<Option<String>> = vec![None; paths.len()];
    reader.for_each(&query, |m| {
        let fields = flatten_json(m.data).map_err(|e| not_json(m.log_time_ns, e))?;
        cells.iter_mut().for_each(|c| *c = None);
        let mut k = 0;
        for (p, value) in fields {
            // (the fields come in the union's order, so the search moves forward)
            k = match paths[k..].iter().position(|q| *q == p) {
                Some(d) => k + d,
                None => paths.iter().position(|q| *q == p).unwrap_or(k),
            };
            cells[k] = Some(value.to_string());
        }
        write!(out, "{}", m.log_time_ns).map_err(write_err)?;
        for c in &cells {
            write!(out, ",{}", c.as_deref().unwrap_or("")).map_err(write_err)?;
        }
        writeln!(out).map_err(write_err)?;
        rows += 1;
        Ok(())
    })?;
    out.flush().map_err(write_err)?;
    Ok(CsvExport { columns, rows })
}

/// A file name for a topic's CSV: `/contact/0/left` → `contact_0_left.csv`.
pub fn csv_file_name(topic: &str) -> String {
    let stem: String = topic
        .trim_start_matches('/')
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{}.csv", if stem.is_empty() { "root" } else { &stem })
}

/// Exports each topic of `query` (all topics if it names none) to `dir/<topic>.csv` (see
/// [`csv_file_name`]) and returns `(topic, file, rows)` per topic.
pub fn export_csv_files(
    reader: &LogReader,
    query: &Query,
    dir: &Path,
) -> Result<Vec<(String, PathBuf, u64)>> {
    let topics: Vec<String> = match &query.topics {
        Some(t) => t.clone(),
        None => reader.channels().iter().map(|c| c.topic.clone()).collect(),
    };
    let range = match (query.start_ns, query.end_ns) {
        (None, None) => None,
        (s, e) => Some((s.unwrap_or(0), e.unwrap_or(u64::MAX))),
    };
    let mut written = Vec::new();
    for topic in topics {
        let file_path = dir.join(csv_file_name(&topic));
        let file = File::create(&file_path).map_err(|source| LogError::Io {
            path: file_path.clone(),
            action: "creating the CSV file",
            source,
        })?;
        let export = export_csv(reader, &topic, range, file)?;
        written.push((topic, file_path, export.rows));
    }
    Ok(written)
}

/// Minimum, maximum and mean of one numeric field.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldStats {
    /// Flattened field path, e.g. `position.1`.
    pub path: String,
    /// Unit from the schema, if any.
    pub unit: Option<String>,
    /// Number of numeric values seen (nulls are skipped).
    pub count: u64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Arithmetic mean.
    pub mean: f64,
}

/// Summary statistics of one topic.
#[derive(Debug, Clone, PartialEq)]
pub struct TopicStats {
    /// The topic.
    pub topic: String,
    /// Its schema name.
    pub schema_name: String,
    /// Messages seen.
    pub messages: u64,
    /// \[ns\] first log time, if any message
    pub first_ns: Option<u64>,
    /// \[ns\] last log time, if any message
    pub last_ns: Option<u64>,
    /// Statistics of each numeric field, in field order.
    pub fields: Vec<FieldStats>,
}

type TopicAccumulator = (usize, HashMap<String, usize>, HashMap<String, String>);

/// Per-topic, per-numeric-field minimum, maximum and mean over the messages of `query`, in
/// one streaming pass. Topics are in the reader's (sorted) order; topics without selected
/// messages are listed with no fields.
pub fn summarize(reader: &LogReader, query: &Query) -> Result<Vec<TopicStats>> {
    let mut stats: Vec<TopicStats> = Vec::new();
    // Per channel id: index into `stats`, field path -> index into its fields, units.
    let mut index_of: HashMap<u16, TopicAccumulator> = HashMap::new();
    for channel in reader.channels() {
        if query
            .topics
            .as_ref()
            .is_some_and(|t| !t.contains(&channel.topic))
        {
            continue;
        }
        index_of.insert(channel.id, (stats.len(), HashMap::new(), units_of(channel)));
        stats.push(TopicStats {
            topic: channel.topic.clone(),
            schema_name: channel.schema_name.clone(),
            messages: 0,
            first_ns: None,
            last_ns: None,
            fields: Vec::new(),
        });
    }
    reader.for_each(query, |m| {
        let Some((i, field_index, units)) = index_of.get_mut(&m.channel.id) else {
            return Ok(());
        };
        let topic = &mut stats[*i];
        topic.messages += 1;
        topic.first_ns.get_or_insert(m.log_time_ns);
        topic.last_ns = Some(m.log_time_ns);
        let fields = flatten_json(m.data).map_err(|e| LogError::Export {
            path: reader.path().to_path_buf(),
            message: format!(
                "message on '{}' at t = {} ns is not JSON: {e}",
                m.channel.topic, m.log_time_ns
            ),
        })?;
        for (path, value) in fields {
            let Scalar::Number(x) = value else { continue };
            let k = match field_index.get(&path) {
                Some(&k) => k,
                None => {
                    let k = topic.fields.len();
                    topic.fields.push(FieldStats {
                        unit: units.get(&unit_key(&path)).cloned(),
                        path: path.clone(),
                        count: 0,
                        min: f64::INFINITY,
                        max: f64::NEG_INFINITY,
                        mean: 0.0,
                    });
                    field_index.insert(path, k);
                    k
                }
            };
            let f = &mut topic.fields[k];
            f.count += 1;
            f.min = f.min.min(x);
            f.max = f.max.max(x);
            f.mean += (x - f.mean) / f.count as f64;
        }
        Ok(())
    })?;
    Ok(stats)
}
