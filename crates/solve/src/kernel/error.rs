//! Why a dynamic or kinematic run (or one of its steps) failed, as values: the report layer
//! tells a corrector that did not converge from a force that cannot be evaluated without
//! reading text. Each variant's message is the sentence the run prints.

use crate::constraints::drivers::MotionError;
use crate::linalg::linear::LinearError;
use crate::physics::applied::ForceError;

/// Which matrix of the integrator could not be set up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixRole {
    /// Both matrices at once, on their first (diagonal) pattern.
    Both,
    /// The scaled Newton iteration matrix of the HHT corrector.
    Newton,
    /// `[M, Jᵀ; J, 0]` of the consistent velocity and acceleration solves.
    Consistent,
}

impl std::fmt::Display for MatrixRole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MatrixRole::Both => "the integrator's matrices",
            MatrixRole::Newton => "the integrator's Newton matrix",
            MatrixRole::Consistent => "the consistent velocity/acceleration solve",
        })
    }
}

/// Which linear solve of a step turned out singular.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SingularSolve {
    /// The corrector's Newton correction.
    Newton,
    /// The mass-weighted projection of the velocities onto the velocity constraints.
    VelocityProjection,
    /// The accelerations and multipliers.
    Acceleration,
}

impl std::fmt::Display for SingularSolve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SingularSolve::Newton => "the integrator's Newton matrix",
            SingularSolve::VelocityProjection => "the velocity projection",
            SingularSolve::Acceleration => "the acceleration solve",
        })
    }
}

/// A failure of the dynamic run (HHT integration, consistent outputs, redundant-row checks) or
/// of the kinematic run of a zero-DOF model (position solve).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IntegrationError {
    /// The caller stopped the run between two steps (Ctrl-C, a time limit).
    #[error("stopped on request (interrupted, or the time limit was reached)")]
    Stopped,
    /// The start state does not have one pose per part.
    #[error("the start state has {state} parts, the model {model}")]
    StartMismatch { state: usize, model: usize },
    /// A matrix's storage or symbolic analysis could not be made.
    #[error("{matrix} cannot be set up: {cause}")]
    Setup {
        matrix: MatrixRole,
        cause: LinearError,
    },
    /// Assembling a matrix kept finding entries outside its (grown) pattern.
    #[error("{0} cannot be set up: its sparsity pattern does not settle")]
    PatternUnsettled(MatrixRole),
    /// The numeric LU of the iteration matrix failed.
    #[error("the integrator's Newton matrix cannot be factorised: {0}")]
    NewtonFactorisation(LinearError),
    /// The numeric LU of `[M, Jᵀ; J, 0]` failed.
    #[error("the consistent velocity/acceleration solve failed: {0}")]
    ConsistentFactorisation(LinearError),
    /// A solve gave a non-finite solution.
    #[error("{0} is singular")]
    Singular(SingularSolve),
    /// The corrector's Newton iteration reached INTEGRATOR MAXIT without converging.
    #[error("the corrector did not converge in {iterations} iterations at time {}", linkage_adm::num::time_text(*.time))]
    CorrectorNotConverged { iterations: usize, time: f64 },
    /// A step failed at the smallest step size the settings allow: the run gives up.
    #[error("{cause} (step size {} at its minimum)", linkage_adm::num::sci(*.step, 4))]
    AtMinimumStep {
        step: f64,
        cause: Box<IntegrationError>,
    },
    /// The run gave up (`cause`) at a singular configuration: the kept constraint rows have
    /// become nearly dependent (`conditioning`: `σ_min/σ_max` of their scaled Jacobian), so
    /// the reactions that hold the motions grow without bound; `elements` are the
    /// constraints whose rows make up the dependent combination.
    #[error(
        "the mechanism is at a singular (locked) configuration at time {time}: the constraints \
         of {elements} have become dependent (conditioning {} of the constraint Jacobian), so \
         the reactions that hold the motions grow without bound and the motions cannot be \
         followed; {cause}",
        linkage_adm::num::sci(*.conditioning, 2)
    )]
    SingularConfiguration {
        time: f64,
        conditioning: f64,
        elements: String,
        cause: Box<IntegrationError>,
    },
    /// A motion's displacement cannot be evaluated.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A constraint's explicit time derivatives (general constraints) cannot be evaluated.
    #[error("{element}: the constraint's time derivatives cannot be evaluated: {cause}")]
    ConstraintRate {
        element: String,
        cause: linkage_expr::EvalError,
    },
    /// A force element cannot be evaluated.
    #[error(transparent)]
    Force(#[from] ForceError),
    /// A SENSOR's FUNCTION or EVALUATE cannot be evaluated.
    #[error("{sensor}: the sensor cannot be evaluated: {cause}")]
    Sensor { sensor: String, cause: String },
    /// A redundant row removed as consistent no longer holds (Adams: "consistent redundant
    /// constraint that becomes inconsistent"); `residual` in the row's report unit.
    #[error(
        "the redundant equation {equation} of {element} (removed as consistent) became \
         inconsistent: residual {}{unit}",
        linkage_adm::num::sci(*.residual, 7)
    )]
    RedundantViolated {
        equation: &'static str,
        element: String,
        residual: f64,
        /// `""` or `" deg"`.
        unit: &'static str,
    },
    /// Kinematic run: a constraint row's residual is not finite.
    #[error("the constraint {equation} of {element} cannot be evaluated at time {}", linkage_adm::num::time_text(*.time))]
    PositionNotEvaluable {
        equation: &'static str,
        element: String,
        time: f64,
    },
    /// Kinematic run: the square constraint Jacobian is singular.
    #[error(
        "the constraint Jacobian is singular at time {}: the mechanism is at a singular \
         (locked or toggle) configuration, or the motions drive it beyond its reach",
        linkage_adm::num::time_text(*.time)
    )]
    PositionsSingular { time: f64 },
    /// Kinematic run: Newton on the positions did not converge; the largest residual (in the
    /// row's report unit) and its row.
    #[error(
        "the positions could not be found from the constraints at time {} in {iterations} \
         iterations: largest residual {}{unit} in {equation} of {element} (the \
         motions may drive the mechanism beyond its reach)",
        linkage_adm::num::time_text(*.time),
        linkage_adm::num::sci(*.residual, 7)
    )]
    PositionsNotFound {
        time: f64,
        iterations: usize,
        residual: f64,
        /// `""` or `" deg"`.
        unit: &'static str,
        equation: &'static str,
        element: String,
    },
}
