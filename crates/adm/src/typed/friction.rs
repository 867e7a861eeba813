//! The typed FRICTION statement (ADM-ELEMENTS §4), read by [`crate::typing`]'s friction
//! typing.

use super::*;

/// Which friction regimes act (`EFFECT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrictionEffect {
    /// Stiction and sliding (the default).
    #[default]
    All,
    /// The stiction regime only: no friction once the joint slides.
    Stiction,
    /// The sliding regime only: no stiction deformation.
    Sliding,
}

/// How the overlap of a sliding joint changes with its travel (`OVERLAP_DELTA`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OverlapDelta {
    /// The overlap stays INITIAL_OVERLAP (the default).
    #[default]
    Constant,
    /// The overlap grows as the I marker moves along +z_j.
    Increase,
    /// The overlap shrinks as the I marker moves along +z_j.
    Decrease,
}

/// The joint loads that feed the friction's normal load (`INPUTS`; ALL by default).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrictionInputs {
    pub preload: bool,
    pub reaction_force: bool,
    pub bending_moment: bool,
    pub torsional_moment: bool,
}

impl FrictionInputs {
    /// Every input (`INPUTS = ALL`, the default).
    pub const ALL: FrictionInputs = FrictionInputs {
        preload: true,
        reaction_force: true,
        bending_moment: true,
        torsional_moment: true,
    };
    /// No input (`INPUTS = NONE`): the friction is zero.
    pub const NONE: FrictionInputs = FrictionInputs {
        preload: false,
        reaction_force: false,
        bending_moment: false,
        torsional_moment: false,
    };
}

impl Default for FrictionInputs {
    fn default() -> Self {
        FrictionInputs::ALL
    }
}

/// A FRICTION statement as written (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    pub header: Header,
    pub joint: IdRef,
    pub mu_static: Located<f64>,
    pub mu_dynamic: Located<f64>,
    pub stiction_transition_velocity: Option<Located<f64>>,
    pub transition_velocity_coefficient: Option<Located<f64>>,
    pub max_stiction_deformation: Option<Located<f64>>,
    pub force_preload: Option<Located<f64>>,
    pub torque_preload: Option<Located<f64>>,
    pub pin_radius: Option<Located<f64>>,
    pub ball_radius: Option<Located<f64>>,
    pub friction_arm: Option<Located<f64>>,
    pub bending_reaction_arm: Option<Located<f64>>,
    pub reaction_arm: Option<Located<f64>>,
    pub initial_overlap: Option<Located<f64>>,
    pub overlap_delta: OverlapDelta,
    pub effect: FrictionEffect,
    /// `INACTIVE_DURING = STATIC`: no friction in static and quasi-static solutions.
    pub inactive_static: bool,
    pub inputs: FrictionInputs,
    /// Where INPUTS is written (the statement's place when it is not).
    pub inputs_span: Span,
}
