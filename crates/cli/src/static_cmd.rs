//! `linkage static`: one static equilibrium at the start time, or a quasi-static series.

use crate::common::{input_error, load, output_times, print_json};
use crate::ic_cmd::save_configuration;
use clap::ValueEnum;
use linkage_api::sink::RequestFailure;
use linkage_api::{CsvSink, NoSink, OutputSink};
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::state::State;
use std::io::Write;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
pub enum StaticFormat {
    Text,
    Json,
    Csv,
}

/// Options of `linkage static`.
pub struct StaticArgs<'a> {
    pub model: &'a Path,
    pub format: StaticFormat,
    /// `(end time, steps)` for a quasi-static series.
    pub series: Option<(f64, usize)>,
    pub save: Option<&'a Path>,
    /// Find the equilibrium by damped dynamics (also when the dataset says EQUILIBRIUM/DYNAMIC).
    pub settle: bool,
    /// Accept an unstable equilibrium (exit 0); otherwise it is the run's failure.
    pub allow_unstable: bool,
    /// Wall-clock seconds after which damped settling stops (after the step it is in).
    pub time_limit: Option<f64>,
    /// Statements to leave out (`--deactivate`).
    pub deactivate: &'a [String],
    /// Where to write the HTML page (`--html`).
    pub html: Option<&'a Path>,
}

pub fn run_static(args: &StaticArgs) -> ExitCode {
    let json_errors = if args.format == StaticFormat::Json {
        crate::common::Format::Json
    } else {
        crate::common::Format::Text
    };
    let series = match args.series {
        Some((end, steps)) => match output_times(end, Some(steps), None) {
            Ok(t) => Some(t),
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        },
        None => None,
    };
    let api_args = linkage_api::statics::StaticArgs {
        series,
        settle: args.settle,
        allow_unstable: args.allow_unstable,
        time_limit: args.time_limit,
        interrupt: None,
    };
    let analysis = linkage_api::statics::analysis(&api_args);
    let loaded = match load(args.model, args.deactivate, Some(analysis)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, json_errors),
    };
    // `--format csv`: one row per equilibrium as it is found, on standard output (the
    // columns of `simulate --out`, the REQUESTs' among them).
    let mut csv = None;
    if args.format == StaticFormat::Csv {
        let requests = match RequestSet::new(&loaded.model) {
            Ok(r) => r,
            Err(d) => return input_error(&d, json_errors),
        };
        let out: Box<dyn Write> = Box::new(std::io::BufWriter::new(std::io::stdout()));
        csv = Some(CsvSink::new(
            out,
            "standard output".into(),
            &loaded.model,
            Some(&requests),
            RequestFailure::Nan,
        ));
    }
    // Ctrl-C stops a quasi-static series after the equilibrium it is at (the CSV keeps
    // every row written).
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&interrupt);
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let api_args = linkage_api::statics::StaticArgs {
        interrupt: Some(interrupt),
        ..api_args
    };
    let bar = crate::common::Progress::on_terminal();
    let sink: &mut dyn OutputSink = match csv.as_mut() {
        Some(c) => c,
        None => &mut NoSink,
    };
    let run = linkage_api::statics::run(
        &loaded,
        linkage_api::Start::Input,
        &api_args,
        &|elapsed, limit| bar.settling(elapsed, limit),
        sink,
    );
    bar.finish();
    let run = match run {
        Ok(r) => r,
        Err(e) => return crate::common::analysis_error(&e, json_errors),
    };
    let mut report = run.report;
    if let Some(c) = csv.as_mut() {
        report.errors.extend(c.close(&loaded.model, c.written));
    }
    let ok = run.ok;
    if let (Some(out), true) = (args.save, ok) {
        if let Some(state) = &run.state {
            if let Err(e) = save_configuration(&loaded.dataset, &loaded.model, state, out) {
                report
                    .errors
                    .push(format!("cannot write {}: {e}", out.display()));
            }
        }
    } else if let (Some(out), false) = (args.save, run.settled) {
        report.errors.push(format!(
            "{} not written: no equilibrium was accepted",
            out.display()
        ));
    }
    if let Some(out) = args.html {
        let mut page = crate::html_out::page(&loaded.model, "static", &report, &[]);
        let series = if run.settled {
            (None, Vec::new())
        } else {
            linkage_html::series::statics_series(&loaded.model, &report)
        };
        match series {
            (Some(frames), plots) => {
                page.animations.push(frames);
                page.plots = plots;
            }
            (None, _) => {
                // One equilibrium: from the input configuration to it, and (Newton) the
                // largest force imbalance of each iteration.
                if !run.imbalance_history.is_empty() {
                    page.plots.push(linkage_html::series::imbalance_plot(
                        &loaded.model,
                        &run.imbalance_history,
                    ));
                }
                let input = State::input(&loaded.model);
                let states: Vec<&State> =
                    std::iter::once(&input).chain(run.state.as_ref()).collect();
                let title = if run.settled {
                    "input → settled, time"
                } else {
                    "input → equilibrium, time"
                };
                page.animations
                    .push(crate::html_out::frames_of_states(title, states.into_iter()));
            }
        }
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e.to_string());
        }
    }
    match args.format {
        StaticFormat::Json => {
            print_json(&report);
        }
        // The rows are written.
        StaticFormat::Csv => {}
        StaticFormat::Text => print!("{}", linkage_report::statics::to_text(&report)),
    }
    // CSV rows carry no errors: they always go to standard error.
    let shown = args.format != StaticFormat::Csv && crate::common::stdout_is_terminal();
    crate::common::errors_to_stderr(&report.errors, shown);
    let passed = if run.settled {
        report.converged && report.errors.is_empty()
    } else {
        ok && report.errors.is_empty()
    };
    if passed {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
