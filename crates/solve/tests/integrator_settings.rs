//! Every INTEGRATOR argument has an effect on a run, or the run's notes name it as unused:
//! ERROR, HMAX, HMIN, HINIT, KMAX, MAXIT and ALPHA change what the integrator does (step
//! counts, iterations, results, measured on the IFToMM A01 pendulum over 2 s); the integrator
//! names and formulations (GSTIFF, WSTIFF, CONSTANT_BDF, HHT, NEWMARK × I3, SI2, SI1) run what
//! their notes say; PATTERN, INTERPOLATE, BETA and GAMMA, ALPHA with a BDF and KMAX with HHT
//! are named as without effect.

use linkage_model::settings::{Formulation, IntegratorMethod, IntegratorNote};
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, Simulation, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

const A01: &str = include_str!("data/benchmarks/a01_pendulum.adm");

/// A01 with `integrator` (the text of an INTEGRATOR statement, or empty) built into a model.
fn model(integrator: &str) -> Model {
    let text = A01.replace("END", &format!("{integrator}\nEND"));
    let ds = linkage_adm::parse_dataset(Arc::from("a01.adm"), &text).expect("parses");
    linkage_model::build_model(&ds).expect("builds").model
}

/// The model's run over `end` seconds with 20 outputs, with the settings its INTEGRATOR
/// statement resolved to.
fn simulate(m: &Model, end: f64) -> Simulation {
    let drivers = ExpressionDrivers::new(m).unwrap();
    let forces = ForceSet::new(m).unwrap();
    let times: Vec<f64> = (0..=20).map(|k| end * k as f64 / 20.0).collect();
    let a = Assembled::new(m, &drivers, &forces, &Tolerances::default());
    let r = run(
        &a,
        &times,
        &m.integrator.settings,
        Start::InitialConditions,
        |_| {},
    );
    let sim = r.simulation.expect("ran");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    assert_eq!(sim.outputs.len(), 21);
    sim
}

fn run_with(integrator: &str) -> Simulation {
    simulate(&model(integrator), 2.0)
}

/// The x of the pendulum's CM at the last output.
fn last_x(sim: &Simulation) -> f64 {
    sim.outputs.last().unwrap().state.poses[0].p.x
}

fn notes(integrator: &str) -> Vec<String> {
    model(integrator)
        .integrator
        .notes
        .iter()
        .map(ToString::to_string)
        .collect()
}

#[test]
fn error_sets_the_number_of_steps() {
    let coarse = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-3");
    let fine = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-7");
    assert!(
        fine.steps > 3 * coarse.steps,
        "{} vs {}",
        fine.steps,
        coarse.steps
    );
}

#[test]
fn hmax_bounds_every_step() {
    let sim = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-3, HMAX = 1E-3");
    // 2 s in steps of at most 1e-3 s.
    assert!(sim.steps >= 2000, "{} steps", sim.steps);
}

#[test]
fn hmin_keeps_steps_from_shrinking_below_it() {
    // ERROR asks for steps far below 0.01 s; HMIN holds them there (a step at HMIN is
    // accepted whatever its estimate).
    let free = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-10");
    let held = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-10, HMIN = 0.01");
    assert!(held.steps <= 200 + 20, "{} steps", held.steps);
    assert!(
        free.steps > 2 * held.steps,
        "{} vs {}",
        free.steps,
        held.steps
    );
}

#[test]
fn hinit_sets_the_first_step() {
    // From 1e-9 s the step at most doubles per step: it takes more steps to reach the size
    // the default first step (span/1000) starts near (measured 83 steps against 70).
    let default = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-3");
    let tiny = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-3, HINIT = 1E-9");
    assert!(
        tiny.steps >= default.steps + 10,
        "{} vs {}",
        tiny.steps,
        default.steps
    );
}

#[test]
fn kmax_limits_the_bdf_order() {
    // Backward Euler (order 1) needs far more steps for the same ERROR than orders up to 6.
    let one = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-5, KMAX = 1");
    let six = run_with("INTEGRATOR/GSTIFF, ERROR = 1E-5, KMAX = 6");
    assert!(one.steps > 5 * six.steps, "{} vs {}", one.steps, six.steps);
}

#[test]
fn maxit_bounds_the_corrector_iterations_of_every_step() {
    let m = model("INTEGRATOR/GSTIFF, ERROR = 1E-6, MAXIT = 5");
    assert_eq!(m.integrator.settings.maxit, 5);
    let sim = simulate(&m, 2.0);
    // Each accepted or rejected step runs at most MAXIT iterations.
    assert!(sim.newton_iterations <= 5 * (sim.steps + sim.rejected));
}

#[test]
fn alpha_sets_the_numerical_damping_of_hht() {
    // More damping (α = −0.3) against nearly none (α = −0.01): the step counts and the
    // results differ; both stay near the pendulum's motion.
    let damped = run_with("INTEGRATOR/HHT, ERROR = 1E-5, ALPHA = -0.3");
    let light = run_with("INTEGRATOR/HHT, ERROR = 1E-5, ALPHA = -0.01");
    assert_ne!(damped.steps, light.steps);
    let (a, b) = (last_x(&damped), last_x(&light));
    assert!(a != b && (a - b).abs() < 1e-2, "{a} vs {b}");
}

#[test]
fn si2_integrates_another_formulation_and_si1_runs_as_si2() {
    let i3 = model("INTEGRATOR/GSTIFF, I3, ERROR = 1E-5");
    let si2 = model("INTEGRATOR/GSTIFF, SI2, ERROR = 1E-5");
    let si1 = model("INTEGRATOR/GSTIFF, SI1, ERROR = 1E-5");
    assert_eq!(i3.integrator.settings.formulation, Formulation::I3);
    assert_eq!(si2.integrator.settings.formulation, Formulation::Si2);
    assert_eq!(si1.integrator.settings.formulation, Formulation::Si2);
    assert!(si1.integrator.notes.contains(&IntegratorNote::Si1AsSi2));
    let (a, b) = (simulate(&i3, 2.0), simulate(&si2, 2.0));
    assert_ne!(last_x(&a), last_x(&b));
    assert!((last_x(&a) - last_x(&b)).abs() < 1e-3);
    // HHT has the index-3 form only, and says so.
    assert_eq!(
        notes("INTEGRATOR/HHT, SI2"),
        ["INTEGRATOR SI2: HHT integrates the index-3 (I3) formulation"]
    );
}

#[test]
fn gstiff_and_wstiff_run_the_same_variable_coefficient_bdf_and_gstiff_says_so() {
    let g = model("INTEGRATOR/GSTIFF, ERROR = 1E-5");
    let w = model("INTEGRATOR/WSTIFF, ERROR = 1E-5");
    assert_eq!(g.integrator.settings, w.integrator.settings);
    assert!(w.integrator.notes.is_empty(), "{:?}", w.integrator.notes);
    assert_eq!(
        g.integrator.notes,
        [IntegratorNote::GstiffAsVariableCoefficient]
    );
    assert_eq!(last_x(&simulate(&g, 2.0)), last_x(&simulate(&w, 2.0)));
}

#[test]
fn constant_bdf_and_newmark_run_what_their_notes_say() {
    let c = model("INTEGRATOR/CONSTANT_BDF, HMAX = 0.01");
    assert!(c.integrator.settings.constant_step);
    let sim = simulate(&c, 2.0);
    assert_eq!((sim.steps, sim.rejected), (200, 0));
    let n = model("INTEGRATOR/NEWMARK, ALPHA = -0.1");
    assert_eq!(n.integrator.settings.method, IntegratorMethod::Hht);
    assert_eq!(
        notes("INTEGRATOR/NEWMARK, ALPHA = -0.1"),
        ["INTEGRATOR NEWMARK is mapped to linkage's HHT-I3 integrator (α = -0.1)"]
    );
}

#[test]
fn arguments_linkage_does_not_use_are_named() {
    assert_eq!(
        notes("INTEGRATOR/WSTIFF, PATTERN = T:F, INTERPOLATE = ON"),
        ["INTEGRATOR arguments without effect in linkage: PATTERN, INTERPOLATE"]
    );
    assert_eq!(
        notes("INTEGRATOR/NEWMARK, BETA = 0.25, GAMMA = 0.5"),
        [
            "INTEGRATOR NEWMARK is mapped to linkage's HHT-I3 integrator (α = -0.3)",
            "INTEGRATOR arguments without effect in linkage: BETA, GAMMA"
        ]
    );
    assert_eq!(
        notes("INTEGRATOR/WSTIFF, ALPHA = -0.1"),
        ["INTEGRATOR WSTIFF does not use ALPHA"]
    );
    assert_eq!(
        notes("INTEGRATOR/HHT, KMAX = 3"),
        ["INTEGRATOR HHT does not use KMAX"]
    );
}
