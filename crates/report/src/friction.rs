//! Joint friction as the reports show it: per FRICTION, the friction force and torque on the
//! joint's I part (J marker axes: along z_j for a sliding joint, about z_j for a turning one),
//! the normal load it came from and the regime. The JSON documents carry the list only when
//! the model has frictions.

use crate::num::{scale_of, sci_in};
use linkage_model::Model;
use linkage_solve::physics::forces::friction::FrictionValue;
use serde::Serialize;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FrictionJson {
    pub name: String,
    /// `FRICTION/1`.
    pub element: String,
    /// The joint's name.
    pub joint: String,
    /// Friction force on the I part, J marker axes, model force units.
    pub force: [f64; 3],
    /// Friction torque on the I part, J marker axes, model force × length units.
    pub torque: [f64; 3],
    /// The normal load (force at the slip surface) the friction is μ times.
    pub normal_load: f64,
    /// Slip speed at the surface (length/time).
    pub slip_speed: f64,
    /// `stiction` (below the stiction transition velocity) or `sliding`.
    pub regime: &'static str,
}

/// The frictions of `model` named for reports (`values` in model order).
pub fn frictions_json(model: &Model, values: &[FrictionValue]) -> Vec<FrictionJson> {
    model
        .frictions
        .iter()
        .zip(values)
        .map(|(f, v)| FrictionJson {
            name: f.origin.name.clone(),
            element: f.origin.element(),
            joint: model.constraints[f.joint].origin.name.clone(),
            force: v.force.to_array(),
            torque: v.torque.to_array(),
            normal_load: v.normal,
            slip_speed: v.slip_speed,
            regime: if v.sticking { "stiction" } else { "sliding" },
        })
        .collect()
}

/// The text table of frictions (nothing when there are none).
pub fn friction_table(s: &mut String, frictions: &[FrictionJson]) {
    if frictions.is_empty() {
        return;
    }
    const DIGITS: usize = 7;
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Joint friction (on the I part, J marker axes; normal load N, slip speed):"
    );
    let w = frictions
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(24);
    let _ = writeln!(
        s,
        "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}   {:>13} {:>13}  regime",
        "element", "FX", "FY", "FZ", "TX", "TY", "TZ", "N", "slip"
    );
    let f_scale = scale_of(frictions.iter().flat_map(|r| r.force));
    let t_scale = scale_of(frictions.iter().flat_map(|r| r.torque)).max(f_scale);
    for r in frictions {
        let f = r.force.map(|x| sci_in(x, DIGITS, f_scale));
        let t = r.torque.map(|x| sci_in(x, DIGITS, t_scale));
        let n = sci_in(r.normal_load, DIGITS, r.normal_load.abs());
        let v = sci_in(r.slip_speed, DIGITS, r.slip_speed.abs());
        let _ = writeln!(
            s,
            "   {:<w$} {:>13} {:>13} {:>13}   {:>13} {:>13} {:>13}   {:>13} {:>13}  {}",
            r.name, f[0], f[1], f[2], t[0], t[1], t[2], n, v, r.regime
        );
    }
}
