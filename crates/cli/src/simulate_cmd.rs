//! `linkage simulate`: dynamic simulation with output at requested times; the CSV gets the
//! dataset's REQUEST outputs as extra columns.

use crate::common::{
    applied_forces, input_error, is_stdout, load, output_times, print_json, Format, Progress,
};
use linkage_report::simulate::ExtraColumns;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run_from, DynamicRun, RunProgress, Start, UnstableStart};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::process::ExitCode;

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
}

/// The most integration steps an HMAX may imply (about a day of computing for a small model).
const MAX_STEPS: f64 = 1e9;

/// REQUEST columns at every output. An output where a request cannot be evaluated gets NaN in
/// every request column; the first such error is reported (the run then exits with 1).
fn request_columns(
    requests: &RequestSet,
    assembled: &Assembled,
    run: &DynamicRun,
    errors: &mut Vec<String>,
) -> ExtraColumns {
    let names = requests.columns();
    let outputs = run.simulation.as_ref().map_or(&[][..], |s| &s.outputs[..]);
    let mut failed = 0usize;
    let values = outputs
        .iter()
        .map(
            |o| match requests.evaluate(assembled.model, &assembled.system, o) {
                Ok(v) => v,
                Err(e) => {
                    if failed == 0 {
                        errors.push(e.to_string());
                    }
                    failed += 1;
                    vec![f64::NAN; names.len()]
                }
            },
        )
        .collect();
    if failed > 1 {
        errors.push(format!(
            "REQUEST columns are NaN at {failed} of {} outputs",
            outputs.len()
        ));
    }
    (names, values)
}

pub fn run_simulate(args: &SimulateArgs) -> ExitCode {
    let loaded = match load(args.model) {
        Ok(l) => l,
        Err(d) => return input_error(&d, args.format),
    };
    let forces = match applied_forces(&loaded) {
        Ok(f) => f,
        Err(d) => return input_error(&d, args.format),
    };
    // REQUESTs only shape the CSV: they are resolved (and their errors reported) only when
    // one is written.
    let requests = match args.out {
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
    // INTEGRATOR settings, resolved by the model (every Adams integrator name is mapped to
    // HHT); the simulate report carries its notes and warnings.
    let integrator = &loaded.model.integrator;
    // A step size bound that would need more steps than any run can take is a typing error.
    if let Some(hmax) = integrator.settings.hmax {
        let steps = args.end / hmax;
        if steps > MAX_STEPS {
            eprintln!(
                "error: INTEGRATOR HMAX = {hmax:e} over --end {} needs at least {steps:.3e} steps \
                 (at most {MAX_STEPS:.0e} are allowed)",
                args.end
            );
            return ExitCode::from(2);
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
    let unstable = if args.allow_unstable {
        UnstableStart::Accept
    } else {
        UnstableStart::Refuse
    };
    let result = run_from(
        &assembled,
        &times,
        &integrator.settings,
        args.start,
        unstable,
        |p| match p {
            RunProgress::Settling { elapsed, limit } => bar.settling(elapsed, limit),
            RunProgress::Integrating(t) => bar.show(t / end, format!("t = {t:.4}")),
        },
    );
    bar.finish();
    let mut report = linkage_report::simulate::summary(&assembled, &result, &loaded.warnings);
    if let Some(out) = args.out {
        let extra = requests
            .as_ref()
            .filter(|r| !r.is_empty())
            .map(|r| request_columns(r, &assembled, &result, &mut report.errors));
        let csv = linkage_report::simulate::to_csv(&loaded.model, &result, extra.as_ref());
        if is_stdout(out) {
            print!("{csv}");
        } else if let Err(e) = linkage_adm::writer::write_atomically(out, &csv) {
            report
                .errors
                .push(format!("cannot write {}: {e}", out.display()));
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
