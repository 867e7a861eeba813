//! Static equilibrium by damped dynamics ("dynamic settling", ADM-REFERENCE §8.3).
//!
//! Time is frozen at the start time (motions and forces see that time), every part gets a
//! damping force `−c m v` and torque `−c I ω` with `c` = GLOBAL_DAMPING (per time unit), and
//! the model is integrated until both the kinetic energy (`Σ ½ m v² + ½ ωᵀ I ω`, divided by
//! the UCF into force × length) and the largest CM or angular acceleration fall below
//! KINETIC_ENERGY_ERROR and ACCELERATION_ERROR, or until SETTLING_TIME runs out.
//!
//! GLOBAL_DAMPING 0 (Adams' default) would never settle an undamped model: the damping is then
//! chosen from the model ([`choose`]): with `ω₁` the lowest angular frequency of the free
//! motions at the start (`√|μ|` of `K_r y = μ M_r y`, statics/stability.rs; an unstable
//! start's negative `μ` counts by its size), `c = 2 ζ ω₁` with `ζ` = [`SETTLE_DAMPING_RATIO`]
//! (near-critical for the lowest mode; every stiffer mode then decays at least at the rate
//! `c/2`), and SETTLING_TIME becomes [`SETTLE_DECAY`]`/ω₁` (the time the slowest mode needs),
//! so that the same 400 outputs cover it whatever the model's time scale. The limits are
//! checked at 400 evenly spaced outputs of one integration (HHT at ERROR 1e-4, steps no longer
//! than the spacing), which stops at the first output where both hold. The settled
//! configuration is then polished with the static Newton iteration, and time is reset to the
//! start.

use crate::constraints::system::System;
use crate::kernel::ExtraDamping;
use crate::physics::applied::Regime;
use crate::pipeline::{Assembled, NotAssembled};
use crate::stages::dynamics::{simulate_with, AfterOutput, IntegratorSettings};
use crate::stages::statics::Solver;
use crate::stages::statics::{equilibrium, Equilibrium, StaticsError};
use crate::state::State;
use crate::tolerances::{
    SETTLE_DAMPING_RATIO, SETTLE_DECAY, SETTLE_NO_STIFFNESS, SETTLING_INTEGRATOR_ERROR,
};
use linkage_model::settings::shown;
use linkage_model::settings::IntegratorMethod;
use linkage_model::Model;

/// Outputs at which the settling checks its limits, evenly spaced over SETTLING_TIME.
const WINDOWS: usize = 400;

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

/// The damping and settling time of a settling, and where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct SettleChoice {
    /// `c` of the damping force `−c m v`, torque `−c I ω` (per time unit).
    pub damping: f64,
    /// Pseudo-time the settling may integrate.
    pub settling_time: f64,
    /// Chosen from the model's lowest mode (GLOBAL_DAMPING was 0), not the dataset's.
    pub from_model: bool,
    /// The lowest angular frequency `ω₁` the choice was made from (rad per time unit).
    pub lowest_frequency: Option<f64>,
}

/// The damping and settling time of a settling of `a` (module docs): the dataset's when its
/// GLOBAL_DAMPING is positive; otherwise chosen from the lowest mode at the assembled
/// configuration. A model whose modes cannot be computed (too large, a massless free motion)
/// or whose free motions all lack stiffness keeps SETTLING_TIME and gets `c =
/// SETTLE_DECAY/SETTLING_TIME` (its velocities decay by `e^−SETTLE_DECAY` over the time).
pub fn choose(a: &Assembled) -> SettleChoice {
    let eq = &a.model.equilibrium;
    if eq.global_damping > 0.0 {
        return SettleChoice {
            damping: eq.global_damping,
            settling_time: eq.settling_time,
            from_model: false,
            lowest_frequency: None,
        };
    }
    let solver = Solver {
        model: a.model,
        sys: &a.system,
        rows: &a.kept,
        drivers: &a.drivers,
        forces: a.forces,
        settings: eq,
    };
    let omega = solver.modes_at(a.state()).ok().flatten().and_then(|m| {
        let largest = m
            .squared_frequencies
            .iter()
            .map(|x| x.abs())
            .fold(0.0, f64::max);
        m.lowest_frequency_above(SETTLE_NO_STIFFNESS * largest)
    });
    match omega {
        Some(w) => SettleChoice {
            damping: 2.0 * SETTLE_DAMPING_RATIO * w,
            settling_time: SETTLE_DECAY / w,
            from_model: true,
            lowest_frequency: Some(w),
        },
        None => SettleChoice {
            damping: SETTLE_DECAY / eq.settling_time,
            settling_time: eq.settling_time,
            from_model: true,
            lowest_frequency: None,
        },
    }
}

/// How the settling of an assembled model went: what stopped it, the pseudo-time integrated,
/// and the Newton polish from where it stopped.
#[derive(Clone, Debug)]
pub struct SettleOutcome {
    /// The damping and settling time used.
    pub choice: SettleChoice,
    pub stop: SettleStop,
    pub time_used: f64,
    /// Where the integration stopped (time reset to the start), before the polish.
    pub state: State,
    /// The static Newton polish from the settled configuration (time reset to the start);
    /// `None` when the integration failed.
    pub equilibrium: Option<Result<Equilibrium, StaticsError>>,
}

impl SettleOutcome {
    /// The equilibrium, when the model settled and the polish converged.
    pub fn settled_equilibrium(&self) -> Option<&Equilibrium> {
        match (&self.stop, &self.equilibrium) {
            (SettleStop::Settled { .. }, Some(Ok(e))) if e.converged => Some(e),
            _ => None,
        }
    }

    /// Why no equilibrium came out of the settling, in a sentence (`None` when one did).
    pub fn failure(&self, model: &Model, sys: &System) -> Option<String> {
        let eq = &model.equilibrium;
        let c = &self.choice;
        match (&self.stop, &self.equilibrium) {
            (SettleStop::Failed(m), _) => Some(format!("dynamic settling failed: {m}")),
            (
                SettleStop::SettlingTime {
                    kinetic_energy,
                    acceleration,
                },
                _,
            ) => Some(format!(
                "the model did not settle within {} = {} (damping {}): kinetic energy {} \
                 (limit {}), largest acceleration {} (limit {})",
                if c.from_model {
                    "the settling time chosen from its lowest mode"
                } else {
                    "SETTLING_TIME"
                },
                shown(c.settling_time),
                shown(c.damping),
                linkage_adm::num::sci(*kinetic_energy, 4),
                linkage_adm::num::sci(eq.kinetic_energy_error, 4),
                linkage_adm::num::sci(*acceleration, 4),
                eq.acceleration_error
            )),
            (SettleStop::Settled { .. }, Some(Ok(e))) if !e.converged => Some(format!(
                "the model settled, but its Newton polish failed: {}",
                e.failure(model, sys).unwrap_or_default()
            )),
            (SettleStop::Settled { .. }, Some(Err(m))) => Some(format!(
                "the model settled, but the static Newton polish failed: {m}"
            )),
            _ => None,
        }
    }
}

/// Settles an assembled model by damped dynamics with time frozen at the start, then polishes
/// with Newton statics at the start time, with the dataset's EQUILIBRIUM settings
/// (`model.equilibrium`); the kept rows and anchored motions are the assembly's. `progress`
/// hears the pseudo-time integrated so far (from 0 to the settling time of [`choose`]) after
/// every step.
pub fn settle(a: &Assembled, progress: impl FnMut(f64)) -> Result<SettleOutcome, NotAssembled> {
    settle_until(a, progress, &|| false)
}

/// [`settle`], stopped between two steps when `stop` says so (Ctrl-C, a wall-clock limit): the
/// outcome is then a failure at the settling time reached, saying it was stopped.
pub fn settle_until(
    a: &Assembled,
    mut progress: impl FnMut(f64),
    stop_now: &dyn Fn() -> bool,
) -> Result<SettleOutcome, NotAssembled> {
    if let Some(why) = a.failure() {
        return Err(why.clone());
    }
    let model = a.model;
    let eq = &model.equilibrium;
    let t0 = a.state().time;
    // Frictions inactive in statics (INACTIVE_DURING = STATIC) are off while settling too.
    let choice = choose(a);
    let mut problem = a.problem(Some(ExtraDamping(choice.damping)), Some(t0));
    problem.regime = Regime::Static;
    let v0 = a.velocities();
    // One integration over SETTLING_TIME, watched at `WINDOWS` evenly spaced outputs (and the
    // start): it ends at the first output where both limits hold.
    let dt = choice.settling_time / WINDOWS as f64;
    let times: Vec<f64> = (0..=WINDOWS).map(|k| t0 + dt * k as f64).collect();
    // HHT-α: its numerical damping helps the settling, and its error is taken per step (a
    // settling run's path does not matter, only where it comes to rest).
    let settings = IntegratorSettings {
        method: IntegratorMethod::Hht,
        error: SETTLING_INTEGRATOR_ERROR,
        hmax: Some(dt),
        ..Default::default()
    };
    let mut stop = None;
    let mut last: Option<(State, f64)> = None;
    let sim = simulate_with(
        &problem,
        a.state(),
        &v0,
        &times,
        &settings,
        |tau| {
            progress(tau - t0);
            if stop_now() {
                AfterOutput::Stop
            } else {
                AfterOutput::Continue
            }
        },
        |out| {
            let ke = out.kinetic_energy(model);
            let acc = out
                .accelerations
                .iter()
                .map(|(a, al)| a.length().max(al.length()))
                .fold(0.0, f64::max);
            let settled = ke <= eq.kinetic_energy_error && acc <= eq.acceleration_error;
            stop = Some(if settled {
                SettleStop::Settled {
                    kinetic_energy: ke,
                    acceleration: acc,
                }
            } else {
                SettleStop::SettlingTime {
                    kinetic_energy: ke,
                    acceleration: acc,
                }
            });
            last = Some((out.state, out.time));
            if settled {
                AfterOutput::Stop
            } else {
                AfterOutput::Continue
            }
        },
    );
    if let Some(f) = sim.failure {
        stop = Some(SettleStop::Failed(format!(
            "at settling time {}: {}",
            f.time - t0,
            f.message
        )));
    }
    let (mut state, tau) = last.unwrap_or_else(|| (a.state().clone(), t0));
    let time_used = tau - t0;
    state.time = t0;
    let stop = stop.unwrap_or_else(|| {
        SettleStop::Failed("the settling integration produced no output".into())
    });
    let equilibrium = match &stop {
        SettleStop::Failed(_) => None,
        _ => Some(equilibrium(
            model, &a.system, &a.kept, &a.drivers, a.forces, &state, eq,
        )),
    };
    Ok(SettleOutcome {
        choice,
        stop,
        time_used,
        state,
        equilibrium,
    })
}
