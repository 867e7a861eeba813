//! Initial conditions on mechanisms with known answers: assembly, consistency, EXACT and joint
//! initial conditions, reactions against closed-form statics.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::pipeline::ic::{initial_conditions, InitialConditions};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run_text(name: &str, text: &str) -> (Model, InitialConditions) {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let ic = initial_conditions(
        &m,
        &linkage_solve::constraints::system::System::new(&m),
        &d,
        &linkage_solve::physics::applied::NoForces,
        &Tolerances::default(),
    );
    (m, ic)
}

fn run(name: &str) -> (Model, InitialConditions) {
    run_text(name, &mechanism_text(name))
}

fn reaction<'a>(
    m: &Model,
    ic: &'a InitialConditions,
    name: &str,
) -> &'a linkage_solve::physics::reactions::Reaction {
    let acc = ic.acceleration.as_ref().unwrap().as_ref().unwrap();
    acc.reactions
        .iter()
        .find(|r| m.constraints[r.element].origin.name == name)
        .unwrap()
}

#[test]
fn exploded_fourbar_assembles_with_consistent_redundancy() {
    let (m, ic) = run("exploded_fourbar.adm");
    assert!(ic.assembly.converged, "{:?}", ic.assembly.residuals.first());
    assert!(ic.assembly.max_residual < 1e-10);
    // At the assembled configuration the four-bar is planar again: DOF 1, 3 redundant, all
    // consistent (at the exploded input the rank analysis sees a different mechanism).
    assert_eq!(ic.analysis.dof, 1);
    assert_eq!(ic.analysis.redundant.len(), 3);
    assert!(ic
        .analysis
        .redundant
        .iter()
        .all(|r| r.consistent == Some(true)));
    assert!(!ic.inconsistent());
    // The least-change assembly, computed independently: the assembled four-bar is planar
    // (both ground pivots are hinges about global z at z = 0), so it is one crank angle φ away
    // from the closed-form pose of every link; linkage minimises
    // Σ_parts |Δp|²/L² + |Δθ|² (assemble.rs: W = diag(1/L², 1/L², 1/L², 1, 1, 1), Δθ the
    // rotation vector of R Rᵢₙᵀ) over that one-parameter family.
    let expected = least_change_fourbar(&m);
    let moved = |name: &str| {
        ic.moved
            .iter()
            .find(|p| m.parts[p.part].origin.name == name)
            .unwrap_or_else(|| panic!("{name} did not move"))
    };
    for (k, name) in ["crank", "coupler", "rocker"].iter().enumerate() {
        let (dp, dth) = expected[k];
        let got = moved(name);
        // Newton on the KKT system stops at rounding of the residual: the minimiser to 1e-9 m
        // and 1e-7° (the cost is flat to second order at the minimum, the constraints exact).
        assert!(
            (got.translation - dp).length() < 1e-9,
            "{name}: moved by {:?}, least change {dp:?}",
            got.translation
        );
        assert!(
            (got.rotation_deg - dth.to_degrees()).abs() < 1e-7,
            "{name}: turned {}°, least change {}°",
            got.rotation_deg,
            dth.to_degrees()
        );
    }
    // Every violated joint is repaired.
    assert!(!ic.repaired.is_empty());
    assert!(
        ic.repaired.iter().all(|r| r.after.abs() < 1e-8),
        "{:?}",
        ic.repaired
    );
}

/// Least-change assembly of `mechanisms/exploded_fourbar.adm` by an independent route: the
/// closed-form planar four-bar pose at crank angle φ (crank 1, coupler 3.5, rocker 3, ground
/// pivots 4 apart, open branch), the weighted change from the input poses
/// `Σ |Δp|²/L² + |Δθ|²`, minimised over φ. (Bisection on the slope of the
/// cost.) Returns each link's (translation of its centre, rotation angle in radians) for crank, coupler, rocker.
fn least_change_fourbar(m: &Model) -> [(glam::DVec3, f64); 3] {
    use glam::{DMat3, DVec3};
    let input = |name: &str| {
        let p = m.parts.iter().find(|p| p.origin.name == name).unwrap();
        (p.p_gb, p.r_gb)
    };
    let inputs = [input("crank"), input("coupler"), input("rocker")];
    let o4 = DVec3::new(4.0, 0.0, 0.0);
    let poses = |phi: f64| -> [(DVec3, DMat3); 3] {
        let a = DVec3::new(phi.cos(), phi.sin(), 0.0);
        // B: circles |B − A| = 3.5 and |B − O4| = 3, the upper intersection.
        let d = o4 - a;
        let dl = d.length();
        let along = (3.5f64.powi(2) - 3.0f64.powi(2) + dl * dl) / (2.0 * dl);
        let h = (3.5f64.powi(2) - along * along).sqrt();
        let u = d / dl;
        let n = DVec3::new(-u.y, u.x, 0.0);
        let b = a + along * u + h * n;
        let rz = |v: DVec3| DMat3::from_rotation_z(v.y.atan2(v.x));
        [
            (a / 2.0, rz(a)),
            ((a + b) / 2.0, rz(b - a)),
            ((o4 + b) / 2.0, rz(b - o4)),
        ]
    };
    let angle = |r: DMat3| {
        ((r.x_axis.x + r.y_axis.y + r.z_axis.z - 1.0) / 2.0)
            .clamp(-1.0, 1.0)
            .acos()
    };
    let changes = |phi: f64| {
        let p = poses(phi);
        [0, 1, 2].map(|k| {
            (
                p[k].0 - inputs[k].0,
                angle(p[k].1 * inputs[k].1.transpose()),
            )
        })
    };
    let l2 = m.characteristic_length.powi(2);
    let cost = |phi: f64| {
        changes(phi)
            .iter()
            .map(|(dp, dth)| dp.length_squared() / l2 + dth * dth)
            .sum::<f64>()
    };
    // The minimum is where dcost/dφ (central differences, h = 1e-6: truncation ~1e-12,
    // rounding ~1e-10 of a slope that changes by ~1 per radian) changes sign: bisection.
    let slope = |phi: f64| (cost(phi + 1e-6) - cost(phi - 1e-6)) / 2e-6;
    let (mut lo, mut hi) = (50f64.to_radians(), 70f64.to_radians());
    assert!(slope(lo) < 0.0 && slope(hi) > 0.0);
    while hi - lo > 1e-14 {
        let mid = 0.5 * (lo + hi);
        if slope(mid) < 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    changes(0.5 * (lo + hi))
}

#[test]
fn door_with_tilted_hinge_cannot_be_assembled_consistently() {
    let (m, ic) = run("door_tilted_hinge.adm");
    assert!(ic.inconsistent());
    let bad: Vec<_> = ic
        .analysis
        .redundant
        .iter()
        .filter(|r| r.consistent == Some(false))
        .collect();
    assert_eq!(bad.len(), 1);
    let row = &ic.analysis.system.rows[bad[0].row];
    assert_eq!(m.constraints[row.element].origin.name, "hinge_top");
    assert!((bad[0].residual.unwrap().abs() - 2.0).abs() < 1e-6);
}

#[test]
fn door_on_aligned_hinges_carries_its_weight_on_the_kept_rows() {
    let (m, ic) = run("door_two_hinges.adm");
    assert!(ic.assembly.converged && !ic.inconsistent());
    assert!(ic.moved.is_empty());
    let bottom = reaction(&m, &ic, "hinge_bottom");
    let top = reaction(&m, &ic, "hinge_top");
    let weight = 20.0 * 9.80665;
    // Total reaction on the door balances its weight (gravity along −y).
    let total = bottom.force + top.force;
    assert!((total.y - weight).abs() < 1e-9 * weight, "{total:?}");
    assert!(
        total.x.abs() < 1e-9 * weight && total.z.abs() < 1e-9 * weight,
        "{total:?}"
    );
    // The top hinge's translation along the hinge axis (Yg) is a removed row: it carries zero.
    assert!(top.force.y.abs() < 1e-12, "{:?}", top.force);
    // The horizontal couple (forces on the door): its CM 0.4 m out along +x, hinges 1.6 m
    // apart. Moments about the bottom hinge: −0.4·W − 1.6·F_top,x = 0, so the top hinge pulls
    // the door towards the wall, F_top,x = −W/4 = −49.03325 N, and the bottom one pushes it out.
    assert!((top.force.x + 49.03325).abs() < 1e-6, "{:?}", top.force);
    assert!(
        (bottom.force.x - 49.03325).abs() < 1e-6,
        "{:?}",
        bottom.force
    );
}

#[test]
fn hanging_pendulum_reaction_equals_its_weight() {
    let (m, ic) = run("pendulum.adm");
    assert!(ic.assembly.converged);
    let r = reaction(&m, &ic, &m.constraints[0].origin.name);
    let weight = 2.0 * 9.80665;
    // On the I part (the rod, I = 202): straight up, +y, against gravity along −y.
    assert!(
        (r.force - glam::DVec3::new(0.0, weight, 0.0)).length() < 1e-9 * weight,
        "{:?}",
        r.force
    );
    assert!(r.torque.length() < 1e-9, "{:?}", r.torque);
    // At rest: no acceleration.
    let acc = ic.acceleration.as_ref().unwrap().as_ref().unwrap();
    assert!(acc.accelerations[0].0.length() < 1e-12 && acc.accelerations[0].1.length() < 1e-12);
}

#[test]
fn exact_coordinates_are_held_while_other_parts_move() {
    // The rocker's pose is EXACT: the crank and coupler must come to it.
    let text = mechanism_text("exploded_fourbar.adm").replacen(
        "PART/4\n, MASS = 3\n",
        "PART/4\n, MASS = 3\n, EXACT = X:Y:Z:PSI:THETA:PHI\n",
        1,
    );
    assert!(text.contains("EXACT"));
    let (m, ic) = run_text("exploded_exact.adm", &text);
    assert!(ic.assembly.converged, "{:?}", ic.assembly.residuals.first());
    let rocker = m
        .parts
        .iter()
        .position(|p| p.origin.name == "rocker")
        .unwrap();
    let (a, b) = (ic.assembly.state.poses[rocker], &m.parts[rocker]);
    assert!((a.p - b.p_gb).length() < 1e-12, "{:?}", a.p - b.p_gb);
    assert!((0..3).all(|c| (a.r.col(c) - b.r_gb.col(c)).length() < 1e-12));
    assert!(ic
        .moved
        .iter()
        .any(|p| m.parts[p.part].origin.name == "coupler"));
}

#[test]
fn joint_initial_displacement_is_held_exactly() {
    // Crank pivot I and J axes coincide at input (angle 0): ask for 5° at the start.
    let text = mechanism_text("fourbar.adm");
    let key = "adams_view_name='crank_pivot'";
    let at = text.find(key).unwrap();
    let end = text[at..].find("\n, J = ").unwrap() + at;
    let line_end = text[end + 1..].find('\n').unwrap() + end + 1;
    let text = format!("{}\n, IC = 5D{}", &text[..line_end], &text[line_end..]);
    let (m, ic) = run_text("fourbar_ic.adm", &text);
    assert!(ic.assembly.converged, "{:?}", ic.assembly.residuals.first());
    let h = ic.hard.iter().find(|h| h.name == "crank_pivot").unwrap();
    assert!((h.quantity.value(&ic.assembly.state) - 5f64.to_radians()).abs() < 1e-10);
    assert!(
        ic.moved.len() == 3,
        "{:?}",
        ic.moved
            .iter()
            .map(|p| &m.parts[p.part].origin.name)
            .collect::<Vec<_>>()
    );
    assert!(!ic.inconsistent());
}

#[test]
fn adams_slider_crank_assembles_with_a_consistent_redundant_equation() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/bthornton191__adamspy__test__files__generic_model__generic_model.adm");
    if !path.exists() {
        assert!(
            std::env::var_os("CI").is_none(),
            "../shared/corpus is missing under CI"
        );
        eprintln!("notice: ../shared/corpus is absent; corpus test skipped");
        return;
    }
    let (m, ic) = run_text(
        "generic_model.adm",
        &std::fs::read_to_string(&path).unwrap(),
    );
    assert!(ic.assembly.converged);
    assert_eq!(ic.analysis.redundant.len(), 1);
    assert_eq!(ic.analysis.redundant[0].consistent, Some(true));
    let row = &ic.analysis.system.rows[ic.analysis.redundant[0].row];
    assert_eq!(
        (m.constraints[row.element].origin.name.as_str(), row.short),
        ("JOINT_2", "Zi.Xj")
    );
    // The motion drives the crank at 30°/s: the velocity IC must produce it.
    let v = ic.velocity.as_ref().unwrap();
    assert!(v.converged, "{}", v.max_error);
}
