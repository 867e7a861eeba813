//! Second time derivatives of general constraints (GCON): measure and direction-cosine series
//! along a path against finite differences of the position measures, the acceleration bias
//! against the second derivative of the residual along a trajectory, and GCON models'
//! accelerations and reactions against closed forms and an equivalent joint model.

use glam::DVec3;
use linkage_expr::{evaluate, evaluate_path_series, parse};
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::constraints::rows::RowGradient;
use linkage_solve::constraints::system::System;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::physics::measures::{MarkerFrames, PathEnv, PositionEnv};
use linkage_solve::pipeline::ic::InitialConditions;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, DynamicRun, IntegratorSettings};
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

fn model(name: &str) -> linkage_model::Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let ds = linkage_adm::read_dataset(&path).expect("dataset parses");
    linkage_model::build_model(&ds).expect("model builds").model
}

fn model_of(text: &str) -> linkage_model::Model {
    let ds =
        linkage_adm::parse_dataset(Arc::from("gcon.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

/// One `(linear, angular)` pair per part.
type Twists = Vec<(DVec3, DVec3)>;

/// Twists and accelerations of the parts of every_row.adm (arbitrary, all non-zero).
fn motion(n: usize) -> (Twists, Twists) {
    let v = (0..n)
        .map(|k| {
            let k = k as f64;
            (
                DVec3::new(0.3 - 0.1 * k, 0.5 + 0.2 * k, -0.4 + 0.05 * k),
                DVec3::new(0.7 - 0.3 * k, -0.6 + 0.4 * k, 0.9 - 0.1 * k),
            )
        })
        .collect();
    let a = (0..n)
        .map(|k| {
            let k = k as f64;
            (
                DVec3::new(-1.2 + 0.3 * k, 0.8, 0.5 - 0.2 * k),
                DVec3::new(0.4 + 0.2 * k, 1.1 - 0.5 * k, -0.7),
            )
        })
        .collect();
    (v, a)
}

/// The state at time `t` along the path `p(t) = p + v t + a t²/2`,
/// `R(t) = exp([ω t + α t²/2]×)·R` (twist v, ω and accelerations a, α at t = 0), TIME
/// advancing with t.
fn along(s: &State, v: &[(DVec3, DVec3)], a: &[(DVec3, DVec3)], t: f64) -> State {
    let mut out = s.clone();
    for k in 0..s.poses.len() {
        out.increment(
            k,
            v[k].0 * t + a[k].0 * (0.5 * t * t),
            v[k].1 * t + a[k].1 * (0.5 * t * t),
        );
    }
    out.time = s.time + t;
    out
}

/// `[f, f', f'']` of `f(t)` by central differences with step `h`.
fn central(f: impl Fn(f64) -> f64, h: f64) -> [f64; 3] {
    let (fm, f0, fp) = (f(-h), f(0.0), f(h));
    [f0, (fp - fm) / (2.0 * h), (fp - 2.0 * f0 + fm) / (h * h)]
}

fn assert_series(got: [f64; 3], want: [f64; 3], what: &str) {
    assert!(
        (got[0] - want[0]).abs() < 1e-12 * (1.0 + want[0].abs()),
        "{what}: value {} vs {}",
        got[0],
        want[0]
    );
    assert!(
        (got[1] - want[1]).abs() < 1e-7 * (1.0 + want[1].abs()),
        "{what}: rate {} vs finite difference {}",
        got[1],
        want[1]
    );
    assert!(
        (got[2] - want[2]).abs() < 2e-5 * (1.0 + want[2].abs()),
        "{what}: second derivative {} vs finite difference {}",
        got[2],
        want[2]
    );
}

#[test]
fn position_measures_follow_the_path_to_second_order() {
    let m = model("every_row.adm");
    let frames = MarkerFrames::new(&m);
    let mut s = State::input(&m);
    s.time = 0.4;
    let (v, a) = motion(m.parts.len());
    let mut texts: Vec<String> = Vec::new();
    for (i, j, k) in [(21, 32, 41), (33, 0, 22), (42, 23, 0), (31, 2, 3)] {
        for kind in ["DX", "DY", "DZ"] {
            texts.push(format!("{kind}({i}, {j}, {k})"));
        }
        for kind in [
            "DM", "AX", "AY", "AZ", "PSI", "THETA", "PHI", "YAW", "PITCH", "ROLL",
        ] {
            texts.push(format!("{kind}({i}, {j})"));
        }
        for system in 1..=29 {
            let components = match system {
                27 => 4,
                29 => 9,
                _ => 3,
            };
            for c in 1..=components {
                texts.push(format!("ORIENT({system}, {c}, {i}, {j})"));
            }
        }
    }
    texts.push("DM(21, 32) * TIME**2 + SIN(AZ(42, 23) * TIME)".into());
    let h = 1e-4;
    for text in &texts {
        let e = parse(text).unwrap_or_else(|err| panic!("{text}: {err}"));
        let env = PathEnv {
            frames: &frames,
            state: &s,
            velocities: &v,
            accelerations: Some(&a),
            time_rate: 1.0,
        };
        let got = evaluate_path_series(&e, &env).unwrap_or_else(|err| panic!("{text}: {err}"));
        let value = |t: f64| {
            let st = along(&s, &v, &a, t);
            evaluate(
                &e,
                &PositionEnv {
                    frames: &frames,
                    state: &st,
                },
            )
            .unwrap_or_else(|err| panic!("{text}: {err}"))
        };
        assert_series(got, central(value, h), text);
    }
}

#[test]
fn velocity_measures_have_no_path_series() {
    let m = model("every_row.adm");
    let frames = MarkerFrames::new(&m);
    let s = State::input(&m);
    let (v, _) = motion(m.parts.len());
    let env = PathEnv {
        frames: &frames,
        state: &s,
        velocities: &v,
        accelerations: None,
        time_rate: 1.0,
    };
    let err = evaluate_path_series(&parse("VX(21)").unwrap(), &env).unwrap_err();
    assert!(err.message.contains("third derivatives"), "{}", err.message);
    let err = evaluate_path_series(&parse("DM(21, 21)").unwrap(), &env).unwrap_err();
    assert!(err.message.contains("coincide"), "{}", err.message);
}

/// `∇Φ·x` for a row gradient and part twists.
fn rate(g: &RowGradient, x: &[(DVec3, DVec3)]) -> f64 {
    g.blocks
        .iter()
        .map(|(k, b)| {
            DVec3::new(b[0], b[1], b[2]).dot(x[*k].0) + DVec3::new(b[3], b[4], b[5]).dot(x[*k].1)
        })
        .sum()
}

/// `Φ̇ = ∇Φ·v + ∂Φ/∂t` and `Φ̈ = ∇Φ·a + γ` for every row of every_row.adm (geometric rows and
/// the three general constraints, one of them with TIME) against differences of the residual
/// along a trajectory.
#[test]
fn acceleration_bias_is_the_second_derivative_of_the_residual() {
    let m = model("every_row.adm");
    let sys = System::new(&m);
    let mut s = State::input(&m);
    s.time = 0.4;
    let (v, a) = motion(m.parts.len());
    let mut g = RowGradient::default();
    let mut gcons = 0;
    for r in 0..sys.rows.len() {
        let row = &sys.rows[r];
        if row.driven {
            continue; // the drive f(t) is the motion's, not the row's
        }
        sys.gradient(r, &s, &mut g);
        let bias = sys.acceleration_bias(r, &s, &v, 1.0).unwrap();
        let explicit = sys.explicit_rate(r, &s, 1.0).unwrap();
        let got = [
            sys.residual(r, &s, 0.0),
            rate(&g, &v) + explicit,
            rate(&g, &a) + bias,
        ];
        let want = central(|t| sys.residual(r, &along(&s, &v, &a, t), 0.0), 1e-4);
        let name = format!(
            "row {r} ({} {})",
            m.constraints[row.element].origin.name, row.label
        );
        assert_series(got, want, &name);
        if row.function.is_some() {
            gcons += 1;
            if row.function.as_ref().is_some_and(|f| f.uses_time()) {
                assert!(explicit.abs() > 1e-3, "{name}: ∂Φ/∂t = {explicit}");
            }
        }
    }
    assert_eq!(gcons, 3);
}

const G: f64 = 9.80665;

/// A point mass on a 2 m distance constraint from the ground origin (the constraint acts at
/// its centre of mass, so it never turns), started 60° from the downward vertical, moving
/// at 1.5 m/s along the circle in the y-z plane.
const DISTANCE_PENDULUM: &str = "distance pendulum
UNITS/FORCE=NEWTON, MASS=KILOGRAM, LENGTH=METER, TIME=SECOND
ACCGRAV/KGRAV=-9.80665
PART/1, GROUND
MARKER/1, PART=1
PART/2, MASS=1.5, CM=20, IP=0.04, 0.1, 0.1, VY=0.75, VZ=1.299038105676658
MARKER/20, PART=2, QP=0, 1.7320508075688772, -1
GCON/1, I=20, FUNCTION=DM(20, 1) - 2
END
";

/// The same pendulum on a revolute joint at the ground origin (axis x), with a negligible
/// moment of inertia about its centre of mass (I/(m L²) ≈ 2e-7).
const REVOLUTE_PENDULUM: &str = "revolute pendulum
UNITS/FORCE=NEWTON, MASS=KILOGRAM, LENGTH=METER, TIME=SECOND
ACCGRAV/KGRAV=-9.80665
PART/1, GROUND
MARKER/1, PART=1
MARKER/2, PART=1, REULER=90D, 90D, 0
PART/2, MASS=1.5, CM=20, IP=1E-6, 1E-6, 1E-6, VY=0.75, VZ=1.299038105676658
MARKER/20, PART=2, QP=0, 1.7320508075688772, -1
MARKER/21, PART=2, REULER=90D, 90D, 0
JOINT/1, REVOLUTE, I=21, J=2
END
";

fn simulate(text: &str, end: f64, steps: usize) -> DynamicRun {
    simulate_with_ic(text, end, steps).0
}

/// The run and the initial conditions it started from.
fn simulate_with_ic(text: &str, end: f64, steps: usize) -> (DynamicRun, InitialConditions) {
    let m = model_of(text);
    let d = ExpressionDrivers::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error: 1e-8,
        ..Default::default()
    };
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let r = run(
        &a,
        &times,
        &settings,
        linkage_solve::stages::dynamics::Start::InitialConditions,
        |_| {},
    );
    (r, a.ic)
}

fn close(got: DVec3, want: DVec3, tol: f64, what: &str) {
    assert!(
        (got - want).length() <= tol,
        "{what}: {got:?} vs {want:?} (difference {:e})",
        (got - want).length()
    );
}

/// At every output of the distance pendulum, given its position p and velocity v: the
/// acceleration is the tangential part of gravity plus the centripetal `−|v|²/L p̂`, the body
/// does not turn, and the constraint's reaction on the mass is the rod tension
/// `−m (|v|²/L + g cos θ) p̂` — the velocity-product term of `DM` that was missing before
/// exact second derivatives.
#[test]
fn distance_pendulum_tension_is_centripetal_plus_gravity() {
    let (r, ic) = simulate_with_ic(DISTANCE_PENDULUM, 2.0, 40);
    let sim = r.simulation.as_ref().expect("simulated");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), 41);
    let (m, l) = (1.5, 2.0);
    let g = DVec3::new(0.0, 0.0, -G);
    // Start: speed 1.5 m/s at height z = −1 m.
    let energy0 = 0.5 * 1.5f64.powi(2) - G;
    for o in &sim.outputs {
        let (p, v) = (o.state.poses[0].p, o.velocities[0].0);
        let (a, alpha) = o.accelerations[0];
        let n = p / p.length();
        assert!(
            (p.length() - l).abs() < 1e-9,
            "t = {}: |p| = {}",
            o.time,
            p.length()
        );
        assert!(v.dot(n).abs() < 1e-9, "t = {}: radial velocity", o.time);
        let energy = 0.5 * v.length_squared() + G * p.z;
        // Energy per unit mass, to the integrator's accuracy (HHT-α dissipates slightly).
        assert!(
            (energy - energy0).abs() < 1e-5 * energy0.abs(),
            "t = {}: energy {energy} vs {energy0}",
            o.time
        );
        let want = g - n * g.dot(n) - n * (v.length_squared() / l);
        close(a, want, 1e-9 * G, &format!("t = {}: acceleration", o.time));
        close(
            alpha,
            DVec3::ZERO,
            1e-9,
            &format!("t = {}: angular acceleration", o.time),
        );
        // g cos θ = g_vec·p̂ (θ from the downward vertical).
        let tension = m * (v.length_squared() / l + g.dot(n));
        let reaction = &o.reactions[0];
        close(
            reaction.force,
            -n * tension,
            1e-9 * m * G,
            &format!("t = {}: reaction force", o.time),
        );
        close(reaction.torque, DVec3::ZERO, 1e-9, "reaction torque");
    }
    // The initial conditions report the same acceleration (no refusal for a GCON).
    let acc = ic.acceleration.as_ref().expect("acceleration IC").as_ref();
    let acc = acc.unwrap_or_else(|e| panic!("{e}"));
    let first = &sim.outputs[0];
    close(
        acc.accelerations[0].0,
        first.accelerations[0].0,
        1e-9 * G,
        "IC acceleration",
    );
}

/// Equivalence: the distance constraint and a revolute joint at the same pivot move the mass
/// alike, with the same accelerations and the same force on it (the revolute's reaction acts
/// at the pivot, the GCON's at the mass; the force is the same vector).
#[test]
fn distance_pendulum_matches_its_revolute_twin() {
    let (a, b) = (
        simulate(DISTANCE_PENDULUM, 2.0, 40),
        simulate(REVOLUTE_PENDULUM, 2.0, 40),
    );
    let (a, b) = (
        a.simulation.as_ref().expect("GCON run"),
        b.simulation.as_ref().expect("revolute run"),
    );
    assert!(a.failure.is_none() && b.failure.is_none());
    for (x, y) in a.outputs.iter().zip(&b.outputs) {
        let t = x.time;
        close(
            x.state.poses[0].p,
            y.state.poses[0].p,
            1e-5,
            &format!("t = {t}: position"),
        );
        close(
            x.velocities[0].0,
            y.velocities[0].0,
            1e-5,
            &format!("t = {t}: velocity"),
        );
        close(
            x.accelerations[0].0,
            y.accelerations[0].0,
            1e-5 * G,
            &format!("t = {t}: acceleration"),
        );
        close(
            x.reactions[0].force,
            y.reactions[0].force,
            1e-5 * 1.5 * G,
            &format!("t = {t}: constraint force"),
        );
    }
}

/// Statics with a general constraint uses its Hessian (the geometric stiffness `λ ∇²Φ`): a
/// point mass held up by a 2 m distance constraint has, about the inverted equilibrium, the
/// stiffness `λ (1 − d̂d̂ᵀ)/L = −(m g/L)(1 − d̂d̂ᵀ)` sideways, which alone makes it unstable
/// (gravity is constant: without the constraint's second derivatives the reduced stiffness
/// would vanish). Hanging, the same term is positive and the equilibrium stable.
#[test]
fn distance_pendulum_statics_see_the_rod_geometric_stiffness() {
    let (m, l) = (1.5, 2.0);
    let solve = |qp: &str| {
        let text = DISTANCE_PENDULUM
            .replace("QP=0, 1.7320508075688772, -1", qp)
            .replace(", VY=0.75, VZ=1.299038105676658", "");
        let model = model_of(&text);
        let d = ExpressionDrivers::new(&model).unwrap_or_else(|e| panic!("{e}"));
        let a = Assembled::new(&model, &d, &NoForces, &Tolerances::default());
        let r = linkage_solve::stages::statics::run(&a, &[0.0]);
        drop(a);
        let eq = r.steps[0].1.clone().unwrap_or_else(|e| panic!("{e}"));
        (model, eq)
    };
    // Inverted, started 0.05 m off.
    let (model, eq) = solve("QP=0, 0.05, 1.9");
    assert!(eq.converged, "{:?}", eq.worst);
    assert_eq!(eq.approximate_rows, 0);
    close(
        eq.state.poses[0].p,
        DVec3::new(0.0, 0.0, l),
        1e-9,
        "inverted",
    );
    let (stable, lowest) = eq.stability.expect("stability evaluated");
    assert!(!stable, "lowest eigenvalue {lowest}");
    // Reduced coordinates measure translations in characteristic lengths Lc.
    let lc = model.characteristic_length;
    let expected = -m * G / l * lc * lc;
    assert!(
        (lowest - expected).abs() < 1e-6 * expected.abs(),
        "{lowest} vs {expected}"
    );
    // The constraint carries the weight: the reaction on the mass is m g upwards.
    close(
        eq.reactions[0].force,
        DVec3::new(0.0, 0.0, m * G),
        1e-6 * m * G,
        "inverted reaction",
    );
    // Hanging, started 0.3 m off: stable.
    let (_, eq) = solve("QP=0.3, 0, -1.9");
    assert!(eq.converged, "{:?}", eq.worst);
    close(
        eq.state.poses[0].p,
        DVec3::new(0.0, 0.0, -l),
        1e-9,
        "hanging",
    );
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
}

/// A general constraint with explicit TIME: the rod length `L(t) = 2 + 0.1 sin 3t`. The
/// outputs' velocities satisfy `v·p̂ = L̇` (the velocity equations carry `−∂Φ/∂t`) and their
/// accelerations `a·p̂ + (|v|² − (v·p̂)²)/|p| = L̈` (the acceleration equations carry the
/// time terms of the bias), at the start (initial conditions) and all along.
#[test]
fn time_dependent_distance_constraint_drives_velocities_and_accelerations() {
    let text = DISTANCE_PENDULUM.replace(
        "FUNCTION=DM(20, 1) - 2",
        "FUNCTION=DM(20, 1) - 2 - 0.1*SIN(3*TIME)",
    );
    let r = simulate(&text, 1.0, 20);
    let sim = r.simulation.as_ref().expect("simulated");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), 21);
    for o in &sim.outputs {
        let t = o.time;
        let (p, v, a) = (o.state.poses[0].p, o.velocities[0].0, o.accelerations[0].0);
        let length = 2.0 + 0.1 * (3.0 * t).sin();
        let rate = 0.3 * (3.0 * t).cos();
        let acc = -0.9 * (3.0 * t).sin();
        let n = p / p.length();
        assert!(
            (p.length() - length).abs() < 1e-9,
            "t = {t}: |p| = {}",
            p.length()
        );
        assert!(
            (v.dot(n) - rate).abs() < 1e-9,
            "t = {t}: v·p̂ = {}",
            v.dot(n)
        );
        let radial = a.dot(n) + (v.length_squared() - v.dot(n).powi(2)) / p.length();
        assert!((radial - acc).abs() < 1e-8, "t = {t}: {radial} vs {acc}");
    }
}

/// A general constraint whose I marker is on ground (Adams' Distance_Case03 writes its GCON so)
/// reports the force on that ground marker: minus the force on the parts it measures, here the
/// rod tension pulling the ground point towards the mass, `+m (|v|²/L + g cos θ) p̂`, with no
/// torque about the point (the force on the mass acts along the line through it).
#[test]
fn a_distance_constraint_on_a_ground_marker_reports_the_tension_on_ground() {
    let text = DISTANCE_PENDULUM.replace(
        "GCON/1, I=20, FUNCTION=DM(20, 1) - 2",
        "GCON/1, I=1, FUNCTION=DM(20, 1) - 2",
    );
    let r = simulate(&text, 1.0, 10);
    let sim = r.simulation.as_ref().expect("simulated");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let (m, l) = (1.5, 2.0);
    let g = DVec3::new(0.0, 0.0, -G);
    for o in &sim.outputs {
        let (p, v) = (o.state.poses[0].p, o.velocities[0].0);
        let n = p / p.length();
        let tension = m * (v.length_squared() / l + g.dot(n));
        let reaction = &o.reactions[0];
        assert!(tension.abs() > 1.0, "t = {}: a real tension", o.time);
        close(
            reaction.force,
            n * tension,
            1e-9 * m * G,
            &format!("t = {}: reaction force on ground", o.time),
        );
        close(reaction.torque, DVec3::ZERO, 1e-8, "reaction torque");
    }
}
