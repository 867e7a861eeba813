//! Linearization on generated models of growing size (issue #6: performance).
//!
//! Each benchmark times `linearize` alone (assembly of M, C, K, J and the eigen solution) at
//! the operating point the initial conditions give, computed once outside the timing.
//!
//! `pendulum_chain(N)`: N links hanging in a chain (a tree, DOF N, 6N coordinates): the dense
//! solution (every mode) up to where it is sensible, and shift-invert for the K = 10 lowest.
//! `parallelogram_chain(N)`: 2N + 1 parts and 3N redundant rows left out of J, DOF 1.

use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::{parallelogram_chain, pendulum_chain};
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{linearize, EigenMethod, LinearOptions, OperatingPoint};
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

/// Times `linearize` with `method` at the model's initial-conditions operating point; returns
/// the number of modes found (checked against `expect`).
fn bench_linearize(bencher: divan::Bencher, text: &str, method: EigenMethod, expect: usize) {
    let m = model(text);
    let d = ExpressionDrivers::new(&m).expect("functions parse");
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let ic = &a.ic;
    let rows = &a.kept;
    let v = ic
        .velocity
        .as_ref()
        .expect("velocity IC")
        .velocities
        .clone();
    let lambda = ic
        .acceleration
        .as_ref()
        .expect("acceleration IC")
        .as_ref()
        .expect("acceleration IC solved")
        .multipliers
        .clone();
    let sys = &a.system;
    let opts = LinearOptions {
        damping: true,
        vectors: true,
        method,
    };
    bencher.bench_local(|| {
        let at = OperatingPoint {
            state: &ic.assembly.state,
            velocities: &v,
            multipliers: &lambda,
        };
        let l = linearize(&m, sys, rows, &NoForces, at, opts).expect("linearization");
        assert_eq!(l.modes.len(), expect);
        l.modes.len()
    });
}

const K: usize = 10;

#[divan::bench(args = [10, 100, 200, 300], sample_count = 3)]
fn pendulum_chain_dense(bencher: divan::Bencher, n: usize) {
    bench_linearize(bencher, &pendulum_chain(n), EigenMethod::Dense, n);
}

#[divan::bench(args = [10, 100, 300, 1000, 3000], sample_count = 3)]
fn pendulum_chain_shift_invert(bencher: divan::Bencher, n: usize) {
    let method = EigenMethod::ShiftInvert {
        modes: K,
        shift: None,
    };
    bench_linearize(bencher, &pendulum_chain(n), method, K);
}

#[divan::bench(args = [10, 100, 1000], sample_count = 3)]
fn parallelogram_chain_shift_invert(bencher: divan::Bencher, n: usize) {
    let method = EigenMethod::ShiftInvert {
        modes: K,
        shift: None,
    };
    // DOF 1: the two eigenvalues are all there is (a real pair ±a at 60°: two modes).
    bench_linearize(bencher, &parallelogram_chain(n, 60.0), method, 2);
}
