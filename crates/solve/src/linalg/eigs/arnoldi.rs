//! Arnoldi with explicit Rayleigh–Ritz, locking and thick restarts (see the module
//! documentation of [`super`]).

use super::krylov::*;
use super::ritz::{ritz_pairs, Pair};
use super::vectors::{dot, norm, orthonormal_columns, pseudo_random};
use super::EigenError;
use crate::tolerances::UNDERFLOW_FLOOR;
use crate::tolerances::VALIDATION_AGREEMENT;

/// How a check of the wanted pairs came out.
enum Check {
    /// The wanted pairs (the first `k`) have converged.
    Converged(usize),
    /// The first `k` pairs have converged and are all there is.
    Complete(usize),
    /// More Krylov steps are needed.
    More,
}

/// The Ritz pairs of `op` with the largest `|θ|` (see the module documentation), `available`
/// being the dimension of the space `op` acts on (its rank). Returns fewer pairs than wanted
/// only when the whole space has been spanned.
pub fn largest_ritz_pairs(
    op: &dyn KrylovOperator,
    available: usize,
    wanted: Wanted,
) -> Result<RitzPairs, EigenError> {
    let n = op.dim();
    let available = available.min(n);
    let mut applications = 0usize;
    if available == 0 || wanted.count == 0 {
        return Ok(RitzPairs {
            pairs: Vec::new(),
            applications,
        });
    }
    let mut basis = Basis {
        w: Vec::new(),
        z: Vec::new(),
        g: Vec::new(),
        f: Vec::new(),
        b: Vec::new(),
    };
    let mut target = wanted.count;
    let mut seed = 0u64;
    // Frontier direction to expand next (set by a check: the residual of the first unconverged
    // wanted pair); otherwise the newest frontier vector (the Arnoldi continuation).
    let mut prefer: Option<Vec<f64>> = None;
    let mut fresh = false;
    // Frontier directions still to expand in a validation round.
    let mut sweep = 0usize;
    let mut check_at = 0usize;
    let mut accepted: Option<Vec<f64>> = None;
    // The first `locked` basis vectors span converged pairs (an invariant subspace).
    let mut locked = 0usize;
    let mut scale = 0.0f64;
    loop {
        // Grow the basis by one vector.
        let mut spanned = basis.len() >= n;
        if basis.f.is_empty() {
            sweep = 0;
        }
        if !spanned {
            if sweep == 0 && (basis.f.is_empty() || fresh) {
                // A fresh direction: T applied to a random vector orthogonal to the basis and
                // the frontier (so that T does not amplify what they already hold).
                fresh = false;
                let mut found = false;
                for _ in 0..3 {
                    seed += 1;
                    let mut raw = vec![0.0; n];
                    pseudo_random(seed, &mut raw);
                    basis.project_out(&mut raw);
                    let mut v = vec![0.0; n];
                    op.apply(&raw, &mut v)?;
                    applications += 1;
                    let (_, _, before, after) = basis.project_out(&mut v);
                    if after > BREAKDOWN * before && after > 0.0 && v.iter().all(|x| x.is_finite())
                    {
                        v.iter_mut().for_each(|x| *x /= after);
                        // v ⟂ W, F, and every z_j lies in their span: a zero row of B.
                        basis.add_frontier(v, vec![0.0; basis.len()]);
                        found = true;
                        break;
                    }
                }
                if found {
                    prefer = None;
                } else if basis.f.is_empty() {
                    spanned = true;
                }
            }
            if !spanned {
                let s = basis.f.len();
                let a = if sweep > 0 {
                    // Validation: the oldest frontier direction.
                    sweep -= 1;
                    let mut e = vec![0.0; s];
                    e[0] = 1.0;
                    e
                } else {
                    match prefer.take() {
                        Some(mut a) if a.len() <= s && norm(&a) > 0.0 => {
                            a.resize(s, 0.0);
                            let size = norm(&a);
                            a.iter_mut().for_each(|x| *x /= size);
                            a
                        }
                        _ => {
                            let mut e = vec![0.0; s];
                            e[s - 1] = 1.0;
                            e
                        }
                    }
                };
                basis.extend(&a, op)?;
                applications += 1;
            }
            spanned |= basis.len() >= n;
        }
        let m = basis.len();
        let max_basis = n.min(MIN_BASIS.max(BASIS_PER_MODE * target + MIN_BASIS));
        if !spanned
            && (!basis.f.is_empty() || fresh)
            && m < check_at
            && m < max_basis
            && m != available
        {
            continue;
        }
        check_at = m + 1.max(m / 8);

        // Rayleigh–Ritz; residuals ‖B y‖ / |θ|.
        let ritz = ritz_pairs(&basis.g, locked)?;
        scale = ritz
            .first()
            .map_or(scale, |r| scale.max(r.theta.0.hypot(r.theta.1)));
        let residual = |r: &Pair| {
            let (dr, di) = basis.residual(&r.y_re, &r.y_im);
            (dot(&dr, &dr) + dot(&di, &di)).sqrt() / r.theta.0.hypot(r.theta.1).max(UNDERFLOW_FLOOR)
        };
        let residuals: Vec<f64> = ritz.iter().map(residual).collect();
        // At most `available` eigenvalues exist (round-off outside the space adds θ ≈ 0).
        let mut cap = 0;
        let mut total = 0;
        for r in &ritz {
            let k = if r.theta.1 == 0.0 { 1 } else { 2 };
            if total + k > available {
                break;
            }
            total += k;
            cap += 1;
        }
        let check = loop {
            let k = target.min(cap);
            if let Some(i) = (0..k).find(|&i| residuals[i] > RESIDUAL_TOLERANCE) {
                // Expand along this pair's residual next (the Arnoldi direction when F is one
                // vector).
                let (dr, di) = basis.residual(&ritz[i].y_re, &ritz[i].y_im);
                prefer = Some(if norm(&dr) >= norm(&di) { dr } else { di });
                break Check::More;
            }
            if k == 0 {
                break Check::More;
            }
            let found: usize = ritz[..k]
                .iter()
                .map(|r| if r.theta.1 == 0.0 { 1 } else { 2 })
                .sum();
            if found >= available {
                break Check::Complete(k);
            }
            if k < target || k == cap {
                break if spanned {
                    Check::Complete(k)
                } else {
                    Check::More
                };
            }
            let last = &ritz[k - 1];
            let covered = wanted
                .beyond
                .is_none_or(|b| last.theta.0.hypot(last.theta.1) < b);
            if covered {
                break Check::Converged(k);
            }
            target += 1;
        };
        let finish = |k: usize| {
            let pairs = ritz[..k]
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let (re, im) = Basis::combine(&basis.w, &r.y_re, &r.y_im);
                    RitzPair {
                        theta: r.theta,
                        re,
                        im,
                        residual: residuals[i],
                    }
                })
                .collect();
            RitzPairs {
                pairs,
                applications,
            }
        };
        let converged = residuals
            .iter()
            .take_while(|&&r| r <= RESIDUAL_TOLERANCE)
            .count();
        match check {
            Check::Complete(k) => return Ok(finish(k)),
            Check::Converged(k) => {
                let signature: Vec<f64> = ritz[..k]
                    .iter()
                    .map(|r| r.theta.0.hypot(r.theta.1))
                    .collect();
                let same = accepted.as_ref().is_some_and(|a| {
                    a.len() == signature.len()
                        && a.iter()
                            .zip(&signature)
                            .all(|(x, y)| (x - y).abs() <= VALIDATION_AGREEMENT * x.abs())
                });
                if same {
                    return Ok(finish(k));
                }
                // Validation round: expand every frontier direction (residual space not yet
                // explored), then a fresh one.
                accepted = Some(signature);
                sweep = basis.f.len();
                fresh = true;
                check_at = m + sweep + VALIDATION_STEPS;
            }
            Check::More if spanned => {
                return Err(EigenError::NotConverged {
                    converged,
                    wanted: target,
                    applications,
                });
            }
            Check::More => {}
        }
        if applications > BASE_APPLICATIONS + APPLICATIONS_PER_MODE * target {
            return Err(EigenError::NotConverged {
                converged,
                wanted: target,
                applications,
            });
        }
        // Lock the leading converged active pairs: a change of basis within span W (no
        // solves) that puts an orthonormal basis of their invariant subspace first.
        let lock: Vec<usize> = ritz
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.active_re.is_empty())
            .map_while(|(i, _)| (residuals[i] <= RESIDUAL_TOLERANCE).then_some(i))
            .collect();
        if !lock.is_empty() {
            let active = m - locked;
            let mut cols: Vec<Vec<f64>> = lock
                .iter()
                .flat_map(|&i| [ritz[i].active_re.clone(), ritz[i].active_im.clone()])
                .collect();
            let dims = orthonormal_columns(cols.clone()).len();
            cols.extend((0..active).map(|i| {
                let mut e = vec![0.0; active];
                e[i] = 1.0;
                e
            }));
            let q_active = orthonormal_columns(cols);
            if q_active.len() == active {
                let q: Vec<Vec<f64>> = (0..locked)
                    .map(|i| {
                        let mut e = vec![0.0; m];
                        e[i] = 1.0;
                        e
                    })
                    .chain(q_active.into_iter().map(|c| {
                        let mut e = vec![0.0; locked];
                        e.extend(c);
                        e
                    }))
                    .collect();
                basis.restart(&q, scale);
                locked += dims;
                // The preferred direction is in frontier coordinates, which a square change of
                // basis leaves alone.
            }
        }
        let m = basis.len();
        if m >= max_basis {
            // Thick restart on the locked vectors, the wanted Ritz vectors and some more.
            let ritz = ritz_pairs(&basis.g, locked)?;
            let keep = ritz.len().min(target + 2.max(target / 2));
            let embed = |v: &[f64]| {
                let mut e = vec![0.0; locked];
                e.extend_from_slice(v);
                e
            };
            let cols = (0..locked)
                .map(|i| {
                    let mut e = vec![0.0; m];
                    e[i] = 1.0;
                    e
                })
                .chain(
                    ritz[..keep]
                        .iter()
                        .filter(|r| !r.active_re.is_empty())
                        .flat_map(|r| [embed(&r.active_re), embed(&r.active_im)]),
                )
                .collect();
            let q = orthonormal_columns(cols);
            basis.restart(&q, scale);
            check_at = basis.len() + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal operator with the given eigenvalues.
    struct Diagonal(Vec<f64>);

    impl KrylovOperator for Diagonal {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn apply(&self, x: &[f64], y: &mut [f64]) -> Result<(), EigenError> {
            for ((yi, xi), d) in y.iter_mut().zip(x).zip(&self.0) {
                *yi = d * xi;
            }
            Ok(())
        }
    }

    #[test]
    fn arnoldi_finds_the_largest_eigenvalues_of_a_diagonal_operator() {
        let d: Vec<f64> = (1..=300).map(|k| 1.0 / k as f64).collect();
        let r = largest_ritz_pairs(
            &Diagonal(d),
            300,
            Wanted {
                count: 5,
                beyond: None,
            },
        )
        .unwrap();
        let got: Vec<f64> = r.pairs.iter().map(|p| p.theta.0).collect();
        for (k, g) in got.iter().enumerate() {
            let want = 1.0 / (k + 1) as f64;
            assert!((g - want).abs() < 1e-10 * want, "{got:?}");
        }
        assert!(r.applications < 150, "{}", r.applications);
    }

    #[test]
    fn a_repeated_eigenvalue_is_found_with_its_multiplicity() {
        // θ = 1 three times: one Krylov sequence sees one copy; fresh vectors find the others.
        let mut d: Vec<f64> = (1..=200).map(|k| 0.5 / k as f64).collect();
        d[7] = 1.0;
        d[50] = 1.0;
        d[120] = 1.0;
        let r = largest_ritz_pairs(
            &Diagonal(d),
            200,
            Wanted {
                count: 1,
                beyond: Some(0.9),
            },
        )
        .unwrap();
        let ones = r
            .pairs
            .iter()
            .filter(|p| (p.theta.0 - 1.0).abs() < 1e-10)
            .count();
        assert_eq!(
            ones,
            3,
            "{:?}",
            r.pairs.iter().map(|p| p.theta).collect::<Vec<_>>()
        );
        assert!((r.pairs[3].theta.0 - 0.5).abs() < 1e-10);
    }

    #[test]
    fn a_small_space_is_spanned_exactly() {
        let r = largest_ritz_pairs(
            &Diagonal(vec![3.0, -2.0]),
            2,
            Wanted {
                count: 10,
                beyond: None,
            },
        )
        .unwrap();
        let got: Vec<f64> = r.pairs.iter().map(|p| p.theta.0).collect();
        assert_eq!(got.len(), 2);
        assert!((got[0] - 3.0).abs() < 1e-14 && (got[1] + 2.0).abs() < 1e-14);
    }
}
