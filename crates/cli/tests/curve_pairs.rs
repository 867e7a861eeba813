//! CVCV end to end (ADM-ELEMENTS §16) against closed forms:
//!
//! * an eccentric circular cam (radius [`RC`], eccentricity [`E`]) on a crank hinged to ground,
//!   and a flat follower on a translational guide: the follower's height is `E sin θ + RC`
//!   (driven: `θ = 2t`, a kinematic run, with the contact force `m_f (g − 4E sin 2t)`; free:
//!   static equilibrium at θ = −90°, and small oscillations about it with
//!   `ω² = (m_f + m_c) g E / (I_c + m_c E²)`); its counts (the CVCV's out-of-plane row is
//!   redundant with the planar joints);
//! * a disc sliding without friction inside a circular trough (a planar joint holds it in the
//!   plane): its centre is a pendulum of length R − r, its spin stays zero, energy is kept.

mod common;
use common::{json, run};
use std::f64::consts::{PI, TAU};
use std::path::PathBuf;

const G: f64 = 9.81;
/// Cam radius and eccentricity.
const RC: f64 = 0.5;
const E: f64 = 0.2;
/// Follower and cam masses, the cam's moment of inertia about its centre.
const M_F: f64 = 2.0;
const M_C: f64 = 1.0;
const I_C: f64 = 0.1;

/// `MATRIX/id` of `n + 1` points on a circle of radius `r` about the origin (closed: the first
/// point repeated last).
fn circle(id: u32, r: f64, n: usize) -> String {
    let values: Vec<String> = (0..=n)
        .map(|i| {
            let th = TAU * i as f64 / n as f64;
            format!("{:.17e}, {:.17e}, 0", r * th.cos(), r * th.sin())
        })
        .collect();
    format!(
        "MATRIX/{id}, FULL = RORDER, ROWS = {}, COLUMNS = 3, VALUES = {}\n",
        n + 1,
        values.join(",\n, ")
    )
}

fn write(tag: &str, text: &str) -> PathBuf {
    let f = std::env::temp_dir().join(format!("linkage-cvcv-{tag}-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

/// The cam (PART/2, its curve CURVE/3 on marker 22 at its centre) at crank angle `theta`
/// and the follower (PART/3, the line CURVE/4 on marker 31) resting on it; `extra` adds
/// statements (a MOTION).
fn cam(tag: &str, theta: f64, extra: &str) -> PathBuf {
    let y_f = E * theta.sin() + RC;
    let text = format!(
        "cam and flat follower
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1, QP = 0, 0, 0
MARKER/2, PART = 1, QP = 0, 0, 0, REULER = 0D, -90D, 0D
ACCGRAV/JGRAV = -{G}
{}CURVE/3, CLOSED, CURVE_POINTS, MATRIX = 1
MATRIX/2, FULL = RORDER, ROWS = 5, COLUMNS = 3, VALUES = -2, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 2, 0, 0
CURVE/4, OPEN, CURVE_POINTS, MATRIX = 2
PART/2, MASS = {M_C}, CM = 20, IP = {I_C}, {I_C}, {I_C}, QG = 0, 0, 0, REULER = {theta}, 0, 0
MARKER/20, PART = 2, QP = {E}, 0, 0
MARKER/21, PART = 2, QP = 0, 0, 0
MARKER/22, PART = 2, QP = {E}, 0, 0
MARKER/23, PART = 2, FLOATING
PART/3, MASS = {M_F}, CM = 30, IP = 0.1, 0.1, 0.1, QG = 0, {}, 0
MARKER/30, PART = 3, QP = 0, {RC}, 0
MARKER/31, PART = 3, QP = 0, {RC}, 0
MARKER/32, PART = 3, FLOATING
MARKER/33, PART = 3, QP = 0, {RC}, 0, REULER = 0D, -90D, 0D
JOINT/1, REVOLUTE, I = 21, J = 1
JOINT/2, TRANSLATIONAL, I = 33, J = 2
{extra}CVCV/6, ICURVE = 3, IRM = 22, IFLOAT = 23, JCURVE = 4, JRM = 31, JFLOAT = 32
END
",
        circle(1, RC, 288),
        y_f - RC
    );
    write(tag, &text)
}

/// The CSV of `linkage simulate` as named columns (units stripped from the header).
fn simulate(f: &std::path::Path, end: f64, steps: usize) -> (Vec<String>, Vec<Vec<f64>>) {
    let csv = f.with_extension("csv");
    let (code, out, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        &end.to_string(),
        "--steps",
        &steps.to_string(),
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.split(' ').next().unwrap_or(h).to_string())
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).expect(name)
}

#[test]
fn a_cam_and_follower_count_their_equations() {
    let f = cam("count", 0.0, "");
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    // 2 parts (12) − revolute 5 − translational 5 − CVCV 2 = 0; the follower's line and the
    // cam's circle lie in one plane the joints keep already: one redundant equation, the
    // CVCV's out-of-plane row, and 1 DOF (the crank).
    assert_eq!(v["constraint_equations"], 12);
    assert_eq!(v["gruebler"], 0);
    assert_eq!(v["dof"], 1);
    let counts = v["constraint_counts"].as_array().unwrap();
    assert!(
        counts
            .iter()
            .any(|c| c["type"] == "Curve-Curve Constraint" && c["count"] == 1),
        "{counts:?}"
    );
    let redundant = v["redundant"].as_array().unwrap();
    assert_eq!(redundant.len(), 1, "{redundant:?}");
    assert_eq!(redundant[0]["name"], "CVCV_6");
    assert_eq!(redundant[0]["equation"], "Curve Offset Along Binormal");
    assert_eq!(v["later_refused_by"].as_array().map(Vec::len), Some(0));
    let (_, text, _) = run(&["verify", f.to_str().unwrap()]);
    assert!(
        text.contains("CVCV_6 (Curve-Curve Constraint)   Curve Offset Along Binormal"),
        "{text}"
    );
}

#[test]
fn a_driven_eccentric_cam_lifts_its_follower_by_e_sin_theta() {
    // θ = 2t: y_f = E sin 2t + RC, ÿ_f = −4E sin 2t, and the follower is pushed by
    // N = m_f (g + ÿ_f), so the reaction on the cam is −N along y. The interpolated circle's
    // support function ripples by ~1e-9·RC (displacement) and its curvature by 4e-5
    // (acceleration, so the force).
    let f = cam(
        "driven",
        0.0,
        "MOTION/5, JOINT = 1, ROTATION, FUNCTION = 2*TIME
REQUEST/9, F2 = DX(23)\\F3 = DY(23)\\F4 = DX(32)\\F6 = DY(32, 22, 23)\n",
    );
    let (h, rows) = simulate(&f, 3.0, 60);
    let (t, y, vy, fy, fx) = (
        col(&h, "time"),
        col(&h, "PART_3.y"),
        col(&h, "PART_3.vy"),
        col(&h, "CVCV_6.fy"),
        col(&h, "CVCV_6.fx"),
    );
    assert_eq!(rows.len(), 61);
    for r in &rows {
        let th = 2.0 * r[t];
        assert!(
            (r[y] - (E * th.sin() + RC)).abs() < 1e-8,
            "y at {}: {}",
            r[t],
            r[y]
        );
        assert!((r[vy] - 2.0 * E * th.cos()).abs() < 1e-7, "vy at {}", r[t]);
        let n = M_F * (G - 4.0 * E * th.sin());
        assert!(
            (r[fy] + n).abs() < 1e-4 * n,
            "force at {}: {} vs {}",
            r[t],
            r[fy],
            -n
        );
        assert!(r[fx].abs() < 1e-6, "no tangential force at {}", r[t]);
    }
    // The contact is the top of the cam circle, (E cos θ, E sin θ + RC): on the follower's
    // line (x from −2 to 2 through evenly spaced points: α linear in x) at β = E cos θ / 2,
    // and on the cam circle at angle π/2 − θ in the cam's frame (α = −1 at angle 0). IFLOAT
    // (23, on the cam) and JFLOAT (32, on the follower) both sit there; IFLOAT's y is the
    // normal of the cam circle (x its tangent, z = IRM's z), so the cam's centre is RC below
    // it along y. Where along the flat the tangency falls follows the interpolated circle's
    // normal direction, which wavers by ~1e-7 rad between its points: 1e-7 in x.
    let (alpha, beta, cx, cy) = (
        col(&h, "CVCV_6.alpha"),
        col(&h, "CVCV_6.beta"),
        col(&h, "CVCV_6.contact.x"),
        col(&h, "CVCV_6.contact.y"),
    );
    let (ix, iy, jx, centre) = (
        col(&h, "REQUEST_9.f2"),
        col(&h, "REQUEST_9.f3"),
        col(&h, "REQUEST_9.f4"),
        col(&h, "REQUEST_9.f6"),
    );
    for r in &rows {
        let th = 2.0 * r[t];
        let (x, y) = (E * th.cos(), E * th.sin() + RC);
        assert!(
            (r[cx] - x).abs() < 1e-7 && (r[cy] - y).abs() < 1e-8,
            "at {}",
            r[t]
        );
        assert!((r[beta] - x / 2.0).abs() < 5e-8, "beta at {}", r[t]);
        let on_cam = (PI / 2.0 - th).rem_euclid(TAU);
        let a = -1.0 + on_cam / PI;
        assert!(
            (r[alpha] - a).abs() < 1e-7 || (r[alpha] - a).abs() > 2.0 - 1e-7,
            "alpha at {}: {} vs {a}",
            r[t],
            r[alpha]
        );
        assert!((r[ix] - r[cx]).abs() < 1e-12 && (r[iy] - r[cy]).abs() < 1e-12);
        assert!((r[jx] - r[cx]).abs() < 1e-12);
        assert!((r[centre] + RC).abs() < 1e-8, "{}", r[centre]);
    }
}

#[test]
fn a_free_cam_rests_with_its_centre_below_the_pivot_and_rocks_about_it() {
    // Gravity on the follower and the cam turns the crank to θ = −90°: y_f = RC − E, and
    // the contact carries the follower's weight.
    let f = cam("free", -PI / 3.0, "");
    let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let parts = v["parts"].as_array().unwrap();
    let follower = parts.iter().find(|p| p["name"] == "PART_3").unwrap();
    let y = follower["position"][1].as_f64().unwrap();
    assert!((y - (RC - E)).abs() < 1e-9, "{y}");
    let cvcv = v["reactions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["name"] == "CVCV_6")
        .unwrap();
    let fy = cvcv["force"][1].as_f64().unwrap();
    assert!((fy + M_F * G).abs() < 1e-9 * M_F * G, "{fy}");
    // About it: V'' = (m_f + m_c) g E (the follower's height E sin θ and the cam's centre),
    // inertia I_c + m_c E² (the follower is at rest to first order there). The interpolated
    // cam circle's radius of curvature is off by RC·h²/12 (h = 2π/288: 2.0e-5 m) at its
    // points, which enters V'' through the follower's height: m_f g·2.0e-5/5.886 = 6.6e-5 in
    // ω², 3.3e-5 in ω.
    let (code, v) = json(&[
        "linear",
        f.to_str().unwrap(),
        "--static-first",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 1, "{modes:?}");
    let freq = modes[0]["frequency"].as_f64().unwrap();
    let exact = ((M_F + M_C) * G * E / (I_C + M_C * E * E)).sqrt() / TAU;
    assert!((freq / exact - 1.0).abs() < 4e-5, "{freq} vs {exact}");
}

/// A disc of radius r (PART/5) in a trough of radius R, on a planar joint, its centre at
/// angle `theta` from the bottom.
fn trough(tag: &str, theta: f64, extra: &str) -> PathBuf {
    let (big, r) = (2.0, 0.5);
    let (x, y) = ((big - r) * theta.sin(), -(big - r) * theta.cos());
    let text = format!(
        "disc in a trough
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1, QP = 0, 0, 0
MARKER/11, PART = 1, FLOATING
ACCGRAV/JGRAV = -{G}
{}CURVE/2, CLOSED, CURVE_POINTS, MATRIX = 1
{}CURVE/4, CLOSED, CURVE_POINTS, MATRIX = 3
PART/5, MASS = 2, CM = 50, IP = 0.15, 0.15, 0.25, QG = {x}, {y}, 0
MARKER/50, PART = 5
MARKER/51, PART = 5
MARKER/52, PART = 5, FLOATING
JOINT/7, PLANAR, I = 51, J = 1
CVCV/8, ICURVE = 2, IRM = 1, IFLOAT = 11, JCURVE = 4, JRM = 51, JFLOAT = 52{extra}
INTEGRATOR/GSTIFF, ERROR = 1E-7
END
",
        circle(1, big, 288),
        circle(3, r, 288),
    );
    write(tag, &text)
}

#[test]
fn a_disc_sliding_in_a_trough_swings_as_a_pendulum_of_length_r_big_minus_r() {
    // θ0 = 0.2 from rest: T = 2π√(L/g)(1 + θ0²/16 + 11θ0⁴/3072), L = R − r = 1.5. The
    // frictionless contact pushes through the disc's centre: no spin.
    let theta0: f64 = 0.2;
    let f = trough("swing", theta0, "");
    let (h, rows) = simulate(&f, 3.0, 300);
    let (t, x, y, vx, vy, wz) = (
        col(&h, "time"),
        col(&h, "PART_5.x"),
        col(&h, "PART_5.y"),
        col(&h, "PART_5.vx"),
        col(&h, "PART_5.vy"),
        col(&h, "PART_5.wz"),
    );
    let mut crossings = Vec::new();
    for w in rows.windows(2) {
        if (w[0][x] > 0.0) != (w[1][x] > 0.0) {
            crossings.push(w[0][t] + (w[1][t] - w[0][t]) * w[0][x] / (w[0][x] - w[1][x]));
        }
    }
    assert!(crossings.len() >= 2, "{crossings:?}");
    let exact = 2.0
        * PI
        * (1.5 / G).sqrt()
        * (1.0 + theta0.powi(2) / 16.0 + 11.0 * theta0.powi(4) / 3072.0);
    let period = 2.0 * (crossings[1] - crossings[0]);
    assert!((period / exact - 1.0).abs() < 1e-5, "{period} vs {exact}");
    assert!((crossings[0] / (exact / 4.0) - 1.0).abs() < 1e-5);
    let energy = |r: &Vec<f64>| 0.5 * 2.0 * (r[vx] * r[vx] + r[vy] * r[vy]) + 2.0 * G * r[y];
    let e0 = energy(&rows[0]);
    for r in &rows {
        assert!(
            (energy(r) - e0).abs() < 1e-6 * e0.abs(),
            "energy at {}",
            r[t]
        );
        assert!(
            (r[x].hypot(r[y]) - 1.5).abs() < 1e-8,
            "path radius at {}",
            r[t]
        );
        assert!(r[wz].abs() < 1e-5, "spin at {}: {}", r[t], r[wz]);
    }
}

#[test]
fn equal_ivel_and_jvel_start_the_disc_rolling() {
    // The contact point moving at 2 m/s along both curves is rolling: at the bottom the centre
    // moves at 2·(R − r)/R = 1.5 m/s along +x (the trough's tangent there, its points running
    // counter-clockwise) and the disc turns at −(R − r)/r · θ̇ = −3 rad/s. The contact point's
    // speed along the trough is (R/(R − r)) v_c through the curves' curvatures, which the
    // interpolated circles hold to 4e-5.
    let f = trough("roll", 0.0, ", IVEL = 2, JVEL = 2");
    let (code, v) = json(&["ic", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let part = &v["parts"][0];
    let vx = part["velocity"][0].as_f64().unwrap();
    let wz = part["angular_velocity"][2].as_f64().unwrap();
    assert!((vx / 1.5 - 1.0).abs() < 1e-4, "{vx}");
    assert!((wz / -3.0 - 1.0).abs() < 1e-4, "{wz}");
    assert!(part["velocity"][1].as_f64().unwrap().abs() < 1e-9);
    // The contact at the bottom of both circles: angle −π/2, α = β = 0.5.
    let c = &v["curve_contacts"][0];
    assert_eq!(c["name"], "CVCV_8");
    assert!((c["alpha"].as_f64().unwrap() - 0.5).abs() < 1e-9, "{c}");
    assert!((c["beta"].as_f64().unwrap() - 0.5).abs() < 1e-9, "{c}");
    assert!((c["point"][1].as_f64().unwrap() + 2.0).abs() < 1e-9, "{c}");
    // Without them the disc starts at rest (the velocity IC's least change).
    let f = trough("rest", 0.0, "");
    let (_, v) = json(&["ic", f.to_str().unwrap(), "--format", "json"]);
    assert!(v["parts"][0]["velocity"][0].as_f64().unwrap().abs() < 1e-12);
}

#[test]
fn idisp_chooses_which_side_of_the_cam_the_follower_touches() {
    // Two contacts satisfy the common-normal conditions between the flat and the circle: its
    // top and its bottom. IDISP at the bottom of the cam (IRM frame) starts the contact there,
    // so the assembly brings the follower's line down to the cam's bottom, y = −RC (θ = 0),
    // at the circle's angle 270° (α = 0.5); without it the closest pair is the top.
    let motion = "MOTION/5, JOINT = 1, ROTATION, FUNCTION = 2*TIME\n";
    let f = cam("idisp", 0.0, motion);
    let text = std::fs::read_to_string(&f)
        .unwrap()
        .replace("JFLOAT = 32\n", "JFLOAT = 32, IDISP = 0, -0.5, 0\n");
    std::fs::write(&f, text).unwrap();
    let (code, v) = json(&["ic", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let follower = v["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "PART_3")
        .unwrap();
    let y = follower["position"][1].as_f64().unwrap();
    assert!((y + RC).abs() < 1e-9, "{y}");
    let c = &v["curve_contacts"][0];
    assert!((c["alpha"].as_f64().unwrap() - 0.5).abs() < 1e-9, "{c}");
    assert!((c["point"][0].as_f64().unwrap() - E).abs() < 1e-9, "{c}");
    let f = cam("top", 0.0, motion);
    let (_, v) = json(&["ic", f.to_str().unwrap(), "--format", "json"]);
    let c = &v["curve_contacts"][0];
    assert!((c["alpha"].as_f64().unwrap() + 0.5).abs() < 1e-9, "{c}");
    assert!((c["point"][1].as_f64().unwrap() - RC).abs() < 1e-9, "{c}");
}
