//! The simulate loop: step-size control on the local error estimate, output times hit exactly,
//! consistent outputs, redundant rows checked after every step, sensors evaluated after every
//! step ([`crate::kernel::sensors`], events located by [`super::events`]). A model without degrees of freedom is handed to the kinematic
//! run.

use super::corrector::StepTolerance;
use super::events;
use super::singular;
use super::stepper::Stepper;
use crate::kernel::error::IntegrationError;
use crate::kernel::output::Output;
use crate::kernel::problem::Problem;
use crate::kernel::redundant::{redundant_tolerance, redundant_violation};
use crate::kernel::results::{Failure, Simulation};
use crate::kernel::sensors::SensorWatch;
use crate::state::State;
use crate::tolerances::{
    AT_MIN_STEP, LOCAL_ERROR_FLOOR, LOCAL_ERROR_ROUNDING, OUTPUT_AT_START, OUTPUT_HIT, SPAN_FLOOR,
    STEP_FITS,
};
use glam::DVec3;
use linkage_model::settings::IntegratorSettings;

/// Simulates from `start` (assembled, with consistent velocities `v0`) to `end`, with output at
/// `times` (ascending, within [start.time, end]).
pub fn simulate(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    progress: impl FnMut(f64),
) -> Simulation {
    let mut outputs = Vec::new();
    let mut progress = progress;
    let each_step = |t| {
        progress(t);
        AfterOutput::Continue
    };
    let mut sim = simulate_with(p, start, v0, times, settings, each_step, |o| {
        outputs.push(o);
        AfterOutput::Continue
    });
    sim.output_count = outputs.len();
    sim.outputs = outputs;
    sim
}

/// One accepted integration step, as a message file's step table shows it (Adams' columns:
/// simulation time, step size, cumulative steps, integration order; corrector iterations in
/// place of function evaluations). The counts are those of the run so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepTaken {
    /// The time the step reached.
    pub time: f64,
    /// Its size (0 for the outputs of a kinematic run, which takes no steps).
    pub step: f64,
    /// The order of the method for the step (BDF 1…6, HHT and NEWMARK 2; 0: no step).
    pub order: usize,
    /// Steps accepted so far, this one included.
    pub steps: usize,
    /// Steps rejected so far.
    pub rejected: usize,
    /// Corrector iterations so far.
    pub iterations: usize,
}

/// What the caller of [`simulate_with`] wants after an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AfterOutput {
    Continue,
    /// End the run at this output (dynamic settling met its limits).
    Stop,
}

/// [`simulate`], handing each output to `on_output` instead of keeping it (the returned
/// simulation's `outputs` is empty): one integrator, one symbolic analysis and no stored
/// history for a run that only watches its outputs (dynamic settling). `progress` sees the
/// time after every accepted step; [`AfterOutput::Stop`] from it ends the run there with
/// [`IntegrationError::Stopped`] (Ctrl-C, a time limit), as from `on_output` at an output.
///
/// Step-size control. With BDF (GSTIFF, WSTIFF, CONSTANT_BDF) INTEGRATOR ERROR bounds the
/// error the run accumulates (positions: translations relative to the characteristic length,
/// rotations in radians), not the error of each step: a step of size h over a run of span T
/// may add `tol = ERROR·h/T` (at least rounding: `LOCAL_ERROR_FLOOR`, or
/// `LOCAL_ERROR_ROUNDING·ε·|x|/L` for parts far from the origin), so the local errors of
/// all steps add up to ERROR at most and the global error follows ERROR whatever the number
/// of steps or the length of the run. The local estimate of order k grows like `h^{k+1}` and
/// `tol` like h: a step whose estimate exceeds `tol` is retried with
/// `h·clamp(0.9 (tol/err)^{1/k}, 0.2, 0.9)`; an accepted one lets the next grow by
/// `clamp(0.9 (tol/err)^{1/k}, 0.2, 2)` up to HMAX. With HHT and NEWMARK, ERROR is the local
/// error of each step, as in Adams (`tol = ERROR`, exponents `1/3`): their estimate
/// `h²|β − 1/6|·|Δa|` carries the α-shift of the accelerations, which does not shrink with
/// the step fast enough to be spread over a run. CONSTANT_BDF steps at HMAX (or the output
/// interval) and accepts every step its corrector solves. A failed step is retried at `h/4`,
/// and at HMIN the run stops. Whatever the method, the corrector's allowance is the step's
/// share of ERROR over the run ([`StepTolerance`]), so a smaller HMAX never makes a run less
/// accurate.
pub fn simulate_with(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    mut progress: impl FnMut(f64) -> AfterOutput,
    on_output: impl FnMut(Output) -> AfterOutput,
) -> Simulation {
    simulate_stepwise(
        p,
        start,
        v0,
        times,
        settings,
        |s| progress(s.time),
        on_output,
    )
}

/// [`simulate_with`], `progress` seeing every accepted step whole ([`StepTaken`]: size, order
/// and the counts so far), not only its time.
pub fn simulate_stepwise(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    mut progress: impl FnMut(&StepTaken) -> AfterOutput,
    mut on_output: impl FnMut(Output) -> AfterOutput,
) -> Simulation {
    let n = p.n();
    let m = p.rows.len();
    let mut sim = Simulation::empty(crate::pipeline::kinematic(m, n, p.controls()));
    if sim.kinematic {
        // Streamed: each output is handed on as it is computed.
        return crate::stages::kinematics::run_streamed(
            p,
            start,
            v0,
            times,
            |time| {
                progress(&StepTaken {
                    time,
                    ..StepTaken::default()
                })
            },
            on_output,
        );
    }
    let length = p.model.characteristic_length;
    let t_end = times.last().copied().unwrap_or(start.time);
    // The output times, which a sensor's DT changes from its event on.
    let mut times = times.to_vec();
    // Consistent accelerations at the start.
    let (mut integ, first) = match Stepper::new(p, start, v0, settings) {
        Ok(x) => x,
        Err(e) => {
            sim.failure = Some(Failure::new(start.time, e));
            return sim;
        }
    };
    let mut next_output = 0;
    // Sensors (not while settling at a frozen time), armed at the start.
    let mut sensors = SensorWatch::new(p.model).filter(|_| p.frozen_time.is_none());
    if let Some(Err(e)) = sensors.as_mut().map(|w| w.start(p.model, &first)) {
        sim.failure = Some(Failure::new(start.time, e));
        return sim;
    }
    if times
        .first()
        .is_some_and(|t| (*t - start.time).abs() <= OUTPUT_AT_START * t_end.abs().max(1.0))
    {
        if on_output(first) == AfterOutput::Stop {
            return sim;
        }
        next_output = 1;
    }
    let span = (t_end - start.time).max(SPAN_FLOOR);
    // CONSTANT_BDF: every step HMAX, or the output interval.
    let constant = settings.constant_step.then(|| {
        settings.hmax.unwrap_or_else(|| {
            times
                .windows(2)
                .map(|w| w[1] - w[0])
                .find(|d| *d > 0.0)
                .unwrap_or(span)
        })
    });
    let hmax = constant.or(settings.hmax).unwrap_or(span / 10.0).min(span);
    let mut h = constant.unwrap_or(
        settings
            .hinit
            .unwrap_or((span / 1000.0).min(hmax))
            .min(hmax),
    );
    let at_min_step = |hs: f64| hs <= settings.hmin * (1.0 + AT_MIN_STEP);
    let per_run = integ.error_per_run();
    // The least local error worth asking for: rounding, which grows with the distance of the
    // parts from the origin (coordinates resolve to ε·|x|, over the characteristic length).
    let extent = start
        .poses
        .iter()
        .map(|q| q.p.abs().max_element())
        .fold(0.0, f64::max);
    let floor = LOCAL_ERROR_FLOOR.max(LOCAL_ERROR_ROUNDING * f64::EPSILON * extent / length);
    while next_output < times.len() {
        let target = times[next_output];
        let t = integ.time();
        let remaining = target - t;
        // Take the rest when it fits; otherwise equal steps to the output, none longer than h
        // (cutting one step short to hit the output made the step sizes jump at every
        // output, which variable-coefficient BDF pays for with rejected steps and accuracy:
        // IFToMM A02 N = 40 had 669 rejected steps, now 253).
        let mut hs = if remaining <= h * (1.0 + STEP_FITS) {
            remaining
        } else {
            remaining / (remaining / h - STEP_FITS).ceil()
        };
        let hit = hs >= remaining - OUTPUT_HIT * span;
        if hit {
            hs = remaining;
        }
        if hs <= 0.0 {
            next_output += 1;
            continue;
        }
        // BDF spends ERROR over the run: this step may add its share `ERROR·h/T`. HHT
        // takes it per step, as Adams does.
        let within = StepTolerance::new(settings.error, per_run, hs, span, floor);
        let tol = within.local;
        let tried = integ.try_step(hs, within);
        (sim.newton_iterations, sim.factorisations) = integ.statistics();
        match tried {
            Ok(err) => {
                // err ∝ h^{k+1} against tol ∝ h (per run): the step scales with
                // (tol/err)^{1/k}; against a fixed tol with (tol/err)^{1/(k+1)}.
                let exponent = |order: usize| {
                    if per_run {
                        1.0 / order.max(1) as f64
                    } else {
                        1.0 / (order as f64 + 1.0)
                    }
                };
                if err > tol && !at_min_step(hs) && constant.is_none() {
                    sim.rejected += 1;
                    let shrink = 0.9 * (tol / err).powf(exponent(integ.order()));
                    h = (hs * shrink.clamp(0.2, 0.9)).max(settings.hmin);
                    continue;
                }
                sim.steps += 1;
                let taken_order = integ.order();
                let (err, order) = integ.accept(err, tol);
                let now = integ.time();
                // Force elements with a state (joint friction) take the accepted step; the
                // next steps are solved with the state that gives.
                if p.forces.has_state() {
                    match integ.output() {
                        Ok(mut o) => {
                            p.forces
                                .accept_state(&mut o.state, &o.velocities, &o.reactions);
                            integ.set_elements(&o.state.elements);
                        }
                        Err(e) => {
                            sim.failure = Some(Failure::new(now, e));
                            return sim;
                        }
                    }
                }
                let taken = StepTaken {
                    time: now,
                    step: hs,
                    order: taken_order,
                    steps: sim.steps,
                    rejected: sim.rejected,
                    iterations: sim.newton_iterations,
                };
                if progress(&taken) == AfterOutput::Stop {
                    sim.failure = Some(Failure::new(now, IntegrationError::Stopped));
                    return sim;
                }
                if let Some(f) = redundant_violation(
                    p,
                    integ.state(),
                    length,
                    redundant_tolerance(settings.error),
                ) {
                    sim.failure = Some(f);
                    return sim;
                }
                let grow = if err > 0.0 {
                    (0.9 * (tol / err).powf(exponent(order))).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                // A step shortened to hit an output does not shrink the step size.
                h = constant.unwrap_or(
                    (hs * grow)
                        .max(if hit { h } else { 0.0 })
                        .min(hmax)
                        .max(settings.hmin),
                );
                // Sensors: an event inside the step continues the run from its time.
                if let Some(w) = sensors.as_mut() {
                    match events::after_step(w, p, &mut integ, settings, span) {
                        Ok(None) => {}
                        Ok(Some(fired)) => {
                            let at_output = hit && !fired.before_step_end;
                            fired.reschedule(&mut times, next_output, at_output, t_end);
                            sim.sensor_events.extend(fired.events);
                            let at = fired.output.time;
                            if fired.stop.is_some() {
                                sim.stopped_by_sensor = fired.stop;
                                let _ = on_output(fired.output);
                                return sim;
                            }
                            let printed = fired.print && (fired.before_step_end || !hit);
                            if printed && on_output(fired.output.clone()) == AfterOutput::Stop {
                                return sim;
                            }
                            h = fired.step.map_or(h, |x| x.min(hmax));
                            if fired.restart || fired.before_step_end {
                                // An event at an output time it restarts from: the
                                // output is written before the restart.
                                if hit && !fired.before_step_end {
                                    if !printed
                                        && on_output(fired.output.clone()) == AfterOutput::Stop
                                    {
                                        return sim;
                                    }
                                    next_output += 1;
                                }
                                match Stepper::new(
                                    p,
                                    &fired.output.state,
                                    &fired.output.velocities,
                                    settings,
                                ) {
                                    Ok((restarted, _)) => integ = restarted,
                                    Err(e) => {
                                        sim.failure = Some(Failure::new(at, e));
                                        return sim;
                                    }
                                }
                                continue;
                            }
                        }
                        Err(e) => {
                            sim.failure = Some(Failure::new(now, e));
                            return sim;
                        }
                    }
                }
                if hit {
                    match integ.output() {
                        Ok(o) => {
                            if on_output(o) == AfterOutput::Stop {
                                return sim;
                            }
                        }
                        Err(e) => {
                            sim.failure = Some(Failure::new(now, e));
                            return sim;
                        }
                    }
                    next_output += 1;
                }
            }
            Err(e) => {
                // A user subroutine's ERRMES with STOP ends the run here, not after retries.
                if linkage_expr::user::is_stop(&e.to_string()) {
                    sim.failure = Some(Failure::new(t, e));
                    return sim;
                }
                if at_min_step(hs) {
                    let cause = IntegrationError::AtMinimumStep {
                        step: hs,
                        cause: Box::new(e),
                    };
                    // A pose where the kept rows lost their independence says so.
                    let cause = singular::diagnose(p, start, integ.state(), cause);
                    sim.failure = Some(Failure::new(t, cause));
                    return sim;
                }
                sim.rejected += 1;
                h = (hs * 0.25).max(settings.hmin);
            }
        }
    }
    sim
}
