//! `COUPLER/` and `GEAR/`: constraints between the motions of joints.

use super::context::{origin, Ctx};
use super::lookup::MarkerTable;
use crate::model::{Constraint, ConstraintKind};
use linkage_adm::{CouplerDof, Dataset, IdRef, JointType};
use std::collections::{HashMap, HashSet};

/// The joints built so far, for the elements that refer to joints.
pub(crate) struct Joints<'c> {
    /// Joint id → index into `constraints`.
    pub index: &'c HashMap<u64, usize>,
    pub constraints: &'c [Constraint],
}

impl Joints<'_> {
    /// The constraint index and type of joint `r` referred to by `elem`; an error when there
    /// is no such joint.
    pub fn joint(&self, cx: &mut Ctx, r: IdRef, elem: &str) -> Option<(usize, JointType)> {
        let Some(&c) = self.index.get(&r.id) else {
            cx.error(r.span, format!("{elem}: JOINT {} does not exist", r.id));
            return None;
        };
        match &self.constraints[c].kind {
            ConstraintKind::Joint { kind, .. } => Some((c, *kind)),
            _ => None,
        }
    }
}

/// Every COUPLER, appended to `constraints`: `Σ r_k·q_k = 0` over 2 or 3 joint coordinates,
/// with `r_1 = 1` when one scale fewer than joints is given. Errors: a duplicate id, a joint
/// count other than 2 or 3, SCALES missing (or a USER coupler) or of the wrong count, a
/// missing joint, a joint type or TYPE a coupler cannot use.
pub(crate) fn couplers(
    ds: &Dataset,
    joint_index: &HashMap<u64, usize>,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = HashSet::new();
    for cp in &ds.couplers {
        let name = &cp.header.name;
        if !cx.unique(&mut seen, "COUPLER", &cp.header) {
            continue;
        }
        if cp.joints.len() < 2 || cp.joints.len() > 3 {
            cx.error(
                cp.header.span,
                format!("{name}: JOINTS must name 2 or 3 joints"),
            );
            continue;
        }
        let Some(scales) = coupler_scales(cp, cx) else {
            continue;
        };
        let joints = Joints {
            index: joint_index,
            constraints,
        };
        let mut terms = Vec::new();
        for (k, r) in cp.joints.iter().enumerate() {
            let Some((c, kind)) = joints.joint(cx, *r, name) else {
                continue;
            };
            let Some(dof) = coupled_coordinate(cp, k, kind, *r, cx) else {
                continue;
            };
            terms.push((c, dof, scales[k]));
        }
        if terms.len() == cp.joints.len() {
            constraints.push(Constraint {
                origin: origin("COUPLER", &cp.header),
                kind: ConstraintKind::Coupler {
                    terms,
                    function: cp.function.clone(),
                },
            });
        }
    }
}

/// A coupler's scale per joint: `1, s_2[, s_3]` when one fewer than the joints is given, or
/// as given. An error when SCALES is missing or has another count.
fn coupler_scales(cp: &linkage_adm::Coupler, cx: &mut Ctx) -> Option<Vec<f64>> {
    let name = &cp.header.name;
    if cp.scales.is_empty() {
        let what = if cp.function.as_ref().is_some_and(|f| f.value.user) {
            "a USER subroutine coupler cannot be run by linkage"
        } else {
            "SCALES is missing"
        };
        cx.error(cp.header.span, format!("{name}: {what}"));
        return None;
    }
    let n = cp.joints.len();
    match (n, cp.scales.len()) {
        (2, 1) => Some(vec![1.0, cp.scales[0]]),
        (3, 2) => Some(vec![1.0, cp.scales[0], cp.scales[1]]),
        (a, b) if a == b => Some(cp.scales.clone()),
        _ => {
            cx.error(
                cp.header.span,
                format!("{name}: {} SCALES for {n} joints", cp.scales.len()),
            );
            None
        }
    }
}

/// The coordinate coupled of the coupler's `k`-th joint (`r`, of type `kind`): a revolute
/// joint's rotation, a translational joint's translation, or what `TYPE` names for a
/// cylindrical joint. An error for any other joint or a TYPE that does not fit.
fn coupled_coordinate(
    cp: &linkage_adm::Coupler,
    k: usize,
    kind: JointType,
    r: IdRef,
    cx: &mut Ctx,
) -> Option<CouplerDof> {
    let name = &cp.header.name;
    match (kind, cp.types.get(k)) {
        (JointType::Revolute, t) if t.is_none_or(|t| *t == CouplerDof::Rotation) => {
            Some(CouplerDof::Rotation)
        }
        (JointType::Translational, t) if t.is_none_or(|t| *t == CouplerDof::Translation) => {
            Some(CouplerDof::Translation)
        }
        (JointType::Cylindrical, Some(t)) => Some(*t),
        (JointType::Cylindrical, None) => {
            cx.error(
                r.span,
                format!(
                    "{name}: TYPE must say T or R for cylindrical JOINT {}",
                    r.id
                ),
            );
            None
        }
        _ => {
            cx.error(r.span, format!("{name}: JOINT {} is {}, a coupler needs a revolute, translational or cylindrical joint (with a matching TYPE)", r.id, kind.keyword()));
            None
        }
    }
}

/// Every GEAR, appended to `constraints`: two joints and the common-velocity marker CV.
/// Errors: a duplicate id, not two joints, CV missing or unusable, a missing joint, a joint
/// that is not revolute, translational or cylindrical (reported, the gear is still kept).
pub(crate) fn gears(
    ds: &Dataset,
    table: &MarkerTable,
    joint_index: &HashMap<u64, usize>,
    cx: &mut Ctx,
    constraints: &mut Vec<Constraint>,
) {
    let mut seen = HashSet::new();
    for g in &ds.gears {
        let name = &g.header.name;
        if !cx.unique(&mut seen, "GEAR", &g.header) {
            continue;
        }
        if g.joints.len() != 2 {
            cx.error(
                g.header.span,
                format!("{name}: JOINTS must name two joints"),
            );
            continue;
        }
        let Some(cv) = g.cv else {
            cx.error(
                g.header.span,
                format!("{name}: CV (common velocity marker) is missing"),
            );
            continue;
        };
        let joints = Joints {
            index: joint_index,
            constraints,
        };
        let cv = table.constraint_marker(cx, cv, name);
        let a = joints.joint(cx, g.joints[0], name);
        let b = joints.joint(cx, g.joints[1], name);
        let (Some(cv), Some(a), Some(b)) = (cv, a, b) else {
            continue;
        };
        for (r, (_, kind)) in g.joints.iter().zip([a, b]) {
            if !matches!(
                kind,
                JointType::Revolute | JointType::Translational | JointType::Cylindrical
            ) {
                cx.error(r.span, format!("{name}: JOINT {} is {}, a gear needs revolute, translational or cylindrical joints", r.id, kind.keyword()));
            }
        }
        constraints.push(Constraint {
            origin: origin("GEAR", &g.header),
            kind: ConstraintKind::Gear {
                joints: [a.0, b.0],
                cv,
            },
        });
    }
}

#[cfg(test)]
mod tests {
    use crate::build::test_support::{errors, ok};
    use crate::model::ConstraintKind;
    use linkage_adm::CouplerDof;

    const JOINTS: &str = "JOINT/1, REVOLUTE, I = 20, J = 1\nJOINT/2, TRANSLATIONAL, I = 30, J = 2\nJOINT/3, CYLINDRICAL, I = 30, J = 21\nJOINT/4, SPHERICAL, I = 21, J = 1\n";

    #[test]
    fn coupler_scales_start_at_one_and_types_follow_the_joints() {
        let b = ok(&format!(
            "{JOINTS}COUPLER/1, JOINTS = 1, 2, SCALES = -2\nCOUPLER/2, JOINTS = 1, 2, 3, TYPE = R:T:T, SCALES = 3, 4, 5"
        ));
        let terms = |k: usize| match &b.model.constraints[k].kind {
            ConstraintKind::Coupler { terms, .. } => terms.clone(),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            terms(4),
            [
                (0, CouplerDof::Rotation, 1.0),
                (1, CouplerDof::Translation, -2.0)
            ]
        );
        assert_eq!(
            terms(5),
            [
                (0, CouplerDof::Rotation, 3.0),
                (1, CouplerDof::Translation, 4.0),
                (2, CouplerDof::Translation, 5.0)
            ]
        );
    }

    #[test]
    fn coupler_and_gear_errors() {
        let e = errors(&format!("{JOINTS}COUPLER/2, JOINTS = 1, 2\nCOUPLER/3, JOINTS = 1, 3, SCALES = 1\nCOUPLER/4, JOINTS = 1, 4, SCALES = 1\nCOUPLER/5, JOINTS = 1, 2, 3, SCALES = 1\nGEAR/1, JOINTS = 1, 4, CV = 20\nGEAR/2, JOINTS = 1, 9"));
        let messages: Vec<&str> = e.iter().map(|(_, _, m)| m.as_str()).collect();
        assert_eq!(
            messages,
            [
                "COUPLER_2: SCALES is missing",
                "COUPLER_3: TYPE must say T or R for cylindrical JOINT 3",
                "COUPLER_4: JOINT 4 is SPHERICAL, a coupler needs a revolute, translational or cylindrical joint (with a matching TYPE)",
                "COUPLER_5: 1 SCALES for 3 joints",
                "GEAR_1: JOINT 4 is SPHERICAL, a gear needs revolute, translational or cylindrical joints",
                "GEAR_2: CV (common velocity marker) is missing",
            ]
        );
    }

    #[test]
    fn gear_refers_to_two_joints_and_a_common_velocity_marker() {
        let b = ok(&format!("{JOINTS}GEAR/1, JOINTS = 1, 2, CV = 21"));
        let gear = b
            .model
            .constraints
            .last()
            .unwrap_or_else(|| panic!("no constraints"));
        let ConstraintKind::Gear { joints, cv } = &gear.kind else {
            panic!("{gear:?}")
        };
        assert_eq!((*joints, b.model.markers[*cv].id), ([0, 1], 21));
        assert_eq!(gear.origin.element(), "GEAR/1");
    }
}
