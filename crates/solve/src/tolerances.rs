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
/// Rounding level of coordinates of order L (relative): the least a control state's correction
/// or SI2's position projection is asked to reach.
pub const CORRECTOR_ROUNDING: f64 = 1e-14;
/// The corrector accepts a correction that no longer contracts (at least halving, with a matrix
/// built during the step) and moves the positions by less than this, a tenth of
/// `CORRECTOR_CONSTRAINT`: rounding noise of coordinates far from the origin (ε·|x| with
/// |x| ≫ L), which the scaled iteration matrix amplifies by 1/(βh²) in the accelerations.
pub const CORRECTOR_NOISE: f64 = 1e-10;
/// … or is below this fraction of the accelerations (translations over L, rotations in
/// radians; at least `CORRECTOR_ACCELERATION_MIN`): noise amplified by the multipliers near a
/// singular pose. (Before issue 31 this accepted a still-contracting correction too, which left
/// a velocity error of the same sign at every step.)
pub const CORRECTOR_RELATIVE: f64 = 1e-8;

/// The dynamics corrector has converged when its last correction changes the step's positions
/// by at most this fraction of the step's share of ERROR (`ERROR·h/T`, translations over the
/// characteristic length) and its velocities by at most that over the run's span T (a velocity
/// error drifts the positions for the rest of the run): the corrector's errors of all steps
/// add up to this fraction of ERROR whatever the number of steps
/// (`stages::dynamics::StepTolerance`). Before issue 31 the velocity part was per step and a
/// test relative to the accelerations accepted more; a cart with an inverted pendulum (in mm)
/// ended 20 % of its velocity's range off with HMAX = 1e-4 at ERROR = 1e-7, now 3e-9.
pub const CORRECTOR_ERROR_FRACTION: f64 = 1e-3;

/// Static equilibrium has converged, whatever the Newton correction, when the largest force
/// or torque imbalance is below this fraction of the largest applied load component (and below
/// IMBALANCE, with the constraints satisfied): the forces balance to rounding, so a correction
/// can only be rounding divided by a stiffness that vanishes (a free motion without
/// stiffness, regularised by STABILITY × a tiny inertia gives drifts of 1e-3 rad per
/// iteration: seen on a 7-link corpus robot arm whose gripper fingers spin about vertical
/// hinges).
pub const STATIC_ROUNDING_IMBALANCE: f64 = 1e-10;

/// A FRICTION whose stiction force is within this fraction of `μs·N` is at its static limit:
/// where static equilibrium fails, the load along its joint exceeds what static friction
/// holds (a block on a ramp steeper than the friction angle). Relative rounding of the cap.
pub const FRICTION_AT_STATIC_LIMIT: f64 = 1e-6;

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
/// −this × the largest stiffness in magnitude (of the reduced eigenvalues and of the full
/// stiffness matrix's entries): a neutral direction (a free rotation about a vertical axis)
/// computes to rounding of either sign.
pub const STABILITY_EIGENVALUE: f64 = 1e-9;

// ---- Linear algebra and eigen solutions (linalg/, stages/linearize.rs) ----

/// The default shift is `σ = −DEFAULT_SHIFT_FRACTION · ω_ref` (just below zero; `ω_ref` the
/// model's frequency scale), so zero (rigid-body) eigenvalues and the lowest frequencies come
/// first.
pub const DEFAULT_SHIFT_FRACTION: f64 = 1e-3;

/// Floor of a divisor or norm that may vanish (a zero vector, a model without inertia): far
/// below any physical magnitude, it only keeps a quotient finite.
pub const UNDERFLOW_FLOOR: f64 = 1e-300;

/// A diagonal entry of R (QR of Jᵀ) counts towards the rank of J when above this fraction of
/// the largest: the rows the analyses keep are independent at the rank tolerance (1e-6 on the
/// row-normalised Jacobian), so a kept row's pivot is far above it, while a dependent
/// direction leaves rounding (≈ 1e-15 relative), far below.
pub const NULL_SPACE_RANK: f64 = 1e-9;

/// A massless part is given this fraction of the smallest nonzero part mass (and, without
/// inertia, of the smallest nonzero principal moment), as Adams does: small enough not to move
/// the other modes, large enough to keep M regular.
pub const MASSLESS_FRACTION: f64 = 1e-8;
/// An eigenvalue is zero (a rigid-body mode) when `|λ|` is at or below this × the model's
/// frequency scale `ω_ref`.
pub const ZERO_EIGENVALUE: f64 = 1e-6;
/// A free motion carries no stiffness when its eigenvalue of the symmetric part of the
/// (reduced) stiffness is at or below this × `‖K‖` (`ω_ref²` on the shift-invert path).
pub const FREE_MOTION: f64 = 1e-10;
/// A motion of one part alone is a free motion without stiffness or damping (deflated before
/// the shift-invert eigen solution) when, as a unit vector, it leaves the part's constraint
/// rows (each normalised) and its columns and rows of K and C (divided by their largest
/// entries) at or below this: `ZERO_EIGENVALUE²`, so that the eigenvalues it stands for are
/// zero by [`ZERO_EIGENVALUE`] (`|λ|² ≲ ‖Kz‖/m ≤ 1e-12 ω_ref²`), far above the rounding
/// (≈ 1e-16) of a true free motion.
pub const LOCAL_FREE_MOTION: f64 = 1e-12;
/// An eigenvalue whose imaginary part is below this × the largest `|λ|` (at least 1) is real:
/// the imaginary part is round-off.
pub const REAL_PAIR: f64 = 1e-12;
/// Around a frequency `ω_F` the undamped shift is `(ω_F (1 − SHIFT_OFFSET))²`: an eigenvalue
/// on the shift makes the KKT matrix singular, one too near makes its θ dwarf the others'.
pub const SHIFT_OFFSET: f64 = 1e-3;
/// A shift that hit an eigenvalue moves by `3.7 · SHIFT_MOVE · (1 + tries)` of its magnitude.
pub const SHIFT_MOVE: f64 = 1e-3;
/// K is symmetric when the largest entry of `K − Kᵀ` is at or below this × its largest entry
/// (rounding of the assembled second derivatives).
pub const SYMMETRIC_STIFFNESS: f64 = 1e-12;

/// Relative residual `‖T u − θ u‖ / |θ|` a wanted Ritz pair of the shift-invert Arnoldi must
/// reach: it bounds the backward error of `λ − σ` relative to `|λ − σ|`, a few digits above
/// the rounding of the sparse solves.
pub const RITZ_RESIDUAL: f64 = 1e-10;
/// A new Krylov direction whose norm after orthogonalisation falls below this fraction of its
/// norm before is dependent (the basis spans an invariant subspace).
pub const KRYLOV_BREAKDOWN: f64 = 1e-11;
/// A direction of a thick restart's discarded part below this × the largest Ritz value is
/// rounding and not kept in the frontier.
pub const RESTART_DIRECTION: f64 = 1e-14;
/// A frontier vector whose row of B is below this × the largest Ritz value carries no residual
/// and is dropped.
pub const RESTART_FRONTIER: f64 = 1e-15;
/// Gram–Schmidt drops a vector whose norm falls below this fraction of its norm before
/// (dependent on the ones kept).
pub const ORTHONORMAL_DEPENDENT: f64 = 1e-10;
/// A validation round accepts the wanted eigenvalues when their `|θ|` agree with the previous
/// round's to this relative difference.
pub const VALIDATION_AGREEMENT: f64 = 1e-6;
/// With a complex shift, the eigenvector's velocity part must be `λ` times its position part to
/// this (squared, relative): otherwise two eigenvalues are equally near the shift.
pub const MIXED_EIGENVECTOR: f64 = 1e-12;

// ---- Dynamics and kinematics (stages/dynamics/, stages/kinematics.rs) ----

/// The corrector refreshes its iteration matrix when a correction is more than this fraction
/// of the one before (modified Newton converging too slowly: a fresh matrix converges
/// quadratically again, and refreshing costs less than several slow iterations).
pub const MATRIX_REFRESH_RATE: f64 = 0.05;
/// The longest run of steps that refactorise the iteration matrix at their first iteration
/// after a matrix kept from an earlier step failed to converge (the run doubles with each
/// successive failure: 1, 2, 4, …; dynamics corrector).
pub const MATRIX_REUSE_BACKOFF: usize = 16;
/// HHT-α with a spectral radius at infinity `(1+α)/(1−α)` above this damps the alternating
/// mode of its index-3 form by less than 1 % per step: its steps project the velocities onto
/// the velocity constraints (at α = 0, on IFToMM A01 at ERROR = 1e-8, the step otherwise
/// shrank without end).
pub const HHT_UNDAMPED_RADIUS: f64 = 0.99;
/// A dynamic run that gave up at its smallest step stands at a singular configuration when
/// the kept constraint rows' scaled, row-normalised Jacobian has its `σ_min/σ_max` below this
/// fraction of the start's (stages/dynamics/singular.rs). Measured on corpus
/// `ssernap…intento2.adm`: 3.7e-3 at the start, 1e-4 at 0.689 s, 8e-8 (2e-5 of the start's)
/// at the step where GSTIFF gives up, 0.6964 s.
pub const SINGULAR_POSE_CONDITIONING: f64 = 1e-3;
/// … and names the elements whose rows weigh at least this fraction of the largest entry of
/// the dependent combination (the left singular vector of `σ_min`).
pub const SINGULAR_POSE_SHARE: f64 = 0.1;
/// … for models of at most this many coordinates (6 per part): a dense SVD at the failure.
pub const SINGULAR_POSE_DENSE_COLUMNS: usize = 600;
/// The least local error a dynamics step is ever asked for (positions, relative to the
/// characteristic length): its share of ERROR over a long run can be smaller, but below this
/// the estimate is rounding (MIN_INTEGRATOR_ERROR of the settings is the same level).
pub const LOCAL_ERROR_FLOOR: f64 = 1e-12;
/// … and at least this many units of rounding of the largest coordinate, `ε·|x|/L`: a model
/// 1e4 lengths from the origin resolves positions to about 2e-12 of them only, and an
/// estimate made of position differences carries that noise.
pub const LOCAL_ERROR_ROUNDING: f64 = 100.0;
/// Accelerations below `CORRECTOR_ACCELERATION_FLOOR / h²` (scaled like the corrections) count
/// as zero in the corrector's relative test: they move the positions by less than this over a
/// step, far below any constraint tolerance.
pub const CORRECTOR_ACCELERATION_FLOOR: f64 = 1e-12;
/// The corrector's relative test compares the correction with at least this acceleration
/// (translations over L per time², rotations in rad per time²), so that a body at rest does
/// not ask for corrections relative to zero.
pub const CORRECTOR_ACCELERATION_MIN: f64 = 1e-8;
/// A redundant row removed as consistent has become inconsistent when its residual exceeds
/// this × L (lengths) or this (dot products, angles): the verify tolerances' defaults, so a
/// run stops where verify would have called the row inconsistent. A dynamic run allows the
/// larger of this and its INTEGRATOR ERROR (the accuracy it integrates the kept rows' motion
/// to); the kinematic run, which solves positions to [`KINEMATIC_POSITION`], allows this.
pub const REDUNDANT_DRIFT: f64 = 1e-6;
/// The first output time is the start time when they differ by less than this fraction of
/// `max(|t_end|, 1)` (rounding of times written in the dataset).
pub const OUTPUT_AT_START: f64 = 1e-12;
/// A step reaches the next output time when it falls short by less than this fraction of the
/// whole span (the step is then stretched to land on it exactly, not leave a sliver).
pub const OUTPUT_HIT: f64 = 1e-12;
/// The rest of the way to an output is taken in one step when it exceeds the step size by
/// less than this fraction (rounding of the step size).
pub const STEP_FITS: f64 = 1e-9;
/// A step is at the minimum step size HMIN when it exceeds it by less than this fraction: a
/// failure there ends the run, an error estimate above ERROR is accepted.
pub const AT_MIN_STEP: f64 = 1e-4;
/// The span of a run is at least this (time units), so that a run whose only output is at its
/// start still has a positive step size (not a tolerance on any result).
pub const SPAN_FLOOR: f64 = 1e-300;
/// The kinematic run (zero DOF) solves the positions until every constraint residual is below
/// this × L (lengths) or this (angles, direction cosines): Newton on a square Jacobian gets
/// there in a few iterations, and it is a hundred times tighter than the dynamics corrector
/// ([`CORRECTOR_CONSTRAINT`]), since nothing is integrated.
pub const KINEMATIC_POSITION: f64 = 1e-10;
/// Constraint rows (constraints/rows.rs): the Euler-angle rate map `E` of a marker motion's
/// angle (B1, B2, B3) is singular (gimbal lock) when `|det E|` is below this; its rates are
/// then zero.
pub const EULER_RATE_SINGULAR: f64 = 1e-12;
/// Constraint rows: the angle `atan2(s, c)` has no defined rate when `s² + c²` is below this
/// (both directions vanish; only an exact zero is expected, the value guards the division).
pub const ATAN2_DEGENERATE: f64 = 1e-300;

// ---- Forces, measures and requests (physics/) ----

/// The mass a massless part is given where a regular mass matrix is needed (model mass units).
pub const MASSLESS_PART_MASS: f64 = 1e-12;

/// An inertia tensor is singular when its determinant is below this fraction of the cube of
/// its mean principal moment (or its trace is not positive).
pub const SINGULAR_INERTIA_RATIO: f64 = 1e-10;

/// The rotational regularisation of a part with singular inertia, as a fraction of `m·L²`
/// (L the model's characteristic length).
pub const INERTIA_REGULARISATION: f64 = 1e-12;

/// Two points closer than this (relative to the model's characteristic length) coincide: the
/// line of action of a translational SFORCE or SPRINGDAMPER between them is undefined.
pub const COINCIDENT_POINTS: f64 = 1e-12;

// ---- Constraints and rank (constraints/, stages/verify.rs) ----

/// Entries of a working row with `|v| ≤ DROP_RELATIVE · ‖r‖₂` are treated as
/// rounding noise and dropped (never stored, never eliminated with).
pub const DROP_RELATIVE: f64 = 1e-15;
/// Reported terms with `|α_i|·‖a_i‖₂ < ALPHA_DROP · max_j |α_j|·‖a_j‖₂` are
/// omitted (for unit-norm rows: `|α| < 1e-9 · max|α|`).
pub const ALPHA_DROP: f64 = 1e-9;
/// ... but only as long as the dropped terms together stay below
/// `DROP_BUDGET · ‖r‖₂` (`Σ |α_i|·‖a_i‖₂`), so that dropping never degrades
/// the reconstruction noticeably (matters for ill-conditioned dependencies,
/// where genuine coefficients can be 1e-9 times smaller than the largest).
pub const DROP_BUDGET: f64 = 1e-12;
/// Back-substitution does not expand a pending term `c_i u_i` with
/// `|c_i| · max|u_i| ≤ PRUNE_RELATIVE · ‖r‖₂` (rounding noise of a
/// coefficient that is zero in exact arithmetic); this bounds the work of
/// recovering coefficients by the size of the true dependency.
pub const PRUNE_RELATIVE: f64 = 1e-14;

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

/// INTEGRATOR ERROR of the damped settling integration: the path to rest need not be accurate,
/// only stable, and the Newton polish settles the final configuration to EQUILIBRIUM ERROR.
pub const SETTLING_INTEGRATOR_ERROR: f64 = 1e-4;

/// The acceleration IC holds its equations to at least this (acceleration units), whatever a
/// tighter IC AERROR asks: the residual of a direct sparse solve is rounding of the
/// accelerations, which a tiny AERROR would report as non-convergence.
pub const ACCELERATION_IC_FLOOR: f64 = 1e-9;

/// Relative weight, in the least-change velocity IC, of a velocity the dataset does not give
/// (an "inexact zero" the solve may change): small enough that the given velocities and the
/// constraints decide, large enough to keep the solve well posed along free motions.
pub const UNGIVEN_VELOCITY_WEIGHT: f64 = 1e-8;

/// The least-change assembly's residual tolerance is never below this × L (lengths) or this
/// (radians), whatever IC ERROR says: rounding of coordinates of order L, which no Newton step
/// can reduce.
pub const ASSEMBLY_ROUNDING: f64 = 1e-13;
/// Levenberg–Marquardt `μ` of the assembly after its KKT matrix proved singular (then ×100 per
/// failure): small against the unit weights of W, so a regular direction is barely changed.
pub const ASSEMBLY_SINGULAR_REGULARISATION: f64 = 1e-8;
/// `μ` of the assembly once it has reached the constraints and moves along them to the least
/// change: rows independent at the input may become dependent there (an exploded loop closes
/// into a planar one), and their rounding-level residuals divided by a vanishing singular value
/// would throw the step away; this `μ` bounds such a step by residual/(2√μ) while a regular
/// row still holds to μ·λ, far below ERROR.
pub const ASSEMBLY_POLISH_REGULARISATION: f64 = 1e-12;
/// `μ` after a step that backtracking could not make decrease the residual (then ×10).
pub const ASSEMBLY_STEP_REGULARISATION: f64 = 1e-6;
/// A trial assembly step is accepted when its squared residual norm grows by at most this
/// fraction: rounding of the norm, not an increase.
pub const ASSEMBLY_BACKTRACK_SLACK: f64 = 1e-12;
/// A squared (scaled) residual norm below this is zero: any step is accepted.
pub const ASSEMBLY_SATISFIED: f64 = 1e-30;

// ---- Explain (stages/explain/) ----

/// An entry of a left null vector from the SVD (unit vectors on the row-normalised Jacobian)
/// below this is rounding and left out of the basis.
pub const NULL_VECTOR_ENTRY: f64 = 1e-13;
/// Null-vector entries below this fraction of the vector's largest are rounding: they neither
/// make a reaction indeterminate nor name an element as involved in the redundancy.
pub const NULL_VECTOR_ROUNDING: f64 = 1e-10;
/// A reaction component is determinate when a null vector changes it by at most this fraction
/// of the sum of the contributions' magnitudes (they cancel to rounding).
pub const DETERMINATE_CANCELLATION: f64 = 1e-7;
/// An axis is constrained by an element when its projection onto the span of the element's
/// force (torque) directions has squared length above this.
pub const CONSTRAINED_AXIS: f64 = 1e-6;
/// A force or torque direction assembled from a row's terms shorter than this is no direction
/// (the row is reported as a scalar equation).
pub const ZERO_DIRECTION: f64 = 1e-12;
/// A direction joins the span of an element's directions when its part orthogonal to the
/// others is above this fraction of its length.
pub const SPAN_INDEPENDENCE: f64 = 1e-9;
/// A pose found by the random moves is admissible when every non-motion row holds to this
/// (lengths relative to L): well inside the verify tolerances (1e-6).
pub const ADMISSIBLE_RESIDUAL: f64 = 1e-8;
/// IC ERROR of the re-assemblies onto the constraints, × L clamped to [1, 100]: tight, so the
/// ranks compared across poses are not blurred by assembly residuals.
pub const TIGHT_ASSEMBLY: f64 = 1e-11;
/// A part's size (for the random moves) is at least this × L (a part whose markers all sit
/// at its centre of mass still moves).
pub const SMALLEST_PART_SIZE: f64 = 1e-3;

// ---- Plant matrices (stages/plant.rs) ----

/// Central-difference step of the plant matrices B, C, D: relative to the size of an input
/// (at least 1), and per unit of an independent coordinate or its rate.
pub const PLANT_STEP: f64 = 1e-6;

/// A mode whose `|μ|` is below this fraction of the largest is taken at that floor in the
/// descent's saddle-free Newton step (statics/descent.rs): a free motion without stiffness
/// moves by TLIMIT/ALIMIT at most, not without bound.
pub const DESCENT_SOFT_MODE: f64 = 1e-9;

/// Steps between two Newton attempts of the descent where every free motion is stiff
/// (statics/descent.rs).
pub const DESCENT_NEWTON_EVERY: usize = 5;

/// How far the descent is kicked off an unstable equilibrium along its negative-curvature
/// mode: the largest part moves this many radians or characteristic lengths (statics/descent.rs).
pub const DESCENT_KICK: f64 = 0.05;

/// Most continuation steps of one descent (each one Newton step, at most TLIMIT/ALIMIT).
pub const DESCENT_STEPS: usize = 400;

/// Largest number of part coordinates (6n) for which the descent computes the dense modes it
/// steers by at every step; larger models go from Newton straight to settling.
pub const DESCENT_MAX_DIM: usize = 600;

/// Damping ratio of the lowest mode when settling chooses its damping (stages/settle.rs):
/// critical.
pub const SETTLE_DAMPING_RATIO: f64 = 1.0;

/// Settling time in units of the slowest mode's `1/ω₁` when settling chooses it
/// (stages/settle.rs): a critically damped mode's energy falls by about `e^−2·SETTLE_DECAY`.
pub const SETTLE_DECAY: f64 = 40.0;

/// A free motion whose `|μ|` is below this fraction of the largest has no stiffness worth
/// damping for (stages/settle.rs): a door on a vertical hinge.
pub const SETTLE_NO_STIFFNESS: f64 = 1e-9;
