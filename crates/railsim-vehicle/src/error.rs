//! The crate's error type, located problems, and the source map that turns byte spans into
//! `line:col`.

pub use railsim_spec::Problem;

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

use railsim_spec::list_problems as list;

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

pub(crate) use railsim_spec::Sink;

pub(crate) use railsim_spec::did_you_mean;
