//! Verify on generated models of growing size (DESIGN §10).
//!
//! `parallelogram_chain(N)`: one closed-loop block of 2N + 1 parts, 15N + 5 rows, 3N redundant.
//! `pendulum_chain(N)`: a tree (N blocks of one joint each).

use linkage_solve::constraints::drivers::NoDrivers;
use linkage_solve::generate::{parallelogram_chain, pendulum_chain};
use linkage_solve::pipeline::verify::verify;
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

#[divan::bench(args = [10, 100, 1000, 5000], sample_count = 10)]
fn verify_parallelogram_chain(bencher: divan::Bencher, n: usize) {
    let m = model(&parallelogram_chain(n, 60.0));
    bencher.bench_local(|| {
        let v = verify(&m, &NoDrivers, &Tolerances::default());
        assert_eq!(v.redundant.len(), 3 * n);
        v.dof
    });
}

#[divan::bench(args = [10, 100, 1000, 10000], sample_count = 10)]
fn verify_pendulum_chain(bencher: divan::Bencher, n: usize) {
    let m = model(&pendulum_chain(n));
    bencher.bench_local(|| verify(&m, &NoDrivers, &Tolerances::default()).dof);
}

#[divan::bench(args = [100, 1000], sample_count = 10)]
fn read_and_build_parallelogram_chain(bencher: divan::Bencher, n: usize) {
    let text = parallelogram_chain(n, 60.0);
    bencher.bench_local(|| model(&text).parts.len());
}
