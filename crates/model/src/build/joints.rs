//! `JOINT/` and `JPRIM/`: the two-marker constraints, with joint initial conditions.

use super::context::{origin, Ctx};
use super::lookup::MarkerTable;
use crate::model::{Constraint, ConstraintKind, JointInitial};
use linkage_adm::{Dataset, JointType, Located};
use std::collections::{HashMap, HashSet};

/// Every JOINT, appended to `constraints`; returns joint id → index into `constraints`.
/// Errors: a duplicate id, unusable markers or markers on one body, a RACKPIN without PD or a
/// SCREW without PITCH. Warning: `IC` on a joint that is neither revolute nor translational.
pub(crate) fn joints(
    ds: &Dataset,
    table: &MarkerTable,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) -> HashMap<u64, usize> {
    let mut joint_index: HashMap<u64, usize> = HashMap::with_capacity(ds.joints.len());
    for jt in &ds.joints {
        // A joint refused below leaves its id free (no duplicate error for a later one).
        if joint_index.contains_key(&jt.header.id) {
            cx.error(
                jt.header.span,
                format!("duplicate JOINT id {}", jt.header.id),
            );
            continue;
        }
        let Some((i, j)) = table.constraint_pair(cx, jt.i, jt.j, &jt.header) else {
            continue;
        };
        let pd = jt.pd.as_ref().map(|v| v.value);
        let pitch = jt.pitch.as_ref().map(|v| v.value);
        if !gearing_given(jt, pd, pitch, cx) {
            continue;
        }
        let initial = joint_initial(jt, cx);
        joint_index.insert(jt.header.id, constraints.len());
        constraints.push(Constraint {
            origin: origin("JOINT", &jt.header),
            kind: ConstraintKind::Joint {
                kind: jt.kind,
                i,
                j,
                initial,
                pd,
                pitch,
            },
        });
    }
    joint_index
}

/// False, after an error, for a RACKPIN without a non-zero pitch diameter `pd` or a SCREW
/// without a non-zero `pitch` (the ratio that couples their two motions).
fn gearing_given(
    jt: &linkage_adm::Joint,
    pd: Option<f64>,
    pitch: Option<f64>,
    cx: &mut Ctx,
) -> bool {
    match jt.kind {
        JointType::Rackpin if pd.is_none_or(|v| v == 0.0) => {
            cx.error(
                jt.header.span,
                format!(
                    "{}: RACKPIN needs a non-zero PD (pitch diameter)",
                    jt.header.name
                ),
            );
            false
        }
        JointType::Screw if pitch.is_none_or(|v| v == 0.0) => {
            cx.error(
                jt.header.span,
                format!("{}: SCREW needs a non-zero PITCH", jt.header.name),
            );
            false
        }
        _ => true,
    }
}

/// A joint's initial conditions: `IC = disp, vel` of a revolute (rotation) or translational
/// (translation) joint, `ICTRAN` and `ICROT` of any joint (they win over `IC`).
fn joint_initial(jt: &linkage_adm::Joint, cx: &mut Ctx) -> JointInitial {
    let mut initial = JointInitial::default();
    let pair = |v: &Located<Vec<f64>>| (v.value.first().copied(), v.value.get(1).copied());
    if let Some(ic) = &jt.ic {
        initial.span = Some(ic.span);
        match jt.kind {
            JointType::Revolute => initial.rotation = pair(ic),
            JointType::Translational => initial.translation = pair(ic),
            _ => cx.warn(
                ic.span,
                format!(
                    "{}: IC applies to revolute and translational joints only; ignored",
                    jt.header.name
                ),
            ),
        }
    }
    if let Some(v) = &jt.ictran {
        initial.span = Some(v.span);
        initial.translation = pair(v);
    }
    if let Some(v) = &jt.icrot {
        initial.span = initial.span.or(Some(v.span));
        initial.rotation = pair(v);
    }
    initial
}

/// Every JPRIM, appended to `constraints`. Errors: a duplicate id, unusable markers or
/// markers on one body.
pub(crate) fn jprims(
    ds: &Dataset,
    table: &MarkerTable,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = HashSet::new();
    for jp in &ds.jprims {
        if !cx.unique(&mut seen, "JPRIM", &jp.header) {
            continue;
        }
        let Some((i, j)) = table.constraint_pair(cx, jp.i, jp.j, &jp.header) else {
            continue;
        };
        constraints.push(Constraint {
            origin: origin("JPRIM", &jp.header),
            kind: ConstraintKind::Jprim {
                kind: jp.kind,
                i,
                j,
            },
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::model::{ConstraintKind, JointInitial};
    use linkage_adm::{JointType, JprimType, Span};

    #[test]
    fn joint_initial_conditions_by_joint_type() {
        let b = ok("JOINT/1, REVOLUTE, I = 20, J = 1, IC = 0.5, 2\nJOINT/2, TRANSLATIONAL, I = 30, J = 2, IC = 3\nJOINT/3, CYLINDRICAL, I = 21, J = 30, ICTRAN = 1, 2, ICROT = 4\nJOINT/4, SPHERICAL, I = 21, J = 1, IC = 1");
        let initial = |k: usize| match &b.model.constraints[k].kind {
            ConstraintKind::Joint { initial, .. } => initial.clone(),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            initial(0),
            JointInitial {
                translation: (None, None),
                rotation: (Some(0.5), Some(2.0)),
                span: Some(Span::new(12, 35)),
            }
        );
        assert_eq!(initial(1).translation, (Some(3.0), None));
        assert_eq!(initial(2).translation, (Some(1.0), Some(2.0)));
        assert_eq!(initial(2).rotation, (Some(4.0), None));
        // IC on a spherical joint: ignored (its position is kept for messages).
        assert_eq!(
            (initial(3).translation, initial(3).rotation, initial(3).span),
            ((None, None), (None, None), Some(Span::new(15, 36)))
        );
        assert_eq!(b.warnings.len(), 1);
        assert_eq!(
            b.warnings[0].message,
            "JOINT_4: IC applies to revolute and translational joints only; ignored"
        );
        assert_eq!(b.model.constraints[0].description(), "Revolute Joint");
    }

    #[test]
    fn joint_and_jprim_errors() {
        let e = errors("JOINT/1, RACKPIN, I = 20, J = 1\nJOINT/1, REVOLUTE, I = 20, J = 21\nJOINT/2, SCREW, I = 20, J = 30, PITCH = 0\nJOINT/3, REVOLUTE, I = 99, J = 22\nJOINT/3, REVOLUTE, I = 20, J = 1\nJOINT/3, REVOLUTE, I = 20, J = 1");
        assert_eq!(
            e,
            [
                (
                    12,
                    1,
                    "JOINT_1: RACKPIN needs a non-zero PD (pitch diameter)".to_string()
                ),
                (
                    13,
                    1,
                    "JOINT_1: I marker 20 and J marker 21 are both on PART_2".to_string()
                ),
                (14, 1, "JOINT_2: SCREW needs a non-zero PITCH".to_string()),
                (15, 24, "JOINT_3: marker 99 does not exist".to_string()),
                (
                    15,
                    32,
                    "JOINT_3: marker 22 is FLOATING; a constraint needs a fixed marker".to_string()
                ),
                // A refused joint leaves its id free: only the third JOINT/3 is a duplicate.
                (17, 1, "duplicate JOINT id 3".to_string()),
            ]
        );
        let b = ok("JPRIM/1, INLINE, I = 20, J = 1\nJPRIM/2, ORIENTATION, I = 30, J = 20");
        let kinds: Vec<_> = b
            .model
            .constraints
            .iter()
            .map(|c| match &c.kind {
                ConstraintKind::Jprim { kind, i, j } => {
                    (*kind, b.model.markers[*i].id, b.model.markers[*j].id)
                }
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(
            kinds,
            [(JprimType::Inline, 20, 1), (JprimType::Orientation, 30, 20)]
        );
        assert_eq!(
            errors("JPRIM/1, INLINE, I = 20, J = 1\nJPRIM/1, INLINE, I = 30, J = 1"),
            [(13, 1, "duplicate JPRIM id 1".to_string())]
        );
        let _ = JointType::Revolute;
    }
}
