//! Curve constraints' contacts as the reports show them: per PTCV its contact parameter α, per
//! CVCV α on curve I and β on curve J (each in [−1, 1]), and the contact point in ground —
//! where the element's floating marker (JFLOAT; IFLOAT and JFLOAT) sits. The JSON documents
//! carry the list only when the model has curve constraints.

use crate::num::{scale_of, sci_in};
use linkage_model::Model;
use linkage_solve::constraints::curve_contacts::CurveContactValue;
use serde::Serialize;
use std::fmt::Write;

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CurveContactJson {
    pub name: String,
    /// `PTCV/3`, `CVCV/6`.
    pub element: String,
    /// The contact parameter on the (I) curve.
    pub alpha: f64,
    /// A CVCV's contact parameter on its J curve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// The contact point in ground, model length units.
    pub point: [f64; 3],
    /// The floating marker's axes there, in ground: x along the curve's tangent, y, z along
    /// the binormal.
    pub x_axis: [f64; 3],
    pub z_axis: [f64; 3],
}

/// The curve contacts of `model` named for reports (`values` in model order).
pub fn curve_contacts_json(model: &Model, values: &[CurveContactValue]) -> Vec<CurveContactJson> {
    values
        .iter()
        .map(|v| {
            let o = &model.constraints[v.element].origin;
            CurveContactJson {
                name: o.name.clone(),
                element: o.element(),
                alpha: v.alpha,
                beta: v.beta,
                point: v.point.to_array(),
                x_axis: v.frame.x_axis.to_array(),
                z_axis: v.frame.z_axis.to_array(),
            }
        })
        .collect()
}

/// The text table of curve contacts (nothing when there are none).
pub fn curve_contact_table(s: &mut String, contacts: &[CurveContactJson]) {
    if contacts.is_empty() {
        return;
    }
    const DIGITS: usize = 7;
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Curve contacts (parameters in [-1, 1]; contact point in ground):"
    );
    let w = contacts
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(24);
    let _ = writeln!(
        s,
        "   {:<w$} {:>13} {:>13}   {:>13} {:>13} {:>13}",
        "element", "alpha", "beta", "X", "Y", "Z"
    );
    let p_scale = scale_of(contacts.iter().flat_map(|r| r.point));
    for r in contacts {
        let p = r.point.map(|x| sci_in(x, DIGITS, p_scale));
        let beta = r
            .beta
            .map_or_else(|| "-".to_string(), |b| sci_in(b, DIGITS, 1.0));
        let _ = writeln!(
            s,
            "   {:<w$} {:>13} {:>13}   {:>13} {:>13} {:>13}",
            r.name,
            sci_in(r.alpha, DIGITS, 1.0),
            beta,
            p[0],
            p[1],
            p[2]
        );
    }
}
