//! What a dynamic or kinematic run returns.

use super::error::IntegrationError;
use super::output::Output;

/// Why a simulation stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub time: f64,
    /// The sentence the reports print: `cause`'s message.
    pub message: String,
    /// What failed, as a value.
    pub cause: IntegrationError,
}

impl Failure {
    /// The failure `cause` at `time`.
    pub fn new(time: f64, cause: IntegrationError) -> Failure {
        Failure {
            time,
            message: cause.to_string(),
            cause,
        }
    }
}

/// Result of a simulation.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The outputs kept: every one from [`crate::stages::dynamics::simulate`]; only the last from a streamed
    /// run ([`crate::stages::dynamics::run_streamed`]), whose outputs went to its caller.
    pub outputs: Vec<Output>,
    /// Outputs produced (kept or streamed).
    pub output_count: usize,
    pub failure: Option<Failure>,
    pub steps: usize,
    pub rejected: usize,
    /// Corrector (Newton) iterations over every step tried, rejected ones included.
    pub newton_iterations: usize,
    /// Factorisations of the iteration matrix.
    pub factorisations: usize,
    /// The model has no degrees of freedom: it was run kinematically.
    pub kinematic: bool,
    /// The sensors that fired, in time order.
    pub sensor_events: Vec<super::sensors::SensorEvent>,
    /// A sensor's HALT or RETURN ended the run (complete, not failed) at the last event.
    pub stopped_by_sensor: Option<super::sensors::SensorStop>,
}

impl Simulation {
    /// A run that has not started: no outputs, no steps.
    pub(crate) fn empty(kinematic: bool) -> Simulation {
        Simulation {
            outputs: Vec::new(),
            output_count: 0,
            failure: None,
            steps: 0,
            rejected: 0,
            newton_iterations: 0,
            factorisations: 0,
            kinematic,
            sensor_events: Vec::new(),
            stopped_by_sensor: None,
        }
    }
}
