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

/// A six-node cantilever along x (steel, L = 1 m, 10 mm square), clamped at node 1, a tip
/// load of fixed direction (PL²/EI ≈ 1.7) and a marker on node 4 given by points.
fn bent_cantilever() -> String {
    let (a, i, j) = (1e-4, 1e-8 / 12.0, 0.1406e-8);
    let coords: Vec<String> = (0..6)
        .map(|k| format!("{}, {}, 0, 0, 0, 0, 0", k + 1, 0.2 * k as f64))
        .collect();
    let sections: Vec<String> = (0..6)
        .map(|k| format!("{}, {a}, {i}, {i}, 0, {j}", k + 1))
        .collect();
    format!(
        "beam\nUNITS/, FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND\n\
         PART/1, GROUND\nMARKER/1, PART = 1\nMARKER/12, PART = 1, FLOATING\n\
         FE_PART/3, TYPE = 3DBEAM, NODE_LABELS = 1, 2, 3, 4, 5, 6\n, COORDINATES = {}\n\
         , SECTION = {}\n, MATERIAL = 1\n\
         MATERIAL/1, DENSITY = 7800, YOUNGS_MODULUS = 2.1E11, POISSONS_RATIO = 0.3\n\
         MARKER/10, FE_PART = 3, NODE_LABEL = 1\n\
         MARKER/11, FE_PART = 3, NODE_LABEL = 6, QP = 1, 0, 0\n\
         MARKER/13, FE_PART = 3, NODE_LABEL = 4, QP = 0.6, 0.01, 0, XP = 0.7, 0.01, 0, ZP = 0.6, 0.01, 1\n\
         JOINT/1, FIXED, I = 10, J = 1\n\
         VFORCE/1, I = 11, JFLOAT = 12, RM = 1, FX = 0, FY = -300, FZ = 0\n\
         EQUILIBRIUM/MAXIT = 100\nEND\n",
        coords.join("\n, "),
        sections.join("\n, "),
    )
}

#[test]
fn static_save_writes_the_deflected_nodes_and_ic_reads_them_back() {
    let dir = std::env::temp_dir().join(format!("linkage-fe-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("beam.adm");
    let saved = dir.join("saved.adm");
    std::fs::write(&input, bent_cantilever()).unwrap();
    let (input, saved_s) = (input.to_string_lossy(), saved.to_string_lossy());
    let (code, eq) = json(&["static", &input, "--save", &saved_s, "--format", "json"]);
    assert_eq!(code, 0, "{eq}");
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(
        text.contains(", 6, 0.869521819"),
        "deflected tip node in COORDINATES:\n{text}"
    );
    let (code, ic) = json(&["ic", &saved_s, "--format", "json"]);
    assert_eq!(code, 0, "{ic}");
    let parts = |v: &serde_json::Value| -> Vec<(String, Vec<f64>)> {
        v["parts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let mut x: Vec<f64> = p["position"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect();
                x.extend(
                    p["reuler"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_f64().unwrap()),
                );
                (p["name"].as_str().unwrap().to_string(), x)
            })
            .collect()
    };
    let (want, got) = (parts(&eq), parts(&ic));
    assert_eq!(want.len(), 6);
    assert_eq!(
        want.iter().map(|p| &p.0).collect::<Vec<_>>(),
        got.iter().map(|p| &p.0).collect::<Vec<_>>()
    );
    // Positions in m, angles in degrees: the saved numbers' resolution (1e-12) and the
    // assembly's tolerance.
    for ((name, a), (_, b)) in want.iter().zip(&got) {
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() < 1e-8, "{name}: {b:?} vs {a:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
