//! The crate's single error type.

/// Formats a location: `source:line` for file input, `source: point n` for in-memory input.
fn at(source_name: &str, line: &Option<usize>, index: &usize) -> String {
    match line {
        Some(l) => format!("{source_name}:{l}"),
        None => format!("{source_name}: point {}", index + 1),
    }
}

/// Formats the location of a second point (the one a point is compared with).
fn other(line: &Option<usize>, index: &usize) -> String {
    match line {
        Some(l) => format!("line {l}"),
        None => format!("point {}", index + 1),
    }
}

pub use railsim_spec::short_number;

/// Everything that can go wrong while reading, building or transforming a profile.
///
/// Every variant names its source (a file name, or the profile name for in-memory data).
/// `line` is the 1-based line of the offending line of the file (`None` for in-memory data,
/// where the 0-based point `index` is reported instead, printed 1-based).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// The file could not be read.
    #[error("{source_name}: cannot read the file: {message}")]
    Io {
        /// file name
        source_name: String,
        /// the operating system's message
        message: String,
    },
    /// A field that must be a number is not one.
    #[error("{source_name}:{line}: expected a number for {what}, found \"{found}\"")]
    NotANumber {
        /// file name
        source_name: String,
        /// 1-based line number
        line: usize,
        /// what was being read (`y`, `z`, `weight`, or a key name)
        what: String,
        /// the text found
        found: String,
    },
    /// A number is NaN or infinite.
    #[error("{}: {what} is not finite (found {value}), expected a finite number", at(.source_name, .line, .index))]
    NonFinite {
        /// file or profile name
        source_name: String,
        /// 1-based line number, if the data came from a file
        line: Option<usize>,
        /// 0-based point index
        index: usize,
        /// which quantity (`y`, `z`, `weight`, `factor`, ...)
        what: String,
        /// the value found
        value: f64,
    },
    /// A coordinate is finite but far outside any wheel or rail profile.
    #[error("{}: {what} = {} mm (profile frame) is out of range, expected |{what}| <= {limit_mm} mm", at(.source_name, .line, .index), short_number(*.value_mm))]
    OutOfRange {
        /// file or profile name
        source_name: String,
        /// 1-based line number, if the data came from a file
        line: Option<usize>,
        /// 0-based point index
        index: usize,
        /// which coordinate (`y` or `z`)
        what: String,
        /// \[mm\] the value found
        value_mm: f64,
        /// \[mm\] the largest magnitude accepted
        limit_mm: f64,
    },
    /// The profile spans too little laterally to be a wheel or rail profile in millimetres.
    #[error("{source_name}: the profile spans only {} mm laterally (y from {} to {} mm), expected at least {limit_mm} mm (coordinates in metres where millimetres are expected?)", short_number(.y_max_mm - .y_min_mm), short_number(*.y_min_mm), short_number(*.y_max_mm))]
    TooNarrow {
        /// file or profile name
        source_name: String,
        /// \[mm\] smallest y
        y_min_mm: f64,
        /// \[mm\] largest y
        y_max_mm: f64,
        /// \[mm\] the narrowest extent accepted
        limit_mm: f64,
    },
    /// Fewer than four points.
    #[error("{source_name}: expected at least 4 profile points, found {found}")]
    TooFewPoints {
        /// file or profile name
        source_name: String,
        /// number of points found
        found: usize,
    },
    /// Two consecutive points coincide.
    #[error("{}: point repeats the point on {} (y = {y_mm} mm, z = {z_mm} mm); expected distinct points", at(.source_name, .line, .index), other(.prev_line, &(.index - 1)))]
    RepeatedPoint {
        /// file or profile name
        source_name: String,
        /// 1-based line of the repeated point, if from a file
        line: Option<usize>,
        /// 1-based line of the earlier point, if from a file
        prev_line: Option<usize>,
        /// 0-based index of the repeated point (in file order)
        index: usize,
        /// \[mm\] y of the point
        y_mm: f64,
        /// \[mm\] z of the point
        z_mm: f64,
    },
    /// A point does not continue the monotonic order in y of the profile.
    #[error("{}: y = {y_mm} mm goes backward from y = {prev_y_mm} mm on {}; expected y strictly monotonic along the profile", at(.source_name, .line, .index), other(.prev_line, &(.index - 1)))]
    NotMonotonic {
        /// file or profile name
        source_name: String,
        /// 1-based line of the offending point, if from a file
        line: Option<usize>,
        /// 1-based line of the previous point, if from a file
        prev_line: Option<usize>,
        /// 0-based index of the offending point (in file order)
        index: usize,
        /// \[mm\] y of the offending point
        y_mm: f64,
        /// \[mm\] y of the previous point
        prev_y_mm: f64,
    },
    /// Two non-adjacent segments of the outline cross.
    #[error("{}: the segment ending here crosses the segment ending at {}; expected an outline that does not intersect itself", at(.source_name, .line, .index), other(.other_line, .other_index))]
    SelfIntersection {
        /// file or profile name
        source_name: String,
        /// 1-based line of the end point of the later segment, if from a file
        line: Option<usize>,
        /// 0-based index of the end point of the later segment
        index: usize,
        /// 1-based line of the end point of the earlier segment, if from a file
        other_line: Option<usize>,
        /// 0-based index of the end point of the earlier segment
        other_index: usize,
    },
    /// A SIMPACK key is unknown.
    #[error(
        "{source_name}:{line}: unknown key '{key}' in the {block} block; expected one of {expected}"
    )]
    UnknownKey {
        /// file name
        source_name: String,
        /// 1-based line number
        line: usize,
        /// the key found
        key: String,
        /// the enclosing block (`header`, `spline`)
        block: String,
        /// the accepted keys
        expected: String,
    },
    /// A SIMPACK key (or a structural line) has a value that is not allowed.
    #[error(
        "{source_name}:{line}: invalid value for '{key}': found \"{found}\", expected {expected}"
    )]
    InvalidValue {
        /// file name
        source_name: String,
        /// 1-based line number
        line: usize,
        /// the key (or structural element)
        key: String,
        /// the text found
        found: String,
        /// what is allowed
        expected: String,
    },
    /// The SIMPACK file has no `point.begin … point.end` block.
    #[error(
        "{source_name}: no point block found; expected 'point.begin' ... 'point.end' inside 'spline.begin' ... 'spline.end'"
    )]
    MissingPointBlock {
        /// file name
        source_name: String,
    },
    /// An argument of a function is out of its range.
    #[error("{source_name}: invalid {what}: found {found}, expected {expected}")]
    InvalidArgument {
        /// profile name or function
        source_name: String,
        /// the argument
        what: String,
        /// the value found
        found: String,
        /// what is allowed
        expected: String,
    },
}
