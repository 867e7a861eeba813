//! `linkage static`: one static equilibrium at the start time, or a quasi-static series.

use crate::common::{input_error, load, print_json, Loaded};
use crate::ic_cmd::save_configuration;
use clap::ValueEnum;
use linkage_adm::Diagnostics;
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::applied::AppliedForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::statics::run;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

#[derive(Clone, Copy, ValueEnum, PartialEq, Eq, Debug)]
pub enum StaticFormat {
    Text,
    Json,
    Csv,
}

/// Options of `linkage static`.
/// Wall-clock seconds after which damped settling stops when `--time-limit` is not given.
pub use linkage_api::statics::DEFAULT_SETTLE_TIME_LIMIT;

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

/// Adds the unstable-equilibrium verdict to `report` unless `allow` (see
/// [`linkage_report::statics::unstable_verdict`]).
fn judge_stability(report: &mut linkage_report::statics::StaticJson, allow: bool) {
    if allow {
        return;
    }
    if let Some(why) = linkage_report::statics::unstable_verdict(report) {
        report.errors.push(why);
    }
}

/// The model's applied force elements.
fn forces(loaded: &Loaded, analysis: Analysis) -> Result<Box<dyn AppliedForces>, Diagnostics> {
    crate::common::applied_forces(loaded, analysis)
}

/// Fills in what the report says about left-out statements and those it ran without.
fn with_coverage(
    mut report: linkage_report::statics::StaticJson,
    loaded: &Loaded,
    analysis: Analysis,
) -> linkage_report::statics::StaticJson {
    (report.left_out, report.runs_without) = crate::common::coverage_json(loaded, analysis);
    report
}

pub fn run_static(args: &StaticArgs) -> ExitCode {
    let json_errors = if args.format == StaticFormat::Json {
        crate::common::Format::Json
    } else {
        crate::common::Format::Text
    };
    let analysis = if args.series.is_some() {
        Analysis::QuasiStatic
    } else {
        Analysis::Static
    };
    let loaded = match load(args.model, args.deactivate, Some(analysis)) {
        Ok(l) => l,
        Err(d) => return input_error(&d, json_errors),
    };
    let applied = match forces(&loaded, analysis) {
        Ok(f) => f,
        Err(d) => return input_error(&d, json_errors),
    };
    let assemble = || {
        Assembled::new(
            &loaded.model,
            &loaded.drivers,
            applied.as_ref(),
            &Tolerances::default(),
        )
    };
    if args.settle || (loaded.model.equilibrium.dynamic && args.series.is_none()) {
        let assembled = assemble();
        let bar = crate::common::Progress::on_terminal();
        let limit = loaded.model.equilibrium.settling_time;
        // Damped settling cannot bound its own wall-clock time (its steps shrink without end
        // on a model that chatters): without --time-limit, a default guard stops it.
        let limit_secs = args.time_limit.unwrap_or(DEFAULT_SETTLE_TIME_LIMIT);
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs_f64(limit_secs);
        let out_of_time = || std::time::Instant::now() >= deadline;
        let settled = linkage_solve::stages::settle::settle_until(
            &assembled,
            |elapsed| bar.settling(elapsed, limit),
            &out_of_time,
        );
        bar.finish();
        let eq_state = settled
            .as_ref()
            .ok()
            .and_then(|o| o.settled_equilibrium())
            .map(|e| e.state.clone());
        let mut report = with_coverage(
            linkage_report::statics::settling_json(&assembled, settled, &loaded.warnings),
            &loaded,
            analysis,
        );
        judge_stability(&mut report, args.allow_unstable);
        if out_of_time() && !report.errors.is_empty() {
            report.errors.push(match args.time_limit {
                Some(secs) => format!("the time limit of {secs} s was reached while settling"),
                None => format!(
                    "the default wall-clock guard of {DEFAULT_SETTLE_TIME_LIMIT} s was reached \
                     while settling (--time-limit S sets another)"
                ),
            });
        }
        if let (Some(out), Some(state)) = (args.save, &eq_state) {
            if report.converged && report.errors.is_empty() {
                if let Err(e) = save_configuration(&loaded.dataset, &loaded.model, state, out) {
                    report
                        .errors
                        .push(format!("cannot write {}: {e}", out.display()));
                }
            }
        }
        if let Some(out) = args.html {
            let mut page = crate::html_out::page(&loaded.model, "static", &report, &[]);
            let input = linkage_solve::state::State::input(&loaded.model);
            let states: Vec<&linkage_solve::state::State> =
                std::iter::once(&input).chain(eq_state.as_ref()).collect();
            page.animations.push(crate::html_out::frames_of_states(
                "input → settled, time",
                states.into_iter(),
            ));
            if let Err(e) = crate::html_out::write(&page, out) {
                report.errors.push(e);
            }
        }
        match args.format {
            StaticFormat::Json => {
                print_json(&report);
            }
            _ => print!("{}", linkage_report::statics::to_text(&report)),
        }
        crate::common::errors_to_stderr(&report.errors, crate::common::stdout_is_terminal());
        return if report.converged && report.errors.is_empty() {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        };
    }
    let times = match args.series {
        Some((end, steps)) => match crate::common::output_times(end, Some(steps), None) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        },
        None => vec![0.0],
    };
    let assembled = assemble();
    let result = run(&assembled, &times);
    let mut report = with_coverage(
        linkage_report::statics::to_json(&assembled, &result, &loaded.warnings),
        &loaded,
        analysis,
    );
    judge_stability(&mut report, args.allow_unstable);
    let ok = result.converged() && report.errors.is_empty();
    if let (Some(out), true) = (args.save, ok) {
        if let Some((_, Ok(eq))) = result.steps.last() {
            if let Err(e) = save_configuration(&loaded.dataset, &loaded.model, &eq.state, out) {
                report
                    .errors
                    .push(format!("cannot write {}: {e}", out.display()));
            }
        }
    } else if let Some(out) = args.save {
        report.errors.push(format!(
            "{} not written: no equilibrium was accepted",
            out.display()
        ));
    }
    if let Some(out) = args.html {
        let mut page = crate::html_out::page(&loaded.model, "static", &report, &[]);
        match linkage_html::series::statics_series(&loaded.model, &report) {
            (Some(frames), plots) => {
                page.animations.push(frames);
                page.plots = plots;
            }
            (None, _) => {
                // One equilibrium: from the input configuration to it, and the largest force
                // imbalance of each Newton iteration.
                let input = linkage_solve::state::State::input(&loaded.model);
                let eq = result.steps.last().and_then(|(_, e)| e.as_ref().ok());
                if let Some(e) = eq.filter(|e| !e.imbalance_history.is_empty()) {
                    page.plots.push(linkage_html::series::imbalance_plot(
                        &loaded.model,
                        &e.imbalance_history,
                    ));
                }
                let states: Vec<&linkage_solve::state::State> = std::iter::once(&input)
                    .chain(eq.map(|e| &e.state))
                    .collect();
                page.animations.push(crate::html_out::frames_of_states(
                    "input → equilibrium, time",
                    states.into_iter(),
                ));
            }
        }
        if let Err(e) = crate::html_out::write(&page, out) {
            report.errors.push(e);
        }
    }
    match args.format {
        StaticFormat::Text => print!("{}", linkage_report::statics::to_text(&report)),
        StaticFormat::Json => {
            print_json(&report);
        }
        StaticFormat::Csv => print!(
            "{}",
            linkage_report::statics::to_csv(&loaded.model, &result)
        ),
    }
    // CSV rows carry no errors: they always go to standard error.
    let shown = args.format != StaticFormat::Csv && crate::common::stdout_is_terminal();
    crate::common::errors_to_stderr(&report.errors, shown);
    if ok && report.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
