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
    normal_load_gradient(f, r_gj, travel, force, torque).0
}

/// [`normal_load`] and its gradient with respect to the reaction: `(N, ∂N/∂force,
/// ∂N/∂torque)`, ground axes, at fixed pose. Each term is a norm of a projection of the
/// reaction in J's axes, `|P x|`, whose gradient is `Pᵀ(P x)/|P x|` (zero where the norm is
/// zero); statics uses it for the `∂Q/∂λ` coupling of the friction to the joint's multipliers.
pub fn normal_load_gradient(
    f: &Friction,
    r_gj: &DMat3,
    travel: f64,
    force: DVec3,
    torque: DVec3,
) -> (f64, DVec3, DVec3) {
    let fj = r_gj.transpose() * force;
    let tj = r_gj.transpose() * torque;
    // |(x, y)| and its gradient in J's axes.
    let planar = |v: DVec3| {
        let n = v.x.hypot(v.y);
        let g = if n > 0.0 {
            DVec3::new(v.x / n, v.y / n, 0.0)
        } else {
            DVec3::ZERO
        };
        (n, g)
    };
    let (radial, d_radial) = planar(fj);
    let (bending, d_bending) = planar(tj);
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
    let per_overlap = overlap.map_or(0.0, |xs| 1.0 / xs);
    let rp = f.pin_radius;
    // ∂|v_z|/∂v.
    let sign_z = |v: DVec3| {
        if v.z != 0.0 {
            DVec3::Z * v.z.signum()
        } else {
            DVec3::ZERO
        }
    };
    let (axial_sign, twist_sign) = (sign_z(fj), sign_z(tj));
    // N and its gradient in J's axes.
    let (n, dn_f, dn_t) = match f.kind {
        FrictionJoint::Translational => (
            sw1 * f.force_preload
                + sw2 * radial
                + sw3 * bending * per_overlap
                + sw4 * tj.z.abs() / f.reaction_arm,
            sw2 * d_radial,
            sw3 * per_overlap * d_bending + sw4 / f.reaction_arm * twist_sign,
        ),
        FrictionJoint::Cylindrical => (
            sw1 * (f.force_preload + f.torque_preload / rp)
                + sw2 * radial
                + sw3 * bending * per_overlap,
            sw2 * d_radial,
            sw3 * per_overlap * d_bending,
        ),
        FrictionJoint::Revolute | FrictionJoint::Universal => (
            sw1 * f.torque_preload / rp
                + sw2 * (radial + f.friction_arm / rp * fj.z.abs())
                + sw3 * bending / f.bending_reaction_arm,
            sw2 * (d_radial + f.friction_arm / rp * axial_sign),
            sw3 / f.bending_reaction_arm * d_bending,
        ),
        FrictionJoint::Spherical => {
            let size = fj.length();
            let d = if size > 0.0 { fj / size } else { DVec3::ZERO };
            (
                sw1 * f.torque_preload / f.ball_radius + sw2 * size,
                sw2 * d,
                DVec3::ZERO,
            )
        }
    };
    (n, *r_gj * dn_f, *r_gj * dn_t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use linkage_adm::{FrictionEffect, FrictionInputs};
    use linkage_model::friction::Friction;

    fn friction(kind: FrictionJoint) -> Friction {
        let ds = linkage_adm::parse_dataset(
            std::sync::Arc::from("t.adm"),
            "t\nPART/1, GROUND\nMARKER/1, PART = 1\nPART/2, MASS = 1, CM = 2, IP = 1, 1, 1\n\
             MARKER/2, PART = 2\nJOINT/1, TRANSLATIONAL, I = 2, J = 1\n\
             FRICTION/1, JOINT = 1, MU_STATIC = 0.5, MU_DYNAMIC = 0.3\nEND\n",
        )
        .unwrap();
        let mut f = linkage_model::build_model(&ds).unwrap().model.frictions[0].clone();
        f.kind = kind;
        f.force_preload = 7.0;
        f.torque_preload = 3.0;
        f.pin_radius = 0.5;
        f.ball_radius = 0.25;
        f.friction_arm = 2.0;
        f.bending_reaction_arm = 4.0;
        f.reaction_arm = 5.0;
        f.effect = FrictionEffect::All;
        f
    }

    const FORCE: DVec3 = DVec3::new(3.0, 4.0, -6.0);
    const TORQUE: DVec3 = DVec3::new(-8.0, 6.0, 10.0);

    /// The translational sum term by term: Fp, |f_radial| = 5, |t_bend|/Xs = 10/Xs with the
    /// overlap 2 grown (INCREASE) by the travel 1.5 − 0.5 = 1, |t_z|/Rr = 2; each input alone.
    #[test]
    fn a_translational_load_adds_its_inputs() {
        let mut f = friction(FrictionJoint::Translational);
        f.initial_overlap = Some(2.0);
        f.overlap_delta = OverlapDelta::Increase;
        f.initial_travel = 0.5;
        let n = |f: &Friction| normal_load(f, &DMat3::IDENTITY, 1.5, FORCE, TORQUE);
        assert!((n(&f) - (7.0 + 5.0 + 10.0 / 3.0 + 2.0)).abs() < 1e-12);
        f.overlap_delta = OverlapDelta::Decrease;
        assert!((n(&f) - (7.0 + 5.0 + 10.0 / 1.0 + 2.0)).abs() < 1e-12);
        f.inputs = FrictionInputs {
            torsional_moment: true,
            ..FrictionInputs::NONE
        };
        assert!((n(&f) - 2.0).abs() < 1e-12);
        // Without INITIAL_OVERLAP the bending moment feeds nothing.
        f.initial_overlap = None;
        f.inputs = FrictionInputs::ALL;
        assert!((n(&f) - (7.0 + 5.0 + 2.0)).abs() < 1e-12);
    }

    /// The gradient against central differences of the load, for every joint kind with every
    /// input on, the reaction seen from a tilted J (to 1e-7 relative: the load is smooth away
    /// from zero components).
    #[test]
    fn the_load_gradient_is_the_derivative_of_the_load() {
        let r_gj = DMat3::from_rotation_x(0.4) * DMat3::from_rotation_z(-1.1);
        for kind in [
            FrictionJoint::Translational,
            FrictionJoint::Cylindrical,
            FrictionJoint::Revolute,
            FrictionJoint::Universal,
            FrictionJoint::Spherical,
        ] {
            let mut f = friction(kind);
            f.initial_overlap = Some(2.0);
            let (n, df, dt) = normal_load_gradient(&f, &r_gj, 0.3, FORCE, TORQUE);
            assert_eq!(n, normal_load(&f, &r_gj, 0.3, FORCE, TORQUE));
            let h = 1e-6;
            for c in 0..3 {
                let e = DVec3::from_array(std::array::from_fn(|k| if k == c { h } else { 0.0 }));
                let by_force = (normal_load(&f, &r_gj, 0.3, FORCE + e, TORQUE)
                    - normal_load(&f, &r_gj, 0.3, FORCE - e, TORQUE))
                    / (2.0 * h);
                let by_torque = (normal_load(&f, &r_gj, 0.3, FORCE, TORQUE + e)
                    - normal_load(&f, &r_gj, 0.3, FORCE, TORQUE - e))
                    / (2.0 * h);
                assert!((by_force - df[c]).abs() < 1e-7, "{kind:?} force {c}");
                assert!((by_torque - dt[c]).abs() < 1e-7, "{kind:?} torque {c}");
            }
        }
    }

    /// The revolute load, times Rp, is `Tp + Rp·|f_r| + Rn·|f_a| + Rp·|t_b|/Rb` (J axes: the
    /// reaction turned by J's rotation); spherical `Tp/Rb + |f|`; cylindrical
    /// `Fp + Tp/Rp + |f_r|` (no overlap).
    #[test]
    fn turning_joints_load_by_their_arms() {
        let f = friction(FrictionJoint::Revolute);
        let torque = 0.5 * normal_load(&f, &DMat3::IDENTITY, 0.0, FORCE, TORQUE);
        assert!((torque - (3.0 + 0.5 * 5.0 + 2.0 * 6.0 + 0.5 * 10.0 / 4.0)).abs() < 1e-12);
        // The same reaction seen from a J marker turned by 90° about x: z_j = −y_g.
        let r_gj = DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2);
        let turned = 0.5 * normal_load(&f, &r_gj, 0.0, FORCE, TORQUE);
        let (fj, tj) = (r_gj.transpose() * FORCE, r_gj.transpose() * TORQUE);
        let expected =
            3.0 + 0.5 * fj.x.hypot(fj.y) + 2.0 * fj.z.abs() + 0.5 * tj.x.hypot(tj.y) / 4.0;
        assert!((turned - expected).abs() < 1e-12, "{turned} vs {expected}");
        let f = friction(FrictionJoint::Spherical);
        let n = normal_load(&f, &DMat3::IDENTITY, 0.0, FORCE, TORQUE);
        assert!((n - (3.0 / 0.25 + FORCE.length())).abs() < 1e-12);
        let f = friction(FrictionJoint::Cylindrical);
        let n = normal_load(&f, &DMat3::IDENTITY, 0.0, FORCE, TORQUE);
        assert!((n - (7.0 + 3.0 / 0.5 + 5.0)).abs() < 1e-12);
    }
}
