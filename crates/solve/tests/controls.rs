//! Control and system elements against closed forms: DIFF (explicit and IMPLICIT), TFSISO,
//! LSE, a controller state coupled to the mechanics, in dynamics (BDF and HHT), statics
//! (STATIC_HOLD) and linearization; VARVAL in a MOTION.

use linkage_model::settings::IntegratorMethod;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::PI;
use std::sync::Arc;

fn model_of(body: &str) -> linkage_model::Model {
    let text = format!("controls\nUNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n{body}\nEND\n");
    let ds = linkage_adm::parse_dataset(Arc::from("controls.adm"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

/// A free body that nothing acts on: the mechanics the control states run beside.
const FREE_BODY: &str =
    "PART/1, GROUND\nPART/2, MASS = 1, IP = 1, 1, 1, CM = 3\nMARKER/3, PART = 2\n";

/// The outputs of a dynamic run of `m` at `steps + 1` times over `[0, end]`.
fn simulate(
    m: &linkage_model::Model,
    end: f64,
    steps: usize,
    method: IntegratorMethod,
) -> Vec<Output> {
    let d = ExpressionDrivers::new(m).unwrap_or_else(|e| panic!("{e}"));
    let f = ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"));
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error: 1e-7,
        method,
        ..Default::default()
    };
    let a = Assembled::new(m, &d, &f, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    assert!(r.error.is_none(), "{:?}", r.error);
    let sim = r.simulation.expect("simulated");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), steps + 1);
    sim.outputs
}

const METHODS: [IntegratorMethod; 2] = [IntegratorMethod::Bdf, IntegratorMethod::Hht];

fn worst(outputs: &[Output], f: impl Fn(&Output) -> (f64, f64)) -> f64 {
    outputs
        .iter()
        .map(|o| {
            let (got, want) = f(o);
            (got - want).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn diff_decays_exponentially_explicit_and_implicit() {
    // y' = −y/τ, y(0) = 2, τ = 0.5: y = 2 e^{−t/τ}; the IMPLICIT twin 0 = ẏ + y/τ; and an
    // algebraic IMPLICIT DIFF 0 = z − 3y, which follows as z = 3y.
    let m = model_of(&format!(
        "{FREE_BODY}DIFF/1, IC = 2, FUNCTION = -DIF(1)/0.5\n\
         DIFF/2, IC = 2, IMPLICIT, FUNCTION = DIF1(2) + DIF(2)/0.5\n\
         DIFF/3, IC = 6, IMPLICIT, FUNCTION = DIF(3) - 3*DIF(1)"
    ));
    assert_eq!(m.controls.count, 3);
    for method in METHODS {
        let out = simulate(&m, 2.0, 20, method);
        let exact = |t: f64| 2.0 * (-t / 0.5).exp();
        for k in 0..2 {
            let e = worst(&out, |o| (o.state.controls.x[k], exact(o.time)));
            assert!(e < 2e-4, "{method:?} DIFF/{}: error {e:e}", k + 1);
        }
        let e = worst(&out, |o| (o.state.controls.xdot[0], -exact(o.time) / 0.5));
        assert!(e < 1e-3, "{method:?} DIF1: error {e:e}");
        let e = worst(&out, |o| {
            (o.state.controls.x[2], 3.0 * o.state.controls.x[0])
        });
        assert!(e < 1e-6, "{method:?} algebraic DIFF: error {e:e}");
    }
}

#[test]
fn tfsiso_lags_follow_their_step_responses() {
    // Unit step into 1/(τs + 1), τ = 0.25: y = 1 − e^{−t/τ}; and into ω²/(s² + 2ζωs + ω²),
    // ω = 2π, ζ = 0.5: y = 1 − e^{−ζωt} sin(ω_d t + φ)/√(1 − ζ²), ω_d = ω√(1 − ζ²), cos φ = ζ.
    let w = 2.0 * PI;
    let m = model_of(&format!(
        "{FREE_BODY}VARIABLE/1, FUNCTION = 1\nARRAY/5, U, VARIABLES = 1\n\
         ARRAY/6, X\nARRAY/7, Y\nARRAY/8, X\nARRAY/9, Y\n\
         TFSISO/1, NUMERATOR = 1, DENOMINATOR = 1, 0.25, U = 5, X = 6, Y = 7\n\
         TFSISO/2, NUMERATOR = {}, DENOMINATOR = {}, {}, 1, U = 5, X = 8, Y = 9\n\
         VARIABLE/11, FUNCTION = ARYVAL(7, 1)\nVARIABLE/12, FUNCTION = ARYVAL(9, 1)",
        w * w,
        w * w,
        2.0 * 0.5 * w
    ));
    let forces = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let zeta: f64 = 0.5;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let second = |t: f64| {
        1.0 - (-zeta * w * t).exp() * (wd * t + zeta.acos()).sin() / (1.0 - zeta * zeta).sqrt()
    };
    for method in METHODS {
        let out = simulate(&m, 2.0, 40, method);
        let y = |o: &Output, id| {
            forces
                .variable(id, &o.state, &o.velocities)
                .unwrap_or_else(|e| panic!("{e}"))
        };
        let e = worst(&out, |o| (y(o, 11), 1.0 - (-o.time / 0.25).exp()));
        assert!(e < 2e-4, "{method:?} first-order lag: error {e:e}");
        let e = worst(&out, |o| (y(o, 12), second(o.time)));
        assert!(e < 1e-3, "{method:?} second-order lag: error {e:e}");
    }
}

#[test]
fn lse_oscillates_at_the_frequency_of_its_a_matrix() {
    // ẋ = A x, A = [0 1; −k/m 0] (k/m = 16): x₁ = cos 4t from x(0) = (1, 0).
    let m = model_of(&format!(
        "{FREE_BODY}ARRAY/1, X, SIZE = 2\nARRAY/2, IC, SIZE = 2, NUMBERS = 1, 0\n\
         MATRIX/3, FULL = RORDER, ROWS = 2, COLUMNS = 2, VALUES = 0, 1, -16, 0\n\
         LSE/1, X = 1, A = 3, IC = 2"
    ));
    for method in METHODS {
        let out = simulate(&m, 3.0, 60, method);
        let e = worst(&out, |o| (o.state.controls.x[0], (4.0 * o.time).cos()));
        assert!(e < 2e-3, "{method:?}: error {e:e}");
        let e = worst(&out, |o| {
            (o.state.controls.x[1], -4.0 * (4.0 * o.time).sin())
        });
        assert!(e < 8e-3, "{method:?}: error {e:e}");
    }
}

/// A unit mass on a translational joint along z, driven by a PID law through a DIFF that
/// integrates its position: `m z̈ = −Kp z − Kd ż − Ki I`, `İ = z`.
fn pid_plant(kp: f64, kd: f64, ki: f64, z0: f64) -> linkage_model::Model {
    model_of(&format!(
        "PART/1, GROUND\nMARKER/5, PART = 1\n\
         PART/2, MASS = 1, IP = 1, 1, 1, CM = 3, QG = 0, 0, {z0}\n\
         MARKER/3, PART = 2\nMARKER/4, PART = 2\n\
         JOINT/1, TRANSLATIONAL, I = 4, J = 5\n\
         DIFF/1, IC = 0, FUNCTION = DZ(3, 5, 5)\n\
         SFORCE/1, TRANSLATIONAL, ACTIONONLY, I = 3, J = 5, \
         FUNCTION = -{kp}*DZ(3, 5, 5) - {kd}*VZ(3, 5, 5, 5) - {ki}*DIF(1)"
    ))
}

#[test]
fn a_pid_controller_state_closes_the_loop_with_the_mechanics() {
    // Kp = Kd = 3, Ki = 1: (s + 1)³, so from z(0) = 1 at rest z = (1 + t − t²) e^{−t}.
    let m = pid_plant(3.0, 3.0, 1.0, 1.0);
    for method in METHODS {
        let out = simulate(&m, 4.0, 40, method);
        let e = worst(&out, |o| {
            let t = o.time;
            (o.state.poses[0].p.z, (1.0 + t - t * t) * (-t).exp())
        });
        assert!(e < 1e-3, "{method:?}: error {e:e}");
        let e = worst(&out, |o| (o.state.controls.x[0], integral(o.time)));
        assert!(e < 1e-3, "{method:?}: integral state error {e:e}");
    }
}

/// The controller's state `I = ∫₀ᵗ z = ∫₀ᵗ (1 + s − s²) e^{−s} ds = (t² + t) e^{−t}` (the
/// antiderivative's derivative is `(2t + 1 − t² − t) e^{−t}`, and it is 0 at t = 0).
fn integral(t: f64) -> f64 {
    (t * t + t) * (-t).exp()
}

#[test]
fn a_motion_follows_the_variable_it_reads() {
    // MOTION z = VARVAL(1), VARIABLE/1 = 0.1·TIME + ARYVAL(2, 1)·TIME², ARRAY/2 = (0.5):
    // z(t) = 0.1 t + 0.5 t² (and the velocity from the series of the inlined function).
    let m = model_of(
        "PART/1, GROUND\nMARKER/5, PART = 1\n\
         PART/2, MASS = 1, IP = 1, 1, 1, CM = 3\nMARKER/3, PART = 2\n\
         JOINT/1, TRANSLATIONAL, I = 3, J = 5\n\
         VARIABLE/1, FUNCTION = 0.1*TIME + ARYVAL(2, 1)*TIME**2\n\
         ARRAY/2, IC, NUMBERS = 0.5\n\
         MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = VARVAL(1)",
    );
    let out = simulate(&m, 1.0, 10, IntegratorMethod::Bdf);
    let e = worst(&out, |o| {
        (o.state.poses[0].p.z, 0.1 * o.time + 0.5 * o.time * o.time)
    });
    assert!(e < 1e-9, "position error {e:e}");
    let e = worst(&out, |o| (o.velocities[0].0.z, 0.1 + o.time));
    assert!(e < 1e-9, "velocity error {e:e}");
    // A VARIABLE that depends on the state cannot drive a motion: named.
    let m = model_of(
        "PART/1, GROUND\nMARKER/5, PART = 1\n\
         PART/2, MASS = 1, IP = 1, 1, 1, CM = 3\nMARKER/3, PART = 2\n\
         JOINT/1, TRANSLATIONAL, I = 3, J = 5\nVARIABLE/1, FUNCTION = DZ(3, 5)\n\
         MOTION/1, JOINT = 1, TRANSLATION, FUNCTION = VARVAL(1)",
    );
    let e = ExpressionDrivers::new(&m)
        .err()
        .map(|d| d.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("MOTION_1: FUNCTION: it depends on the model's state"),
        "{e}"
    );
}

/// A unit mass on a translational joint along z with a spring `−k z` and a force `−DIF(1)`
/// from a state whose law is `law`.
fn spring_with_state(k: f64, law: &str) -> linkage_model::Model {
    model_of(&format!(
        "PART/1, GROUND\nMARKER/5, PART = 1\n\
         PART/2, MASS = 1, IP = 1, 1, 1, CM = 3\nMARKER/3, PART = 2\n\
         JOINT/1, TRANSLATIONAL, I = 3, J = 5\n{law}\n\
         SFORCE/1, TRANSLATIONAL, ACTIONONLY, I = 3, J = 5, \
         FUNCTION = -{k}*DZ(3, 5, 5) - DIF(1)"
    ))
}

/// The static equilibrium of `m` at time 0: the CM height and the control states.
fn equilibrium(m: &linkage_model::Model) -> (f64, Vec<f64>) {
    let d = ExpressionDrivers::new(m).unwrap_or_else(|e| panic!("{e}"));
    let f = ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"));
    let a = Assembled::new(m, &d, &f, &Tolerances::default());
    let r = linkage_solve::stages::statics::run(&a, &[0.0]);
    let eq = r.steps[0].1.as_ref().unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    (eq.state.poses[0].p.z, eq.state.controls.x.clone())
}

#[test]
fn statics_solve_free_states_at_rest_and_keep_held_ones() {
    // ẏ = 1 − y: at rest y = 1, so k z = −1 (k = 10: z = −0.1); held at its IC 2: z = −0.2.
    let (z, x) = equilibrium(&spring_with_state(
        10.0,
        "DIFF/1, IC = 2, FUNCTION = 1 - DIF(1)",
    ));
    assert!(
        (z + 0.1).abs() < 1e-9 && (x[0] - 1.0).abs() < 1e-9,
        "{z} {x:?}"
    );
    let held = "DIFF/1, IC = 2, STATIC_HOLD, FUNCTION = 1 - DIF(1)";
    let (z, x) = equilibrium(&spring_with_state(10.0, held));
    assert!((z + 0.2).abs() < 1e-9 && x[0] == 2.0, "{z} {x:?}");
    // An integrator İ = z − 0.05 holds the mass at z = 0.05 against the spring: I = −k·0.05.
    let pi = "DIFF/1, IC = 0, FUNCTION = DZ(3, 5, 5) - 0.05";
    let (z, x) = equilibrium(&spring_with_state(10.0, pi));
    assert!(
        (z - 0.05).abs() < 1e-9 && (x[0] + 0.5).abs() < 1e-8,
        "{z} {x:?}"
    );
}

/// The eigenvalues (radians per time unit, conjugates included) of `m` linearized at its
/// initial conditions.
fn eigenvalues(m: &linkage_model::Model) -> Vec<(f64, f64)> {
    use linkage_solve::stages::linearize::{run as linear, EigenMethod, LinearOptions};
    let d = ExpressionDrivers::new(m).unwrap_or_else(|e| panic!("{e}"));
    let f = ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"));
    let a = Assembled::new(m, &d, &f, &Tolerances::default());
    let opts = LinearOptions {
        damping: true,
        vectors: false,
        method: EigenMethod::Auto,
    };
    let lin = linear(&a, false, opts)
        .result
        .unwrap_or_else(|e| panic!("{e}"));
    let mut out = Vec::new();
    for mode in &lin.modes {
        out.push((mode.real, mode.imag));
        if mode.imag != 0.0 {
            out.push((mode.real, -mode.imag));
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    out
}

#[test]
fn linear_eigenvalues_include_the_control_states() {
    // The LSE oscillator beside a free body: ±4i (and the free body's 12 zeros).
    let m = model_of(&format!(
        "{FREE_BODY}ARRAY/1, X, SIZE = 2\nARRAY/2, IC, SIZE = 2, NUMBERS = 1, 0\n\
         MATRIX/3, FULL = RORDER, ROWS = 2, COLUMNS = 2, VALUES = 0, 1, -16, 0\n\
         LSE/1, X = 1, A = 3, IC = 2"
    ));
    let ev = eigenvalues(&m);
    let nonzero: Vec<_> = ev.iter().filter(|(re, im)| re.hypot(*im) > 1e-6).collect();
    assert_eq!(nonzero.len(), 2, "{ev:?}");
    for (re, im) in nonzero {
        assert!(re.abs() < 1e-9 && (im.abs() - 4.0).abs() < 1e-9, "{ev:?}");
    }
    // The PID loop with Kp = 11, Kd = 6, Ki = 6: m s³ + Kd s² + Kp s + Ki = (s+1)(s+2)(s+3).
    let ev = eigenvalues(&pid_plant(11.0, 6.0, 6.0, 0.0));
    assert_eq!(ev.len(), 3, "{ev:?}");
    for ((re, im), want) in ev.iter().zip([-3.0, -2.0, -1.0]) {
        assert!((re - want).abs() < 1e-8 && im.abs() < 1e-8, "{ev:?}");
    }
}

#[test]
fn plant_matrices_carry_the_control_states() {
    // A lag 1/(0.25 s + 1) from the plant input VARIABLE/1 to the output VARIABLE/2 =
    // ARYVAL(Y, 1), beside a free body (6 coordinates, 12 states): the 13th state has
    // A = −4, B = 4, C = 1, and D = 0. PINVAL and POUVAL (also spelt POUTVAL) read the lists.
    use linkage_solve::stages::linearize::{assemble, state_matrix, OperatingPoint};
    use linkage_solve::stages::plant::plant;
    let m = model_of(&format!(
        "{FREE_BODY}VARIABLE/1, FUNCTION = 0\nARRAY/5, U, VARIABLES = 1\n\
         ARRAY/6, X\nARRAY/7, Y\n\
         TFSISO/1, NUMERATOR = 1, DENOMINATOR = 1, 0.25, U = 5, X = 6, Y = 7\n\
         VARIABLE/2, FUNCTION = ARYVAL(7, 1)\nPINPUT/1, VARIABLES = 1\nPOUTPUT/1, VARIABLES = 2\n\
         VARIABLE/3, FUNCTION = PINVAL(1, 1) + POUVAL(1, 1) + POUTVAL(1, 1)"
    ));
    let d = ExpressionDrivers::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let mut s = a.state().clone();
    let v = a.velocities();
    let at = OperatingPoint {
        state: &s,
        velocities: &v,
        multipliers: &[],
    };
    let eq = assemble(&m, &a.system, &a.kept, &f, at, true).unwrap_or_else(|e| panic!("{e}"));
    let sm = state_matrix(&eq).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((sm.coordinates, sm.controls), (6, 1));
    let pl = plant(&m, &f, at, &sm, &[1], &[2]).unwrap_or_else(|e| panic!("{e}"));
    let n = 13;
    assert!(
        (sm.a[12 * n + 12] + 4.0).abs() < 1e-12,
        "{:?}",
        &sm.a[12 * n..]
    );
    assert!((pl.b[12] - 4.0).abs() < 1e-6, "{:?}", pl.b);
    assert!(pl.b[..12].iter().all(|x| *x == 0.0), "{:?}", pl.b);
    assert!((pl.c[12] - 1.0).abs() < 1e-6 && pl.c[..12].iter().all(|x| x.abs() < 1e-12));
    assert!(pl.d[0].abs() < 1e-12, "{:?}", pl.d);
    s.controls.x[0] = 0.5;
    let y = f.variable(3, &s, &v).unwrap_or_else(|e| panic!("{e}"));
    assert!((y - 1.0).abs() < 1e-15, "{y}");
}

#[test]
fn a_matrix_file_is_read_relative_to_the_dataset_and_a_missing_one_is_named() {
    // The LSE oscillator's A from an ADAMSMAT file beside the dataset (CORDER, Fortran
    // fields without separators): [0 1; −16 0].
    let dir = std::env::temp_dir().join(format!("linkage-matrix-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{e}"));
    let mat = "ADAMSMAT oscillator\n1\nAOSC\nAOSC FULL CORDER 2 2 4 ( 4F7.2 )\n   0.00 -16.00   1.00   0.00\n";
    std::fs::write(dir.join("a.mat"), mat).unwrap_or_else(|e| panic!("{e}"));
    let text = format!(
        "m\n{FREE_BODY}ARRAY/1, X, SIZE = 2\nARRAY/2, IC, SIZE = 2, NUMBERS = 1, 0\n\
         MATRIX/3, FILE = a.mat, NAME = AOSC\nLSE/1, X = 1, A = 3, IC = 2\nEND\n"
    );
    let path = dir.join("m.adm");
    std::fs::write(&path, &text).unwrap_or_else(|e| panic!("{e}"));
    let ds = linkage_adm::read_dataset(&path).unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(
        m.controls.matrices[0].matrix.values,
        vec![0.0, 1.0, -16.0, 0.0]
    );
    let out = simulate(&m, 1.0, 10, IntegratorMethod::Bdf);
    let e = worst(&out, |o| (o.state.controls.x[0], (4.0 * o.time).cos()));
    assert!(e < 2e-3, "error {e:e}");
    // Without the file: a finding naming it, and the LSE that uses it is refused.
    std::fs::remove_file(dir.join("a.mat")).unwrap_or_else(|e| panic!("{e}"));
    let ds = linkage_adm::read_dataset(&path).unwrap_or_else(|e| panic!("{e}"));
    let found = linkage_solve::coverage::findings(&ds);
    assert!(
        found
            .iter()
            .any(|f| f.element == "MATRIX/3" && f.detail.contains("'a.mat'")),
        "{found:?}"
    );
    let e = linkage_model::build_model(&ds)
        .err()
        .map(|d| d.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("LSE_1: MATRIX_3: the file 'a.mat' cannot be read"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
