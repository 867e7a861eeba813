//! `linkage static` finds a stable equilibrium when Newton does not: the descent off an
//! unstable equilibrium, from an input where Newton runs away, and the refusal of a model with
//! none (issue 32).

mod common;
use common::{corpus, json, run};

/// A double pendulum of two uniform-mass rods (1 m, 1 kg each) in the x–y plane under gravity
/// −y, both links along `angle` from the upward vertical (10° from the inverted pose).
fn double_pendulum(angle_deg: f64) -> std::path::PathBuf {
    let (s, c) = angle_deg.to_radians().sin_cos();
    let d = |k: f64| format!("{}, {}, 0", -s * k, c * k);
    let text = format!(
        "double pendulum 10 deg from inverted\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/101, PART = 1\n\
         PART/2, MASS = 1, CM = 201, IP = 0.0833, 0.0833, 0.0833, QG = {}\n\
         MARKER/201, PART = 2, QP = {}\n\
         MARKER/202, PART = 2, QP = 0, 0, 0\n\
         MARKER/203, PART = 2, QP = {}\n\
         PART/3, MASS = 1, CM = 301, IP = 0.0833, 0.0833, 0.0833\n\
         MARKER/301, PART = 3, QP = {}\n\
         MARKER/302, PART = 3, QP = {}\n\
         JOINT/1, REVOLUTE, I = 202, J = 101\n\
         JOINT/2, REVOLUTE, I = 302, J = 203\n\
         ACCGRAV/JGRAV = -9.80665\n\
         END\n",
        d(0.0),
        d(0.5),
        d(1.0),
        d(1.5),
        d(1.0),
    );
    let f = std::env::temp_dir().join(format!(
        "linkage-double-pendulum-{}-{angle_deg}.adm",
        std::process::id()
    ));
    std::fs::write(&f, text).unwrap();
    f
}

fn position(v: &serde_json::Value, part: usize) -> [f64; 3] {
    let p = &v["parts"][part]["position"];
    [0, 1, 2].map(|i| p[i].as_f64().unwrap())
}

#[test]
fn a_double_pendulum_ten_degrees_from_inverted_hangs_straight_down() {
    let f = double_pendulum(10.0);
    let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], true, "{v}");
    assert_eq!(v["search"]["found"], true, "{v}");
    assert_ne!(v["search"]["path"], "newton", "{v}");
    // Closed form: both links straight down from the pivot, CMs at y = −0.5 and −1.5 m.
    let (a, b) = (position(&v, 0), position(&v, 1));
    for (got, want) in [(a, [0.0, -0.5, 0.0]), (b, [0.0, -1.5, 0.0])] {
        for i in 0..3 {
            assert!((got[i] - want[i]).abs() < 1e-6, "{got:?} vs {want:?}: {v}");
        }
    }
    // --allow-unstable keeps Newton's first equilibrium: the inverted pose (CMs at +0.5, +1.5).
    let (code, v) = json(&[
        "static",
        f.to_str().unwrap(),
        "--allow-unstable",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["search"]["path"], "newton", "{v}");
    assert_eq!(v["stable"], false, "{v}");
    assert!((position(&v, 1)[1] - 1.5).abs() < 1e-6, "{v}");
}

#[test]
fn a_free_falling_body_is_refused_with_the_reason() {
    let text = "free body\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/101, PART = 1\n\
         PART/2, MASS = 1, CM = 201, IP = 1, 1, 1\n\
         MARKER/201, PART = 2\n\
         ACCGRAV/JGRAV = -9.80665\n\
         END\n";
    let f = std::env::temp_dir().join(format!("linkage-falling-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, out, _) = run(&["static", f.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("No equilibrium was accepted."), "{out}");
    assert!(
        out.contains("free motions that nothing resists"),
        "the reason: {out}"
    );
    // Refused without settling: a body that falls for ever would only use the time budget.
    assert!(!out.contains("settling "), "{out}");
}

/// Corpus datasets (by the end of their file names) with a stable equilibrium that Adams'
/// Newton (25 iterations) did not reach before: each now reaches a stable one.
const STABLE: &[&str] = &[
    "test_Distance_Case02.adm",
    "test_Distance_Case03.adm",
    "MultiBodySystemDynamics__MODEL_test7.adm",
    "MultiBodySystemDynamics__MODEL_test10.adm",
    "MultiBodySystemDynamics__test__LWR_6DOF_GRABER.adm",
    "a2m__samples__bipendololeo.adm",
    "fitestv1__Fkinev1.adm",
];

#[test]
fn corpus_models_with_a_stable_equilibrium_reach_it() {
    let Some(dir) = corpus() else { return };
    let all: Vec<std::path::PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    for stem in STABLE {
        let found: Vec<_> = all
            .iter()
            .filter(|p| p.to_string_lossy().ends_with(stem))
            .collect();
        assert_eq!(found.len(), 1, "{stem}");
        let f = found[0];
        let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
        assert_eq!(code, 0, "{}: {v}", f.display());
        assert_eq!(v["converged"], true, "{}", f.display());
        assert_eq!(v["stable"], true, "{}", f.display());
    }
}
