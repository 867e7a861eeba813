//! What can go wrong before a subroutine runs.

use std::path::PathBuf;

/// A problem with the subroutine libraries the user gave.
#[derive(Debug, thiserror::Error)]
pub enum UserError {
    /// A `--user-lib PATH` that names nothing.
    #[error("--user-lib {}: no such file or folder", .0.display())]
    NoSuchPath(PathBuf),
    /// The utility-routine shim could not be loaded (a platform without `memfd_create`, …).
    #[error("the utility routines for user subroutines cannot be loaded: {0}")]
    Shim(String),
}
