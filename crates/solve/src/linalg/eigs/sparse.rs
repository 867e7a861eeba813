//! Sparse matrices in compressed rows: the blocks of the constrained pencil.

use super::EigenError;

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
