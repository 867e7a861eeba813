//! Motions at the three levels (displacement, velocity, acceleration) through the binary, and
//! the messages when a motion function cannot be evaluated.
//!
//! The model is `mechanisms/pendulum.adm` (a rod on a revolute about global z, hanging along
//! −y, L = 1 m) with one MOTION appended on its revolute. A prescribed rotation θ(t) puts the
//! CM at `(0.5 sin θ, −0.5 cos θ)` and the 3-1-3 angle ψ = θ.

mod common;
use common::*;
use std::path::{Path, PathBuf};

/// The pendulum with `motion` appended; returns the file and the motion's line number.
fn pendulum_with(tag: &str, motion: &str) -> (PathBuf, usize) {
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum.adm")).unwrap();
    let body: Vec<&str> = text.lines().filter(|l| l.trim() != "END").collect();
    let line = body.len() + 1;
    let out = std::env::temp_dir().join(format!("linkage-motion-{tag}-{}.adm", std::process::id()));
    std::fs::write(&out, format!("{}\n{motion}\nEND\n", body.join("\n"))).unwrap();
    (out, line)
}

/// Columns `time, rod.x, rod.y, …, rod.psi` of a simulate CSV (by name, without units).
fn rows(csv: &str) -> Vec<(f64, f64, f64, f64)> {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines
        .next()
        .unwrap()
        .split(',')
        .map(linkage_report::units::column_name)
        .collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (t, x, y, psi) = (col("time"), col("rod.x"), col("rod.y"), col("rod.psi"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
            (v[t], v[x], v[y], v[psi])
        })
        .collect()
}

/// Position of the rod's CM and ψ (degrees) for the rotation θ.
fn expected(theta: f64) -> (f64, f64, f64) {
    (0.5 * theta.sin(), -0.5 * theta.cos(), theta.to_degrees())
}

fn check_history(file: &Path, theta: impl Fn(f64) -> f64) {
    let csv = std::env::temp_dir().join(format!(
        "{}.csv",
        file.file_stem().unwrap().to_string_lossy()
    ));
    let (code, _, err) = run(&[
        "simulate",
        file.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "4",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let got = rows(&std::fs::read_to_string(&csv).unwrap());
    assert_eq!(got.len(), 5);
    for (t, x, y, psi) in got {
        let (ex, ey, epsi) = expected(theta(t));
        // The positions come from the motion constraint, held to the IC/integrator error
        // (1e-6 of the model size); ψ is printed in degrees.
        assert!((x - ex).abs() < 1e-6, "t {t}: x {x} vs {ex}");
        assert!((y - ey).abs() < 1e-6, "t {t}: y {y} vs {ey}");
        assert!((psi - epsi).abs() < 1e-4, "t {t}: psi {psi} vs {epsi}");
    }
}

#[test]
fn a_velocity_motion_without_icdisp_integrates_from_the_assembled_displacement() {
    // θ̇ = 2t, θ(0) free (assembled at 0) → θ = t².
    let (f, _) = pendulum_with(
        "vel",
        "MOTION/1, JOINT = 1, ROTATION, VELOCITY, FUNCTION = 2*TIME",
    );
    check_history(&f, |t| t * t);
    // Quasi-static: the same displacement at each output time.
    let (code, out, err) = run(&[
        "static",
        f.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "2",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    for s in steps {
        let t = s["time"].as_f64().unwrap();
        let rod = &s["parts"][0];
        let psi = rod["reuler"][0].as_f64().unwrap();
        assert!(
            (psi - (t * t).to_degrees()).abs() < 1e-4,
            "t {t}: psi {psi}"
        );
    }
}

#[test]
fn velocity_and_acceleration_motions_with_initial_values() {
    // θ̇ = 2t with ICDISP 0.3 → θ = 0.3 + t².
    let (f, _) = pendulum_with(
        "velic",
        "MOTION/1, JOINT = 1, ROTATION, VELOCITY, ICDISP = 0.3, FUNCTION = 2*TIME",
    );
    check_history(&f, |t| 0.3 + t * t);
    // θ̈ = 6t, ICDISP 0.1, ICVEL 0.5 → θ = 0.1 + 0.5 t + t³.
    let (f, _) = pendulum_with(
        "acc",
        "MOTION/1, JOINT = 1, ROTATION, ACCELERATION, ICDISP = 0.1, ICVEL = 0.5, FUNCTION = 6*TIME",
    );
    check_history(&f, |t| 0.1 + 0.5 * t + t * t * t);
}

#[test]
fn the_velocity_ic_of_a_velocity_motion_is_its_function() {
    // θ̇(0) = 1.5 rad/s on a rod whose CM is 0.5 m below the pivot: v = (0.75, 0, 0).
    let (f, _) = pendulum_with(
        "velic0",
        "MOTION/1, JOINT = 1, ROTATION, VELOCITY, FUNCTION = 1.5 + TIME",
    );
    let (code, out, err) = run(&["ic", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let rod = &v["parts"][0];
    assert!(
        (rod["velocity"][0].as_f64().unwrap() - 0.75).abs() < 1e-9,
        "{rod}"
    );
    assert!((rod["angular_velocity"][2].as_f64().unwrap() - 1.5).abs() < 1e-9);
    // θ̈(0) = 1 → tangential acceleration 0.5 m/s² along x, centripetal 1.125 m/s² along +y.
    let a = &rod["acceleration"];
    assert!((a[0].as_f64().unwrap() - 0.5).abs() < 1e-9, "{a}");
    assert!((a[1].as_f64().unwrap() - 1.125).abs() < 1e-9, "{a}");
}

#[test]
fn a_motion_that_cannot_be_evaluated_names_element_line_time_and_cause() {
    let (f, line) = pendulum_with(
        "dom",
        "MOTION/1, JOINT = 1, ROTATION, FUNCTION = SQRT(TIME - 1)",
    );
    let file = f.to_str().unwrap();
    let label = format!("MOTION_1 (MOTION/1, line {line})");
    for args in [
        vec!["ic", file],
        vec!["static", file],
        vec!["simulate", file, "--end", "0.1", "--steps", "2"],
        vec!["linear", file],
    ] {
        let (code, _, err) = run(&args);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(err.contains(&label), "{args:?}: {err}");
        assert!(err.contains("time 0"), "{args:?}: {err}");
        assert!(err.contains("SQRT of negative number"), "{args:?}: {err}");
    }
    // A velocity motion whose function fails later: the quasi-static series stops there.
    let (f, _) = pendulum_with(
        "domlate",
        "MOTION/1, JOINT = 1, ROTATION, VELOCITY, ICDISP = 0, FUNCTION = LOG(0.7 - TIME)",
    );
    let (code, _, err) = run(&["static", f.to_str().unwrap(), "--end", "1", "--steps", "2"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("time 1"), "{err}");
    assert!(err.contains("LOG of non-positive number"), "{err}");
}
