//! Free motions of single parts, found structurally and deflated before the Krylov iteration.
//!
//! A motion `z` of one part alone (its 6 coordinates, every other part still) with
//!
//! ```text
//! J z = 0,   K z = Kᵀ z = 0,   C z = Cᵀ z = 0
//! ```
//!
//! is a free motion without stiffness or damping: `ν = 0` of the undamped problem and a
//! double `λ = 0` (a 2 × 2 Jordan block) of the first-order one. The spin of a rod between two
//! spherical joints, a part hinged to ground with no spring, a free-floating part are such
//! motions. They are found part by part (the null space of a 6-column matrix: cost
//! `O(nnz(J + K + C))`), counted, and projected out of the shift-invert operator: in the mass
//! metric (`z̃ = Lᵀz`) the space they span and its orthogonal complement are both invariant
//! (`zᵀM T x = 0` whenever `zᵀM x = 0`, because `zᵀK = zᵀC = 0` and `J z = 0`), so the Krylov
//! iteration on the complement meets only the other eigenvalues. Without this, a chain of N
//! rods on spherical joints puts N zero eigenvalues first, which the iteration would have to
//! find one by one before the lowest swinging mode.
//!
//! Free motions that involve several parts (the rigid motion of a free-floating assembly) are
//! not found here; the Krylov iteration finds them as before.

use super::krylov::KrylovOperator;
use super::metric::{MassMetric, BLOCK};
use super::{EigenError, SparseMatrix};
use crate::tolerances::LOCAL_FREE_MOTION;
use faer::Mat;

/// The free motions of single parts, as orthonormal vectors in the mass metric, each
/// supported on one part's 6 coordinates.
#[derive(Clone, Debug, Default)]
pub struct LocalFreeMotions {
    /// `(first coordinate of the part, z̃ restricted to the part)`; orthonormal.
    vectors: Vec<(usize, [f64; BLOCK])>,
}

impl LocalFreeMotions {
    /// None: nothing is deflated.
    pub fn none() -> LocalFreeMotions {
        LocalFreeMotions::default()
    }

    /// The free motions of single parts of the pencil `(M, C, K, J)` (module docs), in the
    /// metric `metric`. None unless the metric is the block (per-part) one.
    pub(super) fn find(
        metric: &MassMetric,
        damping: &SparseMatrix,
        stiffness: &SparseMatrix,
        jacobian: &SparseMatrix,
    ) -> LocalFreeMotions {
        if metric.blocks.is_empty() {
            return LocalFreeMotions::none();
        }
        let parts = metric.blocks.len();
        // The scaled equations `A z = 0` restricted to each part's columns: J rows divided by
        // their norms, K and C by their largest entries.
        let mut row_norm = vec![0.0f64; jacobian.nrows()];
        for (r, _, v) in jacobian.entries() {
            row_norm[r] += v * v;
        }
        let mut restricted: Vec<(usize, usize, [f64; BLOCK])> = Vec::new();
        for (r, c, v) in jacobian.entries() {
            let s = row_norm[r].sqrt();
            if s > 0.0 {
                push_entry(&mut restricted, (0, r), c, v / s);
            }
        }
        for (key, a) in [(1, stiffness), (2, damping)] {
            let scale = a.max_abs();
            if scale == 0.0 {
                continue;
            }
            for (i, j, v) in a.entries() {
                // Row i of A z (column j in part j / 6) and row j of Aᵀ z (column i).
                push_entry(&mut restricted, (2 * key, i), j, v / scale);
                push_entry(&mut restricted, (2 * key + 1, j), i, v / scale);
            }
        }
        // Sum the pieces of one equation on one part; group the rows by part.
        restricted.sort_by_key(|&(e, p, _)| (p, e));
        let mut rows: Vec<Vec<[f64; BLOCK]>> = vec![Vec::new(); parts];
        let mut k = 0;
        while k < restricted.len() {
            let (e, p, mut row) = restricted[k];
            k += 1;
            while k < restricted.len() && restricted[k].0 == e && restricted[k].1 == p {
                for (x, y) in row.iter_mut().zip(&restricted[k].2) {
                    *x += y;
                }
                k += 1;
            }
            rows[p].push(row);
        }
        let mut vectors = Vec::new();
        for (p, a) in rows.iter().enumerate() {
            // Padded to 6 rows, so that the SVD's V spans every direction.
            let m = a.len().max(BLOCK);
            let mat = Mat::<f64>::from_fn(m, BLOCK, |i, j| a.get(i).map_or(0.0, |r| r[j]));
            let Ok(svd) = mat.svd() else {
                continue;
            };
            let (s, v) = (svd.S(), svd.V());
            let s = s.column_vector();
            let mut found: Vec<[f64; BLOCK]> = Vec::new();
            for c in 0..BLOCK {
                // ‖A z‖ ≤ LOCAL_FREE_MOTION for the unit z.
                if s[c] > LOCAL_FREE_MOTION {
                    continue;
                }
                let z: [f64; BLOCK] = std::array::from_fn(|i| v[(i, c)]);
                let mut zt = [0.0; BLOCK];
                metric.block_metric_of(p, &z, &mut zt);
                // Orthonormal in the metric among the part's own (other parts' are disjoint).
                for _ in 0..2 {
                    for q in &found {
                        let d: f64 = q.iter().zip(&zt).map(|(a, b)| a * b).sum();
                        zt.iter_mut().zip(q).for_each(|(x, y)| *x -= d * y);
                    }
                }
                let size = zt.iter().map(|x| x * x).sum::<f64>().sqrt();
                if size > 0.0 && size.is_finite() {
                    zt.iter_mut().for_each(|x| *x /= size);
                    found.push(zt);
                }
            }
            vectors.extend(found.into_iter().map(|v| (p * BLOCK, v)));
        }
        LocalFreeMotions { vectors }
    }

    /// Number of free motions found.
    pub fn count(&self) -> usize {
        self.vectors.len()
    }

    /// Removes the components along the free motions from each of the `copies` consecutive
    /// `n`-vectors of `x` (metric coordinates).
    fn project_out(&self, x: &mut [f64], n: usize, copies: usize) {
        for h in 0..copies {
            for (o, v) in &self.vectors {
                let seg = &mut x[h * n + o..h * n + o + BLOCK];
                let c: f64 = seg.iter().zip(v).map(|(a, b)| a * b).sum();
                seg.iter_mut().zip(v).for_each(|(a, b)| *a -= c * b);
            }
        }
    }
}

/// Adds `value` at column `col` (of part `col / 6`) to the restricted row of equation `eq`.
fn push_entry(
    out: &mut Vec<(usize, usize, [f64; BLOCK])>,
    eq: (usize, usize),
    col: usize,
    value: f64,
) {
    let mut row = [0.0; BLOCK];
    row[col % BLOCK] = value;
    // Equation ids: kind in the low bits, row above them.
    out.push((eq.1 * 8 + eq.0, col / BLOCK, row));
}

/// `P T P`, `P` the projection off the local free motions, on states of `copies` consecutive
/// metric vectors of `n` coordinates (1: positions; 2: the first-order state `(a·x̃, ṽ)`).
pub(super) struct Deflated<'a> {
    pub(super) op: &'a dyn KrylovOperator,
    pub(super) motions: &'a LocalFreeMotions,
    pub(super) coordinates: usize,
    pub(super) copies: usize,
}

impl KrylovOperator for Deflated<'_> {
    fn dim(&self) -> usize {
        self.op.dim()
    }

    fn apply(&self, x: &[f64], y: &mut [f64]) -> Result<(), EigenError> {
        let mut xp = x.to_vec();
        self.motions
            .project_out(&mut xp, self.coordinates, self.copies);
        self.op.apply(&xp, y)?;
        self.motions.project_out(y, self.coordinates, self.copies);
        Ok(())
    }
}
