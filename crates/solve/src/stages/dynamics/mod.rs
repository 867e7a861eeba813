//! Dynamic simulation (DESIGN §8, ADM-REFERENCE §8.5): the index-3 DAE (or, for the BDF, its
//! stabilised index-2 form SI2: `bdf.rs`) integrated on the part
//! configuration manifold by a variable-order, variable-step BDF (`bdf.rs`: Adams' GSTIFF and
//! WSTIFF, the default) or by the HHT-α method (Negrut, Rampalli, Ottarsson, Sajdak 2007),
//! described here; both use the same corrector (`corrector.rs`).
//!
//! Per step the unknowns are the accelerations `a` (CM acceleration and angular acceleration of
//! every part, ground axes) and the multipliers `λ` of the independent constraint rows:
//!
//! ```text
//! M a_{n+1} + UCF·[(1+α)(Jᵀλ − Q)_{n+1} − α (Jᵀλ − Q)_n] = 0
//! Φ(q_{n+1}, t_{n+1}) / (β h²) = 0
//! q_{n+1} = q_n ⊕ (h v_n + h²/2 ((1−2β) a_n + 2β a_{n+1})),   v_{n+1} = v_n + h((1−γ) a_n + γ a_{n+1})
//! ```
//!
//! with `β = (1−α)²/4`, `γ = 1/2 − α`, `α ∈ [−1/3, 0]` (⊕: translation added, rotation applied
//! with the exponential map). Newton uses the scaled iteration matrix
//! `[M + (1+α)(βh² K_T + γh C_T), (1+α)Jᵀ; J, 0]` (K_T with the geometric stiffness), kept
//! across iterations and steps while it converges well (modified Newton: refreshed when a
//! correction contracts by less than `MATRIX_REFRESH_RATE` (0.05), when the step size moved by
//! more than a factor 2, or after three iterations with a matrix from an earlier step). The
//! scaling makes the matrix nearly independent of h, which is what allows keeping it across
//! step-size changes. The iteration starts from accelerations and multipliers extrapolated
//! linearly from the last two steps. The step size is controlled with the local error
//! estimate `h²|β − 1/6|·‖a_{n+1} − a_n‖` against the INTEGRATOR ERROR. Output times are hit
//! exactly; at each output the velocities and accelerations are made consistent with the
//! constraints (projection and the acceleration/force solve), which also gives the reactions.
//! Redundant rows (removed as in verify) are checked every step; one that becomes violated
//! stops the run.
//!
//! Layout: `hht.rs` (the method's coefficients), `integrator.rs` (the HHT step), `bdf.rs` (the
//! BDF step), `corrector.rs` (the shared Newton iteration and workspace), `stepper.rs` (either
//! behind one interface), `simulate.rs` (step-size control, outputs), `events.rs` (SENSOR
//! events located by re-stepping), `singular.rs` (a run that gives up at a singular
//! configuration says so), `run.rs` (the dataset-level run). What every analysis
//! shares is in [`crate::kernel`]: the problem view (`problem.rs`: generalized forces,
//! drives), the iteration matrix (`matrix.rs`), the consistent-output solve (`output.rs`), the
//! sensor watch, the redundant-row checks, what a run returns and its errors.
//!
//! Cost: [`Integrator`] holds every buffer a step needs (MuJoCo's "model read-only, data
//! preallocated"): a step allocates nothing once the iteration matrix's sparsity pattern is
//! known (a test counts the allocations). The matrix lives in a
//! [`crate::linalg::linear::FixedPatternLu`]: its pattern (the entries nonzero when first assembled,
//! grown if another becomes nonzero) gets its column ordering and symbolic analysis once;
//! each refresh is a numeric refactorisation into the same storage (for I3 and HHT with the
//! pivots of the last factorisation while they stay acceptable: [`crate::linalg::refactor`]).
//! Per iteration: the rows'
//! residuals and gradients, the generalised forces, one sparse solve — O(rows + parts) for a
//! chain; per refresh additionally the assembly (row second derivatives) and the numeric LU.

mod bdf;
mod corrector;
mod events;
mod hht;
mod integrator;
mod run;
mod simulate;
mod singular;
mod stepper;

pub use bdf::Bdf;
pub use corrector::StepTolerance;
pub use integrator::Integrator;
// The kernel types a run takes and returns, re-exported on the dynamics paths callers use.
pub use crate::kernel::{
    flat, outputs_every, Consistent, ExtraDamping, Failure, IntegrationError, MatrixRole, Output,
    OutputSolver, Problem, SensorEvent, SensorStop, SensorWatch, Simulation, SingularSolve,
};
pub use linkage_model::settings::IntegratorSettings;
pub use run::{
    continue_streamed, run, run_from, run_streamed, Continue, DynamicRun, RunError, RunProgress,
    Start, StartingEquilibrium, Stream, UnstableStart,
};
pub use simulate::{simulate, simulate_stepwise, simulate_with, AfterOutput, StepTaken};
pub use stepper::Stepper;
