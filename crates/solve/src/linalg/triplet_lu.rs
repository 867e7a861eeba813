//! A sparse matrix assembled as `(row, col, value)` triplets and refactorised in place: the
//! triplet list, the column ordering and the symbolic analysis are kept while the assembly
//! repeats the same coordinates, so a refresh neither allocates nor orders again.
//!
//! Exactness: the values are summed in the order faer's triplet constructor sums duplicates
//! (entries bucketed by column in assembly order, then an unstable sort by `(row, col)` within
//! each column), and the pattern is exactly the assembly's coordinates. A refactorisation thus
//! gives, bit for bit, what [`crate::linalg::linear::SparseLu::factor`] of the same triplets
//! gives; when the coordinates change (an entry becomes exactly zero, a multiplier vanishes)
//! the order and the pattern are made afresh.

use crate::linalg::linear::{FixedPatternLu, LinearError};

/// A square sparse matrix given by triplets (see the module docs).
pub struct TripletLu {
    n: usize,
    /// The triplets of the current assembly (duplicates summed); capacity is kept.
    pub entries: Vec<(usize, usize, f64)>,
    /// The coordinates the summation order and the pattern were made for.
    coordinates: Vec<(usize, usize)>,
    /// Triplet positions in summation order.
    order: Vec<usize>,
    /// Start of each column's run in `order` (n + 1).
    column_start: Vec<usize>,
    /// The matrix on that pattern (`None` before the first factorisation).
    lu: Option<FixedPatternLu>,
}

impl TripletLu {
    /// An empty `n × n` matrix.
    pub fn new(n: usize) -> TripletLu {
        TripletLu {
            n,
            entries: Vec::new(),
            coordinates: Vec::new(),
            order: Vec::new(),
            column_start: vec![0; n + 1],
            lu: None,
        }
    }

    /// Forgets the entries (a new assembly follows).
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Whether the entries' coordinates are those the order and pattern were made for.
    fn same_coordinates(&self) -> bool {
        self.lu.is_some()
            && self.coordinates.len() == self.entries.len()
            && self
                .coordinates
                .iter()
                .zip(&self.entries)
                .all(|(&(r, c), &(i, j, _))| r == i && c == j)
    }

    /// The summation order and the pattern of the current entries' coordinates.
    fn plan(&mut self) -> Result<(), LinearError> {
        self.coordinates.clear();
        self.coordinates
            .extend(self.entries.iter().map(|&(i, j, _)| (i, j)));
        let start = &mut self.column_start;
        start.fill(0);
        for &(_, c) in &self.coordinates {
            start[c + 1] += 1;
        }
        for j in 0..self.n {
            start[j + 1] += start[j];
        }
        self.order.clear();
        self.order.resize(self.coordinates.len(), 0);
        let mut next = start.clone();
        for (k, &(_, c)) in self.coordinates.iter().enumerate() {
            self.order[next[c]] = k;
            next[c] += 1;
        }
        let coordinates = &self.coordinates;
        for w in start.windows(2) {
            self.order[w[0]..w[1]].sort_unstable_by_key(|&k| coordinates[k]);
        }
        self.lu = Some(FixedPatternLu::new(
            self.n,
            self.coordinates.iter().copied(),
        )?);
        Ok(())
    }

    /// Factorises the entries. Errors: an entry out of range or not finite, a singular matrix.
    pub fn factor(&mut self) -> Result<(), LinearError> {
        if self
            .entries
            .iter()
            .any(|&(r, c, v)| r >= self.n || c >= self.n || !v.is_finite())
        {
            return Err(LinearError::Factor(
                "an entry is out of range or not finite".into(),
            ));
        }
        if !self.same_coordinates() {
            self.plan()?;
        }
        let Some(lu) = self.lu.as_mut() else {
            return Err(LinearError::Factor("no pattern".into()));
        };
        lu.clear();
        for &k in &self.order {
            let (i, j, v) = self.entries[k];
            lu.add(i, j, v);
        }
        lu.factor()
    }

    /// Solves `A x = b` in place with the last factorisation (`b` becomes `x`).
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), LinearError> {
        match self.lu.as_mut() {
            Some(lu) => lu.solve_in_place(b),
            None => Err(LinearError::Factor("the matrix is not factorised".into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::linear::SparseLu;

    /// A KKT-like matrix with many duplicate contributions per entry.
    fn triplets(shift: f64) -> Vec<(usize, usize, f64)> {
        let mut e = Vec::new();
        for round in 0..5 {
            for i in 0..6 {
                e.push((i, i, 1.0 / (1.0 + i as f64 + round as f64) + shift));
                e.push((i, (i + 1) % 6, 0.1 * (round as f64 + 0.3) / 3.0));
                e.push(((i + 2) % 6, i, 0.7 / (round as f64 + 7.0)));
            }
        }
        e
    }

    #[test]
    fn refactorisations_match_a_fresh_factorisation_bit_for_bit() {
        let mut a = TripletLu::new(6);
        for shift in [0.0, 0.37, 1.1] {
            let e = triplets(shift);
            a.clear();
            a.entries.extend(&e);
            a.factor().expect("regular");
            let mut x = vec![1.0, -2.0, 3.0, 0.5, 0.25, -1.5];
            let mut y = x.clone();
            a.solve_in_place(&mut x).expect("solves");
            SparseLu::factor(6, &e)
                .and_then(|lu| lu.solve(&mut y))
                .expect("solves");
            assert_eq!(x, y);
        }
    }

    #[test]
    fn changed_coordinates_make_a_new_pattern() {
        let mut a = TripletLu::new(2);
        a.entries.extend([(0, 0, 2.0), (1, 1, 4.0)]);
        a.factor().expect("regular");
        a.clear();
        a.entries.extend([(0, 0, 2.0), (0, 1, 1.0), (1, 1, 4.0)]);
        a.factor().expect("regular");
        let mut x = vec![3.0, 4.0];
        a.solve_in_place(&mut x).expect("solves");
        assert_eq!(x, vec![1.0, 1.0]);
        a.clear();
        a.entries.push((0, 0, f64::NAN));
        assert!(a.factor().is_err());
    }
}
