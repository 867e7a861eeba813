//! Function-expression measures evaluated on the solver state (the `linkage-expr` [`Env`]).
//!
//! Position measures (DX, DY, DZ, DM, AX, AY, AZ, PSI, THETA, PHI, YAW, PITCH, ROLL) are
//! built from the same geometric [`Quantity`]s as the constraint rows, so their gradients are
//! exact. The gradient variable of part `k`'s tangent coordinate `c` is `6k + c`.

use crate::rows::{BodyDir, BodyFrame, BodyPoint, EulerSeq, Quantity, RowGradient};
use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_expr::{Dual, Env, EvalError, MarkerArgs, MeasureKind};
use linkage_model::{Body, Model};
use std::collections::HashMap;

/// Marker frames by dataset id (ground frame for id 0).
#[derive(Clone, Debug, Default)]
pub struct MarkerFrames {
    frames: HashMap<u64, BodyFrame>,
}

impl MarkerFrames {
    pub fn new(model: &Model) -> MarkerFrames {
        let frames = model
            .markers
            .iter()
            .map(|m| {
                (
                    m.id,
                    BodyFrame {
                        body: m.body,
                        p_b: m.p_bm,
                        r_b: m.r_bm,
                    },
                )
            })
            .collect();
        MarkerFrames { frames }
    }

    /// The frame of marker `id`; id 0 is the ground frame.
    pub fn get(&self, id: u32) -> Result<BodyFrame, EvalError> {
        if id == 0 {
            return Ok(BodyFrame {
                body: Body::Ground,
                p_b: DVec3::ZERO,
                r_b: DMat3::IDENTITY,
            });
        }
        self.frames.get(&(id as u64)).copied().ok_or_else(|| {
            EvalError::new(
                linkage_expr::EvalErrorKind::UnknownReference,
                format!("marker {id} does not exist"),
            )
        })
    }
}

/// A position-level environment: time and part poses.
pub struct PositionEnv<'a> {
    pub frames: &'a MarkerFrames,
    pub state: &'a State,
}

fn dual(value: f64, g: &RowGradient) -> Dual {
    Dual::new(
        value,
        g.blocks.iter().flat_map(|(k, v)| {
            v.iter()
                .enumerate()
                .map(move |(c, x)| ((6 * k + c) as u32, *x))
        }),
    )
}

fn negate(d: BodyDir) -> BodyDir {
    BodyDir {
        body: d.body,
        v_b: -d.v_b,
    }
}

impl PositionEnv<'_> {
    /// The geometric quantity a position measure is.
    fn quantity(&self, kind: MeasureKind, m: MarkerArgs) -> Result<Option<Quantity>, EvalError> {
        let (fi, fj) = (self.frames.get(m.i)?, self.frames.get(m.j)?);
        let point = |f: BodyFrame| BodyPoint {
            body: f.body,
            p_b: f.p_b,
        };
        let proj = |axis: usize| -> Result<Quantity, EvalError> {
            let fk = self.frames.get(m.k)?;
            Ok(Quantity::Proj {
                i: point(fi),
                j: point(fj),
                e: fk.axis(axis),
            })
        };
        let euler = |seq, k| Quantity::Euler {
            i: fi,
            j: fj,
            seq,
            k,
        };
        Ok(Some(match kind {
            MeasureKind::Dx => proj(0)?,
            MeasureKind::Dy => proj(1)?,
            MeasureKind::Dz => proj(2)?,
            MeasureKind::Dm => {
                let d = fi.eval(self.state).0 - fj.eval(self.state).0;
                let e = BodyDir {
                    body: Body::Ground,
                    v_b: d.try_normalize().unwrap_or(DVec3::X),
                };
                Quantity::Proj {
                    i: point(fi),
                    j: point(fj),
                    e,
                }
            }
            // AX = atan2(−z_i·y_j, z_i·z_j), AY = atan2(z_i·x_j, z_i·z_j), AZ = atan2(x_i·y_j, x_i·x_j).
            MeasureKind::Ax => Quantity::Angle {
                x: fi.axis(2),
                x_ref: fj.axis(2),
                y_ref: negate(fj.axis(1)),
            },
            MeasureKind::Ay => Quantity::Angle {
                x: fi.axis(2),
                x_ref: fj.axis(2),
                y_ref: fj.axis(0),
            },
            MeasureKind::Az => Quantity::Angle {
                x: fi.axis(0),
                x_ref: fj.axis(0),
                y_ref: fj.axis(1),
            },
            MeasureKind::Psi => euler(EulerSeq::Body313, 0),
            MeasureKind::Theta => euler(EulerSeq::Body313, 1),
            MeasureKind::Phi => euler(EulerSeq::Body313, 2),
            MeasureKind::Yaw => euler(EulerSeq::Body321, 0),
            MeasureKind::Pitch => euler(EulerSeq::Body321, 1),
            MeasureKind::Roll => euler(EulerSeq::Body321, 2),
            _ => return Ok(None),
        }))
    }
}

impl Env for PositionEnv<'_> {
    fn time(&self) -> f64 {
        self.state.time
    }

    fn measure(
        &self,
        kind: MeasureKind,
        markers: MarkerArgs,
        gradient: bool,
    ) -> Result<Dual, EvalError> {
        let Some(q) = self.quantity(kind, markers)? else {
            return Err(EvalError::unavailable(format!(
                "{} needs velocities or forces, which a position-level analysis does not have",
                kind.name()
            )));
        };
        let value = q.value(self.state);
        if !gradient {
            return Ok(Dual::constant(value));
        }
        let mut g = RowGradient::default();
        if kind == MeasureKind::Dm && value == 0.0 {
            // |d| has no derivative at d = 0.
            return Ok(Dual::constant(0.0));
        }
        q.gradient(self.state, 1.0, &mut g);
        Ok(dual(value, &g))
    }
}

/// Adds `c · ∂f/∂q` of an expression's gradient to a row gradient.
pub fn add_dual_gradient(d: &Dual, c: f64, g: &mut RowGradient) {
    for &(idx, v) in d.gradient() {
        let (k, comp) = (idx as usize / 6, idx as usize % 6);
        let mut block = [0.0; 6];
        block[comp] = v * c;
        g.add_block(k, block);
    }
}
