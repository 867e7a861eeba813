//! Measures a cart with an inverted pendulum (the dataset of `tests/error_control.rs`)
//! against its Lagrange equations integrated by RK4:
//! `cargo run --release -p linkage-solve --example cart_probe -- ERROR [HMAX|-] [i3|si2|hht]`.
//! Prints the worst cart-velocity difference over 10 s relative to its range, steps, CPU s.
use linkage_model::settings::{Formulation, IntegratorMethod};
use linkage_solve::constraints::drivers::ExpressionDrivers;
#[path = "../tests/common/cart_pendulum.rs"]
#[allow(dead_code)]
mod cart_pendulum;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Start};
use linkage_solve::tolerances::Tolerances;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let error: f64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1e-3);
    let hmax: Option<f64> = args.get(2).and_then(|a| a.parse().ok());
    let (method, formulation) = match args.get(3).map(String::as_str) {
        Some("si2") => (IntegratorMethod::Bdf, Formulation::Si2),
        Some("hht") => (IntegratorMethod::Hht, Formulation::I3),
        _ => (IntegratorMethod::Bdf, Formulation::I3),
    };
    let end = 10.0;
    let outputs = 1000;
    let ds = linkage_adm::parse_dataset(
        Arc::from("cart.adm"),
        &cart_pendulum::dataset_in(std::env::var_os("MM").is_some()),
    )
    .unwrap();
    let m = linkage_model::build_model(&ds).unwrap().model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap();
    let times: Vec<f64> = (0..=outputs)
        .map(|k| end * k as f64 / outputs as f64)
        .collect();
    let settings = IntegratorSettings {
        method,
        error,
        hmax,
        formulation,
        alpha: if method == IntegratorMethod::Hht {
            -0.3
        } else {
            0.0
        },
        kmax: std::env::var("KMAX")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(6),
        ..IntegratorSettings::default()
    };
    let w0 = Instant::now();
    let a = Assembled::new(&m, &d, &f, &Tolerances::default());
    let r = run(&a, &times, &settings, Start::InitialConditions, |_| {});
    let wall = w0.elapsed().as_secs_f64();
    let sim = r.simulation.expect("ran");
    let reference = cart_pendulum::reference(end, outputs);
    let range = reference.iter().map(|r| r.1).fold(f64::MIN, f64::max)
        - reference.iter().map(|r| r.1).fold(f64::MAX, f64::min);
    let scale = if std::env::var_os("MM").is_some() {
        1e3
    } else {
        1.0
    };
    let mut worst = 0.0f64;
    let mut worst_x = 0.0f64;
    for (o, (x, v)) in sim.outputs.iter().zip(&reference) {
        if std::env::var_os("TRACE").is_some() && (o.time * 10.0).fract().abs() < 1e-9 {
            eprintln!(
                "t {:.2} x {x:.5} v {v:.5} dv {:.3e} th {:.4}",
                o.time,
                o.velocities[0].0.x / scale - v,
                o.state.poses[1]
                    .r
                    .x_axis
                    .y
                    .atan2(o.state.poses[1].r.x_axis.x)
            );
        }
        worst = worst.max((o.velocities[0].0.x / scale - v).abs());
        worst_x = worst_x.max((o.state.poses[0].p.x / scale - x).abs());
    }
    println!(
        "ERROR {error:e} HMAX {hmax:?} {method:?} {formulation:?}: cart velocity off by {:.3e} of range \
         (position {worst_x:.2e} m), outputs {}, steps {}, rejected {}, iterations {}, factorisations {}, {wall:.2} s{}",
        worst / range,
        sim.outputs.len(),
        sim.steps,
        sim.rejected,
        sim.newton_iterations,
        sim.factorisations,
        sim.failure.as_ref().map(|f| format!(" FAILED {f:?}")).unwrap_or_default()
    );
}
