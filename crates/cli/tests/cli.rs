//! The `linkage` binary end to end: reports, JSON schema, exit codes, corpus datasets.

mod common;
use common::*;
use std::path::PathBuf;

#[test]
fn bundled_example_verifies_as_text() {
    let ex = root().join("examples/fourbar.adm");
    let (code, out, _) = run(&["verify", ex.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("Gruebler Count"), "{out}");
    assert!(
        out.contains("   0 Degrees of Freedom") || out.contains("    0 Degrees of Freedom"),
        "{out}"
    );
    assert!(
        out.contains("There are 3 redundant constraint equations."),
        "{out}"
    );
    assert!(out.contains("unnecessarily removes this DOF"), "{out}");
}

#[test]
fn json_report_has_the_documented_keys() {
    let door = root().join("mechanisms/door_tilted_hinge.adm");
    let (code, v) = json(&["verify", door.to_str().unwrap(), "--format", "json"]);
    // The tilted hinge is an inconsistent redundancy: verify fails (exit 1).
    assert_eq!(code, 1);
    for key in [
        "title",
        "moving_parts",
        "gruebler",
        "dof",
        "redundant",
        "misaligned",
        "unconstrained_parts",
        "massless_parts",
        "warnings",
        "errors",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["gruebler"], -4);
    assert_eq!(v["dof"], 1);
    let red = v["redundant"].as_array().unwrap();
    assert_eq!(red.len(), 5);
    for r in red {
        assert!(
            r["equation"].is_string() && r["depends_on"].is_array() && r.get("residual").is_some()
        );
        assert!(r["consistent"].is_boolean());
    }
    let bad: Vec<_> = red.iter().filter(|r| r["consistent"] == false).collect();
    assert_eq!(bad.len(), 1);
    assert_eq!(bad[0]["element"], "JOINT/2");
    assert_eq!(bad[0]["name"], "hinge_top");
    assert_eq!(bad[0]["equation"], "Rotation Between Zi & Yj");
    assert!((bad[0]["residual"].as_f64().unwrap().abs() - 2.0).abs() < 1e-6);
    let mis = v["misaligned"].as_array().unwrap();
    assert!(!mis.is_empty());
    assert!(mis.iter().all(|m| m["name"] == "hinge_top"
        && m["equation"].is_string()
        && m["residual"].is_number()));
}

#[test]
fn input_errors_exit_2_with_location() {
    let dir = std::env::temp_dir().join(format!("linkage-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.adm");
    std::fs::write(
        &bad,
        "title\nPART/1, GROUND\nMARKER/1, PART = 1\nPART/2, MASS = 1, CM = 20\nMARKER/20, PART = 2\nJOINT/1, REVOLUTE, I = 20, J = 99\nEND\n",
    )
    .unwrap();
    let (code, _, err) = run(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.adm:6:"), "{err}");
    assert!(err.contains("marker 99 does not exist"), "{err}");

    std::fs::write(&bad, "title\nPART/1, GROUND\nPART/2, MASS = -3\nEND\n").unwrap();
    let (code, _, err) = run(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.adm:3:") && err.contains("negative"),
        "{err}"
    );

    std::fs::write(&bad, "title\nPART/1, GROUND\nPART/1, GROUND\nEND\n").unwrap();
    let (code, _, err) = run(&["verify", bad.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");

    let (code, _, err) = run(&["verify", dir.join("missing.adm").to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot read"), "{err}");
}

#[test]
fn adams_slider_crank_has_one_redundant_equation_zi_xj_of_joint_2() {
    let Some(dir) = corpus() else { return };
    let f = dir.join("bthornton191__adamspy__test__files__generic_model__generic_model.adm");
    let (code, v) = json(&["verify", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0);
    let red = v["redundant"].as_array().unwrap();
    assert_eq!(red.len(), 1, "{v}");
    // Adams Solver C++: "deactivating constraint equation  Zi.Xj in model.JOINT_2".
    assert_eq!(red[0]["name"], "JOINT_2");
    assert_eq!(red[0]["short"], "Zi.Xj");
    assert_eq!(red[0]["equation"], "Rotation Between Zi & Xj");
    assert_eq!(v["dof"], 0);
    assert_eq!(v["gruebler"], -1);
    assert_eq!(red[0]["consistent"], true);
}

#[test]
fn every_corpus_dataset_gives_a_report_or_an_input_diagnostic() {
    let Some(dir) = corpus() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .collect();
    files.sort();
    assert!(files.len() > 40);
    let (mut reports, mut diagnostics) = (0, 0);
    for f in &files {
        let (code, out, err) = run(&["verify", f.to_str().unwrap(), "--format", "json"]);
        match code {
            0 => {
                let v: serde_json::Value =
                    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                assert!(v["dof"].is_number(), "{}", f.display());
                reports += 1;
            }
            2 => {
                assert!(
                    err.contains(".adm"),
                    "{}: diagnostic without location: {err}",
                    f.display()
                );
                diagnostics += 1;
            }
            c => panic!("{}: exit code {c}\n{err}", f.display()),
        }
    }
    eprintln!("corpus: {reports} reports, {diagnostics} input diagnostics");
    assert!(
        reports > diagnostics,
        "{reports} reports vs {diagnostics} diagnostics"
    );
}

#[test]
fn ic_assembles_the_exploded_fourbar_and_the_saved_model_reverifies_clean() {
    let dir = std::env::temp_dir().join(format!("linkage-ic-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("assembled.adm");
    let src = root().join("mechanisms/exploded_fourbar.adm");
    let (code, v) = json(&[
        "ic",
        src.to_str().unwrap(),
        "--format",
        "json",
        "--save",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{v}");
    for key in [
        "converged",
        "iterations",
        "max_residual",
        "moved_parts",
        "redundant",
        "reactions",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["converged"], true);
    assert!(v["max_residual"].as_f64().unwrap() < 1e-10);
    assert!(v["redundant"]
        .as_array()
        .unwrap()
        .iter()
        .all(|r| r["consistent"] == true));
    let reactions = v["reactions"].as_array().unwrap();
    assert_eq!(reactions.len(), 4);
    assert!(reactions
        .iter()
        .all(|r| r["force"].as_array().unwrap().len() == 3 && r["torque"].is_array()));

    // Saved dataset: differs only in moved parts' QG/REULER lines; re-verifies with no
    // misaligned joint and the same DOF and redundancy.
    let original = std::fs::read_to_string(&src).unwrap();
    let saved = std::fs::read_to_string(&out).unwrap();
    let changed: Vec<(&str, &str)> = original
        .lines()
        .zip(saved.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(original.lines().count(), saved.lines().count());
    assert!(
        changed
            .iter()
            .all(|(a, _)| a.starts_with(", QG") || a.starts_with(", REULER")),
        "{changed:?}"
    );
    let (code, w) = json(&["verify", out.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0);
    assert_eq!(w["misaligned"].as_array().unwrap().len(), 0, "{w}");
    assert_eq!(w["dof"], v["dof"]);
    assert_eq!(
        w["redundant"].as_array().unwrap().len(),
        v["redundant"].as_array().unwrap().len()
    );
}

#[test]
fn ic_of_an_inconsistent_model_exits_1_and_names_the_equation() {
    let src = root().join("mechanisms/door_tilted_hinge.adm");
    let out = std::env::temp_dir().join(format!("linkage-ic-door-{}.adm", std::process::id()));
    let (code, v) = json(&[
        "ic",
        src.to_str().unwrap(),
        "--format",
        "json",
        "--save",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{v}");
    assert_eq!(v["inconsistent"], true);
    let bad: Vec<_> = v["redundant"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["consistent"] == false)
        .collect();
    assert_eq!(bad.len(), 1);
    assert_eq!(bad[0]["name"], "hinge_top");
    // Nothing is written for a model that cannot be assembled.
    assert!(!out.exists());
}

#[test]
fn static_reports_equilibrium_as_json_and_saves_it() {
    let src = root().join("mechanisms/pendulum_offset.adm");
    let out = std::env::temp_dir().join(format!("linkage-static-{}.adm", std::process::id()));
    let (code, v) = json(&[
        "static",
        src.to_str().unwrap(),
        "--format",
        "json",
        "--save",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{v}");
    for key in [
        "converged",
        "iterations",
        "imbalance",
        "stable",
        "parts",
        "reactions",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["stable"], true);
    let p = &v["parts"][0];
    assert_eq!(p["name"], "rod");
    assert!((p["position"][1].as_f64().unwrap() - 0.7).abs() < 1e-6);
    assert_eq!(p["reuler"].as_array().unwrap().len(), 3);
    // The saved dataset is the hanging pendulum: a second static run does not move it.
    let (code, w) = json(&["static", out.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0);
    assert!(w["iterations"].as_u64().unwrap() <= 1, "{w}");
    assert!((w["parts"][0]["position"][1].as_f64().unwrap() - 0.7).abs() < 1e-6);
}

#[test]
fn quasi_static_series_as_json_steps_and_csv_rows() {
    let src = root().join("examples/fourbar.adm");
    let (code, v) = json(&[
        "static",
        src.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "4",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 5);
    assert!((steps[4]["time"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!(steps
        .iter()
        .all(|s| s["parts"].is_array() && s["reactions"].is_array()));
    // 30°/s from 60°: the crank is at 90° after one second.
    let crank = steps[4]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "crank")
        .unwrap();
    assert!(
        (crank["reuler"][0].as_f64().unwrap() - 90.0).abs() < 1e-6,
        "{crank}"
    );
    let (code, csv, _) = run(&[
        "static",
        src.to_str().unwrap(),
        "--end",
        "1",
        "--steps",
        "4",
        "--format",
        "csv",
    ]);
    assert_eq!(code, 0);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 6);
    assert!(lines[0].starts_with("time [s],crank.x [m],crank.y [m],crank.z [m],crank.psi [deg]"));
    assert!(lines[0].contains("crank_pivot.fx [N]"));
    assert_eq!(lines[1].split(',').count(), lines[0].split(',').count());
}

#[test]
fn static_non_convergence_of_newton_is_continued_by_the_descent() {
    // MAXIT 1: Adams' Newton stops before the hanging pose; the descent goes on to it and the
    // report says both.
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum_offset.adm"))
        .unwrap()
        .replace("END", "EQUILIBRIUM/, MAXIT = 1\nEND");
    let f = std::env::temp_dir().join(format!("linkage-static-maxit-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, out, _) = run(&["static", f.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("Found by descent."), "{out}");
    assert!(out.contains("did not converge in 1 iterations"), "{out}");
    let (code, v) = json(&["static", f.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    // The hanging pose: CM 0.5 below the pivot at y = 1.2.
    assert!(
        (v["parts"][0]["position"][1].as_f64().unwrap() - 0.7).abs() < 1e-6,
        "{v}"
    );
}

#[test]
fn linear_json_gives_eigenvalues_and_modes_in_cycles_per_time() {
    let src = root().join("mechanisms/pendulum.adm");
    let (code, v) = json(&["linear", src.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let ev = v["eigenvalues"].as_array().unwrap();
    assert_eq!(ev.len(), 1);
    let f = (3.0f64 * 9.80665 / 2.0).sqrt() / std::f64::consts::TAU;
    assert!((ev[0]["imag"].as_f64().unwrap() - f).abs() < 1e-9);
    assert!(ev[0]["real"].as_f64().unwrap().abs() < 1e-9);
    let mode = &v["modes"][0];
    assert!((mode["frequency"].as_f64().unwrap() - f).abs() < 1e-9);
    assert!(mode["damping_ratio"].as_f64().unwrap().abs() < 1e-9);
    assert!(mode["shape"].is_array());
    let (_, v) = json(&[
        "linear",
        src.to_str().unwrap(),
        "--format",
        "json",
        "--no-vectors",
        "--static-first",
        "--no-damping",
    ]);
    assert!(v["modes"][0].get("shape").is_none());
}

#[test]
fn static_settle_reports_the_stopping_criterion() {
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum_offset.adm"))
        .unwrap()
        .replace(
            "END",
            "EQUILIBRIUM/, GLOBAL_DAMPING = 4, SETTLING_TIME = 20\nEND",
        );
    let f = std::env::temp_dir().join(format!("linkage-settle-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, v) = json(&[
        "static",
        f.to_str().unwrap(),
        "--settle",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["settling"]["criterion"], "settled");
    assert_eq!(v["settling"]["polish_converged"], true);
    assert!(v["settling"]["kinetic_energy"].as_f64().unwrap() <= 1e-2);
    assert!(v["settling"]["acceleration"].as_f64().unwrap() <= 1e-2);
    assert!((v["parts"][0]["position"][1].as_f64().unwrap() - 0.7).abs() < 1e-6);
    let (code, text, _) = run(&["static", f.to_str().unwrap(), "--settle"]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains(
            "Dynamic settling (GLOBAL_DAMPING 4, time frozen at the start) settled after"
        ),
        "{text}"
    );
    assert!(text.contains("(KINETIC_ENERGY_ERROR 1.000E-02)"), "{text}");
    assert!(text.contains("Newton polish converged in"), "{text}");
    // Undamped (GLOBAL_DAMPING 0, Adams' default) with a SETTLING_TIME far too short for a
    // free swing: the damping is chosen from the pendulum's own mode (critical) and the
    // settling time adapted to it, and it comes to rest in the hanging pose.
    let undamped = std::fs::read_to_string(&f).unwrap().replace(
        "GLOBAL_DAMPING = 4, SETTLING_TIME = 20",
        "SETTLING_TIME = 2",
    );
    std::fs::write(&f, undamped).unwrap();
    let (code, text, _) = run(&["static", f.to_str().unwrap(), "--settle"]);
    assert_eq!(code, 0, "{text}");
    assert!(text.contains("chosen from the lowest mode"), "{text}");
    assert!(text.contains("settled after"), "{text}");
    assert!(text.contains("The equilibrium is stable."), "{text}");
    let (code, v) = json(&[
        "static",
        f.to_str().unwrap(),
        "--settle",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["settling"]["damping_from_model"], true);
    assert!(v["settling"]["damping"].as_f64().unwrap() > 0.0, "{v}");
    // The same hanging pose as the damped dataset's (CM 0.7 below the pivot's level).
    assert!(
        (v["parts"][0]["position"][1].as_f64().unwrap() - 0.7).abs() < 1e-6,
        "{v}"
    );
}

#[test]
fn simulate_writes_the_documented_csv_columns() {
    let src = root().join("mechanisms/pendulum_offset.adm");
    let out = std::env::temp_dir().join(format!("linkage-sim-{}.csv", std::process::id()));
    let (code, v) = json(&[
        "simulate",
        src.to_str().unwrap(),
        "--end",
        "0.5",
        "--dtout",
        "0.05",
        "--out",
        out.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["completed"], true);
    assert_eq!(v["outputs"], 11);
    let csv = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 12);
    let header: Vec<&str> = lines[0].split(',').collect();
    // Each column with its unit (the dataset is in newton, kilogram, meter, second).
    let want = [
        "time [s]",
        "rod.x [m]",
        "rod.y [m]",
        "rod.z [m]",
        "rod.psi [deg]",
        "rod.theta [deg]",
        "rod.phi [deg]",
        "rod.vx [m/s]",
        "rod.vy [m/s]",
        "rod.vz [m/s]",
        "rod.wx [rad/s]",
        "rod.wy [rad/s]",
        "rod.wz [rad/s]",
        "hinge.fx [N]",
        "hinge.fy [N]",
        "hinge.fz [N]",
        "hinge.tx [N·m]",
        "hinge.ty [N·m]",
        "hinge.tz [N·m]",
    ];
    assert_eq!(&header[..want.len()], &want);
    let last: Vec<f64> = lines[11].split(',').map(|x| x.parse().unwrap()).collect();
    assert!((last[0] - 0.5).abs() < 1e-12);
    // The rod stays on its circle about the pivot (0.3, 1.2) at radius 0.5.
    assert!(((last[1] - 0.3).hypot(last[2] - 1.2) - 0.5).abs() < 1e-8);
}

/// Corpus datasets carrying EQUILIBRIUM settings: those whose elements linkage models reach
/// equilibrium. Datasets refused as input (CONTACT, DIFF, …) are skipped with a
/// notice. Two SOLIDWORKS-exported 3-RPR robots are known not to converge within their
/// settings: Fkinev1's equilibrium lies so far from its input configuration that TLIMIT (20 mm
/// per iteration by default) alone needs more than 20 of its 25 iterations (proved below from
/// the travel of the parts, then solved with MAXIT 40); Controls_Plant_2 has no equilibrium
/// near its input configuration (its stand assembly slides down without bound:
/// `controls_plant_2_has_no_static_equilibrium`).
#[test]
fn corpus_datasets_with_equilibrium_settings_reach_equilibrium() {
    let Some(dir) = corpus() else { return };
    const KNOWN: [&str; 2] = ["Fkinev1.adm", "Controls_Plant_2__Controls_Plant_2.adm"];
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "adm"))
        .filter(|p| {
            std::fs::read_to_string(p).is_ok_and(|t| {
                t.lines()
                    .any(|l| l.to_uppercase().starts_with("EQUILIBRIUM"))
            })
        })
        .collect();
    files.sort();
    let mut converged = 0;
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().to_string();
        if KNOWN.iter().any(|k| name.ends_with(k)) {
            continue;
        }
        let (code, out, err) = run(&["static", f.to_str().unwrap(), "--format", "json"]);
        match code {
            2 => eprintln!(
                "notice: {name} skipped: {}",
                err.lines().next().unwrap_or("")
            ),
            0 => {
                let v: serde_json::Value = serde_json::from_str(&out).unwrap();
                assert_eq!(v["converged"], true, "{name}");
                converged += 1;
            }
            c => panic!("{name}: exit {c}\n{err}"),
        }
    }
    assert!(converged >= 2, "{converged}");
    // Fkinev1 converges once Newton may take a few more steps than MAXIT 25.
    let fk = dir.join("kiterunner347__3-RPR-parallel--robot__RPRAdams__fitestv1__Fkinev1.adm");
    let text = std::fs::read_to_string(&fk).unwrap().replacen(
        "EQUILIBRIUM/",
        "EQUILIBRIUM/, MAXIT = 40",
        1,
    );
    let tmp = std::env::temp_dir().join(format!("linkage-fk-{}.adm", std::process::id()));
    std::fs::write(&tmp, text).unwrap();
    let (code, v) = json(&["static", tmp.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], true);
    let iterations = v["iterations"].as_u64().unwrap();
    // Travel of the centres of mass from the assembled input configuration to the
    // equilibrium: every Newton step moves a part by at most TLIMIT = 20 (mm).
    let (code, start) = json(&["ic", tmp.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{start}");
    let position = |p: &serde_json::Value| -> Vec<f64> {
        p["position"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let travel = v["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let s = start["parts"]
                .as_array()
                .unwrap()
                .iter()
                .find(|q| q["name"] == p["name"])
                .unwrap();
            let (a, b) = (position(p), position(s));
            (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max);
    let lower_bound = (travel / 20.0).ceil() as u64;
    assert!(lower_bound > 20, "travel {travel}");
    assert!(
        iterations >= lower_bound && iterations <= 40,
        "{iterations} vs {lower_bound}"
    );
}

/// A 67-part SOLIDWORKS export (195 redundant equations, parts with tiny inertia about their
/// axes) integrates: the corrector accepts acceleration corrections whose effect on positions
/// and velocities is far below the integration error (before, it stalled at noise level and
/// gave up at the minimum step).
#[test]
fn corpus_robot_with_tiny_inertias_integrates() {
    let Some(dir) = corpus() else { return };
    let f = dir.join(
        "kiterunner347__3-RPR-parallel--robot__Matlab_Adams__Controls_Plant_2__Controls_Plant_2.adm",
    );
    let out = std::env::temp_dir().join(format!("linkage-cp2-{}.csv", std::process::id()));
    let (code, _, err) = run(&[
        "simulate",
        f.to_str().unwrap(),
        "--end",
        "0.1",
        "--steps",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(&out).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(!csv.contains("NaN"));
}

/// Controls_Plant_2 (67 parts, 31 DOF, zero actuator forces) has no static equilibrium that
/// damped dynamics can reach: settled with GLOBAL_DAMPING 20 (time constant 50 ms) for 10 s, its
/// stand assembly (`Stands_Double_2` and its bolts and bearings) keeps descending along gravity,
/// by more than the whole model's height (1.9 m), with kinetic energy that does not decay. A
/// bounded mechanism would have stopped: the potential energy falls without limit along a
/// sliding freedom, so Newton statics cannot converge and rightly reports it.
#[test]
fn controls_plant_2_has_no_static_equilibrium() {
    let Some(dir) = corpus() else { return };
    let f = dir.join(
        "kiterunner347__3-RPR-parallel--robot__Matlab_Adams__Controls_Plant_2__Controls_Plant_2.adm",
    );
    let text = std::fs::read_to_string(&f).unwrap().replacen(
        "EQUILIBRIUM/",
        "EQUILIBRIUM/, GLOBAL_DAMPING = 20, SETTLING_TIME = 10",
        1,
    );
    let tmp = std::env::temp_dir().join(format!("linkage-cp2-settle-{}.adm", std::process::id()));
    std::fs::write(&tmp, text).unwrap();
    let (code, start) = json(&["ic", tmp.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{start}");
    let (code, v) = json(&[
        "static",
        tmp.to_str().unwrap(),
        "--settle",
        "--format",
        "json",
    ]);
    assert_eq!(code, 1, "{v}");
    assert_eq!(
        v["settling"]["criterion"], "settling_time",
        "{}",
        v["settling"]
    );
    assert!(v["settling"]["kinetic_energy"].as_f64().unwrap() > 1.0);
    let y = |doc: &serde_json::Value, name: &str| -> f64 {
        doc["parts"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["name"] == name)
            .unwrap()["position"][1]
            .as_f64()
            .unwrap()
    };
    let heights: Vec<f64> = start["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["position"][1].as_f64().unwrap())
        .collect();
    let height = heights.iter().cloned().fold(f64::MIN, f64::max)
        - heights.iter().cloned().fold(f64::MAX, f64::min);
    // Where the damped integration left it (the Newton polish from there does not converge
    // either, and ends wherever its last iteration put it).
    let settled = serde_json::json!({ "parts": v["settling"]["settled_parts"] });
    let descent = y(&start, "Stands_Double_2") - y(&settled, "Stands_Double_2");
    assert!(
        descent > height,
        "descent {descent} vs model height {height}"
    );
}

#[test]
fn linear_modes_computes_the_lowest_modes_by_shift_invert() {
    // A chain of 10 pendulum links (DOF 10): `--modes 3` gives the 3 lowest modes of the
    // dense solution (relative 1e-8), and says how many of the 20 eigenvalues it computed.
    let f = std::env::temp_dir().join(format!("linkage-modes-{}.adm", std::process::id()));
    std::fs::write(&f, linkage_solve::generate::pendulum_chain(10)).unwrap();
    let path = f.to_str().unwrap();
    let (code, dense) = json(&["linear", path, "--format", "json"]);
    assert_eq!(code, 0, "{dense}");
    assert_eq!(dense["method"], "dense");
    assert_eq!(dense["computed_eigenvalues"], 20);
    let (code, v) = json(&["linear", path, "--modes", "3", "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["method"], "shift-invert");
    assert_eq!(v["states"], 20);
    assert_eq!(v["computed_eigenvalues"], 6);
    assert_eq!(v["shift"], 0.0);
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 3);
    assert_eq!(v["eigenvalues"].as_array().unwrap().len(), 3);
    for (k, m) in modes.iter().enumerate() {
        let got = m["frequency"].as_f64().unwrap();
        let want = dense["modes"][k]["frequency"].as_f64().unwrap();
        assert!(
            (got - want).abs() < 1e-8 * want,
            "mode {k}: {got} vs {want}"
        );
        assert!(m["shape"].is_array());
    }
    let (code, out, _) = run(&["linear", path, "--modes", "3"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("Computed 6 of the 20 eigenvalues (3 modes): the lowest"),
        "{out}"
    );
    // Around the 5th frequency: 2 modes, the 5th among them.
    let f5 = dense["modes"][4]["frequency"].as_f64().unwrap();
    let (code, v) = json(&[
        "linear",
        path,
        "--shift",
        &f5.to_string(),
        "--modes",
        "2",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert!((v["shift"].as_f64().unwrap() - f5).abs() < 1e-12 * f5);
    let near: Vec<f64> = v["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["frequency"].as_f64().unwrap())
        .collect();
    assert_eq!(near.len(), 2, "{near:?}");
    assert!(near.iter().any(|x| (x - f5).abs() < 1e-8 * f5), "{near:?}");
    // K must be positive.
    let (code, _, err) = run(&["linear", path, "--modes", "0"]);
    assert_eq!(code, 2, "{err}");
    let _ = std::fs::remove_file(&f);
}

/// FAST's ADAMS preprocessor gives the nacelle and the generator a tiny transverse inertia
/// (9.999e-4 kg·m²) beside a large axial one, which no rigid body has (I1 + I2 < I3). Adams
/// runs these certification models; linkage warns, naming the part and its principal moments,
/// and goes on. A negative principal moment stays an input error.
#[test]
fn fast_inertias_that_violate_the_triangle_inequality_are_warnings() {
    let Some(dir) = corpus() else { return };
    let src = dir.join("old-NWTC__FAST__CertTest__Old_Adams_files__Test02_ADAMS.adm");
    let (code, out, err) = run(&["verify", src.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}\n{err}");
    let all = format!("{out}{err}");
    for part in ["Nacelle_P", "Generator_P"] {
        assert!(
            all.contains(&format!(
                "warning: {part}: non-physical inertia about the centre of mass: principal moments 9.999000E-04, 9.999000E-04"
            )),
            "{part}: {all}"
        );
    }
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum.adm"))
        .unwrap()
        .replace(
            "IP = 0.16666666666666666, 0.0001",
            "IP = -0.16666666666666666, 0.0001",
        );
    let f = std::env::temp_dir().join(format!("linkage-neg-ip-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    let (code, _, err) = run(&["verify", f.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("negative principal moment"), "{err}");
}

/// A 7-link robot arm of the corpus (LWR_6DOF_GRABER) is in equilibrium as built: its forces
/// balance to 4e-11 N against 88 N of weight. Its gripper fingers turn about hinges along
/// gravity, with no stiffness and inertias of 1.6e-7 kg·m², so the Newton correction of that
/// rounding (STABILITY × inertia is 1.6e-12) drifted them by 6e-4 rad per iteration and the
/// statics never met ERROR. Forces balanced to rounding now end the iteration without a move.
#[test]
fn a_model_balanced_to_rounding_is_in_equilibrium_without_drifting() {
    let Some(dir) = corpus() else { return };
    let src = dir.join("MarcinPiotrowski__MultiBodySystemDynamics__test__LWR_6DOF_GRABER.adm");
    // The arm's balanced pose is an unstable equilibrium: accepted here, as the test is about
    // the iteration ending without a move.
    let (code, st) = json(&[
        "static",
        src.to_str().unwrap(),
        "--allow-unstable",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{st}");
    assert_eq!(st["converged"], true);
    assert_eq!(st["iterations"], 0);
    assert!(st["imbalance"].as_f64().unwrap() < 1e-9, "{st}");
    let (code, ic) = json(&["ic", src.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 0, "{ic}");
    let parts = st["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 7);
    for (a, b) in parts.iter().zip(ic["parts"].as_array().unwrap()) {
        for k in 0..3 {
            let (x, y) = (
                a["position"][k].as_f64().unwrap(),
                b["position"][k].as_f64().unwrap(),
            );
            assert!((x - y).abs() < 1e-12, "{}: {x} vs {y}", a["name"]);
        }
    }
    // And a run can start there.
    let (code, sim) = json(&[
        "simulate",
        src.to_str().unwrap(),
        "--end",
        "0.1",
        "--start-at-equilibrium",
        "--allow-unstable",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{sim}");
    assert_eq!(sim["start"]["from"], "static_equilibrium");
}

/// LWR_1, a 7-link arm of the corpus released far from hanging: its flange link spins about
/// its own axis with almost no stiffness, so its Newton correction is ~5e10 rad. Scaling the
/// whole step to ALIMIT by that correction froze every other link (the imbalance stayed at
/// 4.963 N·m for all 25 iterations); cut on its own, the flange no longer stalls the arm.
/// The arm needs more than the default 25 iterations to swing down, and the report must not
/// claim that no equilibrium exists.
#[test]
fn a_runaway_part_does_not_stall_the_rest_of_the_static_iteration() {
    let Some(dir) = corpus() else { return };
    let src = dir.join("MarcinPiotrowski__MultiBodySystemDynamics__LWR_1.adm");
    let (code, v) = json(&["static", src.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 1, "{v}");
    let imbalance = v["imbalance"].as_f64().unwrap();
    assert!(imbalance < 1.0, "{imbalance} (it started at 4.963)");
    let errors = v["errors"].to_string();
    assert!(!errors.contains("nothing resists"), "{errors}");
    // Settled by damped dynamics instead, the arm comes to rest hanging in about 6 time units;
    // the Newton polish from there converges although the flange's correction along its own
    // axis stays large: the forces are within IMBALANCE and that correction does negligible
    // work against them (the flange's stiffness about its axis is about 2e-3 N·m/rad).
    let text = std::fs::read_to_string(&src).unwrap().replace(
        "\nEND",
        "\nEQUILIBRIUM/, DYNAMIC, GLOBAL_DAMPING = 5, SETTLING_TIME = 50\nEND",
    );
    let f = std::env::temp_dir().join(format!("linkage-lwr1-{}.adm", std::process::id()));
    std::fs::write(&f, text).unwrap();
    // It settles where the polish finds an unstable equilibrium: accepted, as the test is
    // about the runaway part.
    let (code, v) = json(&[
        "static",
        f.to_str().unwrap(),
        "--allow-unstable",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["settling"]["criterion"], "settled");
    assert_eq!(v["settling"]["polish_converged"], true);
    assert!(v["imbalance"].as_f64().unwrap() <= 1e-4);
}
