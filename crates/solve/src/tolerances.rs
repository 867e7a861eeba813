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

// ---- Statics internals (stages/statics.rs, stages/statics/) ----

/// Floor of the constraint tolerance of static equilibrium: the rows are held to IC ERROR, but
/// never tighter than this × L (lengths) or this (angles, dot products): a few units of
/// rounding of coordinates of order L, below which no Newton step can go.
pub const STATIC_CONSTRAINT_FLOOR: f64 = 1e-13;

/// Added to the translational diagonal of the static Newton matrix, × (1 + m): keeps a
/// massless part's block regular when STABILITY × M vanishes, far below any physical
/// stiffness (relative rounding of an entry of order 1).
pub const STATIC_MASS_FLOOR: f64 = 1e-14;

/// After a step cut by TLIMIT/ALIMIT the configuration is projected back onto the constraints
/// to this × max(L, 1): rounding level, so that the next Newton step starts from an assembled
/// pose.
pub const STATIC_CUT_PROJECTION: f64 = 1e-12;

/// A static imbalance is reported among the largest only above this fraction of the largest
/// (a free body's other balance equations hold to rounding of the largest).
pub const STATIC_REPORTED_IMBALANCE: f64 = 1e-9;

/// Rank of the scaled constraint Jacobian in the stability test: `|R_ii|` of its QR above this
/// fraction of the largest (dependent rows of a redundant but consistent model leave rounding
/// of order 1e-15 relative; a real constraint direction is far above).
pub const STABILITY_RANK: f64 = 1e-9;

/// An equilibrium is stable when the smallest eigenvalue of the reduced stiffness is above
/// −this × the largest in magnitude: a neutral direction (a free rotation about a vertical axis)
/// computes to rounding of either sign.
pub const STABILITY_EIGENVALUE: f64 = 1e-9;

// ---- Linear algebra and eigen solutions (linalg/, stages/linearize.rs) ----

// ---- Dynamics and kinematics (stages/dynamics/, stages/kinematics.rs) ----

// ---- Forces, measures and requests (physics/) ----

// ---- Constraints and rank (constraints/, stages/verify.rs) ----

/// Motion quadrature (`∫f` of velocity and acceleration motions, adaptive Simpson): relative
/// accuracy of the integral, a few hundred units of rounding (motion functions are smooth).
pub const MOTION_QUADRATURE: f64 = 1e-12;

/// A misaligned joint's J frame is turned onto the I frame's constrained direction only when
/// that direction (a component of a unit vector orthogonal to another) is longer than this;
/// below it the frames already agree to rounding and there is no direction to turn to.
pub const ALIGNMENT_DIRECTION: f64 = 1e-12;

/// Default rank tolerance of the sparse elimination (`RankSettings`): a row is dependent when
/// its remainder is below this, relative to its norm.
pub const RANK_DEFAULT: f64 = 1e-9;

/// A redundant row is attributed to one row of its element with a dependency coefficient above
/// 1 + this (a coefficient of exactly one, up to rounding, is a plain duplicate).
pub const DEPENDENCY_COEFFICIENT: f64 = 1e-9;

/// An angle row's `sin² + cos²` below this is undefined (the measured axis is parallel to the
/// reference plane's normal): its second derivatives are taken as zero instead of dividing by
/// it. A guard against division by zero, not an accuracy.
pub const UNDEFINED_ANGLE: f64 = 1e-300;

// ---- Assembly, initial conditions and settling (stages/assemble.rs, ic.rs, settle.rs) ----

// ---- Explain (stages/explain/) ----
