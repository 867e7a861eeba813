//! Spline data and interpolation for `AKISPL` (Akima) and `CUBSPL` (natural cubic spline).
//!
//! Both methods produce a piecewise cubic `s(x) = a + b·u + c·u² + d·u³`, `u = x − x_i` on
//! `[x_i, x_{i+1}]`, through every data point.
//!
//! * **Akima** (AKISPL): with interval slopes `m_i = (y_{i+1} − y_i)/(x_{i+1} − x_i)`, extended at
//!   each end by two slopes `m_{-1} = 2m_0 − m_1`, `m_{-2} = 2m_{-1} − m_0` (and symmetrically at the
//!   right end), the slope at node `i` is
//!   `t_i = (|m_{i+1} − m_i|·m_{i−1} + |m_{i−1} − m_{i−2}|·m_i) / (|m_{i+1} − m_i| + |m_{i−1} − m_{i−2}|)`,
//!   or `(m_{i−1} + m_i)/2` when both weights are zero. Each interval is the cubic Hermite
//!   interpolant of `(y_i, t_i)`, `(y_{i+1}, t_{i+1})`. Continuous first derivative.
//! * **Cubic** (CUBSPL): the natural cubic spline (second derivative zero at both ends),
//!   continuous second derivative; second derivatives `M_i` solve
//!   `h_{i−1}M_{i−1} + 2(h_{i−1} + h_i)M_i + h_i M_{i+1} = 6((y_{i+1} − y_i)/h_i − (y_i − y_{i−1})/h_{i−1})`.
//!
//! With two points both methods are the straight line. Outside `[x_0, x_{n−1}]` the end cubic
//! is continued, or, with `linear_extrapolate`, the tangent line at the end point is used.
//! (The exact end conditions Adams uses are not documented; these are the standard ones.)

use thiserror::Error;

/// Invalid spline data given to [`SplineData::new`].
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{message}")]
pub struct SplineError {
    /// Description of the problem.
    pub message: String,
}

/// Interpolation method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SplineMethod {
    /// Akima's method (AKISPL).
    Akima,
    /// Natural cubic spline (CUBSPL).
    Cubic,
}

/// The X/Y data of a 1-D SPLINE statement, validated, with precomputed coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct SplineData {
    x: Vec<f64>,
    y: Vec<f64>,
    linear_extrapolate: bool,
    /// Akima node slopes.
    akima_slopes: Vec<f64>,
    /// Natural-spline second derivatives at the nodes.
    cubic_m: Vec<f64>,
    /// A 2-D spline's curves `y_k(x)` with their `z_k` (strictly increasing); empty for a
    /// 1-D spline. `x`/`y` above are then the first curve's.
    family: Vec<(f64, SplineData)>,
}

impl SplineData {
    /// Validates the data (at least two points, equal lengths, finite values, strictly
    /// increasing x) and precomputes the Akima and natural-cubic coefficients.
    pub fn new(x: Vec<f64>, y: Vec<f64>, linear_extrapolate: bool) -> Result<Self, SplineError> {
        let err = |message: String| Err(SplineError { message });
        if x.len() != y.len() {
            return err(format!(
                "spline has {} x values but {} y values",
                x.len(),
                y.len()
            ));
        }
        if x.len() < 2 {
            return err(format!("spline needs at least 2 points, has {}", x.len()));
        }
        if let Some(v) = x.iter().chain(&y).find(|v| !v.is_finite()) {
            return err(format!("spline data contains the non-finite value {v}"));
        }
        if let Some(w) = x.windows(2).find(|w| w[1] <= w[0]) {
            return err(format!(
                "spline x values must be strictly increasing, but {} is followed by {}",
                w[0], w[1]
            ));
        }
        let akima_slopes = akima_slopes(&x, &y);
        let cubic_m = natural_second_derivatives(&x, &y);
        Ok(SplineData {
            x,
            y,
            linear_extrapolate,
            akima_slopes,
            cubic_m,
            family: Vec::new(),
        })
    }

    /// A 2-D spline: one curve `y_k(x)` per `z_k` (at least two, z strictly increasing), each
    /// validated as by [`SplineData::new`]. [`SplineData::evaluate_surface`] interpolates it.
    pub fn surface(
        x: Vec<f64>,
        z: Vec<f64>,
        ys: Vec<Vec<f64>>,
        linear_extrapolate: bool,
    ) -> Result<Self, SplineError> {
        let err = |message: String| Err(SplineError { message });
        if z.len() != ys.len() || z.len() < 2 {
            return err(format!(
                "a 2-D spline needs at least two curves (one z value each), has {}",
                ys.len()
            ));
        }
        if let Some(v) = z.iter().find(|v| !v.is_finite()) {
            return err(format!("spline data contains the non-finite z value {v}"));
        }
        if let Some(w) = z.windows(2).find(|w| w[1] <= w[0]) {
            return err(format!(
                "spline z values must be strictly increasing, but {} is followed by {}",
                w[0], w[1]
            ));
        }
        let mut family = Vec::with_capacity(z.len());
        for (zk, yk) in z.iter().zip(ys) {
            let curve =
                SplineData::new(x.clone(), yk, linear_extrapolate).map_err(|e| SplineError {
                    message: format!("the curve at z = {zk}: {}", e.message),
                })?;
            family.push((*zk, curve));
        }
        let mut first = family[0].1.clone();
        first.family = family;
        Ok(first)
    }

    /// A 2-D spline's curves with their z values (empty for a 1-D spline).
    pub fn family(&self) -> &[(f64, SplineData)] {
        &self.family
    }

    /// The two curves whose z values bracket `z` (the first or last two beyond the ends) and
    /// the weight `w = (z − z_k)/(z_{k+1} − z_k)` of the upper one: a 2-D spline is cubic along
    /// x and linear between curves, `s(x, z) = (1 − w)·y_k(x) + w·y_{k+1}(x)`, continued
    /// linearly beyond the first and last z. `None` for a 1-D spline.
    pub fn bracket(&self, z: f64) -> Option<(&SplineData, &SplineData, f64, f64)> {
        let m = self.family.len();
        if m < 2 {
            return None;
        }
        let k = self
            .family
            .partition_point(|(zk, _)| *zk <= z)
            .clamp(1, m - 1)
            - 1;
        let (z0, lo) = &self.family[k];
        let (z1, hi) = &self.family[k + 1];
        Some((lo, hi, *z0, *z1))
    }

    /// The x values (strictly increasing).
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// The y values.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Whether values outside the data range use the end tangent line.
    pub fn linear_extrapolate(&self) -> bool {
        self.linear_extrapolate
    }

    /// Cubic coefficients `[a, b, c, d]` of interval `i` (0-based) for `method`.
    fn piece(&self, method: SplineMethod, i: usize) -> [f64; 4] {
        let (Some(&x0), Some(&x1), Some(&y0), Some(&y1)) = (
            self.x.get(i),
            self.x.get(i + 1),
            self.y.get(i),
            self.y.get(i + 1),
        ) else {
            return [0.0; 4];
        };
        let h = x1 - x0;
        let m = (y1 - y0) / h;
        match method {
            SplineMethod::Akima => {
                let t0 = self.akima_slopes.get(i).copied().unwrap_or(m);
                let t1 = self.akima_slopes.get(i + 1).copied().unwrap_or(m);
                [
                    y0,
                    t0,
                    (3.0 * m - 2.0 * t0 - t1) / h,
                    (t0 + t1 - 2.0 * m) / (h * h),
                ]
            }
            SplineMethod::Cubic => {
                let m0 = self.cubic_m.get(i).copied().unwrap_or(0.0);
                let m1 = self.cubic_m.get(i + 1).copied().unwrap_or(0.0);
                [
                    y0,
                    m - h * (2.0 * m0 + m1) / 6.0,
                    m0 / 2.0,
                    (m1 - m0) / (6.0 * h),
                ]
            }
        }
    }

    /// `[s, s', s'', s''']` at `x`.
    pub fn evaluate(&self, method: SplineMethod, x: f64) -> [f64; 4] {
        let n = self.x.len();
        let (first, last) = match (self.x.first(), self.x.last()) {
            (Some(&a), Some(&b)) if n >= 2 => (a, b),
            _ => return [0.0; 4],
        };
        if self.linear_extrapolate && (x < first || x > last) {
            let (i, end) = if x < first { (0, first) } else { (n - 2, last) };
            let [s, ds, _, _] = self.evaluate_piece(method, i, end);
            return [s + ds * (x - end), ds, 0.0, 0.0];
        }
        // Interval i with x_i <= x < x_{i+1}, clamped to the end intervals.
        let i = self.x.partition_point(|&xi| xi <= x).clamp(1, n - 1) - 1;
        self.evaluate_piece(method, i, x)
    }

    fn evaluate_piece(&self, method: SplineMethod, i: usize, x: f64) -> [f64; 4] {
        let [a, b, c, d] = self.piece(method, i);
        let u = x - self.x.get(i).copied().unwrap_or(0.0);
        [
            a + u * (b + u * (c + u * d)),
            b + u * (2.0 * c + 3.0 * d * u),
            2.0 * c + 6.0 * d * u,
            6.0 * d,
        ]
    }
}

fn akima_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let m: Vec<f64> = x
        .windows(2)
        .zip(y.windows(2))
        .map(|(xw, yw)| (yw[1] - yw[0]) / (xw[1] - xw[0]))
        .collect();
    if m.len() < 2 {
        return vec![m.first().copied().unwrap_or(0.0); n];
    }
    // em[k + 2] = m_k, for k = -2 ..= n
    let k = m.len();
    let mut em = vec![0.0; k + 4];
    em[2..k + 2].copy_from_slice(&m);
    em[1] = 2.0 * m[0] - m[1];
    em[0] = 2.0 * em[1] - m[0];
    em[k + 2] = 2.0 * m[k - 1] - m[k - 2];
    em[k + 3] = 2.0 * em[k + 2] - m[k - 1];
    (0..n)
        .map(|i| {
            // m_{i-2}, m_{i-1}, m_i, m_{i+1} = em[i], em[i+1], em[i+2], em[i+3]
            let (mm2, mm1, m0, mp1) = (em[i], em[i + 1], em[i + 2], em[i + 3]);
            let w1 = (mp1 - m0).abs();
            let w2 = (mm1 - mm2).abs();
            if w1 + w2 == 0.0 {
                0.5 * (mm1 + m0)
            } else {
                (w1 * mm1 + w2 * m0) / (w1 + w2)
            }
        })
        .collect()
}

/// Second derivatives of the natural cubic spline (Thomas algorithm).
fn natural_second_derivatives(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut m = vec![0.0; n];
    if n < 3 {
        return m;
    }
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    // Unknowns M_1 .. M_{n-2}; row r (0-based) is node i = r + 1.
    let rows = n - 2;
    let mut diag = vec![0.0; rows];
    let mut rhs = vec![0.0; rows];
    for r in 0..rows {
        let i = r + 1;
        diag[r] = 2.0 * (h[i - 1] + h[i]);
        rhs[r] = 6.0 * ((y[i + 1] - y[i]) / h[i] - (y[i] - y[i - 1]) / h[i - 1]);
    }
    // Forward elimination: sub-diagonal of row r is h[r], super-diagonal is h[r + 1].
    for r in 1..rows {
        let factor = h[r] / diag[r - 1];
        diag[r] -= factor * h[r];
        rhs[r] -= factor * rhs[r - 1];
    }
    // Back substitution.
    for r in (0..rows).rev() {
        let upper = if r + 1 < rows {
            h[r + 1] * m[r + 2]
        } else {
            0.0
        };
        m[r + 1] = (rhs[r] - upper) / diag[r];
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12 * (1.0 + b.abs())
    }

    #[test]
    fn validation() {
        assert!(SplineData::new(vec![0.0], vec![1.0], false).is_err());
        assert!(SplineData::new(vec![0.0, 1.0], vec![1.0], false).is_err());
        assert!(SplineData::new(vec![0.0, 0.0], vec![1.0, 2.0], false).is_err());
        assert!(SplineData::new(vec![0.0, f64::NAN], vec![1.0, 2.0], false).is_err());
        assert!(SplineData::new(vec![0.0, 1.0], vec![1.0, 2.0], false).is_ok());
    }

    #[test]
    fn natural_spline_three_points() {
        // (0,0), (1,1), (2,0): M1 = -3, s(x) = 1.5x - 0.5x³ on [0, 1].
        let s = SplineData::new(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 0.0], false).unwrap();
        for &x in &[0.0, 0.25, 0.5, 0.9] {
            let [v, d1, d2, d3] = s.evaluate(SplineMethod::Cubic, x);
            assert!(close(v, 1.5 * x - 0.5 * x * x * x));
            assert!(close(d1, 1.5 - 1.5 * x * x));
            assert!(close(d2, -3.0 * x));
            assert!(close(d3, -3.0));
        }
    }

    #[test]
    fn two_points_is_linear() {
        let s = SplineData::new(vec![1.0, 3.0], vec![2.0, 6.0], false).unwrap();
        for method in [SplineMethod::Akima, SplineMethod::Cubic] {
            let [v, d1, d2, _] = s.evaluate(method, 2.5);
            assert!(close(v, 5.0) && close(d1, 2.0) && close(d2, 0.0));
        }
    }
}
