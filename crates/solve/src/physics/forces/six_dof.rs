//! BUSHING, FIELD and BEAM: a linear 6-component spring-damper between the I and J frames.
//!
//! Coordinates of I relative to J (ADM-REFERENCE §2.10, Adams BUSHING/FIELD statements):
//!
//! ```text
//! q = [x, y, z, a, b, c]
//!   x, y, z = DX, DY, DZ(I, J, J) = (P_i − P_j)·{x_j, y_j, z_j}
//!   a = AX(I,J) = atan2(−z_i·y_j, z_i·z_j)   (small-angle rotation about x_j)
//!   b = AY(I,J) = atan2( z_i·x_j, z_i·z_j)   (about y_j)
//!   c = AZ(I,J) = atan2( x_i·y_j, x_i·x_j)   (about z_j)
//! q̇ = [ẋ, ẏ, ż, ωx, ωy, ωz]
//!   ẋ, ẏ, ż   = VX, VY, VZ(I, J, J, J): the velocity of I relative to J *as seen from J*,
//!               (v_Pi − v_Pj − ω_j × (P_i − P_j))·{x_j, y_j, z_j}, the rate of x, y, z
//!   ωx, ωy, ωz = WX, WY, WZ(I, J, J) = (ω_i − ω_j)·{x_j, y_j, z_j}
//! ```
//!
//! Generalised load, components along J's axes:
//!
//! ```text
//! [Fx Fy Fz Tx Ty Tz]ᵀ = −K·(q − q₀) − C·q̇ + F₀
//! F = Fx·x_j + Fy·y_j + Fz·z_j on I's body at P_i,  T = Tx·x_j + … on I's body;
//! −F on J's body at P_i and −T on J's body (moment about J's origin: −T − (P_i − P_j) × F).
//! ```
//!
//! The angle differences `q − q₀` are wrapped to (−π, π]. BUSHING: diagonal K, C, `q₀ = 0`,
//! `F₀ = [FORCE, TORQUE]`. FIELD: full K and C (`CMATRIX`, or `CRATIO·K`), `q₀ = LENGTH`,
//! `F₀ = FORCE`. BEAM: see [`super::beam`].

use super::algebra::{Real, V3};
use super::scalar::{angle, wrap_offset};
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyFrame;
use crate::physics::applied::LawError;
use linkage_model::forces::{Bushing, Field};

/// `F = −K·(q − q₀) − C·q̇ + F₀` between frames I and J.
#[derive(Clone, Debug, PartialEq)]
pub struct SixDofLaw {
    pub i: BodyFrame,
    pub j: BodyFrame,
    /// `stiffness[r][c]`, rows and columns in the order x, y, z, a, b, c.
    pub stiffness: [[f64; 6]; 6],
    pub damping: [[f64; 6]; 6],
    /// `q₀`: the undeformed coordinates.
    pub reference: [f64; 6],
    /// `F₀`: the load at `q = q₀`, `q̇ = 0`.
    pub preload: [f64; 6],
}

/// Where I is relative to J, in J's axes (see the module docs).
#[derive(Clone, Debug)]
pub struct Coordinates<R> {
    /// `q − q₀` (angle differences wrapped to (−π, π]).
    pub deflection: [R; 6],
    /// `q̇`.
    pub rates: [R; 6],
    /// x_j, y_j, z_j in ground.
    pub axes: [V3<R>; 3],
    /// I's origin in ground (the point of application).
    pub p_i: V3<R>,
}

fn diagonal(t: [f64; 3], r: [f64; 3]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    for c in 0..3 {
        m[c][c] = t[c];
        m[3 + c][3 + c] = r[c];
    }
    m
}

impl SixDofLaw {
    pub fn bushing(i: BodyFrame, j: BodyFrame, b: &Bushing) -> SixDofLaw {
        let mut preload = [0.0; 6];
        preload[..3].copy_from_slice(&b.force);
        preload[3..].copy_from_slice(&b.torque);
        SixDofLaw {
            i,
            j,
            stiffness: diagonal(b.stiffness, b.rotational_stiffness),
            damping: diagonal(b.damping, b.rotational_damping),
            reference: [0.0; 6],
            preload,
        }
    }

    pub fn field(i: BodyFrame, j: BodyFrame, f: &Field) -> SixDofLaw {
        SixDofLaw {
            i,
            j,
            stiffness: f.stiffness,
            damping: f.damping,
            reference: f.length,
            preload: f.force,
        }
    }

    /// The coordinates `q − q₀`, their rates `q̇`, J's axes and I's origin.
    pub fn coordinates<R: Real>(&self, cx: &Context) -> Result<Coordinates<R>, LawError> {
        let kin = &cx.kin;
        let (pi_b, pj_b) = (self.i.origin(), self.j.origin());
        let ej = [0, 1, 2].map(|k| kin.dir::<R>(&self.j.axis(k)));
        let (xi, zi) = (kin.dir::<R>(&self.i.axis(0)), kin.dir::<R>(&self.i.axis(2)));
        let pi = kin.point::<R>(&pi_b);
        let d = pi.sub(&kin.point::<R>(&pj_b));
        let wj = kin.omega::<R>(self.j.body);
        let v_rel = kin
            .point_velocity::<R>(&pi_b)
            .sub(&kin.point_velocity::<R>(&pj_b))
            .sub(&wj.cross(&d));
        let w_rel = kin.omega::<R>(self.i.body).sub(&wj);
        let [xj, yj, zj] = &ej;
        let a = angle("AX(I,J)", &zi, zj, &yj.neg())?;
        let b = angle("AY(I,J)", &zi, zj, xj)?;
        let c = angle("AZ(I,J)", &xi, xj, yj)?;
        let q = [d.dot(xj), d.dot(yj), d.dot(zj), a, b, c];
        let mut dq: [R; 6] = std::array::from_fn(|r| q[r].shift(-self.reference[r]));
        for x in dq.iter_mut().skip(3) {
            *x = x.shift(wrap_offset(x.value()));
        }
        let rates = [
            v_rel.dot(xj),
            v_rel.dot(yj),
            v_rel.dot(zj),
            w_rel.dot(xj),
            w_rel.dot(yj),
            w_rel.dot(zj),
        ];
        Ok(Coordinates {
            deflection: dq,
            rates,
            axes: ej,
            p_i: pi,
        })
    }

    /// `−K·(q − q₀) − C·q̇ + F₀`, components along J's axes.
    pub fn generalised<R: Real>(&self, c: &Coordinates<R>) -> [R; 6] {
        std::array::from_fn(|r| {
            let mut g = R::cst(self.preload[r]);
            for k in 0..6 {
                let (stiff, damp) = (self.stiffness[r][k], self.damping[r][k]);
                if stiff != 0.0 {
                    g = g.sub(&c.deflection[k].scale(stiff));
                }
                if damp != 0.0 {
                    g = g.sub(&c.rates[k].scale(damp));
                }
            }
            g
        })
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let c = self.coordinates::<R>(cx)?;
        let g = self.generalised(&c);
        Ok(self.apply(c, g))
    }

    /// The loads of generalised components `g` (along J's axes): on I's body at I's origin,
    /// the reaction on J's body at the same point.
    pub fn apply<R: Real>(&self, c: Coordinates<R>, g: [R; 6]) -> Loads<R> {
        let [fx, fy, fz, tx, ty, tz] = g;
        let force = V3::combine(&c.axes, &[fx, fy, fz]);
        let torque = V3::combine(&c.axes, &[tx, ty, tz]);
        let reaction = Load {
            body: self.j.body,
            point: c.p_i.clone(),
            force: force.neg(),
            torque: torque.neg(),
        };
        [
            Some(Load {
                body: self.i.body,
                point: c.p_i,
                force,
                torque,
            }),
            Some(reaction),
        ]
    }
}
