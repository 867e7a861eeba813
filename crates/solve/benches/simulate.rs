//! Dynamic simulation on generated models (issue: dynamics performance), 5 outputs per run;
//! wall time per simulated second = time / simulated interval.
//!
//! `pendulum_chain(N)`: N links hanging in a chain (a tree, DOF N; at rest under gravity).
//! `swinging_chain(N)`: the same chain with gravity across it, so that it swings.
//! `parallelogram_chain(N)`: N parallelogram loops sharing cranks (DOF 1, 3N redundant rows).
//! `sprung_chain(N)`: the swinging chain with a torsion spring-damper at every joint, each an
//! SFORCE whose law is an expression of AZ and WZ (expression forces and their Jacobians).
//!
//! `parallelogram_chain_settle`: equilibrium by damped dynamics (settling and the polish).
//!
//! `*_run`: the whole dynamic analysis the CLI runs (initial conditions, then the
//! integration) over `SHORT` = 0.05 s of model time, where start-up costs weigh (the figures
//! of the issue); `*_integrate`: the integration alone, from the assembled start, over
//! `LONG` = 1 s, closer to the steady cost per simulated second.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::{parallelogram_chain, pendulum_chain};
use linkage_solve::physics::applied::{AppliedForces, NoForces};
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, simulate, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

fn main() {
    divan::main();
}

fn model(text: &str) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from("generated.adm"), text)
        .expect("generated dataset parses");
    linkage_model::build_model(&ds)
        .expect("generated model builds")
        .model
}

fn swinging_chain(n: usize) -> String {
    pendulum_chain(n).replace("JGRAV = -9.80665", "IGRAV = -9.80665")
}

fn sprung_chain(n: usize) -> String {
    let mut springs = String::new();
    for k in 0..n {
        let i = 100 + 10 * k;
        let j = if k == 0 { 1 } else { i - 9 };
        springs.push_str(&format!(
            "SFORCE/{}, I = {i}, J = {j}, ROTATION\n, FUNCTION = -20*AZ({i},{j}) - 0.5*WZ({i},{j},{j})\n",
            1 + k
        ));
    }
    swinging_chain(n).replace("END", &(springs + "END"))
}

/// Simulated intervals (seconds of model time).
const SHORT: f64 = 0.05;
const LONG: f64 = 1.0;

fn output_times(interval: f64) -> Vec<f64> {
    (0..=5).map(|k| interval * k as f64 / 5.0).collect()
}

/// The whole analysis: initial conditions, then the integration.
fn run_analysis(m: &Model) -> usize {
    let d = ExpressionDrivers::new(m).expect("functions parse");
    let a = Assembled::new(m, &d, &NoForces, &Tolerances::default());
    let r = run(
        &a,
        &output_times(SHORT),
        &IntegratorSettings::default(),
        Start::InitialConditions,
        |_| {},
    );
    let sim = r.simulation.expect("simulation ran");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    sim.steps
}

/// Times the integration alone: initial conditions are computed once, outside the timing.
fn bench_integration(bencher: divan::Bencher, m: &Model, forces: &dyn AppliedForces) {
    let d = ExpressionDrivers::new(m).expect("functions parse");
    let a = Assembled::new(m, &d, forces, &Tolerances::default());
    assert!(a.failure().is_none());
    let problem = a.problem(None, None);
    let v0 = a.velocities();
    let times = output_times(LONG);
    bencher.bench_local(|| {
        let sim = simulate(
            &problem,
            a.state(),
            &v0,
            &times,
            &IntegratorSettings::default(),
            |_| {},
        );
        assert!(sim.failure.is_none(), "{:?}", sim.failure);
        sim.steps
    });
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn pendulum_chain_run(bencher: divan::Bencher, n: usize) {
    let m = model(&pendulum_chain(n));
    bencher.bench_local(|| run_analysis(&m));
}

#[divan::bench(args = [10, 30, 100, 1000], sample_count = 3)]
fn parallelogram_chain_run(bencher: divan::Bencher, n: usize) {
    let m = model(&parallelogram_chain(n, 60.0));
    bencher.bench_local(|| run_analysis(&m));
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn pendulum_chain_integrate(bencher: divan::Bencher, n: usize) {
    bench_integration(bencher, &model(&pendulum_chain(n)), &NoForces);
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn swinging_chain_integrate(bencher: divan::Bencher, n: usize) {
    bench_integration(bencher, &model(&swinging_chain(n)), &NoForces);
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn parallelogram_chain_integrate(bencher: divan::Bencher, n: usize) {
    bench_integration(bencher, &model(&parallelogram_chain(n, 60.0)), &NoForces);
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn sprung_chain_integrate(bencher: divan::Bencher, n: usize) {
    let m = model(&sprung_chain(n));
    let forces = linkage_solve::physics::forces::ForceSet::new(&m).expect("the springs build");
    bench_integration(bencher, &m, &forces);
}

/// Dynamic settling (EQUILIBRIUM/DYNAMIC): the parallelogram chain released at 60° with
/// GLOBAL_DAMPING 2 settles after about 8 time units (frozen time, one integration watched at
/// 400 outputs), then the Newton polish; initial conditions included.
#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn parallelogram_chain_settle(bencher: divan::Bencher, n: usize) {
    let text = parallelogram_chain(n, 60.0).replace(
        "END",
        "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 2, SETTLING_TIME = 50\nEND",
    );
    let m = model(&text);
    let d = ExpressionDrivers::new(&m).expect("functions parse");
    bencher.bench_local(|| {
        let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
        let outcome = linkage_solve::stages::settle::settle(&a, |_| {}).expect("assembled");
        assert!(
            outcome.settled_equilibrium().is_some(),
            "{:?}",
            outcome.stop
        );
        outcome.time_used
    });
}
