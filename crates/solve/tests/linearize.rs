//! Natural frequencies against closed forms.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::applied::NoForces;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{run, EigenMethod, LinearOptions, Linearization};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::path::Path;
use std::sync::Arc;

const G: f64 = 9.80665;
const OPTS: LinearOptions = LinearOptions {
    damping: true,
    vectors: true,
    method: EigenMethod::Auto,
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
        &Assembled::new(&m, &d, &NoForces, &Tolerances::default()),
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

// ---------------------------------------------------------------------------------------------
// The sparse shift-invert path against the dense one (issue #6: equivalence of two paths).

fn linear_with(name: &str, text: &str, static_first: bool, method: EigenMethod) -> Linearization {
    let ds =
        linkage_adm::parse_dataset(Arc::from(name), text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let opts = LinearOptions { method, ..OPTS };
    run(
        &Assembled::new(&m, &d, &NoForces, &Tolerances::default()),
        static_first,
        opts,
    )
    .result
    .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Modes away from zero (|λ| > 1e-6 rad per time unit; the models here have frequencies of
/// order 1): zero modes are compared by their count, their split into one or two "modes" and
/// their values are round-off.
fn nonzero(l: &Linearization) -> Vec<&linkage_solve::stages::linearize::Mode> {
    l.modes
        .iter()
        .filter(|m| m.frequency * TAU > 1e-6)
        .collect()
}

/// Frequencies relative 1e-8, damping ratios within 1e-8 (absolute: ζ is at most 1 and often
/// 0), real and imaginary parts within 1e-8 of |λ|, and the mode shapes: magnitudes within
/// 1e-6 and phases (relative to the largest component) within 1e-4 degrees (not for repeated
/// eigenvalues, whose shapes are any combination).
fn assert_same_modes(
    sparse: &[&linkage_solve::stages::linearize::Mode],
    dense: &[&linkage_solve::stages::linearize::Mode],
    what: &str,
) {
    assert_eq!(
        sparse.len(),
        dense.len(),
        "{what}: {sparse:?}\nvs\n{dense:?}"
    );
    // Pair each dense mode with the nearest sparse one (a real pair ±a has one frequency, so
    // the order within it is round-off).
    let mut used = vec![false; sparse.len()];
    let mut matched: Vec<&linkage_solve::stages::linearize::Mode> = Vec::new();
    for d in dense {
        let dist =
            |m: &linkage_solve::stages::linearize::Mode| (m.real - d.real).hypot(m.imag - d.imag);
        let k = (0..sparse.len())
            .filter(|&k| !used[k])
            .min_by(|&a, &b| dist(sparse[a]).total_cmp(&dist(sparse[b])))
            .expect("as many sparse modes as dense ones");
        used[k] = true;
        matched.push(sparse[k]);
    }
    for (s, d) in matched.iter().zip(dense) {
        let mag = d.frequency * TAU;
        assert!(
            (s.frequency - d.frequency).abs() <= 1e-8 * d.frequency,
            "{what}: frequency {} vs {}",
            s.frequency,
            d.frequency
        );
        assert!(
            (s.damping_ratio - d.damping_ratio).abs() <= 1e-8,
            "{what}: damping ratio {} vs {}",
            s.damping_ratio,
            d.damping_ratio
        );
        assert!(
            (s.real - d.real).abs() <= 1e-8 * mag && (s.imag - d.imag).abs() <= 1e-8 * mag,
            "{what}: λ {} {} vs {} {}",
            s.real,
            s.imag,
            d.real,
            d.imag
        );
        let (Some(ss), Some(ds)) = (&s.shape, &d.shape) else {
            continue;
        };
        // A repeated eigenvalue has no unique mode shape.
        let repeated = dense
            .iter()
            .filter(|o| (o.frequency - d.frequency).abs() <= 1e-6 * d.frequency)
            .count()
            > 1;
        if repeated {
            continue;
        }
        let comps = |sh: &[linkage_solve::stages::linearize::PartShape]| {
            sh.iter()
                .flat_map(|p| p.translation.iter().chain(&p.rotation).copied())
                .collect::<Vec<_>>()
        };
        let (cs, cd) = (comps(ss), comps(ds));
        let big = |c: &[linkage_solve::stages::linearize::Component]| {
            c.iter()
                .enumerate()
                .max_by(|a, b| a.1.magnitude.total_cmp(&b.1.magnitude))
                .map(|(i, _)| i)
                .unwrap()
        };
        let (bs, bd) = (big(&cs), big(&cd));
        for (k, (a, b)) in cs.iter().zip(&cd).enumerate() {
            assert!(
                (a.magnitude - b.magnitude).abs() < 1e-6,
                "{what}: shape component {k}: {} vs {}",
                a.magnitude,
                b.magnitude
            );
            if b.magnitude > 1e-2 {
                // A complex eigenvector is fixed up to a factor e^{iφ}; a real one up to sign.
                let rel = |c: &[linkage_solve::stages::linearize::Component],
                           i: usize,
                           r: usize| { c[i].phase_deg - c[r].phase_deg };
                let diff = (rel(&cs, k, bs) - rel(&cd, k, bd)).rem_euclid(180.0);
                assert!(
                    diff.min(180.0 - diff) < 1e-4,
                    "{what}: phase of component {k}: {} vs {}",
                    rel(&cs, k, bs),
                    rel(&cd, k, bd)
                );
            }
        }
    }
}

/// Runs both paths (every mode by shift-invert when `modes` is None) and compares them.
fn compare_paths(
    name: &str,
    text: &str,
    static_first: bool,
    modes: Option<usize>,
) -> (Linearization, Linearization) {
    let dense = linear_with(name, text, static_first, EigenMethod::Dense);
    let k = modes.unwrap_or(2 * dense.dof);
    let sparse = linear_with(
        name,
        text,
        static_first,
        EigenMethod::ShiftInvert {
            modes: k,
            shift: None,
        },
    );
    assert_eq!(sparse.dof, dense.dof, "{name}");
    assert!(matches!(
        sparse.solution,
        linkage_solve::stages::linearize::Solution::ShiftInvert { .. }
    ));
    assert_eq!(
        sparse.zero_eigenvalues, dense.zero_eigenvalues,
        "{name}: zero eigenvalues"
    );
    assert_eq!(
        sparse.expected_zero_eigenvalues, dense.expected_zero_eigenvalues,
        "{name}: expected zero eigenvalues"
    );
    let (ns, nd) = (nonzero(&sparse), nonzero(&dense));
    // With K modes asked for, the sparse path has the K lowest (zero ones first).
    let zero_modes = sparse.modes.len() - ns.len();
    let wanted = if modes.is_some() {
        (k.saturating_sub(zero_modes)).min(nd.len())
    } else {
        nd.len()
    };
    assert!(ns.len() >= wanted, "{name}: {} of {wanted} modes", ns.len());
    assert_same_modes(&ns[..wanted], &nd[..wanted], name);
    (sparse, dense)
}

#[test]
fn shift_invert_reproduces_the_dense_eigenvalues_of_the_test_mechanisms() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../mechanisms");
    let mut compared = 0;
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".adm"))
        .collect();
    names.sort();
    for name in names {
        let text = mechanism_text(&name);
        for static_first in [false, true] {
            // Some mechanisms are broken on purpose (no operating point): skip what the dense
            // path cannot linearise either.
            let ds = linkage_adm::parse_dataset(Arc::from(name.as_str()), &text).unwrap();
            let m = linkage_model::build_model(&ds).unwrap().model;
            let d = ExpressionDrivers::new(&m).unwrap();
            let opts = LinearOptions {
                method: EigenMethod::Dense,
                ..OPTS
            };
            if run(
                &Assembled::new(&m, &d, &NoForces, &Tolerances::default()),
                static_first,
                opts,
            )
            .result
            .is_err()
            {
                continue;
            }
            compare_paths(&name, &text, static_first, None);
            compared += 1;
        }
    }
    assert!(compared >= 20, "only {compared} linearizations compared");
}

#[test]
fn shift_invert_reproduces_the_lowest_modes_of_a_pendulum_chain() {
    let text = linkage_solve::generate::pendulum_chain(40);
    let (sparse, dense) = compare_paths("chain40.adm", &text, false, Some(10));
    assert_eq!(dense.dof, 40);
    assert_eq!(sparse.modes.len(), 10);
    assert_eq!(sparse.computed_eigenvalues, 20);
    assert_eq!(dense.computed_eigenvalues, 80);
    // Hanging at rest: no zero eigenvalues, and the lowest frequencies in increasing order.
    assert_eq!(sparse.zero_eigenvalues, 0);
    assert!(sparse
        .modes
        .windows(2)
        .all(|w| w[0].frequency < w[1].frequency));
}

#[test]
fn shift_invert_reproduces_a_redundant_parallelogram_chain() {
    // 5 loops: 11 parts, 80 rows of which 15 are redundant and left out of J; DOF 1.
    let text = linkage_solve::generate::parallelogram_chain(5, 60.0);
    for static_first in [false, true] {
        let (sparse, dense) = compare_paths("parallelogram5.adm", &text, static_first, None);
        assert_eq!(dense.dof, 1);
        assert_eq!(sparse.computed_eigenvalues, 2);
    }
}

/// Two identical pendulums side by side (repeated frequency) and a free body in zero gravity
/// seen from a third, free part: a double eigenvalue and twelve zero eigenvalues, which a
/// single Krylov sequence cannot see (DESIGN §7: zero modes must match the free motions).
fn twins_and_a_free_body() -> String {
    let mut t = String::from(
        "twins\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         ACCGRAV/, JGRAV = -9.80665\nPART/1, GROUND\nMARKER/1, PART = 1\nMARKER/2, PART = 1, QP = 2, 0, 0\n",
    );
    for (k, x) in [(0usize, 0.0f64), (1, 2.0)] {
        let (p, m) = (2 + k, 100 + 10 * k);
        t.push_str(&format!(
            "PART/{p}, MASS = 1, CM = {}, IP = 0.0833333333333, 0.001, 0.0833333333333\n\
             MARKER/{m}, PART = {p}, QP = {x}, 0, 0\nMARKER/{}, PART = {p}, QP = {x}, -0.5, 0\n\
             JOINT/{}, REVOLUTE, I = {m}, J = {}\n",
            m + 2,
            m + 2,
            1 + k,
            1 + k
        ));
    }
    t.push_str(
        "PART/4, MASS = 3, CM = 400, IP = 0.5, 0.7, 0.9\nMARKER/400, PART = 4, QP = 5, 0, 0\nEND\n",
    );
    t
}

#[test]
fn repeated_frequencies_and_free_bodies_are_found_with_their_multiplicity() {
    let text = twins_and_a_free_body();
    let (sparse, dense) = compare_paths("twins.adm", &text, false, None);
    assert_eq!(dense.dof, 8);
    // The free body: six free motions without stiffness or damping, twelve zero eigenvalues.
    assert_eq!(dense.zero_eigenvalues, 12);
    assert_eq!(sparse.zero_eigenvalues, 12);
    assert_eq!(sparse.expected_zero_eigenvalues, 12);
    // The twins: the compound-pendulum frequency twice.
    let f = (3.0 * G / 2.0).sqrt() / TAU;
    let osc = oscillating(&sparse);
    assert_eq!(osc.len(), 2, "{osc:?}");
    assert!(osc.iter().all(|x| (x - f).abs() < 1e-9 * f), "{osc:?}");
    // The 3 lowest modes (default shift) are zero modes, but every zero eigenvalue is counted.
    let few = linear_with(
        "twins.adm",
        &text,
        false,
        EigenMethod::ShiftInvert {
            modes: 3,
            shift: None,
        },
    );
    assert_eq!(few.zero_eigenvalues, 12);
    assert_eq!(few.expected_zero_eigenvalues, 12);
    // Six free motions (at least six zero modes) and the double pendulum frequency: 8 modes.
    let eight = linear_with(
        "twins.adm",
        &text,
        false,
        EigenMethod::ShiftInvert {
            modes: 8,
            shift: None,
        },
    );
    assert_eq!(oscillating(&eight).len(), 2);
}

#[test]
fn zero_frequency_door_swing_through_the_sparse_path() {
    let l = linear_with(
        "door.adm",
        &mechanism_text("door_two_hinges.adm"),
        false,
        EigenMethod::ShiftInvert {
            modes: 3,
            shift: None,
        },
    );
    assert_eq!(l.dof, 1);
    assert_eq!(l.computed_eigenvalues, 2);
    assert_eq!(l.zero_eigenvalues, 2);
    assert_eq!(l.expected_zero_eigenvalues, 2);
    assert!(l.modes.iter().all(|m| m.frequency * TAU < 1e-6));
}

#[test]
fn a_shift_selects_the_modes_nearest_a_frequency() {
    // Pendulum chain of 12 links, shift at the 6th frequency: the operator Re (A − σB)⁻¹B with
    // σ = iω₆ ranks λ = iω by |ψ| = ω / (|ω − ω₆| (ω + ω₆)); the 3 largest are the 5th–7th.
    let text = linkage_solve::generate::pendulum_chain(12);
    let dense = linear_with("chain12.adm", &text, false, EigenMethod::Dense);
    let w6 = dense.modes[5].frequency * TAU;
    let psi = |m: &linkage_solve::stages::linearize::Mode| {
        let w = m.frequency * TAU;
        w / ((w - w6).abs() * (w + w6)).max(1e-300)
    };
    let mut ranked: Vec<&linkage_solve::stages::linearize::Mode> = dense.modes.iter().collect();
    ranked.sort_by(|a, b| psi(b).total_cmp(&psi(a)));
    assert!(psi(ranked[2]) > 1.2 * psi(ranked[3]), "no clear third mode");
    let mut want: Vec<f64> = ranked[..3].iter().map(|m| m.frequency).collect();
    want.sort_by(f64::total_cmp);
    assert_eq!(
        want,
        dense.modes[4..7]
            .iter()
            .map(|m| m.frequency)
            .collect::<Vec<_>>()
    );
    let l = linear_with(
        "chain12.adm",
        &text,
        false,
        EigenMethod::ShiftInvert {
            modes: 3,
            shift: Some(w6),
        },
    );
    let got: Vec<f64> = l.modes.iter().map(|m| m.frequency).collect();
    assert_eq!(got.len(), 3, "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() < 1e-8 * w, "{got:?} vs {want:?}");
    }
    assert!(l.modes.iter().all(|m| m.damping_ratio.abs() < 1e-8));
    assert!(matches!(
        l.solution,
        linkage_solve::stages::linearize::Solution::ShiftInvert {
            zeros_complete: false,
            ..
        }
    ));
}

#[test]
fn large_models_use_the_sparse_path_by_default() {
    // 320 links: 1920 coordinates, over the dense limits.
    let text = linkage_solve::generate::pendulum_chain(320);
    let l = linear_with("chain320.adm", &text, false, EigenMethod::Auto);
    assert_eq!(l.dof, 320);
    assert!(matches!(
        l.solution,
        linkage_solve::stages::linearize::Solution::ShiftInvert { .. }
    ));
    assert_eq!(
        l.modes.len(),
        linkage_solve::stages::linearize::DEFAULT_MODES
    );
    assert_eq!(
        l.computed_eigenvalues,
        2 * linkage_solve::stages::linearize::DEFAULT_MODES
    );
    // The lowest mode of a long hanging chain of N unit links tends to the heavy chain's
    // ω₁ = 2.405/2 √(g/L_total) (first zero of J₀); within 1% at N = 320.
    let w1 = 2.404_825_557_695_773 / 2.0 * (G / 320.0).sqrt();
    let f1 = l.modes[0].frequency * TAU;
    assert!((f1 - w1).abs() < 1e-2 * w1, "{f1} vs {w1}");
}
