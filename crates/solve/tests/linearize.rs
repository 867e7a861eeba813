//! Natural frequencies against closed forms.

use linkage_model::Model;
use linkage_solve::applied::NoForces;
use linkage_solve::drivers::ExpressionDrivers;
use linkage_solve::linearize::{run, LinearOptions, Linearization};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::path::Path;
use std::sync::Arc;

const G: f64 = 9.80665;
const OPTS: LinearOptions = LinearOptions {
    damping: true,
    vectors: true,
};

fn mechanism_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn linear(name: &str, text: &str, static_first: bool) -> (Model, Linearization) {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let r = run(
        &m,
        &d,
        &NoForces,
        &Tolerances::default(),
        static_first,
        OPTS,
    );
    let lin = r.result.unwrap_or_else(|e| panic!("{name}: {e}"));
    (m, lin)
}

fn oscillating(l: &Linearization) -> Vec<f64> {
    l.modes
        .iter()
        .filter(|m| m.imag > 1e-9)
        .map(|m| m.frequency)
        .collect()
}

#[test]
fn compound_pendulum_frequency_is_sqrt_3g_over_2l() {
    let (_, l) = linear("pendulum.adm", &mechanism_text("pendulum.adm"), false);
    assert_eq!(l.dof, 1);
    let f = oscillating(&l);
    let expected = (3.0 * G / 2.0).sqrt() / TAU; // L = 1 m
    assert_eq!(f.len(), 1);
    assert!(
        (f[0] - expected).abs() < 1e-9 * expected,
        "{} vs {expected}",
        f[0]
    );
    assert!(l.modes[0].damping_ratio.abs() < 1e-12);
    // The mode shape: the rod's rotation about z dominates its phase-consistent translation.
    let shape = l.modes[0].shape.as_ref().unwrap();
    assert!(
        (shape[0].rotation[2].magnitude - 1.0).abs() < 1e-9
            || (shape[0].translation[0].magnitude - 1.0).abs() < 1e-9
    );
}

#[test]
fn pendulum_linearized_away_from_equilibrium_shows_the_geometric_stiffness() {
    // At 30° from hanging, at rest: θ̈ = −(3g/2L) sin θ linearises to ω² = (3g/2L) cos 30°.
    // All of this stiffness comes from the constraint force through ∂²Φ/∂q² (gravity itself is
    // constant), so the test fails if the geometric term is dropped.
    let (_, l) = linear(
        "pendulum_offset.adm",
        &mechanism_text("pendulum_offset.adm"),
        false,
    );
    let f = oscillating(&l);
    let expected = (3.0 * G / 2.0 * 30f64.to_radians().cos()).sqrt() / TAU;
    assert!(
        (f[0] - expected).abs() < 1e-9 * expected,
        "{} vs {expected}",
        f[0]
    );
    // About its static equilibrium it is the plain compound pendulum again.
    let (_, l) = linear(
        "pendulum_offset.adm",
        &mechanism_text("pendulum_offset.adm"),
        true,
    );
    let expected = (3.0 * G / 2.0).sqrt() / TAU;
    assert!((oscillating(&l)[0] - expected).abs() < 1e-7 * expected);
}

#[test]
fn double_pendulum_of_two_rods_matches_the_characteristic_equation() {
    // Two uniform rods (m = 1, L = 1): M = mL²[[4/3, 1/2], [1/2, 1/3]], K = mgL[[3/2, 0], [0, 1/2]];
    // det(K − ω²M) = 0 → (7/36) ω⁴ − (7/6) g ω² + (3/4) g² = 0.
    let text = linkage_solve::generate::pendulum_chain(2);
    let (_, l) = linear("double.adm", &text, false);
    let (a, b, c) = (7.0 / 36.0, -7.0 / 6.0 * G, 0.75 * G * G);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let mut expected = [
        ((-b - disc) / (2.0 * a)).sqrt() / TAU,
        ((-b + disc) / (2.0 * a)).sqrt() / TAU,
    ];
    expected.sort_by(f64::total_cmp);
    let f = oscillating(&l);
    assert_eq!(f.len(), 2, "{:?}", l.modes);
    for (got, want) in f.iter().zip(expected) {
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    }
}

#[test]
fn redundant_fourbar_has_the_frequencies_of_its_non_redundant_twin() {
    let (_, a) = linear("fourbar.adm", &mechanism_text("fourbar.adm"), true);
    let (_, b) = linear(
        "twin.adm",
        &mechanism_text("fourbar_spherical_universal.adm"),
        true,
    );
    assert_eq!(a.dof, 1);
    assert_eq!(b.dof, 1);
    let sorted = |l: &Linearization| {
        let mut v: Vec<(f64, f64)> = l.modes.iter().map(|m| (m.real, m.imag)).collect();
        v.sort_by(|x, y| x.0.total_cmp(&y.0));
        v
    };
    let (ea, eb) = (sorted(&a), sorted(&b));
    assert_eq!(ea.len(), eb.len());
    for (x, y) in ea.iter().zip(&eb) {
        let close = |p: f64, q: f64| (p - q).abs() < 1e-6 * p.abs().max(1.0);
        assert!(close(x.0, y.0) && close(x.1, y.1), "{ea:?} vs {eb:?}");
    }
    // The equilibrium Newton finds from the input pose is the unstable one (statics says so
    // too): a real eigenvalue pair ±a.
    assert!(ea.iter().any(|e| e.0 > 1.0 && e.1 == 0.0), "{ea:?}");
}

#[test]
fn free_motions_without_stiffness_are_zero_frequency_modes() {
    // A door on two aligned vertical hinges under gravity along the hinge axis: the swing has
    // no stiffness → one free motion, two zero eigenvalues, as expected.
    let (_, l) = linear("door.adm", &mechanism_text("door_two_hinges.adm"), false);
    assert_eq!(l.dof, 1);
    assert_eq!(l.zero_eigenvalues, 2);
    assert_eq!(l.expected_zero_eigenvalues, 2);
}
