//! # linkage-solve — constraint rows, rank analysis and the analyses
//!
//! A [`linkage_model::Model`] is compiled into a [`constraints::system::System`] of labelled
//! scalar rows (DESIGN §3); the layers import one way, each only from those above it here:
//!
//! * [`constraints`] — rows with analytic Jacobians and second derivatives, the compiled system,
//!   the constraint graph, sparse rank decisions, motion drivers, residuals in report units.
//! * [`physics`] — applied force elements, mass, expression measures, reactions, REQUEST
//!   outputs, the FE_PART modal reduction.
//! * [`linalg`] — sparse LU (one-off and fixed-pattern) and the sparse eigen solver.
//! * [`kernel`] — what every analysis shares: the problem view, the iteration matrix, the
//!   consistent-output solve and its `Output`, the sensor watch, the run results and errors.
//! * [`pipeline`] — verify → assemble → initial conditions, built once into
//!   [`pipeline::Assembled`], which every stage takes.
//! * [`stages`] — the analyses on an `Assembled`: statics / settle → linearize (+ plant) /
//!   dynamics (kinematics for zero-DOF models), and explain (on verify's result).

pub mod constraints;
pub mod coverage;
pub mod generate;
pub mod kernel;
pub mod linalg;
pub mod physics;
pub mod pipeline;
pub mod stages;
pub mod state;
pub mod tolerances;
