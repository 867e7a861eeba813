//! Why an analysis produced no report: the input errors that the CLI answers with exit code 2,
//! and an output that could not be written (exit code 1).

use linkage_adm::Diagnostics;

/// An argument of an analysis (not of the dataset) that cannot be.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArgumentError {
    /// `--shift` (Python's and a sweep's `shift`) is infinite or NaN.
    #[error("--shift must be a finite frequency")]
    ShiftNotFinite,
    /// A quasi-static series with only one of its end time and step count.
    #[error("a quasi-static series needs both end and steps")]
    IncompleteSeries,
    /// A wall-clock limit that is not a positive finite number of seconds up to a year.
    #[error(transparent)]
    TimeLimit(#[from] crate::budget::TimeLimitError),
}

/// Why an analysis produced no report.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Errors in the dataset or in what it refers to (file:line:column each).
    #[error("{0}")]
    Input(Diagnostics),
    /// Statements the analysis refuses (not modelled, or not run by it), every one at once
    /// with the way to leave it out: an input error.
    #[error("{diagnostics}")]
    Refused {
        analysis: linkage_solve::coverage::Analysis,
        diagnostics: Diagnostics,
    },
    /// Output times that cannot be (`--end`, `--steps`, `--dtout`).
    #[error("{0}")]
    Times(#[from] crate::times::OutputTimesError),
    /// An argument of the analysis itself (not of the dataset) that cannot be.
    #[error(transparent)]
    Argument(#[from] ArgumentError),
    /// An output file that could not be opened (`cannot write FILE: why`).
    #[error("{0}")]
    Output(String),
    /// An output that could not be handed on (a file that cannot be written, a REQUEST that
    /// cannot be evaluated where every value is needed): the analysis stopped there.
    #[error(transparent)]
    Sink(#[from] crate::sink::SinkError),
    /// The analysis ran and failed (no operating point, no state matrices).
    #[error("{0}")]
    Failed(String),
}

impl From<Diagnostics> for Error {
    fn from(d: Diagnostics) -> Error {
        Error::Input(d)
    }
}

impl Error {
    /// The exit code of the CLI: 2 for input errors, 1 for an output that failed.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) | Error::Refused { .. } | Error::Times(_) | Error::Argument(_) => 2,
            Error::Output(_) | Error::Sink(_) | Error::Failed(_) => 1,
        }
    }

    /// One message per error (a diagnostic each, with its file:line:column).
    pub fn messages(&self) -> Vec<String> {
        match self {
            Error::Input(d) | Error::Refused { diagnostics: d, .. } => {
                d.0.iter().map(ToString::to_string).collect()
            }
            other => vec![other.to_string()],
        }
    }
}
