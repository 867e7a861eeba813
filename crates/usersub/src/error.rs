//! What can go wrong: with the libraries the user gave, linking a statement's USER call, and
//! a utility routine's read.

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

/// Why a statement's USER call has no subroutine (the model adds the statement and its place).
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// A statement family whose subroutines linkage does not call.
    #[error("linkage does not call the USER subroutines of {0} statements yet")]
    Unsupported(String),
    /// ROUTINE spells a path the user did not give.
    #[error(
        "its ROUTINE names the file {0}, which linkage loads only when you give that file \
         with --user-lib"
    )]
    SpelledPath(String),
    /// The library ROUTINE names is in none of the places searched.
    #[error("library '{lib}' ({}) is not among the --user-lib files nor in {}", .names.join(", "), places(.folders))]
    NoLibrary {
        lib: String,
        names: Vec<String>,
        folders: Vec<PathBuf>,
    },
    /// No ROUTINE library and the `--user-lib` folders hold no library.
    #[error("{0} is in no library: the --user-lib folders hold no .so file")]
    NoLibraries(String),
    /// The library cannot be loaded (not a shared library, an unresolved reference, …).
    #[error("{} cannot be loaded: {why}", .path.display())]
    Load { path: PathBuf, why: String },
    /// None of the symbol's spellings is in the libraries.
    #[error("no symbol {} in {}", .tried.join(", "), places(.libraries))]
    NoSymbol {
        tried: Vec<String>,
        libraries: Vec<PathBuf>,
    },
}

/// `a, b, c` of paths, or `any folder (none given)`.
fn places(paths: &[PathBuf]) -> String {
    if paths.is_empty() {
        "any folder (none given)".to_string()
    } else {
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        names.join(", ")
    }
}

/// Why a utility routine (SYSFNC, SYSARY) could not give a value.
#[derive(Clone, Debug, thiserror::Error)]
pub enum ReadError {
    /// Called outside a subroutine call linkage made.
    #[error("a utility routine was called outside a subroutine call")]
    NoCall,
    /// A name that is not a function of the expression language (or not a plain word).
    #[error("'{name}' is not a function name{}", .why.as_ref().map(|w| format!(": {w}")).unwrap_or_default())]
    BadName { name: String, why: Option<String> },
    /// SYSARY with a name it does not know.
    #[error("SYSARY: unknown name '{0}'")]
    UnknownArray(String),
    /// The measure cannot be evaluated here.
    #[error("{what}: {why}")]
    Evaluate { what: String, why: String },
    /// The routine panicked.
    #[error("{0} failed")]
    Panicked(String),
    /// A function utility routine (STEP, IMPACT, …) called with arguments it cannot take.
    #[error("{routine}: {why}")]
    Arguments { routine: String, why: String },
}
