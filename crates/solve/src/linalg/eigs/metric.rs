//! The mass metric of the Krylov spaces.

use super::SparseMatrix;

/// The metric of the Krylov spaces: coordinates `x̃ = Lᵀx` with `M = L Lᵀ` (Cholesky factors
/// of M's 6 × 6 diagonal blocks, one per part), so that Euclidean products of `x̃` are
/// kinetic-energy products of `x`. Then the undamped operator is symmetric and its eigenvectors
/// orthogonal: a basis vector orthogonal to the (dominant) zero modes carries none of them,
/// where with the Euclidean product it would carry enough to leave a round-off floor
/// `ε θ_max/θ` on the other residuals. The identity when M has another structure.
#[derive(Clone, Debug)]
pub(super) struct MassMetric {
    /// Row-major lower-triangular 6 × 6 factors; empty for the identity.
    pub(super) blocks: Vec<[f64; 36]>,
}

pub(super) const BLOCK: usize = 6;

impl MassMetric {
    pub(super) fn new(m: &SparseMatrix) -> MassMetric {
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
    pub(super) fn metric_of(&self, x: &[f64], out: &mut [f64]) {
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

    /// `out = Lᵀ z` for the 6 coordinates `z` of part `part` alone (block metric only).
    pub(super) fn block_metric_of(&self, part: usize, z: &[f64; BLOCK], out: &mut [f64; BLOCK]) {
        let l = &self.blocks[part];
        for (i, o) in out.iter_mut().enumerate() {
            *o = (i..BLOCK).map(|r| l[r * BLOCK + i] * z[r]).sum();
        }
    }

    /// `out = L⁻ᵀ x̃`.
    pub(super) fn unmetric(&self, xt: &[f64], out: &mut [f64]) {
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
    pub(super) fn weigh(&self, xt: &[f64], out: &mut [f64]) {
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
