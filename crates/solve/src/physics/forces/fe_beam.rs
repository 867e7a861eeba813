//! FE_PART elements (ADM-ELEMENTS §18; the model side in `linkage_model::fe_parts`): a
//! corotational 3-D Euler–Bernoulli beam between two node bodies, the mass-proportional part
//! of the Rayleigh damping on each node, and FE_LOAD lumped on the nodes.
//!
//! **Elements**: the corotational Euler–Bernoulli beam of [`super::corotational`] (its
//! kinematics, local law and stiffness-proportional damping), with the node frames carrying
//! the element's reference frame E₀: `F_a = R_a·(R_aᵀE₀)`, `F_b` likewise, equal to E₀ at
//! the input. 3DCABLE has no bending or torsion (T = M = 0) and is tension-only [decided].
//!
//! **Damping** `C = CRATIOM·M + CRATIOK·K`: the stiffness part is the kernel's (β =
//! CRATIOK); the mass part is `−α·m·v`, `−α·I_G·ω` on each node (α = CRATIOM,
//! [`NodeDampingLaw`]).
//!
//! Everything is generic over [`Real`], so the tangent stiffness the statics, linearization
//! and integrators need is the exact derivative of these loads.

use super::algebra::{Real, V3};
use super::corotational::{End, Rates, Section};
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
    /// Length, section stiffness, cable flag and β = CRATIOK.
    pub section: Section,
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
            section: Section {
                length: e.length,
                axial: ey * s.area,
                torsion: if cable { 0.0 } else { g * s.jxx },
                bending,
                tension_only: cable,
                cratiok: p.cratiok,
            },
        }
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let end = |body: Body, r: &DMat3| End {
            p: kin.cm::<R>(body),
            frame: [0, 1, 2].map(|k| kin.rotated::<R>(body, r.col(k))),
        };
        let (a, b) = (end(self.a, &self.r_a_e), end(self.b, &self.r_b_e));
        let out = self.section.loads(&a, &b, || Rates {
            dv: kin
                .cm_velocity::<R>(self.b)
                .sub(&kin.cm_velocity::<R>(self.a)),
            wa: kin.omega::<R>(self.a),
            wb: kin.omega::<R>(self.b),
        });
        Ok([
            Some(Load {
                body: self.a,
                point: a.p,
                force: out.force_b.neg(),
                torque: out.torque_a,
            }),
            Some(Load {
                body: self.b,
                point: b.p,
                force: out.force_b,
                torque: out.torque_b,
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
