//! INVAR4, INVAR5, INVAR8 and INVAR9 of a FLEX_BODY → its [`ModalInertia`] (in the modes
//! linkage integrates). Layouts [decided, as the rest of `super`'s table], with m modes:
//!
//! | name | size | meaning |
//! |---|---|---|
//! | `INVAR4` | 3 × m | column j: `Σ m_p s_p × Φ_pj + I_p Φ*_pj` (BCS) |
//! | `INVAR5` | 3m × m | rows 3k … 3k+2, column j: `Σ m_p Φ_pk × Φ_pj` |
//! | `INVAR8` | 3m × 3 | rows 3j … 3j+2: the 3 × 3 `Σ m_p [s_p]×[Φ_pj]×` |
//! | `INVAR9` | 3m² × 3 | rows 3(j·m + k) … +2: the 3 × 3 `Σ m_p [Φ_pj]×[Φ_pk]×` |
//!
//! An invariant switched off by `INVARIANTS` is zero; one switched on but not listed is zero
//! too, and a warning names it. In a principal basis `q = V·η` the mode indices transform
//! with V: `I4·V`, `Σ_j I8_j V_jl`, and `Σ_jk V_jl V_kn (·)_jk` for INVAR5 and INVAR9.

use super::{Ctx, Source};
use crate::controls::DenseMatrix;
use crate::flex_bodies::ModalInertia;
use glam::{DMat3, DVec3};
use std::ops::{Add, Mul};

/// Reads the invariants `switched` on (INVARIANTS 4, 5, 8, 9) for `m` modes; `basis` is the
/// principal basis (row-major m × m) when there is one. `None` after an error (a listed
/// matrix of the wrong size).
pub(super) fn modal_inertia(
    src: &Source,
    m: usize,
    basis: Option<&[f64]>,
    cx: &mut Ctx,
) -> Option<ModalInertia> {
    let on = &src.st.invariants;
    let mut missing = Vec::new();
    let mut read = |index: usize, name: &'static str, rows: usize, cols: usize, cx: &mut Ctx| {
        if !on[index] {
            return Some(None);
        }
        if src.find(name).is_none() {
            missing.push(name);
            return Some(None);
        }
        src.sized(name, rows, cols, cx).map(Some)
    };
    let i4 = read(3, "INVAR4", 3, m, cx)?;
    let i5 = read(4, "INVAR5", 3 * m, m, cx)?;
    let i8 = read(7, "INVAR8", 3 * m, 3, cx)?;
    let i9 = read(8, "INVAR9", 3 * m * m, 3, cx)?;
    if !missing.is_empty() {
        cx.warn(
            src.span(),
            format!(
                "{}: MATRICES has no {}: taken as zero in the inertia coupling of the rigid \
                 and modal coordinates",
                src.st.header.name,
                missing.join(", ")
            ),
        );
    }
    let column = |d: &DenseMatrix, row: usize, j: usize| {
        DVec3::new(d.get(row, j), d.get(row + 1, j), d.get(row + 2, j))
    };
    let block = |d: &DenseMatrix, row: usize| {
        DMat3::from_cols(column(d, row, 0), column(d, row, 1), column(d, row, 2))
    };
    let mut out = ModalInertia {
        i4: i4.map_or(Vec::new(), |d| (0..m).map(|j| column(&d, 0, j)).collect()),
        i5: i5.map_or(Vec::new(), |d| {
            (0..m)
                .map(|k| (0..m).map(|j| column(&d, 3 * k, j)).collect())
                .collect()
        }),
        i8: i8.map_or(Vec::new(), |d| (0..m).map(|j| block(&d, 3 * j)).collect()),
        i9: i9.map_or(Vec::new(), |d| {
            (0..m)
                .map(|j| (0..m).map(|k| block(&d, 3 * (j * m + k))).collect())
                .collect()
        }),
    };
    if let Some(v) = basis {
        out = in_basis(out, v, m);
    }
    Some(out)
}

/// The invariants of the modes `η` of `q = V·η` (`v` row-major m × m).
fn in_basis(i: ModalInertia, v: &[f64], m: usize) -> ModalInertia {
    ModalInertia {
        i4: single(&i.i4, v, m),
        i5: double(&i.i5, v, m),
        i8: single(&i.i8, v, m),
        i9: double(&i.i9, v, m),
    }
}

/// `x'_l = Σ_j x_j V_jl` (empty stays empty).
fn single<T>(x: &[T], v: &[f64], m: usize) -> Vec<T>
where
    T: Copy + Add<Output = T> + Mul<f64, Output = T>,
{
    if x.is_empty() {
        return Vec::new();
    }
    (0..m)
        .map(|l| (0..m).fold(x[0] * 0.0, |acc, j| acc + x[j] * v[j * m + l]))
        .collect()
}

/// `x'_ln = Σ_ab V_al V_bn x_ab` (empty stays empty).
fn double<T>(x: &[Vec<T>], v: &[f64], m: usize) -> Vec<Vec<T>>
where
    T: Copy + Add<Output = T> + Mul<f64, Output = T>,
{
    if x.is_empty() {
        return Vec::new();
    }
    (0..m)
        .map(|l| {
            (0..m)
                .map(|n| {
                    // Zero of T (glam's default matrix is the identity).
                    let mut s = x[0][0] * 0.0;
                    for (a, row) in x.iter().enumerate() {
                        for (b, e) in row.iter().enumerate() {
                            s = s + *e * (v[a * m + l] * v[b * m + n]);
                        }
                    }
                    s
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// In the basis that swaps two modes and scales one, every invariant follows.
    #[test]
    fn invariants_follow_the_principal_basis() {
        let a = DVec3::new(1.0, 2.0, 3.0);
        let b = DVec3::new(-1.0, 0.5, 0.0);
        let ma = DMat3::from_diagonal(a);
        let mb = DMat3::from_diagonal(b);
        let i = ModalInertia {
            i4: vec![a, b],
            i5: vec![vec![a, b], vec![-b, DVec3::ZERO]],
            i8: vec![ma, mb],
            i9: vec![vec![ma, mb], vec![mb, DMat3::ZERO]],
        };
        // q = V·η with q_0 = 2 η_1, q_1 = η_0.
        let v = [0.0, 2.0, 1.0, 0.0];
        let t = in_basis(i, &v, 2);
        assert_eq!(t.i4, vec![b, a * 2.0]);
        assert_eq!(t.i8, vec![mb, ma * 2.0]);
        // (η_0, η_1) ↔ (q_1, q_0 / 2): [l][n] = V_al V_bn x[a][b].
        assert_eq!(t.i5[0][0], DVec3::ZERO);
        assert_eq!(t.i5[0][1], -b * 2.0);
        assert_eq!(t.i5[1][0], b * 2.0);
        assert_eq!(t.i5[1][1], a * 4.0);
        assert_eq!(t.i9[1][1], ma * 4.0);
        assert_eq!(t.i9[0][1], mb * 2.0);
    }
}
