//! # linkage-solve — constraint rows, rank analysis and the analyses
//!
//! A [`linkage_model::Model`] is compiled into a [`system::System`] of labelled scalar rows
//! (DESIGN §3); analyses take the system and a mutable [`state::State`]:
//!
//! * [`verify`] — Gruebler count, DOF, redundant equations by priority, misaligned joints,
//!   consistency, unconstrained and massless parts (DESIGN §4).

pub mod applied;
pub mod assemble;
pub mod drivers;
pub mod dynamics;
pub mod eigs;
pub mod explain;
pub mod forces;
pub mod generate;
pub mod graph;
pub mod hessian;
pub mod ic;
pub mod kinematics;
pub mod linear;
pub mod linearize;
pub mod measures;
pub mod rank;
pub mod reactions;
pub mod requests;
pub mod rows;
pub mod settle;
pub mod state;
pub mod statics;
pub mod system;
pub mod tolerances;
pub mod verify;
