//! The IFToMM multibody benchmarks A01, A02 and A04 and Andrews' squeezing mechanism (Hairer
//! and Wanner), as datasets (`tests/data/benchmarks/`) run through the dynamic simulation and
//! compared with references computed here by independent means (issue 15):
//!
//! - A01 simple pendulum: the exact solution by Jacobi elliptic functions (AGM);
//! - A02 N four-bar chain: the exact one-degree-of-freedom reduction (a parallelogram chain:
//!   every crank turns by the same angle, the couplers translate), integrated by RK4 with a
//!   small fixed step;
//! - A04 Bricard mechanism: a minimal-coordinate formulation (loop closure solved by
//!   Gauss–Newton for the other five joint angles, Lagrange's equation in the first joint
//!   angle) integrated by RK4, plus energy and loop closure at every output;
//! - Andrews' squeezer: the published reference angles at t = 0.03 s.
//!
//! Every test prints its measured error, steps and run time (`--nocapture`). Measured with the
//! default BDF integrator (I3) at ERROR = 1e-6 (max error over every output): A01 over 2000 s
//! 1.2e-5 m; A02 N = 2, 10, 40 over 20 s 1.8e-5, 1.6e-4, 7.6e-4 m (2130, 1686, 2234 steps);
//! A04 3.7e-7 m; Andrews 1.5e-8 relative. With SI2 (`Formulation::Si2`): A01 over 2000 s
//! 1.8e-5 m, A02 N = 2, 10 2.8e-5, 3.9e-4 m (2133, 1762 steps), N = 40 1.15e-4 m (2277
//! steps), A04 5.5e-7 m, Andrews 1.1e-8. A02 with N = 40 is held to the benchmark with I3 and SI2. Its
//! error at the 26 flat (singular) poses does not follow ERROR smoothly; SI2 at 1e-7 leaves
//! the parallelogram branch and stops at 10.5 s (a singular velocity projection). The
//! measurement tables are `#[ignore]`d: run them with
//! `cargo test --release -p linkage-solve --test benchmarks -- --ignored --nocapture`.

use glam::{DMat3, DVec3};
use linkage_model::settings::{Formulation, IntegratorMethod};
use linkage_model::{Body, Model};
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::iftomm_a02;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::dynamics::{run, IntegratorSettings, Output, Simulation, Start};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Gravity of the IFToMM problems (m/s², along −y).
const G: f64 = 9.81;

/// The INTEGRATOR ERROR at which the benchmarks are held to the tolerances (BDF, the
/// default integrator: ERROR bounds the error accumulated over the run).
const BENCHMARK_ERROR: f64 = 1e-6;

fn data_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/benchmarks")
        .join(name)
}

fn dataset(name: &str) -> String {
    std::fs::read_to_string(data_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A finished dynamic run and its wall-clock time.
struct Run {
    model: Model,
    sim: Simulation,
    seconds: f64,
}

/// Simulates `text` from its initial conditions with outputs at `steps` equal intervals up to
/// `end`, at INTEGRATOR ERROR `error`, with the dataset's force elements. Panics when the model
/// does not build or assemble; a failure during the integration is left in `sim.failure`.
fn simulate(name: &str, text: &str, end: f64, steps: usize, error: f64) -> Run {
    simulate_as(name, text, end, steps, error, Formulation::I3)
}

/// [`simulate`] with the BDF in the given formulation.
fn simulate_as(
    name: &str,
    text: &str,
    end: f64,
    steps: usize,
    error: f64,
    formulation: Formulation,
) -> Run {
    let settings = IntegratorSettings {
        error,
        formulation,
        ..Default::default()
    };
    simulate_settings(name, text, end, steps, &settings)
}

/// [`simulate`] with the given integrator settings.
fn simulate_settings(
    name: &str,
    text: &str,
    end: f64,
    steps: usize,
    settings: &IntegratorSettings,
) -> Run {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let model = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let drivers = ExpressionDrivers::new(&model).unwrap();
    let forces = ForceSet::new(&model).unwrap();
    let times: Vec<f64> = (0..=steps).map(|k| end * k as f64 / steps as f64).collect();
    let start = Instant::now();
    let sim = {
        let a = Assembled::new(&model, &drivers, &forces, &Tolerances::default());
        let r = run(&a, &times, settings, Start::InitialConditions, |_| {});
        r.simulation
            .unwrap_or_else(|| panic!("{name}: not run: {:?}", r.error))
    };
    let seconds = start.elapsed().as_secs_f64();
    Run {
        model,
        sim,
        seconds,
    }
}

/// Index of a marker by its id.
fn marker(m: &Model, id: u64) -> usize {
    m.markers
        .iter()
        .position(|k| k.id == id)
        .unwrap_or_else(|| panic!("no MARKER/{id}"))
}

/// Position of marker `id` (ground) at an output.
fn position(m: &Model, o: &Output, id: u64) -> DVec3 {
    let mk = &m.markers[marker(m, id)];
    match mk.body {
        Body::Ground => mk.p_bm,
        Body::Part(k) => o.state.poses[k].p + o.state.poses[k].r * mk.p_bm,
    }
}

/// z axis of marker `id` (ground) at an output.
fn z_axis(m: &Model, o: &Output, id: u64) -> DVec3 {
    let mk = &m.markers[marker(m, id)];
    match mk.body {
        Body::Ground => mk.r_bm.z_axis,
        Body::Part(k) => o.state.poses[k].r * mk.r_bm.z_axis,
    }
}

/// Kinetic plus gravitational potential energy of every part at an output.
fn energy(m: &Model, o: &Output) -> f64 {
    o.kinetic_energy(m)
        - m.parts
            .iter()
            .enumerate()
            .map(|(k, p)| p.mass * m.gravity.dot(o.state.poses[k].p))
            .sum::<f64>()
}

/// The largest kinetic energy over the run.
fn largest_kinetic_energy(r: &Run) -> f64 {
    r.sim
        .outputs
        .iter()
        .map(|o| o.kinetic_energy(&r.model))
        .fold(0.0, f64::max)
}

/// The largest change of the energy from its initial value over the run.
fn energy_drift(r: &Run) -> f64 {
    let e0 = energy(&r.model, &r.sim.outputs[0]);
    r.sim
        .outputs
        .iter()
        .map(|o| (energy(&r.model, o) - e0).abs())
        .fold(0.0, f64::max)
}

/// The largest distance between the I and J markers of any joint over the run, and the largest
/// angle between their z axes (the loop closure of a mechanism of REVOLUTEs).
fn joint_gaps(r: &Run) -> (f64, f64) {
    let (mut gap, mut tilt) = (0.0f64, 0.0f64);
    for o in &r.sim.outputs {
        for c in &r.model.constraints {
            let Some((i, j)) = c.markers() else { continue };
            let (i, j) = (r.model.markers[i].id, r.model.markers[j].id);
            gap = gap.max((position(&r.model, o, i) - position(&r.model, o, j)).length());
            tilt = tilt.max(
                z_axis(&r.model, o, i)
                    .cross(z_axis(&r.model, o, j))
                    .length(),
            );
        }
    }
    (gap, tilt)
}

/// Says how a run went; panics with the solver's message when it stopped early.
fn finished(what: &str, r: &Run) {
    eprintln!(
        "{what}: {:.2} s wall, {} steps ({} rejected), {} corrector iterations, {} \
         factorisations, {} outputs",
        r.seconds,
        r.sim.steps,
        r.sim.rejected,
        r.sim.newton_iterations,
        r.sim.factorisations,
        r.sim.outputs.len()
    );
    if let Some(f) = &r.sim.failure {
        panic!("{what}: the run stopped at t = {}: {}", f.time, f.message);
    }
}

/// `[1.234e-5, …]`.
fn sci(x: &[f64]) -> String {
    let v: Vec<String> = x.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", v.join(", "))
}

/// Classical fourth-order Runge–Kutta for `y'' = f(t, y, y')` with a fixed step, the state
/// recorded at every multiple of `every` steps.
fn rk4(
    f: &mut dyn FnMut(f64, f64, f64) -> f64,
    (y0, v0): (f64, f64),
    h: f64,
    steps: usize,
    every: usize,
) -> Vec<(f64, f64)> {
    let (mut y, mut v) = (y0, v0);
    let mut out = vec![(y, v)];
    for n in 0..steps {
        let t = n as f64 * h;
        let (k1y, k1v) = (v, f(t, y, v));
        let (k2y, k2v) = (
            v + 0.5 * h * k1v,
            f(t + 0.5 * h, y + 0.5 * h * k1y, v + 0.5 * h * k1v),
        );
        let (k3y, k3v) = (
            v + 0.5 * h * k2v,
            f(t + 0.5 * h, y + 0.5 * h * k2y, v + 0.5 * h * k2v),
        );
        let (k4y, k4v) = (v + h * k3v, f(t + h, y + h * k3y, v + h * k3v));
        y += h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if (n + 1) % every == 0 {
            out.push((y, v));
        }
    }
    out
}

// ------------------------------------------------------------------------------------------
// A01: simple pendulum, exact solution by Jacobi elliptic functions.
// ------------------------------------------------------------------------------------------

/// Jacobi elliptic functions `(sn, dn)` of `u` for modulus `k` (0 ≤ k < 1), and the complete
/// elliptic integral `K(k)`, by the arithmetic–geometric mean (descending Landen
/// transformation; Abramowitz & Stegun 16.4 and 17.6).
fn jacobi_sn_dn(u: f64, k: f64) -> (f64, f64, f64) {
    let mut a = vec![1.0f64];
    let mut c = vec![k];
    let mut b = (1.0 - k * k).sqrt();
    while c.last().unwrap().abs() > 1e-17 && a.len() < 40 {
        let an = *a.last().unwrap();
        c.push(0.5 * (an - b));
        a.push(0.5 * (an + b));
        b = (an * b).sqrt();
    }
    let n = a.len() - 1;
    let big_k = PI / (2.0 * a[n]);
    // sn has the period 4K: reduce first so that the recursion works on a small angle.
    let u = u.rem_euclid(4.0 * big_k);
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    for m in (1..=n).rev() {
        phi = 0.5 * (phi + (c[m] / a[m] * phi.sin()).asin());
    }
    let sn = phi.sin();
    (sn, (1.0 - k * k * sn * sn).sqrt(), big_k)
}

/// The A01 dataset's pendulum: point P1 (the CM, L = 1 m from the pivot) released at rest from
/// the horizontal (+x). A physical pendulum with `I_pivot = m L² + I_cm`: the angle θ from the
/// downward vertical obeys `θ'' = −ω0² sin θ`, `ω0² = m g L / I_pivot`, and from θ0 = π/2 at
/// rest `sin(θ/2) = k sn(K − ω0 t, k)`, `k = sin(θ0/2)`.
fn a01_exact(t: f64) -> DVec3 {
    let (m, l, i_cm) = (1.0, 1.0, 1e-4);
    let w0 = (m * G * l / (m * l * l + i_cm)).sqrt();
    let k = (FRAC_PI_2 / 2.0).sin();
    let (_, _, big_k) = jacobi_sn_dn(0.0, k);
    let (sn, dn, _) = jacobi_sn_dn(big_k - w0 * t, k);
    let (s, c) = (k * sn, dn); // sin(θ/2), cos(θ/2)
    DVec3::new(l * 2.0 * s * c, -l * (1.0 - 2.0 * s * s), 0.0)
}

/// Distance of P1 (MARKER/201) from the exact solution at every output.
fn a01_errors(r: &Run) -> Vec<f64> {
    r.sim
        .outputs
        .iter()
        .map(|o| (position(&r.model, o, 201) - a01_exact(o.time)).length())
        .collect()
}

fn a01(end: f64, steps: usize, error: f64) -> (f64, Run) {
    let r = simulate(
        "a01_pendulum.adm",
        &dataset("a01_pendulum.adm"),
        end,
        steps,
        error,
    );
    let what = format!("A01 over {end} s, ERROR = {error:e}");
    let errors = a01_errors(&r);
    let e = errors.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "{what}: max |P1 − exact| = {e:.3e} m (first above 1e-3 at t = {:?}), energy drift \
         {:.3e} J",
        first_above(&r, &errors, 1e-3),
        energy_drift(&r)
    );
    finished(&what, &r);
    (e, r)
}

/// CONSTANT_BDF: A01 over 10 s steps at HMAX exactly (5000 steps at 2e-3 s, 10,000 at
/// 1e-3 s, none rejected whatever the estimate says), stays within the benchmark's 1e-3 m and
/// converges with the step (measured 6.9e-4 and 1.7e-4 m).
#[test]
fn constant_bdf_steps_at_hmax() {
    let mut errors = Vec::new();
    for (h, steps) in [(2e-3, 5000), (1e-3, 10_000)] {
        let settings = IntegratorSettings {
            constant_step: true,
            hmax: Some(h),
            error: 1e-12,
            ..Default::default()
        };
        let text = dataset("a01_pendulum.adm");
        let r = simulate_settings("a01_pendulum.adm", &text, 10.0, 200, &settings);
        finished(&format!("A01, CONSTANT_BDF, HMAX = {h}"), &r);
        let e = a01_errors(&r).into_iter().fold(0.0, f64::max);
        eprintln!("A01, CONSTANT_BDF, HMAX = {h}: max |P1 − exact| = {e:.3e} m");
        assert_eq!((r.sim.steps, r.sim.rejected), (steps, 0));
        assert!(e < 1e-3, "HMAX = {h}: {e:.3e} m");
        errors.push(e);
    }
    assert!(errors[1] < 0.5 * errors[0], "{errors:?}");
}

/// HHT with ALPHA = 0 (Newmark's trapezoidal rule) at ERROR = 1e-8 on A01 over 10 s. Its
/// index-3 form leaves a velocity-constraint violation alternating undamped from step to step;
/// its error estimate stayed at 0.73·ERROR however small the step, which shrank without end
/// (41,058 steps for α = −0.01, and α = 0 stalled at t = 0.046 s). Measured now: α = 0 takes
/// 8900 steps, α = −0.01 9081; both within the benchmark's 1e-3 m.
#[test]
fn hht_without_numerical_damping_finishes_a01() {
    for alpha in [0.0, -0.01] {
        let settings = IntegratorSettings {
            method: IntegratorMethod::Hht,
            alpha,
            error: 1e-8,
            ..Default::default()
        };
        let text = dataset("a01_pendulum.adm");
        let r = simulate_settings("a01_pendulum.adm", &text, 10.0, 200, &settings);
        let what = format!("A01, HHT, ALPHA = {alpha}, ERROR = 1e-8");
        finished(&what, &r);
        let e = a01_errors(&r).into_iter().fold(0.0, f64::max);
        eprintln!(
            "{what}: {} steps, max |P1 − exact| = {e:.3e} m",
            r.sim.steps
        );
        assert!(r.sim.steps < 20_000, "{what}: {} steps", r.sim.steps);
        assert!(e < 1e-3, "{what}: {e:.3e} m");
    }
}

#[test]
fn the_elliptic_reference_is_the_pendulum_solution() {
    // sn(0) = 0, sn(K) = 1, and K(1/√2) = Γ(1/4)² / (4 √π) = 1.854074677301372.
    let k = FRAC_PI_2.sin() / 2f64.sqrt();
    let (sn0, dn0, big_k) = jacobi_sn_dn(0.0, k);
    assert!(sn0.abs() < 1e-15 && (dn0 - 1.0).abs() < 1e-15);
    assert!((big_k - 1.854074677301372).abs() < 1e-14, "{big_k}");
    assert!((jacobi_sn_dn(big_k, k).0 - 1.0).abs() < 1e-14);
    // The reference satisfies θ'' = −ω0² sin θ (central differences) and starts at (1, 0).
    assert!((a01_exact(0.0) - DVec3::X).length() < 1e-14);
    let w2 = G / (1.0 + 1e-4);
    let angle = |t: f64| {
        let p = a01_exact(t);
        p.x.atan2(-p.y)
    };
    for t in [0.3, 1.7, 123.4, 1999.9] {
        let h = 1e-3;
        let acc = (angle(t + h) - 2.0 * angle(t) + angle(t - h)) / (h * h);
        assert!(
            (acc + w2 * angle(t).sin()).abs() < 1e-5,
            "t = {t}: {acc} vs {}",
            -w2 * angle(t).sin()
        );
        // The mass stays on the circle of radius L.
        assert!((a01_exact(t).length() - 1.0).abs() < 1e-14);
    }
}

/// IFToMM A01 as published: 2000 s, 4000 outputs, P1 within 1e-3 m of the exact solution at
/// every output, at ERROR = [`BENCHMARK_ERROR`] (7-13 s).
#[test]
/// A01 as published: 2000 s, 4000 outputs (measured 1.2e-5 m, 2.2 s, 442,000 steps).
fn a01_pendulum_over_2000_s_within_1e_3_m() {
    let (e, _) = a01(2000.0, 4000, BENCHMARK_ERROR);
    assert!(e < 1e-3, "A01: max error {e:.3e} m over 2000 s");
}

/// The first 10 s of A01 (200 outputs), 1e-3 m at every output.
#[test]
fn a01_pendulum_over_10_s_within_1e_3_m() {
    let (e, _) = a01(10.0, 200, BENCHMARK_ERROR);
    assert!(e < 1e-3, "A01: max error {e:.3e} m over 10 s");
}

/// Convergence: the global error on a smooth problem (A01 over 10 s) at ERROR = 1e-4, 1e-6,
/// 1e-8 falls by at least 10 for each factor 100 of ERROR.
#[test]
fn a01_global_error_falls_with_the_integrator_error() {
    let errors: Vec<f64> = [1e-4, 1e-6, 1e-8]
        .iter()
        .map(|&tol| a01(10.0, 200, tol).0)
        .collect();
    eprintln!(
        "A01 global error at ERROR 1e-4, 1e-6, 1e-8: {}",
        sci(&errors)
    );
    for w in errors.windows(2) {
        assert!(w[1] <= 0.1 * w[0], "no convergence: {}", sci(&errors));
    }
}

// ------------------------------------------------------------------------------------------
// A02: N four-bar chain, exact one-degree-of-freedom reduction.
// ------------------------------------------------------------------------------------------

/// Crank angle φ(t) (from +x) of the N-loop chain at `times` (equal steps from 0). The chain
/// moves as a parallelogram: kinetic energy `½ J φ'²` with `J = (N+1) m L²/3 + N m L²` (the
/// cranks about their pivots, the couplers translating with speed L φ'), potential
/// `C sin φ` with `C = m g L ((N+1)/2 + N)`, so `J φ'' = −C cos φ`; integrated by RK4 with
/// 200 steps per output (2.5e-4 s for 400 outputs over 20 s; its energy is checked by
/// `the_a02_reference_keeps_its_energy`).
fn a02_reference(n: usize, end: f64, outputs: usize) -> Vec<(f64, f64)> {
    let nf = n as f64;
    let j = (nf + 1.0) / 3.0 + nf;
    let c = G * ((nf + 1.0) / 2.0 + nf);
    let every = 200;
    let h = end / (outputs * every) as f64;
    rk4(
        &mut |_, phi, _| -c / j * phi.cos(),
        (FRAC_PI_2, -1.0),
        h,
        outputs * every,
        every,
    )
}

/// Distance of B0 (MARKER/203) from the reference at every output.
fn a02_errors(r: &Run, reference: &[(f64, f64)]) -> Vec<f64> {
    r.sim
        .outputs
        .iter()
        .zip(reference)
        .map(|(o, &(phi, _))| {
            (position(&r.model, o, 203) - DVec3::new(phi.cos(), phi.sin(), 0.0)).length()
        })
        .collect()
}

/// Rotation about z of part `k` from its input orientation (radians, in (−π, π]).
fn turned(o: &Output, k: usize) -> f64 {
    let x = o.state.poses[k].r.x_axis;
    x.y.atan2(x.x)
}

/// The time of the first output whose error exceeds `tol`.
fn first_above(r: &Run, errors: &[f64], tol: f64) -> Option<f64> {
    errors
        .iter()
        .position(|&e| e > tol)
        .map(|k| r.sim.outputs[k].time)
}

fn a02(n: usize, end: f64, outputs: usize, error: f64) -> (f64, Run) {
    a02_as(n, end, outputs, error, Formulation::I3)
}

fn a02_as(n: usize, end: f64, outputs: usize, error: f64, formulation: Formulation) -> (f64, Run) {
    let r = simulate_as(
        &format!("a02_fourbar_n{n}.adm"),
        &iftomm_a02(n),
        end,
        outputs,
        error,
        formulation,
    );
    let what = format!("A02 N = {n} over {end} s, ERROR = {error:e}, {formulation:?}");
    let reference = a02_reference(n, end, outputs);
    let errors = a02_errors(&r, &reference);
    let e = errors.iter().copied().fold(0.0, f64::max);
    // Off the parallelogram branch: a coupler turns, or two cranks differ.
    let (mut coupler, mut cranks) = (0.0f64, 0.0f64);
    for o in &r.sim.outputs {
        for k in 1..=n {
            let d = turned(o, k) - turned(o, 0);
            cranks = cranks.max((d - 2.0 * PI * (d / (2.0 * PI)).round()).abs());
            coupler = coupler.max(turned(o, n + k).abs());
        }
    }
    eprintln!(
        "{what}: max |B0 − reference| = {e:.3e} m over {} outputs (first above 1e-3 at t = {:?}), \
         energy drift {:.3e} J, largest coupler rotation {coupler:.1e} rad, crank spread \
         {cranks:.1e} rad",
        r.sim.outputs.len(),
        first_above(&r, &errors, 1e-3),
        energy_drift(&r)
    );
    finished(&what, &r);
    (e, r)
}

/// The checked-in N = 2 file (for the CLI) is what the generator writes; `BLESS=1` rewrites it.
#[test]
fn the_checked_in_a02_dataset_is_the_generator_output() {
    if std::env::var_os("BLESS").is_some() {
        std::fs::write(data_path("a02_fourbar_n2.adm"), iftomm_a02(2)).unwrap();
    }
    assert_eq!(dataset("a02_fourbar_n2.adm"), iftomm_a02(2));
}

#[test]
fn the_a02_reference_keeps_its_energy() {
    for n in [2, 40] {
        let nf = n as f64;
        let (j, c) = ((nf + 1.0) / 3.0 + nf, G * ((nf + 1.0) / 2.0 + nf));
        let e = |&(phi, w): &(f64, f64)| 0.5 * j * w * w + c * phi.sin();
        let r = a02_reference(n, 20.0, 400);
        let e0 = e(&r[0]);
        let drift = r.iter().map(|s| (e(s) - e0).abs()).fold(0.0, f64::max);
        assert!(drift < 1e-9 * e0, "N = {n}: drift {drift}");
        // It turns over: the chain goes through the horizontal many times.
        assert!(r.last().unwrap().0 < -10.0 * PI, "{:?}", r.last());
    }
}

/// The A02 dataset's initial state is the one the reference starts from: parts at rest
/// configuration given, velocities consistent (B0 at 1 m/s along +x).
#[test]
fn a02_starts_with_b0_at_1_m_per_s() {
    let r = simulate("a02_fourbar_n2.adm", &iftomm_a02(2), 0.01, 1, 1e-8);
    let m = &r.model;
    let o = &r.sim.outputs[0];
    let crank = match m.markers[marker(m, 203)].body {
        Body::Part(k) => k,
        Body::Ground => unreachable!(),
    };
    let (v, w) = o.velocities[crank];
    let tip = v + w.cross(position(m, o, 203) - o.state.poses[crank].p);
    assert!((tip - DVec3::X).length() < 1e-9, "B0 velocity {tip}");
    assert!((position(m, o, 203) - DVec3::Y).length() < 1e-12);
}

/// IFToMM A02 with N = 2: 20 s, 400 outputs, B0 within 1e-3 m at every output.
#[test]
fn a02_two_loops_over_20_s_within_1e_3_m() {
    let (e, _) = a02(2, 20.0, 400, BENCHMARK_ERROR);
    assert!(e < 1e-3, "A02 N = 2: max error {e:.3e} m");
}

/// A02 with N = 10.
#[test]
fn a02_ten_loops_over_20_s_within_1e_3_m() {
    let (e, _) = a02(10, 20.0, 400, BENCHMARK_ERROR);
    assert!(e < 1e-3, "A02 N = 10: max error {e:.3e} m");
}

/// IFToMM A02 as published, N = 40, with the SI2 formulation (GSTIFF, SI2): 1.25e-4 m at
/// ERROR = 1e-6, 2209 steps (the index-3 form: `a02_forty_loops_in_the_index_3_form_within_1e_3_m`).
#[test]
fn a02_forty_loops_over_20_s_within_1e_3_m() {
    let (e, r) = a02_as(40, 20.0, 400, BENCHMARK_ERROR, Formulation::Si2);
    assert!(e < 1e-3, "A02 N = 40, SI2: max error {e:.3e} m");
    // It stays on the parallelogram branch through the 26 flat (singular) poses, loops closed.
    let (gap, tilt) = joint_gaps(&r);
    assert!(
        gap < 1e-8 && tilt < 1e-8,
        "gap {gap:.1e} m, tilt {tilt:.1e}"
    );
}

/// IFToMM A02 as published, N = 40, in the default formulation (GSTIFF, I3): within the
/// benchmark's 1e-3 m at ERROR = 1e-6 (measured 8.1e-4 m, 2346 steps, about 1.1 s of CPU on
/// the loaded 2-core build machine, the iteration matrix refactorised with kept pivots).
/// Through the 26 flat poses the kept rows lose rank and the error depends on rounding there:
/// measured 5.2e-3, 8.1e-4, 2.4e-4, 1.1e-5 m at ERROR = 1e-5, 1e-6, 1e-7, 1e-8 (issue 31
/// item 2, open).
#[test]
fn a02_forty_loops_in_the_index_3_form_within_1e_3_m() {
    let (e, r) = a02_as(40, 20.0, 400, BENCHMARK_ERROR, Formulation::I3);
    assert!(e < 1e-3, "A02 N = 40, I3: max error {e:.3e} m");
    let (gap, tilt) = joint_gaps(&r);
    assert!(
        gap < 1e-8 && tilt < 1e-8,
        "gap {gap:.1e} m, tilt {tilt:.1e}"
    );
}

/// SI2 on the small chain: within a tenth of the benchmark tolerance (measured 1.9e-5 m; I3
/// 1.8e-5 m).
#[test]
fn a02_two_loops_with_si2_agrees_with_the_reference() {
    let (e, _) = a02_as(2, 20.0, 400, BENCHMARK_ERROR, Formulation::Si2);
    assert!(e < 1e-4, "A02 N = 2, SI2: max error {e:.3e} m");
}

/// Energy: the conservative N = 2 chain over the 20 s (through the singular position 26
/// times) keeps its energy within a bound that falls by at least 10 for each factor 100 of
/// ERROR (measured 1.1e-3, 1.5e-5, 1.5e-7 J at 1e-4, 1e-6, 1e-8; the kinetic energy reaches
/// 70 J at the lowest position).
#[test]
fn a02_energy_drift_shrinks_with_the_integrator_error() {
    let drifts: Vec<f64> = [1e-4, 1e-6, 1e-8]
        .iter()
        .map(|&tol| energy_drift(&a02(2, 20.0, 400, tol).1))
        .collect();
    eprintln!(
        "A02 N = 2 energy drift at ERROR 1e-4, 1e-6, 1e-8: {} J",
        sci(&drifts)
    );
    for w in drifts.windows(2) {
        assert!(
            w[1] <= 0.1 * w[0],
            "energy drift does not shrink: {}",
            sci(&drifts)
        );
    }
    assert!(
        drifts[2] < 1e-2,
        "energy drift {} J at ERROR = 1e-8",
        drifts[2]
    );
}

// ------------------------------------------------------------------------------------------
// A04: Bricard mechanism, minimal-coordinate reference.
// ------------------------------------------------------------------------------------------

/// The A04 dataset's geometry: joint points and axes (initial position), loop order; rod k
/// joins joint k to joint k + 1, joint 6 (index 5) closes the loop to ground.
const BRICARD_POINTS: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, -1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 0.0, 1.0],
];
const BRICARD_AXES: [[f64; 3]; 6] = [
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 0.0],
];

/// The Bricard linkage in joint coordinates: rod k's pose is the product of rotations
/// `q_0 … q_k` about the joints' initial axes through their initial points.
struct Bricard {
    points: [DVec3; 6],
    axes: [DVec3; 6],
    /// Rod mass, inertia about the CM in the initial axes.
    mass: f64,
    inertia: [DMat3; 5],
}

/// Rod poses `x ↦ R x + t` and, per joint, the current axis and point.
struct Chain {
    r: [DMat3; 5],
    t: [DVec3; 5],
    axis: [DVec3; 5],
    centre: [DVec3; 5],
}

impl Bricard {
    fn new() -> Bricard {
        let v = |a: [f64; 3]| DVec3::from_array(a);
        let (ia, it) = (0.02 / 12.0, 1.01 / 12.0);
        let inertia = std::array::from_fn(|k| {
            let along = (v(BRICARD_POINTS[k + 1]) - v(BRICARD_POINTS[k])).abs();
            DMat3::from_diagonal(DVec3::splat(it) + along * (ia - it))
        });
        Bricard {
            points: BRICARD_POINTS.map(v),
            axes: BRICARD_AXES.map(v),
            mass: 1.0,
            inertia,
        }
    }

    fn chain(&self, q: &[f64; 5]) -> Chain {
        let mut c = Chain {
            r: [DMat3::IDENTITY; 5],
            t: [DVec3::ZERO; 5],
            axis: [DVec3::ZERO; 5],
            centre: [DVec3::ZERO; 5],
        };
        let (mut r, mut t) = (DMat3::IDENTITY, DVec3::ZERO);
        for (k, &qk) in q.iter().enumerate() {
            c.axis[k] = r * self.axes[k];
            c.centre[k] = r * self.points[k] + t;
            let rk = DMat3::from_axis_angle(self.axes[k], qk);
            t += r * (self.points[k] - rk * self.points[k]);
            r *= rk;
            c.r[k] = r;
            c.t[k] = t;
        }
        c
    }

    /// Closure residual (rod 5's end must stay on joint 6's point and axis) and its Jacobian
    /// in the five joint angles.
    fn closure(&self, q: &[f64; 5]) -> ([f64; 6], [[f64; 6]; 5], Chain) {
        let c = self.chain(q);
        let p = c.r[4] * self.points[5] + c.t[4];
        let a = c.r[4] * self.axes[5];
        let dp = p - self.points[5];
        let da = a - self.axes[5];
        let res = [dp.x, dp.y, dp.z, da.x, da.y, da.z];
        let jac = std::array::from_fn(|k| {
            let vp = c.axis[k].cross(p - c.centre[k]);
            let va = c.axis[k].cross(a);
            [vp.x, vp.y, vp.z, va.x, va.y, va.z]
        });
        (res, jac, c)
    }

    /// The joint angles closing the loop for `q0` (Gauss–Newton on the six closure equations
    /// in q1..q4, consistent with one redundant), from `guess`.
    fn close(&self, q0: f64, guess: &[f64; 4]) -> [f64; 5] {
        let mut q = [q0, guess[0], guess[1], guess[2], guess[3]];
        for _ in 0..50 {
            let (res, jac, _) = self.closure(&q);
            let (mut ata, mut atb) = ([[0.0; 4]; 4], [0.0; 4]);
            for i in 0..4 {
                for j in 0..4 {
                    ata[i][j] = (0..6).map(|r| jac[i + 1][r] * jac[j + 1][r]).sum();
                }
                atb[i] = -(0..6).map(|r| jac[i + 1][r] * res[r]).sum::<f64>();
            }
            let dq = solve4(ata, atb);
            for i in 0..4 {
                q[i + 1] += dq[i];
            }
            if dq.iter().map(|d| d.abs()).fold(0.0, f64::max) < 1e-15 {
                break;
            }
        }
        let (res, _, _) = self.closure(&q);
        let r = res.iter().map(|x| x.abs()).fold(0.0, f64::max);
        assert!(
            r < 1e-12,
            "Bricard closure not solved at q0 = {q0}: residual {r}"
        );
        q
    }

    /// Joint rates for q0' = 1 (least squares on the velocity closure, consistent).
    fn rates(&self, q: &[f64; 5]) -> [f64; 5] {
        let (_, jac, _) = self.closure(q);
        let (mut ata, mut atb) = ([[0.0; 4]; 4], [0.0; 4]);
        for i in 0..4 {
            for j in 0..4 {
                ata[i][j] = (0..6).map(|r| jac[i + 1][r] * jac[j + 1][r]).sum();
            }
            atb[i] = -(0..6).map(|r| jac[i + 1][r] * jac[0][r]).sum::<f64>();
        }
        let d = solve4(ata, atb);
        [1.0, d[0], d[1], d[2], d[3]]
    }

    /// Rod k's CM at the initial position.
    fn cm0(&self, k: usize) -> DVec3 {
        0.5 * (self.points[k] + self.points[k + 1])
    }

    /// Generalized mass `M(q0)`, potential `V(q0)` and `dV/dq0`, with the joint angles.
    fn mass_potential(&self, q: &[f64; 5]) -> (f64, f64, f64) {
        let c = self.chain(q);
        let rate = self.rates(q);
        let (mut m, mut v, mut dv) = (0.0, 0.0, 0.0);
        for k in 0..5 {
            let cm = c.r[k] * self.cm0(k) + c.t[k];
            let (mut vel, mut w) = (DVec3::ZERO, DVec3::ZERO);
            for ((axis, centre), rate) in c.axis.iter().zip(&c.centre).zip(&rate).take(k + 1) {
                w += *axis * *rate;
                vel += axis.cross(cm - *centre) * *rate;
            }
            let ig = c.r[k] * self.inertia[k] * c.r[k].transpose();
            m += self.mass * vel.length_squared() + w.dot(ig * w);
            v += self.mass * G * cm.y;
            dv += self.mass * G * vel.y;
        }
        (m, v, dv)
    }

    /// Point P3 (joint 4's point, on rod 3) for the joint angles.
    fn p3(&self, q: &[f64; 5]) -> DVec3 {
        let c = self.chain(q);
        c.r[2] * self.points[3] + c.t[2]
    }
}

/// Solves a 4×4 system by Gaussian elimination with partial pivoting.
fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> [f64; 4] {
    for col in 0..4 {
        let p = (col..4)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap();
        a.swap(col, p);
        b.swap(col, p);
        for row in col + 1..4 {
            let f = a[row][col] / a[col][col];
            let pivot = a[col];
            for (x, p) in a[row][col..].iter_mut().zip(&pivot[col..]) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..4).rev() {
        let s: f64 = (row + 1..4).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    x
}

/// Reference for A04: `q0(t)` from Lagrange's equation `M q0'' + ½ M' q0'² + V' = 0` (M' by
/// central differences of the closed loop), RK4 with `h = end / (outputs·every)`, from rest
/// at the dataset's position; P3 and the energy at each output.
fn a04_reference(end: f64, outputs: usize, every: usize) -> Vec<(DVec3, f64)> {
    let b = Bricard::new();
    let mut guess = [0.0; 4];
    let closed = |q0: f64, guess: &mut [f64; 4]| {
        let q = b.close(q0, guess);
        guess.copy_from_slice(&q[1..]);
        q
    };
    let h = end / (outputs * every) as f64;
    let dq = 1e-5;
    let mut g = guess;
    let states = rk4(
        &mut |_, q0, w| {
            let q = closed(q0, &mut g);
            let (m, _, dv) = b.mass_potential(&q);
            let mut gp = g;
            let mp = b.mass_potential(&closed(q0 + dq, &mut gp)).0;
            let mut gm = g;
            let mm = b.mass_potential(&closed(q0 - dq, &mut gm)).0;
            let dm = (mp - mm) / (2.0 * dq);
            -(0.5 * dm * w * w + dv) / m
        },
        (0.0, 0.0),
        h,
        outputs * every,
        every,
    );
    states
        .iter()
        .map(|&(q0, w)| {
            let q = closed(q0, &mut guess);
            let (m, v, _) = b.mass_potential(&q);
            (b.p3(&q), 0.5 * m * w * w + v)
        })
        .collect()
}

#[test]
fn the_bricard_reference_closes_the_loop_and_keeps_its_energy() {
    let b = Bricard::new();
    // The dataset's position closes with every joint angle 0, and the loop is mobile: a
    // closed position exists for q0 on either side, with all the joints moving.
    let q = b.close(0.0, &[0.0; 4]);
    assert!(q.iter().all(|x| x.abs() < 1e-12), "{q:?}");
    let q = b.close(0.2, &[0.0; 4]);
    assert!(q[1..].iter().all(|x| x.abs() > 1e-3), "{q:?}");
    // It is not at equilibrium: gravity moves it from rest.
    let (m, _, dv) = b.mass_potential(&b.close(0.0, &[0.0; 4]));
    assert!(m > 0.1 && dv.abs() > 0.1, "M = {m}, V' = {dv}");
    // Energy over 2 s and agreement of two step sizes (the reference's own error).
    let coarse = a04_reference(2.0, 40, 25);
    let fine = a04_reference(2.0, 40, 50);
    let e0 = fine[0].1;
    let drift = fine.iter().map(|s| (s.1 - e0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-7, "reference energy drift {drift}");
    let diff = coarse
        .iter()
        .zip(&fine)
        .map(|(a, b)| (a.0 - b.0).length())
        .fold(0.0, f64::max);
    assert!(diff < 1e-7, "reference step-size dependence {diff}");
    // It moves by a sizeable amount.
    let travel = fine
        .iter()
        .map(|s| (s.0 - fine[0].0).length())
        .fold(0.0, f64::max);
    assert!(travel > 0.1, "P3 travel {travel}");
}

fn a04(end: f64, outputs: usize, error: f64) -> (f64, Run) {
    let r = simulate(
        "a04_bricard.adm",
        &dataset("a04_bricard.adm"),
        end,
        outputs,
        error,
    );
    let what = format!("A04 over {end} s, ERROR = {error:e}");
    let reference = a04_reference(end, outputs, 20);
    let errors: Vec<f64> = r
        .sim
        .outputs
        .iter()
        .zip(&reference)
        .map(|(o, s)| (position(&r.model, o, 403) - s.0).length())
        .collect();
    let e = errors.iter().copied().fold(0.0, f64::max);
    let (gap, tilt) = joint_gaps(&r);
    eprintln!(
        "{what}: max |P3 − reference| = {e:.4e} m over {} outputs (first above 1e-3 at t = \
         {:?}), energy drift {:.3e} J (largest kinetic energy {:.3} J), joint gap {gap:.1e} m, \
         axis tilt {tilt:.1e}",
        r.sim.outputs.len(),
        first_above(&r, &errors, 1e-3),
        energy_drift(&r),
        largest_kinetic_energy(&r)
    );
    finished(&what, &r);
    (e, r)
}

/// IFToMM A04: 10 s, P3 within 1e-3 m of the reference at every output; the energy kept
/// within 1e-3 of the largest kinetic energy of the run (about 4.6 J) and the loop closed
/// (every joint's markers coincident and their z axes parallel within 1e-9) at every output.
#[test]
fn a04_bricard_over_10_s_within_1e_3_m() {
    let (e, r) = a04(10.0, 200, BENCHMARK_ERROR);
    assert!(e < 1e-3, "A04: max error of P3 {e:.3e} m");
    let (drift, scale) = (energy_drift(&r), largest_kinetic_energy(&r));
    assert!(scale > 1.0, "A04: the mechanism hardly moves ({scale} J)");
    assert!(
        drift < 1e-3 * scale,
        "A04: energy drift {drift:.3e} J (kinetic energy up to {scale:.3} J)"
    );
    let (gap, tilt) = joint_gaps(&r);
    assert!(gap < 1e-9 && tilt < 1e-9, "A04: gap {gap:e}, tilt {tilt:e}");
}

/// Energy on the Bricard mechanism: the drift falls by at least 10 for each factor 100 of
/// ERROR.
#[test]
fn a04_energy_drift_shrinks_with_the_integrator_error() {
    let drifts: Vec<f64> = [1e-4, 1e-6, 1e-8]
        .iter()
        .map(|&tol| energy_drift(&a04(10.0, 200, tol).1))
        .collect();
    eprintln!(
        "A04 energy drift at ERROR 1e-4, 1e-6, 1e-8: {} J",
        sci(&drifts)
    );
    for w in drifts.windows(2) {
        assert!(
            w[1] <= 0.1 * w[0],
            "energy drift does not shrink: {}",
            sci(&drifts)
        );
    }
}

// ------------------------------------------------------------------------------------------
// Andrews' squeezing mechanism.
// ------------------------------------------------------------------------------------------

/// Published reference at t = 0.03 s (Test Set for IVP Solvers, problem "andrews", computed
/// with PSIDE at rtol = atol = 1e-14): β, Θ, γ, Φ, δ, Ω, ε.
const ANDREWS_REFERENCE: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948,
    0.5244099658805304,
    0.5347301163226948,
    0.1048080741042263e+1,
];

/// Published initial angles β, Θ, γ, Φ, δ, Ω, ε.
const ANDREWS_START: [f64; 7] = [
    -0.06171389001427645,
    0.0,
    0.45527981916307037,
    0.22266839016588588,
    0.48736497954384256,
    -0.22266839016588588,
    1.2305474445498212,
];

/// The seven published angles at every output: each part's absolute angle is its initial one
/// plus its rotation about z (unwrapped from output to output); Θ, Φ, Ω are relative angles.
fn andrews_angles(r: &Run) -> Vec<[f64; 7]> {
    let s = ANDREWS_START;
    // Absolute angles of parts 2..8 (crank 1, rod 2, triangle 3, rod 4, link 5, rod 6,
    // link 7) in the dataset's order.
    let initial = [
        s[0],
        s[0] + s[1],
        s[2],
        s[3] + s[4],
        s[4],
        s[5] + s[6],
        s[6],
    ];
    let mut previous = initial;
    let mut out = Vec::new();
    for o in &r.sim.outputs {
        let mut abs = [0.0; 7];
        for k in 0..7 {
            let x = o.state.poses[k].r.x_axis;
            let raw = initial[k] + x.y.atan2(x.x);
            // Nearest to the previous value modulo 2π.
            abs[k] = raw + 2.0 * PI * ((previous[k] - raw) / (2.0 * PI)).round();
        }
        previous = abs;
        out.push([
            abs[0],
            abs[1] - abs[0],
            abs[2],
            abs[3] - abs[4],
            abs[4],
            abs[5] - abs[6],
            abs[6],
        ]);
    }
    out
}

fn andrews(error: f64, outputs: usize) -> (f64, Run) {
    let r = simulate(
        "andrews_squeezer.adm",
        &dataset("andrews_squeezer.adm"),
        0.03,
        outputs,
        error,
    );
    let what = format!("Andrews' squeezer to 0.03 s, ERROR = {error:e}");
    let angles = andrews_angles(&r);
    let first = angles[0];
    let start = first
        .iter()
        .zip(&ANDREWS_START)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(start < 1e-12, "{what}: initial angles {first:?}");
    let reached = r.sim.outputs.last().unwrap().time;
    let last = angles.last().unwrap();
    let rel: Vec<f64> = last
        .iter()
        .zip(&ANDREWS_REFERENCE)
        .map(|(a, b)| ((a - b) / b).abs())
        .collect();
    let e = rel.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "{what}: at t = {reached}: angles {last:.10?}, relative errors {} (max {e:.2e})",
        sci(&rel)
    );
    finished(&what, &r);
    (e, r)
}

#[test]
fn the_andrews_dataset_starts_at_the_published_state() {
    let r = simulate(
        "andrews_squeezer.adm",
        &dataset("andrews_squeezer.adm"),
        1e-5,
        1,
        1e-8,
    );
    let angles = andrews_angles(&r);
    for (a, b) in angles[0].iter().zip(&ANDREWS_START) {
        assert!((a - b).abs() < 1e-12);
    }
    // At rest, and already closed: the assembly moved nothing.
    let o = &r.sim.outputs[0];
    assert!(o
        .velocities
        .iter()
        .all(|(v, w)| v.length() + w.length() < 1e-12));
    let (gap, tilt) = joint_gaps(&r);
    assert!(gap < 1e-12 && tilt < 1e-12, "gap {gap:e}, tilt {tilt:e}");
    // The published initial accelerations β'' = 14222.44…, Θ'' = −10666.83… rad/s² (the
    // others 0): the crank and rod 2 only.
    let (_, a1) = o.accelerations[0];
    let (_, a2) = o.accelerations[1];
    assert!((a1.z - 14222.443919954114).abs() < 1e-6 * 14222.4, "{a1}");
    assert!(
        (a2.z - a1.z + 10666.832939965585).abs() < 1e-6 * 10666.8,
        "{a2}"
    );
}

/// Andrews' squeezer: the seven angles at t = 0.03 s within 1e-5 relative of the published
/// reference, at ERROR = [`BENCHMARK_ERROR`].
#[test]
fn andrews_squeezer_matches_the_published_angles_at_0_03_s() {
    let (e, _) = andrews(BENCHMARK_ERROR, 300);
    assert!(e < 1e-5, "Andrews: largest relative error {e:.2e}");
}

/// Every benchmark at ERROR 1e-4, 1e-6, 1e-8 with its error and run time (the table of the
/// issue); prints only.
#[test]
#[ignore = "measurement table, long: run with --ignored --nocapture"]
fn benchmark_table() {
    for tol in [1e-4, 1e-6, 1e-8] {
        let _ = std::panic::catch_unwind(|| a01(10.0, 200, tol));
        let _ = std::panic::catch_unwind(|| a02(2, 20.0, 400, tol));
        let _ = std::panic::catch_unwind(|| a04(10.0, 200, tol));
        let _ = std::panic::catch_unwind(|| andrews(tol, 300));
    }
}

/// The long cases of the table: A01 over the published 2000 s, A02 with N = 10 and 40, and
/// Andrews' squeezer and A04 at smaller ERROR; prints only.
#[test]
#[ignore = "measurement table, long: run with --ignored --nocapture"]
fn benchmark_table_long() {
    for tol in [1e-6, 1e-8] {
        let _ = std::panic::catch_unwind(|| a01(2000.0, 4000, tol));
        let _ = std::panic::catch_unwind(|| a02(10, 20.0, 400, tol));
        let _ = std::panic::catch_unwind(|| a02(40, 20.0, 400, tol));
        let _ = std::panic::catch_unwind(|| a02_as(40, 20.0, 400, tol, Formulation::Si2));
    }
    for tol in [1e-9, 1e-10] {
        let _ = std::panic::catch_unwind(|| andrews(tol, 300));
        let _ = std::panic::catch_unwind(|| a04(10.0, 200, tol));
    }
}
