//! Times the phases of a simulation of a generated chain: `cargo run --release --example
//! profile_sim -- N [parallelogram|pendulum|swinging] [interval]` (parallelogram chain, 0.05 s
//! by default; `swinging`: the pendulum chain with gravity across it).
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{simulate, IntegratorSettings};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;
use std::time::Instant;

/// CPU time of this thread in seconds (Linux `/proc/thread-self/schedstat`), less sensitive
/// to other processes than the wall clock; `None` elsewhere.
fn cpu_time() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(100);
    let text = match args.get(2).map(String::as_str) {
        Some("pendulum") => linkage_solve::generate::pendulum_chain(n),
        // Gravity across the hanging chain: it swings.
        Some("swinging") => linkage_solve::generate::pendulum_chain(n)
            .replace("JGRAV = -9.80665", "IGRAV = -9.80665"),
        _ => linkage_solve::generate::parallelogram_chain(n, 60.0),
    };
    let interval: f64 = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(0.05);
    let ds = linkage_adm::parse_dataset(Arc::from("g.adm"), &text).expect("parses");
    let m = linkage_model::build_model(&ds).expect("builds").model;
    let d = ExpressionDrivers::new(&m).expect("functions");
    let t = Instant::now();
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let ic = &a.ic;
    println!(
        "verify + ic {:?} converged {} dof {}",
        t.elapsed(),
        ic.assembly.converged,
        ic.analysis.dof
    );
    let problem = a.problem(None, None);
    let v0 = a.velocities();
    let times: Vec<f64> = (0..=5).map(|k| interval * k as f64 / 5.0).collect();
    let t = Instant::now();
    let cpu = cpu_time();
    let sim = simulate(
        &problem,
        &ic.assembly.state,
        &v0,
        &times,
        &IntegratorSettings::default(),
        |_| {},
    );
    let el = t.elapsed();
    let cpu = cpu_time().zip(cpu).map_or(f64::NAN, |(b, a)| b - a);
    println!(
        "simulate {el:?}, cpu {cpu:.4} s ({:.3} s per simulated second) steps {} rejected {} failure {:?}",
        cpu / interval,
        sim.steps,
        sim.rejected,
        sim.failure
    );
}
