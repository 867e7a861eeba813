//! One verdict per run: the exit code, the last line of the text report and the JSON `errors`
//! list say the same thing (0 and no errors: found what was asked; 1 and one error line: ran
//! and failed).

mod common;
use common::*;

fn mechanism(name: &str) -> String {
    root()
        .join("mechanisms")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

/// The last non-empty line of a text report.
fn last_line(text: &str) -> &str {
    text.lines().rfind(|l| !l.trim().is_empty()).unwrap_or("")
}

/// The JSON `errors` list as strings.
fn errors(v: &serde_json::Value) -> Vec<String> {
    v["errors"]
        .as_array()
        .unwrap_or_else(|| panic!("no errors list: {v}"))
        .iter()
        .map(|e| e.as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_tilted_hinge_is_an_inconsistent_redundancy_and_verify_fails() {
    let door = mechanism("door_tilted_hinge.adm");
    let (code, out, err) = run(&["verify", &door]);
    assert_eq!(code, 1, "{out}\n{err}");
    let last = last_line(&out);
    assert!(
        last.starts_with("error: the model is inconsistent")
            && last.contains("Rotation Between Zi & Yj of hinge_top")
            && last.contains("linkage ic")
            && last.contains("verify --explain"),
        "{out}"
    );
    let (code, v) = json(&["verify", &door, "--format", "json"]);
    assert_eq!(code, 1);
    assert_eq!(errors(&v).len(), 1, "{v}");
    assert!(errors(&v)[0].contains("hinge_top"), "{v}");
    // Its consistent twin verifies cleanly.
    let (code, v) = json(&[
        "verify",
        &mechanism("door_two_hinges.adm"),
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert!(errors(&v).is_empty(), "{v}");
}

#[test]
fn ic_of_the_tilted_hinge_lists_no_false_repair_and_names_the_failure() {
    let door = mechanism("door_tilted_hinge.adm");
    let (code, out, _) = run(&["ic", &door]);
    assert_eq!(code, 1, "{out}");
    assert!(!out.contains("Repaired joints"), "{out}");
    let last = last_line(&out);
    assert!(
        last.starts_with("error: the model cannot be assembled")
            && last.contains("Rotation Between Zi & Yj of hinge_top"),
        "{out}"
    );
    let (code, v) = json(&["ic", &door, "--format", "json"]);
    assert_eq!(code, 1);
    assert!(v["repaired"].as_array().unwrap().is_empty(), "{v}");
    assert_eq!(errors(&v).len(), 1, "{v}");
    // A real repair is still listed: the exploded four-bar's joints hold after the assembly.
    let (code, v) = json(&["ic", &mechanism("exploded_fourbar.adm"), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    let repaired = v["repaired"].as_array().unwrap();
    assert!(!repaired.is_empty(), "{v}");
    assert!(
        repaired
            .iter()
            .all(|r| r["after"].as_f64().unwrap().abs() < 1e-6),
        "{v}"
    );
}

#[test]
fn an_undamped_four_bar_settles_with_damping_chosen_from_its_lowest_mode() {
    // GLOBAL_DAMPING 0 (the default): the settling chooses near-critical damping of the
    // lowest mode and comes to rest; one verdict, no error.
    let fourbar = mechanism("fourbar.adm");
    let (code, out, _) = run(&["static", &fourbar, "--settle"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("chosen from the lowest mode"), "{out}");
    assert!(out.contains("The equilibrium is stable."), "{out}");
    assert!(!out.contains("error:"), "{out}");
    let (code, v) = json(&["static", &fourbar, "--settle", "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["converged"], true);
    assert_eq!(v["stable"], true);
    assert_eq!(errors(&v).len(), 0, "{v}");
}

#[test]
fn newtons_unstable_equilibrium_is_left_for_a_stable_one_unless_allowed() {
    // Newton converges to the four-bar's balanced (unstable) pose; the search goes on down to
    // the hanging one, and says which path found it.
    let fourbar = mechanism("fourbar.adm");
    let (code, out, _) = run(&["static", &fourbar]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("Found by descent."), "{out}");
    assert!(
        out.contains("newton") && out.contains("converged to an unstable equilibrium"),
        "{out}"
    );
    assert!(out.contains("The equilibrium is stable."), "{out}");
    let (code, v) = json(&["static", &fourbar, "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], true);
    assert_eq!(v["search"]["path"], "descent");
    assert_eq!(v["search"]["attempts"][0]["stable"], false);
    assert_eq!(errors(&v).len(), 0, "{v}");
    let (code, v) = json(&["static", &fourbar, "--allow-unstable", "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], false);
    assert!(errors(&v).is_empty(), "{v}");
    // A stable equilibrium needs no flag.
    let (code, v) = json(&["static", &mechanism("pendulum.adm"), "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["stable"], true);
}

#[test]
fn linearizing_about_an_unstable_equilibrium_fails_unless_allowed() {
    let fourbar = mechanism("fourbar.adm");
    let (code, out, _) = run(&["linear", &fourbar, "--static-first"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        last_line(&out).starts_with("error: the static equilibrium linearized about is UNSTABLE"),
        "{out}"
    );
    let (code, v) = json(&["linear", &fourbar, "--static-first", "--format", "json"]);
    assert_eq!(code, 1);
    assert_eq!(errors(&v).len(), 1, "{v}");
    let (code, v) = json(&[
        "linear",
        &fourbar,
        "--static-first",
        "--allow-unstable",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert!(errors(&v).is_empty(), "{v}");
    // The flag belongs to --static-first.
    let (code, _, err) = run(&["linear", &fourbar, "--allow-unstable"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn a_run_does_not_start_from_an_unstable_equilibrium_unless_allowed() {
    let fourbar = mechanism("fourbar.adm");
    let args = [
        "simulate",
        &fourbar,
        "--end",
        "0.01",
        "--start-at-equilibrium",
    ];
    let (code, out, _) = run(&args);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("No simulation was run."), "{out}");
    let last = last_line(&out);
    assert!(
        last.starts_with("error: the starting equilibrium is UNSTABLE")
            && last.contains("--allow-unstable"),
        "{out}"
    );
    let (code, v) = json(&[&args[..], &["--format", "json"]].concat());
    assert_eq!(code, 1);
    assert_eq!(v["outputs"], 0);
    assert_eq!(errors(&v).len(), 1, "{v}");
    let (code, v) = json(&[&args[..], &["--allow-unstable", "--format", "json"]].concat());
    assert_eq!(code, 0, "{v}");
    assert!(errors(&v).is_empty(), "{v}");
    assert_eq!(v["completed"], true);
}

#[test]
fn verify_says_why_consistency_is_unknown_on_an_unassembled_model() {
    let Some(dir) = corpus() else { return };
    let Some(f) = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| {
            p.to_string_lossy().contains("Fkinev1") && p.extension().is_some_and(|x| x == "adm")
        })
    else {
        panic!("no Fkinev1 dataset in {}", dir.display());
    };
    let f = f.to_str().unwrap();
    let (code, out, err) = run(&["verify", f]);
    // Not assembled at the input is a finding, not a failure: exit 0, no errors.
    assert_eq!(code, 0, "{out}\n{err}");
    let lines: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("The model is not assembled at the input configuration"))
        .collect();
    assert_eq!(lines.len(), 1, "{out}");
    assert!(
        lines[0].contains("consistency of the 28 redundant equation(s) is unknown")
            && lines[0].contains("linkage ic"),
        "{out}"
    );
    assert!(!out.contains("Model verified successfully"), "{out}");
    let (code, v) = json(&["verify", f, "--format", "json"]);
    assert_eq!(code, 0);
    assert_eq!(v["assembled"], false);
    assert!(errors(&v).is_empty(), "{v}");
}

/// `script` gives the command a terminal: an error must show once there.
#[test]
fn simulate_errors_show_once_on_a_terminal() {
    let door = mechanism("door_tilted_hinge.adm");
    let cmd = format!(
        "{} simulate {door} --end 0.1",
        env!("CARGO_BIN_EXE_linkage")
    );
    let Ok(out) = std::process::Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .output()
    else {
        eprintln!("notice: `script` is not available; terminal test skipped");
        return;
    };
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert_eq!(text.matches("error: ").count(), 1, "{text}");
    // Piped, the report (stdout) and standard error each carry it once.
    let (code, out, err) = run(&["simulate", &door, "--end", "0.1"]);
    assert_eq!(code, 1);
    assert_eq!(out.matches("error: ").count(), 1, "{out}");
    assert_eq!(err.matches("error: ").count(), 1, "{err}");
}

/// The exploded four-bar is misaligned at its input: verify's counts at the repaired input
/// pose (0 DOF, 2 redundant) are not those of the assembled pose, so verify also assembles
/// it and reports what `ic` finds there (1 DOF, 3 redundant, as for any planar four-bar built
/// from revolutes).
#[test]
fn verify_reports_the_counts_ic_finds_after_assembly() {
    let src = common::root().join("mechanisms/exploded_fourbar.adm");
    let src = src.to_str().unwrap();
    let (_, out, _) = common::run(&["verify", src, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let after = &v["after_assembly"];
    assert_eq!(after["converged"], true, "{v}");
    let (_, out, _) = common::run(&["ic", src, "--format", "json"]);
    let ic: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(ic["dof"], 1, "{ic}");
    assert_eq!(after["dof"], ic["dof"]);
    let names = |list: &serde_json::Value| -> Vec<String> {
        list.as_array()
            .unwrap()
            .iter()
            .map(|r| format!("{} {}", r["name"], r["equation"]))
            .collect()
    };
    assert_eq!(names(&after["redundant"]).len(), 3);
    assert_eq!(names(&after["redundant"]), names(&ic["redundant"]));
    let (_, text, _) = common::run(&["verify", src]);
    assert!(
        text.contains(
            "Assembled (as `linkage ic` and every analysis assemble it): 1 Degrees of Freedom, \
             3 redundant constraint equation(s); these counts, not the ones above"
        ),
        "{text}"
    );
    // An assembled model has no such line.
    let ok = common::root().join("mechanisms/fourbar.adm");
    let (_, out, _) = common::run(&["verify", ok.to_str().unwrap(), "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v.get("after_assembly").is_none(), "{v}");
}
