//! Dynamic simulation against closed forms and conservation laws.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, DynamicRun, IntegratorSettings, RunError, Start};
use linkage_solve::stages::settle::SettleOutcome;
use linkage_solve::stages::statics::StaticRun;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

const G: f64 = 9.80665;

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn simulate(name: &str, text: &str, end: f64, steps: usize, error: f64) -> (Model, DynamicRun) {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error,
        ..Default::default()
    };
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    drop(a);
    (m, r)
}

/// How many redundant equations the assembly of `text` removes.
fn removed_equations(text: &str) -> usize {
    let ds = linkage_adm::parse_dataset(Arc::from("removed.adm"), text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    a.removed.len()
}

/// Complete elliptic integral of the first kind K(k) by the arithmetic–geometric mean.
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        let (an, bn) = ((a + b) / 2.0, (a * b).sqrt());
        a = an;
        b = bn;
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn compound_pendulum_released_from_30_degrees_has_the_elliptic_period() {
    let (_, r) = simulate(
        "pendulum_offset.adm",
        &mechanism_text("pendulum_offset.adm"),
        3.0,
        3000,
        1e-7,
    );
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    // Angular velocity about z changes sign at each extreme: half a period apart.
    let w: Vec<(f64, f64)> = sim
        .outputs
        .iter()
        .map(|o| (o.time, o.velocities[0].1.z))
        .collect();
    let mut crossings = Vec::new();
    for pair in w.windows(2) {
        let ((t0, w0), (t1, w1)) = (pair[0], pair[1]);
        if w0 != 0.0 && w0.signum() != w1.signum() && t0 > 0.0 {
            crossings.push(t0 + (t1 - t0) * w0 / (w0 - w1));
        }
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let period = 2.0 * (crossings[2] - crossings[0]) / 2.0;
    // T = 4 √(I_pivot / (m g d)) K(sin(θ0/2)), I_pivot = m L²/3, d = L/2, L = 1.
    let expected = 4.0 * (2.0 / (3.0 * G)).sqrt() * ellip_k((15f64).to_radians().sin());
    assert!(
        (period - expected).abs() < 1e-4 * expected,
        "period {period} vs {expected}"
    );
}

#[test]
fn conservative_double_pendulum_keeps_its_energy() {
    // Two unit rods started horizontal-ish: lift the chain by rotating the input.
    let text =
        linkage_solve::generate::pendulum_chain(2).replace("JGRAV = -9.80665", "IGRAV = -9.80665");
    let (m, r) = simulate("double.adm", &text, 10.0, 1000, 1e-6);
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let energy = |o: &linkage_solve::stages::dynamics::Output| {
        m.parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let (v, w) = o.velocities[k];
                let ig = o.state.poses[k].r * p.inertia * o.state.poses[k].r.transpose();
                0.5 * p.mass * v.length_squared() + 0.5 * w.dot(ig * w)
                    - p.mass * m.gravity.dot(o.state.poses[k].p)
            })
            .sum::<f64>()
    };
    let e0 = energy(&sim.outputs[0]);
    let scale = 2.0 * G * 2.0; // m g × (height range) of the chain
    let drift = sim
        .outputs
        .iter()
        .map(|o| (energy(o) - e0).abs())
        .fold(0.0, f64::max);
    assert!(drift < 1e-3 * scale, "energy drift {drift} (scale {scale})");
    assert_eq!(sim.outputs.len(), 1001);
}

#[test]
fn damping_makes_the_energy_decrease_monotonically() {
    use linkage_solve::stages::dynamics::{simulate as integrate, ExtraDamping, Problem};
    let text = mechanism_text("pendulum_offset.adm");
    let ds = linkage_adm::parse_dataset(Arc::from("p.adm"), &text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let ic = &a.ic;
    let p = Problem {
        model: &m,
        sys: &a.system,
        rows: &a.kept,
        redundant: &[],
        drivers: &d,
        forces: &NoForces,
        damping: Some(ExtraDamping(0.5)),
        frozen_time: None,
        regime: linkage_solve::physics::applied::Regime::Dynamic,
        coupling: linkage_solve::physics::flex_inertia::FlexCoupling::new(&m),
    };
    let times: Vec<f64> = (0..=200).map(|k| k as f64 * 0.025).collect();
    let v0 = vec![(glam::DVec3::ZERO, glam::DVec3::ZERO)];
    let sim = integrate(
        &p,
        &ic.assembly.state,
        &v0,
        &times,
        &IntegratorSettings {
            error: 1e-6,
            ..Default::default()
        },
        |_| {},
    );
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let part = &m.parts[0];
    let energy: Vec<f64> = sim
        .outputs
        .iter()
        .map(|o| {
            let (v, w) = o.velocities[0];
            let ig = o.state.poses[0].r * part.inertia * o.state.poses[0].r.transpose();
            0.5 * part.mass * v.length_squared() + 0.5 * w.dot(ig * w)
                - part.mass * m.gravity.dot(o.state.poses[0].p)
        })
        .collect();
    for pair in energy.windows(2) {
        assert!(
            pair[1] <= pair[0] + 1e-9,
            "energy rose: {} → {}",
            pair[0],
            pair[1]
        );
    }
    assert!(energy[0] - energy[energy.len() - 1] > 0.5, "{energy:?}");
}

#[test]
fn settling_finds_the_newton_equilibrium_and_says_why_it_stopped() {
    let text = mechanism_text("pendulum_offset.adm").replace(
        "END",
        "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 4, SETTLING_TIME = 20\nEND",
    );
    let ds = linkage_adm::parse_dataset(Arc::from("settle.adm"), &text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    assert!(m.equilibrium.dynamic);
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let s = linkage_solve::stages::settle::settle(&a, |_| {});
    assert!(
        matches!(
            s.as_ref().map(|o| &o.stop),
            Ok(linkage_solve::stages::settle::SettleStop::Settled { .. })
        ),
        "{:?}",
        s
    );
    let eq = s.unwrap().equilibrium.unwrap().unwrap();
    assert!(eq.converged);
    let newton = linkage_solve::stages::statics::run(&a, &[0.0]);
    let n_eq = newton.steps[0].1.as_ref().unwrap();
    assert!((eq.state.poses[0].p - n_eq.state.poses[0].p).length() < 1e-6);
    assert!((eq.state.poses[0].p - glam::DVec3::new(0.3, 0.7, 0.0)).length() < 1e-6);
    // Without damping (GLOBAL_DAMPING 0, and a settling time far too short for a free swing)
    // the damping is chosen from the pendulum's mode at the start (critical, c = 2ω₁ with
    // ω₁² = m g d cos 30° / I_pivot = 2·9.80665·0.5·cos 30° / (2/3) for the 2 kg, 1 m rod
    // 30° from hanging) and the settling time adapted: it settles in the same hanging pose.
    let text = mechanism_text("pendulum_offset.adm")
        .replace("END", "EQUILIBRIUM/, DYNAMIC, SETTLING_TIME = 2\nEND");
    let ds = linkage_adm::parse_dataset(Arc::from("nosettle.adm"), &text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let s = linkage_solve::stages::settle::settle(&a, |_| {}).expect("assembled");
    assert!(s.choice.from_model, "{:?}", s.choice);
    let omega = (2.0 * 9.80665 * 0.5 * 30f64.to_radians().cos() / (2.0 / 3.0)).sqrt();
    assert!(
        (s.choice.lowest_frequency.unwrap() - omega).abs() < 1e-6 * omega,
        "{:?} vs {omega}",
        s.choice
    );
    let eq = s.settled_equilibrium().expect("settled");
    assert!((eq.state.poses[0].p - glam::DVec3::new(0.3, 0.7, 0.0)).length() < 1e-6);
}

#[test]
fn swinging_door_carries_reactions_on_the_kept_rows_only() {
    // The door (hinge axis global y) given an initial spin about y: it swings freely.
    let text =
        mechanism_text("door_two_hinges.adm").replacen("PART/2\n", "PART/2\n, WY = 1.0\n", 1);
    let (m, r) = simulate("door.adm", &text, 1.0, 20, 1e-6);
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let top = m
        .constraints
        .iter()
        .position(|c| c.origin.name == "hinge_top")
        .unwrap();
    let bottom = m
        .constraints
        .iter()
        .position(|c| c.origin.name == "hinge_bottom")
        .unwrap();
    let weight = 20.0 * G;
    for o in &sim.outputs {
        let ft = o.reactions.iter().find(|x| x.element == top).unwrap().force;
        let fb = o
            .reactions
            .iter()
            .find(|x| x.element == bottom)
            .unwrap()
            .force;
        // hinge_top's Yg row is removed: it carries no force along the hinge axis.
        assert!(ft.y.abs() < 1e-9 * weight, "t = {}: {ft:?}", o.time);
        assert!(
            (fb.y + ft.y - weight).abs() < 1e-6 * weight,
            "t = {}",
            o.time
        );
    }
    // It swings at constant angular velocity (no torque about the hinge axis); HHT's numerical
    // dissipation (α = −0.3) costs a few 1e-5 over the second at ERROR 1e-6.
    assert!((sim.outputs[0].velocities[0].1.y - 1.0).abs() < 1e-8);
    let w_end = sim.outputs.last().unwrap().velocities[0].1;
    assert!((w_end.y - 1.0).abs() < 1e-4, "{w_end:?}");
}

/// Two pulleys on revolutes to ground, the first driven; coupled twice.
fn coupled_pulleys(second_ratio: &str) -> String {
    format!(
        "pulleys\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, QP = 1, 0, 0\n\
PART/2, MASS = 1, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2\nPART/3, MASS = 1, CM = 30, IP = 0.1, 0.1, 0.1\nMARKER/30, PART = 3, QP = 1, 0, 0\n\
JOINT/1, REVOLUTE, I = 20, J = 1\nJOINT/2, REVOLUTE, I = 30, J = 2\nCOUPLER/1, JOINTS = 1, 2, TYPE = R:R, SCALES = 1, -2\nCOUPLER/2, JOINTS = 1, 2, TYPE = R:R, SCALES = {second_ratio}\n\
MOTION/1, JOINT = 1, ROTATION, FUNCTION = 90D * TIME\nEND\n"
    )
}

#[test]
fn consistent_duplicate_coupler_runs_and_a_drifting_one_stops_the_run() {
    // The same ratio written twice: the second coupler is redundant and stays consistent.
    let (m, r) = simulate("same.adm", &coupled_pulleys("2, -4"), 1.0, 10, 1e-6);
    assert_eq!(removed_equations(&coupled_pulleys("2, -4")), 1);
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let last = sim.outputs.last().unwrap();
    assert!(
        (last.velocities[1].1.z - 0.5 * 90f64.to_radians()).abs() < 1e-6,
        "{:?}",
        last.velocities[1]
    );
    let _ = m;
    // A slightly different ratio: consistent at the start (all angles zero), inconsistent as
    // soon as the pulleys turn: the run stops, naming the equation, the time and the value.
    let (m, r) = simulate("drift.adm", &coupled_pulleys("1, -2.01"), 1.0, 10, 1e-6);
    let sim = r.simulation.as_ref().unwrap();
    let f = sim.failure.as_ref().expect("the run must stop");
    assert!(f.time > 0.0 && f.time < 0.5, "{f:?}");
    assert!(f.message.contains("became inconsistent"), "{f:?}");
    let named = m
        .constraints
        .iter()
        .any(|c| f.message.contains(&c.origin.name));
    assert!(named, "{f:?}");
    // The cause is a value: the removed row (the motion's, motions come last in the rank
    // order) and its element, as the message names them.
    match &f.cause {
        linkage_solve::stages::dynamics::IntegrationError::RedundantViolated {
            element,
            equation,
            ..
        } => {
            assert_eq!(element, "MOTION_1");
            assert!(f.message.contains(equation), "{f:?}");
        }
        other => panic!("unexpected cause {other:?}"),
    }
    assert_eq!(f.message, f.cause.to_string());
}

/// A zero-DOF model runs kinematically: the four-bar driven at 30°/s (three redundant rows)
/// gives no integration error, the crank angle is exact, and the motion's torque delivers the
/// power that raises the mechanism's kinetic plus potential energy, `τ·ω = d(T + V)/dt`
/// (central differences over ±1 ms, whose truncation error is about 1e-6 of the power).
#[test]
fn zero_dof_fourbar_runs_kinematically_and_the_motion_supplies_the_power() {
    let text = mechanism_text("fourbar_motion.adm");
    let dt = 1e-3;
    let centres = [0.3, 1.1, 2.5];
    let mut times = Vec::new();
    for c in centres {
        times.extend([c - dt, c, c + dt]);
    }
    let ds = linkage_adm::parse_dataset(Arc::from("fourbar_motion.adm"), text.as_str()).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let r = run(
        &a,
        &times,
        &IntegratorSettings::default(),
        Start::InitialConditions,
        |_| {},
    );
    let sim = r.simulation.expect("runs");
    assert!(sim.kinematic);
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), times.len());
    let energy = |o: &linkage_solve::stages::dynamics::Output| -> f64 {
        m.parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let r = o.state.poses[k].r;
                let ig = r * p.inertia * r.transpose();
                let (v, w) = o.velocities[k];
                0.5 * p.mass * v.length_squared() + 0.5 * w.dot(ig * w)
                    - p.mass * m.gravity.dot(o.state.poses[k].p)
            })
            .sum()
    };
    let motion = m
        .constraints
        .iter()
        .position(|c| c.origin.statement == "MOTION")
        .unwrap();
    let (i_marker, _) = m.constraints[motion].markers().unwrap();
    let linkage_model::Body::Part(crank) = m.markers[i_marker].body else {
        panic!("the motion's I marker is on ground")
    };
    for (k, c) in centres.iter().enumerate() {
        let (before, at, after) = (
            &sim.outputs[3 * k],
            &sim.outputs[3 * k + 1],
            &sim.outputs[3 * k + 2],
        );
        assert!((at.time - c).abs() < 1e-12);
        // ω of the crank is 30°/s about z.
        let w = at.velocities[crank].1;
        assert!((w.z - 30f64.to_radians()).abs() < 1e-10, "{w}");
        let de = (energy(after) - energy(before)) / (2.0 * dt);
        let tau = at
            .reactions
            .iter()
            .find(|r| r.element == motion)
            .unwrap()
            .torque;
        let power = tau.dot(w);
        assert!(
            (power - de).abs() <= 1e-5 * de.abs().max(1e-3),
            "t {c}: motion power {power} vs dE/dt {de}"
        );
    }
}

#[test]
fn double_pendulum_far_from_the_origin_swings_like_at_the_origin() {
    // Coordinates of 1e4 m resolve positions to ~2e-12 m only: the corrector must accept
    // rounding-level corrections (it used to stagnate and halve the step down to HMIN).
    let text =
        linkage_solve::generate::pendulum_chain(2).replace("JGRAV = -9.80665", "IGRAV = -9.80665");
    let far = text
        .replace("MARKER/1, PART = 1", "MARKER/1, PART = 1, QP = 10000, 0, 0")
        .replace("QP = 0,", "QP = 10000,");
    let (_, near) = simulate("near.adm", &text, 2.0, 20, 1e-6);
    let (_, far) = simulate("far.adm", &far, 2.0, 20, 1e-6);
    let (near, far) = (
        near.simulation.as_ref().unwrap(),
        far.simulation.as_ref().unwrap(),
    );
    assert!(near.failure.is_none(), "{:?}", near.failure);
    assert!(far.failure.is_none(), "{:?}", far.failure);
    assert_eq!(near.outputs.len(), 21);
    assert_eq!(far.outputs.len(), 21);
    let shift = glam::DVec3::new(1e4, 0.0, 0.0);
    for (a, b) in near.outputs.iter().zip(&far.outputs) {
        for k in 0..2 {
            let dp = (b.state.poses[k].p - shift - a.state.poses[k].p).length();
            let dw = (b.velocities[k].1 - a.velocities[k].1).length();
            // Same motion; the runs differ by rounding, amplified by the chaotic double
            // pendulum (≈ 2e-8 m and 1e-6 rad/s after 2 s).
            assert!(
                dp < 1e-6 && dw < 1e-5,
                "t = {}: dp {dp:e} dw {dw:e}",
                a.time
            );
        }
    }
    // The chain did swing (≈ 1 m at the tip), so the comparison means something.
    let tip = near.outputs.last().unwrap().state.poses[1].p;
    assert!(
        (tip - glam::DVec3::new(0.0, -1.5, 0.0)).length() > 0.5,
        "{tip:?}"
    );
}

#[test]
fn missing_initial_velocities_start_the_pendulum_at_rest() {
    use linkage_solve::stages::dynamics::{simulate as integrate, Problem};
    let ds = linkage_adm::parse_dataset(Arc::from("p.adm"), &mechanism_text("pendulum_offset.adm"))
        .unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let ic = &a.ic;
    let p = Problem {
        model: &m,
        sys: &a.system,
        rows: &a.kept,
        redundant: &[],
        drivers: &d,
        forces: &NoForces,
        damping: None,
        frozen_time: None,
        regime: linkage_solve::physics::applied::Regime::Dynamic,
        coupling: linkage_solve::physics::flex_inertia::FlexCoupling::new(&m),
    };
    // No velocities given (an initial-conditions result without a velocity stage): the
    // same run as with zero velocities.
    let run = |v0: &[(glam::DVec3, glam::DVec3)]| {
        integrate(
            &p,
            &ic.assembly.state,
            v0,
            &[0.0, 0.1],
            &IntegratorSettings::default(),
            |_| {},
        )
    };
    let (missing, zero) = (run(&[]), run(&[(glam::DVec3::ZERO, glam::DVec3::ZERO)]));
    assert!(missing.failure.is_none(), "{:?}", missing.failure);
    assert_eq!(missing.outputs.len(), 2);
    let (v, w) = missing.outputs[0].velocities[0];
    assert_eq!((v.length(), w.length()), (0.0, 0.0));
    for (a, b) in missing.outputs.iter().zip(&zero.outputs) {
        assert_eq!(a.state, b.state);
        assert_eq!(a.velocities, b.velocities);
    }
    // Released from rest, it has started to swing.
    assert!(missing.outputs[1].velocities[0].1.length() > 0.1);
}

/// `pendulum_offset` (rod L = 1 m, m = 2 kg, pivot (0.3, 1.2, 0), released at 30°) with its
/// tip tied by a zero-length spring of stiffness `k` to the ground point one metre right of and
/// one metre below the pivot, and EQUILIBRIUM settings `equilibrium`.
///
/// With θ the rod's angle from hanging (towards +x), the spring's moment about the pivot is
/// `k L (cos θ − sin θ)` (the tip-to-anchor vector is `(1 − L sin θ, −1 + L cos θ)`) and
/// gravity's `−m g (L/2) sin θ`: equilibrium at `tan θ = k / (k + m g / 2)` for L = 1.
fn tied_pendulum(k: f64, equilibrium: &str) -> String {
    mechanism_text("pendulum_offset.adm").replace(
        "END",
        &format!(
            "MARKER/104, PART = 1, QP = 1.3, 0.2, 0\n\
             SPRINGDAMPER/1, TRANSLATIONAL, I = 203, J = 104, K = {k}, C = 0, LENGTH = 0\n\
             {equilibrium}\nEND"
        ),
    )
}

fn run_from(text: &str, start: Start, end: f64) -> (Model, DynamicRun) {
    let ds = linkage_adm::parse_dataset(Arc::from("tied.adm"), text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let forces = linkage_solve::physics::forces::ForceSet::new(&m).unwrap();
    let times: Vec<f64> = (0..=10).map(|k| end * k as f64 / 10.0).collect();
    let settings = IntegratorSettings {
        error: 1e-6,
        ..Default::default()
    };
    let a = Assembled::new(&m, &d, &forces, &Tolerances::default());
    let r = run(&a, &times, &settings, start, |_| {});
    drop(a);
    (m, r)
}

/// The rod's angle from hanging (towards +x), from its centre of mass.
fn rod_angle(p: glam::DVec3) -> f64 {
    (p.x - 0.3).atan2(1.2 - p.y)
}

#[test]
fn a_run_started_at_the_settled_equilibrium_stays_there() {
    let k = 200.0;
    let theta = (k / (k + 2.0 * G / 2.0)).atan(); // 43.63°: 13.6° from the released pose
    let settings = "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 5, SETTLING_TIME = 20";
    // EQUILIBRIUM/DYNAMIC: --start-at-equilibrium settles (damped dynamics, then the polish).
    let (_, r) = run_from(&tied_pendulum(k, settings), Start::Equilibrium, 2.0);
    let found = r.equilibrium.as_ref().expect("an equilibrium was sought");
    let linkage_solve::stages::dynamics::StartingEquilibrium::Settled(outcome) = found else {
        panic!("EQUILIBRIUM/DYNAMIC must settle: {found:?}")
    };
    assert!(
        matches!(
            outcome.stop,
            linkage_solve::stages::settle::SettleStop::Settled { .. }
        ),
        "{:?}",
        outcome.stop
    );
    let eq = found.equilibrium().expect("settled and polished");
    assert!(
        (rod_angle(eq.state.poses[0].p) - theta).abs() < 1e-9,
        "{} vs {}",
        rod_angle(eq.state.poses[0].p).to_degrees(),
        theta.to_degrees()
    );
    // From rest at the equilibrium the rod stays put for the whole run: it neither swings
    // back towards its released pose nor drifts (at ERROR 1e-6).
    let sim = r.simulation.as_ref().expect("the run started");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), 11);
    for o in &sim.outputs {
        assert!(
            (rod_angle(o.state.poses[0].p) - theta).abs() < 1e-8,
            "t = {}",
            o.time
        );
        assert!(o.velocities[0].1.length() < 1e-8, "t = {}", o.time);
    }
    // The same equilibrium by Newton (no DYNAMIC), and the same again when settling is
    // asked for explicitly.
    let newton_text = tied_pendulum(k, "");
    let (_, newton) = run_from(&newton_text, Start::Equilibrium, 0.5);
    let n_found = newton.equilibrium.as_ref().unwrap();
    assert!(matches!(
        n_found,
        linkage_solve::stages::dynamics::StartingEquilibrium::Newton(_)
    ));
    let n_eq = n_found.equilibrium().expect("Newton converges from 30°");
    assert!((rod_angle(n_eq.state.poses[0].p) - theta).abs() < 1e-9);
    let (_, forced) = run_from(
        &tied_pendulum(k, "EQUILIBRIUM/, GLOBAL_DAMPING = 5, SETTLING_TIME = 20"),
        Start::SettledEquilibrium,
        0.5,
    );
    assert!(matches!(
        forced.equilibrium,
        Some(linkage_solve::stages::dynamics::StartingEquilibrium::Settled(_))
    ));
    assert!(forced.simulation.is_some());
    // Started from the initial conditions instead, the released rod swings through the
    // equilibrium angle: the start matters.
    let (_, released) = run_from(&newton_text, Start::InitialConditions, 0.5);
    let swing = released.simulation.unwrap();
    let max_angle = swing
        .outputs
        .iter()
        .map(|o| rod_angle(o.state.poses[0].p))
        .fold(f64::MIN, f64::max);
    assert!(max_angle > theta + 0.1, "{}", max_angle.to_degrees());
}

#[test]
fn a_model_that_does_not_settle_is_not_run_and_says_why() {
    // A light dataset damping and a short settling time: the tied rod is still swinging when
    // time runs out (GLOBAL_DAMPING 0 would have the damping chosen from the model).
    let (_, r) = run_from(
        &tied_pendulum(
            200.0,
            "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 0.01, SETTLING_TIME = 1",
        ),
        Start::Equilibrium,
        1.0,
    );
    assert!(r.simulation.is_none());
    let why = r.error.expect("the run must say why it did not start");
    let RunError::NoEquilibrium(why) = why else {
        panic!("{why}")
    };
    assert!(
        why.contains("did not settle within SETTLING_TIME = 1"),
        "{why}"
    );
    assert!(why.contains("kinetic energy"), "{why}");
}

/// The chain, its settling outcome, its Newton equilibrium and the number of redundant
/// equations its assembly removed.
fn settled_chain(crank_deg: f64) -> (Model, SettleOutcome, StaticRun, usize) {
    let text = linkage_solve::generate::parallelogram_chain(3, crank_deg).replace(
        "END",
        "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 2, SETTLING_TIME = 50\nEND",
    );
    let ds = linkage_adm::parse_dataset(Arc::from("chain3.adm"), &text).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let s = linkage_solve::stages::settle::settle(&a, |_| {}).expect("assembles");
    let newton = linkage_solve::stages::statics::run(&a, &[0.0]);
    let removed = a.removed.len();
    drop(a);
    (m, s, newton, removed)
}

/// Centres of mass of the four cranks (length 1, pivots at (k, 0)) pointing `up` or down.
fn cranks_point(m: &Model, state: &linkage_solve::state::State, up: bool) -> bool {
    (0..=3).all(|k| {
        let want = glam::DVec3::new(k as f64, if up { 0.5 } else { -0.5 }, 0.0);
        m.parts[k].origin.name == format!("crank_{k}") && (state.poses[k].p - want).length() < 1e-6
    })
}

/// A closed-loop model with redundant rows (three parallelogram four-bars sharing cranks,
/// nine redundant equations). Released with its cranks at −60°, settling (damped, frozen time)
/// and Newton statics both find the cranks hanging straight down. Released at +60°, Newton
/// converges to the nearest equilibrium, cranks straight up, and says it is unstable; damped
/// dynamics cannot rest there and settles hanging down: the reason to settle.
#[test]
fn settling_and_newton_agree_on_a_closed_loop_chain_unless_newton_finds_an_unstable_pose() {
    let (m, outcome, newton, removed) = settled_chain(-60.0);
    assert_eq!(removed, 9);
    let settled = outcome
        .settled_equilibrium()
        .unwrap_or_else(|| panic!("{:?}", outcome.stop));
    let n_eq = newton.steps[0].1.as_ref().unwrap();
    assert!(n_eq.converged);
    for k in 0..m.parts.len() {
        let (a, b) = (settled.state.poses[k].p, n_eq.state.poses[k].p);
        assert!(
            (a - b).length() < 1e-6,
            "{}: {a} vs {b}",
            m.parts[k].origin.name
        );
    }
    assert!(cranks_point(&m, &settled.state, false));
    assert_eq!(settled.stability.map(|s| s.0), Some(true));

    let (m, outcome, newton, _) = settled_chain(60.0);
    let n_eq = newton.steps[0].1.as_ref().unwrap();
    assert!(n_eq.converged);
    assert!(cranks_point(&m, &n_eq.state, true));
    assert_eq!(n_eq.stability.map(|s| s.0), Some(false));
    let settled = outcome
        .settled_equilibrium()
        .unwrap_or_else(|| panic!("{:?}", outcome.stop));
    assert!(cranks_point(&m, &settled.state, false));
    assert_eq!(settled.stability.map(|s| s.0), Some(true));
}
