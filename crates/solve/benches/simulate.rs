//! Dynamic simulation on generated models (issue: dynamics performance). Each benchmark
//! simulates a short interval; wall time per simulated second = time / interval.
//!
//! `pendulum_chain(N)`: N links hanging in a chain (a tree, DOF N).
//! `parallelogram_chain(N)`: N parallelogram loops sharing cranks (DOF 1, 3N redundant rows).

use linkage_solve::applied::NoForces;
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::dynamics::{run, IntegratorSettings};
use linkage_solve::generate::{parallelogram_chain, pendulum_chain};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

fn main() {
    divan::main();
}

fn model(text: &str) -> linkage_model::Model {
    let ds = linkage_adm::parse_dataset(Arc::from("generated.adm"), text)
        .expect("generated dataset parses");
    linkage_model::build_model(&ds)
        .expect("generated model builds")
        .model
}

/// Simulated interval of every benchmark (seconds of model time).
const INTERVAL: f64 = 0.05;

fn simulate(m: &linkage_model::Model) -> usize {
    let d = ExpressionDrivers::new(m).expect("functions parse");
    let times: Vec<f64> = (0..=5).map(|k| INTERVAL * k as f64 / 5.0).collect();
    let r = run(
        m,
        &d,
        &NoForces,
        &Tolerances::default(),
        &times,
        &IntegratorSettings::default(),
        false,
        |_| {},
    );
    let sim = r.simulation.expect("simulation ran");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    sim.steps
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn pendulum_chain_per_interval(bencher: divan::Bencher, n: usize) {
    let m = model(&pendulum_chain(n));
    bencher.bench_local(|| simulate(&m));
}

// N = 1000 loops is left out: the corrector stagnates on that model (see the issue notes).
#[divan::bench(args = [10, 30, 100], sample_count = 3)]
fn parallelogram_chain_per_interval(bencher: divan::Bencher, n: usize) {
    let m = model(&parallelogram_chain(n, 60.0));
    bencher.bench_local(|| simulate(&m));
}
