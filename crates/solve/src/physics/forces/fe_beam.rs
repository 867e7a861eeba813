//! FE_PART elements (ADM-ELEMENTS §18; the model side in `linkage_model::fe_parts`): a
//! corotational 3-D Euler–Bernoulli beam between two node bodies, the mass-proportional part
//! of the Rayleigh damping on each node, and FE_LOAD lumped on the nodes.
//!
//! **Kinematics** (large rotations, small strains per element; Crisfield, *Non-linear Finite
//! Element Analysis of Solids and Structures*, vol. 2, 1997, ch. 17, the corotational idea).
//! Node frames carry the element's reference frame E₀: `F_a = R_a·(R_aᵀE₀)`, `F_b` likewise,
//! equal to E₀ at the input. The corotated frame E follows the element:
//!
//! ```text
//! e₁ = (p_b − p_a)/l,   e₃ = e₁ × (f_a2 + f_b2) / |…|,   e₂ = e₃ × e₁
//! u  = l − L₀                                              (axial stretch)
//! θ  = ( e₃·f₂ − e₂·f₃ ,  e₁·f₃ − e₃·f₁ ,  e₂·f₁ − e₁·f₂ ) / 2   for F = F_a, F_b
//! ```
//!
//! θ is the rotation of the node frame relative to E (sin of the angle times the axis, exact
//! to O(θ³), so per-element rotations stay small while the beam turns arbitrarily).
//!
//! **Local law** (the exact Euler–Bernoulli element, e.g. Przemieniecki 1968 §5.6), loads
//! the nodes apply to the element, in E's axes; with `D = [[E·Iyy, −E·Iyz], [−E·Iyz, E·Izz]]`
//! on the (y, z) components:
//!
//! ```text
//! N   = E·A·u/L₀                 (3DCABLE: only when u > 0, a cable does not push)
//! T   = G·J·(θ_bx − θ_ax)/L₀     M_a = D·(4θ_a + 2θ_b)/L₀,  M_b = D·(2θ_a + 4θ_b)/L₀
//! F_b = (N, −(M_az + M_bz)/l, (M_ay + M_by)/l),   F_a = −F_b
//! ```
//!
//! the shear forces from the element's moment equilibrium at its current length, so the
//! loads have zero net force and moment for any motion (objectivity). The loads on the nodes
//! are the opposites: `−F_b, −(T, M_b)` on b, `−F_a, −(−T, M_a)` on a. 3DCABLE has no
//! bending or torsion (T = M = 0) [decided].
//!
//! **Damping** `C = CRATIOM·M + CRATIOK·K`: the stiffness part replaces `u, θ` by
//! `u + β·u̇, θ + β·θ̇` (β = CRATIOK) with the deformation rates `u̇ = e₁·(v_b − v_a)`,
//! `θ̇ = Eᵀ(ω − ω_E)`, `ω_E = e₁ × (v_b − v_a)/l + e₁·(e₁·(ω_a + ω_b)/2)` (zero for a rigid
//! motion of the element); the mass part is `−α·m·v`, `−α·I_G·ω` on each node (α = CRATIOM,
//! [`NodeDampingLaw`]).
//!
//! Everything is generic over [`Real`], so the tangent stiffness the statics, linearization
//! and integrators need is the exact derivative of these loads.

use super::algebra::{Real, V3};
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyFrame;
use crate::physics::applied::LawError;
use glam::{DMat3, DVec3};
use linkage_expr::Expr;
use linkage_model::fe_parts::{FeElement, FeKind, FePart};
use linkage_model::Body;

/// One beam element between node bodies `a` and `b`.
#[derive(Clone, Debug, PartialEq)]
pub struct BeamElementLaw {
    pub a: Body,
    pub b: Body,
    /// E₀ in node a's and b's body axes.
    pub r_a_e: DMat3,
    pub r_b_e: DMat3,
    /// L₀.
    pub length: f64,
    /// E·A.
    pub axial: f64,
    /// G·J (0 for a cable).
    pub torsion: f64,
    /// D = [[E·Iyy, −E·Iyz], [−E·Iyz, E·Izz]] (0 for a cable).
    pub bending: [[f64; 2]; 2],
    /// 3DCABLE: tension only.
    pub tension_only: bool,
    /// β = CRATIOK.
    pub cratiok: f64,
}

impl BeamElementLaw {
    /// The law of element `e` of FE part `p`.
    pub fn new(p: &FePart, e: &FeElement) -> BeamElementLaw {
        let s = &e.section;
        let (ey, g) = (p.youngs_modulus, p.shear_modulus);
        let cable = p.kind == FeKind::Cable3d;
        let bending = if cable {
            [[0.0; 2]; 2]
        } else {
            [[ey * s.iyy, -ey * s.iyz], [-ey * s.iyz, ey * s.izz]]
        };
        BeamElementLaw {
            a: Body::Part(p.nodes[e.a].part),
            b: Body::Part(p.nodes[e.b].part),
            r_a_e: e.r_a_e,
            r_b_e: e.r_b_e,
            length: e.length,
            axial: ey * s.area,
            torsion: if cable { 0.0 } else { g * s.jxx },
            bending,
            tension_only: cable,
            cratiok: p.cratiok,
        }
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let (pa, pb) = (kin.cm::<R>(self.a), kin.cm::<R>(self.b));
        let fa = [0, 1, 2].map(|k| kin.rotated::<R>(self.a, self.r_a_e.col(k)));
        let fb = [0, 1, 2].map(|k| kin.rotated::<R>(self.b, self.r_b_e.col(k)));
        let d = pb.sub(&pa);
        let l = d.norm();
        let inv_l = R::cst(1.0).div(&l);
        let e1 = d.times(&inv_l);
        let z = e1.cross(&fa[1].add(&fb[1]));
        let e3 = z.times(&R::cst(1.0).div(&z.norm()));
        let e2 = e3.cross(&e1);
        let e = [e1.clone(), e2.clone(), e3.clone()];
        let theta = |f: &[V3<R>; 3]| -> [R; 3] {
            [
                e[2].dot(&f[1]).sub(&e[1].dot(&f[2])).scale(0.5),
                e[0].dot(&f[2]).sub(&e[2].dot(&f[0])).scale(0.5),
                e[1].dot(&f[0]).sub(&e[0].dot(&f[1])).scale(0.5),
            ]
        };
        let mut u = l.shift(-self.length);
        let mut ta = theta(&fa);
        let mut tb = theta(&fb);
        if self.cratiok > 0.0 {
            let dv = kin
                .cm_velocity::<R>(self.b)
                .sub(&kin.cm_velocity::<R>(self.a));
            let (wa, wb) = (kin.omega::<R>(self.a), kin.omega::<R>(self.b));
            let spin = e1.dot(&wa.add(&wb)).scale(0.5);
            let w_e = e1.cross(&dv).times(&inv_l).add(&e1.times(&spin));
            let rate = |w: &V3<R>| -> [R; 3] {
                let r = w.sub(&w_e);
                [e[0].dot(&r), e[1].dot(&r), e[2].dot(&r)]
            };
            let (ra, rb) = (rate(&wa), rate(&wb));
            let beta = self.cratiok;
            u = u.add(&e1.dot(&dv).scale(beta));
            for c in 0..3 {
                ta[c] = ta[c].add(&ra[c].scale(beta));
                tb[c] = tb[c].add(&rb[c].scale(beta));
            }
        }
        let l0 = self.length;
        let axial = if self.tension_only && u.value() < 0.0 {
            R::cst(0.0)
        } else {
            u.scale(self.axial / l0)
        };
        let torque_x = tb[0].sub(&ta[0]).scale(self.torsion / l0);
        let bend = |x: &[R; 3], y: &[R; 3], row: usize| -> R {
            // (D·(4x + 2y))_row / L₀ over the (y, z) components.
            let c = |k: usize| x[1 + k].scale(4.0).add(&y[1 + k].scale(2.0));
            c(0).scale(self.bending[row][0] / l0)
                .add(&c(1).scale(self.bending[row][1] / l0))
        };
        let (may, maz) = (bend(&ta, &tb, 0), bend(&ta, &tb, 1));
        let (mby, mbz) = (bend(&tb, &ta, 0), bend(&tb, &ta, 1));
        let fby = maz.add(&mbz).mul(&inv_l).neg();
        let fbz = may.add(&mby).mul(&inv_l);
        // Loads on the nodes: the opposites of the element's end loads.
        let force_b = V3::combine(&e, &[axial, fby, fbz]).neg();
        let torque_b = V3::combine(&e, &[torque_x.clone(), mby, mbz]).neg();
        let torque_a = V3::combine(&e, &[torque_x.neg(), may, maz]).neg();
        Ok([
            Some(Load {
                body: self.a,
                point: pa,
                force: force_b.neg(),
                torque: torque_a,
            }),
            Some(Load {
                body: self.b,
                point: pb,
                force: force_b,
                torque: torque_b,
            }),
        ])
    }
}

/// Mass-proportional Rayleigh damping on one node: `F = −α·m·v`, `T = −α·R·I·Rᵀ·ω`.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeDampingLaw {
    pub body: Body,
    /// α = CRATIOM.
    pub cratiom: f64,
    pub mass: f64,
    /// Rotary inertia in the node's body axes.
    pub inertia: DMat3,
}

impl NodeDampingLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let axes = [DVec3::X, DVec3::Y, DVec3::Z].map(|v| kin.rotated::<R>(self.body, v));
        let w = kin.omega::<R>(self.body);
        let w_b = [axes[0].dot(&w), axes[1].dot(&w), axes[2].dot(&w)];
        let t_b: [R; 3] = std::array::from_fn(|r| {
            (0..3).fold(R::cst(0.0), |acc, c| {
                acc.add(&w_b[c].scale(self.inertia.col(c)[r]))
            })
        });
        let torque = V3::combine(&axes, &t_b).scale_by(-self.cratiom);
        let force = kin
            .cm_velocity::<R>(self.body)
            .scale_by(-self.cratiom * self.mass);
        Ok([
            Some(Load {
                body: self.body,
                point: kin.cm::<R>(self.body),
                force,
                torque,
            }),
            None,
        ])
    }
}

/// FE_LOAD on one node: force and torque per unit length along RM's axes times the node's
/// tributary length (FE_LOAD's extent along the beam and the per-length scaling are
/// [unconfirmed]; linkage spreads it uniformly over the whole part).
#[derive(Clone, Debug)]
pub struct NodeLoadLaw {
    pub body: Body,
    pub tributary: f64,
    pub rm: Option<BodyFrame>,
    pub force: [Option<Expr>; 3],
    pub torque: [Option<Expr>; 3],
}

const NAMES: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];

impl NodeLoadLaw {
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let axes = match &self.rm {
            Some(rm) => [0, 1, 2].map(|k| kin.dir::<R>(&rm.axis(k))),
            None => [DVec3::X, DVec3::Y, DVec3::Z].map(V3::constant),
        };
        let mut c: [R; 6] = std::array::from_fn(|_| R::cst(0.0));
        for (k, e) in self.force.iter().chain(&self.torque).enumerate() {
            if let Some(e) = e {
                c[k] = R::evaluate(e, cx.env)
                    .map_err(|err| LawError::Expression {
                        argument: NAMES[k],
                        cause: err.message,
                    })?
                    .scale(self.tributary);
            }
        }
        let [fx, fy, fz, tx, ty, tz] = c;
        Ok([
            Some(Load {
                body: self.body,
                point: kin.cm::<R>(self.body),
                force: V3::combine(&axes, &[fx, fy, fz]),
                torque: V3::combine(&axes, &[tx, ty, tz]),
            }),
            None,
        ])
    }
}

impl<R: Real> V3<R> {
    /// `c · self` for a constant c.
    fn scale_by(&self, c: f64) -> Self {
        V3 {
            x: self.x.scale(c),
            y: self.y.scale(c),
            z: self.z.scale(c),
        }
    }
}
