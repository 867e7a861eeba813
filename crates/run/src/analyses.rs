//! The analyses a command file runs, each continuing from where the last one left the model
//! (ADM-REFERENCE §7.3): the model is assembled at the current time from the current state
//! ([`Session::input_model`]), the analysis runs, its outputs go to the records as they come,
//! and the session keeps the state it ends at.

use crate::error::RunError;
use crate::msg::MessageFile;
use crate::records::Records;
use crate::session::{Left, Session};
use linkage_adm::commands::SimulateKind;
use linkage_model::Model;
use linkage_solve::coverage::Analysis;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{
    simulate_with, AfterOutput, IntegrationError, Output, SensorStop,
};
use linkage_solve::stages::linearize::{self, LinearOptions};
use linkage_solve::stages::plant;
use linkage_solve::stages::statics;
use linkage_solve::tolerances::Tolerances;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where a command was written and its echo, for messages.
pub struct Place<'c> {
    /// `file.acf:line:column`.
    pub at: String,
    pub command: &'c str,
}

impl Place<'_> {
    fn failed(&self, why: impl Into<String>) -> RunError {
        RunError::Failed {
            place: self.at.clone(),
            command: self.command.to_string(),
            why: why.into(),
        }
    }

    fn refused(&self, why: impl Into<String>) -> RunError {
        RunError::Refused {
            place: self.at.clone(),
            command: self.command.to_string(),
            why: why.into(),
        }
    }
}

/// Output times from the current time `t0` to `end`: every `dtout`, or `steps` equal intervals
/// (one interval when neither is given), `t0` itself excluded.
pub fn output_times(t0: f64, end: f64, steps: Option<u32>, dtout: Option<f64>) -> Vec<f64> {
    let span = end - t0;
    let count = match (steps, dtout) {
        (Some(n), _) => n.max(1) as usize,
        (None, Some(dt)) => ((span / dt) - crate::INTERVAL_SLACK).ceil().max(1.0) as usize,
        (None, None) => 1,
    };
    (1..=count)
        .map(|k| match (steps, dtout) {
            (None, Some(dt)) => (t0 + dt * k as f64).min(end),
            _ => t0 + span * k as f64 / count as f64,
        })
        .collect()
}

/// Everything an analysis writes to.
pub struct Sinks<'s> {
    pub msg: &'s mut MessageFile,
    pub records: &'s mut Records,
    /// DOF and redundant equations of the last model summary (`None` before the first).
    pub counts: &'s mut Option<(i64, usize)>,
    /// Set when the run must stop at the next output.
    pub interrupt: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
}

impl Sinks<'_> {
    fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// The model assembled at the current time from the current state, and the summary lines of
/// verify when the model changed since the last summary.
fn assemble<'m>(
    session: &'m Session,
    model: &'m Model,
    place: &Place,
    analysis: Analysis,
) -> Result<Assembled<'m>, RunError> {
    let refused = session.refusals(analysis);
    if !refused.is_empty() {
        return Err(place.refused(format!(
            "{} refuses this model ({} statement(s) linkage does not model or run):\n{}",
            analysis.name(),
            refused.len(),
            refused.join("\n")
        )));
    }
    let Some(forces) = session.built.forces.as_ref() else {
        return Err(place.refused("the model's forces cannot be evaluated"));
    };
    // The values the sensors stored (SENVAL) carry on from the last analysis.
    let carried = session.left.as_ref().map(|l| &l.state.elements);
    let a = Assembled::continuing(
        model,
        &session.built.drivers,
        forces,
        &Tolerances::default(),
        session.time(),
        carried.unwrap_or(&Default::default()),
    );
    if let Some(why) = a.failure() {
        return Err(place.failed(why.to_string()));
    }
    Ok(a)
}

/// What a report of `analysis` says about the statements left out and those it ran without.
fn coverage(
    session: &Session,
    analysis: Analysis,
) -> (
    Vec<linkage_report::coverage::LeftOutJson>,
    Vec<linkage_report::coverage::FindingJson>,
) {
    (
        linkage_report::coverage::left_out_json(&session.left_out()),
        linkage_report::coverage::runs_without_json(&session.built.findings, analysis),
    )
}

/// Writes the verify summary of an assembled model (counts, DOF, redundant equations) and,
/// after a change of the model, how its DOF and redundancy changed.
pub fn model_summary(session: &Session, a: &Assembled, sinks: &mut Sinks) -> Result<(), RunError> {
    let v = &a.ic.analysis;
    let mut j = linkage_report::verify::to_json(a.model, v, &session.built.warnings);
    j.left_out = linkage_report::coverage::left_out_json(&session.left_out());
    j.not_run = session.built.findings.iter().map(Into::into).collect();
    j.later_refused_by = linkage_report::coverage::refusing_analyses(&session.built.findings);
    let now = (v.dof, v.redundant.len());
    if let Some((dof, redundant)) = *sinks.counts {
        sinks.msg.write(&format!(
            " The model changed: {dof} → {} degrees of freedom, {redundant} → {} redundant \
             constraint equations; verified and assembled again at time {}.",
            now.0,
            now.1,
            session.time()
        ))?;
    }
    *sinks.counts = Some(now);
    sinks.msg.write(&linkage_report::verify::to_text(&j))
}

/// Writes one output to the records (a request that cannot be evaluated ends the run).
fn record(
    session: &Session,
    a: &Assembled,
    sinks: &mut Sinks,
    o: &Output,
    place: &Place,
) -> Result<(), RunError> {
    sinks
        .records
        .write(a.model, &a.system, &session.built.requests, a.forces, o)
        .map_err(|why| place.failed(why.to_string()))
}

/// The output of the initial conditions of `a`.
fn ic_output(a: &Assembled) -> Option<Output> {
    let acc = a.ic.acceleration.as_ref()?.as_ref().ok()?;
    Some(Output {
        time: a.state().time,
        state: a.state().clone(),
        velocities: a.velocities(),
        accelerations: acc.accelerations.clone(),
        reactions: acc.reactions.clone(),
    })
}

/// `SIMULATE/INITIAL_CONDITIONS`: assemble, velocities, accelerations and forces; one output.
pub fn initial_conditions(
    session: &mut Session,
    sinks: &mut Sinks,
    place: &Place,
    summary: bool,
) -> Result<(), RunError> {
    let model = session.input_model();
    let a = assemble(session, &model, place, Analysis::Ic)?;
    if summary {
        model_summary(session, &a, sinks)?;
    }
    let mut j = linkage_report::ic::to_json(&model, &a.ic, &session.built.warnings);
    (j.left_out, j.runs_without) = coverage(session, Analysis::Ic);
    sinks.msg.write(&linkage_report::ic::to_text(&j))?;
    let Some(o) = ic_output(&a) else {
        return Err(place.failed("the acceleration and force initial conditions failed"));
    };
    record(session, &a, sinks, &o, place)?;
    let left = Left {
        state: o.state.clone(),
        velocities: o.velocities.clone(),
    };
    drop(a);
    session.left = Some(left);
    Ok(())
}

/// `SIMULATE/STATIC`: one equilibrium at the current time, or a quasi-static series to `end`.
pub fn statics(
    session: &mut Session,
    sinks: &mut Sinks,
    place: &Place,
    summary: bool,
    times: Option<Vec<f64>>,
) -> Result<(), RunError> {
    let model = session.input_model();
    let analysis = if times.is_some() {
        Analysis::QuasiStatic
    } else {
        Analysis::Static
    };
    let a = assemble(session, &model, place, analysis)?;
    if summary {
        model_summary(session, &a, sinks)?;
    }
    let t0 = session.time();
    let times = times.unwrap_or_else(|| vec![t0]);
    let run = if model.equilibrium.dynamic && times.len() == 1 {
        let outcome = linkage_solve::stages::settle::settle(&a, |_| {})
            .map_err(|why| place.failed(why.to_string()))?;
        let eq = outcome.settled_equilibrium().cloned().ok_or_else(|| {
            place.failed(
                outcome
                    .failure(&model, &a.system)
                    .unwrap_or_else(|| "the model did not settle".into()),
            )
        })?;
        statics::StaticRun {
            steps: vec![(t0, Ok(eq))],
            sensor_events: Vec::new(),
            stopped_by_sensor: None,
        }
    } else {
        statics::run(&a, &times)
    };
    let mut j = linkage_report::statics::to_json(&a, &run, &session.built.warnings);
    (j.left_out, j.runs_without) = coverage(session, analysis);
    sinks.msg.write(&linkage_report::statics::to_text(&j))?;
    let mut last = None;
    for (t, result) in &run.steps {
        let eq = match result {
            Ok(e) if e.converged => e,
            Ok(e) => {
                return Err(place.failed(
                    e.failure(&model, &a.system)
                        .unwrap_or_else(|| format!("no static equilibrium at time {t}")),
                ))
            }
            Err(e) => return Err(place.failed(format!("at time {t}: {e}"))),
        };
        let o = Output {
            time: *t,
            state: eq.state.clone(),
            velocities: a.rest(),
            accelerations: a.rest(),
            reactions: eq.reactions.clone(),
        };
        record(session, &a, sinks, &o, place)?;
        if sinks.interrupted() {
            return Err(RunError::Interrupted { time: o.time });
        }
        last = Some(o);
    }
    let Some(o) = last else {
        return Err(place.failed("no static equilibrium was computed"));
    };
    // A quasi-static series that a SENSOR ended (its events are in the report above).
    let events = linkage_report::sensors::events_json(&model, &run.sensor_events);
    let halted = sensor_stop(sinks, run.stopped_by_sensor, &events, "quasi-static series")?;
    let left = Left {
        state: o.state,
        velocities: o.velocities,
    };
    drop(a);
    session.left = Some(left);
    session.halted = halted;
    Ok(())
}

/// A SENSOR that ended an analysis (`stop`, by the last of `events`): the message line, and
/// for HALT what the session keeps as `halted` (`SENSOR_1 at time 2.5`), which ends the
/// command file: Adams' HALT terminates the solver, so the later commands are not run (the
/// run is complete, not failed: exit 0), whereas RETURN goes on with the next command. The
/// same for a dynamic, kinematic or quasi-static run.
fn sensor_stop(
    sinks: &mut Sinks,
    stop: Option<SensorStop>,
    events: &[linkage_report::sensors::SensorEventJson],
    what: &str,
) -> Result<Option<String>, RunError> {
    let (Some(stop), Some(e)) = (stop, events.last()) else {
        return Ok(None);
    };
    let how = linkage_report::sensors::stop_name(stop);
    let halt = stop == SensorStop::Halt;
    sinks.msg.write(&format!(
        " {} ({how}) ended the {what} at time {}{}",
        e.name,
        e.time,
        if halt {
            "; the command file ends here"
        } else {
            "; the command file goes on"
        }
    ))?;
    Ok(halt.then(|| format!("{} at time {}", e.name, e.time)))
}

/// `SIMULATE/{DYNAMIC | KINEMATIC | TRANSIENT}` to `end` with outputs at `times` (the current
/// time excluded; the first analysis of the file also writes its initial conditions).
pub fn dynamics(
    session: &mut Session,
    sinks: &mut Sinks,
    place: &Place,
    summary: bool,
    kind: SimulateKind,
    times: &[f64],
) -> Result<(), RunError> {
    let model = session.input_model();
    let a = assemble(session, &model, place, Analysis::Simulate)?;
    if summary {
        model_summary(session, &a, sinks)?;
    }
    let zero_dof = a.kept.len() >= 6 * model.parts.len();
    match kind {
        SimulateKind::Kinematic if !zero_dof => {
            return Err(place.refused(format!(
                "a kinematic analysis needs a model without degrees of freedom; this one has {} \
                 (use SIMULATE/DYNAMIC or TRANSIENT)",
                a.ic.analysis.dof
            )))
        }
        SimulateKind::Dynamic if zero_dof => {
            sinks.msg.write(
                " The model has no degrees of freedom: it is run kinematically (positions from \
                 the constraints at each output).",
            )?;
        }
        _ => {}
    }
    let first = session.left.is_none();
    if first {
        if let Some(o) = ic_output(&a) {
            record(session, &a, sinks, &o, place)?;
        }
    }
    let start = a.state().clone();
    let v0 = a.velocities();
    let problem = a.problem(None, None);
    let settings = &model.integrator.settings;
    let clock = Instant::now();
    let mut last: Option<Output> = None;
    let mut write_error: Option<RunError> = None;
    let mut written = 0usize;
    // Ctrl-C is honoured between steps too, not only at outputs.
    let flag = sinks.interrupt.clone();
    let each_step = |_| {
        if flag
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
        {
            AfterOutput::Stop
        } else {
            AfterOutput::Continue
        }
    };
    let sim = simulate_with(&problem, &start, &v0, times, settings, each_step, |o| {
        if let Err(e) = record(session, &a, sinks, &o, place) {
            write_error = Some(e);
            return AfterOutput::Stop;
        }
        written += 1;
        let stop = sinks.interrupted();
        if stop {
            write_error = Some(RunError::Interrupted { time: o.time });
        }
        last = Some(o);
        if stop {
            AfterOutput::Stop
        } else {
            AfterOutput::Continue
        }
    });
    let seconds = clock.elapsed().as_secs_f64();
    sinks.msg.write(&format!(
        " {} to t = {}: {} steps ({} rejected), {} corrector iterations, {} matrix \
         factorisations, {} outputs, {seconds:.3} s CPU",
        if sim.kinematic {
            "Kinematics"
        } else {
            "Dynamics"
        },
        last.as_ref().map_or(session.time(), |o| o.time),
        sim.steps,
        sim.rejected,
        sim.newton_iterations,
        sim.factorisations,
        written,
    ))?;
    if let Some(e) = write_error {
        return Err(e);
    }
    // Sensors: every event in the message file; HALT ends the command file, RETURN goes on
    // with the next command.
    let events = linkage_report::sensors::events_json(&model, &sim.sensor_events);
    if !events.is_empty() {
        sinks
            .msg
            .write(linkage_report::sensors::events_text(&events).trim_end())?;
    }
    let halted = sensor_stop(sinks, sim.stopped_by_sensor, &events, "simulation")?;
    let left = last.map(|o| Left {
        state: o.state,
        velocities: o.velocities,
    });
    let failure = sim.failure.clone();
    drop(a);
    if let Some(left) = left {
        session.left = Some(left);
    }
    session.halted = halted;
    if let Some(f) = failure {
        if matches!(f.cause, IntegrationError::Stopped) {
            return Err(RunError::Interrupted { time: f.time });
        }
        return Err(place.failed(format!("at time {}: {}", f.time, f.message)));
    }
    Ok(())
}

/// `LINEAR/EIGENSOL`: eigenvalues (and modes) about the current operating point.
pub fn eigensolution(
    session: &mut Session,
    sinks: &mut Sinks,
    place: &Place,
    summary: bool,
    opts: LinearOptions,
) -> Result<(), RunError> {
    let model = session.input_model();
    let a = assemble(session, &model, place, Analysis::Linear)?;
    if summary {
        model_summary(session, &a, sinks)?;
    }
    let run = linearize::run(&a, false, opts);
    let mut j = linkage_report::linear::to_json(&model, &run, false, &session.built.warnings);
    (j.left_out, j.runs_without) = coverage(session, Analysis::Linear);
    j.time = session.time();
    if session.left.is_some() {
        j.operating_point = "the state the previous analysis left, assembled at its time";
    }
    sinks.msg.write(&linkage_report::linear::to_text(&j))?;
    if let Err(e) = &run.result {
        return Err(place.failed(e.to_string()));
    }
    Ok(())
}

/// The plant inputs and outputs of `LINEAR/STATEMAT`: VARIABLE ids.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlantIo {
    pub inputs: Vec<u32>,
    pub outputs: Vec<u32>,
}

/// `LINEAR/STATEMAT`: the state matrices about the current operating point, written as plain
/// text matrices (one row per line, numbers separated by blanks: MATLAB's `load` and numpy's
/// `loadtxt` read them): `<file>a` holds A (`2f × 2f`), `<file>b` B (`2f × inputs`), `<file>c`
/// C (`outputs × 2f`), `<file>d` D (`outputs × inputs`) of `ẋ = A x + B u`, `y = C x + D u`,
/// and `<file>st` the basis N that maps the `f` independent coordinates to part coordinates
/// (`6·parts × f`: CM x, y, z in length units, then rotations about the ground axes in
/// radians, per part), so that the states are `x = [z; ż]` with `q = N z`. The inputs and
/// outputs are VARIABLE values ([`linkage_solve::stages::plant`]); without them B, C and D are
/// empty.
pub fn state_matrices(
    session: &mut Session,
    sinks: &mut Sinks,
    place: &Place,
    summary: bool,
    file: &Path,
    io: &PlantIo,
) -> Result<(), RunError> {
    let model = session.input_model();
    let a = assemble(session, &model, place, Analysis::Linear)?;
    if summary {
        model_summary(session, &a, sinks)?;
    }
    let (Some(v), Some(Ok(acc))) = (&a.ic.velocity, &a.ic.acceleration) else {
        return Err(place.failed("the operating point has no accelerations and forces"));
    };
    let op = linearize::OperatingPoint {
        state: a.state(),
        velocities: &v.velocities,
        multipliers: &acc.multipliers,
    };
    let eq = linearize::assemble(&model, &a.system, &a.kept, a.forces, op, true)
        .map_err(|e| place.failed(e.to_string()))?;
    let sm = linearize::state_matrix(&eq).map_err(|e| place.failed(e.to_string()))?;
    let Some(forces) = session.built.forces.as_ref() else {
        return Err(place.refused("the model's forces cannot be evaluated"));
    };
    let pl = plant::plant(&model, forces, op, &sm, &io.inputs, &io.outputs)
        .map_err(|e| place.failed(e.to_string()))?;
    let f = sm.coordinates;
    let states = 2 * f + sm.controls;
    let rows = |values: &[f64], cols: usize| -> String {
        if cols == 0 {
            return String::new();
        }
        values
            .chunks(cols)
            .map(|r| {
                r.iter()
                    .map(|x| format!("{x:.16e}"))
                    .collect::<Vec<_>>()
                    .join(" ")
                    + "\n"
            })
            .collect()
    };
    let name = file.to_string_lossy();
    let files = [
        ("a", rows(&sm.a, states)),
        ("b", rows(&pl.b, pl.inputs)),
        ("c", rows(&pl.c, states)),
        ("d", rows(&pl.d, pl.inputs)),
        ("st", rows(&sm.basis, f)),
    ];
    for (suffix, text) in files {
        let path = PathBuf::from(format!("{name}{suffix}"));
        linkage_adm::writer::write_atomically(&path, &text).map_err(|cause| RunError::Write {
            path: path.display().to_string(),
            cause,
        })?;
    }
    sinks.msg.write(&format!(
        " State matrices at time {}: {states} states ({f} independent coordinates and their \
         rates, {} control states), {} input(s), {} output(s); A, B, C, D in {name}a, {name}b, \
         {name}c, {name}d, the coordinate basis in {name}st.",
        session.time(),
        sm.controls,
        pl.inputs,
        pl.outputs
    ))
}
