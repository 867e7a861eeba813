//! Static equilibrium (DESIGN §6, ADM-REFERENCE §8.2): modified Newton–Raphson on positions and
//! multipliers with the dataset's EQUILIBRIUM settings.
//!
//! Unknowns: tangent position increments of every part and one multiplier per independent
//! constraint row. Equations (model force units):
//!
//! ```text
//! F(q, λ) = Q_applied(q) + Q_gravity − Jᵀλ = 0,     Φ(q, t) = 0
//! [ K_T   Jᵀ ] [δ ]   [  F ]        K_T = −∂Q/∂q + Σ_r λ_r ∂²Φ_r/∂q²   (geometric stiffness)
//! [ J     0  ] [δλ] = [ −Φ ]
//! ```
//!
//! STABILITY adds a fraction of the mass matrix to `K_T` in the Newton matrix only (the
//! equations are unchanged, so the equilibrium is too). PATTERN decides when the matrix is
//! refreshed; TLIMIT and ALIMIT cap each correction. Convergence needs the force imbalance
//! below IMBALANCE, the relative correction below ERROR and the constraints satisfied.
//! After convergence, stability is judged from the smallest eigenvalue of the stiffness reduced
//! to the free motions (`Nᵀ K_T N`, N a basis of the null space of J).

mod descent;
mod newton;
mod stability;

pub use descent::{Descent, Solver};

use stability::reduced_stability;
pub use stability::{modes, Modes, MAX_DENSE_DOF_COLUMNS};

use crate::constraints::drivers::{Drivers, MotionError};
use crate::constraints::rows::RowGradient;
use crate::constraints::system::{RowUnit, System};
use crate::kernel::{
    outputs_every, IntegrationError, Output, SensorEvent, SensorStop, SensorWatch,
};
use crate::linalg::linear::LinearError;
use crate::physics::applied::{AppliedForces, ForceError};
use crate::physics::reactions::{element_reactions, Reaction};
use crate::pipeline::Assembled;
use crate::state::State;
use crate::tolerances::{
    STATIC_CONSTRAINT_FLOOR, STATIC_CUT_PROJECTION, STATIC_REPORTED_IMBALANCE,
    STATIC_ROUNDING_IMBALANCE,
};
use glam::DVec3;
use linkage_model::settings::refresh_at;
use linkage_model::settings::EquilibriumSettings;
use linkage_model::Model;
use newton::{Problem, Workspace};

/// Which equation an imbalance belongs to.
#[derive(Clone, Debug, PartialEq)]
pub enum Imbalance {
    /// Force (component 0..3) or torque (3..6) balance of a part.
    Part { part: usize, component: usize },
    /// A constraint row.
    Row(usize),
}

/// Names of the six balance equations of a part.
const BALANCE: [&str; 6] = [
    "force X", "force Y", "force Z", "torque X", "torque Y", "torque Z",
];

impl Imbalance {
    /// `(element or part name, equation)`: `("PART_2", "force Y balance")`,
    /// `("JOINT_5", "Translation of I Marker Along Zg")`.
    pub fn describe(&self, model: &Model, sys: &System) -> (String, String) {
        match self {
            Imbalance::Part { part, component } => (
                model.parts[*part].origin.name.clone(),
                format!("{} balance", BALANCE[*component]),
            ),
            Imbalance::Row(r) => {
                let row = &sys.rows[*r];
                (
                    model.constraints[row.element].origin.name.clone(),
                    row.label.to_string(),
                )
            }
        }
    }
}

/// A part whose Newton correction exceeds this (translation over the characteristic length,
/// or rotation in radians: a hundred model sizes, or sixteen turns) is moving along a free
/// motion that nothing resists: the correction is a load divided by STABILITY × the part's
/// inertia, not a step towards an equilibrium. Such a part is cut to TLIMIT/ALIMIT on its own
/// instead of scaling (and stalling) every other part's step with it.
pub const RUNAWAY_CORRECTION: f64 = 1e2;

/// Most iterations whose imbalance an [`Equilibrium`] keeps.
pub const IMBALANCE_HISTORY: usize = 10_000;

/// Result of a static equilibrium solve.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    pub state: State,
    pub converged: bool,
    pub iterations: usize,
    /// Largest force/torque imbalance at the end (model force units).
    pub imbalance: f64,
    /// The largest imbalance at each iteration, the last one being `imbalance` (the first
    /// [`IMBALANCE_HISTORY`] + 1 iterations; sized once before the iteration, which then
    /// allocates nothing).
    pub imbalance_history: Vec<f64>,
    /// The constraint rows in the solve and their multipliers (model force units).
    pub multipliers: Vec<(usize, f64)>,
    pub reactions: Vec<Reaction>,
    /// Smallest eigenvalue of the reduced stiffness (scaled to force × length) and whether the
    /// equilibrium is stable; `None` when not evaluated (zero DOF, or too large for the dense
    /// eigen solve).
    pub stability: Option<(bool, f64)>,
    /// The equations with the largest imbalance (largest first).
    pub worst: Vec<(Imbalance, f64)>,
    /// The model has no degrees of freedom: positions come from the constraints alone.
    pub kinematic: bool,
    /// The iteration stalled with a runaway correction ([`RUNAWAY_CORRECTION`]): the largest
    /// imbalances act along free motions that nothing resists, and three iterations of
    /// TLIMIT/ALIMIT moves did not reduce them (no equilibrium near).
    pub unbounded: bool,
    /// Rows whose second derivatives could not be evaluated (a general constraint's
    /// expression failing along a path at the pose): the Newton matrix misses their geometric
    /// stiffness. Every geometric row and every evaluable expression has exact ones.
    pub approximate_rows: usize,
}

impl Equilibrium {
    /// Why this solve did not converge, in a sentence naming the largest imbalances (`None`
    /// when it converged).
    pub fn failure(&self, model: &Model, sys: &System) -> Option<String> {
        if self.converged {
            return None;
        }
        let worst: Vec<String> = self
            .worst
            .iter()
            .map(|(w, v)| {
                let (name, equation) = w.describe(model, sys);
                format!("{name} {equation} ({})", linkage_adm::num::sci(*v, 4))
            })
            .collect();
        let mut why = format!(
            "static equilibrium did not converge in {} iterations; largest imbalance in {}",
            self.iterations,
            worst.join(", ")
        );
        if self.unbounded {
            why.push_str(UNBOUNDED_NOTE);
        }
        Some(why)
    }
}

/// What an unbounded Newton correction means, appended to a non-convergence message.
const UNBOUNDED_NOTE: &str = ": these loads act along free motions that nothing \
    resists (the Newton correction is unbounded, each iteration only moved the parts by \
    TLIMIT/ALIMIT), so the model has no static equilibrium near this configuration; support or \
    drive that motion, or add a restoring force";

/// Why a static equilibrium solve failed (as opposed to not converging, which is an
/// [`Equilibrium`] with `converged == false`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StaticsError {
    /// A motion's displacement cannot be evaluated at the solve's time.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A force element cannot be evaluated at an iterate.
    #[error(transparent)]
    Force(#[from] ForceError),
    /// The forces or constraint residuals are no longer finite.
    #[error(
        "the static iteration diverged at iteration {iteration}: the forces or constraint \
         residuals are no longer finite"
    )]
    NotFinite { iteration: usize },
    /// The Newton matrix cannot be set up or factorised (an entry that is not finite, a
    /// structurally singular matrix); `stability` is EQUILIBRIUM/STABILITY (see
    /// [`StaticsError::Singular`]).
    #[error(
        "the static Newton matrix cannot be factorised: {cause}{}",
        singular_hint(*stability)
    )]
    Factor { cause: LinearError, stability: f64 },
    /// The Newton correction is not finite; `stability` is EQUILIBRIUM/STABILITY (suggested
    /// only when it is 0: a positive one already regularises every massive part, so the
    /// singular motion is a massless part's or a redundant constraint's).
    #[error(
        "the static Newton matrix is singular: the model has free motions with no \
         stiffness{}",
        singular_hint(*stability)
    )]
    Singular { stability: f64 },
    /// A sensor could not be evaluated, or its event not located, in a quasi-static series.
    #[error("sensor: {0}")]
    Sensor(String),
    /// Damped settling found no equilibrium (the reason).
    #[error("{0}")]
    NotSettled(String),
}

/// What to try on a singular static Newton matrix, given EQUILIBRIUM/STABILITY: a positive
/// STABILITY when it is 0, else what a positive one cannot regularise.
fn singular_hint(stability: f64) -> &'static str {
    if stability == 0.0 {
        "; EQUILIBRIUM has STABILITY = 0: a positive STABILITY lets the parts' inertia hold \
         motions without stiffness, or support them"
    } else {
        "; a motion without stiffness and without mass (a massless part, or constraints that \
         leave a motion free): give the part mass or support that motion"
    }
}

/// The rows `rows` with their drive values at `t` (motions' displacements, 0 for the others).
fn drive_values(
    model: &Model,
    sys: &System,
    rows: &[usize],
    drivers: &dyn Drivers,
    t: f64,
) -> Result<Vec<(usize, f64)>, MotionError> {
    rows.iter()
        .map(|&r| {
            let row = &sys.rows[r];
            if !row.driven {
                return Ok((r, 0.0));
            }
            drivers
                .value(row.element, t)
                .map(|f| (r, f))
                .ok_or_else(|| MotionError::at(model, drivers, row.element, t))
        })
        .collect()
}

/// Iterations with a runaway correction are unbounded when the imbalance is not below 0.99×
/// its value this many Newton iterations before.
const RUNAWAY_WINDOW: usize = 3;

/// Solves for static equilibrium at time `start.time` from `start` (assembled), enforcing the
/// constraint rows `rows` (the independent rows of verify/IC).
///
/// Memory: the buffers and both sparse matrices are sized before the first iteration
/// (the Newton workspace of `statics/newton.rs`); an iteration without a cut step allocates nothing itself (force
/// elements and expressions may, see [`crate::stages::dynamics::Integrator`]).
///
/// Force elements with a state (joint friction, [`crate::physics::forces::friction`]): the
/// stiction anchors are held where the analysis starts, and each friction's normal load is
/// taken from its joint's reaction at every Newton iterate, with the coupling `−∂Q/∂λ` in the
/// Newton matrix (`statics/newton/friction_load.rs`), so one Newton solve gives the equilibrium in
/// which the friction acts with the normal load of the final reactions; the elements' state
/// then takes that equilibrium (`accept_state`: the normal loads, the anchors trailed to
/// MAX_STICTION_DEFORMATION). Elements inactive in statics are off throughout.
///
/// This replaced a fixed point (solve with the loads lagged, take the loads from the
/// reactions, solve again until they settle). Measured (`tests/friction.rs`): the block on
/// the ramp, 1 solve of 1 iteration either way (its lagged load was already right); the bar
/// on a pin of radius 0.5 with its centre of mass at 0.1 (`a_pin_with_a_large_radius…`), 2
/// solves of 2 iterations → 1 solve of 3; SolidWorks' RD3 (12 frictions), 5 solves of
/// 4+3+2+1+1 iterations → 1 solve of 5; the same equilibria within 1e-9. The bar with its
/// centre of mass at 0.2 (held: a < μs·R = 0.25) had no equilibrium by the fixed point (a
/// lagged load of about half the weight turned the pin past MAX_STICTION_DEFORMATION in the
/// first solve, out of the stiction spring); the Newton step is now also stopped at the edge
/// of the stiction band once (`friction_load.rs`), and it converges in 4 iterations.
pub fn equilibrium(
    model: &Model,
    sys: &System,
    rows: &[usize],
    drivers: &dyn Drivers,
    forces: &dyn AppliedForces,
    start: &State,
    settings: &EquilibriumSettings,
) -> Result<Equilibrium, StaticsError> {
    if !forces.has_state() {
        return equilibrium_once(model, sys, rows, drivers, forces, start, settings);
    }
    let mut result = equilibrium_once(model, sys, rows, drivers, forces, start, settings);
    if let Some(eq) = result.as_mut().ok().filter(|e| e.converged) {
        let rest = vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()];
        forces.accept_state(&mut eq.state, &rest, &eq.reactions);
    }
    result
}

/// [`equilibrium`] with the stiction anchors held.
#[allow(clippy::too_many_arguments)]
fn equilibrium_once(
    model: &Model,
    sys: &System,
    rows: &[usize],
    drivers: &dyn Drivers,
    forces: &dyn AppliedForces,
    start: &State,
    settings: &EquilibriumSettings,
) -> Result<Equilibrium, StaticsError> {
    let p = Problem {
        model,
        sys,
        used: drive_values(model, sys, rows, drivers, start.time)?,
        forces,
        settings,
    };
    let (n, m) = (p.parts(), p.used.len());
    let length = model.characteristic_length;
    let kinematic = m >= 6 * n;
    let mut w = Workspace::new(&p, start);
    let mut s = start.clone();
    // Control states are at rest in an equilibrium.
    s.controls.xdot.fill(0.0);
    let nx = p.controls();
    let mut lambda = vec![0.0; m];
    w.initial_multipliers(&p, &s, &mut lambda)?;
    let mut iterations = 0;
    let mut converged = false;
    let mut last_imbalance;
    // At most IMBALANCE_HISTORY entries whatever MAXIT says (it is user input).
    let mut imbalance_history = Vec::with_capacity(settings.maxit.min(IMBALANCE_HISTORY) + 1);
    // Constraints are held to the assembly accuracy (IC ERROR), not to the looser EQUILIBRIUM
    // ERROR, so that positions are as accurate as the initial conditions.
    let phi_length = model.ic.error.max(STATIC_CONSTRAINT_FLOOR * length);
    let phi_angle = model.ic.error.max(STATIC_CONSTRAINT_FLOOR);
    let mut projected = false;
    let mut unbounded = false;
    // The imbalances of the last iterations (a ring), and how many were recorded.
    let mut history = [0.0; RUNAWAY_WINDOW];
    let mut recorded = 0usize;
    loop {
        let load = w.residuals(&p, &mut s, &lambda)?;
        if w.force.iter().chain(&w.phi).any(|x| !x.is_finite()) {
            return Err(StaticsError::NotFinite {
                iteration: iterations,
            });
        }
        let imbalance = w.force.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let phi_ok = p
            .used
            .iter()
            .zip(&w.phi)
            .all(|((r, _), v)| match sys.rows[*r].unit {
                RowUnit::Length | RowUnit::Mixed => v.abs() <= phi_length,
                _ => v.abs() <= phi_angle,
            });
        // The control states' equations to the EQUILIBRIUM ERROR (relative above 1).
        let states_ok = w
            .state_residual
            .iter()
            .zip(&s.controls.x)
            .all(|(r, x)| r.abs() <= settings.error * x.abs().max(1.0));
        let phi_ok = phi_ok && states_ok;
        last_imbalance = imbalance;
        if imbalance_history.len() < imbalance_history.capacity() {
            imbalance_history.push(imbalance);
        }
        // Balanced to rounding: no Newton correction can improve the forces, and along a
        // free motion without stiffness (a part spinning about a vertical hinge) the
        // correction is that rounding divided by STABILITY × inertia, a drift of the pose
        // that never falls below ERROR. Only the constraints are settled (least change).
        let balanced =
            imbalance <= settings.imbalance && imbalance <= STATIC_ROUNDING_IMBALANCE * load;
        if balanced && phi_ok {
            converged = true;
            break;
        }
        if iterations >= settings.maxit {
            break;
        }
        // Settle the constraints alone, once; should rounding keep them above their tolerance,
        // the next iteration takes a Newton step as usual.
        if balanced && !projected {
            w.project_onto_constraints(&p, &mut s, phi_length.min(phi_angle));
            projected = true;
            iterations += 1;
            continue;
        }
        projected = false;
        // Newton matrix: refreshed as PATTERN says (always the first time).
        let refresh = !w.has_newton_matrix() || refresh_at(&settings.pattern, iterations);
        if refresh {
            w.refresh_newton_matrix(&p, &s, &lambda)?;
        }
        w.newton_correction(settings.stability)?;
        // Step limits: the whole step is scaled so that no part moves by more than TLIMIT or
        // turns by more than ALIMIT, except parts whose correction runs away (beyond
        // `RUNAWAY_CORRECTION`: a free motion without stiffness, where the correction is a
        // load divided by STABILITY × a tiny inertia). Those are cut to the limits on their
        // own, so that they do not stall everything else, and say nothing about convergence
        // (the forces, IMBALANCE, judge those parts).
        for (k, (step, away)) in w.steps.iter_mut().zip(&mut w.runaway).enumerate() {
            let x = &w.rhs[6 * k..6 * k + 6];
            *step = (DVec3::new(x[0], x[1], x[2]), DVec3::new(x[3], x[4], x[5]));
            *away = step.0.length() > RUNAWAY_CORRECTION * length
                || step.1.length() > RUNAWAY_CORRECTION;
        }
        let limit_scale = |(dx, dth): (DVec3, DVec3)| -> f64 {
            (settings.tlimit / dx.length())
                .min(settings.alimit / dth.length())
                .min(1.0)
        };
        let cut = w.runaway.contains(&true);
        let mut scale: f64 = 1.0;
        let mut correction: f64 = 0.0;
        for (&(dx, dth), &away) in w.steps.iter().zip(&w.runaway) {
            if !away {
                scale = scale.min(limit_scale((dx, dth)));
                correction = correction.max(dx.length() / length).max(dth.length());
            }
        }
        // Nor does a step carry a sticking friction out of its stiction band.
        if !cut {
            scale *= w.stiction_scale(&p, &s, scale);
        }
        // A correction beyond TLIMIT/ALIMIT while the forces are already within IMBALANCE,
        // doing negligible work against them (below ERROR × the largest load × the model
        // size): what is left lies along motions whose stiffness is below IMBALANCE/ALIMIT,
        // where the position changes no force worth the name (a symmetric link turning about
        // its own axis: 17 rad of correction for 3e-5 N·m). Such a configuration is an
        // equilibrium; Newton would only walk the part round by ALIMIT per iteration.
        let work: f64 = (0..6 * n).map(|i| w.rhs[i] * w.force[i]).sum::<f64>().abs();
        let soft = (scale < 1.0 || cut) && work <= settings.error * load * length;
        let done =
            imbalance <= settings.imbalance && phi_ok && (correction <= settings.error || soft);
        // Unbounded: a runaway step, and the imbalance not reduced over the last three.
        let slot = recorded % RUNAWAY_WINDOW;
        let before = history[slot];
        history[slot] = imbalance;
        unbounded = cut && recorded >= RUNAWAY_WINDOW && imbalance >= 0.99 * before;
        recorded += 1;
        if done && correction > settings.error {
            // Converged by the soft-direction test: the step would only walk parts along
            // motions that change no force; the configuration stays as it is.
            converged = true;
            break;
        }
        for (k, (&(dx, dth), &away)) in w.steps.iter().zip(&w.runaway).enumerate() {
            let f = match (away, done) {
                (false, _) => scale,
                (true, false) => limit_scale((dx, dth)),
                // Converged: a runaway part stays where the forces balance.
                (true, true) => 0.0,
            };
            s.increment(k, dx * f, dth * f);
        }
        for (k, l) in lambda.iter_mut().enumerate() {
            *l += w.rhs[6 * n + k] * scale;
        }
        for i in 0..nx {
            if !p.held(i) {
                s.controls.x[i] += w.rhs[6 * n + m + i] * scale;
            }
        }
        if scale < 1.0 || cut {
            // A step cut by TLIMIT/ALIMIT leaves the second-order constraint error of a large
            // move: bring the configuration back onto the constraints (least change) so the
            // next Newton step starts from an assembled pose.
            let tolerance = STATIC_CUT_PROJECTION * model.characteristic_length.max(1.0);
            w.project_onto_constraints(&p, &mut s, tolerance);
        }
        if cut {
            // The multipliers' Newton update shares the runaway direction: start them afresh
            // (least squares) at the new configuration.
            w.initial_multipliers(&p, &s, &mut lambda)?;
        }
        if done {
            // The last (small) correction is applied: the result is one Newton step better
            // than the convergence test.
            converged = true;
            break;
        }
        iterations += 1;
    }
    let worst = largest_imbalances(&p, &w);
    let rows_grads: Vec<(usize, &RowGradient)> = p
        .used
        .iter()
        .zip(&w.grads)
        .map(|((r, _), g)| (*r, g))
        .collect();
    let reactions = element_reactions(model, sys, &rows_grads, &lambda, &s);
    let multipliers = p
        .used
        .iter()
        .zip(&lambda)
        .map(|((r, _), l)| (*r, *l))
        .collect();
    let stability = if converged && !kinematic {
        reduced_stability(model, sys, &p.used, &lambda, forces, &s)
    } else {
        None
    };
    Ok(Equilibrium {
        state: s,
        converged,
        iterations,
        imbalance: last_imbalance,
        imbalance_history,
        multipliers,
        reactions,
        stability,
        worst,
        kinematic,
        unbounded: unbounded && !converged,
        approximate_rows: w.approximate.iter().filter(|a| **a).count(),
    })
}

/// The five equations with the largest residuals at the last evaluation (largest first),
/// leaving out those negligible beside the largest ([`STATIC_REPORTED_IMBALANCE`]: a free
/// body's other five balance equations hold exactly).
fn largest_imbalances(p: &Problem, w: &Workspace) -> Vec<(Imbalance, f64)> {
    let mut worst: Vec<(Imbalance, f64)> = w
        .force
        .iter()
        .enumerate()
        .map(|(i, v)| {
            (
                Imbalance::Part {
                    part: i / 6,
                    component: i % 6,
                },
                *v,
            )
        })
        .chain(
            p.used
                .iter()
                .zip(&w.phi)
                .map(|((r, _), v)| (Imbalance::Row(*r), *v)),
        )
        .collect();
    worst.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    let largest = worst.first().map_or(0.0, |w| w.1.abs());
    worst.retain(|w| w.1.abs() > STATIC_REPORTED_IMBALANCE * largest);
    worst.truncate(5);
    worst
}

/// Distinguishes length rows for reporting.
pub fn is_length(unit: RowUnit) -> bool {
    matches!(unit, RowUnit::Length | RowUnit::Mixed)
}

/// A static analysis of an assembled model: one equilibrium at the start time or a
/// quasi-static series.
#[derive(Clone, Debug)]
pub struct StaticRun {
    /// `(time, equilibrium)` at every output time; stops at the first failure; empty when the
    /// model could not be assembled.
    pub steps: Vec<(f64, StepResult)>,
    /// The SENSORs that fired during a quasi-static series, in time order.
    pub sensor_events: Vec<SensorEvent>,
    /// A sensor's HALT or RETURN ended the series (complete) at the last event.
    pub stopped_by_sensor: Option<SensorStop>,
}

impl StaticRun {
    /// Whether every requested equilibrium converged.
    pub fn converged(&self) -> bool {
        !self.steps.is_empty()
            && self
                .steps
                .iter()
                .all(|(_, e)| e.as_ref().is_ok_and(|e| e.converged))
    }
}

/// Output times of a quasi-static series: `steps` equal intervals from 0 to `end`.
pub fn output_times(end: f64, steps: usize) -> Vec<f64> {
    let steps = steps.max(1);
    (0..=steps).map(|k| end * k as f64 / steps as f64).collect()
}

/// Static equilibrium of an assembled model at each of `times` (one time for a single
/// equilibrium), each started from a linear extrapolation of the previous two; nothing when the
/// model could not be assembled ([`Assembled::failure`] says why).
///
/// SENSORs in a quasi-static series (more than one time) are evaluated on every equilibrium
/// (positions at equilibrium, velocities zero) by the dynamic run's watch
/// ([`crate::stages::dynamics::SensorWatch`]): an event between two outputs is located to
/// the sensor's ERROR by solving the equilibrium at trial times (the secant or bisection of
/// the dynamic run). At the event HALT and RETURN end the series (complete, its last
/// equilibrium the event's), PRINT adds the event's equilibrium to the outputs, DT sets the
/// output interval from the event on (`t* + k·DT` up to the last time), and `SENVAL` takes
/// the stored value from then on; RESTART, CODGEN and STEPSIZE have no integrator to act on.
pub fn run(a: &Assembled, times: &[f64]) -> StaticRun {
    run_from(a, a.state(), times)
}

/// [`run`] from the configuration `start` (a state the last analysis of a command file left on
/// the same assembly) rather than the assembled one: the first equilibrium is sought from it.
pub fn run_from(a: &Assembled, start: &State, times: &[f64]) -> StaticRun {
    run_from_streamed(a, start, times, &mut |_, _| true)
}

/// One step of a quasi-static series as it is solved: its time and result.
pub type StepResult = Result<Equilibrium, StaticsError>;

/// [`run_from`], handing each step to `on_step` as soon as it is solved, in the order of
/// [`StaticRun::steps`] (a CSV written row by row). When `on_step` returns `false` the
/// series stops after that step (Ctrl-C, an output that cannot be written); the run then
/// holds the steps up to it.
pub fn run_from_streamed(
    a: &Assembled,
    start: &State,
    times: &[f64],
    on_step: &mut dyn FnMut(f64, &StepResult) -> bool,
) -> StaticRun {
    let mut out = StaticRun {
        steps: Vec::new(),
        sensor_events: Vec::new(),
        stopped_by_sensor: None,
    };
    if a.failure().is_some() {
        return out;
    }
    let mut watch = (times.len() > 1)
        .then(|| SensorWatch::new(a.model))
        .flatten();
    let end = times.last().copied().unwrap_or(0.0);
    let mut schedule = times.to_vec();
    let solve = |start: &State| {
        equilibrium(
            a.model,
            &a.system,
            &a.kept,
            &a.drivers,
            a.forces,
            start,
            &a.model.equilibrium,
        )
    };
    let mut history: Vec<State> = Vec::new();
    let mut k = 0;
    // The steps handed to `on_step` so far.
    let mut handed = 0;
    let mut hand_on = |steps: &mut Vec<(f64, StepResult)>, handed: &mut usize| {
        while let Some((t, r)) = steps.get(*handed) {
            *handed += 1;
            if !on_step(*t, r) {
                steps.truncate(*handed);
                return false;
            }
        }
        true
    };
    while k < schedule.len() {
        if !hand_on(&mut out.steps, &mut handed) {
            return out;
        }
        let t = schedule[k];
        let mut start = match history.as_slice() {
            [] => start.clone(),
            [only] => only.clone(),
            [.., a, b] => extrapolate(a, b),
        };
        start.time = t;
        let eq = match solve(&start) {
            Ok(eq) if eq.converged && watch.is_some() => eq,
            result => {
                let ok = result.as_ref().is_ok_and(|e| e.converged);
                if let Ok(e) = &result {
                    history.push(e.state.clone());
                }
                out.steps.push((t, result));
                if !ok {
                    break;
                }
                k += 1;
                continue;
            }
        };
        // (Always a watch here.)
        let Some(w) = watch.as_mut() else { break };
        let point = at_rest(a.model, &eq);
        // The equilibria solved while locating an event, and the first failure among them.
        let mut located: Vec<Equilibrium> = Vec::new();
        let mut failed: Option<(f64, StaticsError)> = None;
        let fired = if history.is_empty() {
            w.start(a.model, &point).map(|()| None)
        } else {
            w.after_point(a.model, point, &mut |from, t| {
                let mut s = from.state.clone();
                s.time = t;
                match solve(&s) {
                    Ok(e) if e.converged => {
                        let o = at_rest(a.model, &e);
                        located.push(e);
                        Ok(o)
                    }
                    Ok(e) => {
                        let why = e.failure(a.model, &a.system).unwrap_or_default();
                        failed = Some((t, StaticsError::Sensor(why.clone())));
                        Err(IntegrationError::Sensor {
                            sensor: "the quasi-static event location".into(),
                            cause: why,
                        })
                    }
                    Err(err) => {
                        let why = err.to_string();
                        failed = Some((t, err));
                        Err(IntegrationError::Sensor {
                            sensor: "the quasi-static event location".into(),
                            cause: why,
                        })
                    }
                }
            })
        };
        let fired = match fired {
            Ok(f) => f,
            Err(e) => {
                let (at, err) = failed.unwrap_or((t, StaticsError::Sensor(e.to_string())));
                out.steps.push((at, Err(err)));
                break;
            }
        };
        let Some(fired) = fired else {
            history.push(eq.state.clone());
            out.steps.push((t, Ok(eq)));
            k += 1;
            continue;
        };
        out.sensor_events.extend(fired.events);
        let at = fired.output.time;
        let event = if fired.before_step_end {
            located.into_iter().rev().find(|e| e.state.time == at)
        } else {
            None
        };
        if fired.stop.is_some() {
            out.stopped_by_sensor = fired.stop;
            out.steps.push(match event {
                Some(e) => (at, Ok(e)),
                None => (t, Ok(eq)),
            });
            break;
        }
        if let Some(e) = event.as_ref().filter(|_| fired.print) {
            out.steps.push((at, Ok(e.clone())));
        }
        match fired.dt {
            Some(dt) => {
                let from = match event {
                    Some(e) => e.state,
                    None => {
                        let s = eq.state.clone();
                        out.steps.push((t, Ok(eq)));
                        k += 1;
                        s
                    }
                };
                outputs_every(&mut schedule, k, at, dt, end);
                history = vec![from];
            }
            None => {
                history.push(eq.state.clone());
                out.steps.push((t, Ok(eq)));
                k += 1;
            }
        }
        // The next equilibria start with the values the sensors stored (SENVAL).
        if let Some(s) = history.last_mut() {
            w.carry(s);
        }
    }
    hand_on(&mut out.steps, &mut handed);
    out
}

/// An equilibrium as the sensors see it: positions, zero velocities and accelerations, its
/// reactions.
fn at_rest(model: &Model, e: &Equilibrium) -> Output {
    let rest = vec![(DVec3::ZERO, DVec3::ZERO); model.parts.len()];
    Output {
        time: e.state.time,
        state: e.state.clone(),
        velocities: rest.clone(),
        accelerations: rest,
        reactions: e.reactions.clone(),
    }
}

/// `b + (b − a)` on the configuration manifold.
fn extrapolate(a: &State, b: &State) -> State {
    let mut s = b.clone();
    for k in 0..s.poses.len() {
        let dx = b.poses[k].p - a.poses[k].p;
        let dth = linkage_model::frames::log_so3(&(b.poses[k].r * a.poses[k].r.transpose()));
        s.increment(k, dx, dth);
    }
    s
}
