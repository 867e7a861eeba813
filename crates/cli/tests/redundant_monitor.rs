//! The redundant-equation monitor of `simulate` on a real model: a removed (redundant)
//! equation may drift by max(1e-6, INTEGRATOR ERROR) — times the model's size for lengths, in
//! radians for angles — before the run stops, and a stop names the element, the equation,
//! the time and the residual.
//!
//! Controls_Plant_2 (a 67-part SOLIDWORKS export of a 3-RPR robot, 195 redundant equations,
//! INTEGRATOR ERROR = 1e-4, no end time of its own: Simulink drives it) once stopped at
//! t = 13.7 s because a redundant rotation equation drifted by 5.8e-5° (1.0e-6 rad) against a
//! fixed tolerance of 1e-6.

mod common;
use common::{corpus, json};
use std::path::Path;

const DATASET: &str =
    "kiterunner347__3-RPR-parallel--robot__Matlab_Adams__Controls_Plant_2__Controls_Plant_2.adm";

/// The run's end: past the old stop at 13.7 s.
const END: f64 = 20.0;

fn simulate(f: &Path) -> (i32, serde_json::Value) {
    json(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        &END.to_string(),
        "--steps",
        "200",
        "--format",
        "json",
    ])
}

/// With its own settings (ERROR = 1e-4) Controls_Plant_2 runs the 20 s to the end (measured:
/// 4470 steps, about 7 s), its redundant equations all within 1e-4 of consistency.
#[test]
fn controls_plant_2_runs_to_the_end_with_its_integrator_settings() {
    let Some(dir) = corpus() else { return };
    let (code, v) = simulate(&dir.join(DATASET));
    assert_eq!(code, 0, "{}", v["errors"]);
    assert_eq!(v["completed"], true);
    assert_eq!(v["errors"].as_array().unwrap().len(), 0, "{}", v["errors"]);
    assert!((v["end_time"].as_f64().unwrap() - END).abs() < 1e-9);
    // The monitor had something to watch.
    assert_eq!(v["removed_equations"].as_array().unwrap().len(), 195);
}

/// With ERROR = 1e-6 the monitor allows 1e-6 rad: the redundant rotation equation that drifted
/// at 13.7 s before drifts past it early (measured: `Rotation Between Zi & Yj` of
/// `Concentric4_5`, −5.758e-5° at t = 0.329 s). A stop must name the element, the equation,
/// the time and a residual above the tolerance; a run that holds every removed equation
/// within 1e-6 rad runs to the end.
#[test]
fn a_redundant_equation_past_the_integrator_error_stops_the_run_with_its_name_time_and_value() {
    let Some(dir) = corpus() else { return };
    let text = std::fs::read_to_string(dir.join(DATASET))
        .unwrap()
        .replacen("ERROR = 1.0E-04", "ERROR = 1.0E-06", 1);
    assert!(text.contains("ERROR = 1.0E-06"));
    let f = std::env::temp_dir().join(format!("linkage-cp2-monitor-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, v) = simulate(&f);
    let _ = std::fs::remove_file(&f);
    let errors = v["errors"].as_array().unwrap();
    if code == 0 {
        assert_eq!(v["completed"], true);
        assert!((v["end_time"].as_f64().unwrap() - END).abs() < 1e-9);
        return;
    }
    assert_eq!(code, 1, "{errors:?}");
    assert_eq!(v["completed"], false);
    assert_eq!(errors.len(), 1, "{errors:?}");
    let message = errors[0].as_str().unwrap();
    // "simulation stopped at time T: the redundant equation E of C (removed as consistent)
    // became inconsistent: residual R deg"
    let time: f64 = message
        .strip_prefix("simulation stopped at time ")
        .and_then(|rest| rest.split(':').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no time: {message}"));
    assert!(time > 0.0 && time < END, "{message}");
    let (equation, element) = message
        .split_once("the redundant equation ")
        .and_then(|(_, rest)| rest.split_once(" (removed as consistent)"))
        .and_then(|(named, _)| named.rsplit_once(" of "))
        .unwrap_or_else(|| panic!("no equation and element: {message}"));
    assert!(!equation.is_empty() && !element.is_empty(), "{message}");
    let residual = message
        .split_once("residual ")
        .map(|(_, r)| r.trim())
        .unwrap_or_else(|| panic!("no residual: {message}"));
    match residual.strip_suffix(" deg") {
        // An angle: beyond 1e-6 rad.
        Some(deg) => {
            let radians = deg.parse::<f64>().unwrap().to_radians();
            assert!(radians.abs() > 1e-6, "{message}: within the tolerance");
        }
        // A length, in model units (beyond 1e-6 of the model's size).
        None => assert!(residual.parse::<f64>().unwrap().abs() > 0.0, "{message}"),
    }
}
