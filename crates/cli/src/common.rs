//! What every command shares: loading a dataset, reporting input errors, printing JSON.

use clap::ValueEnum;
use linkage_adm::amend::Selected;
use linkage_adm::{Dataset, Diagnostic, Diagnostics};
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::coverage::{self, Analysis, Finding};
use std::path::Path;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
pub enum Format {
    Text,
    Json,
}

/// A dataset read, built and with its functions parsed.
pub struct Loaded {
    /// The dataset without the statements left out on request.
    pub dataset: Dataset,
    pub model: Model,
    pub drivers: ExpressionDrivers,
    /// Dataset, model and function warnings.
    pub warnings: Vec<Diagnostic>,
    /// The statements left out on request (`--deactivate`).
    pub left_out: Vec<Selected>,
    /// Every statement of the dataset some analysis refuses or runs without.
    pub findings: Vec<Finding>,
}

/// Reads the dataset at `path`, leaves out the statements `deactivate` names, builds it and
/// checks its functions. `analysis` is the analysis the model is loaded for (`None`: verify).
/// When the model does not build, the input errors also name every statement that
/// `analysis` (verify: any analysis) would refuse, so that all of them come at once.
pub fn load(
    path: &Path,
    deactivate: &[String],
    analysis: Option<Analysis>,
) -> Result<Loaded, Diagnostics> {
    let read = linkage_adm::read_dataset(path)?;
    let (dataset, left_out) = if deactivate.is_empty() {
        (read, Vec::new())
    } else {
        let left_out = linkage_adm::amend::select(&read.statements, deactivate)
            .map_err(|e| Diagnostics(vec![Diagnostic::error(read.file.clone(), None, e)]))?;
        (linkage_adm::amend::without(&read, &left_out)?, left_out)
    };
    let findings = coverage::findings(&dataset);
    let built = linkage_model::build_model(&dataset)
        .and_then(|b| ExpressionDrivers::new(&b.model).map(|d| (b, d)));
    let (built, drivers) = match built {
        Ok(b) => b,
        Err(mut d) => {
            d.0.extend(refused_as_diagnostics(&findings, analysis, &d.0));
            return Err(d);
        }
    };
    let mut warnings = built.warnings;
    warnings.extend(drivers.warnings().iter().cloned());
    Ok(Loaded {
        dataset,
        model: built.model,
        drivers,
        warnings,
        left_out,
        findings,
    })
}

/// The findings `analysis` refuses (verify, `None`: that any analysis refuses) as
/// diagnostics, leaving out those at a line some diagnostic of `already` is at: errors for an
/// analysis, notes for verify.
fn refused_as_diagnostics(
    findings: &[Finding],
    analysis: Option<Analysis>,
    already: &[Diagnostic],
) -> Vec<Diagnostic> {
    findings
        .iter()
        .filter(|f| match analysis {
            Some(a) => f.refuses(a),
            None => !f.refused_by.is_empty(),
        })
        .filter(|f| {
            !already
                .iter()
                .any(|d| d.span.is_some_and(|s| s.line == f.span.line))
        })
        .map(|f| {
            let mut d = refusal(f);
            if analysis.is_none() {
                d.severity = linkage_adm::Severity::Note;
            }
            d
        })
        .collect()
}

/// The input error of an analysis refusing `f`, with the option that runs without it.
fn refusal(f: &Finding) -> Diagnostic {
    f.error().with_hint(format!(
        "--deactivate {} runs the rest of the model without it",
        f.element
    ))
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
    match serde_json::to_string_pretty(v) {
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

/// The applied force elements of a loaded model (gravity is applied by the analyses), or the
/// input errors of `analysis`: every statement it refuses, all at once.
pub fn applied_forces(
    loaded: &Loaded,
    analysis: Analysis,
) -> Result<Box<dyn linkage_solve::physics::applied::AppliedForces>, Diagnostics> {
    let refused: Vec<Diagnostic> = loaded
        .findings
        .iter()
        .filter(|f| f.refuses(analysis))
        .map(refusal)
        .collect();
    if !refused.is_empty() {
        return Err(Diagnostics(refused));
    }
    let forces = linkage_solve::physics::forces::ForceSet::new(&loaded.model)?;
    Ok(Box::new(forces))
}

/// What a report of `analysis` says about the statements left out and those it ran without.
pub fn coverage_json(
    loaded: &Loaded,
    analysis: Analysis,
) -> (
    Vec<linkage_report::coverage::LeftOutJson>,
    Vec<linkage_report::coverage::FindingJson>,
) {
    (
        linkage_report::coverage::left_out_json(&loaded.left_out),
        linkage_report::coverage::runs_without_json(&loaded.findings, analysis),
    )
}

/// The most output times a run may ask for: every output keeps each part's state, so a
/// mistyped count (`--dtout 1e-9` over `--end 1e9`) is refused rather than exhausting memory.
pub const MAX_OUTPUT_TIMES: usize = 1_000_000;

/// Slack on the number of `--dtout` intervals in `--end` (a count, so relative to one
/// interval): an `--end` that is a multiple of `--dtout` up to rounding (`0.3 / 0.1` is
/// 2.9999999999999996) gets no extra sliver interval at its end.
pub const INTERVAL_COUNT_SLACK: f64 = 1e-9;

/// Why `--end`, `--steps` or `--dtout` cannot give output times (an input error: exit code 2).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutputTimesError {
    #[error("--end must be a positive time, not {end}")]
    EndNotPositive { end: f64 },
    #[error("--dtout must be a positive time, not {dtout}")]
    DtoutNotPositive { dtout: f64 },
    /// `count` outputs (more than [`MAX_OUTPUT_TIMES`]) every `dtout` up to `end`.
    #[error(
        "--dtout {dtout} over --end {end} asks for {} outputs; at most {} are allowed",
        linkage_adm::num::sci(*.count, 4),
        MAX_OUTPUT_TIMES
    )]
    TooManyIntervals { dtout: f64, end: f64, count: f64 },
    #[error("--steps must be at least 1")]
    NoSteps,
    #[error(
        "--steps {steps} asks for more than the {} outputs allowed",
        MAX_OUTPUT_TIMES
    )]
    TooManySteps { steps: usize },
}

/// Output times from 0 to `end`: `steps` equal intervals, or every `dtout` (the last one
/// shortened to land on `end`); 100 intervals when neither is given. An input error (for
/// exit code 2) when `end` or `dtout` is not a positive finite time, `steps` is 0, or the run
/// would have more than [`MAX_OUTPUT_TIMES`] outputs.
pub fn output_times(
    end: f64,
    steps: Option<usize>,
    dtout: Option<f64>,
) -> Result<Vec<f64>, OutputTimesError> {
    if !(end > 0.0 && end.is_finite()) {
        return Err(OutputTimesError::EndNotPositive { end });
    }
    let intervals = match (steps, dtout) {
        (_, Some(dtout)) => {
            if !(dtout > 0.0 && dtout.is_finite()) {
                return Err(OutputTimesError::DtoutNotPositive { dtout });
            }
            let n = (end / dtout - INTERVAL_COUNT_SLACK).ceil().max(1.0);
            if n > MAX_OUTPUT_TIMES as f64 {
                return Err(OutputTimesError::TooManyIntervals {
                    dtout,
                    end,
                    count: n,
                });
            }
            return Ok((0..=n as usize)
                .map(|k| (k as f64 * dtout).min(end))
                .collect());
        }
        (Some(0), None) => return Err(OutputTimesError::NoSteps),
        (Some(n), None) => n,
        (None, None) => 100,
    };
    if intervals > MAX_OUTPUT_TIMES {
        return Err(OutputTimesError::TooManySteps { steps: intervals });
    }
    Ok(linkage_solve::stages::statics::output_times(end, intervals))
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
}

/// `path` with its links resolved; for a file that does not exist yet, its folder's (so that
/// `./in.adm`, `in.adm` and a link to it compare equal).
fn resolved(path: &Path) -> Option<std::path::PathBuf> {
    if let Ok(p) = std::fs::canonicalize(path) {
        return Some(p);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(name))
}

/// An output path that names the input file (after resolving links).
#[derive(Debug, thiserror::Error)]
#[error("refusing to write {output}: it is the input {input} (choose another output file)")]
pub struct OutputIsInput {
    pub output: String,
    pub input: String,
}

/// An output path that would overwrite the input (after resolving links) is an input error:
/// the message names both.
pub fn check_output(input: &Path, output: &Path) -> Result<(), OutputIsInput> {
    match (resolved(input), resolved(output)) {
        (Some(a), Some(b)) if a == b => Err(OutputIsInput {
            output: output.display().to_string(),
            input: input.display().to_string(),
        }),
        _ => Ok(()),
    }
}

/// Whether an output path means standard output (`-`).
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
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
