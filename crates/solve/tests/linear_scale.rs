//! Modes of large models (issue 35): the free motions of single parts (spins of rods between
//! spherical joints, free-floating bodies) are counted, not listed, and deflated before the
//! shift-invert solution, so `modes: K` gives the K lowest swinging modes of a 1,000-rod chain
//! (which has 1,000 free spins); and K is honoured by every solution (issue 37).

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::generate::hanging_chain;
use linkage_solve::physics::applied::{AppliedForces, NoForces};
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{run, EigenMethod, LinearOptions, Linearization};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::sync::Arc;

const G: f64 = 9.80665;

/// The first ten zeros of the Bessel function J₀ (Abramowitz & Stegun, table 9.5).
const J0_ZEROS: [f64; 10] = [
    2.404_825_557_695_773,
    5.520_078_110_286_311,
    8.653_727_912_911_012,
    11.791_534_439_014_281,
    14.930_917_708_487_786,
    18.071_063_967_910_923,
    21.211_636_629_879_26,
    24.352_471_530_749_303,
    27.493_479_132_040_255,
    30.634_606_468_431_976,
];

fn model(name: &str, text: &str) -> Model {
    let ds = linkage_adm::parse_dataset(Arc::from(name), text).unwrap();
    linkage_model::build_model(&ds).unwrap().model
}

fn linear(m: &Model, forces: &dyn AppliedForces, method: EigenMethod) -> Linearization {
    let d = ExpressionDrivers::new(m).unwrap();
    let opts = LinearOptions {
        damping: true,
        vectors: false,
        method,
    };
    run(
        &Assembled::new(m, &d, forces, &Tolerances::default()),
        false,
        opts,
    )
    .result
    .unwrap()
}

fn lowest(modes: usize) -> EigenMethod {
    EigenMethod::ShiftInvert { modes, shift: None }
}

#[test]
fn hanging_chain_swings_at_the_heavy_chain_frequencies_and_its_spins_are_counted() {
    // 1,000 rods of 1 m on spherical joints: the continuum's ω_k = (j₀ₖ/2)√(g/ℓ), ℓ = 1000 m,
    // twice each (two planes of swing); the discrete chain is within 0.05 % for k ≤ 10.
    let n = 1000;
    let m = model("hanging.adm", &hanging_chain(n));
    let l = linear(&m, &NoForces, lowest(20));
    assert_eq!(l.dof, 3 * n);
    assert_eq!(l.modes.len(), 20);
    for (k, mode) in l.modes.iter().enumerate() {
        let want = J0_ZEROS[k / 2] / 2.0 * (G / n as f64).sqrt();
        let got = mode.frequency * TAU;
        assert!(
            (got - want).abs() < 5e-3 * want,
            "mode {k}: ω = {got} vs the continuum's {want}"
        );
        assert!(mode.damping_ratio.abs() < 1e-8, "{mode:?}");
    }
    // Every rod's spin about its own axis is a free motion: two zero eigenvalues each,
    // counted (and expected), not listed.
    assert_eq!(l.zero_eigenvalues, 2 * n);
    assert_eq!(l.expected_zero_eigenvalues, 2 * n);
    assert_eq!(l.computed_eigenvalues, 2 * n + 40);
}

/// A chain of 4 rods on spherical joints (4 spins) and a free-floating body (6 rigid-body
/// motions).
fn chain_and_a_free_body() -> String {
    hanging_chain(4).replace(
        "END",
        "PART/50, MASS = 3, CM = 500, IP = 0.5, 0.7, 0.9\nMARKER/500, PART = 50, QP = 5, 0, 0\nEND",
    )
}

#[test]
fn rigid_body_and_spin_modes_are_counted_not_listed() {
    let m = model("chain_free.adm", &chain_and_a_free_body());
    let dense = linear(&m, &NoForces, EigenMethod::Dense);
    assert_eq!(dense.dof, 4 * 3 + 6);
    // Ten free motions: twenty zero eigenvalues, which the dense solution lists.
    assert_eq!(dense.zero_eigenvalues, 20);
    assert_eq!(dense.expected_zero_eigenvalues, 20);
    let swinging: Vec<f64> = dense
        .modes
        .iter()
        .map(|m| m.frequency)
        .filter(|&f| f * TAU > 1e-6)
        .collect();
    assert_eq!(swinging.len(), 8, "{swinging:?}");
    let sparse = linear(&m, &NoForces, lowest(3));
    assert_eq!(sparse.zero_eigenvalues, 20);
    assert_eq!(sparse.expected_zero_eigenvalues, 20);
    let got: Vec<f64> = sparse.modes.iter().map(|m| m.frequency).collect();
    assert_eq!(got.len(), 3, "{got:?}");
    for (g, w) in got.iter().zip(&swinging) {
        assert!((g - w).abs() < 1e-8 * w, "{got:?} vs {swinging:?}");
    }
}

#[test]
fn the_modes_asked_for_are_what_every_solution_lists() {
    // A control state makes the solution dense whatever was asked; `modes: 2` still lists 2
    // (the lowest: zero modes of the free body first), out of every eigenvalue computed.
    let text =
        chain_and_a_free_body().replace("END", "DIFF/1, IC = 1, FUNCTION = -DIF(1)/0.5\nEND");
    let m = model("chain_diff.adm", &text);
    let forces = ForceSet::new(&m).unwrap();
    let all = linear(&m, &forces, EigenMethod::Dense);
    assert_eq!(all.computed_eigenvalues, 2 * 18 + 1);
    assert!(all.modes.len() > 2);
    let two = linear(&m, &forces, lowest(2));
    assert_eq!(two.computed_eigenvalues, 2 * 18 + 1);
    assert_eq!(two.modes, all.modes[..2].to_vec());
    // Around the fourth swinging frequency: the 2 nearest, the frequency itself among them.
    let f = all
        .modes
        .iter()
        .map(|m| m.frequency)
        .filter(|&f| f * TAU > 1e-6)
        .nth(3)
        .unwrap();
    let near = linear(
        &m,
        &forces,
        EigenMethod::ShiftInvert {
            modes: 2,
            shift: Some(f * TAU),
        },
    );
    assert_eq!(near.modes.len(), 2);
    assert!(near
        .modes
        .iter()
        .any(|m| (m.frequency - f).abs() < 1e-12 * f));
}
