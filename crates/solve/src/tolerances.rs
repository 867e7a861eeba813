//! Every tolerance of the analyses, with its default, in one place.
//!
//! Lengths are relative to the model's characteristic length L (bounding-box diagonal of its
//! markers); angles are absolute (radians); rank decisions are relative to the scaled,
//! row-normalised Jacobian.

/// Tolerances used by verify (and later by the other analyses).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// A row is redundant when its component orthogonal to the admitted rows is below this
    /// (relative to the row's norm, on the scaled Jacobian). 1e-6: CAD exports place markers to
    /// about 1e-7 relative, and with a tighter value a row that is dependent up to that noise is
    /// taken as independent, making the model look locked or ill-conditioned (seen on a
    /// SOLIDWORKS-exported 3-RPR robot in the corpus: 27 DOF at 1e-9, 31 at 1e-6).
    pub rank: f64,
    /// Rank decisions within this factor of `rank` are reported as near-ties.
    pub near_tie_factor: f64,
    /// A translational equation is violated (misaligned joint, inconsistent redundancy) when
    /// its residual exceeds `length × L`.
    pub length: f64,
    /// A rotational equation is violated when its residual (a dot product of unit axes, ≈ the
    /// angle in radians) exceeds this.
    pub angle: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            rank: 1e-6,
            near_tie_factor: 1e3,
            length: 1e-6,
            angle: 1e-6,
        }
    }
}

/// The dynamics corrector holds the position constraints to `CORRECTOR_CONSTRAINT × L`
/// (lengths) or `CORRECTOR_CONSTRAINT` (dot products, angles).
pub const CORRECTOR_CONSTRAINT: f64 = 1e-9;
/// The corrector has converged when its correction of the accelerations is below this,
/// relative to the accelerations (translations over L, rotations in radians) …
pub const CORRECTOR_RELATIVE: f64 = 1e-8;
/// … or moves the positions (`βh²·|Δa|`, same scaling) by less than this (rounding level of
/// coordinates of order L) …
pub const CORRECTOR_ROUNDING: f64 = 1e-14;
/// … or no longer contracts (at least halving) and moves the positions by less than this,
/// a tenth of `CORRECTOR_CONSTRAINT`: rounding noise of coordinates far from the origin
/// (ε·|x| with |x| ≫ L), which the scaled iteration matrix amplifies by 1/(βh²) in the
/// accelerations.
pub const CORRECTOR_NOISE: f64 = 1e-10;

/// The dynamics corrector also accepts a correction whose effect on positions and velocities
/// (`max(β, γ)·h²·|Δa|`, translations over the characteristic length) is below this fraction of
/// the INTEGRATOR ERROR: further iterations could not change the accepted step by more than a
/// rounding of the error estimate (parts with tiny inertia about some axis otherwise leave
/// corrections at noise level, and the run gave up at the minimum step).
pub const CORRECTOR_ERROR_FRACTION: f64 = 1e-3;

/// Static equilibrium has converged, whatever the Newton correction, when the largest force
/// or torque imbalance is below this fraction of the largest applied load component (and below
/// IMBALANCE, with the constraints satisfied): the forces balance to rounding, so a correction
/// can only be rounding divided by a stiffness that vanishes (a free motion without
/// stiffness, regularised by STABILITY × a tiny inertia gives drifts of 1e-3 rad per
/// iteration: seen on a 7-link corpus robot arm whose gripper fingers spin about vertical
/// hinges).
pub const STATIC_ROUNDING_IMBALANCE: f64 = 1e-10;

// ---- Linear algebra and eigen solutions (linalg/, stages/linearize.rs) ----

// ---- Dynamics and kinematics (stages/dynamics/, stages/kinematics.rs) ----

// ---- Forces, measures and requests (physics/) ----

// ---- Assembly, initial conditions and settling (stages/assemble.rs, ic.rs, settle.rs) ----

/// INTEGRATOR ERROR of the damped settling integration: the path to rest need not be accurate,
/// only stable, and the Newton polish settles the final configuration to EQUILIBRIUM ERROR.
pub const SETTLING_INTEGRATOR_ERROR: f64 = 1e-4;

// ---- Explain (stages/explain/) ----
