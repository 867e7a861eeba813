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

use crate::linalg::linear::{LinearError, SparseLu};
use faer::linalg::solvers::Solve;
use faer::Mat;

/// Why an eigen solution failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EigenError {
    #[error("a matrix entry is out of range or not finite")]
    Input,
    #[error("the shifted KKT matrix cannot be solved (the shift is an eigenvalue or the constraint rows are dependent): {0}")]
    Shift(LinearError),
    #[error("the small projected eigenproblem failed: {0}")]
    Projected(String),
    #[error("shift-invert Arnoldi did not converge: {converged} of {wanted} wanted eigenvalues after {applications} solves")]
    NotConverged {
        converged: usize,
        wanted: usize,
        applications: usize,
    },
}

/// A sparse matrix in compressed rows; duplicate entries are summed in the order given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseMatrix {
    nrows: usize,
    ncols: usize,
    row_start: Vec<usize>,
    cols: Vec<usize>,
    values: Vec<f64>,
}

impl SparseMatrix {
    /// Builds the `nrows × ncols` matrix from `(row, col, value)` entries.
    pub fn from_triplets(
        nrows: usize,
        ncols: usize,
        entries: &[(usize, usize, f64)],
    ) -> Result<SparseMatrix, EigenError> {
        if entries
            .iter()
            .any(|&(r, c, v)| r >= nrows || c >= ncols || !v.is_finite())
        {
            return Err(EigenError::Input);
        }
        // A stable sort keeps the order of duplicates, so sums match a dense accumulation.
        let mut order: Vec<usize> = (0..entries.len()).collect();
        order.sort_by_key(|&k| (entries[k].0, entries[k].1));
        let mut row_start = vec![0; nrows + 1];
        let mut cols = Vec::with_capacity(entries.len());
        let mut values: Vec<f64> = Vec::with_capacity(entries.len());
        let mut last = None;
        for k in order {
            let (r, c, v) = entries[k];
            // `last` names the entry `values` ends with: a duplicate adds to it.
            if let (true, Some(x)) = (last == Some((r, c)), values.last_mut()) {
                *x += v;
            } else {
                cols.push(c);
                values.push(0.0 + v);
                row_start[r + 1] += 1;
                last = Some((r, c));
            }
        }
        for r in 0..nrows {
            row_start[r + 1] += row_start[r];
        }
        Ok(SparseMatrix {
            nrows,
            ncols,
            row_start,
            cols,
            values,
        })
    }

    pub fn nrows(&self) -> usize {
        self.nrows
    }

    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// `y += alpha · A x`. Cost `O(nnz)`.
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        for (r, yr) in y.iter_mut().enumerate().take(self.nrows) {
            let mut s = 0.0;
            for k in self.row_start[r]..self.row_start[r + 1] {
                s += self.values[k] * x[self.cols[k]];
            }
            *yr += alpha * s;
        }
    }

    /// Largest magnitude of an entry (0 for an empty matrix).
    pub fn max_abs(&self) -> f64 {
        self.values.iter().fold(0.0, |a, v| a.max(v.abs()))
    }

    /// The stored entries `(row, col, value)`, duplicates summed.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.nrows).flat_map(move |r| {
            (self.row_start[r]..self.row_start[r + 1])
                .map(move |k| (r, self.cols[k], self.values[k]))
        })
    }
}

/// A linear operator `T` on `Rᴺ` whose largest eigenvalues are wanted.
pub trait KrylovOperator {
    fn dim(&self) -> usize;
    /// `y = T x` (`y` arrives zeroed). Its range is the space searched (constraint-consistent
    /// states): new directions are always images under `T`.
    fn apply(&self, x: &[f64], y: &mut [f64]) -> Result<(), EigenError>;
}

/// Which Ritz values are wanted: the `count` largest `|θ|` (a conjugate pair counted once), and,
/// with `beyond`, more until one of them has `|θ| < beyond` (so that every eigenvalue with
/// `|θ| ≥ beyond` is included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wanted {
    pub count: usize,
    pub beyond: Option<f64>,
}

/// A converged Ritz pair: `θ` with `Im θ ≤ 0` (its conjugate is implied) and the unit vector
/// `u = re + i·im`.
#[derive(Clone, Debug, PartialEq)]
pub struct RitzPair {
    pub theta: (f64, f64),
    pub re: Vec<f64>,
    pub im: Vec<f64>,
    /// `‖T u − θ u‖ / |θ|`.
    pub residual: f64,
}

impl RitzPair {
    /// Eigenvalues this pair stands for (2 for a complex pair).
    pub fn multiplicity(&self) -> usize {
        if self.theta.1 == 0.0 {
            1
        } else {
            2
        }
    }
}

/// Result of [`largest_ritz_pairs`].
#[derive(Clone, Debug, PartialEq)]
pub struct RitzPairs {
    /// Largest `|θ|` first.
    pub pairs: Vec<RitzPair>,
    /// Applications of `T` (sparse solves).
    pub applications: usize,
}

/// Relative residual a wanted Ritz pair must reach.
pub const RESIDUAL_TOLERANCE: f64 = 1e-10;
/// A new direction whose norm falls below this fraction of its vector's norm is dependent
/// (the basis spans an invariant subspace).
const BREAKDOWN: f64 = 1e-11;
/// Smallest basis before a restart.
const MIN_BASIS: usize = 40;
/// Basis size before a restart: `BASIS_PER_MODE · wanted + MIN_BASIS`.
const BASIS_PER_MODE: usize = 6;
/// Steps taken after a fresh vector before the wanted pairs are judged again.
const VALIDATION_STEPS: usize = 4;
/// Solve budget: `BASE_APPLICATIONS + APPLICATIONS_PER_MODE · wanted`.
const BASE_APPLICATIONS: usize = 200;
const APPLICATIONS_PER_MODE: usize = 40;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// SplitMix64: reproducible start vectors without a dependency.
fn pseudo_random(seed: u64, out: &mut [f64]) {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03;
    for x in out.iter_mut() {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        *x = (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    }
}

/// The Krylov data: an orthonormal basis `W` (m vectors), `Z = T W`, `G = Wᵀ Z` (row-major),
/// and the frontier: orthonormal `F` ⟂ W (s vectors) with `B = Fᵀ Z` (s × m), such that
/// `Z = W G + F B` up to round-off. The residual of a Ritz pair `(θ, y)`, `G y = θ y`, is then
/// `T W y − θ W y = F B y`: its norm `‖B y‖` comes without a cancellation-prone subtraction, and
/// new basis vectors are taken from `F` (for an unrestarted Arnoldi basis F is the single next
/// Arnoldi vector; restarts and fresh vectors make it a few).
struct Basis {
    w: Vec<Vec<f64>>,
    z: Vec<Vec<f64>>,
    g: Vec<Vec<f64>>,
    f: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
}

impl Basis {
    fn len(&self) -> usize {
        self.w.len()
    }

    /// Removes the components along `W` and `F` (classical Gram–Schmidt twice). Returns the
    /// coefficients on `W` and on `F` and the norms before and after.
    fn project_out(&self, v: &mut [f64]) -> (Vec<f64>, Vec<f64>, f64, f64) {
        let before = norm(v);
        let mut cw = vec![0.0; self.w.len()];
        let mut cf = vec![0.0; self.f.len()];
        for _ in 0..2 {
            for (vs, acc) in [(&self.w, &mut cw), (&self.f, &mut cf)] {
                let c: Vec<f64> = vs.iter().map(|u| dot(u, v)).collect();
                for ((u, ci), a) in vs.iter().zip(&c).zip(acc.iter_mut()) {
                    *a += ci;
                    for (vi, ui) in v.iter_mut().zip(u) {
                        *vi -= ci * ui;
                    }
                }
            }
        }
        (cw, cf, before, norm(v))
    }

    /// Appends a frontier vector (unit, orthogonal to `W` and `F`) whose products with the
    /// columns of `Z` are `row`.
    fn add_frontier(&mut self, f: Vec<f64>, row: Vec<f64>) {
        self.f.push(f);
        self.b.push(row);
    }

    /// Moves the frontier direction `w = F a` (`a` a unit vector of length s) into the basis,
    /// applies `T` and updates `G`, `F`, `B`; the part of `T w` outside `W` and `F` becomes a new
    /// frontier vector unless it is round-off.
    fn extend(&mut self, a: &[f64], op: &dyn KrylovOperator) -> Result<(), EigenError> {
        let s = self.f.len();
        let m = self.w.len();
        let n = op.dim();
        let mut w = vec![0.0; n];
        for (fk, ak) in self.f.iter().zip(a) {
            for (wi, fi) in w.iter_mut().zip(fk) {
                *wi += ak * fi;
            }
        }
        // wᵀ z_j = aᵀ B e_j, since z_j = W g_j + F b_j and w ⟂ W.
        let g_row: Vec<f64> = (0..m)
            .map(|j| (0..s).map(|k| a[k] * self.b[k][j]).sum())
            .collect();
        // The rest of the frontier: an orthonormal complement of a in Rˢ.
        let mut cols = vec![a.to_vec()];
        cols.extend((0..s).map(|k| {
            let mut e = vec![0.0; s];
            e[k] = 1.0;
            e
        }));
        let comp: Vec<Vec<f64>> = orthonormal_columns(cols).into_iter().skip(1).collect();
        let f_new: Vec<Vec<f64>> = comp
            .iter()
            .map(|c| {
                let mut v = vec![0.0; n];
                for (fk, ck) in self.f.iter().zip(c) {
                    if *ck != 0.0 {
                        for (vi, fi) in v.iter_mut().zip(fk) {
                            *vi += ck * fi;
                        }
                    }
                }
                v
            })
            .collect();
        let b_new: Vec<Vec<f64>> = comp
            .iter()
            .map(|c| {
                (0..m)
                    .map(|j| (0..s).map(|k| c[k] * self.b[k][j]).sum())
                    .collect()
            })
            .collect();
        self.f = f_new;
        self.b = b_new;
        let mut z = vec![0.0; n];
        op.apply(&w, &mut z)?;
        self.w.push(w);
        self.g.push(g_row);
        if z.iter().any(|x| !x.is_finite()) {
            return Err(EigenError::Shift(LinearError::Singular));
        }
        let mut c = z.clone();
        let (cw, cf, before, after) = self.project_out(&mut c);
        for (gi, x) in self.g.iter_mut().zip(&cw) {
            gi.push(*x);
        }
        for (bk, x) in self.b.iter_mut().zip(&cf) {
            bk.push(*x);
        }
        self.z.push(z);
        if after > BREAKDOWN * before && after > 0.0 {
            c.iter_mut().for_each(|x| *x /= after);
            let mut row = vec![0.0; m + 1];
            row[m] = after;
            self.add_frontier(c, row);
        }
        Ok(())
    }

    /// `W ← W Q`, `Z ← Z Q`, `G ← Qᵀ G Q`, `B ← B Q` for orthonormal columns `q` (each of
    /// length m). The part of `Z Q` in the discarded directions, `W (G Q − Q QᵀGQ)`, joins the
    /// frontier, so that `Z = W G + F B` still holds.
    fn restart(&mut self, q: &[Vec<f64>], scale: f64) {
        let m = self.len();
        let combine = |vs: &[Vec<f64>], cs: &[Vec<f64>]| -> Vec<Vec<f64>> {
            cs.iter()
                .map(|qc| {
                    let mut out = vec![0.0; vs.first().map_or(0, Vec::len)];
                    for (v, &c) in vs.iter().zip(qc) {
                        if c != 0.0 {
                            for (o, vi) in out.iter_mut().zip(v) {
                                *o += c * vi;
                            }
                        }
                    }
                    out
                })
                .collect()
        };
        let gq: Vec<Vec<f64>> = (0..m)
            .map(|i| q.iter().map(|qc| dot(&self.g[i], qc)).collect())
            .collect();
        let g_new: Vec<Vec<f64>> = q
            .iter()
            .map(|qa| {
                (0..q.len())
                    .map(|b| (0..m).map(|i| qa[i] * gq[i][b]).sum())
                    .collect()
            })
            .collect();
        // E = G Q − Q G_new (m × q): columns orthogonal to span Q.
        let e: Vec<Vec<f64>> = (0..q.len())
            .map(|b| {
                (0..m)
                    .map(|i| gq[i][b] - (0..q.len()).map(|a| q[a][i] * g_new[a][b]).sum::<f64>())
                    .collect()
            })
            .collect();
        let mut p: Vec<Vec<f64>> = Vec::new();
        for mut col in e.clone() {
            for _ in 0..2 {
                for u in q.iter().chain(p.iter()) {
                    let c = dot(u, &col);
                    for (x, ui) in col.iter_mut().zip(u) {
                        *x -= c * ui;
                    }
                }
            }
            let size = norm(&col);
            if size > 1e-14 * scale {
                col.iter_mut().for_each(|x| *x /= size);
                p.push(col);
            }
        }
        let d = combine(&self.w, &p);
        let c_rows: Vec<Vec<f64>> = p
            .iter()
            .map(|pc| e.iter().map(|ec| dot(pc, ec)).collect())
            .collect();
        let b_new: Vec<Vec<f64>> = self
            .b
            .iter()
            .map(|row| q.iter().map(|qc| dot(row, qc)).collect())
            .collect();
        self.w = combine(&self.w, q);
        self.z = combine(&self.z, q);
        self.g = g_new;
        self.b = b_new;
        for (dv, row) in d.into_iter().zip(c_rows) {
            self.add_frontier(dv, row);
        }
        // Frontier directions no residual depends on are dropped.
        let keep: Vec<bool> = self.b.iter().map(|row| norm(row) > 1e-15 * scale).collect();
        let mut k = 0;
        self.f.retain(|_| {
            k += 1;
            keep[k - 1]
        });
        let mut k = 0;
        self.b.retain(|_| {
            k += 1;
            keep[k - 1]
        });
    }

    /// `(Σ y_re_k v_k, Σ y_im_k v_k)` over `vs` (W or Z).
    fn combine(vs: &[Vec<f64>], y_re: &[f64], y_im: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let n = vs.first().map_or(0, Vec::len);
        let (mut re, mut im) = (vec![0.0; n], vec![0.0; n]);
        for ((v, &a), &b) in vs.iter().zip(y_re).zip(y_im) {
            for ((r, i), vi) in re.iter_mut().zip(im.iter_mut()).zip(v) {
                *r += a * vi;
                *i += b * vi;
            }
        }
        (re, im)
    }

    /// `B y` (real and imaginary parts): the residual of the Ritz pair in frontier coordinates.
    fn residual(&self, y_re: &[f64], y_im: &[f64]) -> (Vec<f64>, Vec<f64>) {
        (
            self.b.iter().map(|row| dot(row, y_re)).collect(),
            self.b.iter().map(|row| dot(row, y_im)).collect(),
        )
    }
}

/// A Ritz value with `Im θ ≤ 0` and its unit coefficient vector in the basis.
struct Ritz {
    theta: (f64, f64),
    y_re: Vec<f64>,
    y_im: Vec<f64>,
}

/// A Ritz pair of the whole basis: unit coefficients `y` over all `m` basis vectors, and the
/// part `y_r` over the active (not locked) ones (empty for a locked pair).
struct Pair {
    theta: (f64, f64),
    y_re: Vec<f64>,
    y_im: Vec<f64>,
    active_re: Vec<f64>,
    active_im: Vec<f64>,
}

/// Ritz pairs with the first `locked` basis vectors spanning a converged invariant subspace:
/// the locked pairs are those of `G_LL`, the others those of `G_RR` (so their accuracy is not
/// limited by round-off at the scale of the larger locked `θ`), each completed to a Ritz vector
/// of the whole basis by `c` with `(G_LL − θ) c = −G_LR y_R`. Largest `|θ|` first.
fn ritz_pairs(g: &[Vec<f64>], locked: usize) -> Result<Vec<Pair>, EigenError> {
    let m = g.len();
    let block = |rows: std::ops::Range<usize>, cols: std::ops::Range<usize>| -> Vec<Vec<f64>> {
        rows.map(|i| g[i][cols.clone()].to_vec()).collect()
    };
    let mut out = Vec::new();
    if locked > 0 {
        for r in rayleigh_ritz(&block(0..locked, 0..locked))? {
            let pad = |v: &[f64]| {
                let mut p = v.to_vec();
                p.resize(m, 0.0);
                p
            };
            out.push(Pair {
                theta: r.theta,
                y_re: pad(&r.y_re),
                y_im: pad(&r.y_im),
                active_re: Vec::new(),
                active_im: Vec::new(),
            });
        }
    }
    if locked < m {
        for r in rayleigh_ritz(&block(locked..m, locked..m))? {
            let (mut c_re, mut c_im) = (vec![0.0; locked], vec![0.0; locked]);
            if locked > 0 {
                // Real form of (G_LL − θ) c = b, b = −G_LR y_R:
                // [G_LL − θ_re, θ_im; −θ_im, G_LL − θ_re] [c_re; c_im] = [b_re; b_im].
                let (tr, ti) = r.theta;
                let a = Mat::<f64>::from_fn(2 * locked, 2 * locked, |i, j| {
                    let (bi, bj) = (i / locked, j / locked);
                    let (ii, jj) = (i % locked, j % locked);
                    let diag = if ii == jj { 1.0 } else { 0.0 };
                    match (bi, bj) {
                        (0, 0) | (1, 1) => g[ii][jj] - tr * diag,
                        (0, 1) => ti * diag,
                        _ => -ti * diag,
                    }
                });
                let mut b = Mat::<f64>::from_fn(2 * locked, 1, |i, _| {
                    let (part, row) = (i / locked, i % locked);
                    let y = if part == 0 { &r.y_re } else { &r.y_im };
                    -(locked..m).map(|j| g[row][j] * y[j - locked]).sum::<f64>()
                });
                a.partial_piv_lu().solve_in_place(b.as_mut());
                if (0..2 * locked).all(|i| b[(i, 0)].is_finite()) {
                    for i in 0..locked {
                        c_re[i] = b[(i, 0)];
                        c_im[i] = b[(locked + i, 0)];
                    }
                }
            }
            let mut y_re = c_re;
            y_re.extend_from_slice(&r.y_re);
            let mut y_im = c_im;
            y_im.extend_from_slice(&r.y_im);
            let nrm = (dot(&y_re, &y_re) + dot(&y_im, &y_im)).sqrt().max(1e-300);
            y_re.iter_mut().for_each(|x| *x /= nrm);
            y_im.iter_mut().for_each(|x| *x /= nrm);
            out.push(Pair {
                theta: r.theta,
                y_re,
                y_im,
                active_re: r.y_re,
                active_im: r.y_im,
            });
        }
    }
    out.sort_by(|a, b| {
        let (ma, mb) = (a.theta.0.hypot(a.theta.1), b.theta.0.hypot(b.theta.1));
        mb.total_cmp(&ma)
    });
    Ok(out)
}

/// Eigen-decomposition of `G`: one entry per eigenvalue with `Im θ ≤ 0`, largest `|θ|` first.
fn rayleigh_ritz(g: &[Vec<f64>]) -> Result<Vec<Ritz>, EigenError> {
    let m = g.len();
    if g.iter().flatten().any(|x| !x.is_finite()) {
        return Err(EigenError::Projected("non-finite projected matrix".into()));
    }
    let gm = Mat::<f64>::from_fn(m, m, |i, j| g[i][j]);
    let eig = gm
        .eigen()
        .map_err(|e| EigenError::Projected(format!("{e:?}")))?;
    let (s, u) = (eig.S(), eig.U());
    let mut out: Vec<Ritz> = (0..m)
        .filter(|&i| s[i].im <= 0.0)
        .map(|i| {
            let mut y_re: Vec<f64> = (0..m).map(|r| u[(r, i)].re).collect();
            let mut y_im: Vec<f64> = (0..m).map(|r| u[(r, i)].im).collect();
            let nrm = (dot(&y_re, &y_re) + dot(&y_im, &y_im)).sqrt().max(1e-300);
            y_re.iter_mut().for_each(|x| *x /= nrm);
            y_im.iter_mut().for_each(|x| *x /= nrm);
            Ritz {
                theta: (s[i].re, s[i].im),
                y_re,
                y_im,
            }
        })
        .collect();
    out.sort_by(|a, b| {
        let (ma, mb) = (a.theta.0.hypot(a.theta.1), b.theta.0.hypot(b.theta.1));
        mb.total_cmp(&ma)
    });
    Ok(out)
}

/// Orthonormalises the vectors (modified Gram–Schmidt, twice), dropping those that are
/// dependent on the ones before.
fn orthonormal_columns(vs: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(vs.len());
    for mut v in vs {
        let before = norm(&v);
        if before == 0.0 {
            continue;
        }
        for _ in 0..2 {
            for q in &out {
                let c = dot(q, &v);
                for (vi, qi) in v.iter_mut().zip(q) {
                    *vi -= c * qi;
                }
            }
        }
        let after = norm(&v);
        if after > 1e-10 * before {
            v.iter_mut().for_each(|x| *x /= after);
            out.push(v);
        }
    }
    out
}

/// How a check of the wanted pairs came out.
enum Check {
    /// The wanted pairs (the first `k`) have converged.
    Converged(usize),
    /// The first `k` pairs have converged and are all there is.
    Complete(usize),
    /// More Krylov steps are needed.
    More,
}

/// The Ritz pairs of `op` with the largest `|θ|` (see the module documentation), `available`
/// being the dimension of the space `op` acts on (its rank). Returns fewer pairs than wanted
/// only when the whole space has been spanned.
pub fn largest_ritz_pairs(
    op: &dyn KrylovOperator,
    available: usize,
    wanted: Wanted,
) -> Result<RitzPairs, EigenError> {
    let n = op.dim();
    let available = available.min(n);
    let mut applications = 0usize;
    if available == 0 || wanted.count == 0 {
        return Ok(RitzPairs {
            pairs: Vec::new(),
            applications,
        });
    }
    let mut basis = Basis {
        w: Vec::new(),
        z: Vec::new(),
        g: Vec::new(),
        f: Vec::new(),
        b: Vec::new(),
    };
    let mut target = wanted.count;
    let mut seed = 0u64;
    // Frontier direction to expand next (set by a check: the residual of the first unconverged
    // wanted pair); otherwise the newest frontier vector (the Arnoldi continuation).
    let mut prefer: Option<Vec<f64>> = None;
    let mut fresh = false;
    // Frontier directions still to expand in a validation round.
    let mut sweep = 0usize;
    let mut check_at = 0usize;
    let mut accepted: Option<Vec<f64>> = None;
    // The first `locked` basis vectors span converged pairs (an invariant subspace).
    let mut locked = 0usize;
    let mut scale = 0.0f64;
    loop {
        // Grow the basis by one vector.
        let mut spanned = basis.len() >= n;
        if basis.f.is_empty() {
            sweep = 0;
        }
        if !spanned {
            if sweep == 0 && (basis.f.is_empty() || fresh) {
                // A fresh direction: T applied to a random vector orthogonal to the basis and
                // the frontier (so that T does not amplify what they already hold).
                fresh = false;
                let mut found = false;
                for _ in 0..3 {
                    seed += 1;
                    let mut raw = vec![0.0; n];
                    pseudo_random(seed, &mut raw);
                    basis.project_out(&mut raw);
                    let mut v = vec![0.0; n];
                    op.apply(&raw, &mut v)?;
                    applications += 1;
                    let (_, _, before, after) = basis.project_out(&mut v);
                    if after > BREAKDOWN * before && after > 0.0 && v.iter().all(|x| x.is_finite())
                    {
                        v.iter_mut().for_each(|x| *x /= after);
                        // v ⟂ W, F, and every z_j lies in their span: a zero row of B.
                        basis.add_frontier(v, vec![0.0; basis.len()]);
                        found = true;
                        break;
                    }
                }
                if found {
                    prefer = None;
                } else if basis.f.is_empty() {
                    spanned = true;
                }
            }
            if !spanned {
                let s = basis.f.len();
                let a = if sweep > 0 {
                    // Validation: the oldest frontier direction.
                    sweep -= 1;
                    let mut e = vec![0.0; s];
                    e[0] = 1.0;
                    e
                } else {
                    match prefer.take() {
                        Some(mut a) if a.len() <= s && norm(&a) > 0.0 => {
                            a.resize(s, 0.0);
                            let size = norm(&a);
                            a.iter_mut().for_each(|x| *x /= size);
                            a
                        }
                        _ => {
                            let mut e = vec![0.0; s];
                            e[s - 1] = 1.0;
                            e
                        }
                    }
                };
                basis.extend(&a, op)?;
                applications += 1;
            }
            spanned |= basis.len() >= n;
        }
        let m = basis.len();
        let max_basis = n.min(MIN_BASIS.max(BASIS_PER_MODE * target + MIN_BASIS));
        if !spanned
            && (!basis.f.is_empty() || fresh)
            && m < check_at
            && m < max_basis
            && m != available
        {
            continue;
        }
        check_at = m + 1.max(m / 8);

        // Rayleigh–Ritz; residuals ‖B y‖ / |θ|.
        let ritz = ritz_pairs(&basis.g, locked)?;
        scale = ritz
            .first()
            .map_or(scale, |r| scale.max(r.theta.0.hypot(r.theta.1)));
        let residual = |r: &Pair| {
            let (dr, di) = basis.residual(&r.y_re, &r.y_im);
            (dot(&dr, &dr) + dot(&di, &di)).sqrt() / r.theta.0.hypot(r.theta.1).max(1e-300)
        };
        let residuals: Vec<f64> = ritz.iter().map(residual).collect();
        // At most `available` eigenvalues exist (round-off outside the space adds θ ≈ 0).
        let mut cap = 0;
        let mut total = 0;
        for r in &ritz {
            let k = if r.theta.1 == 0.0 { 1 } else { 2 };
            if total + k > available {
                break;
            }
            total += k;
            cap += 1;
        }
        let check = loop {
            let k = target.min(cap);
            if let Some(i) = (0..k).find(|&i| residuals[i] > RESIDUAL_TOLERANCE) {
                // Expand along this pair's residual next (the Arnoldi direction when F is one
                // vector).
                let (dr, di) = basis.residual(&ritz[i].y_re, &ritz[i].y_im);
                prefer = Some(if norm(&dr) >= norm(&di) { dr } else { di });
                break Check::More;
            }
            if k == 0 {
                break Check::More;
            }
            let found: usize = ritz[..k]
                .iter()
                .map(|r| if r.theta.1 == 0.0 { 1 } else { 2 })
                .sum();
            if found >= available {
                break Check::Complete(k);
            }
            if k < target || k == cap {
                break if spanned {
                    Check::Complete(k)
                } else {
                    Check::More
                };
            }
            let last = &ritz[k - 1];
            let covered = wanted
                .beyond
                .is_none_or(|b| last.theta.0.hypot(last.theta.1) < b);
            if covered {
                break Check::Converged(k);
            }
            target += 1;
        };
        let finish = |k: usize| {
            let pairs = ritz[..k]
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let (re, im) = Basis::combine(&basis.w, &r.y_re, &r.y_im);
                    RitzPair {
                        theta: r.theta,
                        re,
                        im,
                        residual: residuals[i],
                    }
                })
                .collect();
            RitzPairs {
                pairs,
                applications,
            }
        };
        let converged = residuals
            .iter()
            .take_while(|&&r| r <= RESIDUAL_TOLERANCE)
            .count();
        match check {
            Check::Complete(k) => return Ok(finish(k)),
            Check::Converged(k) => {
                let signature: Vec<f64> = ritz[..k]
                    .iter()
                    .map(|r| r.theta.0.hypot(r.theta.1))
                    .collect();
                let same = accepted.as_ref().is_some_and(|a| {
                    a.len() == signature.len()
                        && a.iter()
                            .zip(&signature)
                            .all(|(x, y)| (x - y).abs() <= 1e-6 * x.abs())
                });
                if same {
                    return Ok(finish(k));
                }
                // Validation round: expand every frontier direction (residual space not yet
                // explored), then a fresh one.
                accepted = Some(signature);
                sweep = basis.f.len();
                fresh = true;
                check_at = m + sweep + VALIDATION_STEPS;
            }
            Check::More if spanned => {
                return Err(EigenError::NotConverged {
                    converged,
                    wanted: target,
                    applications,
                });
            }
            Check::More => {}
        }
        if applications > BASE_APPLICATIONS + APPLICATIONS_PER_MODE * target {
            return Err(EigenError::NotConverged {
                converged,
                wanted: target,
                applications,
            });
        }
        // Lock the leading converged active pairs: a change of basis within span W (no
        // solves) that puts an orthonormal basis of their invariant subspace first.
        let lock: Vec<usize> = ritz
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.active_re.is_empty())
            .map_while(|(i, _)| (residuals[i] <= RESIDUAL_TOLERANCE).then_some(i))
            .collect();
        if !lock.is_empty() {
            let active = m - locked;
            let mut cols: Vec<Vec<f64>> = lock
                .iter()
                .flat_map(|&i| [ritz[i].active_re.clone(), ritz[i].active_im.clone()])
                .collect();
            let dims = orthonormal_columns(cols.clone()).len();
            cols.extend((0..active).map(|i| {
                let mut e = vec![0.0; active];
                e[i] = 1.0;
                e
            }));
            let q_active = orthonormal_columns(cols);
            if q_active.len() == active {
                let q: Vec<Vec<f64>> = (0..locked)
                    .map(|i| {
                        let mut e = vec![0.0; m];
                        e[i] = 1.0;
                        e
                    })
                    .chain(q_active.into_iter().map(|c| {
                        let mut e = vec![0.0; locked];
                        e.extend(c);
                        e
                    }))
                    .collect();
                basis.restart(&q, scale);
                locked += dims;
                // The preferred direction is in frontier coordinates, which a square change of
                // basis leaves alone.
            }
        }
        let m = basis.len();
        if m >= max_basis {
            // Thick restart on the locked vectors, the wanted Ritz vectors and some more.
            let ritz = ritz_pairs(&basis.g, locked)?;
            let keep = ritz.len().min(target + 2.max(target / 2));
            let embed = |v: &[f64]| {
                let mut e = vec![0.0; locked];
                e.extend_from_slice(v);
                e
            };
            let cols = (0..locked)
                .map(|i| {
                    let mut e = vec![0.0; m];
                    e[i] = 1.0;
                    e
                })
                .chain(
                    ritz[..keep]
                        .iter()
                        .filter(|r| !r.active_re.is_empty())
                        .flat_map(|r| [embed(&r.active_re), embed(&r.active_im)]),
                )
                .collect();
            let q = orthonormal_columns(cols);
            basis.restart(&q, scale);
            check_at = basis.len() + 1;
        }
    }
}

/// One eigenvalue of the constrained quadratic problem (a complex pair given once, with
/// `Im λ ≥ 0`) and the position part `x` of its eigenvector.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadraticEigenpair {
    /// λ in radians per time unit.
    pub lambda: (f64, f64),
    /// Complex position vector (`re`, `im`), in the pencil's coordinates.
    pub x_re: Vec<f64>,
    pub x_im: Vec<f64>,
    /// Relative residual of the shift-invert pair.
    pub residual: f64,
}

/// The constrained quadratic pencil `(λ²M + λC + K) x + Jᵀμ = 0`, `J x = 0`.
#[derive(Clone, Debug)]
pub struct ConstrainedPencil {
    pub mass: SparseMatrix,
    pub damping: SparseMatrix,
    pub stiffness: SparseMatrix,
    /// Independent rows only (`r × n`).
    pub jacobian: SparseMatrix,
    metric: MassMetric,
}

/// The metric of the Krylov spaces: coordinates `x̃ = Lᵀx` with `M = L Lᵀ` (Cholesky factors
/// of M's 6 × 6 diagonal blocks, one per part), so that Euclidean products of `x̃` are
/// kinetic-energy products of `x`. Then the undamped operator is symmetric and its eigenvectors
/// orthogonal: a basis vector orthogonal to the (dominant) zero modes carries none of them,
/// where with the Euclidean product it would carry enough to leave a round-off floor
/// `ε θ_max/θ` on the other residuals. The identity when M has another structure.
#[derive(Clone, Debug)]
struct MassMetric {
    /// Row-major lower-triangular 6 × 6 factors; empty for the identity.
    blocks: Vec<[f64; 36]>,
}

const BLOCK: usize = 6;

impl MassMetric {
    fn new(m: &SparseMatrix) -> MassMetric {
        let n = m.nrows();
        let identity = MassMetric { blocks: Vec::new() };
        if !n.is_multiple_of(BLOCK) || m.ncols() != n {
            return identity;
        }
        let mut blocks = vec![[0.0; 36]; n / BLOCK];
        for (i, j, v) in m.entries() {
            if i / BLOCK != j / BLOCK {
                return identity;
            }
            blocks[i / BLOCK][(i % BLOCK) * BLOCK + j % BLOCK] = v;
        }
        for b in &mut blocks {
            // Cholesky of the block's symmetric part.
            let a = *b;
            let mut l = [0.0; 36];
            for i in 0..BLOCK {
                for j in 0..=i {
                    let mut sum = 0.5 * (a[i * BLOCK + j] + a[j * BLOCK + i]);
                    for k in 0..j {
                        sum -= l[i * BLOCK + k] * l[j * BLOCK + k];
                    }
                    if i == j {
                        if sum <= 0.0 || !sum.is_finite() {
                            return identity;
                        }
                        l[i * BLOCK + i] = sum.sqrt();
                    } else {
                        l[i * BLOCK + j] = sum / l[j * BLOCK + j];
                    }
                }
            }
            *b = l;
        }
        MassMetric { blocks }
    }

    /// `out = Lᵀ x`.
    fn metric_of(&self, x: &[f64], out: &mut [f64]) {
        if self.blocks.is_empty() {
            out.copy_from_slice(x);
            return;
        }
        for (k, l) in self.blocks.iter().enumerate() {
            let o = k * BLOCK;
            for i in 0..BLOCK {
                out[o + i] = (i..BLOCK).map(|r| l[r * BLOCK + i] * x[o + r]).sum();
            }
        }
    }

    /// `out = L⁻ᵀ x̃`.
    fn unmetric(&self, xt: &[f64], out: &mut [f64]) {
        if self.blocks.is_empty() {
            out.copy_from_slice(xt);
            return;
        }
        for (k, l) in self.blocks.iter().enumerate() {
            let o = k * BLOCK;
            for i in (0..BLOCK).rev() {
                let s: f64 = (i + 1..BLOCK).map(|r| l[r * BLOCK + i] * out[o + r]).sum();
                out[o + i] = (xt[o + i] - s) / l[i * BLOCK + i];
            }
        }
    }

    /// `out = L x̃` (`= M x`).
    fn weigh(&self, xt: &[f64], out: &mut [f64]) {
        if self.blocks.is_empty() {
            out.copy_from_slice(xt);
            return;
        }
        for (k, l) in self.blocks.iter().enumerate() {
            let o = k * BLOCK;
            for i in 0..BLOCK {
                out[o + i] = (0..=i).map(|c| l[i * BLOCK + c] * xt[o + c]).sum();
            }
        }
    }
}

/// Result of [`ConstrainedPencil::nearest`].
#[derive(Clone, Debug, PartialEq)]
pub struct NearestEigenvalues {
    /// Nearest to the shift first.
    pub pairs: Vec<QuadraticEigenpair>,
    /// Eigenvalues they stand for (conjugates counted).
    pub eigenvalues: usize,
    pub applications: usize,
}

impl ConstrainedPencil {
    /// The pencil of the given matrices (M symmetric positive definite).
    pub fn new(
        mass: SparseMatrix,
        damping: SparseMatrix,
        stiffness: SparseMatrix,
        jacobian: SparseMatrix,
    ) -> ConstrainedPencil {
        let metric = MassMetric::new(&mass);
        ConstrainedPencil {
            mass,
            damping,
            stiffness,
            jacobian,
            metric,
        }
    }

    /// `x = L⁻ᵀ x̃` of a Krylov vector's position part.
    fn unweigh(&self, xt: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; xt.len()];
        self.metric.unmetric(xt, &mut x);
        x
    }

    /// Coordinates `n`.
    pub fn coordinates(&self) -> usize {
        self.mass.nrows()
    }

    /// Free motions `f = n − r` (rows independent).
    pub fn free_motions(&self) -> usize {
        self.coordinates().saturating_sub(self.jacobian.nrows())
    }

    /// Factorises `[Σ cᵢAᵢ, αJᵀ; αJ, 0]`, `α` the bound `Σ|cᵢ| max|Aᵢ|` on the top-left block.
    fn factor_kkt(&self, blocks: &[(f64, &SparseMatrix)]) -> Result<SparseLu, EigenError> {
        self.factor_complex_kkt(blocks, &[])
    }

    /// Factorises the KKT matrix of the complex top-left block `Σ cᵢAᵢ + i Σ dᵢAᵢ` in real
    /// form: unknowns `(x_re, x_im, μ_re, μ_im)` and
    /// `[A_re, −A_im, αJᵀ, 0; A_im, A_re, 0, αJᵀ; αJ, 0, 0, 0; 0, αJ, 0, 0]` (just
    /// `[A_re, αJᵀ; αJ, 0]` when there is no imaginary part).
    fn factor_complex_kkt(
        &self,
        re: &[(f64, &SparseMatrix)],
        im: &[(f64, &SparseMatrix)],
    ) -> Result<SparseLu, EigenError> {
        let n = self.coordinates();
        let r = self.jacobian.nrows();
        let alpha = re
            .iter()
            .chain(im)
            .map(|(c, a)| c.abs() * a.max_abs())
            .sum::<f64>();
        let alpha = if alpha > 0.0 && alpha.is_finite() {
            alpha
        } else {
            1.0
        };
        let complex = im.iter().any(|(c, a)| *c != 0.0 && a.max_abs() > 0.0);
        let copies = if complex { 2 } else { 1 };
        let mut e = Vec::new();
        for b in 0..copies {
            for (c, a) in re {
                if *c != 0.0 {
                    e.extend(a.entries().map(|(i, j, v)| (b * n + i, b * n + j, c * v)));
                }
            }
            for (i, j, v) in self.jacobian.entries() {
                let row = copies * n + b * r + i;
                e.push((row, b * n + j, alpha * v));
                e.push((b * n + j, row, alpha * v));
            }
        }
        if complex {
            for (c, a) in im {
                if *c != 0.0 {
                    for (i, j, v) in a.entries() {
                        e.push((i, n + j, -c * v));
                        e.push((n + i, j, c * v));
                    }
                }
            }
        }
        SparseLu::factor(copies * (n + r), &e).map_err(EigenError::Shift)
    }

    /// The eigenvalues nearest the shift `σ = shift.0 + i·shift.1` (radians per time unit), as
    /// many as `wanted` says. For a real shift `beyond` bounds `θ = 1/|λ − σ|`; for a complex
    /// one the operator is `Re (A − σB)⁻¹B`, whose eigenvalue
    /// `ψ = ½(1/(λ − σ) + 1/(λ − σ̄))` is largest near `σ` and `σ̄`.
    ///
    /// The Krylov space lives in the balanced state `(a·x, v)`, `a = scale > 0`: eigenvectors
    /// `(a x, λ x)` of eigenvalues with `|λ| ≈ a` are then well conditioned.
    pub fn nearest(
        &self,
        shift: (f64, f64),
        scale: f64,
        wanted: Wanted,
    ) -> Result<NearestEigenvalues, EigenError> {
        let (sr, si) = shift;
        let lu = self.factor_complex_kkt(
            &[
                (1.0, &self.stiffness),
                (sr, &self.damping),
                (sr * sr - si * si, &self.mass),
            ],
            &[(si, &self.damping), (2.0 * sr * si, &self.mass)],
        )?;
        let complex = lu_is_complex(&lu, self);
        let scale = if scale > 0.0 && scale.is_finite() {
            scale
        } else {
            1.0
        };
        let op = QuadraticShiftInvert {
            pencil: self,
            lu,
            sigma: (sr, if complex { si } else { 0.0 }),
            scale,
        };
        let ritz = largest_ritz_pairs(&op, 2 * self.free_motions(), wanted)?;
        let n = self.coordinates();
        let mut eigenvalues = 0;
        let mut pairs = Vec::with_capacity(ritz.pairs.len());
        for p in ritz.pairs {
            eigenvalues += p.multiplicity();
            // Position part of the state, unscaled.
            let unscale = |u: &[f64]| {
                let xt: Vec<f64> = u.iter().map(|v| v / scale).collect();
                self.unweigh(&xt)
            };
            let x_re = unscale(&p.re[..n]);
            let mut x_im = unscale(&p.im[..n]);
            let (tr, ti) = p.theta;
            let lambda = if !complex {
                let t2 = tr * tr + ti * ti;
                (sr + tr / t2, -ti / t2)
            } else {
                // v = λx on an eigenvector: λ = xᴴv / xᴴx.
                let (v_re, v_im) = (self.unweigh(&p.re[n..]), self.unweigh(&p.im[n..]));
                let (mut num_re, mut num_im, mut den) = (0.0, 0.0, 0.0);
                for k in 0..n {
                    num_re += x_re[k] * v_re[k] + x_im[k] * v_im[k];
                    num_im += x_re[k] * v_im[k] - x_im[k] * v_re[k];
                    den += x_re[k] * x_re[k] + x_im[k] * x_im[k];
                }
                let den = den.max(1e-300);
                let (lr, li) = (num_re / den, num_im / den);
                // Two eigenvalues with one ψ would give a mixed vector: v ≠ λx.
                let (mut miss, mut size) = (0.0, 0.0);
                for k in 0..n {
                    let dr = v_re[k] - (lr * x_re[k] - li * x_im[k]);
                    let di = v_im[k] - (lr * x_im[k] + li * x_re[k]);
                    miss += dr * dr + di * di;
                    size += v_re[k] * v_re[k] + v_im[k] * v_im[k];
                }
                if miss > 1e-12 * size.max(1e-300) {
                    return Err(EigenError::Projected(
                        "two eigenvalues are equally near the shift; choose another".into(),
                    ));
                }
                if li < 0.0 {
                    x_im.iter_mut().for_each(|v| *v = -*v);
                    (lr, -li)
                } else {
                    (lr, li)
                }
            };
            pairs.push(QuadraticEigenpair {
                lambda,
                x_re,
                x_im,
                residual: p.residual,
            });
        }
        Ok(NearestEigenvalues {
            pairs,
            eigenvalues,
            applications: ritz.applications,
        })
    }

    /// The eigenvalues `ν` nearest the real shift `τ` of the constrained linear problem
    ///
    /// ```text
    /// K̂ x + Jᵀμ = ν M x,   J x = 0,     K̂ = K, or (K + Kᵀ)/2 with `symmetric_part`,
    /// ```
    ///
    /// by Arnoldi on `S = (K̂ − τM)⁻¹M` restricted by J (one KKT factorisation; `θ = 1/(ν − τ)`).
    /// Without damping the quadratic problem is this one with `ν = −λ²`: every `ν` gives the
    /// eigenvalues `λ = ±√(−ν)` with the same `x`, and the free motions are semisimple `ν = 0`
    /// (no Jordan blocks, unlike the first-order form).
    pub fn nearest_linear(
        &self,
        tau: f64,
        wanted: Wanted,
        symmetric_part: bool,
    ) -> Result<LinearEigenpairs, EigenError> {
        let n = self.coordinates();
        let sym;
        let k = if symmetric_part {
            let mut t: Vec<(usize, usize, f64)> = Vec::new();
            for (i, j, v) in self.stiffness.entries() {
                t.push((i, j, 0.5 * v));
                t.push((j, i, 0.5 * v));
            }
            sym = SparseMatrix::from_triplets(n, n, &t)?;
            &sym
        } else {
            &self.stiffness
        };
        let lu = self.factor_kkt(&[(1.0, k), (-tau, &self.mass)])?;
        let op = LinearShiftInvert { pencil: self, lu };
        let ritz = largest_ritz_pairs(&op, self.free_motions(), wanted)?;
        let pairs = ritz
            .pairs
            .into_iter()
            .map(|p| {
                let (tr, ti) = p.theta;
                let t2 = tr * tr + ti * ti;
                LinearEigenpair {
                    nu: (tau + tr / t2, -ti / t2),
                    multiplicity: p.multiplicity(),
                    x_re: self.unweigh(&p.re),
                    x_im: self.unweigh(&p.im),
                    residual: p.residual,
                }
            })
            .collect();
        Ok(LinearEigenpairs {
            pairs,
            applications: ritz.applications,
        })
    }

    /// Eigenvalues `ν` of `K_s x + Jᵀμ = ν M x`, `J x = 0` (`K_s = (K + Kᵀ)/2`) with
    /// `|ν| ≤ zero_tol`, found with shift `τ < 0` (`|τ| ≫ zero_tol`): their number and a real
    /// orthonormal basis of their eigenvectors (the free motions without stiffness), and the
    /// solves it took.
    pub fn stiffness_null_space(
        &self,
        tau: f64,
        zero_tol: f64,
    ) -> Result<(usize, Vec<Vec<f64>>, usize), EigenError> {
        let found = self.nearest_linear(
            tau,
            Wanted {
                count: 1,
                beyond: Some(1.0 / (tau.abs() + zero_tol)),
            },
            true,
        )?;
        let (count, basis) = zero_eigenvectors(&found.pairs, zero_tol);
        Ok((count, basis, found.applications))
    }
}

/// The number of eigenvalues `|ν| ≤ zero_tol` among `pairs` (conjugates counted) and an
/// orthonormal real basis of their vectors.
pub fn zero_eigenvectors(pairs: &[LinearEigenpair], zero_tol: f64) -> (usize, Vec<Vec<f64>>) {
    let mut count = 0;
    let mut vectors = Vec::new();
    for p in pairs {
        if p.nu.0.hypot(p.nu.1) <= zero_tol {
            count += p.multiplicity;
            vectors.push(p.x_re.clone());
            if p.multiplicity == 2 {
                vectors.push(p.x_im.clone());
            }
        }
    }
    (count, orthonormal_columns(vectors))
}

/// One eigenvalue `ν` of the constrained linear problem (`Im ν ≤ 0` for a complex pair, whose
/// conjugate is implied) and its unit eigenvector `x = x_re + i·x_im`.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearEigenpair {
    pub nu: (f64, f64),
    /// 1 for a real `ν`, 2 for a complex pair.
    pub multiplicity: usize,
    pub x_re: Vec<f64>,
    pub x_im: Vec<f64>,
    pub residual: f64,
}

/// Result of [`ConstrainedPencil::nearest_linear`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinearEigenpairs {
    /// Nearest to the shift first.
    pub pairs: Vec<LinearEigenpair>,
    pub applications: usize,
}

/// Whether the factorised KKT matrix is the complex (doubled) one.
fn lu_is_complex(lu: &SparseLu, p: &ConstrainedPencil) -> bool {
    lu.dim() == 2 * (p.coordinates() + p.jacobian.nrows())
}

/// `T = (A − σB)⁻¹B` (real `σ`) or `Re (A − σB)⁻¹B` (complex `σ`) on the balanced state
/// `(a·x, v)`, `a = scale` (see [`ConstrainedPencil::nearest`]).
struct QuadraticShiftInvert<'a> {
    pencil: &'a ConstrainedPencil,
    lu: SparseLu,
    sigma: (f64, f64),
    scale: f64,
}

impl KrylovOperator for QuadraticShiftInvert<'_> {
    fn dim(&self) -> usize {
        2 * self.pencil.coordinates()
    }

    /// `(a x̃₀, ṽ₀) ↦ (a Lᵀx, Lᵀ Re v)` with x from the KKT solve and `v = x₀ + σx`.
    fn apply(&self, w: &[f64], out: &mut [f64]) -> Result<(), EigenError> {
        let n = self.pencil.coordinates();
        let r = self.pencil.jacobian.nrows();
        let (sr, si) = self.sigma;
        let a = self.scale;
        let metric = &self.pencil.metric;
        let xt0: Vec<f64> = w[..n].iter().map(|x| x / a).collect();
        let vt0 = &w[n..];
        let mut x0 = vec![0.0; n];
        metric.unmetric(&xt0, &mut x0);
        // rhs = −M(v₀ + σx₀) − C x₀ = −L(ṽ₀ + σx̃₀) − C x₀ (imaginary part −σ_im L x̃₀).
        let copies = if si != 0.0 { 2 } else { 1 };
        let mut rhs = vec![0.0; copies * (n + r)];
        let mv: Vec<f64> = vt0.iter().zip(&xt0).map(|(v, x)| -(v + sr * x)).collect();
        metric.weigh(&mv, &mut rhs[..n]);
        self.pencil.damping.mul_add(-1.0, &x0, &mut rhs[..n]);
        if si != 0.0 {
            let mx: Vec<f64> = xt0.iter().map(|x| -si * x).collect();
            metric.weigh(&mx, &mut rhs[n..2 * n]);
        }
        self.lu.solve(&mut rhs).map_err(EigenError::Shift)?;
        // Re v − x₀ = σ_re x_re − σ_im x_im.
        let dv: Vec<f64> = (0..n)
            .map(|i| sr * rhs[i] - if si != 0.0 { si * rhs[n + i] } else { 0.0 })
            .collect();
        let (xo, vo) = out.split_at_mut(n);
        metric.metric_of(&rhs[..n], xo);
        metric.metric_of(&dv, vo);
        for i in 0..n {
            xo[i] *= a;
            vo[i] += xt0[i];
        }
        Ok(())
    }
}

/// `x ↦ y` with `(K̂ − τM) y + Jᵀμ = M x`, `J y = 0`, in the metric coordinates.
struct LinearShiftInvert<'a> {
    pencil: &'a ConstrainedPencil,
    lu: SparseLu,
}

impl KrylovOperator for LinearShiftInvert<'_> {
    fn dim(&self) -> usize {
        self.pencil.coordinates()
    }

    /// `x̃ ↦ Lᵀ y`, `(K̂ − τM) y + Jᵀμ = L x̃` (`= M x`).
    fn apply(&self, xt: &[f64], out: &mut [f64]) -> Result<(), EigenError> {
        let n = self.pencil.coordinates();
        let mut rhs = vec![0.0; n + self.pencil.jacobian.nrows()];
        self.pencil.metric.weigh(xt, &mut rhs[..n]);
        self.lu.solve(&mut rhs).map_err(EigenError::Shift)?;
        self.pencil.metric.metric_of(&rhs[..n], out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal operator with the given eigenvalues.
    struct Diagonal(Vec<f64>);

    impl KrylovOperator for Diagonal {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn apply(&self, x: &[f64], y: &mut [f64]) -> Result<(), EigenError> {
            for ((yi, xi), d) in y.iter_mut().zip(x).zip(&self.0) {
                *yi = d * xi;
            }
            Ok(())
        }
    }

    #[test]
    fn sparse_matrix_sums_duplicates_and_multiplies() {
        let a = SparseMatrix::from_triplets(
            2,
            3,
            &[(0, 0, 1.0), (1, 2, 2.0), (0, 0, 0.5), (1, 0, -1.0)],
        )
        .unwrap();
        let mut y = vec![1.0, 1.0];
        a.mul_add(2.0, &[1.0, 5.0, 3.0], &mut y);
        // Row 0: 1.5·1 → y = 1 + 3; row 1: −1 + 6 → y = 1 + 10.
        assert_eq!(y, vec![4.0, 11.0]);
        assert_eq!(a.max_abs(), 2.0);
        assert!(SparseMatrix::from_triplets(1, 1, &[(1, 0, 1.0)]).is_err());
    }

    #[test]
    fn arnoldi_finds_the_largest_eigenvalues_of_a_diagonal_operator() {
        let d: Vec<f64> = (1..=300).map(|k| 1.0 / k as f64).collect();
        let r = largest_ritz_pairs(
            &Diagonal(d),
            300,
            Wanted {
                count: 5,
                beyond: None,
            },
        )
        .unwrap();
        let got: Vec<f64> = r.pairs.iter().map(|p| p.theta.0).collect();
        for (k, g) in got.iter().enumerate() {
            let want = 1.0 / (k + 1) as f64;
            assert!((g - want).abs() < 1e-10 * want, "{got:?}");
        }
        assert!(r.applications < 150, "{}", r.applications);
    }

    #[test]
    fn a_repeated_eigenvalue_is_found_with_its_multiplicity() {
        // θ = 1 three times: one Krylov sequence sees one copy; fresh vectors find the others.
        let mut d: Vec<f64> = (1..=200).map(|k| 0.5 / k as f64).collect();
        d[7] = 1.0;
        d[50] = 1.0;
        d[120] = 1.0;
        let r = largest_ritz_pairs(
            &Diagonal(d),
            200,
            Wanted {
                count: 1,
                beyond: Some(0.9),
            },
        )
        .unwrap();
        let ones = r
            .pairs
            .iter()
            .filter(|p| (p.theta.0 - 1.0).abs() < 1e-10)
            .count();
        assert_eq!(
            ones,
            3,
            "{:?}",
            r.pairs.iter().map(|p| p.theta).collect::<Vec<_>>()
        );
        assert!((r.pairs[3].theta.0 - 0.5).abs() < 1e-10);
    }

    #[test]
    fn a_small_space_is_spanned_exactly() {
        let r = largest_ritz_pairs(
            &Diagonal(vec![3.0, -2.0]),
            2,
            Wanted {
                count: 10,
                beyond: None,
            },
        )
        .unwrap();
        let got: Vec<f64> = r.pairs.iter().map(|p| p.theta.0).collect();
        assert_eq!(got.len(), 2);
        assert!((got[0] - 3.0).abs() < 1e-14 && (got[1] + 2.0).abs() < 1e-14);
    }
}
