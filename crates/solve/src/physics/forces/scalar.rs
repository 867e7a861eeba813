//! SFORCE and SPRINGDAMPER: one scalar f acting along the line J→I, or a torque about z_j.
//!
//! Translational (`d = P_i − P_j`, `u = d/|d|`, f > 0 repels):
//! - action–reaction: `F = f·u` on I's body at `P_i`, `−F` on J's body at `P_j`. The pair
//!   has zero net force and, the forces being collinear with `P_i − P_j`, zero net moment.
//! - ACTIONONLY: `F = f·z_j` on I's body at `P_i`, nothing on J (J only gives the direction).
//!
//! Rotational: `T = f·z_j` on I's body and `−T` on J's (none with ACTIONONLY).
//!
//! SFORCE: `f` is the FUNCTION expression. SPRINGDAMPER (ADM-REFERENCE §2.10):
//! - translational `f = −C·VR(I,J) − K·(DM(I,J) − LENGTH) + FORCE`, with
//!   `DM = |d|`, `VR = (v_Pi − v_Pj)·u`;
//! - rotational `T = −CT·WZ(I,J,J) − KT·(AZ(I,J) − ANGLE) + TORQUE`, with
//!   `WZ(I,J,J) = (ω_i − ω_j)·z_j` and `AZ(I,J) = atan2(x_i·y_j, x_i·x_j)`. The twist
//!   `AZ − ANGLE` is wrapped to (−π, π]: linkage measures the principal angle, so a spring
//!   wound more than half a turn from `ANGLE` is not representable (Adams counts turns).
//!
//! When I and J coincide the line J→I is undefined: a zero force is then no force, any other
//! value is an error.

use super::algebra::{Real, V3};
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyFrame;
use crate::physics::applied::LawError;
use linkage_adm::ForceDof;
use linkage_expr::Expr;
use linkage_model::forces::{Sforce, SpringDamper};
use std::f64::consts::{PI, TAU};

/// Where the scalar comes from.
#[derive(Clone, Debug)]
pub enum Magnitude {
    /// SFORCE: the FUNCTION expression.
    Expression(Expr),
    /// SPRINGDAMPER: stiffness, damping, free length (or angle) and preload.
    Spring {
        stiffness: f64,
        damping: f64,
        free: f64,
        preload: f64,
    },
}

/// The law of an SFORCE or SPRINGDAMPER.
#[derive(Clone, Debug)]
pub struct ScalarLaw {
    pub i: BodyFrame,
    pub j: BodyFrame,
    pub dof: ForceDof,
    pub action_only: bool,
    pub magnitude: Magnitude,
}

/// The multiple of 2π to add to the angle `a` to bring it into (−π, π].
pub(crate) fn wrap_offset(a: f64) -> f64 {
    let w = a - TAU * (a / TAU).round();
    if w <= -PI {
        w + TAU - a
    } else {
        w - a
    }
}

/// `atan2(x·y_ref, x·x_ref)`, the angle `name` (`AZ(I,J)`); an error when `x` is
/// perpendicular to both references.
pub(crate) fn angle<R: Real>(
    name: &'static str,
    x: &V3<R>,
    x_ref: &V3<R>,
    y_ref: &V3<R>,
) -> Result<R, LawError> {
    let (s, c) = (x.dot(y_ref), x.dot(x_ref));
    if s.value() == 0.0 && c.value() == 0.0 {
        return Err(LawError::UndefinedAngle { angle: name });
    }
    Ok(R::atan2(&s, &c))
}

impl ScalarLaw {
    pub fn sforce(i: BodyFrame, j: BodyFrame, s: &Sforce, function: Expr) -> ScalarLaw {
        ScalarLaw {
            i,
            j,
            dof: s.dof,
            action_only: s.action_only,
            magnitude: Magnitude::Expression(function),
        }
    }

    pub fn springdamper(i: BodyFrame, j: BodyFrame, s: &SpringDamper) -> ScalarLaw {
        ScalarLaw {
            i,
            j,
            dof: s.dof,
            action_only: false,
            magnitude: Magnitude::Spring {
                stiffness: s.stiffness,
                damping: s.damping,
                free: s.free,
                preload: s.preload,
            },
        }
    }

    fn expression<R: Real>(&self, cx: &Context) -> Result<Option<R>, LawError> {
        match &self.magnitude {
            Magnitude::Expression(e) => {
                R::evaluate(e, cx.env)
                    .map(Some)
                    .map_err(|err| LawError::Expression {
                        argument: "FUNCTION",
                        cause: err.message,
                    })
            }
            Magnitude::Spring { .. } => Ok(None),
        }
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let (bi, bj) = (self.i.body, self.j.body);
        match self.dof {
            ForceDof::Rotational => {
                let zj = kin.dir::<R>(&self.j.axis(2));
                let f = match self.expression::<R>(cx)? {
                    Some(f) => f,
                    None => self.spring_torque(cx, &zj)?,
                };
                let t = zj.times(&f);
                let reaction = (!self.action_only).then(|| Load::torque(bj, t.neg()));
                Ok([Some(Load::torque(bi, t)), reaction])
            }
            ForceDof::Translational if self.action_only => {
                let f = match self.expression::<R>(cx)? {
                    Some(f) => f,
                    None => return Ok([None, None]),
                };
                let zj = kin.dir::<R>(&self.j.axis(2));
                let pi = kin.point::<R>(&self.i.origin());
                Ok([Some(Load::force(bi, pi, zj.times(&f))), None])
            }
            ForceDof::Translational => {
                let pi = kin.point::<R>(&self.i.origin());
                let pj = kin.point::<R>(&self.j.origin());
                let d = pi.sub(&pj);
                let len2 = d.dot(&d);
                if len2.value().sqrt() <= cx.tiny_length {
                    // Undefined direction: only a zero force is acceptable.
                    let f = match (self.expression::<f64>(cx)?, &self.magnitude) {
                        (Some(f), _) => f,
                        (
                            None,
                            Magnitude::Spring {
                                stiffness,
                                free,
                                preload,
                                ..
                            },
                        ) => stiffness * free + preload,
                        (None, _) => 0.0,
                    };
                    if f == 0.0 {
                        return Ok([None, None]);
                    }
                    return Err(LawError::CoincidentPoints { force: f });
                }
                let len = len2.sqrt();
                let u = V3 {
                    x: d.x.div(&len),
                    y: d.y.div(&len),
                    z: d.z.div(&len),
                };
                let f = match (self.expression::<R>(cx)?, &self.magnitude) {
                    (Some(f), _) => f,
                    (
                        None,
                        Magnitude::Spring {
                            stiffness,
                            damping,
                            free,
                            preload,
                        },
                    ) => {
                        let vr = kin
                            .point_velocity::<R>(&self.i.origin())
                            .sub(&kin.point_velocity::<R>(&self.j.origin()))
                            .dot(&u);
                        vr.scale(-damping)
                            .sub(&len.shift(-free).scale(*stiffness))
                            .shift(*preload)
                    }
                    (None, Magnitude::Expression(_)) => R::cst(0.0),
                };
                let force = u.times(&f);
                Ok([
                    Some(Load::force(bi, pi, force.clone())),
                    Some(Load::force(bj, pj, force.neg())),
                ])
            }
        }
    }

    /// `−CT·WZ(I,J,J) − KT·wrap(AZ(I,J) − ANGLE) + TORQUE`.
    fn spring_torque<R: Real>(&self, cx: &Context, zj: &V3<R>) -> Result<R, LawError> {
        let Magnitude::Spring {
            stiffness,
            damping,
            free,
            preload,
        } = &self.magnitude
        else {
            return Ok(R::cst(0.0));
        };
        let kin = &cx.kin;
        let xi = kin.dir::<R>(&self.i.axis(0));
        let (xj, yj) = (kin.dir::<R>(&self.j.axis(0)), kin.dir::<R>(&self.j.axis(1)));
        let az = angle("AZ(I,J)", &xi, &xj, &yj)?;
        let twist = az.shift(-free);
        let twist = twist.shift(wrap_offset(twist.value()));
        let wz = kin
            .omega::<R>(self.i.body)
            .sub(&kin.omega::<R>(self.j.body))
            .dot(zj);
        Ok(wz
            .scale(-damping)
            .sub(&twist.scale(*stiffness))
            .shift(*preload))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_offset_brings_angles_into_half_open_interval() {
        for a in [0.0, 1.0, -1.0, 3.0, -3.5, 7.0, PI, -PI, 10.0 * PI] {
            let w = a + wrap_offset(a);
            assert!(w > -PI - 1e-12 && w <= PI + 1e-12, "{a} -> {w}");
            assert!(((w - a) / TAU - ((w - a) / TAU).round()).abs() < 1e-12);
        }
        assert!((-PI + wrap_offset(-PI) - PI).abs() < 1e-12);
    }
}
