//! `MOTION/` (joint or marker form) and `GCON/`: the constraints driven by a function of
//! time or of the state.

use super::context::{origin, Ctx};
use super::couplings::Joints;
use super::lookup::MarkerTable;
use crate::model::{Constraint, ConstraintKind, MotionCoordinate};
use linkage_adm::{Dataset, IdRef, JointType, MotionDof, MotionTarget};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// Every MOTION, appended to `constraints`. A joint motion drives the joint's rotation about
/// or translation along z_j (a cylindrical joint's must say which); a marker motion drives one
/// axis of I in J. Errors: a duplicate id, FUNCTION missing, a missing joint, a coordinate the
/// joint does not have, unusable markers or markers on one body.
pub(crate) fn motions(
    ds: &Dataset,
    table: &MarkerTable,
    joint_index: &HashMap<u64, usize>,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = HashSet::new();
    for m in &ds.motions {
        let name = &m.header.name;
        if !cx.unique(&mut seen, "MOTION", &m.header) {
            continue;
        }
        if m.function.is_none() {
            cx.error(m.header.span, format!("{name}: FUNCTION is missing"));
            continue;
        }
        let target = match m.target {
            MotionTarget::Joint { joint, dof } => {
                let joints = Joints {
                    index: joint_index,
                    constraints,
                };
                joint_motion(m, &joints, joint, dof, cx)
            }
            MotionTarget::Markers { i, j, axis } => table
                .constraint_pair(cx, i, j, &m.header)
                .map(|(mi, mj)| (None, mi, mj, MotionCoordinate::Marker(axis))),
        };
        let Some((joint, i, j, coordinate)) = target else {
            continue;
        };
        constraints.push(Constraint {
            origin: origin("MOTION", &m.header),
            kind: ConstraintKind::Motion {
                joint,
                i,
                j,
                coordinate,
                level: m.level,
                function: m.function.clone(),
                icdisp: m.icdisp,
                icvel: m.icvel,
            },
        });
    }
}

/// What a joint-form motion drives: (the joint's constraint index, its I and J markers, the
/// coordinate). An error when the joint is missing or has no such coordinate.
fn joint_motion(
    m: &linkage_adm::Motion,
    joints: &Joints,
    joint: IdRef,
    dof: Option<MotionDof>,
    cx: &mut Ctx,
) -> Option<(Option<usize>, usize, usize, MotionCoordinate)> {
    let name = &m.header.name;
    let (c, kind) = joints.joint(cx, joint, name)?;
    let (i, j) = joints.constraints[c].markers()?;
    let coordinate = match (kind, dof) {
        (JointType::Revolute, None | Some(MotionDof::Rotation)) => MotionCoordinate::RotationZ,
        (JointType::Translational, None | Some(MotionDof::Translation)) => {
            MotionCoordinate::TranslationZ
        }
        (JointType::Cylindrical, Some(MotionDof::Rotation)) => MotionCoordinate::RotationZ,
        (JointType::Cylindrical, Some(MotionDof::Translation)) => MotionCoordinate::TranslationZ,
        (JointType::Cylindrical, None) => {
            cx.error(
                m.header.span,
                format!(
                    "{name}: a motion on cylindrical JOINT {} must say TRANSLATION or ROTATION",
                    joint.id
                ),
            );
            return None;
        }
        (k, d) => {
            cx.error(
                joint.span,
                format!(
                    "{name}: cannot drive {} of a {} joint (JOINT {})",
                    match d {
                        Some(MotionDof::Translation) => "translation",
                        _ => "rotation",
                    },
                    k.keyword(),
                    joint.id
                ),
            );
            return None;
        }
    };
    Some((Some(c), i, j, coordinate))
}

/// Every GCON, appended to `constraints`: `f(q) = 0` with its I marker. Errors: a duplicate
/// id, the I marker missing or unusable, FUNCTION missing.
pub(crate) fn gcons(
    ds: &Dataset,
    table: &MarkerTable,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = HashSet::new();
    for g in &ds.gcons {
        let name = &g.header.name;
        if !cx.unique(&mut seen, "GCON", &g.header) {
            continue;
        }
        let Some(i) = g.i else {
            cx.error(g.header.span, format!("{name}: I marker is missing"));
            continue;
        };
        let Some(i) = table.constraint_marker(cx, i, name) else {
            continue;
        };
        if g.function.is_none() {
            cx.error(g.header.span, format!("{name}: FUNCTION is missing"));
            continue;
        }
        constraints.push(Constraint {
            origin: origin("GCON", &g.header),
            kind: ConstraintKind::Gcon {
                i,
                expr: g
                    .function
                    .as_ref()
                    .map(|f| linkage_expr::parse(&f.value.expr.text).map(Arc::new)),
                function: g.function.clone(),
            },
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::model::{ConstraintKind, MotionCoordinate};
    use linkage_adm::MotionAxis;

    const JOINTS: &str = "JOINT/1, REVOLUTE, I = 20, J = 1\nJOINT/2, TRANSLATIONAL, I = 30, J = 2\nJOINT/3, CYLINDRICAL, I = 30, J = 21\n";

    #[test]
    fn motions_drive_the_joint_coordinate_or_a_marker_axis() {
        let b = ok(&format!("{JOINTS}MOTION/1, JOINT = 1, FUNCTION = TIME\nMOTION/2, JOINT = 2, FUNCTION = 0\nMOTION/3, JOINT = 3, TRANSLATION, FUNCTION = 0\nMOTION/4, I = 20, J = 1, B2, FUNCTION = 0\nGCON/1, I = 20, FUNCTION = DX(20)"));
        let motion = |k: usize| match &b.model.constraints[k].kind {
            ConstraintKind::Motion {
                joint,
                i,
                j,
                coordinate,
                ..
            } => (
                *joint,
                b.model.markers[*i].id,
                b.model.markers[*j].id,
                *coordinate,
            ),
            other => panic!("{other:?}"),
        };
        assert_eq!(motion(3), (Some(0), 20, 1, MotionCoordinate::RotationZ));
        assert_eq!(motion(4), (Some(1), 30, 2, MotionCoordinate::TranslationZ));
        assert_eq!(motion(5), (Some(2), 30, 21, MotionCoordinate::TranslationZ));
        assert_eq!(
            motion(6),
            (None, 20, 1, MotionCoordinate::Marker(MotionAxis::B2))
        );
        assert_eq!(b.model.constraints[3].description(), "Rotational Motion");
        assert_eq!(b.model.constraints[6].description(), "Rotational Motion");
        let ConstraintKind::Gcon { i, function, expr } = &b.model.constraints[7].kind else {
            panic!("{:?}", b.model.constraints[7])
        };
        assert_eq!(b.model.markers[*i].id, 20);
        assert!(function.is_some());
        // The FUNCTION is parsed once, here, for every analysis.
        let parsed = expr.as_ref().expect("a FUNCTION").as_ref().expect("parses");
        let text = &function.as_ref().unwrap().value.expr.text;
        assert_eq!(**parsed, linkage_expr::parse(text).unwrap());
    }

    #[test]
    fn motion_and_gcon_errors() {
        let e = errors(&format!("{JOINTS}MOTION/1, JOINT = 3, FUNCTION = 0\nMOTION/2, JOINT = 1, TRANSLATION, FUNCTION = 0\nMOTION/3, JOINT = 1\nMOTION/4, JOINT = 8, FUNCTION = 0\nMOTION/4, JOINT = 1, FUNCTION = 0\nGCON/1, FUNCTION = 0\nGCON/2, I = 20"));
        let messages: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
        assert_eq!(
            messages,
            [
                "MOTION_1: a motion on cylindrical JOINT 3 must say TRANSLATION or ROTATION",
                "MOTION_2: cannot drive translation of a REVOLUTE joint (JOINT 1)",
                "MOTION_3: FUNCTION is missing",
                "MOTION_4: JOINT 8 does not exist",
                "duplicate MOTION id 4",
                "GCON_1: I marker is missing",
                "GCON_2: FUNCTION is missing",
            ]
        );
    }
}
