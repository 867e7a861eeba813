//! Applied forces as the analyses see them (gravity is added by the analyses themselves).
//!
//! Generalised force of part k: `Q[6k..6k+3]` the force at its centre of mass and
//! `Q[6k+3..6k+6]` the torque about its centre of mass, both in ground axes, in model force
//! (and force × length) units. Jacobians are with respect to the tangent coordinates of
//! [`crate::state::State::increment`] (`δx`, `δθ` in ground) and to the part velocities
//! (`v` of the CM, `ω`, ground axes), as `(row, column, value)` triplets in `6n × 6n` index
//! space (duplicates are summed by the consumer).

use crate::constraints::rows::Velocities;
use crate::physics::forces::friction::FrictionValue;
use crate::physics::reactions::Reaction;
use crate::state::State;

/// A force element that cannot be evaluated at a state: a domain error in its expression, an
/// angle that is not defined, a law the element's settings do not allow.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{element}: {cause} (time {})", linkage_adm::num::time_text(*.time))]
pub struct ForceError {
    /// The element's name (`SFORCE_3` or its view name).
    pub element: String,
    pub time: f64,
    /// What failed, from the element's law or expression.
    pub cause: LawError,
}

/// Why a force law cannot be evaluated at a state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LawError {
    /// An expression argument (`FUNCTION`, `FX`, …) cannot be evaluated: the evaluator's
    /// message (a domain error, a data element that cannot be evaluated, a VARIABLE cycle).
    #[error("{argument}: {cause}")]
    Expression {
        argument: &'static str,
        cause: String,
    },
    /// A rotation angle (`AX(I,J)`, `AY(I,J)`, `AZ(I,J)`) about an axis perpendicular to the
    /// plane it is measured in.
    #[error(
        "{angle}: the rotation angle is undefined (axis perpendicular to the plane of \
         measurement)"
    )]
    UndefinedAngle { angle: &'static str },
    /// I and J coincide while the force along their line is not zero.
    #[error("I and J coincide, so the direction of the force {force} is undefined")]
    CoincidentPoints { force: f64 },
}

/// Which analysis the forces are evaluated for: elements inactive in statics
/// (`INACTIVE_DURING = STATIC` frictions) act only in the dynamic regime. An argument of every
/// evaluation, so that one force set serves a static and a dynamic analysis without a switch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Regime {
    /// Dynamics, the initial conditions, linearization, kinematics, the reports' outputs.
    #[default]
    Dynamic,
    /// Static equilibrium, quasi-statics and dynamic settling.
    Static,
}

/// A set of applied force elements.
pub trait AppliedForces {
    /// Adds the generalised forces in `regime` at positions `s`, velocities `v` and time
    /// `s.time` to `out` (length 6n). An error names the element, the time and the cause
    /// (e.g. a domain error in its expression).
    fn add_forces(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        out: &mut [f64],
    ) -> Result<(), ForceError>;

    /// Adds `∂Q/∂q` to `dq` and, when given, `∂Q/∂v` to `dv` (in `regime`).
    fn add_jacobians(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        dq: &mut Vec<(usize, usize, f64)>,
        dv: Option<&mut Vec<(usize, usize, f64)>>,
    ) -> Result<(), ForceError>;

    /// Whether some element carries a state of its own from one accepted state to the next
    /// (joint friction: its stiction anchor and normal load, [`crate::physics::forces::friction`]).
    /// That state is data of the run's [`State`] (`State::elements`), never of the set; the
    /// analyses call the two methods below only then.
    fn has_state(&self) -> bool {
        false
    }

    /// Starts the elements' state in `s` at its configuration (the IC: stiction anchors at the
    /// assembled pose).
    fn start_state(&self, _s: &mut State) {}

    /// Updates the elements' state in `s` after the accepted state `(s, v)` whose constraint
    /// reactions are `reactions`; returns the largest change of a load the state holds
    /// (model force units), which a static analysis iterates to zero.
    fn accept_state(&self, _s: &mut State, _v: &Velocities, _reactions: &[Reaction]) -> f64 {
        0.0
    }

    /// The joint frictions, whose normal loads follow the joints' reactions (statics solves
    /// them with the multipliers); `None` without frictions.
    fn joint_frictions(&self) -> Option<&crate::physics::forces::friction::FrictionSet> {
        None
    }

    /// The friction of every FRICTION at `(s, v)` in `regime` with the state `s` carries, in
    /// model order, for the reports (none without frictions).
    fn friction_values(&self, _regime: Regime, _s: &State, _v: &Velocities) -> Vec<FrictionValue> {
        Vec::new()
    }

    /// Number of control states (DIFF, LSE, TFSISO) whose equations this set evaluates
    /// ([`crate::physics::controls`]); 0 by default.
    fn control_count(&self) -> usize {
        0
    }

    /// The control states' residuals `r(q, v, x, ẋ, t)` at `s` (states in `s.controls`),
    /// `v` into `out` (length [`Self::control_count`]).
    fn control_residuals(
        &self,
        s: &State,
        v: &Velocities,
        out: &mut [f64],
    ) -> Result<(), ForceError> {
        let _ = (s, v, out);
        Ok(())
    }

    /// `∂r/∂(q, v, x, ẋ)` as `(state, variable, value)` triplets, variables numbered as in
    /// [`crate::physics::controls`] (`6n` positions, `6n` velocities, `nx` states, `nx`
    /// rates).
    fn control_jacobian(
        &self,
        s: &State,
        v: &Velocities,
        out: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), ForceError> {
        let _ = (s, v, out);
        Ok(())
    }

    /// `∂Q/∂x` and `∂Q/∂ẋ` (in `regime`) as `(row of Q, column, value)` triplets, column `i`
    /// for state i and `nx + i` for its rate.
    fn add_control_force_jacobian(
        &self,
        regime: Regime,
        s: &State,
        v: &Velocities,
        out: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), ForceError> {
        let _ = (regime, s, v, out);
        Ok(())
    }
}

/// No applied forces (models without force elements).
pub struct NoForces;

impl AppliedForces for NoForces {
    fn add_forces(
        &self,
        _: Regime,
        _: &State,
        _: &Velocities,
        _: &mut [f64],
    ) -> Result<(), ForceError> {
        Ok(())
    }
    fn add_jacobians(
        &self,
        _: Regime,
        _: &State,
        _: &Velocities,
        _: &mut Vec<(usize, usize, f64)>,
        _: Option<&mut Vec<(usize, usize, f64)>>,
    ) -> Result<(), ForceError> {
        Ok(())
    }
}
