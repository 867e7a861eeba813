//! # linkage-model — a dataset resolved into an immutable mechanical model
//!
//! [`build_model`] turns a typed [`linkage_adm::Dataset`] into a [`Model`]: units and the units
//! consistency factor, part frames (QG/REULER or XG/ZG), markers (QP/REULER or ZP/XP) placed in
//! their part's frame, inertia moved to the centre of mass, and every constraint, force and data element with
//! its references resolved. Every reference is checked; an input error is a
//! [`linkage_adm::Diagnostic`] naming file, line and column. Nothing here panics on user input.
//!
//! Frames (monogram-style names): `R_GB` is the rotation of body frame B in ground G, `p_GB` the
//! position of B's origin in G; a marker M on part P stores `p_BM` and `R_BM` in the part's
//! body frame B, whose origin is the centre of mass and whose axes are the part's BCS axes.

pub mod bodies;
pub mod build;
pub mod contacts;
pub mod controls;
pub mod curves;
pub mod fe_parts;
pub mod flex_bodies;
pub mod forces;
pub mod frames;
pub mod friction;
pub mod functions;
pub mod graphics;
pub mod inertia;
pub mod modal_basis;
pub mod model;
pub mod requests;
pub mod saved;
pub mod sensors;
pub mod settings;
pub mod units;

pub use build::{build_model, build_model_with, TYPED_ONLY};
pub use model::*;
