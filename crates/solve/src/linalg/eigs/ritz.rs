//! Ritz pairs of the projected matrix `G = WᵀTW`, with the locked part kept apart.

use super::vectors::dot;
use super::EigenError;
use crate::tolerances::UNDERFLOW_FLOOR;
use faer::linalg::solvers::Solve;
use faer::Mat;

/// A Ritz value with `Im θ ≤ 0` and its unit coefficient vector in the basis.
pub(super) struct Ritz {
    pub(super) theta: (f64, f64),
    pub(super) y_re: Vec<f64>,
    pub(super) y_im: Vec<f64>,
}

/// A Ritz pair of the whole basis: unit coefficients `y` over all `m` basis vectors, and the
/// part `y_r` over the active (not locked) ones (empty for a locked pair).
pub(super) struct Pair {
    pub(super) theta: (f64, f64),
    pub(super) y_re: Vec<f64>,
    pub(super) y_im: Vec<f64>,
    pub(super) active_re: Vec<f64>,
    pub(super) active_im: Vec<f64>,
}

/// Ritz pairs with the first `locked` basis vectors spanning a converged invariant subspace:
/// the locked pairs are those of `G_LL`, the others those of `G_RR` (so their accuracy is not
/// limited by round-off at the scale of the larger locked `θ`), each completed to a Ritz vector
/// of the whole basis by `c` with `(G_LL − θ) c = −G_LR y_R`. Largest `|θ|` first.
pub(super) fn ritz_pairs(g: &[Vec<f64>], locked: usize) -> Result<Vec<Pair>, EigenError> {
    let m = g.len();
    let block = |rows: std::ops::Range<usize>, cols: std::ops::Range<usize>| -> Vec<Vec<f64>> {
        rows.map(|i| g[i][cols.clone()].to_vec()).collect()
    };
    let mut out = Vec::new();
    if locked > 0 {
        for r in rayleigh_ritz(&block(0..locked, 0..locked))? {
            let pad = |v: &[f64]| {
                let mut p = v.to_vec();
                p.resize(m, 0.0);
                p
            };
            out.push(Pair {
                theta: r.theta,
                y_re: pad(&r.y_re),
                y_im: pad(&r.y_im),
                active_re: Vec::new(),
                active_im: Vec::new(),
            });
        }
    }
    if locked < m {
        for r in rayleigh_ritz(&block(locked..m, locked..m))? {
            let (mut c_re, mut c_im) = (vec![0.0; locked], vec![0.0; locked]);
            if locked > 0 {
                // Real form of (G_LL − θ) c = b, b = −G_LR y_R:
                // [G_LL − θ_re, θ_im; −θ_im, G_LL − θ_re] [c_re; c_im] = [b_re; b_im].
                let (tr, ti) = r.theta;
                let a = Mat::<f64>::from_fn(2 * locked, 2 * locked, |i, j| {
                    let (bi, bj) = (i / locked, j / locked);
                    let (ii, jj) = (i % locked, j % locked);
                    let diag = if ii == jj { 1.0 } else { 0.0 };
                    match (bi, bj) {
                        (0, 0) | (1, 1) => g[ii][jj] - tr * diag,
                        (0, 1) => ti * diag,
                        _ => -ti * diag,
                    }
                });
                let mut b = Mat::<f64>::from_fn(2 * locked, 1, |i, _| {
                    let (part, row) = (i / locked, i % locked);
                    let y = if part == 0 { &r.y_re } else { &r.y_im };
                    -(locked..m).map(|j| g[row][j] * y[j - locked]).sum::<f64>()
                });
                a.partial_piv_lu().solve_in_place(b.as_mut());
                if (0..2 * locked).all(|i| b[(i, 0)].is_finite()) {
                    for i in 0..locked {
                        c_re[i] = b[(i, 0)];
                        c_im[i] = b[(locked + i, 0)];
                    }
                }
            }
            let mut y_re = c_re;
            y_re.extend_from_slice(&r.y_re);
            let mut y_im = c_im;
            y_im.extend_from_slice(&r.y_im);
            let nrm = (dot(&y_re, &y_re) + dot(&y_im, &y_im))
                .sqrt()
                .max(UNDERFLOW_FLOOR);
            y_re.iter_mut().for_each(|x| *x /= nrm);
            y_im.iter_mut().for_each(|x| *x /= nrm);
            out.push(Pair {
                theta: r.theta,
                y_re,
                y_im,
                active_re: r.y_re,
                active_im: r.y_im,
            });
        }
    }
    out.sort_by(|a, b| {
        let (ma, mb) = (a.theta.0.hypot(a.theta.1), b.theta.0.hypot(b.theta.1));
        mb.total_cmp(&ma)
    });
    Ok(out)
}

/// Eigen-decomposition of `G`: one entry per eigenvalue with `Im θ ≤ 0`, largest `|θ|` first.
pub(super) fn rayleigh_ritz(g: &[Vec<f64>]) -> Result<Vec<Ritz>, EigenError> {
    let m = g.len();
    if g.iter().flatten().any(|x| !x.is_finite()) {
        return Err(EigenError::NonFiniteProjection);
    }
    let gm = Mat::<f64>::from_fn(m, m, |i, j| g[i][j]);
    let eig = gm
        .eigen()
        .map_err(|e| EigenError::Projected(format!("{e:?}")))?;
    let (s, u) = (eig.S(), eig.U());
    let mut out: Vec<Ritz> = (0..m)
        .filter(|&i| s[i].im <= 0.0)
        .map(|i| {
            let mut y_re: Vec<f64> = (0..m).map(|r| u[(r, i)].re).collect();
            let mut y_im: Vec<f64> = (0..m).map(|r| u[(r, i)].im).collect();
            let nrm = (dot(&y_re, &y_re) + dot(&y_im, &y_im))
                .sqrt()
                .max(UNDERFLOW_FLOOR);
            y_re.iter_mut().for_each(|x| *x /= nrm);
            y_im.iter_mut().for_each(|x| *x /= nrm);
            Ritz {
                theta: (s[i].re, s[i].im),
                y_re,
                y_im,
            }
        })
        .collect();
    out.sort_by(|a, b| {
        let (ma, mb) = (a.theta.0.hypot(a.theta.1), b.theta.0.hypot(b.theta.1));
        mb.total_cmp(&ma)
    });
    Ok(out)
}
