//! Verify on mechanisms of known mobility (`mechanisms/`, checked independently by
//! `mechanisms/check.py`): Gruebler count, DOF, redundancy, consistency, misalignment.

use linkage_model::Model;
use linkage_solve::constraints::drivers::NoDrivers;
use linkage_solve::pipeline::verify::{verify, Verification};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;

fn verify_file(name: &str) -> (Model, Verification) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    let ds = linkage_adm::read_dataset(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let v = verify(&m, &NoDrivers, &Tolerances::default());
    (m, v)
}

fn mobility(name: &str) -> (i64, i64, usize) {
    let (_, v) = verify_file(name);
    (v.gruebler, v.dof, v.redundant.len())
}

fn redundant_names(m: &Model, v: &Verification) -> Vec<String> {
    v.redundant
        .iter()
        .map(|r| {
            let row = &v.system.rows[r.row];
            format!("{} {}", m.constraints[row.element].origin.name, row.short)
        })
        .collect()
}

#[test]
fn pendulum_has_one_free_rotation() {
    assert_eq!(mobility("pendulum.adm"), (1, 1, 0));
    assert_eq!(mobility("pendulum_offset.adm"), (1, 1, 0));
}

#[test]
fn door_on_two_aligned_hinges_has_five_consistent_redundant_equations() {
    let (m, v) = verify_file("door_two_hinges.adm");
    assert_eq!((v.gruebler, v.dof, v.redundant.len()), (-4, 1, 5));
    assert!(v.misaligned.is_empty());
    assert!(v.assembled);
    for r in &v.redundant {
        assert_eq!(r.consistent, Some(true), "{:?}", redundant_names(&m, &v));
        // Every redundant equation of the second hinge depends on the first hinge's equations.
        assert!(!r.depends_on.is_empty());
    }
    // Translations are admitted first: the second hinge's translation along the hinge axis
    // (global y) duplicates the first's, and the two hinge points already fix the door's tilt,
    // so all four axis-parallelism rows are redundant (the pattern of Adams View's own
    // two-revolute example, ADM-REFERENCE §6.1).
    let mut names = redundant_names(&m, &v);
    names.sort();
    assert_eq!(
        names,
        [
            "hinge_bottom Zi.Xj",
            "hinge_bottom Zi.Yj",
            "hinge_top Yg",
            "hinge_top Zi.Xj",
            "hinge_top Zi.Yj"
        ]
    );
}

#[test]
fn door_with_tilted_hinge_is_inconsistent_on_that_hinge() {
    let (m, v) = verify_file("door_tilted_hinge.adm");
    // Analysed as intended (hinge repaired in place): DOF 1, the second hinge redundant.
    assert_eq!((v.gruebler, v.dof, v.redundant.len()), (-4, 1, 5));
    let bad: Vec<_> = v
        .redundant
        .iter()
        .filter(|r| r.consistent == Some(false))
        .collect();
    assert_eq!(bad.len(), 1, "{:?}", redundant_names(&m, &v));
    for r in &bad {
        let row = &v.system.rows[r.row];
        assert_eq!(m.constraints[row.element].origin.name, "hinge_top");
        assert!(
            row.label.starts_with("Rotation Between Zi"),
            "{}",
            row.label
        );
        // 2° tilt about x, hinge axis along y: the Zi·Yj (or Zi·Xj) row is off by 2°.
        let deg = r.residual.unwrap().abs();
        assert!((deg - 2.0).abs() < 1e-6, "residual {deg}°");
    }
    assert!(v
        .misaligned
        .iter()
        .all(|mis| m.constraints[v.system.rows[mis.row].element].origin.name == "hinge_top"));
    assert!(!v.misaligned.is_empty());
}

#[test]
fn planar_fourbar_of_revolutes_has_three_redundant_rotations() {
    let (m, v) = verify_file("fourbar.adm");
    assert_eq!((v.gruebler, v.dof, v.redundant.len()), (-2, 1, 3));
    assert!(v.redundant.iter().all(|r| r.consistent == Some(true)));
    // With translations admitted first, three out-of-plane rotations of the loop's last joints
    // are the redundant ones (the names Adams Solver gives for this loop order).
    let names = redundant_names(&m, &v);
    assert_eq!(
        names,
        [
            "coupler_rocker Zi.Xj",
            "rocker_pivot Zi.Xj",
            "rocker_pivot Zi.Yj"
        ],
        "{names:?}"
    );
}

#[test]
fn fourbar_with_motion_is_kinematically_determinate() {
    assert_eq!(mobility("fourbar_motion.adm"), (-3, 0, 3));
}

#[test]
fn fourbar_with_spherical_and_universal_has_no_redundancy() {
    assert_eq!(mobility("fourbar_spherical_universal.adm"), (1, 1, 0));
}

#[test]
fn fourbar_with_inline_primitive_has_no_redundancy() {
    assert_eq!(mobility("fourbar_inline.adm"), (1, 1, 0));
}

#[test]
fn slider_crank_has_three_redundant_equations() {
    let (_, v) = verify_file("slider_crank.adm");
    assert_eq!((v.gruebler, v.dof, v.redundant.len()), (-2, 1, 3));
    assert!(v.redundant.iter().all(|r| r.consistent == Some(true)));
}

#[test]
fn bennett_linkage_moves_despite_negative_gruebler() {
    assert_eq!(mobility("bennett.adm"), (-2, 1, 3));
}

#[test]
fn door_on_spherical_and_inline_has_no_redundancy() {
    assert_eq!(mobility("door_hinge_spherical_inline.adm"), (1, 1, 0));
}

#[test]
fn chain_of_three_parallelograms_is_one_loop_block_with_nine_redundant() {
    let (_, v) = verify_file("fourbar_parallelogram_chain3.adm");
    assert_eq!((v.gruebler, v.dof, v.redundant.len()), (-8, 1, 9));
    // One closed-loop block holds every joint.
    assert!(v.topology.blocks.iter().any(|b| b.elements.len() == 10));
}

#[test]
fn exploded_fourbar_reports_its_broken_joints() {
    let (m, v) = verify_file("exploded_fourbar.adm");
    assert!(!v.misaligned.is_empty());
    // Broken at its input: not assembled, so the consistency of its redundancy is unknown.
    assert!(!v.assembled);
    assert!(
        v.redundant.iter().all(|r| r.consistent.is_none()),
        "{:?}",
        v.redundant
    );
    let broken: std::collections::BTreeSet<_> = v
        .misaligned
        .iter()
        .map(|x| {
            m.constraints[v.system.rows[x.row].element]
                .origin
                .name
                .clone()
        })
        .collect();
    assert_eq!(broken.len(), 2, "{broken:?}");
}

/// One row of `mechanisms/check.py`'s EXPECT table: the independent checker's counts.
struct Expected {
    file: String,
    parts: usize,
    rows: usize,
    gruebler: i64,
    dof: i64,
    redundant: usize,
    assembled: bool,
    /// The table's DOF and redundancy are those after assembly (its comment says so).
    after_assembly: bool,
}

/// The EXPECT table of `mechanisms/check.py`, read from the script itself (so the two cannot
/// drift apart).
fn check_py_expectations() -> Vec<Expected> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../mechanisms/check.py");
    let text = std::fs::read_to_string(&path).expect("check.py");
    let start = text.find("EXPECT = {").expect("EXPECT table");
    let body = &text[start..text[start..].find("\n}").map_or(text.len(), |e| start + e)];
    body.lines()
        .filter_map(|line| {
            let line = line.trim();
            let (file, rest) = line.strip_prefix('"')?.split_once("\": (")?;
            let (tuple, comment) = rest.split_once(')')?;
            let f: Vec<&str> = tuple.split(',').map(str::trim).collect();
            let int = |k: usize| f[k].parse::<i64>().expect("an integer");
            Some(Expected {
                file: file.to_string(),
                parts: int(0) as usize,
                rows: int(1) as usize,
                gruebler: int(2),
                dof: int(3),
                redundant: int(4) as usize,
                assembled: f[5] == "True",
                after_assembly: comment.contains("after assembly"),
            })
        })
        .collect()
}

#[test]
fn every_mechanism_has_the_counts_of_the_independent_checker() {
    let expected = check_py_expectations();
    assert!(expected.len() >= 13, "EXPECT rows read: {}", expected.len());
    for e in &expected {
        let (m, v) = verify_file(&e.file);
        let name = &e.file;
        assert_eq!(v.moving_parts, e.parts, "{name}: moving parts");
        assert_eq!(v.rows, e.rows, "{name}: constraint rows");
        assert_eq!(v.gruebler, e.gruebler, "{name}: Gruebler");
        // check.py calls a mechanism assembled when every row holds; linkage's `assembled`
        // is about the independent rows, and an inconsistent redundant row is reported apart.
        let every_row_holds =
            v.assembled && v.redundant.iter().all(|r| r.consistent != Some(false));
        assert_eq!(every_row_holds, e.assembled, "{name}: assembled at input");
        let (dof, redundant) = if e.after_assembly {
            let drivers =
                linkage_solve::constraints::drivers::ExpressionDrivers::new(&m).expect("drivers");
            let a = linkage_solve::pipeline::Assembled::new(
                &m,
                &drivers,
                &linkage_solve::physics::applied::NoForces,
                &Tolerances::default(),
            );
            (a.ic.analysis.dof, a.ic.analysis.redundant.len())
        } else {
            (v.dof, v.redundant.len())
        };
        assert_eq!(
            (dof, redundant),
            (e.dof, e.redundant),
            "{name}: DOF, redundant"
        );
    }
}
