//! Where the outputs of an analysis go: one trait every front end implements.
//!
//! An analysis hands each output it computes (an IC, each equilibrium of a static or
//! quasi-static analysis, each output time of a simulation) to an [`OutputSink`] as soon as
//! it has it, with the dataset's REQUEST values evaluated once for every sink that reads them.
//! Implementations: [`CsvSink`] (the CSV of `linkage simulate --out`, Python and sweeps), the
//! command file's `.req`/`.csv` records (`linkage-run`), the HTML page's history (the CLI),
//! [`Tee`] to feed several, [`NoSink`] for none.
//!
//! A CSV row is: time, each part's CM position, 3-1-3 angles and velocities, each constraint
//! element's reaction on its I marker ([`linkage_report::simulate::CsvHistory`]), then
//! [`row_values`]: the REQUEST components, then each FRICTION's, curve contact's and control
//! state's columns ([`linkage_report::element_columns`]).

use linkage_model::Model;
use linkage_report::element_columns;
use linkage_report::simulate::CsvHistory;
use linkage_solve::physics::applied::Regime;
use linkage_solve::physics::requests::{RequestAngles, RequestError, RequestSet};
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{Output, StepTaken};
use std::io::Write;

/// An output stopped the analysis: why.
#[derive(Debug, thiserror::Error)]
pub enum SinkError {
    /// A REQUEST that cannot be evaluated (a sink that must have every value).
    #[error(transparent)]
    Request(#[from] RequestError),
    /// A file cannot be written.
    #[error("cannot write {path}: {cause}")]
    Write { path: String, cause: std::io::Error },
    /// The front end was asked to stop (Ctrl-C) after the output at `time`.
    #[error("interrupted at time {}", linkage_adm::num::time_text(*.time))]
    Interrupted { time: f64 },
}

/// The REQUEST values of an output: `None` when no sink asked for them, else their values
/// or why they cannot be evaluated.
pub type RequestValues<'a> = Option<&'a Result<Vec<f64>, RequestError>>;

/// A receiver of an analysis's outputs.
pub trait OutputSink {
    /// Whether [`OutputSink::output`] reads the REQUEST values (they are then evaluated for
    /// it; an input error in a REQUEST stops the analysis before it starts).
    fn wants_requests(&self) -> bool {
        false
    }

    /// The analysis has its assembled problem (compiled and assembled now when `now`, else
    /// the last analysis's taken over), before its first output.
    fn assembled(&mut self, _a: &Assembled, _now: bool) -> Result<(), SinkError> {
        Ok(())
    }

    /// A simulation's integrator at the output that follows: the last step it accepted, with
    /// the counts so far (a message file's step table); before the first step, zeros. Called
    /// before every [`OutputSink::output`] of a simulation, by no other analysis.
    fn steps_so_far(&mut self, _at: &StepTaken) {}

    /// One output on `a` with its REQUEST values (see [`OutputSink::wants_requests`]). An
    /// error stops the analysis after this output.
    fn output(
        &mut self,
        a: &Assembled,
        o: &Output,
        requests: RequestValues,
    ) -> Result<(), SinkError>;
}

/// No outputs kept.
pub struct NoSink;

impl OutputSink for NoSink {
    fn output(&mut self, _: &Assembled, _: &Output, _: RequestValues) -> Result<(), SinkError> {
        Ok(())
    }
}

/// Every output to each of several sinks, in order.
pub struct Tee<'s>(pub Vec<&'s mut dyn OutputSink>);

impl OutputSink for Tee<'_> {
    fn wants_requests(&self) -> bool {
        self.0.iter().any(|s| s.wants_requests())
    }

    fn assembled(&mut self, a: &Assembled, now: bool) -> Result<(), SinkError> {
        self.0.iter_mut().try_for_each(|s| s.assembled(a, now))
    }

    fn steps_so_far(&mut self, at: &StepTaken) {
        self.0.iter_mut().for_each(|s| s.steps_so_far(at));
    }

    fn output(&mut self, a: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        self.0.iter_mut().try_for_each(|s| s.output(a, o, r))
    }
}

/// The CSV columns after the part and reaction columns: each REQUEST's components, then the
/// element columns.
pub fn column_names(model: &Model, requests: Option<&RequestSet>) -> Vec<String> {
    let mut names = requests.map(RequestSet::columns).unwrap_or_default();
    names.extend(element_columns::names(model));
    names
}

/// The values of [`column_names`] at output `o` of `a`: `requests` (the REQUEST values), then
/// each FRICTION's, curve contact's and control state's.
pub fn row_values(a: &Assembled, o: &Output, requests: &[f64]) -> Vec<f64> {
    let mut values = requests.to_vec();
    let frictions = if a.model.frictions.is_empty() {
        Vec::new()
    } else {
        a.forces
            .friction_values(Regime::Dynamic, &o.state, &o.velocities)
    };
    let contacts =
        linkage_solve::constraints::curve_contacts::curve_contacts(a.model, &a.system, &o.state);
    element_columns::values(a.model, &frictions, &contacts, &o.state, &mut values);
    values
}

/// What a [`CsvSink`] does at an output where a REQUEST cannot be evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestFailure {
    /// NaN in every request column, the first error kept for the report (`simulate --out`).
    Nan,
    /// The analysis stops with the request's error (a command file).
    Stop,
}

/// The time histories as CSV, one row per output, each row flushed: a run that stops keeps
/// whole rows. The columns are fixed at the first output.
pub struct CsvSink<W: Write> {
    csv: CsvHistory<W>,
    /// The file's name, for messages.
    pub path: String,
    /// The REQUEST columns (`None`: the model's requests are not written).
    requests: Option<usize>,
    /// [`column_names`].
    names: Vec<String>,
    failure: RequestFailure,
    /// Outputs at which a request could not be evaluated.
    pub request_failures: usize,
    /// The first request error, and write errors.
    pub errors: Vec<String>,
    /// Rows written.
    pub written: usize,
}

impl<W: Write> CsvSink<W> {
    /// A CSV of `model`'s outputs to `out` (named `path` in messages), with the REQUEST
    /// columns of `requests`.
    pub fn new(
        out: W,
        path: String,
        model: &Model,
        requests: Option<&RequestSet>,
        failure: RequestFailure,
    ) -> Self {
        let requests = requests.filter(|r| !r.is_empty());
        CsvSink {
            csv: CsvHistory::new(out),
            path,
            requests: requests.map(|r| r.columns().len()),
            names: column_names(model, requests),
            failure,
            request_failures: 0,
            errors: Vec::new(),
            written: 0,
        }
    }

    /// The header alone (no output was written), so that the file says which columns it
    /// lacks.
    pub fn finish_empty(&mut self, model: &Model) -> std::io::Result<()> {
        self.csv.finish_empty(model)
    }

    /// Ends the file after an analysis of `outputs` outputs (the header alone when no row was
    /// written) and returns what the report must say of it: the first request error, at how
    /// many outputs the REQUEST columns are NaN, a write error.
    pub fn close(&mut self, model: &Model, outputs: usize) -> Vec<String> {
        let mut errors = std::mem::take(&mut self.errors);
        if self.request_failures > 1 {
            errors.push(format!(
                "REQUEST columns are NaN at {} of {outputs} outputs",
                self.request_failures
            ));
        }
        let ended = if self.written == 0 {
            self.finish_empty(model)
        } else {
            self.flush()
        };
        if let Err(e) = ended {
            errors.push(format!("cannot write {}: {e}", self.path));
        }
        errors
    }

    /// Flushes the file.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.csv.flush()
    }

    fn write_error(&self, cause: std::io::Error) -> SinkError {
        SinkError::Write {
            path: self.path.clone(),
            cause,
        }
    }
}

impl<W: Write> OutputSink for CsvSink<W> {
    fn wants_requests(&self) -> bool {
        self.requests.is_some()
    }

    fn output(&mut self, a: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        let nan;
        let requests: &[f64] = match (self.requests, r) {
            (None, _) | (_, None) => &[],
            (Some(_), Some(Ok(v))) => v,
            (Some(n), Some(Err(e))) => {
                if self.failure == RequestFailure::Stop {
                    return Err(SinkError::Request(e.clone()));
                }
                if self.request_failures == 0 {
                    self.errors.push(e.to_string());
                }
                self.request_failures += 1;
                nan = vec![f64::NAN; n];
                &nan
            }
        };
        let values = row_values(a, o, requests);
        if let Err(e) = self.csv.write(a.model, o, &self.names, &values) {
            return Err(self.write_error(e));
        }
        self.written += 1;
        Ok(())
    }
}

/// An analysis's outputs on their way to a sink: the REQUESTs evaluated once per output when
/// the sink reads them.
pub(crate) struct Feed<'s> {
    sink: &'s mut dyn OutputSink,
    requests: Option<RequestSet>,
    /// The REQUEST angles of the last output, which the next continues (ψ and φ split at
    /// θ ≈ 0 as the last output had them, as Adams writes them).
    angles: RequestAngles,
}

impl<'s> Feed<'s> {
    /// Outputs of `model` to `sink`; its REQUESTs resolved when the sink reads them (an input
    /// error in one is returned before the analysis runs).
    pub(crate) fn new(
        model: &Model,
        sink: &'s mut dyn OutputSink,
    ) -> Result<Feed<'s>, linkage_adm::Diagnostics> {
        let requests = if sink.wants_requests() {
            Some(RequestSet::new(model)?)
        } else {
            None
        };
        Ok(Feed {
            sink,
            requests,
            angles: RequestAngles::new(),
        })
    }

    /// The analysis has its assembled problem.
    pub(crate) fn assembled(&mut self, a: &Assembled, now: bool) -> Result<(), SinkError> {
        self.sink.assembled(a, now)
    }

    /// The integrator's step and counts at the output that follows.
    pub(crate) fn steps_so_far(&mut self, at: &StepTaken) {
        self.sink.steps_so_far(at);
    }

    /// One output of `a`.
    pub(crate) fn output(&mut self, a: &Assembled, o: &Output) -> Result<(), SinkError> {
        let angles = &mut self.angles;
        let values = self
            .requests
            .as_ref()
            .map(|r| r.evaluate_continuing(a.model, &a.system, o, angles));
        self.sink.output(a, o, values.as_ref())
    }
}
