//! SENSOR events inside a dynamic step: the kernel's [`SensorWatch`] evaluates the sensors and
//! locates an event through a `reach(from, t)` closure; here that closure re-steps: a fresh
//! integrator started from the accepted state at the step's start integrates to each trial
//! time with the run's error control (the running integrator's own step is never rolled
//! back). The contract of the watch is in [`crate::kernel::sensors`].

use super::corrector::StepTolerance;
use super::stepper::Stepper;
use crate::kernel::error::IntegrationError;
use crate::kernel::output::Output;
use crate::kernel::problem::Problem;
use crate::kernel::sensors::{Fired, SensorWatch};
use crate::tolerances::LOCAL_ERROR_FLOOR;
use linkage_model::settings::IntegratorSettings;

/// After an accepted step of `integ`: evaluates `watch`'s sensors on its output, locates an
/// event inside the step by re-stepping from the step's start, and says what fired. `span`
/// is the run's length (the error per step is `ERROR·h/span` for BDF).
pub(super) fn after_step(
    watch: &mut SensorWatch,
    p: &Problem,
    integ: &mut Stepper,
    settings: &IntegratorSettings,
    span: f64,
) -> Result<Option<Fired>, IntegrationError> {
    let o1 = integ.output()?;
    // Trial times are re-stepped with the force elements' state the run has now (that of
    // the accepted step, as the running integrator's next step would be).
    let elements = &o1.state.elements.clone();
    watch.after_point(p.model, o1, &mut |from, t| {
        if from.state.elements == *elements {
            integrate_to(p, from, t, settings, span)
        } else {
            let mut start = from.clone();
            start.state.elements.clone_from(elements);
            integrate_to(p, &start, t, settings, span)
        }
    })
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
