//! `verify --explain` on mechanisms with known answers: replacement advice (checked by
//! re-verifying the changed model and the rewritten dataset), determinate reactions, singular
//! configurations, Bricard's linkage, conflicting drivers.

use linkage_adm::{JointType, JprimType};
use linkage_model::{ConstraintKind, Model};
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::pipeline::verify::{verify, Verification};
use linkage_solve::stages::explain::repair::realize;
use linkage_solve::stages::explain::{
    explain, ConflictKind, Direction, ElementType, Explanation, Proposal,
};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;

fn model_from_text(name: &str, text: &str) -> Model {
    let ds =
        linkage_adm::parse_dataset(name.into(), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model
}

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn mechanism(name: &str) -> Model {
    model_from_text(name, &mechanism_text(name))
}

fn analyse(m: &Model) -> (Verification, Explanation) {
    let d = ExpressionDrivers::new(m).unwrap();
    let tol = Tolerances::default();
    let v = verify(m, &d, &tol);
    let e = explain(m, &d, &tol, &v);
    (v, e)
}

fn kinds(p: &Proposal) -> Vec<ElementType> {
    let mut k: Vec<ElementType> = p
        .changes
        .iter()
        .flat_map(|c| c.into.iter().map(|n| n.kind))
        .collect();
    k.sort_by_key(|t| format!("{t:?}"));
    k
}

/// Verifies the changed model, and the dataset rewritten with the proposal's edits.
fn verify_applied(name: &str, p: &Proposal) -> (i64, usize) {
    let text = mechanism_text(name);
    let ds = linkage_adm::parse_dataset(name.into(), &text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let real = realize(&m, &p.changes);
    let tol = Tolerances::default();
    let d = ExpressionDrivers::new(&real.model).unwrap();
    let v = verify(&real.model, &d, &tol);
    let written = linkage_adm::edit::apply_edits(&ds, &real.edits).unwrap();
    let m2 = model_from_text("written.adm", &written);
    let d2 = ExpressionDrivers::new(&m2).unwrap();
    let v2 = verify(&m2, &d2, &tol);
    assert_eq!((v.dof, v.redundant.len()), (v2.dof, v2.redundant.len()));
    assert_eq!(m2.constraints.len(), real.model.constraints.len());
    (v2.dof, v2.redundant.len())
}

#[test]
fn fourbar_takes_a_single_inline_or_a_spherical_and_a_universal() {
    let (v, e) = analyse(&mechanism("fourbar.adm"));
    assert_eq!((v.dof, v.redundant.len()), (1, 3));
    assert!(!e.suggestions.is_empty());
    // Single changes first; every one shown removes the whole redundancy, keeping DOF 1.
    let first = &e.suggestions[0];
    assert_eq!(first.changes.len(), 1);
    assert_eq!(kinds(first), [ElementType::Jprim(JprimType::Inline)]);
    for p in &e.suggestions {
        assert_eq!((p.dof_after, p.redundant_after), (1, 0));
        assert!(p.indeterminate_after.is_empty());
    }
    let counts: Vec<usize> = e.suggestions.iter().map(|p| p.changes.len()).collect();
    assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
    assert_eq!(verify_applied("fourbar.adm", first), (1, 0));

    let pair = e
        .suggestions
        .iter()
        .find(|p| {
            kinds(p)
                == [
                    ElementType::Joint(JointType::Spherical),
                    ElementType::Joint(JointType::Universal),
                ]
        })
        .expect("a spherical + universal proposal");
    assert_eq!(pair.changes.len(), 2);
    assert_eq!(verify_applied("fourbar.adm", pair), (1, 0));
    // The universal's cross pin: one marker turned so that z_i ⟂ z_j at the input pose.
    let m = mechanism("fourbar.adm");
    let real = realize(&m, &pair.changes);
    let u = pair
        .changes
        .iter()
        .find(|c| c.into[0].kind == ElementType::Joint(JointType::Universal))
        .unwrap();
    let ConstraintKind::Joint { i, j, .. } = real.model.constraints[u.element].kind else {
        panic!("not a joint");
    };
    let zi = real.model.marker_in_ground(i).1.z_axis;
    let zj = real.model.marker_in_ground(j).1.z_axis;
    assert!(zi.dot(zj).abs() < 1e-12, "{zi} {zj}");
    // And the pin is not along the coupler (that would leave its spin free): the pin on the
    // coupler side is the in-plane normal, perpendicular to global z as well.
    assert!((zi.z.abs() < 1e-12) || (zj.z.abs() < 1e-12));
}

#[test]
fn fourbar_in_plane_reactions_are_determinate_out_of_plane_are_not() {
    let (_, e) = analyse(&mechanism("fourbar.adm"));
    assert_eq!(e.reactions.len(), 4);
    for r in &e.reactions {
        // J axes: z along global z (the hinge axes); x, y in the plane.
        assert_eq!(r.determinate, [Direction::Force(0), Direction::Force(1)]);
        assert_eq!(
            r.indeterminate,
            [
                Direction::Force(2),
                Direction::Torque(0),
                Direction::Torque(1)
            ]
        );
    }
}

#[test]
fn door_spherical_and_inline_make_the_axial_hinge_forces_determinate() {
    let m = mechanism("door_two_hinges.adm");
    let (v, e) = analyse(&m);
    assert_eq!((v.dof, v.redundant.len()), (1, 5));
    // The hinges' J axes: z is the hinge axis (global y).
    for r in &e.reactions {
        let (_, rj) = m.marker_in_ground(m.constraints[r.element].markers().unwrap().1);
        assert!((rj.z_axis - glam::DVec3::Y).length() < 1e-12);
        assert!(
            r.indeterminate.contains(&Direction::Force(2)),
            "{}: {:?}",
            m.constraints[r.element].origin.name,
            r.indeterminate
        );
    }
    assert_eq!(e.reactions.len(), 2);
    let p = e
        .suggestions
        .iter()
        .find(|p| {
            kinds(p)
                == [
                    ElementType::Joint(JointType::Spherical),
                    ElementType::Jprim(JprimType::Inline),
                ]
        })
        .expect("a spherical + inline proposal");
    assert_eq!((p.dof_after, p.redundant_after), (1, 0));
    assert!(p.indeterminate_after.is_empty());
    // The hinge made spherical carries the whole axial force, now determinate; the inline
    // primitive carries none (its axis is free), so nothing axial stays indeterminate.
    let spherical = p
        .changes
        .iter()
        .find(|c| c.into[0].kind == ElementType::Joint(JointType::Spherical))
        .unwrap();
    let name = &m.constraints[spherical.element].origin.name;
    let made = p.now_determinate.iter().find(|r| &r.name == name).unwrap();
    assert_eq!(
        made.directions,
        [
            Direction::Force(0),
            Direction::Force(1),
            Direction::Force(2)
        ]
    );
    assert_eq!(verify_applied("door_two_hinges.adm", p), (1, 0));
    // After the change no reaction is indeterminate.
    let real = realize(&m, &p.changes);
    let (v2, e2) = analyse(&real.model);
    assert!(v2.redundant.is_empty());
    assert!(e2.reactions.iter().all(|r| r.indeterminate.is_empty()));
    assert!(e2.reactions.iter().all(|r| !r.determinate.is_empty()));
    assert!(e2.suggestions.is_empty());
}

#[test]
fn parallelogram_chain_with_horizontal_cranks_is_a_singular_configuration() {
    let text = linkage_solve::generate::parallelogram_chain(3, 0.0);
    let m = model_from_text("chain0.adm", &text);
    let (v, e) = analyse(&m);
    // At the collinear pose each loop gains an in-plane mobility.
    assert_eq!((v.dof, v.redundant.len()), (4, 12));
    let mob = &e.mobility;
    assert!(mob.singular);
    assert_eq!((mob.at_input.dof, mob.at_input.redundant), (4, 12));
    let g = mob.generic.unwrap();
    assert_eq!((g.dof, g.redundant), (1, 9));
    // Proposals are checked at the regular configuration: one change per loop.
    assert!(e.suggestions_at_regular_configuration);
    let p = &e.suggestions[0];
    assert_eq!((p.dof_after, p.redundant_after, p.changes.len()), (1, 0, 3));

    for m in [
        model_from_text(
            "chain60.adm",
            &linkage_solve::generate::parallelogram_chain(3, 60.0),
        ),
        mechanism("fourbar_parallelogram_chain3.adm"),
    ] {
        let (v, e) = analyse(&m);
        assert_eq!((v.dof, v.redundant.len()), (1, 9));
        assert!(!e.mobility.singular);
        let g = e.mobility.generic.unwrap();
        assert_eq!((g.dof, g.redundant), (1, 9));
        assert_eq!(
            e.mobility.assembled_trials, e.mobility.trials,
            "{:?}",
            e.mobility.generic
        );
        assert!(!e.suggestions_at_regular_configuration);
    }
}

#[test]
fn bricard_linkage_moves_with_one_structural_redundancy() {
    let m = mechanism("bricard.adm");
    let (v, e) = analyse(&m);
    assert_eq!(v.moving_parts, 5);
    assert_eq!(v.rows, 30);
    assert_eq!(v.gruebler, 0);
    assert!(v.assembled && v.misaligned.is_empty());
    assert_eq!((v.dof, v.redundant.len()), (1, 1));
    let g = e.mobility.generic.unwrap();
    assert_eq!((g.dof, g.redundant), (1, 1));
    assert!(!e.mobility.singular);
    assert_eq!((e.mobility.assembled_trials, e.mobility.trials), (3, 3));
    // A single joint made weaker (e.g. a cylindrical) removes the redundancy.
    let p = &e.suggestions[0];
    assert_eq!((p.changes.len(), p.dof_after, p.redundant_after), (1, 1, 0));
    assert_eq!(verify_applied("bricard.adm", p), (1, 0));
    // Every joint's reaction is indeterminate before (one loop, one redundancy).
    assert_eq!(e.reactions.len(), 6);
    assert!(e.reactions.iter().all(|r| !r.indeterminate.is_empty()));
}

#[test]
fn motion_and_joint_ic_on_the_same_rotation_conflict() {
    let m = mechanism("revolute_motion_ic_conflict.adm");
    let (v, e) = analyse(&m);
    assert_eq!((v.dof, v.redundant.len()), (0, 0));
    assert_eq!(e.conflicts.len(), 1, "{:?}", e.conflicts);
    let c = &e.conflicts[0];
    assert_eq!(c.name, "hinge");
    assert_eq!(c.what, "IC rotation");
    assert_eq!(c.kind, ConflictKind::Conflict);
    assert_eq!(c.with, ["hinge_drive (Rotational Motion)"]);
    assert!(!c.with_constraints_only);
    // IC = 10D against the motion's 0 at T = 0.
    assert!(
        (c.mismatch.unwrap().abs() - 10.0).abs() < 1e-9,
        "{:?}",
        c.mismatch
    );
    // With IC = 0D the two agree: a duplicate.
    let text = mechanism_text("revolute_motion_ic_conflict.adm").replace("IC = 10D", "IC = 0D");
    let (_, e) = analyse(&model_from_text("same.adm", &text));
    assert_eq!(e.conflicts.len(), 1);
    assert_eq!(e.conflicts[0].kind, ConflictKind::Duplicate);
    assert!(e.conflicts[0].mismatch.unwrap().abs() < 1e-9);
}

#[test]
fn second_motion_and_exact_coordinates_on_a_pinned_part_are_named() {
    let text = mechanism_text("revolute_motion_ic_conflict.adm")
        .replace(", IC = 10D\n", "\n")
        .replace(
            ", IP = 0.16666666666666666, 0.0001, 0.16666666666666666\n",
            ", IP = 0.16666666666666666, 0.0001, 0.16666666666666666\n, EXACT = X:Y\n",
        )
        .replace(
            "!\nACCGRAV/",
            "!\nMOTION/2\n, ROTATIONAL\n, JOINT = 1\n, FUNCTION = 60.0D * TIME + 5D\n!\nACCGRAV/",
        );
    let m = model_from_text("drivers.adm", &text);
    let (v, e) = analyse(&m);
    // The second motion is redundant for verify as well.
    assert_eq!(v.redundant.len(), 1);
    let second = e
        .conflicts
        .iter()
        .find(|c| c.name == "MOTION_2")
        .expect("MOTION_2 named");
    assert_eq!(second.kind, ConflictKind::Conflict);
    assert_eq!(second.with, ["hinge_drive (Rotational Motion)"]);
    assert!((second.mismatch.unwrap().abs() - 5.0).abs() < 1e-9);
    // The rod's CM position is fixed by the hinge already (it swings about the pin, and the
    // hinge pins its top end): EXACT X and Y of the CM duplicate the constraints and motion.
    let exact: Vec<_> = e.conflicts.iter().filter(|c| c.name == "rod").collect();
    assert_eq!(exact.len(), 2, "{:?}", e.conflicts);
    for c in exact {
        assert!(c.what.starts_with("EXACT"));
        assert_eq!(c.kind, ConflictKind::Duplicate);
    }
}

#[test]
fn a_tree_has_determinate_reactions_and_needs_no_change() {
    let (v, e) = analyse(&mechanism("pendulum.adm"));
    assert_eq!((v.dof, v.redundant.len()), (1, 0));
    assert!(e.suggestions.is_empty());
    assert!(e.conflicts.is_empty());
    assert!(!e.mobility.singular);
    assert_eq!(e.mobility.generic.unwrap().dof, 1);
    assert_eq!(e.reactions.len(), 1);
    assert!(e.reactions[0].indeterminate.is_empty());
    assert_eq!(
        e.reactions[0].determinate,
        [
            Direction::Force(0),
            Direction::Force(1),
            Direction::Force(2),
            Direction::Torque(0),
            Direction::Torque(1)
        ]
    );
}

#[test]
fn every_slider_crank_proposal_verifies_after_rewriting_the_dataset() {
    let (v, e) = analyse(&mechanism("slider_crank.adm"));
    assert_eq!((v.dof, v.redundant.len()), (1, 3));
    assert!(!e.suggestions.is_empty());
    for p in &e.suggestions {
        assert_eq!((p.dof_after, p.redundant_after), (1, 0));
        assert_eq!(verify_applied("slider_crank.adm", p), (1, 0));
    }
}

#[test]
fn translational_with_three_redundant_rotations_becomes_an_inline_primitive() {
    // A slider on a translational joint along global x whose orientation a JPRIM ORIENTATION
    // fixes a second time.
    let text = "slider\nUNITS/\n, FORCE = NEWTON\n, MASS = KILOGRAM\n, LENGTH = METER\n\
        , TIME = SECOND\nPART/1\n, GROUND\nMARKER/1\n, PART = 1\n, REULER = 90D, 90D, 0D\n\
        PART/2\n, MASS = 1\n, CM = 3\n, IP = 1, 1, 1\nMARKER/2\n, PART = 2\n\
        , REULER = 90D, 90D, 0D\nMARKER/3\n, PART = 2\n, QP = 0.5, 0.2, 0\n\
        !  adams_view_name='rail'\nJOINT/1\n, TRANSLATIONAL\n, I = 2\n, J = 1\n\
        JPRIM/1\n, ORIENTATION\n, I = 2\n, J = 1\nEND\n";
    let m = model_from_text("slider.adm", text);
    let (v, e) = analyse(&m);
    assert_eq!((v.dof, v.redundant.len()), (1, 3));
    let p = &e.suggestions[0];
    assert_eq!(p.changes.len(), 1);
    let (from, to) = p.changes[0].describe(&m);
    assert_eq!(
        (from.as_str(), to.as_str()),
        ("TRANSLATIONAL", "JPRIM INLINE")
    );
    assert_eq!((p.dof_after, p.redundant_after), (1, 0));
    // Applied to the text: the joint becomes a primitive in place, named as before.
    let ds = linkage_adm::parse_dataset("slider.adm".into(), text).unwrap();
    let real = realize(&m, &p.changes);
    let out = linkage_adm::edit::apply_edits(&ds, &real.edits).unwrap();
    assert_eq!(
        out,
        text.replace("JOINT/1\n, TRANSLATIONAL", "JPRIM/2\n, INLINE")
    );
    let m2 = model_from_text("out.adm", &out);
    assert_eq!(m2.constraints[0].origin.name, "rail");
    let (v2, _) = analyse(&m2);
    assert_eq!((v2.dof, v2.redundant.len()), (1, 0));
}
