//! Times the phases of a simulation of a generated chain: `cargo run --release --example
//! profile_sim -- N`.
use linkage_solve::applied::NoForces;
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100);
    let text = if std::env::args().nth(2).as_deref() == Some("pendulum") {
        linkage_solve::generate::pendulum_chain(n)
    } else {
        linkage_solve::generate::parallelogram_chain(n, 60.0)
    };
    let ds = linkage_adm::parse_dataset(Arc::from("g.adm"), &text).expect("parses");
    let m = linkage_model::build_model(&ds).expect("builds").model;
    let d = ExpressionDrivers::new(&m).expect("functions");
    let t = Instant::now();
    let v = linkage_solve::verify::verify(&m, &d, &Tolerances::default());
    println!("verify {:?} dof {}", t.elapsed(), v.dof);
    let t = Instant::now();
    let ic = linkage_solve::ic::initial_conditions(&m, &d, &NoForces, &Tolerances::default());
    println!("ic {:?} converged {}", t.elapsed(), ic.assembly.converged);
    let t = Instant::now();
    let times: Vec<f64> = (0..=5).map(|k| 0.01 * k as f64).collect();
    let r = linkage_solve::dynamics::run(
        &m,
        &d,
        &NoForces,
        &Tolerances::default(),
        &times,
        &Default::default(),
        false,
        |_| {},
    );
    let sim = r.simulation.expect("ran");
    println!(
        "run (incl. ic) {:?} steps {} rejected {} failure {:?}",
        t.elapsed(),
        sim.steps,
        sim.rejected,
        sim.failure
    );
}
