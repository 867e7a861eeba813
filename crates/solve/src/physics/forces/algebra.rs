//! Scalars and 3-vectors that carry (or not) exact derivatives, and the kinematics of
//! body-fixed points and directions lifted into them.
//!
//! Every force law is written once, generic over [`Real`]: with `f64` it gives values (no
//! allocation), with [`Dual`] it gives values and exact sparse gradients (forward-mode
//! differentiation). The gradient variables are those of [`crate::physics::applied`]: for `n` moving
//! parts, index `6k + c` is part k's tangent position coordinate c (`δx` then `δθ`, ground
//! axes) and `6n + 6k + c` its velocity coordinate c (`v` of the CM then `ω`, ground axes).
//!
//! The only primitive derivatives are those of the four lifted quantities of a moving part k:
//!
//! | quantity | value | non-zero partials |
//! |---|---|---|
//! | [`Kinematics::cm`] | `p` | `∂p/∂δx_c = e_c` |
//! | [`Kinematics::rotated`]`(v_b)` | `e = R·v_b` | `∂e/∂δθ_c = e_c × e` (from `R ← exp([δθ]×)R`) |
//! | [`Kinematics::cm_velocity`] | `v` | `∂v/∂v_c = e_c` |
//! | [`Kinematics::omega`] | `ω` | `∂ω/∂ω_c = e_c` |
//!
//! Points (`p + R·p_b`), point velocities (`v + ω × R·p_b`) and everything built from them
//! get their derivatives from the arithmetic (product rule of `·`, `×`, …). Ground quantities
//! are constants.

use crate::constraints::rows::{BodyDir, BodyPoint, Velocities};
use crate::state::State;
use glam::DVec3;
use linkage_expr::{evaluate, evaluate_with_gradient, Dual, Env, EvalError, Expr};
use linkage_model::Body;

/// A scalar with optional derivatives: `f64` (value only) or [`Dual`] (value and gradient).
pub trait Real: Clone {
    /// Whether the type carries derivatives (measures are then requested with gradients).
    const GRADIENT: bool;
    fn cst(v: f64) -> Self;
    fn value(&self) -> f64;
    /// A value with the given partial derivatives (ignored by `f64`).
    fn lift(value: f64, gradient: impl Iterator<Item = (u32, f64)>) -> Self;
    /// From a value returned by a [`linkage_expr::Env`] (its gradient dropped by `f64`).
    fn from_dual(d: Dual) -> Self;
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
    /// Division; the caller makes sure `o` is not zero.
    fn div(&self, o: &Self) -> Self;
    fn neg(&self) -> Self;
    fn scale(&self, c: f64) -> Self;
    /// `self + c` for a constant c.
    fn shift(&self, c: f64) -> Self;
    /// Square root; the caller makes sure the value is positive.
    fn sqrt(&self) -> Self;
    /// `atan2(s, c)`; the caller makes sure `(s, c) ≠ (0, 0)`.
    fn atan2(s: &Self, c: &Self) -> Self;
    /// `f(self)` given its value `f(x)` and slope `f'(x)` (the chain rule: `d f = f'·d x`).
    fn chain(&self, value: f64, slope: f64) -> Self;
    /// Evaluates an expression (with gradient for [`Dual`]).
    fn evaluate<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<Self, EvalError>;
}

impl Real for f64 {
    const GRADIENT: bool = false;
    fn cst(v: f64) -> Self {
        v
    }
    fn value(&self) -> f64 {
        *self
    }
    fn lift(value: f64, _: impl Iterator<Item = (u32, f64)>) -> Self {
        value
    }
    fn from_dual(d: Dual) -> Self {
        d.value()
    }
    fn add(&self, o: &Self) -> Self {
        self + o
    }
    fn sub(&self, o: &Self) -> Self {
        self - o
    }
    fn mul(&self, o: &Self) -> Self {
        self * o
    }
    fn div(&self, o: &Self) -> Self {
        self / o
    }
    fn neg(&self) -> Self {
        -self
    }
    fn scale(&self, c: f64) -> Self {
        self * c
    }
    fn shift(&self, c: f64) -> Self {
        self + c
    }
    fn sqrt(&self) -> Self {
        f64::sqrt(*self)
    }
    fn atan2(s: &Self, c: &Self) -> Self {
        s.atan2(*c)
    }
    fn chain(&self, value: f64, _: f64) -> Self {
        value
    }
    fn evaluate<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<Self, EvalError> {
        evaluate(expr, env)
    }
}

impl Real for Dual {
    const GRADIENT: bool = true;
    fn cst(v: f64) -> Self {
        Dual::constant(v)
    }
    fn value(&self) -> f64 {
        Dual::value(self)
    }
    fn lift(value: f64, gradient: impl Iterator<Item = (u32, f64)>) -> Self {
        Dual::new(value, gradient.filter(|(_, d)| *d != 0.0))
    }
    fn from_dual(d: Dual) -> Self {
        d
    }
    fn add(&self, o: &Self) -> Self {
        self + o
    }
    fn sub(&self, o: &Self) -> Self {
        self - o
    }
    fn mul(&self, o: &Self) -> Self {
        self * o
    }
    fn div(&self, o: &Self) -> Self {
        self / o
    }
    fn neg(&self) -> Self {
        -self
    }
    fn scale(&self, c: f64) -> Self {
        Dual::scale(self, c)
    }
    fn shift(&self, c: f64) -> Self {
        self.map(Dual::value(self) + c, 1.0)
    }
    fn sqrt(&self) -> Self {
        Dual::sqrt(self)
    }
    fn atan2(s: &Self, c: &Self) -> Self {
        // d atan2(s, c) = (c·ds − s·dc) / (s² + c²).
        let (sv, cv) = (Dual::value(s), Dual::value(c));
        let den = sv * sv + cv * cv;
        (s.scale(cv / den) - c.scale(sv / den)).map(sv.atan2(cv), 1.0)
    }
    fn chain(&self, value: f64, slope: f64) -> Self {
        self.map(value, slope)
    }
    fn evaluate<E: Env + ?Sized>(expr: &Expr, env: &E) -> Result<Self, EvalError> {
        evaluate_with_gradient(expr, env)
    }
}

/// A 3-vector of [`Real`]s (ground axes unless stated otherwise).
#[derive(Clone, Debug, PartialEq)]
pub struct V3<R> {
    pub x: R,
    pub y: R,
    pub z: R,
}

impl<R: Real> V3<R> {
    pub fn constant(v: DVec3) -> Self {
        V3 {
            x: R::cst(v.x),
            y: R::cst(v.y),
            z: R::cst(v.z),
        }
    }

    pub fn zero() -> Self {
        Self::constant(DVec3::ZERO)
    }

    /// `value` with partials `∂value/∂(variable i) = g` for each `(i, g)`.
    pub fn lift(value: DVec3, gradient: &[(u32, DVec3)]) -> Self {
        V3 {
            x: R::lift(value.x, gradient.iter().map(|(i, g)| (*i, g.x))),
            y: R::lift(value.y, gradient.iter().map(|(i, g)| (*i, g.y))),
            z: R::lift(value.z, gradient.iter().map(|(i, g)| (*i, g.z))),
        }
    }

    pub fn value(&self) -> DVec3 {
        DVec3::new(self.x.value(), self.y.value(), self.z.value())
    }

    pub fn add(&self, o: &Self) -> Self {
        V3 {
            x: self.x.add(&o.x),
            y: self.y.add(&o.y),
            z: self.z.add(&o.z),
        }
    }

    pub fn sub(&self, o: &Self) -> Self {
        V3 {
            x: self.x.sub(&o.x),
            y: self.y.sub(&o.y),
            z: self.z.sub(&o.z),
        }
    }

    pub fn neg(&self) -> Self {
        V3 {
            x: self.x.neg(),
            y: self.y.neg(),
            z: self.z.neg(),
        }
    }

    /// `s · self` for a scalar s.
    pub fn times(&self, s: &R) -> Self {
        V3 {
            x: self.x.mul(s),
            y: self.y.mul(s),
            z: self.z.mul(s),
        }
    }

    pub fn dot(&self, o: &Self) -> R {
        self.x
            .mul(&o.x)
            .add(&self.y.mul(&o.y))
            .add(&self.z.mul(&o.z))
    }

    pub fn cross(&self, o: &Self) -> Self {
        V3 {
            x: self.y.mul(&o.z).sub(&self.z.mul(&o.y)),
            y: self.z.mul(&o.x).sub(&self.x.mul(&o.z)),
            z: self.x.mul(&o.y).sub(&self.y.mul(&o.x)),
        }
    }

    /// Euclidean length; the caller makes sure the vector is not zero.
    pub fn norm(&self) -> R {
        self.dot(self).sqrt()
    }

    /// `Σ c_k · axes_k`: components along three axes back to a vector.
    pub fn combine(axes: &[V3<R>; 3], c: &[R; 3]) -> Self {
        axes[0]
            .times(&c[0])
            .add(&axes[1].times(&c[1]))
            .add(&axes[2].times(&c[2]))
    }
}

/// Positions and velocities of the parts, as a source of lifted [`V3`]s.
#[derive(Clone, Copy)]
pub struct Kinematics<'a> {
    pub state: &'a State,
    pub velocities: &'a Velocities,
}

fn unit(c: usize) -> DVec3 {
    match c {
        0 => DVec3::X,
        1 => DVec3::Y,
        _ => DVec3::Z,
    }
}

/// Gradient variable index (`u32`, as [`Dual`] uses).
fn var(i: usize) -> u32 {
    u32::try_from(i).unwrap_or(u32::MAX)
}

impl Kinematics<'_> {
    /// Number of moving parts (`n` of the variable layout).
    pub fn nparts(&self) -> usize {
        self.state.poses.len()
    }

    /// Centre of mass of a body (the ground origin for ground).
    pub fn cm<R: Real>(&self, b: Body) -> V3<R> {
        match b {
            Body::Ground => V3::zero(),
            Body::Part(k) => {
                let p = self.state.poses[k].p;
                if !R::GRADIENT {
                    return V3::constant(p);
                }
                V3::lift(p, &[0, 1, 2].map(|c| (var(6 * k + c), unit(c))))
            }
        }
    }

    /// A body-fixed vector `R·v_b` (ground: `v_b` itself).
    pub fn rotated<R: Real>(&self, b: Body, v_b: DVec3) -> V3<R> {
        match b {
            Body::Ground => V3::constant(v_b),
            Body::Part(k) => {
                let e = self.state.poses[k].r * v_b;
                if !R::GRADIENT {
                    return V3::constant(e);
                }
                V3::lift(
                    e,
                    &[0, 1, 2].map(|c| (var(6 * k + 3 + c), unit(c).cross(e))),
                )
            }
        }
    }

    /// Velocity of the centre of mass.
    pub fn cm_velocity<R: Real>(&self, b: Body) -> V3<R> {
        match b {
            Body::Ground => V3::zero(),
            Body::Part(k) => {
                let v = self.velocities[k].0;
                if !R::GRADIENT {
                    return V3::constant(v);
                }
                let n = self.nparts();
                V3::lift(v, &[0, 1, 2].map(|c| (var(6 * n + 6 * k + c), unit(c))))
            }
        }
    }

    /// Angular velocity.
    pub fn omega<R: Real>(&self, b: Body) -> V3<R> {
        match b {
            Body::Ground => V3::zero(),
            Body::Part(k) => {
                let w = self.velocities[k].1;
                if !R::GRADIENT {
                    return V3::constant(w);
                }
                let n = self.nparts();
                V3::lift(w, &[0, 1, 2].map(|c| (var(6 * n + 6 * k + 3 + c), unit(c))))
            }
        }
    }

    /// A body-fixed point in ground.
    pub fn point<R: Real>(&self, p: &BodyPoint) -> V3<R> {
        self.cm::<R>(p.body).add(&self.rotated(p.body, p.p_b))
    }

    /// Velocity of a body-fixed point: `v + ω × R·p_b`.
    pub fn point_velocity<R: Real>(&self, p: &BodyPoint) -> V3<R> {
        let arm = self.rotated::<R>(p.body, p.p_b);
        self.cm_velocity::<R>(p.body)
            .add(&self.omega::<R>(p.body).cross(&arm))
    }

    /// A body-fixed direction in ground.
    pub fn dir<R: Real>(&self, d: &BodyDir) -> V3<R> {
        self.rotated(d.body, d.v_b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Pose;
    use glam::DMat3;

    #[test]
    fn dual_atan2_and_shift_have_exact_derivatives() {
        let s = Dual::variable(0.3, 0);
        let c = Dual::variable(-0.7, 1);
        let a = <Dual as Real>::atan2(&s, &c);
        assert!((a.value() - 0.3f64.atan2(-0.7)).abs() < 1e-15);
        let den = 0.3 * 0.3 + 0.7 * 0.7;
        assert!((a.derivative(0) - (-0.7 / den)).abs() < 1e-15);
        assert!((a.derivative(1) - (-0.3 / den)).abs() < 1e-15);
        let b = s.shift(2.0);
        assert_eq!((b.value(), b.derivative(0)), (2.3, 1.0));
    }

    #[test]
    fn lifted_point_velocity_has_the_rigid_body_partials() {
        let state = State {
            poses: vec![Pose {
                p: DVec3::new(1.0, 2.0, 3.0),
                r: DMat3::from_rotation_z(0.4),
            }],
            time: 0.0,
            controls: Default::default(),
            elements: Default::default(),
        };
        let v = [(DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.5, -0.4, 0.2))];
        let kin = Kinematics {
            state: &state,
            velocities: &v,
        };
        let p = BodyPoint {
            body: Body::Part(0),
            p_b: DVec3::new(0.5, 0.0, -1.0),
        };
        let vp: V3<Dual> = kin.point_velocity(&p);
        let u = state.poses[0].r * p.p_b;
        let w = v[0].1;
        assert!((vp.value() - (v[0].0 + w.cross(u))).length() < 1e-15);
        // ∂v_P/∂δθ_c = ω × (e_c × u); ∂v_P/∂ω_c = e_c × u; ∂v_P/∂v_c = e_c.
        for c in 0..3 {
            let dth = w.cross(unit(c).cross(u));
            let dw = unit(c).cross(u);
            let got =
                |i: u32| DVec3::new(vp.x.derivative(i), vp.y.derivative(i), vp.z.derivative(i));
            assert!((got(3 + c as u32) - dth).length() < 1e-15);
            assert!((got(9 + c as u32) - dw).length() < 1e-15);
            assert!((got(6 + c as u32) - unit(c)).length() < 1e-15);
        }
        let plain: V3<f64> = kin.point_velocity(&p);
        assert_eq!(plain.value(), vp.value());
    }
}
