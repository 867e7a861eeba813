//! The normal load of a friction: the joint's reaction split into components, each switched
//! on by INPUTS and turned into an equivalent force at the slip surface (ADM-ELEMENTS §4.2).
//!
//! The reaction on the joint's I marker (force `f` and torque `t` about I's origin) is taken
//! in J's axes; radial means perpendicular to z_j, axial along it; the bending moment is
//! `(t_x, t_y)`, the torsional one `t_z`. With SW1…SW4 the PRELOAD, REACTION_FORCE,
//! BENDING_MOMENT and TORSIONAL_MOMENT switches, the load N (force at the surface; the
//! friction is `μ·N`, its torque `R·μ·N` with R the pin or ball radius):
//!
//! ```text
//! translational   N = SW1·Fp + SW2·|f_radial| + SW3·|t_bend|/Xs + SW4·|t_z|/Rr
//! cylindrical     N = SW1·(Fp + Tp/Rp) + SW2·|f_radial| + SW3·|t_bend|/Xs
//! revolute,       N = SW1·Tp/Rp + SW2·(|f_radial| + (Rn/Rp)·|f_z|) + SW3·|t_bend|/Rb
//! universal/hooke     (so that the torque is μ·(Tp + Rp·|f_r| + Rn·|f_a| + Rp·|t_b|/Rb))
//! spherical       N = SW1·Tp/Rball + SW2·|f|
//! ```
//!
//! Xs is the overlap: INITIAL_OVERLAP plus (INCREASE) or minus (DECREASE) the travel along
//! z_j since the input configuration, or constant; it is kept above 1% of INITIAL_OVERLAP
//! (decided: a slider about to leave its guide keeps a finite bending load). Without
//! INITIAL_OVERLAP the bending term of a sliding joint is left out (the model warns). Rp is
//! PIN_RADIUS, Rn FRICTION_ARM, Rb BENDING_REACTION_ARM, Rr REACTION_ARM. For universal and
//! hooke joints the axial direction is J's z axis, as for a revolute joint (decided; the
//! reference does not say). The spherical and the translational forms are documented for
//! Adams; the others follow the argument descriptions (`[unconfirmed]` in the reference).

use glam::{DMat3, DVec3};
use linkage_adm::OverlapDelta;
use linkage_model::friction::{Friction, FrictionJoint};

/// The smallest overlap, as a fraction of INITIAL_OVERLAP.
const LEAST_OVERLAP: f64 = 0.01;

/// The normal load N of `f` (see the module docs) from the reaction on its I marker (`force`,
/// `torque` about I's origin, ground axes), with J's axes `r_gj` and the travel
/// `(P_i − P_j)·z_j`.
pub fn normal_load(f: &Friction, r_gj: &DMat3, travel: f64, force: DVec3, torque: DVec3) -> f64 {
    let fj = r_gj.transpose() * force;
    let tj = r_gj.transpose() * torque;
    let radial = fj.x.hypot(fj.y);
    let bending = tj.x.hypot(tj.y);
    let on = |b: bool| if b { 1.0 } else { 0.0 };
    let (sw1, sw2, sw3, sw4) = (
        on(f.inputs.preload),
        on(f.inputs.reaction_force),
        on(f.inputs.bending_moment),
        on(f.inputs.torsional_moment),
    );
    let overlap = f.initial_overlap.map(|x0| {
        let travel = travel - f.initial_travel;
        let x = match f.overlap_delta {
            OverlapDelta::Constant => x0,
            OverlapDelta::Increase => x0 + travel,
            OverlapDelta::Decrease => x0 - travel,
        };
        x.max(LEAST_OVERLAP * x0)
    });
    let bend_over_overlap = overlap.map_or(0.0, |xs| bending / xs);
    let rp = f.pin_radius;
    match f.kind {
        FrictionJoint::Translational => {
            sw1 * f.force_preload
                + sw2 * radial
                + sw3 * bend_over_overlap
                + sw4 * tj.z.abs() / f.reaction_arm
        }
        FrictionJoint::Cylindrical => {
            sw1 * (f.force_preload + f.torque_preload / rp) + sw2 * radial + sw3 * bend_over_overlap
        }
        FrictionJoint::Revolute | FrictionJoint::Universal => {
            sw1 * f.torque_preload / rp
                + sw2 * (radial + f.friction_arm / rp * fj.z.abs())
                + sw3 * bending / f.bending_reaction_arm
        }
        FrictionJoint::Spherical => sw1 * f.torque_preload / f.ball_radius + sw2 * fj.length(),
    }
}
