//! What every command shares: loading a dataset, reporting input errors, printing JSON.

use clap::ValueEnum;
use linkage_adm::Diagnostics;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

// Loading a dataset and the analyses' shared pieces live in the library that the Python
// package and sweeps use too.
use linkage_adm::ReadOptions;
pub use linkage_api::{output_times, Loaded};
use linkage_solve::coverage::Analysis;
use std::sync::OnceLock;

/// How this process reads datasets: the command line's `--lenient-arguments`, set once by
/// `main` before any command runs.
static READ_OPTIONS: OnceLock<ReadOptions> = OnceLock::new();

/// Sets how every dataset of this process is read (the first call wins).
pub fn set_read_options(options: ReadOptions) {
    let _ = READ_OPTIONS.set(options);
}

/// How datasets are read (strict unless `--lenient-arguments`).
pub fn read_options() -> ReadOptions {
    READ_OPTIONS.get().copied().unwrap_or_default()
}

/// The command line's `--user-lib` paths, set once by `main`.
static USER_LIBRARIES: OnceLock<Vec<PathBuf>> = OnceLock::new();

/// Sets the user-subroutine libraries of every dataset of this process (the first call wins).
pub fn set_user_libraries(paths: Vec<PathBuf>) {
    let _ = USER_LIBRARIES.set(paths);
}

/// The `--user-lib` paths (none unless given).
pub fn user_libraries() -> &'static [PathBuf] {
    USER_LIBRARIES.get().map_or(&[], Vec::as_slice)
}

/// The dataset at `path` read with the command line's read options, its USER calls linked to
/// the `--user-lib` libraries.
fn source(path: &Path) -> Result<linkage_api::Source, Diagnostics> {
    linkage_api::Source::read_with(path, read_options())?.with_user_libraries(user_libraries())
}

/// [`linkage_api::load`] with the command line's read options and user libraries.
pub fn load(
    path: &Path,
    deactivate: &[String],
    analysis: Option<Analysis>,
) -> Result<Loaded, Diagnostics> {
    source(path)?.into_loaded(deactivate, analysis)
}

/// [`linkage_api::load_model`] with the command line's read options and user libraries.
pub fn load_model(
    path: &Path,
    deactivate: &[String],
    analysis: Option<Analysis>,
) -> Result<Loaded, Diagnostics> {
    source(path)?.into_model(deactivate, analysis)
}

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
pub enum Format {
    Text,
    Json,
}

/// Prints input errors (and, for JSON, an object with `errors`) and returns exit code 2.
pub fn input_error(d: &Diagnostics, format: Format) -> ExitCode {
    if format == Format::Json {
        let errors: Vec<String> = d.0.iter().map(|e| e.to_string()).collect();
        println!(
            "{}",
            serde_json::json!({ "errors": errors, "warnings": [] })
        );
    }
    eprintln!("{d}");
    ExitCode::from(2)
}

/// The exit of an analysis that gave no report: input errors as [`input_error`], any other
/// error on standard error with its exit code.
pub fn analysis_error(e: &linkage_api::Error, format: Format) -> ExitCode {
    match e {
        linkage_api::Error::Input(d) | linkage_api::Error::Refused { diagnostics: d, .. } => {
            input_error(d, format)
        }
        other => {
            eprintln!("error: {other}");
            ExitCode::from(other.exit_code())
        }
    }
}

/// Whether standard output is a terminal (where a report shows its errors to the user).
pub fn stdout_is_terminal() -> bool {
    use std::io::IsTerminal;
    std::io::stdout().is_terminal()
}

/// Prints `errors` as `error: …` lines on standard error, unless the report holding them (which
/// ends with them) was shown on a terminal: each error appears once there, and a report sent to
/// a file or a pipe still has its failure reach the user.
pub fn errors_to_stderr(errors: &[String], report_on_terminal: bool) {
    if !report_on_terminal {
        for e in errors {
            eprintln!("error: {e}");
        }
    }
}

/// Pretty JSON on stdout; false (after a message) when serialisation fails.
pub fn print_json<T: serde::Serialize>(v: &T) -> bool {
    let document = serde_json::to_value(v).map(linkage_report::with_schema_version);
    match document.and_then(|d| serde_json::to_string_pretty(&d)) {
        Ok(s) => {
            println!("{s}");
            true
        }
        Err(e) => {
            eprintln!("error: cannot write JSON: {e}");
            false
        }
    }
}

/// A progress bar on standard error when it is a terminal; silent otherwise (pipes, files,
/// tests).
pub struct Progress(Option<indicatif::ProgressBar>);

impl Progress {
    pub fn on_terminal() -> Progress {
        use std::io::IsTerminal;
        if !std::io::stderr().is_terminal() {
            return Progress(None);
        }
        let b = indicatif::ProgressBar::new(1000);
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}% {msg} {elapsed}")
        {
            b.set_style(style);
        }
        Progress(Some(b))
    }

    /// Shows `fraction` (clamped to 0…1) done, with a message.
    pub fn show(&self, fraction: f64, message: String) {
        if let Some(b) = &self.0 {
            b.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
            b.set_message(message);
        }
    }

    /// Dynamic settling: `elapsed` pseudo-time out of SETTLING_TIME `limit`.
    pub fn settling(&self, elapsed: f64, limit: f64) {
        self.show(
            elapsed / limit,
            format!(
                "settling: {elapsed:.4} of SETTLING_TIME {}",
                linkage_model::settings::shown(limit)
            ),
        );
    }

    pub fn finish(&self) {
        if let Some(b) = &self.0 {
            b.finish_and_clear();
        }
    }

    /// Clears the bar and starts it again at 0 for the next analysis.
    pub fn clear(&self) {
        if let Some(b) = &self.0 {
            b.finish_and_clear();
            b.set_message("");
            b.reset();
        }
    }
}

/// An output path that is the input file (the same file by identity: another spelling, a
/// symbolic or a hard link) is an input error: the message names both.
pub fn check_output(input: &Path, output: &Path) -> Result<(), linkage_api::OutputIsInput> {
    linkage_api::check_outputs([input], [output])
}

/// Whether an output path means standard output (`-`).
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// glibc's allocator serves blocks above 128 kB by `mmap` and gives freed memory at the top of
/// the heap back to the system, so a run that reads a large dataset (growing and freeing many
/// big buffers) has the kernel zero the same pages again and again: on the 10,000-loop chain
/// a third fewer page faults (52,000 → 35,000) without these limits. One process runs one
/// command, so freed memory is kept for reuse; the peak resident size does not change.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: called first thing in `main`, before any other thread exists and before any
    // allocation that these settings would concern; both are documented mallopt parameters
    // with values in their accepted ranges (the mmap threshold's maximum is 32 MiB).
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
    }
}

/// A closed pipe ends the program quietly, as for other command-line tools
/// (`linkage verify --explain big.adm | head -1`): SIGPIPE back to its default action, which
/// Rust's runtime sets to "ignore" (every later `print!` would then panic).
pub fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
