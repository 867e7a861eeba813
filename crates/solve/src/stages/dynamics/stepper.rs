//! The integrator a run steps with: HHT-α or BDF, behind one interface for the simulate loop.

use super::bdf::Bdf;
use super::corrector::StepTolerance;
use super::integrator::Integrator;
use crate::constraints::rows::Velocities;
use crate::kernel::error::IntegrationError;
use crate::kernel::output::Output;
use crate::kernel::problem::Problem;
use crate::state::{ElementState, State};
use linkage_model::settings::{IntegratorMethod, IntegratorSettings};

/// HHT-α (second order) or variable-order BDF.
pub enum Stepper<'p, 'a> {
    Hht(Box<Integrator<'p, 'a>>),
    Bdf(Box<Bdf<'p, 'a>>),
}

impl<'p, 'a> Stepper<'p, 'a> {
    /// The integrator `settings.method` names, started at `start` (see [`Integrator::new`],
    /// [`Bdf::new`]), and the output at the start.
    pub fn new(
        p: &'p Problem<'a>,
        start: &State,
        v0: &Velocities,
        settings: &IntegratorSettings,
    ) -> Result<(Stepper<'p, 'a>, Output), IntegrationError> {
        Ok(match settings.method {
            IntegratorMethod::Hht => {
                let (i, o) = Integrator::new(p, start, v0, settings)?;
                (Stepper::Hht(Box::new(i)), o)
            }
            IntegratorMethod::Bdf => {
                let (i, o) = Bdf::new(p, start, v0, settings, settings.kmax)?;
                (Stepper::Bdf(Box::new(i)), o)
            }
        })
    }

    /// The trial step of size `h`, allowed a local error `tolerance`, and its local error
    /// estimate.
    pub fn try_step(&mut self, h: f64, tolerance: StepTolerance) -> Result<f64, IntegrationError> {
        match self {
            Stepper::Hht(i) => i.try_step(h, tolerance),
            Stepper::Bdf(b) => b.try_step(h, tolerance),
        }
    }

    /// Whether ERROR is spread over the run (BDF) or taken per step (HHT; see
    /// [`super::simulate_with`]).
    pub fn error_per_run(&self) -> bool {
        matches!(self, Stepper::Bdf(_))
    }

    /// The order of the method for the trial just computed: its error estimate is
    /// proportional to `h^{order+1}`.
    pub fn order(&self) -> usize {
        match self {
            Stepper::Hht(_) => 2,
            Stepper::Bdf(b) => b.order(),
        }
    }

    /// Makes the trial current; returns the error estimate and the order the next step size
    /// is to be chosen with (`err` is the trial's, for a method of fixed order).
    pub fn accept(&mut self, err: f64, tolerance: f64) -> (f64, usize) {
        match self {
            Stepper::Hht(i) => {
                i.accept();
                (err, 2)
            }
            Stepper::Bdf(b) => b.accept(tolerance),
        }
    }

    pub fn output(&mut self) -> Result<Output, IntegrationError> {
        match self {
            Stepper::Hht(i) => i.output(),
            Stepper::Bdf(b) => b.output(),
        }
    }

    pub fn time(&self) -> f64 {
        match self {
            Stepper::Hht(i) => i.time(),
            Stepper::Bdf(b) => b.time(),
        }
    }

    pub fn state(&self) -> &State {
        match self {
            Stepper::Hht(i) => i.state(),
            Stepper::Bdf(b) => b.state(),
        }
    }

    /// Replaces the force elements' state the next steps are solved with.
    pub fn set_elements(&mut self, elements: &ElementState) {
        match self {
            Stepper::Hht(i) => i.set_elements(elements),
            Stepper::Bdf(b) => b.set_elements(elements),
        }
    }

    pub fn statistics(&self) -> (usize, usize) {
        match self {
            Stepper::Hht(i) => i.statistics(),
            Stepper::Bdf(b) => b.statistics(),
        }
    }
}
