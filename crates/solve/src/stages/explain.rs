//! Explain and repair redundancy (`linkage verify --explain`).
//!
//! Four findings, all from the rank analysis of the constraint Jacobian (scaled and
//! row-normalised as in [`crate::pipeline::verify`]; decided per loop by [`dense`]: an SVD where loops
//! are small, the sparse greedy analysis otherwise):
//!
//! * **Which reactions are determinate** ([`reactions`]). With redundant equations the
//!   multipliers λ solving `Jᵀλ = Q` are not unique: any vector of the left null space of the
//!   Jacobian can be added. A reaction component (force along or torque about an axis of the
//!   joint's J marker, or the value of a scalar equation) is determined iff every basis vector
//!   of that null space gives it zero. The basis is the SVD's, or — for large loops — the
//!   vectors `e_r − Σ c_k e_k` of the redundant rows' `depends_on`, with no new factorisation.
//! * **Singular pose vs structural redundancy** ([`generic`]). The configuration is moved by
//!   small random steps (10⁻² of each part's size and 10⁻² rad) and, when that hints at a
//!   singular pose, along single joint coordinates, re-assembled by least change onto the
//!   constraints (motions left free) and analysed again; the largest rank found gives the
//!   generic DOF and redundancy. A different rank at the input flags a singular configuration.
//! * **Redundant drivers and initial conditions** ([`conflicts`]): motions, joint initial
//!   conditions and EXACT part coordinates ranked after the constraints; a dependent one fixes
//!   a DOF twice, and it conflicts when the linearised values disagree.
//! * **Replacement advice** ([`repair`]): weaker joints or primitive sets at the same markers
//!   for the joints involved in the redundancy, each checked by the rank analysis of the
//!   changed model; see that module for the search and the ranking measure. At a singular
//!   input they are checked at the regular configuration the second finding found.

pub mod conflicts;
pub mod dense;
pub mod generic;
pub mod reactions;
pub mod repair;

use crate::constraints::drivers::Drivers;
use crate::pipeline::verify::Verification;
use crate::state::State;
use crate::tolerances::Tolerances;
use linkage_model::Model;

pub use conflicts::{ConflictKind, DriverConflict};
pub use generic::{GenericMobility, Mobility};
pub use reactions::{Direction, ElementReactions};
pub use repair::{Change, ElementType, NewElement, Proposal, Realized, Turn};

/// Everything `--explain` finds.
#[derive(Clone, Debug)]
pub struct Explanation {
    /// DOF and redundancy at the input and at nearby regular configurations.
    pub mobility: GenericMobility,
    /// Reactions of every constraint element at the analysed configuration.
    pub reactions: Vec<ElementReactions>,
    /// Proposed changes, best first (numbered from 1 in reports).
    pub suggestions: Vec<Proposal>,
    /// The proposals were checked at a regular configuration near the input (the input pose is
    /// singular).
    pub suggestions_at_regular_configuration: bool,
    pub conflicts: Vec<DriverConflict>,
}

/// Explains the redundancy that `v` (the verification of `model` at its input configuration)
/// found.
pub fn explain(
    model: &Model,
    drivers: &dyn Drivers,
    tol: &Tolerances,
    v: &Verification,
) -> Explanation {
    let input = State::input(model);
    let length = model.characteristic_length;
    let base = dense::analyse(&v.system, &input, &v.topology, length, tol);
    let reactions = reactions::determinacy(&v.system, &input, length, &base.null);
    let at_input = Mobility::new(v.moving_parts, v.rows, base.rank);
    let mobility = generic::generic_mobility(model, &v.system, &v.topology, &input, tol, at_input);
    let (state, regular) = match (&mobility.regular_state, mobility.singular) {
        (Some(s), true) => (s.clone(), true),
        _ => (input.clone(), false),
    };
    let suggestions = repair::propose(model, tol, v, &state, &repair::RepairSettings::default());
    let conflicts = conflicts::driver_conflicts(model, &v.system, &input, drivers, tol);
    Explanation {
        mobility,
        reactions,
        suggestions,
        suggestions_at_regular_configuration: regular,
        conflicts,
    }
}
