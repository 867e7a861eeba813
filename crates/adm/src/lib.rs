//! # linkage-adm — the Adams dataset language
//!
//! Reads Adams Solver datasets (`.adm`) and command files (`.acf`) into values:
//!
//! ```text
//! text ──lexer──▶ logical statements (continuations joined, comments captured, spans kept)
//!      ──parse──▶ [`Statement`] (generic: keyword, id, arguments with spans)
//!      ──typing─▶ [`Dataset`] (typed PART, MARKER, JOINT, JPRIM, MOTION, COUPLER, GEAR, GCON, …)
//! command text ──lexer, parse──▶ [`CommandFile`] ──typing─▶ [`TypedCommandFile`] ([`Command`]s)
//! ```
//!
//! The crate knows nothing about mechanics: it does not resolve references between elements
//! (that is `linkage-model`'s job) and it never panics on user input. Every problem is a
//! [`Diagnostic`] carrying the file, line and column it comes from.
//!
//! Beside the dataset language: Adams request files, read ([`reqfile`]) and written
//! ([`reqwriter`], streamed one output block at a time).

pub mod amend;
pub mod commands;
pub mod diagnostic;
pub mod edit;
pub mod input;
pub mod num;
pub mod reqfile;
pub mod reqwriter;
pub mod statement;
pub mod typed;
pub mod writer;

mod keywords;
mod lexer;
mod parse;
mod typing;

pub use commands::{
    parse_commands, parse_typed_commands, read_commands, read_typed_commands, type_commands,
    Command, CommandFile, TypedCommandFile,
};
pub use diagnostic::{Diagnostic, Diagnostics, Severity, Span};
pub use statement::{keyword_id, Argument, ExprText, Statement, Value};
pub use typed::*;
pub use typing::contact;
pub use typing::fe_part;
pub use typing::flex_body;
pub use typing::graphics;

use std::path::Path;
use std::sync::Arc;

/// How a dataset is read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// An argument a statement does not take (a misspelling such as `MASSS = 1` in a PART)
    /// is a warning and ignored, instead of an input error with a "did you mean"
    /// suggestion (Adams stops on it). The CLI's `--lenient-arguments`.
    pub lenient_arguments: bool,
}

/// Reads and types a dataset file. I/O failures become a diagnostic naming the file.
pub fn read_dataset(path: &Path) -> Result<Dataset, Diagnostics> {
    read_dataset_with(path, ReadOptions::default())
}

/// [`read_dataset`] with `options`.
pub fn read_dataset_with(path: &Path, options: ReadOptions) -> Result<Dataset, Diagnostics> {
    let file: Arc<str> = Arc::from(path.display().to_string());
    match crate::input::read_input(path) {
        Ok(bytes) => {
            let text = crate::input::text_of(bytes);
            parse_dataset_with(file, &text, options)
        }
        Err(e) => Err(Diagnostics(vec![Diagnostic::error(
            file,
            None,
            format!("cannot read dataset: {e}"),
        )])),
    }
}

/// The canonical names of every statement of the dataset language (ADM-REFERENCE §1.5), in
/// alphabetical order.
pub fn dataset_keywords() -> impl Iterator<Item = &'static str> {
    keywords::DATASET_STATEMENTS.iter().map(|s| s.name)
}

/// Parses and types dataset text. `file` is the name used in diagnostics.
///
/// Returns the dataset (with its warnings) or every error found.
pub fn parse_dataset(file: Arc<str>, text: &str) -> Result<Dataset, Diagnostics> {
    parse_dataset_with(file, text, ReadOptions::default())
}

/// [`parse_dataset`] with `options`.
pub fn parse_dataset_with(
    file: Arc<str>,
    text: &str,
    options: ReadOptions,
) -> Result<Dataset, Diagnostics> {
    // Line 1 is the title: statements start at line index 1.
    let parsed = parse::parse(
        file.clone(),
        text,
        1,
        parse::Language::Dataset,
        options.lenient_arguments,
    );
    typing::type_dataset(file, text, parsed)
}
