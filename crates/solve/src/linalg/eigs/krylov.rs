//! The Krylov data of the Arnoldi iteration: the operator interface, what is wanted, the
//! converged pairs, and the basis with its frontier (expansion and restart).

use super::vectors::{dot, norm, orthonormal_columns};
use super::EigenError;
use crate::linalg::linear::LinearError;

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

/// Result of [`super::largest_ritz_pairs`].
#[derive(Clone, Debug, PartialEq)]
pub struct RitzPairs {
    /// Largest `|θ|` first.
    pub pairs: Vec<RitzPair>,
    /// Applications of `T` (sparse solves).
    pub applications: usize,
}

pub(super) use crate::tolerances::KRYLOV_BREAKDOWN as BREAKDOWN;
pub use crate::tolerances::RITZ_RESIDUAL as RESIDUAL_TOLERANCE;
use crate::tolerances::{RESTART_DIRECTION, RESTART_FRONTIER};
/// Smallest basis before a restart.
pub(super) const MIN_BASIS: usize = 40;
/// Basis size before a restart: `BASIS_PER_MODE · wanted + MIN_BASIS`.
pub(super) const BASIS_PER_MODE: usize = 6;
/// Steps taken after a fresh vector before the wanted pairs are judged again.
pub(super) const VALIDATION_STEPS: usize = 4;
/// Solve budget: `BASE_APPLICATIONS + APPLICATIONS_PER_MODE · wanted`.
pub(super) const BASE_APPLICATIONS: usize = 200;
pub(super) const APPLICATIONS_PER_MODE: usize = 40;

/// The Krylov data: an orthonormal basis `W` (m vectors), `Z = T W`, `G = Wᵀ Z` (row-major),
/// and the frontier: orthonormal `F` ⟂ W (s vectors) with `B = Fᵀ Z` (s × m), such that
/// `Z = W G + F B` up to round-off. The residual of a Ritz pair `(θ, y)`, `G y = θ y`, is then
/// `T W y − θ W y = F B y`: its norm `‖B y‖` comes without a cancellation-prone subtraction, and
/// new basis vectors are taken from `F` (for an unrestarted Arnoldi basis F is the single next
/// Arnoldi vector; restarts and fresh vectors make it a few).
pub(super) struct Basis {
    pub(super) w: Vec<Vec<f64>>,
    pub(super) z: Vec<Vec<f64>>,
    pub(super) g: Vec<Vec<f64>>,
    pub(super) f: Vec<Vec<f64>>,
    pub(super) b: Vec<Vec<f64>>,
}

impl Basis {
    pub(super) fn len(&self) -> usize {
        self.w.len()
    }

    /// Removes the components along `W` and `F` (classical Gram–Schmidt twice). Returns the
    /// coefficients on `W` and on `F` and the norms before and after.
    pub(super) fn project_out(&self, v: &mut [f64]) -> (Vec<f64>, Vec<f64>, f64, f64) {
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
    pub(super) fn add_frontier(&mut self, f: Vec<f64>, row: Vec<f64>) {
        self.f.push(f);
        self.b.push(row);
    }

    /// Moves the frontier direction `w = F a` (`a` a unit vector of length s) into the basis,
    /// applies `T` and updates `G`, `F`, `B`; the part of `T w` outside `W` and `F` becomes a new
    /// frontier vector unless it is round-off.
    pub(super) fn extend(&mut self, a: &[f64], op: &dyn KrylovOperator) -> Result<(), EigenError> {
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
    pub(super) fn restart(&mut self, q: &[Vec<f64>], scale: f64) {
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
            if size > RESTART_DIRECTION * scale {
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
        let keep: Vec<bool> = self
            .b
            .iter()
            .map(|row| norm(row) > RESTART_FRONTIER * scale)
            .collect();
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
    pub(super) fn combine(vs: &[Vec<f64>], y_re: &[f64], y_im: &[f64]) -> (Vec<f64>, Vec<f64>) {
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
    pub(super) fn residual(&self, y_re: &[f64], y_im: &[f64]) -> (Vec<f64>, Vec<f64>) {
        (
            self.b.iter().map(|row| dot(row, y_re)).collect(),
            self.b.iter().map(|row| dot(row, y_im)).collect(),
        )
    }
}
