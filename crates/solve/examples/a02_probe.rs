//! Measures IFToMM A02 (N loops, 20 s, 400 outputs): max B0 error against the exact
//! one-degree-of-freedom reduction, steps, rejections, corrector iterations, factorisations,
//! thread CPU time. `cargo run --release -p linkage-solve --example a02_probe -- N ERROR [si2|i3]`;
//! with `TRACE=1` in the environment also the reference angle and the error at every output.
use linkage_model::settings::Formulation;
use linkage_model::Body;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::iftomm_a02;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;
use std::time::Instant;

fn cpu_time() -> f64 {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap();
    text.split_whitespace()
        .next()
        .unwrap()
        .parse::<f64>()
        .unwrap()
        * 1e-9
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(40);
    let error: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(1e-6);
    let formulation = match args.get(3).map(String::as_str) {
        Some("i3") => Formulation::I3,
        _ => Formulation::Si2,
    };
    let end = 20.0;
    let outputs = 400;
    let ds = linkage_adm::parse_dataset(Arc::from("a02.adm"), &iftomm_a02(n)).unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let times: Vec<f64> = (0..=outputs)
        .map(|k| end * k as f64 / outputs as f64)
        .collect();
    let settings = IntegratorSettings {
        error,
        formulation,
        ..IntegratorSettings::default()
    };
    let (c0, w0) = (cpu_time(), Instant::now());
    let a = Assembled::new(&m, &d, &NoForces, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let (cpu, wall) = (cpu_time() - c0, w0.elapsed().as_secs_f64());
    let sim = r.simulation.expect("ran");
    // Reference: J φ'' = −C cos φ by RK4, 200 steps per output.
    let nf = n as f64;
    let (j, c) = ((nf + 1.0) / 3.0 + nf, 9.81 * ((nf + 1.0) / 2.0 + nf));
    let f = |phi: f64| -c / j * phi.cos();
    let every = 200;
    let h = end / (outputs * every) as f64;
    let (mut y, mut v) = (std::f64::consts::FRAC_PI_2, -1.0);
    let mut refs = vec![y];
    for k in 0..outputs * every {
        let (k1y, k1v) = (v, f(y));
        let (k2y, k2v) = (v + 0.5 * h * k1v, f(y + 0.5 * h * k1y));
        let (k3y, k3v) = (v + 0.5 * h * k2v, f(y + 0.5 * h * k2y));
        let (k4y, k4v) = (v + h * k3v, f(y + h * k3y));
        y += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if (k + 1) % every == 0 {
            refs.push(y);
        }
    }
    let mk = m.markers.iter().find(|k| k.id == 203).unwrap();
    let mut worst = 0.0f64;
    for (o, phi) in sim.outputs.iter().zip(&refs) {
        let p = match mk.body {
            Body::Ground => mk.p_bm,
            Body::Part(k) => o.state.poses[k].p + o.state.poses[k].r * mk.p_bm,
        };
        let e = (p - glam::DVec3::new(phi.cos(), phi.sin(), 0.0)).length();
        if std::env::var_os("TRACE").is_some() {
            println!("t {:.3} phi {:.4} err {e:.3e}", o.time, phi);
        }
        worst = worst.max(e);
    }
    println!(
        "N={n} ERROR={error:e} {formulation:?}: err {worst:.3e} m, outputs {}, steps {}, rejected {}, iters {}, factorisations {}, cpu {cpu:.3} s, wall {wall:.3} s, failure {:?}",
        sim.outputs.len(), sim.steps, sim.rejected, sim.newton_iterations, sim.factorisations, sim.failure.map(|f| (f.time, f.message))
    );
}
