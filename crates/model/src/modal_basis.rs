//! The principal basis of a flexible body's modes when its modal stiffness `K` (GENSTIFF) or
//! generalized mass `M` (INVAR6) is not diagonal.
//!
//! The modal coordinates of the dataset, `q`, and the principal coordinates `η` are related
//! by `q = V·η`, where `V` solves the symmetric-definite eigenproblem `K·V = M·V·Λ` with
//! `Vᵀ·M·V = 1`: in `η` the generalized mass is the identity and the stiffness the diagonal
//! `Λ = diag(ω_j²)`, so each principal coordinate is a mode of the body on its own. Every
//! quantity linear in the modes changes with the basis (`Φ' = Φ·V`, `I3' = I3·V`), the
//! kinetic and strain energies are unchanged, so the frequencies and motions are those of
//! the dataset's basis. `η = Vᵀ·M·q` (since `V⁻¹ = Vᵀ·M`).
//!
//! Method: Cholesky `M = L·Lᵀ`, the symmetric `C = L⁻¹·K·L⁻ᵀ` diagonalised by cyclic Jacobi
//! rotations (`C = W·Λ·Wᵀ`), `V = L⁻ᵀ·W`; columns in ascending `Λ`. O(m³) per sweep for m
//! modes, a handful of sweeps.

/// Why no principal basis exists.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BasisError {
    #[error(
        "{name} is not symmetric (entry ({row}, {column}) = {value}, its transpose {transpose})"
    )]
    NotSymmetric {
        name: &'static str,
        row: usize,
        column: usize,
        value: f64,
        transpose: f64,
    },
    #[error("INVAR6 (the generalized mass) is not positive definite")]
    MassNotPositive,
}

/// Relative asymmetry `|a_ij − a_ji|` (of the largest entry) that is an error.
const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// `m × m` row-major matrices `k` and `mass` → `(Λ, V)`, `V` row-major (`q_i = Σ_j V_ij η_j`).
pub fn principal_basis(
    k: &[f64],
    mass: &[f64],
    m: usize,
) -> Result<(Vec<f64>, Vec<f64>), BasisError> {
    symmetric(k, m, "GENSTIFF")?;
    symmetric(mass, m, "INVAR6")?;
    // Cholesky, lower triangular L (row-major).
    let mut l = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..=i {
            let s = mass[i * m + j] - (0..j).map(|p| l[i * m + p] * l[j * m + p]).sum::<f64>();
            if i == j {
                if s <= 0.0 || !s.is_finite() {
                    return Err(BasisError::MassNotPositive);
                }
                l[i * m + i] = s.sqrt();
            } else {
                l[i * m + j] = s / l[j * m + j];
            }
        }
    }
    // Y = L⁻¹·K (forward substitution per column), C = Y·L⁻ᵀ = L⁻¹·Yᵀ (K symmetric).
    let forward = |b: &[f64]| -> Vec<f64> {
        let mut y = vec![0.0; m * m];
        for c in 0..m {
            for i in 0..m {
                let s = b[i * m + c] - (0..i).map(|p| l[i * m + p] * y[p * m + c]).sum::<f64>();
                y[i * m + c] = s / l[i * m + i];
            }
        }
        y
    };
    let y = forward(k);
    let yt: Vec<f64> = (0..m * m).map(|x| y[(x % m) * m + x / m]).collect();
    let mut c = forward(&yt);
    // Symmetrise the rounding.
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (c[i * m + j] + c[j * m + i]);
            c[i * m + j] = v;
            c[j * m + i] = v;
        }
    }
    let (lambda, w) = jacobi(c, m);
    // V = L⁻ᵀ·W: back substitution with Lᵀ per column of W.
    let mut v = vec![0.0; m * m];
    for col in 0..m {
        for i in (0..m).rev() {
            let s = w[i * m + col]
                - (i + 1..m)
                    .map(|p| l[p * m + i] * v[p * m + col])
                    .sum::<f64>();
            v[i * m + col] = s / l[i * m + i];
        }
    }
    // Ascending eigenvalues.
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|a, b| lambda[*a].total_cmp(&lambda[*b]));
    let sorted_lambda = order.iter().map(|&j| lambda[j]).collect();
    let sorted_v = (0..m * m).map(|x| v[(x / m) * m + order[x % m]]).collect();
    Ok((sorted_lambda, sorted_v))
}

fn symmetric(a: &[f64], m: usize, name: &'static str) -> Result<(), BasisError> {
    let scale = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    for i in 0..m {
        for j in 0..i {
            let (x, y) = (a[i * m + j], a[j * m + i]);
            if (x - y).abs() > SYMMETRY_TOLERANCE * scale {
                return Err(BasisError::NotSymmetric {
                    name,
                    row: i + 1,
                    column: j + 1,
                    value: x,
                    transpose: y,
                });
            }
        }
    }
    Ok(())
}

/// Cyclic Jacobi on the symmetric `c` (row-major): eigenvalues and eigenvectors (columns).
fn jacobi(mut c: Vec<f64>, m: usize) -> (Vec<f64>, Vec<f64>) {
    let mut w = vec![0.0; m * m];
    for i in 0..m {
        w[i * m + i] = 1.0;
    }
    let norm = c.iter().map(|v| v * v).sum::<f64>().sqrt();
    for _sweep in 0..100 {
        let off: f64 = (0..m)
            .flat_map(|i| (0..m).filter(move |j| *j != i).map(move |j| (i, j)))
            .map(|(i, j)| c[i * m + j] * c[i * m + j])
            .sum::<f64>()
            .sqrt();
        if off <= 1e-15 * norm || off == 0.0 {
            break;
        }
        for p in 0..m {
            for q in p + 1..m {
                let apq = c[p * m + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (c[q * m + q] - c[p * m + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let cs = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * cs;
                // C ← Jᵀ C J with the rotation J in the (p, q) plane.
                for r in 0..m {
                    let (a, b) = (c[r * m + p], c[r * m + q]);
                    c[r * m + p] = cs * a - sn * b;
                    c[r * m + q] = sn * a + cs * b;
                }
                for r in 0..m {
                    let (a, b) = (c[p * m + r], c[q * m + r]);
                    c[p * m + r] = cs * a - sn * b;
                    c[q * m + r] = sn * a + cs * b;
                }
                for r in 0..m {
                    let (a, b) = (w[r * m + p], w[r * m + q]);
                    w[r * m + p] = cs * a - sn * b;
                    w[r * m + q] = sn * a + cs * b;
                }
            }
        }
    }
    ((0..m).map(|i| c[i * m + i]).collect(), w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_coupled_modes_give_their_eigenvalues_and_a_mass_orthonormal_basis() {
        // K = [[3, −1], [−1, 3]], M = [[2, 0], [0, 2]]: λ = 1 (V ∝ (1, 1)) and 2 (∝ (1, −1)).
        let (k, m) = ([3.0, -1.0, -1.0, 3.0], [2.0, 0.0, 0.0, 2.0]);
        let (lambda, v) = principal_basis(&k, &m, 2).unwrap();
        assert!((lambda[0] - 1.0).abs() < 1e-14 && (lambda[1] - 2.0).abs() < 1e-14);
        // Vᵀ M V = 1 and Vᵀ K V = Λ.
        for i in 0..2 {
            for j in 0..2 {
                let vmv: f64 = (0..2)
                    .flat_map(|a| (0..2).map(move |b| (a, b)))
                    .map(|(a, b)| v[a * 2 + i] * m[a * 2 + b] * v[b * 2 + j])
                    .sum();
                let vkv: f64 = (0..2)
                    .flat_map(|a| (0..2).map(move |b| (a, b)))
                    .map(|(a, b)| v[a * 2 + i] * k[a * 2 + b] * v[b * 2 + j])
                    .sum();
                let one = if i == j { 1.0 } else { 0.0 };
                assert!((vmv - one).abs() < 1e-14, "{vmv}");
                assert!((vkv - one * lambda[i]).abs() < 1e-14, "{vkv}");
            }
        }
        assert!((v[0] - v[2]).abs() < 1e-14, "first mode ∝ (1, 1): {v:?}");
    }

    #[test]
    fn asymmetric_or_indefinite_data_are_errors() {
        assert!(matches!(
            principal_basis(&[1.0, 0.5, 0.0, 1.0], &[1.0, 0.0, 0.0, 1.0], 2),
            Err(BasisError::NotSymmetric {
                name: "GENSTIFF",
                ..
            })
        ));
        assert_eq!(
            principal_basis(&[1.0, 0.0, 0.0, 1.0], &[1.0, 2.0, 2.0, 1.0], 2),
            Err(BasisError::MassNotPositive)
        );
    }
}
