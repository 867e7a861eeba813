//! `linkage simulate`: dynamic simulation with output at requested times; the CSV gets the
//! dataset's REQUEST outputs as extra columns.

use crate::common::{input_error, is_stdout, load, output_times, print_json, Format, Progress};
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::stages::dynamics::{Output, RunProgress, Start};
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

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

pub fn run_simulate(args: &SimulateArgs) -> ExitCode {
    let loaded = match load(args.model, args.deactivate, Some(Analysis::Simulate)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let times = match output_times(args.end, args.steps, args.dtout) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    // The page keeps every k-th output (bounded memory) with its REQUEST values.
    let mut history = match args.html {
        None => None,
        Some(_) => {
            let columns = match RequestSet::new(&loaded.model) {
                Ok(r) => r.columns(),
                Err(d) => return input_error(&d, args.format),
            };
            if let Err(e) = linkage_html::history::check_columns(&loaded.model, &columns, args.plot)
            {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
            Some(
                linkage_html::history::History::new(times.len(), columns)
                    .with_columns(args.plot.to_vec()),
            )
        }
    };
    let bar = Progress::on_terminal();
    let end = args.end;
    // Ctrl-C, or the time limit, stops the run after the step it is in (the CSV keeps every
    // row written).
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let csv = args.out.map(|out| {
        let path = out.to_path_buf();
        linkage_api::simulate::CsvTarget {
            name: out.display().to_string(),
            open: Box::new(move || -> std::io::Result<Box<dyn Write>> {
                if is_stdout(&path) {
                    Ok(Box::new(std::io::BufWriter::new(std::io::stdout())))
                } else {
                    Ok(Box::new(std::io::BufWriter::new(std::fs::File::create(
                        &path,
                    )?)))
                }
            }),
        }
    });
    let mut record = |o: &Output, values: &[f64]| {
        if let Some(h) = history.as_mut() {
            h.record(o, values);
        }
    };
    let result = linkage_api::simulate::simulate(
        &loaded,
        linkage_api::simulate::SimulateArgs {
            times: &times,
            start: args.start,
            allow_unstable: args.allow_unstable,
            time_limit: args.time_limit,
            csv,
            progress: &mut |p| match p {
                RunProgress::Settling { elapsed, limit } => bar.settling(elapsed, limit),
                RunProgress::Integrating(t) => bar.show(t / end, format!("t = {t:.4}")),
            },
            interrupted: &|| interrupt.load(Ordering::Relaxed),
            observe: args
                .html
                .is_some()
                .then_some(&mut record as &mut linkage_api::simulate::Observer<'_>),
        },
    );
    bar.finish();
    let mut report = match result {
        Ok(r) => r,
        Err(e) => return crate::common::analysis_error(&e, args.format),
    };
    if let (Some(out), Some(h)) = (args.html, history.as_mut()) {
        h.finish();
        let mut page = crate::html_out::page(&loaded.model, "simulate", &report, &[]);
        page.plots = h.plots(&loaded.model);
        page.notes.extend(h.note());
        page.notes.extend(h.plots_note(&loaded.model));
        page.animations.push(h.frames.clone());
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e.to_string());
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
