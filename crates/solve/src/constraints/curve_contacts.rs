//! Where each curve constraint touches its curves: the contact parameters of every PTCV (α on
//! its curve) and CVCV (α on curve I, β on curve J), the contact point in ground, and the speed
//! of the contact along each curve — for the outputs, and the speeds for the initial
//! conditions' VEL, IVEL and JVEL equations ([`speed_equations`]).
//!
//! The values come from the element's own rows (their warm-started contact,
//! [`crate::constraints::rows::curve_gap`], [`crate::constraints::rows::curve_curve`]), so an
//! output reads the contact the solve used.

use crate::constraints::rows::curve_curve::CurveContact;
use crate::constraints::rows::curve_gap::CurveGap;
use crate::constraints::rows::{BodyFrame, Quantity, RowGradient, Velocities};
use crate::constraints::system::System;
use crate::state::State;
use glam::{DMat3, DVec3};
use linkage_model::{Body, ConstraintKind, Model};

/// One curve constraint's contact at a state.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveContactValue {
    /// Index into [`Model::constraints`].
    pub element: usize,
    /// The contact parameter on the (I) curve, in [−1, 1].
    pub alpha: f64,
    /// A CVCV's contact parameter on its J curve.
    pub beta: Option<f64>,
    /// The contact point in ground (on the PTCV's curve; on a CVCV's I curve).
    pub point: DVec3,
    /// The floating markers' axes there, in ground (ADM-ELEMENTS §15, §16). PTCV's JFLOAT: x
    /// along the tangent, y away from the centre of curvature (on a straight piece, where
    /// there is no centre, y = x × the curve frame's reference axis, as on a curve bending
    /// toward `reference × x`), z = x × y. CVCV's IFLOAT and JFLOAT: x along curve I's
    /// tangent, z along IRM's z, y = z × x.
    pub frame: DMat3,
}

/// The row quantity of a curve element: a PTCV's first row or a CVCV's.
enum Contact<'a> {
    Point(&'a CurveGap),
    Pair(&'a CurveContact),
}

fn contact_of(sys: &System, e: usize) -> Option<Contact<'_>> {
    let r = sys.element_rows.get(e)?.clone().next()?;
    match sys.rows[r].terms.first().map(|t| &t.1) {
        Some(Quantity::CurveGap(q)) => Some(Contact::Point(q)),
        Some(Quantity::CurveContact(q)) => Some(Contact::Pair(q)),
        _ => None,
    }
}

/// Every PTCV's and CVCV's contact at state `s`, in model order (an element without rows —
/// a curve the model could not build — is left out).
pub fn curve_contacts(model: &Model, sys: &System, s: &State) -> Vec<CurveContactValue> {
    let mut out = Vec::new();
    for (e, c) in model.constraints.iter().enumerate() {
        if !matches!(c.kind, ConstraintKind::Ptcv(_) | ConstraintKind::Cvcv(_)) {
            continue;
        }
        match contact_of(sys, e) {
            Some(Contact::Point(q)) => {
                let alpha = q.alpha_at(s);
                let (p_m, r_m) = q.frame.eval(s);
                let [c, c1, c2, _] = q.curve.eval(alpha);
                let x = c1.normalize_or_zero();
                let toward = c2 - x * x.dot(c2);
                let toward = if toward.length() > 1e-9 * c2.length().max(c1.length_squared()) {
                    toward.normalize()
                } else {
                    q.curve.reference_axis.cross(x).normalize_or_zero()
                };
                let y = -toward;
                out.push(CurveContactValue {
                    element: e,
                    alpha,
                    beta: None,
                    point: p_m + r_m * c,
                    frame: r_m * DMat3::from_cols(x, y, x.cross(y)),
                });
            }
            Some(Contact::Pair(q)) => {
                let [alpha, beta] = q.parameters_at(s);
                let (point, frame) = q.contact_frame(s);
                out.push(CurveContactValue {
                    element: e,
                    alpha,
                    beta: Some(beta),
                    point,
                    frame,
                });
            }
            None => {}
        }
    }
    out
}

/// Where the floating markers of the curve constraints are at state `s`: (marker id, its frame
/// on its body) for every PTCV's JFLOAT and CVCV's IFLOAT and JFLOAT, at the contact point with
/// the axes of [`CurveContactValue::frame`]. A measure of such a marker reads the contact as a
/// point of the marker's body at that instant: its position and axes are the contact's, its
/// velocity and acceleration those of the body's material point there.
pub fn floating_placements(model: &Model, sys: &System, s: &State) -> Vec<(u64, BodyFrame)> {
    let mut out = Vec::new();
    if !model
        .constraints
        .iter()
        .any(|c| matches!(c.kind, ConstraintKind::Ptcv(_) | ConstraintKind::Cvcv(_)))
    {
        return out;
    }
    for v in curve_contacts(model, sys, s) {
        let floats = match &model.constraints[v.element].kind {
            ConstraintKind::Ptcv(p) => vec![p.jfloat],
            ConstraintKind::Cvcv(c) => vec![c.ifloat, c.jfloat],
            _ => continue,
        };
        for m in floats {
            let mk = &model.markers[m];
            let pose = s.pose(mk.body);
            out.push((
                mk.id,
                BodyFrame {
                    body: mk.body,
                    p_b: pose.r.transpose() * (v.point - pose.p),
                    r_b: pose.r.transpose() * v.frame,
                },
            ));
        }
    }
    out
}

/// The sliding speeds of one curve element along some twists (`[PTCV's, 0]`, `[I, J]`).
type SpeedsOf<'a> = dyn Fn(&Velocities) -> [f64; 2] + 'a;

/// The linear velocity equations `∇s·v = given` of the given initial sliding speeds: a PTCV's
/// VEL (`s = α̇·|c'|`, the point's speed along the curve relative to the curve's body) and a
/// CVCV's IVEL and JVEL (`α̇·|c_I'|`, `β̇·|c_J'|`, the contact point's speed along each curve
/// relative to its body), at state `s`. The gradient is the speed along each
/// unit twist of the element's bodies (the speeds are linear in the twists).
pub fn speed_equations(model: &Model, sys: &System, s: &State) -> Vec<(RowGradient, f64)> {
    let nparts = s.poses.len();
    let mut out = Vec::new();
    for (e, c) in model.constraints.iter().enumerate() {
        let wanted: [(Option<f64>, usize); 2] = match &c.kind {
            ConstraintKind::Ptcv(p) => [(p.vel, 0), (None, 1)],
            ConstraintKind::Cvcv(p) => [(p.ivel, 0), (p.jvel, 1)],
            _ => continue,
        };
        let Some(contact) = contact_of(sys, e) else {
            continue;
        };
        let (bodies, speed): (Vec<Body>, Box<SpeedsOf>) = match contact {
            Contact::Point(q) => (
                vec![q.point.body, q.frame.body],
                Box::new(move |v: &Velocities| [q.sliding_speed(s, v), 0.0]),
            ),
            Contact::Pair(q) => (
                vec![q.frames[0].body, q.frames[1].body],
                Box::new(move |v: &Velocities| q.sliding_speeds(s, v)),
            ),
        };
        for (given, k) in wanted {
            let Some(given) = given else { continue };
            out.push((speed_gradients(nparts, &bodies, |v| speed(v)[k]), given));
        }
    }
    out
}

/// The gradient of a function `f` linear in the twists of `bodies`: its value along each unit
/// twist.
fn speed_gradients(nparts: usize, bodies: &[Body], f: impl Fn(&Velocities) -> f64) -> RowGradient {
    let mut g = RowGradient::default();
    let mut v = vec![(DVec3::ZERO, DVec3::ZERO); nparts];
    let mut parts: Vec<usize> = bodies.iter().filter_map(|b| b.part()).collect();
    parts.dedup();
    for k in parts {
        let mut block = [0.0; 6];
        for (c, out) in block.iter_mut().enumerate() {
            let mut unit = DVec3::ZERO;
            unit[c % 3] = 1.0;
            v[k] = if c < 3 {
                (unit, DVec3::ZERO)
            } else {
                (DVec3::ZERO, unit)
            };
            *out = f(&v);
        }
        v[k] = (DVec3::ZERO, DVec3::ZERO);
        g.add_block(k, block);
    }
    g
}
