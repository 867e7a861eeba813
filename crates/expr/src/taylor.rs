//! Truncated Taylor series in time: `f(t + h) ≈ c0 + c1·h + c2·h²`.
//!
//! Used by [`crate::evaluate_time_series`] and [`crate::evaluate_path_series`] to obtain f,
//! df/dt and d²f/dt² = 2·c2 exactly (to the order carried) for expressions of TIME and of
//! quantities whose series the environment supplies.

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Taylor {
    /// Coefficients of h⁰, h¹, h².
    pub c: [f64; 3],
}

/// `a · b` with an exact zero when either factor is zero (so that `0 · ∞ = 0`).
#[inline]
fn mul0(a: f64, b: f64) -> f64 {
    if a == 0.0 || b == 0.0 {
        0.0
    } else {
        a * b
    }
}

impl Taylor {
    pub fn constant(v: f64) -> Self {
        Taylor { c: [v, 0.0, 0.0] }
    }

    /// The independent variable itself at `t`.
    #[cfg(test)]
    pub fn variable(t: f64) -> Self {
        Taylor { c: [t, 1.0, 0.0] }
    }

    /// The series of a quantity with value `f`, rate `f'` and second derivative `f''`.
    pub fn from_derivatives([f, d1, d2]: [f64; 3]) -> Self {
        Taylor {
            c: [f, d1, 0.5 * d2],
        }
    }

    /// `[f, f', f'']`.
    pub fn derivatives(&self) -> [f64; 3] {
        [self.c[0], self.c[1], 2.0 * self.c[2]]
    }

    pub fn add(&self, o: &Self) -> Self {
        Taylor {
            c: [self.c[0] + o.c[0], self.c[1] + o.c[1], self.c[2] + o.c[2]],
        }
    }

    pub fn sub(&self, o: &Self) -> Self {
        Taylor {
            c: [self.c[0] - o.c[0], self.c[1] - o.c[1], self.c[2] - o.c[2]],
        }
    }

    pub fn scale(&self, k: f64) -> Self {
        Taylor {
            c: [self.c[0] * k, mul0(self.c[1], k), mul0(self.c[2], k)],
        }
    }

    pub fn mul(&self, o: &Self) -> Self {
        let [a0, a1, a2] = self.c;
        let [b0, b1, b2] = o.c;
        Taylor {
            c: [
                a0 * b0,
                mul0(a0, b1) + mul0(a1, b0),
                mul0(a0, b2) + mul0(a1, b1) + mul0(a2, b0),
            ],
        }
    }

    pub fn div(&self, o: &Self) -> Self {
        let [a0, a1, a2] = self.c;
        let [b0, b1, b2] = o.c;
        let q0 = a0 / b0;
        let q1 = (a1 - mul0(q0, b1)) / b0;
        let q2 = (a2 - mul0(q0, b2) - mul0(q1, b1)) / b0;
        Taylor { c: [q0, q1, q2] }
    }

    /// `g(self)`: with `x = a + b·h + c·h²`,
    /// `g(x) = g0 + g1·(b·h + c·h²) + ½·g2·b²·h² + O(h³)`.
    pub fn chain(&self, g0: f64, g1: f64, g2: f64) -> Self {
        let [_, b, c] = self.c;
        Taylor {
            c: [g0, mul0(g1, b), mul0(g1, c) + mul0(0.5 * g2, mul0(b, b))],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_and_quotient() {
        let t = Taylor::variable(2.0);
        // t² at 2: 4, 4, 2
        assert_eq!(t.mul(&t).derivatives(), [4.0, 4.0, 2.0]);
        // 1/t at 2: 0.5, -0.25, 0.25
        let r = Taylor::constant(1.0).div(&t).derivatives();
        assert!((r[0] - 0.5).abs() < 1e-15);
        assert!((r[1] + 0.25).abs() < 1e-15);
        assert!((r[2] - 0.25).abs() < 1e-15);
        // sin(t²) via chain
        let s = t.mul(&t);
        let v = s.c[0];
        let d = s.chain(v.sin(), v.cos(), -v.sin()).derivatives();
        // d/dt sin(t²) = 2t cos(t²); d² = 2cos(t²) - 4t² sin(t²)
        assert!((d[1] - 4.0 * v.cos()).abs() < 1e-12);
        assert!((d[2] - (2.0 * v.cos() - 16.0 * v.sin())).abs() < 1e-12);
    }
}
