//! SENSORs during a dynamic run (ADM-ELEMENTS §5): evaluation after every accepted step, event
//! location to the sensor's ERROR, and the actions the simulate loop carries out.
//!
//! Contract.
//! - Each sensor watches `g(t) = FUNCTION − VALUE`, evaluated on the consistent output of every
//!   accepted step (positions, velocities and time: `StateEnv`; accelerations and forces are
//!   not available to a sensor). It is *true* as [`linkage_model::sensors::Sensor::holds`]
//!   says and *fires* when it becomes true: after a step at whose beginning it was false. A
//!   sensor true at the start of a run fires only after having been false (so a run that
//!   continues after a RETURN goes on); after firing it fires again only after having been
//!   false.
//! - Event location: when a step from `t₀` to `t₁` carries `g` across the band `|g| ≤ ERROR`
//!   (g changes sign, or GE/LE end beyond it), the event time `t*` is found by the secant
//!   method on `g` (Illinois variant, keeping a bracket), or by bisection with `BISECTION`,
//!   until `|g(t*)| ≤ ERROR`. Each trial time is reached by *re-stepping*: a fresh integrator
//!   started from the accepted state at `t₀` integrates to it with the run's error control
//!   (the integrator's own step is never rolled back). The run then continues from `t*`.
//! - Actions at `t*`: HALT ends the run there with an output at `t*` (the run is complete, not
//!   failed); RETURN does the same and, in a command file, returns to the next command (HALT
//!   ends the command file); PRINT writes an output at `t*`; RESTART and CODGEN restart the
//!   integrator from `t*` (order 1, a new factorisation and pivot sequence); STEPSIZE sets the
//!   next trial step; YYDUMP keeps the state at `t*` in the event record for the report; DT
//!   sets the output interval from `t*` on (outputs at `t* + k·DT` up to the run's end, in
//!   place of the requested ones not yet written: [`Fired::reschedule`]).
//!   EVALUATE (or FUNCTION when there is none) is evaluated at `t*` and stored as the sensor's
//!   value, which `SENVAL(id)` returns from then on in forces, VARIABLEs and REQUESTs (the
//!   [`SensorValues`] the force set shares; a changed value restarts the integrator at `t*`).
//!
//! Cost: one consistent-output solve per accepted step when the model has sensors (none
//! otherwise); an event costs a few short re-integrations from the step's start.

use super::corrector::StepTolerance;
use super::error::IntegrationError;
use super::output::Output;
use super::problem::Problem;
use super::stepper::Stepper;
use crate::physics::applied::AppliedForces;
use crate::physics::forces::data::{DataElements, SensorValues};
use crate::physics::measures::{MarkerFrames, StateEnv};
use crate::tolerances::LOCAL_ERROR_FLOOR;
use linkage_expr::Expr;
use linkage_model::settings::IntegratorSettings;
use linkage_model::Model;

/// Most trial times of one event location (secant or bisection).
const MAX_LOCATION_TRIALS: usize = 60;

/// A sensor that fired, as the reports show it.
#[derive(Clone, Debug)]
pub struct SensorEvent {
    /// `SENSOR_3`.
    pub name: String,
    /// `SENSOR/3`.
    pub element: String,
    pub time: f64,
    /// FUNCTION at the event.
    pub function: f64,
    /// The value stored for `SENVAL` (EVALUATE at the event, else FUNCTION).
    pub stored: f64,
    /// The actions carried out (`HALT`, `RETURN`, `PRINT`, `RESTART`, `CODGEN`, `YYDUMP`,
    /// `STEPSIZE`).
    pub actions: Vec<&'static str>,
    /// YYDUMP: the output (state and velocities) at the event.
    pub dump: Option<Box<Output>>,
}

/// How a sensor ended the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorStop {
    /// HALT: the run (and a command file) ends.
    Halt,
    /// RETURN: the run ends; a command file goes on with its next command.
    Return,
}

/// What the simulate loop does after sensors fired.
#[derive(Debug)]
pub struct Fired {
    /// The consistent output at the event time.
    pub output: Output,
    /// The event lies before the integrator's current time (it was located inside the last
    /// step): the integrator must continue from `output`.
    pub before_step_end: bool,
    pub stop: Option<SensorStop>,
    /// PRINT: write `output`.
    pub print: bool,
    /// RESTART or CODGEN: restart the integrator from `output`.
    pub restart: bool,
    /// STEPSIZE: the next trial step.
    pub step: Option<f64>,
    /// DT: the output interval from the event on (the smallest of the sensors that fired).
    pub dt: Option<f64>,
    pub events: Vec<SensorEvent>,
}

impl Fired {
    /// DT in a dynamic run: from the event on, the output times are `t* + k·DT` up to `end`
    /// (the last one `end`), in place of those not written yet, `schedule[next..]`
    /// ([`outputs_every`], shared with the kinematic and quasi-static runs). `event_written`:
    /// the event lies on the output `schedule[next]`, which is still written (the step ended
    /// on it), so it is kept. Nothing changes without a DT.
    pub fn reschedule(&self, schedule: &mut Vec<f64>, next: usize, event_written: bool, end: f64) {
        if let Some(dt) = self.dt {
            let kept = (next + usize::from(event_written)).min(schedule.len());
            outputs_every(schedule, kept, self.output.time, dt, end);
        }
    }
}

/// The sensors of a run and what they saw last.
pub struct SensorWatch {
    frames: MarkerFrames,
    data: DataElements,
    /// Per sensor: true at the last accepted point.
    active: Vec<bool>,
    /// The last accepted point and `g` of every sensor there.
    last: Option<(Output, Vec<f64>)>,
    /// Per sensor: its stored value (`SENVAL`), 0 before it first fires; shared with the
    /// forces, which read it through `SENVAL`.
    pub stored: SensorValues,
}

fn function(model: &Model, s: usize) -> Result<&Expr, IntegrationError> {
    let sensor = &model.sensors[s];
    sensor
        .function
        .as_deref()
        .ok_or_else(|| IntegrationError::Sensor {
            sensor: sensor.origin.name.clone(),
            cause: "its FUNCTION cannot be evaluated by linkage (a USER subroutine)".into(),
        })
}

impl SensorWatch {
    /// The watch over `model`'s sensors; `None` when it has none (the run pays nothing).
    /// The stored values are those `forces` read (`SENVAL`), so a firing changes the forces
    /// from then on.
    pub fn new(model: &Model, forces: &dyn AppliedForces) -> Option<SensorWatch> {
        if model.sensors.is_empty() {
            return None;
        }
        let mut data = DataElements::new(model).0;
        if let Some(v) = forces.sensor_values() {
            data.sensor_values = v.clone();
        }
        Some(SensorWatch {
            frames: MarkerFrames::new(model),
            stored: data.sensor_values.clone(),
            data,
            active: vec![false; model.sensors.len()],
            last: None,
        })
    }

    /// `expr` at output `o`.
    fn eval(
        &self,
        model: &Model,
        s: usize,
        expr: &Expr,
        o: &Output,
    ) -> Result<f64, IntegrationError> {
        let env = StateEnv::new(&self.frames, &o.state, &o.velocities, &self.data);
        linkage_expr::evaluate(expr, &env).map_err(|e| IntegrationError::Sensor {
            sensor: model.sensors[s].origin.name.clone(),
            cause: e.to_string(),
        })
    }

    /// `g = FUNCTION − VALUE` of every sensor at `o`.
    fn gaps(&self, model: &Model, o: &Output) -> Result<Vec<f64>, IntegrationError> {
        (0..model.sensors.len())
            .map(|s| Ok(self.eval(model, s, function(model, s)?, o)? - model.sensors[s].value))
            .collect()
    }

    /// The sensors at the start of the run (`first`, the output at the start time): those
    /// true there are armed only once they have been false (a run that continues after a
    /// RETURN does not stop again at once).
    pub fn start(&mut self, model: &Model, first: &Output) -> Result<(), IntegrationError> {
        let g = self.gaps(model, first)?;
        for (s, sensor) in model.sensors.iter().enumerate() {
            self.active[s] = sensor.holds(g[s]);
        }
        self.last = Some((first.clone(), g));
        Ok(())
    }

    /// After an accepted step of `integ`: evaluates the sensors on its output, locates an
    /// event inside the step by re-stepping from the step's start, and says what fired.
    /// `span` is the run's length (the error per step is `ERROR·h/span` for BDF).
    pub fn after_step(
        &mut self,
        p: &Problem,
        integ: &mut Stepper,
        settings: &IntegratorSettings,
        span: f64,
    ) -> Result<Option<Fired>, IntegrationError> {
        let o1 = integ.output()?;
        self.after_point(p.model, o1, &mut |from, t| {
            integrate_to(p, from, t, settings, span)
        })
    }

    /// After the run reached the point `o1` (an accepted step, a kinematic output, a
    /// quasi-static equilibrium): evaluates the sensors there, locates an event since the
    /// last point with `reach(from, t)` (the run's own point at time `t`, continued from the
    /// point `from`: re-stepping, a position solve, an equilibrium), and says what fired.
    pub fn after_point(
        &mut self,
        model: &Model,
        o1: Output,
        reach: &mut dyn FnMut(&Output, f64) -> Result<Output, IntegrationError>,
    ) -> Result<Option<Fired>, IntegrationError> {
        let g1 = self.gaps(model, &o1)?;
        let Some((o0, g0)) = self.last.take() else {
            self.last = Some((o1, g1));
            return Ok(None);
        };
        // Sensors that become true in this step; those whose g stepped over the band need
        // the crossing located.
        let mut earliest: Option<(f64, Output, Vec<f64>)> = None;
        let mut firing_at_end = Vec::new();
        for (s, sensor) in model.sensors.iter().enumerate() {
            if self.active[s] {
                continue;
            }
            let crossed = g0[s] * g1[s] < 0.0;
            let beyond = g1[s].abs() > sensor.error;
            if sensor.holds(g1[s]) && !beyond {
                firing_at_end.push(s);
            } else if crossed && (sensor.holds(g1[s]) || beyond) {
                let (t, o, g) = self.locate(model, s, &o0, g0[s], &o1, g1[s], reach)?;
                if earliest.as_ref().is_none_or(|(te, _, _)| t < *te) {
                    earliest = Some((t, o, g));
                }
            }
        }
        let (output, g, before) = match earliest {
            Some((_, o, g)) => (o, g, true),
            None if !firing_at_end.is_empty() => (o1.clone(), g1.clone(), false),
            None => {
                for (s, sensor) in model.sensors.iter().enumerate() {
                    self.active[s] = sensor.holds(g1[s]);
                }
                self.last = Some((o1, g1));
                return Ok(None);
            }
        };
        // Every sensor that is newly true at the event time fires there.
        let firing: Vec<usize> = (0..g.len())
            .filter(|&s| !self.active[s] && model.sensors[s].holds(g[s]))
            .collect();
        let fired = self.fire(model, output.clone(), &g, &firing, before)?;
        self.last = Some((output, g));
        Ok(fired)
    }

    /// The event of sensor `s` between `o0` (g0) and `o1` (g1): the time where `|g| ≤ ERROR`,
    /// by the Illinois secant method (or bisection), each trial reached from `o0` by `reach`.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &self,
        model: &Model,
        s: usize,
        o0: &Output,
        g0: f64,
        o1: &Output,
        g1: f64,
        reach: &mut dyn FnMut(&Output, f64) -> Result<Output, IntegrationError>,
    ) -> Result<(f64, Output, Vec<f64>), IntegrationError> {
        let sensor = &model.sensors[s];
        let (mut ta, mut ga) = (o0.time, g0);
        let (mut tb, mut gb) = (o1.time, g1);
        let mut best = (o1.time, o1.clone());
        let mut side = 0i8;
        for _ in 0..MAX_LOCATION_TRIALS {
            let t = if sensor.bisection {
                0.5 * (ta + tb)
            } else {
                (ta - ga * (tb - ta) / (gb - ga)).clamp(ta, tb)
            };
            let o = reach(o0, t)?;
            let g = self.eval(model, s, function(model, s)?, &o)? - sensor.value;
            if g.abs() <= sensor.error {
                let all = self.gaps(model, &o)?;
                return Ok((t, o, all));
            }
            best = (t, o);
            // Keep the bracket; Illinois: halve the stale end's g when one side repeats.
            if (g < 0.0) == (ga < 0.0) {
                ta = t;
                ga = g;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                tb = t;
                gb = g;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        // Not within ERROR after the trials (a discontinuous FUNCTION): the end of the
        // bracket where the sensor holds.
        let o = if tb < best.0 { reach(o0, tb)? } else { best.1 };
        let all = self.gaps(model, &o)?;
        Ok((o.time, o, all))
    }

    /// Fires `firing` at output `o` (their gaps `g`): stores SENVAL, collects the actions.
    fn fire(
        &mut self,
        model: &Model,
        output: Output,
        g: &[f64],
        firing: &[usize],
        before_step_end: bool,
    ) -> Result<Option<Fired>, IntegrationError> {
        for (s, sensor) in model.sensors.iter().enumerate() {
            self.active[s] = sensor.holds(g[s]);
        }
        if firing.is_empty() {
            return Ok(None);
        }
        let mut fired = Fired {
            output,
            before_step_end,
            stop: None,
            print: false,
            restart: false,
            step: None,
            dt: None,
            events: Vec::new(),
        };
        for &s in firing {
            let sensor = &model.sensors[s];
            let stored = match &sensor.evaluate {
                Some(e) => self.eval(model, s, e, &fired.output)?,
                None => g[s] + sensor.value,
            };
            // A new stored value changes the forces that read SENVAL: the integrator
            // restarts from the event.
            if self.stored.get(s) != stored {
                fired.restart = true;
            }
            self.stored.set(s, stored);
            let a = &sensor.actions;
            if a.halt {
                fired.stop = Some(SensorStop::Halt);
            } else if a.return_ && fired.stop.is_none() {
                fired.stop = Some(SensorStop::Return);
            }
            fired.print |= a.print;
            fired.restart |= a.restart || a.codgen;
            if let Some(h) = sensor.stepsize {
                fired.step = Some(fired.step.map_or(h, |x: f64| x.min(h)));
            }
            if let Some(dt) = sensor.dt {
                fired.dt = Some(fired.dt.map_or(dt, |x: f64| x.min(dt)));
            }
            fired.events.push(SensorEvent {
                name: sensor.origin.name.clone(),
                element: sensor.origin.element(),
                time: fired.output.time,
                function: g[s] + sensor.value,
                stored,
                actions: sensor.action_names(),
                dump: a.yydump.then(|| Box::new(fired.output.clone())),
            });
        }
        Ok(Some(fired))
    }
}

/// The consistent output at time `t` of a fresh integrator started from `from` (order 1),
/// with the run's error control: the local error of a step of size h at most
/// `ERROR·h/span` for BDF (at least [`LOCAL_ERROR_FLOOR`]), ERROR for HHT.
fn integrate_to(
    p: &Problem,
    from: &Output,
    t: f64,
    settings: &IntegratorSettings,
    span: f64,
) -> Result<Output, IntegrationError> {
    let (mut integ, first) = Stepper::new(p, &from.state, &from.velocities, settings)?;
    if t <= from.time {
        return Ok(first);
    }
    let per_run = integ.error_per_run();
    let mut h = (t - from.time).min(settings.hmax.unwrap_or(f64::INFINITY));
    while integ.time() < t {
        let remaining = t - integ.time();
        let hs = h.min(remaining);
        let last = hs >= remaining * (1.0 - 1e-12);
        let hs = if last { remaining } else { hs };
        let within = StepTolerance::new(settings.error, per_run, hs, span, LOCAL_ERROR_FLOOR);
        let tol = within.local;
        match integ.try_step(hs, within) {
            Ok(err) if err <= tol || hs <= settings.hmin => {
                integ.accept(err, tol);
                if last {
                    break;
                }
                let grow = if err > 0.0 {
                    (0.9 * (tol / err).powf(1.0 / (integ.order() as f64 + 1.0))).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                h = hs * grow;
            }
            Ok(err) => {
                let shrink = 0.9 * (tol / err).powf(1.0 / (integ.order() as f64 + 1.0));
                h = (hs * shrink.clamp(0.2, 0.9)).max(settings.hmin);
            }
            Err(e) if hs <= settings.hmin => return Err(e),
            Err(_) => h = (hs * 0.25).max(settings.hmin),
        }
    }
    integ.output()
}

/// Output times closer than this fraction of a sensor's DT to the end are the end.
const OUTPUT_GRID: f64 = 1e-9;

/// A sensor's `DT` from the event at `at` on: keeps `schedule[..kept]`, then outputs every
/// `dt` up to `end`, the last one at `end` (a remainder shorter than `OUTPUT_GRID·dt` is
/// dropped). Shared by the kinematic and quasi-static runs.
pub fn outputs_every(schedule: &mut Vec<f64>, kept: usize, at: f64, dt: f64, end: f64) {
    schedule.truncate(kept);
    let mut j = 1.0;
    while at + j * dt <= end + OUTPUT_GRID * dt {
        schedule.push((at + j * dt).min(end));
        j += 1.0;
    }
    if schedule
        .last()
        .is_some_and(|last| *last < end - OUTPUT_GRID * dt)
    {
        schedule.push(end);
    }
}
