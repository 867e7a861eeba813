//! FRICTION on joints (ADM-ELEMENTS §4) as the model holds it: the joint resolved to its
//! constraint and markers, every default filled in.
//!
//! Defaults (model units): STICTION_TRANSITION_VELOCITY 0.1, TRANSITION_VELOCITY_COEFFICIENT
//! 1.5, MAX_STICTION_DEFORMATION 0.01, preloads 0, PIN_RADIUS, BALL_RADIUS, FRICTION_ARM,
//! BENDING_REACTION_ARM and REACTION_ARM 1, OVERLAP_DELTA CONSTANT, EFFECT ALL, INPUTS ALL.
//! The documented ones are Adams'; MAX_STICTION_DEFORMATION, PIN_RADIUS and REACTION_ARM are
//! `[unconfirmed]` in the reference and take the values above (decided, tested).
//!
//! INITIAL_OVERLAP has no default: without it the bending moment of a translational or
//! cylindrical joint does not feed the normal load (a warning says so when INPUTS would have
//! used it).

use crate::bodies::Origin;
use linkage_adm::{FrictionEffect, FrictionInputs, OverlapDelta};

/// Default STICTION_TRANSITION_VELOCITY (model length/time) [doc: AS/state_friction.html].
pub const DEFAULT_STICTION_VELOCITY: f64 = 0.1;
/// Default TRANSITION_VELOCITY_COEFFICIENT: the dynamic regime from 1.5·vs.
pub const DEFAULT_TRANSITION_COEFFICIENT: f64 = 1.5;
/// Default MAX_STICTION_DEFORMATION (model length) [unconfirmed in the reference; decided].
pub const DEFAULT_MAX_STICTION_DEFORMATION: f64 = 0.01;
/// Default radii and arms (model length).
pub const DEFAULT_ARM: f64 = 1.0;

/// The joint types friction acts on, by the way the joint slips.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrictionJoint {
    /// Slides along z_j.
    Translational,
    /// Turns about z_j.
    Revolute,
    /// Slides along and turns about z_j.
    Cylindrical,
    /// Turns about any axis (the ball of radius BALL_RADIUS).
    Spherical,
    /// UNIVERSAL or HOOKE: turns about the two cross axes (the pin of radius PIN_RADIUS).
    Universal,
}

/// A FRICTION, resolved (see the module docs for the defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    pub origin: Origin,
    /// The joint (index into [`crate::Model::constraints`]) and its I and J markers.
    pub joint: usize,
    pub kind: FrictionJoint,
    pub i: usize,
    pub j: usize,
    pub mu_static: f64,
    pub mu_dynamic: f64,
    /// vs: the stiction regime below it (surface speed, length/time).
    pub stiction_velocity: f64,
    /// β: the dynamic regime above β·vs.
    pub transition_coefficient: f64,
    /// Δmax: the largest stiction deformation (length).
    pub max_stiction_deformation: f64,
    pub force_preload: f64,
    pub torque_preload: f64,
    pub pin_radius: f64,
    pub ball_radius: f64,
    pub friction_arm: f64,
    pub bending_reaction_arm: f64,
    pub reaction_arm: f64,
    /// INITIAL_OVERLAP, and how it changes with the travel along z_j.
    pub initial_overlap: Option<f64>,
    pub overlap_delta: OverlapDelta,
    /// `(P_i − P_j)·z_j` at the input configuration: the travel the overlap changes from.
    pub initial_travel: f64,
    pub effect: FrictionEffect,
    pub inactive_static: bool,
    pub inputs: FrictionInputs,
}

impl Friction {
    /// The radius that turns the joint's rotation into a surface slip (and the friction
    /// force at the surface into a torque): PIN_RADIUS, or BALL_RADIUS for a spherical joint.
    pub fn radius(&self) -> f64 {
        match self.kind {
            FrictionJoint::Spherical => self.ball_radius,
            _ => self.pin_radius,
        }
    }
}
