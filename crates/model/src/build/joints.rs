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
    let mut joint_index: HashMap<u64, usize> = HashMap::new();
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
