//! IFToMM A02, the N four-bar chain (`generate::iftomm_a02`): the whole 20 s dynamic run at
//! INTEGRATOR ERROR = 1e-6 with 400 outputs, as the benchmark asks, for N = 2, 10 and 40 (the
//! published N = 40 has 120 redundant equations and passes a singular pose every half turn).
//! Accuracy against the exact one-degree-of-freedom reduction is asserted by
//! `tests/benchmarks.rs` (measured at ERROR = 1e-6, I3: 1.8e-5, 1.6e-4 and 7.6e-4 m; SI2 on
//! N = 40: 1.15e-4 m); this bench gives the seconds of both formulations, and prints
//! the steps taken once per case.

use linkage_model::settings::Formulation;
use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::iftomm_a02;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;

fn main() {
    divan::main();
}

/// The benchmark's span and outputs.
const END: f64 = 20.0;
const OUTPUTS: usize = 400;

fn model(n: usize) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from("a02.adm"), &iftomm_a02(n))
        .expect("generated dataset parses");
    linkage_model::build_model(&ds)
        .expect("generated model builds")
        .model
}

/// The whole analysis (initial conditions, integration): steps taken.
fn run_a02(m: &Model, formulation: Formulation) -> usize {
    let d = ExpressionDrivers::new(m).expect("functions parse");
    let a = Assembled::new(m, &d, &NoForces, &Tolerances::default());
    let times: Vec<f64> = (0..=OUTPUTS)
        .map(|k| END * k as f64 / OUTPUTS as f64)
        .collect();
    let settings = IntegratorSettings {
        error: 1e-6,
        formulation,
        ..IntegratorSettings::default()
    };
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let sim = r.simulation.expect("simulation ran");
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    sim.steps
}

#[divan::bench(args = [2, 10, 40], sample_count = 3)]
fn a02_20_s(bencher: divan::Bencher, n: usize) {
    let m = model(n);
    eprintln!("A02 N = {n}, I3: {} steps", run_a02(&m, Formulation::I3));
    bencher.bench_local(|| run_a02(&m, Formulation::I3));
}

#[divan::bench(args = [2, 10, 40], sample_count = 3)]
fn a02_20_s_si2(bencher: divan::Bencher, n: usize) {
    let m = model(n);
    eprintln!("A02 N = {n}, SI2: {} steps", run_a02(&m, Formulation::Si2));
    bencher.bench_local(|| run_a02(&m, Formulation::Si2));
}
