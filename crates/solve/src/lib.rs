//! # linkage-solve — constraint rows, rank analysis and the analyses
//!
//! A [`linkage_model::Model`] is compiled into a [`constraints::system::System`] of labelled
//! scalar rows (DESIGN §3); the analyses are stages that each take the previous stage's result:
//!
//! * [`constraints`] — rows with analytic Jacobians and second derivatives, the compiled system,
//!   the constraint graph, sparse rank decisions, motion drivers.
//! * [`physics`] — applied force elements, expression measures, reactions, REQUEST outputs.
//! * [`linalg`] — sparse LU (one-off and fixed-pattern) and the sparse eigen solver.
//! * [`stages`] — verify → assemble/ic → statics / settle → linearize / dynamics
//!   (kinematics for zero-DOF models), and explain.

pub mod constraints;
pub mod coverage;
pub mod generate;
pub mod linalg;
pub mod physics;
pub mod pipeline;
pub mod stages;
pub mod state;
pub mod tolerances;
