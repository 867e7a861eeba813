//! `SIMULATE/{INITIAL_CONDITIONS | STATIC | DYNAMIC | KINEMATIC | TRANSIENT}`: the API's
//! analyses from where the last one left the model (ADM-REFERENCE §7.3), their reports in the
//! message file, their outputs in the records.

use super::{Place, Sinks};
use crate::error::RunError;
use crate::session::Progress;
use crate::step_table::StepTable;
use crate::watch::Event;
use linkage_adm::commands::SimulateKind;
use linkage_api::statics::StaticArgs;
use linkage_api::Start;
use linkage_report::sensors::SensorEventJson;
use linkage_solve::stages::dynamics::RunProgress;
use std::sync::atomic::Ordering;

/// The outcome of an analysis call: a message-file write that failed inside it comes first.
pub(super) fn outcome<T>(
    sinks: &mut Sinks,
    place: &Place,
    r: Result<T, linkage_api::Error>,
) -> Result<T, RunError> {
    if let Some(e) = sinks.failed_write.take() {
        return Err(e);
    }
    if let Some(why) = sinks.refusal.take() {
        return Err(place.refused(why));
    }
    r.map_err(|e| place.analysis_error(e))
}

/// `SIMULATE/INITIAL_CONDITIONS`: assemble, velocities, accelerations and forces; one output.
pub fn initial_conditions(
    progress: &mut Progress,
    sinks: &mut Sinks,
    place: &Place,
) -> Result<(), RunError> {
    let start = progress.start();
    let run = linkage_api::ic::run(sinks.loaded, start, sinks);
    let run = outcome(sinks, place, run)?;
    sinks.msg.write(&linkage_report::ic::to_text(&run.report))?;
    if run.failed || run.left.is_none() {
        let why = run.report.errors.first().cloned().unwrap_or_else(|| {
            "the model could not be assembled, or its acceleration and force initial \
             conditions failed"
                .into()
        });
        return Err(place.failed(why));
    }
    progress.leave(run.left);
    Ok(())
}

/// `SIMULATE/STATIC`: one equilibrium at the current time (by damped settling with
/// EQUILIBRIUM/DYNAMIC), or a quasi-static series at `times`.
pub fn statics(
    progress: &mut Progress,
    sinks: &mut Sinks,
    place: &Place,
    times: Option<Vec<f64>>,
    allow_unstable: bool,
) -> Result<(), RunError> {
    let args = StaticArgs {
        series: times,
        settle: false,
        allow_unstable,
        time_limit: None,
        interrupt: None,
    };
    let start = progress.start();
    let run = linkage_api::statics::run(sinks.loaded, start, &args, &|_, _| {}, sinks);
    let run = outcome(sinks, place, run)?;
    sinks
        .msg
        .write(&linkage_report::statics::to_text(&run.report))?;
    if !run.ok {
        let why = run
            .report
            .errors
            .first()
            .cloned()
            .unwrap_or_else(|| "no static equilibrium was found".into());
        return Err(place.failed(why));
    }
    // A quasi-static series that a SENSOR ended (its events are in the report above).
    progress.halted = sensor_stop(
        sinks,
        run.report.ended_by_sensor.as_deref(),
        &run.report.sensors,
        "quasi-static series",
    )?;
    progress.leave(run.left);
    Ok(())
}

/// A SENSOR that ended an analysis (`ended`: the report's `SENSOR_1 (HALT)` or
/// `SENSOR_1 (RETURN)`, the last of `events`): the message line, and for HALT what the session keeps as `halted` (`SENSOR_1 at time 2.5`),
/// which ends the command file: Adams' HALT terminates the solver, so the later commands are
/// not run (the run is complete, not failed: exit 0), whereas RETURN goes on with the next
/// command.
fn sensor_stop(
    sinks: &mut Sinks,
    ended: Option<&str>,
    events: &[SensorEventJson],
    what: &str,
) -> Result<Option<String>, RunError> {
    let (Some(ended), Some(e)) = (ended, events.last()) else {
        return Ok(None);
    };
    let halt = ended.ends_with("(HALT)");
    sinks.msg.write(&format!(
        " {ended} ended the {what} at time {}{}",
        linkage_adm::num::time_text(e.time),
        if halt {
            "; the command file ends here"
        } else {
            "; the command file goes on"
        }
    ))?;
    Ok(halt.then(|| format!("{} at time {}", e.name, linkage_adm::num::time_text(e.time))))
}

/// `SIMULATE/{DYNAMIC | KINEMATIC | TRANSIENT}` to the last of `times` (the current time
/// excluded; the first analysis of the file also writes its initial conditions).
pub fn dynamics(
    progress: &mut Progress,
    sinks: &mut Sinks,
    place: &Place,
    kind: SimulateKind,
    times: &[f64],
) -> Result<(), RunError> {
    let start = progress.start();
    let (t0, end) = (start.time(), times.last().copied().unwrap_or(start.time()));
    sinks.steps = Some(StepTable::new(t0, end));
    let watch = sinks.watch.clone();
    let mut told = |p: RunProgress| {
        if let RunProgress::Integrating(time) = p {
            watch.tell(&Event::Integrating {
                command: place.command,
                start: t0,
                end,
                time,
            });
        }
    };
    // The first analysis writes the initial conditions as its first output.
    let mut with_start = Vec::with_capacity(times.len() + 1);
    if matches!(start, Start::Input) {
        with_start.push(start.time());
    }
    with_start.extend_from_slice(times);
    let flag = sinks.interrupt.clone();
    let interrupted = move || flag.as_ref().is_some_and(|f| f.load(Ordering::Relaxed));
    sinks.need_kinematic = matches!(kind, SimulateKind::Kinematic);
    let args = linkage_api::simulate::SimulateArgs {
        times: &with_start,
        start: linkage_solve::stages::dynamics::Start::InitialConditions,
        allow_unstable: true,
        time_limit: sinks.time_limit,
        csv: None,
        progress: &mut told,
        interrupted: &interrupted,
        observe: None,
    };
    let run = linkage_api::simulate::run(sinks.loaded, start, args, sinks);
    sinks.watch.tell(&Event::Done);
    sinks.steps = None;
    let run = outcome(sinks, place, run)?;
    if let Some(why) = sinks.refusal.take() {
        return Err(place.refused(why));
    }
    let report = &run.report;
    sinks
        .msg
        .write(&linkage_report::simulate::to_text(report))?;
    if let Some(st) = &run.statistics {
        sinks.msg.write(&format!(
            " {} to t = {}: {} steps ({} rejected), {} corrector iterations, {} matrix \
             factorisations, {} outputs, {:.3} s CPU",
            if st.kinematic {
                "Kinematics"
            } else {
                "Dynamics"
            },
            report.end_time,
            st.steps,
            st.rejected,
            st.corrector_iterations,
            st.factorisations,
            st.outputs,
            st.seconds
        ))?;
    }
    let halted = sensor_stop(
        sinks,
        report.ended_by_sensor.as_deref(),
        &report.sensors,
        "simulation",
    )?;
    let end = report.end_time;
    let error = report.errors.first().cloned();
    progress.halted = halted;
    progress.leave(run.left);
    if let Some(e) = run.sink_error {
        return Err(match e {
            linkage_api::SinkError::Interrupted { time } => RunError::Interrupted { time },
            other => place.failed(other.to_string()),
        });
    }
    if run.interrupted {
        return Err(RunError::Interrupted { time: end });
    }
    match error {
        Some(why) => Err(place.failed(why)),
        None => Ok(()),
    }
}
