//! A dataset stepped as a co-simulation plant (`linkage_api::cosim`): the spring-mass-damper
//! plant of `tests/fmu/smd_plant.adm` against the closed form of its step response, a saved
//! state that gives the same step twice, and a step that fails with an error, not a panic.

use linkage_api::cosim::{ports, CosimError, Plant};
use linkage_solve::coverage::Analysis;
use std::path::PathBuf;

fn plant_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/fmu/smd_plant.adm")
}

fn plant() -> Plant {
    let loaded = linkage_api::load(&plant_path(), &[], Some(Analysis::Simulate)).unwrap();
    let ports = ports(&loaded.model, None, None).unwrap();
    Plant::new(loaded, ports)
}

/// m = 2 kg, k = 800 N/m, c = 40 N s/m (tests/fmu/smd_plant.adm).
const M: f64 = 2.0;
const K: f64 = 800.0;
const C: f64 = 40.0;

/// The position of the plant at rest at 0 under a force step `f` from time 0:
/// `z = f/k (1 − e^{−ζωt} (cos ω_d t + ζ/√(1−ζ²) sin ω_d t))`.
fn step_response(f: f64, t: f64) -> f64 {
    let w = (K / M).sqrt();
    let zeta = C / (2.0 * (K * M).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let decay = (-zeta * w * t).exp();
    f / K * (1.0 - decay * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin()))
}

#[test]
fn plant_ports_are_the_pinput_and_poutput_variables_with_their_names() {
    let p = plant();
    let ports = p.ports();
    assert_eq!((ports.pinput, ports.poutput), (None, None));
    let inputs: Vec<(u32, &str)> = ports
        .inputs
        .iter()
        .map(|p| (p.id, p.name.as_str()))
        .collect();
    let outputs: Vec<(u32, &str)> = ports
        .outputs
        .iter()
        .map(|p| (p.id, p.name.as_str()))
        .collect();
    assert_eq!(inputs, [(1, "force")]);
    assert_eq!(outputs, [(2, "position")]);
}

#[test]
fn stepped_spring_mass_damper_follows_the_closed_form_step_response() {
    let mut p = plant();
    p.initialize(false).unwrap();
    assert_eq!(p.outputs().unwrap(), [0.0]);
    let force = 100.0;
    p.set_input(0, force).unwrap();
    let h = 0.01;
    let final_value = force / K;
    let mut worst: f64 = 0.0;
    for n in 1..=100 {
        let t = n as f64 * h;
        p.step(t).unwrap();
        assert_eq!(p.time(), t);
        let z = p.outputs().unwrap()[0];
        worst = worst.max((z - step_response(force, t)).abs());
    }
    // Within 1e-3 of the final value (0.125 m) at every communication point over 1 s.
    assert!(worst < 1e-3 * final_value, "worst error {worst:e} m");
}

#[test]
fn initialisation_with_statics_starts_at_the_deflection_the_held_input_gives() {
    let mut p = plant();
    let force = 100.0;
    p.set_input(0, force).unwrap();
    p.initialize(true).unwrap();
    // Static equilibrium under the held force: z = F/k, and the step keeps it there.
    let z0 = p.outputs().unwrap()[0];
    assert!((z0 - force / K).abs() < 1e-9 * force / K, "{z0}");
    p.step(0.5).unwrap();
    let z = p.outputs().unwrap()[0];
    assert!((z - force / K).abs() < 1e-6 * force / K, "{z}");
}

#[test]
fn a_restored_state_steps_to_the_same_outputs() {
    let mut p = plant();
    p.initialize(false).unwrap();
    p.set_input(0, 50.0).unwrap();
    p.step(0.05).unwrap();
    let saved = p.save().unwrap();
    p.step(0.1).unwrap();
    let first = p.outputs().unwrap()[0];
    p.set_input(0, -50.0).unwrap();
    p.step(0.2).unwrap();
    p.restore(&saved).unwrap();
    assert_eq!(p.time(), 0.05);
    assert_eq!(p.inputs(), [50.0]);
    p.step(0.1).unwrap();
    let again = p.outputs().unwrap()[0];
    assert!(
        (first - again).abs() <= 1e-12 * first.abs(),
        "{first} vs {again}"
    );
}

#[test]
fn a_step_with_a_non_finite_input_fails_with_an_error() {
    let mut p = plant();
    p.initialize(false).unwrap();
    p.set_input(0, f64::NAN).unwrap();
    let err = p.step(0.1).unwrap_err();
    assert!(matches!(err, CosimError::Failed(_)), "{err}");
}

#[test]
fn ports_of_one_plant_list_or_of_every_one_each_variable_once() {
    let Some(path) =
        corpus("Dinh-Hao-Nguyen__MSCAdams_Wiper_Project__ControlSimulink__Controls_Plant_5.adm")
    else {
        return;
    };
    let loaded = linkage_api::load(&path, &[], Some(Analysis::Simulate)).unwrap();
    // Four PINPUTs and four POUTPUTs with the same VARIABLEs: each once.
    let all = ports(&loaded.model, None, None).unwrap();
    let ids = |p: &[linkage_api::cosim::Port]| p.iter().map(|p| p.id).collect::<Vec<_>>();
    assert_eq!(ids(&all.inputs), [32]);
    assert_eq!(ids(&all.outputs), [3, 2, 34, 33, 22]);
    assert_eq!(all.inputs[0].name, "matlab_torque");
    let one = ports(&loaded.model, Some(2), Some(4)).unwrap();
    assert_eq!(ids(&one.outputs), [3, 2, 34, 33, 22]);
    let err = ports(&loaded.model, Some(9), None).unwrap_err();
    assert_eq!(
        err.to_string(),
        "PINPUT/9 is not in the dataset (it has PINPUT 1, 2, 3, 4)"
    );
}

/// A corpus dataset, or `None` (with a notice) where the corpus is missing outside CI.
fn corpus(name: &str) -> Option<PathBuf> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/corpus")
        .join(name);
    if path.is_file() {
        return Some(path);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "{} is missing under CI",
        path.display()
    );
    eprintln!("skipped: {} is missing", path.display());
    None
}

#[test]
fn a_step_before_the_initialisation_is_refused() {
    let mut p = plant();
    assert!(matches!(p.step(0.1), Err(CosimError::NotInitialized)));
    assert!(matches!(
        p.set_input(3, 1.0),
        Err(CosimError::NoInput { index: 3, count: 1 })
    ));
}
