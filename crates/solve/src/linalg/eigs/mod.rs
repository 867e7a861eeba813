//! Eigenvalues of a large constrained second-order system nearest a shift (DESIGN §7, issue #6):
//! shift-invert Arnoldi on one sparse KKT factorisation, without a null-space basis.
//!
//! # The problem
//!
//! In `n` coordinates with `r` independent constraint rows `J` (`r × n`, full row rank), the
//! free motions of `M q̈ + C q̇ + K q + Jᵀμ = 0`, `J q = 0` are `q = x e^{λt}`:
//!
//! ```text
//! (λ²M + λC + K) x + Jᵀμ = 0,   J x = 0,
//! ```
//!
//! with `2f` eigenvalues, `f = n − r`. With an orthonormal basis `N` of the null space of `J`
//! these are the eigenvalues of the reduced problem `(λ²NᵀMN + λNᵀCN + NᵀKN) z = 0` that the
//! dense path solves; here `N` is never formed.
//!
//! # The shift-invert operator ([`ConstrainedPencil::nearest`])
//!
//! In first-order form on the state `w = (x, v)` (`2n` entries) the problem is `A w = λ B w`
//! with `A = [0 1; −K −C]`, `B = [1 0; 0 M]`, the second row carrying `−Jᵀμ` and the states
//! restricted to `J x = 0`, `J v = 0`. For a shift `σ` that is not an eigenvalue, the operator
//! `T = (A − σB)⁻¹B` maps `(x₀, v₀)` to the `(x, v)` with
//!
//! ```text
//! v − σx = x₀                                       (first row)
//! −K x − C v − σ M v − Jᵀμ = M v₀,   J x = 0        (second row, constrained)
//! ```
//!
//! Substituting `v = x₀ + σx` into the second row gives one sparse KKT solve,
//!
//! ```text
//! [ K + σC + σ²M   Jᵀ ] [x]   [ −M(v₀ + σx₀) − C x₀ ]
//! [ J              0  ] [μ] = [ 0                   ],     then v = x₀ + σx,
//! ```
//!
//! so `J x = 0` always and `J v = J x₀`: every image under `T` of a consistent state is
//! consistent, and new Krylov directions are always images under `T`. Every non-zero eigenvalue
//! `θ` of `T` has a consistent eigenvector (`θx = x_out` lies in the null space of `J`, and then
//! `θ J v = J x = 0`), and `θ = 1/(λ − σ)`: `λ = σ + 1/θ`; round-off outside the consistent
//! states only adds `θ ≈ 0` (`λ = ∞`), never a wrong finite eigenvalue. Projecting the KKT
//! system on `N` gives exactly the shift-invert operator of the reduced problem, so both paths
//! have the same spectrum. The eigenvalues nearest `σ` are the largest `|θ|`.
//!
//! * A real `σ` (just below zero for the lowest modes): for an undamped system (`λ = ±iω`)
//!   `|λ − σ|² = ω² + σ²` grows with `ω`, so the nearest are the lowest frequencies.
//! * A frequency `ω_F` (complex `σ = −ε + iω_F`): the operator is the real part
//!   `Re (A − σB)⁻¹B` (real arithmetic; the KKT matrix in real 2 × 2 block form), whose
//!   eigenvectors are those of `T` and whose eigenvalues `ψ = ½(1/(λ − σ) + 1/(λ − σ̄))` are
//!   largest near `σ` and `σ̄`; `λ` is recovered from the eigenvector as `λ = xᴴv / xᴴx`
//!   (checked: `v = λx`).
//!
//! Without damping ([`ConstrainedPencil::nearest_linear`]) the same construction on
//! `K x + Jᵀμ = ν M x`, `ν = −λ²`, needs only `n`-vectors, `S = (K − τM)⁻¹M`, and has no Jordan
//! blocks at the free motions (`ν = 0` is semisimple, while `λ = 0` of an undamped free motion
//! is a 2 × 2 Jordan block of `A`).
//!
//! Free motions of single parts without stiffness or damping ([`deflate`]) are found before
//! the iteration and projected out of both operators (their span and its mass-orthogonal
//! complement are invariant): the iteration never meets their zero eigenvalues, which are
//! counted instead ([`ConstrainedPencil::local_free_motions`]).
//!
//! The KKT matrix is factorised once (sparse LU, [`crate::linalg::linear::SparseLu`]); its `J` block is
//! scaled by the magnitude of the top-left block (the multiplier is not used). One application
//! costs one triangular solve pair and a few sparse products: `O(nnz(L + U))`, linear in the
//! size of a chain. Krylov vectors use the mass metric `x̃ = Lᵀx`, `M = LLᵀ` (block Cholesky, one block per part),
//! in which the undamped operator is symmetric.
//!
//! # Arnoldi with explicit Rayleigh–Ritz ([`largest_ritz_pairs`])
//!
//! An orthonormal basis `W` (`N × m`) is grown one vector at a time with full
//! re-orthogonalisation (classical Gram–Schmidt applied twice); `Z = T W` is stored, the
//! projected matrix `G = Wᵀ Z` gives Ritz pairs `G y = θ y`, `u = W y`, and the frontier `F`
//! (orthonormal, ⟂ W, `B = Fᵀ Z`, so that `Z = W G + F B`) holds the directions not yet in the
//! basis: for plain Arnoldi it is the next Arnoldi vector. **Convergence test**: for each wanted
//! pair (a complex-conjugate pair is one mode; its conjugate has the same residual)
//!
//! ```text
//! ‖T u − θ u‖ = ‖F B y‖ = ‖B y‖ ≤ tol · |θ|,   ‖u‖ = ‖y‖ = 1,   tol = 1e-10,
//! ```
//!
//! which bounds the backward error of `λ − σ = 1/θ` relative to `|λ − σ|`. Each step expands
//! the frontier direction of the first unconverged wanted pair's residual. Converged leading
//! pairs are **locked** (an orthonormal basis of their invariant subspace is moved to the front
//! of `W`, and the other Ritz pairs come from the rest of `G` with the correction
//! `(G_LL − θ)c = −G_LR y`), so that zero modes with `θ = 1/|σ|` do not set a round-off floor
//! `ε θ_max/θ` on the others. When the basis reaches `max(40, 6K + 40)` vectors it is restarted
//! thickly on the locked vectors and the wanted Ritz vectors and some more
//! (`W ← W Q`, `Z ← Z Q`, `G ← QᵀGQ`, `B ← BQ`; the part `W(GQ − Q QᵀGQ)` joins the frontier, a
//! Krylov–Schur restart that needs no Schur form). A single Krylov sequence sees one copy of a
//! multiple eigenvalue (several free parts, symmetric mechanisms), so once the wanted pairs have
//! converged, every frontier direction and then a fresh random direction (made orthogonal to
//! the basis before `T` is applied) are expanded: the result is accepted when such a round
//! leaves the wanted eigenvalues unchanged. The cost is a number of solves that grows with `K`
//! (for the lowest 10 modes of a pendulum chain about 40, whatever its length) and `O(N m²)` for
//! the orthogonalisation, not `O(n³)`.

//!
//! # Layout
//!
//! * [`sparse`]: the compressed-row matrices of the pencil;
//! * [`deflate`]: free motions of single parts, counted and projected out of the operators;
//! * [`pencil`]: the constrained pencil, its KKT factorisations and the two eigen problems;
//! * [`shift_invert`]: the shift-invert operators applied by the Krylov iteration;
//! * [`metric`]: the mass metric of the Krylov spaces;
//! * [`krylov`]: the Krylov basis (`W`, `Z`, `G`, frontier) and its updates;
//! * [`ritz`]: Ritz pairs of the projected matrix, with locking;
//! * [`arnoldi`]: the iteration (expansion, checks, locking, restarts);
//! * [`vectors`]: small dense vector helpers.

pub mod arnoldi;
pub mod deflate;
pub mod krylov;
pub mod metric;
pub mod pencil;
pub mod ritz;
pub mod shift_invert;
pub mod sparse;
pub mod vectors;

pub use arnoldi::largest_ritz_pairs;
pub use krylov::{KrylovOperator, RitzPair, RitzPairs, Wanted, RESIDUAL_TOLERANCE};
pub use pencil::{
    zero_eigenvectors, ConstrainedPencil, LinearEigenpair, LinearEigenpairs, NearestEigenvalues,
    QuadraticEigenpair,
};
pub use sparse::SparseMatrix;

use crate::linalg::linear::LinearError;
/// Why an eigen solution failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EigenError {
    #[error("a matrix entry is out of range or not finite")]
    Input,
    #[error("the shifted KKT matrix cannot be solved (the shift is an eigenvalue or the constraint rows are dependent): {0}")]
    Shift(LinearError),
    /// The projected matrix `G` has a non-finite entry.
    #[error("the small projected eigenproblem failed: non-finite projected matrix")]
    NonFiniteProjection,
    /// The dense eigen solver failed on `G` (its message).
    #[error("the small projected eigenproblem failed: {0}")]
    Projected(String),
    /// With a complex shift, two eigenvalues have the same `ψ`: the eigenvector mixes them.
    #[error("the small projected eigenproblem failed: two eigenvalues are equally near the shift; choose another")]
    AmbiguousShift,
    #[error("shift-invert Arnoldi did not converge: {converged} of {wanted} wanted eigenvalues after {applications} solves")]
    NotConverged {
        converged: usize,
        wanted: usize,
        applications: usize,
    },
}
