//! Why a command file stopped.

use linkage_adm::Diagnostics;

/// Why a command file could not be run to its end.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The command file, the dataset or a command's statement does not read, type or build
    /// (every diagnostic, with file, line and column).
    #[error("{0}")]
    Input(Diagnostics),
    /// A command that linkage does not carry out, or cannot carry out on this model.
    #[error("{place}: {command}: {why}")]
    Refused {
        /// `file.acf:line:column`.
        place: String,
        command: String,
        why: String,
    },
    /// An analysis ran and failed (no assembly, no equilibrium, the integration stopped).
    #[error("{place}: {command}: {why}")]
    Failed {
        place: String,
        command: String,
        why: String,
    },
    /// The run was interrupted (Ctrl-C): it stopped after the output at `time`.
    #[error("interrupted at time {}: the files hold every output up to it", linkage_adm::num::time_text(*.time))]
    Interrupted { time: f64 },
    /// The command file has nothing to run: no dataset (line 1, FILE/MODEL or `--model`), or
    /// no analysis (SIMULATE, LINEAR) nor FILE/COMMAND that could hold one.
    #[error("{file}: {why}")]
    Empty { file: String, why: &'static str },
    /// An output file of the run is one of the files it reads (by identity: another
    /// spelling, a symbolic or a hard link): refused before anything is written to it.
    #[error(transparent)]
    OutputIsInput(#[from] linkage_api::OutputIsInput),
    /// An output file cannot be written.
    #[error("cannot write {path}: {cause}")]
    Write { path: String, cause: std::io::Error },
}

impl RunError {
    /// The exit code of `linkage run`: 2 for input errors and refused commands, 1 for an
    /// analysis that failed, a file that cannot be written, or an interrupted run (as an
    /// interrupted `linkage simulate`).
    pub fn exit_code(&self) -> u8 {
        match self {
            RunError::Input(_)
            | RunError::Refused { .. }
            | RunError::Empty { .. }
            | RunError::OutputIsInput(_) => 2,
            RunError::Failed { .. } | RunError::Write { .. } | RunError::Interrupted { .. } => 1,
        }
    }
}
