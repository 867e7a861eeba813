//! The commands of a command file, by family: analyses ([`simulate`]: SIMULATE of every kind;
//! [`linear`]: LINEAR), settings and model changes ([`settings`]). Every analysis is the API's
//! ([`linkage_api`]): it starts where the session says ([`crate::session::Session::start`]),
//! hands its outputs to [`Sinks`] (the `.req`/`.csv` records, the model summary in the `.msg`
//! when the model was assembled after a change) and leaves the state the session keeps.

pub mod linear;
pub mod settings;
pub mod simulate;

use crate::error::RunError;
use crate::msg::MessageFile;
use crate::records::Records;
use crate::step_table::StepTable;
use linkage_api::sink::{OutputSink, RequestValues, SinkError};
use linkage_api::Loaded;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{Output, StepTaken};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Where a command was written and its echo, for messages.
pub struct Place<'c> {
    /// `file.acf:line:column`.
    pub at: String,
    pub command: &'c str,
}

impl Place<'_> {
    pub fn failed(&self, why: impl Into<String>) -> RunError {
        RunError::Failed {
            place: self.at.clone(),
            command: self.command.to_string(),
            why: why.into(),
        }
    }

    pub fn refused(&self, why: impl Into<String>) -> RunError {
        RunError::Refused {
            place: self.at.clone(),
            command: self.command.to_string(),
            why: why.into(),
        }
    }

    /// The run error of an analysis that gave no report: input errors as they are (every
    /// refused statement at once), an interruption as such, the rest as the command's failure.
    pub fn analysis_error(&self, e: linkage_api::Error) -> RunError {
        match e {
            linkage_api::Error::Input(d) => RunError::Input(d),
            linkage_api::Error::Refused {
                analysis,
                diagnostics,
            } => self.refused(format!(
                "{} refuses this model ({} statement(s) linkage does not model or run):\n{}",
                analysis.name(),
                diagnostics.0.len(),
                diagnostics
            )),
            linkage_api::Error::Sink(SinkError::Interrupted { time }) => {
                RunError::Interrupted { time }
            }
            linkage_api::Error::Times(t) => self.refused(t.to_string()),
            other => self.failed(other.to_string()),
        }
    }
}

/// Everything an analysis of a command file writes to, as the sink of its outputs.
pub struct Sinks<'s> {
    pub msg: &'s mut MessageFile,
    pub records: &'s mut Records,
    /// DOF and redundant equations of the last model summary (`None` before the first).
    pub counts: &'s mut Option<(i64, usize)>,
    /// Set when the run must stop at the next output.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Wall-clock seconds each dynamic simulation may take (`None`: the API's default,
    /// [`linkage_api::budget::DEFAULT_SIMULATE_TIME_LIMIT`]).
    pub time_limit: Option<f64>,
    /// The model changed since the last summary: write one when the analysis assembles.
    pub summary: bool,
    /// The model the analysis runs on (for the summary's findings and warnings).
    pub loaded: &'s Loaded,
    /// The analysis compiled and assembled the model.
    pub assembled: bool,
    /// A message-file write that failed inside the analysis.
    pub failed_write: Option<RunError>,
    /// The analysis needs a model without degrees of freedom (SIMULATE/KINEMATIC): one with
    /// some is refused when it is assembled, before any output.
    pub need_kinematic: bool,
    /// Why the analysis was refused at its assembly.
    pub refusal: Option<String>,
    /// The step table of a dynamic simulation (dropped at the assembly of a model without
    /// degrees of freedom, which takes no steps).
    pub steps: Option<StepTable>,
    /// Told how far a dynamic simulation has come (a terminal's progress bar).
    pub watch: crate::watch::Watch,
}

impl Sinks<'_> {
    pub fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// The summary of verify of an assembled model (counts, DOF, redundant equations) and,
    /// after a change of the model, how its DOF and redundancy changed.
    fn model_summary(&mut self, a: &Assembled) -> Result<(), RunError> {
        let v = &a.ic.analysis;
        let loaded = self.loaded;
        let mut j = linkage_report::verify::to_json(a.model, v, &loaded.warnings);
        j.left_out = linkage_report::coverage::left_out_json(&loaded.left_out);
        j.not_run = loaded.findings.iter().map(Into::into).collect();
        j.later_refused_by = linkage_report::coverage::refusing_analyses(&loaded.findings);
        let now = (v.dof, v.redundant.len());
        if let Some((dof, redundant)) = *self.counts {
            self.msg.write(&format!(
                " The model changed: {dof} → {} degrees of freedom, {redundant} → {} redundant \
                 constraint equations; verified and assembled again at time {}.",
                now.0,
                now.1,
                linkage_adm::num::time_text(a.state().time)
            ))?;
        }
        *self.counts = Some(now);
        self.msg.write(&linkage_report::verify::to_text(&j))
    }
}

impl OutputSink for Sinks<'_> {
    fn wants_requests(&self) -> bool {
        true
    }

    fn assembled(&mut self, a: &Assembled, now: bool) -> Result<(), SinkError> {
        self.assembled |= now;
        if a.is_kinematic() {
            self.steps = None;
        }
        if self.need_kinematic && !a.is_kinematic() {
            self.refusal = Some(format!(
                "a kinematic analysis needs a model without degrees of freedom; this one has {} \
                 (use SIMULATE/DYNAMIC or TRANSIENT)",
                a.ic.analysis.dof
            ));
            return Err(SinkError::Interrupted {
                time: a.state().time,
            });
        }
        if std::mem::take(&mut self.summary) {
            if let Err(e) = self.model_summary(a) {
                let time = a.state().time;
                self.failed_write = Some(e);
                return Err(SinkError::Interrupted { time });
            }
        }
        Ok(())
    }

    fn steps_so_far(&mut self, at: &StepTaken) {
        if let Some(table) = self.steps.as_mut() {
            table.steps_so_far(at);
        }
    }

    fn output(&mut self, a: &Assembled, o: &Output, r: RequestValues) -> Result<(), SinkError> {
        self.records.output(a, o, r)?;
        if let Some(lines) = self.steps.as_mut().and_then(|t| t.at_output(o.time)) {
            if let Err(e) = self.msg.write(lines.trim_end_matches('\n')) {
                self.failed_write = Some(e);
                return Err(SinkError::Interrupted { time: o.time });
            }
        }
        if self.interrupted() {
            return Err(SinkError::Interrupted { time: o.time });
        }
        Ok(())
    }
}
