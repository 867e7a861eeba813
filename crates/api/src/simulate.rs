//! Dynamic simulation of a loaded model: the summary report, and the time histories streamed
//! as CSV (part states, reactions, then the dataset's REQUEST outputs) row by row.

use crate::error::Error;
use crate::source::{applied_forces, coverage_json, Loaded};
use linkage_report::element_columns;
use linkage_report::simulate::{CsvHistory, SimulateJson};
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::applied::AppliedForces;
use linkage_solve::physics::requests::{RequestAngles, RequestSet};
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{
    run_streamed, AfterOutput, Output, RunProgress, Start, Stream, UnstableStart,
};
use linkage_solve::tolerances::Tolerances;
use std::io::Write;
use std::time::{Duration, Instant};

/// The most integration steps an HMAX may imply (about a day of computing for a small model).
const MAX_STEPS: f64 = 1e9;

/// Where the time histories go: opened only once the model is known to run (so that input
/// errors come first), named `name` in messages.
pub struct CsvTarget {
    pub name: String,
    pub open: Box<dyn FnOnce() -> std::io::Result<Box<dyn Write>> + Send>,
}

/// A front end's view of each output and its REQUEST values (see
/// [`SimulateArgs::observe`]).
pub type Observer<'o> = dyn FnMut(&Output, &[f64]) + 'o;

/// What `linkage simulate` asks for (the output times already from `--end`/`--steps`/`--dtout`).
pub struct SimulateArgs<'a> {
    pub times: &'a [f64],
    pub start: Start,
    /// Start from an unstable equilibrium rather than stop (with an equilibrium start).
    pub allow_unstable: bool,
    /// Wall-clock seconds after which the run stops (after the step it is in).
    pub time_limit: Option<f64>,
    /// The time histories (`--out`).
    pub csv: Option<CsvTarget>,
    /// Told how far the run has come.
    pub progress: &'a mut dyn FnMut(RunProgress),
    /// Stops the run after the step it is in when true (Ctrl-C).
    pub interrupted: &'a dyn Fn() -> bool,
    /// Called with every output and its REQUEST values (empty when the model has none): how
    /// a front end keeps a history of its own (the CLI's `--html` page).
    pub observe: Option<&'a mut Observer<'a>>,
}

/// The CSV of `--out`, written row by row as the outputs come (bounded memory whatever their
/// number; each row flushed, so a run that stops keeps whole rows). REQUEST columns follow the
/// part and reaction columns; an output where a request cannot be evaluated gets NaN in every
/// request column, and the first such error is reported (the run then has an error).
struct CsvStream<'r> {
    csv: CsvHistory<Box<dyn Write>>,
    path: String,
    requests: Option<&'r RequestSet>,
    /// The forces, for the FRICTION columns after the requests'.
    forces: &'r dyn AppliedForces,
    /// How many of `names` are REQUEST columns (the element columns follow).
    request_columns: usize,
    /// The request columns (once: they do not change during the run).
    names: Vec<String>,
    request_failures: usize,
    errors: Vec<String>,
    /// The REQUEST angles of the last row, which the next continues.
    angles: RequestAngles,
}

impl CsvStream<'_> {
    fn write(&mut self, assembled: &Assembled, o: &Output) -> std::io::Result<()> {
        let names = &self.names;
        let requests = self.request_columns;
        let mut values = match self.requests {
            None => Vec::new(),
            Some(r) => {
                match r.evaluate_continuing(assembled.model, &assembled.system, o, &mut self.angles)
                {
                    Ok(v) => v,
                    Err(e) => {
                        if self.request_failures == 0 {
                            self.errors.push(e.to_string());
                        }
                        self.request_failures += 1;
                        vec![f64::NAN; requests]
                    }
                }
            }
        };
        let frictions = if assembled.model.frictions.is_empty() {
            Vec::new()
        } else {
            self.forces.friction_values(&o.state, &o.velocities)
        };
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            assembled.model,
            &assembled.system,
            &o.state,
        );
        element_columns::values(
            assembled.model,
            &frictions,
            &contacts,
            &o.state,
            &mut values,
        );
        self.csv.write(assembled.model, o, names, &values)
    }
}

/// An HMAX that would need more steps than any run can take over `end` (a typing error),
/// placed at the HMAX argument of the INTEGRATOR statement that set it.
pub fn check_hmax(loaded: &Loaded, end: f64) -> Result<(), Error> {
    let Some(hmax) = loaded.model.integrator.settings.hmax else {
        return Ok(());
    };
    let steps = end / hmax;
    if steps <= MAX_STEPS {
        return Ok(());
    }
    let at = loaded
        .dataset
        .statements
        .iter()
        .rev()
        .filter(|st| st.keyword == "INTEGRATOR")
        .find_map(|st| st.args.iter().find(|a| a.key == "HMAX").map(|a| a.span));
    let d = linkage_adm::Diagnostic::error(
        loaded.dataset.file.clone(),
        at,
        format!(
            "INTEGRATOR HMAX = {} over --end {end} needs at least {} steps (at most {} are \
             allowed)",
            linkage_adm::num::general(hmax, 6),
            linkage_adm::num::sci(steps, 4),
            linkage_adm::num::general(MAX_STEPS, 6)
        ),
    );
    Err(Error::Input(linkage_adm::Diagnostics(vec![d])))
}

/// `linkage simulate --format json` of `loaded`, the time histories streamed to `args.csv`.
/// The summary's `errors` are the verdict.
pub fn simulate(loaded: &Loaded, args: SimulateArgs) -> Result<SimulateJson, Error> {
    let forces = applied_forces(loaded, Analysis::Simulate)?;
    // REQUESTs only shape the CSV: they are resolved (and their errors reported) only when
    // one is written.
    let requests = match (&args.csv, &args.observe) {
        (None, None) => None,
        _ => Some(RequestSet::new(&loaded.model)?),
    };
    let end = args.times.last().copied().unwrap_or(0.0);
    // INTEGRATOR settings, resolved by the model (GSTIFF/WSTIFF run the BDF, HHT/NEWMARK
    // HHT-α, the other Adams names the BDF with a note); the report carries its notes.
    let integrator = &loaded.model.integrator;
    check_hmax(loaded, end)?;
    let assembled = Assembled::new(
        &loaded.model,
        &loaded.drivers,
        forces.as_ref(),
        &Tolerances::default(),
    );
    let deadline = args
        .time_limit
        .map(|secs| Instant::now() + Duration::from_secs_f64(secs));
    let mut csv = match args.csv {
        None => None,
        Some(target) => {
            let sink = (target.open)()
                .map_err(|e| Error::Output(format!("cannot write {}: {e}", target.name)))?;
            let requests = requests.as_ref().filter(|r| !r.is_empty());
            let mut names = requests.map(RequestSet::columns).unwrap_or_default();
            let request_columns = names.len();
            names.extend(element_columns::names(&loaded.model));
            Some(CsvStream {
                csv: CsvHistory::new(sink),
                path: target.name,
                requests,
                forces: forces.as_ref(),
                request_columns,
                names,
                request_failures: 0,
                errors: Vec::new(),
                angles: RequestAngles::new(),
            })
        }
    };
    let mut write_error: Option<String> = None;
    let mut observe = args.observe;
    let observed_requests = requests.as_ref().filter(|r| !r.is_empty());
    let mut on_output = |o: &Output| {
        if let Some(f) = observe.as_mut() {
            let values = observed_requests
                .and_then(|r| r.evaluate(assembled.model, &assembled.system, o).ok())
                .unwrap_or_default();
            f(o, &values);
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
    let interrupted = args.interrupted;
    let result = run_streamed(
        &assembled,
        args.times,
        &integrator.settings,
        args.start,
        unstable,
        args.progress,
        Stream {
            on_output: &mut on_output,
            stop: &|| interrupted() || deadline.is_some_and(|d| Instant::now() >= d),
        },
    );
    let mut report = linkage_report::simulate::summary(&assembled, &result, &loaded.warnings);
    if let Some(last) = result.simulation.as_ref().and_then(|s| s.outputs.last()) {
        let values = forces.friction_values(&last.state, &last.velocities);
        report.frictions = linkage_report::friction::frictions_json(&loaded.model, &values);
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            &loaded.model,
            &assembled.system,
            &last.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(&loaded.model, &contacts);
    }
    (report.left_out, report.runs_without) = coverage_json(loaded, Analysis::Simulate);
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
    Ok(report)
}
