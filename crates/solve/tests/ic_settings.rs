//! Initial conditions under the dataset's IC statement (ERROR, MAXIT, ALIMIT, TLIMIT), joint
//! initial velocities (IC, ICTRAN, ICROT), part initial velocities as least-change targets, and
//! the detection of massless and unconstrained parts, each against a value derived by hand.

use glam::DVec3;
use linkage_model::Model;
use linkage_solve::constraints::drivers::{ExpressionDrivers, NoDrivers};
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::ic::{initial_conditions, InitialConditions};
use linkage_solve::pipeline::verify::verify;
use linkage_solve::tolerances::{Tolerances, UNGIVEN_VELOCITY_WEIGHT};
use std::path::Path;
use std::sync::Arc;

fn model_of(text: &str) -> Model {
    let ds =
        linkage_adm::parse_dataset(Arc::from("ic.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

fn ic_of(m: &Model) -> InitialConditions {
    let d = ExpressionDrivers::new(m).unwrap();
    initial_conditions(
        m,
        &linkage_solve::constraints::system::System::new(m),
        &d,
        &NoForces,
        &Tolerances::default(),
    )
}

fn exploded_fourbar(ic_statement: &str) -> Model {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../mechanisms/exploded_fourbar.adm"),
    )
    .unwrap()
    .replace("\nEND", &format!("\n{ic_statement}\nEND"));
    model_of(&text)
}

/// The coupler's rotation and translation of the exploded four-bar's assembly.
fn coupler_change(m: &Model, ic: &InitialConditions) -> (f64, DVec3) {
    let c = ic
        .moved
        .iter()
        .find(|p| m.parts[p.part].origin.name == "coupler")
        .unwrap();
    (c.rotation_deg, c.translation)
}

/// MAXIT bounds the iterations (two are not enough to close the exploded loop: no
/// convergence); ALIMIT and TLIMIT bound each step, so the ~5.6° and 0.23 m the coupler must
/// move take at least 5.6/0.5 and 0.23/0.02 iterations, to the same least-change result;
/// a looser ERROR stops earlier with a residual within it.
#[test]
fn ic_statement_settings_bound_the_assembly_iterations() {
    let default = exploded_fourbar("");
    let reference = ic_of(&default);
    assert!(reference.assembly.converged);
    let (rot, tr) = coupler_change(&default, &reference);
    assert!(rot > 5.0 && tr.length() > 0.2, "{rot} {tr}");

    let m = exploded_fourbar("IC/MAXIT = 2");
    let ic = ic_of(&m);
    assert!(!ic.assembly.converged);
    assert_eq!(ic.assembly.iterations, 2);
    assert!(ic.assembly.max_residual > 1e-10);

    for (statement, at_least) in [
        (
            "IC/ALIMIT = 0.5D, MAXIT = 100",
            (rot / 0.5).floor() as usize,
        ),
        (
            "IC/TLIMIT = 0.02, MAXIT = 100",
            (tr.length() / 0.02).floor() as usize,
        ),
    ] {
        let m = exploded_fourbar(statement);
        let ic = ic_of(&m);
        assert!(ic.assembly.converged, "{statement}");
        assert!(
            ic.assembly.iterations >= at_least,
            "{statement}: {} iterations",
            ic.assembly.iterations
        );
        // Same least change (to the default ERROR 1e-10, with margin).
        let (r, t) = coupler_change(&m, &ic);
        assert!((r - rot).abs() < 1e-7, "{statement}: {r} vs {rot}");
        assert!((t - tr).length() < 1e-9, "{statement}: {t} vs {tr}");
    }

    let m = exploded_fourbar("IC/ERROR = 1E-4");
    let ic = ic_of(&m);
    assert!(ic.assembly.converged);
    assert!(ic.assembly.max_residual <= 1e-4);
    assert!(
        ic.assembly.iterations < reference.assembly.iterations,
        "{} vs {}",
        ic.assembly.iterations,
        reference.assembly.iterations
    );
}

const HEADER: &str = "ic
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1
";

/// JOINT IC (revolute: rotation, rate) and ICTRAN/ICROT (cylindrical) are held exactly: a rod
/// pinned at its top end (CM 0.5 below) given IC = 10D, 2 is turned by 10° and spins at
/// 2 rad/s, its CM moving at ω × r; a sleeve on a cylindrical given ICTRAN = 0.1, 0.5 and
/// ICROT = 20D, −1 sits 0.1 up the axis turned by 20°, rising at 0.5 and turning at −1 rad/s.
#[test]
fn joint_initial_displacements_and_velocities_are_held() {
    let m = model_of(&format!(
        "{HEADER}PART/2, MASS = 2, CM = 20, IP = 0.2, 0.2, 0.01, QG = 0, -0.5, 0
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 0, 0.5, 0
JOINT/1, REVOLUTE, I = 21, J = 1, IC = 10D, 2
MARKER/3, PART = 1, QP = 2, 0, 0
PART/3, MASS = 1, CM = 30, IP = 0.1, 0.1, 0.1, QG = 2, 0, 0
MARKER/30, PART = 3
JOINT/2, CYLINDRICAL, I = 30, J = 3, ICTRAN = 0.1, 0.5, ICROT = 20D, -1
END
"
    ));
    let ic = ic_of(&m);
    assert!(ic.assembly.converged);
    let v = ic.velocity.as_ref().unwrap();
    assert!(v.converged, "{}", v.max_error);
    let s = &ic.assembly.state;
    // Rod: CM at Rz(10°)·(0, −0.5, 0), ω = 2 z, v = ω × r.
    let th = 10f64.to_radians();
    let r = DVec3::new(0.5 * th.sin(), -0.5 * th.cos(), 0.0);
    assert!((s.poses[0].p - r).length() < 1e-10, "{:?}", s.poses[0].p);
    assert!((v.velocities[0].1 - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-10);
    assert!(
        (v.velocities[0].0 - DVec3::new(0.0, 0.0, 2.0).cross(r)).length() < 1e-10,
        "{:?}",
        v.velocities[0].0
    );
    // Sleeve.
    assert!((s.poses[1].p - DVec3::new(2.0, 0.0, 0.1)).length() < 1e-10);
    let x = s.poses[1].r.x_axis;
    assert!((x.y.atan2(x.x) - 20f64.to_radians()).abs() < 1e-10);
    assert!((v.velocities[1].0 - DVec3::new(0.0, 0.0, 0.5)).length() < 1e-10);
    assert!((v.velocities[1].1 - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-10);
}

/// Part velocities are least-change targets (weights 1/L² on VX, VY, VZ and 1 on WX, WY, WZ,
/// UNGIVEN_VELOCITY_WEIGHT on those not given): a free block takes its VX and WZ exactly; a rod
/// pinned 0.5 above its CM can only have v_x = 0.5 ω, so VX = 1 alone gives
/// ω = 0.5 w/(0.25 w + u) (w = 1/L², u the ungiven weight) and VX = 1 with WZ = 1 gives the
/// compromise ω = (0.5 w + 1)/(0.25 w + 1).
#[test]
fn part_initial_velocities_are_least_change_targets() {
    let text = |rod_velocity: &str| {
        format!(
            "{HEADER}PART/2, MASS = 2, CM = 20, IP = 0.2, 0.2, 0.01, QG = 0, -0.5, 0{rod_velocity}
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 0, 0.5, 0
JOINT/1, REVOLUTE, I = 21, J = 1
PART/3, MASS = 1, CM = 30, IP = 0.1, 0.1, 0.1, QG = 3, 0, 0, VX = 1, WZ = 2
MARKER/30, PART = 3
END
"
        )
    };
    let omega = |rod_velocity: &str| {
        let m = model_of(&text(rod_velocity));
        let ic = ic_of(&m);
        let v = ic.velocity.as_ref().unwrap();
        assert!(v.converged);
        // The free block.
        assert!((v.velocities[1].0 - DVec3::X).length() < 1e-12);
        assert!((v.velocities[1].1 - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        // The rod turns about the pin at the origin: v = ω × (0, −0.5, 0) = (0.5 ω, 0, 0).
        let (lin, ang) = v.velocities[0];
        assert!((lin - DVec3::new(0.5 * ang.z, 0.0, 0.0)).length() < 1e-12);
        (ang.z, 1.0 / m.characteristic_length.powi(2))
    };
    let u = UNGIVEN_VELOCITY_WEIGHT;
    let (got, w) = omega(", VX = 1");
    let want = 0.5 * w / (0.25 * w + u);
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    let (got, w) = omega(", VX = 1, WZ = 1");
    let want = (0.5 * w + 1.0) / (0.25 * w + 1.0);
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
    assert!(got > 1.0 && got < 2.0);
}

/// Verify names a part no constraint touches, a part whose constraints do not reach ground, a
/// massless part and which of its coordinates the constraints leave free (a massless ball on a
/// SPHERICAL: its three rotations; welded: none); the acceleration IC reports a massless part
/// that is free to move rather than dividing by its zero mass.
#[test]
fn massless_and_unconstrained_parts_are_detected() {
    let m = model_of(&format!(
        "{HEADER}PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2
JOINT/1, REVOLUTE, I = 20, J = 1
PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = 5, 0, 0
MARKER/30, PART = 3
PART/4, CM = 40, QG = 1, 0, 0
MARKER/40, PART = 4
MARKER/41, PART = 2, QP = 1, 0, 0
JOINT/2, SPHERICAL, I = 40, J = 41
PART/5, CM = 50, QG = 0, 1, 0
MARKER/50, PART = 5
MARKER/51, PART = 2, QP = 0, 1, 0
JOINT/3, FIXED, I = 50, J = 51
PART/6, MASS = 1, CM = 60, IP = 1, 1, 1, QG = 0, 0, 4
MARKER/60, PART = 6
PART/7, MASS = 1, CM = 70, IP = 1, 1, 1, QG = 0, 0, 5
MARKER/70, PART = 7
JOINT/4, SPHERICAL, I = 70, J = 60
END
"
    ));
    let name = |k: usize| m.parts[k].origin.name.as_str();
    let names = |ks: &[usize]| ks.iter().map(|&k| name(k).to_string()).collect::<Vec<_>>();
    let v = verify(&m, &NoDrivers, &Tolerances::default());
    assert_eq!(names(&v.unconstrained_parts), ["PART_3"]);
    let mut ungrounded = names(&v.ungrounded_parts);
    ungrounded.sort();
    assert_eq!(ungrounded, ["PART_6", "PART_7"]);
    assert_eq!(names(&v.massless_parts), ["PART_4", "PART_5"]);
    assert_eq!(v.massless_free.len(), 1, "{:?}", v.massless_free);
    assert_eq!(name(v.massless_free[0].part), "PART_4");
    assert_eq!(v.massless_free[0].coordinates, ["rx", "ry", "rz"]);

    let ic = ic_of(&m);
    assert!(ic.assembly.converged);
    let err = ic
        .acceleration
        .as_ref()
        .expect("the acceleration IC ran")
        .as_ref()
        .expect_err("a free massless part has no acceleration");
    assert!(err.to_string().contains("PART_4"), "{err}");
}
