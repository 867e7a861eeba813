//! `FRICTION/`: the joint resolved, defaults filled in ([`crate::friction`]).
//!
//! Errors: a duplicate id, a JOINT that does not exist, a joint type friction does not act
//! on (only TRANSLATIONAL, REVOLUTE, CYLINDRICAL, SPHERICAL, UNIVERSAL and HOOKE have it in
//! Adams), two frictions on one joint. Warning: INPUTS that use the bending moment of a
//! translational or cylindrical joint without INITIAL_OVERLAP (that input is then left out).

use super::context::{origin, Ctx};
use crate::friction::{
    Friction, FrictionJoint, DEFAULT_ARM, DEFAULT_MAX_STICTION_DEFORMATION,
    DEFAULT_STICTION_VELOCITY, DEFAULT_TRANSITION_COEFFICIENT,
};
use crate::model::{Body, Constraint, ConstraintKind, Marker, Part};
use glam::DVec3;
use linkage_adm::{Dataset, JointType, Located};
use std::collections::HashSet;

/// The ground position and z axis of marker `m` at the input configuration.
fn placed(parts: &[Part], markers: &[Marker], m: usize) -> (DVec3, DVec3) {
    let mk = &markers[m];
    match mk.body {
        Body::Ground => (mk.p_bm, mk.r_bm * DVec3::Z),
        Body::Part(k) => {
            let p = &parts[k];
            (p.p_gb + p.r_gb * mk.p_bm, p.r_gb * mk.r_bm * DVec3::Z)
        }
    }
}

fn or(v: &Option<Located<f64>>, default: f64) -> f64 {
    v.as_ref().map_or(default, |x| x.value)
}

pub(crate) fn frictions(
    ds: &Dataset,
    constraints: &[Constraint],
    parts: &[Part],
    markers: &[Marker],
    cx: &mut Ctx,
) -> Vec<Friction> {
    let mut seen = HashSet::new();
    let mut joints_used = HashSet::new();
    let mut out = Vec::with_capacity(ds.frictions.len());
    for f in &ds.frictions {
        if !cx.unique(&mut seen, "FRICTION", &f.header) {
            continue;
        }
        let name = &f.header.name;
        let found = constraints
            .iter()
            .enumerate()
            .find(|(_, c)| c.origin.statement == "JOINT" && c.origin.id == f.joint.id);
        let Some((joint, c)) = found else {
            cx.error(
                f.joint.span,
                format!("{name}: JOINT {} does not exist", f.joint.id),
            );
            continue;
        };
        let ConstraintKind::Joint { kind, i, j, .. } = &c.kind else {
            continue;
        };
        let kind = match kind {
            JointType::Translational => FrictionJoint::Translational,
            JointType::Revolute => FrictionJoint::Revolute,
            JointType::Cylindrical => FrictionJoint::Cylindrical,
            JointType::Spherical => FrictionJoint::Spherical,
            JointType::Universal | JointType::Hooke => FrictionJoint::Universal,
            other => {
                cx.error(
                    f.joint.span,
                    format!(
                        "{name}: friction acts on TRANSLATIONAL, REVOLUTE, CYLINDRICAL, SPHERICAL, \
                         UNIVERSAL and HOOKE joints; JOINT {} is {}",
                        f.joint.id,
                        other.keyword()
                    ),
                );
                continue;
            }
        };
        if !joints_used.insert(joint) {
            cx.error(
                f.joint.span,
                format!("{name}: JOINT {} already has a FRICTION", f.joint.id),
            );
            continue;
        }
        let slides = matches!(
            kind,
            FrictionJoint::Translational | FrictionJoint::Cylindrical
        );
        if slides && f.inputs.bending_moment && f.initial_overlap.is_none() {
            cx.warn(
                f.inputs_span,
                format!(
                    "{name}: the bending moment of JOINT {} does not feed the friction without \
                     INITIAL_OVERLAP (the overlap that turns it into a force)",
                    f.joint.id
                ),
            );
        }
        let (p_i, _) = placed(parts, markers, *i);
        let (p_j, z_j) = placed(parts, markers, *j);
        out.push(Friction {
            origin: origin("FRICTION", &f.header),
            joint,
            kind,
            i: *i,
            j: *j,
            mu_static: f.mu_static.value,
            mu_dynamic: f.mu_dynamic.value,
            stiction_velocity: or(&f.stiction_transition_velocity, DEFAULT_STICTION_VELOCITY),
            transition_coefficient: or(
                &f.transition_velocity_coefficient,
                DEFAULT_TRANSITION_COEFFICIENT,
            ),
            max_stiction_deformation: or(
                &f.max_stiction_deformation,
                DEFAULT_MAX_STICTION_DEFORMATION,
            ),
            force_preload: or(&f.force_preload, 0.0),
            torque_preload: or(&f.torque_preload, 0.0),
            pin_radius: or(&f.pin_radius, DEFAULT_ARM),
            ball_radius: or(&f.ball_radius, DEFAULT_ARM),
            friction_arm: or(&f.friction_arm, DEFAULT_ARM),
            bending_reaction_arm: or(&f.bending_reaction_arm, DEFAULT_ARM),
            reaction_arm: or(&f.reaction_arm, DEFAULT_ARM),
            initial_overlap: f.initial_overlap.as_ref().map(|x| x.value),
            overlap_delta: f.overlap_delta,
            initial_travel: (p_i - p_j).dot(z_j),
            effect: f.effect,
            inactive_static: f.inactive_static,
            inputs: f.inputs,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::build_model;
    use crate::friction::FrictionJoint;
    use std::sync::Arc;

    fn build(body: &str) -> Result<crate::Model, String> {
        let text = format!(
            "t\nPART/1, GROUND\nMARKER/10, PART = 1\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1\n\
             MARKER/20, PART = 2, QP = 0, 0, 3\nJOINT/5, TRANSLATIONAL, I = 20, J = 10\n\
             JOINT/6, FIXED, I = 20, J = 10\n{body}\nEND\n"
        );
        let ds =
            linkage_adm::parse_dataset(Arc::from("m.adm"), &text).map_err(|d| d.to_string())?;
        build_model(&ds).map(|b| b.model).map_err(|d| d.to_string())
    }

    /// Defaults filled in, the joint and its travel at the input resolved.
    #[test]
    fn friction_resolves_its_joint_and_takes_the_defaults() {
        let m = build("FRICTION/1, JOINT = 5, MU_STATIC = 0.5, MU_DYNAMIC = 0.3")
            .unwrap_or_else(|e| panic!("{e}"));
        let f = &m.frictions[0];
        assert_eq!(f.kind, FrictionJoint::Translational);
        assert_eq!(m.constraints[f.joint].origin.id, 5);
        assert_eq!(
            (
                f.stiction_velocity,
                f.transition_coefficient,
                f.max_stiction_deformation
            ),
            (0.1, 1.5, 0.01)
        );
        assert_eq!(
            (f.pin_radius, f.friction_arm, f.force_preload),
            (1.0, 1.0, 0.0)
        );
        assert!(
            (f.initial_travel - 3.0).abs() < 1e-12,
            "{}",
            f.initial_travel
        );
    }

    /// A missing joint, a FIXED joint and a second friction on a joint are errors at JOINT.
    #[test]
    fn friction_on_a_missing_or_fixed_joint_is_an_error() {
        let e = build(
            "FRICTION/1, JOINT = 9, MU_STATIC = 0.5, MU_DYNAMIC = 0.3\n\
             FRICTION/2, JOINT = 6, MU_STATIC = 0.5, MU_DYNAMIC = 0.3\n\
             FRICTION/3, JOINT = 5, MU_STATIC = 0.5, MU_DYNAMIC = 0.3\n\
             FRICTION/4, JOINT = 5, MU_STATIC = 0.5, MU_DYNAMIC = 0.3",
        )
        .err()
        .unwrap_or_default();
        assert!(e.contains("FRICTION_1: JOINT 9 does not exist"), "{e}");
        assert!(e.contains("JOINT 6 is FIXED"), "{e}");
        assert!(
            e.contains("FRICTION_4: JOINT 5 already has a FRICTION"),
            "{e}"
        );
    }
}
