//! The shift-invert operators the Arnoldi iteration applies (one sparse KKT solve each).

use super::krylov::KrylovOperator;
use super::metric::MassMetric;
use super::{EigenError, SparseMatrix};
use crate::linalg::linear::SparseLu;

/// What the operators read of the pencil: `n` coordinates, `r` constraint rows, the mass
/// metric and the damping matrix.
pub(super) struct PencilView<'a> {
    pub(super) coordinates: usize,
    pub(super) constraints: usize,
    pub(super) metric: &'a MassMetric,
    pub(super) damping: &'a SparseMatrix,
}

/// `T = (A − σB)⁻¹B` (real `σ`) or `Re (A − σB)⁻¹B` (complex `σ`) on the balanced state
/// `(a·x, v)`, `a = scale` (see [`super::ConstrainedPencil::nearest`]).
pub(super) struct QuadraticShiftInvert<'a> {
    pub(super) pencil: PencilView<'a>,
    pub(super) lu: SparseLu,
    pub(super) sigma: (f64, f64),
    pub(super) scale: f64,
}

impl KrylovOperator for QuadraticShiftInvert<'_> {
    fn dim(&self) -> usize {
        2 * self.pencil.coordinates
    }

    /// `(a x̃₀, ṽ₀) ↦ (a Lᵀx, Lᵀ Re v)` with x from the KKT solve and `v = x₀ + σx`.
    fn apply(&self, w: &[f64], out: &mut [f64]) -> Result<(), EigenError> {
        let n = self.pencil.coordinates;
        let r = self.pencil.constraints;
        let (sr, si) = self.sigma;
        let a = self.scale;
        let metric = self.pencil.metric;
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
pub(super) struct LinearShiftInvert<'a> {
    pub(super) pencil: PencilView<'a>,
    pub(super) lu: SparseLu,
}

impl KrylovOperator for LinearShiftInvert<'_> {
    fn dim(&self) -> usize {
        self.pencil.coordinates
    }

    /// `x̃ ↦ Lᵀ y`, `(K̂ − τM) y + Jᵀμ = L x̃` (`= M x`).
    fn apply(&self, xt: &[f64], out: &mut [f64]) -> Result<(), EigenError> {
        let n = self.pencil.coordinates;
        let mut rhs = vec![0.0; n + self.pencil.constraints];
        self.pencil.metric.weigh(xt, &mut rhs[..n]);
        self.lu.solve(&mut rhs).map_err(EigenError::Shift)?;
        self.pencil.metric.metric_of(&rhs[..n], out);
        Ok(())
    }
}
