//! Static equilibrium and quasi-statics against closed-form answers.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::statics::{output_times, run, StaticRun};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn solve(name: &str, text: &str, times: &[f64]) -> (Model, StaticRun) {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let r = run(&a, times);
    drop(a);
    (m, r)
}

fn part(m: &Model, name: &str) -> usize {
    m.parts
        .iter()
        .position(|p| p.origin.name == name)
        .unwrap_or_else(|| panic!("no part {name}"))
}

#[test]
fn pendulum_started_at_30_degrees_finds_the_hanging_equilibrium() {
    let (m, r) = solve(
        "pendulum_offset.adm",
        &mechanism_text("pendulum_offset.adm"),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    // Pivot at (0.3, 1.2, 0), rod length 1: the centre of mass hangs 0.5 below it.
    let p = eq.state.poses[0].p;
    assert!(
        (p - glam::DVec3::new(0.3, 0.7, 0.0)).length() < 1e-6,
        "{p:?}"
    );
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
    // The hinge carries the weight.
    let w = 2.0 * 9.80665;
    // On the I part (the rod, JOINT/1 I = 202): straight up, +y (gravity is −y).
    let f = eq.reactions[0].force;
    assert!(
        (f - glam::DVec3::new(0.0, w, 0.0)).length() < 1e-6 * w,
        "{f:?}"
    );
    let _ = m;
}

#[test]
fn inverted_pendulum_is_an_unstable_equilibrium() {
    // The offset pendulum turned to point straight up (rod frame z along −y … +y).
    let text = mechanism_text("pendulum_offset.adm")
        .replace(", QG = 0.55, 0.7669872981077805, 0", ", QG = 0.3, 1.7, 0")
        .replace(", REULER = 30D, 90D, 90D", ", REULER = 180D, 90D, 90D");
    let (m, r) = solve("inverted.adm", &text, &[0.0]);
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged);
    assert!((eq.state.poses[0].p - glam::DVec3::new(0.3, 1.7, 0.0)).length() < 1e-9);
    let (stable, lowest) = eq.stability.unwrap();
    assert!(!stable, "lowest eigenvalue {lowest}");
    // About the pivot the gravity stiffness is −m g (L/2) per radian. The reported eigenvalue
    // is for a unit free-motion vector in scaled coordinates (translations over the
    // characteristic length Lc): the rotation about the pivot has norm² 1 + (0.5/Lc)².
    let lc = m.characteristic_length;
    let expected = -2.0 * 9.80665 * 0.5 / (1.0 + (0.5 / lc).powi(2));
    assert!(
        (lowest - expected).abs() < 1e-6 * expected.abs(),
        "{lowest} vs {expected}"
    );
}

#[test]
fn redundant_fourbar_reaches_the_same_equilibrium_as_its_non_redundant_twin() {
    let (ma, ra) = solve("fourbar.adm", &mechanism_text("fourbar.adm"), &[0.0]);
    let (mb, rb) = solve(
        "twin.adm",
        &mechanism_text("fourbar_spherical_universal.adm"),
        &[0.0],
    );
    let (ea, eb) = (
        ra.steps[0].1.as_ref().unwrap(),
        rb.steps[0].1.as_ref().unwrap(),
    );
    assert!(
        ea.converged && eb.converged,
        "{:?} {:?}",
        ea.worst,
        eb.worst
    );
    for name in ["crank", "coupler", "rocker"] {
        let (pa, pb) = (
            ea.state.poses[part(&ma, name)].p,
            eb.state.poses[part(&mb, name)].p,
        );
        assert!((pa - pb).length() < 1e-6, "{name}: {pa:?} vs {pb:?}");
    }
    // It moved from the input pose (crank at 60°) to hang under gravity.
    assert!(
        (ea.state.poses[part(&ma, "crank")].p - ma.parts[part(&ma, "crank")].p_gb).length() > 1e-2
    );
    // The same stability verdict and reduced stiffness for both (equivalence).
    let (sa, sb) = (ea.stability.unwrap(), eb.stability.unwrap());
    assert_eq!(sa.0, sb.0);
    assert!(
        (sa.1 - sb.1).abs() < 1e-6 * sa.1.abs().max(1.0),
        "{sa:?} vs {sb:?}"
    );
}

#[test]
fn quasi_static_slider_crank_follows_the_kinematics_and_balances_gravity() {
    // Crank driven at 90°/s from its input angle (60°): r = 100 mm, l = 300 mm.
    let text = mechanism_text("slider_crank.adm").replace(
        "!------------------------ GRAVITATIONAL ACCELERATION",
        "MOTION/1, JOINT = 1, ROTATION, FUNCTION = 90D * TIME\n!------------------------ GRAVITATIONAL ACCELERATION",
    );
    let times = output_times(2.0, 8);
    let (m, r) = solve("slider_crank_motion.adm", &text, &times);
    assert!(
        r.converged(),
        "{:?}",
        r.steps
            .last()
            .map(|s| s.1.as_ref().map(|e| e.worst.clone()))
    );
    assert_eq!(r.steps.len(), 9);
    let (rr, l) = (100.0f64, 300.0f64);
    let (mc, mr, ms) = (0.5, 1.2, 0.8);
    let g = 9806.65;
    // Potential energy of the closed-form configuration at crank angle θ (kg·mm²/s²).
    let potential = |th: f64| {
        let a = glam::DVec2::new(rr * th.cos(), rr * th.sin());
        let b = glam::DVec2::new(a.x + (l * l - a.y * a.y).sqrt(), 0.0);
        g * (mc * a.y / 2.0 + mr * (a.y + b.y) / 2.0 + ms * b.y)
    };
    let slider = part(&m, "slider");
    let motion = m
        .constraints
        .iter()
        .position(|c| c.origin.name == "MOTION_1")
        .unwrap();
    for (t, eq) in &r.steps {
        let eq = eq.as_ref().unwrap();
        let th = (60.0 + 90.0 * t).to_radians();
        let xb = rr * th.cos() + (l * l - (rr * th.sin()).powi(2)).sqrt();
        let p = eq.state.poses[slider].p;
        assert!(
            (p.x - xb).abs() < 1e-6,
            "t = {t}: slider at {} vs closed form {xb}",
            p.x
        );
        // Virtual work: the motion's torque on the crank balances dV/dθ (N·mm, UCF 1000).
        let h = 1e-6;
        let dv = (potential(th + h) - potential(th - h)) / (2.0 * h) / m.ucf();
        let tz = eq
            .reactions
            .iter()
            .find(|x| x.element == motion)
            .unwrap()
            .torque
            .z;
        // The motion's reaction on its I part (the crank) holds it against gravity:
        // τ + (−dV/dθ) = 0, so τ_z = +dV/dθ, sign included (it changes sign past 90°).
        assert!(
            (tz - dv).abs() < 1e-6 * (1.0 + dv.abs()),
            "t = {t}: motion torque {tz} vs dV/dθ {dv}"
        );
    }
    // At the input angle: the independent holding torque of mechanisms/README.md.
    let t0 = r.steps[0]
        .1
        .as_ref()
        .unwrap()
        .reactions
        .iter()
        .find(|x| x.element == motion)
        .unwrap()
        .torque
        .z;
    // Counter-clockwise (+z) on the crank: gravity pulls the crank at 60° clockwise.
    assert!((t0 - 416.782625).abs() < 1e-5, "{t0}");
}

#[test]
fn zero_dof_model_is_solved_kinematically() {
    let (_, r) = solve(
        "fourbar_motion.adm",
        &mechanism_text("fourbar_motion.adm"),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.kinematic && eq.converged);
    assert!(eq.stability.is_none());
}

/// A body with no joint and no force but its weight has no static equilibrium: every Newton
/// correction is unbounded and only the limits move it. The solve says so instead of just
/// not converging, and names the one equation that cannot balance.
#[test]
fn a_free_body_under_gravity_has_no_equilibrium_and_says_why() {
    let text =
        "free body\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
                PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, QP = 1, 1, 1\n\
                PART/2, MASS = 3, CM = 20, IP = 1, 1, 1\nMARKER/20, PART = 2\n\
                ACCGRAV/, JGRAV = -9.80665\nEND\n";
    let (m, r) = solve("free.adm", text, &[0.0]);
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(!eq.converged);
    assert!(eq.unbounded);
    assert_eq!(eq.worst.len(), 1, "{:?}", eq.worst);
    let sys = linkage_solve::constraints::system::System::new(&m);
    let why = eq.failure(&m, &sys).unwrap();
    assert!(
        why.contains("largest imbalance in PART_2 force Y balance (-2.942E+01)"),
        "{why}"
    );
    assert!(why.contains("free motions that nothing resists"), "{why}");
    // A pendulum that merely needs many ALIMIT-limited iterations is not called unbounded.
    let (_, r) = solve(
        "pendulum_maxit.adm",
        &mechanism_text("pendulum_offset.adm")
            .replace("END", "EQUILIBRIUM/, MAXIT = 1, ALIMIT = 1D\nEND"),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(!eq.converged && !eq.unbounded);
}
