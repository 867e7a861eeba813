//! A dynamic analysis from the dataset: initial conditions (or static equilibrium first), then
//! the simulation.

use super::{simulate, IntegratorSettings, Problem, Simulation};
use crate::constraints::system::System;
use crate::physics::applied::AppliedForces;
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
    Newton(Result<crate::stages::statics::Equilibrium, String>),
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

/// A dynamic analysis from the dataset: initial conditions (or static equilibrium first), then
/// the simulation.
#[derive(Clone, Debug)]
pub struct DynamicRun {
    pub ic: crate::stages::ic::InitialConditions,
    /// The equilibrium the run was asked to start from, and how it was found.
    pub equilibrium: Option<StartingEquilibrium>,
    pub simulation: Option<Simulation>,
    /// Why no simulation was run.
    pub error: Option<String>,
}

/// Runs initial conditions (and finds static equilibrium first when `start` asks for it), then
/// integrates to the last of `times`. Every stage uses the rows the initial conditions kept;
/// the starting equilibrium is at rest and at the start time.
#[allow(clippy::too_many_arguments)]
pub fn run(
    model: &Model,
    drivers: &crate::constraints::drivers::ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &crate::tolerances::Tolerances,
    times: &[f64],
    settings: &IntegratorSettings,
    start: Start,
    mut progress: impl FnMut(RunProgress),
) -> DynamicRun {
    let sys = System::new(model);
    let ic = crate::stages::ic::initial_conditions(model, drivers, forces, tol);
    let fail = |ic, equilibrium, why: String| DynamicRun {
        ic,
        equilibrium,
        simulation: None,
        error: Some(why),
    };
    if let Some(why) = ic.failure(model) {
        return fail(ic, None, why);
    }
    // The rows every stage keeps, and motions anchored at the assembled configuration.
    let (rows, redundant) = ic.kept_and_removed_rows();
    let anchored = drivers.anchored(&sys, &rows, &ic.assembly.state);
    let settle = match start {
        Start::InitialConditions => None,
        Start::Equilibrium => Some(model.equilibrium.dynamic),
        Start::SettledEquilibrium => Some(true),
    };
    let (equilibrium, state, v0) = match settle {
        None => {
            let v0 = ic
                .velocity
                .as_ref()
                .map(|v| v.velocities.clone())
                .unwrap_or_default();
            (None, ic.assembly.state.clone(), v0)
        }
        Some(settle) => {
            let found = if settle {
                let limit = model.equilibrium.settling_time;
                StartingEquilibrium::Settled(crate::stages::settle::settle_assembled(
                    model,
                    drivers,
                    forces,
                    &ic,
                    |elapsed| progress(RunProgress::Settling { elapsed, limit }),
                ))
            } else {
                StartingEquilibrium::Newton(
                    crate::stages::statics::equilibrium(
                        model,
                        &sys,
                        &rows,
                        &anchored,
                        forces,
                        &ic.assembly.state,
                        &model.equilibrium,
                    )
                    .map_err(|e| e.to_string()),
                )
            };
            let Some(e) = found.equilibrium() else {
                let why = found
                    .failure(model, &sys)
                    .unwrap_or_else(|| "no static equilibrium was found".into());
                return fail(
                    ic,
                    Some(found),
                    format!("no static equilibrium to start from: {why}"),
                );
            };
            let state = e.state.clone();
            let rest = vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()];
            (Some(found), state, rest)
        }
    };
    let problem = Problem {
        model,
        sys: &sys,
        rows: &rows,
        redundant: &redundant,
        drivers: &anchored,
        forces,
        damping: None,
        frozen_time: None,
    };
    let sim = simulate(&problem, &state, &v0, times, settings, |t| {
        progress(RunProgress::Integrating(t))
    });
    DynamicRun {
        ic,
        equilibrium,
        simulation: Some(sim),
        error: None,
    }
}
