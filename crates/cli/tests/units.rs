//! Every report states its units: the `units` object of the JSON reports, the `units:` line of
//! the text reports, the unit suffix of every CSV column; `compare` matches columns by name
//! with or without that suffix.

mod common;
use common::*;
use std::path::PathBuf;

/// The slider-crank is in newton, kilogram, millimeter, second (UCF 1000).
fn slider_crank() -> String {
    root()
        .join("mechanisms/slider_crank.adm")
        .to_string_lossy()
        .into_owned()
}

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("linkage-units-{}-{tag}", std::process::id()))
}

/// Every JSON report states the version of its layout, also each report of a multi-model
/// verify.
#[test]
fn json_reports_state_their_schema_version() {
    let src = slider_crank();
    for command in ["verify", "ic", "static", "linear"] {
        let (_, v) = json(&[command, &src, "--format", "json"]);
        assert_eq!(v["schema_version"].as_u64(), Some(1), "{command}");
    }
    let (_, v) = json(&["verify", &src, &src, "--format", "json"]);
    let reports = v.as_array().expect("a list of reports");
    assert_eq!(reports.len(), 2);
    assert!(reports
        .iter()
        .all(|r| r["schema_version"].as_u64() == Some(1)));
}

#[test]
fn millimeter_model_reports_state_millimeter_units_in_json() {
    let src = slider_crank();
    for command in ["verify", "ic", "static", "linear"] {
        let (_, v) = json(&[command, &src, "--format", "json"]);
        let u = &v["units"];
        assert_eq!(
            u["system"], "NEWTON KILOGRAM MILLIMETER SECOND",
            "{command}: {u}"
        );
        assert_eq!(u["dataset"]["length"], "MILLIMETER", "{command}: {u}");
        assert_eq!(u["ucf"].as_f64(), Some(1000.0), "{command}: {u}");
        assert_eq!(u["length"], "millimeter", "{command}: {u}");
        assert_eq!(u["force"], "newton", "{command}: {u}");
        assert_eq!(u["torque"], "newton·millimeter", "{command}: {u}");
        assert_eq!(u["velocity"], "millimeter/second", "{command}: {u}");
        assert_eq!(u["acceleration"], "millimeter/second²", "{command}: {u}");
        assert_eq!(u["angular_velocity"], "radian/second", "{command}: {u}");
        // 3-1-3 angles and verify's residuals in degrees; linear's mode-shape rotations in
        // radians, its frequencies in cycles per second.
        let (angle, frequency) = if command == "linear" {
            ("radian", serde_json::json!("cycle/second"))
        } else {
            ("degree", serde_json::Value::Null)
        };
        assert_eq!(u["angle"], angle, "{command}: {u}");
        assert_eq!(u["frequency"], frequency, "{command}: {u}");
    }
    let (code, v) = json(&[
        "simulate", &src, "--end", "0.02", "--steps", "2", "--format", "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["units"]["torque"], "newton·millimeter", "{v}");
    assert_eq!(v["units"]["angle"], "degree", "{v}");
}

#[test]
fn millimeter_model_text_reports_have_a_units_line() {
    let src = slider_crank();
    let want = "  units: NEWTON KILOGRAM MILLIMETER SECOND (UCF 1000); torque newton·millimeter";
    for args in [
        vec!["verify", src.as_str()],
        vec!["ic", src.as_str()],
        vec!["static", src.as_str()],
        vec!["linear", src.as_str()],
        vec!["simulate", src.as_str(), "--end", "0.02", "--steps", "2"],
    ] {
        let (_, out, _) = run(&args);
        // In the header: the third line, after the title and the file.
        let line = out.lines().nth(2).unwrap_or_default();
        assert!(line.starts_with(want), "{}: {out}", args[0]);
    }
    let (_, out, _) = run(&["linear", &src]);
    assert!(out.contains("frequencies in cycle/second"), "{out}");
}

#[test]
fn a_dataset_without_units_says_model_units() {
    let text = std::fs::read_to_string(root().join("mechanisms/pendulum_offset.adm"))
        .unwrap_or_else(|e| panic!("{e}"));
    let start = text.find("UNITS/").unwrap_or_else(|| panic!("no UNITS"));
    let end = start
        + text[start..]
            .find("\n!")
            .unwrap_or_else(|| panic!("UNITS end"));
    let src = temp("no-units.adm");
    std::fs::write(&src, format!("{}{}", &text[..start], &text[end + 1..]))
        .unwrap_or_else(|e| panic!("{e}"));
    let src = src.to_string_lossy().into_owned();
    let (_, v) = json(&["ic", &src, "--format", "json"]);
    assert_eq!(
        v["units"]["system"], "model units (no UNITS statement)",
        "{v}"
    );
    assert_eq!(v["units"]["dataset"]["force"], "NONE", "{v}");
    assert_eq!(v["units"]["torque"], "model force·model length", "{v}");
    let (_, out, _) = run(&["ic", &src]);
    assert!(
        out.contains("units: model units (no UNITS statement) (UCF 1)"),
        "{out}"
    );
    let (_, csv, _) = run(&["static", &src, "--format", "csv"]);
    assert!(csv.starts_with("time [T],rod.x [L],"), "{csv}");
    assert!(csv.contains("hinge.tz [F·L]"), "{csv}");
}

#[test]
fn csv_columns_carry_their_units_and_compare_still_matches_them() {
    let src = slider_crank();
    // The slider-crank's equilibrium is unstable (a verdict of its own): accepted here, where
    // only the CSV's columns matter.
    let (code, csv, err) = run(&["static", &src, "--format", "csv", "--allow-unstable"]);
    assert_eq!(code, 0, "{err}");
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    assert_eq!(header[0], "time [s]");
    assert!(header.contains(&"crank.x [mm]"), "{header:?}");
    assert!(header.contains(&"crank.psi [deg]"), "{header:?}");
    assert!(
        header.iter().any(|h| h.ends_with(".tz [N·mm]")),
        "{header:?}"
    );
    let out = temp("sim.csv");
    let out_s = out.to_string_lossy().into_owned();
    let (code, _, err) = run(&[
        "simulate", &src, "--end", "0.02", "--steps", "4", "--out", &out_s,
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("{e}"));
    let header = text.lines().next().unwrap_or_default();
    assert!(header.contains("crank.wz [rad/s]"), "{header}");
    assert!(header.contains("crank.vx [mm/s]"), "{header}");
    // The same history with the units dropped from its header (a file written before the
    // suffix, or edited by a script): compare matches every column by name.
    let bare_header: Vec<&str> = header
        .split(',')
        .map(linkage_report::units::column_name)
        .collect();
    let bare = temp("bare.csv");
    let body: String = text.lines().skip(1).map(|l| format!("{l}\n")).collect();
    std::fs::write(&bare, format!("{}\n{body}", bare_header.join(",")))
        .unwrap_or_else(|e| panic!("{e}"));
    let bare_s = bare.to_string_lossy().into_owned();
    let (code, j) = json(&["compare", &out_s, &bare_s, "--format", "json"]);
    assert_eq!(code, 0, "{j}");
    assert_eq!(j["only_in_a"], serde_json::json!([]), "{j}");
    assert_eq!(j["only_in_b"], serde_json::json!([]), "{j}");
    let columns = header.split(',').count() - 1;
    assert_eq!(j["signals"].as_array().map(Vec::len), Some(columns), "{j}");
}
