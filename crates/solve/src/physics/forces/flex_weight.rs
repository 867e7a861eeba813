//! The weight's modal load on a FLEX_BODY (the model side in `linkage_model::flex_bodies`).
//!
//! The potential of the weight of a flexible body is `V = −gᵀ·Σ m_p r_p / UCF` with
//! `r_p = x + A·(s_p + Φ_p·q)`: the reference body carries `I1·g` at its centre of mass
//! (the analyses' weight), and the modal part `−gᵀ·A·I3·q / UCF` (INVAR3 `I3 = Σ m_p Φ_p`,
//! BCS axes) gives, per mode j,
//!
//! - the generalized force `Q_j = gᵀ·A·I3_j / UCF` on the modal coordinate (a force
//!   `Q_j·axis` on the mode body, whose position along `axis` is q_j), and
//! - the torque `(A·I3_j·q_j) × g / UCF` on the reference body (`δV` under a rotation δθ of
//!   A: the weight of the deformation's first moment about the BCS).
//!
//! Generic over [`Real`], so the statics and integrators get the exact derivative in A and q.

use super::algebra::{Real, V3};
use super::{Context, Load, Loads};
use crate::physics::applied::LawError;
use glam::DVec3;
use linkage_model::flex_bodies::{FlexBody, FlexMode};
use linkage_model::Body;

/// The modal weight of one mode of a flex body.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalWeightLaw {
    pub reference: Body,
    pub mode: Body,
    /// Ground direction of the mode body's guide and its point at q = 0.
    pub axis: DVec3,
    pub rest: DVec3,
    /// `I3_j = Σ m_p Φ_pj` in the BCS (the reference body's axes).
    pub first_moment: DVec3,
    /// `g / UCF`: the weight of a unit mass in force units.
    pub weight: DVec3,
}

impl ModalWeightLaw {
    /// The law of mode `mode` of `body` under gravity `g` (model units) with the units
    /// consistency factor `ucf`; `None` when the mode has no first moment or there is no
    /// gravity.
    pub fn new(body: &FlexBody, mode: &FlexMode, g: DVec3, ucf: f64) -> Option<ModalWeightLaw> {
        (mode.first_moment != DVec3::ZERO && g != DVec3::ZERO).then(|| ModalWeightLaw {
            reference: Body::Part(body.reference),
            mode: Body::Part(mode.part),
            axis: body.axis,
            rest: body.rest,
            first_moment: mode.first_moment,
            weight: g / ucf,
        })
    }

    pub fn loads<R: Real>(&self, cx: &Context) -> Result<Loads<R>, LawError> {
        let kin = &cx.kin;
        let weight = V3::constant(self.weight);
        // A·I3_j in ground.
        let moment = kin.rotated::<R>(self.reference, self.first_moment);
        let q = kin
            .cm::<R>(self.mode)
            .sub(&V3::constant(self.rest))
            .dot(&V3::constant(self.axis));
        let generalized = moment.dot(&weight);
        Ok([
            Some(Load::force(
                self.mode,
                kin.cm::<R>(self.mode),
                V3::constant(self.axis).times(&generalized),
            )),
            Some(Load::torque(
                self.reference,
                moment.times(&q).cross(&weight),
            )),
        ])
    }
}
