//! BEAM `FORMULATION = STRING` and `NONLINEAR` (issue 16 item 7) against closed forms:
//! the beam-column tip stiffness of a cantilever under axial tension and compression
//! (Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed., 1961, §1.11: tip deflection
//! `δ = F/P·(L − tanh(kL)/k)` in tension, `F/P·(tan(kL)/k − L)` in compression,
//! `k = √(|P|/EI)`), the chord shortening `F²L⁵/(15(EI)²)` of a tip-loaded cantilever
//! (½∫w′² of its cubic deflection), the objectivity of the NONLINEAR beam under a large
//! rigid rotation, a chain of NONLINEAR beams bent by an end moment into the circle of
//! radius `EI/M`, and small deflections where NONLINEAR equals LINEAR.
//!
//! Beam: steel, L = 1 m, 10 mm square section: E = 2.1e11 Pa, A = 1e-4 m², I = b⁴/12
//! (EI = 175 N·m²), G = 8e10 Pa, J = 0.1406·b⁴.

use glam::{DMat3, DVec3};
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::{AppliedForces, Regime};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::statics::Equilibrium;
use linkage_solve::state::State;
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::PI;
use std::sync::Arc;

const E: f64 = 2.1e11;
const G: f64 = 8.0e10;
const B: f64 = 0.01;
const L: f64 = 1.0;

fn ei() -> f64 {
    E * B.powi(4) / 12.0
}

/// The section of every beam here; `formulation` appended.
fn section(length: f64, formulation: &str) -> String {
    let (a, i, j) = (B * B, B.powi(4) / 12.0, 0.1406 * B.powi(4));
    format!(
        "LENGTH = {length}, IXX = {j}, IYY = {i}, IZZ = {i}, AREA = {a}, EMODULUS = {E}, GMODULUS = {G}, FORMULATION = {formulation}"
    )
}

fn load(text: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let ds =
        linkage_adm::parse_dataset(Arc::from("beam.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

fn equilibrium(text: &str) -> (Model, Equilibrium) {
    let (m, d, f) = load(text);
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.clone().unwrap_or_else(|e| panic!("{e}"));
    assert!(eq.converged, "{:?}", eq.worst);
    (m, eq)
}

/// A cantilever BEAM from the ground origin to part 2's CM at (L, 0, 0), loaded at the tip
/// by ground-fixed FX, FY.
fn cantilever(formulation: &str, fx: f64, fy: f64) -> String {
    format!(
        "cantilever\nUNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n\
         PART/2, MASS = 1, CM = 20, IP = 1E-3, 1E-3, 1E-3, QG = {L}, 0, 0\nMARKER/20, PART = 2\n\
         BEAM/1, I = 20, J = 1, {}\n\
         VFORCE/1, I = 20, JFLOAT = 12, RM = 1, FX = {fx}, FY = {fy}, FZ = 0\nEND\n",
        section(L, formulation)
    )
}

fn tip(formulation: &str, fx: f64, fy: f64) -> DVec3 {
    let (_, eq) = equilibrium(&cantilever(formulation, fx, fy));
    eq.state.poses[0].p
}

#[test]
fn tensioned_string_beam_is_laterally_stiffer_as_the_beam_column_formula_says() {
    // P·L²/EI = 1: the tension raises the tip stiffness from 3·EI/L³ by 40 %. The cubic
    // shape functions of the geometric stiffness are within 7.3e-4 of the exact
    // beam-column stiffness at this load (1e-3 asserted).
    let p = ei() / (L * L);
    let f = 0.1;
    let k = (p / ei()).sqrt();
    let exact = f / p * (L - (k * L).tanh() / k);
    let y = tip("STRING", p, f).y;
    assert!((y / exact - 1.0).abs() < 1e-3, "{y} vs {exact}");
    let linear = tip("LINEAR", p, f).y;
    let cantilever = f * L.powi(3) / (3.0 * ei());
    assert!((linear / cantilever - 1.0).abs() < 1e-9, "{linear}");
    assert!(y < 0.75 * linear, "tension stiffens: {y} vs {linear}");
}

#[test]
fn compressed_string_beam_is_laterally_softer_as_the_beam_column_formula_says() {
    // P·L²/EI = −0.5: within 3.5e-4 of the exact stiffness (1e-3 asserted).
    let p = 0.5 * ei() / (L * L);
    let f = 0.1;
    let k = (p / ei()).sqrt();
    let exact = f / p * ((k * L).tan() / k - L);
    let y = tip("STRING", -p, f).y;
    assert!((y / exact - 1.0).abs() < 1e-3, "{y} vs {exact}");
    assert!(
        y > 1.15 * f * L.powi(3) / (3.0 * ei()),
        "compression softens"
    );
}

#[test]
fn string_beam_bending_shortens_the_chord_by_half_the_integral_of_the_slope_squared() {
    // No axial load: the axis does not stretch, so the tip comes back by ½∫w′² =
    // F²L⁵/(15(EI)²) (exact: the tip-loaded cantilever's deflection is the cubic the
    // geometric stiffness assumes). LINEAR keeps the tip at x = L.
    let f = 5.0;
    let shortening = f * f * L.powi(5) / (15.0 * ei() * ei());
    let t = tip("STRING", 0.0, f);
    assert!(
        ((L - t.x) / shortening - 1.0).abs() < 1e-6,
        "{} vs {shortening}",
        L - t.x
    );
    let y = f * L.powi(3) / (3.0 * ei());
    assert!((t.y / y - 1.0).abs() < 1e-9, "{} vs {y}", t.y);
    assert!((tip("LINEAR", 0.0, f).x - L).abs() < 1e-12);
}

/// Two parts: part 3 (J's) at the origin and part 2 (I's) at `R·p_local`, both turned by
/// `R`, the I part additionally by `turn_i`.
fn two_parts(formulation: &str, r: DMat3, p_local: DVec3, turn_i: DMat3) -> Model {
    let euler = |m: DMat3| {
        let (a, b, c) = glam::DQuat::from_mat3(&m).to_euler(glam::EulerRot::ZXZ);
        format!(
            "{}D, {}D, {}D",
            a.to_degrees(),
            b.to_degrees(),
            c.to_degrees()
        )
    };
    let p = r * p_local;
    let text = format!(
        "two parts\nUNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\nPART/1, GROUND\n\
         PART/2, MASS = 1, CM = 20, IP = 1, 1, 1, QG = {}, {}, {}, REULER = {}\nMARKER/20, PART = 2\n\
         PART/3, MASS = 1, CM = 30, IP = 1, 1, 1, REULER = {}\nMARKER/30, PART = 3\n\
         BEAM/1, I = 20, J = 30, {}\nEND\n",
        p.x,
        p.y,
        p.z,
        euler(r * turn_i),
        euler(r),
        section(L, formulation)
    );
    load(&text).0
}

/// The generalised loads on parts 2 and 3 at the input pose, at rest.
fn loads(m: &Model) -> Vec<f64> {
    let f = ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"));
    let s = State::input(m);
    let mut out = vec![0.0; 12];
    f.add_forces(
        Regime::Dynamic,
        &s,
        &[(DVec3::ZERO, DVec3::ZERO); 2],
        &mut out,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    out
}

#[test]
fn nonlinear_beam_turned_rigidly_through_a_large_angle_carries_no_load() {
    // Both ends turned by 120° about a skew axis: no deformation, no load. The same beam
    // with its I end swung by ψ = 1 mrad about J's z (chord length kept, I's axes not
    // turned) carries exactly the corotational shear 12·EI·sin ψ/L² against the turned y
    // direction of the chord and the torque 6·EI·sin ψ/L about z (θ_a = θ_b = −sin ψ).
    let r = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 2.0 * PI / 3.0);
    let rest = loads(&two_parts(
        "NONLINEAR",
        r,
        DVec3::new(L, 0.0, 0.0),
        DMat3::IDENTITY,
    ));
    let shear = 12.0 * ei() / L.powi(2) * 1e-3;
    assert!(
        rest.iter().all(|x| x.abs() < 1e-9 * shear),
        "a rigid rotation loads the beam: {rest:?}"
    );
    let psi: f64 = 1e-3;
    let swung = loads(&two_parts(
        "NONLINEAR",
        r,
        L * DVec3::new(psi.cos(), psi.sin(), 0.0),
        DMat3::IDENTITY,
    ));
    let e2 = r * DVec3::new(-psi.sin(), psi.cos(), 0.0);
    let force = -e2 * 12.0 * ei() * psi.sin() / L.powi(2);
    let torque = r * DVec3::Z * 6.0 * ei() * psi.sin() / L;
    let on_i = DVec3::from_slice(&swung[0..3]);
    let about_i = DVec3::from_slice(&swung[3..6]);
    assert!(
        (on_i - force).length() < 1e-6 * force.length(),
        "{on_i:?} vs {force:?}"
    );
    assert!(
        (about_i - torque).length() < 1e-6 * torque.length(),
        "{about_i:?} vs {torque:?}"
    );
}

/// `(∂Q/∂q, ∂Q/∂v)` of parts 2 and 3, dense, at the input pose and at rest.
fn tangents(m: &Model) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let f = ForceSet::new(m).unwrap_or_else(|e| panic!("{e}"));
    let s = State::input(m);
    let (mut tq, mut tv) = (Vec::new(), Vec::new());
    f.add_jacobians(
        Regime::Dynamic,
        &s,
        &[(DVec3::ZERO, DVec3::ZERO); 2],
        &mut tq,
        Some(&mut tv),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let dense = |t: &[(usize, usize, f64)]| {
        let mut d = vec![vec![0.0; 12]; 12];
        for &(r, c, x) in t {
            d[r][c] += x;
        }
        d
    };
    (dense(&tq), dense(&tv))
}

#[test]
fn nonlinear_beam_equals_linear_for_small_deflections() {
    // Small deflections are what the tangent stiffness and damping at the undeformed pose
    // describe: NONLINEAR's equal LINEAR's (Euler–Bernoulli: no shear areas), here at a
    // generic turned pose, with CRATIO damping, to rounding (1e-9 of the largest entry).
    let r = DMat3::from_axis_angle(DVec3::new(-0.3, 0.5, 0.8).normalize(), 0.7);
    let at = DVec3::new(L, 0.0, 0.0);
    let (kn, cn) = tangents(&two_parts(
        "NONLINEAR, CRATIO = 0.01",
        r,
        at,
        DMat3::IDENTITY,
    ));
    let (kl, cl) = tangents(&two_parts("LINEAR, CRATIO = 0.01", r, at, DMat3::IDENTITY));
    for (what, n, l) in [("stiffness", kn, kl), ("damping", cn, cl)] {
        let scale = l.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        assert!(scale > 1e5, "{what}: a real matrix ({scale})");
        for (row, (rn, rl)) in n.iter().zip(&l).enumerate() {
            for (col, (a, b)) in rn.iter().zip(rl).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-9 * scale,
                    "{what} ({row}, {col}): NONLINEAR {a} vs LINEAR {b}"
                );
            }
        }
    }
}

#[test]
fn nonlinear_beam_chain_bent_by_an_end_moment_follows_the_circle_of_radius_ei_over_m() {
    // Eight NONLINEAR beams of length L/8 in a chain clamped at the ground origin, a moment
    // M = (π/2)·EI/L at the tip: the exact elastica is a quarter circle of radius
    // R = EI/M = 2L/π, the tip at (R, R) turned 90°. Each corotational element turns its
    // end by φ = 2·asin(M·h/(2·EI)) (h = L/8) with its chord, of length h, at φ/2; the tip
    // of the chain is Σ h·(cos((k+½)φ), sin((k+½)φ)) — exact for the discrete model
    // (1e-6 asserted), within (φ/2)²/6 = 0.16 % of the circle per element (4e-3·R
    // asserted).
    let n = 8;
    let h = L / n as f64;
    let moment = PI / 2.0 * ei() / L;
    let mut text = String::from(
        "chain\nUNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         EQUILIBRIUM/MAXIT = 200\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n",
    );
    for k in 1..=n {
        let x = h * k as f64;
        // Part k+1: marker 100k+1 (I of beam k) and 100k+2 (J of beam k+1), at its CM.
        text += &format!(
            "PART/{}, MASS = 0.1, CM = {}, IP = 1E-4, 1E-4, 1E-4, QG = {x}, 0, 0\nMARKER/{}, PART = {}\nMARKER/{}, PART = {}\n",
            k + 1,
            100 * k + 1,
            100 * k + 1,
            k + 1,
            100 * k + 2,
            k + 1
        );
        let j = if k == 1 { 1 } else { 100 * (k - 1) + 2 };
        text += &format!(
            "BEAM/{k}, I = {}, J = {j}, {}\n",
            100 * k + 1,
            section(h, "NONLINEAR")
        );
    }
    text += &format!(
        "VTORQUE/1, I = {}, JFLOAT = 12, RM = 1, TX = 0, TY = 0, TZ = {moment}\nEND\n",
        100 * n + 1
    );
    let (_, eq) = equilibrium(&text);
    let last = &eq.state.poses[n - 1];
    let phi = 2.0 * (moment * h / (2.0 * ei())).asin();
    let discrete = (0..n).fold(DVec3::ZERO, |acc, k| {
        let a = (k as f64 + 0.5) * phi;
        acc + h * DVec3::new(a.cos(), a.sin(), 0.0)
    });
    assert!(
        (last.p - discrete).length() < 1e-6 * L,
        "{:?} vs {discrete:?}",
        last.p
    );
    let turned = n as f64 * phi;
    let x_axis = last.r.x_axis;
    assert!(
        (x_axis - DVec3::new(turned.cos(), turned.sin(), 0.0)).length() < 1e-6,
        "{x_axis:?}"
    );
    let r = ei() / moment;
    assert!(
        (last.p - DVec3::new(r, r, 0.0)).length() < 4e-3 * r,
        "{:?} vs ({r}, {r}, 0)",
        last.p
    );
}
