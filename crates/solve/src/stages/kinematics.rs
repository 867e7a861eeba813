//! Kinematic analysis of models without degrees of freedom (Adams: "the data set is
//! kinematically determinate").
//!
//! When the independent constraint rows fix every coordinate (`m = 6n` after the redundant rows
//! are removed), motion follows from the constraints alone; the equations of motion only give
//! the reactions. At every output time `t`:
//!
//! ```text
//! positions      Φ(q, t) = 0             Newton: J δ = −Φ (J square and regular)
//! velocities     J v = ḟ(t)              (motion rates; 0 for joints)
//! accelerations  J a = f̈(t) − γ(q, v)    γ: velocity-product terms of Φ̈
//! reactions      M a + UCF·Jᵀλ = UCF·Q   (λ from the same KKT solve)
//! ```
//!
//! Nothing is integrated, so there is no integration error: positions are exact to
//! [`POSITION_TOLERANCE`] at every output. Each position solve starts from a second-order
//! extrapolation `q + v Δt + a Δt²/2` of the previous output. Removed rows are checked at every
//! output like in the dynamic run.

use crate::constraints::residuals::{report_residual, report_unit_suffix};
use crate::constraints::rows::RowGradient;
use crate::constraints::system::RowUnit;
use crate::kernel::redundant::redundant_violation;
use crate::kernel::{
    flat, outputs_every, Failure, IntegrationError, Output, OutputSolver, Problem, SensorWatch,
    Simulation,
};
use crate::linalg::kkt::{jacobian_entries, CoordinateScale, Zeros};
use crate::linalg::linear::SparseLu;
use crate::stages::dynamics::AfterOutput;
use crate::state::State;
use crate::tolerances::KINEMATIC_POSITION;
use glam::DVec3;

/// Largest constraint residual accepted for positions: lengths relative to the model's
/// characteristic length, angles and direction cosines absolute
/// ([`crate::tolerances::KINEMATIC_POSITION`]).
pub const POSITION_TOLERANCE: f64 = KINEMATIC_POSITION;

/// Newton iterations per output time before the position solve gives up.
pub const MAX_ITERATIONS: usize = 25;

/// Runs the kinematic analysis at `times` from the assembled `start` with velocities `v0`
/// (used only as the first velocity guess), handing each output to `on_output` as it is
/// computed (nothing is kept: a run of a million outputs needs the memory of one). The
/// returned simulation's `outputs` is empty and `output_count` counts the outputs handed
/// over. `progress` sees the time after each output; [`AfterOutput::Stop`] from it ends the
/// run there with [`IntegrationError::Stopped`] (Ctrl-C, a time limit), and from
/// `on_output` ends it at that output (its sink failed).
///
/// SENSORs are evaluated at every output, as a dynamic run evaluates them after every step
/// (the watch and its event location are [`crate::stages::dynamics::SensorWatch`]'s): an
/// event between two outputs is located to the sensor's ERROR by solving the positions at
/// trial times. At the event, HALT and RETURN end the run (its last output the event),
/// PRINT writes an output there, DT sets the output interval from the event on (outputs at
/// `t* + k·DT` up to the last requested time); RESTART, CODGEN and STEPSIZE have nothing to
/// act on (there is no integrator) and are reported with the event.
pub(crate) fn run_streamed(
    p: &Problem,
    start: &State,
    v0: &[(DVec3, DVec3)],
    times: &[f64],
    mut progress: impl FnMut(f64) -> AfterOutput,
    mut on_output: impl FnMut(Output) -> AfterOutput,
) -> Simulation {
    let mut sim = Simulation::empty(true);
    let mut solver = match OutputSolver::new(p, start, v0) {
        Ok(s) => s,
        Err(e) => {
            sim.failure = Some(Failure::new(start.time, e));
            return sim;
        }
    };
    // Hands an output on; `false` when the run ends there.
    let mut emit = |sim: &mut Simulation, o: Output| {
        sim.output_count += 1;
        on_output(o) == AfterOutput::Continue
    };
    let mut sensors = SensorWatch::new(p.model);
    let end = times.last().copied().unwrap_or(start.time);
    let mut schedule = times.to_vec();
    let v0 = flat(v0);
    let mut previous: Option<Output> = None;
    let mut k = 0;
    while k < schedule.len() {
        let t = schedule[k];
        let output = match point(p, &mut solver, start, &v0, previous.as_ref(), t) {
            Ok(o) => o,
            Err(f) => {
                sim.failure = Some(f);
                return sim;
            }
        };
        sim.steps += 1;
        let Some(w) = sensors.as_mut() else {
            previous = Some(output.clone());
            if !emit(&mut sim, output) {
                return sim;
            }
            if progress(t) == AfterOutput::Stop {
                sim.failure = Some(Failure::new(t, IntegrationError::Stopped));
                return sim;
            }
            k += 1;
            continue;
        };
        let fired = if previous.is_none() {
            w.start(p.model, &output).map(|()| None)
        } else {
            w.after_point(p.model, output.clone(), &mut |from, t| {
                point(p, &mut solver, start, &v0, Some(from), t).map_err(|f| f.cause)
            })
        };
        let fired = match fired {
            Ok(f) => f,
            Err(e) => {
                sim.failure = Some(Failure::new(t, e));
                return sim;
            }
        };
        let Some(fired) = fired else {
            previous = Some(output.clone());
            if !emit(&mut sim, output) {
                return sim;
            }
            if progress(t) == AfterOutput::Stop {
                sim.failure = Some(Failure::new(t, IntegrationError::Stopped));
                return sim;
            }
            k += 1;
            continue;
        };
        sim.sensor_events.extend(fired.events);
        if fired.stop.is_some() {
            sim.stopped_by_sensor = fired.stop;
            emit(&mut sim, fired.output);
            return sim;
        }
        let at = fired.output.time;
        if fired.before_step_end && fired.print && !emit(&mut sim, fired.output.clone()) {
            return sim;
        }
        match fired.dt {
            // From the event on, outputs every DT: the output at t (after the event) is
            // replaced by the new grid.
            Some(dt) => {
                if !fired.before_step_end {
                    if !emit(&mut sim, output) {
                        return sim;
                    }
                    k += 1;
                }
                outputs_every(&mut schedule, k, at, dt, end);
                previous = Some(fired.output);
            }
            None => {
                previous = Some(output.clone());
                if !emit(&mut sim, output) {
                    return sim;
                }
                k += 1;
            }
        }
        // The next positions are solved with the values the sensors stored (SENVAL).
        if let Some(o) = previous.as_mut() {
            w.carry(&mut o.state);
        }
        if progress(at.max(t)) == AfterOutput::Stop {
            sim.failure = Some(Failure::new(at.max(t), IntegrationError::Stopped));
            return sim;
        }
    }
    sim
}

/// The consistent output at time `t`: positions by Newton from a second-order extrapolation
/// `q + v Δt + a Δt²/2` of `from` (or from `start`), removed rows checked, then
/// velocities, accelerations and reactions.
fn point(
    p: &Problem,
    solver: &mut OutputSolver,
    start: &State,
    v0: &[f64],
    from: Option<&Output>,
    t: f64,
) -> Result<Output, Failure> {
    let (mut guess, v) = match from {
        None => (start.clone(), v0.to_vec()),
        Some(o) => {
            let dt = t - o.time;
            let vel = flat(&o.velocities);
            // Accelerations reported as NaN (unknown second derivatives) do not extrapolate.
            let acc = flat(&o.accelerations);
            let d: Vec<f64> = (0..vel.len())
                .map(|i| {
                    let a = if acc[i].is_finite() { acc[i] } else { 0.0 };
                    vel[i] * dt + 0.5 * a * dt * dt
                })
                .collect();
            (apply(&o.state, &d), vel)
        }
    };
    guess.time = t;
    let s = positions(p, guess).map_err(|e| Failure::new(t, e))?;
    if let Some(f) = redundant_violation(
        p,
        &s,
        p.model.characteristic_length,
        crate::tolerances::REDUNDANT_DRIFT,
    ) {
        return Err(f);
    }
    solver.output(p, &s, &v).map_err(|e| Failure::new(t, e))
}

/// Whether the residual `v` of a row with unit `unit` is within [`POSITION_TOLERANCE`].
fn holds(unit: RowUnit, v: f64, length: f64) -> bool {
    match unit {
        RowUnit::Length | RowUnit::Mixed => v.abs() <= POSITION_TOLERANCE * length,
        _ => v.abs() <= POSITION_TOLERANCE,
    }
}

/// Solves `Φ(q, t) = 0` for the positions by Newton's method from `s` (time `s.time`).
fn positions(p: &Problem, mut s: State) -> Result<State, IntegrationError> {
    let n = p.model.parts.len();
    let m = p.rows.len();
    let length = p.model.characteristic_length;
    let mut drives = vec![0.0; m];
    p.drives_into(s.time, &mut drives)?;
    let mut g = RowGradient::default();
    let mut worst = (0usize, 0.0f64);
    for _ in 0..MAX_ITERATIONS {
        let phi: Vec<f64> = p
            .rows
            .iter()
            .zip(&drives)
            .map(|(&r, &d)| p.sys.residual(r, &s, d))
            .collect();
        if let Some(k) = phi.iter().position(|v| !v.is_finite()) {
            let row = &p.sys.rows[p.rows[k]];
            return Err(IntegrationError::PositionNotEvaluable {
                equation: row.label,
                element: p.model.constraints[row.element].origin.name.clone(),
                time: s.time,
            });
        }
        worst = phi
            .iter()
            .enumerate()
            .map(|(k, v)| {
                // Lengths relative to the characteristic length.
                let reference = match p.sys.rows[p.rows[k]].unit {
                    RowUnit::Length | RowUnit::Mixed => length,
                    _ => 1.0,
                };
                (k, v.abs() / reference)
            })
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if p.rows
            .iter()
            .zip(&phi)
            .all(|(&r, &v)| holds(p.sys.rows[r].unit, v, length))
        {
            return Ok(s);
        }
        let mut entries = Vec::new();
        for (k, &r) in p.rows.iter().enumerate() {
            p.sys.gradient(r, &s, &mut g);
            jacobian_entries(&mut entries, k, &g, CoordinateScale::IDENTITY, Zeros::Skip);
        }
        let mut rhs: Vec<f64> = phi.iter().map(|v| -v).collect();
        let solved = (m == 6 * n)
            .then(|| SparseLu::factor(m, &entries).and_then(|lu| lu.solve(&mut rhs)))
            .and_then(Result::ok);
        if solved.is_none() {
            return Err(IntegrationError::PositionsSingular { time: s.time });
        }
        s = State {
            time: s.time,
            ..apply(&s, &rhs)
        };
    }
    let row = &p.sys.rows[p.rows[worst.0]];
    let value = p.sys.residual(p.rows[worst.0], &s, drives[worst.0]);
    Err(IntegrationError::PositionsNotFound {
        time: s.time,
        iterations: MAX_ITERATIONS,
        residual: report_residual(row.unit, value),
        unit: report_unit_suffix(row.unit),
        equation: row.label,
        element: p.model.constraints[row.element].origin.name.clone(),
    })
}

/// `s` with every part moved by the tangent increment `d` (6 per part: translation, rotation
/// vector in ground axes).
fn apply(s: &State, d: &[f64]) -> State {
    let mut t = s.clone();
    for (k, c) in d.chunks_exact(6).enumerate() {
        t.increment(
            k,
            DVec3::new(c[0], c[1], c[2]),
            DVec3::new(c[3], c[4], c[5]),
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use crate::constraints::drivers::ExpressionDrivers;
    use crate::stages::dynamics::IntegratorSettings;

    use crate::stages::dynamics::IntegrationError;

    fn load(text: &str) -> linkage_model::Model {
        let ds =
            linkage_adm::parse_dataset(std::sync::Arc::from("test.adm"), text).expect("parses");
        linkage_model::build_model(&ds).expect("builds").model
    }

    /// A slider driven along x by `x = 0.1 + 0.2 t²` on a translational joint (zero DOF):
    /// exact positions, velocities, accelerations and the driving force `m ẍ` at every output.
    #[test]
    fn a_driven_slider_follows_its_motion_exactly() {
        let model = load(
            "slider\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
             PART/1, GROUND\nMARKER/1, PART = 1, REULER = 90D, 90D, 0D\n\
             PART/2, MASS = 3, CM = 2, IP = 1, 1, 1\nMARKER/2, PART = 2\n\
             MARKER/3, PART = 2, REULER = 90D, 90D, 0D\n\
             JOINT/1, TRANSLATIONAL, I = 3, J = 1\n\
             MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = 0.1 + 0.2*TIME**2\nEND\n",
        );
        let drivers = ExpressionDrivers::new(&model).unwrap();
        let forces = crate::physics::applied::NoForces;
        let tol = crate::tolerances::Tolerances::default();
        let times = [0.0, 0.5, 1.0, 2.0];
        let assembled = crate::pipeline::Assembled::new(&model, &drivers, &forces, &tol);
        let run = crate::stages::dynamics::run(
            &assembled,
            &times,
            &IntegratorSettings::default(),
            crate::stages::dynamics::Start::InitialConditions,
            |_| {},
        );
        let sim = run.simulation.expect("runs");
        assert!(sim.kinematic);
        assert!(sim.failure.is_none(), "{:?}", sim.failure);
        assert_eq!(sim.outputs.len(), 4);
        for o in &sim.outputs {
            let t = o.time;
            let x = o.state.poses[0].p.x;
            assert!((x - (0.1 + 0.2 * t * t)).abs() < 1e-12, "t {t}: x {x}");
            assert!((o.velocities[0].0.x - 0.4 * t).abs() < 1e-10);
            assert!((o.accelerations[0].0.x - 0.4).abs() < 1e-9);
            // The motion pushes the slider (its joint's I marker) with m ẍ = +1.2 N along x;
            // no gravity.
            let motion = o
                .reactions
                .iter()
                .find(|r| model.constraints[r.element].origin.name == "MOTION_1")
                .unwrap();
            assert!((motion.force.x - 1.2).abs() < 1e-9, "{:?}", motion.force);
        }
    }

    /// The slider's motion `x = SQRT(0.5 − t)` has no value after t = 0.5: the run stops at
    /// the first output past it, with the motion and the time as values.
    #[test]
    fn a_motion_without_a_value_stops_the_run_naming_it() {
        let model = load(
            "slider\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
             PART/1, GROUND\nMARKER/1, PART = 1, REULER = 90D, 90D, 0D\n\
             PART/2, MASS = 3, CM = 2, IP = 1, 1, 1\nMARKER/2, PART = 2\n\
             MARKER/3, PART = 2, REULER = 90D, 90D, 0D\n\
             JOINT/1, TRANSLATIONAL, I = 3, J = 1\n\
             MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = SQRT(0.5 - TIME)\nEND\n",
        );
        let drivers = ExpressionDrivers::new(&model).unwrap();
        let forces = crate::physics::applied::NoForces;
        let tol = crate::tolerances::Tolerances::default();
        let assembled = crate::pipeline::Assembled::new(&model, &drivers, &forces, &tol);
        let run = crate::stages::dynamics::run(
            &assembled,
            &[0.0, 0.25, 1.0],
            &IntegratorSettings::default(),
            crate::stages::dynamics::Start::InitialConditions,
            |_| {},
        );
        let sim = run.simulation.expect("runs");
        assert!(sim.kinematic);
        assert_eq!(sim.outputs.len(), 2);
        let f = sim.failure.expect("stops");
        assert_eq!(f.time, 1.0);
        match &f.cause {
            IntegrationError::Motion(crate::constraints::drivers::MotionError {
                element,
                time,
                ..
            }) => {
                assert!(element.starts_with("MOTION_1"), "{element}");
                assert_eq!(*time, 1.0);
            }
            other => panic!("unexpected cause {other:?}"),
        }
        assert_eq!(f.message, f.cause.to_string());
    }
}
