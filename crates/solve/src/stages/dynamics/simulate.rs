//! The simulate loop: step-size control on the local error estimate, output times hit exactly,
//! consistent outputs, redundant rows checked after every step. A model without degrees of
//! freedom is handed to the kinematic run.

use super::error::IntegrationError;
use super::integrator::Integrator;
use super::output::Output;
use super::problem::Problem;
use super::redundant::{redundant_tolerance, redundant_violation};
use super::results::{Failure, Simulation};
use crate::state::State;
use crate::tolerances::{AT_MIN_STEP, OUTPUT_AT_START, OUTPUT_HIT, SPAN_FLOOR, STEP_FITS};
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
/// Step-size control: a step whose error estimate exceeds ERROR is retried with
/// `h·clamp(0.9 (ERROR/err)^{1/3}, 0.2, 0.9)`; an accepted one lets the next grow by
/// `clamp(0.9 (ERROR/err)^{1/3}, 0.2, 2)` up to HMAX; a failed one is retried at `h/4`, and
/// at HMIN the run stops.
pub fn simulate_with(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    settings: &IntegratorSettings,
    mut progress: impl FnMut(f64) -> AfterOutput,
    mut on_output: impl FnMut(Output) -> AfterOutput,
) -> Simulation {
    let n = p.n();
    let m = p.rows.len();
    let mut sim = Simulation::empty(m >= 6 * n && n > 0);
    if sim.kinematic {
        let mut run = crate::stages::kinematics::run(p, start, v0, times, |t| {
            let _ = progress(t);
        });
        for o in std::mem::take(&mut run.outputs) {
            if on_output(o) == AfterOutput::Stop {
                break;
            }
        }
        return run;
    }
    let length = p.model.characteristic_length;
    let t_end = times.last().copied().unwrap_or(start.time);
    // Consistent accelerations at the start.
    let (mut integ, first) = match Integrator::new(p, start, v0, settings) {
        Ok(x) => x,
        Err(e) => {
            sim.failure = Some(Failure::new(start.time, e));
            return sim;
        }
    };
    let mut next_output = 0;
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
    let hmax = settings.hmax.unwrap_or(span / 10.0).min(span);
    let mut h = settings
        .hinit
        .unwrap_or((span / 1000.0).min(hmax))
        .min(hmax);
    let at_min_step = |hs: f64| hs <= settings.hmin * (1.0 + AT_MIN_STEP);
    while next_output < times.len() {
        let target = times[next_output];
        let t = integ.time();
        let remaining = target - t;
        // Take the rest when it fits; split it in two rather than leave a sliver.
        let mut hs = if remaining <= h * (1.0 + STEP_FITS) {
            remaining
        } else if remaining < 2.0 * h {
            remaining / 2.0
        } else {
            h
        };
        let hit = hs >= remaining - OUTPUT_HIT * span;
        if hit {
            hs = remaining;
        }
        if hs <= 0.0 {
            next_output += 1;
            continue;
        }
        let tried = integ.try_step(hs);
        (sim.newton_iterations, sim.factorisations) = integ.statistics();
        match tried {
            Ok(err) => {
                let tol = settings.error;
                if err > tol && !at_min_step(hs) {
                    sim.rejected += 1;
                    h = (hs * (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 0.9))
                        .max(settings.hmin);
                    continue;
                }
                sim.steps += 1;
                integ.accept();
                let now = integ.time();
                if progress(now) == AfterOutput::Stop {
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
                    (0.9 * (tol / err).powf(1.0 / 3.0)).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                // A step shortened to hit an output does not shrink the step size.
                h = (hs * grow)
                    .max(if hit { h } else { 0.0 })
                    .min(hmax)
                    .max(settings.hmin);
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
                if at_min_step(hs) {
                    let cause = IntegrationError::AtMinimumStep {
                        step: hs,
                        cause: Box::new(e),
                    };
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
