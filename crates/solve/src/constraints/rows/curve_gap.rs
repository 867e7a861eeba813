//! PTCV: the rows that keep a body-fixed point on a curve carried by another body
//! (ADM-ELEMENTS §15), with the contact parameter solved inside the row.
//!
//! **Equations.** With `ρ = R_Mᵀ(P_I − p_M)` the point in the frame M of the curve (the RM
//! marker) and `c(α)` the curve ([`linkage_model::curves`]), the contact parameter `α(ρ)`
//! solves the tangency condition `g(α, ρ) = (ρ − c(α))·c'(α) = 0` (the nearest point),
//! by Newton warm-started from the last contact (so it follows the curve continuously and
//! across the seam of a closed curve). The two rows are the components of the gap
//! `d = ρ − c(α)` in the normal plane:
//!
//! ```text
//! Φ_n = e_n(α)·d,   Φ_b = e_b(α)·d,
//! e_b = unit(a − t̂ (t̂·a)),  e_n = e_b × t̂,   t̂ = c'/|c'|
//! ```
//!
//! with `a` a fixed axis of the curve frame never along the tangent (z for a curve in the x-y
//! plane, whose `e_b = z` is its binormal and `e_n` its in-plane normal).
//!
//! **Equivalence with α as a coordinate.** The formulation with α as an extra coordinate has
//! the three rows `ρ − c(α) = 0`, whose tangential component is `g/|c'|`. Eliminating α by
//! `g = 0` leaves exactly these two rows on the same manifold, and their Jacobian at
//! satisfaction (`d = 0`) is `e·∂ρ/∂q` — the normal and binormal components of the point's
//! motion relative to the curve — the same as the reduced Jacobian of the three-row form. A
//! PTCV thus removes 2 degrees of freedom and has no tangential reaction.
//!
//! **Derivatives, exact.** Along a motion of the bodies, `ρ(t)` has a series `[ρ, ρ̇, ρ̈]`
//! (body point and frame series of [`crate::constraints::rows`]), and the contact parameter's
//! rates follow from differentiating `g = 0` twice (`D = |c'|² − d·c''`):
//!
//! ```text
//! α̇ = ρ̇·c'/D,   ḋ = ρ̇ − c' α̇,
//! α̈ = [(ρ̈ − c'' α̇²)·c' + 2 ḋ·c'' α̇ + d·c''' α̇²]/D
//! ```
//!
//! The rows' series then come from second-order jets (value, rate, acceleration) of `c(α(t))`,
//! `t̂`, `e_n`, `e_b` and `d` ([`Jet`]). The gradient is the rate along the three unit
//! directions of `ρ`, mapped to the bodies as for a projection (`∂/∂x_I = G`, `∂/∂θ_I = u_I ×
//! G`, `∂/∂x_M = −G`, `∂/∂θ_M = −(P_I − x_M) × G`, `G = R_M ∇_ρΦ`); the Hessian is by
//! polarization of the series ([`crate::constraints::hessian`]), so the curvature's geometric
//! stiffness (a point on a circle is a pendulum) is in statics and linearization.
//!
//! Cost: a few curve evaluations (Newton from the last contact, typically 1–3 steps) per row.

use crate::constraints::rows::{dir_series, dot_series, point_series, BodyFrame, BodyPoint};
use crate::constraints::rows::{RowGradient, Velocities};
use crate::state::State;
use glam::DVec3;
use linkage_model::curves::Curve;
use std::sync::{Arc, Mutex};

/// A scalar's `[value, rate, acceleration]`.
pub type ScalarJet = [f64; 3];
/// A vector's `[value, rate, acceleration]`.
pub type Jet = [DVec3; 3];

pub(crate) fn jet_cross(a: &Jet, b: &Jet) -> Jet {
    [
        a[0].cross(b[0]),
        a[1].cross(b[0]) + a[0].cross(b[1]),
        a[2].cross(b[0]) + 2.0 * a[1].cross(b[1]) + a[0].cross(b[2]),
    ]
}

pub(crate) fn jet_scale(s: ScalarJet, v: &Jet) -> Jet {
    [
        v[0] * s[0],
        v[1] * s[0] + v[0] * s[1],
        v[2] * s[0] + v[1] * (2.0 * s[1]) + v[0] * s[2],
    ]
}

pub(crate) fn jet_sub(a: &Jet, b: &Jet) -> Jet {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `unit(v) = v·(v·v)^(−1/2)` as a jet.
pub(crate) fn jet_unit(v: &Jet) -> Jet {
    let [x0, x1, x2] = dot_series(v, v);
    let f0 = 1.0 / x0.sqrt();
    let f1 = -0.5 * f0 / x0;
    let f2 = -1.5 * f1 / x0;
    jet_scale([f0, f1 * x1, f2 * x1 * x1 + f1 * x2], v)
}

/// One row of a PTCV (module docs): the point, the curve's frame, which normal-plane component.
#[derive(Clone, Debug)]
pub struct CurveGap {
    /// The I marker's origin.
    pub point: BodyPoint,
    /// The RM marker's frame (the curve's coordinates are in it).
    pub frame: BodyFrame,
    pub curve: Arc<Curve>,
    /// 0: the in-plane normal component `e_n·d`; 1: the binormal component `e_b·d`.
    pub axis: usize,
    /// The last contact (the Newton warm start), shared by the PTCV's two rows.
    pub contact: Arc<Mutex<LastContact>>,
}

/// The last contact a curve constraint solved: the configuration it was solved for (`key`: a
/// PTCV's point in the curve frame, a CVCV's relative pose of its two curve frames) and the
/// curve parameters found (`params`). It is the warm start of the next solve, and the answer
/// again for the same configuration, so that every evaluation at one pose gives the same
/// numbers to the last bit (the fixed-pattern matrices rely on it). Shared by the rows of one
/// element.
#[derive(Clone, Copy, Debug)]
pub struct LastContact<K = DVec3, P = f64> {
    pub key: K,
    pub params: P,
}

impl LastContact {
    /// No contact yet: the first solve searches the whole curve.
    pub fn none() -> LastContact {
        LastContact {
            key: DVec3::NAN,
            params: f64::NAN,
        }
    }
}

impl<K: PartialEq + Copy, P: Copy> LastContact<K, P> {
    /// The parameters for configuration `key`: the remembered ones when `key` is the last one,
    /// else `solve(the last parameters)`, remembered. A poisoned lock is taken over (the data
    /// is two plain values, always whole).
    pub fn solve_at(cell: &Mutex<Self>, key: K, solve: impl FnOnce(P) -> P) -> P {
        let mut last = cell
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if last.key == key {
            return last.params;
        }
        let params = solve(last.params);
        *last = LastContact { key, params };
        params
    }
}

impl PartialEq for CurveGap {
    fn eq(&self, other: &Self) -> bool {
        self.point == other.point
            && self.frame == other.frame
            && self.axis == other.axis
            && Arc::ptr_eq(&self.curve, &other.curve)
    }
}

impl CurveGap {
    /// `[ρ, ρ̇, ρ̈]`: the point in the curve's frame, along the twists `v` and accelerations
    /// `acc` (zero when `None`).
    fn rho_series(&self, s: &State, v: &Velocities, acc: Option<&Velocities>) -> Jet {
        let pi = point_series(&self.point, s, v, acc);
        let po = point_series(&self.frame.origin(), s, v, acc);
        let w = jet_sub(&pi, &po);
        let c: [ScalarJet; 3] =
            std::array::from_fn(|k| dot_series(&w, &dir_series(&self.frame.axis(k), s, v, acc)));
        std::array::from_fn(|o| DVec3::new(c[0][o], c[1][o], c[2][o]))
    }

    /// `ρ` at state `s`.
    fn rho(&self, s: &State) -> DVec3 {
        let (p_i, _) = self.point.eval(s);
        let (p_m, r_m) = self.frame.eval(s);
        r_m.transpose() * (p_i - p_m)
    }

    /// The contact parameter for the point `rho` (curve frame), warm-started from the last one
    /// and remembered.
    pub fn contact(&self, rho: DVec3) -> f64 {
        LastContact::solve_at(&self.contact, rho, |last| {
            self.curve.nearest(rho, last.is_finite().then_some(last))
        })
    }

    /// The contact parameter at state `s`.
    pub fn alpha_at(&self, s: &State) -> f64 {
        self.contact(self.rho(s))
    }

    /// The point's speed along the curve relative to the curve's body, `α̇·|c'|` with
    /// `α̇ = ρ̇·c'/D` (module docs), along the twists `v` (PTCV's VEL).
    pub fn sliding_speed(&self, s: &State, v: &Velocities) -> f64 {
        let rho = self.rho_series(s, v, None);
        let alpha = self.contact(rho[0]);
        let [c, c1, c2, _] = self.curve.eval(alpha);
        let den = c1.length_squared() - (rho[0] - c).dot(c2);
        if den > 0.0 {
            rho[1].dot(c1) / den * c1.length()
        } else {
            0.0
        }
    }

    /// The row's `[Φ, Φ̇, Φ̈]` for the point series `rho` at contact parameter `alpha`.
    fn gap_series(&self, rho: &Jet, alpha: f64) -> ScalarJet {
        let [c, c1, c2, c3] = self.curve.eval(alpha);
        let d = rho[0] - c;
        let den = c1.length_squared() - d.dot(c2);
        let (ad, add) = if den > 0.0 {
            let ad = rho[1].dot(c1) / den;
            let dd = rho[1] - c1 * ad;
            let add =
                ((rho[2] - c2 * (ad * ad)).dot(c1) + 2.0 * dd.dot(c2) * ad + d.dot(c3) * ad * ad)
                    / den;
            (ad, add)
        } else {
            (0.0, 0.0)
        };
        let cj: Jet = [c, c1 * ad, c2 * (ad * ad) + c1 * add];
        let tj: Jet = [c1, c2 * ad, c3 * (ad * ad) + c2 * add];
        let dj = jet_sub(rho, &cj);
        let th = jet_unit(&tj);
        let a = self.curve.reference_axis;
        let along = dot_series(&th, &[a, DVec3::ZERO, DVec3::ZERO]);
        let eb = jet_unit(&jet_sub(
            &[a, DVec3::ZERO, DVec3::ZERO],
            &jet_scale(along, &th),
        ));
        let e = if self.axis == 0 {
            jet_cross(&eb, &th)
        } else {
            eb
        };
        dot_series(&e, &dj)
    }

    /// `Φ` at state `s`.
    pub fn value(&self, s: &State) -> f64 {
        let rho = self.rho(s);
        let alpha = self.contact(rho);
        self.gap_series(&[rho, DVec3::ZERO, DVec3::ZERO], alpha)[0]
    }

    /// `[Φ, Φ̇, Φ̈]` along the twists `v` and accelerations `acc`.
    pub fn series(&self, s: &State, v: &Velocities, acc: Option<&Velocities>) -> ScalarJet {
        let rho = self.rho_series(s, v, acc);
        let alpha = self.contact(rho[0]);
        self.gap_series(&rho, alpha)
    }

    /// Adds `c·∂Φ/∂q` to `g`.
    pub fn gradient(&self, s: &State, c: f64, g: &mut RowGradient) {
        let rho = self.rho(s);
        let alpha = self.contact(rho);
        let grad_rho = DVec3::from_array(std::array::from_fn(|k| {
            let mut dir = DVec3::ZERO;
            dir[k] = 1.0;
            self.gap_series(&[rho, dir, DVec3::ZERO], alpha)[1]
        }));
        let (p_i, u_i) = self.point.eval(s);
        let (_, r_m) = self.frame.eval(s);
        let big_g = r_m * grad_rho;
        let x_m = s.pose(self.frame.body).p;
        add_block(g, self.point.body, c, big_g, u_i.cross(big_g));
        add_block(g, self.frame.body, -c, big_g, (p_i - x_m).cross(big_g));
    }
}

fn add_block(g: &mut RowGradient, body: linkage_model::Body, c: f64, dx: DVec3, dth: DVec3) {
    if let Some(k) = body.part() {
        g.add_block(
            k,
            [
                c * dx.x,
                c * dx.y,
                c * dx.z,
                c * dth.x,
                c * dth.y,
                c * dth.z,
            ],
        );
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::state::{ControlValues, Pose};
    use glam::DMat3;
    use linkage_model::curves::CurveSpec;
    use linkage_model::{Body, Origin};

    /// Asserts that the gradient blocks `g` of parts 0 and 1 match central differences of
    /// `value` at `s` (step 1e-6, within 1e-7), for the row named `what`.
    pub(crate) fn assert_gradient_matches_differences(
        value: impl Fn(&State) -> f64,
        g: &RowGradient,
        s: &State,
        what: &str,
    ) {
        let h = 1e-6;
        for k in 0..2 {
            let block = g.blocks.iter().find(|(b, _)| *b == k).unwrap().1;
            for c in 0..6 {
                let mut e = DVec3::ZERO;
                e[c % 3] = 1.0;
                let (dx, dth) = if c < 3 {
                    (e, DVec3::ZERO)
                } else {
                    (DVec3::ZERO, e)
                };
                let (mut sp, mut sm) = (s.clone(), s.clone());
                sp.increment(k, dx * h, dth * h);
                sm.increment(k, -dx * h, -dth * h);
                let fd = (value(&sp) - value(&sm)) / (2.0 * h);
                assert!(
                    (fd - block[c]).abs() < 1e-7,
                    "{what} part {k} coordinate {c}: {fd} vs {}",
                    block[c]
                );
            }
        }
    }

    /// A constant twist of parts 0 and 1 (CM velocity, angular velocity) for rate checks.
    pub(crate) const TWIST: [(DVec3, DVec3); 2] = [
        (DVec3::new(0.3, -0.2, 0.5), DVec3::new(0.4, 0.1, -0.3)),
        (DVec3::new(-0.1, 0.2, 0.1), DVec3::new(0.2, -0.5, 0.3)),
    ];

    /// Asserts that the series `[Φ, Φ̇, Φ̈]` of a row along the constant twist `v` (the CM
    /// moving by v t, the body turning by ω t about it) matches `value` at `s` and its central
    /// first and second differences (step 1e-4: within 1e-7 and 1e-5), and that `Φ̇ = ∇Φ·v`
    /// with the gradient `g` (within 1e-12).
    pub(crate) fn assert_series_matches_differences(
        value: impl Fn(&State) -> f64,
        [q, qd, qdd]: [f64; 3],
        g: &RowGradient,
        s: &State,
        v: &[(DVec3, DVec3)],
        what: &str,
    ) {
        let along = |t: f64| {
            let mut st = s.clone();
            for (k, (vx, w)) in v.iter().enumerate() {
                st.increment(k, *vx * t, *w * t);
            }
            st
        };
        let h = 1e-4;
        let (qp, qm) = (value(&along(h)), value(&along(-h)));
        assert!((q - value(s)).abs() < 1e-15, "{what} value");
        assert!((qd - (qp - qm) / (2.0 * h)).abs() < 1e-7, "{what} rate");
        assert!(
            (qdd - (qp - 2.0 * q + qm) / (h * h)).abs() < 1e-5,
            "{what}: {qdd} vs {}",
            (qp - 2.0 * q + qm) / (h * h)
        );
        assert!((qd - g.rate(v)).abs() < 1e-12, "{what}: rate = ∇Φ·v");
    }

    /// A non-planar open cubic through 6 points, carried by part 1 through a tilted frame; the
    /// point on part 0, off the curve by ~0.1 (the rows are checked off the manifold, where
    /// the contact parameter's own rates matter).
    fn setup(axis: usize) -> (CurveGap, State) {
        let points = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.5, 0.2),
            DVec3::new(2.0, 0.2, 0.5),
            DVec3::new(3.0, -0.4, 0.3),
            DVec3::new(4.0, 0.1, -0.2),
            DVec3::new(5.0, 0.6, 0.0),
        ];
        let spec = CurveSpec {
            points,
            order: 4,
            closed: false,
            through_points: true,
        };
        let origin = Origin {
            statement: "CURVE",
            id: 1,
            name: "CURVE_1".into(),
            span: Default::default(),
            statement_index: 0,
        };
        let curve = Arc::new(Curve::new(origin, &spec).unwrap());
        let gap = CurveGap {
            point: BodyPoint {
                body: Body::Part(0),
                p_b: DVec3::new(0.3, -0.2, 0.1),
            },
            frame: BodyFrame {
                body: Body::Part(1),
                p_b: DVec3::new(0.5, 0.1, -0.3),
                r_b: DMat3::from_rotation_z(0.4) * DMat3::from_rotation_x(0.2),
            },
            curve,
            axis,
            contact: Arc::new(Mutex::new(LastContact::none())),
        };
        let r1 = DMat3::from_rotation_y(0.3) * DMat3::from_rotation_z(-0.2);
        let p1 = DVec3::new(0.2, -0.1, 0.4);
        // Place the point near c(0.1), displaced 0.1 off the curve.
        let (c, _) = {
            let e = gap.curve.eval(0.1);
            (e[0], e[1])
        };
        let (pm, rm) = (p1 + r1 * gap.frame.p_b, r1 * gap.frame.r_b);
        let target = pm + rm * (c + DVec3::new(0.03, 0.08, -0.05));
        let r0 = DMat3::from_rotation_x(0.7);
        let p0 = target - r0 * gap.point.p_b;
        let s = State {
            poses: vec![Pose { p: p0, r: r0 }, Pose { p: p1, r: r1 }],
            time: 0.0,
            controls: ControlValues::default(),
            elements: Default::default(),
        };
        (gap, s)
    }

    #[test]
    fn gradient_and_rates_match_finite_differences_off_the_curve() {
        for axis in [0, 1] {
            let (gap, s) = setup(axis);
            let mut g = RowGradient::default();
            gap.gradient(&s, 1.0, &mut g);
            let what = format!("axis {axis}");
            assert_gradient_matches_differences(|st| gap.value(st), &g, &s, &what);
            // Φ̈ along a constant twist against the second difference of Φ along it.
            let series = gap.series(&s, &TWIST, None);
            assert_series_matches_differences(|st| gap.value(st), series, &g, &s, &TWIST, &what);
        }
    }
}
