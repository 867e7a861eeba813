//! Force elements in whole analyses against hand-derived values: static deflections and
//! reactions (signs included), natural frequencies and damping ratios of the linearization,
//! free decay and constant-load motion in the dynamic run. The force laws themselves are
//! written in `physics/forces/six_dof.rs` and `beam.rs` (BUSHING, FIELD, BEAM) and
//! ADM-REFERENCE §2.10 (VFORCE, VTORQUE, GFORCE: components along RM, applied at I).

use glam::{DMat3, DVec3};
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Start};
use linkage_solve::stages::linearize::{EigenMethod, LinearOptions, Linearization};
use linkage_solve::stages::statics::Equilibrium;
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::sync::Arc;

const G: f64 = 9.80665;

const HEADER: &str = "\
force elements
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1
MARKER/2, PART = 1, FLOATING
";

fn load(body: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let text = format!("{HEADER}{body}\nEND\n");
    let ds = linkage_adm::parse_dataset(Arc::from("forces.adm"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

fn statics(body: &str) -> (Model, Equilibrium) {
    let (m, d, f) = load(body);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let mut r = linkage_solve::stages::statics::run(&a, &[0.0]);
    drop(a);
    let eq = r.steps.remove(0).1.unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    (m, eq)
}

fn linear(body: &str, static_first: bool) -> Linearization {
    let (m, d, f) = load(body);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    linkage_solve::stages::linearize::run(
        &a,
        static_first,
        LinearOptions {
            damping: true,
            vectors: false,
            method: EigenMethod::Auto,
        },
    )
    .result
    .unwrap_or_else(|e| panic!("{e}"))
}

/// A dynamic run to `end` with `steps` outputs at INTEGRATOR ERROR `error`.
fn dynamics(body: &str, end: f64, steps: usize, error: f64) -> (Model, Vec<Output>) {
    let (m, d, f) = load(body);
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error,
        ..Default::default()
    };
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    drop(a);
    let sim = r.simulation.unwrap_or_else(|| panic!("{:?}", r.error));
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), times.len());
    (m, sim.outputs)
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tolerance {tol})");
}

fn close3(a: DVec3, b: DVec3, tol: f64, what: &str) {
    assert!(
        (a - b).length() <= tol,
        "{what}: {a:?} vs {b:?} (tolerance {tol})"
    );
}

/// Rotation angles of `r` as the six-DOF laws measure them against ground (ADM-REFERENCE
/// §5.3): AX = atan2(−z·Y, z·Z), AY = atan2(z·X, z·Z), AZ = atan2(x·Y, x·X).
fn ax_ay_az(r: DMat3) -> DVec3 {
    let (x, z) = (r.x_axis, r.z_axis);
    DVec3::new((-z.y).atan2(z.z), z.x.atan2(z.z), x.y.atan2(x.x))
}

/// Every expected (undamped natural frequency ω in rad/s, damping ratio ζ) is one of the
/// modes, to 1e-8 relative (dense eigen solution, rounding only).
fn assert_modes(l: &Linearization, expected: &[(f64, f64)]) {
    let modes: Vec<(f64, f64)> = l
        .modes
        .iter()
        .filter(|m| m.frequency > 1e-6)
        .map(|m| (m.frequency * TAU, m.damping_ratio))
        .collect();
    assert_eq!(modes.len(), expected.len(), "{modes:?} vs {expected:?}");
    for &(w, zeta) in expected {
        let found = modes
            .iter()
            .find(|(mw, _)| (mw - w).abs() < 1e-8 * w)
            .unwrap_or_else(|| panic!("no mode at ω = {w}: {modes:?}"));
        close(found.1, zeta, 1e-8, &format!("ζ of the mode at ω = {w}"));
    }
}

/// A 2 kg block with principal inertias 0.5, 0.8, 1 on a BUSHING at its centre to ground.
const BLOCK: &str = "PART/2, MASS = 2, CM = 20, IP = 0.5, 0.8, 1
MARKER/20, PART = 2
";
const BUSHING: &str = "BUSHING/1, I = 20, J = 1, K = 100, 200, 300, C = 2, 4, 6
, KT = 10, 20, 30, CT = 0.1, 0.2, 0.3";

/// Static: `F = −K q − C q̇ + F₀` on I along J's axes. Gravity −y, preload FORCE = (3, 0, 0)
/// and TORQUE = (0, 0, 0.5): x = 3/100, y = −m g/200, rotation about z = 0.5/30, the rest 0
/// (exact: the law is linear and the load passes through I = CM).
#[test]
fn bushing_deflects_by_load_over_stiffness() {
    let (_, eq) = statics(&format!(
        "{BLOCK}{BUSHING}, FORCE = 3, 0, 0, TORQUE = 0, 0, 0.5\nACCGRAV/JGRAV = -{G}"
    ));
    let pose = eq.state.poses[0];
    close3(
        pose.p,
        DVec3::new(0.03, -2.0 * G / 200.0, 0.0),
        1e-10,
        "deflection",
    );
    close3(
        ax_ay_az(pose.r),
        DVec3::new(0.0, 0.0, 0.5 / 30.0),
        1e-10,
        "rotation",
    );
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
}

/// Linear about the gravity equilibrium: six uncoupled oscillators, ω = √(k/m) and
/// ζ = c/(2√(k m)) for the translations, ω = √(kt/I) and ζ = ct/(2√(kt I)) for the rotations.
#[test]
fn bushing_modes_have_the_frequencies_and_damping_of_its_six_springs() {
    let l = linear(&format!("{BLOCK}{BUSHING}\nACCGRAV/JGRAV = -{G}"), true);
    let osc = |k: f64, c: f64, m: f64| ((k / m).sqrt(), c / (2.0 * (k * m).sqrt()));
    assert_modes(
        &l,
        &[
            osc(100.0, 2.0, 2.0),
            osc(200.0, 4.0, 2.0),
            osc(300.0, 6.0, 2.0),
            osc(10.0, 0.1, 0.5),
            osc(20.0, 0.2, 0.8),
            osc(30.0, 0.3, 1.0),
        ],
    );
}

/// Dynamic free decay: released from x = 0.01 at rest, with gravity along −y: each axis is a
/// damped oscillator, σ = c/(2m), ω_d = √(k/m − σ²):
/// x = x₀ e^(−σt) (cos ω_d t + σ/ω_d sin ω_d t), y = y_s (1 − e^(−σt) (cos ω_d t + σ/ω_d sin ω_d t))
/// with y_s = −m g/k_y; z and the rotations stay 0.
#[test]
fn bushing_free_decay_follows_the_damped_oscillator() {
    let block = BLOCK.replace("IP = 0.5, 0.8, 1", "IP = 0.5, 0.8, 1, QG = 0.01, 0, 0");
    let (_, outs) = dynamics(
        &format!("{block}{BUSHING}\nACCGRAV/JGRAV = -{G}"),
        2.0,
        40,
        1e-9,
    );
    let decay = |k: f64, c: f64, t: f64| {
        let (m, s) = (2.0, c / 4.0);
        let wd = (k / m - s * s).sqrt();
        (-s * t).exp() * ((wd * t).cos() + s / wd * (wd * t).sin())
    };
    let ys = -2.0 * G / 200.0;
    for o in &outs {
        let t = o.time;
        let p = o.state.poses[0].p;
        // HHT at ERROR 1e-9: 1e-6 of the 0.01 m and 0.098 m amplitudes.
        close(p.x, 0.01 * decay(100.0, 2.0, t), 1e-8, "x");
        close(p.y, ys * (1.0 - decay(200.0, 4.0, t)), 1e-7, "y");
        close(p.z, 0.0, 1e-12, "z");
        close3(ax_ay_az(o.state.poses[0].r), DVec3::ZERO, 1e-12, "rotation");
    }
}

/// FIELD with a coupled K (K_xy = 20) and the reference LENGTH = (0.1, 0, 0, 0, 0, 0), preload
/// FORCE = (1, 0, 0, 0, 0, 0.2) and gravity −y: `K (q − q₀) = F₀ + W`,
/// [100 20; 20 200] (dx, dy) = (1, −m g), dz = 0, rotation about z = 0.2/30.
#[test]
fn field_deflects_by_the_inverse_of_its_coupled_matrix() {
    let (_, eq) = statics(&format!("{BLOCK}{FIELD}\nACCGRAV/JGRAV = -{G}"));
    let (fx, fy) = (1.0, -2.0 * G);
    let det = 100.0 * 200.0 - 20.0 * 20.0;
    let (dx, dy) = (
        (200.0 * fx - 20.0 * fy) / det,
        (100.0 * fy - 20.0 * fx) / det,
    );
    let pose = eq.state.poses[0];
    close3(pose.p, DVec3::new(0.1 + dx, dy, 0.0), 1e-10, "deflection");
    close3(
        ax_ay_az(pose.r),
        DVec3::new(0.0, 0.0, 0.2 / 30.0),
        1e-10,
        "rotation",
    );
}

const FIELD: &str = "FIELD/1, I = 20, J = 1
, KMATRIX = 100, 20, 0, 0, 0, 0, 20, 200, 0, 0, 0, 0, 0, 0, 300, 0, 0, 0
, 0, 0, 0, 10, 0, 0, 0, 0, 0, 0, 20, 0, 0, 0, 0, 0, 0, 30
, CRATIO = 0.004, LENGTH = 0.1, 0, 0, 0, 0, 0, FORCE = 1, 0, 0, 0, 0, 0.2";

/// Linear about the static equilibrium: C = CRATIO·K is proportional damping, so each mode
/// has ζ = CRATIO·ω/2. Translations: ω² = k/m with k the eigenvalues of the x–y block
/// [100 20; 20 200], 150 ± √(50² + 20²), and 300 along z. Rotations: the preload torque has
/// turned the block by c = 0.2/30 about z, so its inertia in the field's axes is
/// I_g = Rz(c) diag(0.5, 0.8, 1) Rz(c)ᵀ: about z ω² = 30/1, about x and y the roots of
/// det(diag(10, 20) − ω² I_g,xy) = 0.
#[test]
fn field_modes_are_those_of_its_matrix_with_proportional_damping() {
    let l = linear(&format!("{BLOCK}{FIELD}\nACCGRAV/JGRAV = -{G}"), true);
    let cratio = 0.004;
    // Eigenvalues of [100 20; 20 200]: 150 ± √(50² + 20²).
    let r = (50.0f64 * 50.0 + 20.0 * 20.0).sqrt();
    let mode = |k: f64, m: f64| {
        let w = (k / m).sqrt();
        (w, cratio * w / 2.0)
    };
    let c = 0.2f64 / 30.0;
    let ig = DMat3::from_rotation_z(c)
        * DMat3::from_diagonal(DVec3::new(0.5, 0.8, 1.0))
        * DMat3::from_rotation_z(-c);
    let (a, b, d) = (ig.x_axis.x, ig.y_axis.x, ig.y_axis.y);
    // (10 − λa)(20 − λd) − λ²b² = 0: (ad − b²) λ² − (10d + 20a) λ + 200 = 0.
    let (qa, qb, qc) = (a * d - b * b, -(10.0 * d + 20.0 * a), 200.0);
    let disc = (qb * qb - 4.0 * qa * qc).sqrt();
    assert_modes(
        &l,
        &[
            mode(150.0 - r, 2.0),
            mode(150.0 + r, 2.0),
            mode(300.0, 2.0),
            mode((-qb - disc) / (2.0 * qa), 1.0),
            mode((-qb + disc) / (2.0 * qa), 1.0),
            mode(30.0, 1.0),
        ],
    );
}

/// A cantilever BEAM from ground (J, x along the beam) to a tip part (I at its centre,
/// L = 2 m), E = 2e5, G = 8e4, A = 0.01, Ixx = 2e-5, Iyy = 1e-5, Izz = 2e-5, ASY = ASZ = 1.2.
fn cantilever(extra: &str) -> String {
    format!(
        "PART/3, MASS = 1, CM = 30, IP = 0.1, 0.2, 0.3, QG = 2, 0, 0
MARKER/30, PART = 3
BEAM/1, I = 30, J = 1, LENGTH = 2, IXX = 2E-5, IYY = 1E-5, IZZ = 2E-5, AREA = 0.01
, ASY = 1.2, ASZ = 1.2, EMODULUS = 2E5, GMODULUS = 8E4, CRATIO = 0.001
{extra}"
    )
}

/// Tip loads along the ground axes (VFORCE at the tip, VTORQUE about x): Timoshenko
/// cantilever, linear in the deflections of I along and about J's axes:
/// axial x − L = N L/(E A); y = P L³/(3 E Izz) + P L ASY/(G A), rotation about z
/// c = P L²/(2 E Izz); z = Q L³/(3 E Iyy) + Q L ASZ/(G A), b = −Q L²/(2 E Iyy); twist
/// a = T L/(G Ixx).
#[test]
fn beam_cantilever_deflects_as_timoshenko_beam_theory_says() {
    let (n, p, q, t) = (5.0, 0.1, -0.03, 0.02);
    let (_, eq) = statics(&cantilever(&format!(
        "VFORCE/1, I = 30, JFLOAT = 2, RM = 1, FX = {n}\\FY = {p}\\FZ = {q}
VTORQUE/1, I = 30, JFLOAT = 2, RM = 1, TX = {t}\\TY = 0\\TZ = 0"
    )));
    let (l, e, g, a) = (2.0f64, 2e5, 8e4, 0.01);
    let (ixx, iyy, izz, asy, asz) = (2e-5, 1e-5, 2e-5, 1.2, 1.2);
    let y = p * l.powi(3) / (3.0 * e * izz) + p * l * asy / (g * a);
    let z = q * l.powi(3) / (3.0 * e * iyy) + q * l * asz / (g * a);
    let pose = eq.state.poses[0];
    // Linear in (x, y, z, AX, AY, AZ): exact to the Newton's rounding.
    close3(
        pose.p,
        DVec3::new(l + n * l / (e * a), y, z),
        1e-10,
        "tip position",
    );
    close3(
        ax_ay_az(pose.r),
        DVec3::new(
            t * l / (g * ixx),
            -q * l * l / (2.0 * e * iyy),
            p * l * l / (2.0 * e * izz),
        ),
        1e-10,
        "tip rotation",
    );
    // The shear terms are resolved (3e-4 m of the 0.067 m deflection).
    assert!(p * l * asy / (g * a) > 1e3 * 1e-10);
}

/// Linear: the tip mass (m = 1, inertias 0.1, 0.2, 0.3) on the beam's end stiffness: axial
/// ω² = E A/(L m), torsion ω² = G Ixx/(L Jx); each bending plane a 2×2 problem
/// det(K₂ − ω² diag(m, J)) = 0 with K₂ = [12EI/(L³(1+Φ)), ∓6EI/(L²(1+Φ)); ·, (4+Φ)EI/(L(1+Φ))],
/// Φ = 12 E I AS/(G A L²); CRATIO damping is proportional, ζ = CRATIO·ω/2.
#[test]
fn beam_modes_are_the_tip_mass_on_the_end_stiffness() {
    let l = linear(&cantilever(""), false);
    let (len, e, g, a) = (2.0f64, 2e5, 8e4, 0.01);
    let cratio = 0.001;
    let mode = |w: f64| (w, cratio * w / 2.0);
    let bending = |i: f64, as_: f64, jr: f64| {
        let phi = 12.0 * e * i * as_ / (g * a * len * len);
        let k11 = 12.0 * e * i / (len.powi(3) * (1.0 + phi));
        let k12 = 6.0 * e * i / (len * len * (1.0 + phi));
        let k22 = (4.0 + phi) * e * i / (len * (1.0 + phi));
        // m J ω⁴ − (k11 J + k22 m) ω² + (k11 k22 − k12²) = 0 with m = 1.
        let (qa, qb, qc) = (jr, -(k11 * jr + k22), k11 * k22 - k12 * k12);
        let d = (qb * qb - 4.0 * qa * qc).sqrt();
        [
            ((-qb - d) / (2.0 * qa)).sqrt(),
            ((-qb + d) / (2.0 * qa)).sqrt(),
        ]
    };
    let [y1, y2] = bending(2e-5, 1.2, 0.3);
    let [z1, z2] = bending(1e-5, 1.2, 0.2);
    assert_modes(
        &l,
        &[
            mode((e * a / len).sqrt()),
            mode((g * 2e-5 / (len * 0.1)).sqrt()),
            mode(y1),
            mode(y2),
            mode(z1),
            mode(z2),
        ],
    );
}

/// A block welded to ground (FIXED, I at its origin) carrying constant loads; its reaction on
/// the block is minus their resultant about the I origin:
/// VFORCE FX = 10 along RM's x (RM turned 90° about z, so ground +y) at (1, 0, 0);
/// VTORQUE TZ = 4 about RM's z; GFORCE FZ = 5, TX = 3 in ground axes at (0, 2, 0).
/// Resultant F = (0, 10, 5), moment (1,0,0)×(0,10,0) + (0,2,0)×(0,0,5) + (0,0,4) + (3,0,0)
/// = (13, 0, 14); reaction (0, −10, −5), (−13, 0, −14).
#[test]
fn vector_loads_are_balanced_by_the_weld_with_the_right_signs() {
    let (m, eq) = statics(
        "MARKER/3, PART = 1, REULER = 90D, 0D, 0D
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 1, 0, 0
MARKER/22, PART = 2, QP = 0, 2, 0
JOINT/1, FIXED, I = 20, J = 1
VFORCE/1, I = 21, JFLOAT = 2, RM = 3, FX = 10\\FY = 0\\FZ = 0
VTORQUE/1, I = 21, JFLOAT = 2, RM = 3, TX = 0\\TY = 0\\TZ = 4
GFORCE/1, I = 22, JFLOAT = 2, RM = 1, FX = 0\\FY = 0\\FZ = 5\\TX = 3\\TY = 0\\TZ = 0",
    );
    let weld = m
        .constraints
        .iter()
        .position(|c| c.origin.name == "JOINT_1")
        .unwrap();
    let r = eq.reactions.iter().find(|r| r.element == weld).unwrap();
    close3(
        r.force,
        DVec3::new(0.0, -10.0, -5.0),
        1e-9,
        "reaction force",
    );
    close3(
        r.torque,
        DVec3::new(-13.0, 0.0, -14.0),
        1e-9,
        "reaction torque",
    );
}

/// Free blocks (no gravity) under constant loads at their centres: p = p₀ + F t²/(2m) and
/// a rotation about a principal axis θ = T t²/(2 I): GFORCE with RM turned 90° about z
/// (FX = 2 → ground +y, TZ = 0.3) on one, VFORCE (FZ = −1) and VTORQUE (TX = 0.2) in ground
/// axes on the other.
#[test]
fn constant_vector_loads_accelerate_free_blocks() {
    let (_, outs) = dynamics(
        "MARKER/3, PART = 1, REULER = 90D, 0D, 0D
PART/2, MASS = 2, CM = 20, IP = 0.5, 0.8, 1.5
MARKER/20, PART = 2
PART/3, MASS = 4, CM = 30, IP = 0.4, 0.8, 1.5, QG = 1, 0, 0
MARKER/30, PART = 3
GFORCE/1, I = 20, JFLOAT = 2, RM = 3, FX = 2\\FY = 0\\FZ = 0\\TX = 0\\TY = 0\\TZ = 0.3
VFORCE/1, I = 30, JFLOAT = 2, RM = 1, FX = 0\\FY = 0\\FZ = -1
VTORQUE/1, I = 30, JFLOAT = 2, RM = 1, TX = 0.2\\TY = 0\\TZ = 0",
        1.0,
        10,
        1e-9,
    );
    for o in &outs {
        let t = o.time;
        let (a, b) = (o.state.poses[0], o.state.poses[1]);
        // Uniform acceleration: HHT is exact up to its Newton tolerance.
        close3(
            a.p,
            DVec3::new(0.0, 0.5 * t * t, 0.0),
            1e-9,
            "GFORCE: F/m = 1 along y",
        );
        close3(
            ax_ay_az(a.r),
            DVec3::new(0.0, 0.0, 0.3 / 1.5 * t * t / 2.0),
            1e-9,
            "GFORCE: T/I = 0.2 about z",
        );
        close3(
            b.p,
            DVec3::new(1.0, 0.0, -0.25 * t * t / 2.0),
            1e-9,
            "VFORCE: F/m = −0.25 along z",
        );
        close3(
            ax_ay_az(b.r),
            DVec3::new(0.2 / 0.4 * t * t / 2.0, 0.0, 0.0),
            1e-9,
            "VTORQUE: T/I = 0.5 about x",
        );
    }
}

/// Vector loads with state-dependent components are springs and dampers to the
/// linearization: VFORCE FX = −100·DX, VTORQUE TZ = −5·AZ, GFORCE FY = −50·DY − 0.5·VY on one
/// block otherwise free: three oscillators (ω² = 100/2, 5/1.5, 50/2; the last with
/// ζ = 0.5/(2√(50·2))) and three zero-frequency modes.
#[test]
fn state_dependent_vector_loads_linearize_to_springs_and_dampers() {
    let l = linear(
        "PART/2, MASS = 2, CM = 20, IP = 0.5, 0.8, 1.5
MARKER/20, PART = 2
VFORCE/1, I = 20, JFLOAT = 2, RM = 1, FX = -100*DX(20, 1, 1)\\FY = 0\\FZ = 0
VTORQUE/1, I = 20, JFLOAT = 2, RM = 1, TX = 0\\TY = 0\\TZ = -5*AZ(20, 1)
GFORCE/1, I = 20, JFLOAT = 2, RM = 1, FX = 0\\FY = -50*DY(20, 1, 1) - 0.5*VY(20, 1, 1, 1)\\FZ = 0\\TX = 0\\TY = 0\\TZ = 0",
        false,
    );
    assert_modes(
        &l,
        &[
            (50f64.sqrt(), 0.0),
            ((5.0f64 / 1.5).sqrt(), 0.0),
            (25f64.sqrt(), 0.5 / (2.0 * 100f64.sqrt())),
        ],
    );
}

/// `e^(−σt) (cos ω_d t + σ/ω_d sin ω_d t)`: the free decay from rest of a unit displacement
/// of an oscillator with ω² = `w2` and ζ = `zeta`.
fn free_decay(w2: f64, zeta: f64, t: f64) -> f64 {
    let w = w2.sqrt();
    let (s, wd) = (zeta * w, w * (1.0 - zeta * zeta).sqrt());
    (-s * t).exp() * ((wd * t).cos() + s / wd * (wd * t).sin())
}

/// FIELD released at rest from its static equilibrium (no gravity: (dx, dy) = K⁻¹ (1, 0),
/// turned by 0.2/30 about z) displaced by a = 0.01 along the eigenvector v of the x–y block
/// for k₁ = 150 − √2900: only that mode moves, (x, y) = equilibrium + a v · free decay with
/// ω² = k₁/m and the proportional damping ζ = CRATIO·ω/2; the rotation stays put.
#[test]
fn field_free_decay_moves_one_mode() {
    let k1 = 150.0 - 2900f64.sqrt();
    let v = DVec3::new(20.0, k1 - 100.0, 0.0).normalize();
    let det = 100.0 * 200.0 - 20.0 * 20.0;
    let eq = DVec3::new(0.1 + 200.0 / det, -20.0 / det, 0.0);
    let c = 0.2f64 / 30.0;
    let start = eq + 0.01 * v;
    let block = format!(
        "PART/2, MASS = 2, CM = 20, IP = 0.5, 0.8, 1, QG = {}, {}, 0, REULER = {}D, 0D, 0D
MARKER/20, PART = 2
",
        start.x,
        start.y,
        c.to_degrees()
    );
    // ω ≈ 6.9 rad/s over 1 s: INTEGRATOR ERROR 1e-11 resolves the decay to ~1e-7 of the
    // amplitude (at 1e-9 the error is ~2e-6 of it; it falls with ERROR).
    let (_, outs) = dynamics(&format!("{block}{FIELD}"), 1.0, 20, 1e-11);
    let w = (k1 / 2.0).sqrt();
    for o in &outs {
        let t = o.time;
        let p = o.state.poses[0].p;
        let expected = eq + 0.01 * v * free_decay(k1 / 2.0, 0.004 * w / 2.0, t);
        // 1e-6 of the 0.01 amplitude.
        close3(p, expected, 1e-8, &format!("t = {t}"));
        close3(
            ax_ay_az(o.state.poses[0].r),
            DVec3::new(0.0, 0.0, c),
            1e-12,
            "rotation",
        );
    }
}

/// BEAM: the tip mass released at rest from an axial stretch of 1e-3 vibrates along the beam
/// only: x = L + 1e-3 · free decay with ω² = E A/(L m) = 1000 and ζ = CRATIO·ω/2.
#[test]
fn beam_axial_free_decay() {
    // ω ≈ 31.6 rad/s over 2.5 periods: the integrator's phase error is the largest
    // difference, 1.8e-7, 4.2e-8, 9.2e-9 of the 1e-3 stretch at ERROR 1e-10, 1e-11, 1e-12
    // (converging to the closed form); at 1e-12 it is held to 2e-8.
    let (_, outs) = dynamics(
        &cantilever("").replace("QG = 2, 0, 0", "QG = 2.001, 0, 0"),
        0.5,
        25,
        1e-12,
    );
    let w2: f64 = 2e5 * 0.01 / 2.0;
    let zeta = 0.001 * w2.sqrt() / 2.0;
    for o in &outs {
        let t = o.time;
        let p = o.state.poses[0].p;
        close3(
            p,
            DVec3::new(2.0 + 1e-3 * free_decay(w2, zeta, t), 0.0, 0.0),
            2e-8,
            &format!("t = {t}"),
        );
        close3(ax_ay_az(o.state.poses[0].r), DVec3::ZERO, 1e-12, "rotation");
    }
}
