//! Dynamic simulation of a loaded model: the summary report, and the time histories streamed
//! as CSV (part states, reactions, then the dataset's REQUEST outputs) row by row.

use crate::error::Error;
use crate::sink::{CsvSink, Feed, NoSink, OutputSink, RequestFailure, RequestValues, SinkError};
use crate::source::Loaded;
use crate::start::{assemble, input_model, Left, Start};
use linkage_report::simulate::SimulateJson;
use linkage_solve::coverage::Analysis;
use linkage_solve::physics::applied::Regime;
use linkage_solve::physics::requests::RequestSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{
    continue_streamed, run_streamed, AfterOutput, Continue, IntegrationError, Output, RunProgress,
    StepTaken, Stream, UnstableStart,
};
use std::io::Write;
use std::time::Instant;

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
    pub start: linkage_solve::stages::dynamics::Start,
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

/// The CSV of `--out`: opened when the analysis has its assembly (input errors first), then
/// written row by row ([`CsvSink`]: NaN request columns where a request cannot be evaluated).
struct CsvFile<'m> {
    target: Option<CsvTarget>,
    model: &'m linkage_model::Model,
    requests: Option<&'m RequestSet>,
    sink: Option<CsvSink<Box<dyn Write>>>,
}

impl OutputSink for CsvFile<'_> {
    fn wants_requests(&self) -> bool {
        self.requests.is_some()
    }

    fn assembled(&mut self, _: &Assembled, _: bool) -> Result<(), SinkError> {
        if let Some(target) = self.target.take() {
            let out = (target.open)().map_err(|cause| SinkError::Write {
                path: target.name.clone(),
                cause,
            })?;
            self.sink = Some(CsvSink::new(
                out,
                target.name,
                self.model,
                self.requests,
                RequestFailure::Nan,
            ));
        }
        Ok(())
    }

    fn output(&mut self, a: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        match self.sink.as_mut() {
            Some(s) => s.output(a, o, r),
            None => Ok(()),
        }
    }
}

/// The observer of [`SimulateArgs::observe`] as a sink.
struct Observed<'o, 'a> {
    observe: &'o mut Observer<'a>,
}

impl OutputSink for Observed<'_, '_> {
    fn wants_requests(&self) -> bool {
        true
    }

    fn output(&mut self, _: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        let values = match r {
            Some(Ok(v)) => v.as_slice(),
            _ => &[],
        };
        (self.observe)(o, values);
        Ok(())
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

/// `linkage simulate --format json` of `loaded` from its input, the time histories streamed to
/// `args.csv`. The summary's `errors` are the verdict.
pub fn simulate(loaded: &Loaded, args: SimulateArgs) -> Result<SimulateJson, Error> {
    run(loaded, Start::Input, args, &mut NoSink).map(|r| r.report)
}

/// What a simulation gave.
pub struct SimulateRun {
    /// `linkage simulate --format json`.
    pub report: SimulateJson,
    /// Where the run leaves the model: its last output (`None` when it wrote none).
    pub left: Option<Left>,
    /// The run was stopped by `args.interrupted` (Ctrl-C) or the time limit.
    pub interrupted: bool,
    /// An output could not be written to `sink`: the run stopped there.
    pub sink_error: Option<SinkError>,
    /// The integrator's work (`None` when nothing was integrated).
    pub statistics: Option<Statistics>,
}

/// What a simulation's integrator did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Statistics {
    /// Kinematic analysis (no degrees of freedom) rather than integration.
    pub kinematic: bool,
    pub steps: usize,
    pub rejected: usize,
    pub corrector_iterations: usize,
    pub factorisations: usize,
    /// Outputs handed on.
    pub outputs: usize,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
}

/// A simulation of `loaded` from `start` to the last of `args.times` (the start's own time
/// among them gives an output there), every output handed to `sink` (and to `args.csv` and
/// `args.observe`). From the input, or a state left on a changed model, the model is
/// assembled first; from a state left on the same assembly the run continues from it.
pub fn run(
    loaded: &Loaded,
    start: Start,
    args: SimulateArgs,
    sink: &mut dyn OutputSink,
) -> Result<SimulateRun, Error> {
    // The refusals first, all at once.
    loaded.forces(Analysis::Simulate)?;
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
    check_hmax(loaded, end - start.time())?;
    let deadline =
        crate::budget::deadline(args.time_limit, crate::budget::DEFAULT_SIMULATE_TIME_LIMIT)
            .map_err(crate::error::ArgumentError::from)?;
    let mut csv = CsvFile {
        target: args.csv,
        model: &loaded.model,
        requests: requests.as_ref().filter(|r| !r.is_empty()),
        sink: None,
    };
    let mut observe = args.observe;
    let mut observed = observe.as_mut().map(|o| Observed { observe: &mut **o });
    let mut sinks: Vec<&mut dyn OutputSink> = vec![sink, &mut csv];
    if let Some(o) = observed.as_mut() {
        sinks.push(o);
    }
    let mut tee = crate::sink::Tee(sinks);
    let mut feed = Feed::new(&loaded.model, &mut tee)?;
    let model = input_model(loaded, &start);
    let begun = assemble(loaded, model.as_ref(), start, Analysis::Simulate)?;
    let assembled_now = begun.assembled_now();
    let from = begun.from;
    let assembled = begun.assembled;
    let mut sink_error = feed.assembled(&assembled, assembled_now).err();
    let unopened = sink_error.is_some();
    let mut last: Option<Output> = None;
    // The integrator's last accepted step, handed on before each output.
    let taken = std::cell::Cell::new(StepTaken::default());
    let mut on_step = |s: &StepTaken| taken.set(*s);
    let mut on_output = |o: &Output| {
        feed.steps_so_far(&taken.get());
        if let Err(e) = feed.output(&assembled, o) {
            sink_error = Some(e);
            return AfterOutput::Stop;
        }
        last = Some(o.clone());
        AfterOutput::Continue
    };
    let unstable = if args.allow_unstable {
        UnstableStart::Accept
    } else {
        UnstableStart::Refuse
    };
    let interrupted = args.interrupted;
    let clock = Instant::now();
    let stream = Stream {
        on_output: &mut on_output,
        stop: &|| interrupted() || Instant::now() >= deadline,
        on_step: Some(&mut on_step),
    };
    let result = match (&from, unopened) {
        (_, true) => linkage_solve::stages::dynamics::DynamicRun {
            equilibrium: None,
            simulation: None,
            error: None,
        },
        (Some((state, velocities)), false) => continue_streamed(
            &assembled,
            args.times,
            &integrator.settings,
            Continue { state, velocities },
            args.progress,
            stream,
        ),
        (None, false) => run_streamed(
            &assembled,
            args.times,
            &integrator.settings,
            args.start,
            unstable,
            args.progress,
            stream,
        ),
    };
    let seconds = clock.elapsed().as_secs_f64();
    let statistics = result.simulation.as_ref().map(|sim| Statistics {
        kinematic: sim.kinematic,
        steps: sim.steps,
        rejected: sim.rejected,
        corrector_iterations: sim.newton_iterations,
        factorisations: sim.factorisations,
        outputs: sim.output_count,
        seconds,
    });
    let mut report = linkage_report::simulate::summary(&assembled, &result, &loaded.warnings);
    if from.is_some() {
        // A command file's run on the last analysis's assembly, from the state it left.
        report.start.from = "continued";
    }
    if let Some(last) = result.simulation.as_ref().and_then(|s| s.outputs.last()) {
        let values =
            assembled
                .forces
                .friction_values(Regime::Dynamic, &last.state, &last.velocities);
        report.frictions = linkage_report::friction::frictions_json(&loaded.model, &values);
        let contacts = linkage_solve::constraints::curve_contacts::curve_contacts(
            &loaded.model,
            &assembled.system,
            &last.state,
        );
        report.curve_contacts =
            linkage_report::curve_contacts::curve_contacts_json(&loaded.model, &contacts);
    }
    (report.left_out, report.runs_without) = loaded.coverage(Analysis::Simulate);
    if let Some(c) = csv.sink.as_mut() {
        let outputs = result.simulation.as_ref().map_or(0, |s| s.output_count);
        report.errors.extend(c.close(&loaded.model, outputs));
    }
    if let Some(e) = &sink_error {
        report.errors.push(e.to_string());
    }
    let stopped = result
        .simulation
        .as_ref()
        .and_then(|s| s.failure.as_ref())
        .is_some_and(|f| matches!(f.cause, IntegrationError::Stopped));
    let out_of_time = Instant::now() >= deadline;
    if out_of_time && stopped {
        report.errors.push(match args.time_limit {
            Some(secs) => {
                format!("the time limit of {secs} s was reached; the outputs up to it are written")
            }
            None => format!(
                "the default wall-clock limit of {} s was reached (--time-limit sets another); \
                 the outputs up to it are written",
                crate::budget::DEFAULT_SIMULATE_TIME_LIMIT
            ),
        });
    }
    let left = last.map(|o| Left {
        state: o.state,
        velocities: o.velocities,
        assembly: None,
    });
    let left = left.map(|mut l| {
        l.assembly = Some(assembled.into_assembly());
        l
    });
    Ok(SimulateRun {
        report,
        left,
        interrupted: stopped && !out_of_time,
        sink_error,
        statistics,
    })
}
