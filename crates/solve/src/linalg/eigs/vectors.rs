//! Small dense vector helpers of the Krylov iteration.

use crate::tolerances::ORTHONORMAL_DEPENDENT;

pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(super) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// SplitMix64: reproducible start vectors without a dependency.
pub(super) fn pseudo_random(seed: u64, out: &mut [f64]) {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03;
    for x in out.iter_mut() {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        *x = (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
    }
}

/// Orthonormalises the vectors (modified Gram–Schmidt, twice), dropping those that are
/// dependent on the ones before.
pub(super) fn orthonormal_columns(vs: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(vs.len());
    for mut v in vs {
        let before = norm(&v);
        if before == 0.0 {
            continue;
        }
        for _ in 0..2 {
            for q in &out {
                let c = dot(q, &v);
                for (vi, qi) in v.iter_mut().zip(q) {
                    *vi -= c * qi;
                }
            }
        }
        let after = norm(&v);
        if after > ORTHONORMAL_DEPENDENT * before {
            v.iter_mut().for_each(|x| *x /= after);
            out.push(v);
        }
    }
    out
}
