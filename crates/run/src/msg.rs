//! The message file (`<name>.msg`): what the run did, line by line, written as it happens.
//!
//! Layout: a banner, then for every command its echo (` command: <text>`), followed by the
//! reports of the analyses it ran (the model summary of verify before the first analysis and
//! after every change of the model, the IC, static and linear reports, the integrator
//! statistics of each dynamic run, written after its step table, which
//! [`crate::step_table`] writes as the run goes), warnings and errors with the simulation time. Each line is
//! flushed when written, so that an interrupted run leaves every line it wrote.

use crate::error::RunError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The open message file.
pub struct MessageFile {
    path: PathBuf,
    out: BufWriter<File>,
}

impl MessageFile {
    /// Creates (or truncates) the file at `path`.
    pub fn create(path: &Path) -> Result<MessageFile, RunError> {
        let file = File::create(path).map_err(|cause| RunError::Write {
            path: path.display().to_string(),
            cause,
        })?;
        Ok(MessageFile {
            path: path.to_path_buf(),
            out: BufWriter::new(file),
        })
    }

    /// Writes `text` (one or more lines; a final newline is added when missing) and flushes.
    pub fn write(&mut self, text: &str) -> Result<(), RunError> {
        let mut t = text.to_string();
        if !t.ends_with('\n') {
            t.push('\n');
        }
        self.out
            .write_all(t.as_bytes())
            .and_then(|_| self.out.flush())
            .map_err(|cause| RunError::Write {
                path: self.path.display().to_string(),
                cause,
            })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}
