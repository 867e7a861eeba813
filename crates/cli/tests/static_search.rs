//! `linkage static` finds a stable equilibrium when Newton does not: the descent off an
//! unstable equilibrium (a double pendulum near inverted, a tensioned chain released folded),
//! from an input where Newton runs away, `--settle` of an undamped pendulum chain, and the
//! refusal of a model with none, with the reason (a falling body, a block on a ramp steeper
//! than its friction angle) (issue 32).

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

/// A planar chain of uniform rods (1 m, 1 kg each) hinged to ground at the origin and to each
/// other, link k along `angles_deg[k]` measured from −y (straight down is 0°), then
/// `extra` statements (the tip's end marker is 100·n + 3 for n links). Gravity −y when
/// `gravity`, else along z, across the hinges (no work in the plane).
fn chain(name: &str, angles_deg: &[f64], gravity: bool, extra: &str) -> std::path::PathBuf {
    let mut text = format!(
        "chain {name}\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/101, PART = 1\n"
    );
    let mut at = [0.0f64; 2];
    for (k, a) in angles_deg.iter().enumerate() {
        let (s, c) = a.to_radians().sin_cos();
        let u = [s, -c];
        let p = |f: f64| format!("{}, {}, 0", at[0] + f * u[0], at[1] + f * u[1]);
        let id = 100 * (k + 2);
        text += &format!(
            "PART/{n}, MASS = 1, CM = {m1}, IP = 0.0833, 0.0833, 0.0833\n\
             MARKER/{m1}, PART = {n}, QP = {}\n\
             MARKER/{m2}, PART = {n}, QP = {}\n\
             MARKER/{m3}, PART = {n}, QP = {}\n\
             JOINT/{n}, REVOLUTE, I = {m2}, J = {prev}\n",
            p(0.5),
            p(0.0),
            p(1.0),
            n = k + 2,
            m1 = id + 1,
            m2 = id + 2,
            m3 = id + 3,
            prev = if k == 0 { 101 } else { id - 100 + 3 },
        );
        at = [at[0] + u[0], at[1] + u[1]];
    }
    text += if gravity {
        "ACCGRAV/JGRAV = -9.80665\n"
    } else {
        "ACCGRAV/KGRAV = -9.80665\n"
    };
    text += extra;
    text += "END\n";
    let f = std::env::temp_dir().join(format!("linkage-chain-{name}-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

#[test]
fn a_tensioned_chain_released_far_from_rest_pulls_straight() {
    // Three links folded back on themselves (0°, 160°, −30° from −y; no gravity in the
    // plane); a spring (k = 100 N/m, free length 0.5 m) from the tip (marker 403) to a ground
    // anchor at (0, −4) holds the chain in tension. The one stable equilibrium is the straight
    // chain pointing at the anchor: CMs at y = −0.5, −1.5, −2.5, the spring stretched to 1 m
    // (tension 50 N).
    let f = chain(
        "tensioned",
        &[0.0, 160.0, -30.0],
        false,
        "MARKER/102, PART = 1, QP = 0, -4, 0\n\
         SPRINGDAMPER/1, TRANSLATION, I = 403, J = 102, K = 100, C = 0, LENGTH = 0.5\n",
    );
    let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], true, "{v}");
    for (k, y) in [-0.5, -1.5, -2.5].into_iter().enumerate() {
        let p = position(&v, k);
        assert!(
            p[0].abs() < 1e-6 && (p[1] - y).abs() < 1e-6,
            "link {k}: {p:?}: {v}"
        );
    }
    // Newton from the folded input stops on a folded (unstable) equilibrium; the search goes
    // on to the straight chain.
    assert_eq!(v["search"]["attempts"][0]["path"], "newton", "{v}");
    assert_eq!(v["search"]["attempts"][0]["stable"], false, "{v}");
    assert_eq!(v["search"]["found"], true, "{v}");
    let _ = std::fs::remove_file(&f);
}

#[test]
fn undamped_pendulum_chain_settles_to_hanging_straight_down() {
    // Four links at 30°, 60°, 90°, 45° from the hanging pose, GLOBAL_DAMPING 0 (Adams'
    // default): `static --settle` chooses the damping and comes to rest hanging straight
    // down, CMs at y = −0.5, −1.5, −2.5, −3.5 m.
    let f = chain("settle", &[30.0, 60.0, 90.0, 45.0], true, "");
    let (code, v) = json(&[
        "static",
        f.to_str().unwrap(),
        "--settle",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["converged"], true, "{v}");
    assert_eq!(v["stable"], true, "{v}");
    for (k, y) in [-0.5, -1.5, -2.5, -3.5].into_iter().enumerate() {
        let p = position(&v, k);
        assert!(
            p[0].abs() < 1e-6 && (p[1] - y).abs() < 1e-6,
            "link {k}: {p:?}: {v}"
        );
    }
    assert_eq!(v["settling"]["global_damping"], 0.0, "{v}");
    assert_eq!(v["settling"]["damping_from_model"], true, "{v}");
    assert_eq!(v["settling"]["criterion"], "settled", "{v}");
    let _ = std::fs::remove_file(&f);
}

#[test]
fn a_block_on_a_ramp_steeper_than_its_friction_angle_is_refused_with_the_reason() {
    // 40° ramp, μs = 0.5: tan 40° = 0.84 > μs, so friction cannot hold the 2 kg block.
    let (s, c) = 40f64.to_radians().sin_cos();
    let g = 9.80665;
    let text = format!(
        "block on a steep ramp\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/11, PART = 1\n\
         PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1\nMARKER/20, PART = 2\nMARKER/21, PART = 2\n\
         JOINT/1, TRANSLATIONAL, I = 21, J = 11\n\
         FRICTION/1, JOINT = 1, MU_STATIC = 0.5, MU_DYNAMIC = 0.3, INPUTS = REACTION_FORCE\n\
         ACCGRAV/JGRAV = {}, KGRAV = {}\nEND\n",
        -g * c,
        -g * s
    );
    let f = std::env::temp_dir().join(format!("linkage-steep-ramp-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, out, _) = run(&["static", f.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("No equilibrium was accepted."), "{out}");
    // The reason: the friction holds at most μs·N = μs·m·g·cos 40° = 7.512 N of the
    // m·g·sin 40° = 12.61 N along the joint; the imbalance left is their difference, 5.095 N.
    let limit = 0.5 * 2.0 * g * c;
    assert!(
        out.contains(&format!(
            "FRICTION_1 is at its static limit μs·N = {}",
            linkage_adm::num::sci(limit, 4)
        )),
        "{out}"
    );
    assert!(
        out.contains("along JOINT_1 is more than static friction holds"),
        "{out}"
    );
    let imbalance = 2.0 * g * s - limit;
    assert!(
        out.contains(&format!("({})", linkage_adm::num::sci(-imbalance, 4))),
        "imbalance m·g·(sin θ − μs·cos θ) = {imbalance}: {out}"
    );
    // Refused without settling: a block that slides for ever would only use the time budget.
    assert!(!out.contains("settling "), "{out}");
    let _ = std::fs::remove_file(&f);
}

#[test]
fn an_unstable_quasi_static_series_suggests_only_what_works_on_a_series() {
    // The series starts on Newton's inverted equilibrium and follows it: `--settle` takes no
    // series, so the message does not send the user there.
    let f = double_pendulum(10.0);
    let (code, out, _) = run(&["static", f.to_str().unwrap(), "--end", "1", "--steps", "1"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("is UNSTABLE"), "{out}");
    assert!(
        out.contains("the series follows the equilibrium it started from"),
        "{out}"
    );
    assert!(!out.contains("--settle"), "{out}");
    let (code, _, err) = run(&[
        "static",
        f.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "1",
        "--allow-unstable",
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn a_singular_newton_matrix_with_stability_zero_suggests_a_positive_stability() {
    // A free body under gravity with EQUILIBRIUM/STABILITY = 0: nothing (no stiffness, no
    // inertia term) holds its six motions, so the Newton matrix is singular.
    let text = "free body, stability 0\n\
         UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\n\
         MARKER/101, PART = 1\n\
         PART/2, MASS = 1, CM = 201, IP = 1, 1, 1\n\
         MARKER/201, PART = 2\n\
         ACCGRAV/JGRAV = -9.80665\n\
         EQUILIBRIUM/STABILITY = 0\n\
         END\n";
    let f = std::env::temp_dir().join(format!("linkage-stability0-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, out, _) = run(&["static", f.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("the static Newton matrix cannot be factorised"),
        "{out}"
    );
    assert!(
        out.contains("EQUILIBRIUM has STABILITY = 0: a positive STABILITY"),
        "{out}"
    );
    // With Adams' default STABILITY the same body is refused for the motion nothing resists,
    // with no STABILITY advice.
    std::fs::write(&f, text.replace("EQUILIBRIUM/STABILITY = 0\n", "")).unwrap();
    let (code, out, _) = run(&["static", f.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(!out.contains("STABILITY"), "{out}");
    let _ = std::fs::remove_file(&f);
}
