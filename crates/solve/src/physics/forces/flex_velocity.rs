//! The quadratic velocity terms of a flex body's inertia coupling (the mass matrix's part is
//! `physics::flex_inertia`; the kinetic energy in `linkage_model::flex_bodies`).
//!
//! Lagrange's equations in the body's axes (Kirchhoff's form for the reference body, whose
//! kinetic energy depends on q but not on its pose) with `ω` the angular velocity and `c`
//! the undeformed centre of mass in BCS axes, `d = I3·q`, `e = I3·q̇`,
//! `ΔJ = Σ_j q_j L_j − Σ_jk q_j q_k I9_jk`, `∂_j ΔJ = L_j − Σ_k q_k (I9_jk + I9_kj)`,
//! `J̇ = Σ_j q̇_j ∂_j ΔJ`, `K_j = K_j(0) + Σ_k q_k I5_kj` give the velocity terms of the
//! inertial forces beyond a rigid body's `ω × I_cm ω`:
//!
//! ```text
//! force on the reference body (at its CM):   F = A·(ω × (ω × d) + 2 ω × e)
//! torque on the reference body:              T = A·(J̇ω + Σ_jk q̇_j q̇_k I5_kj + ω × (ΔJ ω + Σ_j q̇_j K_j))
//! generalized force on mode j:               F_j = Σ_k q̇_k ω·(I5_kj − I5_jk) − ½ ωᵀ(∂_j ΔJ)ω
//! ```
//!
//! They enter as loads `−F`, `−T` and `−F_j·axis` (on the mode body), divided by the UCF
//! (force units, as every element). Written once over [`Real`], so the integrators, statics
//! and linear get their exact derivatives in A, ω, q and q̇. One element per body acts on the
//! reference body, one per mode on its mode body.

use super::algebra::{Real, V3};
use super::{Context, Load, Loads};
use crate::physics::applied::LawError;
use crate::physics::flex_inertia::FlexTerms;
use glam::{DMat3, DVec3};
use linkage_model::Body;
use std::sync::Arc;

/// Which load a [`ModalVelocityLaw`] gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// The force and torque on the reference body.
    Reference,
    /// The generalized force on mode j.
    Mode(usize),
}

/// The quadratic velocity terms of one flex body, on its reference body or one mode.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalVelocityLaw {
    pub terms: Arc<FlexTerms>,
    pub target: Target,
    /// `1 / UCF`.
    pub per_ucf: f64,
}

/// `M·v` for a constant matrix.
fn apply<R: Real>(m: &DMat3, v: &V3<R>) -> V3<R> {
    V3::constant(m.x_axis)
        .times(&v.x)
        .add(&V3::constant(m.y_axis).times(&v.y))
        .add(&V3::constant(m.z_axis).times(&v.z))
}

/// `Σ_i s_i·u_i` for constant vectors.
fn sum<R: Real>(s: &[R], u: &[DVec3]) -> V3<R> {
    s.iter().zip(u).fold(V3::zero(), |acc, (x, v)| {
        acc.add(&V3::constant(*v).times(x))
    })
}

impl ModalVelocityLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let t = &*self.terms;
        let reference = Body::Part(t.reference);
        let axes = [DVec3::X, DVec3::Y, DVec3::Z].map(|e| kin.rotated::<R>(reference, e));
        let w_ground = kin.omega::<R>(reference);
        let w = V3 {
            x: w_ground.dot(&axes[0]),
            y: w_ground.dot(&axes[1]),
            z: w_ground.dot(&axes[2]),
        };
        let axis = V3::constant(t.axis);
        let q: Vec<R> = t
            .modes
            .iter()
            .map(|&p| {
                kin.cm::<R>(Body::Part(p))
                    .sub(&V3::constant(t.rest))
                    .dot(&axis)
            })
            .collect();
        let qd: Vec<R> = t
            .modes
            .iter()
            .map(|&p| kin.cm_velocity::<R>(Body::Part(p)).dot(&axis))
            .collect();
        // (∂_j ΔJ)·ω.
        let dj_w = |j: usize| -> V3<R> {
            let mut out = apply(&t.l[j], &w);
            if let Some(row) = t.i9.get(j) {
                for (k, x) in row.iter().enumerate() {
                    let sym = *x + t.i9[k][j];
                    out = out.sub(&apply(&sym, &w).times(&q[k]));
                }
            }
            out
        };
        let half = R::cst(0.5);
        match self.target {
            Target::Reference => {
                let d = sum(&q, &t.i3);
                let e = sum(&qd, &t.i3);
                let two = R::cst(2.0);
                let force_b = w.cross(&w.cross(&d)).add(&w.cross(&e).times(&two));
                // ΔJ ω, J̇ ω, Σ q̇_j K_j and Σ q̇_j q̇_k I5_kj.
                let mut dj = V3::zero();
                let mut jdot = V3::zero();
                let mut kq = V3::zero();
                for j in 0..t.modes.len() {
                    dj = dj.add(&apply(&t.l[j], &w).times(&q[j]));
                    jdot = jdot.add(&dj_w(j).times(&qd[j]));
                    let mut kj = V3::constant(t.k0[j]);
                    for (k, row) in t.i5.iter().enumerate() {
                        kj = kj.add(&V3::constant(row[j]).times(&q[k]));
                    }
                    kq = kq.add(&kj.times(&qd[j]));
                }
                for (j, row) in t.i9.iter().enumerate() {
                    for (k, x) in row.iter().enumerate() {
                        dj = dj.sub(&apply(x, &w).times(&q[j].mul(&q[k])));
                    }
                }
                let mut kdot = V3::zero();
                for (k, row) in t.i5.iter().enumerate() {
                    for (j, x) in row.iter().enumerate() {
                        kdot = kdot.add(&V3::constant(*x).times(&qd[j].mul(&qd[k])));
                    }
                }
                let torque_b = jdot.add(&kdot).add(&w.cross(&dj.add(&kq)));
                let scale = R::cst(-self.per_ucf);
                let to_ground =
                    |v: &V3<R>| V3::combine(&axes, &[v.x.clone(), v.y.clone(), v.z.clone()]);
                let force = to_ground(&force_b).times(&scale);
                let torque = to_ground(&torque_b).times(&scale);
                Ok([
                    Some(Load {
                        body: reference,
                        point: kin.cm::<R>(reference),
                        force,
                        torque,
                    }),
                    None,
                ])
            }
            Target::Mode(j) => {
                let mut g = w.dot(&dj_w(j)).mul(&half).neg();
                for (k, row) in t.i5.iter().enumerate() {
                    let skew_part = row[j] - t.i5[j][k];
                    g = g.add(&w.dot(&V3::constant(skew_part)).mul(&qd[k]));
                }
                let mode = Body::Part(t.modes[j]);
                let f = axis.times(&g.scale(-self.per_ucf));
                Ok([Some(Load::force(mode, kin.cm::<R>(mode), f)), None])
            }
        }
    }
}
