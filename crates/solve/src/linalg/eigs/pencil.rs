//! The constrained quadratic pencil, its KKT factorisations and its two eigen problems
//! (first-order shift-invert, and the undamped linear one).

use super::arnoldi::largest_ritz_pairs;
use super::deflate::{Deflated, LocalFreeMotions};
use super::krylov::{KrylovOperator, Wanted};
use super::metric::MassMetric;
use super::shift_invert::{LinearShiftInvert, PencilView, QuadraticShiftInvert};
use super::vectors::orthonormal_columns;
use super::{EigenError, SparseMatrix};
use crate::linalg::kkt::{ConstraintBlocks, CoordinateScale, SaddlePoint, Zeros};
use crate::linalg::linear::SparseLu;
use crate::tolerances::MIXED_EIGENVECTOR;
use crate::tolerances::UNDERFLOW_FLOOR;

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
    /// Free motions of single parts, deflated from both eigen problems.
    local_free: LocalFreeMotions,
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
        let local_free = LocalFreeMotions::find(&metric, &damping, &stiffness, &jacobian);
        ConstrainedPencil {
            mass,
            damping,
            stiffness,
            jacobian,
            metric,
            local_free,
        }
    }

    /// What the shift-invert operators read.
    fn view(&self) -> PencilView<'_> {
        PencilView {
            coordinates: self.coordinates(),
            constraints: self.jacobian.nrows(),
            metric: &self.metric,
            damping: &self.damping,
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

    /// Free motions of single parts without stiffness or damping ([`super::deflate`]): each
    /// is `ν = 0` of the undamped problem and a double `λ = 0`. Neither eigen problem returns
    /// them; they are counted here.
    pub fn local_free_motions(&self) -> usize {
        self.local_free.count()
    }

    /// `op` with the local free motions projected out, and the dimension of what is left
    /// (`copies` consecutive `n`-vectors per state).
    fn deflated<'a>(&'a self, op: &'a dyn KrylovOperator, copies: usize) -> (Deflated<'a>, usize) {
        let left = self.free_motions().saturating_sub(self.local_free.count());
        (
            Deflated {
                op,
                motions: &self.local_free,
                coordinates: self.coordinates(),
                copies,
            },
            copies * left,
        )
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
        // Both constraint blocks scaled by α, explicit zeros of J kept.
        let mut kkt = SaddlePoint::new(copies * n, copies * r).with_blocks(ConstraintBlocks {
            scale: CoordinateScale::IDENTITY,
            row_factor: alpha,
            transpose_factor: alpha,
            zeros: Zeros::Keep,
        });
        for b in 0..copies {
            for (c, a) in re {
                if *c != 0.0 {
                    kkt.add_triplets(a.entries().map(|(i, j, v)| (b * n + i, b * n + j, c * v)));
                }
            }
            for (i, j, v) in self.jacobian.entries() {
                kkt.add_constraint_entry(b * r + i, b * n + j, v);
            }
        }
        if complex {
            for (c, a) in im {
                if *c != 0.0 {
                    for (i, j, v) in a.entries() {
                        kkt.add(i, n + j, -c * v);
                        kkt.add(n + i, j, c * v);
                    }
                }
            }
        }
        kkt.factor().map_err(EigenError::Shift)
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
        // Whether the factorised KKT matrix is the complex (doubled) one.
        let complex = lu.dim() == 2 * (self.coordinates() + self.jacobian.nrows());
        let scale = if scale > 0.0 && scale.is_finite() {
            scale
        } else {
            1.0
        };
        let op = QuadraticShiftInvert {
            pencil: self.view(),
            lu,
            sigma: (sr, if complex { si } else { 0.0 }),
            scale,
        };
        let (op, available) = self.deflated(&op, 2);
        let ritz = largest_ritz_pairs(&op, available, wanted)?;
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
                let den = den.max(UNDERFLOW_FLOOR);
                let (lr, li) = (num_re / den, num_im / den);
                // Two eigenvalues with one ψ would give a mixed vector: v ≠ λx.
                let (mut miss, mut size) = (0.0, 0.0);
                for k in 0..n {
                    let dr = v_re[k] - (lr * x_re[k] - li * x_im[k]);
                    let di = v_im[k] - (lr * x_im[k] + li * x_re[k]);
                    miss += dr * dr + di * di;
                    size += v_re[k] * v_re[k] + v_im[k] * v_im[k];
                }
                if miss > MIXED_EIGENVECTOR * size.max(UNDERFLOW_FLOOR) {
                    return Err(EigenError::AmbiguousShift);
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
        let op = LinearShiftInvert {
            pencil: self.view(),
            lu,
        };
        let (op, available) = self.deflated(&op, 1);
        let ritz = largest_ritz_pairs(&op, available, wanted)?;
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
