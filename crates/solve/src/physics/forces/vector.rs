//! VFORCE, VTORQUE and GFORCE: force and torque components given by expressions along the
//! axes of the RM marker (ADM-REFERENCE §2.10).
//!
//! ```text
//! F = FX·x_rm + FY·y_rm + FZ·z_rm,   T = TX·x_rm + TY·y_rm + TZ·z_rm
//! F at P_i and T on I's body;  −F at P_i and −T on the body of the floating marker JFLOAT
//! ```
//!
//! JFLOAT floats on its part and sits at I's origin, so the reaction acts at the point of
//! that part instantaneously coincident with `P_i`: the pair has zero net force and moment.
//! VFORCE has no torque, VTORQUE no force; a component not given is zero.

use super::algebra::{Real, V3};
use super::{Context, Load, Loads};
use crate::constraints::rows::BodyFrame;
use crate::physics::applied::LawError;
use linkage_expr::Expr;
use linkage_model::Body;

/// The law of a VFORCE, VTORQUE or GFORCE.
#[derive(Clone, Debug)]
pub struct VectorLaw {
    pub i: BodyFrame,
    /// The body JFLOAT floats on.
    pub reaction: Body,
    pub rm: BodyFrame,
    /// `FX, FY, FZ` (`None` = 0).
    pub force: [Option<Expr>; 3],
    /// `TX, TY, TZ` (`None` = 0).
    pub torque: [Option<Expr>; 3],
}

const NAMES: [&str; 6] = ["FX", "FY", "FZ", "TX", "TY", "TZ"];

impl VectorLaw {
    fn components<R: Real>(
        cx: &Context,
        exprs: &[Option<Expr>; 3],
        names: &[&'static str],
    ) -> Result<Option<[R; 3]>, LawError> {
        if exprs.iter().all(Option::is_none) {
            return Ok(None);
        }
        let mut out = [R::cst(0.0), R::cst(0.0), R::cst(0.0)];
        for ((slot, e), name) in out.iter_mut().zip(exprs).zip(names) {
            if let Some(e) = e {
                *slot = R::evaluate(e, cx.env).map_err(|err| LawError::Expression {
                    argument: name,
                    cause: err.message,
                })?;
            }
        }
        Ok(Some(out))
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let axes = [0, 1, 2].map(|k| kin.dir::<R>(&self.rm.axis(k)));
        let force =
            Self::components::<R>(cx, &self.force, &NAMES[..3])?.map(|c| V3::combine(&axes, &c));
        let torque =
            Self::components::<R>(cx, &self.torque, &NAMES[3..])?.map(|c| V3::combine(&axes, &c));
        let pi = match &force {
            Some(_) => kin.point::<R>(&self.i.origin()),
            None => V3::zero(),
        };
        let (force, torque) = (
            force.unwrap_or_else(V3::zero),
            torque.unwrap_or_else(V3::zero),
        );
        let reaction = Load {
            body: self.reaction,
            point: pi.clone(),
            force: force.neg(),
            torque: torque.neg(),
        };
        Ok([
            Some(Load {
                body: self.i.body,
                point: pi,
                force,
                torque,
            }),
            Some(reaction),
        ])
    }
}
