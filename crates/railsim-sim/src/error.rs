//! The crate's error type: located problems, from the scene file and from the vehicle and track
//! files it refers to, all reported together.

/// One located problem: `file` is the scene file for problems of the scene itself, and the
/// vehicle or track file (with its own line and column) for problems found while compiling those.
pub use railsim_spec::Problem;

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

/// Errors of building and running a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The scene (or a file it names) is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene compiles but cannot be simulated (e.g. a profile file cannot be read).
    #[error("cannot build the simulation: {message}")]
    Model {
        /// What is wrong.
        message: String,
    },
    /// The initial state could not be found.
    #[error("initial state: {message}")]
    Initial {
        /// What failed.
        message: String,
    },
    /// The simulation stopped: it went unstable, derailed, or the integrator failed. The log
    /// written so far is kept and readable.
    #[error("simulation stopped at t = {t:.6} s: {body}: {quantity}{}", log_note(.log))]
    Stopped {
        /// \[s\] time of the last good state (or of the failed evaluation).
        t: f64,
        /// The body, wheelset or wheel concerned ("integrator" or "model" when none).
        body: String,
        /// What went wrong, with the value.
        quantity: String,
        /// The log that was kept, if any.
        log: Option<std::path::PathBuf>,
        /// The state digest of the samples recorded before the stop (as
        /// `RunSummary::digest`; set by `Simulation::run`), so that a re-run can be compared
        /// with a stopped one.
        digest: Option<u64>,
        /// What the run reports up to the stop (set by `Simulation::run`): its statistics and
        /// the EN 14363 / EN 12299 assessment of the samples recorded before it. A sample that
        /// crossed a limit is in the statistics, the assessment and the digest but not in the
        /// log, nor in `samples` (which counts the logged ones). Boxed: the error stays small
        /// on its other paths.
        summary: Option<Box<crate::run::RunSummary>>,
    },
    /// A stability study (`crate::stability`) was set up wrongly or found nothing to measure.
    #[error("{message}")]
    Study {
        /// What is wrong, naming the study and the values.
        message: String,
    },
    /// Writing the log failed.
    #[error(transparent)]
    Log(#[from] railsim_log::LogError),
    /// Invalid integrator settings or a dense-output request outside the last step.
    #[error("integrator: {0}")]
    Ode(railsim_ode::OdeError),
}

impl From<railsim_ode::OdeError> for SimError {
    fn from(e: railsim_ode::OdeError) -> Self {
        SimError::Ode(e)
    }
}

fn log_note(log: &Option<std::path::PathBuf>) -> String {
    match log {
        Some(p) => format!(" (the log up to this point is kept in {})", p.display()),
        None => String::new(),
    }
}

use railsim_spec::list_problems as list;

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

pub(crate) use railsim_spec::Sink;

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
