//! FRICTION on joints against closed forms: a block on a ramp that sticks or slides, a disc
//! spun down by the friction of its pin, the preload brake of the FAST models, a block held
//! on a ramp in static equilibrium.

mod common;
use common::corpus;
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::{AppliedForces, Regime};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

const G: f64 = 9.80665;

fn load(text: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

/// The outputs of a dynamic run of `text` from its initial conditions to `end`, `steps`
/// outputs, INTEGRATOR ERROR `error`.
fn simulate(text: &str, end: f64, steps: usize, error: f64) -> Vec<Output> {
    let (m, d, f) = load(text);
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error,
        ..Default::default()
    };
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), steps + 1);
    sim.outputs
}

/// A 2 kg block on a translational joint along ground z, on a ramp inclined by `deg`:
/// gravity has `−g cos θ` across the joint (y) and `−g sin θ` along it (z).
fn ramp(deg: f64, friction: &str) -> String {
    let (s, c) = deg.to_radians().sin_cos();
    format!(
        "block on a ramp\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2\nMARKER/21, PART = 2\n\
JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 0.5, MU_DYNAMIC = 0.3, INPUTS = REACTION_FORCE{friction}\n\
ACCGRAV/, JGRAV = {}, KGRAV = {}\nEND\n",
        -G * c,
        -G * s
    )
}

/// tan 20° = 0.364 < μs = 0.5: the block sticks. Over 3 s it creeps only by the stiction
/// deformation of its load, `Δmax·tan θ/μs` = 7.28 mm (Δmax = 10 mm, the default), never
/// beyond Δmax, and comes to rest there.
#[test]
fn a_block_on_a_ramp_below_the_friction_angle_sticks() {
    let out = simulate(&ramp(20.0, ""), 3.0, 60, 1e-6);
    let z0 = out[0].state.poses[0].p.z;
    let creep = out
        .iter()
        .map(|o| (o.state.poses[0].p.z - z0).abs())
        .fold(0.0, f64::max);
    assert!(creep < 0.01, "creep {creep}");
    let last = out.last().unwrap();
    let held = 0.01 * 20f64.to_radians().tan() / 0.5;
    let dz = z0 - last.state.poses[0].p.z;
    assert!((dz - held).abs() < 1e-4, "{dz} vs {held}");
    assert!(
        last.velocities[0].0.length() < 1e-4,
        "{:?}",
        last.velocities[0]
    );
}

/// tan 30° = 0.577 > μs = 0.5: the block slides, and once beyond the transition velocity
/// (1.5·vs = 0.15 m/s) it accelerates at `g(sin θ − μd cos θ)` = 2.3554 m/s². The friction
/// reported is `μd·m g cos θ` against the slip.
#[test]
fn a_block_on_a_ramp_above_the_friction_angle_slides_at_the_dynamic_rate() {
    let text = ramp(30.0, "");
    let out = simulate(&text, 2.0, 20, 1e-7);
    let (s, c) = 30f64.to_radians().sin_cos();
    let expected = G * (s - 0.3 * c);
    // Both outputs are well beyond 0.15 m/s (reached before 0.1 s).
    let (a, b) = (&out[10], &out[20]);
    let rate = (a.velocities[0].0.z - b.velocities[0].0.z) / (b.time - a.time);
    assert!(
        (rate - expected).abs() < 1e-4 * expected,
        "{rate} vs {expected}"
    );
    assert!((b.accelerations[0].0.z + expected).abs() < 1e-4 * expected);
    // The friction at the end, as the reports give it (J axes: along +z, against the slip).
    let (_, _, f) = load(&text);
    let mut s = b.state.clone();
    f.accept_state(&mut s, &b.velocities, &b.reactions);
    let v = f.friction_values(Regime::Dynamic, &s, &b.velocities);
    let normal = 2.0 * G * c;
    assert!((v[0].normal - normal).abs() < 1e-6 * normal, "{:?}", v[0]);
    assert!(
        (v[0].force.z - 0.3 * normal).abs() < 1e-6 * normal,
        "{:?}",
        v[0]
    );
    assert!(!v[0].sticking);
}

/// EFFECT = STICTION keeps only the stiction regime: a block that breaks away slides without
/// friction, at g sin θ.
#[test]
fn stiction_only_friction_lets_a_sliding_block_go_free() {
    let out = simulate(&ramp(30.0, ", EFFECT = STICTION"), 1.0, 10, 1e-7);
    let (a, b) = (&out[5], &out[10]);
    let rate = (a.velocities[0].0.z - b.velocities[0].0.z) / (b.time - a.time);
    let expected = G * 0.5;
    assert!((rate - expected).abs() < 1e-4 * expected, "{rate}");
}

/// A 2 kg disc (I_zz = 0.5 kg m²) spinning at 10 rad/s on a horizontal revolute joint with a
/// 5 cm pin: the radial reaction m g and μd = 0.15 give a constant friction torque
/// `μd·Rp·m g`, so ω falls by `μd·Rp·m g/I` = 0.29420 rad/s² (surface speed 0.5 m/s, far above
/// the transition velocity).
#[test]
fn a_spinning_disc_decelerates_at_the_pin_friction_rate() {
    let text = format!(
        "disc on a pin\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 0.3, 0.3, 0.5, WZ = 10\nMARKER/20, PART = 2\nMARKER/21, PART = 2\n\
JOINT/1, REVOLUTE, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 0.2, MU_DYNAMIC = 0.15, PIN_RADIUS = 0.05\n\
ACCGRAV/, JGRAV = {}\nEND\n",
        -G
    );
    let out = simulate(&text, 2.0, 20, 1e-7);
    let alpha = 0.15 * 0.05 * 2.0 * G / 0.5;
    for o in out.iter().skip(1) {
        let w = o.velocities[0].1.z;
        let expected = 10.0 - alpha * o.time;
        assert!(
            (w - expected).abs() < 1e-5,
            "t {}: {w} vs {expected}",
            o.time
        );
    }
}

/// The FAST high-speed-shaft brake: a revolute joint with `INPUTS = PRELOAD`,
/// `FRICTION_TORQUE_PRELOAD = Tp = 2`, μs = μd = 1 holds any torque below `μ·Tp` (turning by
/// less than Δmax/Rp = 0.01 rad) and slips above it at `(T − μd·Tp)/I`.
fn brake(torque: f64) -> String {
    format!(
        "brake\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 0.3, 0.3, 0.5\nMARKER/20, PART = 2\nMARKER/21, PART = 2\n\
JOINT/1, REVOLUTE, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 1, MU_DYNAMIC = 1, INPUTS = PRELOAD, \
FRICTION_TORQUE_PRELOAD = 2\n\
SFORCE/1, ROTATIONAL, I = 21, J = 11, FUNCTION = {torque}\nEND\n"
    )
}

#[test]
fn a_preload_brake_holds_below_its_torque() {
    let out = simulate(&brake(1.5), 2.0, 20, 1e-6);
    let turned = out
        .iter()
        .map(|o| {
            let r = o.state.poses[0].r;
            r.col(0).y.atan2(r.col(0).x).abs()
        })
        .fold(0.0, f64::max);
    // Held by the stiction spring at 0.01·1.5/2 = 7.5 mrad.
    assert!(turned < 0.01, "turned {turned} rad");
    let last = out.last().unwrap();
    assert!(
        last.velocities[0].1.z.abs() < 1e-4,
        "{:?}",
        last.velocities[0]
    );
}

#[test]
fn a_preload_brake_slips_above_its_torque() {
    let out = simulate(&brake(3.0), 2.0, 20, 1e-7);
    let (a, b) = (&out[10], &out[20]);
    let rate = (b.velocities[0].1.z - a.velocities[0].1.z) / (b.time - a.time);
    let expected = (3.0 - 2.0) / 0.5;
    assert!(
        (rate - expected).abs() < 1e-4 * expected,
        "{rate} vs {expected}"
    );
}

/// Static equilibrium of the block on the 20° ramp: held by friction, with the stiction
/// deformation `Δmax·tan θ/μs` and a friction force `m g sin θ` up the ramp.
#[test]
fn a_block_on_a_ramp_is_held_in_static_equilibrium() {
    let text = ramp(20.0, "");
    let (m, d, f) = load(&text);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let z0 = a.state().poses[0].p.z;
    let r = linkage_solve::stages::statics::run(&a, &[0.0]);
    let eq = r.steps[0].1.as_ref().unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    let held = 0.01 * 20f64.to_radians().tan() / 0.5;
    let dz = z0 - eq.state.poses[0].p.z;
    assert!((dz - held).abs() < 1e-9, "{dz} vs {held}");
    let rest = vec![Default::default(); 1];
    let v = f.friction_values(Regime::Dynamic, &eq.state, &rest);
    let along = 2.0 * G * 20f64.to_radians().sin();
    assert!((v[0].force.z - along).abs() < 1e-6 * along, "{:?}", v[0]);
    assert!(v[0].sticking);
}

/// `INACTIVE_DURING = STATIC`: the same block has no static equilibrium (nothing holds it
/// along the ramp), while the friction still acts in the dynamic run.
#[test]
fn friction_inactive_in_statics_holds_nothing_there() {
    let text = ramp(20.0, ", INACTIVE_DURING = STATIC");
    let (m, d, f) = load(&text);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let r = linkage_solve::stages::statics::run(&a, &[0.0]);
    let held = r.steps[0].1.as_ref().is_ok_and(|e| e.converged);
    assert!(!held, "a block on a frictionless ramp found an equilibrium");
    let out = simulate(&text, 1.0, 10, 1e-6);
    let dz = out[0].state.poses[0].p.z - out[10].state.poses[0].p.z;
    assert!(dz.abs() < 0.01, "{dz}");
}

/// A corpus dataset without the statements `leave_out` names (`--deactivate`), its findings
/// checked: nothing refused but what `refused` allows.
fn corpus_model(dir: &std::path::Path, file: &str, leave_out: &[&str]) -> Model {
    let ds = linkage_adm::read_dataset(&dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let names: Vec<String> = leave_out.iter().map(|s| s.to_string()).collect();
    let chosen = linkage_adm::amend::select(&ds.statements, &names).unwrap();
    let ds = linkage_adm::amend::without(&ds, &chosen).unwrap_or_else(|e| panic!("{e}"));
    let refused: Vec<String> = linkage_solve::coverage::findings(&ds)
        .iter()
        .filter(|f| f.refuses(linkage_solve::coverage::Analysis::Simulate))
        .map(|f| f.title())
        .collect();
    assert!(refused.is_empty(), "{file}: {refused:?}");
    assert!(!ds.frictions.is_empty(), "{file}");
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{file}: {e}"))
        .model
}

/// The corpus datasets with FRICTION run. SolidWorks' RD3 (twelve frictions, one
/// INACTIVE_DURING = STATIC) passes ic, static and 1 s of simulate as it is; the Adams Controls
/// plants of baqumau (IRB-140 arm: six revolute frictions with torque preloads and arms;
/// Bot_3 rover: REACTION_FORCE:BENDING_MOMENT inputs; the 3WD robots: 114 frictions)
/// simulate with their CONTACTs left out (not modelled in this branch); their statics have no
/// equilibrium without the contacts that carry them. The bicycle plant needs its CONTACTs and
/// VARVAL in MOTION functions; FAST Test02 (the preload brake) calls 29 USER subroutines.
#[test]
fn corpus_datasets_with_friction_run() {
    let Some(dir) = corpus() else { return };
    let rd3 = corpus_model(&dir, "ssernap__T_MSC_ADAMS__RD3.adm", &[]);
    assert_eq!(rd3.frictions.len(), 12);
    let d = ExpressionDrivers::new(&rd3).unwrap();
    let f = ForceSet::new(&rd3).unwrap();
    let a = Assembled::new(&rd3, &d, &f, &Tolerances::default());
    assert!(a.failure().is_none(), "{:?}", a.failure());
    assert!(matches!(&a.ic.acceleration, Some(Ok(_))));
    let r = linkage_solve::stages::statics::run(&a, &[0.0]);
    let eq = r.steps[0].1.as_ref().unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    let times: Vec<f64> = (0..=10).map(|k| 0.1 * k as f64).collect();
    let settings = IntegratorSettings::default();
    let run_ok = |a: &Assembled, name: &str| {
        let r = run(a, &times, &settings, Start::InitialConditions, |_| {});
        let sim = r
            .simulation
            .unwrap_or_else(|| panic!("{name}: {:?}", r.error));
        assert!(sim.failure.is_none(), "{name}: {:?}", sim.failure);
        assert_eq!(sim.outputs.len(), times.len(), "{name}");
    };
    run_ok(&a, "RD3");
    for file in [
        "baqumau__Mechatronics-baqumau__Robotics__Manipulator_Robots__ABB_IRB-140_Robot__Dynamics_and_Control-ADAMS_and_MATLAB__IRB140_Plant_1.adm",
        "baqumau__Mechatronics-baqumau__Robotics__Mobile_Robots__baqubot_Rover-DWR__Dynamics_and_Control-ADAMS_and_MATLAB__Bot_3.adm",
        "baqumau__Mechatronics-baqumau__Robotics__Mobile_Robots__3WD_OMR_Formations__Dynamics_and_Control-ADAMS_and_MATLAB__twoRobotsPlant_1_v2020.adm",
    ] {
        let m = corpus_model(&dir, file, &["CONTACT"]);
        let d = ExpressionDrivers::new(&m).unwrap();
        let f = ForceSet::new(&m).unwrap();
        let a = Assembled::new(&m, &d, &f, &Tolerances::default());
        assert!(a.failure().is_none(), "{file}: {:?}", a.failure());
        run_ok(&a, file);
    }
}

/// A 2 kg body whose centre of mass is at the joint, on a `joint` along ground z (gravity −y
/// gives the radial reaction m g), started with `start` (PART velocity arguments).
fn spinner(joint: &str, friction: &str, inertia: &str, start: &str) -> String {
    format!(
        "spinner\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = {inertia}, {start}\nMARKER/20, PART = 2\n\
MARKER/21, PART = 2{}\n\
JOINT/1, {joint}, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 0.2, MU_DYNAMIC = 0.15{friction}\n\
ACCGRAV/, JGRAV = {}\nEND\n",
        // A universal joint's I axis is perpendicular to J's (x against z).
        if joint == "UNIVERSAL" {
            ", REULER = 90D, 90D, 0D"
        } else {
            ""
        },
        -G
    )
}

/// Spherical: the friction torque `μd·Rb·m g` against the spin, ω falling at
/// `μd·Rb·m g/I` = 0.58840 rad/s² (Rb = 0.1 m, I = 0.5 kg m²).
#[test]
fn a_ball_joint_spins_down_at_the_ball_friction_rate() {
    let text = spinner(
        "SPHERICAL",
        ", BALL_RADIUS = 0.1",
        "0.5, 0.5, 0.5",
        "WZ = 10",
    );
    let out = simulate(&text, 2.0, 10, 1e-7);
    let alpha = 0.15 * 0.1 * 2.0 * G / 0.5;
    for o in out.iter().skip(1) {
        let w = o.velocities[0].1;
        assert!(
            (w.z - (10.0 - alpha * o.time)).abs() < 1e-5,
            "t {}: {w}",
            o.time
        );
        assert!(w.x.abs() + w.y.abs() < 1e-8, "{w}");
    }
}

/// Universal (hooke): spinning about J's axis, the pin friction of a revolute joint,
/// `μd·Rp·m g/I` = 0.29420 rad/s² (Rp = 0.05 m).
#[test]
fn a_universal_joint_spins_down_at_the_pin_friction_rate() {
    let text = spinner(
        "UNIVERSAL",
        ", PIN_RADIUS = 0.05",
        "0.3, 0.3, 0.5",
        "WZ = 10",
    );
    let out = simulate(&text, 2.0, 10, 1e-7);
    let alpha = 0.15 * 0.05 * 2.0 * G / 0.5;
    for o in out.iter().skip(1) {
        let w = o.velocities[0].1.z;
        assert!(
            (w - (10.0 - alpha * o.time)).abs() < 1e-5,
            "t {}: {w}",
            o.time
        );
    }
}

/// Cylindrical: sliding at 3 m/s and turning at 40 rad/s on a pin of Rp = 0.1 m, the
/// surface slips at (3, 4) m/s; the friction `μd·m g` acts against that slip. With I = m Rp²
/// both parts slow in proportion, so the slip keeps its direction: v falls at
/// `μd g·3/5` = 0.88260 m/s², ω at `μd g·(4/5)/Rp` = 11.768 rad/s².
#[test]
fn a_cylindrical_joint_slows_sliding_and_turning_along_the_surface_slip() {
    let text = spinner(
        "CYLINDRICAL",
        ", PIN_RADIUS = 0.1, INPUTS = REACTION_FORCE",
        "0.02, 0.02, 0.02",
        "VZ = 3, WZ = 40",
    );
    let out = simulate(&text, 1.0, 10, 1e-7);
    let decel = 0.15 * G;
    for o in out.iter().skip(1) {
        let (v, w) = (o.velocities[0].0.z, o.velocities[0].1.z);
        let ve = 3.0 - decel * 0.6 * o.time;
        let we = 40.0 - decel * 0.8 / 0.1 * o.time;
        assert!((v - ve).abs() < 1e-5, "t {}: v {v} vs {ve}", o.time);
        assert!((w - we).abs() < 1e-4, "t {}: w {w} vs {we}", o.time);
    }
}

/// A 2 kg bar pinned at one end by a revolute joint of pin radius R = 0.5 with
/// `INPUTS = REACTION_FORCE` (μs = 0.5, Δmax = 10 mm), its centre of mass a from the pin
/// (0.1, and 0.2 close to the limit), gravity across the bar. The weight's torque m g a is
/// below the most the pin holds, μs·R·m g (a < μs R = 0.25): the bar is held by the stiction
/// torque `R·μs·(R φ/Δmax)·N`, N = m g (the radial reaction: the only load is the weight), so
/// it turns by φ with `φ = a·cos φ·Δmax/(μs R²)` (the weight's arm shortens as it turns):
/// 7.99974 and 15.9980 mrad. At the start the normal load is not the final one (the first
/// iterate's multipliers, or the IC's reaction `m (g − a α)`), so the first Newton step would
/// turn the a = 0.2 bar past Δmax, out of the stiction band, had it no step limit there.
#[test]
fn a_pin_with_a_large_radius_holds_a_bar_by_its_friction_torque() {
    for (arm, most_iterations) in [(0.1, 4), (0.2, 8)] {
        let text = format!(
            "bar on a pin\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/11, PART = 1\n\
PART/2, MASS = 2, CM = 20, IP = 0.02, 0.05, 0.05\nMARKER/20, PART = 2, QP = {arm}, 0, 0\n\
MARKER/21, PART = 2\nJOINT/1, REVOLUTE, I = 21, J = 11\n\
FRICTION/1, JOINT = 1, MU_STATIC = 0.5, MU_DYNAMIC = 0.3, PIN_RADIUS = 0.5, \
INPUTS = REACTION_FORCE\n\
ACCGRAV/, JGRAV = -9.80665\nEND\n"
        );
        let (m, d, f) = load(&text);
        let a = Assembled::new(&m, &d, &f, &Tolerances::default());
        let r = linkage_solve::stages::statics::run(&a, &[0.0]);
        let eq = r.steps[0].1.as_ref().unwrap_or_else(|e| panic!("{e}"));
        assert!(eq.converged, "a = {arm}: {:?}", eq.worst);
        let turned = {
            let x = eq.state.poses[0].r.col(0);
            -x.y.atan2(x.x)
        };
        let phi0 = arm * 0.01 / (0.5 * 0.5 * 0.5);
        let expected = (0..8).fold(phi0, |phi: f64, _| phi0 * phi.cos());
        assert!(
            (turned - expected).abs() < 1e-9,
            "a = {arm}: {turned} vs {expected}"
        );
        let rest = vec![Default::default(); 1];
        let v = f.friction_values(Regime::Dynamic, &eq.state, &rest);
        let weight = 2.0 * G;
        // The normal load is the final reaction, and the friction torque the weight's.
        assert!((v[0].normal - weight).abs() < 1e-9 * weight, "{:?}", v[0]);
        let torque = weight * arm * expected.cos();
        assert!(
            (v[0].torque.z.abs() - torque).abs() < 1e-9 * torque,
            "{:?}",
            v[0]
        );
        // One Newton solve with the load of the iterate's reaction (a = 0.1: 3 iterations;
        // the fixed point on a lagged load took 2 solves of 2 and found nothing for 0.2).
        assert!(
            eq.iterations <= most_iterations,
            "a = {arm}: {} iterations",
            eq.iterations
        );
        eprintln!("a = {arm}: {} iterations", eq.iterations);
    }
}
