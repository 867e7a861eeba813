//! Sparse linear solves (faer's sparse LU with partial pivoting).
//!
//! Two interfaces:
//!
//! * [`SparseLu::factor`]: one-off systems given as `(row, col, value)` triplets (duplicates
//!   summed); every call orders and factorises from scratch.
//! * [`FixedPatternLu`]: a matrix whose sparsity pattern is fixed (per topology) and whose
//!   values change, factorised many times (the integrator's iteration matrix). The column
//!   ordering (COLAMD) and the symbolic analysis are computed once per pattern; each
//!   refactorisation writes the values into preallocated storage and reuses the scratch
//!   memory, and solves work in the caller's buffer. Values are added by coordinates, in
//!   runs down a column: the first assembly finds each run's slots by binary search in the
//!   column's sorted row indices and logs them; later assemblies making the same calls replay
//!   the log (a precomputed map from contributions to slots), searching again only where the
//!   calls differ. No allocation once the log has its size. A nonzero value outside the
//!   pattern is kept aside and reported by [`FixedPatternLu::has_missing`];
//!   [`FixedPatternLu::grow`] then extends the pattern (a new symbolic analysis) and the
//!   caller assembles again.
//!
//! A singular or ill-posed system is reported, never a panic or a silent NaN.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat, Triplet};
use faer::{Conj, Mat, MatMut, Par};

use super::refactor::KeptPivotLu;

/// A factorised square sparse matrix.
pub struct SparseLu {
    lu: Lu<usize, f64>,
    n: usize,
}

/// Why a linear solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearError {
    /// An entry outside the `n × n` matrix, or one that is not finite.
    #[error("the matrix could not be factorised: an entry is out of range or not finite")]
    BadEntry,
    /// A pattern coordinate outside the matrix.
    #[error("the matrix could not be factorised: an entry is out of range")]
    OutOfRange,
    /// A value that is not finite.
    #[error("the matrix could not be factorised: an entry is not finite")]
    NotFinite,
    /// A right-hand side whose length is not the matrix order.
    #[error("the matrix could not be factorised: right-hand side of the wrong length")]
    RhsLength,
    /// The scratch memory could not be allocated.
    #[error("the matrix could not be factorised: out of memory")]
    OutOfMemory,
    /// A solve before a successful factorisation.
    #[error("the matrix could not be factorised: the matrix is not factorised")]
    NotFactorised,
    /// The sparse solver's own failure (its message).
    #[error("the matrix could not be factorised: {0}")]
    Factor(String),
    #[error("the matrix is singular (the solution is not finite)")]
    Singular,
}

/// faer's failures in words (never its debug text, `Generic(OutOfMemory)`).
fn faer_failure(e: faer::sparse::FaerError) -> LinearError {
    match e {
        faer::sparse::FaerError::OutOfMemory => LinearError::OutOfMemory,
        faer::sparse::FaerError::IndexOverflow => LinearError::Factor(
            "the matrix is too large for the sparse solver's indices".to_string(),
        ),
        #[allow(unreachable_patterns)]
        _ => LinearError::Factor("the sparse solver failed".to_string()),
    }
}

impl From<faer::sparse::linalg::LuError> for LinearError {
    fn from(e: faer::sparse::linalg::LuError) -> Self {
        match e {
            faer::sparse::linalg::LuError::SymbolicSingular { index } => LinearError::Factor(
                format!("the matrix is structurally singular (no pivot in column {index})"),
            ),
            faer::sparse::linalg::LuError::Generic(e) => faer_failure(e),
        }
    }
}

impl From<faer::sparse::CreationError> for LinearError {
    fn from(e: faer::sparse::CreationError) -> Self {
        match e {
            faer::sparse::CreationError::Generic(e) => faer_failure(e),
            faer::sparse::CreationError::OutOfBounds { .. } => LinearError::OutOfRange,
        }
    }
}

impl SparseLu {
    /// Factorises the `n × n` matrix with the given entries.
    pub fn factor(n: usize, entries: &[(usize, usize, f64)]) -> Result<SparseLu, LinearError> {
        if entries
            .iter()
            .any(|(r, c, v)| *r >= n || *c >= n || !v.is_finite())
        {
            return Err(LinearError::BadEntry);
        }
        let trip: Vec<Triplet<usize, usize, f64>> = entries
            .iter()
            .map(|&(r, c, v)| Triplet::new(r, c, v))
            .collect();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip)?;
        let lu = a.sp_lu()?;
        Ok(SparseLu { lu, n })
    }

    /// Order of the matrix.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solves `A x = b` in place (`b` becomes `x`).
    pub fn solve(&self, b: &mut [f64]) -> Result<(), LinearError> {
        if b.len() != self.n {
            return Err(LinearError::RhsLength);
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

/// A square sparse matrix with a fixed pattern, refactorised in place (see the module docs).
///
/// Cost: [`FixedPatternLu::new`] and [`FixedPatternLu::grow`] O(nnz log nnz) plus the
/// symbolic analysis; [`FixedPatternLu::add`] O(1) when replayed, O(log column length)
/// otherwise;
/// [`FixedPatternLu::factor`] the numeric LU only (Gilbert–Peierls with partial pivoting:
/// its L and U storage is reused and grows only when pivoting produces more fill than any
/// earlier factorisation); [`FixedPatternLu::solve_in_place`] two triangular solves.
pub struct FixedPatternLu {
    n: usize,
    /// Compressed columns: rows of column j are `row_idx[col_ptr[j]..col_ptr[j + 1]]`, sorted.
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    /// Whether `numeric` holds the factors of the current values.
    factored: bool,
    /// Nonzero contributions outside the pattern since the last [`FixedPatternLu::clear`].
    missing: Vec<(usize, usize)>,
    /// The slots the assembly met, in call order (the map from contributions to slots). For
    /// every run of `rows` entries of column `col` from row `row`: `row, col, rows`, then
    /// `CONSECUTIVE, slot` when they lie one after the other in the pattern, or `SCATTERED`
    /// and each entry's slot (`ABSENT` when it is outside the pattern). An assembly that
    /// repeats the same calls (the usual case: the same loops over the same model) replays
    /// the slots instead of searching them; where the calls diverge, the log is recorded
    /// afresh from there.
    slot_log: Vec<u32>,
    /// Position of the next call in `slot_log` since the last clear.
    cursor: usize,
    /// The factors with their pivot sequence kept across refactorisations
    /// ([`FixedPatternLu::keep_pivots`]); `None`: faer's factorisation with partial pivoting
    /// every time.
    kept: Option<KeptPivotLu>,
}

/// `slot_log` markers (see there).
const CONSECUTIVE: u32 = 0;
const SCATTERED: u32 = 1;
const ABSENT: u32 = u32::MAX;

/// Where the entries of a run are.
enum Run {
    /// From this slot on, one after the other.
    Consecutive(usize),
    /// Their slots (or `ABSENT`) are at this position of `slot_log`.
    Scattered(usize),
}

fn lu_error(e: faer::sparse::linalg::LuError) -> LinearError {
    match e {
        faer::sparse::linalg::LuError::SymbolicSingular { .. } => LinearError::Singular,
        other => LinearError::Factor(format!("{other:?}")),
    }
}

impl FixedPatternLu {
    /// The `n × n` pattern holding the given coordinates (duplicates merged), with every value
    /// zero. Errors: a coordinate out of range, or faer's symbolic analysis failing.
    pub fn new(
        n: usize,
        coordinates: impl IntoIterator<Item = (usize, usize)>,
    ) -> Result<FixedPatternLu, LinearError> {
        let mut coords: Vec<(usize, usize)> = coordinates.into_iter().collect();
        if coords.iter().any(|&(r, c)| r >= n || c >= n) {
            return Err(LinearError::OutOfRange);
        }
        // Column-major order.
        coords.sort_unstable_by_key(|&(r, c)| (c, r));
        coords.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(_, c) in &coords {
            col_ptr[c + 1] += 1;
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let row_idx: Vec<usize> = coords.iter().map(|&(r, _)| r).collect();
        let nnz = row_idx.len();
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic =
            factorize_symbolic_lu(pattern.as_ref(), Default::default()).map_err(faer_failure)?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|_| LinearError::OutOfMemory)?;
        let solve_scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
            .map_err(|_| LinearError::OutOfMemory)?;
        Ok(FixedPatternLu {
            n,
            pattern,
            values: vec![0.0; nnz],
            symbolic,
            numeric: NumericLu::new(),
            factor_scratch,
            solve_scratch,
            factored: false,
            missing: Vec::new(),
            slot_log: Vec::new(),
            cursor: 0,
            kept: None,
        })
    }

    /// From now on, refactorisations keep the pivot sequence of the last factorisation with
    /// partial pivoting while its pivots stay acceptable ([`KeptPivotLu`]: no pivot search and
    /// no symbolic work, several times faster for the integrator's iteration matrix); the
    /// setting survives [`FixedPatternLu::grow`].
    pub fn keep_pivots(&mut self) {
        if self.kept.is_none() {
            self.kept = Some(KeptPivotLu::new(self.n));
        }
    }

    /// Matrix dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// A matrix with the same pattern (and symbolic analysis), values zero.
    pub fn same_pattern(&self) -> Result<FixedPatternLu, LinearError> {
        let oom = |_| LinearError::OutOfMemory;
        Ok(FixedPatternLu {
            n: self.n,
            pattern: self.pattern.clone(),
            values: vec![0.0; self.values.len()],
            symbolic: self.symbolic.clone(),
            numeric: NumericLu::new(),
            factor_scratch: MemBuffer::try_new(
                self.symbolic
                    .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            )
            .map_err(oom)?,
            solve_scratch: MemBuffer::try_new(
                self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
            )
            .map_err(oom)?,
            factored: false,
            missing: Vec::new(),
            slot_log: Vec::new(),
            cursor: 0,
            kept: None,
        })
    }

    /// Sets every value to zero (the pattern stays) and forgets missing entries.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
        self.missing.clear();
        self.factored = false;
        self.cursor = 0;
    }

    /// Slot of `(row, col)` in the value array.
    #[inline]
    fn slot(&self, row: usize, col: usize) -> Option<usize> {
        if col >= self.n {
            return None;
        }
        let ptr = self.pattern.col_ptr();
        let (start, end) = (ptr[col], ptr[col + 1]);
        self.pattern.row_idx()[start..end]
            .binary_search(&row)
            .ok()
            .map(|k| start + k)
    }

    /// Where the `rows` entries of column `col` from row `row` are: replayed from the log when
    /// the call repeats the last assembly's, searched (and logged) otherwise. `None` when the
    /// indices do not fit the log (more than 2³² − 1 entries): the caller searches.
    #[inline]
    fn run(&mut self, row: usize, col: usize, rows: usize) -> Option<Run> {
        let key = [row, col, rows].map(|x| u32::try_from(x).ok().filter(|&x| x != ABSENT));
        let [Some(r), Some(c), Some(n)] = key else {
            return None;
        };
        let at = self.cursor;
        if let Some([lr, lc, ln, kind]) = self.slot_log.get(at..at + 4) {
            if [*lr, *lc, *ln] == [r, c, n] {
                return if *kind == CONSECUTIVE {
                    let k = self.slot_log[at + 4] as usize;
                    self.cursor = at + 5;
                    Some(Run::Consecutive(k))
                } else {
                    self.cursor = at + 4 + rows;
                    Some(Run::Scattered(at + 4))
                };
            }
        }
        // The calls diverge from the last assembly's: record them from here.
        self.slot_log.truncate(at);
        let slot32 = |k: usize| u32::try_from(k).ok().filter(|&k| k != ABSENT);
        let consecutive = self
            .slot(row, col)
            .filter(|&k| {
                rows > 0
                    && k + rows <= self.pattern.col_ptr()[col + 1]
                    && self.pattern.row_idx()[k + rows - 1] == row + rows - 1
            })
            .and_then(|k| slot32(k).map(|k32| (k, k32)));
        self.slot_log.extend([r, c, n]);
        Some(match consecutive {
            Some((k, k32)) => {
                self.slot_log.extend([CONSECUTIVE, k32]);
                self.cursor = at + 5;
                Run::Consecutive(k)
            }
            None => {
                self.slot_log.push(SCATTERED);
                for i in 0..rows {
                    let k = self.slot(row + i, col).and_then(slot32).unwrap_or(ABSENT);
                    self.slot_log.push(k);
                }
                self.cursor = at + 4 + rows;
                Run::Scattered(at + 4)
            }
        })
    }

    /// Adds `value` at `(row, col)`. A nonzero value outside the pattern is recorded (see
    /// [`FixedPatternLu::has_missing`]); a zero one is ignored.
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        self.add_block((row, col), (1, 1), 1.0, |_, _| value);
    }

    /// Adds the dense block `scale · value(i, j)`, `i < rows`, `j < cols`, at `(row0, col0)`:
    /// one slot per column when the block's rows are consecutive in the pattern. An entry
    /// outside the pattern is missing when `value(i, j)` is nonzero, whatever `scale` (so a
    /// block that happens to be scaled by zero still claims its place).
    #[inline]
    pub fn add_block(
        &mut self,
        (row0, col0): (usize, usize),
        (rows, cols): (usize, usize),
        scale: f64,
        value: impl Fn(usize, usize) -> f64,
    ) {
        for j in 0..cols {
            let col = col0 + j;
            match self.run(row0, col, rows) {
                Some(Run::Consecutive(k)) => {
                    for (i, x) in self.values[k..k + rows].iter_mut().enumerate() {
                        *x += scale * value(i, j);
                    }
                }
                Some(Run::Scattered(at)) => {
                    for i in 0..rows {
                        let v = value(i, j);
                        match self.slot_log[at + i] {
                            ABSENT if v != 0.0 => self.missing.push((row0 + i, col)),
                            ABSENT => {}
                            k => self.values[k as usize] += scale * v,
                        }
                    }
                }
                None => {
                    for i in 0..rows {
                        let v = value(i, j);
                        match self.slot(row0 + i, col) {
                            Some(k) => self.values[k] += scale * v,
                            None if v != 0.0 => self.missing.push((row0 + i, col)),
                            None => {}
                        }
                    }
                }
            }
        }
        self.factored = false;
    }

    /// Whether a nonzero value fell outside the pattern since the last clear.
    pub fn has_missing(&self) -> bool {
        !self.missing.is_empty()
    }

    /// Extends the pattern by the missing entries (a new symbolic analysis); values are
    /// cleared, so the caller assembles again.
    pub fn grow(&mut self) -> Result<(), LinearError> {
        let ptr = self.pattern.col_ptr();
        let rows = self.pattern.row_idx();
        let existing = (0..self.n).flat_map(|j| (ptr[j]..ptr[j + 1]).map(move |k| (rows[k], j)));
        let coords: Vec<(usize, usize)> = existing.chain(self.missing.iter().copied()).collect();
        let keep = self.kept.is_some();
        *self = FixedPatternLu::new(self.n, coords)?;
        if keep {
            self.keep_pivots();
        }
        Ok(())
    }

    /// Factorises the current values. Errors: a value that is not finite, a structurally or
    /// numerically singular matrix.
    pub fn factor(&mut self) -> Result<(), LinearError> {
        self.factored = false;
        if self.values.iter().any(|v| !v.is_finite()) {
            return Err(LinearError::NotFinite);
        }
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        if let Some(kept) = self.kept.as_mut() {
            kept.factor(a, self.symbolic.col_perm()).map_err(lu_error)?;
            self.factored = true;
            return Ok(());
        }
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                Par::Seq,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(lu_error)?;
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` in place with the last factorisation (`b` becomes `x`).
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), LinearError> {
        if !self.factored {
            return Err(LinearError::NotFactorised);
        }
        if b.len() != self.n {
            return Err(LinearError::RhsLength);
        }
        if let Some(kept) = self.kept.as_mut() {
            return if kept.solve_in_place(b) && b.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(LinearError::Singular)
            };
        }
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, self.n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
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
    fn the_sparse_solver_failures_are_words_not_debug_text() {
        let oom: LinearError =
            faer::sparse::linalg::LuError::Generic(faer::sparse::FaerError::OutOfMemory).into();
        assert_eq!(
            oom.to_string(),
            "the matrix could not be factorised: out of memory"
        );
        let singular: LinearError =
            faer::sparse::linalg::LuError::SymbolicSingular { index: 3 }.into();
        assert!(singular
            .to_string()
            .contains("structurally singular (no pivot in column 3)"));
        for e in [oom, singular] {
            assert!(!format!("{e}").contains("Generic"), "{e}");
        }
    }

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

    /// The 3 × 3 KKT matrix of `solves_a_small_kkt_system` with its (1,1) entry `d`.
    fn kkt(d: f64) -> Vec<(usize, usize, f64)> {
        vec![
            (0, 0, d),
            (1, 1, 2.0),
            (0, 2, 1.0),
            (2, 0, 1.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
        ]
    }

    #[test]
    fn refactorising_a_fixed_pattern_matches_a_fresh_factorisation() {
        let mut lu = FixedPatternLu::new(3, kkt(1.0).iter().map(|&(r, c, _)| (r, c))).unwrap();
        assert_eq!((lu.dim(), lu.nnz()), (3, 6));
        for d in [2.0, 5.0, -3.0] {
            lu.clear();
            for (r, c, v) in kkt(d) {
                lu.add(r, c, v);
            }
            assert!(!lu.has_missing());
            lu.factor().unwrap();
            let mut x = [1.0, 3.0, 2.0];
            lu.solve_in_place(&mut x).unwrap();
            let mut y = [1.0, 3.0, 2.0];
            SparseLu::factor(3, &kkt(d)).unwrap().solve(&mut y).unwrap();
            for i in 0..3 {
                assert!((x[i] - y[i]).abs() < 1e-14, "d = {d}: {x:?} vs {y:?}");
            }
        }
        // d = 2: x = (0.5, 1.5, 0) exactly as in the triplet test.
        lu.clear();
        for (r, c, v) in kkt(2.0) {
            lu.add(r, c, v);
        }
        lu.factor().unwrap();
        let mut x = [1.0, 3.0, 2.0];
        lu.solve_in_place(&mut x).unwrap();
        assert!((x[0] - 0.5).abs() < 1e-14 && (x[1] - 1.5).abs() < 1e-14 && x[2].abs() < 1e-14);
    }

    #[test]
    fn a_value_outside_the_pattern_is_reported_and_the_pattern_grows() {
        // Pattern without (0, 2): that entry is missing until the pattern grows.
        let mut lu = FixedPatternLu::new(
            3,
            kkt(2.0)
                .iter()
                .map(|&(r, c, _)| (r, c))
                .filter(|&rc| rc != (0, 2)),
        )
        .unwrap();
        lu.add(1, 0, 0.0); // a zero outside the pattern is not a missing entry
        assert!(!lu.has_missing());
        for (r, c, v) in kkt(2.0) {
            lu.add(r, c, v);
        }
        assert!(lu.has_missing());
        lu.grow().unwrap();
        assert_eq!(lu.nnz(), 6);
        for (r, c, v) in kkt(2.0) {
            lu.add(r, c, v);
        }
        assert!(!lu.has_missing());
        lu.factor().unwrap();
        let mut x = [1.0, 3.0, 2.0];
        lu.solve_in_place(&mut x).unwrap();
        assert!((x[0] - 0.5).abs() < 1e-14 && (x[1] - 1.5).abs() < 1e-14 && x[2].abs() < 1e-14);
    }

    #[test]
    fn dense_blocks_land_on_their_entries() {
        // Full 2 × 2 block at (1, 1) plus a diagonal entry at (0, 0); a block whose rows are
        // not all in the pattern goes entry by entry.
        let coords = [(0, 0), (1, 1), (2, 1), (1, 2), (2, 2)];
        let mut lu = FixedPatternLu::new(3, coords).unwrap();
        lu.add(0, 0, 4.0);
        lu.add_block((1, 1), (2, 2), 1.0, |i, j| if i == j { 3.0 } else { 1.0 });
        lu.add_block((0, 0), (2, 1), 1.0, |i, _| if i == 0 { 1.0 } else { 0.0 });
        assert!(!lu.has_missing());
        // Scaled by zero, a nonzero block outside the pattern still claims its place.
        lu.add_block((0, 1), (1, 2), 0.0, |_, _| 1.0);
        assert!(lu.has_missing());
        lu.missing.clear();
        lu.factor().unwrap();
        // [5 0 0; 0 3 1; 0 1 3] x = [5, 4, 4] → x = (1, 1, 1).
        let mut x = [5.0, 4.0, 4.0];
        lu.solve_in_place(&mut x).unwrap();
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-14), "{x:?}");
        let mut twin = lu.same_pattern().unwrap();
        assert_eq!(twin.nnz(), lu.nnz());
        assert!(twin.solve_in_place(&mut x).is_err(), "not factorised yet");
    }

    #[test]
    fn assemblies_in_another_order_replay_what_matches_and_search_the_rest() {
        let coords = [(0, 0), (1, 0), (2, 0), (1, 1), (2, 2), (0, 2)];
        let mut lu = FixedPatternLu::new(3, coords).unwrap();
        // [2 0 1; 1 3 0; 1 0 4] x = [3, 4, 5] → x = (1, 1, 1).
        let fill_a = |lu: &mut FixedPatternLu| {
            lu.add_block((0, 0), (3, 1), 1.0, |i, _| [2.0, 1.0, 1.0][i]);
            lu.add(1, 1, 3.0);
            lu.add(0, 2, 1.0);
            lu.add(2, 2, 4.0);
        };
        let fill_b = |lu: &mut FixedPatternLu| {
            lu.add(2, 2, 4.0);
            lu.add_block((0, 0), (2, 1), 1.0, |i, _| [2.0, 1.0][i]);
            lu.add(2, 0, 1.0);
            lu.add(1, 1, 1.0);
            lu.add(0, 2, 1.0);
            lu.add(1, 1, 2.0);
        };
        for fill in [
            &fill_a as &dyn Fn(&mut FixedPatternLu),
            &fill_a,
            &fill_b,
            &fill_b,
            &fill_a,
        ] {
            lu.clear();
            fill(&mut lu);
            assert!(!lu.has_missing());
            lu.factor().unwrap();
            let mut x = [3.0, 4.0, 5.0];
            lu.solve_in_place(&mut x).unwrap();
            assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-14), "{x:?}");
        }
    }

    #[test]
    fn a_singular_fixed_pattern_matrix_is_an_error_not_a_panic() {
        let e = [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0)];
        let mut lu = FixedPatternLu::new(2, e.iter().map(|&(r, c, _)| (r, c))).unwrap();
        for (r, c, v) in e {
            lu.add(r, c, v);
        }
        let r = lu.factor().and_then(|_| lu.solve_in_place(&mut [1.0, 2.0]));
        assert!(r.is_err());
        lu.clear();
        lu.add(0, 0, f64::NAN);
        assert!(lu.factor().is_err());
        assert!(FixedPatternLu::new(2, [(0, 2)]).is_err());
    }
}
