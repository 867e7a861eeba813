//! `linkage simulate` end to end: where a run starts (initial conditions, Newton or settled
//! equilibrium), what the summary says about removed equations and the final state, and how
//! a run that cannot start fails.

mod common;
use common::{json, root, run};
use std::path::PathBuf;

const G: f64 = 9.80665;

/// `mechanisms/pendulum_offset.adm` with `extra` statements before END, written to a temp
/// file named after `tag`.
fn pendulum_with(tag: &str, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum_offset.adm"))
        .unwrap()
        .replace("END", &format!("{extra}\nEND"));
    let f = std::env::temp_dir().join(format!("linkage-sim-{tag}-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    f
}

/// `pendulum_offset` with its tip tied by a zero-length spring (K = 200) to the ground point
/// (1.3, 0.2, 0), and the given EQUILIBRIUM statement. Equilibrium angle from hanging:
/// `tan θ = k / (k + m g / 2)` (moment balance about the pivot; see the solver's dynamics
/// tests), 43.63°.
fn tied_pendulum(tag: &str, equilibrium: &str) -> PathBuf {
    pendulum_with(
        tag,
        &format!(
            "MARKER/104, PART = 1, QP = 1.3, 0.2, 0\n\
             SPRINGDAMPER/1, TRANSLATIONAL, I = 203, J = 104, K = 200, C = 0, LENGTH = 0\n\
             {equilibrium}"
        ),
    )
}

/// `linkage simulate FILE --end 0.5 --start-at-equilibrium`: exit code, stdout, stderr.
fn simulate_from_equilibrium(f: &std::path::Path) -> (i32, String, String) {
    run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "0.5",
        "--start-at-equilibrium",
    ])
}

/// `linkage simulate FILE --end 0.5 --steps 5 [extra…] --format json`.
fn simulate_json(f: &std::path::Path, extra: &[&str]) -> (i32, serde_json::Value) {
    let mut args = vec![
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "0.5",
        "--steps",
        "5",
        "--format",
        "json",
    ];
    args.extend_from_slice(extra);
    json(&args)
}

fn equilibrium_angle() -> f64 {
    (200.0 / (200.0 + 2.0 * G / 2.0)).atan()
}

fn angle_of(v: &serde_json::Value) -> f64 {
    let x = v[0].as_f64().unwrap();
    let y = v[1].as_f64().unwrap();
    (x - 0.3).atan2(1.2 - y)
}

#[test]
fn start_at_equilibrium_by_settling_starts_at_rest_at_the_equilibrium() {
    let f = tied_pendulum(
        "settle",
        "EQUILIBRIUM/, GLOBAL_DAMPING = 5, SETTLING_TIME = 20",
    );
    let (code, v) = simulate_json(&f, &["--start-at-equilibrium", "--settle"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["start"]["from"], "settled_equilibrium");
    assert_eq!(v["start"]["found"], true);
    let st = &v["start"]["settling"];
    assert_eq!(st["criterion"], "settled");
    assert!(st["kinetic_energy"].as_f64().unwrap() <= st["kinetic_energy_limit"].as_f64().unwrap());
    assert!(st["acceleration"].as_f64().unwrap() <= st["acceleration_limit"].as_f64().unwrap());
    assert_eq!(st["polish_converged"], true);
    assert_eq!(v["completed"], true);
    // After 0.5 s the rod is still at the equilibrium angle, at rest.
    let rod = &v["final_state"][0];
    assert_eq!(rod["name"], "rod");
    assert!(
        (angle_of(&rod["position"]) - equilibrium_angle()).abs() < 1e-8,
        "{rod}"
    );
    for k in 0..3 {
        assert!(
            rod["angular_velocity"][k].as_f64().unwrap().abs() < 1e-8,
            "{rod}"
        );
    }
    // --settle needs --start-at-equilibrium.
    let (code, _, err) = run(&["simulate", f.to_str().unwrap(), "--end", "0.5", "--settle"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn equilibrium_dynamic_in_the_dataset_makes_the_start_settle() {
    let f = tied_pendulum(
        "dynamic",
        "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 5, SETTLING_TIME = 20",
    );
    let (code, text, _) = simulate_from_equilibrium(&f);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("Dynamic settling (GLOBAL_DAMPING 5"),
        "{text}"
    );
    assert!(text.contains("settled after"), "{text}");
    assert!(
        text.contains("Started at rest from the settled equilibrium"),
        "{text}"
    );
    // Without DYNAMIC the same option uses Newton statics.
    let f = tied_pendulum("newton", "");
    let (code, v) = simulate_json(&f, &["--start-at-equilibrium"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["start"]["from"], "static_equilibrium");
    assert!(v["start"].get("settling").is_none());
    assert!((angle_of(&v["final_state"][0]["position"]) - equilibrium_angle()).abs() < 1e-8);
}

#[test]
fn a_start_that_does_not_settle_exits_1_naming_the_limits() {
    // A dataset damping (GLOBAL_DAMPING 0 would have it chosen from the model, which settles)
    // far too light for SETTLING_TIME 1.
    let f = tied_pendulum(
        "swinging",
        "EQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 0.01, SETTLING_TIME = 1",
    );
    let (code, text, err) = simulate_from_equilibrium(&f);
    assert_eq!(code, 1, "{text}");
    assert!(
        text.contains("did NOT settle: SETTLING_TIME 1 ran out"),
        "{text}"
    );
    assert!(text.contains("No simulation was run."), "{text}");
    assert!(
        err.contains("no static equilibrium to start from: the model did not settle within SETTLING_TIME = 1"),
        "{err}"
    );
}

#[test]
fn summary_lists_the_removed_equations_and_the_final_state() {
    let src = root().join("mechanisms/door_two_hinges.adm");
    let (code, v) = simulate_json(&src, &[]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["start"]["from"], "initial_conditions");
    let removed = v["removed_equations"].as_array().unwrap();
    assert_eq!(removed.len(), 5, "{v}");
    assert!(removed
        .iter()
        .any(|e| e["name"] == "hinge_top" && e["short"] == "Yg"));
    // The door hangs in neutral equilibrium (gravity along the hinge axis): it stays at its
    // input pose, CM (0.4, 1.0, 0).
    let door = &v["final_state"][0];
    for (k, want) in [0.4, 1.0, 0.0].iter().enumerate() {
        assert!(
            (door["position"][k].as_f64().unwrap() - want).abs() < 1e-9,
            "{door}"
        );
        assert!(
            door["acceleration"][k].as_f64().unwrap().abs() < 1e-9,
            "{door}"
        );
    }
    let (_, text, _) = run(&["simulate", src.to_str().unwrap(), "--end", "0.2"]);
    assert!(
        text.contains("5 redundant constraint equation(s) left out, as in verify"),
        "{text}"
    );
    assert!(text.contains("hinge_top                Translation of I Marker Along Yg (Yg)"));
}

#[test]
fn a_model_with_an_inconsistent_redundancy_is_not_run_and_the_equation_is_named() {
    let src = root().join("mechanisms/door_tilted_hinge.adm");
    let (code, v) = simulate_json(&src, &[]);
    assert_eq!(code, 1, "{v}");
    assert_eq!(v["start"]["found"], false);
    let e = v["errors"][0].as_str().unwrap();
    assert!(
        e.contains("Rotation Between Zi & Yj of hinge_top (residual 2.0000E+00 deg)"),
        "{e}"
    );
}

/// Output times that make no sense, or that would exhaust memory (a mistyped --dtout), are
/// input errors: exit 2 with the reason, before any analysis.
#[test]
fn output_times_are_validated() {
    let src = root().join("mechanisms/pendulum.adm");
    let src = src.to_str().unwrap();
    for (args, why) in [
        (
            &["--end", "1e9", "--dtout", "1e-9"][..],
            "asks for 1.000E+18 outputs; at most 1000000 are allowed",
        ),
        (
            &["--end", "1", "--dtout", "0"][..],
            "--dtout must be a positive time, not 0",
        ),
        (
            &["--end", "-1"][..],
            "--end must be a positive time, not -1",
        ),
        (
            &["--end", "1", "--steps", "0"][..],
            "--steps must be at least 1",
        ),
    ] {
        let mut all = vec!["simulate", src];
        all.extend_from_slice(args);
        let (code, _, err) = run(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
    }
    let (code, _, err) = run(&["static", src, "--end", "1", "--steps", "100000000000"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("asks for more than the 1000000 outputs allowed"),
        "{err}"
    );
}

/// INTEGRATOR values linkage cannot use are warnings in the summary naming what is used
/// instead; an HMAX that would need more than 1e9 steps is an input error.
#[test]
fn unusable_integrator_settings_are_reported() {
    let with = |tag: &str, integrator: &str| {
        pendulum_with(&format!("integ-{tag}"), &format!("INTEGRATOR/{integrator}"))
    };
    let f = with("bad", "HHT, ALPHA = 0.5, ERROR = 1E-30");
    let (code, v) = simulate_json(&f, &[]);
    assert_eq!(code, 0, "{v}");
    let warnings = v["warnings"].to_string();
    assert!(
        warnings.contains("INTEGRATOR ALPHA = 0.5 is outside HHT's range"),
        "{warnings}"
    );
    assert!(
        warnings.contains(
            "INTEGRATOR ERROR = 1E-30 is below what double precision can meet; 1E-12 is used"
        ),
        "{warnings}"
    );
    // The summary names the integrator and what its ERROR bounds.
    assert_eq!(
        v["integrator"], "HHT-α (α = -0.3), ERROR = 0.000000000001 per step",
        "{v}"
    );
    let f = with("si2", "GSTIFF, SI2, KMAX = 4, ERROR = 1E-5");
    let (code, v) = simulate_json(&f, &[]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(
        v["integrator"], "BDF (GSTIFF, SI2), orders 1 … 4, ERROR = 0.00001 over the run",
        "{v}"
    );
    let f = with("hmax", "HMAX = 1E-12");
    let (code, _, err) = run(&["simulate", f.to_str().unwrap(), "--end", "1"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("HMAX = 1E-12 over --end 1 needs at least 1.000E+12 steps"),
        "{err}"
    );
}

/// Three parallelogram loops released with their cranks at +60°: Newton statics converges to
/// the nearest equilibrium, cranks straight up, which is unstable: the run refuses to start
/// there (exit 1, pointing to settling); with `--allow-unstable` it starts there and warns;
/// settling starts it hanging (stable, no warning).
#[test]
fn a_start_at_an_unstable_equilibrium_fails_unless_allowed() {
    let text = linkage_solve::generate::parallelogram_chain(3, 60.0).replace(
        "END",
        "EQUILIBRIUM/, GLOBAL_DAMPING = 2, SETTLING_TIME = 50\nEND",
    );
    let f = std::env::temp_dir().join(format!("linkage-chain3-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, v) = simulate_json(&f, &["--start-at-equilibrium"]);
    assert_eq!(code, 1, "{v}");
    assert_eq!(v["start"]["stable"], false);
    assert!(
        v["errors"]
            .to_string()
            .contains("--settle` finds a stable one"),
        "{v}"
    );
    let (code, v) = simulate_json(&f, &["--start-at-equilibrium", "--allow-unstable"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["start"]["stable"], false);
    assert!(
        v["warnings"]
            .to_string()
            .contains("the run starts at an UNSTABLE equilibrium"),
        "{v}"
    );
    let crank_y = |v: &serde_json::Value| v["final_state"][0]["position"][1].as_f64().unwrap();
    assert!((crank_y(&v) - 0.5).abs() < 1e-6, "{v}");
    let (code, v) = simulate_json(&f, &["--start-at-equilibrium", "--settle"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["start"]["stable"], true);
    assert!(!v["warnings"].to_string().contains("UNSTABLE"), "{v}");
    assert!((crank_y(&v) + 0.5).abs() < 1e-6, "{v}");
}
