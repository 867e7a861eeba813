//! # linkage-api — one entry point per analysis, shared by every front end
//!
//! The `linkage` CLI, the Python package (`python/`) and parameter sweeps ([`sweep`]) call the
//! same functions, so that each gives exactly the CLI's JSON report:
//!
//! ```text
//! Source::read(path) ─set(statement, argument, value)*─▶ Source ─load(deactivate)─▶ Loaded
//! Loaded ─▶ verify::verify · ic::ic · statics::statics · linear::linear · simulate::simulate
//!        ─▶ the report (linkage_report::*Json: `errors` empty ⇔ exit code 0)
//! ```
//!
//! [`job::Job`] names an analysis with its arguments as data (what a sweep spec or a Python
//! call gives) and runs it to a JSON value and an exit code. Input errors are
//! [`Error::Input`] (exit code 2), with file:line:column.

pub mod budget;
pub mod cosim;
pub mod error;
pub mod files;
pub mod ic;
pub mod job;
pub mod linear;
pub mod simulate;
pub mod sink;
pub mod source;
pub mod start;
pub mod statics;
pub mod sweep;
pub mod times;
pub mod verify;

pub use error::Error;
pub use files::{check_outputs, dataset_files, same_file, OutputIsInput};
pub use sink::{CsvSink, NoSink, OutputSink, SinkError};
pub use source::{load, load_model, ArgValue, Loaded, Refusal, Source};
pub use start::{Left, Start};
pub use times::{
    output_times, output_times_after, OutputTimesError, INTERVAL_COUNT_SLACK, MAX_OUTPUT_TIMES,
};
