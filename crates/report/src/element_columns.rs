//! Time-history columns of the elements with values of their own: each FRICTION's force,
//! torque (ground axes, on the joint's I part), normal load and slip speed, the states of
//! every DIFF, LSE, GSE-free TFSISO (the control states), and each curve constraint's contact
//! (its parameters on the curves, in [−1, 1], and the contact point in ground, where its
//! floating marker sits), named after the element:
//!
//! ```text
//! FRICTION_1.fx .fy .fz [force]  .tx .ty .tz [torque]  .normal [force]  .slip [velocity]
//! DIFF_3.state                    (one state)
//! LSE_4.state1 … .stateN          (several: the element's X array in order)
//! PTCV_5.alpha  .contact.x .contact.y .contact.z [length]
//! CVCV_6.alpha .beta  .contact.x .contact.y .contact.z [length]
//! ```
//!
//! Control states have the units of whatever their equations describe: no suffix. Written
//! after the REQUEST columns by `simulate --out` (and the command files' `.csv`).

use linkage_model::{ConstraintKind, Model};
use linkage_solve::constraints::curve_contacts::CurveContactValue;
use linkage_solve::physics::forces::friction::FrictionValue;
use linkage_solve::state::State;

/// The column names, in the order [`values`] fills them.
pub fn names(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    for f in &model.frictions {
        for c in ["fx", "fy", "fz", "tx", "ty", "tz", "normal", "slip"] {
            out.push(format!("{}.{c}", f.origin.name));
        }
    }
    for e in &model.controls.states {
        if e.size == 1 {
            out.push(format!("{}.state", e.origin.name));
        } else {
            for k in 1..=e.size {
                out.push(format!("{}.state{k}", e.origin.name));
            }
        }
    }
    for c in &model.constraints {
        let components: &[&str] = match c.kind {
            ConstraintKind::Ptcv(_) => &["alpha"],
            ConstraintKind::Cvcv(_) => &["alpha", "beta"],
            _ => continue,
        };
        for k in components
            .iter()
            .chain(&["contact.x", "contact.y", "contact.z"])
        {
            out.push(format!("{}.{k}", c.origin.name));
        }
    }
    out
}

/// The values at state `s` with the frictions' values `frictions` and the curve constraints'
/// contacts `contacts` (model order), appended to `out`: as many as [`names`] (a friction or
/// contact without a value, or a state outside `s`, is NaN).
pub fn values(
    model: &Model,
    frictions: &[FrictionValue],
    contacts: &[CurveContactValue],
    s: &State,
    out: &mut Vec<f64>,
) {
    for k in 0..model.frictions.len() {
        match frictions.get(k) {
            Some(v) => {
                out.extend(v.force.to_array());
                out.extend(v.torque.to_array());
                out.push(v.normal);
                out.push(v.slip_speed);
            }
            None => out.extend([f64::NAN; 8]),
        }
    }
    for e in &model.controls.states {
        for k in e.offset..e.offset + e.size {
            out.push(s.controls.x.get(k).copied().unwrap_or(f64::NAN));
        }
    }
    for (e, c) in model.constraints.iter().enumerate() {
        let pair = match c.kind {
            ConstraintKind::Ptcv(_) => false,
            ConstraintKind::Cvcv(_) => true,
            _ => continue,
        };
        match contacts.iter().find(|v| v.element == e) {
            Some(v) => {
                out.push(v.alpha);
                if pair {
                    out.push(v.beta.unwrap_or(f64::NAN));
                }
                out.extend(v.point.to_array());
            }
            None => out.extend(vec![f64::NAN; 4 + usize::from(pair)]),
        }
    }
}
