//! CONTACT: unilateral forces between the geometries of two parts (ADM-ELEMENTS §1).
//!
//! At each evaluation the geometry adapter ([`geometry`], parry3d-f64) finds the *incidents*
//! between every I geometry and every J geometry: connected regions of penetration, each
//! with its distinct penetrating points (a material point of each body and its depth) and
//! the normal `n` (from J towards I) at its deepest point. Then, per incident (Adams computes
//! one contact force per incident):
//!
//! - the penetration `g` and its rate `ġ` are those of the deepest point:
//!   `g = (P_j − P_i)·n`, `ġ = (v_Pj − v_Pi)·n + (P_j − P_i)·(ω_j × n)`, with `P_i` the
//!   material point of I deepest inside J, `P_j` its match on J's surface and `n` fixed in J
//!   (on a sphere the point is `centre ∓ r·n`: it does not turn with the sphere);
//! - the normal force `Fn(g, ġ)` is the IMPACT or POISSON law ([`laws`]);
//! - friction (if on) opposes the slip velocity `v_t` of I on J at the incident,
//!   `v = Σ w_k (v_Pi,k − v_Pj,k)`, `v_t = v − (v·n) n`, with magnitude `μ(|v_t|)·Fn`;
//! - the incident's force `Fn·n + F_t` is shared among its points in proportion to
//!   `w_k = g_k^e / Σ g^e` (e the IMPACT exponent, 1 for POISSON) and applied at each point
//!   `P_i,k` of I: +share on I, −share on J at the same point (zero net force and moment). A box resting flat on a plane therefore carries its whole weight
//!   through one incident, `k·g^e = m·g`, spread evenly over its four corners.
//!
//! Derivatives: the points are material points of each body and `n` a direction fixed in J,
//! lifted by [`Kinematics`], so the Jacobians are exact for the frozen contact features
//! (vertex–face contacts; for smooth surfaces the feature moves to second order only). The
//! choice of the deepest point and the incident grouping are held fixed while differentiating.
//!
//! Friction mode: `ON` and `DYNAMICS_ONLY` use the same law. The force depends on slip
//! velocity only, so it is zero in static equilibrium either way; linearization includes its
//! damping `∂F/∂v` for both.

pub mod geometry;
pub mod laws;

use super::algebra::{Kinematics, Real, V3};
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyPoint;
use crate::physics::applied::LawError;
use geometry::{body_placement, Incident, Placed};
use glam::DVec3;
use linkage_adm::contact::{Friction, NormalLaw};
use linkage_model::contacts::Contact;
use linkage_model::{Body, Model};

/// Points of one incident closer than this (× the characteristic length) are one point.
pub const POINT_MERGE: f64 = 1e-9;

/// The law of one CONTACT.
#[derive(Clone, Debug)]
pub struct ContactLaw {
    pub body_i: Body,
    pub body_j: Body,
    pub i: Vec<Placed>,
    pub j: Vec<Placed>,
    pub normal: NormalLaw,
    pub friction: Friction,
    /// Points closer than this are one ([`POINT_MERGE`] × characteristic length).
    pub merge: f64,
}

/// Why a CONTACT has no law.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A geometry the geometry library cannot shape.
    #[error("GRAPHICS/{graphic}: {why}")]
    Shape {
        graphic: u64,
        why: geometry::ShapeError,
    },
    /// A pair of shapes the geometry library cannot collide (two planes).
    #[error(
        "GRAPHICS/{} and GRAPHICS/{}: contact between a {} and a {} is not computed by the \
         geometry library",
        .graphics.0, .graphics.1, .shapes.0, .shapes.1
    )]
    Unsupported {
        graphics: (u64, u64),
        shapes: (String, String),
    },
}

impl ContactLaw {
    /// The law of contact `c` of `model`; an error names a geometry parry cannot shape or a
    /// pair of geometries it cannot collide (two planes).
    pub fn new(model: &Model, c: &Contact) -> Result<ContactLaw, ContactError> {
        let place = |g: &linkage_model::contacts::ContactGeometry| {
            geometry::place(model, g).map_err(|why| ContactError::Shape {
                graphic: g.graphic,
                why,
            })
        };
        let i = c
            .i_geometries
            .iter()
            .map(place)
            .collect::<Result<Vec<_>, _>>()?;
        let j = c
            .j_geometries
            .iter()
            .map(place)
            .collect::<Result<Vec<_>, _>>()?;
        for a in &i {
            for b in &j {
                if !geometry::supported(a, b) {
                    return Err(ContactError::Unsupported {
                        graphics: (a.graphic, b.graphic),
                        shapes: (
                            format!("{:?}", a.shape.shape_type()),
                            format!("{:?}", b.shape.shape_type()),
                        ),
                    });
                }
            }
        }
        Ok(ContactLaw {
            body_i: model.markers[c.i].body,
            body_j: model.markers[c.j].body,
            i,
            j,
            normal: c.normal.clone(),
            friction: c.friction.clone(),
            merge: POINT_MERGE * model.characteristic_length,
        })
    }

    /// The incidents at the positions of `kin` (values only).
    pub fn incidents(&self, kin: &Kinematics) -> Vec<Incident> {
        let (pi, pj) = (
            body_placement(kin.state, self.body_i),
            body_placement(kin.state, self.body_j),
        );
        let mut out = Vec::new();
        for a in &self.i {
            for b in &self.j {
                geometry::incidents(a, &pi, b, &pj, self.merge, &mut out);
            }
        }
        out
    }

    /// The loads on I's body and J's body (sums over incidents and points, see the module
    /// docs); `[None, None]` when nothing penetrates.
    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let incidents = self.incidents(kin);
        if incidents.is_empty() {
            return Ok([None, None]);
        }
        let mut at: Option<V3<R>> = None;
        let mut force = V3::<R>::zero();
        let mut torque = V3::<R>::zero();
        for inc in &incidents {
            for (point, f) in self.incident_forces::<R>(kin, inc) {
                let origin = at.get_or_insert_with(|| point.clone()).clone();
                torque = torque.add(&point.sub(&origin).cross(&f));
                force = force.add(&f);
            }
        }
        let Some(origin) = at else {
            return Ok([None, None]);
        };
        let on_i = Load {
            body: self.body_i,
            point: origin.clone(),
            force: force.clone(),
            torque: torque.clone(),
        };
        let on_j = Load {
            body: self.body_j,
            point: origin,
            force: force.neg(),
            torque: torque.neg(),
        };
        Ok([Some(on_i), Some(on_j)])
    }

    /// The force on I at each point of an incident (ground axes, application point).
    fn incident_forces<R: Real>(&self, kin: &Kinematics, inc: &Incident) -> Vec<(V3<R>, V3<R>)> {
        let material = |body: Body, p_b: DVec3| BodyPoint { body, p_b };
        let n = kin.rotated::<R>(self.body_j, inc.normal_j);
        let e = laws::share_exponent(&self.normal);
        struct Pt<R> {
            pi: V3<R>,
            pj: V3<R>,
            g: R,
            share: R,
        }
        let mut pts: Vec<Pt<R>> = Vec::with_capacity(inc.points.len());
        // Contact points: material points, or a sphere's centre ∓ r·n.
        let at_i = |p: &geometry::IncidentPoint| {
            kin.point::<R>(&material(self.body_i, p.on_i))
                .sub(&n.times(&R::cst(p.r_i)))
        };
        let at_j = |p: &geometry::IncidentPoint| {
            kin.point::<R>(&material(self.body_j, p.on_j))
                .add(&n.times(&R::cst(p.r_j)))
        };
        for p in &inc.points {
            let pi = at_i(p);
            let pj = at_j(p);
            let g = pj.sub(&pi).dot(&n);
            let share = if g.value() > 0.0 {
                laws::pow(&g, e)
            } else {
                R::cst(0.0)
            };
            pts.push(Pt { pi, pj, g, share });
        }
        let total = pts.iter().fold(R::cst(0.0), |s, p| s.add(&p.share));
        if total.value() <= 0.0 {
            return Vec::new();
        }
        let g = pts[inc.deepest].g.clone();
        if g.value() <= 0.0 {
            return Vec::new();
        }
        // Velocity of the material point of body b at the place `at`: v + ω × (at − c).
        let velocity = |b: Body, at: &V3<R>| {
            kin.cm_velocity::<R>(b)
                .add(&kin.omega::<R>(b).cross(&at.sub(&kin.cm::<R>(b))))
        };
        let vi = velocity(self.body_i, &pts[inc.deepest].pi);
        let vj = velocity(self.body_j, &pts[inc.deepest].pj);
        let w_j = kin.omega::<R>(self.body_j);
        let gap = pts[inc.deepest].pj.sub(&pts[inc.deepest].pi);
        let gdot = vj.sub(&vi).dot(&n).add(&gap.dot(&w_j.cross(&n)));
        let fn_ = laws::normal_force(&self.normal, &g, &gdot);
        if fn_.value() <= 0.0 {
            return Vec::new();
        }
        let weights: Vec<R> = pts.iter().map(|p| p.share.div(&total)).collect();
        let mut f = n.times(&fn_);
        if self.friction.mode != linkage_adm::contact::FrictionMode::Off {
            let mut v = V3::<R>::zero();
            for (p, w) in pts.iter().zip(&weights) {
                let vi = velocity(self.body_i, &p.pi);
                let vj = velocity(self.body_j, &p.pj);
                v = v.add(&vi.sub(&vj).times(w));
            }
            let v_t = v.sub(&n.times(&v.dot(&n)));
            if let Some(ft) = laws::friction_force(&self.friction, &fn_, &v_t) {
                f = f.add(&ft);
            }
        }
        pts.iter()
            .zip(&weights)
            .map(|(p, w)| (p.pi.clone(), f.times(w)))
            .collect()
    }
}
