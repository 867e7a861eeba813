//! Input mistakes stop the run as Adams stops on them (a misspelt argument with a "did you
//! mean"), unless `--lenient-arguments` downgrades them; rounding noise is never printed as a
//! result (ic's moved parts, linear's zero-frequency modes).

mod common;
use common::*;
use std::path::PathBuf;

/// The four-bar example with the crank's `MASS = 1` misspelt `MASSS = 1`, in a scratch
/// folder; its path and the line of the mistake.
fn misspelt_fourbar(name: &str) -> (PathBuf, usize) {
    let dir = root().join("target/test-input-mistakes").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(root().join("examples/fourbar.adm")).unwrap();
    assert!(text.contains("\n, MASS = 1\n"));
    let text = text.replacen("\n, MASS = 1\n", "\n, MASSS = 1\n", 1);
    let line = text.lines().position(|l| l == ", MASSS = 1").unwrap() + 1;
    let path = dir.join("masss.adm");
    std::fs::write(&path, text).unwrap();
    (path, line)
}

#[test]
fn a_misspelt_argument_is_an_input_error_that_names_the_argument_meant() {
    let (model, line) = misspelt_fourbar("verify");
    let model = model.to_str().unwrap();
    let (code, out, err) = run(&["verify", model]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains(&format!(
            "masss.adm:{line}:3: error: unknown argument 'MASSS' of PART (did you mean MASS?)"
        )),
        "{err}"
    );
    // The hint lists what PART takes and names the way out.
    assert!(
        err.contains("hint: PART takes ") && err.contains("--lenient-arguments"),
        "{err}"
    );
    assert!(!out.contains("verified successfully"), "{out}");
    // Every analysis refuses it the same way.
    for args in [
        vec!["ic", model],
        vec!["static", model],
        vec!["linear", model],
        vec!["simulate", model, "--end", "0.1"],
    ] {
        let (code, _, err) = run(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains("unknown argument 'MASSS' of PART"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn lenient_arguments_reads_on_with_a_warning_on_every_command() {
    let (model, line) = misspelt_fourbar("lenient");
    let model = model.to_str().unwrap();
    let warning = format!(
        "masss.adm:{line}:3: warning: unknown argument 'MASSS' of PART ignored (did you mean MASS?)"
    );
    let (code, out, err) = run(&["verify", model, "--lenient-arguments"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(format!("{out}{err}").contains(&warning), "{out}{err}");
    // The flag goes anywhere on the command line, on every command. The four-bar is driven
    // (no degree of freedom): its crank's mass changes no motion.
    let (code, out, err) = run(&["--lenient-arguments", "simulate", model, "--end", "0.1"]);
    assert_eq!(code, 0, "{out}{err}");
    let (code, out, err) = run(&["ic", "--lenient-arguments", model]);
    assert_eq!(code, 0, "{out}{err}");
    // A command file reads its dataset the same way.
    let dir = PathBuf::from(model).parent().unwrap().to_path_buf();
    let acf = dir.join("masss.acf");
    std::fs::write(
        &acf,
        "masss\nmasss_run\nSIMULATE/KINEMATIC, END = 0.1, STEPS = 2\nSTOP\n",
    )
    .unwrap();
    let acf = acf.to_str().unwrap();
    let out_dir = dir.to_str().unwrap();
    let (code, _, err) = run(&["run", acf, "--out-dir", out_dir]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown argument 'MASSS' of PART"), "{err}");
    let (code, out, err) = run(&["run", acf, "--out-dir", out_dir, "--lenient-arguments"]);
    assert_eq!(code, 0, "{out}{err}");
}

#[test]
fn moved_parts_never_print_a_negative_zero() {
    // The exploded four-bar's assembly moves the crank and rocker in the x-y plane; their z
    // translations are rounding (≈ -1e-17 m), printed as 0.000000, never -0.000000.
    let model = root().join("mechanisms/exploded_fourbar.adm");
    let (code, out, err) = run(&["ic", model.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let moved: Vec<&str> = out
        .lines()
        .filter(|l| l.contains("translation ("))
        .collect();
    assert_eq!(moved.len(), 3, "{out}");
    assert!(!out.contains("-0.000000"), "{out}");
    assert!(
        moved[0].contains("crank")
            && moved[0].contains("translation (0.002386, -0.001386, 0.000000)"),
        "{out}"
    );
}

#[test]
fn zero_frequency_modes_are_counted_not_listed() {
    // A door on a spherical joint and an inline primitive: one free rotation about the hinge
    // line, no stiffness. Its eigenvalue pair is zero up to rounding (±6e-9 Hz): counted as
    // the 2 zero eigenvalues, not listed as modes with damping ratio ±1.
    let model = root().join("mechanisms/door_hinge_spherical_inline.adm");
    let model = model.to_str().unwrap();
    let (code, out, err) = run(&["linear", model]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("E-09"), "{out}");
    assert!(!out.contains("Mode 1:"), "{out}");
    assert!(
        out.contains(
            "(2 modes at zero frequency, rounding noise of rigid-body motions, not listed"
        ),
        "{out}"
    );
    assert!(out.contains("2 zero eigenvalues"), "{out}");
    // The JSON keeps every eigenvalue, each mode marked.
    let (code, v) = json(&["linear", model, "--format", "json"]);
    assert_eq!(code, 0);
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 2);
    assert!(modes.iter().all(|m| m["zero"] == true), "{v}");
    // A real mode is listed, its damping noise-free: the undamped pendulum, 0.610416 Hz.
    let pendulum = root().join("mechanisms/pendulum.adm");
    let (code, out, err) = run(&["linear", pendulum.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let row = out
        .lines()
        .find(|l| l.trim_start().starts_with("1 "))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(row.contains("6.10416E-01"), "{row}");
    assert!(row.trim_end().ends_with("0.00000E+00"), "{row}");
}
