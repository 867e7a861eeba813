//! Time-history columns of the elements with values of their own: each FRICTION's force,
//! torque (ground axes, on the joint's I part), normal load and slip speed, and the states of
//! every DIFF, LSE, GSE-free TFSISO (the control states), named after the element:
//!
//! ```text
//! FRICTION_1.fx .fy .fz [force]  .tx .ty .tz [torque]  .normal [force]  .slip [velocity]
//! DIFF_3.state                    (one state)
//! LSE_4.state1 … .stateN          (several: the element's X array in order)
//! ```
//!
//! Control states have the units of whatever their equations describe: no suffix. Written
//! after the REQUEST columns by `simulate --out` (and the command files' `.csv`).

use linkage_model::Model;
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
    out
}

/// The values at state `s` with the frictions' values `frictions` (model order), appended to
/// `out`: as many as [`names`] (a friction without a value, or a state outside `s`, is NaN).
pub fn values(model: &Model, frictions: &[FrictionValue], s: &State, out: &mut Vec<f64>) {
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
}
