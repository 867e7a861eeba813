//! CURVE and PTCV end to end (ADM-ELEMENTS §14, §15): a point kept on a circle given by its
//! points (a closed curve through CURVE_POINTS) is a pendulum of the circle's radius — its
//! counts in verify, its frequency in linear, its period and its reaction m(g cos θ + v²/R) in
//! simulate, also when it loops the circle across the seam of the closed curve; a PTCV that a
//! revolute joint makes redundant is named as such.

mod common;
use common::{json, run};
use std::f64::consts::{PI, TAU};
use std::path::PathBuf;

const G: f64 = 9.81;
const R: f64 = 2.0;
const MASS: f64 = 2.0;
/// Points on the circle. The interpolating periodic cubic has a curvature error of h²/12 at
/// its points (h = 2π/144: 1.6e-4 relative), which bounds every comparison below.
const POINTS: usize = 144;

/// Ground with the curve's marker (1, at the circle's centre) and the JFLOAT marker (11),
/// gravity along −y, the circle of radius [`R`] in the x-y plane as MATRIX/1 → CURVE/2.
fn header() -> String {
    let values: Vec<String> = (0..=POINTS)
        .map(|i| {
            let th = TAU * i as f64 / POINTS as f64;
            format!("{:.17e}, {:.17e}, 0", R * th.cos(), R * th.sin())
        })
        .collect();
    format!(
        "UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/1, PART = 1, QP = 0, 0, 0
MARKER/11, PART = 1, FLOATING
ACCGRAV/JGRAV = -{G}
MATRIX/1, FULL = RORDER, ROWS = {}, COLUMNS = 3, VALUES = {}
CURVE/2, CLOSED, CURVE_POINTS, MATRIX = 1
",
        POINTS + 1,
        values.join(",\n, ")
    )
}

/// A point mass of [`MASS`] at angle `theta` from the bottom of the circle with initial
/// velocity `vx` along x, on the circle by PTCV/3.
fn pendulum(tag: &str, theta: f64, vx: f64) -> PathBuf {
    pendulum_with(tag, theta, vx, "", "")
}

/// [`pendulum`] with more PTCV arguments (`, VEL = 3`) and more statements.
fn pendulum_with(tag: &str, theta: f64, vx: f64, ptcv: &str, extra: &str) -> PathBuf {
    let (x, y) = (R * theta.sin(), -R * theta.cos());
    let text = format!(
        "pendulum on a curve\n{}POINT_MASS/4, MASS = {MASS}, QG = {x}, {y}, 0, VX = {vx}
MARKER/40, POINT_MASS = 4
PTCV/3, I = 40, JFLOAT = 11, RM = 1, CURVE = 2{ptcv}
{extra}INTEGRATOR/GSTIFF, ERROR = 1E-7
END
",
        header()
    );
    let f = std::env::temp_dir().join(format!("linkage-ptcv-{tag}-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

/// One output of a simulated pendulum: time, position, velocity, the PTCV's reaction.
struct Sample {
    t: f64,
    x: f64,
    y: f64,
    v2: f64,
    force: f64,
}

fn simulate(f: &std::path::Path, end: f64, steps: usize) -> Vec<Sample> {
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
    let header: Vec<&str> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.split(' ').next().unwrap_or(h))
        .collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (t, x, y, vx, vy, fx, fy) = (
        col("time"),
        col("POINT_MASS_4.x"),
        col("POINT_MASS_4.y"),
        col("POINT_MASS_4.vx"),
        col("POINT_MASS_4.vy"),
        col("PTCV_3.fx"),
        col("PTCV_3.fy"),
    );
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            Sample {
                t: v[t],
                x: v[x],
                y: v[y],
                v2: v[vx] * v[vx] + v[vy] * v[vy],
                force: v[fx].hypot(v[fy]),
            }
        })
        .collect()
}

/// The largest relative error of the reaction against `m(g cos θ + v²/R)` (the normal force
/// of a point on a circle of radius R, θ from the bottom).
fn worst_reaction_error(samples: &[Sample]) -> f64 {
    samples
        .iter()
        .map(|s| {
            let theta = s.x.atan2(-s.y);
            let expected = MASS * (G * theta.cos() + s.v2 / R);
            (s.force - expected).abs() / expected.abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_point_on_a_curve_keeps_one_degree_of_freedom() {
    let f = pendulum("count", 0.3, 0.0);
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    // A point mass (3) less the PTCV's 2 equations.
    assert_eq!(v["point_masses"], 1);
    assert_eq!(v["constraint_equations"], 2);
    assert_eq!(v["gruebler"], 1);
    assert_eq!(v["dof"], 1);
    assert_eq!(v["redundant"].as_array().map(Vec::len), Some(0));
    assert_eq!(
        v["later_refused_by"].as_array().map(Vec::len),
        Some(0),
        "{v}"
    );
}

#[test]
fn a_ptcv_on_the_circle_a_hinge_already_keeps_is_redundant() {
    // A bar hinged at the circle's centre: its end at radius R is on the circle already, so
    // both PTCV equations duplicate the hinge's (DOF 1 either way, Gruebler 6 − 5 − 2 = −1).
    let text = format!(
        "hinged\n{}PART/5, MASS = 1, CM = 50, IP = 1, 1, 1
MARKER/50, PART = 5, QP = 1, 0, 0
MARKER/51, PART = 5, QP = 0, 0, 0
MARKER/52, PART = 5, QP = {R}, 0, 0
JOINT/6, REVOLUTE, I = 51, J = 1
PTCV/3, I = 52, JFLOAT = 11, RM = 1, CURVE = 2
END
",
        header()
    );
    let f = std::env::temp_dir().join(format!("linkage-ptcv-hinge-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["gruebler"], -1);
    assert_eq!(v["dof"], 1);
    let redundant: Vec<(String, String)> = v["redundant"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["name"].as_str().unwrap().to_string(),
                r["equation"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(redundant.len(), 2, "{redundant:?}");
    assert!(
        redundant.contains(&(
            "PTCV_3".into(),
            "Translation of I Marker Normal to Curve".into()
        )),
        "{redundant:?}"
    );
    let (_, text, _) = run(&["verify", f.to_str().unwrap()]);
    assert!(
        text.contains("PTCV_3 (Point-Curve Constraint)   Translation of I Marker Normal to Curve"),
        "{text}"
    );
}

#[test]
fn small_oscillations_on_a_circle_have_the_pendulum_frequency() {
    // √(g/R)/2π about the bottom; the curve's curvature error (1.6e-4) halves in ω.
    let f = pendulum("linear", 0.2, 0.0);
    let (code, v) = json(&[
        "linear",
        f.to_str().unwrap(),
        "--static-first",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    let freq = v["modes"][0]["frequency"].as_f64().unwrap();
    let exact = (G / R).sqrt() / TAU;
    assert!((freq / exact - 1.0).abs() < 1.2e-4, "{freq} vs {exact}");
    assert_eq!(v["modes"].as_array().map(Vec::len), Some(1));
}

#[test]
fn a_point_on_a_circle_swings_with_the_pendulum_period_and_reaction() {
    // θ0 = 0.3 rad from rest: T = 2π√(R/g)(1 + θ0²/16 + 11θ0⁴/3072) (the series of the
    // complete elliptic integral; the next term is below 1e-6). Two zero crossings of x are
    // half a period apart.
    let theta0: f64 = 0.3;
    let f = pendulum("swing", theta0, 0.0);
    let s = simulate(&f, 3.0, 600);
    let mut crossings = Vec::new();
    for w in s.windows(2) {
        if (w[0].x > 0.0) != (w[1].x > 0.0) {
            crossings.push(w[0].t + (w[1].t - w[0].t) * w[0].x / (w[0].x - w[1].x));
        }
    }
    assert!(crossings.len() >= 2, "{crossings:?}");
    let period = 2.0 * (crossings[1] - crossings[0]);
    let exact =
        2.0 * PI * (R / G).sqrt() * (1.0 + theta0.powi(2) / 16.0 + 11.0 * theta0.powi(4) / 3072.0);
    assert!((period / exact - 1.0).abs() < 2e-4, "{period} vs {exact}");
    // The first crossing is a quarter period after the release.
    assert!(
        (crossings[0] / (exact / 4.0) - 1.0).abs() < 2e-4,
        "{crossings:?}"
    );
    let worst = worst_reaction_error(&s);
    assert!(worst < 2e-4, "reaction off by {worst}");
}

#[test]
fn a_point_looping_a_closed_curve_crosses_its_seam() {
    // 12 m/s at the bottom of a circle of radius 2 loops it (v² > 5gR = 98.1): the point passes
    // the seam of the closed curve (α = ±1 at angle 0) on every turn. Energy is conserved, the
    // point stays on the circle and the reaction is m(g cos θ + v²/R) all the way round.
    let f = pendulum("loop", 0.0, 12.0);
    let s = simulate(&f, 3.0, 600);
    let (mut turned, mut prev) = (0.0, 0.0);
    for p in &s {
        let th = p.x.atan2(-p.y);
        let mut d = th - prev;
        d -= TAU * (d / TAU).round();
        turned += d;
        prev = th;
    }
    assert!(turned > 2.0 * TAU, "turned {turned} rad");
    let energy = |p: &Sample| 0.5 * MASS * p.v2 + MASS * G * p.y;
    let e0 = energy(&s[0]);
    for p in &s {
        assert!(
            (energy(p) - e0).abs() < 1e-5 * e0.abs(),
            "energy at {}",
            p.t
        );
        assert!((p.x.hypot(p.y) - R).abs() < 1e-7, "radius at {}", p.t);
    }
    let worst = worst_reaction_error(&s);
    assert!(worst < 5e-4, "reaction off by {worst}");
}

/// PTCV's VEL starts the point sliding along the curve's tangent (+x at the bottom of the
/// counter-clockwise circle) at that speed, and the swing then rises to the energy height:
/// cos θ_max = 1 − v0²/(2gR). The JFLOAT marker sits at the contact point (REQUEST DX, DY of
/// marker 11 read the point's position) with x along the tangent and y away from the centre
/// of curvature; the α column is the point's angle on the circle (α = −1 at angle 0, the
/// first matrix point).
#[test]
fn ptcv_vel_starts_the_point_sliding_and_jfloat_follows_the_contact() {
    let v0 = 3.0;
    let f = pendulum_with(
        "vel",
        0.0,
        0.0,
        ", VEL = 3",
        "REQUEST/9, F2 = DX(11)\\F3 = DY(11)\\F4 = DX(11, 1, 11)\\F6 = DY(1, 11, 11)\n",
    );
    let csv = f.with_extension("csv");
    let (code, out, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "2",
        "--steps",
        "200",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|h| h.split(' ').next().unwrap_or(h))
        .collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let (x, y, vx, vy) = (
        col("POINT_MASS_4.x"),
        col("POINT_MASS_4.y"),
        col("POINT_MASS_4.vx"),
        col("POINT_MASS_4.vy"),
    );
    assert!((rows[0][vx] - v0).abs() < 1e-9, "{}", rows[0][vx]);
    assert!(rows[0][vy].abs() < 1e-9);
    let cos_max = 1.0 - v0 * v0 / (2.0 * G * R);
    let x_max = R * (1.0 - cos_max * cos_max).sqrt();
    let reached = rows.iter().map(|r| r[x]).fold(f64::MIN, f64::max);
    // 200 outputs over 2 s sample the turning point within 1e-2 s: x is within
    // ẍ·δt²/2 ≈ 5·1e-4/2 of its maximum there.
    assert!((reached - x_max).abs() < 3e-4, "{reached} vs {x_max}");
    let (dx, dy, tangent_x, away_y, alpha) = (
        col("REQUEST_9.f2"),
        col("REQUEST_9.f3"),
        col("REQUEST_9.f4"),
        col("REQUEST_9.f6"),
        col("PTCV_3.alpha"),
    );
    for r in &rows {
        assert!((r[dx] - r[x]).abs() < 1e-12 && (r[dy] - r[y]).abs() < 1e-12);
        // DX(11, 1, 11): the point's position from the centre along JFLOAT's x (the tangent)
        // is 0; DY(1, 11, 11): the centre seen from the contact along JFLOAT's y is −R (y
        // points away from the centre). The interpolated circle's tangent leans off the
        // true one by up to ~7e-7 rad between its points (1.3e-6 m at R = 2), its radius
        // off R by up to 2e-8 m.
        assert!(r[tangent_x].abs() < 3e-6, "{}", r[tangent_x]);
        assert!((r[away_y] + R).abs() < 5e-8, "{}", r[away_y]);
        let angle = r[y].atan2(r[x]).rem_euclid(TAU);
        let expected = -1.0 + angle / PI;
        assert!(
            (r[alpha] - expected).abs() < 1e-9 || (r[alpha] - expected).abs() > 2.0 - 1e-9,
            "{} vs {expected}",
            r[alpha]
        );
    }
}

/// The FRS5 feed-system models (two corpus variants) hold 18 PTCVs on two matrix CURVEs (a
/// polyline, ORDER = 2, and a cubic through its points): verify counts them (302 equations,
/// 538 DOF, none refused), and with their CONTACTs (Parasolid files not in the corpus) and
/// SENSORs left out the initial conditions assemble them onto their curves and report their
/// reactions: a force at the I marker and no torque (a point constraint).
#[test]
fn corpus_models_with_matrix_curves_run_their_ptcvs() {
    let Some(dir) = common::corpus() else { return };
    for name in [
        "bthornton191__adamspy__test__files__real_analysis_with_spikes__FRS5_doe_8_LAUL_analysis.adm",
        "bthornton191__adamspy__test__files__real_analysis_with_spikes_2__FRS5_doe_1_LAUL_analysis.adm",
    ] {
        let f = dir.join(name);
        let f = f.to_str().unwrap();
        let (code, v) = json(&["verify", f, "--format", "json"]);
        assert_eq!(code, 0, "{name}");
        let counts = v["constraint_counts"].as_array().unwrap();
        let ptcvs = counts
            .iter()
            .find(|c| c["type"] == "Point-Curve Constraint")
            .map(|c| c["count"].as_u64().unwrap());
        assert_eq!(ptcvs, Some(18), "{name}");
        assert_eq!(v["constraint_equations"], 302, "{name}");
        assert_eq!(v["dof"], 538, "{name}");
        let refused: Vec<&str> = v["not_run"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|e| e["element"].as_str())
            .filter(|e| e.starts_with("PTCV") || e.starts_with("CURVE"))
            .collect();
        assert!(refused.is_empty(), "{name}: {refused:?}");
        let (code, ic) = json(&[
            "ic",
            f,
            "--deactivate",
            "CONTACT,SENSOR",
            "--format",
            "json",
        ]);
        assert_eq!(code, 0, "{name}: {ic}");
        assert_eq!(ic["converged"], true, "{name}");
        let reactions: Vec<&serde_json::Value> = ic["reactions"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r["type"] == "Point-Curve Constraint")
            .collect();
        assert_eq!(reactions.len(), 18, "{name}");
        for r in reactions {
            let t: Vec<f64> = r["torque"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(t, [0.0, 0.0, 0.0], "{name}: {r}");
        }
    }
}

/// The drillsim models keep their PTCVs on a USER curve: every one is named (not modelled:
/// the curve is a USER subroutine), and refused by the force analyses.
#[test]
fn ptcvs_on_a_user_curve_are_named_each() {
    let Some(dir) = common::corpus() else { return };
    let f = dir.join("bthornton191__adamspy__test__existing_drillsim__test_analysis_1.adm");
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0);
    let named: Vec<&serde_json::Value> = v["not_run"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| {
            e["element"]
                .as_str()
                .is_some_and(|s| s.starts_with("PTCV/"))
        })
        .collect();
    assert_eq!(named.len(), 96);
    for e in &named {
        assert!(
            e["detail"]
                .as_str()
                .unwrap()
                .contains("CURVE/9001 is a USER subroutine"),
            "{e}"
        );
        assert_eq!(e["refused_by"].as_array().unwrap().len(), 5, "{e}");
    }
    // The curve itself is named for its USER call.
    assert!(v["not_run"]
        .as_array()
        .unwrap()
        .iter()
        .any(|e| e["element"] == "CURVE/9001" && e["reason"] == "USER subroutine"));
}
