//! `linkage verify --explain` and `--apply K --save OUT.adm` end to end.

mod common;
use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn mechanism(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../mechanisms")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkage-explain-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn json(args: &[&str]) -> (i32, Value) {
    let (code, out, err) = run(args);
    let v = serde_json::from_str(&out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}\n{err}"));
    (code, v)
}

fn explain(path: &str) -> Value {
    let (code, v) = json(&["verify", path, "--explain", "--format", "json"]);
    assert_eq!(code, 0, "{v}");
    v
}

/// Sorted `to` keywords (without marker notes) of a suggestion.
fn kinds(s: &Value) -> Vec<String> {
    let mut k: Vec<String> = s["changes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let to = c["to"].as_str().unwrap();
            to.split(" (").next().unwrap().to_string()
        })
        .collect();
    k.sort();
    k
}

fn apply_and_verify(src: &str, number: u64, out: &Path) -> Value {
    let (code, v) = json(&[
        "verify",
        src,
        "--apply",
        &number.to_string(),
        "--save",
        out.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{v}");
    assert_eq!(v["applied"]["number"], number);
    explain(out.to_str().unwrap())
}

#[test]
fn fourbar_json_has_the_explain_keys_and_both_proposals_apply() {
    let src = mechanism("fourbar.adm");
    let v = explain(&src);
    for key in [
        "suggestions",
        "indeterminate",
        "determinate",
        "generic_dof",
        "generic_redundant",
        "singular_configuration",
        "conflicting_drivers",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["generic_dof"], 1);
    assert_eq!(v["generic_redundant"], 3);
    assert_eq!(v["singular_configuration"], false);
    assert_eq!(v["conflicting_drivers"].as_array().unwrap().len(), 0);
    assert_eq!(v["indeterminate"].as_array().unwrap().len(), 4);
    assert!(v.get("applied").is_none());
    let sug = v["suggestions"].as_array().unwrap();
    for (k, s) in sug.iter().enumerate() {
        assert_eq!(s["number"], k as u64 + 1);
        assert_eq!(s["dof_after"], 1);
        assert_eq!(s["redundant_after"], 0);
        for c in s["changes"].as_array().unwrap() {
            assert!(c["name"].is_string() && c["from"] == "REVOLUTE" && c["to"].is_string());
        }
    }
    // Proposal 1: a single change.
    assert_eq!(sug[0]["changes"].as_array().unwrap().len(), 1);
    assert_eq!(kinds(&sug[0]), ["JPRIM INLINE"]);
    let pair = sug
        .iter()
        .find(|s| kinds(s) == ["SPHERICAL", "UNIVERSAL"])
        .expect("spherical + universal");

    let dir = scratch("fourbar");
    for (tag, number) in [("single", 1), ("pair", pair["number"].as_u64().unwrap())] {
        let out = dir.join(format!("{tag}.adm"));
        let after = apply_and_verify(&src, number, &out);
        assert_eq!(after["dof"], 1, "{tag}");
        assert_eq!(after["redundant"].as_array().unwrap().len(), 0, "{tag}");
        assert_eq!(after["indeterminate"].as_array().unwrap().len(), 0, "{tag}");
        assert_eq!(after["suggestions"].as_array().unwrap().len(), 0, "{tag}");
    }
    // Everything but the changed joints and the statements added before END is kept.
    let before = std::fs::read_to_string(&src).unwrap();
    let after = std::fs::read_to_string(dir.join("pair.adm")).unwrap();
    let n = before.lines().count() - 1; // up to END
    let changed: Vec<(&str, &str)> = before
        .lines()
        .zip(after.lines())
        .take(n)
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(
        changed,
        [
            (", REVOLUTE", ", SPHERICAL"),
            (", REVOLUTE", ", UNIVERSAL"),
            (", I = 303", ", I = 404"),
        ]
    );
    let tail = &after[after.find("MARKER/404").unwrap()..];
    assert!(tail.starts_with("MARKER/404\n, PART = 3\n, QP = 1.75, 0.0, 0.0\n"));
    assert!(after.ends_with(", REULER = 180.0D, 90.0D, 180.0D\nEND\n"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn door_axial_reactions_are_indeterminate_until_spherical_and_inline() {
    let src = mechanism("door_two_hinges.adm");
    let v = explain(&src);
    let ind = v["indeterminate"].as_array().unwrap();
    for hinge in ["hinge_bottom", "hinge_top"] {
        let r = ind.iter().find(|r| r["name"] == hinge).unwrap();
        assert!(r["directions"]
            .as_array()
            .unwrap()
            .contains(&Value::from("force along Zj")));
    }
    let p = v["suggestions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| kinds(s) == ["JPRIM INLINE", "SPHERICAL"])
        .expect("spherical + inline");
    assert_eq!(p["redundant_after"], 0);
    assert_eq!(p["indeterminate_after"].as_array().unwrap().len(), 0);
    let dir = scratch("door");
    let out = dir.join("door.adm");
    let after = apply_and_verify(&src, p["number"].as_u64().unwrap(), &out);
    assert_eq!(after["dof"], 1);
    assert_eq!(after["redundant"].as_array().unwrap().len(), 0);
    assert_eq!(after["indeterminate"].as_array().unwrap().len(), 0);
    let det = after["determinate"].as_array().unwrap();
    assert_eq!(det.len(), 2);
    let spherical = det.iter().find(|r| r["type"] == "Spherical Joint").unwrap();
    assert_eq!(
        spherical["directions"],
        serde_json::json!(["force along Xj", "force along Yj", "force along Zj"])
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn parallelogram_chain_singular_only_with_horizontal_cranks() {
    let dir = scratch("chain");
    for (deg, singular) in [(0.0, true), (60.0, false)] {
        let path = dir.join(format!("chain{deg}.adm"));
        std::fs::write(&path, linkage_solve::generate::parallelogram_chain(3, deg)).unwrap();
        let v = explain(path.to_str().unwrap());
        assert_eq!(v["singular_configuration"], singular, "{deg}");
        assert_eq!(v["generic_dof"], 1, "{deg}");
        assert_eq!(v["generic_redundant"], 9, "{deg}");
        assert_eq!(v["dof"], if singular { 4 } else { 1 });
        let (code, text, _) = run(&["verify", path.to_str().unwrap(), "--explain"]);
        assert_eq!(code, 0);
        assert_eq!(text.contains("SINGULAR CONFIGURATION"), singular, "{text}");
    }
    let v = explain(&mechanism("fourbar_parallelogram_chain3.adm"));
    assert_eq!(v["singular_configuration"], false);
    assert_eq!(v["generic_dof"], 1);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bricard_generic_dof_one_with_one_redundancy() {
    let v = explain(&mechanism("bricard.adm"));
    assert_eq!(v["gruebler"], 0);
    assert_eq!(v["dof"], 1);
    assert_eq!(v["generic_dof"], 1);
    assert_eq!(v["generic_redundant"], 1);
    assert_eq!(v["singular_configuration"], false);
}

#[test]
fn motion_and_joint_ic_conflict_is_named() {
    let v = explain(&mechanism("revolute_motion_ic_conflict.adm"));
    let c = v["conflicting_drivers"].as_array().unwrap();
    assert_eq!(c.len(), 1, "{v}");
    assert_eq!(c[0]["name"], "hinge");
    assert_eq!(c[0]["type"], "IC rotation");
    assert_eq!(c[0]["kind"], "conflict");
    assert_eq!(
        c[0]["with"],
        serde_json::json!(["hinge_drive (Rotational Motion)"])
    );
    assert_eq!(c[0]["mismatch_unit"], "degrees");
    assert!((c[0]["mismatch"].as_f64().unwrap().abs() - 10.0).abs() < 1e-9);
    let (code, text, _) = run(&[
        "verify",
        &mechanism("revolute_motion_ic_conflict.adm"),
        "--explain",
    ]);
    assert_eq!(code, 0);
    assert!(text.contains(
        "hinge IC rotation fixes the same DOF as hinge_drive (Rotational Motion): CONFLICT"
    ));
}

#[test]
fn text_report_and_bad_apply_arguments() {
    let src = mechanism("fourbar.adm");
    let (code, text, _) = run(&["verify", &src, "--explain"]);
    assert_eq!(code, 0);
    for part in [
        "EXPLAIN REDUNDANCY",
        "Uniquely determined (can be trusted):",
        "Not unique",
        "Proposed changes",
        "    1. ",
        "--apply K --save OUT.adm",
        "Motions and initial conditions:",
    ] {
        assert!(text.contains(part), "missing {part:?}:\n{text}");
    }
    // Without --explain nothing is added to the JSON.
    let (_, v) = json(&["verify", &src, "--format", "json"]);
    assert!(v.get("suggestions").is_none());
    // A proposal that does not exist: nothing written, exit 1.
    let dir = scratch("bad");
    let out = dir.join("never.adm");
    let (code, v) = json(&[
        "verify",
        &src,
        "--apply",
        "99",
        "--save",
        out.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(code, 1);
    assert!(v["errors"][0].as_str().unwrap().contains("--apply 99"));
    assert!(!out.exists());
    // --apply needs --save (usage error).
    let (code, _, err) = run(&["verify", &src, "--apply", "1"]);
    assert_eq!(code, 2, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
