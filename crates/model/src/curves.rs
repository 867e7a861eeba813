//! CURVE: a parametric 3-D curve `c(α)`, `α ∈ [−1, 1]`, in the frame of the marker that
//! carries it (the RM marker of a PTCV or CVCV), from a MATRIX of points (ADM-ELEMENTS §14).
//!
//! The curve is a B-spline of ORDER `k` (degree `k − 1`; 4 = cubic, the default; 2 = a
//! polyline through its points):
//!
//! ```text
//! c(t) = Σ_j B_{j,k}(t) P_j,     t = t_lo + (α + 1)/2 · (t_hi − t_lo)
//! ```
//!
//! * OPEN: a clamped knot vector (k equal knots at each end), so the curve starts at the first
//!   control point and ends at the last one.
//! * CLOSED: a periodic B-spline with uniform knots over the distinct points (the matrix repeats
//!   its first point last; that repetition is dropped); `α` wraps with period 2, the curve is
//!   `C^{k−2}` across the seam.
//! * CURVE_POINTS: the matrix rows are points *on* the curve. The control points solve
//!   `Σ_j B_j(t_i) P_j = Q_i` at parameters `t_i` that are uniform for a closed curve and
//!   chord-length (with knots by averaging the parameters, so the system is well posed) for an
//!   open one. Without CURVE_POINTS the rows are the control points.
//!
//! Derivatives in `α` are B-splines of lower order (`c' = Σ (k−1)(P_{j+1} − P_j)/(t_{j+k} −
//! t_{j+1}) B_{j,k−1}`), scaled by `dt/dα = (t_hi − t_lo)/2`; [`Curve::eval`] returns the value
//! and the first three derivatives. Beyond the ends of an open curve the end pieces continue
//! as polynomials, so a contact point may be followed a little past an end.
//!
//! Cost: O(k²) per evaluation, no allocation. Construction: O(n³) for interpolation (a dense
//! solve on the n points; curve matrices hold tens to hundreds of points).

use crate::bodies::Origin;
use glam::DVec3;

/// The highest B-spline ORDER accepted (degree 7).
pub const MAX_ORDER: usize = 8;

/// A B-spline `Σ_j B_{j,k}(t) P_j` over a knot vector of `n + k` knots (`order` 0: the zero
/// curve, the derivative of a piecewise-constant one).
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    order: usize,
    knots: Vec<f64>,
    ctrl: Vec<DVec3>,
}

/// The `k` basis functions `B_{μ−k+1+r, k}(t)`, r = 0..k, that are non-zero on knot span μ
/// (Cox–de Boor recursion, built up one degree at a time).
fn basis(knots: &[f64], k: usize, mu: usize, t: f64) -> [f64; MAX_ORDER] {
    let mut n = [0.0; MAX_ORDER];
    let mut left = [0.0; MAX_ORDER];
    let mut right = [0.0; MAX_ORDER];
    n[0] = 1.0;
    for d in 1..k {
        left[d] = t - knots[mu + 1 - d];
        right[d] = knots[mu + d] - t;
        let mut saved = 0.0;
        for r in 0..d {
            let den = right[r + 1] + left[d - r];
            let tmp = if den != 0.0 { n[r] / den } else { 0.0 };
            n[r] = saved + right[r + 1] * tmp;
            saved = left[d - r] * tmp;
        }
        n[d] = saved;
    }
    n
}

impl BSpline {
    /// The knot span `μ ∈ [k − 1, n − 1]` holding `t` (the end spans beyond the ends).
    fn span(&self, t: f64) -> usize {
        let p = self.order - 1;
        let n = self.ctrl.len();
        let inner = &self.knots[p + 1..n];
        p + inner.partition_point(|&u| u <= t)
    }

    /// `c(t)`.
    pub fn eval(&self, t: f64) -> DVec3 {
        if self.order == 0 || self.ctrl.is_empty() {
            return DVec3::ZERO;
        }
        let mu = self.span(t);
        let b = basis(&self.knots, self.order, mu, t);
        let first = mu + 1 - self.order;
        (0..self.order).map(|r| self.ctrl[first + r] * b[r]).sum()
    }

    /// `dc/dt`, a B-spline of order `k − 1` on the inner knots.
    fn derivative(&self) -> BSpline {
        if self.order <= 1 {
            return BSpline {
                order: 0,
                knots: Vec::new(),
                ctrl: Vec::new(),
            };
        }
        let p = (self.order - 1) as f64;
        let ctrl = (0..self.ctrl.len() - 1)
            .map(|j| {
                let den = self.knots[j + self.order] - self.knots[j + 1];
                if den > 0.0 {
                    (self.ctrl[j + 1] - self.ctrl[j]) * (p / den)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        BSpline {
            order: self.order - 1,
            knots: self.knots[1..self.knots.len() - 1].to_vec(),
            ctrl,
        }
    }
}

/// A CURVE from a MATRIX, evaluated in `α` (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    pub origin: Origin,
    pub closed: bool,
    pub order: usize,
    /// The curve and its first three derivatives in the spline parameter t.
    splines: [BSpline; 4],
    t_lo: f64,
    t_hi: f64,
    /// An axis of the curve frame never along the tangent: z for a curve in the x-y plane
    /// (its binormal), else the frame axis most nearly normal to every tangent. PTCV measures
    /// its out-of-plane equation along it.
    pub reference_axis: DVec3,
    /// Every point has z = 0: the curve lies in its frame's x-y plane (a CVCV needs that).
    pub planar: bool,
}

/// The points of a matrix curve and how to read them.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveSpec {
    pub points: Vec<DVec3>,
    pub order: usize,
    pub closed: bool,
    /// CURVE_POINTS: the points are on the curve (interpolated), not control points.
    pub through_points: bool,
}

/// Why a matrix curve cannot be built (each message a sentence the builder prefixes with the
/// CURVE's name).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CurveError {
    #[error("ORDER = {0} is outside 2..={MAX_ORDER}")]
    Order(usize),
    #[error(
        "{count} {}point(s): an {} curve of ORDER {order} needs at least {need}",
        if *closed { "distinct " } else { "" },
        if *closed { "closed" } else { "open" }
    )]
    TooFewPoints {
        count: usize,
        closed: bool,
        order: usize,
        need: usize,
    },
    /// Consecutive points (1-based) that coincide on a curve through its points.
    #[error(
        "points {0} and {1} coincide: a curve through its points needs distinct consecutive \
         points"
    )]
    Coincident(usize, usize),
    #[error("the interpolation through the points is singular")]
    SingularInterpolation,
}

impl Curve {
    /// Builds the curve. Errors ([`CurveError`]): fewer points than the order needs, an ORDER
    /// out of 2..=[`MAX_ORDER`], coincident consecutive points of an interpolated curve, a
    /// singular interpolation.
    pub fn new(origin: Origin, spec: &CurveSpec) -> Result<Curve, CurveError> {
        let k = spec.order;
        if !(2..=MAX_ORDER).contains(&k) {
            return Err(CurveError::Order(k));
        }
        let mut pts = spec.points.clone();
        let scale = pts.iter().map(|p| p.length()).fold(0.0, f64::max).max(1.0);
        if spec.closed && pts.len() > 1 {
            let (first, last) = (pts[0], pts[pts.len() - 1]);
            if (first - last).length() <= 1e-9 * scale {
                pts.pop();
            }
        }
        let need = if spec.closed { 3.max(k - 1) } else { k.max(2) };
        if pts.len() < need {
            return Err(CurveError::TooFewPoints {
                count: pts.len(),
                closed: spec.closed,
                order: k,
                need,
            });
        }
        if spec.through_points {
            let n = pts.len() + usize::from(spec.closed);
            for w in 0..n - 1 {
                if (pts[(w + 1) % pts.len()] - pts[w]).length() <= 1e-12 * scale {
                    return Err(CurveError::Coincident(w + 1, (w + 1) % pts.len() + 1));
                }
            }
        }
        let (spline, t_lo, t_hi) = if spec.closed {
            periodic(&pts, k, spec.through_points)?
        } else {
            clamped(&pts, k, spec.through_points)?
        };
        let d1 = spline.derivative();
        let d2 = d1.derivative();
        let d3 = d2.derivative();
        let mut curve = Curve {
            origin,
            closed: spec.closed,
            order: k,
            splines: [spline, d1, d2, d3],
            t_lo,
            t_hi,
            reference_axis: DVec3::Z,
            planar: spec.points.iter().all(|p| p.z.abs() <= 1e-12 * scale),
        };
        curve.reference_axis = curve.choose_reference_axis(&spec.points, scale);
        Ok(curve)
    }

    fn choose_reference_axis(&self, points: &[DVec3], scale: f64) -> DVec3 {
        if points.iter().all(|p| p.z.abs() <= 1e-12 * scale) {
            return DVec3::Z;
        }
        let samples = 64 * points.len().max(4);
        let worst = |axis: DVec3| {
            (0..samples)
                .map(|s| {
                    let a = -1.0 + 2.0 * s as f64 / (samples - 1) as f64;
                    let t = self.eval(a)[1].normalize_or_zero();
                    t.dot(axis).abs()
                })
                .fold(0.0, f64::max)
        };
        [DVec3::Z, DVec3::Y, DVec3::X]
            .into_iter()
            .min_by(|a, b| worst(*a).total_cmp(&worst(*b)))
            .unwrap_or(DVec3::Z)
    }

    /// `α` wrapped into [−1, 1) for a closed curve; unchanged for an open one.
    pub fn wrap(&self, alpha: f64) -> f64 {
        if self.closed {
            alpha - 2.0 * ((alpha + 1.0) / 2.0).floor()
        } else {
            alpha
        }
    }

    /// `[c, dc/dα, d²c/dα², d³c/dα³]` at `α` (in the curve's frame).
    pub fn eval(&self, alpha: f64) -> [DVec3; 4] {
        let a = self.wrap(alpha);
        let s = 0.5 * (self.t_hi - self.t_lo);
        let t = self.t_lo + (a + 1.0) * s;
        [
            self.splines[0].eval(t),
            self.splines[1].eval(t) * s,
            self.splines[2].eval(t) * (s * s),
            self.splines[3].eval(t) * (s * s * s),
        ]
    }

    /// Number of polynomial pieces (spans) over [−1, 1].
    pub fn pieces(&self) -> usize {
        (self.t_hi - self.t_lo).round().max(1.0) as usize
    }

    /// The parameter of the point of the curve nearest to `p` (curve frame): Newton on
    /// `g(α) = (p − c)·c' = 0` from `guess` when it converges to a minimum of the distance
    /// there, otherwise from the nearest of a sampling of the whole curve (8 samples per
    /// piece). Returns `α` (wrapped on a closed curve).
    pub fn nearest(&self, p: DVec3, guess: Option<f64>) -> f64 {
        if let Some(a) = guess.and_then(|g| self.newton(p, g)) {
            return a;
        }
        let samples = 8 * self.pieces() * self.order + 1;
        let mut best = (f64::INFINITY, -1.0);
        for s in 0..samples {
            let a = -1.0 + 2.0 * s as f64 / (samples - 1) as f64;
            let d = (p - self.eval(a)[0]).length_squared();
            if d < best.0 {
                best = (d, a);
            }
        }
        self.newton(p, best.1).unwrap_or(best.1)
    }

    /// Newton on `g(α) = (p − c)·c'`, steps limited to a quarter piece; `None` when it does
    /// not converge within 30 steps or ends on a maximum of the distance.
    fn newton(&self, p: DVec3, start: f64) -> Option<f64> {
        let max_step = 0.5 / self.pieces() as f64;
        let mut a = start;
        for _ in 0..30 {
            let [c, c1, c2, _] = self.eval(a);
            let d = p - c;
            let g = d.dot(c1);
            let dg = d.dot(c2) - c1.length_squared();
            if dg >= 0.0 {
                return None;
            }
            let step = (-g / dg).clamp(-max_step, max_step);
            a += step;
            if step.abs() <= 1e-13 {
                return Some(self.wrap(a));
            }
        }
        None
    }
}

/// Gaussian elimination with partial pivoting of `A X = B` (A n×n row-major, B n vectors).
fn solve_dense(mut a: Vec<f64>, mut b: Vec<DVec3>) -> Option<Vec<DVec3>> {
    let n = b.len();
    for col in 0..n {
        let piv =
            (col..n).max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))?;
        if a[piv * n + col].abs() < 1e-14 {
            return None;
        }
        if piv != col {
            for j in 0..n {
                a.swap(piv * n + j, col * n + j);
            }
            b.swap(piv, col);
        }
        for i in col + 1..n {
            let f = a[i * n + col] / a[col * n + col];
            if f != 0.0 {
                for j in col..n {
                    a[i * n + j] -= f * a[col * n + j];
                }
                let bc = b[col];
                b[i] -= bc * f;
            }
        }
    }
    for col in (0..n).rev() {
        let mut x = b[col];
        for j in col + 1..n {
            x -= b[j] * a[col * n + j];
        }
        b[col] = x / a[col * n + col];
    }
    Some(b)
}

/// An open curve: clamped knots; through the points with chord-length parameters and knots by
/// averaging, or on control points with uniform interior knots. Returns the spline and its
/// parameter range.
fn clamped(pts: &[DVec3], k: usize, through: bool) -> Result<(BSpline, f64, f64), CurveError> {
    let n = pts.len();
    let p = k - 1;
    let mut knots = vec![0.0; n + k];
    for u in knots.iter_mut().skip(n) {
        *u = 1.0;
    }
    if !through {
        for j in 1..n - p {
            knots[j + p] = j as f64 / (n - p) as f64;
        }
        return Ok((
            BSpline {
                order: k,
                knots,
                ctrl: pts.to_vec(),
            },
            0.0,
            1.0,
        ));
    }
    let mut u = vec![0.0; n];
    let total: f64 = pts.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    for i in 1..n {
        u[i] = u[i - 1] + (pts[i] - pts[i - 1]).length() / total;
    }
    u[n - 1] = 1.0;
    for j in 1..n - p {
        knots[j + p] = u[j..j + p].iter().sum::<f64>() / p as f64;
    }
    let probe = BSpline {
        order: k,
        knots,
        ctrl: vec![DVec3::ZERO; n],
    };
    let mut a = vec![0.0; n * n];
    for (i, &ui) in u.iter().enumerate() {
        let mu = probe.span(ui);
        let b = basis(&probe.knots, k, mu, ui);
        for r in 0..k {
            a[i * n + mu + 1 - k + r] += b[r];
        }
    }
    let ctrl = solve_dense(a, pts.to_vec()).ok_or(CurveError::SingularInterpolation)?;
    Ok((BSpline { ctrl, ..probe }, 0.0, 1.0))
}

/// A closed curve: a periodic B-spline over the `m` distinct points (uniform integer knots,
/// control points repeated `k − 1` times around the seam); through the points at `t_i = k − 1
/// + i`, or on them as control points.
fn periodic(pts: &[DVec3], k: usize, through: bool) -> Result<(BSpline, f64, f64), CurveError> {
    let m = pts.len();
    let p = k - 1;
    let total = m + p;
    let knots: Vec<f64> = (0..total + k).map(|j| j as f64).collect();
    let (t_lo, t_hi) = (p as f64, (m + p) as f64);
    let ctrl_of = |base: &[DVec3]| (0..total).map(|j| base[j % m]).collect::<Vec<_>>();
    if !through {
        return Ok((
            BSpline {
                order: k,
                knots,
                ctrl: ctrl_of(pts),
            },
            t_lo,
            t_hi,
        ));
    }
    let mut a = vec![0.0; m * m];
    for i in 0..m {
        let t = t_lo + i as f64;
        let mu = p + i;
        let b = basis(&knots, k, mu, t);
        for r in 0..k {
            a[i * m + (mu + 1 - k + r) % m] += b[r];
        }
    }
    let base = solve_dense(a, pts.to_vec()).ok_or(CurveError::SingularInterpolation)?;
    Ok((
        BSpline {
            order: k,
            knots,
            ctrl: ctrl_of(&base),
        },
        t_lo,
        t_hi,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_adm::Span;

    fn origin() -> Origin {
        Origin {
            statement: "CURVE",
            id: 1,
            name: "CURVE_1".into(),
            span: Span::default(),
            statement_index: 0,
        }
    }

    fn circle(n: usize, r: f64) -> Vec<DVec3> {
        (0..=n)
            .map(|i| {
                let th = std::f64::consts::TAU * i as f64 / n as f64;
                DVec3::new(r * th.cos(), r * th.sin(), 0.0)
            })
            .collect()
    }

    /// Curvature `|c' × c''| / |c'|³`.
    fn curvature(c: &[DVec3; 4]) -> f64 {
        c[1].cross(c[2]).length() / c[1].length().powi(3)
    }

    #[test]
    fn a_closed_cubic_through_points_of_a_circle_is_that_circle() {
        // 24 points on a circle of radius 2: an interpolating periodic cubic deviates from the
        // circle by O(h⁴) in radius (2.2e-5 at most here) and O(h²) in curvature: h²/12 = 5.7e-3
        // relative at the points for the angular step h = 2π/24 (measured: 5.78e-3).
        let r = 2.0;
        let spec = CurveSpec {
            points: circle(24, r),
            order: 4,
            closed: true,
            through_points: true,
        };
        let c = Curve::new(origin(), &spec).unwrap();
        for i in 0..24 {
            let a = -1.0 + 2.0 * i as f64 / 24.0;
            // The data points themselves, exactly (to rounding).
            let th = std::f64::consts::TAU * i as f64 / 24.0;
            let q = DVec3::new(r * th.cos(), r * th.sin(), 0.0);
            assert!((c.eval(a)[0] - q).length() < 1e-12, "point {i}");
        }
        for s in 0..500 {
            let a = -1.0 + 2.0 * s as f64 / 500.0;
            let e = c.eval(a);
            assert!(
                (e[0].length() - r).abs() < 3e-5,
                "radius at {a}: {}",
                e[0].length()
            );
            assert!(
                (curvature(&e) * r - 1.0).abs() < 6e-3,
                "curvature at {a}: {}",
                curvature(&e) * r
            );
            // The tangent is perpendicular to the radius.
            let tr = e[0].normalize().dot(e[1].normalize()).abs();
            assert!(tr < 2e-4, "tangent·radius {tr} at {a}");
        }
        // Continuous across the seam, derivatives included (C² for a cubic).
        let (lo, hi) = (c.eval(-1.0), c.eval(1.0 - 1e-12));
        for d in 0..3 {
            assert!(
                (lo[d] - hi[d]).length() < 1e-8 * (1.0 + lo[d].length()),
                "d{d}"
            );
        }
        // The parameter wraps with period 2.
        assert!((c.eval(0.3)[0] - c.eval(2.3)[0]).length() < 1e-12);
        assert!((c.eval(0.3)[0] - c.eval(-1.7)[0]).length() < 1e-12);
        // Nearest point: a point at radius 3 and angle 100° projects onto the same angle.
        let th = 100f64.to_radians();
        let a = c.nearest(DVec3::new(3.0 * th.cos(), 3.0 * th.sin(), 0.4), None);
        let q = c.eval(a)[0];
        assert!((q.y.atan2(q.x) - th).abs() < 1e-4, "{a}");
    }

    #[test]
    fn order_two_is_the_polyline_through_its_points() {
        let pts = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(4.0, 6.0, 0.0),
        ];
        for through in [false, true] {
            let spec = CurveSpec {
                points: pts.clone(),
                order: 2,
                closed: false,
                through_points: through,
            };
            let c = Curve::new(origin(), &spec).unwrap();
            assert_eq!(c.eval(-1.0)[0], pts[0]);
            assert!((c.eval(1.0)[0] - pts[3]).length() < 1e-15);
            // Straight segments: zero second derivative, a constant tangent per segment.
            let e = c.eval(0.9);
            assert_eq!(e[2], DVec3::ZERO);
            assert!((e[1].normalize() - DVec3::new(0.6, 0.8, 0.0)).length() < 1e-12);
            // Every point lies on the polyline.
            for s in 0..=100 {
                let q = c.eval(-1.0 + 0.02 * s as f64)[0];
                let on = pts.windows(2).any(|w| {
                    let (a, b) = (w[0], w[1]);
                    let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                    (a + (b - a) * t - q).length() < 1e-12
                });
                assert!(on, "{q}");
            }
            if through {
                // Chord-length parameters: the corners at α = −1 + 2·(1/8), −1 + 2·(3/8).
                assert!((c.eval(-0.75)[0] - pts[1]).length() < 1e-12);
                assert!((c.eval(-0.25)[0] - pts[2]).length() < 1e-12);
            }
        }
    }

    #[test]
    fn control_points_give_a_clamped_cubic_with_its_end_tangents() {
        // A Bezier cubic (4 control points, order 4): c'(t=0) = 3(P1 − P0); α = 2t − 1.
        let pts = vec![
            DVec3::ZERO,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
        ];
        let spec = CurveSpec {
            points: pts.clone(),
            order: 4,
            closed: false,
            through_points: false,
        };
        let c = Curve::new(origin(), &spec).unwrap();
        let e = c.eval(-1.0);
        assert!((e[1] - (pts[1] - pts[0]) * 1.5).length() < 1e-12);
        // Midpoint of the Bezier: (P0 + 3P1 + 3P2 + P3)/8.
        let mid = (pts[0] + pts[1] * 3.0 + pts[2] * 3.0 + pts[3]) / 8.0;
        assert!((c.eval(0.0)[0] - mid).length() < 1e-12);
        // Third derivative in t: 6(P3 − 3P2 + 3P1 − P0), times (1/2)³.
        let d3 = (pts[3] - pts[2] * 3.0 + pts[1] * 3.0 - pts[0]) * 6.0 / 8.0;
        assert!((c.eval(0.2)[3] - d3).length() < 1e-12);
    }

    #[test]
    fn too_few_points_and_bad_orders_are_errors() {
        let spec = |n: usize, order: usize| CurveSpec {
            points: circle(n, 1.0)[..n].to_vec(),
            order,
            closed: false,
            through_points: true,
        };
        assert_eq!(
            Curve::new(origin(), &spec(3, 4)).unwrap_err().to_string(),
            "3 point(s): an open curve of ORDER 4 needs at least 4"
        );
        assert_eq!(
            Curve::new(origin(), &spec(5, 1)).unwrap_err(),
            CurveError::Order(1)
        );
        assert_eq!(
            Curve::new(origin(), &spec(5, 9)).unwrap_err(),
            CurveError::Order(9)
        );
        assert!(Curve::new(origin(), &spec(5, 4)).is_ok());
    }
}
