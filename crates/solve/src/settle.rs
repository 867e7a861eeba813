//! Static equilibrium by damped dynamics ("dynamic settling", ADM-REFERENCE §8.3).
//!
//! Time is frozen at the start time (motions and forces see that time), every part gets a
//! damping force `−c m v` and torque `−c I ω` with `c` = GLOBAL_DAMPING (per time unit), and
//! the model is integrated until both the kinetic energy and the largest acceleration fall
//! below KINETIC_ENERGY_ERROR and ACCELERATION_ERROR, or until SETTLING_TIME runs out. The
//! settled configuration is then polished with the static Newton iteration, and time is reset to
//! the start.

use crate::applied::AppliedForces;
use crate::drivers::ExpressionDrivers;
use crate::dynamics::{simulate, ExtraDamping, IntegratorSettings, Problem};
use crate::state::State;
use crate::statics::{equilibrium, Equilibrium};
use crate::system::System;
use crate::tolerances::Tolerances;
use glam::DVec3;
use linkage_model::settings::EquilibriumSettings;
use linkage_model::Model;

/// What ended the settling.
#[derive(Clone, Debug, PartialEq)]
pub enum SettleStop {
    /// Kinetic energy and accelerations both fell below their limits.
    Settled {
        kinetic_energy: f64,
        acceleration: f64,
    },
    /// SETTLING_TIME ran out first: the model did not settle.
    SettlingTime {
        kinetic_energy: f64,
        acceleration: f64,
    },
    /// The integration failed.
    Failed(String),
}

/// Result of dynamic settling.
#[derive(Clone, Debug)]
pub struct Settling {
    pub ic: crate::ic::InitialConditions,
    pub stop: Option<SettleStop>,
    /// Pseudo-time integrated.
    pub time_used: f64,
    /// The static Newton polish from the settled configuration (time reset to the start).
    pub equilibrium: Option<Result<Equilibrium, String>>,
}

/// Settles the model by damped dynamics, then polishes with Newton statics.
pub fn settle(
    model: &Model,
    drivers: &ExpressionDrivers,
    forces: &dyn AppliedForces,
    tol: &Tolerances,
    eq: &EquilibriumSettings,
) -> Settling {
    let ic = crate::ic::initial_conditions(model, drivers, forces, tol);
    if !ic.assembly.converged || ic.inconsistent() {
        return Settling {
            ic,
            stop: None,
            time_used: 0.0,
            equilibrium: None,
        };
    }
    let sys = System::new(model);
    let (rows, redundant) = ic.kept_and_removed_rows();
    let drivers = &drivers.anchored(&sys, &rows, &ic.assembly.state);
    let t0 = ic.assembly.state.time;
    let problem = Problem {
        model,
        sys: &sys,
        rows: &rows,
        redundant: &redundant,
        drivers,
        forces,
        damping: Some(ExtraDamping(eq.global_damping)),
        frozen_time: Some(t0),
    };
    let mut state: State = ic.assembly.state.clone();
    let mut vel: Vec<(DVec3, DVec3)> = ic
        .velocity
        .as_ref()
        .map(|v| v.velocities.clone())
        .unwrap_or_else(|| vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()]);
    let windows = 400usize;
    let dt = eq.settling_time / windows as f64;
    let settings = IntegratorSettings {
        error: 1e-4,
        hmax: Some(dt),
        ..Default::default()
    };
    let mut stop = None;
    let mut tau = t0;
    for _ in 0..windows {
        let sim = simulate(&problem, &state, &vel, &[tau, tau + dt], &settings, |_| {});
        if let Some(f) = sim.failure {
            stop = Some(SettleStop::Failed(format!(
                "at settling time {}: {}",
                f.time - t0,
                f.message
            )));
            break;
        }
        let Some(out) = sim.outputs.last() else {
            stop = Some(SettleStop::Failed(
                "the settling integration produced no output".into(),
            ));
            break;
        };
        state = out.state.clone();
        vel = out.velocities.clone();
        tau = out.time;
        let ke: f64 = model
            .parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let ig = state.poses[k].r * p.inertia * state.poses[k].r.transpose();
                0.5 * p.mass * vel[k].0.length_squared() + 0.5 * vel[k].1.dot(ig * vel[k].1)
            })
            .sum();
        let acc = out
            .accelerations
            .iter()
            .map(|(a, al)| a.length().max(al.length()))
            .fold(0.0, f64::max);
        if ke <= eq.kinetic_energy_error && acc <= eq.acceleration_error {
            stop = Some(SettleStop::Settled {
                kinetic_energy: ke,
                acceleration: acc,
            });
            break;
        }
        if tau - t0 >= eq.settling_time * (1.0 - 1e-12) {
            stop = Some(SettleStop::SettlingTime {
                kinetic_energy: ke,
                acceleration: acc,
            });
            break;
        }
    }
    let time_used = tau - t0;
    state.time = t0;
    let equilibrium = match &stop {
        Some(SettleStop::Failed(_)) | None => None,
        _ => Some(equilibrium(model, &sys, &rows, drivers, forces, &state, eq)),
    };
    Settling {
        ic,
        stop,
        time_used,
        equilibrium,
    }
}
