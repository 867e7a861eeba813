//! FE_PART through the binary: the corpus dataset's six-node 3DBEAM counted in `verify` as
//! Adams' chapter counts a nonlinear FE body (markers use nodes 1, 4 and 6: 18 constraint
//! modes; 18 interior DOF, so 18 of the 20 normal modes; 6 rigid-body modes), the count
//! following `MSC_NLFE_MNFSWAP_EIGENVALUES` (set on the child process only), and the nodes'
//! columns in the simulate CSV.

mod common;
use common::*;
use std::process::Command;

const DATASET: &str = "bthornton191__adams_vscode__test__files__test.adm";

fn verify_json(path: &str, modes: Option<&str>) -> serde_json::Value {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_linkage"));
    cmd.args(["verify", path, "--format", "json"]);
    match modes {
        Some(m) => cmd.env("MSC_NLFE_MNFSWAP_EIGENVALUES", m),
        None => cmd.env_remove("MSC_NLFE_MNFSWAP_EIGENVALUES"),
    };
    let out = cmd.output().unwrap_or_else(|e| panic!("binary runs: {e}"));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("not JSON: {e}"))
}

#[test]
fn corpus_fe_part_is_counted_as_an_equivalent_flexible_body() {
    let Some(dir) = corpus() else { return };
    let path = dir.join(DATASET);
    let path = path.to_string_lossy();
    let v = verify_json(&path, None);
    let fe = &v["fe_parts"][0];
    assert_eq!(fe["name"], "Fe_Part_1");
    assert_eq!(fe["marker_nodes"], serde_json::json!([1, 4, 6]));
    assert_eq!(fe["normal_modes_requested"], 20);
    assert_eq!(fe["normal_modes"], 18);
    assert_eq!(fe["constraint_modes"], 18);
    assert_eq!(fe["rigid_body_modes"], 6);
    assert_eq!(fe["gruebler_dof"], 42);
    assert_eq!(fe["nodal_dof"], 36);
    // PART_3 (6) + the FE part (42); no constraints. DOF by rank: 6 + 36 nodal.
    assert_eq!(v["gruebler"], 48);
    assert_eq!(v["dof"], 42);
    assert_eq!(v["moving_parts"], 1);
    assert_eq!(
        v["unconstrained_parts"],
        serde_json::json!(["PART_3", "Fe_Part_1"])
    );
    // Ten normal modes asked for: 10 + 18 + 6.
    let v = verify_json(&path, Some("10"));
    assert_eq!(v["fe_parts"][0]["gruebler_dof"], 34);
    assert_eq!(v["gruebler"], 40);
    let (code, text, _) = run(&["verify", &path]);
    assert_eq!(code, 0);
    assert!(
        text.contains("Fe_Part_1: 6 nodes; 18 normal modes (20 requested) + 18 constraint modes"),
        "{text}"
    );
}

#[test]
fn corpus_fe_part_nodes_have_csv_columns() {
    let Some(dir) = corpus() else { return };
    let path = dir.join(DATASET);
    let (code, csv, err) = run(&[
        "simulate",
        &path.to_string_lossy(),
        "--deactivate",
        "CONTACT",
        "--end",
        "0.01",
        "--steps",
        "2",
        "--out",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let header = csv.lines().next().unwrap_or_default();
    for n in 1..=6 {
        assert!(
            header.contains(&format!("Fe_Part_1.node_{n}.x [mm]")),
            "{header}"
        );
    }
    // Free fall from rest: node 4 drops g·t²/2 = 0.4903 mm in 0.01 s.
    let cols: Vec<&str> = header.split(',').collect();
    let k = cols
        .iter()
        .position(|c| *c == "Fe_Part_1.node_4.y [mm]")
        .unwrap();
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let drop = 47.02729423 - last[k];
    assert!((drop / (0.5 * 9806.65 * 1e-4) - 1.0).abs() < 1e-3, "{drop}");
}
