//! The solver kernel every analysis shares: what a solve at a state needs and returns,
//! independent of which stage asks.
//!
//! * [`problem`] — [`Problem`], the read-only view of the assembled problem a solve works on
//!   (kept rows, redundant rows, anchored drivers, forces, settling damping, frozen time),
//!   with the generalised forces and drives at a state.
//! * [`matrix`] — the saddle-point iteration matrix `[M + c_K K + c_C C, c_λ Jᵀ; J, 0]` in a
//!   fixed-pattern LU: the integrators' Newton matrix, whose pattern the consistent-output
//!   solve copies.
//! * [`output`] — the consistent-output solve ([`OutputSolver`]: velocity projection,
//!   accelerations, multipliers, reactions) and its [`Output`]; used by the acceleration IC,
//!   the kinematic run, every dynamic output and the REQUESTs.
//! * [`sensors`] — [`SensorWatch`]: SENSORs evaluated on each accepted point of any run
//!   (dynamic, kinematic, quasi-static), event location through the run's own `reach`, actions.
//! * [`redundant`] — the redundant rows monitored along a run.
//! * [`results`] — what a run returns ([`Simulation`], [`Failure`]).
//! * [`error`] — [`IntegrationError`], the failures of these solves ([`SingularSolve`],
//!   [`MatrixRole`]).
//!
//! The kernel reads `constraints`, `physics` and `linalg` and never a stage: the pipeline
//! (initial conditions) and every stage build on it.

pub mod error;
pub mod matrix;
pub mod output;
pub mod problem;
pub mod redundant;
pub mod results;
pub mod sensors;

pub use error::{IntegrationError, MatrixRole, SingularSolve};
pub use output::{Consistent, Output, OutputSolver};
pub use problem::{flat, ExtraDamping, Problem};
pub use results::{Failure, Simulation};
pub use sensors::{outputs_every, SensorEvent, SensorStop, SensorWatch};
