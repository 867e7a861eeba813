//! `linkage simulate`: dynamic simulation with output at requested times; the CSV gets the
//! dataset's REQUEST outputs as extra columns.

use crate::common::{
    applied_forces, input_error, is_stdout, load, output_times, print_json, Format, Progress,
};
use linkage_report::simulate::CsvHistory;
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{
    run_streamed, AfterOutput, Output, RunProgress, Start, Stream, UnstableStart,
};
use linkage_solve::tolerances::Tolerances;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Options of `linkage simulate`.
pub struct SimulateArgs<'a> {
    pub model: &'a Path,
    pub format: Format,
    pub end: f64,
    pub steps: Option<usize>,
    pub dtout: Option<f64>,
    pub out: Option<&'a Path>,
    pub start: Start,
    /// Start from an unstable equilibrium rather than stop (with `--start-at-equilibrium`).
    pub allow_unstable: bool,
    /// Wall-clock seconds after which the run stops (after the step it is in).
    pub time_limit: Option<f64>,
    /// Statements to leave out (`--deactivate`).
    pub deactivate: &'a [String],
    /// Where to write the HTML page (`--html`).
    pub html: Option<&'a Path>,
    /// The columns the page plots (`--plot`; empty: the default plots).
    pub plot: &'a [String],
}

/// The CSV of `--out`, written row by row as the outputs come (bounded memory whatever their
/// number; each row flushed, so a run that stops keeps whole rows). REQUEST columns follow the
/// part and reaction columns; an output where a request cannot be evaluated gets NaN in every
/// request column, and the first such error is reported (the run then exits with 1).
struct CsvStream<'r> {
    csv: CsvHistory<Box<dyn Write>>,
    path: String,
    requests: Option<&'r RequestSet>,
    /// The request columns (once: they do not change during the run).
    names: Vec<String>,
    request_failures: usize,
    errors: Vec<String>,
}

impl CsvStream<'_> {
    fn write(&mut self, assembled: &Assembled, o: &Output) -> std::io::Result<()> {
        let names = &self.names;
        let values = match self.requests {
            None => Vec::new(),
            Some(r) => match r.evaluate(assembled.model, &assembled.system, o) {
                Ok(v) => v,
                Err(e) => {
                    if self.request_failures == 0 {
                        self.errors.push(e.to_string());
                    }
                    self.request_failures += 1;
                    vec![f64::NAN; names.len()]
                }
            },
        };
        self.csv.write(assembled.model, o, names, &values)
    }
}

pub fn run_simulate(args: &SimulateArgs) -> ExitCode {
    let loaded = match load(args.model, args.deactivate, Some(Analysis::Simulate)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let forces = match applied_forces(&loaded, Analysis::Simulate) {
        Ok(f) => f,
        Err(d) => return input_error(&d, args.format),
    };
    // REQUESTs only shape the CSV: they are resolved (and their errors reported) only when
    // one is written.
    let requests = match args.out.or(args.html) {
        Some(_) => match RequestSet::new(&loaded.model) {
            Ok(r) => Some(r),
            Err(d) => return input_error(&d, args.format),
        },
        None => None,
    };
    let times = match output_times(args.end, args.steps, args.dtout) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    // INTEGRATOR settings, resolved by the model (GSTIFF/WSTIFF run the BDF, HHT/NEWMARK
    // HHT-α, the other Adams names the BDF with a note); the simulate report carries its
    // notes and warnings.
    let integrator = &loaded.model.integrator;
    // A step size bound that would need more steps than any run can take is a typing error.
    match linkage_api::simulate::check_hmax(&loaded, args.end) {
        Ok(()) => {}
        Err(linkage_api::Error::Input(d)) => return input_error(&d, args.format),
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(e.exit_code());
        }
    }
    let bar = Progress::on_terminal();
    let end = args.end;
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    // Ctrl-C, or the time limit, stops the run after the step it is in (the CSV keeps every
    // row written).
    let deadline = args
        .time_limit
        .map(|secs| Instant::now() + std::time::Duration::from_secs_f64(secs));
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let mut csv = match args.out {
        None => None,
        Some(out) => {
            let sink: Box<dyn Write> = if is_stdout(out) {
                Box::new(std::io::BufWriter::new(std::io::stdout()))
            } else {
                match std::fs::File::create(out) {
                    Ok(f) => Box::new(std::io::BufWriter::new(f)),
                    Err(e) => {
                        eprintln!("error: cannot write {}: {e}", out.display());
                        return ExitCode::from(1);
                    }
                }
            };
            Some(CsvStream {
                csv: CsvHistory::new(sink),
                path: out.display().to_string(),
                requests: requests.as_ref().filter(|r| !r.is_empty()),
                names: requests
                    .as_ref()
                    .filter(|r| !r.is_empty())
                    .map(RequestSet::columns)
                    .unwrap_or_default(),
                request_failures: 0,
                errors: Vec::new(),
            })
        }
    };
    // The page keeps every k-th output (bounded memory) with its REQUEST values.
    let page_requests = requests.as_ref().filter(|r| !r.is_empty());
    let request_columns = page_requests.map(RequestSet::columns).unwrap_or_default();
    if let Err(e) = linkage_html::history::check_columns(&loaded.model, &request_columns, args.plot)
    {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let mut history = args.html.map(|_| {
        linkage_html::history::History::new(times.len(), request_columns.clone())
            .with_columns(args.plot.to_vec())
    });
    let mut write_error: Option<String> = None;
    let mut on_output = |o: &Output| {
        if let Some(h) = history.as_mut() {
            let values = page_requests
                .and_then(|r| r.evaluate(assembled.model, &assembled.system, o).ok())
                .unwrap_or_default();
            h.record(o, &values);
        }
        if let Some(c) = csv.as_mut() {
            if let Err(e) = c.write(&assembled, o) {
                write_error = Some(format!("cannot write {}: {e}", c.path));
                return AfterOutput::Stop;
            }
        }
        AfterOutput::Continue
    };
    let unstable = if args.allow_unstable {
        UnstableStart::Accept
    } else {
        UnstableStart::Refuse
    };
    let result = run_streamed(
        &assembled,
        &times,
        &integrator.settings,
        args.start,
        unstable,
        |p| match p {
            RunProgress::Settling { elapsed, limit } => bar.settling(elapsed, limit),
            RunProgress::Integrating(t) => bar.show(t / end, format!("t = {t:.4}")),
        },
        Stream {
            on_output: &mut on_output,
            stop: &|| {
                interrupt.load(Ordering::Relaxed) || deadline.is_some_and(|d| Instant::now() >= d)
            },
        },
    );
    bar.finish();
    let mut report = linkage_report::simulate::summary(&assembled, &result, &loaded.warnings);
    (report.left_out, report.runs_without) =
        crate::common::coverage_json(&loaded, Analysis::Simulate);
    if let Some(c) = csv.as_mut() {
        report.errors.append(&mut c.errors);
        if c.request_failures > 1 {
            report.errors.push(format!(
                "REQUEST columns are NaN at {} of {} outputs",
                c.request_failures,
                result.simulation.as_ref().map_or(0, |s| s.output_count)
            ));
        }
        if result
            .simulation
            .as_ref()
            .is_some_and(|s| s.output_count == 0)
        {
            // No output at all: the header alone, so the file says which columns it lacks.
            if let Err(e) = c.csv.finish_empty(&loaded.model) {
                report.errors.push(format!("cannot write {}: {e}", c.path));
            }
        }
    }
    if let Some(e) = write_error {
        report.errors.push(e);
    }
    if let (Some(secs), Some(d)) = (args.time_limit, deadline) {
        if Instant::now() >= d
            && result
                .simulation
                .as_ref()
                .is_some_and(|s| s.failure.is_some())
        {
            report.errors.push(format!(
                "the time limit of {secs} s was reached; the outputs up to it are written"
            ));
        }
    }
    if let (Some(out), Some(h)) = (args.html, history.as_mut()) {
        h.finish();
        let mut page = crate::html_out::page(&loaded.model, "simulate", &report, &[]);
        page.plots = h.plots(&loaded.model);
        page.notes.extend(h.note());
        page.notes.extend(h.plots_note(&loaded.model));
        page.animations.push(h.frames.clone());
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e);
        }
    }
    // With `--out -` the time histories are standard output: the summary goes to stderr.
    let csv_on_stdout = args.out.is_some_and(is_stdout);
    match (args.format, csv_on_stdout) {
        (Format::Text, false) => print!("{}", linkage_report::simulate::to_text(&report)),
        (Format::Text, true) => eprint!("{}", linkage_report::simulate::to_text(&report)),
        (Format::Json, false) => {
            print_json(&report);
        }
        (Format::Json, true) => match serde_json::to_string_pretty(&report) {
            Ok(j) => eprintln!("{j}"),
            Err(e) => eprintln!("error: cannot write JSON: {e}"),
        },
    }
    // The summary ends with its errors: repeated on standard error only when it was not shown
    // on a terminal (the summary is on standard error itself with `--out -`).
    let shown = csv_on_stdout || crate::common::stdout_is_terminal();
    crate::common::errors_to_stderr(&report.errors, shown);
    if report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
