//! The constrained solve: THE one place where the saddle-point (KKT) matrix
//!
//! ```text
//! [ A        t · S Jᵀ ] [x]   [f]
//! [ ρ · J S   −μ 1    ] [λ] = [g]
//! ```
//!
//! is assembled and solved. `x` has `n` coordinates (6 per part for the analyses: the centre of
//! mass translation `c = 0, 1, 2` and the rotation about ground axes `c = 3, 4, 5` of part `k` at
//! `6k + c`), `λ` one multiplier per kept constraint row (`m` of them, at `n + k`).
//!
//! * `A` (`n × n`) is given by its entries: per-part 6 × 6 blocks (mass `diag(m·1, I_g)`,
//!   coordinate weights) and/or triplets (force Jacobians, geometric stiffness `Σλ∇²Φ`).
//! * `J` (`m × n`) comes from the kept rows' [`RowGradient`]s (or entry by entry, for a matrix
//!   that is not laid out by parts, e.g. the eigen solver's complex form).
//! * `S = diag(s_c)` is an optional column scaling ([`CoordinateScale`]: e.g. `s = L` on
//!   translations to work in characteristic lengths; the identity by default).
//! * `t` scales the `Jᵀ` block (dynamics: `(1+α)·UCF`), `ρ` the `J` block (the eigen solver
//!   scales both by the magnitude of `A`); both 1 by default. Each entry is `t·(s_c·x)` and
//!   `ρ·(s_c·x)`, so with the defaults the gradient's values go in unchanged (bit for bit).
//! * `μ ≥ 0` regularises the multiplier block (Levenberg–Marquardt in the assembly).
//!
//! Contract: the matrix is square of order `n + m`; duplicate entries are summed (in the order
//! added for a one-off factorisation, per slot for a fixed pattern). A zero gradient value is
//! either left out of the sparsity pattern ([`Zeros::Skip`], the default: the pattern follows
//! the geometry) or stored as an explicit zero ([`Zeros::Keep`]); the choice changes the
//! ordering and hence the rounding of the factorisation, so a caller keeps the one its results
//! were recorded with. The order of the calls fixes the order of the entries. Failures are
//! [`LinearError`]s (singular matrix, non-finite entry), never panics.
//!
//! Two forms:
//!
//! * [`SaddlePoint`]: the entries as triplets, factorised once ([`SparseLu`]): a Newton step
//!   of the assembly, the IC's velocity and acceleration solves, the eigen solver's KKT. Its
//!   storage is reused across [`SaddlePoint::clear`]s. Cost: `O(nnz)` to assemble plus the
//!   sparse LU (ordering, symbolic and numeric).
//! * fixed pattern: the same blocks written into a [`FixedPatternLu`] refactorised in place
//!   ([`add_part_mass_blocks`], [`add_constraint_row_blocks`]); the pattern starts as the
//!   diagonal and grows on the first assembly ([`assemble_growing`]); each later assembly
//!   replays the slots and each refresh is a numeric refactorisation, allocation-free (the
//!   integrator's iteration matrix and output projection own their `FixedPatternLu`s).
//!
//! Entries at distinct positions may be added in any order without changing the result (the
//! matrix is sorted into compressed columns before it is factorised); only entries at the same
//! position are summed in the order added. So a stage keeps its results bit for bit when it
//! adds its triplets (force Jacobians, then second derivatives, …) in the order it did.
//!
//! # How each analysis writes its matrix with it
//!
//! | analysis | form | `A` | constraint blocks |
//! |---|---|---|---|
//! | assembly Newton (`stages/assemble.rs`) | [`SaddlePoint`] | [`SaddlePoint::add_coordinate_weights`] `W = diag(1/L², 1)` | [`SaddlePoint::add_constraint_row`], [`SaddlePoint::add_multiplier_regularisation`] `μ` |
//! | statics Newton | its own triplet list, refactorised by [`crate::linalg::triplet_lu::TripletLu`] | `−∂Q/∂q`, `Σλ∇²Φ`, `STABILITY·M/UCF` | [`push_constraint_row`] |
//! | statics projection / initial multipliers | as above | `diag(1/L², 1)` / `diag(1, L²)` | [`push_constraint_row`] |
//! | ic velocity | [`SaddlePoint`] | translations by [`SaddlePoint::add`], [`SaddlePoint::add_rotational_block`] `R D Rᵀ` with [`Zeros::Keep`] | [`SaddlePoint::add_constraint_row`] |
//! | ic acceleration / force | [`SaddlePoint`] | [`SaddlePoint::add_part_mass`] `diag(m, I_g)`, [`Zeros::Skip`] | [`SaddlePoint::add_constraint_row`] |
//! | dynamics iteration matrix | [`assemble_growing`] on its own [`FixedPatternLu`] | [`add_part_mass_blocks`], [`FixedPatternLu::add`] / `add_block` for `βh²K`, `γhC` | [`add_constraint_row_blocks`] with `t = (1+α)·UCF` |
//! | dynamics output projection | as above | [`add_part_mass_blocks`] with the regularisation of `physics::mass` | [`add_constraint_row_blocks`], `t = 1` |
//! | kinematics (zero DOF: `J` square) | [`jacobian_entries`] into [`SparseLu::factor`] | — | [`CoordinateScale::IDENTITY`], [`Zeros::Skip`] |
//! | linearize | [`jacobian_entries`] (`S = L` on translations, [`Zeros::Keep`]), [`null_space`]; the eigen solver's complex form by [`SaddlePoint::add_constraint_entry`] with `ρ = t = α` | | |
//! | explain, assembly rank | [`scaled_row`] | | |
//!
//! Beside the solve, the pieces linearize and explain need from the same Jacobian:
//! [`jacobian_entries`] (the `m × n` matrix `J S` on its own), [`scaled_row`] (a row scaled as
//! in the rank analysis, translations × L, and its norm) and [`null_space`] (an orthonormal
//! basis of the null space of a dense `J`).

use crate::constraints::rows::RowGradient;
use crate::linalg::linear::{FixedPatternLu, LinearError, SparseLu};
use crate::tolerances::NULL_SPACE_RANK;
use crate::tolerances::UNDERFLOW_FLOOR;
use faer::Mat;

/// Coordinates per part.
pub const PART_COORDINATES: usize = 6;

/// The column scaling `s_c` of the part coordinates: `translation` for `c mod 6 < 3`,
/// `rotation` otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoordinateScale {
    pub translation: f64,
    pub rotation: f64,
}

impl CoordinateScale {
    /// No scaling.
    pub const IDENTITY: CoordinateScale = CoordinateScale {
        translation: 1.0,
        rotation: 1.0,
    };

    /// Translations in characteristic lengths: `s = L` on translations (a column of `∂Φ/∂x`
    /// times `L` is the derivative with respect to `x/L`), 1 on rotations.
    pub fn lengths(characteristic_length: f64) -> CoordinateScale {
        CoordinateScale {
            translation: characteristic_length,
            rotation: 1.0,
        }
    }

    /// `s_c` of coordinate `c` (any part).
    #[inline]
    pub fn of(&self, c: usize) -> f64 {
        if c % PART_COORDINATES < 3 {
            self.translation
        } else {
            self.rotation
        }
    }
}

/// Whether zero gradient values enter the sparsity pattern (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Zeros {
    Skip,
    Keep,
}

/// How the constraint blocks are written: `ρ·(s_c·x)` in `J`, `t·(s_c·x)` in `Jᵀ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstraintBlocks {
    pub scale: CoordinateScale,
    /// `ρ`.
    pub row_factor: f64,
    /// `t`.
    pub transpose_factor: f64,
    pub zeros: Zeros,
}

impl Default for ConstraintBlocks {
    fn default() -> Self {
        ConstraintBlocks {
            scale: CoordinateScale::IDENTITY,
            row_factor: 1.0,
            transpose_factor: 1.0,
            zeros: Zeros::Skip,
        }
    }
}

/// A saddle-point matrix as triplets, factorised once (see the module docs).
#[derive(Clone, Debug)]
pub struct SaddlePoint {
    coordinates: usize,
    rows: usize,
    blocks: ConstraintBlocks,
    entries: Vec<(usize, usize, f64)>,
}

impl SaddlePoint {
    /// An empty matrix on `coordinates` unknowns `x` and `rows` multipliers, constraint blocks
    /// written as [`ConstraintBlocks::default`] says (unscaled, zeros skipped).
    pub fn new(coordinates: usize, rows: usize) -> SaddlePoint {
        SaddlePoint {
            coordinates,
            rows,
            blocks: ConstraintBlocks::default(),
            entries: Vec::new(),
        }
    }

    /// The same with other constraint blocks.
    pub fn with_blocks(mut self, blocks: ConstraintBlocks) -> SaddlePoint {
        self.blocks = blocks;
        self
    }

    /// Order of the matrix, `n + m`.
    pub fn dim(&self) -> usize {
        self.coordinates + self.rows
    }

    /// Index of the multiplier of row `k` (in the solution vector and the right-hand side).
    pub fn multiplier(&self, k: usize) -> usize {
        self.coordinates + k
    }

    /// Forgets the entries (the storage stays), for a new assembly of the same shape.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// The entries in the order added.
    pub fn entries(&self) -> &[(usize, usize, f64)] {
        &self.entries
    }

    /// Adds `value` at `(i, j)` of the whole matrix (an entry of `A`, usually).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        self.entries.push((i, j, value));
    }

    /// Adds every triplet of `A`.
    pub fn add_triplets(&mut self, entries: impl IntoIterator<Item = (usize, usize, f64)>) {
        self.entries.extend(entries);
    }

    /// Adds `weight(c)` on the diagonal of every coordinate, in order.
    pub fn add_coordinate_weights(&mut self, weight: impl Fn(usize) -> f64) {
        for c in 0..self.coordinates {
            self.entries.push((c, c, weight(c)));
        }
    }

    /// Adds part `k`'s mass block `diag(mass·1, inertia)` (`inertia` the 3 × 3 rotational
    /// block, e.g. `I_g = R I Rᵀ`), translations first, row by row; zero entries of `inertia`
    /// are left out with [`Zeros::Skip`].
    pub fn add_part_mass(&mut self, k: usize, mass: f64, inertia: &glam::DMat3, zeros: Zeros) {
        let o = PART_COORDINATES * k;
        for c in 0..3 {
            self.entries.push((o + c, o + c, mass));
            for d in 0..3 {
                let x = inertia.col(d)[c];
                if zeros == Zeros::Keep || x != 0.0 {
                    self.entries.push((o + 3 + c, o + 3 + d, x));
                }
            }
        }
    }

    /// Adds part `k`'s 3 × 3 rotational block (row by row; zero entries left out with
    /// [`Zeros::Skip`]).
    pub fn add_rotational_block(&mut self, k: usize, block: &glam::DMat3, zeros: Zeros) {
        let o = PART_COORDINATES * k + 3;
        for c in 0..3 {
            for d in 0..3 {
                let x = block.col(d)[c];
                if zeros == Zeros::Keep || x != 0.0 {
                    self.entries.push((o + c, o + d, x));
                }
            }
        }
    }

    /// Adds one entry `x = ∂Φ_k/∂q_col` of the constraint blocks: `ρ(s x)` at `(n + k, col)`
    /// and `t(s x)` at `(col, n + k)` (skipped when zero with [`Zeros::Skip`]).
    #[inline]
    pub fn add_constraint_entry(&mut self, k: usize, col: usize, x: f64) {
        push_constraint_entry(&mut self.entries, self.coordinates, &self.blocks, k, col, x);
    }

    /// Adds constraint row `k` from its gradient (6 columns per part, in the gradient's order).
    pub fn add_constraint_row(&mut self, k: usize, g: &RowGradient) {
        push_constraint_row(&mut self.entries, self.coordinates, &self.blocks, k, g);
    }

    /// Adds `−μ` on the diagonal of every multiplier (nothing for `μ = 0`).
    pub fn add_multiplier_regularisation(&mut self, mu: f64) {
        if mu > 0.0 {
            for k in 0..self.rows {
                self.entries
                    .push((self.coordinates + k, self.coordinates + k, -mu));
            }
        }
    }

    /// Factorises the matrix (sparse LU with partial pivoting, from scratch).
    pub fn factor(&self) -> Result<SparseLu, LinearError> {
        SparseLu::factor(self.dim(), &self.entries)
    }

    /// Factorises and solves in place: `rhs = [f; g]` becomes `[x; λ]`.
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        self.factor()?.solve(rhs)
    }
}

/// Appends entry `x = ∂Φ_k/∂q_col` of the constraint blocks to a triplet list whose first
/// `coordinates` unknowns are `x`: `ρ(s x)` at `(coordinates + k, col)`, then `t(s x)` at
/// `(col, coordinates + k)` (nothing for a zero with [`Zeros::Skip`]). [`SaddlePoint`] writes
/// its constraint blocks with this; a stage that keeps its own triplet list (statics, whose
/// refactorisation reuses the list's ordering) writes them with it too.
#[inline]
pub fn push_constraint_entry(
    out: &mut Vec<(usize, usize, f64)>,
    coordinates: usize,
    blocks: &ConstraintBlocks,
    k: usize,
    col: usize,
    x: f64,
) {
    if blocks.zeros == Zeros::Skip && x == 0.0 {
        return;
    }
    let row = coordinates + k;
    let sx = blocks.scale.of(col) * x;
    out.push((row, col, blocks.row_factor * sx));
    out.push((col, row, blocks.transpose_factor * sx));
}

/// Appends constraint row `k` from its gradient (6 columns per part, in the gradient's order)
/// by [`push_constraint_entry`].
pub fn push_constraint_row(
    out: &mut Vec<(usize, usize, f64)>,
    coordinates: usize,
    blocks: &ConstraintBlocks,
    k: usize,
    g: &RowGradient,
) {
    for (body, v) in &g.blocks {
        for (c, x) in v.iter().enumerate() {
            push_constraint_entry(out, coordinates, blocks, k, PART_COORDINATES * body + c, *x);
        }
    }
}

/// Why a fixed-pattern assembly failed; the caller names the matrix (`"{what} cannot be set
/// up: {error}"`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PatternError {
    #[error("{0}")]
    Grow(LinearError),
    #[error("its sparsity pattern does not settle")]
    Unsettled,
}

/// Assembles `a` with `fill` until no entry falls outside its pattern, growing it
/// ([`FixedPatternLu::grow`]) at most twice. Returns whether the pattern grew.
pub fn assemble_growing(
    a: &mut FixedPatternLu,
    mut fill: impl FnMut(&mut FixedPatternLu),
) -> Result<bool, PatternError> {
    let mut grew = false;
    // The values do not change between passes, so the second one finds every entry.
    for _ in 0..3 {
        a.clear();
        fill(a);
        if !a.has_missing() {
            return Ok(grew);
        }
        a.grow().map_err(PatternError::Grow)?;
        grew = true;
    }
    Err(PatternError::Unsettled)
}

/// Adds part `k`'s mass blocks `mass·1` and `inertia + regularisation·1` (rotational) to a
/// fixed-pattern matrix, as two 3 × 3 blocks.
pub fn add_part_mass_blocks(
    a: &mut FixedPatternLu,
    k: usize,
    mass: f64,
    inertia: &glam::DMat3,
    regularisation: f64,
) {
    let o = PART_COORDINATES * k;
    let diagonal = |x: f64| move |i: usize, j: usize| if i == j { x } else { 0.0 };
    a.add_block((o, o), (3, 3), 1.0, diagonal(mass));
    a.add_block((o + 3, o + 3), (3, 3), 1.0, |i, j| {
        inertia.col(j)[i] + diagonal(regularisation)(i, j)
    });
}

/// Adds constraint row `k` of a fixed-pattern saddle-point matrix on `coordinates` unknowns:
/// per part of the gradient, the `Jᵀ` column block scaled by `transpose_factor` (`t`), then
/// the `J` row block (unscaled). Zero values claim their places too.
pub fn add_constraint_row_blocks(
    a: &mut FixedPatternLu,
    coordinates: usize,
    k: usize,
    g: &RowGradient,
    transpose_factor: f64,
) {
    let row = coordinates + k;
    for (body, b) in &g.blocks {
        let col = PART_COORDINATES * body;
        a.add_block((col, row), (6, 1), transpose_factor, |i, _| b[i]);
        a.add_block((row, col), (1, 6), 1.0, |_, j| b[j]);
    }
}

/// Appends row `k` of `J S` alone, `(k, col, s_col·x)`, to `out` (zeros kept or skipped as
/// `zeros` says).
pub fn jacobian_entries(
    out: &mut Vec<(usize, usize, f64)>,
    k: usize,
    g: &RowGradient,
    scale: CoordinateScale,
    zeros: Zeros,
) {
    for (body, b) in &g.blocks {
        for (c, x) in b.iter().enumerate() {
            if zeros == Zeros::Keep || *x != 0.0 {
                out.push((k, PART_COORDINATES * body + c, x * scale.of(c)));
            }
        }
    }
}

/// The row gradient scaled as in the rank analysis (translation columns × `length`) as
/// `(6·part + coordinate, value)` entries, nonzero ones only, and its 2-norm (the row
/// normalisation).
pub fn scaled_row(g: &RowGradient, length: f64, out: &mut Vec<(usize, f64)>) -> f64 {
    out.clear();
    for (body, v) in &g.blocks {
        for (c, x) in v.iter().enumerate() {
            let x = if c < 3 { x * length } else { *x };
            if x != 0.0 {
                out.push((PART_COORDINATES * body + c, x));
            }
        }
    }
    out.iter().map(|(_, x)| x * x).sum::<f64>().sqrt()
}

/// Orthonormal basis (columns) of the null space of the dense `a` (rows × cols), by QR of
/// `aᵀ`: the columns of Q past the rank, the rank counting the diagonal entries of R above
/// [`NULL_SPACE_RANK`] × the largest. The identity when `a` has no rows. Cost `O(rows·cols²)`.
pub fn null_space(a: &Mat<f64>) -> Mat<f64> {
    let (rows, cols) = (a.nrows(), a.ncols());
    if rows == 0 {
        return Mat::<f64>::identity(cols, cols);
    }
    let at = a.transpose().to_owned();
    let qr = at.qr();
    let q = qr.compute_Q();
    let r = qr.R();
    let d = rows.min(cols);
    let rmax = (0..d).map(|i| r[(i, i)].abs()).fold(0.0, f64::max);
    let rank = (0..d)
        .filter(|&i| r[(i, i)].abs() > NULL_SPACE_RANK * rmax.max(UNDERFLOW_FLOOR))
        .count();
    q.subcols(rank, cols - rank).to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two masses on a line (`A = diag(2, 4)`, coordinates `x₁`, `x₂`) joined by the
    /// constraint `x₂ − x₁ = g` (`J = [−1 1]`): `[A Jᵀ; J 0][x; λ] = [f; g]`.
    fn two_masses() -> SaddlePoint {
        let mut kkt = SaddlePoint::new(2, 1);
        kkt.add(0, 0, 2.0);
        kkt.add(1, 1, 4.0);
        kkt.add_constraint_entry(0, 0, -1.0);
        kkt.add_constraint_entry(0, 1, 1.0);
        kkt
    }

    #[test]
    fn a_constrained_least_change_step_has_the_closed_form_solution() {
        // min ½(2x₁² + 4x₂²) − (f₁x₁ + f₂x₂) s.t. x₂ − x₁ = g:
        // 2x₁ − λ = f₁, 4x₂ + λ = f₂, x₂ − x₁ = g  ⇒  x₁ = (f₁ + f₂ − 4g)/6.
        let (f1, f2, g) = (1.0, 2.0, 0.5);
        let mut rhs = vec![f1, f2, g];
        two_masses().solve(&mut rhs).unwrap();
        let x1 = (f1 + f2 - 4.0 * g) / 6.0;
        let x2 = x1 + g;
        let lambda = 2.0 * x1 - f1;
        for (got, want) in rhs.iter().zip([x1, x2, lambda]) {
            assert!((got - want).abs() < 1e-14, "{rhs:?}");
        }
    }

    #[test]
    fn the_transpose_factor_scales_the_multiplier_only() {
        // With t·Jᵀ the solution x is unchanged and λ is divided by t.
        let mut scaled = two_masses();
        scaled.clear();
        let mut scaled = scaled.with_blocks(ConstraintBlocks {
            transpose_factor: 4.0,
            ..ConstraintBlocks::default()
        });
        scaled.add(0, 0, 2.0);
        scaled.add(1, 1, 4.0);
        scaled.add_constraint_entry(0, 0, -1.0);
        scaled.add_constraint_entry(0, 1, 1.0);
        let mut a = vec![1.0, 2.0, 0.5];
        let mut b = a.clone();
        two_masses().solve(&mut a).unwrap();
        scaled.solve(&mut b).unwrap();
        assert!((a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14);
        assert!((a[2] - 4.0 * b[2]).abs() < 1e-14);
    }

    #[test]
    fn a_regularised_multiplier_block_relaxes_the_constraint() {
        // [1 1; 1 −μ][x; λ] = [0; g]  ⇒  x = g/(1 + μ).
        let mut kkt = SaddlePoint::new(1, 1);
        kkt.add(0, 0, 1.0);
        kkt.add_constraint_entry(0, 0, 1.0);
        kkt.add_multiplier_regularisation(0.25);
        let mut rhs = vec![0.0, 1.0];
        kkt.solve(&mut rhs).unwrap();
        assert!((rhs[0] - 0.8).abs() < 1e-15);
    }

    #[test]
    fn a_dependent_row_makes_the_matrix_singular_not_a_panic() {
        let mut kkt = SaddlePoint::new(2, 2);
        kkt.add_coordinate_weights(|_| 1.0);
        for k in 0..2 {
            kkt.add_constraint_entry(k, 0, 1.0);
        }
        let mut rhs = vec![0.0, 0.0, 1.0, 1.0];
        assert!(kkt.solve(&mut rhs).is_err());
    }

    fn part_row(blocks: Vec<(usize, [f64; 6])>) -> RowGradient {
        RowGradient { blocks }
    }

    #[test]
    fn the_fixed_pattern_form_solves_the_same_system_as_the_one_off_form() {
        // One part, mass 2, inertia diag(1, 2, 3), held by x = 0 and θ_z = 0 rows.
        let inertia = glam::DMat3::from_diagonal(glam::DVec3::new(1.0, 2.0, 3.0));
        let rows = [
            part_row(vec![(0, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0])]),
            part_row(vec![(0, [0.0, 0.0, 0.0, 0.0, 0.0, 1.0])]),
        ];
        let rhs: Vec<f64> = (1..=8).map(f64::from).collect();
        let mut once = SaddlePoint::new(6, 2);
        once.add_part_mass(0, 2.0, &inertia, Zeros::Skip);
        for (k, g) in rows.iter().enumerate() {
            once.add_constraint_row(k, g);
        }
        let mut want = rhs.clone();
        once.solve(&mut want).unwrap();
        // x = g₀ = 7, θ_z = g₁ = 8; the free coordinates are f/mass: 2/2 and 5/2.
        assert!((want[0] - 7.0).abs() < 1e-15 && (want[5] - 8.0).abs() < 1e-15);
        assert!((want[1] - 1.0).abs() < 1e-15 && (want[4] - 5.0 / 2.0).abs() < 1e-15);

        let mut fixed = FixedPatternLu::new(8, (0..8).map(|i| (i, i))).unwrap();
        for pass in 0..2 {
            let grew = assemble_growing(&mut fixed, |a| {
                add_part_mass_blocks(a, 0, 2.0, &inertia, 0.0);
                for (k, g) in rows.iter().enumerate() {
                    add_constraint_row_blocks(a, 6, k, g, 1.0);
                }
            })
            .unwrap();
            assert_eq!(grew, pass == 0);
            fixed.factor().unwrap();
            let mut got = rhs.clone();
            fixed.solve_in_place(&mut got).unwrap();
            for (g, w) in got.iter().zip(&want) {
                assert!((g - w).abs() < 1e-14, "{got:?} {want:?}");
            }
        }
    }

    #[test]
    fn scaled_jacobian_and_null_space() {
        let g = part_row(vec![(1, [1.0, 0.0, 0.0, 0.0, 0.0, 2.0])]);
        let mut e = Vec::new();
        let norm = scaled_row(&g, 10.0, &mut e);
        assert_eq!(e, vec![(6, 10.0), (11, 2.0)]);
        assert!((norm - 104f64.sqrt()).abs() < 1e-14);
        let mut t = Vec::new();
        jacobian_entries(&mut t, 0, &g, CoordinateScale::lengths(10.0), Zeros::Keep);
        assert_eq!(t.len(), 6);
        assert_eq!((t[0], t[5]), ((0, 6, 10.0), (0, 11, 2.0)));
        // J = [1 1 0]: null space spanned by (1, −1, 0)/√2 and (0, 0, 1).
        let j = Mat::<f64>::from_fn(1, 3, |_, c| if c < 2 { 1.0 } else { 0.0 });
        let n = null_space(&j);
        assert_eq!(n.ncols(), 2);
        for c in 0..2 {
            assert!((n[(0, c)] + n[(1, c)]).abs() < 1e-14);
            let len: f64 = (0..3).map(|r| n[(r, c)] * n[(r, c)]).sum();
            assert!((len - 1.0).abs() < 1e-14);
        }
    }
}
