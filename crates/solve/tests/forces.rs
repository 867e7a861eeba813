//! Force elements: hand-computed loads, exact Jacobians against central finite differences
//! (the oracle), action–reaction balance, data elements through expressions, diagnostics.

use glam::{DMat3, DVec3};
use linkage_expr::{evaluate_with_gradient, parse, Env, SplineData, SplineMethod};
use linkage_model::Model;
use linkage_solve::physics::applied::{AppliedForces, LawError, Regime};
use linkage_solve::physics::forces::data::DataElements;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::physics::measures::{MarkerFrames, StateEnv};
use linkage_solve::state::State;
use std::sync::Arc;

type Twist = Vec<(DVec3, DVec3)>;

/// Ground, and two parts in generic (non-symmetric) poses with markers in generic frames.
const BASE: &str = "\
linkage force tests
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1, QP = 0.1, -0.2, 0.3, REULER = 10D, 20D, 30D
MARKER/2, PART = 1
PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = 1, 0.5, -0.3, REULER = 15D, 25D, 35D
MARKER/20, PART = 2
MARKER/21, PART = 2, QP = 0.3, 0.1, -0.2, REULER = 40D, 50D, 60D
MARKER/22, PART = 2, FLOATING
PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, QG = -0.4, 1.2, 0.8, REULER = -20D, 35D, 10D
MARKER/30, PART = 3
MARKER/31, PART = 3, QP = -0.2, 0.25, 0.15, REULER = 5D, 60D, -30D
MARKER/32, PART = 3, FLOATING
";

/// Line of the first statement appended to [`BASE`].
const FIRST_EXTRA_LINE: u32 = 14;

fn model(extra: &str) -> Model {
    let text = format!("{BASE}{extra}\nEND\n");
    let ds = linkage_adm::parse_dataset(Arc::from("forces.adm"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

fn force_set(m: &Model) -> ForceSet {
    ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"))
}

/// Errors of `ForceSet::new` as `(line, col, message)`.
fn force_errors(extra: &str) -> Vec<(u32, u32, String)> {
    match ForceSet::new(&model(extra)) {
        Ok(_) => panic!("expected errors for {extra}"),
        Err(d) => {
            d.0.into_iter()
                .map(|d| {
                    let s = d.span.unwrap_or_default();
                    (s.line, s.col, d.message)
                })
                .collect()
        }
    }
}

/// Velocities with every component non-zero.
fn velocities() -> Twist {
    vec![
        (DVec3::new(0.3, -0.2, 0.5), DVec3::new(0.7, 0.4, -0.6)),
        (DVec3::new(-0.4, 0.6, 0.1), DVec3::new(-0.3, 0.9, 0.5)),
    ]
}

fn state(m: &Model) -> State {
    let mut s = State::input(m);
    s.time = 0.25;
    s
}

fn q(f: &ForceSet, s: &State, v: &Twist) -> Vec<f64> {
    let mut out = vec![0.0; 6 * s.poses.len()];
    f.add_forces(Regime::Dynamic, s, v, &mut out)
        .unwrap_or_else(|e| panic!("{e}"));
    out
}

fn dense(n: usize, triplets: &[(usize, usize, f64)]) -> Vec<Vec<f64>> {
    let mut m = vec![vec![0.0; n]; n];
    for &(r, c, x) in triplets {
        m[r][c] += x;
    }
    m
}

/// `(∂Q/∂q, ∂Q/∂v)` by central differences.
fn finite_differences(f: &ForceSet, s: &State, v: &Twist) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = 6 * s.poses.len();
    let h = 1e-6;
    let mut dq = vec![vec![0.0; n]; n];
    let mut dv = vec![vec![0.0; n]; n];
    for col in 0..n {
        let (k, c) = (col / 6, col % 6);
        let mut e = [0.0; 6];
        e[c] = h;
        let (dx, dth) = (DVec3::new(e[0], e[1], e[2]), DVec3::new(e[3], e[4], e[5]));
        let (mut sp, mut sm) = (s.clone(), s.clone());
        sp.increment(k, dx, dth);
        sm.increment(k, -dx, -dth);
        let (qp, qm) = (q(f, &sp, v), q(f, &sm, v));
        let (mut vp, mut vm) = (v.clone(), v.clone());
        vp[k].0 += dx;
        vp[k].1 += dth;
        vm[k].0 -= dx;
        vm[k].1 -= dth;
        let (qvp, qvm) = (q(f, s, &vp), q(f, s, &vm));
        for row in 0..n {
            dq[row][col] = (qp[row] - qm[row]) / (2.0 * h);
            dv[row][col] = (qvp[row] - qvm[row]) / (2.0 * h);
        }
    }
    (dq, dv)
}

fn assert_close(what: &str, analytic: &[Vec<f64>], numeric: &[Vec<f64>]) {
    let scale = numeric.iter().flatten().fold(1.0f64, |a, x| a.max(x.abs()));
    for (r, (ra, rn)) in analytic.iter().zip(numeric).enumerate() {
        for (c, (a, x)) in ra.iter().zip(rn).enumerate() {
            assert!(
                (a - x).abs() <= 1e-7 * scale,
                "{what}: entry ({r}, {c}): analytic {a} vs finite differences {x} (scale {scale})"
            );
        }
    }
}

/// Every element kind once, connecting parts 2 and 3 (none touches ground).
const ELEMENTS: &[(&str, &str)] = &[
    (
        "sforce translational",
        "SFORCE/1, I = 21, J = 31, TRANSLATIONAL, FUNCTION = 10*DM(21,31) + 3*VR(21,31) - 2*AZ(21,31) + TIME",
    ),
    (
        "sforce rotational",
        "SFORCE/2, I = 21, J = 31, ROTATIONAL, FUNCTION = -5*AZ(21,31) - 0.5*WZ(21,31,31) + DX(21,30,1)",
    ),
    (
        "springdamper translational",
        "SPRINGDAMPER/1, I = 21, J = 31, TRANSLATIONAL, K = 100, C = 3, LENGTH = 0.5, FORCE = 2",
    ),
    (
        "springdamper rotational",
        "SPRINGDAMPER/2, I = 21, J = 31, ROTATIONAL, KT = 30, CT = 2, ANGLE = 10D, TORQUE = 1",
    ),
    (
        "bushing",
        "BUSHING/1, I = 21, J = 31, K = 100, 200, 300, C = 1, 2, 3, KT = 40, 50, 60, CT = 0.4, 0.5, 0.6, FORCE = 1, -2, 3, TORQUE = -0.1, 0.2, 0.3",
    ),
    (
        "field",
        "FIELD/1, I = 21, J = 31\n, KMATRIX = 100, 2, 3, 4, 5, 6, 7, 200, 9, 10, 11, 12, 13, 14, 300, 16, 17, 18\n, 19, 20, 21, 40, 23, 24, 25, 26, 27, 28, 50, 30, 31, 32, 33, 34, 35, 60\n, CRATIO = 0.02, LENGTH = 0.1, 0.2, 0.3, 0.01, 0.02, 0.03, FORCE = 1, 2, 3, 0.1, 0.2, 0.3",
    ),
    (
        "beam",
        "BEAM/1, I = 21, J = 31, LENGTH = 0.8, IXX = 2E-6, IYY = 1E-6, IZZ = 1.5E-6, AREA = 1E-3, ASY = 1.2, ASZ = 1.1, EMODULUS = 2E8, GMODULUS = 8E7, CRATIO = 0.01",
    ),
    (
        "beam string",
        "BEAM/1, I = 21, J = 31, LENGTH = 0.8, IXX = 2E-6, IYY = 1E-6, IZZ = 1.5E-6, AREA = 1E-3, ASY = 1.2, ASZ = 1.1, EMODULUS = 2E6, GMODULUS = 8E5, CRATIO = 1, FORMULATION = STRING",
    ),
    (
        "beam nonlinear",
        "BEAM/1, I = 21, J = 31, LENGTH = 0.8, IXX = 2E-6, IYY = 1E-6, IZZ = 1.5E-6, AREA = 1E-3, EMODULUS = 2E8, GMODULUS = 8E7, CRATIO = 0.01, FORMULATION = NONLINEAR",
    ),
    (
        "beam nonlinear with cmatrix",
        "BEAM/1, I = 21, J = 31, LENGTH = 0.8, IXX = 2E-6, IYY = 1E-6, IZZ = 1.5E-6, AREA = 1E-3, EMODULUS = 2E4, GMODULUS = 8E3, FORMULATION = NONLINEAR\n, CMATRIX = 1, 0.2, 0.3, 0.4, 0.5, 0.6, 2, 0.9, 1, 1.1, 1.2, 3, 1.6, 1.7, 1.8, 4, 2.3, 2.4, 5, 3, 6",
    ),
    (
        "vforce",
        "VFORCE/1, I = 21, JFLOAT = 32, RM = 1, FX = 10*DX(21,31)\\FY = VY(21,31,1,31)\\FZ = 3*WZ(21,31,31) + 1",
    ),
    (
        "vtorque",
        "VTORQUE/1, I = 21, JFLOAT = 32, RM = 31, TX = AX(21,31)\\TY = 2\\TZ = VM(21,31)",
    ),
    (
        "gforce",
        "GFORCE/1, I = 31, JFLOAT = 22, RM = 21, FX = DY(31,21,21)\\FY = -VX(31,21,21,21)\\FZ = 5\\TX = WX(31,21,1)\\TY = PSI(31,21)\\TZ = -3*DM(31,21)",
    ),
];

/// Elements with one side on ground (no action–reaction balance among the parts).
const GROUND_ELEMENTS: &[(&str, &str)] = &[
    (
        "springdamper to ground",
        "SPRINGDAMPER/1, I = 21, J = 1, K = 100, C = 3, LENGTH = 0.5",
    ),
    (
        "bushing with I on ground",
        "BUSHING/1, I = 1, J = 31, K = 100, 200, 300, C = 1, 2, 3, KT = 40, 50, 60, CT = 0.4, 0.5, 0.6",
    ),
    (
        "field with CMATRIX to ground",
        "FIELD/1, I = 21, J = 1\n, KMATRIX = 100, 2, 3, 4, 5, 6, 7, 200, 9, 10, 11, 12, 13, 14, 300, 16, 17, 18\n, 19, 20, 21, 40, 23, 24, 25, 26, 27, 28, 50, 30, 31, 32, 33, 34, 35, 60\n, CMATRIX = 1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 2, 0.9, 1, 1.1, 1.2, 1.3, 1.4, 3, 1.6, 1.7, 1.8\n, 1.9, 2, 2.1, 4, 2.3, 2.4, 2.5, 2.6, 2.7, 2.8, 5, 3, 3.1, 3.2, 3.3, 3.4, 3.5, 6",
    ),
    (
        "vforce reacting on ground",
        "VFORCE/1, I = 21, JFLOAT = 2, RM = 31, FX = VX(21)\\FY = DY(21, 30)\\FZ = 2",
    ),
    (
        "sforce actiononly rotational",
        "SFORCE/1, I = 31, J = 21, ROTATIONAL, ACTIONONLY, FUNCTION = WX(31, 21, 21) + AY(31, 21)",
    ),
];

#[test]
fn every_element_jacobian_matches_finite_differences() {
    for (name, text) in ELEMENTS.iter().chain(GROUND_ELEMENTS) {
        let m = model(text);
        let f = force_set(&m);
        let (s, v) = (state(&m), velocities());
        let n = 6 * m.parts.len();
        let (mut tq, mut tv) = (Vec::new(), Vec::new());
        f.add_jacobians(Regime::Dynamic, &s, &v, &mut tq, Some(&mut tv))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (nq, nv) = finite_differences(&f, &s, &v);
        assert_close(&format!("{name} ∂Q/∂q"), &dense(n, &tq), &nq);
        assert_close(&format!("{name} ∂Q/∂v"), &dense(n, &tv), &nv);
        assert!(
            nq.iter().flatten().any(|x| x.abs() > 1e-3),
            "{name}: ∂Q/∂q should not vanish at a generic configuration"
        );
        // Without dv only dq is produced.
        let mut only = Vec::new();
        f.add_jacobians(Regime::Dynamic, &s, &v, &mut only, None)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(dense(n, &only), dense(n, &tq), "{name}");
    }
}

#[test]
fn action_reaction_elements_have_zero_net_force_and_moment() {
    for (name, text) in ELEMENTS {
        let m = model(text);
        let f = force_set(&m);
        let s = state(&m);
        let out = q(&f, &s, &velocities());
        let (mut force, mut moment) = (DVec3::ZERO, DVec3::ZERO);
        let mut largest = 0.0f64;
        for (k, pose) in s.poses.iter().enumerate() {
            let fk = DVec3::new(out[6 * k], out[6 * k + 1], out[6 * k + 2]);
            let tk = DVec3::new(out[6 * k + 3], out[6 * k + 4], out[6 * k + 5]);
            force += fk;
            // Moment about the ground origin of the force at the CM plus the torque.
            moment += tk + pose.p.cross(fk);
            largest = largest.max(fk.length()).max(tk.length());
        }
        assert!(largest > 1e-3, "{name}: no load at all");
        assert!(
            force.length() < 1e-10 * largest,
            "{name}: net force {force}"
        );
        assert!(
            moment.length() < 1e-10 * largest,
            "{name}: net moment {moment}"
        );
    }
}

#[test]
fn action_only_sforce_loads_i_only_along_z_j() {
    let m = model("SFORCE/1, I = 21, J = 31, ACTIONONLY, FUNCTION = 4*DX(21,31,31) + VX(21,31,31,31)\nSFORCE/2, I = 21, J = 31, ROTATIONAL, ACTIONONLY, FUNCTION = 2.5");
    let f = force_set(&m);
    let (s, v) = (state(&m), velocities());
    let out = q(&f, &s, &v);
    assert!(out[6..].iter().all(|x| *x == 0.0), "J's part is not loaded");
    let (p21, r21) = frame(&m, &s, 21);
    let (p31, r31) = frame(&m, &s, 31);
    let zj = r31.z_axis;
    // DX(21,31,31) and VX(21,31,31,31) by hand.
    let dx = (p21 - p31).dot(r31.x_axis);
    let (v2, w2) = v[0];
    let (v3, w3) = v[1];
    let vel = |vc: DVec3, w: DVec3, c: DVec3, p: DVec3| vc + w.cross(p - c);
    let rel = vel(v2, w2, s.poses[0].p, p21) - vel(v3, w3, s.poses[1].p, p31) - w3.cross(p21 - p31);
    let f1 = 4.0 * dx + rel.dot(r31.x_axis);
    let force = zj * f1;
    let torque = (p21 - s.poses[0].p).cross(force) + zj * 2.5;
    let _ = r21;
    assert_vec(&out[0..3], force, 1e-12);
    assert_vec(&out[3..6], torque, 1e-12);
    let (mut tq, mut tv) = (Vec::new(), Vec::new());
    f.add_jacobians(Regime::Dynamic, &s, &v, &mut tq, Some(&mut tv))
        .unwrap();
    let (nq, nv) = finite_differences(&f, &s, &v);
    assert_close("actiononly ∂Q/∂q", &dense(12, &tq), &nq);
    assert_close("actiononly ∂Q/∂v", &dense(12, &tv), &nv);
}

/// Marker `id`'s origin and axes in ground at state `s`.
fn frame(m: &Model, s: &State, id: u64) -> (DVec3, DMat3) {
    let mk = m.markers.iter().find(|x| x.id == id).unwrap();
    match mk.body {
        linkage_model::Body::Ground => (mk.p_bm, mk.r_bm),
        linkage_model::Body::Part(k) => (
            s.poses[k].p + s.poses[k].r * mk.p_bm,
            s.poses[k].r * mk.r_bm,
        ),
    }
}

fn assert_vec(got: &[f64], want: DVec3, tol: f64) {
    let g = DVec3::new(got[0], got[1], got[2]);
    assert!(
        (g - want).length() <= tol * (1.0 + want.length()),
        "got {g}, want {want}"
    );
}

/// One part whose CM sits at `qg` with body-fixed 3-1-3 angles `reuler` (degrees), marker 20
/// at its CM (same axes) and marker 21 at `qp21` in its frame; `extra` appended.
fn single_part(qg: [f64; 3], reuler: [f64; 3], qp21: [f64; 3], extra: &str) -> Model {
    let text = format!(
        "single part\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, REULER = 30D, 0, 0\nPART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = {}, {}, {}, REULER = {}D, {}D, {}D\nMARKER/20, PART = 2\nMARKER/21, PART = 2, QP = {}, {}, {}\n{extra}\nEND\n",
        qg[0], qg[1], qg[2], reuler[0], reuler[1], reuler[2], qp21[0], qp21[1], qp21[2]
    );
    let ds = linkage_adm::parse_dataset(Arc::from("single.adm"), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

#[test]
fn spring_stretched_by_delta_pulls_back_with_k_delta_plus_damping() {
    // Spring from the ground origin to a point 1.2 away along u = (0.6, 0.8, 0): stretched by
    // δ = 0.2 beyond LENGTH = 1, separating at VR = v·u = 0.6 (v = (1, 0, 0)).
    let u = DVec3::new(0.6, 0.8, 0.0);
    let p = u * 1.2;
    let m = single_part(
        [p.x, p.y, p.z - 0.5],
        [0.0; 3],
        [0.0, 0.0, 0.5],
        "SPRINGDAMPER/1, I = 21, J = 1, K = 100, C = 5, LENGTH = 1, FORCE = 1",
    );
    let f = force_set(&m);
    let s = State::input(&m);
    let v = vec![(DVec3::X, DVec3::ZERO)];
    let out = q(&f, &s, &v);
    let magnitude = -5.0 * 0.6 - 100.0 * 0.2 + 1.0; // −22: attraction
    let force = u * magnitude;
    assert_vec(&out[0..3], force, 1e-12);
    // Applied 0.5 above the CM.
    assert_vec(&out[3..6], DVec3::new(0.0, 0.0, 0.5).cross(force), 1e-12);
}

#[test]
fn rotational_spring_twisted_by_phi_resists_with_kt_phi() {
    let phi = 0.3f64;
    let m = single_part(
        [0.0, 0.0, 0.0],
        [phi.to_degrees(), 0.0, 0.0],
        [0.0; 3],
        "SPRINGDAMPER/1, I = 20, J = 1, ROTATIONAL, KT = 50, CT = 2, ANGLE = 5D, TORQUE = 0.5",
    );
    let f = force_set(&m);
    let s = State::input(&m);
    let v = vec![(DVec3::ZERO, DVec3::new(0.1, 0.2, 0.7))];
    let out = q(&f, &s, &v);
    let t = -50.0 * (phi - 5f64.to_radians()) - 2.0 * 0.7 + 0.5;
    assert_vec(&out[0..3], DVec3::ZERO, 1e-12);
    assert_vec(&out[3..6], DVec3::Z * t, 1e-12);
}

#[test]
fn rotational_spring_twist_is_measured_the_short_way_round() {
    // AZ = 175°, ANGLE = −175°: the twist is −10°, not 350°.
    let m = single_part(
        [0.0; 3],
        [175.0, 0.0, 0.0],
        [0.0; 3],
        "SPRINGDAMPER/1, I = 20, J = 1, ROTATIONAL, KT = 10, ANGLE = -175D",
    );
    let out = q(
        &force_set(&m),
        &State::input(&m),
        &vec![(DVec3::ZERO, DVec3::ZERO)],
    );
    assert!(
        (out[5] - -10.0 * (-10f64).to_radians()).abs() < 1e-12,
        "{}",
        out[5]
    );
}

#[test]
fn bushing_deflected_along_and_about_one_axis() {
    // J = marker 2 on ground, axes rotated 30° about z. I = the part's CM marker with axes
    // rotated α about x_j and origin displaced δ along y_j.
    let (delta, alpha) = (0.01, 0.02f64);
    let yj = DMat3::from_rotation_z(30f64.to_radians()).y_axis;
    let p = yj * delta;
    let m = single_part(
        [p.x, p.y, p.z],
        [30.0, alpha.to_degrees(), 0.0],
        [0.0; 3],
        "BUSHING/1, I = 20, J = 2, K = 10, 20, 30, KT = 4, 5, 6, FORCE = 0, 0, 7",
    );
    let f = force_set(&m);
    let s = State::input(&m);
    let out = q(&f, &s, &vec![(DVec3::ZERO, DVec3::ZERO)]);
    let xj = DMat3::from_rotation_z(30f64.to_radians()).x_axis;
    assert_vec(&out[0..3], -yj * 20.0 * delta + DVec3::Z * 7.0, 1e-12);
    assert_vec(&out[3..6], -xj * 4.0 * alpha, 1e-12);
}

#[test]
fn beam_cantilever_tip_load_matches_timoshenko_deflection() {
    // A beam clamped at the ground frame, length L along x. A tip load P along y is balanced
    // by the beam force at y = P·L³/(3EI) + P·L·ASY/(G·A), c = P·L²/(2EI), and along z at
    // z = P·L³/(3EI_yy) + P·L·ASZ/(G·A), b = −P·L²/(2EI_yy).
    let (l, e, g, a): (f64, f64, f64, f64) = (2.0, 2.0e9, 8.0e7, 0.01);
    let (ixx, iyy, izz, asy, asz) = (3e-5, 2e-5, 1e-5, 1.2, 1.1);
    let p = 10.0;
    let beam = format!("BEAM/1, I = 20, J = 1, LENGTH = {l}, IXX = {ixx}, IYY = {iyy}, IZZ = {izz}, AREA = {a}, ASY = {asy}, ASZ = {asz}, EMODULUS = {e}, GMODULUS = {g}");
    let y = p * l.powi(3) / (3.0 * e * izz) + p * l * asy / (g * a);
    let c = p * l * l / (2.0 * e * izz);
    let m = single_part([l, y, 0.0], [c.to_degrees(), 0.0, 0.0], [0.0; 3], &beam);
    let out = q(
        &force_set(&m),
        &State::input(&m),
        &vec![(DVec3::ZERO, DVec3::ZERO)],
    );
    assert_vec(&out[0..3], DVec3::new(0.0, -p, 0.0), 1e-9);
    assert_vec(&out[3..6], DVec3::ZERO, 1e-9);
    // Shear matters here: without it the deflection would be smaller.
    assert!(p * l * asy / (g * a) > 1e-3 * y);

    let z = p * l.powi(3) / (3.0 * e * iyy) + p * l * asz / (g * a);
    let b = -p * l * l / (2.0 * e * iyy);
    // Rotation b about y = Rz(90°)·Rx(b)·Rz(−90°).
    let m = single_part([l, 0.0, z], [90.0, b.to_degrees(), -90.0], [0.0; 3], &beam);
    let out = q(
        &force_set(&m),
        &State::input(&m),
        &vec![(DVec3::ZERO, DVec3::ZERO)],
    );
    assert_vec(&out[0..3], DVec3::new(0.0, 0.0, -p), 1e-9);
    assert_vec(&out[3..6], DVec3::ZERO, 1e-9);

    // Axial: stretched by s, the beam pulls back with E·A·s/L.
    let s_ax = 1e-4;
    let m = single_part([l + s_ax, 0.0, 0.0], [0.0; 3], [0.0; 3], &beam);
    let out = q(
        &force_set(&m),
        &State::input(&m),
        &vec![(DVec3::ZERO, DVec3::ZERO)],
    );
    assert_vec(&out[0..3], DVec3::new(-e * a * s_ax / l, 0.0, 0.0), 1e-9);
}

#[test]
fn field_uses_the_full_matrix_read_by_columns() {
    // Only K(1,2) (row x, column y; the 7th value) is non-zero: a y deflection gives an x force.
    let mut k = vec!["0"; 36];
    k[6] = "100";
    let m = single_part(
        [0.0, 0.02, 0.0],
        [0.0; 3],
        [0.0; 3],
        &format!(
            "FIELD/1, I = 20, J = 1, KMATRIX = {}, LENGTH = 0, 0.05, 0, 0, 0, 0",
            k.join(", ")
        ),
    );
    let out = q(
        &force_set(&m),
        &State::input(&m),
        &vec![(DVec3::ZERO, DVec3::ZERO)],
    );
    assert_vec(
        &out[0..3],
        DVec3::new(-100.0 * (0.02 - 0.05), 0.0, 0.0),
        1e-12,
    );
}

#[test]
fn vforce_components_along_rm_with_reaction_on_the_floating_marker_part() {
    let m = model("VFORCE/1, I = 21, JFLOAT = 32, RM = 1, FX = 1\\FY = 2\\FZ = 3\nVTORQUE/1, I = 21, JFLOAT = 32, RM = 1, TX = 0.5\\TY = 0\\TZ = 0");
    let f = force_set(&m);
    let s = state(&m);
    let out = q(&f, &s, &velocities());
    let (p21, _) = frame(&m, &s, 21);
    let (_, rm) = frame(&m, &s, 1);
    let force = rm * DVec3::new(1.0, 2.0, 3.0);
    let torque = rm.x_axis * 0.5;
    assert_vec(&out[0..3], force, 1e-12);
    assert_vec(
        &out[3..6],
        (p21 - s.poses[0].p).cross(force) + torque,
        1e-12,
    );
    assert_vec(&out[6..9], -force, 1e-12);
    assert_vec(
        &out[9..12],
        (p21 - s.poses[1].p).cross(-force) - torque,
        1e-12,
    );
}

#[test]
fn sforce_between_part_and_ground_repels_along_the_line() {
    let m = model("SFORCE/1, I = 21, J = 1, FUNCTION = 10 + 2*DM(21, 1)");
    let f = force_set(&m);
    let s = state(&m);
    let out = q(&f, &s, &velocities());
    let (p21, _) = frame(&m, &s, 21);
    let (p1, _) = frame(&m, &s, 1);
    let d = p21 - p1;
    let force = d.normalize() * (10.0 + 2.0 * d.length());
    assert_vec(&out[0..3], force, 1e-12);
    assert_vec(&out[3..6], (p21 - s.poses[0].p).cross(force), 1e-12);
    assert!(out[6..].iter().all(|x| *x == 0.0));
}

#[test]
fn varval_aryval_and_akispl_feed_a_force_expression() {
    let m = model("VARIABLE/1, FUNCTION = 2*DM(21,31) + VARVAL(2)\nVARIABLE/2, FUNCTION = VX(21,31)\nARRAY/5, IC, SIZE = 2, NUMBERS = 7, 11\nARRAY/6, U, SIZE = 2, VARIABLES = 1, 2\nSPLINE/3, X = 0, 1, 2, 3, 4, Y = 0, 1, 4, 9, 16\nSFORCE/1, I = 21, J = 31, FUNCTION = VARVAL(1) + ARYVAL(5, 2) + 3*ARYVAL(6, 2) + AKISPL(DM(21,31), 0, 3)");
    let f = force_set(&m);
    let (s, v) = (state(&m), velocities());
    let out = q(&f, &s, &v);
    let (p21, _) = frame(&m, &s, 21);
    let (p31, _) = frame(&m, &s, 31);
    let d = p21 - p31;
    let dm = d.length();
    let vel = |vc: DVec3, w: DVec3, c: DVec3, p: DVec3| vc + w.cross(p - c);
    let vx = (vel(v[0].0, v[0].1, s.poses[0].p, p21) - vel(v[1].0, v[1].1, s.poses[1].p, p31)).x;
    let spline = SplineData::new(
        vec![0.0, 1.0, 2.0, 3.0, 4.0],
        vec![0.0, 1.0, 4.0, 9.0, 16.0],
        false,
    )
    .unwrap();
    let akima = spline.evaluate(SplineMethod::Akima, dm)[0];
    let magnitude = 2.0 * dm + vx + 11.0 + 3.0 * vx + akima;
    assert_vec(&out[0..3], d.normalize() * magnitude, 1e-12);
    let (mut tq, mut tv) = (Vec::new(), Vec::new());
    f.add_jacobians(Regime::Dynamic, &s, &v, &mut tq, Some(&mut tv))
        .unwrap();
    let (nq, nv) = finite_differences(&f, &s, &v);
    assert_close("data ∂Q/∂q", &dense(12, &tq), &nq);
    assert_close("data ∂Q/∂v", &dense(12, &tv), &nv);
}

#[test]
fn varval_cycle_is_an_evaluation_error_naming_the_cycle() {
    let m = model("VARIABLE/1, FUNCTION = 1 + VARVAL(2)\nVARIABLE/2, FUNCTION = VARVAL(1)\nSFORCE/1, I = 21, J = 31, FUNCTION = VARVAL(1)");
    let f = force_set(&m);
    let s = state(&m);
    let mut out = vec![0.0; 12];
    let err = f
        .add_forces(Regime::Dynamic, &s, &velocities(), &mut out)
        .unwrap_err();
    assert_eq!(err.element, "SFORCE_1 (SFORCE/1, line 16)");
    assert_eq!(err.time, s.time);
    let LawError::Expression { argument, cause } = &err.cause else {
        panic!("an expression error: {err}");
    };
    assert_eq!(*argument, "FUNCTION");
    assert!(
        cause.contains("cycle") && cause.contains("1 → 2 → 1"),
        "{err}"
    );
}

#[test]
fn accelerations_and_element_forces_are_unavailable() {
    for (expr, name) in [("ACCX(21)", "ACCX"), ("JOINT(1, 0, 2, 0)", "JOINT")] {
        let m = model(&format!("SFORCE/1, I = 21, J = 31, FUNCTION = {expr}"));
        let f = force_set(&m);
        let mut out = vec![0.0; 12];
        let err = f
            .add_forces(Regime::Dynamic, &state(&m), &velocities(), &mut out)
            .unwrap_err();
        let cause = err.cause.to_string();
        assert!(cause.contains(name) && cause.contains("not"), "{err}");
    }
}

#[test]
fn syntax_error_points_inside_the_expression() {
    // "FUNCTION = 3 * / 2": the parser stops at '/', 4 bytes into the expression.
    let line = "SFORCE/1, I = 21, J = 31, FUNCTION = 3 * / 2";
    let col = line.find("3 *").unwrap() as u32 + 1 + 4;
    let e = force_errors(line);
    assert_eq!((e[0].0, e[0].1), (FIRST_EXTRA_LINE, col), "{e:?}");
    assert!(
        e[0].2.starts_with("SFORCE_1: syntax error in FUNCTION"),
        "{}",
        e[0].2
    );
    // Across a continuation line: the position is on the second line.
    let e = force_errors(
        "VFORCE/1, I = 21, JFLOAT = 32, RM = 1, FX = 1\\FY = 2*DM(21,31)\n, + 4 * * 2\\FZ = 0",
    );
    assert_eq!((e[0].0, e[0].1), (FIRST_EXTRA_LINE + 1, 9), "{e:?}");
    assert!(e[0].2.contains("syntax error in FY"), "{}", e[0].2);
    // In a VARIABLE a force uses.
    let e = force_errors(
        "VARIABLE/4, FUNCTION = 1 + * 2\nSFORCE/1, I = 21, J = 31, FUNCTION = VARVAL(4)",
    );
    assert_eq!(
        e,
        [(
            FIRST_EXTRA_LINE,
            28,
            "VARIABLE_4: syntax error in FUNCTION: expected an operand (number, name, '(' or '['), \
             found '*' (used by SFORCE_1 (SFORCE/1, line 15))"
                .to_string()
        )]
    );
}

#[test]
fn user_subroutines_are_refused_naming_element_and_line() {
    let e = force_errors("SFORCE/7, I = 21, J = 31, FUNCTION = USER(1, 2)\nGFORCE/1, I = 21, JFLOAT = 32, RM = 1, FUNCTION = USER(5, 6)\nFIELD/1, I = 21, J = 31, FUNCTION = USER(1)\nVARIABLE/3, FUNCTION = USER(9)\nSFORCE/8, I = 21, J = 31, FUNCTION = 2*VARVAL(3)");
    let msg = |k: usize| e[k].2.as_str();
    assert_eq!(e.len(), 4, "{e:?}");
    assert_eq!((e[0].0, e[0].1), (FIRST_EXTRA_LINE, 38));
    assert!(
        msg(0).starts_with("SFORCE_7 (SFORCE/7, line 14): FUNCTION calls a USER subroutine"),
        "{}",
        msg(0)
    );
    assert!(
        msg(1).starts_with("GFORCE_1 (GFORCE/1, line 15)"),
        "{}",
        msg(1)
    );
    assert!(
        msg(2).starts_with("FIELD_1 (FIELD/1, line 16)"),
        "{}",
        msg(2)
    );
    // The USER VARIABLE is refused where a force uses it.
    assert_eq!(e[3].0, FIRST_EXTRA_LINE + 4);
    assert!(
        msg(3).contains("VARIABLE/3") && msg(3).contains("USER"),
        "{}",
        msg(3)
    );
    // An unused USER VARIABLE is no obstacle.
    assert!(ForceSet::new(&model("VARIABLE/3, FUNCTION = USER(9)")).is_ok());
}

#[test]
fn references_to_missing_or_unusable_data_are_errors() {
    // A DIFF that does not exist is named when the forces are built.
    let e = force_errors("SFORCE/1, I = 21, J = 31, FUNCTION = DIF(1)");
    assert!(e[0].2.contains("DIFF/1 does not exist"), "{e:?}");
    let e = force_errors("SFORCE/1, I = 21, J = 31, FUNCTION = VARVAL(9)\nARRAY/2, X, SIZE = 2\nSFORCE/2, I = 21, J = 31, FUNCTION = ARYVAL(2, 1)\nSPLINE/4, X = 0, 1, Y = 0, 1, 2, Y = 1, 3, 4\nSFORCE/3, I = 21, J = 31, FUNCTION = CUBSPL(TIME, 0, 4)\nSFORCE/4, I = 21, J = 31, FUNCTION = AKISPL(TIME, 0, 8)");
    // The 2-D spline (SPLINE/4) is interpolated: no error for SFORCE/3.
    assert_eq!(e.len(), 3, "{e:?}");
    assert!(e[0].2.contains("VARIABLE/9 does not exist"), "{}", e[0].2);
    assert!(
        e[1].2
            .contains("ARRAY/2 is an X or Y array that no LSE or TFSISO uses"),
        "{}",
        e[1].2
    );
    assert!(e[2].2.contains("SPLINE/8 does not exist"), "{}", e[2].2);
}

#[test]
fn coincident_points_with_a_non_zero_force_are_an_error() {
    let m = model("MARKER/23, PART = 2, QP = 0.3, 0.1, -0.2\nSFORCE/1, I = 21, J = 23, FUNCTION = 5\nSFORCE/2, I = 21, J = 23, FUNCTION = 0");
    let f = force_set(&m);
    let mut out = vec![0.0; 12];
    let err = f
        .add_forces(Regime::Dynamic, &state(&m), &velocities(), &mut out)
        .unwrap_err();
    assert!(err.element.starts_with("SFORCE_1"), "{err}");
    assert_eq!(err.cause, LawError::CoincidentPoints { force: 5.0 });
    assert!(err.to_string().contains("coincide"), "{err}");
}

#[test]
fn velocity_measure_gradients_match_finite_differences() {
    let m = model("");
    let frames = MarkerFrames::new(&m);
    let data = DataElements::default();
    let (s, v) = (state(&m), velocities());
    let n = 6 * m.parts.len();
    let exprs = [
        "VX(21, 31, 1, 30)",
        "VY(21, 31, 31, 31)",
        "VZ(21)",
        "VM(21, 31, 30)",
        "VR(21, 31)",
        "WX(21, 31, 1)",
        "WY(21, 31, 31)",
        "WZ(21, 31)",
        "WM(21, 31)",
        "VX(21, 31, 31, 31)*DX(21, 31, 31) + TIME",
    ];
    for text in exprs {
        let e = parse(text).unwrap();
        let eval = |s: &State, v: &Twist| {
            linkage_expr::evaluate(&e, &StateEnv::new(&frames, s, v, &data)).unwrap()
        };
        let d = evaluate_with_gradient(&e, &StateEnv::new(&frames, &s, &v, &data)).unwrap();
        assert!((d.value() - eval(&s, &v)).abs() < 1e-14, "{text}");
        let h = 1e-6;
        for col in 0..n {
            let (k, c) = (col / 6, col % 6);
            let mut e6 = [0.0; 6];
            e6[c] = h;
            let (dx, dth) = (
                DVec3::new(e6[0], e6[1], e6[2]),
                DVec3::new(e6[3], e6[4], e6[5]),
            );
            let (mut sp, mut sm) = (s.clone(), s.clone());
            sp.increment(k, dx, dth);
            sm.increment(k, -dx, -dth);
            let fd_q = (eval(&sp, &v) - eval(&sm, &v)) / (2.0 * h);
            let (mut vp, mut vm) = (v.clone(), v.clone());
            vp[k].0 += dx;
            vp[k].1 += dth;
            vm[k].0 -= dx;
            vm[k].1 -= dth;
            let fd_v = (eval(&s, &vp) - eval(&s, &vm)) / (2.0 * h);
            let (aq, av) = (d.derivative(col as u32), d.derivative((n + col) as u32));
            assert!(
                (aq - fd_q).abs() < 1e-7,
                "{text}: ∂/∂q[{col}] {aq} vs {fd_q}"
            );
            assert!(
                (av - fd_v).abs() < 1e-7,
                "{text}: ∂/∂v[{col}] {av} vs {fd_v}"
            );
        }
    }
}

#[test]
fn velocity_measures_by_hand() {
    let m = model("");
    let frames = MarkerFrames::new(&m);
    let data = DataElements::default();
    let (s, v) = (state(&m), velocities());
    let env = StateEnv::new(&frames, &s, &v, &data).with_mode(5);
    let val = |t: &str| linkage_expr::evaluate(&parse(t).unwrap(), &env).unwrap();
    let (p21, _) = frame(&m, &s, 21);
    let (p31, r31) = frame(&m, &s, 31);
    let vel = |k: usize, p: DVec3| v[k].0 + v[k].1.cross(p - s.poses[k].p);
    let rel = vel(0, p21) - vel(1, p31);
    let d = p21 - p31;
    // VX(21,31,31,31): seen from marker 31's frame, along its x axis.
    let seen = rel - v[1].1.cross(d);
    assert!((val("VX(21,31,31,31)") - seen.dot(r31.x_axis)).abs() < 1e-13);
    assert!((val("VM(21,31)") - rel.length()).abs() < 1e-13);
    assert!((val("VR(21,31)") - rel.dot(d) / d.length()).abs() < 1e-13);
    assert!(
        (val("VR(21,31,31)") - val("VR(21,31)")).abs() < 1e-13,
        "VR does not depend on l"
    );
    assert!((val("WZ(21,31,31)") - (v[0].1 - v[1].1).dot(r31.z_axis)).abs() < 1e-13);
    assert!((val("WM(21)") - v[0].1.length()).abs() < 1e-13);
    assert_eq!(val("MODE"), 5.0);
    assert_eq!(env.time(), 0.25);
}

#[test]
fn a_variable_that_does_not_parse_matters_only_when_a_force_uses_it() {
    // INCANG is not a function linkage knows: harmless in an output VARIABLE…
    let line = "VARIABLE/4, FUNCTION = INCANG(21, 31, 1)";
    let f = force_set(&model(&format!(
        "{line}\nSFORCE/1, I = 21, J = 31, FUNCTION = 1"
    )));
    assert_eq!(f.warnings().len(), 1);
    let w = &f.warnings()[0];
    assert_eq!(
        w.span.map(|s| (s.line, s.col)),
        Some((FIRST_EXTRA_LINE, 24))
    );
    assert!(
        w.message.contains("no force element uses it"),
        "{}",
        w.message
    );
    // …an error located in the VARIABLE when a force uses it (here through an ARRAY).
    let e = force_errors(&format!(
        "{line}\nARRAY/1, U, VARIABLES = 4\nSFORCE/1, I = 21, J = 31, FUNCTION = ARYVAL(1, 1)"
    ));
    assert_eq!((e[0].0, e[0].1), (FIRST_EXTRA_LINE, 24), "{e:?}");
    assert!(
        e[0].2.starts_with("VARIABLE_4: syntax error in FUNCTION")
            && e[0].2.ends_with("(used by SFORCE_1 (SFORCE/1, line 16))"),
        "{}",
        e[0].2
    );
}
