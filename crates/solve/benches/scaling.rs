//! How each analysis scales with model size (DESIGN §10): verify, ic, static, linear and
//! simulate on generated models of growing size, each timed at three or four sizes (the
//! median of `RUNS` runs) and summarised by its size exponent `p`, the least-squares slope of
//! `log t` against `log N` (`t ∝ N^p`: 1 is linear).
//!
//! * verify, ic, static: `parallelogram_chain(N)` (N loops, 2N + 1 parts, 3N redundant rows;
//!   ic and static include the verification that chooses the kept rows);
//! * linear: `hanging_chain(N)` (N rods on spherical joints: 2N swinging modes and N free
//!   spins), the 20 lowest modes without vectors (`linear --modes 20 --no-vectors`), from the
//!   assembled start;
//! * simulate: `pendulum_chain(N)` from the initial conditions over 0.05 s, 5 outputs.
//!
//! Run with `cargo bench -p linkage-solve --bench scaling` (a few minutes; the machine's
//! other load shows in the spread, which is printed). Model text is read and built outside the
//! timing.

use linkage_model::Model;
use linkage_solve::constraints::drivers::{ExpressionDrivers, NoDrivers};
use linkage_solve::generate::{hanging_chain, parallelogram_chain, pendulum_chain};
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::stages::linearize::{EigenMethod, LinearOptions};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;
use std::time::Instant;

/// Timed runs per size (the median is reported).
const RUNS: usize = 3;

fn model(text: &str) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from("generated.adm"), text)
        .expect("generated dataset parses");
    linkage_model::build_model(&ds)
        .expect("generated model builds")
        .model
}

/// Median, min and max seconds of `RUNS` runs of `f`.
fn time(mut f: impl FnMut()) -> (f64, f64, f64) {
    let mut t: Vec<f64> = (0..RUNS)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[RUNS / 2], t[0], t[RUNS - 1])
}

/// Least-squares slope of `log t` against `log n`.
fn exponent(points: &[(usize, f64)]) -> f64 {
    let xs: Vec<f64> = points.iter().map(|(n, _)| (*n as f64).ln()).collect();
    let ys: Vec<f64> = points.iter().map(|(_, t)| t.ln()).collect();
    let k = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Times `run(model)` at each size and prints the table and the exponent.
fn stage(name: &str, sizes: &[usize], text: fn(usize) -> String, run: fn(&Model)) {
    let mut points = Vec::new();
    for &n in sizes {
        let m = model(&text(n));
        let (median, lo, hi) = time(|| run(&m));
        println!("{name:<8} N = {n:>6}: {median:>9.4} s  (min {lo:.4}, max {hi:.4})");
        points.push((n, median));
    }
    println!("{name:<8} size exponent {:.2}\n", exponent(&points));
}

fn parallelogram(n: usize) -> String {
    parallelogram_chain(n, 60.0)
}

fn assembled(m: &Model, f: impl FnOnce(&Assembled)) {
    let d = ExpressionDrivers::new(m).expect("functions parse");
    let a = Assembled::new(m, &d, &NoForces, &Tolerances::default());
    assert!(a.failure().is_none());
    f(&a);
}

fn main() {
    stage("verify", &[1000, 3000, 10000], parallelogram, |m| {
        let v = linkage_solve::pipeline::verify::verify(m, &NoDrivers, &Tolerances::default());
        assert_eq!(v.dof, 1);
    });
    stage("ic", &[300, 1000, 3000], parallelogram, |m| {
        assembled(m, |_| {})
    });
    stage("static", &[300, 1000, 3000], parallelogram, |m| {
        assembled(m, |a| {
            let r = linkage_solve::stages::statics::run(a, &[0.0]);
            assert!(matches!(r.steps.first(), Some((_, Ok(e))) if e.converged));
        })
    });
    stage("linear", &[100, 300, 1000, 3000], hanging_chain, |m| {
        assembled(m, |a| {
            let opts = LinearOptions {
                damping: true,
                vectors: false,
                method: EigenMethod::ShiftInvert {
                    modes: 20,
                    shift: None,
                },
            };
            let l = linkage_solve::stages::linearize::run(a, false, opts)
                .result
                .expect("linearized");
            assert_eq!(l.modes.len(), 20);
        })
    });
    stage("simulate", &[10, 30, 100], pendulum_chain, |m| {
        let d = ExpressionDrivers::new(m).expect("functions parse");
        let a = Assembled::new(m, &d, &NoForces, &Tolerances::default());
        let times: Vec<f64> = (0..=5).map(|k| 0.05 * k as f64 / 5.0).collect();
        let r = run(
            &a,
            &times,
            &IntegratorSettings::default(),
            Start::InitialConditions,
            |_| {},
        );
        let sim = r.simulation.expect("simulation ran");
        assert!(sim.failure.is_none(), "{:?}", sim.failure);
    });
}
