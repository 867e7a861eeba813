//! Dynamic simulation against closed forms and conservation laws.

use linkage_model::Model;
use linkage_solve::applied::NoForces;
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::dynamics::{run, DynamicRun, IntegratorSettings};
use linkage_solve::tolerances::Tolerances;
use std::path::Path;
use std::sync::Arc;

const G: f64 = 9.80665;

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn simulate(name: &str, text: &str, end: f64, steps: usize, error: f64) -> (Model, DynamicRun) {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let settings = IntegratorSettings {
        error,
        ..Default::default()
    };
    let r = run(
        &m,
        &d,
        &NoForces,
        &Tolerances::default(),
        &times,
        &settings,
        false,
        |_| {},
    );
    (m, r)
}

/// Complete elliptic integral of the first kind K(k) by the arithmetic–geometric mean.
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..30 {
        let (an, bn) = ((a + b) / 2.0, (a * b).sqrt());
        a = an;
        b = bn;
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn compound_pendulum_released_from_30_degrees_has_the_elliptic_period() {
    let (_, r) = simulate(
        "pendulum_offset.adm",
        &mechanism_text("pendulum_offset.adm"),
        3.0,
        3000,
        1e-7,
    );
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    // Angular velocity about z changes sign at each extreme: half a period apart.
    let w: Vec<(f64, f64)> = sim
        .outputs
        .iter()
        .map(|o| (o.time, o.velocities[0].1.z))
        .collect();
    let mut crossings = Vec::new();
    for pair in w.windows(2) {
        let ((t0, w0), (t1, w1)) = (pair[0], pair[1]);
        if w0 != 0.0 && w0.signum() != w1.signum() && t0 > 0.0 {
            crossings.push(t0 + (t1 - t0) * w0 / (w0 - w1));
        }
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let period = 2.0 * (crossings[2] - crossings[0]) / 2.0;
    // T = 4 √(I_pivot / (m g d)) K(sin(θ0/2)), I_pivot = m L²/3, d = L/2, L = 1.
    let expected = 4.0 * (2.0 / (3.0 * G)).sqrt() * ellip_k((15f64).to_radians().sin());
    assert!(
        (period - expected).abs() < 1e-4 * expected,
        "period {period} vs {expected}"
    );
}

#[test]
fn conservative_double_pendulum_keeps_its_energy() {
    // Two unit rods started horizontal-ish: lift the chain by rotating the input.
    let text =
        linkage_solve::generate::pendulum_chain(2).replace("JGRAV = -9.80665", "IGRAV = -9.80665");
    let (m, r) = simulate("double.adm", &text, 10.0, 1000, 1e-6);
    let sim = r.simulation.as_ref().unwrap();
    assert!(sim.failure.is_none(), "{:?}", sim.failure);
    let energy = |o: &linkage_solve::dynamics::Output| {
        m.parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let (v, w) = o.velocities[k];
                let ig = o.state.poses[k].r * p.inertia * o.state.poses[k].r.transpose();
                0.5 * p.mass * v.length_squared() + 0.5 * w.dot(ig * w)
                    - p.mass * m.gravity.dot(o.state.poses[k].p)
            })
            .sum::<f64>()
    };
    let e0 = energy(&sim.outputs[0]);
    let scale = 2.0 * G * 2.0; // m g × (height range) of the chain
    let drift = sim
        .outputs
        .iter()
        .map(|o| (energy(o) - e0).abs())
        .fold(0.0, f64::max);
    assert!(drift < 1e-3 * scale, "energy drift {drift} (scale {scale})");
    assert_eq!(sim.outputs.len(), 1001);
}
