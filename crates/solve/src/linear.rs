//! Sparse linear solves (faer's sparse LU with partial pivoting).
//!
//! Analyses assemble their matrices as `(row, col, value)` triplets (duplicates summed) and
//! solve in place. A singular or ill-posed system is reported, never a panic or a silent NaN.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

/// A factorised square sparse matrix.
pub struct SparseLu {
    lu: Lu<usize, f64>,
    n: usize,
}

/// Why a linear solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearError {
    #[error("the matrix could not be factorised: {0}")]
    Factor(String),
    #[error("the matrix is singular (the solution is not finite)")]
    Singular,
}

impl SparseLu {
    /// Factorises the `n × n` matrix with the given entries.
    pub fn factor(n: usize, entries: &[(usize, usize, f64)]) -> Result<SparseLu, LinearError> {
        if entries
            .iter()
            .any(|(r, c, v)| *r >= n || *c >= n || !v.is_finite())
        {
            return Err(LinearError::Factor(
                "an entry is out of range or not finite".into(),
            ));
        }
        let trip: Vec<Triplet<usize, usize, f64>> = entries
            .iter()
            .map(|&(r, c, v)| Triplet::new(r, c, v))
            .collect();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip)
            .map_err(|e| LinearError::Factor(format!("{e:?}")))?;
        let lu = a
            .sp_lu()
            .map_err(|e| LinearError::Factor(format!("{e:?}")))?;
        Ok(SparseLu { lu, n })
    }

    /// Order of the matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solves `A x = b` in place (`b` becomes `x`).
    pub fn solve(&self, b: &mut [f64]) -> Result<(), LinearError> {
        if b.len() != self.n {
            return Err(LinearError::Factor(
                "right-hand side of the wrong length".into(),
            ));
        }
        let mut m = Mat::from_fn(self.n, 1, |i, _| b[i]);
        self.lu.solve_in_place(m.as_mut());
        for (i, x) in b.iter_mut().enumerate() {
            *x = m[(i, 0)];
        }
        if b.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(LinearError::Singular)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_kkt_system() {
        // [2 0 1; 0 2 1; 1 1 0] x = [1, 3, 2] → x = (0.5, 1.5, 0).
        let e = [
            (0, 0, 2.0),
            (1, 1, 2.0),
            (0, 2, 1.0),
            (2, 0, 1.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
        ];
        let lu = SparseLu::factor(3, &e).unwrap();
        let mut b = [1.0, 3.0, 2.0];
        lu.solve(&mut b).unwrap();
        assert!(
            (b[0] - 0.5).abs() < 1e-14 && (b[1] - 1.5).abs() < 1e-14 && b[2].abs() < 1e-14,
            "{b:?}"
        );
    }

    #[test]
    fn singular_matrix_is_an_error_not_a_panic() {
        let e = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0)];
        let r = SparseLu::factor(2, &e).and_then(|lu| lu.solve(&mut [1.0, 2.0]));
        assert!(r.is_err());
    }
}
