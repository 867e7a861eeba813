//! `linkage fmu`: the FMU file (a zip with the model description, the dataset and the binary
//! where the FMI version puts it), and its refusals with their exit codes. (FMPy imports and
//! co-simulates the FMUs in tests/fmu/test_fmu.py.)

mod common;

use common::{root, run};
use std::path::PathBuf;

fn plant() -> String {
    root().join("tests/fmu/smd_plant.adm").display().to_string()
}

/// A stand-in for the FMU binary (the packager only copies its bytes).
fn fake_binary(dir: &std::path::Path) -> String {
    let p = dir.join("liblinkage_fmu_binary.so");
    std::fs::write(&p, b"\x7fELF stand-in").unwrap();
    p.display().to_string()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("linkage-fmu-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn contains(hay: &[u8], needle: &str) -> bool {
    hay.windows(needle.len()).any(|w| w == needle.as_bytes())
}

#[test]
fn fmu_is_a_zip_with_description_dataset_and_binary_where_each_version_puts_it() {
    let dir = scratch("ok");
    let binary = fake_binary(&dir);
    for (fmi, folder) in [("3", "binaries/x86_64-linux/"), ("2", "binaries/linux64/")] {
        let out = dir.join(format!("p{fmi}.fmu"));
        let out_s = out.display().to_string();
        let (code, stdout, stderr) = run(&[
            "fmu",
            &plant(),
            "--out",
            &out_s,
            "--fmi",
            fmi,
            "--binary",
            &binary,
        ]);
        assert_eq!(code, 0, "{stderr}");
        assert!(
            stdout.contains("inputs (every PINPUT): force (VARIABLE/1)"),
            "{stdout}"
        );
        assert!(
            stdout.contains("outputs (every POUTPUT): position (VARIABLE/2)"),
            "{stdout}"
        );
        let bytes = std::fs::read(&out).unwrap();
        assert_eq!(&bytes[..4], b"PK\x03\x04");
        for name in [
            "modelDescription.xml",
            "resources/smd_plant.adm",
            "resources/linkage-fmu.json",
        ] {
            assert!(contains(&bytes, name), "{name}");
        }
        assert!(contains(&bytes, &format!("{folder}smd_plant.so")));
        // The same dataset gives the same FMU, byte for byte.
        let again = dir.join("again.fmu").display().to_string();
        let (code, _, _) = run(&[
            "fmu",
            &plant(),
            "--out",
            &again,
            "--fmi",
            fmi,
            "--binary",
            &binary,
        ]);
        assert_eq!(code, 0);
        assert_eq!(std::fs::read(&again).unwrap(), bytes);
    }
}

#[test]
fn a_missing_binary_says_how_to_build_it_and_writes_nothing() {
    let dir = scratch("nobinary");
    let out = dir.join("p.fmu");
    let (code, _, stderr) = run(&[
        "fmu",
        &plant(),
        "--out",
        &out.display().to_string(),
        "--binary",
        "/nonexistent/liblinkage_fmu_binary.so",
    ]);
    assert_eq!(code, 1);
    assert!(stderr.contains("cargo build --release"), "{stderr}");
    assert!(!out.exists());
}

#[test]
fn a_dataset_without_plant_inputs_or_outputs_is_an_input_error() {
    let dir = scratch("noports");
    let binary = fake_binary(&dir);
    let model = root()
        .join("examples/spring_mass.adm")
        .display()
        .to_string();
    let out = dir.join("p.fmu").display().to_string();
    let (code, _, stderr) = run(&["fmu", &model, "--out", &out, "--binary", &binary]);
    assert_eq!(code, 2);
    assert!(stderr.contains("has no PINPUT and no POUTPUT"), "{stderr}");
}

#[test]
fn a_parameter_that_names_no_numeric_argument_is_an_input_error() {
    let dir = scratch("param");
    let binary = fake_binary(&dir);
    let out = dir.join("p.fmu").display().to_string();
    let (code, _, stderr) = run(&[
        "fmu",
        &plant(),
        "--out",
        &out,
        "--binary",
        &binary,
        "--parameter",
        "SPRINGDAMPER/1.Q",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        stderr.trim(),
        "--parameter SPRINGDAMPER/1.Q: SPRINGDAMPER/1 has no argument Q"
    );
    let (code, _, stderr) = run(&[
        "fmu",
        &plant(),
        "--out",
        &out,
        "--binary",
        &binary,
        "--pinput",
        "7",
    ]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("PINPUT/7 is not in the dataset (it has PINPUT 1)"),
        "{stderr}"
    );
}
