//! A dynamic analysis from the dataset: initial conditions (or static equilibrium first), then
//! the simulation.

use super::{
    simulate, simulate_stepwise, AfterOutput, IntegratorSettings, Output, Simulation, StepTaken,
};
use crate::constraints::system::System;
use crate::pipeline::{Assembled, NotAssembled};
use crate::state::State;
use glam::DVec3;
use linkage_model::Model;

/// How far a [`run`] has got.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunProgress {
    /// Settling to the starting equilibrium: pseudo-time integrated out of SETTLING_TIME.
    Settling { elapsed: f64, limit: f64 },
    /// The simulation itself has reached this time.
    Integrating(f64),
}

/// Where a dynamic run starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// The initial conditions: the assembled configuration with its velocities (Adams'
    /// default).
    InitialConditions,
    /// Static equilibrium found as the dataset's EQUILIBRIUM statement says: by damped
    /// dynamics with `DYNAMIC`, otherwise by Newton statics; the run starts from it at rest.
    Equilibrium,
    /// Static equilibrium found by damped dynamics (settling, then the Newton polish), whatever
    /// the dataset says; the run starts from it at rest.
    SettledEquilibrium,
}

/// How the starting equilibrium of a [`Start::Equilibrium`] or [`Start::SettledEquilibrium`]
/// run was found.
#[derive(Clone, Debug)]
pub enum StartingEquilibrium {
    /// Newton statics at the start time.
    Newton(Result<crate::stages::statics::Equilibrium, crate::stages::statics::StaticsError>),
    /// Damped dynamics with frozen time, then the Newton polish.
    Settled(crate::stages::settle::SettleOutcome),
}

impl StartingEquilibrium {
    /// The equilibrium the run starts from, if one was found.
    pub fn equilibrium(&self) -> Option<&crate::stages::statics::Equilibrium> {
        match self {
            StartingEquilibrium::Newton(Ok(e)) if e.converged => Some(e),
            StartingEquilibrium::Newton(_) => None,
            StartingEquilibrium::Settled(o) => o.settled_equilibrium(),
        }
    }

    /// Why no equilibrium was found (`None` when one was).
    pub fn failure(&self, model: &Model, sys: &System) -> Option<String> {
        match self {
            StartingEquilibrium::Newton(Ok(e)) => e.failure(model, sys),
            StartingEquilibrium::Newton(Err(m)) => Some(format!("static equilibrium failed: {m}")),
            StartingEquilibrium::Settled(o) => o.failure(model, sys),
        }
    }
}

/// Why a dynamic run did not start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The model could not be assembled.
    #[error(transparent)]
    NotAssembled(#[from] NotAssembled),
    /// The starting equilibrium was asked for and not found (the reason, as the statics or
    /// settling stage states it).
    #[error("no static equilibrium to start from: {0}")]
    NoEquilibrium(String),
    /// The starting equilibrium was found but is unstable, and the caller refused to start
    /// from an unstable one ([`UnstableStart::Refuse`]); nothing was integrated.
    #[error(
        "the starting equilibrium is UNSTABLE (negative stiffness {} along a free motion)",
        linkage_adm::num::sci(*.lowest_stiffness, 4)
    )]
    UnstableEquilibrium { lowest_stiffness: f64 },
}

/// Whether a run may start from an unstable static equilibrium.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnstableStart {
    /// Start from it (it stays there only as long as rounding allows).
    Accept,
    /// Stop with [`RunError::UnstableEquilibrium`] before integrating.
    Refuse,
}

/// A dynamic analysis of an assembled model: static equilibrium first when asked, then the
/// simulation.
#[derive(Clone, Debug)]
pub struct DynamicRun {
    /// The equilibrium the run was asked to start from, and how it was found.
    pub equilibrium: Option<StartingEquilibrium>,
    pub simulation: Option<Simulation>,
    /// Why no simulation was run.
    pub error: Option<RunError>,
}

/// Integrates an assembled model to the last of `times`, from its initial conditions or (when
/// `start` asks for it) from static equilibrium at rest at the start time. Every stage uses the
/// rows and anchored motions of the assembly. Every output is kept.
pub fn run(
    a: &Assembled,
    times: &[f64],
    settings: &IntegratorSettings,
    start: Start,
    progress: impl FnMut(RunProgress),
) -> DynamicRun {
    run_inner(
        a,
        times,
        settings,
        Begin::Start(start, UnstableStart::Accept),
        progress,
        None,
    )
}

/// A state a dynamic run continues from: where the last analysis of a command file left the
/// model, on the same assembly (positions and velocities consistent with its kept rows).
#[derive(Clone, Copy, Debug)]
pub struct Continue<'s> {
    pub state: &'s State,
    /// CM velocity and angular velocity of every part, ground axes.
    pub velocities: &'s [(DVec3, DVec3)],
}

/// Where [`run_inner`] starts.
enum Begin<'s> {
    /// From the assembly (initial conditions or equilibrium).
    Start(Start, UnstableStart),
    /// From a given state.
    From(Continue<'s>),
}

/// [`run`], with the choice of whether an unstable starting equilibrium stops the run before
/// it integrates (`unstable`); `run` accepts one.
pub fn run_from(
    a: &Assembled,
    times: &[f64],
    settings: &IntegratorSettings,
    start: Start,
    unstable: UnstableStart,
    progress: impl FnMut(RunProgress),
) -> DynamicRun {
    run_inner(
        a,
        times,
        settings,
        Begin::Start(start, unstable),
        progress,
        None,
    )
}

/// Where a streamed run's outputs go, and when it must stop.
pub struct Stream<'s> {
    /// Each output as it is computed; [`AfterOutput::Stop`] ends the run there.
    pub on_output: &'s mut dyn FnMut(&Output) -> AfterOutput,
    /// Asked after every integration step: `true` ends the run there
    /// ([`super::IntegrationError::Stopped`]).
    pub stop: &'s dyn Fn() -> bool,
    /// Told every accepted step (a message file's step table), before `stop` is asked.
    pub on_step: Option<&'s mut dyn FnMut(&StepTaken)>,
}

/// [`run_from`], handing each output to `stream.on_output` as it is computed (a CSV written
/// row by row) and keeping only the last one (for the final state): memory does not grow with
/// the number of outputs; `stream.stop` ends the run between steps (an interrupted run, a time
/// limit).
pub fn run_streamed(
    a: &Assembled,
    times: &[f64],
    settings: &IntegratorSettings,
    start: Start,
    unstable: UnstableStart,
    progress: impl FnMut(RunProgress),
    stream: Stream<'_>,
) -> DynamicRun {
    run_inner(
        a,
        times,
        settings,
        Begin::Start(start, unstable),
        progress,
        Some(stream),
    )
}

/// [`run_streamed`] continuing from `from` (no equilibrium first): how a command file's
/// simulation goes on from where the last analysis left the model, on the same assembly.
pub fn continue_streamed(
    a: &Assembled,
    times: &[f64],
    settings: &IntegratorSettings,
    from: Continue<'_>,
    progress: impl FnMut(RunProgress),
    stream: Stream<'_>,
) -> DynamicRun {
    run_inner(
        a,
        times,
        settings,
        Begin::From(from),
        progress,
        Some(stream),
    )
}

fn run_inner(
    a: &Assembled,
    times: &[f64],
    settings: &IntegratorSettings,
    begin: Begin<'_>,
    mut progress: impl FnMut(RunProgress),
    stream: Option<Stream<'_>>,
) -> DynamicRun {
    let model = a.model;
    let fail = |equilibrium, why: RunError| DynamicRun {
        equilibrium,
        simulation: None,
        error: Some(why),
    };
    if let Some(why) = a.failure() {
        return fail(None, why.clone().into());
    }
    let (settle, unstable) = match begin {
        Begin::From(_) => (None, UnstableStart::Accept),
        Begin::Start(Start::InitialConditions, u) => (None, u),
        Begin::Start(Start::Equilibrium, u) => (Some(model.equilibrium.dynamic), u),
        Begin::Start(Start::SettledEquilibrium, u) => (Some(true), u),
    };
    let (equilibrium, state, v0) = match settle {
        None => match begin {
            Begin::From(from) => (None, from.state.clone(), from.velocities.to_vec()),
            Begin::Start(..) => (None, a.state().clone(), a.velocities()),
        },
        Some(settle) => {
            let found = if settle {
                let limit = model.equilibrium.settling_time;
                let settled = crate::stages::settle::settle(a, |elapsed| {
                    progress(RunProgress::Settling { elapsed, limit })
                });
                match settled {
                    Ok(outcome) => StartingEquilibrium::Settled(outcome),
                    Err(why) => return fail(None, why.into()),
                }
            } else {
                StartingEquilibrium::Newton(crate::stages::statics::equilibrium(
                    model,
                    &a.system,
                    &a.kept,
                    &a.drivers,
                    a.forces,
                    a.state(),
                    &model.equilibrium,
                ))
            };
            let Some(e) = found.equilibrium() else {
                let why = found
                    .failure(model, &a.system)
                    .unwrap_or_else(|| "no static equilibrium was found".into());
                return fail(Some(found), RunError::NoEquilibrium(why));
            };
            if let (UnstableStart::Refuse, Some((false, lowest_stiffness))) =
                (unstable, e.stability)
            {
                return fail(
                    Some(found.clone()),
                    RunError::UnstableEquilibrium { lowest_stiffness },
                );
            }
            let state = e.state.clone();
            (Some(found), state, a.rest())
        }
    };
    let problem = a.problem(None, None);
    let sim = match stream {
        None => simulate(&problem, &state, &v0, times, settings, |t| {
            progress(RunProgress::Integrating(t))
        }),
        Some(Stream {
            on_output,
            stop,
            mut on_step,
        }) => {
            let (mut last, mut count) = (None, 0usize);
            let each_step = |s: &StepTaken| {
                progress(RunProgress::Integrating(s.time));
                if let Some(f) = on_step.as_mut() {
                    f(s);
                }
                if stop() {
                    AfterOutput::Stop
                } else {
                    AfterOutput::Continue
                }
            };
            let mut sim =
                simulate_stepwise(&problem, &state, &v0, times, settings, each_step, |o| {
                    count += 1;
                    let next = on_output(&o);
                    last = Some(o);
                    next
                });
            sim.output_count = count;
            sim.outputs = last.into_iter().collect();
            sim
        }
    };
    DynamicRun {
        equilibrium,
        simulation: Some(sim),
        error: None,
    }
}
