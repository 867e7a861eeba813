//! Statics, linearization and dynamics with force elements, against closed forms.

use linkage_model::Model;
use linkage_solve::constraints::drivers::ExpressionDrivers;
use linkage_solve::physics::forces::ForceSet;
use linkage_solve::pipeline::Assembled;
use linkage_solve::stages::linearize::{EigenMethod, LinearOptions};
use linkage_solve::tolerances::Tolerances;
use std::f64::consts::TAU;
use std::sync::Arc;

const G: f64 = 9.80665;

fn load(text: &str) -> (Model, ExpressionDrivers, ForceSet) {
    let ds = linkage_adm::parse_dataset(Arc::from("t.adm"), text).unwrap_or_else(|e| panic!("{e}"));
    let m = linkage_model::build_model(&ds)
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let d = ExpressionDrivers::new(&m).unwrap();
    let f = ForceSet::new(&m).unwrap_or_else(|e| panic!("{e}"));
    (m, d, f)
}

/// A block of mass m on a vertical guide (translational joint along y) hanging from a spring
/// to ground, free length 0.5 m, spring attached 1 m above the block's pin.
fn spring_on_guide(m: f64, k: f64, c: f64) -> String {
    format!(
        "spring on a guide\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
PART/1, GROUND\nMARKER/1, PART = 1, QP = 0, 1, 0\nMARKER/2, PART = 1, REULER = 0D, -90D, 0D\n\
PART/2, MASS = {m}, CM = 20, IP = 0.01, 0.01, 0.01\nMARKER/20, PART = 2\nMARKER/21, PART = 2, REULER = 0D, -90D, 0D\n\
JOINT/1, TRANSLATIONAL, I = 21, J = 2\nSPRINGDAMPER/1, TRANSLATIONAL, I = 20, J = 1, K = {k}, C = {c}, LENGTH = 0.5\n\
ACCGRAV/, JGRAV = -9.80665\nEND\n"
    )
}

#[test]
fn spring_and_mass_on_a_guide_deflect_by_mg_over_k() {
    let (m, d, f) = load(&spring_on_guide(2.0, 1000.0, 0.0));
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    // Spring from y = 1 down to the block: length 1 − y; equilibrium k(1 − y − 0.5) = m g.
    let y = eq.state.poses[0].p.y;
    let expected = 1.0 - 0.5 - 2.0 * G / 1000.0;
    assert!((y - expected).abs() < 1e-9, "{y} vs {expected}");
    assert_eq!(eq.stability.map(|s| s.0), Some(true));
}

#[test]
fn mass_spring_damper_frequency_and_damping_ratio() {
    // ADM-REFERENCE §12: m = 1, k = 100, c = 2 → λ = −1 ± 9.94987i rad/s, fn = 1.59155 Hz,
    // ζ = 0.1; without damping Imag = 1.59155 Hz.
    let (m, d, f) = load(&spring_on_guide(1.0, 100.0, 2.0));
    let run = linkage_solve::stages::linearize::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        true,
        LinearOptions {
            damping: true,
            vectors: false,
            method: EigenMethod::Auto,
        },
    );
    let l = run.result.unwrap();
    assert_eq!(l.dof, 1);
    let mode = &l.modes[0];
    assert!((mode.frequency - 10.0 / TAU).abs() < 1e-9, "{mode:?}");
    assert!((mode.damping_ratio - 0.1).abs() < 1e-9, "{mode:?}");
    assert!(
        (mode.real / TAU + 0.159155).abs() < 1e-6 && (mode.imag / TAU - 1.58357).abs() < 1e-5,
        "{mode:?}"
    );
    let run = linkage_solve::stages::linearize::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        true,
        LinearOptions {
            damping: false,
            vectors: false,
            method: EigenMethod::Auto,
        },
    );
    let mode = &run.result.unwrap().modes[0];
    assert!(
        mode.real.abs() < 1e-9 && (mode.imag / TAU - 1.59155).abs() < 1e-5,
        "{mode:?}"
    );
}

#[test]
fn pendulum_with_a_torsion_spring_settles_where_the_torques_balance() {
    // Rod (m = 2, L = 1) pinned at its top end, hanging along −y; a rotational spring about the
    // pivot with KT = 5 N·m/rad whose free angle is 60° (about +z): KT(60° − θ) = m g (L/2) sin θ.
    // mechanisms/pendulum.adm: hinge JOINT/1 with I = 202 (rod top), J = 102 (ground origin),
    // axis global z.
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../mechanisms/pendulum.adm"),
    )
    .unwrap()
    .replace(
        "\nEND",
        "\nSPRINGDAMPER/1, ROTATIONAL, I = 202, J = 102, KT = 5, ANGLE = 60D\nEND",
    );
    assert!(text.contains("SPRINGDAMPER"));
    let (m, d, f) = load(&text);
    let r = linkage_solve::stages::statics::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        &[0.0],
    );
    let eq = r.steps[0].1.as_ref().unwrap();
    assert!(eq.converged, "{:?}", eq.worst);
    // θ from the torque balance (bisection).
    let g = |th: f64| 5.0 * (60f64.to_radians() - th) - 2.0 * G * 0.5 * th.sin();
    let (mut a, mut b) = (0.0f64, 60f64.to_radians());
    for _ in 0..200 {
        let c = 0.5 * (a + b);
        if g(c) > 0.0 {
            a = c
        } else {
            b = c
        }
    }
    let theta = 0.5 * (a + b);
    // Pivot at the rod's top end; CM 0.5 below it when hanging.
    let pivot = m
        .marker_in_ground(m.markers.iter().position(|mk| mk.id == 102).unwrap())
        .0;
    let cm = eq.state.poses[0].p - pivot;
    let got = cm.x.atan2(-cm.y).abs();
    assert!(
        (got - theta).abs() < 1e-6,
        "{} vs {}",
        got.to_degrees(),
        theta.to_degrees()
    );
}

#[test]
fn damped_mass_spring_through_the_sparse_path() {
    // m = 2, k = 300, c = 3: ω_n = √(k/m), ζ = c/(2√(km)), λ = −ζω_n ± iω_n√(1 − ζ²).
    let (mass, k, c) = (2.0, 300.0, 3.0);
    let (m, d, f) = load(&spring_on_guide(mass, k, c));
    let run = linkage_solve::stages::linearize::run(
        &Assembled::new(&m, &d, &f, &Tolerances::default()),
        true,
        LinearOptions {
            damping: true,
            vectors: true,
            method: EigenMethod::ShiftInvert {
                modes: 1,
                shift: None,
            },
        },
    );
    let l = run.result.unwrap();
    assert!(matches!(
        l.solution,
        linkage_solve::stages::linearize::Solution::ShiftInvert { .. }
    ));
    assert_eq!((l.dof, l.computed_eigenvalues, l.modes.len()), (1, 2, 1));
    let wn = (k / mass).sqrt();
    let zeta = c / (2.0 * (k * mass).sqrt());
    let mode = &l.modes[0];
    assert!((mode.frequency * TAU - wn).abs() < 1e-9 * wn, "{mode:?}");
    assert!((mode.damping_ratio - zeta).abs() < 1e-9, "{mode:?}");
    assert!((mode.real + zeta * wn).abs() < 1e-9 * wn, "{mode:?}");
    assert!(
        (mode.imag - wn * (1.0 - zeta * zeta).sqrt()).abs() < 1e-9 * wn,
        "{mode:?}"
    );
    // The block moves along the guide (global y) only.
    let shape = &mode.shape.as_ref().unwrap()[0];
    assert!(
        (shape.translation[1].magnitude - 1.0).abs() < 1e-12,
        "{shape:?}"
    );
    assert!(shape.translation[0].magnitude < 1e-9 && shape.rotation[2].magnitude < 1e-9);
    assert_eq!((l.zero_eigenvalues, l.expected_zero_eigenvalues), (0, 0));
}

/// A chain of `n` pendulum links with a rotational damper (and a weak torsion spring) at each
/// joint: non-proportional damping, complex mode shapes.
fn damped_chain(n: usize, ct: f64, kt: f64) -> String {
    let text = linkage_solve::generate::pendulum_chain(n);
    let mut extra = String::new();
    for k in 0..n {
        let m = 100 + 10 * k;
        let j = if k == 0 { 1 } else { 100 + 10 * (k - 1) + 1 };
        extra.push_str(&format!(
            "SPRINGDAMPER/{}, ROTATIONAL, I = {m}, J = {j}, KT = {kt}, CT = {ct}\n",
            1 + k
        ));
    }
    text.replace("END\n", &format!("{extra}END\n"))
}

#[test]
fn damped_chain_shift_invert_matches_the_dense_eigenvalues() {
    // First-order shift-invert path (C ≠ 0) against the dense solution: every mode, and then
    // the 4 lowest, λ within 1e-8 |λ| and ζ within 1e-8.
    let (m, d, f) = load(&damped_chain(8, 0.3, 0.5));
    let solve = |method| {
        linkage_solve::stages::linearize::run(
            &Assembled::new(&m, &d, &f, &Tolerances::default()),
            true,
            LinearOptions {
                damping: true,
                vectors: false,
                method,
            },
        )
        .result
        .unwrap()
    };
    let dense = solve(EigenMethod::Dense);
    assert_eq!(dense.dof, 8);
    assert!(dense
        .modes
        .iter()
        .all(|m| m.damping_ratio > 0.0 && m.damping_ratio < 1.0));
    for k in [16, 4] {
        let sparse = solve(EigenMethod::ShiftInvert {
            modes: k,
            shift: None,
        });
        assert_eq!(sparse.modes.len(), k.min(dense.modes.len()), "{sparse:?}");
        for (s, e) in sparse.modes.iter().zip(&dense.modes) {
            let mag = e.frequency * TAU;
            assert!(
                (s.real - e.real).abs() < 1e-8 * mag && (s.imag - e.imag).abs() < 1e-8 * mag,
                "K = {k}: {s:?} vs {e:?}"
            );
            assert!((s.damping_ratio - e.damping_ratio).abs() < 1e-8);
        }
    }
}

#[test]
fn damped_chain_modes_around_a_frequency_match_dense_modes() {
    // Complex shift σ = −ε + iω₅ (operator Re (A − σB)⁻¹B): 3 modes, each one of the dense
    // solution (λ within 1e-8 |λ|), the 5th among them.
    let (m, d, f) = load(&damped_chain(8, 0.3, 0.5));
    let solve = |method| {
        linkage_solve::stages::linearize::run(
            &Assembled::new(&m, &d, &f, &Tolerances::default()),
            true,
            LinearOptions {
                damping: true,
                vectors: true,
                method,
            },
        )
        .result
        .unwrap()
    };
    let dense = solve(EigenMethod::Dense);
    let w5 = dense.modes[4].frequency * TAU;
    let near = solve(EigenMethod::ShiftInvert {
        modes: 3,
        shift: Some(w5),
    });
    assert_eq!(near.modes.len(), 3, "{:?}", near.modes);
    for s in &near.modes {
        let e = dense
            .modes
            .iter()
            .min_by(|a, b| {
                let da = (a.real - s.real).hypot(a.imag - s.imag);
                let db = (b.real - s.real).hypot(b.imag - s.imag);
                da.total_cmp(&db)
            })
            .unwrap();
        let mag = e.frequency * TAU;
        assert!(
            (s.real - e.real).abs() < 1e-8 * mag && (s.imag - e.imag).abs() < 1e-8 * mag,
            "{s:?} vs {e:?}"
        );
        assert!((s.damping_ratio - e.damping_ratio).abs() < 1e-8);
    }
    let f5 = dense.modes[4].frequency;
    assert!(near
        .modes
        .iter()
        .any(|s| (s.frequency - f5).abs() < 1e-8 * f5));
}

/// A door on a vertical hinge under gravity along the hinge: its free rotation carries no
/// stiffness at all, and the reduced stiffness computes to rounding of either sign. That is a
/// neutral equilibrium, not an unstable one.
#[test]
fn a_free_motion_without_stiffness_is_not_called_unstable() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../mechanisms/door_hinge_spherical_inline.adm"),
    )
    .expect("mechanism");
    let ds = linkage_adm::parse_dataset(std::sync::Arc::from("door.adm"), &text).expect("parses");
    let model = linkage_model::build_model(&ds).expect("builds").model;
    let drivers =
        linkage_solve::constraints::drivers::ExpressionDrivers::new(&model).expect("drivers");
    let a = linkage_solve::pipeline::Assembled::new(
        &model,
        &drivers,
        &linkage_solve::physics::applied::NoForces,
        &linkage_solve::tolerances::Tolerances::default(),
    );
    let run = linkage_solve::stages::statics::run(&a, &[0.0]);
    let eq = run.steps[0].1.as_ref().expect("solves");
    assert!(eq.converged);
    let (stable, lowest) = eq.stability.expect("evaluated");
    assert!(lowest.abs() < 1e-9, "a rounding-level stiffness: {lowest}");
    assert!(stable, "neutral, not unstable: {lowest}");
}
